"""Tasks per second of ldlpgs.study serial, on a LocalCluster of 1 and of 2 worker processes, as
the tasks grow (papers/studies-on-dask.md). Runs each `python3 -m ldlpgs.study` command REPEATS
times and prints a Markdown table of the medians, with the load average before each workload.

Usage, from the project root (the package in build/python):
    PYTHONPATH=build/python /usr/bin/python3 papers/scripts/study_scaling.py [REPEATS]
"""
import glob
import os
import re
import statistics
import subprocess
import sys

SWEEP = ["sweep", "--solvers", "pgs,block-gs,ldl-pgs,direct", "--iterations", "1,2,4,8", "--mass-ratios", "1,10,100,1000"]
# The tasks grow (chain-10, -100, -1000: 1, 13, 120 ms each serially), then their number (ten
# times chain-100's), then the orderings of the test matrices (one of them, bcsstk13, half the time).
WORKLOADS = [(f"sweep, chain-{n}", [*SWEEP, "--scenes", f"chain-{n}"]) for n in (10, 100, 1000)] + [
    ("sweep, chain-100, 40 mass ratios", [*SWEEP[:-1], ",".join(str(r) for r in range(1, 41)), "--scenes", "chain-100"]),
    ("orderings, tests/data/matrices", ["orderings", *sorted(glob.glob("tests/data/matrices/*.mtx"))])]
WHERE = [("serial", []), ("1 worker", ["--workers", "1"]), ("2 workers", ["--workers", "2"])]
SUMMARY = re.compile(r"(\d+) tasks \((\d+) failed\) in ([0-9.]+) s, ([0-9.]+) tasks/s")
READY = re.compile(r"ready in ([0-9.]+) s")


def run(args):
    """(tasks, seconds, tasks per second, cluster start-up seconds or None) of one command."""
    p = subprocess.run([sys.executable, "-m", "ldlpgs.study", "--quiet", *args], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"study_scaling.py: {' '.join(args[:4])} ...: exit {p.returncode}\n{p.stderr}")
    tasks, _, seconds, rate = SUMMARY.search(p.stdout).groups()
    ready = READY.search(p.stderr)
    return int(tasks), float(seconds), float(rate), float(ready.group(1)) if ready else None


def main():
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    print(f"| workload | tasks | load before | {' | '.join(f'{w}: tasks/s (s)' for w, _ in WHERE)} | "
          "cluster start-up s (1, 2 workers) |")
    print("|---|---|---|" + "---|" * len(WHERE) + "---|")
    for name, args in WORKLOADS:
        load = os.getloadavg()[0]
        cells, startups = [], []
        for _, where in WHERE:
            runs = [run([*where, *args]) for _ in range(repeats)]
            tasks = runs[0][0]
            cells.append(f"{statistics.median(r[2] for r in runs):.1f} ({statistics.median(r[1] for r in runs):.2f})")
            if where:
                startups.append(f"{statistics.median(r[3] for r in runs):.1f}")
        print(f"| {name} | {tasks} | {load:.1f} | {' | '.join(cells)} | {', '.join(startups)} |", flush=True)


if __name__ == "__main__":
    main()
