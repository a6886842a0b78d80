#!/usr/bin/env python3
"""The certificate table of papers/orderings.md ("The best order, with a certificate").

Usage: python3 papers/scripts/certificate_table.py [LDLPGS] [TIME_LIMIT_S]

For each problem: `ldlpgs order PROBLEM --ordering best,meca --certify --certify-time-limit-s T
--json` (a scene first through `ldlpgs export SCENE [ARGS]`, which shatters as `step` does), and
one Markdown row: blocks, best's winner and block flops, meca's, the certificate (the optimum, or
the lower bound it proved) and its time.
"""
import json
import os
import sys
import tempfile

import run_ldlpgs

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LDLPGS = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "bin", "ldlpgs")
LIMIT = sys.argv[2] if len(sys.argv) > 2 else "30"

# (scene, export arguments): the talk's mechanisms whole and shattered, then the built-in scenes
SCENES = [
    ("tracked-vehicle", ["--no-shatter"]),
    ("multi-wheeled-vehicle", ["--no-shatter"]),
    ("multi-wheeled-vehicle", ["--shards", "10"]),
    ("multi-wheeled-vehicle", []),
    ("mechanism-50", ["--no-shatter"]),
    ("mechanism-50", []),
    ("pendulum", []),
    ("chain-10", []),
    ("heavy-chain-10-1000", []),
    ("ragdoll", []),
    ("four-bar", []),
    ("rope-bridge", []),
    ("driven-crank", []),
]
# the generated families at the talk's sizes (FAMILY:CONSTRAINTS)
FAMILIES = [f"{f}:{m}" for f in ("chain", "tree", "ladder", "loop", "grid", "star") for m in (20, 40, 60)] + ["heavy:20"]


def ldlpgs(*args):
    return run_ldlpgs.run(LDLPGS, *args)


def row(label, problem, blocks_args, command):
    j = json.loads(ldlpgs("order", problem, *blocks_args, "--ordering", "best,meca", "--certify",
                          "--certify-time-limit-s", LIMIT, "--json"))
    best, meca = j["results"][:2]  # a third row, "optimal", is the certificate's order when it beats both
    cert = f"optimum {j['lower_bound_block_flops']:.0f}" if j["optimum_proved"] else \
        f"lower bound {j['lower_bound_block_flops']:.0f}"
    mark = lambda r: " (certified)" if r["certified_optimal"] else ""
    how = ("chordal" if j["chordal"] else f"{j['peeled_blocks']} peeled, {j['atoms']} atoms, "
           f"{j['certify_states']} sets")
    print(f"| {label} | {j['blocks']} | {best['chosen']} {best['block_flops']:.0f}{mark(best)} | "
          f"{meca['block_flops']:.0f}{mark(meca)} | {cert} | {how} | {j['certify_ms'] / 1000:.2f} s | {command} |",
          flush=True)


def main():
    print("| problem | blocks | best: winner, block flops | meca | certificate | how | time | command |")
    print("|---|---:|---|---:|---|---|---:|---|")
    with tempfile.TemporaryDirectory() as tmp:
        mtx, blocks = os.path.join(tmp, "h.mtx"), os.path.join(tmp, "h.blocks")
        for scene, args in SCENES:
            ldlpgs("export", scene, *args, "--matrix-file", mtx, "--blocks-file", blocks)
            label = " ".join([scene, *args])
            row(label, mtx, ["--blocks", blocks],
                f"`ldlpgs export {label} --matrix-file h.mtx --blocks-file h.blocks`, then `order h.mtx --blocks h.blocks`")
        for f in FAMILIES:
            row(f, f, [], f"`ldlpgs order {f}`")


if __name__ == "__main__":
    main()
