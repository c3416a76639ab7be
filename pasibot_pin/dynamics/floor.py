"""Walking on a real floor: heel and toe as unilateral Coulomb contacts, time-stepped (first version).

The welded simulator (:mod:`pasibot_pin.dynamics.simulator`) holds the stance foot flat on the
ground. Here nothing holds either foot: each sole touches the floor at its heel and its toe,
each point unilateral (it may lift, never sink) with Coulomb friction mu. The loops and the
motors stay bilateral rows of the same :class:`~pasibot_pin.constraints.ConstraintSystem`.

One step of length h is a velocity-level time-stepping (Moreau, Anitescu): the velocity after
the step solves the convex QP

    min_v  1/2 (v - v-)^T M (v - v-) - h (tau - b)^T v
    s.t.   J_b v = -Phi_t                                  (loops, cranks: bilateral)
           (J_n +- mu J_t) v >= -gap / h                   (each contact point: its friction cone)

with proxsuite. Its multipliers are the contact impulses: a point's normal impulse is the sum
of its two cone rows' and the tangential one mu times their difference, so |F_t| <= mu F_n
holds by construction (the planar cone is exactly two half-planes). A point that reaches the
floor stops there in one step (an inelastic touchdown, found by the step rather than
scheduled); a point leaves the floor when its normal impulse is zero. Positions are then
projected back onto the loops (mass metric), so the loops drift by less than Newton's
tolerance. Each step reports the contact mode of each foot: ``flat`` (heel and toe load),
``heel``, ``toe``, ``sliding`` or ``air``.

Units: SI, angles [rad], impulses [N.s]; forces are impulses over h [N].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin
import proxsuite

from pasibot_pin.constraints import ConstraintSystem, coordinate, symmetric_mass_matrix
from pasibot_pin.constraints.planar import PlanarRowBlocks
from pasibot_pin.constraints.system import planar_kinematics
from pasibot_pin.dynamics.simulator import AnkleSpring, ankle_indices, spring_forces

SIDES = ("right", "left")
POINTS = ("heel", "toe")
MODES = ("flat", "heel", "toe", "sliding", "air")
LOAD_TOL = 1e-3
"""A contact point carries load when its normal force exceeds this [N] (the QP's impulses are
accurate to about 1e-8 N.s)."""
SLIP_TOL = 1e-4
"""A loaded point slides when its tangential speed exceeds this [m/s]."""
ROLL_LIMIT = math.radians(60.0)
"""A foot standing on its heel or toe alone has rolled over it past this sole pitch [rad]."""
SLIP_LIMIT = 0.02
"""A foot has slipped when its loaded points have slid this far in all while it bore weight [m]."""
STEP_ADVANCE = 2.0
"""A landing is a step when the foot lands at least this many crank lengths L ahead of where it
last stood (a foot that lands where it stood has hopped, not stepped) [-]."""
BEARING_SHARE = 0.25
"""A foot bears weight when its normal force exceeds this share of the robot's weight (a dragging
swing toe does not count as a slip) [-]."""


def _check(name: str, value: float, low: float, high: float = math.inf, low_open: bool = False) -> float:
    value = float(value)
    ok = math.isfinite(value) and (value > low if low_open else value >= low) and value <= high
    if not ok:
        bound = f"> {low:g}" if low_open else f">= {low:g}"
        raise ValueError(f"parameter {name!r} must be a finite number {bound}, got {value!r}")
    return value


@dataclass(frozen=True)
class FloorSettings:
    """How to simulate on the floor.

    Attributes:
        omega: crank rate [rad/s] (rheonomic cranks, theta0 + omega t).
        spring: the ankle springs (``None``: free ankles).
        mu: sole-floor Coulomb friction [-].
        dt: time step [s].
        theta0: initial right crank angle [rad].
        hip: ``free`` or ``level`` (pitch held at 0).
        fall_limit: the run stops when |hip pitch| passes this [rad].

    """

    omega: float = 0.1
    spring: AnkleSpring | None = None
    mu: float = 0.8
    dt: float = 1e-3
    theta0: float = math.pi / 2
    hip: str = "free"
    fall_limit: float = math.radians(60.0)

    def __post_init__(self) -> None:
        _check("omega", self.omega, 0.0)
        _check("mu", self.mu, 0.0)
        _check("dt", self.dt, 0.0, 0.01, low_open=True)
        _check("theta0", self.theta0, -1e3, 1e3)
        _check("fall_limit", self.fall_limit, 0.0, math.pi, low_open=True)
        if self.hip not in ("free", "level"):
            raise ValueError(f"parameter 'hip' must be free or level, got {self.hip!r}")


@dataclass
class FloorResult:
    """Samples of a floor run, one per step.

    Attributes:
        t: times [s].
        q, v: configurations and velocities.
        hip_pitch: [rad].
        modes: contact mode of each foot per sample, ``{"right": [...], "left": [...]}`` (:data:`MODES`).
        normal, tangential: contact forces (n, 4) [N], columns right heel, right toe, left heel, left toe.
        motor_torque: crank torques (n, 2) [N.m], right, left.
        touchdowns: (t, side, point) of every point that starts to carry load after carrying none.
        steps: (t, side, x, length) of every step: a foot that lands (air -> loaded) at least
            :data:`STEP_ADVANCE` L ahead of where it last stood; x is where it lands (the middle of
            its heel and toe) and length its distance ahead of the other foot [m].
        landings: (t, side, x) of every landing, steps and hops alike [m].
        outcome: ``walks N steps`` (N landings, no failure), or the cause and time of the failure:
            the hip pitch beyond its limit, a foot rolled over its heel or toe, a foot slipped, a
            loop that cannot close, a contact problem the solver could not solve.
        failed: True when the run stopped on a failure.

    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    hip_pitch: np.ndarray
    modes: dict[str, list[str]]
    normal: np.ndarray
    tangential: np.ndarray
    motor_torque: np.ndarray
    touchdowns: list[tuple[float, str, str]] = field(default_factory=list)
    steps: list[tuple[float, str, float, float]] = field(default_factory=list)
    landings: list[tuple[float, str, float]] = field(default_factory=list)
    outcome: str = ""
    failed: bool = False

    def step_lengths(self) -> np.ndarray:
        """The landing foot's distance ahead of the other foot at each step [m]."""
        return np.array([length for *_, length in self.steps])

    def step_durations(self) -> np.ndarray:
        """Time from one step to the next [s]."""
        return np.diff([t for t, *_ in self.steps])

    def friction_use(self) -> np.ndarray:
        """|F_t| / F_n of each point (n, 4) [-] (0 where the point carries no load)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            use = np.abs(self.tangential) / self.normal
        return np.where(self.normal > 0, use, 0.0)


class FloorSimulator:
    """The ``spring`` biped on a floor (see the module docstring).

    Args:
        robot: ``pp.load("spring", 2)`` (or a copy with other masses).
        settings: :class:`FloorSettings`.

    """

    def __init__(self, robot, settings: FloorSettings):
        if robot.legs != 2 or not robot.floating:
            raise ValueError("the floor simulator needs the two-legged robot with its floating hip")
        self.robot, self.settings = robot, settings
        model = robot.model
        self.ankles = ankle_indices(robot) if robot.spec.free_ankle else {}
        scalars = [
            coordinate(
                f"{side}_j0_crank", robot.idx_v(f"{side}_j0_crank"), settings.theta0 + k * math.pi, settings.omega
            )
            for k, side in enumerate(SIDES)
        ]
        if settings.hip == "level":
            scalars.append(coordinate("hip_pitch", 2, 0.0, 0.0))
        self.bilateral = ConstraintSystem(model, robot.data, robot.loop_constraints, scalars, robot.geometry.L)
        frames = [model.frames[robot.frame_id(f"{side}_{point}")] for side in SIDES for point in POINTS]
        ends = planar_kinematics(model).ends(
            np.array([f.parentJoint for f in frames]),
            np.array([f.placement.translation for f in frames]),
            np.array([f.placement.rotation for f in frames]),
        )
        self.points = PlanarRowBlocks(ends, [(k, -1) for k in range(len(frames))], [])
        self._crank_rows = [self.bilateral.labels.index(f"{side}_j0_crank") for side in SIDES]
        gravity = float(np.linalg.norm(model.gravity.linear))
        self.weight = gravity * sum(model.inertias[j].mass for j in range(1, model.njoints))

    # ---- one step
    def contact_rows(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Gaps (4,) [m], tangential positions (4,) [m], J_n (4, nv) and J_t (4, nv) of heel and toe points."""
        rows, jac, _, _ = self.points.evaluate(q)
        return rows.imag, rows.real, jac.imag, jac.real

    def step(self, t: float, q: np.ndarray, v: np.ndarray, h: float):
        """One step: (q+, v+, normal and tangential impulses (4,) [N.s], bilateral impulses)."""
        model, data, s = self.robot.model, self.robot.data, self.settings
        rows = self.bilateral.evaluate(q, None, t + h)
        gap, _, jn, jt = self.contact_rows(q)
        mass = symmetric_mass_matrix(model, data, q)
        bias = pin.nonLinearEffects(model, data, q, v)
        tau = spring_forces(self.robot, s.spring, q, v, self.ankles) if s.spring is not None else np.zeros(model.nv)
        g = -(mass @ v + h * (tau - bias))
        cone = np.vstack((jn + s.mu * jt, jn - s.mu * jt))
        lower = np.concatenate((-gap / h, -gap / h))
        result = proxsuite.proxqp.dense.solve(
            H=mass,
            g=g,
            A=rows.jac,
            b=-rows.phi_t - rows.phi / h,
            C=cone,
            l=lower,
            u=np.full(len(lower), 1e20),
            eps_abs=1e-10,
        )
        if result.info.status != proxsuite.proxqp.QPSolverOutput.PROXQP_SOLVED:
            raise ValueError(f"the contact QP did not solve ({result.info.status})")
        v_new = np.array(result.x)
        z = -np.array(result.z)  # impulses of the cone rows (>= 0)
        k = len(gap)
        normal, tangential = z[:k] + z[k:], s.mu * (z[:k] - z[k:])
        q_new = self.bilateral.project(q + h * v_new, t + h, metric="mass", max_iter=20)
        return q_new, v_new, normal, tangential, -np.array(result.y)

    def modes(self, normal: np.ndarray, slip: np.ndarray) -> dict[str, str]:
        """Contact mode of each foot from its heel and toe normal forces [N] and tangential speeds [m/s]."""
        out = {}
        for i, side in enumerate(SIDES):
            loaded = normal[2 * i : 2 * i + 2] > LOAD_TOL
            sliding = np.any(loaded & (np.abs(slip[2 * i : 2 * i + 2]) > SLIP_TOL))
            if not loaded.any():
                out[side] = "air"
            elif sliding:
                out[side] = "sliding"
            elif loaded.all():
                out[side] = "flat"
            else:
                out[side] = POINTS[int(np.argmax(loaded))]
        return out

    # ---- a run
    def initial_state(self, swing_pitch: float | None = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """Both feet flat on the floor at theta0, the hip level; the velocity that keeps them there.

        At the touchdown angle (theta0 = pi/2) both ankles lie on the stance line, so both soles
        rest on the floor; the velocity keeps both feet still, the hip level and the cranks at
        omega (a least-squares solve of the consistent, redundant rows).
        """
        from pasibot_pin.model.closure import analytic_configurations

        robot = self.robot
        guess, _ = analytic_configurations(robot, [self.settings.theta0], swing_foot_pitch=swing_pitch)
        q = self.bilateral.project(guess[0], 0.0)  # loops closed to Newton's tolerance
        _, _, jn, jt = self.contact_rows(q)
        rows = self.bilateral.evaluate(q, None, 0.0)
        jac = np.vstack((rows.jac, jn, jt, np.eye(q.size)[2:3]))
        rhs = np.concatenate((-rows.phi_t, np.zeros(2 * len(jn) + 1)))
        v = np.linalg.lstsq(jac, rhs, rcond=None)[0]
        return q, v

    def run(self, duration: float, q0: np.ndarray | None = None, v0: np.ndarray | None = None) -> FloorResult:
        """Integrate for ``duration`` [s] (or until the hip passes the fall limit or a step fails)."""
        s = self.settings
        _check("duration", duration, 0.0, 1e4, low_open=True)
        q, v = self.initial_state() if q0 is None else (np.array(q0, float), np.array(v0, float))
        n = max(1, math.ceil(duration / s.dt - 1e-9))
        h = duration / n
        rec: dict[str, list] = {k: [] for k in ("t", "q", "v", "normal", "tangential", "motor")}
        modes: dict[str, list[str]] = {side: [] for side in SIDES}
        touchdowns: list[tuple[float, str, str]] = []
        steps: list[tuple[float, str, float, float]] = []
        landings: list[tuple[float, str, float]] = []
        along0 = self.contact_rows(q)[1]
        stand = {side: float(np.mean(along0[2 * i : 2 * i + 2])) for i, side in enumerate(SIDES)}
        advance = STEP_ADVANCE * self.robot.geometry.L
        loaded_before = np.zeros(2 * len(SIDES), dtype=bool)
        slid = np.zeros(len(SIDES))
        failure = ""
        t = 0.0
        for _ in range(n):
            try:
                q_new, v_new, normal, tangential, bilateral = self.step(t, q, v, h)
            except ValueError as err:
                cause = "a loop cannot close" if "loop closure" in str(err) else "the contact problem failed"
                failure = f"{cause} at t = {t:.3f} s ({err})"
                break
            t += h
            q, v = q_new, v_new
            gap, along, _, jt = self.contact_rows(q)
            slip = jt @ v
            mode = self.modes(normal / h, slip)
            loaded = normal / h > LOAD_TOL
            for k in np.nonzero(loaded & ~loaded_before)[0]:
                touchdowns.append((t, SIDES[k // 2], POINTS[k % 2]))
            for i, side in enumerate(SIDES):
                pair = slice(2 * i, 2 * i + 2)
                if loaded[pair].any() and not loaded_before[pair].any() and t > h:
                    x = float(np.mean(along[pair]))
                    landings.append((t, side, x))
                    if x > stand[side] + advance:
                        steps.append((t, side, x, x - stand[SIDES[1 - i]]))
                    stand[side] = x
                if np.sum(normal[pair]) / h > BEARING_SHARE * self.weight:
                    slid[i] += h * float(np.max(np.where(loaded[pair], np.abs(slip[pair]), 0.0)))
                pitch = math.atan2(gap[2 * i + 1] - gap[2 * i], along[2 * i + 1] - along[2 * i])
                if mode[side] in POINTS and abs(pitch) > ROLL_LIMIT:
                    failure = f"the {side} foot rolled over its {mode[side]} at t = {t:.3f} s"
                if slid[i] > SLIP_LIMIT:
                    failure = f"the {side} foot slipped {1e3 * slid[i]:.0f} mm by t = {t:.3f} s"
            loaded_before = loaded
            rec["t"].append(t)
            rec["q"].append(q)
            rec["v"].append(v)
            rec["normal"].append(normal / h)
            rec["tangential"].append(tangential / h)
            rec["motor"].append(bilateral[self._crank_rows] / h)
            for side in SIDES:
                modes[side].append(mode[side])
            if abs(q[2]) > s.fall_limit:
                failure = f"fell: |hip pitch| passed {math.degrees(s.fall_limit):.0f} deg at t = {t:.3f} s"
            if failure:
                break
        qs = np.array(rec["q"]).reshape(-1, self.robot.model.nq)
        return FloorResult(
            t=np.array(rec["t"]),
            q=qs,
            v=np.array(rec["v"]).reshape(qs.shape),
            hip_pitch=qs[:, 2].copy(),
            modes=modes,
            normal=np.array(rec["normal"]).reshape(-1, 4),
            tangential=np.array(rec["tangential"]).reshape(-1, 4),
            motor_torque=np.array(rec["motor"]).reshape(-1, 2),
            touchdowns=touchdowns,
            steps=steps,
            landings=landings,
            outcome=failure or f"walks {len(steps)} steps in {t:.3f} s",
            failed=bool(failure),
        )
