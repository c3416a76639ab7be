"""Options shared by several subcommands."""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np

from pasibot_pin.model.params import VARIANTS


def add_robot_options(parser: argparse.ArgumentParser, legs_default: int = 2) -> None:
    """``--variant`` and ``--legs``."""
    parser.add_argument("--variant", default="spring", help=f"leg variant: {', '.join(VARIANTS)} (default spring)")
    parser.add_argument("--legs", type=int, default=legs_default, help=f"1 or 2 legs (default {legs_default})")


def write_columns_csv(path: Path, cols: dict[str, np.ndarray]) -> None:
    """Write equal-length columns as CSV (header = column names, full float precision)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(list(cols))
        for row in zip(*cols.values()):
            writer.writerow([repr(float(x)) for x in row])
