#!/usr/bin/env python3
"""The tables of papers/factor.md, from `ldlpgs verify --json` and `ldlpgs bench --json`.

Usage: python3 papers/scripts/factor_tables.py [build/bin/ldlpgs]   (prints Markdown to stdout)
Run it on an idle machine: the timings are medians, but two cores shared with a build are not.
Each table is preceded by what its numbers depend on: the commit, the BLAS that CHOLMOD
supernodal called (`ldlpgs bench`'s `blas`) and the load average before and after it.
TABLES (default verify,mechanisms,matrices,blas) selects tables; `blas` times CHOLMOD supernodal
on a few problems with the system's BLAS and, through LD_LIBRARY_PATH, with Debian's reference
BLAS and LAPACK.
"""
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LDLPGS = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "bin", "ldlpgs")
MATRICES = os.path.join(ROOT, "tests", "data", "matrices")
FAMILIES = ["chain", "tree", "ladder", "loop", "heavy", "grid", "star"]
# Constraints giving dim(H) about 90, 250, 1000, 4800 and 11300 (3.8-4 rows per constraint):
# the talk's sizes (20-60 constraints) and 300-3000.
SIZES = [22, 63, 253, 1265, 3000]
# Debian's reference BLAS and LAPACK (libblas3, liblapack3): first on the library path, they
# replace the libblas.so.3 and liblapack.so.3 alternatives (OpenBLAS once build.sh installed it).
REFERENCE_BLAS = "/usr/lib/x86_64-linux-gnu/blas:/usr/lib/x86_64-linux-gnu/lapack"
# The problems where CHOLMOD supernodal has dense fronts worth BLAS-3 (the most flops per row).
BLAS_PROBLEMS = ["heavy:63", "heavy:253", "grid:1265", "bcsstk13.mtx", "dwt_992.mtx", "bcsstk02.mtx"]


def run(*args, env=None):
    out = subprocess.run([LDLPGS, *args, "--json"], capture_output=True, text=True, env=env)
    if out.returncode not in (0, 1):
        sys.exit(f"{' '.join(args)}: {out.stderr.strip()}")
    return json.loads(out.stdout)


def matrices():
    names = sorted(f for f in os.listdir(MATRICES) if f.endswith(".mtx") and f != "Pd.mtx")
    return [os.path.join(MATRICES, f) for f in names]


def commit():
    out = subprocess.run(["git", "-C", ROOT, "describe", "--always", "--dirty"], capture_output=True, text=True)
    return out.stdout.strip() or "unknown"


def load():
    return "/".join(f"{x:.2f}" for x in os.getloadavg())


def measured(title, table):
    """Prints the table's title, runs table() (which returns the BLAS it saw, or None) and states
    the conditions of the measurement under it."""
    print(f"### {title}\n")
    before = load()
    blas = table()
    print(f"\nMeasured at {commit()}, load average (1/5/15 min) {before} before and {load()} after"
          + (f", BLAS {blas}" if blas else "") + ".\n")


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
          " Eigen simplicial | Eigen dense | ratio CHOLMOD | ratio CHOLMOD supernodal | ratio Eigen simplicial |"
          " ratio dense | fastest other factor / ours |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    blas, kernels = set(), set()
    for p in problems:
        b = run("bench", p)
        blas.add(b["blas"])
        kernels.add(b["kernels"])
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
              f" | {cell('eigen_dense')} | {ratio('cholmod')} | {ratio('cholmod_supernodal')}"
              f" | {ratio('eigen_simplicial')} | {ratio('eigen_dense')} | {fastest_other(b)} |")
    return ", ".join(sorted(blas)) + "; our kernels " + ", ".join(sorted(kernels))


# The target's measure: the fastest factorization of CHOLMOD simplicial, CHOLMOD supernodal and Eigen
# simplicial (same permutation) over ours, and which one it was.
def fastest_other(b):
    others = [(b[f"{n}_factor_us"], label) for n, label in
              (("cholmod", "CHOLMOD"), ("cholmod_supernodal", "CHOLMOD supernodal"), ("eigen_simplicial", "Eigen"))
              if b[f"{n}_factor_us"] is not None]
    if not others:
        return "-"
    us, label = min(others)
    return f"{us / b['factor_us']:.2f}x ({label})"


def blas_table():
    """CHOLMOD supernodal's factor time with each BLAS, on the same problems, one after the other."""
    print("| matrix | n | flops | ldlpgs factor us | CHOLMOD supernodal factor us, reference BLAS |"
          " CHOLMOD supernodal factor us, system BLAS | reference / system | ratio CHOLMOD supernodal (factor + solve), reference |"
          " ratio, system |")
    print("|---|---|---|---|---|---|---|---|---|")
    reference_env = dict(os.environ, LD_LIBRARY_PATH=REFERENCE_BLAS)
    seen = set()
    for p in BLAS_PROBLEMS:
        if p.endswith(".mtx"):
            p = os.path.join(MATRICES, p)
        ref, sys_ = run("bench", p, env=reference_env), run("bench", p)
        seen.update([f"reference {ref['blas']}", f"system {sys_['blas']}"])

        def total(b, name):
            return b[f"{name}factor_us"] + b[f"{name}solve_us"]

        s = "cholmod_supernodal_"
        print(f"| {sys_['matrix']} | {sys_['n']} | {sys_['flops']:.3g} | {sys_['factor_us']:.1f}"
              f" | {ref[s + 'factor_us']:.1f} | {sys_[s + 'factor_us']:.1f} | {ref[s + 'factor_us'] / sys_[s + 'factor_us']:.2f}x"
              f" | {total(ref, s) / total(ref, ''):.2f}x | {total(sys_, s) / total(sys_, ''):.2f}x |")
    return "; ".join(sorted(seen))


if __name__ == "__main__":
    which = os.environ.get("TABLES", "verify,mechanisms,matrices,blas").split(",")
    if "verify" in which:
        measured("Verification against CHOLMOD (ordering best, the default)", verify_table)
    if "mechanisms" in which:
        # heavy at 1265 constraints is a dense n = 5000 matrix: seconds per factorization for
        # every solver, minutes for the medians; `ldlpgs bench heavy:1265` times it alone.
        measured("Speed on mechanisms (ordering best, the default; medians; factor + solve in microseconds)",
                 lambda: bench_table([f"{f}:{m}" for m in SIZES for f in FAMILIES
                                      if not (f == "heavy" and m >= 1265)]))
    if "matrices" in which:
        measured("Speed on the test matrices (ordering best, the default; blocks auto)", lambda: bench_table(matrices()))
    if "blas" in which:
        measured("CHOLMOD supernodal: reference BLAS against the system's (ordering best, the default)", blas_table)
