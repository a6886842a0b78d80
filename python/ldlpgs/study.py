"""Studies as tables of independent tasks, run one after another or on a Dask cluster.

Two studies, each a pandas DataFrame with one row per result:

- orderings(matrices): every ordering on every Matrix Market file, the columns of the report's
  orderings table (`ldlpgs report`, data/orderings.csv): nnz_L, flops, block_fill_edges,
  block_flops, ordering_ms and CHOLMOD's cholmod_nnz_L, cholmod_flops for the same permutation.
  A task is one matrix.
- sweep(scenes, solvers, iterations, timesteps, mass_ratios): every combination stepped as
  `ldlpgs sweep` steps it (ldlpgs.sweep_run, the program's own code): solve_us, position and
  angular errors, failed and failure. A task is one scene configuration.

Serial by default; with client= a dask.distributed.Client the tasks run on its cluster. A task
that raises fails alone: its row (one per task) carries the error's text in task_error and the
other tasks complete. A worker that dies takes nothing with it: Dask runs its tasks again
elsewhere and each task gives its rows once. write_table() writes a table as the report writes
its data (NAME.json and NAME.csv).

From the command line (the summary's tasks per second are papers/studies-on-dask.md's):
    python3 -m ldlpgs.study orderings MATRIX.mtx ... [--orderings all] [--out-dir DIR]
    python3 -m ldlpgs.study sweep --scenes chain-10,four-bar [--solvers ...] [--iterations 1,4]
        [--timesteps 0.01] [--mass-ratios 1,1000] [--seconds 1] [--out-dir DIR]
    either with --workers N (a LocalCluster of N worker processes) or --scheduler ADDRESS.
"""
import argparse
import json
import math
import os
import sys
import time

import pandas as pd

import ldlpgs

# The columns and their types (pandas' nullable ones: a failed task's row has no values). The
# names are the program's (docs/cli.md, "Command-line vocabulary"); task_error is the study's own.
ORDERINGS_COLUMNS = {
    "matrix": "object", "n": "Int64", "blocks": "Int64", "ordering": "object", "chosen": "object",
    "nnz_L": "Int64", "flops": "float64", "block_fill_edges": "Int64", "block_flops": "float64",
    "ordering_ms": "float64", "cholmod_nnz_L": "Int64", "cholmod_flops": "float64", "task_error": "object",
}
SWEEP_COLUMNS = {
    "scene": "object", "solver": "object", "iterations": "Int64", "timestep_s": "float64",
    "mass_ratio": "float64", "simulated_s": "float64", "solve_us": "float64", "position_error_m": "float64",
    "position_error_max_m": "float64", "angular_error_rad": "float64", "angular_error_max_rad": "float64",
    "penetration_max_m": "float64", "failed": "boolean", "failure": "object", "task_error": "object",
}
# Measurements: they differ from run to run, everything else is determined by the task.
TIME_COLUMNS = ("ordering_ms", "solve_us")
SOLVERS = ("pgs", "block-gs", "ldl-pgs", "direct")  # `ldlpgs sweep`'s, in its order
ITERATIONS = (1, 4, 16, 64)  # the quick sweep's


def error_text(e):
    """An exception as one line: the library's message for its ValueErrors (InputError,
    ArgumentError), the type's name before anything else's."""
    text = str(e) if isinstance(e, ValueError) else f"{type(e).__name__}: {e}"
    return " ".join(text.split())


def ordering_task(matrix, orderings="all", max_block=6):
    """One matrix file: a row per ordering (ldlpgs.order with CHOLMOD's counts)."""
    name = os.path.basename(str(matrix))
    try:
        a = ldlpgs.mmread(str(matrix))
        blocks = len(ldlpgs.block_sizes(a, max_block=max_block))
        results = ldlpgs.order(a, orderings=orderings, max_block=max_block, cholmod=True)
    except Exception as e:  # the task fails alone, in its row
        return [{"matrix": name, "task_error": error_text(e)}]
    return [{"matrix": name, "n": a.shape[0], "blocks": blocks,
             **{k: v for k, v in r.items() if k in ORDERINGS_COLUMNS}} for r in results.values()]


def sweep_task(scene, solver, iterations, timestep, mass_ratio, seconds):
    """One scene configuration: its row of `ldlpgs sweep` (ldlpgs.sweep_run)."""
    try:
        point = ldlpgs.sweep_run(scene, solver, iterations, seconds, timestep, mass_ratio)
    except Exception as e:
        return [{"scene": str(scene), "solver": solver, "iterations": iterations, "timestep_s": timestep,
                 "mass_ratio": mass_ratio, "simulated_s": seconds, "task_error": error_text(e)}]
    return [{k: v for k, v in point.items() if k in SWEEP_COLUMNS}]


def run_tasks(task, arguments, client=None, error_row=lambda args, text: [{"task_error": text}]):
    """Every task(*args) for args in arguments (a list of rows each), the rows in the arguments'
    order. With a Dask client on its cluster (pure=False: a task runs once per call, not once per
    distinct arguments). A task that Dask gives up on (its workers died allowed-failures times,
    distributed.scheduler.allowed-failures) is the rows error_row(args, its error's text)."""
    if client is None:
        return [row for args in arguments for row in task(*args)]
    from distributed import wait
    futures = client.map(task, *zip(*arguments), pure=False) if arguments else []
    wait(futures)
    rows = []
    for args, future in zip(arguments, futures):
        if future.status == "finished":
            rows += future.result()
        else:
            rows += error_row(args, error_text(future.exception()))
    return rows


def table(rows, columns):
    """The rows (dicts, a missing key no value) as a DataFrame of these columns and types."""
    frame = pd.DataFrame.from_records(rows, columns=list(columns))
    return frame.astype(columns)


def orderings(matrices, orderings="all", max_block=6, client=None):
    """Every ordering on every matrix file (a task per matrix): a DataFrame of ORDERINGS_COLUMNS."""
    arguments = [(str(m), orderings, max_block) for m in matrices]
    rows = run_tasks(ordering_task, arguments, client,
                     lambda args, text: [{"matrix": os.path.basename(args[0]), "task_error": text}])
    return table(rows, ORDERINGS_COLUMNS)


def sweep(scenes, solvers=SOLVERS, iterations=ITERATIONS, timesteps=(None,), mass_ratios=(None,), seconds=1.0,
          client=None):
    """Every scene x solver x iterations x timestep x mass ratio (None: the scene's own timestep
    or ratio) stepped for `seconds` simulated (a task per combination; direct, whose iterations
    mean nothing, once at 1, as `ldlpgs sweep` runs it): a DataFrame of SWEEP_COLUMNS."""
    arguments = [(scene, solver, its, dt, ratio, seconds)
                 for scene in scenes for dt in timesteps for ratio in mass_ratios for solver in solvers
                 for its in ((1,) if solver == "direct" else iterations)]
    rows = run_tasks(sweep_task, arguments, client,
                     lambda args, text: [dict(zip(("scene", "solver", "iterations", "timestep_s", "mass_ratio",
                                                   "simulated_s"), args), task_error=text)])
    return table(rows, SWEEP_COLUMNS)


def _plain(value):
    """A table's value as JSON has it: None for a missing or non-finite number (as the program's
    JSON writes them), Python's int, float, bool, str."""
    if value is None or value is pd.NA:
        return None
    if hasattr(value, "item"):  # NumPy's scalars
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def records(frame):
    """The DataFrame's rows as the dicts the JSON holds (None where there is no value)."""
    return [{c: _plain(v) for c, v in zip(frame.columns, row)} for row in frame.itertuples(index=False)]


def write_table(frame, directory, name):
    """DIR/NAME.json ({"command": "study", "ldlpgs_version", "records", "table"}, keys sorted and
    one space of indent, as `ldlpgs report` writes data/*.json) and DIR/NAME.csv (a line per row,
    the columns in the order the JSON's sorted keys give them, strings quoted, no value empty: a
    NaN to pandas.read_csv). Returns the two paths."""
    os.makedirs(directory, exist_ok=True)
    rows = records(frame)
    json_path = os.path.join(directory, name + ".json")
    with open(json_path, "w") as f:
        json.dump({"ldlpgs_version": ldlpgs.__version__, "command": "study", "table": name, "records": rows},
                  f, indent=1, sort_keys=True, allow_nan=False)
        f.write("\n")
    columns = []
    for row in rows:
        columns += [c for c in sorted(row) if c not in columns]

    def cell(v):
        if v is None:
            return ""
        if isinstance(v, str):
            return '"' + v.replace('"', '""') + '"'
        return json.dumps(v)

    csv_path = os.path.join(directory, name + ".csv")
    with open(csv_path, "w") as f:
        f.write(",".join(columns) + "\n")
        for row in rows:
            f.write(",".join(cell(row.get(c)) for c in columns) + "\n")
    return json_path, csv_path


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # bad input is one line (argparse prints the usage before it)
        self.exit(2, f"{self.prog}: {message} (--help for the options)\n")


def _list(kind, what):
    def parse(text):
        try:
            return [kind(x) for x in text.split(",") if x]
        except ValueError:
            raise argparse.ArgumentTypeError(f"{what} must be a comma-separated list of numbers, got {text!r}")
    return parse


def _cluster(args):
    """The client of --scheduler or of a LocalCluster of --workers processes (one thread each),
    or None (serial); and a description for the summary."""
    if args.scheduler is None and args.workers is None:
        return None, "serial"
    from distributed import Client, LocalCluster
    if args.scheduler is not None:
        client = Client(args.scheduler, timeout=args.connect_timeout_s)
        return client, f"{len(client.scheduler_info()['workers'])} workers at {args.scheduler}"
    cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True, dashboard_address=None)
    return Client(cluster), f"a LocalCluster of {args.workers} worker processes"


def main(argv=None):
    parser = _Parser(prog="python3 -m ldlpgs.study",
                     description="Studies as tables of independent tasks, serial or on a Dask cluster. "
                                 "These options come before the study's name, the study's after it.")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS", help="a Dask scheduler (tcp://host:8786) to run the tasks on")
    where.add_argument("--workers", type=int, metavar="N", help="run the tasks on a LocalCluster of N worker processes")
    parser.add_argument("--connect-timeout-s", type=float, default=10.0, metavar="S",
                        help="give up on --scheduler after this many seconds (default 10)")
    parser.add_argument("--out-dir", metavar="DIR", help="write DIR/orderings.{json,csv} or DIR/sweep.{json,csv}")
    parser.add_argument("--quiet", action="store_true", help="print the summary line only, not the table")
    studies = parser.add_subparsers(dest="study", required=True, parser_class=_Parser)
    o = studies.add_parser("orderings", help="every ordering on every matrix (a task per matrix)")
    o.add_argument("matrices", nargs="+", metavar="MATRIX", help="Matrix Market files")
    o.add_argument("--orderings", default="all", help="comma-separated names (default all)")
    o.add_argument("--max-block", type=int, default=6)
    s = studies.add_parser("sweep", help="scenes x solvers x iterations x timesteps x mass ratios (a task each)")
    s.add_argument("--scenes", required=True, type=_list(str, "--scenes"), metavar="LIST",
                   help="built-in scenes' names or scene files, comma-separated")
    s.add_argument("--solvers", type=_list(str, "--solvers"), default=list(SOLVERS), metavar="LIST",
                   help=f"default {','.join(SOLVERS)} (direct once, at 1 iteration)")
    s.add_argument("--iterations", type=_list(int, "--iterations"), default=list(ITERATIONS), metavar="LIST",
                   help=f"default {','.join(map(str, ITERATIONS))}")
    s.add_argument("--timesteps", type=_list(float, "--timesteps"), default=[None], metavar="LIST",
                   help="s (default: the scene's)")
    s.add_argument("--mass-ratios", type=_list(float, "--mass-ratios"), default=[None], metavar="LIST",
                   help="heaviest over lightest dynamic mass, reached by scaling the heaviest body (default: the scene's)")
    s.add_argument("--seconds", type=float, default=1.0, help="simulated time per run (default 1)")
    args = parser.parse_args(argv)
    if args.workers is not None and args.workers < 1:
        parser.error("--workers must be at least 1")
    if not (0 < args.connect_timeout_s < math.inf):
        parser.error(f"--connect-timeout-s must be finite and positive, got {args.connect_timeout_s}")
    if args.study == "sweep":
        unknown = [v for v in args.solvers if v not in ldlpgs.solvers()]
        if unknown:
            parser.error(f"--solvers: unknown solver {unknown[0]!r} (known: {', '.join(ldlpgs.solvers())})")
        if not (0 < args.seconds < math.inf):
            parser.error(f"--seconds must be finite and positive, got {args.seconds}")

    started = time.perf_counter()
    try:
        client, where_text = _cluster(args)
    except (OSError, ValueError) as e:  # no scheduler at that address, or not an address
        parser.error(f"--scheduler {args.scheduler}: {error_text(e)}")
    try:
        if client is not None:
            print(f"ldlpgs.study: {where_text} ready in {time.perf_counter() - started:.1f} s", file=sys.stderr)
        start = time.perf_counter()
        if args.study == "orderings":
            frame = orderings(args.matrices, args.orderings, args.max_block, client=client)
            tasks = len(args.matrices)
        else:
            frame = sweep(args.scenes, args.solvers, args.iterations, args.timesteps, args.mass_ratios, args.seconds,
                          client=client)
            tasks = len(frame)
        seconds = time.perf_counter() - start
    finally:
        if client is not None:
            cluster = client.cluster
            client.close()
            if cluster is not None and args.workers is not None:
                cluster.close()
    if not args.quiet:
        with pd.option_context("display.max_rows", None, "display.max_columns", None, "display.width", 200):
            print(frame.to_string(index=False))
    if args.out_dir:
        for path in write_table(frame, args.out_dir, args.study):
            print(f"ldlpgs.study: wrote {path}", file=sys.stderr)
    failed = int(frame["task_error"].notna().sum())  # a failed task has one row
    print(f"{args.study}: {tasks} tasks ({failed} failed) in {seconds:.2f} s, {tasks / seconds:.2f} tasks/s, "
          f"{where_text}")
    return 0


if __name__ == "__main__":
    # The tasks from ldlpgs.study, not __main__: the workers find them by that name.
    from ldlpgs.study import main as study_main
    sys.exit(study_main())
