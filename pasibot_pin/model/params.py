"""Parameters of PASIBOT as data: geometry, masses, variants.

All lengths are in metres, masses in kilograms. Link lengths are stored as ratios of the
crank length ``L`` (seed tables 3.1.1 to 3.6.1) so that one number rescales the robot.

Nothing here computes kinematics or dynamics: this module only holds and validates numbers.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace
from typing import Any

from pasibot_pin.errors import ParameterError
from pasibot_pin.model.variants import VARIANT_RECORDS, Variant, get_variant

VARIANTS: tuple[str, ...] = tuple(VARIANT_RECORDS)
"""The leg variants of the seed: foot rigid to L5 (§4.2), parallel extension (§4.3),
revolute ankle with a torsion spring (§7); their records are :data:`~pasibot_pin.model.variants.VARIANT_RECORDS`."""

LEG_COUNTS: tuple[int, ...] = (1, 2)

GRAVITY: float = 9.81
"""Gravitational acceleration [m/s^2] (the seed's value)."""

SOLE_FLOOR_MU: float = 0.8
"""The sole-floor Coulomb friction coefficient every study and command takes by default [-]
(the contact study, the floor simulation, the MJCF export; issue 12: 0.8)."""

# Seed tables 3.1.1, 3.2.1, 3.5.1, 3.6.1: link length / crank length L.
SEED_LINK_RATIOS: Mapping[str, float] = {
    "r1": 1.0,  # L1 crank
    "r2": 5.0,  # L2 coupler, 1-2-4 (2 at its mid-point)
    "r3": 2.5,  # L3 rocker, 3-2
    "r4": 9.0,  # L4, 4-5-6
    "r5": 18.0,  # L5 shank, 6-7-13
    "r6": 6.0,  # L6, 8-5
    "r7": 6.0,  # L7, 8-7
    "r8": 4.2,  # L8 stabiliser, 10-9-4
    "r9": 9.0,  # L9, 9-11
    "r10": 2.1,  # L10, 6-11 (and the foot bar 12-13)
    "r11": 18.0,  # L11, 11-12
    "r12": 4.0,  # L12, slider line below joint 0
    "r13": 12.0,  # L13, joint 8 below joint 3
}

# Seed Table 7.1.1: percentage of the total human mass.
SEED_MASS_FRACTIONS: Mapping[str, float] = {
    "hip": 0.25,
    "thigh": 0.10,
    "shank": 0.05,
    "foot": 0.02,
}
SEED_TOTAL_MASS: float = 65.0
"""The seed's nominal total mass [kg]. The modelled parts only add up to about 38 kg."""

THIGH_LINKS: tuple[str, ...] = ("l1", "l2", "l3", "l4", "l6")
SHANK_LINKS: tuple[str, ...] = ("l5", "l7")
EXTENSION_LINKS: tuple[str, ...] = ("l8", "l9", "l10", "l11", "foot_bar")
MASS_LINKS: tuple[str, ...] = (*THIGH_LINKS, *SHANK_LINKS, "slider", *EXTENSION_LINKS)
"""Every key a :class:`MassModel` may give a mass."""


def required_mass_links(variant: str | Variant) -> tuple[str, ...]:
    """The link masses a leg of ``variant`` needs (:attr:`MassModel.links` keys)."""
    names = ("l1", "l2", "l3", "l4", "l5", "l6", "l7")
    return names + ("slider", *EXTENSION_LINKS) if get_variant(variant).extension else names


LENGTH_RANGE: tuple[float, float] = (1e-12, 1e12)
"""Accepted crank length L and hip half width [m]: wide, but every length, square and mass stays a finite float."""

RATIO_RANGE: tuple[float, float] = (1e-3, 1e3)
"""Accepted dimensionless sizes (K, link ratios, sole extents over L) [-]."""


def _check_positive(name: str, value: float) -> float:
    """``value`` as a float if it is a positive finite number (not a bool, not a string), else ParameterError."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ParameterError(f"parameter {name!r} must be a positive finite number, got {short_repr(value)}")
    try:
        number = float(value)
    except OverflowError:
        number = math.inf
    if not math.isfinite(number) or number <= 0.0:
        raise ParameterError(f"parameter {name!r} must be a positive finite number, got {short_repr(value)}")
    return number


def short_repr(value: object) -> str:
    """``repr(value)``, cut to a readable length (a 5,000-digit integer is named by its size)."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > 10**15:
        return f"a {len(str(abs(value))) if abs(value) < 10**4000 else 'more than 4000'}-digit integer"
    try:
        text = repr(value)
    except RecursionError:  # a list nested thousands deep
        return f"a deeply nested {type(value).__name__}"
    return text if len(text) <= 60 else text[:57] + "..."


def _check_range(name: str, value: float, bounds: tuple[float, float], unit: str) -> float:
    value = _check_positive(name, value)
    low, high = bounds
    if not low <= value <= high:
        raise ParameterError(f"parameter {name!r} = {value!r} {unit} is outside [{low:g}, {high:g}] {unit}")
    return value


def check_variant(variant: str | Variant) -> str:
    """Return ``variant`` if it is known, else raise ``ValueError`` listing the valid ones."""
    return get_variant(variant).name


def check_legs(legs: int) -> int:
    """Return ``legs`` if it is 1 or 2, else raise ``ValueError``."""
    if isinstance(legs, bool) or not isinstance(legs, numbers.Integral) or legs not in LEG_COUNTS:
        raise ParameterError(f"parameter 'legs' must be the integer 1 or 2, got {short_repr(legs)}")
    return int(legs)


@dataclass(frozen=True)
class Geometry:
    """Leg geometry.

    Attributes:
        L: crank length [m].
        K: ratio L0 / L of the frame link 0-3 [-].
        ratios: link lengths over L, keys ``r1`` .. ``r13`` (seed Tab 3.6.1) [-].
        foot_toe: ankle-to-toe distance along the sole, over L [-] (rigid, spring).
        foot_heel: ankle-to-heel distance along the sole, over L [-] (rigid, spring).
        parallel_toe: toe ahead of joint 13, over L [-] (parallel variant).
        parallel_heel: heel behind joint 13, over L [-] (parallel variant; the seed's
            "BF 4.1L" is measured from the toe, so heel = 4.1 - 1.5).
        hip_half_width: lateral offset of each leg's plane from the hip centre [m].

    """

    L: float = 0.05
    K: float = 2.0
    ratios: Mapping[str, float] = field(default_factory=lambda: dict(SEED_LINK_RATIOS))
    foot_toe: float = 1.5
    foot_heel: float = 0.5
    parallel_toe: float = 1.5
    parallel_heel: float = 2.6
    hip_half_width: float = 0.1

    def __post_init__(self) -> None:
        object.__setattr__(self, "L", _check_range("L", self.L, LENGTH_RANGE, "m"))
        object.__setattr__(self, "K", _check_range("K", self.K, RATIO_RANGE, "[-]"))
        if not isinstance(self.ratios, Mapping):
            raise ParameterError(f"parameter 'ratios' must map r1..r13 to numbers, got {self.ratios!r}")
        unknown = set(self.ratios) - set(SEED_LINK_RATIOS)
        if unknown:
            raise ParameterError(f"unknown link ratio(s) {sorted(unknown)}; valid: {list(SEED_LINK_RATIOS)}")
        merged = dict(SEED_LINK_RATIOS)
        merged.update(self.ratios)
        for key, value in merged.items():
            merged[key] = _check_range(key, value, RATIO_RANGE, "[-]")
        object.__setattr__(self, "ratios", merged)
        for name in ("foot_toe", "foot_heel", "parallel_toe", "parallel_heel"):
            object.__setattr__(self, name, _check_range(name, getattr(self, name), RATIO_RANGE, "[-]"))
        object.__setattr__(
            self, "hip_half_width", _check_range("hip_half_width", self.hip_half_width, LENGTH_RANGE, "m")
        )
        if merged["r4"] <= merged["r7"]:
            raise ParameterError("parameter 'r4' must exceed 'r7' (joint 5 lies on L4 at L4 - L7 from joint 4)")
        if merged["r5"] <= merged["r6"]:
            raise ParameterError("parameter 'r5' must exceed 'r6' (joint 7 lies on L5 at L6 from joint 6)")

    def length(self, index: int) -> float:
        """Length of link ``L<index>`` [m]; ``length(0)`` is the frame link K*L."""
        if index == 0:
            return self.K * self.L
        return self.ratios[f"r{index}"] * self.L

    def with_(self, **changes: float) -> Geometry:
        """Copy with some fields or link ratios changed (``r4=9.5``, ``K=2.2``, ...)."""
        ratio_changes = {k: v for k, v in changes.items() if k in SEED_LINK_RATIOS}
        other = {k: v for k, v in changes.items() if k not in SEED_LINK_RATIOS}
        valid = {f.name for f in fields(self)}
        bad = set(other) - valid
        if bad:
            raise ParameterError(
                f"unknown geometry parameter(s) {sorted(bad)}; valid: {sorted(valid | set(SEED_LINK_RATIOS))}"
            )
        if "ratios" in other:
            given = other.pop("ratios")
            if not isinstance(given, Mapping):
                raise ParameterError(f"parameter 'ratios' must map r1..r13 to numbers, got {given!r}")
            ratio_changes = {**given, **ratio_changes}
        ratios = dict(self.ratios)
        ratios.update(ratio_changes)
        return replace(self, ratios=ratios, **other)

    def foot_extent(self, variant: str | Variant) -> tuple[float, float]:
        """(toe, heel) distances from the ankle along the sole [m] for ``variant``."""
        toe, heel = get_variant(variant).foot_fields
        return getattr(self, toe) * self.L, getattr(self, heel) * self.L


@dataclass(frozen=True)
class MassModel:
    """Point masses of one leg and of the hip [kg], and where the masses sit.

    Every link carries its mass at its mid-point, with no rotational inertia (seed §7).

    Attributes:
        hip: mass of the hip (body) [kg].
        links: mass of each leg link, keys ``l1`` .. ``l11``, ``slider``, ``foot_bar`` [kg].
        foot: mass of each foot [kg].
        foot_com: position of the foot's centre of mass ahead of the ankle along the sole [m].
        hip_com: (x, z) of the body's centre of mass relative to joint 8, hip frame [m].
        rule: name of the rule that produced the masses.

    """

    hip: float
    links: Mapping[str, float]
    foot: float
    foot_com: float
    hip_com: tuple[float, float] = (0.0, 0.0)
    rule: str = "custom"

    def __post_init__(self) -> None:
        _check_positive("hip mass", self.hip)
        _check_positive("foot mass", self.foot)
        if not isinstance(self.links, Mapping):
            raise ParameterError(f"parameter 'links' must map link names to masses, got {self.links!r}")
        unknown = set(self.links) - set(MASS_LINKS)
        if unknown:
            raise ParameterError(
                f"parameter 'links': unknown link(s) {sorted(unknown)}; valid: {', '.join(MASS_LINKS)}"
            )
        for key, value in self.links.items():
            _check_positive(f"mass of {key}", value)
        for value, name in ((self.foot_com, "foot_com"), *zip(self.hip_com, ("hip_com x", "hip_com z"))):
            if not math.isfinite(float(value)):
                raise ParameterError(f"parameter {name!r} must be finite, got {value!r}")

    def with_(self, **changes: Any) -> MassModel:
        """Copy with some fields changed (``hip=30.0``, ``hip_com=(0.3, 0.0)``, ...)."""
        return replace(self, **changes)

    def check_links(self, variant: str | Variant) -> None:
        """Raise ``ValueError`` naming the links ``variant`` needs that have no mass here."""
        missing = [n for n in required_mass_links(variant) if n not in self.links]
        if missing:
            raise ParameterError(
                f"parameter 'links' of the mass model lacks {', '.join(missing)} "
                f"(the {get_variant(variant).name} variant needs {', '.join(required_mass_links(variant))})"
            )


def _shared_by_length(total: float, names: tuple[str, ...], geometry: Geometry) -> dict[str, float]:
    lengths = {n: geometry.length(int(n[1:])) for n in names}
    norm = sum(lengths.values())
    return {n: total * lengths[n] / norm for n in names}


def _foot_com(geometry: Geometry, variant: str) -> float:
    """COM of a uniform sole from heel to toe, measured ahead of the ankle [m]."""
    toe, heel = geometry.foot_extent(variant)
    return (toe - heel) / 2.0


def percentage_mass_model(
    geometry: Geometry | None = None,
    variant: str = "spring",
    total_mass: float = SEED_TOTAL_MASS,
    fractions: Mapping[str, float] = SEED_MASS_FRACTIONS,
    rule: str = "seed-percentages",
) -> MassModel:
    """Masses from a human-percentage rule (seed §7.1, Table 7.1.1).

    The hip gets ``fractions['hip']``; the thigh fraction is shared by length over L1, L2,
    L3, L4, L6; the shank fraction over L5, L7; each foot gets ``fractions['foot']``.
    The parallel extension (not in the seed's mass table) is given the thigh's mass per
    unit length: L8, L9, L10, L11, the foot bar (length L10) and a slider block one crank
    length long.

    Args:
        geometry: leg geometry (default: the seed's, L = 0.05 m).
        variant: leg variant, for the foot's extent.
        total_mass: total human mass the percentages refer to [kg].
        fractions: keys ``hip``, ``thigh``, ``shank``, ``foot``, each a fraction of
            ``total_mass``.
        rule: a name recorded in the result.

    Returns:
        The mass model.

    """
    geometry = geometry or Geometry()
    check_variant(variant)
    _check_positive("total_mass", total_mass)
    missing = {"hip", "thigh", "shank", "foot"} - set(fractions)
    if missing:
        raise ParameterError(f"mass fractions lack {sorted(missing)}")
    for key in ("hip", "thigh", "shank", "foot"):
        _check_positive(f"mass fraction {key}", fractions[key])
    links = _shared_by_length(total_mass * fractions["thigh"], THIGH_LINKS, geometry)
    links.update(_shared_by_length(total_mass * fractions["shank"], SHANK_LINKS, geometry))
    thigh_length = sum(geometry.length(int(n[1:])) for n in THIGH_LINKS)
    density = total_mass * fractions["thigh"] / thigh_length  # [kg/m]
    for index in (8, 9, 10, 11):
        links[f"l{index}"] = density * geometry.length(index)
    links["foot_bar"] = density * geometry.length(10)
    links["slider"] = density * geometry.L
    return MassModel(
        hip=total_mass * fractions["hip"],
        links=links,
        foot=total_mass * fractions["foot"],
        foot_com=_foot_com(geometry, variant),
        rule=rule,
    )


def human_description_fractions() -> dict[str, float]:
    """Segment mass fractions of example-robot-data's ``human_description`` model.

    The data are read from the installed ``example-robot-data`` distribution (found
    through its file list, not a hard-coded path): pelvis, upper leg, lower leg and foot
    masses over the model's total mass.

    Returns:
        ``{'hip', 'thigh', 'shank', 'foot'}`` fractions of the total mass, and ``total``
        [kg] under the key ``'total_mass'``.

    """
    import xml.etree.ElementTree as ET  # deferred: keeps the CLI's start fast
    from importlib.metadata import PackageNotFoundError, distribution  # deferred: keeps the CLI's start fast

    try:
        dist = distribution("example-robot-data")
    except PackageNotFoundError as err:  # pragma: no cover - dependency is mandatory
        raise RuntimeError("example-robot-data is not installed") from err
    candidates = [f for f in dist.files or [] if str(f).endswith("human_description/robots/human.urdf")]
    if not candidates:
        raise RuntimeError("example-robot-data has no human_description/robots/human.urdf")
    root = ET.parse(candidates[0].locate()).getroot()
    masses = {}
    for link in root.findall("link"):
        mass = link.find("inertial/mass")
        if mass is not None:
            masses[str(link.get("name"))] = float(mass.attrib["value"])
    total = sum(masses.values())
    return {
        "hip": masses["middle_pelvis"] / total,
        "thigh": masses["right_upperleg"] / total,
        "shank": masses["right_lowerleg"] / total,
        "foot": masses["right_foot"] / total,
        "total_mass": total,
    }


def human_description_mass_model(
    geometry: Geometry | None = None, variant: str = "spring", total_mass: float = SEED_TOTAL_MASS
) -> MassModel:
    """Masses from the segment fractions of example-robot-data's human model.

    Same sharing rule as :func:`percentage_mass_model`, with the fractions of
    :func:`human_description_fractions` (pelvis 14.3 %, thigh 12.3 %, shank 4.8 %,
    foot 1.2 %).
    """
    fractions = human_description_fractions()
    return percentage_mass_model(geometry, variant, total_mass, fractions, rule="example-robot-data human")


MASS_RULES = {
    "seed": percentage_mass_model,
    "human": human_description_mass_model,
}
