# What the tests share: the program they compare the module with (LDLPGS_BIN, set by ctest), the
# test matrices (LDLPGS_MATRICES), and running the program for its JSON.
import json
import os
import pathlib
import subprocess

import pytest
import scipy.io

SOURCE = pathlib.Path(os.environ.get("LDLPGS_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
MATRICES = pathlib.Path(os.environ.get("LDLPGS_MATRICES", SOURCE / "tests" / "data" / "matrices"))
BIN = os.environ.get("LDLPGS_BIN", str(SOURCE / "build" / "bin" / "ldlpgs"))

# Small test matrices: real symmetric and general files, and a pattern file (values differ there:
# our reader gives CHOLMOD's, SciPy ones, so only pattern quantities are compared on it).
REAL = ["bcsstk01.mtx", "LFAT5.mtx", "bcsstk02.mtx", "494_bus.mtx", "pts5ldd03.mtx"]
PATTERN = ["can___24.mtx", "dwt_878.mtx"]


def matrix(name):
    return scipy.io.mmread(str(MATRICES / name))


def run(*args, expect=0):
    """The program's exit code and output; fails the test unless the exit code is `expect`."""
    p = subprocess.run([BIN, *map(str, args)], capture_output=True, text=True)
    if expect is not None and p.returncode != expect:
        pytest.fail(f"{BIN} {' '.join(map(str, args))}: exit {p.returncode}\n{p.stderr}")
    return p


def run_json(*args, expect=0):
    return json.loads(run(*args, "--json", expect=expect).stdout)


def same(py, cli, rel=1e-12, path="", skip=()):
    """Compares a module dict with the program's JSON: the same keys, values equal to round-off
    (numbers), exactly (everything else); lists and tuples alike. Returns the differences."""
    out = []
    if isinstance(cli, dict):
        if not isinstance(py, dict):
            return [f"{path}: {py!r} is not a dict"]
        if set(py) != set(cli):
            out.append(f"{path}: keys only in the module {sorted(set(py) - set(cli))}, "
                       f"only in the program {sorted(set(cli) - set(py))}")
        for k in set(py) & set(cli):
            if k not in skip:
                out += same(py[k], cli[k], rel, f"{path}.{k}", skip)
    elif isinstance(cli, list):
        if len(py) != len(cli):
            return [f"{path}: {py!r} != {cli!r}"]
        for i, (a, b) in enumerate(zip(py, cli)):
            out += same(a, b, rel, f"{path}[{i}]", skip)
    elif isinstance(cli, (int, float)) and not isinstance(cli, bool):
        if py != pytest.approx(cli, rel=rel, abs=1e-300):
            out.append(f"{path}: {py!r} != {cli!r}")
    elif py != cli:
        out.append(f"{path}: {py!r} != {cli!r}")
    return out
