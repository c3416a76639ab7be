"""``pasibot optimize``: multi-objective design optimisation (Optuna NSGA-II), resumable.

The varied parameters (``--vary``, default as ``pasibot sweep``) are drawn by NSGA-II; each
design's metrics give the objectives (``--objective METRIC:min|max``, repeatable; default
``peak_crank_torque_Nm:min``) and constraints (``--constraint METRIC>=BOUND``, repeatable, e.g.
``cop_margin_m>=0``). The table goes to ``OUT/results.parquet``, the study to ``OUT/optuna.log``;
the Pareto-optimal designs are exported to ``OUT/best``. Run the same command again to continue
an interrupted run.
"""

from __future__ import annotations

import argparse

from pasibot_pin.cli.explore_options import add_explore_options, finish_run, run_resumable, start_run


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser("optimize", help="multi-objective design optimisation (NSGA-II, resumable)", description=__doc__)
    p.add_argument("--trials", type=int, default=200, help="designs to evaluate (default 200)")
    p.add_argument("--population", type=int, default=20, help="designs per generation (default 20)")
    p.add_argument("--seed", type=int, default=0, help="the sampler's seed (default 0)")
    p.add_argument("--objective", action="append", default=None, metavar="METRIC[:min|max]", help="repeatable")
    p.add_argument("--constraint", action="append", default=None, metavar="METRIC>=BOUND", help="repeatable")
    add_explore_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Check every input, run the optimisation, write the table, figures and the Pareto designs."""
    from pasibot_pin.explore.optimize import (  # deferred: keeps the CLI's start fast
        OptimizePlan,
        objectives_of,
        parse_constraint,
        run_optimize,
    )

    base, ranges, by = start_run(args)
    plan = OptimizePlan(
        ranges=ranges,
        objectives=objectives_of(args.objective),
        constraints=tuple(parse_constraint(c) for c in args.constraint or ()),
        trials=args.trials,
        population=args.population,
        seed=args.seed,
        base=base,
        floor=args.floor,
    )
    result = run_resumable(args, run_optimize, plan, "trials")
    objectives = tuple(o.metric for o in plan.objectives[:2])
    pair = objectives if len(objectives) == 2 else (objectives[0], "stride_m")
    what = f"{result.evaluated} trials evaluated"
    finish_run(args, result.table, plan.names, by, what, pair, result.pareto, plan.constraints)
    return 0
