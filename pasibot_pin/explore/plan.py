"""Which designs a sweep evaluates: parameter ranges, Latin hypercube or grid, a seed.

A :class:`SweepPlan` is data (it is saved as ``plan.json`` beside the results, and a resumed run
must have the same plan). Its rows are fully determined by the plan: the same plan gives the
same designs on any machine and executor.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

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
            kind = "a categorical parameter (set it in the design file)" if self.name in CHOICES else "unknown"
            raise ValueError(f"--vary {self.name}: {kind}; numeric parameters: {', '.join(SPECS)}")
        for label, value in (("low", self.low), ("high", self.high)):
            if not math.isfinite(value):
                raise ValueError(f"--vary {self.name}: the {label} bound must be a finite number, got {value!r}")
        if not self.low < self.high:
            raise ValueError(f"--vary {self.name}={self.low:g}:{self.high:g}: the low bound must be below the high one")
        if self.low < spec.low or self.high > spec.high:
            raise ValueError(
                f"--vary {self.name}={self.low:g}:{self.high:g}: outside the parameter's bounds "
                f"[{spec.low:g}, {spec.high:g}] [{spec.unit}]"
            )

    def text(self) -> str:
        """``NAME=LO:HI``, as on the command line."""
        return f"{self.name}={self.low:g}:{self.high:g}"


def parse_range(text: str) -> Range:
    """A :class:`Range` from ``NAME=LO:HI`` (one-line ValueError naming what is wrong)."""
    name, sep, bounds = str(text).partition("=")
    low, sep2, high = bounds.partition(":")
    if not sep or not sep2 or not name.strip():
        raise ValueError(f"--vary {text!r}: write NAME=LO:HI, e.g. K=1.8:2.4")
    try:
        lo, hi = float(low), float(high)
    except ValueError:
        raise ValueError(f"--vary {text!r}: LO and HI must be numbers") from None
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
        ranges: the varied parameters.
        n: the number of designs (``grid``: levels ** d for d varied parameters, at least 2 levels each;
            any other n is refused with the nearest grid sizes).
        method: ``lhs`` or ``grid``.
        seed: the Latin hypercube's random seed.
        base: the design every other parameter is taken from (default the seed design).
        floor: also walk every design this many steps on the floor (``None``: no; slower).

    """

    ranges: tuple[Range, ...] = DEFAULT_RANGES
    n: int = 100
    method: str = "lhs"
    seed: int = 0
    base: Design = field(default_factory=Design)
    floor: int | None = None

    def __post_init__(self) -> None:
        check_floor(self.floor)
        if isinstance(self.n, bool) or not isinstance(self.n, (int, np.integer)) or not 1 <= self.n <= 10_000_000:
            raise ValueError(f"parameter 'n' must be an integer in [1, 1e7], got {self.n!r}")
        if self.method not in METHODS:
            raise ValueError(f"parameter 'method' must be one of {', '.join(METHODS)}, got {self.method!r}")
        if not self.ranges:
            raise ValueError("a sweep needs at least one --vary NAME=LO:HI")
        names = [r.name for r in self.ranges]
        if len(set(names)) != len(names):
            raise ValueError(
                f"--vary names a parameter twice: {', '.join(sorted({n for n in names if names.count(n) > 1}))}"
            )
        object.__setattr__(self, "ranges", tuple(self.ranges))
        if self.method == "grid":
            d = len(self.ranges)
            levels = max(2, round(self.n ** (1.0 / d)))
            if levels**d != self.n:  # n means the number of designs: a grid has levels**d of them
                below, above = max(2, int(self.n ** (1.0 / d) + 1e-9)), None
                above = below if below**d > self.n else below + 1
                sizes = sorted({below**d, above**d} - {self.n})
                offer = " or ".join(f"--n {size} ({round(size ** (1.0 / d))} levels)" for size in sizes)
                raise ParameterError(
                    f"--n {self.n} with --method grid over {d} varied parameter(s): a grid has levels^{d} designs; "
                    f"take {offer}"
                )

    @property
    def names(self) -> tuple[str, ...]:
        """The varied parameters, in order."""
        return tuple(r.name for r in self.ranges)

    def points(self) -> np.ndarray:
        """The varied parameters' values, one row per design (N, d), in their units."""
        low = np.array([r.low for r in self.ranges])
        high = np.array([r.high for r in self.ranges])
        if self.method == "grid":
            levels = max(2, round(self.n ** (1.0 / len(self.ranges))))
            axes = [np.linspace(lo, hi, levels) for lo, hi in zip(low, high)]
            return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, len(axes))
        from scipy.stats import qmc

        unit = qmc.LatinHypercube(d=len(self.ranges), seed=np.random.default_rng(self.seed)).random(self.n)
        return qmc.scale(unit, low, high)

    def design(self, values: Sequence[float]) -> Design:
        """The base design with the varied parameters set to ``values``."""
        return self.base.with_(**{name: float(v) for name, v in zip(self.names, values)})

    def to_dict(self) -> dict:
        """A JSON-able record (``plan.json``)."""
        return {
            "ranges": [[r.name, r.low, r.high] for r in self.ranges],
            "n": int(self.n),
            "method": self.method,
            "seed": int(self.seed),
            "base": self.base.to_dict(),
            "floor": self.floor,
        }

    @classmethod
    def from_dict(cls, data: Mapping) -> SweepPlan:
        """The plan of a ``plan.json``."""
        return cls(
            ranges=tuple(Range(str(n), float(lo), float(hi)) for n, lo, hi in data["ranges"]),
            n=int(data["n"]),
            method=str(data["method"]),
            seed=int(data["seed"]),
            base=Design.from_dict(data["base"]),
            floor=data.get("floor"),
        )


def parse_ranking(text: str, option: str = "by") -> tuple[str, str]:
    """``METRIC[:min|max]`` -> (metric, sense), the sense defaulting to the metric's own.

    Raises:
        ValueError: an unknown metric or sense, naming ``option``.

    """
    from pasibot_pin.studies.design_metrics import ALL_METRICS

    name, _, sense = str(text).partition(":")
    if name not in ALL_METRICS:
        raise ValueError(f"{option} {text!r}: unknown metric {name!r}; valid: {', '.join(ALL_METRICS)}")
    sense = sense or ALL_METRICS[name].sense or "min"
    if sense not in ("min", "max"):
        raise ValueError(f"{option} {text!r}: the sense must be min or max")
    return name, sense


def check_floor(floor: int | None) -> int | None:
    """``floor`` if ``None`` or a step count to walk on the floor, else a one-line error naming ``--floor``."""
    from pasibot_pin.studies.design_metrics import check_floor_steps

    return check_floor_steps(floor, "--floor")


def ranges_or_default(texts: Iterable[str] | None) -> tuple[Range, ...]:
    """The ranges of ``--vary`` options, or :data:`DEFAULT_RANGES` when there are none."""
    texts = list(texts or ())
    return tuple(parse_range(t) for t in texts) if texts else DEFAULT_RANGES
