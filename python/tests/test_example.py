# examples/compare_orderings.py runs (so that it cannot rot): a table of every ordering and a PNG.
import os
import subprocess
import sys

import pytest

import ldlpgs
from cli import MATRICES, SOURCE


def test_compare_orderings_example(tmp_path):
    pytest.importorskip("matplotlib", reason="python3-matplotlib is not installed (the example draws with it)")
    out = tmp_path / "flops.png"
    p = subprocess.run([sys.executable, str(SOURCE / "examples" / "compare_orderings.py"), str(MATRICES / "can___24.mtx"),
                        "--plot-file", str(out)], capture_output=True, text=True, env=dict(os.environ, MPLBACKEND="Agg"))
    assert p.returncode == 0, p.stderr
    for name in ldlpgs.orderings():
        assert f"\n{name} " in p.stdout
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
