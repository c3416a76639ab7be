"""The simplest walking model (Garcia, Chatterjee, Ruina and Coleman 1998): a validation case.

M. Garcia, A. Chatterjee, A. Ruina and M. Coleman, "The simplest walking model: stability,
complexity, and scaling", J. Biomech. Eng. 120(2):281-288 (1998), doi:10.1115/1.2798313.

Two rigid massless legs of length ``l`` hinged at a point-mass hip ``M``, infinitesimal point
feet (foot mass ``m``, ``beta = m/M -> 0``), walking down a slope ``gamma`` [rad]. Time is scaled
by ``sqrt(l/g)`` (so ``t`` is dimensionless and rates are in rad per scaled time unit). State
``y = (theta, theta', phi, phi')``: ``theta`` the stance leg's angle from the slope normal, ``phi``
the angle between the legs (both rad). Between collisions (Garcia eq. 3-4, beta -> 0)::

    theta'' = sin(theta - gamma)
    phi''   = sin(phi) (theta'^2 - cos(theta - gamma)) + sin(theta - gamma)

Heel strike when ``phi - 2 theta = 0`` (the swing foot reaches the slope). The crossing near
mid-stance (``phi ~ 2 theta ~ 0``, the swing foot scuffing past the stance foot) is ignored, as in
the paper: the collision counted is the next upward crossing of ``phi - 2 theta``, with the stance
leg past the normal (``theta < 0``). The plastic collision swaps the legs (Garcia eq. 5)::

    theta+ = -theta-,   theta'+ = cos(2 theta-) theta'-,
    phi+   = -2 theta-, phi'+   = cos(2 theta-) (1 - cos(2 theta-)) theta'-

The Poincaré section is just after heel strike, where ``phi = 2 theta`` and
``phi' = (1 - cos 2 theta) theta'``: two of the four coordinates follow from ``(theta, theta')``, so
the step map :meth:`SimplestWalker.step` acts on ``z = (theta, theta')`` (R^2 -> R^2).
Garcia et al. linearise the map of the full state (:meth:`SimplestWalker.step_full`, R^4 -> R^4).
Its image lies on the 2-D collision manifold, so its Jacobian has rank 2: two multipliers are
trivially 0, and the other two equal the eigenvalues of the reduced map's Jacobian (``AB`` and
``BA`` share their non-zero eigenvalues, ``A`` the section's embedding, ``B`` the full map's
``(theta, theta')`` rows).

At ``gamma = 0.009`` (``tests/test_poincare.py`` checks all of this): the stable ("long period")
gait is ``theta* = 0.2003109005``, ``theta'* = -0.1998324730`` (Garcia's published
0.20031090049483, -0.19983247291764), step time 3.8825; its multipliers are
``-0.1900998 +- 0.5575988 i`` (``|lambda| = 0.589113``), central differences and an exact
variational linearisation agreeing to 1e-7. Garcia's published pair ``-0.19120869 +- 0.55633364 i``
is what *forward* differences with a step of 1e-5 on ``(theta, theta')`` give (reproduced to 7
digits): the ~1e-3 gap is that scheme's ``O(h)`` bias, not a different gait.

Cost: one step is ~6-10 ms (DOP853, tolerances 1e-12); the fixed point from ``(0.2, -0.2)`` with
its Jacobian takes 4 Newton iterations, 25 steps, ~0.2 s wall / ~0.12 s CPU on one core (plus
~1 s the first time, importing scipy.integrate).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pasibot_pin.errors import MissingExtraError, ParameterError, SimulationError

__all__ = ["FallError", "SimplestWalker", "Stride"]


class FallError(SimulationError):
    """The simplest walker fell (the hip reached the slope) or took no step within the time limit."""


@dataclass(frozen=True)
class Stride:
    """One step of the simplest walker, heel strike to heel strike.

    Attributes:
        start: the state just after the previous heel strike, ``(theta, theta', phi, phi')``.
        before: the state just before the next heel strike.
        after: the state just after it (the next step's ``start``).
        period: the step's duration [scaled time, ``t sqrt(g/l)``].

    """

    start: np.ndarray
    before: np.ndarray
    after: np.ndarray
    period: float


def _solve_ivp():
    """``scipy.integrate.solve_ivp``, or :class:`MissingExtraError` naming the extra."""
    try:
        from scipy.integrate import solve_ivp  # deferred: optional extra (scipy)
    except ImportError as err:  # pragma: no cover - scipy ships with the sweep extra
        raise MissingExtraError("the simplest walker needs scipy: pip install 'pasibot_pin[sweep]'") from err
    return solve_ivp


@dataclass(frozen=True)
class SimplestWalker:
    """Garcia et al.'s simplest walker on a slope, integrated with DOP853.

    Attributes:
        gamma: slope [rad], > 0 for downhill.
        rtol: relative tolerance of the integrator [-].
        atol: absolute tolerance of the integrator [rad, rad per scaled time].
        max_time: longest step before the walker is declared stalled [scaled time].

    """

    gamma: float = 0.009
    rtol: float = 1e-12
    atol: float = 1e-12
    max_time: float = 20.0

    def __post_init__(self) -> None:
        for name in ("gamma", "rtol", "atol", "max_time"):
            value = getattr(self, name)
            if not math.isfinite(value) or (name != "gamma" and value <= 0):
                raise ParameterError(f"{name} must be finite{'' if name == 'gamma' else ' and > 0'}, got {value!r}")

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        """The swing-phase equations: ``y' = (theta', theta'', phi', phi'')`` [per scaled time]."""
        theta, dtheta, phi, dphi = y
        s = math.sin(theta - self.gamma)
        return np.array([dtheta, s, dphi, math.sin(phi) * (dtheta * dtheta - math.cos(theta - self.gamma)) + s])

    @staticmethod
    def heelstrike(before: np.ndarray) -> np.ndarray:
        """The collision and leg swap (beta -> 0): the state just after heel strike."""
        theta, dtheta = float(before[0]), float(before[1])
        c = math.cos(2.0 * theta)
        return np.array([-theta, c * dtheta, -2.0 * theta, c * (1.0 - c) * dtheta])

    @staticmethod
    def on_section(z: np.ndarray) -> np.ndarray:
        """The full post-heel-strike state ``(theta, theta', 2 theta, (1 - cos 2 theta) theta')`` of ``z``."""
        theta, dtheta = float(z[0]), float(z[1])
        return np.array([theta, dtheta, 2.0 * theta, (1.0 - math.cos(2.0 * theta)) * dtheta])

    def stride(self, start: np.ndarray) -> Stride:
        """Integrate one step from ``start`` (a full state) to the next heel strike.

        Args:
            start: ``(theta, theta', phi, phi')`` just after a heel strike [rad, rad per scaled time].

        Returns:
            The :class:`Stride`.

        Raises:
            FallError: the hip reached the slope (``|theta| >= pi/2``), or no heel strike past
                mid-stance within ``max_time``.

        """
        start = np.asarray(start, dtype=float)
        if start.shape != (4,) or not np.all(np.isfinite(start)):
            raise ParameterError(f"start must be 4 finite numbers (theta, theta', phi, phi'), got {start!r}")
        t_scuff, y_scuff = self._integrate(start, 0.0, direction=-1.0)
        t_strike, before = self._integrate(y_scuff, t_scuff, direction=+1.0)
        if before[0] >= 0.0:
            raise FallError(f"the swing foot struck the slope before mid-stance (theta = {before[0]:.4g} rad)")
        return Stride(start, before, self.heelstrike(before), t_strike)

    def _integrate(self, y0: np.ndarray, t0: float, direction: float) -> tuple[float, np.ndarray]:
        """Integrate from ``(t0, y0)`` to the first crossing of ``phi - 2 theta = 0`` in ``direction``."""

        def collision(t: float, y: np.ndarray) -> float:
            return y[2] - 2.0 * y[0]

        def fall(t: float, y: np.ndarray) -> float:
            return math.pi / 2.0 - abs(y[0])

        collision.terminal, collision.direction = True, direction  # type: ignore[attr-defined]  # scipy's events
        fall.terminal = True  # type: ignore[attr-defined]
        sol = _solve_ivp()(
            self.rhs,
            (t0, t0 + self.max_time),
            y0,
            method="DOP853",
            rtol=self.rtol,
            atol=self.atol,
            events=(collision, fall),
        )
        if sol.t_events[1].size:
            raise FallError(f"the walker fell: the hip reached the slope at t = {sol.t_events[1][0]:.4g}")
        if not sol.t_events[0].size:
            what = "heel strike" if direction > 0 else "mid-stance"
            raise FallError(f"no {what} within {self.max_time:g} time units")
        return float(sol.t_events[0][0]), np.asarray(sol.y_events[0][0], dtype=float)

    def step(self, z: np.ndarray) -> np.ndarray:
        """The reduced step map ``(theta, theta') -> (theta, theta')``, section just after heel strike.

        Args:
            z: ``(theta [rad], theta' [rad per scaled time])`` just after a heel strike.

        Returns:
            ``(theta, theta')`` just after the next heel strike.

        Raises:
            FallError: the walker fell or stalled.

        """
        z = np.asarray(z, dtype=float)
        return self.stride(self.on_section(z)).after[:2].copy()

    def step_full(self, y: np.ndarray) -> np.ndarray:
        """Garcia et al.'s map of the full state ``(theta, theta', phi, phi') -> same``, after heel strike."""
        return self.stride(np.asarray(y, dtype=float)).after

    def period(self, z: np.ndarray) -> float:
        """The duration of the step from the section point ``z = (theta, theta')`` [scaled time]."""
        return self.stride(self.on_section(np.asarray(z, dtype=float))).period
