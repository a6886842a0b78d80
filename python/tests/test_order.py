# ldlpgs.order and ldlpgs.cholmod_counts against `ldlpgs order --json --cholmod --perm-out`: the
# same orderings, permutations, nnz(L), flops, block fill and block flops, and CHOLMOD's counts.
import numpy as np
import pytest
import scipy.io
import scipy.sparse

import ldlpgs
from cli import MATRICES, PATTERN, REAL, matrix, run_json


def read_perms(directory, names):
    return {n: np.loadtxt(directory / f"{n}.perm", dtype=int, ndmin=1) for n in names}


@pytest.mark.parametrize("name", REAL + PATTERN)
def test_order_matches_program(name, tmp_path):
    cli = run_json("order", MATRICES / name, "--cholmod", "--perm-dir", tmp_path)
    py = ldlpgs.order(matrix(name), cholmod=True)
    assert list(py) == [r["ordering"] for r in cli["results"]]
    perms = read_perms(tmp_path, list(py))
    for r in cli["results"]:
        p = py[r["ordering"]]
        missing = set(r) - set(p)
        assert not missing, f"{r['ordering']}: the program's fields {sorted(missing)} are not in the module's"
        for key, value in r.items():
            if key != "ordering_ms":  # a measurement
                assert p[key] == value, f"{r['ordering']}: {key}"
        assert p["ordering_ms"] >= 0
        np.testing.assert_array_equal(p["perm"], perms[r["ordering"]])


@pytest.mark.parametrize("name", ["bcsstk01.mtx", "can___24.mtx"])
def test_cholmod_counts(name, tmp_path):
    cli = run_json("order", MATRICES / name, "--cholmod", "--perm-dir", tmp_path)
    a = matrix(name)
    for r in cli["results"]:
        perm = np.loadtxt(tmp_path / f"{r['ordering']}.perm", dtype=int)
        counts = ldlpgs.cholmod_counts(a, perm)
        cholmod_fields = sorted(k for k in r if "cholmod" in k)
        assert [counts[k.replace("cholmod_", "")] for k in cholmod_fields] == [r[k] for k in cholmod_fields]
        # our own count is CHOLMOD's (block orderings: dense blocks that CHOLMOD finds dense too)
        assert counts == {"nnz_L": r["nnz_L"], "flops": r["flops"]}


def test_blocks_arguments(tmp_path):
    a = matrix("494_bus.mtx")
    cli = run_json("order", MATRICES / "494_bus.mtx", "--blocks", 4)
    py = ldlpgs.order(a, blocks=4)
    assert [py[r["ordering"]]["block_flops"] for r in cli["results"]] == [r["block_flops"] for r in cli["results"]]
    sizes = [3, 5] * 61 + [6]  # sums to 494
    (tmp_path / "sizes").write_text("\n".join(map(str, sizes)) + "\n")
    from_file = ldlpgs.order(a, blocks=str(tmp_path / "sizes"), orderings="meca,amd")
    from_list = ldlpgs.order(a, blocks=sizes, orderings=["meca", "amd"])
    cli = run_json("order", MATRICES / "494_bus.mtx", "--blocks", tmp_path / "sizes", "--ordering", "meca,amd")
    for r in cli["results"]:
        for py in (from_file, from_list):
            assert (py[r["ordering"]]["nnz_L"], py[r["ordering"]]["block_fill_edges"]) == (r["nnz_L"], r["block_fill_edges"])


def test_lower_triangle_and_formats():
    a = matrix("bcsstk01.mtx")
    full = ldlpgs.order(a, orderings="meca,metis")
    for other in (ldlpgs.order(scipy.sparse.tril(a), orderings="meca,metis", lower=True),
                  ldlpgs.order(scipy.sparse.csr_matrix(a), orderings="meca,metis"),
                  ldlpgs.order(scipy.sparse.coo_matrix(a).astype(np.float32).astype(np.float64), orderings="meca,metis")):
        for name in full:
            assert other[name]["nnz_L"] == full[name]["nnz_L"]
            np.testing.assert_array_equal(other[name]["perm"], full[name]["perm"])


def test_orderings_listed():
    names = ldlpgs.orderings()
    assert "meca" in names and "amd-scalar" in names
    assert list(ldlpgs.order(matrix("LFAT5.mtx"))) == list(names)


def test_certify_adds_the_optimal_order_as_the_program_does(tmp_path):
    # a ring of 20 constraints of 1 to 6 rows: the certificate's optimum is below every ordering's
    sizes = [1, 3, 4, 5, 6] * 4
    offsets = np.cumsum([0] + sizes)
    n = offsets[-1]
    dense = np.zeros((n, n))
    for b in range(len(sizes)):
        c = (b + 1) % len(sizes)
        dense[offsets[b]:offsets[b + 1], offsets[c]:offsets[c + 1]] = -1
    dense += dense.T
    dense += np.diag(np.abs(dense).sum(axis=1) + 1)
    a = scipy.sparse.csc_matrix(dense)
    mtx, blocks = tmp_path / "ring.mtx", tmp_path / "ring.blocks"
    scipy.io.mmwrite(str(mtx), a, symmetry="symmetric")
    blocks.write_text("".join(f"{s}\n" for s in sizes))
    cli = run_json("order", mtx, "--blocks", blocks, "--ordering", "best", "--certify", "--perm-dir", tmp_path)
    py = ldlpgs.order(a, blocks=sizes, orderings="best", certify=True)
    assert list(py) == ["best", "optimal"] == [r["ordering"] for r in cli["results"]]
    optimal = py["optimal"]
    assert optimal["chosen"] == "certify" and optimal["certified_optimal"] and optimal["optimum_proved"]
    assert optimal["block_flops"] == optimal["lower_bound_block_flops"] < py["best"]["block_flops"]
    assert optimal["block_flops"] == cli["results"][1]["block_flops"]
    np.testing.assert_array_equal(optimal["perm"], read_perms(tmp_path, ["optimal"])["optimal"])


def test_certify_and_chosen_match_program():
    name = REAL[0]
    cli = run_json("order", MATRICES / name, "--ordering", "best,meca", "--certify")
    py = ldlpgs.order(matrix(name), orderings="best,meca", certify=True)
    for r in cli["results"]:
        p = py[r["ordering"]]
        for key in ("chosen", "block_flops", "certified_optimal", "lower_bound_block_flops"):
            assert p[key] == r[key], f"{r['ordering']}: {key}"
        assert p["optimum_proved"] == cli["optimum_proved"]
    assert py["best"]["block_flops"] <= py["meca"]["block_flops"]
    f = ldlpgs.analyze(matrix(name))
    assert f.ordering == "best" and f.chosen == py["best"]["chosen"]
    with pytest.raises(ValueError, match="certify_time_limit_s"):
        ldlpgs.order(matrix(name), certify=True, certify_time_limit_s=-1)
