"""``pasibot gait``: foot paths of one leg, or the biped's multi-step walk, as CSV and a plot.

``--legs 1``: one crank turn in the leg frame (x forward, z up, origin at the crank pivot),
one CSV row per sample: the crank angle, the ankle, toe and heel positions, the foot pitch, the
ankle's velocity and acceleration, and whether the leg is in stance. ``--legs 2`` (the default,
as in every command): the biped walking ``--steps`` steps in the world frame: both crank angles,
the time, the step, the stance leg, the hip's position and pitch, and each foot's ankle, toe,
heel and pitch. Each column's name ends in its unit (``theta_rad``, ``ankle_x_m``, ``t_s``).
"""

from __future__ import annotations

import argparse

from pasibot_pin.cli.common import (
    add_design_option,
    add_output_options,
    add_robot_options,
    add_steps_option,
    atomic_path,
    check_outputs,
    design_of,
    given,
)


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser(
        "gait",
        help="foot paths of one leg (--legs 1) or a multi-step biped walk (--legs 2) as CSV and plot",
        description=__doc__,
    )
    add_robot_options(p)
    add_steps_option(p, "steps (half crank turns) to walk, --legs 2")
    p.add_argument("--step-deg", type=float, default=5.0, help="crank increment between samples [deg] (default 5)")
    p.add_argument("--omega", type=float, default=0.1, help="crank rate [rad/s] (default 0.1, seed Fig 5.1)")
    p.add_argument(
        "--foot",
        default=None,
        help="--legs 2 stance contact: flat (sole welded level), point (ankle pinned, hip level), "
        "toe (toe pinned, hip level) (default flat)",
    )
    add_output_options(p, "write the samples to this CSV file", "write a figure to this file")
    add_design_option(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Compute, print a summary, write the CSV and the plot."""
    from pasibot_pin.report import kinematics as rep  # deferred: keeps the CLI's start fast
    from pasibot_pin.studies.kinematics_study import (  # deferred: keeps the CLI's start fast
        GaitSettings,
        LegRun,
        gait_run,
    )

    steps = args.steps if given(args, "steps") else None  # with --legs 1, --steps is refused, not ignored
    design = design_of(args)
    variant = args.variant if design is None else design.variant
    settings = GaitSettings(variant, args.legs, steps, args.step_deg, args.omega, args.foot, design)
    check_outputs(args, f"gait_{'design' if design is not None else variant}_{args.legs}leg")
    result = gait_run(settings)
    print(rep.leg_summary(result) if isinstance(result, LegRun) else rep.walk_summary(result))
    if args.csv is not None:
        with atomic_path(args.csv) as tmp:
            if isinstance(result, LegRun):
                rep.write_leg_csv(tmp, result)
            else:
                rep.write_walk_csv(tmp, result)
        print(f"wrote {args.csv}")
    if args.plot is not None:
        with atomic_path(args.plot) as tmp:
            if isinstance(result, LegRun):
                rep.write_leg_plot(tmp, result)
            else:
                rep.write_walk_plot(tmp, result)
        print(f"wrote {args.plot}")
    return 0
