"""Options and checks shared by several subcommands.

One grammar: the options several commands share (``--variant``, ``--legs``, ``--scenario``,
``--steps``, ``--fps``, ``--mu``, ``--out DIR``, ``--force``) are defined once here, with one
default each (:data:`DEFAULTS`); ``tests/test_cli_grammar.py`` checks every subcommand's parser
against it. A command that must know whether a shared option was given (``gait --steps`` with
one leg is refused) asks :func:`given`, so the default itself stays the same everywhere.

Every output path is checked before any work starts (:func:`check_output_file`,
:func:`check_output_folder`, :func:`check_plot_file`): not a folder, not an existing file
without ``--force``, a folder that exists and is writable or can be created, and for figures
an extension matplotlib can write. ``--force`` replaces regular files only: a symbolic link is
refused (naming the file it points to, so the user can name that file; the link is kept), and so
are devices, pipes and sockets. The checks raise ``ValueError`` or ``FileExistsError``, which
``pasibot`` prints as one line with exit code 2. A FILE option ending in ``/`` is refused (it names
a folder). The numeric flags' ranges are in :mod:`pasibot_pin.cli.bounds`.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from pasibot_pin.errors import ParameterError
from pasibot_pin.files import check_replaceable, temporary_name
from pasibot_pin.model.design import load_design
from pasibot_pin.model.params import SOLE_FLOOR_MU, VARIANTS
from pasibot_pin.model.scenarios import SCENARIOS
from pasibot_pin.report.files import atomic_path, atomic_paths, write_columns_csv

__all__ = [
    "DEFAULTS",
    "add_fps_option",
    "add_mu_option",
    "add_out_folder_option",
    "add_design_option",
    "add_output_options",
    "design_of",
    "add_robot_options",
    "add_scenario_option",
    "add_steps_option",
    "given",
    "atomic_path",
    "atomic_paths",
    "check_output_file",
    "check_output_folder",
    "check_outputs",
    "check_plot_file",
    "write_columns_csv",
]


DEFAULTS: dict[str, object] = {
    "--variant": "spring",
    "--legs": 2,
    "--scenario": "run1",
    "--steps": 2,
    "--fps": 30.0,
    "--mu": SOLE_FLOOR_MU,
    "--force": False,
}
"""The one default of each option several commands share (``--out DIR`` has none: each command names its folder)."""


class _Given(argparse.Action):
    """``store`` that also records the option in ``namespace._given`` (see :func:`given`)."""

    def __call__(self, parser, namespace, values, option_string=None):
        setattr(namespace, self.dest, values)
        recorded = set(getattr(namespace, "_given", ()))
        recorded.add(self.dest)
        namespace._given = recorded


def float_list(text: str) -> list[float]:
    """An argparse type: comma-separated numbers (``0.1,1,5``), at least one."""
    try:
        values = [float(x) for x in text.split(",") if x.strip()]
    except ValueError as err:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}") from err
    if not values:
        raise argparse.ArgumentTypeError("expected at least one number")
    return values


def file_path(text: str) -> Path:
    """An argparse type for a FILE option: a path that does not end in a separator (``out/new/`` is a folder)."""
    if text.endswith(("/", os.sep)):
        raise argparse.ArgumentTypeError(f"{text} ends in {os.sep}, so it names a folder; give a file name")
    return Path(text)


def given(args: argparse.Namespace, dest: str) -> bool:
    """Whether the shared option ``dest`` (e.g. ``"steps"``) was on the command line."""
    return dest in getattr(args, "_given", ())


def add_robot_options(parser: argparse.ArgumentParser, legs: bool = True) -> None:
    """``--variant`` and (unless ``legs`` is false) ``--legs``."""
    parser.add_argument(
        "--variant",
        default=DEFAULTS["--variant"],
        action=_Given,
        help=f"leg variant: {', '.join(VARIANTS)} (default spring)",
    )
    if legs:
        parser.add_argument(
            "--legs", type=int, default=DEFAULTS["--legs"], action=_Given, help="1 or 2 legs (default 2, the biped)"
        )


def add_scenario_option(parser: argparse.ArgumentParser) -> None:
    """``--scenario`` (a seed scenario: quasi-static, run1..run4 or 1..4)."""
    parser.add_argument(
        "--scenario",
        default=DEFAULTS["--scenario"],
        help=f"seed scenario: {', '.join(SCENARIOS)} (1..4 work too; default run1)",
    )


def add_steps_option(parser: argparse.ArgumentParser, what: str = "steps to walk, one per half crank turn") -> None:
    """``--steps`` (default 2); :func:`given` tells whether it was on the command line."""
    parser.add_argument("--steps", type=int, default=DEFAULTS["--steps"], action=_Given, help=f"{what} (default 2)")


def add_fps_option(parser: argparse.ArgumentParser) -> None:
    """``--fps``: animation frames per second (default 30)."""
    parser.add_argument("--fps", type=float, default=DEFAULTS["--fps"], help="animation frames per second (default 30)")


def add_mu_option(parser: argparse.ArgumentParser) -> None:
    """``--mu``: the sole-floor Coulomb friction coefficient (default :data:`SOLE_FLOOR_MU`)."""
    parser.add_argument(
        "--mu",
        type=float,
        default=DEFAULTS["--mu"],
        action=_Given,
        help=f"sole-floor Coulomb friction coefficient (default {SOLE_FLOOR_MU:g})",
    )


def add_out_folder_option(parser: argparse.ArgumentParser, default: Path | None, what: str) -> None:
    """``--out DIR``: the folder a command writes its files into."""
    text = f"output folder: {what}" + (f" (default {default}/)" if default is not None else "")
    parser.add_argument("--out", type=Path, default=default, metavar="DIR", help=text, action=_Given)


def add_design_option(parser: argparse.ArgumentParser) -> None:
    """``--design FILE``: a design file (.toml or .json) instead of the seed design."""
    parser.add_argument(
        "--design",
        type=Path,
        default=None,
        metavar="FILE",
        help="design file (.toml/.json: geometry, masses, spring, crank speed; default the seed design)",
    )


def design_of(args: argparse.Namespace):
    """The ``--design`` file's design, or ``None`` without ``--design``.

    ``--variant``, when given, replaces the design's variant. A bad file is a one-line ValueError.
    """
    if getattr(args, "design", None) is None:
        return None
    design = load_design(args.design)
    if given(args, "variant"):
        design = design.with_(variant=args.variant)
    return design


def add_force_option(parser: argparse.ArgumentParser, what: str = "overwrite existing output files") -> None:
    """``--force``."""
    parser.add_argument("--force", action="store_true", default=DEFAULTS["--force"], help=what)


def add_output_options(parser: argparse.ArgumentParser, csv_help: str, plot_help: str) -> None:
    """``--csv FILE``, ``--plot FILE``, ``--out DIR`` (both under their default names) and ``--force``."""
    parser.add_argument("--csv", type=file_path, default=None, metavar="FILE", help=csv_help)
    parser.add_argument(
        "--plot",
        type=file_path,
        default=None,
        metavar="FILE",
        help=f"{plot_help} (.png, .pdf, .svg, ...; no extension: .png)",
    )
    add_out_folder_option(parser, None, "write the CSV and the figure into DIR under their default names")
    add_force_option(parser)


def _check_writable_folder(folder: Path, option: str, path: Path) -> None:
    """``folder`` exists and is writable, or its nearest existing ancestor is a writable folder."""
    folder = Path(folder) if str(folder) else Path(".")
    probe = folder
    while not probe.exists():
        if probe.is_symlink():  # a dangling link: mkdir would fail
            raise ParameterError(f"{option} {path}: {probe} is a broken link")
        parent = probe.parent
        if parent == probe:
            break
        probe = parent
    if probe.exists() and not probe.is_dir():
        raise ParameterError(f"{option} {path}: {probe} is a file, not a folder")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise ParameterError(f"{option} {path}: folder {probe} is not writable")
    if probe != folder:  # the folder will be created: try it (/proc, /sys refuse even root)
        trial = temporary_name(probe / "probe")
        try:
            os.mkdir(trial, 0o700)
        except OSError as err:
            raise ParameterError(f"{option} {path}: cannot create a folder in {probe} ({err.strerror})") from None
        os.rmdir(trial)


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
        raise ParameterError(f"{option} {path} is a folder; give a file name")
    if os.path.lexists(path):
        if not force:
            raise FileExistsError(f"{option} {path} exists; pass --force to overwrite it")
        check_replaceable(path, option)  # --force replaces a regular file, never a device or a link
    _check_writable_folder(path.parent, option, path)
    _probe_folder(path.parent, option, path)
    return path


def _probe_folder(folder: Path, option: str, path: Path) -> None:
    """Create and remove a temporary file in ``folder`` when it exists.

    A folder that refuses files even to root (``/sys``, a read-only mount) is refused before any work.
    """
    folder = Path(folder) if str(folder) else Path(".")
    if not folder.is_dir():
        return  # created later, under an ancestor where a folder was created (checked)
    probe = temporary_name(folder / "probe")
    try:
        fd = os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except OSError as err:
        raise ParameterError(f"{option} {path}: cannot write in folder {folder} ({err.strerror})") from None
    os.close(fd)
    os.unlink(probe)


def check_output_folder(path: Path, option: str) -> Path:
    """Check, before any work, that ``path`` is a folder we can write into (or create).

    Raises:
        ValueError: ``path`` is a file, or it (or its nearest existing parent) is not writable.

    """
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise ParameterError(f"{option} {path} is a file, not a folder")
    _check_writable_folder(path, option, path)
    return path


def plot_formats() -> dict[str, str]:
    """Figure formats matplotlib can write: extension (without dot) -> description."""
    from matplotlib.backend_bases import FigureCanvasBase  # deferred: heavy (matplotlib), keeps the CLI's start fast

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
        raise ParameterError(
            f"{option} {path}: matplotlib cannot write .{ext}; use one of .{', .'.join(sorted(formats))}"
        )
    return check_output_file(path, option, force)


def check_outputs(args: argparse.Namespace, stem: str | None = None) -> None:
    """Check ``--csv`` and ``--plot`` before any work (see :func:`check_output_file`, :func:`check_plot_file`).

    With ``--out DIR`` (and a ``stem``), a CSV or figure not named by ``--csv``/``--plot`` is
    ``DIR/<stem>.csv`` and ``DIR/<stem>.png``. ``args.plot`` is replaced by the name that will be
    written (``.png`` added when it has no extension).
    """
    out = getattr(args, "out", None)
    csv_option, plot_option = "--csv", "--plot"
    if out is not None and stem is not None:
        check_output_folder(out, "--out")
        if args.csv is None:  # a file the user named by --out DIR: the messages name --out
            args.csv, csv_option = Path(out) / f"{stem}.csv", "--out"
        if args.plot is None:
            args.plot, plot_option = Path(out) / f"{stem}.png", "--out"
    csv_path = check_output_file(args.csv, csv_option, args.force)
    plot_path = check_plot_file(args.plot, plot_option, args.force)
    if csv_path is not None and plot_path is not None and csv_path.resolve() == plot_path.resolve():
        raise ParameterError(f"--csv and --plot name the same file {csv_path}")
    args.csv, args.plot = csv_path, plot_path
