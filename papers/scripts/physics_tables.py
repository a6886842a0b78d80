#!/usr/bin/env python3
"""The tables of papers/physics.md, from `ldlpgs step --json` on the built-in scenes.

Usage: python3 papers/scripts/physics_tables.py [build/bin/ldlpgs]   (prints Markdown to stdout)
Timings are medians per step on this machine; run it on an idle machine.
"""
import json
import math
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LDLPGS = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "bin", "ldlpgs")
SCENES = ["pendulum", "chain-10", "heavy-chain-10-1000", "heavy-chain-10-1e6", "ragdoll", "four-bar",
          "rope-bridge", "tracked-vehicle", "multi-wheeled-vehicle"]
STEPS = "300"


def step(scene, *args):
    out = subprocess.run([LDLPGS, "step", scene, "--no-shatter", "--steps", STEPS, *args, "--json"], capture_output=True, text=True)
    if out.returncode not in (0, 1):
        sys.exit(f"{scene} {' '.join(args)}: {out.stderr.strip()}")
    return json.loads(out.stdout)


def solvers_table():
    print("| scene | bodies | constraints | rows | solver | solve us (median) | position error max (m) |"
          " angular error max (rad) | velocity residual max | energy initial -> final (J) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for scene in SCENES:
        for solver in ["pgs", "block-gs", "ldl-pgs"]:
            j = step(scene, "--solver", solver)
            final = "blew up" if j["energy_final_j"] is None else f"{j['energy_final_j']:.4g}"
            print(f"| {scene} | {j['bodies']} | {j['constraints']} | {j['rows']} | {solver} |"
                  f" {j['solve_us']:.1f} | {j['position_error_max_m']:.2e} | {j['angular_error_max_rad']:.2e} |"
                  f" {j['velocity_residual_max']:.2e} | {j['energy_initial_j']:.4g} -> {final} |")


def compliance_table():
    epsilons = ["0", "1e-12", "1e-10", "1e-8", "1e-6", "1e-4"]
    print("| scene | " + " | ".join(f"eps = {e}" for e in epsilons) + " |")
    print("|---|" + "---|" * len(epsilons))
    for scene in ["four-bar", "tracked-vehicle", "heavy-chain-10-1000", "heavy-chain-10-1e6", "rope-bridge"]:
        cells = []
        for e in epsilons:
            j = step(scene, "--solver", "ldl-pgs", "--compliance", e)
            cells.append("singular" if j["failed_steps"] else
                         f"{j['position_error_max_m']:.1e} / {j['angular_error_max_rad']:.0e}")
        print(f"| {scene} | " + " | ".join(cells) + " |")


def swinging_chain(angle):
    """heavy-chain-10-1000 turned by `angle` about z around its suspension point (the origin)."""
    with open(os.path.join(ROOT, "physics", "scenes", "heavy-chain-10-1000.json")) as f:
        scene = json.load(f)
    c, s = math.cos(angle), math.sin(angle)

    def turn(v):
        return [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]]

    for b in scene["bodies"]:
        b["position"] = turn(b["position"])
        if not b.get("static"):  # q <- rot_z(angle) q, quaternions [w, x, y, z]
            w, x, y, z = b["orientation"]
            cw, sw = math.cos(angle / 2), math.sin(angle / 2)
            b["orientation"] = [cw * w - sw * z, cw * x - sw * y, cw * y + sw * x, cw * z + sw * w]
    for con in scene["constraints"]:
        con["anchor"] = turn(con["anchor"])
    scene["name"] = f"heavy-chain-10-1000 at {angle} rad"
    path = os.path.join(tempfile.mkdtemp(), "swinging-heavy-chain.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    return path


def timestep_table():
    scene = swinging_chain(0.3)
    print("| timestep | direct | ldl-pgs | pgs (10 iterations) |")
    print("|---|---|---|---|")
    for dt in ["0.01", "0.005", "0.002", "0.001"]:
        cells = []
        for solver in ["direct", "ldl-pgs", "pgs"]:
            out = subprocess.run([LDLPGS, "step", scene, "--no-shatter", "--steps", str(round(2 / float(dt))), "--solver", solver,
                                  "--timestep", dt, "--json"], capture_output=True, text=True)
            j = json.loads(out.stdout)
            cells.append("blew up" if j["energy_final_j"] is None else f"{j['position_error_max_m']:.1e}")
        print(f"| {dt} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    print("### Solvers on the built-in scenes (10 iterations, 300 steps of the scene's timestep)\n")
    solvers_table()
    print("\n### Compliance: largest position error (m) / angular error (rad) of ldl-pgs, 300 steps\n")
    compliance_table()
    print("\n### Swinging 1:1000 chain (released at 0.3 rad), largest position error (m) over 2 s\n")
    timestep_table()
