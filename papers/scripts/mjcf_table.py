#!/usr/bin/env python3
"""The MJCF models' table of papers/physics.md ("MJCF models: Gymnasium's"): each model stepped
by ldlpgs (ldl-pgs, the talk and schur schedules) and by MuJoCo's own step (mujoco-testspeed,
Debian's libmujoco-samples) in one run, one row per model, as markdown.

    python3 papers/scripts/mjcf_table.py build/bin/ldlpgs tests/data/mjcf/gymnasium/*.xml

Columns: what ldlpgs dropped (it steps without it), its largest joint error (m, rad) over the
run and its deepest contact (m), its step time (us, median), MuJoCo's (us, its mean over the
run). Steps: --steps (default 2000) of each model's own timestep.
"""
import argparse
import json
import re
import subprocess
import sys


def ours(program, model, steps, schedule):
    run = subprocess.run([program, "step", model, "--steps", str(steps), "--schedule", schedule, "--json"],
                         capture_output=True, text=True)
    if run.returncode != 0:
        return None, run.stderr.strip().splitlines()[-1] if run.stderr.strip() else "exit %d" % run.returncode
    dropped = run.stderr.strip().split(": dropped: ", 1)
    return json.loads(run.stdout), dropped[1] if len(dropped) == 2 else ""


def mujoco_us(model, steps):
    run = subprocess.run(["mujoco-testspeed", model, str(steps), "1"], capture_output=True, text=True)
    match = re.search(r"Time per step\s*:\s*([0-9.]+) ms", run.stdout)
    return 1000 * float(match.group(1)) if match else float("nan")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("program")
    parser.add_argument("models", nargs="+")
    parser.add_argument("--steps", type=int, default=2000)
    args = parser.parse_args()
    print("| model | dropped | talk: joints (m / rad), contact (m), step (us) | schur: the same | MuJoCo step (us) |")
    print("|---|---|---|---|---|")
    for model in args.models:
        cells, dropped = [], ""
        for schedule in ("talk", "schur"):
            result, dropped = ours(args.program, model, args.steps, schedule)
            if result is None:
                cells.append("refused: " + dropped)
                continue
            cells.append("%.2g / %.2g, %.2g, %.1f" % (result["position_error_max_m"], result["angular_error_max_rad"],
                                                    result["penetration_max_m"], result["step_us"]))
        name = model.rsplit("/", 1)[-1]
        print("| %s | %s | %s | %s | %.1f |" % (name, dropped or "nothing", cells[0], cells[1],
                                              mujoco_us(model, args.steps)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
