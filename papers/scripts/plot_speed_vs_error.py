#!/usr/bin/env python3
"""Speed against error, one plot per case (papers/speed-vs-error.md), from `ldlpgs sweep --json`.

Usage: python3 papers/scripts/plot_speed_vs_error.py SWEEP.json OUTDIR
Writes OUTDIR/speed-vs-error-CASE.png for each case of SWEEP.json and lists them on stderr.

Log-log: x = median solve time per step (us), y = largest position error over the constraints
after the run (m). One curve per iterative solver through its iteration counts (each point
labelled with its count), direct as a single marker; a failed run (non-finite state, failed
factorization or energy blow-up: apps/sweep_case.cpp) is an 'x' at the top of the plot. The dotted
line is 1 cm, the stability study's threshold.
"""
import json
import os
import sys

from debian_python import require

matplotlib = require("matplotlib", "python3-matplotlib")

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after the backend)

STYLE = {"pgs": ("#1f77b4", "o"), "block-gs": ("#2ca02c", "s"), "ldl-pgs": ("#d62728", "^"),
         "direct": ("#000000", "D")}
CENTIMETRE = 0.01
FLOOR = 1e-16  # an error of exactly 0 cannot be drawn on a log axis


def by_case(points):
    """{scene: [points]} in the order the sweep ran them."""
    cases = {}
    for p in points:
        cases.setdefault(p["scene"], []).append(p)
    return cases


def clamp_value(points):
    """Where failed runs are drawn: a decade above the largest finite error (and above 1 cm)."""
    finite = [max(p["position_error_m"], FLOOR) for p in points if not p["failed"]]
    return 10 * max(finite + [CENTIMETRE])


def draw_solver(ax, solver, points, clamp):
    """One solver's points in iteration order: a line through the finite ones, an 'x' per failure."""
    colour, marker = STYLE.get(solver, ("#7f7f7f", "v"))
    points = sorted(points, key=lambda p: p["iterations"])
    ok = [p for p in points if not p["failed"]]
    if ok:
        xs, ys = [p["solve_us"] for p in ok], [max(p["position_error_m"], FLOOR) for p in ok]
        ax.plot(xs, ys, color=colour, marker=marker, markersize=5, linewidth=1,
                linestyle="none" if solver == "direct" else "-", label=solver)
        if solver != "direct":
            for p, x, y in zip(ok, xs, ys):
                ax.annotate(str(p["iterations"]), (x, y), xytext=(3, 3), textcoords="offset points",
                            fontsize=6, color=colour)
    failed = [p for p in points if p["failed"]]
    if failed:
        ax.plot([p["solve_us"] for p in failed], [clamp] * len(failed), color=colour, marker="x", markersize=7,
                linestyle="none", label=None if ok else f"{solver} (all failed)")
        if solver != "direct":
            for p in failed:
                ax.annotate(str(p["iterations"]), (p["solve_us"], clamp), xytext=(3, -9),
                            textcoords="offset points", fontsize=6, color=colour)


def plot_case(scene, points, path):
    """The speed-against-error plot of one case into `path` (PNG); a scene with contacts gets a
    second panel, the deepest contact over the run against the same times."""
    contacts = any((p.get("penetration_max_m") or 0) > 0 for p in points)
    fig, axes = plt.subplots(1, 2 if contacts else 1, figsize=(12.0 if contacts else 6.4, 4.6), squeeze=False)
    panels = [("position_error_m", "position error after the run (m)")]
    if contacts:
        panels.append(("penetration_max_m", "deepest contact during the run (m)"))
    solvers = list(dict.fromkeys(p["solver"] for p in points))
    for ax, (field, label) in zip(axes[0], panels):
        shown = [dict(p, position_error_m=p[field] if p[field] is not None else 0) for p in points]
        clamp = clamp_value(shown)
        for solver in solvers:
            draw_solver(ax, solver, [p for p in shown if p["solver"] == solver], clamp)
        ax.axhline(CENTIMETRE, color="#555555", linestyle=":", linewidth=1, label="1 cm")
        if any(p["failed"] for p in shown):
            ax.plot([], [], color="#555555", marker="x", linestyle="none", label=f"failed (drawn at {clamp:.0e} m)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("median solve time per step (us)")
        ax.set_ylabel(label)
        ax.grid(True, which="major", color="#dddddd", linewidth=0.5)
        ax.legend(fontsize=7, loc="best", frameon=True)
    axes[0][0].set_title(f"{scene}: speed against error (labels: iterations)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__.strip().splitlines()[2])
    with open(sys.argv[1]) as f:
        data = json.load(f)
    # `sweep --json` prints {"points": [...]}, report's data/sweep.json holds {"records": [...]}
    points = data["points"] if "points" in data else data["records"]
    out_dir = sys.argv[2]
    os.makedirs(out_dir, exist_ok=True)
    for scene, case_points in by_case(points).items():
        path = os.path.join(out_dir, f"speed-vs-error-{scene}.png")
        plot_case(scene, case_points, path)
        print(path, file=sys.stderr)


if __name__ == "__main__":
    main()
