"""Small file writers shared by the report sections and the commands (CSV columns, figures).

They write through :mod:`pasibot_pin.files` (a temporary name, renamed when complete), whose
helpers are re-exported here for the report and the command line.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from pasibot_pin.files import PART_MARKER, atomic_path, atomic_paths, temporary_name, write_text_atomic, writing
from pasibot_pin.viz.figure_files import FIGURE_DPI, PNG_COMPRESS_LEVEL, save_figure_file

__all__ = [
    "FIGURE_DPI",
    "PNG_COMPRESS_LEVEL",
    "PART_MARKER",
    "atomic_path",
    "atomic_paths",
    "save_figure_file",
    "write_dict_rows",
    "temporary_name",
    "write_columns_csv",
    "write_text_atomic",
    "writing",
]


def write_columns_csv(path: Path, cols: dict[str, np.ndarray]) -> None:
    """Write equal-length columns as CSV (header = column names with their units, full float precision).

    Args:
        path: output file; its folder is created. Written to a temporary name, then renamed.
        cols: column name -> values (anything ``float()`` accepts), in SI units; the header names each
            column with its unit (:func:`pasibot_pin.units.with_unit`: ``theta`` -> ``theta_rad``).

    """
    from pasibot_pin.units import with_unit  # deferred: keeps the CLI's start fast

    with atomic_path(Path(path)) as tmp, tmp.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow([with_unit(name) for name in cols])
        for row in zip(*cols.values()):
            writer.writerow([repr(float(x)) for x in row])


def write_dict_rows(path: Path, rows: list[dict]) -> None:
    """Write ``rows`` (one dict each, the first's keys as the header) as CSV straight to ``path``.

    Written under a temporary name and renamed (:func:`~pasibot_pin.files.writing`), unless ``path``
    is a temporary name already (the caller renames it, :func:`atomic_paths`).
    """
    with writing(Path(path)) as tmp, tmp.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]) if rows else [])
        writer.writeheader()
        writer.writerows(rows)
