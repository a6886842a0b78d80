#!/usr/bin/env python3
"""Peers side by side (papers/peers.md), from `ldlpgs peers SCENE --json` files.

Usage: python3 papers/scripts/plot_peers.py PEERS.json [PEERS.json ...] --out-dir DIR [--table]
Files of the same scene (repeated runs) are merged: each engine's step time is the median of its
runs' medians (the errors are deterministic, the same in every run).
Writes DIR/peers-SCENE.png for each file: log-log, x = median wall time of one whole step (us),
y = the largest joint separation after the run (left) and the largest distance of any body from
the reference trajectory (right; our direct solver at a 16x smaller timestep, or, for a scene
it cannot run, the second reference, MuJoCo's RK4 at that timestep), one point per engine and
solver. A run that blew up is an 'x' above the plot's data. --table prints the markdown table
of papers/peers.md on stdout (with the distance from the RK4 reference, rk4_trajectory_error_m,
when the files have it, and from our direct solver at the scene's own timestep,
direct_same_step_error_m).
"""
import argparse
import json
import os

from debian_python import require

matplotlib = require("matplotlib", "python3-matplotlib")

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after the backend)

FLOOR = 1e-16  # an error of exactly 0 cannot be drawn on a log axis
STYLE = {  # family -> colour; variant -> marker
    "ldlpgs": "#d62728", "ode": "#1f77b4", "bullet": "#2ca02c", "mujoco": "#9467bd"}
MARKERS = ["o", "s", "^", "D", "v"]


# The names of `ldlpgs peers --json` before the CLI vocabulary (docs/cli.md): runs kept from then
# read as they would be printed now.
OLD_NAMES = {"separation": "position_error_m", "trajectory_error": "trajectory_error_m",
             "rk4_trajectory_error": "rk4_trajectory_error_m", "direct_same_step_error": "direct_same_step_error_m",
             "timestep": "timestep_s", "seconds": "simulated_s", "references_apart": "references_apart_m"}


def renamed(data):
    def rename(d):
        return {OLD_NAMES.get(k, k): v for k, v in d.items()}
    data = rename(data)
    data["engines"] = [rename(r) for r in data["engines"]]
    return data


def family(engine):
    return engine.split("-")[0]


def draw(ax, rows, key, ylabel):
    finite = [r[key] for r in rows if r.get(key) is not None]
    top = 10 * max(finite + [1e-3])
    seen = {}
    for r in rows:
        f = family(r["engine"])
        marker = MARKERS[seen.setdefault(f, [0])[0] % len(MARKERS)]
        seen[f][0] += 1
        y = r.get(key)
        blew = not r["finite"]
        if y is None and not blew:
            continue  # no reference to compare to
        ax.plot([r["step_us"]], [top if blew else max(y, FLOOR)], color=STYLE.get(f, "#7f7f7f"),
                marker="x" if blew else marker, markersize=7, linestyle="none", label=r["engine"])
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("median wall time per step (us)")
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", linewidth=0.3)


def plot(data, path):
    rows = [r for r in data["engines"] if "skipped" not in r]
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    draw(left, rows, "position_error_m", "largest joint separation at the end (m)")
    if data.get("reference") or not data.get("rk4_reference"):
        draw(right, rows, "trajectory_error_m", "largest distance from the reference (m)")
    else:
        draw(right, rows, "rk4_trajectory_error_m", "largest distance from MuJoCo RK4, dt / 16 (m)")
    right.legend(fontsize=7, loc="best")
    fig.suptitle(f"{data['scene']}: {data['bodies']} bodies, {data['rows']} rows, "
                 f"{data['steps']} steps of {data['timestep_s']} s")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def fmt(row, key):
    """A number, "blew up" (the run's state went non-finite) or "-" (no reference to compare to)."""
    if not row["finite"]:
        return "blew up"
    x = row.get(key)
    return "-" if x is None else format(x, ".2e")


def table(files):
    keys = ["position_error_m", "trajectory_error_m"]
    heads = ["separation (m)", "trajectory (m)"]
    if any("rk4_reference" in data for data in files):  # files written since the RK4 reference
        keys.append("rk4_trajectory_error_m")
        heads.append("vs RK4 (m)")
    keys.append("direct_same_step_error_m")
    heads.append("vs direct (m)")
    print("| scene | engine | step (us) | " + " | ".join(heads) + " |")
    print("|---|---|---:|" + "---:|" * len(heads))
    for data in files:
        for r in data["engines"]:
            if "skipped" in r:
                print(f"| {data['scene']} | {r['engine']} | skipped: {r['skipped']} |" + " |" * len(heads))
            else:
                cells = " | ".join(fmt(r, k) for k in keys)
                print(f"| {data['scene']} | {r['engine']} | {r['step_us']:.1f} | {cells} |")


def merge(runs):
    """One scene's runs as one: the first run's rows, step_us the median over the runs."""
    data = runs[0]
    for i, row in enumerate(data["engines"]):
        if "skipped" not in row:
            times = sorted(run["engines"][i]["step_us"] for run in runs)
            row["step_us"] = times[len(times) // 2]
            row["runs"] = len(times)
    return data


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+")
    parser.add_argument("--out-dir", required=True)
    parser.add_argument("--table", action="store_true")
    args = parser.parse_args()
    scenes = {}
    for name in args.files:
        with open(name) as f:
            data = renamed(json.load(f))
        scenes.setdefault(data["scene"], []).append(data)
    files = [merge(runs) for runs in scenes.values()]
    for data in files:
        plot(data, os.path.join(args.out_dir, f"peers-{data['scene']}.png"))
    if args.table:
        table(files)


if __name__ == "__main__":
    main()
