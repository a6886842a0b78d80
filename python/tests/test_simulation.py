# ldlpgs.Simulation against `ldlpgs step SCENE --no-shatter --trace-file --json`: the same final
# positions and orientations of every body (the module does not shatter), the same largest
# constraint error; and the state arrays' shapes, setters and per-row errors.
import csv
import json
import os
import pathlib

import numpy as np
import pytest

import ldlpgs
from cli import SOURCE, run, run_json

STEPS = 40


def program_final_pose(scene, tmp_path, *options):
    trace = tmp_path / "trace.csv"
    summary = run_json("step", scene, "--steps", STEPS, "--no-shatter", "--trace-file", trace, *options)
    with open(trace) as f:
        rows = [r for r in csv.DictReader(f) if int(r["step"]) == STEPS]
    positions = {r["body"]: [float(r[k]) for k in ("x", "y", "z")] for r in rows}
    orientations = {r["body"]: [float(r[k]) for k in ("qw", "qx", "qy", "qz")] for r in rows}
    return summary, positions, orientations


CASES = [("chain-10", "ldl-pgs"), ("chain-10", "pgs"), ("four-bar", "ldl-pgs"), ("ragdoll", "ldl-pgs"),
         ("pendulum", "direct"), ("tracked-vehicle", "block-gs"), ("rope-bridge", "ldl-pgs")]


@pytest.mark.parametrize("scene,solver", CASES)
def test_trajectory_matches_program(scene, solver, tmp_path):
    summary, positions, orientations = program_final_pose(scene, tmp_path, "--solver", solver)
    sim = ldlpgs.Simulation(scene, solver=solver)
    report = sim.step(STEPS)
    assert report["failed_steps"] == summary["failed_steps"] == 0
    assert len(sim.body_names) == summary["bodies"]
    for i, body in enumerate(sim.body_names):
        np.testing.assert_allclose(sim.positions[i], positions[body], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(sim.orientations[i], orientations[body], rtol=1e-12, atol=1e-12)
    assert report["position_error_max_m"] == pytest.approx(summary["position_error_max_m"], rel=1e-9, abs=1e-15)
    assert report["angular_error_max_rad"] == pytest.approx(summary["angular_error_max_rad"], rel=1e-9, abs=1e-15)
    assert sim.energy == pytest.approx(summary["energy_final_j"], rel=1e-9)


def test_scene_file_dict_and_options(tmp_path):
    path = SOURCE / "physics" / "scenes" / "four-bar.json"
    summary, positions, _ = program_final_pose(path, tmp_path, "--iterations", 4, "--timestep", 0.005,
                                               "--post-stabilize", 0, "--compliance", 1e-6)
    for scene in (str(path), path, json.loads(path.read_text())):
        sim = ldlpgs.Simulation(scene, iterations=4, timestep=0.005, post_stabilize=0, compliance=1e-6)
        sim.step(STEPS)
        assert sim.time == pytest.approx(STEPS * 0.005)
        for i, body in enumerate(sim.body_names):
            np.testing.assert_allclose(sim.positions[i], positions[body], rtol=1e-12, atol=1e-12)


def test_mjcf_model(tmp_path):
    model = "/usr/share/mujoco/model/humanoid/humanoid.xml"
    if not os.path.exists(model):
        pytest.skip("libmujoco-samples not installed")
    _, positions, _ = program_final_pose(model, tmp_path)
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing dropped: its joint dynamics and actuators are converted
        sim = ldlpgs.Simulation(model)
    sim.step(STEPS)
    # dynamic bodies only: the program's trace gives MuJoCo's massless world body a NaN position
    # (its whole-body centre of mass divides by a zero mass)
    for i, body in enumerate(sim.body_names):
        if not sim.static[i]:
            np.testing.assert_allclose(sim.positions[i], positions[body], rtol=1e-12, atol=1e-12)


GYMNASIUM = SOURCE / "tests" / "data" / "mjcf" / "gymnasium"


def test_controls_drive_the_actuators():
    sim = ldlpgs.Simulation(str(GYMNASIUM / "reacher.xml"))
    assert sim.actuator_names == ["actuator0", "actuator1"]  # unnamed in the file: kind and index
    np.testing.assert_array_equal(sim.controls, [0, 0])
    pushed = ldlpgs.Simulation(str(GYMNASIUM / "reacher.xml"))
    pushed.controls = np.array([0.5, 0.0])
    np.testing.assert_array_equal(pushed.controls, [0.5, 0])
    sim.step(10)
    pushed.step(10)
    # the first link turns about +z (the motor's joint axis) when pushed, and not when not
    turned = lambda s: np.arctan2(s.positions[1][1], s.positions[1][0])
    assert turned(pushed) > turned(sim) + 0.05
    with pytest.raises(ldlpgs.InputError, match="3 given, the model has 2 actuators"):
        sim.controls = [0, 0, 0]
    with pytest.raises(ldlpgs.InputError, match=r"actuator .* \(1\): 2 outside its ctrlrange \[-1, 1\]"):
        sim.controls = [0, 2]
    with pytest.raises(ldlpgs.InputError, match="not a finite number"):
        sim.controls = [np.nan, 0]


def test_unmodelled_dynamics_raise_unless_allowed(tmp_path):
    model = tmp_path / "tendon.xml"
    model.write_text('<mujoco><worldbody><body><joint name="j"/><geom size=".1"/></body></worldbody>'
                     '<tendon><fixed name="t" limited="true" range="-1 1"><joint joint="j" coef="1"/></fixed>'
                     '</tendon></mujoco>')
    with pytest.raises(ldlpgs.InputError, match='tendon "t"'):
        ldlpgs.Simulation(str(model))
    with pytest.warns(UserWarning, match='tendon "t": its range'):
        ldlpgs.Simulation(str(model), allow_dropped=True).step(2)


def test_state_arrays():
    sim = ldlpgs.Simulation("chain-10")
    n = len(sim.body_names)
    sim.step(5)
    assert sim.positions.shape == (n, 3) and sim.orientations.shape == (n, 4) and sim.velocities.shape == (n, 6)
    np.testing.assert_allclose(np.linalg.norm(sim.orientations, axis=1), 1, rtol=1e-12)
    assert not sim.velocities[sim.static].any()
    assert sim.impulses.shape == (sim.num_rows,)
    e = sim.constraint_errors()
    assert e["error"].shape == e["angular"].shape == e["constraint"].shape == (sim.num_rows,)
    assert e["error"][~e["angular"]].max() == e["position_max"]
    # writing the state back: moving every dynamic body up by 1 m keeps the chain's errors
    p = sim.positions
    p[~sim.static] += [0, 1, 0]
    sim.positions = p
    np.testing.assert_array_equal(sim.positions, p)
    v = np.zeros((n, 6))
    sim.velocities = v
    sim.apply_force("link9", [1.0, 0, 0])
    sim.gravity = [0, 0, 0]
    sim.step(1)
    assert sim.velocities[sim.body_names.index("link9"), 0] > 0


def test_shapes_and_contacts():
    # A 2 kg unit cube added in code onto a ground plane, under y-up gravity: after it settles, four
    # contact points at its bottom corners, normals along y, and normal impulses that carry its
    # weight per step (m g dt), the analytic value.
    scene = {"name": "cube", "timestep": 0.01,
             "bodies": [{"name": "ground", "static": True, "position": [0, 0, 0]},
                        {"name": "cube", "mass": 2, "inertia": [1 / 3, 1 / 3, 1 / 3], "position": [0, 0.5, 0]}]}
    sim = ldlpgs.Simulation(scene)
    sim.add_shape("ground", "plane", normal=[0, 1, 0])
    sim.add_shape(1, "box", half_extents=[0.5, 0.5, 0.5], friction=0.8)
    report = sim.step(100)
    assert report["contacts_max"] == 4
    assert report["penetration_max_m"] <= 0.006
    c = sim.contacts
    assert c["position"].shape == (4, 3) and c["impulse"].shape == (4, 3)
    np.testing.assert_allclose(np.abs(c["normal"][:, 1]), 1, atol=1e-12)
    np.testing.assert_allclose(np.abs(c["position"][:, [0, 2]]), 0.5, atol=1e-6)
    assert abs(c["impulse"][:, 0].sum() - 2 * 9.81 * 0.01) < 1e-6
    with pytest.raises(ldlpgs.InputError, match="radius"):
        sim.add_shape(1, "sphere", radius=-1)
    with pytest.raises(ldlpgs.InputError, match="plane"):
        sim.add_shape(1, "plane", normal=[0, 1, 0])
    with pytest.raises(ldlpgs.InputError, match="unknown shape type"):
        sim.add_shape(1, "cone")
