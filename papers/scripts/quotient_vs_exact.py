#!/usr/bin/env python3
"""The quotient-graph orderings (mda, mda-w, meca, meca-w) against their explicit-graph
references (the -exact forms): the ratio of scalar flops and nnz(L), per problem, on
the test matrices (blocks auto, Pd.mtx left out), the families at 20, 40, 60, 300, 1000 and
3000 constraints and the grid at 5000 and 8000 (where meca's approximate score had been 16 %
off); prints, per ordering, the geometric mean of the flop ratio, the worst case
and every problem more than 2% off (either way).

Usage: python3 papers/scripts/quotient_vs_exact.py [build/bin/ldlpgs]   (about 4 minutes on 2 cores,
nearly all of it the -exact orderings at 3000 constraints)
"""
import glob
import json
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build/bin/ldlpgs")
PAIRS = [("mda", "mda-exact"), ("mda-w", "mda-w-exact"), ("meca", "meca-exact"), ("meca-w", "meca-w-exact")]


def problems():
    out = [f for f in sorted(glob.glob(os.path.join(ROOT, "tests/data/matrices/*.mtx"))) if not f.endswith("Pd.mtx")]
    families = subprocess.run([BIN, "order", "nofamily:1"], capture_output=True, text=True).stderr
    names = families[families.index("(") + 1 : families.index(")")].split(", ")
    return out + [f"{fam}:{size}" for fam in names for size in (20, 40, 60, 300, 1000, 3000)] + ["grid:5000", "grid:8000"]


def run(problem):
    names = ",".join(a + "," + b for a, b in PAIRS)
    r = subprocess.run([BIN, "order", problem, "--ordering", names, "--json"], capture_output=True, text=True, check=True)
    return {x["ordering"]: x for x in json.loads(r.stdout)["results"]}


def main():
    results = {p: run(p) for p in problems()}
    for fast, exact in PAIRS:
        logs, worst, off = [], (0, "", 0), []
        for p, res in results.items():
            name = os.path.basename(p)
            flops = res[fast]["flops"] / res[exact]["flops"]
            nnz = res[fast]["nnz_L"] / res[exact]["nnz_L"]
            logs.append(math.log(flops))
            if flops > worst[0]:
                worst = (flops, name, nnz)
            if abs(flops - 1) > 0.02:
                off.append(f"{name} {flops:.3f} (nnz {nnz:.3f})")
        print(f"{fast} / {exact}: flops geometric mean {math.exp(sum(logs) / len(logs)):.4f} over {len(logs)} problems, "
              f"worst {worst[0]:.4f} on {worst[1]} (nnz {worst[2]:.4f}); more than 2% off: {', '.join(off) or 'none'}")


if __name__ == "__main__":
    main()
