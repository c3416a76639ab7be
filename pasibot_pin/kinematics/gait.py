"""Biped posture in the world frame and a multi-step prescribed gait (seed §4.2.3, §4.3.3).

A prescribed gait is kinematic: the legs follow the cranks and the stance foot is held, with no
dynamics (a walk, in this package, is the simulation on the floor: :mod:`pasibot_pin.studies.walking`).

The two-legged robot steps by turning both cranks, pi apart. Each half crank turn is one
step: the right leg is in stance while its crank runs from 90 deg to 270 deg, the left leg
during the next half turn, and so on. At every half turn the stance and swing legs exchange:
the new stance foot is held where it is on the ground, and the old one is released.

How the stance foot holds the ground (``foot``):

- ``flat`` (default, the physical case): the stance sole is welded level to the ground
  (a planar weld: x, z, pitch). The ``spring`` variant also keeps the hip level and the
  swing foot level. For ``rigid`` the hip then pitches with the shank (the rigid foot can be
  level only if the body tilts), and at each exchange the pose jumps: the new stance foot
  arrives tilted and off the ground, and the weld puts it flat on the ground.
  :attr:`Gait.exchange_jump` records the jump.
- ``point``: the seed's punctiform foot (Fig 4.2.7): the stance ankle is pinned to the
  ground and the hip is kept level.
- ``toe``: the seed's fixed-length foot (Fig 4.2.8): the stance toe is pinned to the ground
  and the hip is kept level; the stance sole tilts about the toe. The new stance toe
  arrives above the ground, so the pose jumps down at each exchange.

The body orientation is the hip's pitch in the world, from ``atan2`` of its rotation matrix
(:func:`body_pitch`), not the seed's ``arccos((tr R - 1) / 2)``, which loses the sign
(:func:`seed_trace_angle` reproduces that for comparison).

Lengths [m], angles [rad], time [s].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from pasibot_pin import constraints
from pasibot_pin.errors import ClosureError, ParameterError
from pasibot_pin.model import closure
from pasibot_pin.model.coordinates import SIDES, other
from pasibot_pin.model.design import check_parameter
from pasibot_pin.reprs import short_repr

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot

FOOT_MODES: tuple[str, ...] = ("flat", "point", "toe")
"""How the stance foot holds the ground (see the module docstring)."""

MAX_GAIT_SAMPLES: int = 1_000_000
"""Most samples one :func:`prescribed_gait` takes (``steps * samples_per_step + 1``): memory stays bounded."""

CLOSURE_TOL: float = 1e-10
"""Largest closure residual accepted at any sample of a gait [m, rad]."""


def body_pitch(rotation: np.ndarray) -> float:
    """Signed pitch of a frame in the x-z plane, counter-clockwise positive [rad] (atan2)."""
    return math.atan2(rotation[2, 0], rotation[0, 0])


def seed_trace_angle(rotation: np.ndarray) -> float:
    """The seed's angle ``arccos((tr R - 1) / 2)`` [rad]: always >= 0, so it loses the sign.

    Kept only to show the seed's error (docs/reference.md §9); use :func:`body_pitch`.
    """
    return math.acos(max(-1.0, min(1.0, (float(np.trace(rotation)) - 1.0) / 2.0)))


DEFAULT_OMEGA: float = 0.1
"""The crank rate a gait is time-stamped at when none is given [rad/s] (the seed's Fig 5.1, ``pasibot gait``'s)."""


@dataclass
class Gait:
    """A sampled multi-step gait of the two-legged robot.

    Attributes:
        robot: the robot (two legs).
        theta: right-crank angle at each sample (N,) [rad]; the left crank is ``theta + pi``.
        t: time since the start (N,) [s], ``(theta - theta[0]) / omega``.
        q: closed configurations (N, nq).
        stance: the stance leg at each sample (``right`` / ``left``), length N.
        step: step index at each sample (N,); step k spans the half turn
            ``theta_start + k pi .. theta_start + (k + 1) pi``. The sample at an exchange
            belongs to the new step; the last sample to the last step.
        foot: ``flat``, ``point`` or ``toe``.
        omega: crank rate [rad/s] (the time stamps' rate).
        contacts: the constraint models in force during each step (loops plus the stance contact).
        residual: largest closure residual at each sample (N,) [m or rad].
        exchange_jump: largest change of q at each exchange, between the pose reached at the
            end of a step and the pose with the new stance contact [m or rad] (zero when the
            new stance foot lands level, as with ``spring`` and ``parallel``).

    """

    __repr__ = short_repr

    robot: PasibotRobot
    theta: np.ndarray
    t: np.ndarray
    q: np.ndarray
    stance: list[str]
    step: np.ndarray
    foot: str
    omega: float
    contacts: list[list] = field(default_factory=list)
    residual: np.ndarray = field(default_factory=lambda: np.zeros(0))
    exchange_jump: list[float] = field(default_factory=list)

    @property
    def n(self) -> int:
        """Number of samples."""
        return len(self.theta)

    def positions(self, frame: str) -> np.ndarray:
        """World position of ``frame`` at every sample, shape (N, 3) [m]."""
        model, data = self.robot.model, self.robot.data
        fid = self.robot.frame_id(frame)
        out = np.zeros((self.n, 3))
        for k, q in enumerate(self.q):
            pin.framesForwardKinematics(model, data, q)
            out[k] = data.oMf[fid].translation
        return out

    def frames_xz(self, frames: list[str]) -> dict[str, np.ndarray]:
        """World (x, z) of several frames at every sample: ``{name: (N, 2)}`` [m]."""
        model, data = self.robot.model, self.robot.data
        ids = {name: self.robot.frame_id(name) for name in frames}
        out = {name: np.zeros((self.n, 2)) for name in frames}
        for k, q in enumerate(self.q):
            pin.framesForwardKinematics(model, data, q)
            for name, fid in ids.items():
                out[name][k] = data.oMf[fid].translation[[0, 2]]
        return out

    def pitch(self, frame: str = "hip") -> np.ndarray:
        """Pitch of ``frame`` in the world at every sample (atan2, signed) (N,) [rad]."""
        model, data = self.robot.model, self.robot.data
        fid = self.robot.frame_id(frame)
        out = np.zeros(self.n)
        for k, q in enumerate(self.q):
            pin.framesForwardKinematics(model, data, q)
            out[k] = body_pitch(data.oMf[fid].rotation)
        return out

    def hip_path(self) -> np.ndarray:
        """World (x, z) of the hip (the crank axis, the leg frame's origin) (N, 2) [m]."""
        return self.frames_xz(["hip"])["hip"]


def _contact(robot: PasibotRobot, side: str, foot: str, q: np.ndarray) -> pin.RigidConstraintModel:
    """The stance contact for ``side``: its x and y from ``q``, on the ground z = 0.

    ``flat`` welds the foot level (pitch 0); ``point`` and ``toe`` pin the ankle or the toe.
    Where the foot lands on the ground and level (``spring``, ``parallel``, ``point``) the
    contact holds it exactly where it is; otherwise the pose jumps onto the ground.
    """
    frame = {"flat": f"{side}_foot", "point": f"{side}_foot", "toe": f"{side}_toe"}[foot]
    pin.framesForwardKinematics(robot.model, robot.data, q)
    position = robot.data.oMf[robot.frame_id(frame)].translation.copy()
    position[2] = 0.0
    if foot == "flat":
        return constraints.weld_constraint(robot.model, frame, pin.SE3(np.eye(3), position), f"{side}_foot_weld")
    return constraints.ground_point_constraint(robot.model, frame, position, f"{frame}_pin")


def _prescriptions(robot: PasibotRobot, stance: str, foot: str) -> list[closure.Prescribed]:
    """Both cranks, plus what the contact leaves free (hip pitch, spring foot pitches)."""
    out: list[closure.Prescribed] = [closure.joint_coordinate(robot, j) for j in robot.actuated_joints]
    if foot == "flat":
        if robot.spec.free_ankle:
            out += [closure.hip_pitch(robot), closure.frame_pitch(robot, f"{other(stance)}_foot")]
        return out
    out.append(closure.hip_pitch(robot))
    if robot.spec.free_ankle:
        out += [closure.frame_pitch(robot, f"{stance}_foot"), closure.frame_pitch(robot, f"{other(stance)}_foot")]
    return out


def _targets(robot: PasibotRobot, prescribed, q_prev: np.ndarray, dtheta: float) -> np.ndarray:
    """Crank targets moved by ``dtheta`` from ``q_prev`` (continuation); every pitch held at 0."""
    targets = np.zeros(len(prescribed))
    for row, p in enumerate(prescribed):
        if closure.is_crank(robot, p):
            targets[row] = q_prev[p.index] + dtheta
    return targets


def _is_int(value) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)


def _check_gait_args(robot: PasibotRobot, steps, samples_per_step, theta_start, omega, foot, first_stance) -> None:
    if getattr(robot, "legs", None) != 2:
        raise ParameterError("parameter 'robot' must be a two-legged robot (load(..., legs=2)) for a gait")
    if not _is_int(steps) or steps < 1:
        raise ParameterError(f"parameter 'steps' must be an integer >= 1, got {steps!r}")
    if not _is_int(samples_per_step) or samples_per_step < 2:
        raise ParameterError(f"parameter 'samples_per_step' must be an integer >= 2, got {samples_per_step!r}")
    if steps * samples_per_step + 1 > MAX_GAIT_SAMPLES:
        raise ParameterError(
            f"parameters 'steps' x 'samples_per_step' + 1 = {steps * samples_per_step + 1} samples "
            f"exceed {MAX_GAIT_SAMPLES}; take fewer steps or samples"
        )
    if not math.isfinite(theta_start):
        raise ParameterError(f"parameter 'theta_start' must be finite, got {theta_start!r}")
    if omega is not None:
        check_parameter("omega", omega, low_open=True)  # the design record's crank speeds, > 0
    if foot not in FOOT_MODES:
        raise ParameterError(f"unknown foot {foot!r}; valid: {', '.join(FOOT_MODES)}")
    if first_stance not in SIDES:
        raise ParameterError(f"parameter 'first_stance' must be right or left, got {first_stance!r}")


def prescribed_gait(
    robot: PasibotRobot,
    steps: int = 2,
    samples_per_step: int = 40,
    theta_start: float = math.pi / 2,
    omega: float | None = None,
    foot: str = "flat",
    first_stance: str = "right",
) -> Gait:
    """The prescribed gait of ``steps`` steps: both cranks turn, stance and swing exchange at every half turn.

    The right crank starts at ``theta_start`` with the right foot touching down (stance),
    the left crank pi apart. The starting stance contact (ankle for ``flat``/``point``,
    toe for ``toe``) sits at the world origin on the ground z = 0.

    Args:
        robot: a two-legged robot (``load(variant, legs=2)``).
        steps: number of steps (half crank turns), >= 1.
        samples_per_step: samples per step, >= 2; the gait has ``steps * samples_per_step + 1``
            samples, both ends included.
        theta_start: right-crank angle at the start [rad] (pi/2: touch-down).
        omega: crank rate [rad/s] for the time stamps; ``None``: :data:`DEFAULT_OMEGA`.
        foot: ``flat``, ``point`` or ``toe`` (see the module docstring).
        first_stance: the leg in stance during the first step (``right``; ``left`` is
            meaningful when ``theta_start`` puts the left foot at touch-down).

    Returns:
        The :class:`Gait`; every sample satisfies its closure to :data:`CLOSURE_TOL`.

    Raises:
        ValueError: bad arguments (named), or a pose where the loops cannot close.

    """
    _check_gait_args(robot, steps, samples_per_step, theta_start, omega, foot, first_stance)
    theta_start = float(theta_start)
    n = steps * samples_per_step + 1
    dtheta = math.pi / samples_per_step
    theta = theta_start + dtheta * np.arange(n)
    stance_side = first_stance
    q, cmodels, prescribed = _start_pose(robot, theta_start, stance_side, foot)
    qs = np.zeros((n, robot.model.nq))
    stance: list[str] = []
    step_index = np.zeros(n, dtype=int)
    residual = np.zeros(n)
    contacts = [cmodels]
    jumps: list[float] = []
    for i in range(n):
        k = min(i // samples_per_step, steps - 1)
        if i > 0 and i % samples_per_step == 0 and i // samples_per_step < steps:
            stance_side = other(stance_side)
            q, cmodels, prescribed, jump = _exchange(robot, q, prescribed, cmodels, stance_side, foot, dtheta)
            contacts.append(cmodels)
            jumps.append(jump)
        elif i > 0:
            q = closure.solve_configuration(robot, q, prescribed, _targets(robot, prescribed, q, dtheta), cmodels)
        qs[i] = q
        stance.append(stance_side)
        step_index[i] = k
        residual[i] = float(np.max(np.abs(closure.constraint_residual(robot, q, cmodels))))
        if residual[i] > CLOSURE_TOL:
            raise ClosureError(
                f"gait: closure residual {residual[i]:.3e} exceeds {CLOSURE_TOL:g} at theta = "
                f"{math.degrees(theta[i]):.3f} deg (step {k}, stance {stance_side})"
            )
    omega = DEFAULT_OMEGA if omega is None else float(omega)
    t = (theta - theta_start) / omega
    return Gait(
        robot=robot,
        theta=theta,
        t=t,
        q=qs,
        stance=stance,
        step=step_index,
        foot=foot,
        omega=omega,
        contacts=contacts,
        residual=residual,
        exchange_jump=jumps,
    )


def _start_pose(robot: PasibotRobot, theta_start: float, stance_side: str, foot: str):
    """The gait's first pose, its contact rows and prescriptions: the requested contact, hip level.

    The flat assembly first, then (for a point or toe contact, or a free ankle) the closed pose
    with that contact; the starting contact point moved to the world origin (a rigid translation).
    """
    q = closure.assemble(robot, theta_start, stance=stance_side, ankle_x=0.0)
    contact = _contact(robot, stance_side, foot, q)
    cmodels = list(robot.loop_constraints) + [contact]
    prescribed = _prescriptions(robot, stance_side, foot)
    if foot != "flat" or robot.spec.free_ankle:
        q = closure.solve_configuration(robot, q, prescribed, _targets(robot, prescribed, q, 0.0), cmodels)
    pin.framesForwardKinematics(robot.model, robot.data, q)
    anchor = "foot" if foot in ("flat", "point") else "toe"
    origin = robot.data.oMf[robot.frame_id(f"{stance_side}_{anchor}")].translation
    q[0] -= origin[0]
    q[1] -= origin[2]
    contact = _contact(robot, stance_side, foot, q)
    return q, list(robot.loop_constraints) + [contact], prescribed


def _exchange(robot: PasibotRobot, q, prescribed, cmodels, new_stance: str, foot: str, dtheta: float):
    """The stance exchange at a half turn: (q, contact rows, prescriptions, pose jump) of the new stance.

    First the pose at the half turn with the old contact, then the new stance foot held where it
    is (level for ``flat``); the jump is the largest coordinate change between the two poses.
    """
    q_end = closure.solve_configuration(robot, q, prescribed, _targets(robot, prescribed, q, dtheta), cmodels)
    contact = _contact(robot, new_stance, foot, q_end)
    cmodels = list(robot.loop_constraints) + [contact]
    prescribed = _prescriptions(robot, new_stance, foot)
    q = closure.solve_configuration(robot, q_end, prescribed, _targets(robot, prescribed, q_end, 0.0), cmodels)
    return q, cmodels, prescribed, float(np.max(np.abs(pin.difference(robot.model, q_end, q))))


def step_advances(
    robot: PasibotRobot, steps: int = 2, samples_per_step: int = 12, foot: str = "flat", omega=None
) -> np.ndarray:
    """The hip's advance in each of ``steps`` steps, from the start of a step to the start of the next [m].

    Both ends are the same phase of the gait: just after an exchange (the first, the start). The
    last sample of a gait is the *end* of its last step, before the exchange: for the ``rigid``
    foot, square to its shank, the body is pitched ~30 deg there, and the exchange that puts the
    new stance foot flat turns the whole robot back, so the hip's travel to that sample is not a
    step's advance. A gait of one step more gives the next start.
    """
    w = prescribed_gait(robot, steps + 1, samples_per_step, foot=foot, omega=omega)
    starts = w.hip_path()[::samples_per_step, 0][: steps + 1]
    return np.diff(starts)


def gait_and_advances(
    robot: PasibotRobot, steps: int = 2, samples_per_step: int = 40, omega: float | None = None, foot: str = "flat"
) -> tuple[Gait, np.ndarray]:
    """``prescribed_gait(robot, steps, samples_per_step, ...)`` and its :func:`step_advances`, from one gait [-, m].

    :func:`step_advances` takes one step more than the gait; that longer gait passes through every
    sample of the shorter one but its last, the end of its last step (which the longer one goes on
    to solve as the start of its exchange: the same solve, made once more here). Both results are
    those of the two calls, number for number, for the work of the longer gait alone.

    Args:
        robot: a two-legged robot (``load(variant, legs=2)``).
        steps: steps (half crank turns) of the gait, >= 1.
        samples_per_step: samples per step, >= 2.
        omega: crank rate [rad/s] for the time stamps; ``None``: :data:`DEFAULT_OMEGA`.
        foot: ``flat``, ``point`` or ``toe``.

    Returns:
        (the :class:`Gait` of ``steps`` steps from right touch-down at pi/2, the hip's advance in
        each of its steps [m]).

    Raises:
        ValueError: as :func:`prescribed_gait`.

    """
    _check_gait_args(robot, steps, samples_per_step, math.pi / 2, omega, foot, "right")
    longer = prescribed_gait(robot, steps + 1, samples_per_step, omega=omega, foot=foot)
    advances = np.diff(longer.hip_path()[::samples_per_step, 0][: steps + 1])
    n = steps * samples_per_step + 1
    dtheta = math.pi / samples_per_step
    stance, cmodels, q = longer.stance[n - 2], longer.contacts[steps - 1], longer.q[n - 2]
    prescribed = _prescriptions(robot, stance, foot)
    q_end = closure.solve_configuration(robot, q, prescribed, _targets(robot, prescribed, q, dtheta), cmodels)
    residual = float(np.max(np.abs(closure.constraint_residual(robot, q_end, cmodels))))
    if residual > CLOSURE_TOL:
        raise ClosureError(
            f"gait: closure residual {residual:.3e} exceeds {CLOSURE_TOL:g} at theta = "
            f"{math.degrees(math.pi / 2 + dtheta * (n - 1)):.3f} deg (step {steps - 1}, stance {stance})"
        )
    theta = math.pi / 2 + dtheta * np.arange(n)
    shorter = Gait(
        robot=robot,
        theta=theta,
        t=(theta - math.pi / 2) / (DEFAULT_OMEGA if omega is None else float(omega)),
        q=np.vstack((longer.q[: n - 1], q_end)),
        stance=[*longer.stance[: n - 1], stance],
        step=np.minimum(longer.step[:n], steps - 1),
        foot=foot,
        omega=DEFAULT_OMEGA if omega is None else float(omega),
        contacts=longer.contacts[:steps],
        residual=np.append(longer.residual[: n - 1], residual),
        exchange_jump=longer.exchange_jump[: steps - 1],
    )
    return shorter, advances


def stride_advance(robot: PasibotRobot, samples_per_step: int = 12, foot: str = "flat") -> float:
    """The hip's advance per step over a whole stride (two steps, from one step start to the same phase) [m].

    One definition for every variant (:func:`step_advances`): 8 L with a level hip (the linkage's
    stroke); 6.9 L for the ``rigid`` variant with flat feet, whose body pitches with its shank.
    """
    return float(np.mean(step_advances(robot, 2, samples_per_step, foot)))
