"""The ``pasibot`` command line (also ``python -m pasibot_pin``).

Each subcommand lives in its own module of :mod:`pasibot_pin.cli` and registers
itself with ``register(subparsers)``. Everything runs headless and writes files.
"""

from __future__ import annotations

import argparse
import importlib
import sys

import pinocchio as pin

from pasibot_pin import __version__
from pasibot_pin.cli import COMMANDS


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every subcommand registered."""
    parser = argparse.ArgumentParser(prog="pasibot", description="PASIBOT closed-loop biped in Pinocchio")
    parser.add_argument("--version", action="version", version=f"pasibot {__version__} (pin {pin.__version__})")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name in COMMANDS:
        importlib.import_module(f"pasibot_pin.cli.{name}").register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; returns the exit code (2 for bad input, with a one-line message)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except (ValueError, FileExistsError) as err:
        print(f"pasibot {args.command}: error: {err}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
