"""``pasibot sweep``: evaluate many designs (Latin hypercube or grid), one table, resumable.

Every design is the base design (the seed's, or ``--design FILE``) with the ``--vary``
parameters set (``--vary NAME=LO:HI`` for a number, ``--vary variant=parallel,spring,rigid`` for a
categorical parameter); its metrics (path, torques, spring, contact, energy) go in one row of
``OUT/results.parquet``. An interrupted run keeps every finished design: run the same command
again to continue. ``--dask local`` runs on a Dask LocalCluster, ``--dask tcp://HOST:8786`` on a
cluster (``dask scheduler`` on one machine, ``dask worker tcp://HOST:8786`` on each).
"""

from __future__ import annotations

import argparse
import math

from pasibot_pin.cli.explore_options import add_explore_options, finish_run, run_resumable, start_run
from pasibot_pin.explore.plan import SweepPlan


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser("sweep", help="evaluate many designs into one table (resumable)", description=__doc__)
    p.add_argument(
        "--n",
        type=int,
        default=100,
        help="number of designs (grid: levels^d for d varied parameters, e.g. 128 = 2^7) (default 100)",
    )
    p.add_argument("--method", default="lhs", choices=("lhs", "grid"), help="Latin hypercube or grid (default lhs)")
    p.add_argument("--seed", type=int, default=0, help="the Latin hypercube's random seed (default 0)")
    add_explore_options(p)
    p.add_argument(
        "--3d",
        dest="spatial",
        action="store_true",
        help="with --floor: walk on the 3-D floor (free hip, the designs' soles; adds floor_max_hip_roll_deg)",
    )
    p.add_argument("--slope", type=float, default=0.0, metavar="DEG",
                   help="with --floor: walk up a slope, uphill positive [deg] (default 0: flat)")  # fmt: skip
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Check every input, run the sweep, write the table, figures and best designs."""
    from pasibot_pin.explore.sweep import run_sweep  # deferred: keeps the CLI's start fast

    base, ranges, by = start_run(args)
    plan = SweepPlan(ranges=ranges, n=args.n, method=args.method, seed=args.seed, base=base, floor=args.floor,
                    spatial=args.spatial, slope=math.radians(args.slope))  # fmt: skip
    result = run_resumable(args, run_sweep, plan, "designs")
    finish_run(args, result.table, plan.names, by, f"{result.evaluated} designs evaluated")
    return 0
