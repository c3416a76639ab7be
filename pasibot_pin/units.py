"""Units in CSV headers: each column's name gets its SI unit as a suffix (``theta_rad``, ``Ta_Nm``).

The studies name their columns plainly (``theta``, ``Ta``, ``ground_Fx``) and always hold SI
values; the CSV writers pass every header through :func:`with_unit`, so a table read without
its documentation still says what it holds. Dimensionless columns and labels (``stance``,
``feasible``, ``mu_needed``, ``cot_*``, the contact modes) keep their names, as do names that
already end in a unit (``hip_pitch_deg``, ``stride_m``).
"""

from __future__ import annotations

UNIT_SUFFIXES: tuple[str, ...] = (
    "_s", "_rad", "_deg", "_m", "_N", "_Nm", "_J", "_kg", "_m_s", "_m_s2", "_rad_s", "_Nm_rad", "_W",
)  # fmt: skip
"""Suffixes that already name a unit: a column ending in one is left as it is."""

EXACT: dict[str, str] = {
    "t": "s",
    "theta": "rad",
    "theta_left": "rad",
    "theta_right": "rad",
    "beta": "rad",
    "beta_swing": "rad",
    "beta_right": "rad",
    "beta_left": "rad",
    "Ta": "Nm",
    "Te": "Nm",
    "Ta_swing": "Nm",
    "Te_swing": "Nm",
    "Ta_right": "Nm",
    "Ta_left": "Nm",
    "motor": "Nm",
    "Fx": "N",
    "Fz": "N",
    "My": "Nm",
    "s_cop": "m",
    "cop_x": "m",
    "margin": "m",
    "swing_sole_height": "m",
    "omega": "rad_s",
    "mass": "kg",
    "distance": "m",
    "speed": "m_s",
    "dE": "J",
    "single_peak": "Nm",
    "single_rms": "Nm",
    "spring_K_e": "Nm_rad",
    "spring_beta0": "rad",
    "spring_stored": "J",
    "spring_released": "J",
    "spring_residual_net": "J",
    "spring_residual_pos": "J",
}
"""Column name -> unit, for the names no pattern below covers."""

PATTERNS: tuple[tuple[str, str, str], ...] = (
    ("prefix", "W_", "J"),  # work
    ("suffix", "_crank_torque", "Nm"),
    ("suffix", "_Fx", "N"),
    ("suffix", "_Fz", "N"),
    ("suffix", "_Fn", "N"),
    ("suffix", "_Ft", "N"),
    ("suffix", "_M", "Nm"),
    ("suffix", "_pitch", "rad"),
    ("suffix", "_vx", "m_s"),
    ("suffix", "_vz", "m_s"),
    ("suffix", "_ax", "m_s2"),
    ("suffix", "_az", "m_s2"),
    ("suffix", "_x", "m"),
    ("suffix", "_z", "m"),
)
"""(kind, text, unit): a column starting or ending with ``text`` is in ``unit`` (first match wins)."""


def unit_of(name: str) -> str | None:
    """The SI unit of column ``name`` as a suffix text (``Nm``, ``m_s``), or ``None`` (dimensionless, a label)."""
    if name in EXACT:
        return EXACT[name]
    for kind, text, unit in PATTERNS:
        if (kind == "prefix" and name.startswith(text)) or (kind == "suffix" and name.endswith(text)):
            return unit
    return None


def with_unit(name: str) -> str:
    """``name`` with its unit appended (``theta`` -> ``theta_rad``); unchanged if it has one or none applies."""
    if name.endswith(UNIT_SUFFIXES):
        return name
    unit = unit_of(name)
    return name if unit is None else f"{name}_{unit}"
