"""``pasibot info``: nq, nv, loops, actuation, Grübler's DOF, the numerical mobility and the robot's mass.

It describes the robot of a design: ``--design FILE``, else the default design of ``--variant``, the
same robot ``pasibot walk --variant`` builds (its ``body_mass`` on the hip). The seed scenarios'
robots (the K_e tables) carry the seed's stated masses; their summaries say "seed scenario".
"""

from __future__ import annotations

import argparse

from pasibot_pin.cli.common import add_design_option, add_robot_options, design_of
from pasibot_pin.model.design import Design, design_robot


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser(
        "info",
        help="print the model's size, loops, actuation, mobility and mass (the default design's robot)",
        description=__doc__,
    )
    add_robot_options(p)
    add_design_option(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Print the summary of the requested design's robot (the default design of ``--variant`` without ``--design``)."""
    design = design_of(args) or Design(variant=args.variant)
    print(design_robot(design, args.legs, visuals=False).summary())
    return 0
