"""Ankle spring stiffness from inverse dynamics: T_e = -K_e (beta - beta0), least squares.

K_e is minus the slope of the least-squares line of the stance ankle torque T_e [N.m]
against the ankle angle beta [rad] (seed §7.3.2). The fit also gives the rest angle beta0
where the line crosses zero, R^2, and the residual torque a linear spring cannot supply
(it must come from elsewhere: a motor, a preload schedule, or the robot falls).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pasibot_pin.dynamics.inverse import STANCE_RANGE, check_fit_window, crank_grid, inverse_dynamics
from pasibot_pin.dynamics.spring_energy import AnkleSpring
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import design_robot
from pasibot_pin.reprs import short_repr

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot

LOW_R2: float = 0.9
"""Below this R^2 a single K_e does not describe T_e(beta) (seed run 4: R^2 ~ 0.58)."""


class LowFitQualityWarning(UserWarning):
    """T_e(beta) is far from linear: one stiffness does not describe it."""


@dataclass(frozen=True)
class SpringFit:
    """A linear torsion spring fitted to T_e(beta).

    Attributes:
        K_e: stiffness [N.m/rad] (minus the slope).
        beta0: rest angle, where the fitted torque is zero [rad] (NaN-free: inf if K_e = 0).
        r2: coefficient of determination [-].
        residual: T_e minus the fitted line at each fitted sample [N.m].
        rms_residual: root mean square of ``residual`` [N.m].
        max_residual: largest absolute residual [N.m].
        samples: number of fitted samples.
        warning: a message when R^2 < :data:`LOW_R2`, else empty.

    """

    __repr__ = short_repr

    K_e: float
    beta0: float
    r2: float
    residual: np.ndarray
    rms_residual: float
    max_residual: float
    samples: int
    warning: str = ""

    def torque(self, beta: np.ndarray | float) -> np.ndarray | float:
        """The fitted spring torque -K_e (beta - beta0) [N.m]."""
        return -self.K_e * (np.asarray(beta) - self.beta0)

    def summary(self) -> str:
        """One line: K_e, beta0 (deg), R^2, residual."""
        text = (
            f"K_e = {self.K_e:.2f} N.m/rad, beta0 = {math.degrees(self.beta0):.2f} deg, R^2 = {self.r2:.4f}, "
            f"residual rms {self.rms_residual:.3f} N.m (max {self.max_residual:.3f} N.m), {self.samples} samples"
        )
        return text + (f"  WARNING: {self.warning}" if self.warning else "")


def fit_spring(beta: np.ndarray, torque: np.ndarray, warn: bool = True) -> SpringFit:
    """Least-squares line of ``torque`` [N.m] against ``beta`` [rad].

    Raises:
        ValueError: fewer than two samples, non-finite values, mismatched shapes, or a
            constant beta (no slope can be fitted).

    """
    beta = np.asarray(beta, dtype=float).reshape(-1)
    torque = np.asarray(torque, dtype=float).reshape(-1)
    if beta.shape != torque.shape:
        raise ParameterError(f"parameters 'beta' and 'torque' differ in length ({beta.size} vs {torque.size})")
    if beta.size < 2:
        raise ParameterError("parameter 'beta' needs at least two samples for a spring fit")
    if not (np.all(np.isfinite(beta)) and np.all(np.isfinite(torque))):
        raise ParameterError("parameters 'beta' and 'torque' must be finite")
    db = beta - beta.mean()
    sxx = float(db @ db)
    if sxx <= 1e-24:
        raise ParameterError("parameter 'beta' is constant: the spring slope is undefined")
    slope = float(db @ (torque - torque.mean())) / sxx
    intercept = float(torque.mean() - slope * beta.mean())
    residual = torque - (slope * beta + intercept)
    ss_tot = float(((torque - torque.mean()) ** 2).sum())
    r2 = 1.0 - float(residual @ residual) / ss_tot if ss_tot > 0 else 1.0
    k_e = -slope
    beta0 = -intercept / slope if slope != 0 else math.inf
    message = ""
    if r2 < LOW_R2:
        message = (
            f"R^2 = {r2:.3f} < {LOW_R2}: T_e(beta) is not linear, a single K_e is not meaningful "
            "(compare torque curves at given theta instead)"
        )
        if warn:
            warnings.warn(message, LowFitQualityWarning, stacklevel=2)
    return SpringFit(
        K_e=k_e,
        beta0=beta0,
        r2=r2,
        residual=residual,
        rms_residual=float(np.sqrt(np.mean(residual**2))),
        max_residual=float(np.max(np.abs(residual))),
        samples=int(beta.size),
        warning=message,
    )


def fit_result(result, fit_thetas=None, warn: bool = True) -> SpringFit:
    """Fit the stance T_e(beta) of a :class:`~pasibot_pin.dynamics.inverse.TorqueResult`.

    Args:
        result: the torques along the motion.
        fit_thetas: stance-crank angles of the window [rad] (each must be a sample of
            ``result`` and inside stance); default every sample.
        warn: emit :class:`LowFitQualityWarning` when R^2 is low.

    Raises:
        ValueError: a window outside stance, or angles that are not samples of the result.

    """
    if fit_thetas is None:
        mask = np.ones(len(result.t), dtype=bool)
    else:
        window = check_fit_window(fit_thetas)
        theta = np.asarray(result.theta_right if all(s == "right" for s in result.stance) else result.theta)
        mask = np.zeros(theta.size, dtype=bool)
        for th in window:
            hit = np.abs(theta - th) < 1e-9
            if not hit.any():
                raise ParameterError(f"parameter 'fit_thetas': {th:.4f} rad is not a sample of the result")
            mask |= hit
    return fit_spring(result.beta[mask], result.Te[mask], warn=warn)


def design_spring(design, robot: PasibotRobot | None = None):
    """The ankle spring of a design [N.m/rad, rad, N.m.s/rad], fitted where the design leaves it unset.

    K_e and beta0 come from the design if it sets them, otherwise from the stance fit of the
    constrained inverse dynamics of the design's two-legged robot at its crank speed (the
    torque analysis, right foot held, one stance). Returns ``None`` for a variant without a
    spring ankle.

    Args:
        design: a :class:`~pasibot_pin.model.design.Design`.
        robot: its two-legged robot, if already loaded (:func:`~pasibot_pin.model.design.design_robot`).

    """
    robot = design_robot(design, 2) if robot is None or robot.legs != 2 else robot
    if not robot.spec.free_ankle:
        return None
    stiffness, rest = design.spring_stiffness, design.spring_rest_angle
    if stiffness is None or rest is None:
        result = inverse_dynamics(robot, crank_grid(*STANCE_RANGE, 61), design.omega, stance="right")
        fit = fit_result(result, None, warn=False)
        stiffness = fit.K_e if stiffness is None else stiffness
        rest = fit.beta0 if rest is None else rest
    return AnkleSpring(stiffness, rest, design.spring_damping)
