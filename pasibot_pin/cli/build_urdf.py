"""``pasibot build-urdf``: render the xacro source for any parameter set."""

from __future__ import annotations

import argparse
from pathlib import Path

from pasibot_pin.cli.common import (
    add_design_option,
    add_force_option,
    add_robot_options,
    check_output_file,
    check_output_folder,
    design_of,
)
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.assembly import check_full_turn
from pasibot_pin.model.description import render_default_urdfs, render_urdf, shape_soles, write_urdf
from pasibot_pin.model.params import SEED_LINK_RATIOS, Geometry, check_legs, check_variant, percentage_mass_model


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser("build-urdf", help="render urdf/pasibot.urdf.xacro to URDF")
    add_robot_options(p)
    p.add_argument(
        "--out", type=Path, metavar="FILE|DIR", help="output file (default: print to stdout); with --defaults, a folder"
    )
    p.add_argument(
        "--defaults",
        action="store_true",
        help="re-render every default URDF: into urdf/ of a source checkout, or into the --out folder",
    )
    add_force_option(p, "overwrite an existing, different file")
    add_design_option(p)
    p.add_argument("--L", type=float, help="crank length [m]")
    p.add_argument("--K", type=float, help="L0 / L")
    p.add_argument("--ratio", action="append", default=[], metavar="rN=VALUE", help="a link ratio, e.g. r4=9.5")
    p.set_defaults(func=run)


def parse_ratios(items: list[str]) -> dict[str, float]:
    """``['r4=9.5', ...]`` -> ``{'r4': 9.5}``; ValueError for anything but a known ``rN=NUMBER``."""
    out: dict[str, float] = {}
    for item in items:
        key, sep, value = item.partition("=")
        key = key.strip()
        if not sep or key not in SEED_LINK_RATIOS:
            raise ParameterError(f"--ratio expects rN=VALUE with rN one of r1..r{len(SEED_LINK_RATIOS)}, got {item!r}")
        try:
            out[key] = float(value)
        except ValueError:
            raise ParameterError(f"--ratio expects rN=VALUE with a number VALUE, got {item!r}") from None
    return out


def run(args: argparse.Namespace) -> int:
    """Render and write (or print) the URDF."""
    if args.defaults:
        if args.L is not None or args.K is not None or args.ratio or args.design is not None:
            raise ParameterError("--defaults renders the default parameters; it takes no --L, --K, --ratio or --design")
        out_dir = None if args.out is None else check_output_folder(args.out, "--out")
        for path in render_default_urdfs(out_dir, force=args.force):
            print(f"wrote {path}")
        return 0
    check_variant(args.variant)
    check_legs(args.legs)
    check_output_file(args.out, "--out", force=True)  # an equal file is left alone; a different one needs --force
    changes: dict[str, float] = parse_ratios(args.ratio)
    if args.L is not None:
        changes["L"] = args.L
    if args.K is not None:
        changes["K"] = args.K
    design = design_of(args)
    if design is None:
        variant, geometry, inertia = args.variant, Geometry().with_(**changes), "point"
        masses = percentage_mass_model(geometry, variant)
    else:  # the design's geometry, masses and inertia; --L, --K, --ratio change it
        design = design.with_(**changes)
        variant, geometry, masses, inertia = design.variant, design.geometry(), design.masses(), design.inertia
    check_full_turn(geometry, variant)
    text = render_urdf(variant, args.legs, geometry, masses, inertia)
    if design is not None:  # the soles with the design's lateral shape (a plate or a comb)
        text = shape_soles(text, design.footprint(), geometry.L)
    if args.out is None:
        print(text, end="")
    else:
        print(f"wrote {write_urdf(args.out, text, force=args.force)}")
    return 0
