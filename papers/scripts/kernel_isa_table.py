#!/usr/bin/env python3
"""Our factorization with the AVX2 and the AVX-512 kernels, alternated over three rounds: the
median factor time of each (`ldlpgs bench PROBLEM --ordering meca-w --kernels ISA --json`).
Usage: python3 papers/scripts/kernel_isa_table.py build/bin/ldlpgs (papers/factor.md, "Eight
lanes with AVX-512"). Needs a CPU with AVX-512F."""
import json
import statistics
import subprocess
import sys

PROBLEMS = ["chain:300", "ladder:300", "tree:600", "grid:625", "star:120", "heavy:63", "heavy:253",
            "tests/data/matrices/bcsstk13.mtx"]
ISAS = ["avx2", "avx512"]


def factor_us(binary, problem, isa):
    args = [binary, "bench", problem, "--ordering", "meca-w", "--kernels", isa, "--json"]
    if problem.endswith(".mtx"):
        args += ["--blocks", "auto"]
    out = subprocess.run(args, capture_output=True, text=True, check=True)
    return json.loads(out.stdout)["factor_us"]


def main():
    binary = sys.argv[1]
    times = {}
    for _ in range(3):
        for problem in PROBLEMS:
            for isa in ISAS:
                times.setdefault((problem, isa), []).append(factor_us(binary, problem, isa))
    print("| problem | avx2 factor us | avx512 factor us | avx2 / avx512 |")
    print("|---|---:|---:|---:|")
    for problem in PROBLEMS:
        a, b = (statistics.median(times[(problem, isa)]) for isa in ISAS)
        print(f"| {problem} | {a:.2f} | {b:.2f} | {a / b:.2f} |")


if __name__ == "__main__":
    main()
