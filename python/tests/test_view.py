# Simulation.record() and view() (python/view.cpp): the page the module writes for a run is the
# program's for the same run (`ldlpgs view SCENE --no-shatter`, which the module steps as), and
# a notebook shows it in an iframe.
import base64
import html
import json
import re

import numpy as np
import pytest

import ldlpgs
from cli import run

DATA = re.compile(r'<script id="ldlpgs-data" type="application/json">(.*?)</script>', re.S)


def data(page):
    return json.loads(DATA.search(page).group(1))


def test_the_program_writes_the_same_page(tmp_path):
    sim = ldlpgs.Simulation("box-stack-1000")
    sim.record()
    sim.step(60)
    page = sim.view()
    path = tmp_path / "program.html"
    run("view", "box-stack-1000", "--steps", 60, "--no-shatter", "--html-file", path)
    assert page.html == path.read_text()
    # 1 s of 1/60 s steps at 30 frames per second: every other step, and the start
    assert page.frames == 31
    d = data(page.html)
    assert d["frames"] == 31 and d["steps"] == 60
    last = np.frombuffer(base64.b64decode(d["positions"]), dtype=np.float32).reshape(31, -1, 3)[-1]
    np.testing.assert_allclose(last, sim.positions, atol=1e-6)


def test_notebook_shows_the_page_in_an_iframe(tmp_path):
    sim = ldlpgs.Simulation("pendulum")
    sim.record(frame_rate=10)
    sim.step(100)
    page = sim.view()
    shown = page._repr_html_()
    assert shown.startswith('<iframe srcdoc="') and '"' not in shown[len('<iframe srcdoc="'):shown.index('" style=')]
    assert html.unescape(shown[len('<iframe srcdoc="'):shown.index('" style=')]) == page.html
    page.save(tmp_path / "p.html")
    assert (tmp_path / "p.html").read_text() == page.html
    assert page.frames == 11  # 1 s at 10 frames per second, and the start


def test_without_record_the_current_pose():
    sim = ldlpgs.Simulation("chain-10")
    sim.step(5)
    d = data(sim.view().html)
    assert d["frames"] == 1 and d["steps"] == 0
    first = np.frombuffer(base64.b64decode(d["positions"]), dtype=np.float32).reshape(-1, 3)
    np.testing.assert_allclose(first, sim.positions, atol=1e-6)
    assert np.frombuffer(base64.b64decode(d["time"]), dtype=np.float32)[0] == pytest.approx(sim.time)


def test_bad_arguments():
    sim = ldlpgs.Simulation("pendulum")
    with pytest.raises(ldlpgs.InputError, match="frame_rate"):
        sim.record(frame_rate=0)
    with pytest.raises(ldlpgs.InputError, match="max_frames"):
        sim.record(max_frames=1)
    with pytest.raises(ldlpgs.InputError, match="cannot write the HTML file"):
        sim.view().save("/nonexistent-dir/p.html")
