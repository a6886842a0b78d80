# ldlpgs.analyze / Factor against dense NumPy (the solution, A[P][:, P] = L D L^T, the inertia
# by Sylvester's law) and ldlpgs.verify against `ldlpgs verify --json` on the same matrix.
import numpy as np
import pytest
import scipy.sparse

import ldlpgs
from cli import MATRICES, PATTERN, REAL, matrix, run, run_json, same

ORDERINGS = ["meca", "amd", "amd-scalar", "natural"]
EPS = np.finfo(float).eps


def dense_tolerance(a):
    """Two backward-stable solutions differ by about cond(A) eps (as factor/verify.h allows)."""
    return max(1e-10, 10 * EPS * np.linalg.cond(a, 1))


@pytest.mark.parametrize("ordering", ORDERINGS)
@pytest.mark.parametrize("name", REAL)
def test_solve_matches_dense(name, ordering):
    a = matrix(name).tocsc()
    dense = a.toarray()
    f = ldlpgs.analyze(a, ordering=ordering).factorize(a)
    assert f.status in ("ok", "indefinite")
    rng = np.random.default_rng(1)
    b = rng.standard_normal(a.shape[0])
    b_copy = b.copy()
    x = f.solve(b)
    np.testing.assert_array_equal(b, b_copy)  # b is not changed
    x_dense = np.linalg.solve(dense, b)
    assert np.abs(x - x_dense).max() / np.abs(x_dense).max() <= dense_tolerance(dense)
    backward = np.abs(dense @ x - b).max() / (np.abs(dense).sum(1).max() * np.abs(x).max() + np.abs(b).max())
    assert backward < 1e-14
    # many right-hand sides: each column as solved alone; f(b) and solve_A are solve
    bs = rng.standard_normal((a.shape[0], 3))
    xs = f(bs)
    assert xs.shape == bs.shape
    for k in range(3):
        np.testing.assert_allclose(xs[:, k], f.solve_A(bs[:, k]), rtol=1e-13, atol=1e-300)
    assert f(np.zeros((a.shape[0], 0))).shape == (a.shape[0], 0)


@pytest.mark.parametrize("regularization", [0.0, 1e-3])
@pytest.mark.parametrize("name", ["bcsstk01.mtx", "494_bus.mtx", "pts5ldd03.mtx"])
def test_factors_reproduce_matrix(name, regularization):
    a = matrix(name).tocsc()
    f = ldlpgs.analyze(a, ordering="meca").factorize(a, regularization=regularization)
    p, l, d = f.P(), f.L(), f.D()
    assert scipy.sparse.isspmatrix_csc(l) and l.shape == a.shape
    assert sorted(p) == list(range(a.shape[0]))
    np.testing.assert_array_equal(l.diagonal(), 1)
    assert scipy.sparse.triu(l, 1).count_nonzero() == 0
    assert l.nnz == f.nnz_L  # every block dense, diagonal included
    ap = a.toarray()[np.ix_(p, p)]
    ap += regularization * np.diag(np.diag(ap))
    ldl = (l @ scipy.sparse.diags(d) @ l.T).toarray()
    assert np.abs(ldl - ap).max() <= 1e-13 * np.abs(ap).max() * max(1.0, np.abs(d).max() / np.abs(d).min()) ** 0.5


def test_inertia_of_indefinite_matrix():
    a = matrix("bcsstk01.mtx").tocsc()
    eigenvalues = np.linalg.eigvalsh(a.toarray())
    shift = 0.5 * (eigenvalues[20] + eigenvalues[21])  # between two eigenvalues: 21 negative
    shifted = (a - shift * scipy.sparse.identity(a.shape[0])).tocsc()
    f = ldlpgs.analyze(shifted).factorize(shifted)
    assert f.status == "indefinite"
    assert f.inertia == (a.shape[0] - 21, 21, 0)  # Sylvester: the inertia of D is A's
    x = f.solve(np.ones(a.shape[0]))
    np.testing.assert_allclose(shifted @ x, np.ones(a.shape[0]), atol=1e-8)
    assert "negative" in f.message or "indefinite" in f.message


def test_singular_matrix_status():
    a = scipy.sparse.csc_matrix(np.array([[1.0, 1.0], [1.0, 1.0]]))
    f = ldlpgs.analyze(a, blocks=1).factorize(a)
    assert f.status == "zero pivot"
    with pytest.raises(ValueError, match="zero"):
        f.solve(np.ones(2))
    assert f.factorize(a, regularization=1e-2).status == "ok"  # [[1.01, 1], [1, 1.01]]


def test_factorize_again_with_new_values():
    a = matrix("494_bus.mtx").tocsc()
    f = ldlpgs.analyze(a)
    assert f.status is None and f.inertia is None
    for scale in (1.0, 3.0):
        b = np.arange(a.shape[0], dtype=float)
        x = f.factorize(scale * a).solve(b)
        np.testing.assert_allclose((scale * a) @ x, b, rtol=0, atol=1e-9 * np.abs(b).max())


@pytest.mark.parametrize("ordering", ["meca", "amd-scalar", "metis"])
@pytest.mark.parametrize("name", REAL)
def test_verify_matches_program(name, ordering):
    # The program exits 1 when the factorizations disagree; its JSON is compared either way.
    cli = run_json("verify", MATRICES / name, "--ordering", ordering, expect=None)
    py = ldlpgs.verify(matrix(name), ordering=ordering, name=name)
    differences = same(py, cli)
    assert not differences, "\n".join(differences)
    assert py["ok"]


def test_verify_blocks_and_tolerance():
    name = "494_bus.mtx"
    cli = run_json("verify", MATRICES / name, "--blocks", 2, "--tolerance", 1e-11, "--backward-tolerance", 1e-13)
    py = ldlpgs.verify(matrix(name), blocks=2, tolerance=1e-11, backward_tolerance=1e-13, name=name)
    assert not same(py, cli)


@pytest.mark.parametrize("name", PATTERN)
def test_verify_pattern_file_through_mmread(name):
    # scipy.io.mmread gives a pattern file's entries the value 1; ldlpgs.mmread the program's values
    cli = run_json("verify", MATRICES / name)
    differences = same(ldlpgs.verify(ldlpgs.mmread(str(MATRICES / name)), name=name), cli)
    assert not differences, "\n".join(differences)


@pytest.mark.parametrize("name", REAL)
def test_mmread_is_scipys_on_real_files(name):
    ours, scipys = ldlpgs.mmread(str(MATRICES / name)), matrix(name).tocsc()
    assert ours.shape == scipys.shape and abs(ours - scipys).max() == 0
