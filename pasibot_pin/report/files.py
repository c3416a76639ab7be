"""Small file writers shared by the report sections and the commands."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np


def write_columns_csv(path: Path, cols: dict[str, np.ndarray]) -> None:
    """Write equal-length columns as CSV (header = column names, full float precision).

    Args:
        path: output file; its folder is created.
        cols: column name -> values (anything ``float()`` accepts).

    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(list(cols))
        for row in zip(*cols.values()):
            writer.writerow([repr(float(x)) for x in row])
