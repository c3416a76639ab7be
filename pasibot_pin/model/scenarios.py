"""Scenarios and modelling presets of the torque analysis (seed §7, docs/reference.md §5): data only.

A :class:`Scenario` is what the seed varied between its runs: crank speed, body mass and
body COM. A :class:`ModelChoices` is *how* the torques are computed: every modelling choice
of the seed's MATLAB code is one field, so each can be switched on alone. The ``seed``
preset switches all of them on and reproduces the seed's stored K_e numbers.

Units: SI; angles [rad].
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

from pasibot_pin.errors import ParameterError

SEED_STEP: float = 0.1
"""The seed's crank sample step [rad] (``Theta1 = 0:0.1:2*pi``)."""

SEED_FIT_THETAS: tuple[float, ...] = tuple(round(2.6 + SEED_STEP * k, 10) for k in range(23))
"""The seed's 23 fit samples, right crank at 2.6, 2.7, ..., 4.8 rad (MATLAB indices 27:49)."""

SEED_FOOT_PARTS: tuple[float, float] = (1.0, 0.3)
"""The seed's foot split into a toe part and a heel part [kg] (1.3 kg rounded to 0.1 kg)."""


def seed_foot_com(toe: float, heel: float) -> float:
    """COM of the seed's two-part foot ahead of the ankle [m] (toe and heel bars, point masses mid-bar).

    Args:
        toe: ankle-to-toe length [m] (the geometry's, ``Geometry.foot_extent``).
        heel: ankle-to-heel length [m].

    """
    m_toe, m_heel = SEED_FOOT_PARTS
    return (m_toe * toe / 2 - m_heel * heel / 2) / (m_toe + m_heel)


DEFAULT_BODY_MASS: float = 16.0
"""The body (hip) mass of the seed's runs 1 and 2 as its text states it [kg]: the default body of the
energy and contact studies (:data:`SCENARIOS` holds every run's own)."""

SEED_ROUNDED_LINK_MASSES: Mapping[str, float] = {
    "l1": 0.3,
    "l2": 1.4,
    "l3": 0.7,
    "l4": 2.5,
    "l5": 2.4,
    "l6": 1.7,
    "l7": 0.8,
}
"""Seed Tab 7.1.2: the percentage-rule link masses rounded to 0.1 kg, as its code uses them [kg]."""

SEED_ROUNDED_FOOT_MASS: float = 1.3
"""The seed's foot mass as its code uses it [kg]: the percentage rule's foot rounded to 0.1 kg (the
toe and heel parts of :data:`SEED_FOOT_PARTS` together)."""


@dataclass(frozen=True)
class Scenario:
    """One run of the seed's torque analysis.

    Attributes:
        name: key in :data:`SCENARIOS`.
        omega: crank speed [rad/s]; 0 means quasi-static (v = a = 0).
        body_mass: body (hip) mass as the seed's text states it [kg].
        seed_body_mass: the body mass its code actually used [kg] (16.3 for "16 kg").
        body_com_dx: body COM ahead of joint 8 [m].
        seed_K_e: the seed's stored K_e [N.m/rad] (``None`` where it only states "about").
        seed_K_e_clean: the seed's model without the L5/L6 swap and the acceleration lag [N.m/rad].
        description: one line for reports.

    """

    name: str
    omega: float
    body_mass: float
    seed_body_mass: float
    body_com_dx: float
    seed_K_e: float | None
    seed_K_e_clean: float | None
    description: str

    @property
    def quasi_static(self) -> bool:
        """True when the run is quasi-static (omega = 0)."""
        return self.omega == 0.0


SCENARIOS: Mapping[str, Scenario] = {
    "quasi-static": Scenario(
        "quasi-static", 0.0, 16.0, 16.3, 0.0, None, None, "seed §7.3: static equilibrium, body 16 kg at joint 8"
    ),
    "run1": Scenario("run1", 0.1, 16.0, 16.3, 0.0, 331.05, 332.05, "seed §7.4.2: 0.1 rad/s, body 16 kg at joint 8"),
    "run2": Scenario("run2", 0.1, 16.0, 16.3, 0.30, 331.05, 332.05, "seed §7.4.3: 0.1 rad/s, body 16 kg, COM +0.30 m"),
    "run3": Scenario("run3", 0.1, 30.0, 30.0, 0.30, 453.21, 454.20, "seed §7.4.4: 0.1 rad/s, body 30 kg, COM +0.30 m"),
    "run4": Scenario("run4", 5.0, 20.0, 20.0, 0.30, 424.22, 395.74, "seed §7.4.5: 5 rad/s, body 20 kg, COM +0.30 m"),
}
"""The seed's quasi-static run and its four dynamic runs (docs/reference.md §5 table)."""

ACCELERATION_MODES: tuple[str, ...] = ("exact", "central", "lagged")
SWING_FOOT_MODES: tuple[str, ...] = ("level", "square")
MASS_MODES: tuple[str, ...] = ("exact", "rounded")


@dataclass(frozen=True)
class ModelChoices:
    """How the torques are computed. Each field is one modelling choice.

    Attributes:
        masses: ``exact`` (percentage rule, body mass of the scenario's text) or ``rounded``
            (the seed code's masses rounded to 0.1 kg, body 16.3 kg for "16 kg").
        swap_l5_l6: give L5 the mass of L6 and vice versa (the seed's dynamic script does).
        swing_foot: ``level`` (parallel to the ground) or ``square`` (rigid at 90 deg to its shank).
        seed_foot: the seed's foot, toe part 1.0 kg and heel part 0.3 kg: COM 0.02596 m
            ahead of the ankle (else a uniform sole, COM 0.025 m).
        accelerations: ``exact`` (closure derivatives), ``central`` (second differences of
            the COM positions with step ``step``) or ``lagged`` (the same, each used one
            sample late, as the seed does).
        step: crank sample step of the differences [rad].
        fit_thetas: stance-crank angles of the fit window [rad]; ``None``: every stance sample.
        inertia: ``point`` masses or ``uniform`` rods.

    """

    masses: str = "exact"
    swap_l5_l6: bool = False
    swing_foot: str = "level"
    seed_foot: bool = False
    accelerations: str = "exact"
    step: float = SEED_STEP
    fit_thetas: tuple[float, ...] | None = None
    inertia: str = "point"

    def __post_init__(self) -> None:
        for name, value, valid in (
            ("masses", self.masses, MASS_MODES),
            ("swing_foot", self.swing_foot, SWING_FOOT_MODES),
            ("accelerations", self.accelerations, ACCELERATION_MODES),
            ("inertia", self.inertia, ("point", "uniform")),
        ):
            if value not in valid:
                raise ParameterError(f"unknown {name} {value!r}; valid: {', '.join(valid)}")
        if not (math.isfinite(self.step) and self.step > 0):
            raise ParameterError(f"parameter 'step' must be a positive angle [rad], got {self.step!r}")
        if self.accelerations != "exact" and self.inertia != "point":
            raise ParameterError("difference accelerations (the seed's) need point masses: set inertia='point'")

    def with_(self, **changes: Any) -> ModelChoices:
        """Copy with some choices changed."""
        return replace(self, **changes)


_SEED = ModelChoices(
    masses="rounded",
    swap_l5_l6=True,
    swing_foot="square",
    seed_foot=True,
    accelerations="lagged",
    fit_thetas=SEED_FIT_THETAS,
)

PRESETS: Mapping[str, ModelChoices] = {
    "default": ModelChoices(),
    "seed": _SEED,
    # the seed's model with its two bugs undone: no L5/L6 mass swap, exact accelerations
    "seed-clean": replace(_SEED, swap_l5_l6=False, accelerations="exact"),
}
"""``default``: the physically right model. ``seed``: every choice of the seed's code.
``seed-clean``: the seed's model with the L5/L6 swap undone and exact accelerations."""

SEED_CHOICE_NAMES: Mapping[str, str] = {
    "masses": "masses rounded to 0.1 kg (body 16.3 kg)",
    "seed_foot": "foot of 1.0 + 0.3 kg parts (COM 0.02596 m)",
    "swing_foot": "swing foot rigid at 90 deg to its shank",
    "fit_thetas": "fit on the 23 samples theta = 2.6..4.8 rad",
    "swap_l5_l6": "L5/L6 masses swapped",
    "accelerations": "0.1 rad second differences used one sample late",
}
"""Human names of the seed's choices, in the order the attribution table switches them on."""


def get_scenario(name: str | int) -> Scenario:
    """The scenario called ``name``: ``quasi-static``, ``run1`` .. ``run4``, or just ``1`` .. ``4``.

    Every command and study names scenarios through this one function, so ``1`` and ``run1``
    are the same everywhere (ValueError naming the valid ones otherwise).
    """
    key = str(name)
    if key not in SCENARIOS and f"run{key}" in SCENARIOS:
        key = f"run{key}"
    if key not in SCENARIOS:
        raise ParameterError(f"unknown scenario {name!r}; valid: {', '.join(SCENARIOS)} (or 1..4)")
    return SCENARIOS[key]


def get_preset(name: str) -> ModelChoices:
    """The preset called ``name`` (ValueError naming the valid ones otherwise)."""
    if name not in PRESETS:
        raise ParameterError(f"unknown preset {name!r}; valid: {', '.join(PRESETS)}")
    return PRESETS[name]
