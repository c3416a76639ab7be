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
import csv
import dataclasses
import fcntl
import os
import secrets
import shutil
import stat
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

from pasibot_pin.errors import ParameterError

PART_MARKER = ".part-"
"""What the temporary names contain (``.gait.part-1a2b3c4d.png``)."""

MARKER = ".pasibot"
"""The file that marks a folder as a pasibot output folder (``--force`` replaces only in those) and that
a run locks (:func:`fcntl.flock`) while it writes there."""

LIVE_TEMPORARIES: set[str] = set()
"""Temporary files of this process not yet renamed or removed (a signal handler removes them)."""


def remove_temporaries() -> None:
    """Remove every temporary file this process is writing (called by the SIGTERM/SIGINT handlers)."""
    for name in list(LIVE_TEMPORARIES):
        with contextlib.suppress(OSError):
            os.unlink(name)
        LIVE_TEMPORARIES.discard(name)


def check_replaceable(path: Path, option: str) -> None:
    """Refuse to replace anything at ``path`` but a regular file (``--force`` never replaces a device or a link).

    A symbolic link is refused, even one to a regular file: the message names the file it points to,
    so the user can name that file instead (the link itself is left as it is).

    Raises:
        FileExistsError: ``path`` is a symbolic link, a device, a pipe, a socket or a folder.

    """
    path = Path(path)
    try:
        info = os.lstat(path)
    except FileNotFoundError:
        return
    except OSError:  # a path through a file, or one we may not look at: the write will say why
        return
    if stat.S_ISLNK(info.st_mode):
        raise FileExistsError(
            f"{option} {path} is a symbolic link (to {os.readlink(path)}); name the file itself, pasibot replaces "
            "only regular files"
        )
    if not stat.S_ISREG(info.st_mode):
        kind = "a folder" if stat.S_ISDIR(info.st_mode) else "not a regular file (a device, pipe or socket)"
        raise FileExistsError(f"{option} {path} is {kind}; pasibot replaces only regular files")


def temporary_name(path: Path) -> Path:
    """A fresh temporary name beside ``path`` with the same extension (nothing is created)."""
    path = Path(path)
    return path.with_name(f".{path.stem}{PART_MARKER}{secrets.token_hex(4)}{path.suffix}")


@contextlib.contextmanager
def atomic_paths(*paths: Path | None) -> Iterator[list[Any]]:
    """Temporary names for ``paths``, renamed over them together when the block ends without error.

    ``None`` entries stay ``None`` (the list is typed ``Any``: a ``Path`` wherever a path was given).
    Folders are created. On any exception (Ctrl-C included) the temporary files are removed and the
    targets are left as they were.

    Example:
        >>> with atomic_paths(Path("a.png")) as (tmp,):  # doctest: +SKIP
        ...     fig.savefig(tmp)

    """
    targets = [None if p is None else Path(p) for p in paths]
    temps: list[Path | None] = []
    for target in targets:
        if target is not None:
            check_replaceable(target, "file")
            target.parent.mkdir(parents=True, exist_ok=True)
        temps.append(None if target is None else temporary_name(target))
    LIVE_TEMPORARIES.update(os.fspath(t) for t in temps if t is not None)
    try:
        yield temps
        for tmp, target in zip(temps, targets):
            if tmp is None or target is None:  # None in both lists at once
                continue
            if not tmp.exists():
                raise FileNotFoundError(f"nothing was written to {target}")
            check_replaceable(target, "file")  # nothing but a regular file appeared there meanwhile
        for tmp, target in zip(temps, targets):
            if tmp is not None and target is not None:
                os.replace(tmp, target)
    except OSError as err:  # name the file the caller asked for, not its temporary name
        for tmp, target in zip(temps, targets):
            if tmp is not None and target is not None and err.filename is not None:
                if os.fspath(err.filename) == os.fspath(tmp):
                    err.filename = os.fspath(target)
        raise
    finally:
        for tmp in temps:
            if tmp is not None:
                tmp.unlink(missing_ok=True)
                LIVE_TEMPORARIES.discard(os.fspath(tmp))


@contextlib.contextmanager
def atomic_path(path: Path) -> Iterator[Path]:
    """One file of :func:`atomic_paths`: yields the temporary name to write to."""
    with atomic_paths(path) as (tmp,):
        if tmp is None:  # never: a path was given
            raise ParameterError("atomic_path needs a path")
        yield tmp


@contextlib.contextmanager
def writing(path: Path) -> Iterator[Path]:
    """The name to write ``path`` to, renamed to ``path`` at the end when the block ends without error.

    A temporary name (:func:`atomic_path`), or ``path`` itself when it is a temporary name already
    (then the caller renames it).
    """
    path = Path(path)
    if PART_MARKER in path.name:
        path.parent.mkdir(parents=True, exist_ok=True)
        yield path
        return
    with atomic_path(path) as tmp:
        yield tmp


def write_text_atomic(path: Path, text: str, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` through a temporary file (its folder is created)."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding=encoding)
    return path


class OutputFolder:
    """An output folder a run owns while it writes: marked as pasibot's, locked, removed if the run fails.

    :meth:`claim` creates the folder (and its missing parents) or takes an existing one, writes the
    :data:`MARKER` file into a folder that is new or empty, and locks the marker
    (:func:`fcntl.flock`): a second run on the same folder is refused at once. ``--force`` over a
    folder that holds files but no marker (a folder pasibot did not make) is refused: pasibot
    replaces only in its own folders. :meth:`release` unlocks; :meth:`discard` (a failed run)
    removes what this run created: the folders it made, or else the names it added.

    Args:
        path: the folder.
        option: the option that named it, for the messages (``--out``).
        ours: names only pasibot writes there (a folder holding nothing else is pasibot's, marker or not).

    """

    def __init__(self, path: Path, option: str = "--out", ours: tuple[str, ...] = ()):
        self.path = Path(path)
        self.option = option
        self.ours = frozenset(ours)
        self.created: Path | None = None  # the topmost folder this run made
        self.made: list[Path] = []  # every folder this run made, the run's own first
        self.before: set[str] = set()  # the names the folder held before the run
        self._lock: int | None = None

    @property
    def marked(self) -> bool:
        """Whether the folder holds the :data:`MARKER` (pasibot made it)."""
        return (self.path / MARKER).is_file()

    def claim(self, force: bool = False) -> OutputFolder:
        """Create or take the folder, mark it when new or empty, and lock it.

        Raises:
            FileExistsError: ``force`` on a folder holding files without the marker, or another
                run holds the folder's lock.

        """
        path = self.path
        if not path.is_dir():
            made = [path]
            while not made[-1].parent.exists() and made[-1].parent != made[-1]:
                made.append(made[-1].parent)
            path.mkdir(parents=True, exist_ok=True)
            self.created = made[-1]
            self.made = made  # this folder first, then each parent this run created
        self.before = {entry.name for entry in path.iterdir()}
        foreign = self.before - {MARKER}
        if not self.marked:
            if foreign and foreign <= self.ours:  # a run of an older pasibot, without the marker: ours
                foreign = set()
            if force and foreign:
                raise FileExistsError(
                    f"{self.option} {path} holds files pasibot did not write (no {MARKER} marker in it); "
                    "--force replaces only in pasibot's own output folders: use another folder"
                )
            if not foreign:
                (path / MARKER).write_text("an output folder of pasibot (pasibot_pin): --force may replace its files\n")
        # a folder of other files is not ours to mark (the command's own checks decide), but it is locked all the same
        fd = os.open(path / MARKER if self.marked else path, os.O_RDONLY)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise FileExistsError(
                f"{self.option} {path} is in use by another pasibot run; wait for it to end or use another folder"
            ) from None
        self._lock = fd
        self._remove_stale_temporaries()
        return self

    def _remove_stale_temporaries(self) -> None:
        """Remove half-written files a killed run left here (``.NAME.part-*``): this run holds the lock now."""
        for entry in self.path.glob(f".*{PART_MARKER}*"):
            if entry.is_file() and not entry.is_symlink():
                with contextlib.suppress(OSError):
                    entry.unlink()
                    self.before.discard(entry.name)

    def release(self) -> None:
        """Unlock the folder (the marker stays)."""
        if self._lock is not None:
            with contextlib.suppress(OSError):
                fcntl.flock(self._lock, fcntl.LOCK_UN)
            os.close(self._lock)
            self._lock = None

    def discard(self) -> None:
        """Remove what this run created: the folders it made, or the names it added to the folder."""
        self.release()
        if self.made:  # its own folder, then each parent it made while nothing else has moved in
            shutil.rmtree(self.made[0], ignore_errors=True)
            for parent in self.made[1:]:
                try:
                    parent.rmdir()
                except OSError:  # another run writes there now: not ours to remove
                    break
            return
        if not self.path.is_dir():
            return
        for entry in self.path.iterdir():
            if entry.name in self.before:
                continue
            if entry.is_dir() and not entry.is_symlink():
                shutil.rmtree(entry, ignore_errors=True)
            else:
                with contextlib.suppress(OSError):
                    entry.unlink()


# --------------------------------------------------------------------------- tables of dataclass rows
def row_record(row: Any) -> dict:
    """A dataclass row as CSV fields: floats by ``repr`` (read back bit for bit), the rest as they are."""
    return {k: (repr(v) if isinstance(v, float) else v) for k, v in dataclasses.asdict(row).items()}


def read_rows(lines: Iterable[str], kind: type) -> list:
    """The rows of CSV ``lines`` (a header, then rows) as ``kind`` dataclasses; a missing column keeps its default."""
    types = {f.name: f.type for f in dataclasses.fields(kind)}
    rows = []
    for record in csv.DictReader(lines):
        values: dict[str, Any] = {}
        for key, text in record.items():
            kind_of = types[key]
            values[key] = text if kind_of == "str" else int(text) if kind_of == "int" else float(text)
        rows.append(kind(**values))
    return rows


def append_row(path: Path, row: Any) -> None:
    """Append one dataclass row to a CSV (its header first when the file is new): a partial table resumes."""
    new = not Path(path).is_file()
    with open(path, "a", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=[f.name for f in dataclasses.fields(row)], lineterminator="\n")
        if new:
            writer.writeheader()
        writer.writerow(row_record(row))


def write_rows(path: Path, kind: type, rows: Iterable[Any], head: Iterable[str] = ()) -> Path:
    """Write dataclass rows as CSV atomically: the ``head`` lines (``# ...``), the header, one line per row."""
    path = Path(path)
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as handle:
        for line in head:
            handle.write(f"{line}\n")
        writer = csv.DictWriter(handle, fieldnames=[f.name for f in dataclasses.fields(kind)], lineterminator="\n")
        writer.writeheader()
        for row in rows:
            writer.writerow(row_record(row))
    return path
