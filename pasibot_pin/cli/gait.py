"""``pasibot gait``: foot paths of one leg, or the biped's multi-step walk, as CSV and a plot.

``--legs 1``: one crank turn in the leg frame (x forward, z up, origin at the crank pivot),
one CSV row per sample with the columns of
:data:`~pasibot_pin.studies.kinematics_study.LEG_COLUMNS`. ``--legs 2``: the biped walking
``--steps`` steps in the world frame, columns
:func:`~pasibot_pin.studies.kinematics_study.walk_columns`. All SI units, angles in rad.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from pasibot_pin.cli.common import add_robot_options, atomic_path, check_outputs


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser(
        "gait",
        help="foot paths of one leg (--legs 1) or a multi-step biped walk (--legs 2) as CSV and plot",
        description=__doc__,
    )
    add_robot_options(p, legs_default=1)
    p.add_argument("--steps", type=int, default=None, help="steps (half crank turns) to walk, --legs 2 (default 2)")
    p.add_argument("--step-deg", type=float, default=5.0, help="crank increment between samples [deg] (default 5)")
    p.add_argument("--omega", type=float, default=0.1, help="crank rate [rad/s] (default 0.1, seed Fig 5.1)")
    p.add_argument(
        "--foot",
        default=None,
        help="--legs 2 stance contact: flat (sole welded level), point (ankle pinned, hip level), "
        "toe (toe pinned, hip level) (default flat)",
    )
    p.add_argument("--csv", type=Path, default=None, help="write the samples to this CSV file")
    p.add_argument(
        "--plot", type=Path, default=None, help="write a figure to this file (.png, .pdf, .svg; no extension: .png)"
    )
    p.add_argument("--force", action="store_true", help="overwrite existing output files")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Compute, print a summary, write the CSV and the plot."""
    from pasibot_pin.report import kinematics as rep
    from pasibot_pin.studies.kinematics_study import GaitSettings, LegRun, gait_run

    settings = GaitSettings(args.variant, args.legs, args.steps, args.step_deg, args.omega, args.foot)
    check_outputs(args)
    result = gait_run(settings)
    one_leg = isinstance(result, LegRun)
    print(rep.leg_summary(result) if one_leg else rep.walk_summary(result))
    if args.csv is not None:
        with atomic_path(args.csv) as tmp:
            (rep.write_leg_csv if one_leg else rep.write_walk_csv)(tmp, result)
        print(f"wrote {args.csv}")
    if args.plot is not None:
        with atomic_path(args.plot) as tmp:
            (rep.write_leg_plot if one_leg else rep.write_walk_plot)(tmp, result)
        print(f"wrote {args.plot}")
    return 0
