"""THE constraint system of a robot: residual, Jacobian, drift, projections and the KKT solves.

Every closed-loop computation of the package goes through :class:`ConstraintSystem`: the
loop closures at the cut joints, the stance-foot weld, prescribed (possibly time-dependent)
coordinates such as the cranks' theta0 + omega t or a held hip, frame pitches (a level swing
foot) and motor couplings (one motor for both cranks: q_L - q_R - pi = 0). This module is
the only one that calls Pinocchio's Jacobian algorithms; :mod:`.pinocchio_models` the only one
that calls its constraint API.

Rows, in order (``labels``):

* each constraint model: x and z of p1 - p2 (world axes) for a point coincidence, plus the
  pitch difference for a weld; the out-of-plane rows are identically zero and dropped, so J
  has full row rank away from singular poses;
* each scalar row: a linear combination of coordinates (:class:`CoordinateRow`) or a frame's
  pitch (:class:`PitchRow`) minus its target, offset + rate t.

With Phi(q, t) the rows, J = dPhi/dq, the drift J_dot v (the rows' second time derivative at
zero joint acceleration) and Phi_t = dPhi/dt:

* ``project``: Newton on Phi(q, t) = 0 (square: exact solve; otherwise minimum-norm or
  minimum-M-norm corrections);
* ``velocity``: J v = -Phi_t (square);  ``acceleration``: J a = -J_dot v (square);
* ``forward_dynamics``: [M J^T; J 0][a; mu] = [tau - h; -J_dot v], lambda = -mu;
* ``impulse``: [M J^T; J 0][v+; mu] = [M v-; -Phi_t] (inelastic impact, velocity projection).

The model is planar (x-z plane, every rotation about y), so the angular velocity of every
body is along y: the point rows use that. Pitch is counter-clockwise seen from the right
(about -y). Units: SI, angles [rad].
"""

from __future__ import annotations

import copy
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from pasibot_pin.constraints.pinocchio_models import anchor_points, is_weld, planar_rows
from pasibot_pin.constraints.planar import PlanarKinematics, PlanarRowBlocks
from pasibot_pin.errors import ClosureError, ParameterError, SingularPoseError

_PLANAR_CACHE: dict[int, tuple[pin.Model, PlanarKinematics | None]] = {}


def planar_kinematics(model: pin.Model) -> PlanarKinematics | None:
    """The exact planar kinematics of ``model`` (cached), or ``None`` when the model is not planar."""
    entry = _PLANAR_CACHE.get(id(model))
    if entry is None or entry[0] is not model:
        try:
            kin = PlanarKinematics(model)
        except ValueError:
            kin = None
        if len(_PLANAR_CACHE) >= 16:
            _PLANAR_CACHE.pop(next(iter(_PLANAR_CACHE)))
        entry = _PLANAR_CACHE[id(model)] = (model, kin)  # the entry keeps the model alive: no id reuse
    return entry[1]


RELATIVE_TOL = 2e-11
"""Newton stops when every length row is below RELATIVE_TOL * length_scale (1e-12 m at L = 0.05 m)."""
ANGLE_TOL = 1e-12
"""... and every angle row below this [rad]."""
STEP_LIMIT = 0.5
"""Largest Newton step component [rad or m/L]: keeps far-off starts on their assembly branch."""


def planar_pitch(rotation: np.ndarray) -> float:
    """Counter-clockwise angle of a frame's x axis in the x-z plane [rad] (atan2, signed)."""
    return math.atan2(rotation[2, 0], rotation[0, 0])


# --------------------------------------------------------------------------- scalar rows (data)
@dataclass(frozen=True)
class CoordinateRow:
    """A linear coordinate row: sum_k c_k q[i_k] - (offset + rate t) = 0.

    Prescribed joint angles, the hip pitch held level, the cranks turning at omega, and the
    one-motor coupling q_L - q_R - pi = 0 are all of this kind.

    Attributes:
        name: label (``right_j0_crank``, ``hip_pitch``, ``crank_coupling``).
        terms: ((velocity index, coefficient), ...); nq == nv for every PASIBOT model.
        offset: target at t = 0 [rad or m].
        rate: its time derivative [rad/s or m/s].

    """

    name: str
    terms: tuple[tuple[int, float], ...]
    offset: float = 0.0
    rate: float = 0.0

    @property
    def index(self) -> int:
        """The coordinate index of a one-term row."""
        if len(self.terms) != 1:
            raise ValueError(f"row {self.name!r} combines {len(self.terms)} coordinates: it has no single index")
        return self.terms[0][0]

    def at(self, offset: float, rate: float = 0.0) -> CoordinateRow:
        """The same row with another target."""
        return CoordinateRow(self.name, self.terms, float(offset), float(rate))


@dataclass(frozen=True)
class PitchRow:
    """A frame's world pitch: pitch(frame) - (offset + rate t) = 0 (wrapped to (-pi, pi]).

    Attributes:
        name: label (the frame name).
        frame: Pinocchio frame index.
        offset: target at t = 0 [rad].
        rate: its time derivative [rad/s].

    """

    name: str
    frame: int
    offset: float = 0.0
    rate: float = 0.0

    def at(self, offset: float, rate: float = 0.0) -> PitchRow:
        """The same row with another target."""
        return PitchRow(self.name, self.frame, float(offset), float(rate))


ScalarRow = CoordinateRow | PitchRow


def coordinate(name: str, index: int, offset: float = 0.0, rate: float = 0.0) -> CoordinateRow:
    """One coordinate q[index] = offset + rate t."""
    return CoordinateRow(name, ((int(index), 1.0),), float(offset), float(rate))


def coupling(name: str, index: int, minus: int, offset: float) -> CoordinateRow:
    """Two coordinates locked together: q[index] - q[minus] = offset (one motor for two cranks)."""
    return CoordinateRow(name, ((int(index), 1.0), (int(minus), -1.0)), float(offset))


@dataclass
class Rows:
    """The rows evaluated at (q, v, t).

    Attributes:
        phi: residual Phi(q, t) (m,) [m, rad].
        jac: Jacobian dPhi/dq (m, nv).
        drift: J_dot v (m,) [m/s^2, rad/s^2] (zeros without v).
        phi_t: dPhi/dt (m,) [m/s, rad/s].

    """

    phi: np.ndarray
    jac: np.ndarray
    drift: np.ndarray
    phi_t: np.ndarray


class Projection(NamedTuple):
    """What :meth:`ConstraintSystem.project_rows` computed.

    Attributes:
        q: the closed configuration (nq,).
        rows: the rows evaluated at ``q`` (residual below the tolerance, J, no drift).
        initial_residual: the largest |Phi| at the start configuration [m, rad].

    """

    q: np.ndarray
    rows: Rows
    initial_residual: float


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross product of two (n, 3) arrays (np.cross is slow on small arrays)."""
    return np.column_stack(
        (
            a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1],
            a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
            a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0],
        )
    )


def _wrap(angle: np.ndarray | float):
    return np.remainder(np.asarray(angle) + math.pi, 2 * math.pi) - math.pi


_LOWER: dict[int, tuple[np.ndarray, np.ndarray]] = {}


def frame_rows(
    model: pin.Model, frames: Sequence[int], points: Sequence[int], pitches: Sequence[int] = ()
) -> PlanarRowBlocks:
    """Planar rows of frames of ``model``: the world position of each of ``points``, the pitch of ``pitches``.

    The public way to build rows outside a :class:`ConstraintSystem` (contact points, a sole's
    pose): the same exact planar kinematics (complex products, batched over leading axes of q).

    Args:
        model: a planar model (every rotation about y).
        frames: frame ids.
        points: indices into ``frames`` whose world (x, z) rows are wanted, in this order.
        pitches: indices into ``frames`` whose world pitch rows are wanted.

    Returns:
        :class:`~pasibot_pin.constraints.planar.PlanarRowBlocks`: ``evaluate(q)`` gives the points as
        x + i z [m], their Jacobian and the pitch rows [rad].

    Raises:
        ParameterError: the model is not planar.

    """
    kin = planar_kinematics(model)
    if kin is None:
        raise ParameterError("frame_rows needs a planar model (every rotation about y)")
    placed = [model.frames[int(f)] for f in frames]
    ends = kin.ends(
        np.array([f.parentJoint for f in placed]),
        np.array([f.placement.translation for f in placed]).reshape(-1, 3),
        np.array([f.placement.rotation for f in placed]).reshape(-1, 3, 3),
    )
    return PlanarRowBlocks(ends, [(int(k), -1) for k in points], [(int(k), -1) for k in pitches])


def symmetric_mass_matrix(model: pin.Model, data: pin.Data, q: np.ndarray) -> np.ndarray:
    """Joint-space mass matrix M(q), both triangles filled [kg, kg.m, kg.m^2].

    ``pin.crba`` fills the upper triangle; the lower one is copied from it.
    """
    mass = np.array(pin.crba(model, data, q))
    lower = _LOWER.get(model.nv)
    if lower is None:
        lower = _LOWER[model.nv] = np.tril_indices(model.nv, -1)
    mass[lower] = mass.T[lower]
    return mass


# --------------------------------------------------------------------------- the system
class ConstraintSystem:
    """Constraint models (loops, welds, ground pins) plus scalar rows on one Pinocchio model.

    Args:
        model: the Pinocchio model (planar: every rotation about y; nq == nv).
        data: its data (the system writes kinematics into it).
        cmodels: ``RigidConstraintModel`` s (CONTACT_3D points, CONTACT_6D welds).
        scalars: :class:`CoordinateRow` / :class:`PitchRow` rows, in order.
        length_scale: the robot's length unit L [m]; Newton's tolerance is relative to it.
        kinematics: ``planar`` (the exact vectorised planar kinematics of :mod:`.planar`, when the
            model is planar; Pinocchio otherwise) or ``pinocchio`` (Pinocchio's joint Jacobians
            and classical accelerations: the reference the tests compare with).

    """

    def __init__(
        self,
        model: pin.Model,
        data: pin.Data,
        cmodels: Sequence[pin.RigidConstraintModel] = (),
        scalars: Sequence[ScalarRow] = (),
        length_scale: float = 0.05,
        kinematics: str = "planar",
    ):
        if model.nq != model.nv:
            raise ValueError(f"the constraint system needs nq == nv (revolute/prismatic joints), got {model.nq}")
        self.model, self.data = model, data
        self.cmodels = list(cmodels)
        self.length_scale = float(length_scale)
        self._zero_v = np.zeros(model.nv)
        if kinematics not in ("planar", "pinocchio"):
            raise ValueError(f"parameter 'kinematics' must be 'planar' or 'pinocchio', got {kinematics!r}")
        self._planar = planar_kinematics(model) if kinematics == "planar" else None
        # the two ends of every constraint model
        ends = []
        for cm in self.cmodels:
            for joint, placement in anchor_points(cm):
                ends.append((joint, np.array(placement.translation), np.array(placement.rotation)))
        self._model_ends = ends
        slices = planar_rows(self.cmodels)
        self.n_constraint_rows = slices[-1].stop if slices else 0
        self._rx = np.array([sl.start for sl in slices], dtype=int)
        self._rz = self._rx + 1
        self._a = 2 * np.arange(len(self.cmodels))
        self._b = self._a + 1
        weld = [is_weld(cm) for cm in self.cmodels]
        self._weld_rows = np.array([sl.start + 2 for sl, w in zip(slices, weld) if w], dtype=int)
        self._weld_a = np.array([2 * c for c, w in enumerate(weld) if w], dtype=int)
        self._weld_b = self._weld_a + 1
        self._constraint_labels = []
        for cm, w in zip(self.cmodels, weld):
            self._constraint_labels += [f"{cm.name}.{a}" for a in (("x", "z", "pitch") if w else ("x", "z"))]
        self._set_scalars(scalars)

    def _set_scalars(self, scalars: Sequence[ScalarRow]) -> None:
        """Lay out the scalar rows (and the frames of the pitch rows) after the constraint rows."""
        model, nv = self.model, self.model.nv
        self.scalars = list(scalars)
        ends = list(self._model_ends)
        row = self.n_constraint_rows
        self.nrows = row + len(self.scalars)
        lin, lin_rows, pitch_rows, pitch_ends = [], [], [], []
        for k, s in enumerate(self.scalars):
            if isinstance(s, CoordinateRow):
                vec = np.zeros(nv)
                for index, coef in s.terms:
                    vec[index] += coef
                lin.append(vec)
                lin_rows.append(row + k)
            elif isinstance(s, PitchRow):
                frame = model.frames[s.frame]
                pitch_rows.append(row + k)
                pitch_ends.append(len(ends))
                placement = frame.placement
                ends.append((int(frame.parentJoint), np.array(placement.translation), np.array(placement.rotation)))
            else:
                raise TypeError(f"scalar row {s!r} is neither a CoordinateRow nor a PitchRow")
        self._joints = np.array([e[0] for e in ends], dtype=int)
        unique, index = np.unique(self._joints, return_inverse=True)
        self._unique_joints = [int(j) for j in unique]
        self._unique_index = index.reshape(-1)
        self._trans = np.array([e[1] for e in ends], dtype=float).reshape(-1, 3)
        self._rots = np.array([e[2] for e in ends], dtype=float).reshape(-1, 3, 3)
        mask = np.zeros((len(ends), nv))
        for k, joint in enumerate(self._joints):
            for sup in model.supports[int(joint)]:
                if sup == 0:
                    continue
                jm = model.joints[sup]
                mask[k, jm.idx_v : jm.idx_v + jm.nv] = 1.0
        self._mask = mask
        self._planar_ends = None if self._planar is None else self._planar.ends(self._joints, self._trans, self._rots)
        self._lin = np.array(lin).reshape(-1, nv)
        self._lin_rows = np.array(lin_rows, dtype=int)
        self._pitch_rows = np.array(pitch_rows, dtype=int)
        self._pitch_ends = np.array(pitch_ends, dtype=int)
        self._offset = np.array([s.offset for s in self.scalars], dtype=float)
        self._rate = np.array([s.rate for s in self.scalars], dtype=float)
        self._is_pitch = np.array([isinstance(s, PitchRow) for s in self.scalars], dtype=bool)
        # tolerances per row: lengths relative to L, angles absolute
        tol = np.full(self.nrows, RELATIVE_TOL * self.length_scale)
        tol[self._weld_rows] = ANGLE_TOL
        for k, s in enumerate(self.scalars):
            if isinstance(s, PitchRow) or self._angular(s):
                tol[row + k] = ANGLE_TOL
        self.tolerance = tol
        self.labels = self._constraint_labels + [s.name for s in self.scalars]
        self._coef = None
        if self._planar_ends is not None:
            pairs = [(2 * c, 2 * c + 1) for c in range(len(self.cmodels))]
            pitch_pairs = [(int(a), int(b)) for a, b in zip(self._weld_a, self._weld_b)]
            pitch_pairs += [(int(e), -1) for e in self._pitch_ends]
            self._blocks = PlanarRowBlocks(self._planar_ends, pairs, pitch_pairs)
            template = np.zeros((self.nrows, nv))
            n_weld = len(self._weld_rows)
            template[self._weld_rows] = self._blocks.pitch_A[:n_weld]
            template[self._pitch_rows] = self._blocks.pitch_A[n_weld:]
            template[self._lin_rows] = self._lin
            self._jac_template = template
            # point rows straight in our order: P (m, 2K) picks x (real part) and z (imaginary part)
            # of every term, interleaved as a complex array viewed as floats; the pitch and coordinate
            # rows are linear: L q + l0
            blocks = self._blocks
            n_terms = blocks.D_moving.shape[1]
            pick = np.zeros((self.nrows, n_terms, 2))
            pick[self._rx, :, 0] = blocks.D_moving
            pick[self._rz, :, 1] = blocks.D_moving
            self._pick_T = pick.reshape(self.nrows, 2 * n_terms).T.copy()
            offset = np.zeros(self.nrows)
            offset[self._weld_rows] = blocks.pitch_a0[:n_weld]
            offset[self._pitch_rows] = blocks.pitch_a0[n_weld:]
            offset[self._rx], offset[self._rz] = blocks.fixed_rows.real, blocks.fixed_rows.imag
            template[self._rx], template[self._rz] = blocks.fixed_jac.real, blocks.fixed_jac.imag
            self._linear_T, self._linear_0 = template.T.copy(), offset  # J is built transposed: no copy
            self._phi_t = np.zeros(self.nrows)
            self._phi_t[row:] = -self._rate
            wrapped = np.concatenate((self._weld_rows, np.nonzero(self._is_pitch)[0] + row)).astype(int)
            self._wrapped = [int(r) for r in wrapped]
            # one sample (the simulator's case): the terms' values, Jacobian and drift as the rows of one
            # complex array (nv rows i A^T, one of ones, one for -w^2), turned into rows by one product
            if not blocks.has_sliders:
                self._one_sample_tables(blocks)

    def _one_sample_tables(self, blocks: PlanarRowBlocks) -> None:
        """Tables of :meth:`_evaluate_one`: the terms' constants folded into one real picking matrix.

        A moving term is C exp(i A q) with C = c exp(i a0). Its (real, imaginary) parts are a 2 x 2
        real map of those of exp(i A q), so the picking matrix absorbs C:
        W[2k] = Re C P_x + Im C P_z and W[2k + 1] = -Im C P_x + Re C P_z (P: ``_pick_T`` rows).
        Terms with the same pitch row A (the points of one body) share exp(i A q): their rows of W
        are summed, so the biped's 28 terms need 16 phases.
        """
        nv, n0 = self.model.nv, self.n_constraint_rows
        big_c = blocks.moving_c * np.exp(1j * blocks.moving_a0)
        px, pz = self._pick_T[0::2], self._pick_T[1::2]
        weights = np.empty_like(self._pick_T)
        weights[0::2] = big_c.real[:, None] * px + big_c.imag[:, None] * pz
        weights[1::2] = -big_c.imag[:, None] * px + big_c.real[:, None] * pz
        # terms turned by the same pitch share one phase: their picked constants add up
        pitches, group = np.unique(blocks.moving_AT.T, axis=0, return_inverse=True)
        merged = np.zeros((2 * len(pitches), self.nrows))
        np.add.at(merged, 2 * group.reshape(-1), weights[0::2])
        np.add.at(merged, 2 * group.reshape(-1) + 1, weights[1::2])
        self._weights_T = merged
        self._phase_T = pitches.T.copy()  # (nv, number of distinct pitches)
        # rows: i A^T (the Jacobian), 1 (the value), then w^2 (the drift, filled per call: a buffer)
        self._coef = np.vstack((1j * self._phase_T, np.ones(len(pitches)), np.zeros(len(pitches))))
        constant = np.vstack((self._linear_T, self._linear_0, np.zeros(self.nrows)))
        constant[nv, n0:] -= self._offset  # the scalar rows' targets at t = 0
        self._constant = constant
        self._rate_all = np.zeros(self.nrows)
        self._rate_all[n0:] = self._rate

    def _angular(self, row: CoordinateRow) -> bool:
        """True when every coordinate of the row is a rotation (revolute joints and the hip pitch)."""
        for index, _ in row.terms:
            for j in range(1, self.model.njoints):
                jm = self.model.joints[j]
                if jm.idx_v <= index < jm.idx_v + jm.nv:
                    name = jm.shortname()
                    if "Prismatic" in name or name in ("JointModelPX", "JointModelPY", "JointModelPZ"):
                        return False
                    if name == "JointModelComposite":
                        return index - jm.idx_v == jm.nv - 1  # the planar hip: x, z, then pitch
        return True

    # ---- construction helpers
    def with_scalars(self, scalars: Sequence[ScalarRow]) -> ConstraintSystem:
        """The same constraint models with other scalar rows (shares the constraint layout)."""
        other = copy.copy(self)
        other._set_scalars(scalars)
        return other

    def targets(self, t: float = 0.0) -> np.ndarray:
        """Targets of the scalar rows at time t: offset + rate t [rad, m]."""
        return self._offset + self._rate * t

    # ---- evaluation
    def evaluate(
        self,
        q: np.ndarray,
        v: np.ndarray | None = None,
        t: float = 0.0,
        targets: Sequence[float] | None = None,
    ) -> Rows:
        """Phi(q, t), J(q), J_dot v (with ``v``) and Phi_t, in one kinematic pass.

        Args:
            q: configuration (nq,).
            v: velocity (nv,) for the drift, or ``None``.
            t: time [s] of the rheonomic targets.
            targets: the scalar rows' targets instead of offset + rate t.

        """
        if self._planar_ends is not None:
            return self._evaluate_planar(q, v, t, targets)
        model, data = self.model, self.data
        nv = model.nv
        if v is None:
            pin.computeJointJacobians(model, data, q)
        else:
            pin.forwardKinematics(model, data, q, v, self._zero_v)
            pin.computeJointJacobians(model, data, q)  # world frame, at the origin; keeps data.v, data.a
        m = self.nrows
        phi, jac, drift = np.zeros(m), np.zeros((m, nv)), np.zeros(m)
        joints = self._joints
        if len(joints):
            jw = data.J
            homog = np.array([data.oMi[j].homogeneous for j in self._unique_joints])[self._unique_index]
            rot = homog[:, :3, :3]
            p = homog[:, :3, 3] + (rot @ self._trans[:, :, None])[:, :, 0]
            # every rotation is about y: v_p = v_O + w x p gives vx = v_Ox + w_y p_z, vz = v_Oz - w_y p_x
            jwy = jw[4][None, :] * self._mask
            jx = jw[0][None, :] * self._mask + p[:, 2:3] * jwy
            jz = jw[2][None, :] * self._mask - p[:, 0:1] * jwy
            if v is not None:
                # classical acceleration of each point at zero joint acceleration, joint frame, then world
                vel = np.array([data.v[j].vector for j in self._unique_joints])[self._unique_index]
                acc = np.array([data.a[j].vector for j in self._unique_joints])[self._unique_index]
                w = vel[:, 3:]
                vp = vel[:, :3] + _cross(w, self._trans)
                ap = (rot @ (acc[:, :3] + _cross(acc[:, 3:], self._trans) + _cross(w, vp))[:, :, None])[:, :, 0]
                alpha_y = np.sum(rot[:, 1, :] * acc[:, 3:], axis=1)
            a, b, rx, rz = self._a, self._b, self._rx, self._rz
            if len(a):
                phi[rx] = p[a, 0] - p[b, 0]
                phi[rz] = p[a, 2] - p[b, 2]
                jac[rx] = jx[a] - jx[b]
                jac[rz] = jz[a] - jz[b]
                if v is not None:
                    drift[rx] = ap[a, 0] - ap[b, 0]
                    drift[rz] = ap[a, 2] - ap[b, 2]
            x_axis = self._rots[:, :, 0]  # the frame's x axis in its joint frame
            pitch = np.arctan2(np.sum(rot[:, 2, :] * x_axis, axis=1), np.sum(rot[:, 0, :] * x_axis, axis=1))
            wa, wb, wr = self._weld_a, self._weld_b, self._weld_rows
            if len(wr):
                phi[wr] = _wrap(pitch[wa] - pitch[wb])
                jac[wr] = -(jwy[wa] - jwy[wb])  # pitch is about -y
                if v is not None:
                    drift[wr] = -(alpha_y[wa] - alpha_y[wb])
            pr, pe = self._pitch_rows, self._pitch_ends
            if len(pr):
                phi[pr] = pitch[pe]
                jac[pr] = -jwy[pe]
                if v is not None:
                    drift[pr] = -alpha_y[pe]
        return self._finish(phi, jac, drift, q, t, targets)

    def _finish(self, phi, jac, drift, q, t, targets) -> Rows:
        """Fill the coordinate rows, subtract the scalar rows' targets and add Phi_t (any batch shape)."""
        lr = self._lin_rows
        if len(lr):
            phi[..., lr] = q @ self._lin.T
            jac[..., lr, :] = self._lin
        n0 = self.n_constraint_rows
        if self.scalars:
            goal = self.targets(t) if targets is None else np.asarray(targets, dtype=float)
            ds = phi[..., n0:] - goal
            ds[..., self._is_pitch] = _wrap(ds[..., self._is_pitch])
            phi[..., n0:] = ds
        phi_t = np.zeros(phi.shape)
        phi_t[..., n0:] = -self._rate
        return Rows(phi, jac, drift, phi_t)

    def _evaluate_planar(self, q, v, t, targets) -> Rows:
        """:meth:`evaluate` through the exact planar kinematics (complex products, no Pinocchio call).

        ``q`` (and ``v``) may carry leading batch axes: (N, nv) gives rows (N, m) and J (N, m, nv).
        The point rows come out in our order from one product with the picking matrix; the pitch
        and coordinate rows are linear in q.
        """
        if self._coef is not None:
            if q.ndim == 1:
                return self._evaluate_one(q, v, t, targets)
            if q.ndim == 2:
                return self._evaluate_batch(q, v, t, targets)
        value, jac_t, term_drift = self._blocks.terms(q, v)
        phi = value.view(float) @ self._pick_T + q @ self._linear_T + self._linear_0
        # J transposed in memory (a column-major view): what Pinocchio's Eigen takes without a copy
        jac = np.swapaxes(jac_t.view(float) @ self._pick_T + self._linear_T, -1, -2)
        drift = np.zeros(phi.shape) if term_drift is None else term_drift.view(float) @ self._pick_T
        if self.scalars:
            goal = self._offset + self._rate * t if targets is None else np.asarray(targets, dtype=float)
            phi[..., self.n_constraint_rows :] -= goal
        if phi.ndim == 1:
            for r in self._wrapped:  # one or two angle rows: scalar arithmetic is cheaper here
                phi[r] = math.remainder(phi[r], 2 * math.pi)
            return Rows(phi, jac, drift, self._phi_t.copy())
        if len(self._wrapped):
            phi[..., self._wrapped] = _wrap(phi[..., self._wrapped])
        return Rows(phi, jac, drift, np.broadcast_to(self._phi_t, phi.shape).copy())

    def _evaluate_one(self, q, v, t, targets) -> Rows:
        """:meth:`_evaluate_planar` for one sample in a dozen numpy calls (the simulator's inner loop).

        The terms' phases e = exp(i A q), times the rows of one coefficient array (i A^T for the
        Jacobian, 1 for the value, w^2 for minus the drift, w = A v), give J^T, the point rows and
        the drift in one product with the picking matrix (which holds the terms' constants,
        :meth:`_one_sample_tables`).
        """
        # ndarray.dot rather than @: the same product with less call overhead on these small arrays
        nv = self.model.nv
        phase = np.exp(q.dot(self._coef[:nv]))  # exp(i A q); the real part of the exponent is exactly 0
        if v is None:
            out = (self._coef[: nv + 1] * phase).view(float).dot(self._weights_T) + self._constant[: nv + 1]
            drift = np.zeros(self.nrows)
        else:
            w = v.dot(self._phase_T)
            coef = self._coef
            np.multiply(w, w, out=coef[nv + 1])  # the drift of a term is -w^2 times its value
            out = (coef * phase).view(float).dot(self._weights_T) + self._constant
            drift = -out[nv + 1]
        phi = out[nv] + q.dot(self._linear_T)
        if targets is None:
            if t:
                phi -= t * self._rate_all
        else:
            phi[self.n_constraint_rows :] += self._offset - np.asarray(targets, dtype=float)
        for r in self._wrapped:  # one or two angle rows: scalar arithmetic is cheaper here
            phi[r] = math.remainder(phi[r], 2 * math.pi)
        # J transposed in memory (column-major): what Pinocchio's Eigen takes without a copy
        return Rows(phi, out[:nv].T, drift, self._phi_t.copy())

    def _evaluate_batch(self, q, v, t, targets) -> Rows:
        """:meth:`_evaluate_planar` for a batch (N, nv) through the tables of :meth:`_evaluate_one`.

        The phases e = exp(i A q) (N, P) of the distinct body pitches, times i A^T, give J^T of every
        sample in one (N nv, 2P) x (2P, m) product; the values and the drift (-w^2 e, w = A v) one
        (N, 2P) x (2P, m) product each.
        """
        nv, n = self.model.nv, len(q)
        angle = q @ self._phase_T
        phase = np.empty(angle.shape, dtype=complex)  # exp(i A q) (N, P), by cos and sin (cheaper)
        np.cos(angle, out=phase.real)
        np.sin(angle, out=phase.imag)
        weights = self._weights_T
        n_phase = phase.shape[1]
        jac_t = (self._coef[:nv] * phase[:, None, :]).view(float).reshape(n * nv, 2 * n_phase) @ weights
        jac_t = jac_t.reshape(n, nv, self.nrows) + self._constant[:nv]
        phi = phase.view(float) @ weights + (q @ self._linear_T + self._constant[nv])
        if v is None:
            drift = np.zeros((n, self.nrows))
        else:
            w = v @ self._phase_T
            drift = (w * w * phase).view(float) @ weights
            np.negative(drift, out=drift)
        n0 = self.n_constraint_rows
        if targets is None:
            if t:
                phi -= t * self._rate_all
        else:
            phi[:, n0:] += self._offset - np.asarray(targets, dtype=float)
        if len(self._wrapped):
            phi[:, self._wrapped] = _wrap(phi[:, self._wrapped])
        # J transposed in memory (a column-major view per sample)
        return Rows(phi, np.swapaxes(jac_t, 1, 2), drift, np.broadcast_to(self._phi_t, phi.shape).copy())

    def residual(self, q: np.ndarray, t: float = 0.0, targets: Sequence[float] | None = None) -> np.ndarray:
        """Phi(q, t) (m,) [m, rad]."""
        return self.evaluate(q, None, t, targets).phi

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        """J = dPhi/dq (m, nv)."""
        return self.evaluate(q).jac

    def constraint_jacobian(self, q: np.ndarray) -> np.ndarray:
        """The rows of the constraint models only, J_c (n_constraint_rows, nv)."""
        return self.evaluate(q).jac[: self.n_constraint_rows]

    def drift(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """J_dot(q, v) v (m,): the rows' acceleration at zero joint acceleration [m/s^2, rad/s^2]."""
        return self.evaluate(q, v).drift

    # ---- projections
    def project(
        self,
        q: np.ndarray,
        t: float = 0.0,
        targets: Sequence[float] | None = None,
        metric: str = "euclidean",
        max_iter: int = 50,
    ) -> np.ndarray:
        """Newton onto Phi(q, t) = 0 from ``q``: the closed configuration (:meth:`project_rows`'s ``q``)."""
        return self.project_rows(q, t, targets, metric, max_iter).q

    def project_rows(
        self,
        q: np.ndarray,
        t: float = 0.0,
        targets: Sequence[float] | None = None,
        metric: str = "euclidean",
        max_iter: int = 50,
    ) -> Projection:
        """Newton onto Phi(q, t) = 0 from ``q``, with the rows at the answer.

        Nothing is stored on the system (it is cached and shared): everything the projection
        computed is in the returned :class:`Projection`.

        Args:
            q: start configuration.
            t: time [s].
            targets: the scalar rows' targets instead of offset + rate t.
            metric: ``euclidean`` (minimum-norm corrections; exact for a square system) or
                ``mass`` (minimum M-norm corrections, a KKT solve: the simulator's projection).
            max_iter: iteration limit.

        Returns:
            :class:`Projection`: q with every row below :attr:`tolerance`, the rows evaluated
            there, and the largest residual at the start.

        Raises:
            ClosureError: no convergence (naming the worst row).
            SingularPoseError: the Jacobian lost rank on the way.

        """
        q = np.array(q, dtype=float)
        rows = None
        initial = 0.0
        for k in range(max_iter):
            rows = self.evaluate(q, None, t, targets)
            error = np.abs(rows.phi)
            if k == 0:
                initial = float(error.max()) if self.nrows else 0.0
            if (error < self.tolerance).all():
                return Projection(q, rows, initial)
            step = self._newton_step(q, rows, metric)
            largest = np.abs(step).max()
            if largest > STEP_LIMIT:
                step *= STEP_LIMIT / largest
            q = pin.integrate(self.model, q, step)
        worst = int(np.argmax(np.abs(rows.phi) / self.tolerance))
        raise ClosureError(
            f"loop closure failed: constraint {self.labels[worst]} keeps a residual of {abs(rows.phi[worst]):.3e} "
            f"after {max_iter} Newton iterations at t = {t:.4f} s; the loop cannot assemble there"
        )

    def project_many(self, q: np.ndarray, targets: np.ndarray, max_iter: int = 50) -> tuple[np.ndarray, Rows]:
        """Newton onto Phi = 0 for a batch of samples at once (square systems, planar kinematics).

        Each sample iterates exactly as :meth:`project` would from its own start, and stops once
        all its rows are below :attr:`tolerance`; the batch shares the kinematic evaluations and
        the factorisations (one ``np.linalg.solve`` on (N, m, m) per iteration).

        Args:
            q: starting configurations (N, nq).
            targets: the scalar rows' targets per sample (N, n_scalars) or shared (n_scalars,).
            max_iter: iteration limit.

        Returns:
            (q, rows): the closed configurations (N, nq) and the rows evaluated there (J (N, m, nv)).

        Raises:
            ValueError: no convergence or a singular pose, naming the first failing sample.

        """
        q = np.array(q, dtype=float)
        if q.ndim != 2 or self._planar_ends is None or self.nrows != self.model.nv:
            raise ValueError("project_many needs a batch (N, nq) and a square planar constraint system")
        targets = np.broadcast_to(np.asarray(targets, dtype=float), (len(q), len(self.scalars)))
        rows = self.evaluate(q, None, 0.0, targets)
        for _ in range(max_iter):
            open_ = np.any(np.abs(rows.phi) >= self.tolerance, axis=1)
            if not np.any(open_):
                return q, rows
            try:
                step = np.linalg.solve(rows.jac[open_], -rows.phi[open_][:, :, None])[:, :, 0]
            except np.linalg.LinAlgError as err:
                raise SingularPoseError("closure Newton: singular pose, the constraint Jacobian lost rank") from err
            largest = np.max(np.abs(step), axis=1, keepdims=True)
            step *= np.minimum(1.0, STEP_LIMIT / np.maximum(largest, 1e-300))
            q[open_] += step  # nq == nv and every joint is Euclidean: integrate is a sum
            part = self.evaluate(q[open_], None, 0.0, targets[open_])
            rows.phi[open_], rows.jac[open_] = part.phi, part.jac
        k = int(np.argmax(np.any(np.abs(rows.phi) >= self.tolerance, axis=1)))
        worst = int(np.argmax(np.abs(rows.phi[k]) / self.tolerance))
        raise ClosureError(
            f"loop closure failed: constraint {self.labels[worst]} keeps a residual of {abs(rows.phi[k, worst]):.3e} "
            f"after {max_iter} Newton iterations (sample {k}, targets {np.round(targets[k], 6).tolist()}); "
            "the loop cannot assemble there"
        )

    def motion_many(self, q: np.ndarray, rates: np.ndarray, accelerations: np.ndarray, jac: np.ndarray | None = None):
        """(v, a, J) for a batch of configurations on the manifold (square system).

        Args:
            q: configurations (N, nq) on the manifold.
            rates: the scalar rows' rates (N, n_scalars) or (n_scalars,) [rad/s, m/s].
            accelerations: their second derivatives, same shapes [rad/s^2, m/s^2].
            jac: J at ``q`` (N, m, nv) if already known (from :meth:`project_many`).

        """
        jac = self.evaluate(q).jac if jac is None else jac
        n0, shape = self.n_constraint_rows, (len(q), self.nrows)
        rhs = np.zeros(shape)
        rhs[:, n0:] = rates
        v = _square_solve_many(jac, rhs, "velocity")
        rows = self.evaluate(q, v)
        rhs = -rows.drift
        rhs[:, n0:] += accelerations
        return v, _square_solve_many(rows.jac, rhs, "acceleration"), rows.jac

    def _newton_step(self, q: np.ndarray, rows: Rows, metric: str) -> np.ndarray:
        jac = rows.jac
        # a square system has one Newton step whatever the metric: no mass matrix needed
        if metric == "mass" and jac.shape[0] != jac.shape[1]:
            # M delta = J^T lambda, J delta = -phi: the KKT with M(q), no bias force and tau = 0
            self._mass_only(q)
            try:
                return self._kkt_solve(self._zero_v, jac, rows.phi)[0]
            except SingularPoseError:
                # M is singular (a point mass on its own joint axis: a foot with toe = heel has no
                # inertia about its ankle). The metric only picks which correction closes the rows:
                # the minimum-norm one below closes them as well.
                pass
        if jac.shape[0] == jac.shape[1]:
            try:
                return np.linalg.solve(jac, -rows.phi)
            except np.linalg.LinAlgError as err:
                raise SingularPoseError("closure Newton: singular pose, the constraint Jacobian lost rank") from err
        return np.linalg.lstsq(jac, -rows.phi, rcond=None)[0]

    def velocity(self, q: np.ndarray, t: float = 0.0, rates: Sequence[float] | None = None) -> np.ndarray:
        """V on the manifold: J v = -Phi_t (square), i.e. [J_c; J_s] v = [0; s_dot*].

        Args:
            q: configuration (on the manifold).
            t: time [s].
            rates: the scalar rows' rates instead of their ``rate``.

        """
        rows = self.evaluate(q, None, t)
        rhs = -rows.phi_t if rates is None else self._rhs_rates(rates)
        return _square_solve(rows.jac, rhs, "velocity")

    def _rhs_rates(self, rates: Sequence[float]) -> np.ndarray:
        rhs = np.zeros(self.nrows)
        rhs[self.n_constraint_rows :] = np.asarray(rates, dtype=float)
        return rhs

    def acceleration(
        self, q: np.ndarray, v: np.ndarray, t: float = 0.0, accelerations: Sequence[float] | None = None
    ) -> np.ndarray:
        """A on the manifold: J a = [0; s_ddot*] - J_dot v (square)."""
        rows = self.evaluate(q, v, t)
        rhs = -rows.drift
        if accelerations is not None:
            rhs[self.n_constraint_rows :] += np.asarray(accelerations, dtype=float)
        return _square_solve(rows.jac, rhs, "acceleration")

    def motion(
        self, q: np.ndarray, rates: Sequence[float], accelerations: Sequence[float], jac: np.ndarray | None = None
    ):
        """(v, a, J) on the manifold for given scalar-row rates and accelerations (square system).

        ``jac``: J at ``q`` if already known (e.g. ``rows.jac`` of :meth:`project_rows`).
        """
        jac = self.evaluate(q).jac if jac is None else jac
        v = _square_solve(jac, self._rhs_rates(rates), "velocity")
        rows = self.evaluate(q, v)
        rhs = -rows.drift
        rhs[self.n_constraint_rows :] += np.asarray(accelerations, dtype=float)
        return v, _square_solve(rows.jac, rhs, "acceleration"), rows.jac

    # ---- dynamics on the same rows
    def _kkt(self, q: np.ndarray, v: np.ndarray, tau: np.ndarray, jac: np.ndarray, gamma: np.ndarray):
        """Solve M a + h(q, v) = tau + J^T lambda, J a = -gamma in Pinocchio's C++; returns (a, lambda).

        M(q) from ``pin.crba`` and h(q, v) from ``pin.nonLinearEffects`` (cheaper than the
        ``computeAllTerms`` of ``forwardDynamics(q, v, ...)``), then :meth:`_kkt_solve`.

        Raises:
            ValueError: a singular system (the constraint Jacobian lost rank) or a non-finite answer.

        """
        pin.crba(self.model, self.data, q)  # the full symmetric M
        pin.nonLinearEffects(self.model, self.data, q, v)
        return self._kkt_solve(tau, jac, gamma)

    def _mass_only(self, q: np.ndarray) -> np.ndarray:
        """M(q) in ``data`` with a zero bias force h, for the KKT solves without dynamics; returns M."""
        mass = pin.crba(self.model, self.data, q)
        self.data.nle[:] = 0.0
        return mass

    def _kkt_solve(self, tau: np.ndarray, jac: np.ndarray, gamma: np.ndarray):
        """Solve M a + h = tau + J^T lambda, J a = -gamma with M and h already in ``data``: :func:`kkt_solve`."""
        return kkt_solve(self.model, self.data, tau, jac, gamma)

    def forward_dynamics(self, q: np.ndarray, v: np.ndarray, tau: np.ndarray, t: float = 0.0, mass_ready: bool = False):
        """Constrained forward dynamics, one KKT solve: returns (a, lambda, Rows).

        J^T lambda is the constraint force (generalised); M a + h = tau + J^T lambda, J a = -J_dot v.

        ``mass_ready``: ``data`` already holds M(q) of this very ``q`` (the last :meth:`impulse` was at
        ``q`` and nothing ran ``crba`` since): ``pin.crba`` is skipped, the answer is the same bits.
        """
        rows = self.evaluate(q, v, t)
        if mass_ready:
            pin.nonLinearEffects(self.model, self.data, q, v)
            a, lam = self._kkt_solve(tau, rows.jac, rows.drift)
        else:
            a, lam = self._kkt(q, v, tau, rows.jac, rows.drift)
        return a, lam, rows

    def impulse(self, q: np.ndarray, v_minus: np.ndarray, t: float = 0.0, rows: Rows | None = None):
        """Inelastic impact / M-orthogonal velocity projection onto J v + Phi_t = 0.

        M (v+ - v-) = J^T Lambda, J v+ = -Phi_t: the KKT with M(q), no bias force and
        tau = M v-, so that its "acceleration" is v+.

        Returns:
            (v_plus, Lambda): the velocity after and the impulse per row [N.s, N.m.s].

        """
        rows = self.evaluate(q, None, t) if rows is None else rows
        mass = self._mass_only(q)
        return self._kkt_solve(mass.dot(v_minus), rows.jac, rows.phi_t)


def kkt_solve(model: pin.Model, data: pin.Data, tau: np.ndarray, jac: np.ndarray, gamma: np.ndarray):
    """Solve M a + h = tau + J^T lambda, J a = -gamma with M and h already in ``data``; returns (a, lambda).

    ``pin.forwardDynamics`` with the rows ``jac`` as its constraint Jacobian: a Cholesky
    factorisation of M (the upper triangle of ``data.M``) and of J M^-1 J^T (J must have full row
    rank). Every KKT solve of the package goes through here: the simulator's accelerations and
    impacts, the lockstep walks and the floor's contact QP (with H for M and g for h - tau).

    Args:
        model: the Pinocchio model.
        data: its data, holding M in ``data.M`` and h in ``data.nle``.
        tau: generalised force (nv,).
        jac: the rows' Jacobian J (m, nv).
        gamma: the rows' right-hand side: J a = -gamma (m,).

    Returns:
        (a (nv,), lambda (m,)), both new arrays.

    Raises:
        ValueError: a singular system (the constraint Jacobian lost rank) or a non-finite answer.

    """
    try:
        a = pin.forwardDynamics(model, data, tau, jac, gamma, 0.0)  # a new array
    except RuntimeError as err:
        raise SingularPoseError(f"KKT system singular: the constraint Jacobian lost rank: {err}") from err
    lam = data.lambda_c.copy()
    if not math.isfinite(a.dot(a) + lam.dot(lam)):  # a NaN or an infinity anywhere shows in the sum
        raise SingularPoseError("KKT solve returned non-finite values: the constraint Jacobian lost rank")
    return a, lam


def split_torques(tau: np.ndarray, s_matrix: np.ndarray, jac: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Solve tau = S^T u + J^T lambda (square) for (u, lambda).

    Raises:
        ValueError: when [S^T J^T] is not square or singular (the actuators cannot hold the motion).

    """
    mat = np.hstack((s_matrix.T, jac.T))
    if mat.shape[0] != mat.shape[1]:
        raise ValueError(f"split: {mat.shape[1]} unknowns for nv = {mat.shape[0]}; the system must be square")
    try:
        x = np.linalg.solve(mat, tau)
    except np.linalg.LinAlgError as err:
        raise SingularPoseError("split: [S^T J_c^T] is singular at this pose") from err
    if not np.all(np.isfinite(x)):
        raise SingularPoseError("split: the actuator and constraint forces are not finite")
    ns = s_matrix.shape[0]
    return x[:ns], x[ns:]


def _square_solve_many(matrix: np.ndarray, rhs: np.ndarray, what: str) -> np.ndarray:
    """Solve a batch of square systems (N, n, n) x = (N, n), with the errors of :func:`_square_solve`."""
    if matrix.shape[-2] != matrix.shape[-1]:
        raise ValueError(
            f"{what}: constraints plus prescriptions give {matrix.shape[-2]} rows for nv = {matrix.shape[-1]}; "
            "prescribe exactly the free coordinates"
        )
    try:
        sol = np.linalg.solve(matrix, rhs[..., None])[..., 0]
    except np.linalg.LinAlgError as err:
        raise SingularPoseError(f"{what}: singular pose, the matrix lost rank") from err
    if not np.all(np.isfinite(sol)):
        raise SingularPoseError(f"{what}: singular pose, the solution is not finite")
    return sol


def _square_solve(matrix: np.ndarray, rhs: np.ndarray, what: str) -> np.ndarray:
    if matrix.shape[0] != matrix.shape[1]:
        raise ValueError(
            f"{what}: constraints plus prescriptions give {matrix.shape[0]} rows for nv = {matrix.shape[1]}; "
            "prescribe exactly the free coordinates"
        )
    try:
        sol = np.linalg.solve(matrix, rhs)
    except np.linalg.LinAlgError as err:
        raise SingularPoseError(f"{what}: singular pose, the constraint Jacobian lost rank") from err
    if not np.all(np.isfinite(sol)):
        raise SingularPoseError(f"{what}: singular pose, the solution is not finite")
    return sol


# --------------------------------------------------------------------------- frame kinematics
def frame_jacobian(model: pin.Model, data: pin.Data, q: np.ndarray, frame: int) -> np.ndarray:
    """The 6 x nv LOCAL_WORLD_ALIGNED Jacobian of a frame (linear, then angular rows)."""
    return pin.computeFrameJacobian(model, data, q, frame, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED).reshape(6, model.nv)
