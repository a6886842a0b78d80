#!/usr/bin/env python3
"""The contact tables of papers/physics.md, from `ldlpgs step --json` on the scenes with contacts.

Usage: python3 papers/scripts/contact_tables.py [build/bin/ldlpgs] [TABLE]   (prints Markdown to stdout)
TABLE: solvers (default: every table), orderings or noshapes. Timings are medians per step on
this machine; run it on an idle machine.
"""
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LDLPGS = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "bin", "ldlpgs")
TABLE = sys.argv[2] if len(sys.argv) > 2 else "all"
HUMANOID = "/usr/share/mujoco/model/humanoid/humanoid.xml"
# (scene, steps): 2 s of each (the humanoid's file steps 5 ms)
SCENES = [("box-stack-1000", 120), ("pyramid-10", 120), ("ball-chain-20-1000", 600),
          ("tracked-vehicle-on-ground", 120), ("multi-wheeled-vehicle-on-ground", 120), (HUMANOID, 400)]
CONFIGS = [("ldl-pgs, contacts in the factor (default)", []),
           ("ldl-pgs, contacts as rows, block-gs schedule", ["--factor-contacts-after", "0"]),
           ("ldl-pgs, contacts as rows, the talk's schedule", ["--factor-contacts-after", "0",
                                                               "--contact-schedule", "talk"]),
           ("pgs", ["--solver", "pgs"])]


def step(scene, steps, *args):
    out = subprocess.run([LDLPGS, "step", scene, "--steps", str(steps), *args, "--json"], capture_output=True,
                         text=True)
    if out.returncode not in (0, 1) or not out.stdout:
        return None
    return json.loads(out.stdout)


def name(scene):
    return "humanoid (MJCF)" if scene == HUMANOID else scene


def solvers_table():
    print("| scene | solver | step us (median) | contacts (most) | deepest contact (m) | joint error max (m) |"
          " symbolic phases | failure |")
    print("|---|---|---|---|---|---|---|---|")
    for scene, steps in SCENES:
        for label, args in CONFIGS:
            j = step(scene, steps, *args)
            if j is None:
                print(f"| {name(scene)} | {label} | | | | | | refused |")
                continue
            failure = j["failure"] or ""
            print(f"| {name(scene)} | {label} | {j['step_us']:.0f} | {j['contacts_max']} |"
                  f" {j['penetration_max_m']:.3g} | {j['position_error_max_m']:.2e} | {j['symbolic_analyses']} |"
                  f" {failure} |")


def orderings_table():
    # the symbolic phase runs again whenever the set of factored contacts changes
    print("| scene | ordering | symbolic phases | their time, all (us) | per phase (us) | step us (median) |")
    print("|---|---|---|---|---|---|")
    for scene, steps in [("pyramid-10", 300), ("box-stack-1000", 300)]:
        for ordering in ["natural", "amd", "metis", "mda", "meca", "best"]:
            j = step(scene, steps, "--ordering", ordering)
            per = j["symbolic_us"] / max(1, j["symbolic_analyses"])
            print(f"| {scene} | {ordering} | {j['symbolic_analyses']} | {j['symbolic_us']:.0f} | {per:.0f} |"
                  f" {j['step_us']:.0f} |")


def noshapes_table():
    # what scenes without shapes cost: compare with the same table from a build before contacts
    print("| scene | step us (median) | solve us (median) |")
    print("|---|---|---|")
    for scene in ["chain-10", "heavy-chain-10-1000", "ragdoll", "tracked-vehicle", "mechanism-50"]:
        j = step(scene, 300)
        print(f"| {scene} | {j['step_us']:.1f} | {j['solve_us']:.1f} |")


if TABLE in ("all", "solvers"):
    solvers_table()
    print()
if TABLE in ("all", "orderings"):
    orderings_table()
    print()
if TABLE in ("all", "noshapes"):
    noshapes_table()
