"""Small file writers shared by the report sections and the commands (CSV columns, figures).

They write through :mod:`pasibot_pin.files` (a temporary name, renamed when complete), whose
helpers are re-exported here for the report and the command line.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from pasibot_pin.files import PART_MARKER, atomic_path, atomic_paths, temporary_name, write_text_atomic

__all__ = [
    "FIGURE_DPI",
    "PART_MARKER",
    "atomic_path",
    "atomic_paths",
    "save_figure_file",
    "write_dict_rows",
    "temporary_name",
    "write_columns_csv",
    "write_text_atomic",
]


def write_columns_csv(path: Path, cols: dict[str, np.ndarray]) -> None:
    """Write equal-length columns as CSV (header = column names, full float precision).

    Args:
        path: output file; its folder is created. Written to a temporary name, then renamed.
        cols: column name -> values (anything ``float()`` accepts).

    """
    with atomic_path(Path(path)) as tmp, tmp.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(list(cols))
        for row in zip(*cols.values()):
            writer.writerow([repr(float(x)) for x in row])


def write_dict_rows(path: Path, rows: list[dict]) -> None:
    """Write ``rows`` (one dict each, the first's keys as the header) as CSV straight to ``path``.

    The caller writes to a temporary name and renames (:func:`atomic_paths`).
    """
    with Path(path).open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]) if rows else [])
        writer.writeheader()
        writer.writerows(rows)


PNG_COMPRESS_LEVEL = 3
"""zlib level of the report's PNGs: a third faster to write than Pillow's default 6, files ~4 % larger."""


FIGURE_DPI = 100
"""Resolution of every figure the report and the commands write [dots per inch]."""


def save_figure_file(fig, path: Path, dpi: float = FIGURE_DPI) -> None:
    """``fig.savefig(path, dpi=dpi)``; a PNG at :data:`PNG_COMPRESS_LEVEL` (the same pixels).

    A figure with a layout engine (constrained layout) is laid out once here, at ``dpi``, and then
    saved with the engine off: ``savefig`` would otherwise draw the whole figure twice (once, not
    rendered, to lay it out). The positions, hence the pixels, are the same; the engine and the
    figure's dpi are restored afterwards.
    """
    options = {"pil_kwargs": {"compress_level": PNG_COMPRESS_LEVEL}} if Path(path).suffix.lower() == ".png" else {}
    engine = fig.get_layout_engine()
    if engine is None or not fig.axes:
        fig.savefig(path, dpi=dpi, **options)
        return
    original_dpi = fig.dpi
    try:
        fig.dpi = dpi
        engine.execute(fig)
        fig.set_layout_engine("none")
        fig.savefig(path, dpi=dpi, **options)
    finally:
        fig.set_layout_engine(engine)
        fig.dpi = original_dpi
