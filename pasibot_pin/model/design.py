"""The design record: every parameter a user may change, with its unit and its bounds (data only).

A :class:`Design` is one PASIBOT: its variant and motor layout, its geometry (L, K, the link
ratios, the sole), its masses (the human-percentage rule, the body's mass and COM), its ankle
spring and its crank speed. It is the one parameter object the studies take, the row a design
sweep varies, and a file (TOML or JSON) the command line reads with ``--design FILE``.

Each numeric parameter has a :class:`ParameterSpec`: unit, default (the seed's design) and
the bounds a sweep may explore. A value outside its bounds, NaN, or an unknown name is
rejected with a one-line :class:`~pasibot_pin.errors.ParameterError` (a ``ValueError``) naming the
parameter, before any work starts.

Units: SI; link ratios and sole lengths over the crank length L; angles [rad].
"""

from __future__ import annotations

import json
import math
import numbers
import os
import sys
import tempfile
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from pasibot_pin.errors import ParameterError
from pasibot_pin.model.params import (
    MASS_RULES,
    SEED_LINK_RATIOS,
    SEED_MASS_FRACTIONS,
    SEED_TOTAL_MASS,
    VARIANTS,
    Geometry,
    MassModel,
    human_description_fractions,
    percentage_mass_model,
    short_repr,
)
from pasibot_pin.model.robot import load
from pasibot_pin.model.scenarios import DEFAULT_BODY_MASS
from pasibot_pin.model.spatial import CENTRED_SOLE, Footprint, LateralMass
from pasibot_pin.model.variants import MOTOR_LAYOUTS

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib


@dataclass(frozen=True)
class ParameterSpec:
    """One numeric design parameter.

    Attributes:
        name: its name in the record, in files and in sweep tables (``L``, ``K``, ``r4`` ...).
        unit: its unit (``m``, ``kg``, ``rad/s``, ``L`` for multiples of the crank length, ``-``).
        default: the seed design's value.
        low: the smallest value a sweep may use.
        high: the largest value a sweep may use.
        doc: what it is, in a few words.

    """

    name: str
    unit: str
    default: float
    low: float
    high: float
    doc: str


def _ratio_spec(key: str, value: float) -> ParameterSpec:
    return ParameterSpec(key, "L", value, 0.5 * value, 2.0 * value, f"link L{key[1:]} over the crank length")


SPECS: Mapping[str, ParameterSpec] = {
    spec.name: spec
    for spec in (
        ParameterSpec("L", "m", Geometry.L, 0.005, 2.0, "crank length"),
        ParameterSpec("K", "-", Geometry.K, 1.0, 4.0, "frame link 0-3 over L (a full crank turn needs 1.491 < K < 3)"),
        *(_ratio_spec(k, v) for k, v in SEED_LINK_RATIOS.items()),
        ParameterSpec("foot_toe", "L", Geometry.foot_toe, 0.1, 10.0, "ankle to toe along the sole (rigid, spring)"),
        ParameterSpec("foot_heel", "L", Geometry.foot_heel, 0.1, 10.0, "ankle to heel along the sole (rigid, spring)"),
        ParameterSpec("parallel_toe", "L", Geometry.parallel_toe, 0.1, 10.0, "toe ahead of joint 13 (parallel)"),
        ParameterSpec("parallel_heel", "L", Geometry.parallel_heel, 0.1, 10.0, "heel behind joint 13 (parallel)"),
        ParameterSpec(
            "sole_inner", "L", CENTRED_SOLE, 0.0, 10.0, "sole's reach from its leg plane to the midline (3-D)"
        ),
        ParameterSpec("sole_outer", "L", CENTRED_SOLE, 0.0, 10.0, "sole's reach from its leg plane outward (3-D)"),
        ParameterSpec("sole_gap_from", "L", 0.0, 0.0, 10.0, "sole cut away toward the midline from here (a comb) ..."),
        ParameterSpec("sole_gap_to", "L", 0.0, 0.0, 10.0, "... to here (0, 0: no gap)"),
        ParameterSpec("hip_half_width", "L", Geometry.hip_half_width / Geometry.L, 0.5, 20.0, "leg plane to midline"),
        ParameterSpec("total_mass", "kg", SEED_TOTAL_MASS, 5.0, 500.0, "human mass the percentages refer to"),
        ParameterSpec("thigh_fraction", "-", SEED_MASS_FRACTIONS["thigh"], 0.005, 0.5, "thigh links' share"),
        ParameterSpec("shank_fraction", "-", SEED_MASS_FRACTIONS["shank"], 0.005, 0.5, "shank links' share"),
        ParameterSpec("foot_fraction", "-", SEED_MASS_FRACTIONS["foot"], 0.002, 0.5, "each foot's share"),
        ParameterSpec("body_mass", "kg", DEFAULT_BODY_MASS, 0.5, 500.0, "body (hip) mass"),
        ParameterSpec("body_com_dx", "m", 0.0, -1.0, 1.0, "body COM ahead of joint 8"),
        ParameterSpec("lateral_mass", "kg", math.nan, 0.0, 500.0, "share of the body the crank moves sideways (3-D)"),
        ParameterSpec("lateral_amplitude", "L", math.nan, 0.0, 20.0, "its sideways reach each side of the midline"),
        ParameterSpec(
            "lateral_phase", "rad", math.nan, -2 * math.pi, 2 * math.pi, "its phase ahead of the right crank"
        ),
        ParameterSpec("spring_stiffness", "N.m/rad", math.nan, 0.0, 5000.0, "ankle spring K_e (unset: fitted)"),
        ParameterSpec("spring_rest_angle", "rad", math.nan, 0.3, 2.8, "spring rest angle beta0 (unset: fitted)"),
        ParameterSpec("spring_damping", "N.m.s/rad", 0.0, 0.0, 200.0, "ankle damping"),
        ParameterSpec("omega", "rad/s", 0.1, 0.0, 20.0, "crank speed"),
    )
}
"""Every numeric parameter of a :class:`Design`, by name (``r1`` .. ``r13`` are the link ratios)."""

MIN_WALK_OMEGA: float = 0.05
"""The slowest crank speed a walk is simulated at [rad/s] (20 steps at 0.05 rad/s are 21 minutes): a walk's
crank speed lies in [MIN_WALK_OMEGA, ``SPECS["omega"].high``], the design record's range raised at its low end."""


def check_parameter(name: str, value: object, low: float | None = None, low_open: bool = False) -> float:
    """``value`` as a float when it lies in :data:`SPECS` ``name``'s range, else a one-line ParameterError naming it.

    The one check of a design parameter's range outside the record itself: a study that takes a bare number
    (a crank speed [rad/s], a stiffness) reads its unit and range here.

    Args:
        name: the parameter's name in :data:`SPECS` (``omega``, ``spring_stiffness``, ...).
        value: the value given.
        low: a stricter lower bound the use needs (a walk's :data:`MIN_WALK_OMEGA`), inside the range.
        low_open: the lower bound itself is refused (a crank speed that must turn: > 0).

    Raises:
        ParameterError: not a real number, NaN, infinite, or outside the range, naming ``name``, its unit and range.

    """
    spec = SPECS[name]
    bottom = spec.low if low is None else max(spec.low, low)
    opening = "(" if low_open else "["
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ParameterError(f"parameter {name!r} must be a number [{spec.unit}], got {short_repr(value)}")
    try:
        number = float(value)
    except OverflowError:  # an integer too large for a float
        number = math.inf
    above = number > bottom if low_open else number >= bottom
    if not (above and number <= spec.high):  # NaN and infinities fail here
        raise ParameterError(
            f"parameter {name!r} = {short_repr(value)} [{spec.unit}] is outside {opening}{bottom:g}, {spec.high:g}]"
        )
    return number


CHOICES: Mapping[str, tuple[str, ...]] = {
    "variant": VARIANTS,
    "motors": tuple(MOTOR_LAYOUTS),
    "mass_rule": tuple(MASS_RULES),
    "inertia": ("point", "uniform"),
}
"""Every categorical parameter of a :class:`Design` and its valid values."""

OPTIONAL = (
    "spring_stiffness",
    "spring_rest_angle",
    "thigh_fraction",
    "shank_fraction",
    "foot_fraction",
    "lateral_mass",
    "lateral_amplitude",
    "lateral_phase",
)
"""Parameters that may be left unset (``None``, absent from a file): the study fits the spring, the
mass rule gives the shares."""


def check_value(name: str, value: object) -> float | str | None:
    """``value`` if it is valid for parameter ``name``, else a one-line ValueError naming it."""
    if name in CHOICES:
        if not isinstance(value, str) or value not in CHOICES[name]:
            raise ParameterError(
                f"parameter {name!r} must be one of {', '.join(CHOICES[name])}, got {short_repr(value)}"
            )
        return str(value)
    spec = SPECS.get(name)
    if spec is None:
        raise ParameterError(f"unknown design parameter {short_repr(name)}; valid: {', '.join([*CHOICES, *SPECS])}")
    if value is None and name in OPTIONAL:
        return None
    return check_parameter(name, value)  # the number in its one range


@dataclass(frozen=True)
class Design:
    """One PASIBOT design. Defaults are the seed's design (docs/reference.md §4, §5).

    Attributes:
        variant: ``rigid``, ``parallel`` or ``spring``.
        motors: ``two`` (one per crank) or ``one`` (one motor, cranks coupled pi apart).
        mass_rule: ``seed`` (the seed's Tab 7.1.1 percentages) or ``human``
            (example-robot-data's human model); ``*_fraction`` override the rule's shares.
        inertia: ``point`` masses or ``uniform`` rods.
        L: crank length [m].
        K: frame link 0-3 over L [-].
        ratios: link lengths over L, ``r1`` .. ``r13`` [-].
        foot_toe, foot_heel, parallel_toe, parallel_heel: sole extents over L [-].
        sole_inner, sole_outer: the sole's lateral reach from its leg's plane toward the midline
            and away from it, over L [-] (the 3-D floor's footprint; the planar floor ignores it).
        sole_gap_from, sole_gap_to: the sole is cut away between these reaches toward the midline,
            over L [-]: two prongs, a comb whose inner prong can pass beside the other foot's
            (both 0: one plate).
        hip_half_width: each leg's plane from the midline, over L [-].
        total_mass: human mass the percentages refer to [kg].
        thigh_fraction, shank_fraction, foot_fraction: shares of ``total_mass`` [-]
            (``None``: the rule's own).
        body_mass: body (hip) mass [kg].
        body_com_dx: body COM ahead of joint 8 [m].
        lateral_mass, lateral_amplitude, lateral_phase: a share of the body [kg] that the right
            crank moves sideways on a slider through the hip, ``amplitude sin(theta + phase)``
            (amplitude over L [-], phase [rad]; :class:`~pasibot_pin.model.spatial.LateralMass`);
            the 3-D floor's, the planar model cannot see it (``None``: no moved mass).
        spring_stiffness: ankle spring K_e [N.m/rad] (``None``: fitted by the study).
        spring_rest_angle: its rest angle beta0 [rad] (``None``: fitted).
        spring_damping: ankle damping [N.m.s/rad].
        omega: crank speed [rad/s].

    """

    variant: str = "spring"
    motors: str = "two"
    mass_rule: str = "seed"
    inertia: str = "point"
    # the geometry's defaults are Geometry's own (one source for the seed's numbers)
    L: float = Geometry.L
    K: float = Geometry.K
    ratios: Mapping[str, float] = field(default_factory=lambda: dict(SEED_LINK_RATIOS))
    foot_toe: float = Geometry.foot_toe
    foot_heel: float = Geometry.foot_heel
    parallel_toe: float = Geometry.parallel_toe
    parallel_heel: float = Geometry.parallel_heel
    sole_inner: float = CENTRED_SOLE
    sole_outer: float = CENTRED_SOLE
    sole_gap_from: float = 0.0
    sole_gap_to: float = 0.0
    hip_half_width: float = Geometry.hip_half_width / Geometry.L
    total_mass: float = SEED_TOTAL_MASS
    thigh_fraction: float | None = None
    shank_fraction: float | None = None
    foot_fraction: float | None = None
    body_mass: float = DEFAULT_BODY_MASS
    body_com_dx: float = 0.0
    lateral_mass: float | None = None
    lateral_amplitude: float | None = None
    lateral_phase: float | None = None
    spring_stiffness: float | None = None
    spring_rest_angle: float | None = None
    spring_damping: float = 0.0
    omega: float = 0.1

    def __post_init__(self) -> None:
        if not isinstance(self.ratios, Mapping):
            raise ParameterError(
                "parameter 'ratios' must be a table of link ratios (r1 = 1.0, r4 = 9.5, ...), "
                f"got {short_repr(self.ratios)}"
            )
        unknown = set(self.ratios) - set(SEED_LINK_RATIOS)
        if unknown:
            raise ParameterError(f"unknown link ratio(s) {sorted(unknown)}; valid: {', '.join(SEED_LINK_RATIOS)}")
        merged = {**SEED_LINK_RATIOS, **{k: check_value(k, v) for k, v in self.ratios.items()}}
        object.__setattr__(self, "ratios", merged)
        for f in fields(self):
            if f.name == "ratios":
                continue
            object.__setattr__(self, f.name, check_value(f.name, getattr(self, f.name)))
        self.footprint()  # the sole's gap lies inside it
        self.lateral()  # a lateral mass has its reach, and is less than the body

    # ---- views for the model layer
    def geometry(self) -> Geometry:
        """The leg geometry [m] (:class:`~pasibot_pin.model.params.Geometry`)."""
        return Geometry(
            L=self.L,
            K=self.K,
            ratios=dict(self.ratios),
            foot_toe=self.foot_toe,
            foot_heel=self.foot_heel,
            parallel_toe=self.parallel_toe,
            parallel_heel=self.parallel_heel,
            hip_half_width=self.hip_half_width * self.L,
        )

    def footprint(self) -> Footprint:
        """The soles' lateral shape [m] (:class:`~pasibot_pin.model.spatial.Footprint`): a plate, or two prongs.

        Raises:
            ParameterError: a gap that does not lie inside the sole (``sole_gap_from`` < ``sole_gap_to`` <
                ``sole_inner``), or a gap of one bound only.

        """
        L, gap = self.L, (self.sole_gap_from, self.sole_gap_to)
        if gap == (0.0, 0.0):
            return Footprint.plate(self.sole_inner * L, self.sole_outer * L)
        if not (-self.sole_outer < gap[0] < gap[1] < self.sole_inner):
            raise ParameterError(
                f"parameters 'sole_gap_from' = {gap[0]:g}, 'sole_gap_to' = {gap[1]:g} [L]: a gap in the sole needs "
                f"-sole_outer < sole_gap_from < sole_gap_to < sole_inner = {self.sole_inner:g}"
            )
        return Footprint(((gap[0] * L, self.sole_outer * L), (self.sole_inner * L, -gap[1] * L)))

    def lateral(self) -> LateralMass | None:
        """The share of the body the crank moves sideways [kg, m, rad], or ``None`` (no mass, or no reach).

        Raises:
            ParameterError: a lateral mass with no amplitude given, or one not less than ``body_mass``.

        """
        if self.lateral_mass is None or self.lateral_mass == 0.0:
            return None
        if self.lateral_amplitude is None:
            raise ParameterError("parameter 'lateral_amplitude' is needed with 'lateral_mass' (its reach [L])")
        if self.lateral_mass >= self.body_mass:
            raise ParameterError(
                f"parameter 'lateral_mass' = {self.lateral_mass:g} kg must be less than "
                f"'body_mass' = {self.body_mass:g} kg"
            )
        phase = 0.0 if self.lateral_phase is None else self.lateral_phase
        return LateralMass(self.lateral_mass, self.lateral_amplitude * self.L, phase)

    def fractions(self) -> dict[str, float]:
        """The mass shares of the rule, with the design's overrides [-] (``hip`` is the body: see ``body_mass``)."""
        base = dict(SEED_MASS_FRACTIONS) if self.mass_rule == "seed" else human_description_fractions()
        out = {k: base[k] for k in ("hip", "thigh", "shank", "foot")}
        for key in ("thigh", "shank", "foot"):
            value = getattr(self, f"{key}_fraction")
            if value is not None:
                out[key] = value
        return out

    def masses(self) -> MassModel:
        """Link, foot and body masses [kg] and where they sit [m]."""
        model = percentage_mass_model(self.geometry(), self.variant, self.total_mass, self.fractions(), self.mass_rule)
        return model.with_(hip=self.body_mass, hip_com=(self.body_com_dx, 0.0), rule=f"design ({self.mass_rule})")

    # ---- records
    def values(self) -> dict[str, float | str | None]:
        """Every parameter by its flat name (``variant``, ``L``, ``K``, ``r1`` .. ``r13``, ...): a sweep row."""
        out: dict[str, float | str | None] = {}
        for f in fields(self):
            if f.name == "ratios":
                out.update(self.ratios)
            else:
                out[f.name] = getattr(self, f.name)
        return out

    def with_(self, **changes: float | str) -> Design:
        """A copy with parameters changed by flat name (``K=2.2``, ``r4=9.5``, ``variant="rigid"``)."""
        ratios: dict[str, Any] = {k: v for k, v in changes.items() if k in SEED_LINK_RATIOS}
        other: dict[str, Any] = {k: v for k, v in changes.items() if k not in SEED_LINK_RATIOS}
        names = {f.name for f in fields(self)} - {"ratios"}
        for name in other:
            if name not in names:
                check_value(name, other[name])  # raises: unknown parameter
        return replace(self, ratios={**self.ratios, **ratios}, **other)

    def to_dict(self) -> dict:
        """A plain dict (``None`` for the parameters left to the study's fit or to the mass rule)."""
        data = asdict(self)
        data["ratios"] = dict(self.ratios)
        return data

    @classmethod
    def from_dict(cls, data: Mapping) -> Design:
        """A design from a dict; keys absent keep the seed design's values, unknown keys are an error."""
        data = dict(data)
        ratios = data.pop("ratios", None)
        if ratios is None:
            ratios = {}
        if not isinstance(ratios, Mapping):
            raise ParameterError(
                f"parameter 'ratios' must be a table of link ratios (r1 = 1.0, r4 = 9.5, ...), got {short_repr(ratios)}"
            )
        ratios = dict(ratios)
        for key in list(data):
            if key in SEED_LINK_RATIOS:  # flat ratio names are accepted too
                ratios[key] = data.pop(key)
        names = {f.name for f in fields(cls)}
        for key in data:
            if key not in names:
                check_value(key, data[key])
        return cls(ratios=ratios, **data)

    def save(self, path: str | os.PathLike, force: bool = False) -> Path:
        """Write the design to ``path`` (``.toml`` or ``.json``), atomically; never over a file without ``force``.

        Raises:
            FileExistsError: ``path`` exists and ``force`` is false.
            ValueError: an extension other than ``.toml`` / ``.json``.

        """
        path = Path(path)
        if path.suffix not in (".toml", ".json"):
            raise ParameterError(f"parameter 'path': a design file ends in .toml or .json, got {path.name!r}")
        if path.exists() and not force:
            raise FileExistsError(f"{path} exists; use --force (force=True) to overwrite it")
        text = _to_toml(self.to_dict()) if path.suffix == ".toml" else _to_json(self.to_dict())
        fd, tmp = tempfile.mkstemp(dir=path.parent if str(path.parent) else ".", prefix=f".{path.name}.", suffix=".tmp")
        try:
            os.fchmod(fd, 0o666 & ~_umask())  # mkstemp's 0600 -> what open() gives (0644 with umask 022)
            with os.fdopen(fd, "w") as handle:
                handle.write(text)
            os.replace(tmp, path)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
        return path


def _umask() -> int:
    """The process's file-creation mask (read by setting it and setting it back)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def design_robot(design: Design, legs: int = 2, visuals: bool = True):
    """The robot of ``design`` (:func:`pasibot_pin.model.robot.load` with its geometry, masses and inertia).

    ``visuals=False`` skips the URDF text and the geometry models (design sweeps). With visuals, the
    soles are drawn with the design's lateral shape (:meth:`Design.footprint`).
    """
    return load(
        design.variant,
        legs,
        geometry=design.geometry(),
        masses=design.masses(),
        inertia=design.inertia,
        visuals=visuals,
        footprint=design.footprint() if visuals else None,
    )


def load_design(path: str | os.PathLike) -> Design:
    """Read a design file (``.toml`` or ``.json``); a one-line ValueError for a bad file or value."""
    path = Path(path)
    if path.is_dir():
        raise ParameterError(f"parameter 'design': {str(path)!r} is a folder; give a design file (.toml or .json)")
    if path.exists() and not path.is_file():
        raise ParameterError(f"parameter 'design': {str(path)!r} is not a regular file (a device or a pipe)")
    if not path.is_file():
        raise ParameterError(f"parameter 'design': no design file {str(path)!r}")
    try:
        if path.suffix == ".toml":
            data = tomllib.loads(path.read_text())
        elif path.suffix == ".json":
            data = json.loads(path.read_text())
        else:
            raise ParameterError(f"parameter 'design': a design file ends in .toml or .json, got {path.name!r}")
    except RecursionError:
        raise ParameterError(f"parameter 'design': {path} nests tables or lists too deeply") from None
    except (tomllib.TOMLDecodeError, json.JSONDecodeError, UnicodeDecodeError) as err:
        reason = " ".join(str(err).split())
        raise ParameterError(f"parameter 'design': {path} is not valid {path.suffix[1:].upper()}: {reason}") from None
    except ValueError:  # a number Python refuses to read: an integer of more digits than its limit
        raise ParameterError(
            f"parameter 'design': {path} holds a number too long to read (an integer of thousands of digits)"
        ) from None
    if not isinstance(data, dict):
        raise ParameterError(f"parameter 'design': {path} must hold a table of parameters")
    return Design.from_dict(data)


def _toml_value(value) -> str:
    if isinstance(value, str):
        return json.dumps(value)
    return repr(float(value))


NOTES: dict[str, str] = {
    "total_mass": " the human mass the seed's percentages apply to, not the robot's",
    "body_mass": " the body on the hip",
}
"""A design file's comment beside a field whose name alone could mislead."""


def _to_toml(data: Mapping) -> str:
    """The flat TOML of a design: parameters first, then the [ratios] table; unset values left out."""
    lines = ["# PASIBOT design (pasibot_pin): SI units, link ratios and soles over L, angles in rad", ""]
    for key, value in data.items():
        if key == "ratios" or value is None:  # TOML has no null: an unset parameter is left out
            continue
        unit = SPECS[key].unit if key in SPECS else ""
        note = NOTES.get(key, "")
        lines.append(f"{key} = {_toml_value(value)}" + (f"  # [{unit}]{note}" if unit else ""))
    lines += ["", "[ratios]  # link length / L"]
    lines += [f"{key} = {_toml_value(value)}" for key, value in data["ratios"].items()]
    return "\n".join(lines) + "\n"


def _to_json(data: Mapping) -> str:
    return json.dumps(dict(data), indent=2) + "\n"
