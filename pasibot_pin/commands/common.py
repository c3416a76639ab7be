"""Options shared by several subcommands."""

from __future__ import annotations

import argparse

from ..params import VARIANTS


def add_robot_options(parser: argparse.ArgumentParser, legs_default: int = 2) -> None:
    """``--variant`` and ``--legs``."""
    parser.add_argument("--variant", default="spring", help=f"leg variant: {', '.join(VARIANTS)} (default spring)")
    parser.add_argument("--legs", type=int, default=legs_default, help=f"1 or 2 legs (default {legs_default})")
