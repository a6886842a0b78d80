# ldlpgs.study: its rows are the program's (`ldlpgs order --json --cholmod`, `ldlpgs sweep
# --json`); on a LocalCluster of two worker processes (README's Dask session, run here as written)
# the tables equal the serial ones; a bad matrix file fails alone; a worker killed in the middle
# of a run loses no row and duplicates none; the command line writes the report's data format.
import doctest
import functools
import json
import os
import re
import signal
import subprocess
import sys

import pandas as pd
import pytest

import ldlpgs
from ldlpgs import study
from cli import MATRICES, SOURCE, run_json

SMALL = ["bcsstk01.mtx", "can___24.mtx", "LFAT5.mtx", "494_bus.mtx"]
# a grid of 40 tasks: every dimension of the sweep, a failing direct on nothing (all equality scenes)
GRID = dict(scenes=["chain-100", "heavy-chain-10-1000"], solvers=["pgs", "ldl-pgs", "direct"], iterations=[1, 8],
            timesteps=[None, 0.005], mass_ratios=[None, 1e4], seconds=0.5)


def without_times(frame):
    return frame.drop(columns=[c for c in study.TIME_COLUMNS if c in frame.columns])


def bad_matrix(tmp_path):
    path = tmp_path / "bad.mtx"
    path.write_text("%%MatrixMarket matrix coordinate real symmetric\n3 3 1\n1 1 oops\n")
    return path


@pytest.fixture(scope="module")
def session():
    """README's Dask session, run from the project root as a doctest: its globals (the client)
    and the doctest's outcome."""
    readme = (SOURCE / "README.md").read_text()
    block = re.search(r"A Dask session.*?```python\n(.*?)```", readme, re.S)
    assert block, "README.md has no Dask session"
    test = doctest.DocTestParser().get_doctest(block.group(1), {}, "README.md", "README.md", 0)
    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE)
    cwd = os.getcwd()
    os.chdir(SOURCE)
    try:
        runner.run(test, clear_globs=False)
    finally:
        os.chdir(cwd)
    client = test.globs.get("client")
    yield runner.summarize(verbose=False), client
    if client is not None:
        client.close()


def test_readme_session(session):
    result, client = session
    assert result.attempted >= 3 and result.failed == 0, "README.md's Dask session gave another output (above)"
    assert len(client.scheduler_info()["workers"]) == 2


def test_orderings_rows_are_the_programs():
    frame = study.orderings([MATRICES / "bcsstk01.mtx"])
    cli = run_json("order", MATRICES / "bcsstk01.mtx", "--cholmod")
    assert list(frame["ordering"]) == [r["ordering"] for r in cli["results"]]
    for row, r in zip(study.records(frame), cli["results"]):
        for key in study.ORDERINGS_COLUMNS:
            if key in r and key != "ordering_ms":
                assert row[key] == r[key], f"{r['ordering']}: {key}"
        assert (row["matrix"], row["n"], row["blocks"], row["task_error"]) == ("bcsstk01.mtx", cli["n"], cli["blocks"], None)


def test_sweep_rows_are_the_programs():
    frame = study.sweep(["heavy-chain-10-1000", "four-bar"], iterations=[1, 4], seconds=0.5)
    cli = run_json("sweep", "--cases", "heavy-chain-10-1000,four-bar", "--iterations", "1,4", "--seconds", "0.5")
    rows = study.records(frame)
    assert [(r["scene"], r["solver"], r["iterations"]) for r in rows] == \
           [(p["scene"], p["solver"], p["iterations"]) for p in cli["points"]]
    for row, point in zip(rows, cli["points"]):
        for key, value in point.items():
            if key != "solve_us":
                assert row[key] == value, f"{point['scene']} {point['solver']} {point['iterations']}: {key}"
        assert row["simulated_s"] == cli["simulated_s"] and row["task_error"] is None


def test_cluster_table_equals_serial(session, tmp_path):
    _, client = session
    matrices = [MATRICES / m for m in SMALL] + [MATRICES / "Pd.mtx", bad_matrix(tmp_path)]
    serial = study.orderings(matrices)
    assert serial["task_error"].notna().sum() == 2  # Pd.mtx (not symmetric) and bad.mtx
    pd.testing.assert_frame_equal(without_times(study.orderings(matrices, client=client)), without_times(serial))
    serial = study.sweep(**GRID)
    assert len(serial) == 2 * 2 * 2 * (2 * 2 + 1) and serial["task_error"].isna().all()
    assert set(serial["mass_ratio"]) == {1.0, 1000.0, 1.0e4}  # the scenes' own (chain-100's links are alike), 1e4
    pd.testing.assert_frame_equal(without_times(study.sweep(**GRID, client=client)), without_times(serial))


@pytest.mark.parametrize("on_cluster", [False, True])
def test_bad_matrix_fails_alone(session, tmp_path, on_cluster):
    bad = bad_matrix(tmp_path)
    with pytest.raises(ldlpgs.InputError) as raised:
        ldlpgs.mmread(str(bad))
    frame = study.orderings([MATRICES / "bcsstk01.mtx", bad, MATRICES / "can___24.mtx"],
                            client=session[1] if on_cluster else None)
    failed = frame[frame["task_error"].notna()]
    assert list(failed["matrix"]) == ["bad.mtx"] and list(failed["task_error"]) == [str(raised.value)]
    done = frame[frame["task_error"].isna()]
    assert list(done.groupby("matrix", sort=False).size().items()) == [("bcsstk01.mtx", len(ldlpgs.orderings())),
                                                                      ("can___24.mtx", len(ldlpgs.orderings()))]
    assert done["nnz_L"].notna().all() and (done["nnz_L"] == done["cholmod_nnz_L"]).all()


def test_bad_scene_fails_alone():
    with pytest.raises(ldlpgs.InputError) as raised:
        ldlpgs.Simulation("no-such-scene")
    frame = study.sweep(["chain-10", "no-such-scene", "box-stack-1000"], solvers=["ldl-pgs", "direct"],
                        iterations=[1], seconds=0.1)
    failed = frame[frame["task_error"].notna()]
    assert list(zip(failed["scene"], failed["solver"])) == [("no-such-scene", "ldl-pgs"), ("no-such-scene", "direct"),
                                                            ("box-stack-1000", "direct")]
    assert list(failed["task_error"])[:2] == [str(raised.value)] * 2
    assert "direct" in list(failed["task_error"])[2]  # the direct solver takes no contacts
    done = frame[frame["task_error"].isna()]
    assert list(zip(done["scene"], done["solver"])) == [("chain-10", "ldl-pgs"), ("chain-10", "direct"),
                                                        ("box-stack-1000", "ldl-pgs")]
    assert done["position_error_max_m"].notna().all() and not done["failed"].any()


def killing_task(marker, *args):
    """study.sweep_task, except that the first run of the grid's fourth task kills the worker
    process running it (SIGKILL: as a crash or the kernel's OOM killer would), before its row."""
    if args == KILLED and not os.path.exists(marker):
        open(marker, "w").close()
        os.kill(os.getpid(), signal.SIGKILL)
    return study.sweep_task(*args)


KILLED = ("chain-100", "pgs", 8, 0.005, None, 0.5)


def test_killed_worker_loses_nothing(session, tmp_path):
    _, client = session
    arguments = [(scene, solver, its, dt, ratio, GRID["seconds"]) for scene in GRID["scenes"]
                 for dt in GRID["timesteps"] for ratio in GRID["mass_ratios"] for solver in GRID["solvers"]
                 for its in ((1,) if solver == "direct" else GRID["iterations"])]
    assert KILLED in arguments
    client.wait_for_workers(2)
    pids = set(client.run(os.getpid).values())
    marker = tmp_path / "killed"
    rows = study.run_tasks(functools.partial(killing_task, str(marker)), arguments, client)
    assert marker.exists(), "no worker was killed"
    client.wait_for_workers(2)  # the nanny starts another worker process
    assert len(pids & set(client.run(os.getpid).values())) == 1, "the killed worker's process was not replaced"
    frame = study.table(rows, study.SWEEP_COLUMNS)
    assert frame["task_error"].isna().all(), list(frame["task_error"].dropna())
    # one row per task, in the tasks' order, each the serial run's
    pd.testing.assert_frame_equal(without_times(frame), without_times(study.sweep(**GRID)))


def python_study(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "ldlpgs.study", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd)


def test_command_line_on_a_scheduler_writes_the_report_format(session, tmp_path):
    _, client = session
    matrices = [MATRICES / "bcsstk01.mtx", bad_matrix(tmp_path)]
    p = python_study("--scheduler", client.scheduler.address, "--out-dir", tmp_path / "out", "--quiet",
                     "orderings", *matrices)
    assert p.returncode == 0, p.stderr
    assert re.fullmatch(r"orderings: 2 tasks \(1 failed\) in [0-9.]+ s, [0-9.]+ tasks/s, 2 workers at tcp://\S+\n",
                        p.stdout)
    data = json.loads((tmp_path / "out" / "orderings.json").read_text())
    # the report's data/*.json: the header, and keys sorted as nlohmann::json writes them
    assert list(data) == ["command", "ldlpgs_version", "records", "table"]
    assert (data["command"], data["ldlpgs_version"], data["table"]) == ("study", ldlpgs.__version__, "orderings")
    assert all(list(r) == sorted(r) for r in data["records"])
    def untimed(records):
        return [{k: v for k, v in r.items() if k not in study.TIME_COLUMNS} for r in records]
    serial = study.orderings(matrices)
    assert untimed(data["records"]) == untimed(study.records(serial))
    csv = (tmp_path / "out" / "orderings.csv").read_text().splitlines()
    assert csv[0] == ",".join(sorted(study.ORDERINGS_COLUMNS))
    assert csv[1].startswith('240,5140.0,48,5140.0,464,"meca",5140.0,"bcsstk01.mtx",48,464,"best",')
    back = pd.read_csv(tmp_path / "out" / "orderings.csv")[list(study.ORDERINGS_COLUMNS)]
    pd.testing.assert_frame_equal(without_times(back), without_times(serial), check_dtype=False)


@pytest.mark.parametrize("args, message", [
    (["sweep", "--scenes", "chain-10", "--iterations", "1,x"], "--iterations must be a comma-separated list of numbers"),
    (["sweep", "--scenes", "chain-10", "--solvers", "pgs,gauss"], "--solvers: unknown solver 'gauss'"),
    (["sweep", "--scenes", "chain-10", "--seconds", "0"], "--seconds must be finite and positive"),
    (["--scheduler", "no-such-scheme://x", "orderings", "a.mtx"], "--scheduler no-such-scheme://x: "),
    (["--workers", "0", "orderings", "a.mtx"], "--workers must be at least 1"),
    # nothing listens there: refused within the timeout, not after Dask's 30 s
    (["--scheduler", "tcp://127.0.0.1:9", "--connect-timeout-s", "1", "orderings", "a.mtx"],
     "--scheduler tcp://127.0.0.1:9: "),
    (["--connect-timeout-s", "0", "orderings", "a.mtx"], "--connect-timeout-s must be finite and positive"),
    (["--workers", "2", "--scheduler", "tcp://x:1", "orderings", "a.mtx"], "not allowed with argument"),
    (["sweep"], "the following arguments are required: --scenes"),
])
def test_command_line_bad_input_is_one_line(args, message, capsys):
    # (in this process: the command line is study.main's, and a python3 for each costs a second)
    with pytest.raises(SystemExit) as exit:
        study.main(args)
    out, err = capsys.readouterr()
    assert exit.value.code == 2 and out == ""
    assert err.count("\n") == 1 and message in err, err
