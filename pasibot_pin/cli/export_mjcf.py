"""``pasibot export-mjcf``: the robot as an MJCF file for MuJoCo (any variant and design).

The tree, masses and COMs are the Pinocchio model's; the loop closures are ``equality
connect`` constraints at the cut joints; the ankle springs are joint stiffness and damping
about their rest angle (the design's, or fitted by the torque analysis where the design
leaves them unset); the cranks have position (default) or velocity servos; the soles are
capsules on a floor plane (``--slope DEG``: the plane tilted, rising along +x, gravity vertical, as
``pasibot walk --slope``). The ``home`` keyframe closes every loop. ``--3d`` writes the hip as a
``freejoint`` and each sole as boxes of the design's footprint (``sole_inner``, ``sole_outer``,
its gap), the two-legged robot only.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from pasibot_pin.cli.common import (
    add_force_option,
    add_mu_option,
    add_robot_options,
    check_output_file,
    file_path,
    given,
)
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import Design, design_robot, load_design
from pasibot_pin.report.files import write_text_atomic


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser("export-mjcf", help="write the robot as an MJCF file for MuJoCo", description=__doc__)
    p.add_argument("--out", type=file_path, required=True, metavar="FILE", help="MJCF file to write (.xml)")
    p.add_argument("--design", type=Path, default=None, help="design file (.toml or .json) instead of the seed design")
    add_robot_options(p)  # --variant given overrides the design's variant
    p.add_argument("--actuator", default="position", choices=("position", "velocity", "none"), help="crank servos")
    p.add_argument("--weld", default="none", choices=("none", "right", "left"), help="weld this foot where it stands")
    p.add_argument("--no-floor", action="store_true", help="no floor contact (e.g. with --weld)")
    p.add_argument(
        "--3d",
        dest="spatial",
        action="store_true",
        help="a free hip (freejoint) and the soles as boxes of the design's footprint (two legs)",
    )
    add_mu_option(p)
    p.add_argument("--slope", type=float, default=0.0, metavar="DEG",
                   help="tilt the floor plane: its slope, uphill positive [deg] (default 0; planar)")  # fmt: skip
    add_force_option(p, "overwrite an existing file")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Build the design's robot and spring, write the MJCF."""
    from pasibot_pin.model.mjcf import MjcfOptions, check_twin, to_mjcf  # deferred: keeps the CLI's start fast
    from pasibot_pin.studies.methods.spring_fit import design_spring  # deferred: keeps the CLI's start fast

    check_output_file(args.out, "--out", args.force)
    if args.spatial and (args.legs != 2 or args.weld != "none"):
        raise ParameterError("--3d exports the two-legged robot on the floor: drop --legs 1 and --weld")
    if args.slope and (args.spatial or args.no_floor):
        raise ParameterError("--slope tilts the planar export's floor: drop --3d and --no-floor")
    design = load_design(args.design) if args.design is not None else Design()
    if given(args, "variant"):
        design = design.with_(variant=args.variant)
    check_twin(design)
    robot = design_robot(design, args.legs)
    spring = design_spring(design)
    options = MjcfOptions(
        actuator=args.actuator,
        weld_foot=None if args.weld == "none" else args.weld,
        floor=not args.no_floor,
        mu=args.mu,
        slope=math.radians(args.slope),
        footprint=design.footprint() if args.spatial else None,
        **(
            {}
            if spring is None
            else {
                "spring_stiffness": spring.stiffness,
                "spring_rest_angle": spring.rest_angle,
                "spring_damping": spring.damping,
            }
        ),
    )
    write_text_atomic(args.out, to_mjcf(robot, options))
    text = f" (ankle spring K_e = {spring.stiffness:.2f} N.m/rad)" if spring is not None else ""
    kind = ", 3-D (free hip, box soles)" if args.spatial else (f", on a {args.slope:g} deg slope" if args.slope else "")
    print(f"wrote {args.out}: {design.variant}, {args.legs} leg(s){kind}, {len(robot.loops)} loop closures{text}")
    return 0
