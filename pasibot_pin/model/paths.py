"""Where the robot description lives. Importable from any working directory."""

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
