"""The biped's coordinate names, in one place: its two sides and the floating hip's indices.

The two-legged robot's root joint is the planar floating hip: q[HIP_X] forward [m], q[HIP_Z] up
[m], q[HIP_PITCH] counter-clockwise seen from the right [rad]; the velocity has the same three
first entries (nq == nv, every joint revolute or prismatic). Joint and frame names carry a side
prefix, ``right_`` or ``left_``.
"""

from __future__ import annotations

from pasibot_pin.errors import ParameterError

SIDES: tuple[str, str] = ("right", "left")
"""The two sides, right first (the right leg is the first stance leg)."""

HIP_X, HIP_Z, HIP_PITCH = 0, 1, 2
"""Indices of the floating hip's forward position, height and pitch in q and v."""


def other(side: str) -> str:
    """The other leg's side (``right`` <-> ``left``); ParameterError for anything else."""
    if side not in SIDES:
        raise ParameterError(f"unknown side {side!r}; valid: right, left")
    return SIDES[1] if side == SIDES[0] else SIDES[0]
