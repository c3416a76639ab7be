"""How to simulate on the floor: :class:`FloorSettings` and the cranks' start (:func:`crank_advance`).

Units: SI, angles [rad].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pasibot_pin.dynamics.floor.ground import MAX_SLOPE, Ground, check_mu, check_step
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import check_parameter
from pasibot_pin.model.variants import MOTOR_LAYOUTS

if TYPE_CHECKING:
    from pasibot_pin.dynamics.spring_energy import AnkleSpring


def crank_advance(t: float, ramp: float) -> tuple[float, float]:
    """How far a crank has turned by ``t`` [s] per unit of omega, and its rate over omega [-].

    Over ``ramp`` [s] the rate rises as the smoothstep 3 x^2 - 2 x^3 (x = t / ramp), so neither
    the rate nor the crank acceleration jumps at either end; then it stays at 1. The advance is
    ramp (x^3 - x^4 / 2) during the ramp and t - ramp / 2 after it; ``ramp = 0``: t and 1.

    Returns:
        (advance [s], rate [-]): the crank angle is theta0 + omega advance, its rate omega rate.

    """
    if t <= 0.0:
        return 0.0, 0.0 if ramp > 0 else 1.0
    if t >= ramp:
        return t - 0.5 * ramp, 1.0
    x = t / ramp
    return ramp * x**3 * (1.0 - 0.5 * x), x * x * (3.0 - 2.0 * x)


def crank_advances(times: np.ndarray, ramp: float) -> np.ndarray:
    """:func:`crank_advance`'s advance [s] at each of ``times`` (N,) [s], at once."""
    t = np.maximum(np.asarray(times, dtype=float), 0.0)
    if ramp <= 0:
        return t
    x = np.minimum(t / ramp, 1.0)
    return np.where(t >= ramp, t - 0.5 * ramp, ramp * x**3 * (1.0 - 0.5 * x))


def check_number(name: str, value: float, low: float, high: float = math.inf, low_open: bool = False) -> float:
    """``value`` as a float, or a one-line ParameterError naming it: finite, above ``low``, at most ``high``."""
    value = float(value)
    ok = math.isfinite(value) and (value > low if low_open else value >= low) and value <= high
    if not ok:
        bound = f"> {low:g}" if low_open else f">= {low:g}"
        raise ParameterError(f"parameter {name!r} must be a finite number {bound}, got {value!r}")
    return value


@dataclass(frozen=True)
class FloorSettings:
    """How to simulate on the floor.

    Attributes:
        omega: crank rate [rad/s] (rheonomic cranks, theta0 + omega t).
        crank_ramp: the cranks' rate rises from 0 to omega over this long [s], smoothly
            (:func:`crank_advance`); 0: they turn at omega from t = 0 (an impulsive start).
        spring: the ankle springs (``None``: free ankles).
        mu: sole-floor Coulomb friction [-].
        dt: time step [s].
        theta0: initial right crank angle [rad].
        hip: ``free`` or ``level`` (pitch held at 0).
        fall_limit: a run without a verdict stops when |hip pitch| passes this [rad].
        motors: the motor layout (:data:`~pasibot_pin.model.variants.MOTOR_LAYOUTS`): ``two``
            (each crank on its own motor) or ``one`` (one motor, the cranks coupled pi apart).
        slope: the ground's angle, rising along +x (uphill positive) [rad], at most :data:`MAX_SLOPE`.
        step_height: a step edge's height on the ground, up positive [m] (0: none;
            :class:`~pasibot_pin.dynamics.floor.ground.Ground`).
        step_at: where the step edge is along the ground [m].

    """

    omega: float = 0.1
    spring: AnkleSpring | None = None
    crank_ramp: float = 0.0
    mu: float = 0.8
    dt: float = 1e-3
    theta0: float = math.pi / 2
    hip: str = "free"
    fall_limit: float = math.radians(60.0)
    motors: str = "two"
    slope: float = 0.0
    step_height: float = 0.0
    step_at: float = 0.0

    def __post_init__(self) -> None:
        check_parameter("omega", self.omega)  # the design record's range (0: cranks held)
        check_number("slope", self.slope, -MAX_SLOPE, MAX_SLOPE)
        check_step(self.step_height, self.step_at)
        check_number("crank_ramp", self.crank_ramp, 0.0, 1e3)
        check_mu(self.mu)
        check_number("dt", self.dt, 0.0, 0.01, low_open=True)
        check_number("theta0", self.theta0, -1e3, 1e3)
        check_number("fall_limit", self.fall_limit, 0.0, math.pi, low_open=True)
        if self.hip not in ("free", "level"):
            raise ParameterError(f"parameter 'hip' must be free or level, got {self.hip!r}")
        if self.motors not in MOTOR_LAYOUTS:
            raise ParameterError(f"parameter 'motors' must be one of {', '.join(MOTOR_LAYOUTS)}, got {self.motors!r}")

    @property
    def ground(self) -> Ground:
        """The ground of these settings: its slope, friction and step edge."""
        return Ground(self.slope, self.mu, self.step_at, self.step_height)


def step_count(duration: float, dt: float, most: int) -> int:
    """The time steps of ``dt`` [s] a run of ``duration`` [s] takes, checked: at least 1, at most ``most``.

    Raises:
        ParameterError: a duration that is not a positive number up to 1e5 s, or that needs more than ``most`` steps.

    """
    check_number("duration", duration, 0.0, 1e5, low_open=True)
    n = max(1, math.ceil(duration / dt - 1e-9))
    if n > most:
        raise ParameterError(f"parameter 'duration' = {duration:g} s needs {n:.3g} steps of {dt:g} s; at most {most:g}")
    return n
