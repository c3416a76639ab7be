"""The valid range of every numeric flag of every command, checked before any work starts.

Each numeric flag (``type=int``, ``type=float`` or a comma-separated list of numbers) has a
:class:`Bound`: its range, its unit, whether it must be an integer. :func:`check_flags` checks
the parsed arguments of a command against :data:`BOUNDS` before the command runs, so a bad
value is one line naming the flag and its range (``--mu must be in [0, 10], got 1e+300``),
never a hang, a NaN, an out-of-memory error or a message about something the user did not
type. ``tests/test_cli_fuzz.py`` checks that every numeric flag of every command is listed
here, and tries the same hostile values (huge, tiny, NaN, inf, negative, zero) on each.

The bounds follow from what a value implies: a count bounds the memory of its arrays (a few
hundred MB at most), a time step and a duration the number of integration steps (at most
:data:`MAX_INTEGRATION_STEPS`), a physical input the range the model is valid in (a crank
speed within the design record's, a friction coefficient a floor may have). A flag that sets a design
parameter takes the record's range and unit (:func:`spec_bound`): one range per parameter.
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass

from pasibot_pin.dynamics.floor.ground import MAX_MU, MAX_SLOPE, MAX_STEP_AT, MAX_STEP_HEIGHT
from pasibot_pin.errors import ParameterError
from pasibot_pin.explore.executors import MAX_WORKERS
from pasibot_pin.model.design import MIN_WALK_OMEGA, SPECS

MAX_INTEGRATION_STEPS: int = 10_000_000
"""The most integration steps one run may take (a duration over a time step)."""


@dataclass(frozen=True)
class Bound:
    """The valid values of one numeric flag.

    Attributes:
        low: the smallest valid value.
        high: the largest valid value.
        unit: the unit printed after the range (``s``, ``rad/s``; empty for none).
        integer: the flag takes whole numbers.
        low_open: ``low`` itself is not valid.
        extra: values valid besides the range (``--hold -1``), with what they mean.

    """

    low: float
    high: float
    unit: str = ""
    integer: bool = False
    low_open: bool = False
    extra: tuple[tuple[float, str], ...] = ()

    def text(self) -> str:
        """The range as the messages print it: ``an integer in [2, 100000]``, ``in (0, 600] s``."""
        opening = "(" if self.low_open else "["
        head = "an integer in" if self.integer else "in"
        unit = f" {self.unit}" if self.unit else ""
        extra = "".join(f" or {_number(value)} ({meaning})" for value, meaning in self.extra)
        return f"{head} {opening}{_number(self.low)}, {_number(self.high)}]{unit}{extra}"

    def holds(self, value: object) -> bool:
        """Whether ``value`` is valid (a bool or a non-number never is)."""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            return False
        if any(value == special for special, _ in self.extra):
            return True
        if self.integer and not isinstance(value, int):
            return False
        if not math.isfinite(value):
            return False
        above = value > self.low if self.low_open else value >= self.low
        return above and value <= self.high


def check_number(flag: str, value: object, bound: Bound) -> None:
    """Raise :class:`ParameterError` naming ``flag`` and its range when ``value`` is outside ``bound``."""
    if not bound.holds(value):
        raise ParameterError(f"{flag} must be {bound.text()}, got {_shown(value)}")


def _number(value: float) -> str:
    """``value`` as the messages print it: an integer in full, a float in ``%g``."""
    return str(int(value)) if float(value).is_integer() and abs(value) < 1e15 else f"{value:g}"


def _shown(value: object) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10**12:
        return f"{float(value):g}"
    return repr(value)


def spec_bound(
    name: str, low: float | None = None, low_open: bool = False, scale: float = 1.0, unit: str | None = None
) -> Bound:
    """The flag's :class:`Bound` of design parameter ``name``: its range and unit in the design record (``SPECS``).

    Args:
        name: the parameter's name in :data:`~pasibot_pin.model.design.SPECS`.
        low: a stricter lower bound the command needs (a walk's crank speed), inside the range.
        low_open: the lower bound itself is refused.
        scale: the flag's unit over the record's (``math.degrees(1)`` for a flag in degrees of a record in rad).
        unit: the flag's unit when it is not the record's (``""`` for none).

    """
    spec = SPECS[name]
    bottom = spec.low if low is None else max(spec.low, low)
    return Bound(bottom * scale, spec.high * scale, spec.unit if unit is None else unit, low_open=low_open)


_MU = Bound(0.0, MAX_MU)  # the ground's one range
_FPS = Bound(0.1, 240.0, "1/s")
_LEGS = Bound(1, 2, integer=True)
_OMEGA = spec_bound("omega")  # the design record's crank speeds
_TURNING = spec_bound("omega", low_open=True)  # cranks that turn
_WALKING = spec_bound("omega", low=MIN_WALK_OMEGA)  # a walk's crank speeds
_SLOPE = Bound(-round(math.degrees(MAX_SLOPE), 9), round(math.degrees(MAX_SLOPE), 9), "deg")  # the ground's range
_WALK_STEPS = Bound(1, 1000, integer=True)
_SAMPLES_PER_STEP = Bound(2, 1000, integer=True)
_EXPLORE = {
    "--workers": Bound(1, MAX_WORKERS, integer=True),
    "--best": Bound(0, 100, integer=True),
    "--floor": Bound(1, 1000, "steps", integer=True),  # studies.design_metrics.MAX_FLOOR_STEPS
    "--seed": Bound(0, 2**32 - 1, integer=True),
}
_WALK_VIEW = {
    "--steps": _WALK_STEPS,
    "--samples-per-step": _SAMPLES_PER_STEP,
    "--fps": _FPS,
    "--reactions": _OMEGA,  # 0: quasi-static
}

BOUNDS: dict[str, dict[str, Bound]] = {
    "info": {"--legs": _LEGS},
    "build-urdf": {"--legs": _LEGS, "--L": spec_bound("L"), "--K": spec_bound("K", unit="")},
    "analyze": {},
    "view": {
        **_WALK_VIEW,
        "--repeat": Bound(1, 1000, integer=True),
        "--hold": Bound(0.0, 86400.0, "s", extra=((-1, "until Ctrl-C"),)),
    },
    "export-html": dict(_WALK_VIEW),
    "export-mjcf": {"--legs": _LEGS, "--mu": _MU, "--slope": _SLOPE},
    "gait": {
        "--legs": _LEGS,
        "--steps": _WALK_STEPS,
        "--step-deg": Bound(0.0, 90.0, "deg", low_open=True),
        "--omega": _TURNING,
    },
    "torques": {
        "--omega": _OMEGA,
        "--samples": Bound(2, 100_000, integer=True),
        "--steps": Bound(1, 1000, integer=True),
    },
    "simulate": {
        "--duration": Bound(0.01, 600.0, "s"),
        "--mu": _MU,
        "--steps": Bound(1, 1000, integer=True),
        "--stiffness": spec_bound("spring_stiffness"),
        "--rest-angle": spec_bound("spring_rest_angle", scale=math.degrees(1.0), unit="deg"),
        "--damping": spec_bound("spring_damping"),
        "--dt": Bound(1e-5, 0.1, "s"),
        "--fps": _FPS,
    },
    "contact": {
        "--mu": _MU,
        "--samples": Bound(2, 100_000, integer=True),
        "--sole": Bound(-2.0, 2.0, "m"),
    },
    "energy": {
        "--omegas": _TURNING,
        "--body-mass": spec_bound("body_mass"),
        "--com-dx": spec_bound("body_com_dx"),
        "--nodes": Bound(2, 1000, integer=True),
        "--flywheel": Bound(0.0, 1000.0, "kg.m^2", low_open=True),
    },
    "walk": {
        "--omega": _WALKING,
        "--mu": _MU,
        "--slope": _SLOPE,
        "--step-height": Bound(-MAX_STEP_HEIGHT, MAX_STEP_HEIGHT, "m"),  # the ground's ranges
        "--step-at": Bound(-MAX_STEP_AT, MAX_STEP_AT, "m"),
    },  # --steps: its own type, [1, 1000]
    "sweep": {"--n": Bound(1, 1_000_000, integer=True), "--slope": _SLOPE, **_EXPLORE},
    "find-walker": {
        "--omega": _WALKING,
        "--budget": Bound(1, 10_000, integer=True),  # explore.find_walker.MAX_BUDGET
        "--steps": Bound(3, 1000, "steps", integer=True),  # verdict.MIN_STRIDE_STEPS: fewer cannot say walks
        "--workers": _EXPLORE["--workers"],
        "--seed": _EXPLORE["--seed"],
    },
    "optimize": {
        "--trials": Bound(1, 1_000_000, integer=True),
        "--population": Bound(2, 10_000, integer=True),
        **_EXPLORE,
    },
}
"""command -> numeric flag -> its valid values. ``--sole`` and ``--omegas`` bound each of their numbers."""

MAX_LIST: int = 100
"""The most numbers a list flag (``--omegas``) takes."""


def check_flags(command: str, args: argparse.Namespace) -> None:
    """Check every numeric flag of ``command`` in ``args`` against :data:`BOUNDS` (unset flags pass).

    Raises:
        ParameterError: a value outside its range, naming the flag and the range.

    """
    for flag, bound in BOUNDS.get(command, {}).items():
        value = getattr(args, flag.lstrip("-").replace("-", "_"), None)
        if value is None:
            continue
        if isinstance(value, (list, tuple)):
            if not value or len(value) > MAX_LIST:
                raise ParameterError(f"{flag} takes 1 to {MAX_LIST} numbers, got {len(value)}")
            for item in value:
                check_number(flag, item, bound)
        else:
            check_number(flag, value, bound)
    if command in ("view", "export-html"):
        check_frames(args)


MAX_FRAMES: int = 10_000
"""The most animation frames ``view`` and ``export-html`` draw (``--steps`` x ``--samples-per-step``): each
frame is a closure solve and, in the HTML, every body's transform (about 50 MB at this bound)."""


def check_frames(args: argparse.Namespace) -> None:
    """``--steps`` x ``--samples-per-step`` at most :data:`MAX_FRAMES` (``view``, ``export-html``)."""
    frames = args.steps * args.samples_per_step
    if frames > MAX_FRAMES:
        raise ParameterError(
            f"--steps {args.steps} x --samples-per-step {args.samples_per_step} = {frames} frames; at most {MAX_FRAMES}"
        )


def check_integration_steps(duration: float, dt: float, what: str) -> None:
    """Refuse a ``duration`` [s] over a time step ``dt`` [s] of more than :data:`MAX_INTEGRATION_STEPS` steps."""
    steps = duration / dt
    if steps > MAX_INTEGRATION_STEPS:
        raise ParameterError(
            f"{what} gives {steps:.3g} integration steps; at most {MAX_INTEGRATION_STEPS:.0e} "
            f"(a shorter --duration or a longer --dt)"
        )
