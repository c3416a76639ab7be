"""Which designs a sweep evaluates: parameter ranges and choices, Latin hypercube or grid, a seed.

A numeric parameter varies over a :class:`Range` (``--vary K=1.8:2.4``), a categorical one (the
variant, the motor layout, the mass rule, the inertia: :data:`~pasibot_pin.model.design.CHOICES`)
over a :class:`Choice` of its values (``--vary variant=parallel,spring,rigid``). In a Latin
hypercube a choice is one more dimension cut into equal strata, one per value (the values are
drawn in equal shares); in a grid it is one more axis with every value.

A :class:`SweepPlan` is data (it is saved as ``plan.json`` beside the results, and a resumed run
must have the same plan). Its rows are fully determined by the plan: the same plan gives the
same designs on any machine and executor.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from pasibot_pin.dynamics.floor.ground import MAX_SLOPE
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import CHOICES, SPECS, Design


@dataclass(frozen=True)
class Range:
    """One varied parameter: its name in the design record and its bounds (units of :data:`SPECS`)."""

    name: str
    low: float
    high: float

    def __post_init__(self) -> None:
        spec = SPECS.get(self.name)
        if spec is None:
            if self.name in CHOICES:
                raise ParameterError(
                    f"--vary {self.name}: a categorical parameter: list its values, "
                    f"e.g. {self.name}={','.join(CHOICES[self.name])}"
                )
            raise ParameterError(f"--vary {self.name}: unknown; numeric parameters: {', '.join(SPECS)}")
        for label, value in (("low", self.low), ("high", self.high)):
            if not math.isfinite(value):
                raise ParameterError(f"--vary {self.name}: the {label} bound must be a finite number, got {value!r}")
        if not self.low < self.high:
            raise ParameterError(
                f"--vary {self.name}={self.low:g}:{self.high:g}: the low bound must be below the high one"
            )
        if self.low < spec.low or self.high > spec.high:
            raise ParameterError(
                f"--vary {self.name}={self.low:g}:{self.high:g}: outside the parameter's bounds "
                f"[{spec.low:g}, {spec.high:g}] [{spec.unit}]"
            )

    def text(self) -> str:
        """``NAME=LO:HI``, as on the command line."""
        return f"{self.name}={self.low:g}:{self.high:g}"


@dataclass(frozen=True)
class Choice:
    """One varied categorical parameter: its name in the design record and the values it takes.

    A plan's points hold the index of the value (0, 1, ...) in this parameter's column.
    """

    name: str
    values: tuple[str, ...]

    def __post_init__(self) -> None:
        valid = CHOICES.get(self.name)
        if valid is None:
            raise ParameterError(f"--vary {self.name}: not a categorical parameter; categorical: {', '.join(CHOICES)}")
        values = tuple(str(v) for v in self.values)
        if not values:
            raise ParameterError(f"--vary {self.name}=: list at least one value of {', '.join(valid)}")
        bad = [v for v in values if v not in valid]
        if bad:
            raise ParameterError(f"--vary {self.name}: {', '.join(bad)} not among its values {', '.join(valid)}")
        if len(set(values)) != len(values):
            raise ParameterError(f"--vary {self.name}: a value is listed twice")
        object.__setattr__(self, "values", values)

    def value(self, index: float) -> str:
        """The value at ``index`` (a point's entry: 0, 1, ...)."""
        return self.values[min(max(int(index), 0), len(self.values) - 1)]

    def text(self) -> str:
        """``NAME=A,B,...``, as on the command line."""
        return f"{self.name}={','.join(self.values)}"


Varied = Range | Choice
"""A varied parameter: numeric (:class:`Range`) or categorical (:class:`Choice`)."""


def parse_range(text: str) -> Varied:
    """A :class:`Range` from ``NAME=LO:HI``, or a :class:`Choice` from ``NAME=A,B,...``.

    A choice is a categorical parameter of :data:`~pasibot_pin.model.design.CHOICES`; a bad text is a
    one-line ValueError naming what is wrong.
    """
    name, sep, bounds = str(text).partition("=")
    if sep and name.strip() in CHOICES and ":" not in bounds:
        return Choice(name.strip(), tuple(v.strip() for v in bounds.split(",") if v.strip()))
    low, sep2, high = bounds.partition(":")
    if not sep or not sep2 or not name.strip():
        raise ParameterError(f"--vary {text!r}: write NAME=LO:HI, e.g. K=1.8:2.4")
    try:
        lo, hi = float(low), float(high)
    except ValueError:
        raise ParameterError(f"--vary {text!r}: LO and HI must be numbers") from None
    return Range(name.strip(), lo, hi)


DEFAULT_RANGES: tuple[Range, ...] = (
    Range("K", 1.7, 2.6),
    Range("r4", 8.0, 10.0),
    Range("r5", 16.0, 20.0),
    Range("foot_toe", 1.0, 3.0),
    Range("foot_heel", 0.3, 1.5),
    Range("body_com_dx", -0.05, 0.05),
    Range("body_mass", 10.0, 25.0),
)
"""The ranges of ``pasibot sweep`` without ``--vary``: around the seed design (K = 2, L4 = 9 L,
L5 = 18 L, sole 1.5 L ahead and 0.5 L behind the ankle, body 16.25 kg above joint 8)."""

METHODS: tuple[str, ...] = ("lhs", "grid")
"""Sampling methods: a Latin hypercube of ``n`` points, or a full grid of about ``n`` points."""


@dataclass(frozen=True)
class SweepPlan:
    """The designs of a sweep.

    Attributes:
        ranges: the varied parameters (:class:`Range` and :class:`Choice`).
        n: the number of designs (``grid``: every value of each choice times levels ** d for the d
            numeric parameters, at least 2 levels each; any other n is refused with the nearest grid sizes).
        method: ``lhs`` or ``grid``.
        seed: the Latin hypercube's random seed.
        base: the design every other parameter is taken from (default the seed design).
        floor: also walk every design this many steps on the floor (``None``: no; slower).
        spatial: walk on the 3-D floor (free hip, the designs' soles; about four times slower).
        slope: the floor's angle, uphill positive [rad] (with ``floor``, the planar floor; 0: flat).

    """

    ranges: tuple[Varied, ...] = DEFAULT_RANGES
    n: int = 100
    method: str = "lhs"
    seed: int = 0
    base: Design = field(default_factory=Design)
    floor: int | None = None
    spatial: bool = False
    slope: float = 0.0

    def __post_init__(self) -> None:
        check_floor(self.floor)
        if self.spatial and self.floor is None:
            raise ParameterError("--3d walks the designs on the 3-D floor: give --floor STEPS too")
        if self.slope:
            check_slope(self.slope)
            if self.floor is None:
                raise ParameterError("--slope walks the designs up a slope on the floor: give --floor STEPS too")
        if isinstance(self.n, bool) or not isinstance(self.n, (int, np.integer)) or not 1 <= self.n <= 10_000_000:
            raise ParameterError(f"parameter 'n' must be an integer in [1, 1e7], got {self.n!r}")
        if self.method not in METHODS:
            raise ParameterError(f"parameter 'method' must be one of {', '.join(METHODS)}, got {self.method!r}")
        if not self.ranges:
            raise ParameterError("a sweep needs at least one --vary NAME=LO:HI")
        names = [r.name for r in self.ranges]
        if len(set(names)) != len(names):
            raise ParameterError(
                f"--vary names a parameter twice: {', '.join(sorted({n for n in names if names.count(n) > 1}))}"
            )
        object.__setattr__(self, "ranges", tuple(self.ranges))
        if self.method == "grid":
            self._check_grid_size()

    def _check_grid_size(self) -> None:
        """A grid has (values of the choices) x levels ** d designs: refuse any other ``n``, offering the nearest."""
        k = math.prod(len(r.values) for r in self.ranges if isinstance(r, Choice))
        d = sum(isinstance(r, Range) for r in self.ranges)
        if d == 0:
            if self.n != k:
                raise ParameterError(f"--n {self.n} with --method grid over choices only: the grid has --n {k} designs")
            return
        per = self.n / k
        levels = max(2, round(per ** (1.0 / d)))
        if k * levels**d != self.n:  # n means the number of designs
            below = max(2, int(per ** (1.0 / d) + 1e-9))
            above = below if below**d > per else below + 1
            sizes = sorted({k * below**d, k * above**d} - {self.n})
            offer = " or ".join(f"--n {size} ({round((size / k) ** (1.0 / d))} levels)" for size in sizes)
            raise ParameterError(
                f"--n {self.n} with --method grid over {d} numeric parameter(s) and {k} choice(s): a grid has "
                f"{k} x levels^{d} designs; take {offer}"
            )

    @property
    def names(self) -> tuple[str, ...]:
        """The varied parameters, in order."""
        return tuple(r.name for r in self.ranges)

    def points(self) -> np.ndarray:
        """The varied parameters' values, one row per design (N, d), in their units.

        A choice's column holds the index of its value (:meth:`values`).
        """
        numeric = [r for r in self.ranges if isinstance(r, Range)]
        low = np.array([r.low for r in numeric])
        high = np.array([r.high for r in numeric])
        if self.method == "grid":
            per_choice = self.n / math.prod(len(r.values) for r in self.ranges if isinstance(r, Choice))
            levels = max(2, round(per_choice ** (1.0 / len(numeric)))) if numeric else 1
            axes = [
                np.linspace(r.low, r.high, levels) if isinstance(r, Range) else np.arange(len(r.values), dtype=float)
                for r in self.ranges
            ]
            return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, len(axes))
        from scipy.stats import qmc  # deferred: optional extra (scipy)

        unit = qmc.LatinHypercube(d=len(self.ranges), seed=np.random.default_rng(self.seed)).random(self.n)
        if len(numeric) == len(self.ranges):
            return qmc.scale(unit, low, high)
        out = np.empty_like(unit)
        for k, r in enumerate(self.ranges):
            if isinstance(r, Range):
                out[:, k] = qmc.scale(unit[:, k : k + 1], [r.low], [r.high])[:, 0]
            else:  # one stratum per value: the values in equal shares
                out[:, k] = np.floor(unit[:, k] * len(r.values))
        return out

    def values(self, point: Sequence[float]) -> list[float | str]:
        """One point's parameter values: a number per :class:`Range`, a value per :class:`Choice`."""
        return [r.value(x) if isinstance(r, Choice) else float(x) for r, x in zip(self.ranges, point)]

    def design(self, values: Sequence[float | str]) -> Design:
        """The base design with the varied parameters set to ``values`` (a point, or :meth:`values`)."""
        changes = {
            r.name: (v if isinstance(v, str) else r.value(v)) if isinstance(r, Choice) else float(v)
            for r, v in zip(self.ranges, values)
        }
        return self.base.with_(**changes)

    def to_dict(self) -> dict:
        """A JSON-able record (``plan.json``)."""
        return {
            "ranges": [range_record(r) for r in self.ranges],
            "n": int(self.n),
            "method": self.method,
            "seed": int(self.seed),
            "base": self.base.to_dict(),
            "floor": self.floor,
            "spatial": bool(self.spatial),
            "slope": float(self.slope),
        }

    @classmethod
    def from_dict(cls, data: Mapping) -> SweepPlan:
        """The plan of a ``plan.json``."""
        return cls(
            ranges=tuple(range_of_record(r) for r in data["ranges"]),
            n=int(data["n"]),
            method=str(data["method"]),
            seed=int(data["seed"]),
            base=Design.from_dict(data["base"]),
            floor=data.get("floor"),
            spatial=bool(data.get("spatial", False)),
            slope=float(data.get("slope", 0.0)),
        )


def range_record(r: Varied) -> list:
    """A varied parameter as JSON: ``[name, low, high]`` or ``[name, [values]]``."""
    return [r.name, list(r.values)] if isinstance(r, Choice) else [r.name, r.low, r.high]


def range_of_record(record: Sequence) -> Varied:
    """The varied parameter of a :func:`range_record`."""
    if len(record) == 2:
        return Choice(str(record[0]), tuple(record[1]))
    name, low, high = record
    return Range(str(name), float(low), float(high))


def parse_ranking(text: str, option: str = "by") -> tuple[str, str]:
    """``METRIC[:min|max]`` -> (metric, sense), the sense defaulting to the metric's own.

    Raises:
        ValueError: an unknown metric or sense, naming ``option``.

    """
    from pasibot_pin.studies.design_metrics import ALL_METRICS  # deferred: keeps the CLI's start fast

    name, _, sense = str(text).partition(":")
    if name not in ALL_METRICS:
        raise ParameterError(f"{option} {text!r}: unknown metric {name!r}; valid: {', '.join(ALL_METRICS)}")
    sense = sense or ALL_METRICS[name].sense or "min"
    if sense not in ("min", "max"):
        raise ParameterError(f"{option} {text!r}: the sense must be min or max")
    return name, sense


def check_slope(slope: float) -> float:
    """``slope`` [rad] if within the ground's one range (``MAX_SLOPE``), else one line naming ``--slope``."""
    if not (isinstance(slope, (int, float)) and math.isfinite(slope) and abs(slope) <= MAX_SLOPE):
        raise ParameterError(
            f"--slope must be within +-{math.degrees(MAX_SLOPE):.6g} deg, got {math.degrees(slope)!r} deg"
        )
    return float(slope)


def check_floor(floor: int | None) -> int | None:
    """``floor`` if ``None`` or a step count to walk on the floor, else a one-line error naming ``--floor``."""
    from pasibot_pin.studies.design_metrics import check_floor_steps  # deferred: keeps the CLI's start fast

    return check_floor_steps(floor, "--floor")


def ranges_or_default(texts: Iterable[str] | None) -> tuple[Varied, ...]:
    """The ranges of ``--vary`` options, or :data:`DEFAULT_RANGES` when there are none."""
    texts = list(texts or ())
    return tuple(parse_range(t) for t in texts) if texts else DEFAULT_RANGES
