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

(:mod:`pasibot_pin.dynamics.floor.qp`: an exact KKT solve on the last step's active cone rows,
checked to be the QP's solution; proxsuite where it is not, or where the active rows are
redundant). Its multipliers are the contact impulses: a point's normal impulse is the sum
of its two cone rows' and the tangential one mu times their difference, so |F_t| <= mu F_n
holds by construction (the planar cone is exactly two half-planes). A point that reaches the
floor stops there in one step (an inelastic touchdown, found by the step rather than
scheduled); a point leaves the floor when its normal impulse is zero. Positions are then
projected back onto the loops (mass metric), so the loops drift by less than Newton's
tolerance. With the cranks driven the loops fix every leg coordinate, so a run solves the same
step on the free coordinates (the hip, a free ankle), the legs' shape known ahead in closed form
(:mod:`pasibot_pin.dynamics.floor.shape_track`, :meth:`FloorSimulator._track_step`). Each step reports
the contact mode of each foot: ``flat`` (heel and toe load),
``heel``, ``toe``, ``sliding`` or ``air`` (:func:`mode_runs` run-length encodes a sequence).
The cranks turn at omega from t = 0, or start smoothly over ``FloorSettings.crank_ramp``
(:func:`crank_advance`).

Units: SI, angles [rad], impulses [N.s]; forces are impulses over h [N].
"""

from __future__ import annotations

import functools
import math
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from pasibot_pin.constraints import ConstraintSystem, coordinate, coupling, frame_rows, symmetric_mass_matrix
from pasibot_pin.dynamics.floor.qp import ContactQP
from pasibot_pin.dynamics.floor.run import (
    LOAD_TOL,
    FloorResult,
    RunLog,
    StartState,
    foot_mode,
    point_sample,
)
from pasibot_pin.dynamics.floor.settings import FloorSettings, crank_advance, crank_advances, step_count
from pasibot_pin.dynamics.floor.shape_track import ShapeSplit, ShapeTrack
from pasibot_pin.dynamics.floor.tracked_step import FreeStepper, PointRows, check_speed
from pasibot_pin.dynamics.spring_energy import ankle_indices, spring_forces
from pasibot_pin.dynamics.verdict import GaitCriteria, GaitJudge, GaitSample, JudgeFactory
from pasibot_pin.errors import (
    NoRestError,
    ParameterError,
    SimulationError,
)
from pasibot_pin.model.closure import analytic_configurations
from pasibot_pin.model.coordinates import HIP_PITCH, HIP_X, HIP_Z, SIDES
from pasibot_pin.model.spatial import Footprint
from pasibot_pin.model.variants import MOTOR_LAYOUTS

MAX_STEPS = 20_000_000
"""Most time steps one run takes (a bound on its time and memory)."""
STARTS = ("consistent", "flat")
SETTLE_RAMP = 1.0
"""The settled start engages the ankle springs over this long (a smooth ramp from zero) [s]."""
SETTLE_DT = 2e-3
"""Time step of the settling [s] (the springs are implicit: any step is stable)."""
SETTLE_DAMPING = 15.0
"""Artificial velocity damping of the settling only, v <- v (1 - SETTLE_DAMPING h) [1/s]."""
SETTLE_MARGIN = 0.9
"""The settling uses this share of mu, so the settled state holds its points strictly inside the cones [-]."""
SETTLE_MAX = 6.0
"""The settling gives up (no consistent start) after this long [s]."""
REST_SPEED = 1e-7
"""A state is at rest when no velocity component exceeds this [m/s, rad/s] (the QP and the
projection leave about 5e-9)."""


class _StepTerms(NamedTuple):
    """The QP terms of one floor step (:meth:`FloorSimulator._terms`)."""

    mass: np.ndarray
    hessian: np.ndarray
    g: np.ndarray
    cone: np.ndarray
    lower: np.ndarray
    mu: float


def _impulses(z: np.ndarray, mu: float) -> tuple[np.ndarray, np.ndarray]:
    """Normal and tangential impulses (points,) [N.s] of the cone multipliers z (2 points,).

    A point's rows k (n + mu t) and k + points (n - mu t) give n = z_k + z_(k+points) and
    t = mu (z_k - z_(k+points)).
    """
    k = len(z) // 2
    return z[:k] + z[k:], mu * (z[:k] - z[k:])


class FloorSimulator:
    """The ``spring`` biped on a floor (see the module docstring).

    Args:
        robot: ``pp.load("spring", 2)`` (or a copy with other masses).
        settings: :class:`FloorSettings`.
        footprint: the soles (default the centred plate); its :attr:`~pasibot_pin.model.spatial.Footprint.points`
            are each foot's contact points, heel to toe (heel and toe by default).

    """

    def __init__(self, robot, settings: FloorSettings, footprint: Footprint | None = None):
        if robot.legs != 2 or not robot.floating:
            raise ParameterError("the floor simulator needs the two-legged robot with its floating hip")
        self.robot, self.settings = robot, settings
        self.footprint = Footprint.centred(robot.geometry.L) if footprint is None else footprint
        names = self.sole_points = self.footprint.points
        model = robot.model
        self.ankles = ankle_indices(robot) if robot.spec.free_ankle else {}
        layout = MOTOR_LAYOUTS[settings.motors]
        phase = {f"{side}_j0_crank": k * math.pi for k, side in enumerate(SIDES)}
        scalars = [
            coordinate(name, robot.idx_v(name), settings.theta0 + phase[name], settings.omega) for name in layout.motors
        ]
        scalars += [coupling(f"{a}-{b}", robot.idx_v(a), robot.idx_v(b), offset) for a, b, offset in layout.couplings]
        self._motor_index = [robot.idx_v(name) for name in layout.motors]
        if settings.hip == "level":
            scalars.append(coordinate("hip_pitch", HIP_PITCH, 0.0, 0.0))
        self._target_offsets = np.array([row.offset for row in scalars])
        self._target_rates = np.array([row.rate for row in scalars])
        self.bilateral = ConstraintSystem(model, robot.data, robot.loop_constraints, scalars, robot.geometry.L)
        frames = [robot.frame_id(f"{side}_{point}") for side in SIDES for point in names]
        self.points = frame_rows(model, frames, range(len(frames)))
        self._crank_rows = [self.bilateral.labels.index(name) for name in layout.motors]
        self._motor_targets = [row - self.bilateral.n_constraint_rows for row in self._crank_rows]
        self._split: ShapeSplit | None | bool = False  # False: not looked for yet (:meth:`_shape_split`)
        gravity = float(np.linalg.norm(model.gravity.linear))
        self.weight = gravity * sum(model.inertias[j].mass for j in range(1, model.njoints))
        self._zero_v = np.zeros(model.nv)
        # cone rows k (jn + mu jt) and k + points (jn - mu jt) of each point k; a flat foot whose heel and
        # toe both stick has four dependent rows
        n_points, n = len(frames), len(names)
        feet = [[k + j for j in range(n)] + [k + j + n_points for j in range(n)] for k in range(0, n_points, n)]
        self._feet = feet
        self._qp = ContactQP(model, feet)  # remembers the last step's active cone rows
        self._held_qp: ContactQP | None = None  # the settling's own QP (its active set is not the run's)
        self._held_targets = self.targets(0.0) if settings.crank_ramp > 0 else self.bilateral.targets(0.0)
        self._rows_at: tuple | None = None  # (q bytes, the projection's rows there, their targets)
        self.ground = settings.ground  # its treads and frame: the general step, the tracked step and the judge
        self.turn = self.ground.turn  # the ground's frame, e^(-i slope)
        self._contact_rows = PointRows(self.points, self.ground)  # the contact rows at the last configuration asked

    @property
    def crank_rows(self) -> list[int]:
        """The bilateral rows that are motors (their multipliers are the motors' impulses)."""
        return list(self._crank_rows)

    @property
    def motor_index(self) -> list[int]:
        """The motors' velocity indices."""
        return list(self._motor_index)

    def springs(self, q: np.ndarray, h: float, scale: float = 1.0) -> tuple[np.ndarray, float]:
        """The ankle springs' torque at ``q`` (nv,) [N.m] and their implicit term on H (see :meth:`step`)."""
        return self._springs(q, h, scale)

    def targets(self, t: float) -> np.ndarray:
        """The scalar rows' targets at ``t`` [rad]: the cranks at theta0 + omega advance (:func:`crank_advance`)."""
        return self._target_offsets + self._target_rates * crank_advance(t, self.settings.crank_ramp)[0]

    def targets_many(self, times: np.ndarray) -> np.ndarray:
        """:meth:`targets` at each of ``times`` (N,) [s]: (N, scalar rows) [rad]."""
        advance = crank_advances(times, self.settings.crank_ramp)
        return self._target_offsets + self._target_rates * advance[:, None]

    def shape_track(self, h: float) -> ShapeTrack | None:
        """The legs' shape along the crank schedule, for steps of ``h`` [s] (``None``: the rows have no split).

        Without the planar contact rows: the 3-D floor (:mod:`~pasibot_pin.dynamics.floor.shape_track3d`) reads
        the shapes, their velocities and tangents, and computes its own contacts.
        """
        split = self._shape_split()
        return None if split is None else ShapeTrack(self.robot, split, self.targets_many, h)

    def _shape_split(self) -> ShapeSplit | None:
        """The free coordinates and the shape of the bilateral rows (found once; ``None``: no such split)."""
        if self._split is False:
            q, _ = self.initial_state()
            self._split = ShapeSplit.of(self.robot, self.bilateral, q, self.targets(0.0), self._target_rates)
        return self._split if isinstance(self._split, ShapeSplit) else None

    # ---- one step
    def contact_rows(self, q: np.ndarray, flat: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Gaps (4,) [m], tangential positions (4,) [m], J_n (4, nv) and J_t (4, nv) of heel and toe points.

        Across and along the ground, each gap above the tread under the point
        (:meth:`~pasibot_pin.dynamics.floor.ground.Ground.planar_gaps`); ``flat``: the world's x and z
        read as along and across the ground, whatever its slope (the start before it is turned onto it).
        """
        rows, jac, _, _ = self.points.evaluate(q)
        if self.turn != 1.0 and not flat:  # along and across a sloped ground
            rows, jac = rows * self.turn, jac * self.turn
        return self.ground.planar_gaps(rows), rows.real, jac.imag, jac.real

    def _contact_at(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`contact_rows` from the cached rows (:class:`~pasibot_pin.dynamics.floor.tracked_step.PointRows`).

        The arrays are views of the cache: read them, never write into them.
        """
        rows, jac = self._contact_rows.at(q)
        return self._contact_rows.gaps(q), rows.real, jac.imag, jac.real

    def step(
        self,
        t: float,
        q: np.ndarray,
        v: np.ndarray,
        h: float,
        spring_scale: float = 1.0,
        mu: float | None = None,
        held: bool = False,
    ):
        """One step: (q+, v+, normal and tangential impulses (4,) [N.s], the motors' impulses [N.m.s]).

        The ankle springs and dampers are linearly implicit: their torque at the end of the step,
        tau(q + h v+, v+) = tau(q, 0) - (K h + c) v+, so the stiff foot-on-spring mode is stable at
        any step. ``spring_scale`` scales the springs (the settling ramps it), ``mu`` overrides the
        friction coefficient; ``held`` holds the cranks at theta0 (the targets of t = 0, at rest: the
        settling start), with a QP of its own. The QP on every coordinate, then Newton's projection (the general
        path; :meth:`run` takes :meth:`_track_step` where the shape is known ahead).

        Raises:
            ValueError: the QP failed, a loop cannot close, or the state diverged (non-finite or
                faster than :data:`SPEED_LIMIT`).

        """
        terms = self._terms(q, v, h, spring_scale, mu)
        targets: np.ndarray | None = self._held_targets
        if not held:
            targets = self.targets(t + h) if self.settings.crank_ramp > 0 else None  # None: offset + rate t
        phi, jac = self._bilateral_rows(q, t + h, targets)
        # Phi(q + h v, t + h) = 0 to first order (Phi at t + h holds the rate)
        qp = self._qp
        if held:
            if self._held_qp is None:
                self._held_qp = ContactQP(self.robot.model, self._feet)
            qp = self._held_qp
        v_new, bilateral, z = qp.solve(terms.hessian, terms.g, jac, -phi / h, terms.cone, terms.lower)
        check_speed(v_new)
        normal, tangential = _impulses(z, terms.mu)
        q_new, after, _ = self.bilateral.project_rows(q + h * v_new, t + h, targets, metric="mass", max_iter=20)
        self._rows_at = (q_new.tobytes(), after, self._goal(t + h, targets))  # the rows at q_new, t + h
        return q_new, v_new, normal, tangential, bilateral[self._crank_rows]

    def _terms(self, q: np.ndarray, v: np.ndarray, h: float, spring_scale: float = 1.0, mu: float | None = None):
        """The step's QP terms at (q, v): H, g, the cone rows and their bounds (:class:`_StepTerms`)."""
        model, data, s = self.robot.model, self.robot.data, self.settings
        mu = s.mu if mu is None else mu
        gap, _, jn, jt = self._contact_at(q)
        mass = symmetric_mass_matrix(model, data, q)
        bias = pin.nonLinearEffects(model, data, q, v)
        hessian = mass
        tau, stiffness = self._springs(q, h, spring_scale)
        if stiffness:
            hessian = mass.copy()
            for i in self.ankles.values():
                hessian[i, i] += stiffness
        g = -(mass @ v + h * (tau - bias))
        cone = np.concatenate((jn + mu * jt, jn - mu * jt))
        lower = -gap / h
        return _StepTerms(mass, hessian, g, cone, np.concatenate((lower, lower)), mu)

    def _springs(self, q: np.ndarray, h: float, scale: float = 1.0) -> tuple[np.ndarray, float]:
        """The ankle springs' torque at ``q`` (nv,) [N.m] and their implicit term on each ankle's diagonal of H.

        tau(q + h v+, v+) = tau(q, 0) - (K h + c) v+ puts h (h K + c) [kg.m^2] on H. No springs (or
        ``scale`` 0): zero torque and 0.
        """
        spring = self.settings.spring
        if spring is None or scale <= 0:
            return self._zero_v, 0.0
        spring = spring if scale == 1.0 else spring.scaled(scale)
        tau = spring_forces(self.robot, spring, q, self._zero_v, self.ankles)
        return tau, h * (h * spring.stiffness + spring.damping)

    def _goal(self, t: float, targets: np.ndarray | None) -> np.ndarray:
        """The scalar rows' targets at ``t`` [rad] (``targets``, or offset + rate t)."""
        return self.bilateral.targets(t) if targets is None else np.asarray(targets, dtype=float)

    def _bilateral_rows(self, q: np.ndarray, t: float, targets: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
        """Phi(q, t) and J(q) of the bilateral rows.

        When the last step's projection ended at ``q``, its rows serve: J is the same and only the
        scalar rows' targets move (Phi there is below Newton's tolerance, so no angle wraps); the
        two differ from a new evaluation by round-off (1e-15 rad).
        """
        cached = self._rows_at
        if cached is not None and cached[0] == np.asarray(q, dtype=float).tobytes():
            _, rows, goal = cached
            phi = rows.phi.copy()
            phi[self.bilateral.n_constraint_rows :] += goal - self._goal(t, targets)
            return phi, rows.jac
        rows = self.bilateral.evaluate(q, None, t, targets)
        return rows.phi, rows.jac

    def modes(self, normal: np.ndarray, slip: np.ndarray) -> dict[str, str]:
        """Contact mode of each foot from its heel and toe normal forces [N] and tangential speeds [m/s]."""
        loaded = [float(f) > LOAD_TOL for f in normal]
        slips = [float(x) for x in slip]
        return {side: foot_mode(loaded, slips, i, self.sole_points) for i, side in enumerate(SIDES)}

    # ---- the start
    def initial_state(self, swing_pitch: float | None = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """The geometric double support: both feet flat on the floor at theta0, the hip level.

        The hip's height puts the lowest sole point on the floor and none below it: a foot the
        linkage tilts (the rigid variant's) touches at its lowest point.

        At the touchdown angle (theta0 = pi/2) both ankles lie on the stance line, so both soles
        rest on the floor; the velocity keeps both feet still, the hip level and the cranks at
        omega (a least-squares solve of the consistent, redundant rows). With preloaded ankle
        springs this state is *not* one the robot can hold (see :meth:`start_state`).
        """
        robot = self.robot
        guess, _ = analytic_configurations(robot, [self.settings.theta0], swing_foot_pitch=swing_pitch)
        q = self.bilateral.project(guess[0], 0.0)  # loops closed to Newton's tolerance
        # the lowest sole point on the floor, none below it: a foot the linkage tilts (the rigid
        # variant's, square to its shank) touches at one point instead of sinking into the floor
        # (a point past a step edge, on the tread it is over)
        gap, _, jn, jt = self.contact_rows(q, flat=True)  # the Jacobians do not depend on the hip's height
        q[HIP_Z] -= float(np.min(gap))
        rows = self.bilateral.evaluate(q, None, 0.0)
        jac = np.vstack((rows.jac, jn, jt, np.eye(q.size)[2:3]))
        rate = crank_advance(0.0, self.settings.crank_ramp)[1]  # 0 with a ramp: the cranks start at rest
        rhs = np.concatenate((-rate * rows.phi_t, np.zeros(2 * len(jn) + 1)))
        v = np.linalg.lstsq(jac, rhs, rcond=None)[0]
        return self._on_slope(q, v)

    def _on_slope(self, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """A state on the flat floor turned rigidly about the origin onto the sloped ground (as it is when flat)."""
        if self.turn == 1.0:
            return q, v
        up = self.turn.conjugate()  # e^(i slope)
        hip, rate = complex(q[HIP_X], q[HIP_Z]) * up, complex(v[HIP_X], v[HIP_Z]) * up
        q, v = q.copy(), v.copy()
        q[HIP_X], q[HIP_Z], q[HIP_PITCH] = hip.real, hip.imag, q[HIP_PITCH] + self.settings.slope
        v[HIP_X], v[HIP_Z] = rate.real, rate.imag
        return q, v

    def hip_view(self, q: np.ndarray) -> tuple[float, float]:
        """The judge's hip: its position along the ground [m] and its pitch from the ground's normal [rad]."""
        if self.turn == 1.0:
            return q.item(HIP_X), q.item(HIP_PITCH)
        return (complex(q.item(HIP_X), q.item(HIP_Z)) * self.turn).real, q.item(HIP_PITCH) - self.settings.slope

    def rest_forces(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
        """Contact forces holding ``q`` at rest, the cranks held.

        Returns:
            (normal, tangential, speed): the forces (4,) [N] of one step from rest, and the largest
            velocity that step reaches [m/s, rad/s] (0 when ``q`` is an equilibrium).

        """
        h = self.settings.dt
        _, v, normal, tangential, _ = self.step(0.0, q, np.zeros(self.robot.model.nv), h, held=True)
        self._rows_at = None  # the run's rows are its own
        return normal / h, tangential / h, float(np.max(np.abs(v)))

    def start_state(self) -> StartState:
        """A consistent start at theta0: both feet on the floor, at rest, every contact force in its cone.

        The geometric double support (:meth:`initial_state`, both soles flat, hip level) is used
        when the floor can hold it at rest: one step from rest stays at rest (no velocity above
        :data:`REST_SPEED`). That is so without ankle springs. A preloaded spring (the fitted
        one: about 69 N.m at the front ankle) needs a centre of pressure far outside the sole, so
        the robot is *settled*: the cranks held at theta0, the springs engaged over
        :data:`SETTLE_RAMP` from zero, velocities damped (:data:`SETTLE_DAMPING`, settling only)
        and friction :data:`SETTLE_MARGIN` x mu, until it is at rest (:data:`REST_SPEED`). The
        robot then stands where the springs and gravity balance, each foot on its sole, heel or
        toe, its points strictly inside the cones of the real mu, the loops closed by Newton.

        Raises:
            ValueError: the robot finds no rest within :data:`SETTLE_MAX` (it falls or keeps sliding).

        """
        s = self.settings
        q, _ = self.initial_state()
        normal, tangential, speed = self.rest_forces(q)
        if speed <= REST_SPEED:
            return self._start(q, "flat", 0.0, normal, tangential)
        v = np.zeros(self.robot.model.nv)
        h, t = SETTLE_DT, 0.0
        while t < SETTLE_MAX:
            ramp = min(1.0, t / SETTLE_RAMP)
            scale = ramp * ramp * (3 - 2 * ramp)
            q, v, *_ = self.step(0.0, q, v * (1.0 - SETTLE_DAMPING * h), h, scale, s.mu * SETTLE_MARGIN, held=True)
            t += h
            if abs(q[HIP_PITCH]) > s.fall_limit:
                raise NoRestError(
                    f"no consistent start: settling at theta0 the robot falls (hip pitch past the limit at {t:.2f} s)"
                )
            if t >= SETTLE_RAMP and np.max(np.abs(v)) < REST_SPEED:
                if h == s.dt:  # at rest with the run's own step: an equilibrium of the run's map
                    normal, tangential, _ = self.rest_forces(q)
                    return self._start(q, "settled", t, normal, tangential)
                h = s.dt
        raise NoRestError(f"no consistent start: the robot does not come to rest within {SETTLE_MAX:g} s of settling")

    def _start(self, q, kind, settle_time, normal, tangential) -> StartState:
        loops = self.bilateral.evaluate(q).phi[: self.bilateral.n_constraint_rows]
        gap, along, *_ = self.contact_rows(q)
        return StartState(
            q=q,
            v=np.zeros(self.robot.model.nv),
            kind=kind,
            settle_time=settle_time,
            normal=normal,
            tangential=tangential,
            modes=self.modes(normal, np.zeros(len(normal))),
            loop_residual=float(np.max(np.abs(loops))),
            gaps=gap,
            along=along,
        )

    def run(
        self,
        duration: float,
        q0: np.ndarray | None = None,
        v0: np.ndarray | None = None,
        start: str = "consistent",
        criteria: GaitCriteria | None = None,
        stop_on_verdict: bool = False,
        judge: JudgeFactory | None = None,
    ) -> FloorResult:
        """Integrate for ``duration`` [s], judging the walk (:mod:`pasibot_pin.dynamics.verdict`).

        Args:
            duration: simulated time [s] (the longest run).
            q0: start configuration (with ``v0``); default by ``start``.
            v0: start velocity.
            start: ``consistent`` (:meth:`start_state`: at rest, the contact forces in their cones;
                the cranks start turning at t = 0; where the robot cannot stand at theta0 at all,
                the flat start, with the reason in ``start_note``) or ``flat`` (:meth:`initial_state`,
                the geometric double support, whatever the springs' preload).
            criteria: what counts as walking (default :class:`GaitCriteria`).
            stop_on_verdict: stop as soon as the walk's outcome is decided (else at ``duration``,
                or when the hip passes the fall limit, a foot rolls over or slips far, or a step fails).
            judge: the observer of the walk, built from the run's first sample
                (:data:`~pasibot_pin.dynamics.verdict.JudgeFactory`; default: a
                :class:`~pasibot_pin.dynamics.verdict.GaitJudge` by ``criteria``). It sees every sample
                and decides the verdict; the engine does not know what it checks.

        Returns:
            :class:`FloorResult`, with the :class:`~pasibot_pin.dynamics.verdict.Verdict` when the
            cranks turn (omega > 0).

        """
        s = self.settings
        n = step_count(duration, s.dt, MAX_STEPS)
        if start not in STARTS:
            raise ParameterError(f"parameter 'start' must be one of {', '.join(STARTS)}, got {start!r}")
        if judge is not None and criteria is not None:
            raise ParameterError("give the run a 'judge' or 'criteria', not both (the judge has its own)")
        criteria = GaitCriteria() if criteria is None else criteria
        q, v, begin, start_kind, note = self._begin(q0, v0, start)
        h = duration / n
        log = RunLog(self.weight, s.fall_limit, self.robot.model.nq, len(self._crank_rows), self.sole_points)
        observer = None
        if s.omega > 0:
            first = self._sample(0.0, q, v)
            observer = judge(first) if judge is not None else self.judge_of(criteria)(first)
        track, stepper = self._tracker(h)
        t = 0.0
        # the loop's constants, looked up once
        names, motor_index, has_step = self.sole_points, self._motor_index, self.ground.has_step
        hip_view, update = self.hip_view, None if observer is None else observer.update
        for _ in range(n):
            try:
                q, v, normal, tangential, motor, points = self._advance(t, q, v, h, track, stepper)
            except SimulationError as err:
                log.stop_on(err, t)
                if observer is not None:
                    observer.diverged(t, str(err))
                break
            t += h
            forces = ([x / h for x in normal], [x / h for x in tangential], [x / h for x in motor])
            power = tuple([tau * v.item(i) for tau, i in zip(forces[2], motor_index)])
            sample, loaded = point_sample(t, hip_view(q), points, forces[0], power, names)
            log.record(t, q, v, sample, forces, loaded, points[2])
            if has_step and self._tripped(t, points[0], log, observer):
                break
            if update is not None and update(sample) and stop_on_verdict:
                break
            if not stop_on_verdict and log.stopped(t, q):
                break
        verdict = None if observer is None else observer.verdict(t)
        return log.result(verdict, begin, start_kind, note)

    def _tripped(self, t: float, gaps: list[float], log: RunLog, observer: GaitJudge | None) -> bool:
        """True when a contact point came through the step's riser at ``t`` [s] (the run stops: ``tripped``)."""
        k = self.ground.riser_hit(gaps)
        if k is None:
            return False
        side, point = SIDES[k // len(self.sole_points)], self.sole_points[k % len(self.sole_points)]
        detail = f"the {side} {point} hit the step's riser, {1e3 * -gaps[k]:.1f} mm below the tread"
        log.stop_reason = f"{detail} at t = {t:.3f} s"
        if observer is not None:
            observer.tripped(t, detail)
        return True

    def judge_of(self, criteria: GaitCriteria | None = None) -> JudgeFactory:
        """The default judge of this robot's walk: a :class:`GaitJudge` by ``criteria`` (default ones)."""
        return functools.partial(
            GaitJudge, self.settings.omega, self.robot.geometry.L, self.weight, criteria or GaitCriteria()
        )

    def _begin(self, q0, v0, start):
        """(q, v, start state or None, start kind, note) of a run (see :meth:`run`)."""
        if (q0 is None) != (v0 is None):
            raise ParameterError("give both 'q0' and 'v0' or neither")
        if q0 is not None:
            q, v = np.array(q0, dtype=float), np.array(v0, dtype=float)
            nq = self.robot.model.nq
            for name, x in (("q0", q), ("v0", v)):
                if x.shape != (nq,) or not np.all(np.isfinite(x)):
                    raise ParameterError(f"parameter {name!r} must be {nq} finite numbers")
            return q, v, None, "given", ""
        if start == "flat":
            return (*self.initial_state(), None, "flat", "")
        try:
            begin = self.start_state()
        except SimulationError as err:  # the robot cannot stand at theta0: start from the flat double support
            return (*self.initial_state(), None, "flat", str(err))
        return begin.q, begin.v, begin, begin.kind, ""

    def _tracker(self, h: float) -> tuple[ShapeTrack | None, FreeStepper | None]:
        """A run's shape track and its tracked step (``None``, ``None`` where the rows have no split)."""
        split = self._shape_split()
        if split is None:
            return None, None
        track = ShapeTrack(self.robot, split, self.targets_many, h, self.points)
        ankles = list(self.ankles.values())
        stepper = FreeStepper(
            self.robot,
            split,
            self._contact_rows,
            self._qp,
            self._springs,
            ankles,
            self._motor_targets,
            self.settings.mu,
            track.form,
        )
        return track, stepper

    def _advance(self, t: float, q: np.ndarray, v: np.ndarray, h: float, track, stepper):
        """One step of a run: the tracked one where the track has the shape, else :meth:`step`.

        Returns:
            (q, v, normal, tangential, motor impulses as lists, the points' (heights, x, tangential
            speeds) after the step as lists).

        """
        if track is not None and (shape := track.step(t, q)) is not None:
            out = stepper.step(q, v, h, shape)
            if out is not None:
                return out
        q, v, normal, tangential, motor = self.step(t, q, v, h)
        return q, v, normal.tolist(), tangential.tolist(), motor.tolist(), self._contact_rows.lists(q, v)

    def _sample(self, t: float, q: np.ndarray, v: np.ndarray) -> GaitSample:
        """The :class:`GaitSample` at ``t`` without forces (a run's start: a point on the floor counts as loaded)."""
        points = self._contact_rows.lists(q, v)
        return point_sample(t, self.hip_view(q), points, None, (0.0, 0.0), self.sole_points)[0]
