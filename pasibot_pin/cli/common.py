"""Options shared by several subcommands."""

from __future__ import annotations

import argparse
from pathlib import Path

from pasibot_pin.model.params import VARIANTS
from pasibot_pin.report.files import write_columns_csv

__all__ = ["add_output_options", "add_robot_options", "check_outputs", "write_columns_csv"]


def add_robot_options(parser: argparse.ArgumentParser, legs_default: int = 2) -> None:
    """``--variant`` and ``--legs``."""
    parser.add_argument("--variant", default="spring", help=f"leg variant: {', '.join(VARIANTS)} (default spring)")
    parser.add_argument("--legs", type=int, default=legs_default, help=f"1 or 2 legs (default {legs_default})")


def add_output_options(parser: argparse.ArgumentParser, csv_help: str, plot_help: str) -> None:
    """``--csv``, ``--plot`` and ``--force`` (refuse to overwrite without it)."""
    parser.add_argument("--csv", type=Path, default=None, help=csv_help)
    parser.add_argument("--plot", type=Path, default=None, help=plot_help)
    parser.add_argument("--force", action="store_true", help="overwrite existing output files")


def check_outputs(args: argparse.Namespace) -> None:
    """Refuse, before any work, to overwrite an existing ``--csv`` or ``--plot`` file without ``--force``."""
    for path, option in ((args.csv, "--csv"), (args.plot, "--plot")):
        if path is not None and path.exists() and not args.force:
            raise FileExistsError(f"{option} {path} exists; pass --force to overwrite it")
