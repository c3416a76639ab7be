"""Small file writers shared by the report sections and the commands.

Every file is written under a temporary name in its own folder (``.NAME.part-XXXXXXXX.EXT``,
the extension kept so writers that pick a format from it still work) and renamed over the
target with :func:`os.replace` only when complete: an interrupted run leaves either the old
file or the new one, never half a file. :func:`atomic_paths` does it for several files at
once (all renamed together at the end, or none).
"""

from __future__ import annotations

import contextlib
import csv
import os
import secrets
from collections.abc import Iterator
from pathlib import Path

import numpy as np

PART_MARKER = ".part-"
"""What the temporary names contain (``.gait.part-1a2b3c4d.png``)."""


def temporary_name(path: Path) -> Path:
    """A fresh temporary name beside ``path`` with the same extension (nothing is created)."""
    path = Path(path)
    return path.with_name(f".{path.stem}{PART_MARKER}{secrets.token_hex(4)}{path.suffix}")


@contextlib.contextmanager
def atomic_paths(*paths: Path | None) -> Iterator[list[Path | None]]:
    """Temporary names for ``paths``, renamed over them together when the block ends without error.

    ``None`` entries stay ``None``. Folders are created. On any exception (Ctrl-C included)
    the temporary files are removed and the targets are left as they were.

    Example:
        >>> with atomic_paths(Path("a.png")) as (tmp,):  # doctest: +SKIP
        ...     fig.savefig(tmp)

    """
    targets = [None if p is None else Path(p) for p in paths]
    temps: list[Path | None] = []
    for target in targets:
        if target is not None:
            target.parent.mkdir(parents=True, exist_ok=True)
        temps.append(None if target is None else temporary_name(target))
    try:
        yield temps
        for tmp, target in zip(temps, targets):
            if tmp is None:
                continue
            if not tmp.exists():
                raise FileNotFoundError(f"nothing was written to {target}")
            os.replace(tmp, target)
    finally:
        for tmp in temps:
            if tmp is not None:
                tmp.unlink(missing_ok=True)


@contextlib.contextmanager
def atomic_path(path: Path) -> Iterator[Path]:
    """One file of :func:`atomic_paths`: yields the temporary name to write to."""
    with atomic_paths(path) as (tmp,):
        yield tmp


def write_text_atomic(path: Path, text: str, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` through a temporary file (its folder is created)."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding=encoding)
    return path


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


PNG_COMPRESS_LEVEL = 3
"""zlib level of the report's PNGs: a third faster to write than Pillow's default 6, files ~4 % larger."""


def save_figure_file(fig, path: Path, dpi: float) -> None:
    """``fig.savefig(path, dpi=dpi)``; a PNG at :data:`PNG_COMPRESS_LEVEL` (the same pixels)."""
    options = {"pil_kwargs": {"compress_level": PNG_COMPRESS_LEVEL}} if Path(path).suffix.lower() == ".png" else {}
    fig.savefig(path, dpi=dpi, **options)
