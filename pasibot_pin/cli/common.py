"""Options and checks shared by several subcommands.

Every output path is checked before any work starts (:func:`check_output_file`,
:func:`check_output_folder`, :func:`check_plot_file`): not a folder, not an existing file
without ``--force``, a folder that exists and is writable or can be created, and for figures
an extension matplotlib can write. The checks raise ``ValueError`` or ``FileExistsError``,
which ``pasibot`` prints as one line with exit code 2.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from pasibot_pin.model.params import VARIANTS
from pasibot_pin.report.files import atomic_path, atomic_paths, write_columns_csv

__all__ = [
    "add_output_options",
    "add_robot_options",
    "atomic_path",
    "atomic_paths",
    "check_output_file",
    "check_output_folder",
    "check_outputs",
    "check_plot_file",
    "write_columns_csv",
]


def add_robot_options(parser: argparse.ArgumentParser, legs_default: int = 2) -> None:
    """``--variant`` and ``--legs``."""
    parser.add_argument("--variant", default="spring", help=f"leg variant: {', '.join(VARIANTS)} (default spring)")
    parser.add_argument("--legs", type=int, default=legs_default, help=f"1 or 2 legs (default {legs_default})")


def add_output_options(parser: argparse.ArgumentParser, csv_help: str, plot_help: str) -> None:
    """``--csv``, ``--plot`` and ``--force`` (refuse to overwrite without it)."""
    parser.add_argument("--csv", type=Path, default=None, help=csv_help)
    parser.add_argument(
        "--plot", type=Path, default=None, help=f"{plot_help} (.png, .pdf, .svg, ...; no extension: .png)"
    )
    parser.add_argument("--force", action="store_true", help="overwrite existing output files")


def _check_writable_folder(folder: Path, option: str, path: Path) -> None:
    """``folder`` exists and is writable, or its nearest existing ancestor is a writable folder."""
    folder = Path(folder) if str(folder) else Path(".")
    probe = folder
    while not probe.exists():
        if probe.is_symlink():  # a dangling link: mkdir would fail
            raise ValueError(f"{option} {path}: {probe} is a broken link")
        parent = probe.parent
        if parent == probe:
            break
        probe = parent
    if probe.exists() and not probe.is_dir():
        raise ValueError(f"{option} {path}: {probe} is a file, not a folder")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise ValueError(f"{option} {path}: folder {probe} is not writable")


def check_output_file(path: Path | None, option: str, force: bool = False) -> Path | None:
    """Check, before any work, that ``path`` can be written as a file.

    Args:
        path: the file to write (``None``: nothing to check).
        option: the option's name for the message (``--csv``).
        force: allow overwriting an existing file.

    Returns:
        ``path`` as a :class:`~pathlib.Path` (or ``None``).

    Raises:
        ValueError: ``path`` is a folder, or its folder is a file or not writable.
        FileExistsError: ``path`` exists and ``force`` is false.

    """
    if path is None:
        return None
    path = Path(path)
    if not path.name or path.is_dir() or str(path).endswith(os.sep):
        raise ValueError(f"{option} {path} is a folder; give a file name")
    if path.exists() and not force:
        raise FileExistsError(f"{option} {path} exists; pass --force to overwrite it")
    _check_writable_folder(path.parent, option, path)
    return path


def check_output_folder(path: Path, option: str) -> Path:
    """Check, before any work, that ``path`` is a folder we can write into (or create).

    Raises:
        ValueError: ``path`` is a file, or it (or its nearest existing parent) is not writable.

    """
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise ValueError(f"{option} {path} is a file, not a folder")
    _check_writable_folder(path, option, path)
    return path


def plot_formats() -> dict[str, str]:
    """Figure formats matplotlib can write: extension (without dot) -> description."""
    from matplotlib.backend_bases import FigureCanvasBase

    return dict(FigureCanvasBase.get_supported_filetypes())


def check_plot_file(path: Path | None, option: str = "--plot", force: bool = False) -> Path | None:
    """:func:`check_output_file` for a figure, on the name that will actually be written.

    A name without an extension gets matplotlib's default ``.png`` (``--plot out/gait`` writes
    ``out/gait.png``): that is the name returned and checked.

    Raises:
        ValueError: an extension matplotlib cannot write (the message lists those it can),
            or any reason of :func:`check_output_file`.

    """
    if path is None:
        return None
    path = Path(path)
    if path.name and not path.is_dir() and not path.suffix:
        path = path.with_name(path.name + ".png")
    formats = plot_formats()
    ext = path.suffix.lower().lstrip(".")
    if path.suffix and ext not in formats:
        raise ValueError(f"{option} {path}: matplotlib cannot write .{ext}; use one of .{', .'.join(sorted(formats))}")
    return check_output_file(path, option, force)


def check_outputs(args: argparse.Namespace) -> None:
    """Check ``--csv`` and ``--plot`` before any work (see :func:`check_output_file`, :func:`check_plot_file`).

    ``args.plot`` is replaced by the name that will be written (``.png`` added when it has no extension).
    """
    csv_path = check_output_file(args.csv, "--csv", args.force)
    plot_path = check_plot_file(args.plot, "--plot", args.force)
    if csv_path is not None and plot_path is not None and csv_path.resolve() == plot_path.resolve():
        raise ValueError(f"--csv and --plot name the same file {csv_path}")
    args.csv, args.plot = csv_path, plot_path
