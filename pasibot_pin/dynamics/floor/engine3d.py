"""The biped on a floor in three dimensions: a free hip that can roll, yaw and drift sideways.

The planar floor (:mod:`pasibot_pin.dynamics.floor`) holds the hip in the sagittal plane. Here
the hip is Pinocchio's free flyer (:func:`~pasibot_pin.model.spatial.free_flyer_model`), the legs
stay in their planes at y = -/+ ``hip_half_width``, and each sole touches the ground at its
corners (:class:`~pasibot_pin.model.spatial.Footprint`): unilateral points with Coulomb friction
in 3-D (a four-sided pyramid, |F_t1| + |F_t2| <= mu F_n, inscribed in the cone).

One step is the planar floor's scheme (Moreau, Anitescu): the velocity after the step solves

    min_u  1/2 (u - u-)^T M (u - u-) - h (tau - b)^T u
    s.t.   J_b u = -Phi_t           (loops, cranks: the planar rows of each leg)
           (J_n +- mu J_tk) u >= -gap / h     (each corner, each tangent k of the ground)

then the positions advance by h u and are projected back onto the loops (mass metric). The
velocity u is the hip's linear and angular velocity *in world axes* (then the legs' rates): with
the hip's y, roll and yaw held, u is the planar velocity and the step the planar step, term for
term, so :class:`Floor3D` with ``hold_lateral=True`` and a footprint of no width reproduces the
planar walk (tests/test_floor3d.py). Free, the QP is solved exactly on the hip's freedoms
(:mod:`.ldp`), the legs' shape known ahead (:mod:`.shape_track3d`), and a settled gait repeats (:mod:`.repeat3d`).
The planar judge hears each foot's heel and toe (the corners summed), plus ``tipped`` and ``collided``.

Units: SI, angles [rad], impulses [N.s]; forces are impulses over h [N].
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pinocchio as pin

from pasibot_pin.constraints import symmetric_mass_matrix
from pasibot_pin.constraints.solves import kkt_solve
from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.ground import Ground
from pasibot_pin.dynamics.floor.ldp import floating_qp, ldp_free_qp, solve_spd
from pasibot_pin.dynamics.floor.qp import ContactQP, proxsuite_free_qp, reduced_qp
from pasibot_pin.dynamics.floor.repeat3d import PeriodStep, Replayed, SettledGait, period_grid
from pasibot_pin.dynamics.floor.result3d import CLEARANCE_EVERY, Floor3DResult, floor3d_result, group_minima, group_sums
from pasibot_pin.dynamics.floor.run import foot_samples, point_sample
from pasibot_pin.dynamics.floor.settings import step_count
from pasibot_pin.dynamics.floor.shape_track3d import SpatialShape, SpatialTrack
from pasibot_pin.dynamics.floor.tracked_step import SPEED_LIMIT, check_speed
from pasibot_pin.dynamics.verdict import GaitCriteria, GaitSample, JudgeFactory, Verdict
from pasibot_pin.errors import (
    ClosureError,
    ContactSolveError,
    ParameterError,
    SimulationError,
    SingularPoseError,
)
from pasibot_pin.model.closure import angular_coordinates
from pasibot_pin.model.spatial import (
    NQ_ROOT,
    NV_ROOT,
    PLANAR_NQ_ROOT,
    CornerJacobians,
    Footprint,
    LateralMass,
    check_interference,
    corner_frames,
    free_flyer_model,
    leg_clearance,
    planar_to_spatial,
    planar_velocity_to_spatial,
    roll_pitch_yaw,
    sole_geometry,
)

STEP_LIMIT = 0.5
"""Largest correction of one Newton iteration of the projection [m, rad]."""
MAX_STEPS = 2_000_000
"""Most time steps one 3-D run takes."""
TOUCH = 1e-9
"""Soles that touch (plates meeting edge to edge at the midline) are clear; deeper than this they intersect [m]."""
HELD = (1, 3, 5)
"""The world-aligned velocity entries the planar walk holds: y, roll and yaw."""
LATERAL_TOLERANCE = 1e-10
"""The lateral mass's row is closed to this [m]."""


class Floor3D:
    """The two-legged robot on a 3-D ground (see the module docstring).

    Args:
        planar: the planar floor simulator of the same robot and settings (its loops, cranks,
            springs, start and targets are this one's).
        footprint: the soles' lateral shape.
        ground: the ground (default: the flat floor with the settings' mu).
        hold_lateral: hold the hip's y, roll and yaw (the planar walk, in 3-D).
        lateral: a share of the body moved sideways by the right crank
            (:class:`~pasibot_pin.model.spatial.LateralMass`): one more bilateral row,
            ``y - amplitude sin(theta + phase) = 0``, on the model's slider.

    Attributes:
        tracked: take the tracked step (:mod:`~pasibot_pin.dynamics.floor.shape_track3d`: the legs' shape known
            ahead, the hip and a free ankle left to the QP) where the track has the shape; ``False``:
            the general step on every coordinate (the check of the tracked one).
        repeats: repeat a settled gait's steps (:mod:`~pasibot_pin.dynamics.floor.repeat3d`); ``False``: simulate all.

    """

    def __init__(
        self,
        planar: FloorSimulator,
        footprint: Footprint,
        ground: Ground | None = None,
        hold_lateral: bool = False,
        lateral: LateralMass | None = None,
    ) -> None:
        if planar.settings.hip != "free":
            raise ParameterError("the 3-D floor needs settings.hip = 'free' (a level hip is a planar constraint)")
        self.planar, self.settings = planar, planar.settings
        self.footprint = footprint
        self.ground = planar.settings.ground if ground is None else ground
        if self.ground.has_step:
            raise ParameterError(
                "parameter 'step_height': a step edge is the planar floor's so far (walk without --3d)"
            )
        self._along = self.ground.tangents[0]
        self.hold = hold_lateral
        robot = planar.robot
        self.lateral = lateral if lateral is not None and lateral.mass > 0.0 else None
        self.model = free_flyer_model(robot.model, 0.0 if self.lateral is None else self.lateral.mass)
        self.nq_robot = robot.model.nq + NQ_ROOT - PLANAR_NQ_ROOT  # the slider's coordinate comes after
        self.nv_robot = robot.model.nv + NV_ROOT - PLANAR_NQ_ROOT
        crank = self.model.joints[self.model.getJointId(robot.actuated_joints[0])]
        self._crank_q, self._crank_v = crank.idx_q, crank.idx_v  # the right crank, which moves the lateral mass
        self.corners = corner_frames(self.model, self.extend(planar_to_spatial(robot.q0)), footprint)
        frame, self._normal = self.ground.frame(), self.ground.normal
        axes = np.abs(frame).argmax(axis=1)
        if (frame[range(3), axes] == 1.0).all() and (np.abs(frame).sum(axis=1) == 1.0).all():
            self._frame = None  # the ground's frame is the world's axes in another order (flat): rows picked
            self._corner_rows = CornerJacobians(self.model, self.corners, tuple(int(a) for a in axes))
        else:
            self._frame, self._corner_rows = frame, CornerJacobians(self.model, self.corners)
        self.data = self.model.createData()
        self._kkt_data = self.model.createData()
        self._contact_cache: tuple[bytes, tuple[np.ndarray, np.ndarray, np.ndarray]] | None = None
        self._rotation_key, self._rotation_value = b"", np.eye(3)
        self.per_point = len(footprint.contact_offsets)  # corners at each of heel and toe
        n = len(self.corners)
        self.n_corners = n
        if hold_lateral:
            # cone rows k (n + mu t) and k + n (n - mu t): a foot's four rows of heel and toe, as the planar floor's
            feet = [[k, k + 1, k + n, k + 1 + n] for k in range(0, n, 2)] if self.per_point == 1 else []
            self._qp: ContactQP | None = ContactQP(self.model, feet)
        else:
            self._qp = None
        self._geometry, self._geometry_data = sole_geometry(
            self.model, self.extend(planar_to_spatial(robot.q0)), footprint
        )
        self._shift = NV_ROOT - PLANAR_NQ_ROOT
        self._crank_rows = planar.crank_rows
        self._motor_index = [i + self._shift for i in planar.motor_index]
        targets = [row - planar.bilateral.n_constraint_rows for row in planar.crank_rows]
        # the motors' rows of D^T (C-ordered: as D's columns picked out); the first ones: a view, not a copy
        self._motor_targets = slice(0, len(targets)) if targets == list(range(len(targets))) else np.array(targets)
        self.tracked = True
        self.repeats = True
        self.fallback = 0

    # ---- coordinates
    def spatial_state(self, q2: np.ndarray, v2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """A planar state as a 3-D one: (q, u), u in world-aligned root coordinates (the slider on its crank)."""
        q, u = planar_to_spatial(q2), planar_velocity_to_spatial(v2)
        return self.extend(q), self.extend_velocity(q, u)

    def extend(self, q: np.ndarray) -> np.ndarray:
        """The robot's configuration with the lateral mass where its crank puts it (unchanged without one)."""
        if self.lateral is None or len(q) > self.nq_robot:
            return q
        return np.append(q, self.lateral.position(float(q[self._crank_q]))[0])

    def extend_velocity(self, q: np.ndarray, u: np.ndarray) -> np.ndarray:
        """The robot's velocity with the lateral mass's rate from its crank's (unchanged without one)."""
        if self.lateral is None or len(u) > self.nv_robot:
            return u
        return np.append(u, self.lateral.position(float(q[self._crank_q]))[1] * u[self._crank_v])

    def planar_view(self, q: np.ndarray) -> np.ndarray:
        """The planar configuration of the hip's x, z, pitch and the legs (the loops' rows read only the legs)."""
        roll, pitch, yaw = roll_pitch_yaw(q)
        return np.concatenate(([q[0], q[2], pitch], q[NQ_ROOT : self.nq_robot]))

    def _rotation(self, q: np.ndarray) -> np.ndarray:
        """The root's rotation matrix (kept for the quaternion asked last: read it, never write into it)."""
        key = q[3:7].tobytes()
        if key != self._rotation_key:
            self._rotation_key, self._rotation_value = key, pin.Quaternion(q[3:7]).normalized().toRotationMatrix()
        return self._rotation_value

    def _attitude(self, q: np.ndarray) -> tuple[float, float, float]:
        """:func:`~pasibot_pin.model.spatial.roll_pitch_yaw` of ``q`` from :meth:`_rotation` (the same arithmetic)."""
        roll, pitch, yaw = pin.rpy.matrixToRpy(self._rotation(q))
        return float(roll), float(-pitch), float(yaw)

    def _advance(self, q: np.ndarray, du: np.ndarray, legs: np.ndarray | None = None) -> np.ndarray:
        """Q moved by du: the hip by du's world-axes translation and rotation, the legs by addition (or at ``legs``).

        With ``legs`` given, only du's first six (the hip's) are read.
        """
        rotation = pin.exp3(du[3:6]).dot(self._rotation(q))
        rest = q[NQ_ROOT:] + du[NV_ROOT:] if legs is None else legs
        return np.concatenate((q[:3] + du[:3], pin.Quaternion(rotation).coeffs(), rest))

    def _transform(self, q: np.ndarray) -> np.ndarray:
        """T (nv, nv) with v = T u: Pinocchio's local root velocity from the world-aligned one."""
        rotation = self._rotation(q)
        transform = np.eye(self.model.nv)
        transform[:3, :3] = rotation.T
        transform[3:6, 3:6] = rotation.T
        return transform

    @staticmethod
    def _times_transform(matrix: np.ndarray, rotation: np.ndarray) -> np.ndarray:
        """``matrix @ T`` in place (2-D, rows of nv) without forming T: the root's columns turned by R^T; ``matrix``."""
        turned = rotation.T
        matrix[:, :3] = matrix[:, :3].dot(turned)
        matrix[:, 3:6] = matrix[:, 3:6].dot(turned)
        return matrix

    def _mass(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """M in world-aligned coordinates, and R (the root's rotation: v = T u, T = diag(R^T, R^T, I))."""
        rotation = self._rotation(q)
        mass = self._times_transform(symmetric_mass_matrix(self.model, self.data, q), rotation)
        mass[:3] = rotation.dot(mass[:3])  # T^T (M T): the root's rows turned by R
        mass[3:6] = rotation.dot(mass[3:6])
        return mass, rotation

    def _mass_and_bias(self, q: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """M and b in world-aligned coordinates, and the root's rotation R (v = T u, T = diag(R^T, R^T, I))."""
        mass_u, rotation = self._mass(q)
        v = u.copy()  # the root's six turned into the local axes in place (the same products, no concatenation)
        linear, angular = rotation.T.dot(u[:3], out=v[:3]), rotation.T.dot(u[3:6], out=v[3:6])
        # d/dt (R^T p') = R^T p'' - w x v: the local acceleration that a world-aligned u' = 0 means
        drift = np.zeros(self.model.nv)
        (vx, vy, vz), (wx, wy, wz) = linear.tolist(), angular.tolist()
        drift[0], drift[1], drift[2] = wz * vy - wy * vz, wx * vz - wz * vx, wy * vx - wx * vy  # -(w x v)
        bias = pin.rnea(self.model, self.data, q, v, drift)
        bias[:3], bias[3:6] = rotation.dot(bias[:3]), rotation.dot(bias[3:6])  # T^T b
        return mass_u, bias, rotation

    def contact(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Each corner's position (k, 3) [m], its Jacobian in the ground's frame (k, 3, nv) on u, its gap (k,) [m].

        Kept for the configuration asked last (a step's end is the judge's sample and the next
        step's start): read the arrays, never write into them.
        """
        key = q.tobytes()
        cached = self._contact_cache
        if cached is not None and cached[0] == key:
            return cached[1]
        points, jac = self._corner_rows(self.model, self.data, q)  # Pinocchio's LOCAL_WORLD_ALIGNED linear rows
        if self._frame is not None:  # in the ground's frame (flat: picked in that order already)
            jac = self._frame @ jac
        jac = self._times_transform(jac.reshape(-1, self.model.nv), self._rotation(q)).reshape(jac.shape)
        out = (points, jac, points.dot(self._normal))  # the ground's gap (no step edge in 3-D)
        self._contact_cache = (key, out)
        return out

    def _bilateral(self, q: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Phi and J (world-aligned u) of the loops and cranks at ``t``, plus the held rows when held."""
        planar = self.planar
        targets = planar.targets(t) if self.settings.crank_ramp > 0 else None
        rows = planar.bilateral.evaluate(self.planar_view(q), None, t, targets)
        jac = np.zeros((rows.jac.shape[0], self.model.nv))
        jac[:, NV_ROOT : self.nv_robot] = rows.jac[:, PLANAR_NQ_ROOT:]
        phi = rows.phi
        if self.lateral is not None:  # the slider follows the right crank: y - a sin(theta + phase) = 0
            y, slope, _ = self.lateral.position(float(q[self._crank_q]))
            row = np.zeros(self.model.nv)
            row[-1], row[self._crank_v] = 1.0, -slope
            phi, jac = np.append(phi, q[-1] - y), np.vstack((jac, row))
        if self.hold:
            rotation = self._rotation(q)
            # y, and the rotation's roll and yaw errors (small: the hip turns about y alone)
            held = np.array([q[1], rotation[2, 1], rotation[1, 0]])
            phi = np.concatenate((phi, held))
            jac = np.vstack((jac, np.eye(self.model.nv)[list(HELD)]))
        return phi, jac

    def _tolerance(self) -> np.ndarray:
        tol = self.planar.bilateral.tolerance
        if self.lateral is not None:
            tol = np.append(tol, LATERAL_TOLERANCE)
        return np.concatenate((tol, np.full(3, 1e-12))) if self.hold else tol

    def project(self, q: np.ndarray, t: float, max_iter: int = 20) -> np.ndarray:
        """Newton onto the loops (and held rows) from ``q``, minimum mass-norm corrections (M at each iterate)."""
        tol = self._tolerance()
        phi = np.zeros(0)
        data = self._kkt_data
        for _ in range(max_iter):
            phi, jac = self._bilateral(q, t)
            if (np.abs(phi) < tol).all():
                return q
            data.M[:] = self._mass(q)[0]
            data.nle[:] = 0.0
            try:
                step, _ = kkt_solve(self.model, data, np.zeros(self.model.nv), jac, phi)
            except SingularPoseError:  # M singular (a foot's point mass on its own ankle axis): the metric
                step = np.linalg.lstsq(jac, -phi, rcond=None)[0]  # only picks the correction; least norm closes too
            largest = np.abs(step).max()
            if largest > STEP_LIMIT:
                step *= STEP_LIMIT / largest
            q = self._advance(q, step)
        worst = int(np.argmax(np.abs(phi) / tol))
        raise ClosureError(
            f"3-D floor: the loops did not close (row {worst} keeps {abs(phi[worst]):.3e}) at t = {t:.4f} s"
        )

    # ---- one step
    def _terms(self, q: np.ndarray, u: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The step's M, H (M and the springs' implicit term) and g = -(M u + h (tau - b)), world-aligned."""
        mass, bias, _ = self._mass_and_bias(q, u)
        if self.settings.spring is None:  # no ankle spring: no torque, no implicit term
            return mass, mass, -(mass.dot(u) - h * bias)
        hessian = mass
        spring_tau, stiffness = self.planar.springs(self.planar_view(q), h)
        tau = np.zeros(self.model.nv)
        tau[NV_ROOT : self.nv_robot] = spring_tau[PLANAR_NQ_ROOT:]
        if stiffness:
            hessian = mass.copy()
            for i in self.planar.ankles.values():
                hessian[i + self._shift, i + self._shift] += stiffness
        return mass, hessian, -(mass.dot(u) + h * (tau - bias))

    def _cone(self, q: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray, int]:
        """The corners' pyramid rows C (blocks x corners, nv) on u, their bounds l = -gap / h, and the blocks."""
        _, jac, gap = self.contact(q)
        tangents = 1 if self.hold else 2  # held: along the ground only
        n, nv = jac.shape[0], jac.shape[2]
        scaled = (self.ground.mu * jac[:, 1 : 1 + tangents]).transpose(1, 0, 2)  # mu t_k rows (tangents, n, nv)
        cone = np.empty((tangents, 2, n, nv))  # blocks n + mu t_1, n - mu t_1, n + mu t_2, n - mu t_2
        np.add(jac[:, 0], scaled, out=cone[:, 0])
        np.subtract(jac[:, 0], scaled, out=cone[:, 1])
        lower = np.empty((2 * tangents, n))
        np.divide(gap, -h, out=lower)  # -gap / h, every block
        return cone.reshape(-1, nv), lower.reshape(-1), 2 * tangents

    def step(self, t: float, q: np.ndarray, u: np.ndarray, h: float):
        """One step from (q, u) at ``t``: (q+, u+, each corner's normal impulse (k,), the motors' impulses) [N.s]."""
        _, hessian, g = self._terms(q, u, h)
        cone, lower, blocks = self._cone(q, h)
        phi, a_eq = self._bilateral(q, t + h)
        if self._qp is not None:
            u_new, bilateral, z = self._qp.solve(hessian, g, a_eq, -phi / h, cone, lower)
        else:
            # on the free motions the loops and cranks leave (the hip's six, a free ankle): 32 rows, few unknowns,
            # exactly by a least-distance NNLS; proxsuite where that does not answer
            solved = floating_qp(hessian, g, a_eq, -phi / h, cone, lower, NV_ROOT)
            if solved is None:
                solved = reduced_qp(hessian, g, a_eq, -phi / h, cone, lower, solver=proxsuite_free_qp)
                self.fallback += 1
            if solved is None:  # pragma: no cover - proxsuite answers or raises
                raise ContactSolveError("the 3-D contact QP did not solve")
            u_new, bilateral, z = solved
        check_speed(u_new)
        normal = np.add.reduce(z.reshape(blocks, -1))
        q_new = self.project(self._advance(q, h * u_new), t + h)
        return q_new, u_new, normal, bilateral[self._crank_rows]

    def tracked_step(self, q: np.ndarray, u: np.ndarray, h: float, shape: SpatialShape, track: SpatialTrack):
        """One step with the legs' shape known ahead (:mod:`.shape_track3d`), as :meth:`step`'s.

        ``None`` where the free coordinates' QP does not answer exactly (the general step takes it).
        """
        mass, hessian, g = self._terms(q, u, h)
        cone, lower, blocks = self._cone(q, h)
        free, block = track.rows, track.block
        base = hessian.dot(shape.velocity) + g
        found = ldp_free_qp(hessian[block], base[free], cone[:, free], lower - cone.dot(shape.velocity))
        if found is None:
            return None
        u_free, z = found
        if not np.maximum.reduce(np.abs(u_free)) <= SPEED_LIMIT:  # check_speed's test (NaN too), its cost at a miss
            check_speed(u_free)
        x = shape.velocity.copy()
        x[free] = u_free
        motor = shape.tangent.T[self._motor_targets].dot(hessian.dot(x) + g - cone.T.dot(z))
        shift = solve_spd(mass[block], mass.dot(shape.moved)[free])  # the projection: F by the mass metric
        if shift is None:  # M_FF singular: as the general projection's least-norm step, F stays
            shift = np.zeros(len(u_free))
        du = h * u_free - shift  # F's move: the hip's six, then a free ankle's
        legs = shape.end  # the legs on the next shape, a free ankle advanced
        if len(track.free_legs):
            legs = legs.copy()
            legs[track.free_legs] = q[NQ_ROOT + track.free_legs] + du[NV_ROOT:]
        return self._advance(q, du, legs), x, np.add.reduce(z.reshape(blocks, -1)), motor

    def _step_any(self, t: float, q: np.ndarray, u: np.ndarray, h: float, track: SpatialTrack | None):
        """The tracked step where the track has the legs' shape at ``t``, else the general :meth:`step`."""
        if track is not None and (shape := track.step(t, q[NQ_ROOT : self.nq_robot])) is not None:
            out = self.tracked_step(q, u, h, shape, track)
            if out is not None:
                return out
        return self.step(t, q, u, h)

    def spatial_track(self, h: float) -> SpatialTrack | None:
        """The legs' shape track for steps of ``h`` [s].

        ``None`` held (the planar walk's own step), with a lateral mass (its slider is no planar
        coordinate), with :attr:`tracked` off, or where the planar rows have no split.
        """
        if self.hold or self.lateral is not None or not self.tracked:
            return None
        track = self.planar.shape_track(h)
        return None if track is None else SpatialTrack(track, self.model.nv, NV_ROOT, PLANAR_NQ_ROOT)

    def _points(self, q: np.ndarray, u: np.ndarray, normal: np.ndarray | None):
        """The judge's view at (q, u) (:meth:`_view`)."""
        points, jac, _ = self.contact(q)
        return self._view(points, jac @ u, normal)

    def _hip_view(self, q: np.ndarray, pitch: float) -> tuple[float, float]:
        """The judge's hip: along the ground [m], its pitch from the ground's normal [rad] (the planar floor's)."""
        return float(q[:3].dot(self._along)), pitch - self.ground.angle

    def _view(self, points: np.ndarray, velocity: np.ndarray, normal: np.ndarray | None, gap: np.ndarray | None = None):
        """Each heel's and toe's (heights, x along the ground, speeds) and loads, from :meth:`_views_of`'s inputs."""
        k = self.per_point
        if k > 2:
            heights, xs, speeds, loads = self._views_of(points, velocity, normal, gap)
            return (heights.tolist(), xs.tolist(), speeds.tolist()), None if loads is None else loads.tolist()
        # one step's numbers as floats (gap: contact's), _views_of's reductions to the bit (group_sums, group_minima)
        gaps = (self.ground.gap(points) if gap is None else gap).tolist()
        xs = [s / k for s in group_sums(points.dot(self._along).tolist(), k)]
        speeds = [s / k for s in group_sums(velocity[:, 1].tolist(), k)]
        loads = None if normal is None else group_sums(normal.tolist(), k)
        return (group_minima(gaps, k), xs, speeds), loads

    def views(self, steps: PeriodStep) -> list:
        """The judge's two feet (:func:`~pasibot_pin.dynamics.floor.run.foot_samples`) of a period's stacked steps."""
        heights, xs, speeds, loads = self._views_of(steps.points, steps.velocity, steps.normal)
        assert loads is not None
        return foot_samples(heights, xs, speeds, loads)

    def _views_of(
        self, points: np.ndarray, velocity: np.ndarray, normal: np.ndarray | None, gap: np.ndarray | None = None
    ):
        """(heights, x along the ground, speeds, loads) of each heel and toe, on any leading axes.

        From the corners' world positions (..., k, 3) [m], ground-frame velocities (..., k, 3) [m/s],
        normal forces (..., k) [N] (``None``: loads ``None``) and gaps (k,) [m] (``None``: from the points).
        """
        lead, k = points.shape[:-2], self.per_point
        # heel and toe of each foot: the mean of their corners (one corner: the point itself)
        along = (points @ self._along).reshape(*lead, -1, k)
        gap = (self.ground.gap(points.reshape(-1, 3)) if gap is None else gap).reshape(*lead, -1, k)
        speeds = velocity[..., 1].reshape(*lead, -1, k).sum(axis=-1) / k
        loads = None if normal is None else normal.reshape(*lead, -1, k).sum(axis=-1)
        return gap.min(axis=-1), along.sum(axis=-1) / k, speeds, loads

    def sole_clearance(self, q: np.ndarray) -> float:
        """The least distance between the two feet's sole plates at ``q`` [m] (negative: they intersect).

        Pinocchio's geometry (coal) on the soles' boxes (:func:`~pasibot_pin.model.spatial.sole_boxes`),
        every pair of a right and a left plate.
        """
        pin.framesForwardKinematics(self.model, self.data, q)
        pin.updateGeometryPlacements(self.model, self.data, self._geometry, self._geometry_data)
        nearest = pin.computeDistances(self._geometry, self._geometry_data)  # the pair of the least distance
        results = self._geometry_data.distanceResults
        if nearest < len(results):  # read that one (each result read is a copy)
            return float(results[nearest].min_distance)
        return min(float(result.min_distance) for result in results)

    def start(self) -> tuple[np.ndarray, np.ndarray, str]:
        """The planar floor's consistent start (both feet flat, at rest), in 3-D: (q, u, start kind)."""
        try:
            begin = self.planar.start_state()
            q2, v2, kind = begin.q, begin.v, begin.kind
        except SimulationError:
            (q2, v2), kind = self.planar.initial_state(), "flat"
        q, u = self.spatial_state(q2, v2)
        return q, u, kind

    def run(
        self,
        duration: float,
        q0: np.ndarray | None = None,
        u0: np.ndarray | None = None,
        criteria: GaitCriteria | None = None,
        stop_on_verdict: bool = True,
        judge: JudgeFactory | None = None,
    ) -> Floor3DResult:
        """Integrate for ``duration`` [s] from the consistent start (or from ``q0``, ``u0``), judging the walk.

        ``judge`` builds the walk's observer from the first sample (as :meth:`FloorSimulator.run`'s;
        default: a :class:`~pasibot_pin.dynamics.verdict.GaitJudge` by ``criteria``); it also hears the
        hip's roll and the soles' collisions. A gait that settles repeats itself from then on
        (:mod:`~pasibot_pin.dynamics.floor.repeat3d`; :attr:`repeats` off: every step simulated).
        """
        if self.settings.omega <= 0:
            raise ParameterError("the 3-D walk needs turning cranks (omega > 0)")
        h, n = self.time_grid(duration)
        if (q0 is None) != (u0 is None):
            raise ParameterError("give both 'q0' and 'u0' or neither")
        if judge is not None and criteria is not None:
            raise ParameterError("give the run a 'judge' or 'criteria', not both (the judge has its own)")
        if q0 is None:  # the feet and legs at the geometric start (both soles flat): refused before any work
            flat, _ = self.spatial_state(*self.planar.initial_state())
            check_interference(self.footprint, self.planar.robot.geometry, self.sole_clearance(flat) + TOUCH)
            q, u, _ = self.start()
        else:
            q = self.extend(np.array(q0, dtype=float))
            u = self.extend_velocity(q, np.array(u0, dtype=float))
        points, _ = self._points(q, u, None)
        first, _ = point_sample(0.0, self._hip_view(q, roll_pitch_yaw(q)[1]), points, None, (0.0, 0.0))
        observer = (judge or self.planar.judge_of(criteria))(first)
        return self._walk(q, u, h, n, observer, stop_on_verdict)

    def _settled_gait(self, h: float) -> SettledGait | None:
        """The watch for a repeating gait (:mod:`.repeat3d`); ``None`` held, off flat ground, or :attr:`repeats` off."""
        if self.hold or not self.repeats or self.ground.angle != 0.0 or self.ground.has_step:
            return None
        period = round(2.0 * math.pi / self.settings.omega / h)
        angular = np.zeros(self.model.nq, dtype=bool)
        angular[NQ_ROOT : self.nq_robot] = angular_coordinates(self.planar.robot.model)[PLANAR_NQ_ROOT:]
        return SettledGait(period, period + math.ceil(self.settings.crank_ramp / h) + 1, angular, self.views)

    def _walk(self, q, u, h: float, n: int, observer, stop_on_verdict: bool) -> Floor3DResult:
        """The run's steps from (q, u), each heard by ``observer``; a settled gait's steps repeated, not simulated."""
        track, watch = self.spatial_track(h), self._settled_gait(h)
        times, qs, normals, attitudes = [0.0], [q.copy()], [np.zeros(self.n_corners)], [roll_pitch_yaw(q)]
        t, settled_at = 0.0, math.nan
        least = self.sole_clearance(q)
        for k in range(1, n + 1):
            measure = k % CLEARANCE_EVERY == 0
            if watch is not None and watch.motion is not None:
                row = watch.replay()
                if measure and math.isnan(row.clearance):
                    row = row._replace(clearance=self.sole_clearance(row.q))
                    watch.measured(row.clearance)
                t += h
                sample = GaitSample(t, float(row.q[0]), row.attitude[1], row.feet, row.power)
            else:
                try:
                    q, u, normal, motor = self._step_any(t, q, u, h, track)
                except SimulationError as err:
                    observer.diverged(t, str(err))
                    break
                t += h
                power = tuple(m * float(u[i]) for m, i in zip((motor / h).tolist(), self._motor_index))
                corners, jac, gap = self.contact(q)
                velocity, attitude, load = jac @ u, self._attitude(q), normal / h
                clearance = self.sole_clearance(q) if measure else math.nan
                points, loads = self._view(corners, velocity, load, gap)
                sample, _ = point_sample(t, self._hip_view(q, attitude[1]), points, loads, power)
                row = Replayed(q, u, load, power, sample.feet, attitude, clearance)
                step = PeriodStep(q, u, row.normal, np.array(power), corners, velocity, np.array(attitude), clearance)
                if watch is not None and watch.push(step):
                    settled_at = t
            q, u = row.q, row.u
            times.append(t)
            qs.append(q.copy())
            normals.append(row.normal)
            attitudes.append(row.attitude)
            observer.update(sample)
            observer.roll(t, row.attitude[0])
            if measure:
                least = min(least, row.clearance)
                if row.clearance < -TOUCH:
                    observer.collided(t, f"the soles intersect by {-1000 * row.clearance:.1f} mm")
            if stop_on_verdict and observer.final(t):
                break
        qs_all = np.array(qs)
        result = self._result(
            np.array(times),
            qs_all[:, : self.nq_robot],
            np.array(normals),
            np.array(attitudes),
            observer.verdict(t),
            least,
        )
        lateral = qs_all[:, self.nq_robot] if self.lateral is not None else None
        return replace(result, u_end=u[: self.nv_robot].copy(), lateral_y=lateral, settled_at_s=settled_at)

    def time_grid(self, duration: float) -> tuple[float, int]:
        """The run's time step h [s] and its number of steps for ``duration`` [s].

        Held, the planar floor's (``duration`` in whole steps of at most ``dt``); free,
        :func:`~pasibot_pin.dynamics.floor.repeat3d.period_grid` (a settled gait repeats step for step).
        """
        s = self.settings
        if self.hold:
            n = step_count(duration, s.dt, MAX_STEPS)
            return duration / n, n
        return period_grid(duration, s.dt, s.omega, MAX_STEPS)

    def _result(
        self, t: np.ndarray, q: np.ndarray, normal: np.ndarray, attitude: np.ndarray, verdict: Verdict, clearance: float
    ) -> Floor3DResult:
        """The run's result (:func:`~.result3d.floor3d_result`) with this floor's fallbacks and the legs' clearance."""
        geometry = self.planar.robot.geometry
        legs = leg_clearance(self.footprint, geometry.hip_half_width, geometry.L)
        return floor3d_result(t, q, normal, attitude, verdict, clearance, self.fallback, legs)
