#!/usr/bin/env python3
"""Block partitions that see inside blocks: the whole-constraint partition against
the refined one (`--split-blocks`: exact zeros dropped, each constraint cut into runs of rows with
identical patterns, sparse/partition.h partition_refine), against scalar AMD and METIS on the same
nonzero pattern; then factor time (ldlpgs bench) of both partitions against CHOLMOD.

Problems: the talk's mechanisms exported (`ldlpgs export SCENE [--no-shatter]`), and the families
at 20, 40, 60 and 300 constraints. Three rows of numbers per problem:
  stored  whole constraints on the stored pattern (the export's explicit zeros count as entries:
          what `order H.mtx --blocks H.blocks` reports without the flag)
  whole   whole constraints on the nonzero pattern (the exported matrix rewritten without its
          exact off-diagonal zeros by this script; a family's matrix has none)
  split   the same matrix with --split-blocks
amd-scalar and metis-scalar are counted on the nonzero pattern.

Usage: python3 papers/scripts/partition_study.py [build/bin/ldlpgs]   (about a minute on 2 cores)
"""
import json
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_ldlpgs import run  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build/bin/ldlpgs")
SCENES = ["tracked-vehicle", "multi-wheeled-vehicle", "mechanism-50"]
FAMILIES = ["chain", "tree", "ladder", "loop", "heavy", "grid", "star"]
SIZES = [20, 40, 60, 300]
ORDERINGS = "best,meca-w,amd-scalar,metis-scalar"


def without_zeros(src, dst):
    """Copies a symmetric Matrix Market file without its exact zeros off the diagonal."""
    with open(src) as f:
        lines = f.read().splitlines()
    header = [l for l in lines if l.startswith("%")]
    body = [l for l in lines if l.strip() and not l.startswith("%")]
    n, _, _ = body[0].split()
    kept = [l for l in body[1:] if float(l.split()[2]) != 0.0 or l.split()[0] == l.split()[1]]
    with open(dst, "w") as f:
        f.write("\n".join(header + [f"{n} {n} {len(kept)}"] + kept) + "\n")


def order(problem, *flags):
    j = json.loads(run(BIN, "order", problem, *flags, "--ordering", ORDERINGS, "--json"))
    return j["blocks"], {r["ordering"]: r for r in j["results"]}


def bench(args, ordering):
    return json.loads(run(BIN, "bench", *args, "--ordering", ordering, "--json"))


def problems(tmp):
    """(name, [stored args], [whole args], [split args]) per problem."""
    out = []
    for scene in SCENES:
        for shatter in ([], ["--no-shatter"]):
            stem = os.path.join(tmp, scene + "".join(shatter))
            run(BIN, "export", scene, "--matrix-file", stem + ".mtx", "--blocks-file", stem + ".blocks", *shatter)
            without_zeros(stem + ".mtx", stem + "-nz.mtx")
            name = scene + (" whole" if shatter else "")
            out.append((name, [stem + ".mtx", "--blocks", stem + ".blocks"],
                        [stem + "-nz.mtx", "--blocks", stem + ".blocks"],
                        [stem + "-nz.mtx", "--blocks", stem + ".blocks", "--split-blocks"]))
    for fam in FAMILIES:
        for size in SIZES:
            p = f"{fam}:{size}"
            out.append((p, [p], [p], [p, "--split-blocks"]))
    return out


def main():
    with tempfile.TemporaryDirectory() as tmp:
        rows = []
        print("| problem | blocks whole -> split | best stored | best whole | best split | meca-w whole -> split "
              "| amd-scalar | metis-scalar | nnz(L) best whole -> split, amd-scalar | split/amd |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for name, stored, whole, split in problems(tmp):
            _, s = order(*stored)
            nb, w = order(*whole)
            ns, r = order(*split)
            f = lambda x: f"{x['flops']:,.0f}"  # noqa: E731
            print(f"| {name} | {nb} -> {ns} | {f(s['best'])} | {f(w['best'])} ({w['best']['chosen']}) "
                  f"| {f(r['best'])} ({r['best']['chosen']}) | {f(w['meca-w'])} -> {f(r['meca-w'])} "
                  f"| {f(r['amd-scalar'])} | {f(r['metis-scalar'])} "
                  f"| {w['best']['nnz_L']} -> {r['best']['nnz_L']}, {r['amd-scalar']['nnz_L']} "
                  f"| {r['best']['flops'] / r['amd-scalar']['flops']:.3f} |")
            if nb != ns or not name[-1].isdigit() or name.endswith(":60") or name.endswith(":300"):
                rows.append((name, whole, split, nb != ns))
        print()
        print("Factor time, microseconds (bench medians; best's order; CHOLMOD simplicial with the same "
              "permutation, and with amd-scalar's):")
        print()
        print("| problem | ours whole | ours split | CHOLMOD whole's perm | CHOLMOD split's perm | CHOLMOD amd-scalar "
              "| ours amd-scalar |")
        print("|---|---|---|---|---|---|---|")
        for name, whole, split, changed in rows:
            bw = bench(whole, "best")
            bs = bench(split, "best") if changed else bw
            ba = bench(split, "amd-scalar")
            print(f"| {name} | {bw['factor_us']:.1f} | {bs['factor_us']:.1f} | {bw['cholmod_factor_us']:.1f} "
                  f"| {bs['cholmod_factor_us']:.1f} | {ba['cholmod_factor_us']:.1f} | {ba['factor_us']:.1f} |")


if __name__ == "__main__":
    main()
