"""``pasibot build-urdf``: render the xacro source for any parameter set."""

from __future__ import annotations

import argparse
from pathlib import Path

from pasibot_pin.cli.common import add_robot_options


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser("build-urdf", help="render urdf/pasibot.urdf.xacro to URDF")
    add_robot_options(p)
    p.add_argument("--out", type=Path, help="output file (default: print to stdout)")
    p.add_argument("--defaults", action="store_true", help="re-render every committed default URDF in urdf/")
    p.add_argument("--force", action="store_true", help="overwrite an existing, different file")
    p.add_argument("--L", type=float, help="crank length [m]")
    p.add_argument("--K", type=float, help="L0 / L")
    p.add_argument("--ratio", action="append", default=[], metavar="rN=VALUE", help="a link ratio, e.g. r4=9.5")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Render and write (or print) the URDF."""
    from pasibot_pin.model.description import render_default_urdfs, render_urdf, write_urdf
    from pasibot_pin.model.params import Geometry, percentage_mass_model

    if args.defaults:
        for path in render_default_urdfs(force=args.force):
            print(f"wrote {path}")
        return 0
    changes: dict[str, float] = {}
    if args.L is not None:
        changes["L"] = args.L
    if args.K is not None:
        changes["K"] = args.K
    for item in args.ratio:
        key, _, value = item.partition("=")
        try:
            changes[key.strip()] = float(value)
        except ValueError as err:
            raise ValueError(f"--ratio expects rN=VALUE, got {item!r}") from err
    geometry = Geometry().with_(**changes)
    text = render_urdf(args.variant, args.legs, geometry, percentage_mass_model(geometry, args.variant))
    if args.out is None:
        print(text, end="")
    else:
        print(f"wrote {write_urdf(args.out, text, force=args.force)}")
    return 0
