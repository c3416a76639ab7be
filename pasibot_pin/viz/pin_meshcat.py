"""Pinocchio's ``MeshcatVisualizer``, imported without the packages of Pinocchio's viser viewer.

``pinocchio.visualize`` imports every viewer it ships. With coal installed its viser viewer runs
``import trimesh`` and ``import viser`` and, when either fails, only marks itself unusable. We never
use it, and trimesh alone pulls in scipy.spatial and networkx: 1.2 s of CPU in every process that
draws a 3-D page. So while ``pinocchio.visualize`` is first imported here, the packages of
:data:`SKIPPED` that are not imported yet fail at once (a ``None`` entry in ``sys.modules``); they
are importable again afterwards. The meshcat viewer is the same class either way.

Importing this module is the import (``pasibot analyze`` does it before its workers fork).
"""

from __future__ import annotations

import sys

SKIPPED: tuple[str, ...] = ("trimesh", "viser")
"""What ``pinocchio.visualize`` imports for its viser viewer only."""

_blocked = [] if "pinocchio.visualize" in sys.modules else [name for name in SKIPPED if name not in sys.modules]
try:
    for _name in _blocked:
        sys.modules[_name] = None  # type: ignore[assignment]  # import's documented "fail at once" entry
    from pinocchio.visualize import MeshcatVisualizer
finally:
    for _name in _blocked:
        if _name in sys.modules and sys.modules[_name] is None:
            del sys.modules[_name]

__all__ = ["SKIPPED", "MeshcatVisualizer"]
