"""One leg's kinematics: foot paths and Jacobians (seed §4, §5); its metrics are in :mod:`.path_metrics`.

Everything here works on the one-leg model (``load(variant, legs=1)``), whose world frame is
the leg frame of docs/reference.md §4: origin at the crank pivot 0, x toward the rocker pivot 3 (forward),
z up. Points are reported as (x, z) [m]; angles [rad]; the crank rate ``omega`` [rad/s].

- :func:`leg_cycle` samples a crank turn on the closure manifold: ankle, toe and heel paths,
  foot pitch and, with ``omega``, the ankle's velocity and acceleration.
- :func:`pasibot_pin.kinematics.path_metrics.straight_line_metrics` gives the stance stroke, the
  ankle band, the straightness deviation, the swing lift, the crank-angle span near the ground and
  the foot pitch; :func:`pasibot_pin.kinematics.path_metrics.k_sweep` repeats the cycle for
  several frame ratios K (seed Fig 4.2.4).
- :func:`open_chain_jacobian` is the seed's 6x4 geometric Jacobian of the open chain
  theta1, theta2, theta4, theta6 (tree joints ``j0_crank``, ``j1``, ``j4``, ``j6``) from
  joint 0 to the ankle; :func:`constrained_jacobian` is the ankle velocity per unit crank
  rate on the closure manifold; :func:`ankle_motion` gives the ankle velocity and acceleration
  from the Jacobians and the drift terms.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from pasibot_pin.constraints import frame_jacobian, planar_pitch
from pasibot_pin.errors import ParameterError
from pasibot_pin.model import closure
from pasibot_pin.model.design import check_parameter
from pasibot_pin.reprs import short_repr

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot

STANCE: tuple[float, float] = (math.pi / 2, 3 * math.pi / 2)
"""Crank-angle window of the stance phase [rad] (docs/reference.md §4: 90 deg to 270 deg)."""

OPEN_CHAIN: tuple[str, ...] = ("j0_crank", "j1", "j4", "j6")
"""Tree joints of the seed's open chain theta1, theta2, theta4, theta6 (joint 0 to the ankle)."""

LOCAL_WORLD_ALIGNED = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def check_one_leg(robot: PasibotRobot) -> None:
    """ValueError unless ``robot`` is a one-leg model (``load(variant, legs=1)``)."""
    if getattr(robot, "legs", None) != 1:
        raise ParameterError("parameter 'robot' must be a one-leg robot (load(variant, legs=1)), the leg frame")


def _check_omega(omega: float | None) -> None:
    if omega is not None:
        check_parameter("omega", omega, low_open=True)  # the design record's crank speeds, > 0


def crank_grid(step: float = math.radians(1.0), start: float = 0.0, turns: float = 1.0) -> np.ndarray:
    """Crank angles from ``start`` over ``turns`` turns every ``step``, both ends included [rad].

    Raises:
        ValueError: when ``step`` does not divide the range into whole samples.

    """
    if not math.isfinite(step) or step <= 0.0:
        raise ParameterError(f"parameter 'step' must be a positive crank increment [rad], got {step!r}")
    if not math.isfinite(turns) or turns <= 0.0:
        raise ParameterError(f"parameter 'turns' must be positive, got {turns!r}")
    count = 2 * math.pi * turns / step
    n = round(count)
    if n < 2 or abs(count - n) > 1e-9 * max(count, 1.0):
        raise ParameterError(
            f"parameter 'step' = {math.degrees(step):.6g} deg must divide {360 * turns:g} deg into at least 2 samples"
        )
    return start + step * np.arange(n + 1)


# --------------------------------------------------------------------------- the cycle
@dataclass
class LegCycle:
    """One leg sampled over crank angles, in the leg frame.

    Attributes:
        robot: the one-leg robot.
        theta: crank angles (N,) [rad].
        q: closed configurations (N, nq).
        ankle: ankle (joint 13) positions (N, 2), x and z [m].
        toe: toe positions (N, 2) [m].
        heel: heel positions (N, 2) [m].
        foot_pitch: sole direction (heel -> toe), counter-clockwise from +x (N,) [rad].
        omega: crank rate [rad/s] or ``None``.
        v: joint velocities (N, nv) [rad/s, m/s] (with ``omega``).
        a: joint accelerations (N, nv) at constant ``omega`` (with ``omega``).
        ankle_velocity: ankle velocity (N, 2) [m/s] (with ``omega``).
        ankle_acceleration: ankle acceleration (N, 2) [m/s^2] (with ``omega``).

    """

    __repr__ = short_repr

    robot: PasibotRobot
    theta: np.ndarray
    q: np.ndarray
    ankle: np.ndarray
    toe: np.ndarray
    heel: np.ndarray
    foot_pitch: np.ndarray
    omega: float | None = None
    v: np.ndarray | None = None
    a: np.ndarray | None = None
    ankle_velocity: np.ndarray | None = None
    ankle_acceleration: np.ndarray | None = None

    def in_stance(self) -> np.ndarray:
        """Boolean mask (N,) of the samples in the stance window 90..270 deg (mod 360)."""
        return stance_mask(self.theta)


def stance_mask(theta: np.ndarray) -> np.ndarray:
    """True where the crank angle lies in the stance window [90, 270] deg (mod 360)."""
    wrapped = np.mod(np.asarray(theta, dtype=float), 2 * math.pi)
    tol = 1e-12
    return (wrapped >= STANCE[0] - tol) & (wrapped <= STANCE[1] + tol)


def _xz(data: pin.Data, fid: int) -> np.ndarray:
    return data.oMf[fid].translation[[0, 2]].copy()


def leg_cycle(
    robot: PasibotRobot,
    thetas: Sequence[float] | np.ndarray | None = None,
    omega: float | None = None,
) -> LegCycle:
    """Sample the leg over crank angles on the closure manifold (warm-started Newton).

    Args:
        robot: a one-leg robot (``load(variant, legs=1)``); the ``spring`` foot is held level.
        thetas: crank angles [rad], ordered (default: one turn every 1 deg, 0 to 360 deg).
        omega: crank rate [rad/s]; when given, joint and ankle velocities and accelerations
            are computed at constant rate.

    Returns:
        The :class:`LegCycle`.

    Raises:
        ValueError: not a one-leg robot, bad ``omega`` or angles, or a loop that cannot close.

    """
    check_one_leg(robot)
    _check_omega(omega)
    thetas = crank_grid() if thetas is None else np.asarray(thetas, dtype=float).reshape(-1)
    if thetas.size == 0 or not np.all(np.isfinite(thetas)):
        raise ParameterError("parameter 'thetas' must be a non-empty sequence of finite crank angles [rad]")
    qs = sweep(robot, thetas)
    model, data = robot.model, robot.data
    ids = {name: robot.frame_id(f"right_{name}") for name in ("foot", "toe", "heel")}
    n = len(thetas)
    ankle, toe, heel, pitch = np.zeros((n, 2)), np.zeros((n, 2)), np.zeros((n, 2)), np.zeros(n)
    for k, q in enumerate(qs):
        pin.framesForwardKinematics(model, data, q)
        ankle[k], toe[k], heel[k] = _xz(data, ids["foot"]), _xz(data, ids["toe"]), _xz(data, ids["heel"])
        pitch[k] = planar_pitch(data.oMf[ids["foot"]].rotation)
    cycle = LegCycle(robot, thetas, qs, ankle, toe, heel, pitch, omega)
    if omega is not None:  # exact v and a of the closed form (its jets), then the ankle's by Pinocchio
        _, cycle.v, cycle.a, _ = closure.analytic_motion(robot, thetas, float(omega))
        cycle.ankle_velocity, cycle.ankle_acceleration = np.zeros((n, 2)), np.zeros((n, 2))
        for k, q in enumerate(qs):
            pin.forwardKinematics(model, data, q, cycle.v[k], cycle.a[k])
            cycle.ankle_velocity[k] = pin.getFrameVelocity(model, data, ids["foot"], LOCAL_WORLD_ALIGNED).linear[[0, 2]]
            accel = pin.getFrameClassicalAcceleration(model, data, ids["foot"], LOCAL_WORLD_ALIGNED)
            cycle.ankle_acceleration[k] = accel.linear[[0, 2]]
    return cycle


def leg_prescriptions(robot: PasibotRobot) -> list[closure.Prescribed]:
    """What fixes a one-leg pose besides the loops: the crank, and for ``spring`` the foot pitch.

    The ``spring`` foot hangs on a free ankle; here it is held level (pitch 0), as the
    biped holds both its stance and its swing foot.
    """
    out: list[closure.Prescribed] = [closure.joint_coordinate(robot, j) for j in robot.actuated_joints]
    if robot.spec.free_ankle:
        out.append(closure.frame_pitch(robot, "right_foot"))
    return out


def _leg_targets(robot: PasibotRobot, prescribed, theta: float) -> list[float]:
    return [float(theta) if p.name in robot.actuated_joints else 0.0 for p in prescribed]


def configuration_at(robot: PasibotRobot, theta: float, q_guess: np.ndarray | None = None) -> np.ndarray:
    """Closed configuration of a one-leg robot at crank angle ``theta`` [rad].

    Warm-started from ``q_guess`` (default: the analytic assembly).
    """
    check_one_leg(robot)
    if not math.isfinite(theta):
        raise ParameterError(f"parameter 'theta' must be finite, got {theta!r}")
    q_guess = closure.assemble(robot, float(theta)) if q_guess is None else q_guess
    prescribed = leg_prescriptions(robot)
    return closure.solve_configuration(robot, q_guess, prescribed, _leg_targets(robot, prescribed, theta))


def sweep(robot: PasibotRobot, thetas: Sequence[float] | np.ndarray) -> np.ndarray:
    """Closed configurations of a one-leg robot at crank angles (N, nq).

    The closed form (:func:`~pasibot_pin.model.closure.analytic_configurations`, the assembly
    branch of the seed) for every sample at once, then one batched Newton
    (:meth:`~pasibot_pin.constraints.ConstraintSystem.project_many`) that only iterates where the
    closed form is not closed to the tolerance. The ``spring`` foot is held level
    (:func:`leg_prescriptions`).
    """
    check_one_leg(robot)
    thetas = np.asarray(thetas, dtype=float).reshape(-1)
    if thetas.size == 0 or not np.all(np.isfinite(thetas)):
        raise ParameterError("parameter 'thetas' must be a non-empty sequence of finite crank angles [rad]")
    prescribed = leg_prescriptions(robot)
    guess, _ = closure.analytic_configurations(robot, thetas)
    targets = np.array([_leg_targets(robot, prescribed, float(theta)) for theta in thetas])
    try:
        q, _ = closure.system(robot, None, prescribed).project_many(guess, targets)
    except ValueError:  # name the crank angle where the loop cannot close, as Newton per sample does
        q = guess
        for k, theta in enumerate(thetas):
            q[k] = configuration_at(robot, float(theta), guess[k])
    return q


def frame_xz(robot: PasibotRobot, q: np.ndarray, frame: str = "right_foot") -> np.ndarray:
    """World (x, z) of a frame at ``q`` [m] (the leg frame for a one-leg robot)."""
    pin.framesForwardKinematics(robot.model, robot.data, q)
    return _xz(robot.data, robot.frame_id(frame))


# --------------------------------------------------------------------------- Jacobians
def open_chain_columns(robot: PasibotRobot, side: str = "right") -> list[int]:
    """Velocity indices of the open chain theta1, theta2, theta4, theta6 of one leg."""
    return [robot.idx_v(f"{side}_{j}") for j in OPEN_CHAIN]


def ankle_on_chain(robot: PasibotRobot, side: str = "right") -> str:
    """Name of a frame at the ankle (joint 13) carried by the shank L5, the chain's end.

    ``rigid``: the foot (rigid to L5); ``spring``: the foot (at joint 13; its own ankle
    joint is outside the chain); ``parallel``: the shank's side of the cut joint 13.
    """
    return f"{side}_{robot.spec.ankle_frame}"


def open_chain_jacobian(
    robot: PasibotRobot, q: np.ndarray, side: str = "right", frame: str | None = None
) -> np.ndarray:
    """The seed's 6x4 geometric Jacobian from joint 0 to the ankle (seed §5).

    Columns: the rates of ``j0_crank``, ``j1``, ``j4``, ``j6`` (seed theta1, theta2, theta4,
    theta6), the tree joints between the hip and the ankle. Rows: linear velocity (x, y, z)
    [m/s per rad/s] and angular velocity (x, y, z) [rad/s per rad/s] of the ankle, in the
    hip frame's axes (the leg frame; for one leg, the world). Column i is the seed's
    ``[z_i x (p_e - p_i); z_i]`` with the joint axis z_i = -y, i.e.
    ``(-(z_e - z_i), 0, x_e - x_i, 0, -1, 0)``.

    Args:
        robot: a loaded robot (one or two legs).
        q: configuration (need not close the loops: this is the open chain).
        side: ``right`` or ``left``.
        frame: end frame (default :func:`ankle_on_chain`); it must ride on the shank L5.

    Returns:
        Array (6, 4).

    Raises:
        ValueError: a wrong-size ``q`` or a frame not carried by the chain.

    """
    model, data = robot.model, robot.data
    q = np.asarray(q, dtype=float)
    if q.shape != (model.nq,):
        raise ParameterError(f"parameter 'q' must have size nq = {model.nq}")
    frame = ankle_on_chain(robot, side) if frame is None else frame
    fid = robot.frame_id(frame)
    shank = model.getJointId(f"{side}_j6")
    parent = model.frames[fid].parentJoint
    if parent != shank and shank not in model.supports[parent]:
        raise ParameterError(f"frame {frame!r} is not carried by the open chain j0_crank-j1-j4-j6 of the {side} leg")
    jac = frame_jacobian(model, data, q, fid)
    cols = jac[:, open_chain_columns(robot, side)]
    if robot.floating:  # express in the hip frame's axes
        pin.framesForwardKinematics(model, data, q)
        rot = data.oMf[robot.frame_id("hip")].rotation.T
        cols = np.vstack((rot @ cols[:3], rot @ cols[3:]))
    return cols


@dataclass(frozen=True)
class AnkleMotion:
    """Motion of a one-leg robot's ankle at one crank angle, constant crank rate.

    Attributes:
        theta: crank angle [rad].
        omega: crank rate [rad/s].
        q: configuration.
        v: joint velocities on the closure manifold (nv,).
        a: joint accelerations on the closure manifold (nv,).
        jacobian: constrained Jacobian, ankle (x, z) velocity per unit crank rate (2,) [m/rad].
        velocity: ankle (x, z) velocity [m/s].
        acceleration: ankle (x, z) acceleration [m/s^2] (= J a + drift).
        drift: ankle (x, z) acceleration at zero joint acceleration [m/s^2] (Jdot v).
        chain_rates: rates of the open chain j0_crank, j1, j4, j6 [rad/s].

    """

    __repr__ = short_repr

    theta: float
    omega: float
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    jacobian: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    drift: np.ndarray
    chain_rates: np.ndarray


def _crank_rates(robot: PasibotRobot, omega: float) -> np.ndarray:
    """Rates of :func:`leg_prescriptions`: the crank at omega, the rest 0."""
    return np.array([omega if p.name in robot.actuated_joints else 0.0 for p in leg_prescriptions(robot)])


def constrained_jacobian(robot: PasibotRobot, q: np.ndarray, frame: str = "right_foot") -> np.ndarray:
    """Velocity of a frame's origin per unit crank rate on the closure manifold (x, z) [m/rad].

    Solves [J_c; J_s] v = [0; e_crank] for the joint rates of a unit crank rate, then maps
    them by the frame Jacobian. For one leg this is d(x, z)/d theta of the frame.
    """
    check_one_leg(robot)
    prescribed = leg_prescriptions(robot)
    v = closure.solve_velocity(robot, q, prescribed, _crank_rates(robot, 1.0))
    jac = frame_jacobian(robot.model, robot.data, q, robot.frame_id(frame))
    return (jac @ v)[[0, 2]]


def ankle_motion(robot: PasibotRobot, q: np.ndarray, omega: float = 0.1, frame: str = "right_foot") -> AnkleMotion:
    """Ankle velocity and acceleration at ``q`` for a crank turning at constant ``omega``.

    v solves [J_c; J_s] v = [0; omega]; a solves [J_c; J_s] a = [-Jdot_c v; 0]. The ankle
    velocity is J v and its acceleration J a + Jdot v, the drift Jdot v being the frame's
    classical acceleration at a = 0 (Pinocchio).

    Args:
        robot: a one-leg robot.
        q: a closed configuration.
        omega: crank rate [rad/s].
        frame: the tracked frame (default the ankle, ``right_foot``).

    """
    check_one_leg(robot)
    _check_omega(omega)
    model, data = robot.model, robot.data
    prescribed = leg_prescriptions(robot)
    rates = _crank_rates(robot, omega)
    v = closure.solve_velocity(robot, q, prescribed, rates)
    a = closure.solve_acceleration(robot, q, v, prescribed, np.zeros(len(prescribed)))
    fid = robot.frame_id(frame)
    jac = frame_jacobian(model, data, q, fid)
    pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
    drift = pin.getFrameClassicalAcceleration(model, data, fid, LOCAL_WORLD_ALIGNED).linear[[0, 2]]
    velocity = (jac @ v)[[0, 2]]
    acceleration = (jac @ a)[[0, 2]] + drift
    return AnkleMotion(
        theta=float(q[robot.idx_q("right_j0_crank")]),
        omega=float(omega),
        q=np.array(q),
        v=v,
        a=a,
        jacobian=velocity / omega,
        velocity=velocity,
        acceleration=acceleration,
        drift=drift,
        chain_rates=v[open_chain_columns(robot)],
    )
