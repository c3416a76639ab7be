"""Options and steps shared by ``pasibot sweep`` and ``pasibot optimize``."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from pasibot_pin.cli.common import add_force_option, check_output_folder
from pasibot_pin.errors import ParameterError
from pasibot_pin.explore.executors import check_scheduler, check_workers
from pasibot_pin.explore.plan import DEFAULT_RANGES, check_floor, parse_ranking, ranges_or_default
from pasibot_pin.extras import require
from pasibot_pin.files import OutputFolder
from pasibot_pin.model.design import Design, load_design


def add_explore_options(p: argparse.ArgumentParser) -> None:
    """``--out DIR``, ``--vary``, ``--design``, executors, outputs and the best designs."""
    p.add_argument(
        "--out", type=Path, required=True, metavar="DIR", help="folder of the run (created; resumed if it holds one)"
    )
    p.add_argument(
        "--vary",
        action="append",
        default=None,
        metavar="NAME=LO:HI|NAME=A,B",
        help=(
            "a numeric parameter and its range, or a categorical one and its values, e.g. "
            f"variant=parallel,spring,rigid (repeatable; default: {' '.join(r.text() for r in DEFAULT_RANGES)})"
        ),
    )
    p.add_argument("--design", type=Path, default=None, help="base design file (.toml/.json; default the seed's)")
    p.add_argument("--workers", type=int, default=None, help="worker processes (default: one per core)")
    p.add_argument("--dask", default=None, metavar="ADDRESS", help="'local' (a LocalCluster) or a scheduler address")
    p.add_argument("--csv", action="store_true", help="also write results.csv")
    p.add_argument("--best", type=int, default=3, help="export the N best designs as TOML, URDF, MJCF (default 3)")
    p.add_argument(
        "--by",
        default="peak_crank_torque_Nm:min",
        metavar="METRIC[:min|max]",
        help="how the best designs are ranked (default peak_crank_torque_Nm:min)",
    )
    p.add_argument(
        "--floor",
        type=int,
        default=None,
        metavar="STEPS",
        help="also walk every design this many steps on the floor and judge it (slower; adds floor_* columns)",
    )
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    add_force_option(p, "replace another run (or other files) in --out")


def start_run(args: argparse.Namespace):
    """Check the shared inputs before any work: (base design, ranges, (metric, sense))."""
    # the extra first: a plain install says so in one line and writes nothing
    needed = ["pyarrow", "scipy"] + (["optuna"] if args.command == "optimize" else [])
    require("sweep", needed + (["distributed"] if args.dask is not None else []), f"pasibot {args.command}")
    check_output_folder(args.out, "--out")
    base = load_design(args.design) if args.design is not None else Design()
    ranges = ranges_or_default(args.vary)
    check_workers(args.workers)
    check_floor(args.floor)
    if isinstance(args.best, bool) or not 0 <= args.best <= 100:
        raise ParameterError(f"--best must be in [0, 100], got {args.best!r}")
    by = parse_ranking(args.by, "--by")
    check_scheduler(args.dask)  # last: it may wait a few seconds for the scheduler
    return base, ranges, by


def run_resumable(args: argparse.Namespace, runner, plan, what: str):
    """``runner(plan, OUT, ...)`` with the shared flags, the folder claimed (marked and locked) meanwhile.

    On Ctrl-C, say that the finished work is kept. A run that fails or stops before any design
    finished removes what it created (its folder, or the files it added), so the same command
    can run again; the lock is held until :func:`finish_run` ends.
    """
    from pasibot_pin.explore.store import OWNED, PARTS  # deferred: keeps the CLI's start fast

    out = Path(args.out)
    folder = OutputFolder(out, ours=OWNED).claim(force=args.force)  # refused at once if another run writes there
    args.claimed = folder
    try:
        flags = {"workers": args.workers, "dask": args.dask, "force": args.force, "csv": args.csv}
        return runner(plan, out, progress=not args.no_progress, **flags)
    except BaseException as err:
        finished = (out / PARTS).is_dir() and any((out / PARTS).glob("part-*.parquet"))
        if finished:
            folder.release()
        else:
            folder.discard()
        if isinstance(err, KeyboardInterrupt) and finished:
            print(f"pasibot {args.command}: stopped; the finished {what} are kept in {out}: run the same command again")
        raise


def finish_run(
    args: argparse.Namespace, table, varied, by: tuple[str, str], what: str, objectives=None, rows=None, constraints=()
) -> None:
    """Figures, the best designs (``rows``, or the ``--best`` by ``--by``), a summary line.

    ``constraints``: the ``--constraint``s; the Pareto figure greys the designs that violate one.
    """
    out = Path(args.out)
    try:
        _finish(args, out, table, varied, by, what, objectives, rows, constraints)
    finally:
        claimed = getattr(args, "claimed", None)
        if claimed is not None:
            claimed.release()


def _finish(args, out: Path, table, varied, by, what: str, objectives, rows, constraints=()) -> None:
    from pasibot_pin.explore.sweep import best_rows, export_best, write_figures  # deferred: keeps the CLI's start fast

    figures = write_figures(table, out, varied, objectives, constraints)
    feasible = int(np.sum(table.column("feasible").to_numpy(zero_copy_only=False)))
    print(f"{what}; {table.num_rows} in {out / 'results.parquet'}, {feasible} feasible")
    if "floor_walks" in table.column_names:
        walks = int(np.nansum(table.column("floor_walks").to_numpy(zero_copy_only=False)))
        print(f"{walks} of {table.num_rows} designs walk on the floor (walkers rank first)")
    print(f"figures: {', '.join(str(f) for f in figures)}")
    rows = (best_rows(table, by[0], by[1], args.best) if rows is None else list(rows))[: args.best]
    if rows:
        export_best(table, rows, out / "best")
        for rank, row in enumerate(rows, 1):
            value = table.column(by[0])[row].as_py()
            print(f"  best {rank}: index {table.column('index')[row].as_py()}, {by[0]} = {value:.4g}")
        print(f"best designs (TOML, URDF, MJCF): {out / 'best'}")
