#!/usr/bin/env python3
"""The scale scene of papers/factor.md: a hub carrying N arms on ball joints.

Usage: python3 papers/scripts/star_scene.py N OUT.json

A 10 kg hub (inertia 1 kg m^2 about each axis) on a ball joint to the ground at (0, 5, 0); N
arms of 1 kg (inertia 0.1) around it at radius 2 m, heights 5, 5.1 and 5.2 m in turn, each on a
ball joint to the hub at the midpoint between them. With `--no-shatter` every constraint shares
the hub, so H_0 is dense: 3 N + 3 rows (3003 for N = 1000). Then, e.g.,
`/usr/bin/time build/bin/ldlpgs spy OUT.json --no-shatter` and
`build/bin/ldlpgs step OUT.json --no-shatter --steps 2`.
"""
import json
import math
import sys


def scene(n):
    bodies = [{"name": "ground", "static": True, "position": [0, 0, 0]},
              {"name": "hub", "mass": 10, "inertia": [1, 1, 1], "position": [0, 5, 0]}]
    constraints = [{"type": "ball", "bodies": ["ground", "hub"], "anchor": [0, 5, 0]}]
    for i in range(n):
        a = 2 * math.pi * i / n
        at = [2 * math.cos(a), 5 + 0.1 * (i % 3), 2 * math.sin(a)]
        bodies.append({"name": f"arm{i}", "mass": 1, "inertia": [0.1, 0.1, 0.1], "position": at})
        constraints.append({"type": "ball", "bodies": ["hub", f"arm{i}"],
                            "anchor": [0.5 * at[0], 0.5 * (at[1] + 5), 0.5 * at[2]]})
    return {"name": f"star-{n}", "gravity": [0, -9.81, 0], "timestep": 0.01, "bodies": bodies,
            "constraints": constraints}


def main():
    if len(sys.argv) != 3 or not sys.argv[1].isdigit() or int(sys.argv[1]) < 1:
        sys.exit("usage: python3 papers/scripts/star_scene.py N OUT.json (N a positive integer)")
    with open(sys.argv[2], "w") as out:
        json.dump(scene(int(sys.argv[1])), out)


if __name__ == "__main__":
    main()
