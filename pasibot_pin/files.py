"""Atomic file writing, for every layer: a file appears whole under its name, or not at all.

Every file is written under a temporary name in its own folder (``.NAME.part-XXXXXXXX.EXT``,
the extension kept so writers that pick a format from it still work) and renamed over the
target with :func:`os.replace` only when complete: an interrupted run leaves either the old
file or the new one, never half a file. :func:`atomic_paths` does it for several files at
once (all renamed together at the end, or none). It imports nothing of the package, so the
model (URDF), the viewer (HTML), the report and the command line all use this one.
"""

from __future__ import annotations

import contextlib
import os
import secrets
from collections.abc import Iterator
from pathlib import Path

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
