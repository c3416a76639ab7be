"""Where the robot description and the committed results live. Importable from any working directory.

Both are read, never written, by the package: ``make urdf`` and the scripts of ``tools/`` write them.
"""

from __future__ import annotations

from pathlib import Path

from pasibot_pin.model.params import check_legs, check_variant

PACKAGE_ROOT: Path = Path(__file__).resolve().parent.parent
"""The ``pasibot_pin`` package folder."""


def _find_urdf_dir() -> Path:
    # Installed wheel: the top-level urdf/ folder is packaged as pasibot_pin/urdf.
    # Source checkout or editable install: it is the repository's top-level urdf/.
    for candidate in (PACKAGE_ROOT / "urdf", PACKAGE_ROOT.parent / "urdf"):
        if (candidate / "pasibot.urdf.xacro").is_file():
            return candidate
    raise FileNotFoundError(f"cannot find the urdf/ folder next to {PACKAGE_ROOT}")


URDF_DIR: Path = _find_urdf_dir()
"""Folder holding the xacro source and the rendered default URDFs."""

XACRO_PATH: Path = URDF_DIR / "pasibot.urdf.xacro"
"""The parametric xacro source."""

PACKAGE_DIRS: list[str] = [str(URDF_DIR)]
"""Package directories to resolve ``package://`` URIs (the model uses primitives only)."""


def urdf_path(variant: str = "spring", legs: int = 2) -> Path:
    """Path of the committed URDF rendered with default parameters.

    Args:
        variant: ``rigid``, ``parallel`` or ``spring``.
        legs: 1 or 2.

    Returns:
        The path ``urdf/pasibot_<variant>_<legs>leg.urdf`` inside the package.

    """
    return URDF_DIR / f"pasibot_{check_variant(variant)}_{check_legs(legs)}leg.urdf"


URDF_PATH: Path = URDF_DIR / "pasibot_spring_2leg.urdf"
"""The default robot: the ankle-spring biped."""


RESULTS_FOLDER: str = "results"
"""The folder of the committed results inside an installed package (``pasibot_pin/results``)."""


def result_path(name: str) -> Path:
    """The committed result ``name`` (``walking_map.csv``, ``answers_summary.json``, ...) the package reads at run time.

    Installed wheel: pyproject's force-include packages ``docs/results/NAME`` as ``pasibot_pin/results/NAME``.
    Source checkout or editable install: the repository's ``docs/results/NAME``, beside the package as ``urdf/``
    is. The one place the package looks for its data; it never writes there (``tools/`` does).

    Returns:
        The first of the two that exists; the packaged path when neither does (the caller's ``is_file()`` says so).

    """
    packaged = PACKAGE_ROOT / RESULTS_FOLDER / name
    for candidate in (packaged, PACKAGE_ROOT.parent / "docs" / RESULTS_FOLDER / name):
        if candidate.is_file():
            return candidate
    return packaged
