# Bad input raises a ValueError (ldlpgs.InputError, ldlpgs.ArgumentError) carrying our message,
# never a crash: non-square, unsymmetric (naming the entry), wrong-sized b, unknown ordering, and
# the other checks the library leaves to its callers. Where the program takes the same input, its
# message is the module's.
import numpy as np
import pytest
import scipy.sparse

import ldlpgs
from cli import MATRICES, SOURCE, matrix, run

A = matrix("bcsstk01.mtx").tocsc()


def every_matrix_entry_point(a):
    """Each function that reads a matrix, called on `a`."""
    good = A
    return [lambda: ldlpgs.order(a), lambda: ldlpgs.analyze(a), lambda: ldlpgs.verify(a),
            lambda: ldlpgs.cholmod_counts(a, np.arange(a.shape[0])),
            lambda: ldlpgs.analyze(good).factorize(a)]


def test_error_classes():
    assert issubclass(ldlpgs.InputError, ValueError) and issubclass(ldlpgs.ArgumentError, ValueError)


@pytest.mark.parametrize("call", range(5))
def test_not_square(call):
    with pytest.raises(ValueError, match=r"A is 3 x 4: not square"):
        every_matrix_entry_point(scipy.sparse.random(3, 4, density=0.5, format="csc"))[call]()


@pytest.mark.parametrize("call", range(5))
def test_unsymmetric_values(call):
    a = scipy.sparse.csc_matrix(np.array([[4.0, 1.0, 0], [2.0, 4.0, 0], [0, 0, 4.0]]))
    with pytest.raises(ValueError, match=r"not symmetric: A\[1, 0\] = 2 but A\[0, 1\] = 1"):
        every_matrix_entry_point(a)[call]()


def test_unsymmetric_pattern():
    a = scipy.sparse.csc_matrix(np.array([[4.0, 0, 0], [0, 4.0, 0], [0, 1.0, 4.0]]))
    with pytest.raises(ValueError, match=r"A\[2, 1\] = 1 is stored but A\[1, 2\] is not"):
        ldlpgs.order(a)
    upper = scipy.sparse.csc_matrix(np.array([[4.0, 1.0], [0, 4.0]]))
    with pytest.raises(ValueError, match=r"A\[0, 1\] = 1 is stored but A\[1, 0\] is not"):
        ldlpgs.analyze(upper)
    # an explicit zero is an entry of the pattern
    z = scipy.sparse.csc_matrix((np.array([4.0, 0.0, 4.0]), np.array([0, 1, 1]), np.array([0, 2, 3])), shape=(2, 2))
    with pytest.raises(ValueError, match=r"A\[1, 0\] = 0 is stored but A\[0, 1\] is not"):
        ldlpgs.order(z)
    # the lower triangle alone is fine with lower=True, and the upper one is refused there
    assert ldlpgs.analyze(a, lower=True).factorize(a, lower=True).status == "ok"
    with pytest.raises(ValueError, match=r"A\[0, 1\] = 1 is above the diagonal"):
        ldlpgs.order(upper, lower=True)


def test_program_refuses_the_same_unsymmetric_matrix(tmp_path):
    a = scipy.sparse.coo_matrix(np.array([[4.0, 1.0], [2.0, 4.0]]))
    scipy.io.mmwrite(str(tmp_path / "u.mtx"), a, symmetry="general")
    assert "not symmetric" in run("order", tmp_path / "u.mtx", expect=2).stderr
    with pytest.raises(ValueError, match="not symmetric"):
        ldlpgs.order(a)


@pytest.mark.parametrize("bad,message", [
    (np.eye(3), "must be a scipy.sparse matrix, got ndarray"),
    (scipy.sparse.csc_matrix(np.eye(2) * (1 + 1j)), "complex"),
    (scipy.sparse.csc_matrix(np.array([[np.nan, 0], [0, 1.0]])), r"not finite: A\[0, 0\] = nan"),
    (scipy.sparse.csc_matrix((0, 0)), "empty"),
])
def test_bad_matrix(bad, message):
    with pytest.raises(ValueError, match=message):
        ldlpgs.order(bad)


@pytest.mark.parametrize("b", [np.ones(47), np.ones(49), np.ones((47, 2)), np.ones((48, 2, 2)), np.ones(())])
def test_wrong_sized_b(b):
    f = ldlpgs.analyze(A).factorize(A)
    with pytest.raises(ValueError, match=r"b must have 48 rows"):
        f.solve(b)


def test_bad_b_kind():
    f = ldlpgs.analyze(A).factorize(A)
    with pytest.raises(ValueError, match="must be dense"):
        f.solve(scipy.sparse.csc_matrix(np.ones((48, 1))))
    with pytest.raises(ValueError, match="complex"):
        f.solve(np.ones(48) * 1j)
    with pytest.raises(ValueError, match="not an array of numbers"):
        f.solve(["x"] * 48)


def test_unknown_ordering():
    cli = run("order", MATRICES / "bcsstk01.mtx", "--ordering", "nope", expect=2).stderr.strip()
    for call in (lambda: ldlpgs.order(A, orderings="meca,nope"), lambda: ldlpgs.order(A, orderings=["nope"]),
                 lambda: ldlpgs.analyze(A, ordering="nope"), lambda: ldlpgs.verify(A, ordering="nope"),
                 lambda: ldlpgs.Simulation("chain-10", ordering="nope")):
        with pytest.raises(ldlpgs.InputError) as e:
            call()
        assert cli == f"ldlpgs: {e.value}"  # the program's message


@pytest.mark.parametrize("blocks,message", [
    ([1] * 47, "blocks sum to 47 rows, A has 48"), ([0] + [1] * 48, r"blocks\[0\] = 0"),
    (0, ""), (True, "got a bool"), (2.5, "got float"), ("/no/such/partition", "/no/such/partition"),
])
def test_bad_blocks(blocks, message):
    with pytest.raises(ValueError, match=message):
        ldlpgs.analyze(A, blocks=blocks)


def test_bad_permutation():
    with pytest.raises(ValueError, match="47 entries"):
        ldlpgs.cholmod_counts(A, np.arange(47))
    with pytest.raises(ValueError, match=r"entry 1 of the permutation, 0, is repeated"):
        ldlpgs.cholmod_counts(A, np.zeros(48, dtype=int))
    with pytest.raises(ValueError, match="outside 0..47"):
        ldlpgs.cholmod_counts(A, np.arange(1, 49))
    # the value itself, not clipped to n (it said 48 for 1000)
    with pytest.raises(ValueError, match=r"entry 47 of the permutation, 1000, is outside 0..47"):
        ldlpgs.cholmod_counts(A, np.r_[np.arange(47), 1000])
    # floats are refused, not truncated to integers
    with pytest.raises(ValueError, match="integers, got dtype float64"):
        ldlpgs.cholmod_counts(A, np.arange(48) + 0.5)


@pytest.mark.parametrize("keyword", [{"tolerance": np.nan}, {"backward_tolerance": np.inf}, {"per_condition": -1.0}])
def test_bad_verify_tolerance(keyword):
    with pytest.raises(ValueError, match="must be finite and >= 0"):
        ldlpgs.verify(A, **keyword)


def test_factor_misuse():
    f = ldlpgs.analyze(A)
    with pytest.raises(ldlpgs.ArgumentError, match=r"factorize\(A\) first"):
        f.solve(np.ones(48))
    for method in (f.L, f.D):
        with pytest.raises(ValueError, match="first"):
            method()
    with pytest.raises(ldlpgs.ArgumentError, match="the symbolic phase analyzed 48"):
        f.factorize(matrix("bcsstk02.mtx"))
    other = A.copy().tolil()
    other[0, 47] = other[47, 0] = 1e-3  # a new entry: another pattern of the same size
    with pytest.raises(ldlpgs.ArgumentError, match="column 0 stores other entries than the pattern"):
        f.factorize(other.tocsc())
    with pytest.raises(ValueError, match="regularization"):
        f.factorize(A, regularization=-1)


@pytest.mark.parametrize("mass", [float("nan"), float("inf"), 10**400, object(), "a\ud800"])
def test_scene_dict_that_is_not_json(mass):
    # NaN and inf (JSON has none), an integer no double holds, a value of no JSON type, a lone
    # surrogate: ldlpgs.InputError in one line, not the JSON parser's RuntimeError or a traceback
    scene = {"name": "s", "bodies": [{"name": "a", "mass": mass, "inertia": [1, 1, 1]}], "constraints": []}
    with pytest.raises(ldlpgs.InputError, match="<dict>: not a scene in JSON terms") as e:
        ldlpgs.Simulation(scene)
    assert "\n" not in str(e.value) and "Traceback" not in str(e.value) and "At:" not in str(e.value)


def test_scene_dict_numpy_scalars():
    # np.int64 is no JSON type, but is the number it holds
    scene = {"name": "s", "constraints": [],
             "bodies": [{"name": "a", "mass": np.int64(2), "inertia": [1.0, 1.0, 1.0], "position": [0, 0, 0],
                         "orientation": [1, 0, 0, 0]}]}
    assert ldlpgs.Simulation(scene).body_names == ["a"]


def test_simulation_errors():
    with pytest.raises(ValueError, match="no-such-scene: no such file and no built-in scene"):
        ldlpgs.Simulation("no-such-scene")
    with pytest.raises(ValueError, match=r"unknown body"):
        ldlpgs.Simulation(str(SOURCE / "tests" / "data" / "scenes" / "unknown_body.json"))
    with pytest.raises(ValueError, match=r"syntax_error.json"):
        ldlpgs.Simulation(str(SOURCE / "tests" / "data" / "scenes" / "syntax_error.json"))
    with pytest.raises(ValueError, match=r"solver=gauss: unknown \(known: pgs"):
        ldlpgs.Simulation("chain-10", solver="gauss")
    with pytest.raises(ValueError, match="direct solves equality constraints only"):
        ldlpgs.Simulation("ragdoll", solver="direct")
    for kwargs, message in [({"iterations": 0}, "iterations"), ({"timestep": -1.0}, "timestep"),
                            ({"baumgarte": 2.0}, "baumgarte"), ({"compliance": float("nan")}, "compliance"),
                            ({"schedule": "x"}, "schedule"), ({"post_stabilize": -2}, "post_stabilize"),
                            ({"post_stabilize_own_factor": True, "post_stabilize_refactor": True}, "exclude each other")]:
        with pytest.raises(ValueError, match=message):
            ldlpgs.Simulation("chain-10", **kwargs)
    sim = ldlpgs.Simulation("chain-10")
    with pytest.raises(ValueError, match=r"positions must have shape \(11, 3\)"):
        sim.positions = np.zeros((10, 3))
    with pytest.raises(ValueError, match="no body named"):
        sim.apply_force("nobody", [0, 0, 0])
    with pytest.raises(ValueError):
        sim.apply_force(99, [0, 0, 0])
    with pytest.raises(ValueError):
        sim.orientations = np.zeros((11, 4))  # not unit quaternions
    with pytest.raises(ValueError):
        sim.velocities = np.ones((11, 6))  # the ground is static
    with pytest.raises(ValueError, match="steps"):
        sim.step(-1)
