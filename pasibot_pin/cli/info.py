"""``pasibot info``: nq, nv, loops, actuation, Grübler's DOF and the numerical mobility."""

from __future__ import annotations

import argparse

from pasibot_pin.cli.common import add_design_option, add_robot_options, design_of
from pasibot_pin.model.design import design_robot
from pasibot_pin.model.robot import load


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser("info", help="print the model's size, loops, actuation and mobility")
    add_robot_options(p)
    add_design_option(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Print the summary of the requested robot."""
    design = design_of(args)
    robot = load(args.variant, args.legs) if design is None else design_robot(design, args.legs)
    print(robot.summary())
    return 0
