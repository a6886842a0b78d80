#!/usr/bin/env python3
"""The talk's figures beside ours (papers/talk-figures.md): per mechanism, constraints, dim(H),
density of H, flops of the block LDL^T and its time, and the spy plots of H and L.

Usage: python3 papers/scripts/talk_figures.py [build/bin/ldlpgs] [--figures DIR]   (prints Markdown to stdout)
DIR (default papers/figures) receives the spy files and plots; `ldlpgs report` gives its own.

For each row: `ldlpgs spy SCENE ARGS --json-file papers/figures/NAME.json --scene-file S.json` gives
the counts and the data of the plot (papers/scripts/plot_spy.py draws papers/figures/NAME.png), then
`ldlpgs export S.json` and `ldlpgs bench M.mtx --blocks B --json` time the numeric factorization
of that H_0 (field factor_us, a median) and one solve, and `ldlpgs step S.json --solver
direct --steps 1000 --json` the whole equality solve of a step (field solve_us: J, W,
H = J W J^T, the factorization and the solve). Run it on an idle machine.
"""
import argparse
import json
import os
import platform
import sys
import tempfile

import plot_spy
import run_ldlpgs

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FIGURES = os.path.join(ROOT, "papers", "figures")
LDLPGS = os.path.join(ROOT, "build", "bin", "ldlpgs")

# (the talk's mechanism, its figures: constraints, dim(H), density, flops, time;
#  the figure's name, our scene and spy arguments)
ROWS = [
    ("a 50-constraint mechanism", ("50", "246", "12%", "90k", "70 us (Core i9)"),
     "mechanism-50", "mechanism-50", ["--no-shatter"]),
    ("tracked vehicle", ("40", "200", "7.5%", "43k", "35 us"),
     "tracked-vehicle", "tracked-vehicle", ["--no-shatter"]),
    ("multi-wheeled vehicle", ("20", "88", "100%", "250k", "-"),
     "multi-wheeled-vehicle", "multi-wheeled-vehicle", ["--no-shatter"]),
    ("the same, shattered", ("29", "142", "17.5%", "35k", "34 us"),
     "multi-wheeled-vehicle-10-shards", "multi-wheeled-vehicle", ["--shards", "10"]),
]
# The talk's ordering, MECA, everywhere (the programs' default is best, which on the tracked
# vehicle chooses meca-w's 38.3k against MECA's 41.4k: papers/orderings.md).
ORDERING = ["--ordering", "meca"]
# Ours only: what shatter() chooses by flops (--shatter 20, the default).
EXTRA = [
    ("multi-wheeled vehicle, shards chosen by flops", "multi-wheeled-vehicle-shattered", "multi-wheeled-vehicle", []),
    ("50-constraint mechanism, shards chosen by flops", "mechanism-50-shattered", "mechanism-50", []),
    ("tracked vehicle, shards chosen by flops", None, "tracked-vehicle", []),
]


def ldlpgs(*args):
    return run_ldlpgs.run(LDLPGS, *args)


def measure(name, scene, args, tmp):
    """spy (and its plot), then export + bench of the mechanism it spied."""
    spy_file = os.path.join(FIGURES, f"{name}.json") if name else os.path.join(tmp, "spy.json")
    scene_file, mtx, blocks = (os.path.join(tmp, f) for f in ("scene.json", "h.mtx", "h.blocks"))
    ldlpgs("spy", scene, *args, *ORDERING, "--json-file", spy_file, "--scene-file", scene_file)
    with open(spy_file) as f:
        spy = json.load(f)
    if name:
        plot_spy.plot(spy, os.path.join(FIGURES, f"{name}.png"))
    ldlpgs("export", scene_file, "--no-shatter", "--matrix-file", mtx, "--blocks-file", blocks)
    bench = json.loads(ldlpgs("bench", mtx, "--blocks", blocks, *ORDERING, "--json"))
    assert bench["n"] == spy["n"] and bench["flops"] == spy["flops"], (bench, spy["flops"])
    step = json.loads(ldlpgs("step", scene_file, "--no-shatter", "--solver", "direct", *ORDERING, "--steps", "1000", "--json"))
    return spy, bench, step


def cells(spy, bench, step):
    """Our constraints, dim(H), density, flops, time of the numeric factorization (and of one
    solve), time of a step's equality solve."""
    return [str(spy["constraints"]), str(spy["n"]), f"{100 * spy['density']:.1f}%", f"{spy['flops'] / 1000:.1f}k",
            f"{bench['factor_us']:.1f} us ({bench['solve_us']:.1f} us)",
            f"{step['solve_us']:.1f} us"]


def command(scene, args):
    return "`ldlpgs spy " + " ".join([scene, *args, *ORDERING]) + "`"


def machine():
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return f"{cpu}, {os.cpu_count()} cores, load average {load:.2f} when the table was made"


def main():
    global FIGURES, LDLPGS
    parser = argparse.ArgumentParser(description="The talk's figures beside ours (papers/talk-figures.md)")
    parser.add_argument("ldlpgs", nargs="?", default=LDLPGS)
    parser.add_argument("--figures", default=FIGURES)
    args = parser.parse_args()
    FIGURES, LDLPGS = args.figures, args.ldlpgs
    os.makedirs(FIGURES, exist_ok=True)
    print("| mechanism | constraints | dim(H) | density(H) | LDL flops | time | ours: factor (solve) |"
          " ours: step's solve | our command |")
    print("|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for label, talk, name, scene, args in ROWS:
            ours = cells(*measure(name, scene, args, tmp))
            pairs = [f"{t} / {o}" for t, o in zip(talk[:4], ours[:4])]
            print(f"| {label} | " + " | ".join(pairs + [talk[4], *ours[4:]]) + f" | {command(scene, args)} |")
        for label, name, scene, args in EXTRA:
            spy, bench, step = measure(name, scene, args, tmp)
            label += "" if spy["shattered"] else " (left whole)"
            ours = cells(spy, bench, step)
            pairs = [f"- / {o}" for o in ours[:4]]
            print(f"| {label} | " + " | ".join(pairs + ["-", *ours[4:]]) + f" | {command(scene, args)} |")
    print(f"\nMachine: {machine()}.")


if __name__ == "__main__":
    main()
