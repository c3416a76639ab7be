"""One motor for both cranks (seed §8, future work 2): torque, peak, RMS, flywheel.

The cranks are coupled pi apart by a rigid 1:1 transmission (a chain or a gear train). In
the model this is one extra constraint row, c_k(q) = q_L - q_R - pi = 0 (Jacobian
e_L - e_R), and the actuation map has one motor, on the right crank (S_m = e_R). Pinocchio's
``JointModelMimic`` would express the same coupling, but the constraint algorithms reject it
(docs/reference.md §7), so the row is added to our own split:

    tau = S_m^T u_m + S_e^T u_e + J_c^T lambda + (e_L - e_R) lambda_k,

a square system (1 motor + 2 ankles + 15 in-plane constraint rows + 1 coupling row = nv = 19
for the ``spring`` biped). lambda_k is the torque the transmission delivers to the left
crank. The prescribed motion of the two-motor analysis already holds the cranks pi apart,
so q, v, a and tau are the same; only their split changes (checked per sample). By virtual
power the motor torque must be T_a + T_a' of the two-motor solution; the tests check that.

A flywheel of inertia J on the motor shaft, with the motor giving its mean torque, takes
up the fluctuation: the shaft's kinetic energy follows 1/2 J w^2 = 1/2 J w0^2 - E(theta),
E(theta) = integral of (u_m - mean u_m) d theta, so the speed fluctuates by
delta = (w_max - w_min) / w_mean ~ Delta E / (J w^2) (to first order in delta; the robot's
own torque demand is taken at constant speed).

Units: SI; torques [N.m]; angles [rad].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pasibot_pin.constraints import split_torques
from pasibot_pin.dynamics.stance_plan import actuation, couplings
from pasibot_pin.errors import ParameterError
from pasibot_pin.model import closure
from pasibot_pin.model.design import check_parameter
from pasibot_pin.model.variants import get_motor_layout
from pasibot_pin.reprs import short_repr

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot


@dataclass
class SingleMotorResult:
    """Torques of the one-motor drive along a motion.

    Attributes:
        t: time [s].
        theta: stance crank angle [rad].
        motor: the motor torque on the right crank shaft [N.m].
        transmission: torque the coupling delivers to the left crank [N.m].
        ankle: (N x 2) generalised forces of the stance and swing beta [N.m] (same as two motors).
        coupling_residual: max |q_L - q_R - pi| over the samples (wrapped) [rad].

    """

    __repr__ = short_repr

    t: np.ndarray
    theta: np.ndarray
    motor: np.ndarray
    transmission: np.ndarray
    ankle: np.ndarray
    coupling_residual: float

    def peak(self) -> float:
        """Largest |motor torque| [N.m]."""
        return float(np.max(np.abs(self.motor)))

    def rms(self) -> float:
        """Root mean square of the motor torque over the samples' time span (trapezoid) [N.m]."""
        return rms(self.t, self.motor)


def rms(t: np.ndarray, y: np.ndarray) -> float:
    """Time-RMS of samples ``y`` at times ``t`` (trapezoid; plain RMS when t is constant)."""
    t, y = np.asarray(t, dtype=float), np.asarray(y, dtype=float)
    span = t[-1] - t[0] if t.size > 1 else 0.0
    if span <= 0:
        return float(np.sqrt(np.mean(y**2)))
    return float(math.sqrt(np.trapezoid(y**2, t) / span))


def coupled_split(robot: PasibotRobot, result) -> SingleMotorResult:
    """Split the inverse-dynamics torques of ``result`` with one motor and the coupling row.

    Args:
        robot: the two-legged robot (any variant) the result was computed with (same model).
        result: a :class:`~pasibot_pin.dynamics.inverse.TorqueResult` (its q, tau, stance per sample).

    Raises:
        ValueError: not a biped; cranks not pi apart; a singular split.

    """
    if robot.legs != 2:
        raise ParameterError(f"coupled_split needs a two-legged robot, got legs={robot.legs}")
    layout = get_motor_layout("one")
    qi_r, qi_l = robot.idx_q("right_j0_crank"), robot.idx_q("left_j0_crank")
    n = len(result.t)
    motor, trans, ankle = np.zeros(n), np.zeros(n), np.zeros((n, 2))
    n_spring = 2 if robot.spec.free_ankle else 0
    worst = 0.0
    cache: dict[str, tuple] = {}
    for k in range(n):
        q, tau, side = np.asarray(result.q[k]), np.asarray(result.tau[k]), result.stance[k]
        worst = max(worst, abs(math.remainder(q[qi_l] - q[qi_r] - math.pi, 2 * math.pi)))
        if side not in cache:
            rs = robot.with_stance(side, q)
            # the coupling q_L - q_R - pi = 0 is one more row of the constraint system
            cache[side] = (closure.system(rs, None, couplings(rs, layout)), actuation(rs, side, layout))
        rows, s_matrix = cache[side]
        try:
            u, lam = split_torques(tau, s_matrix, rows.jacobian(q))
        except ValueError as err:
            raise type(err)(f"coupled split at sample {k}: {err}") from None
        motor[k], trans[k] = u[0], lam[-1]
        ankle[k, :n_spring] = -u[1 : 1 + n_spring]  # generalised forces of beta = pi/2 - q_ankle
    if worst > 1e-9:
        raise ParameterError(
            f"parameter 'result': the cranks are not pi apart (max |q_L - q_R - pi| = {worst:.3e} rad)"
        )
    return SingleMotorResult(
        t=np.asarray(result.t, dtype=float),
        theta=np.asarray(result.theta, dtype=float),
        motor=motor,
        transmission=trans,
        ankle=ankle,
        coupling_residual=worst,
    )


@dataclass(frozen=True)
class Flywheel:
    """Flywheel smoothing of a motor torque over one period.

    Attributes:
        inertia: flywheel inertia on the motor shaft [kg.m^2].
        omega: mean shaft speed [rad/s].
        mean_torque: the motor's constant torque with the flywheel [N.m].
        peak_without: peak |torque| the motor gives without a flywheel [N.m].
        energy_swing: Delta E = max - min of integral (u - mean u) d theta [J].
        speed_fluctuation: (w_max - w_min) / w_mean with the flywheel (exact in the energy balance) [-].
        speed_fluctuation_linear: Delta E / (J w^2) [-].

    """

    inertia: float
    omega: float
    mean_torque: float
    peak_without: float
    energy_swing: float
    speed_fluctuation: float
    speed_fluctuation_linear: float


def flywheel(theta: np.ndarray, torque: np.ndarray, omega: float, inertia: float) -> Flywheel:
    """Smooth a periodic motor torque u(theta) with a flywheel of inertia ``inertia``.

    The motor gives the mean torque (the average of u over the samples' crank span); the
    flywheel's kinetic energy absorbs E(theta) = integral (u - mean u) d theta. With the mean
    speed ``omega`` the shaft speed is w(theta) = sqrt(w0^2 - 2 E(theta) / J), w0 chosen so
    that the time-mean speed is ``omega``.

    Args:
        theta: crank angles of one period, increasing [rad].
        torque: motor torque at those angles (load at constant speed) [N.m].
        omega: mean crank speed [rad/s], > 0.
        inertia: flywheel inertia [kg.m^2], > 0.

    Raises:
        ValueError: bad omega or inertia, or a flywheel too small for the model (Delta E > J w^2:
            the speed would vary by more than its mean, so the load at constant speed is meaningless).

    """
    theta, torque = np.asarray(theta, dtype=float), np.asarray(torque, dtype=float)
    if theta.size < 2 or theta.shape != torque.shape or np.any(np.diff(theta) <= 0):
        raise ParameterError("parameters 'theta' (increasing) and 'torque' must be same-length arrays of >= 2 samples")
    check_parameter("omega", omega, low_open=True)  # the design record's crank speeds, > 0
    if not (math.isfinite(inertia) and inertia > 0):
        raise ParameterError(f"parameter 'inertia' must be a positive flywheel inertia [kg.m^2], got {inertia!r}")
    span = theta[-1] - theta[0]
    mean = float(np.trapezoid(torque, theta) / span)
    dev = torque - mean
    energy = np.concatenate(([0.0], np.cumsum(0.5 * (dev[1:] + dev[:-1]) * np.diff(theta))))
    swing = float(energy.max() - energy.min())

    if swing > inertia * omega**2:
        raise ParameterError(
            f"parameter 'inertia': {inertia:g} kg.m^2 is too small to smooth this torque: the energy swing "
            f"{swing:.4g} J exceeds J w^2 = {inertia * omega**2:.4g} J, the speed would vary by more than its mean"
        )
    floor = math.sqrt(max(2.0 * float(energy.max()) / inertia, 0.0))  # w0 below this stops the shaft

    def speeds(w0: float) -> np.ndarray:
        return np.sqrt(np.maximum(w0**2 - 2.0 * energy / inertia, 0.0))

    def time_mean(w0: float) -> float:  # mean speed = span / time taken
        w = speeds(w0)
        if np.any(w <= 0):
            return 0.0
        return float(span / np.trapezoid(1.0 / w, theta))

    lo, hi = floor * (1 + 1e-12) + 1e-300, floor + 2.0 * omega
    if time_mean(lo) >= omega:
        raise ParameterError(
            f"parameter 'inertia': {inertia:g} kg.m^2 is too small, the shaft would stop or reverse "
            f"(energy swing {swing:.4g} J against 1/2 J w^2 = {0.5 * inertia * omega**2:.4g} J)"
        )
    for _ in range(200):  # bisection: the time-mean speed grows with w0
        mid = 0.5 * (lo + hi)
        if time_mean(mid) < omega:
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-15 * omega:
            break
    w0 = 0.5 * (lo + hi)
    w = speeds(w0)
    return Flywheel(
        inertia=float(inertia),
        omega=float(omega),
        mean_torque=mean,
        peak_without=float(np.max(np.abs(torque))),
        energy_swing=swing,
        speed_fluctuation=float((w.max() - w.min()) / omega),
        speed_fluctuation_linear=swing / (inertia * omega**2),
    )


def inertia_for(theta: np.ndarray, torque: np.ndarray, omega: float, fluctuation: float) -> float:
    """Flywheel inertia that keeps the speed fluctuation at ``fluctuation`` (first order) [kg.m^2]."""
    if not (math.isfinite(fluctuation) and fluctuation > 0):
        raise ParameterError(f"parameter 'fluctuation' must be positive, got {fluctuation!r}")
    probe = flywheel(theta, torque, omega, 1e6)
    return probe.energy_swing / (fluctuation * omega**2)
