#!/usr/bin/env python3
"""The tables of papers/factor.md, from `ldlpgs verify --json` and `ldlpgs bench --json`.

Usage: python3 papers/factor_tables.py [build/bin/ldlpgs]   (prints Markdown to stdout)
Run it on an idle machine: the timings are medians, but two cores shared with a build are not.
"""
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LDLPGS = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "bin", "ldlpgs")
MATRICES = os.path.join(ROOT, "tests", "data", "matrices")
FAMILIES = ["chain", "tree", "ladder", "loop", "heavy", "grid", "star"]
# Constraints giving dim(H) about 90, 250, 1000 and 5000 (about 3.95 rows per constraint).
SIZES = [22, 63, 253, 1265]


def run(*args):
    out = subprocess.run([LDLPGS, *args, "--json"], capture_output=True, text=True)
    if out.returncode not in (0, 1):
        sys.exit(f"{' '.join(args)}: {out.stderr.strip()}")
    return json.loads(out.stdout)


def matrices():
    names = sorted(f for f in os.listdir(MATRICES) if f.endswith(".mtx") and f != "Pd.mtx")
    return [os.path.join(MATRICES, f) for f in names]


def fmt(x, spec):
    return "-" if x is None else format(x, spec)


def verify_table():
    print("| matrix | n | nnz(L) | CHOLMOD nnz(L) | cond_1 est. | L diff | D diff | x diff | tolerance |"
          " backward error | CHOLMOD backward error | agree |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    problems = matrices() + [f"{f}:{m}" for f in FAMILIES for m in SIZES[:3]]
    for p in problems:
        v = run("verify", p)
        print(f"| {v['matrix']} | {v['n']} | {v['nnz_L']} | {v['cholmod_nnz_L']} | {fmt(v['condition_estimate'], '.1e')}"
              f" | {fmt(v['L_rel_diff'], '.1e')} | {fmt(v['D_rel_diff'], '.1e')} | {fmt(v['x_rel_diff'], '.1e')}"
              f" | {fmt(v['tolerance']['factor'], '.0e')} | {fmt(v['backward_error'], '.1e')}"
              f" | {fmt(v['cholmod_backward_error'], '.1e')} | {'yes' if v['ok'] else '**no**'} |")


def bench_table(problems):
    print("| matrix | n | flops | ldlpgs factor us | solve us | GFlop/s | CHOLMOD | CHOLMOD supernodal |"
          " Eigen simplicial | Eigen dense | ratio CHOLMOD | ratio Eigen simplicial | ratio dense |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for p in problems:
        b = run("bench", p)
        ours = b["factor_us"] + b["solve_us"]

        def both(name):
            f, s = b[f"{name}_factor_us"], b[f"{name}_solve_us"]
            return None if f is None else (f, s)

        def cell(name):
            t = both(name)
            return "-" if t is None else f"{t[0]:.1f} + {t[1]:.1f}"

        def ratio(name):
            t = both(name)
            return "-" if t is None else f"{(t[0] + t[1]) / ours:.2f}x"

        print(f"| {b['matrix']} | {b['n']} | {b['flops']:.3g} | {b['factor_us']:.1f} | {b['solve_us']:.1f}"
              f" | {b['gflops']:.2f} | {cell('cholmod')} | {cell('cholmod_supernodal')} | {cell('eigen_simplicial')}"
              f" | {cell('eigen_dense')} | {ratio('cholmod')} | {ratio('eigen_simplicial')} | {ratio('eigen_dense')} |")


if __name__ == "__main__":
    which = os.environ.get("TABLES", "verify,mechanisms,matrices").split(",")
    if "verify" in which:
        print("### Verification against CHOLMOD (ordering meca)\n")
        verify_table()
        print()
    if "mechanisms" in which:
        print("### Speed on mechanisms (ordering meca; medians; factor + solve in microseconds)\n")
        # heavy at 1265 constraints is a dense n = 5000 matrix: seconds per factorization for
        # every solver, minutes for the medians; `ldlpgs bench heavy:1265` times it alone.
        bench_table([f"{f}:{m}" for m in SIZES for f in FAMILIES if not (f == "heavy" and m == SIZES[-1])])
        print()
    if "matrices" in which:
        print("### Speed on the test matrices (ordering meca, blocks auto)\n")
        bench_table(matrices())
