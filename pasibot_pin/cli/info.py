"""``pasibot info``: nq, nv, loops, actuation, Grübler's DOF and the numerical mobility."""

from __future__ import annotations

import argparse

from pasibot_pin.cli.common import add_robot_options


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser("info", help="print the model's size, loops, actuation and mobility")
    add_robot_options(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Print the summary of the requested robot."""
    from pasibot_pin.model.robot import load

    print(load(args.variant, args.legs).summary())
    return 0
