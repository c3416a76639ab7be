"""The constraint rows of a robot evaluated: residual, Jacobian, drift and Phi_t, one sample or a batch.

:class:`RowSystem` lays out the rows of a set of Pinocchio constraint models plus scalar rows
(:mod:`.rows`) on one model, and evaluates them in one kinematic pass: with the exact planar
kinematics (:mod:`.planar`: a few complex products; a batch over leading axes of q) or with
Pinocchio's joint Jacobians and classical accelerations (the reference).
:class:`~pasibot_pin.constraints.system.ConstraintSystem` adds the solves on these rows.

Units: SI, angles [rad].
"""

from __future__ import annotations

import copy
import math
from collections.abc import Sequence
from typing import TypeVar

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

from pasibot_pin.constraints.pinocchio_models import anchor_points, is_weld, planar_rows
from pasibot_pin.constraints.planar import PlanarEnds, PlanarRowBlocks
from pasibot_pin.constraints.rows import (
    ANGLE_TOL,
    RELATIVE_TOL,
    CoordinateRow,
    PitchRow,
    Rows,
    ScalarRow,
    cross_rows,
    planar_kinematics,
    wrap_angle,
)
from pasibot_pin.errors import ParameterError

_S = TypeVar("_S", bound="RowSystem")


class RowSystem:
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
            raise ParameterError(f"the constraint system needs nq == nv (revolute/prismatic joints), got {model.nq}")
        self.model, self.data = model, data
        self.cmodels = list(cmodels)
        self.length_scale = float(length_scale)
        self._zero_v = np.zeros(model.nv)
        if kinematics not in ("planar", "pinocchio"):
            raise ParameterError(f"parameter 'kinematics' must be 'planar' or 'pinocchio', got {kinematics!r}")
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
        self.scalars = list(scalars)
        self.nrows = self.n_constraint_rows + len(self.scalars)
        self._set_ends(self._lay_out_scalar_rows())
        self.tolerance = self._row_tolerances()
        self.labels = self._constraint_labels + [s.name for s in self.scalars]
        self._coef: np.ndarray | None = None  # the one-sample tables' coefficients (planar rows)
        if self._planar_ends is not None:
            self._planar_tables(self._planar_ends)

    def _lay_out_scalar_rows(self) -> list[tuple[int, np.ndarray, np.ndarray]]:
        """The coordinate rows' coefficients and the pitch rows' frames; returns every end (joint, placement)."""
        model, nv, row = self.model, self.model.nv, self.n_constraint_rows
        ends = list(self._model_ends)
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
        self._lin = np.array(lin).reshape(-1, nv)
        self._lin_rows = np.array(lin_rows, dtype=int)
        self._pitch_rows = np.array(pitch_rows, dtype=int)
        self._pitch_ends = np.array(pitch_ends, dtype=int)
        self._offset = np.array([s.offset for s in self.scalars], dtype=float)
        self._rate = np.array([s.rate for s in self.scalars], dtype=float)
        self._is_pitch = np.array([isinstance(s, PitchRow) for s in self.scalars], dtype=bool)
        return ends

    def _set_ends(self, ends: list[tuple[int, np.ndarray, np.ndarray]]) -> None:
        """Every row end's joint, placement and the coordinates that move it (a mask over v)."""
        model, nv = self.model, self.model.nv
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

    def _row_tolerances(self) -> np.ndarray:
        """Newton's tolerance per row: lengths relative to L, angles absolute."""
        tol = np.full(self.nrows, RELATIVE_TOL * self.length_scale)
        tol[self._weld_rows] = ANGLE_TOL
        for k, s in enumerate(self.scalars):
            if isinstance(s, PitchRow) or self._angular(s):
                tol[self.n_constraint_rows + k] = ANGLE_TOL
        return tol

    def _planar_tables(self, ends: PlanarEnds) -> None:
        """The exact planar path's tables: the rows' blocks, the linear part of J and Phi, the picking matrix."""
        nv, row = self.model.nv, self.n_constraint_rows
        pairs = [(2 * c, 2 * c + 1) for c in range(len(self.cmodels))]
        pitch_pairs = [(int(a), int(b)) for a, b in zip(self._weld_a, self._weld_b)]
        pitch_pairs += [(int(e), -1) for e in self._pitch_ends]
        self._blocks = PlanarRowBlocks(ends, pairs, pitch_pairs)
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
        cols = blocks.phase_columns()
        big_c, plain, slid = cols.turn, cols.plain, cols.slid
        px, pz = self._pick_T[0::2], self._pick_T[1::2]
        weights = np.empty_like(self._pick_T)
        weights[0::2] = big_c.real[:, None] * px + big_c.imag[:, None] * pz
        weights[1::2] = -big_c.imag[:, None] * px + big_c.real[:, None] * pz
        # terms turned by the same pitch share one phase: their picked constants add up
        merged = np.zeros((2 * len(cols.pitches), self.nrows))
        np.add.at(merged, 2 * cols.group, weights[0::2][plain])
        np.add.at(merged, 2 * cols.group + 1, weights[1::2][plain])
        # a slid term's two columns (e q_s and e) both carry its plain coefficients; the e column's
        # Jacobian row is e_s (the product rule), no value, and 2 i w v_s for its drift (filled per call)
        slid_weights = np.stack((weights[0::2][slid], weights[1::2][slid]), axis=1).reshape(2 * len(slid), self.nrows)
        self._weights_T = np.vstack((merged, slid_weights, slid_weights))
        self._phase_T = np.ascontiguousarray(cols.exponents.T)  # (nv, columns): w = A v
        self._exponent = 1j * self._phase_T  # exp(q . exponent) = exp(i A q)
        self._slid_a, self._slid_b = cols.slid_a, cols.slid_b  # the e q_s and the e columns
        self._slid_index = cols.slider  # each slid term's slider coordinate
        # rows: i A^T (the Jacobian), 1 (the value), then w^2 (the drift, filled per call: a buffer)
        jac_coef = 1j * self._phase_T
        jac_coef[:, self._slid_b] = cols.slid_slide.T
        value_coef = np.ones(self._phase_T.shape[1])
        value_coef[self._slid_b] = 0.0
        self._coef = np.ascontiguousarray(np.vstack((jac_coef, value_coef, np.zeros(len(value_coef)))))
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
    def with_scalars(self: _S, scalars: Sequence[ScalarRow]) -> _S:
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
        targets: ArrayLike | None = None,
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
                vp = vel[:, :3] + cross_rows(w, self._trans)
                ap = (rot @ (acc[:, :3] + cross_rows(acc[:, 3:], self._trans) + cross_rows(w, vp))[:, :, None])[:, :, 0]
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
                phi[wr] = wrap_angle(pitch[wa] - pitch[wb])
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
            ds[..., self._is_pitch] = wrap_angle(ds[..., self._is_pitch])
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
        coef = self._coef
        if coef is not None:
            if q.ndim == 1:
                return self._evaluate_one(q, v, t, targets, coef)
            if q.ndim == 2:
                return self._evaluate_batch(q, v, t, targets, coef)
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
            phi[..., self._wrapped] = wrap_angle(phi[..., self._wrapped])
        return Rows(phi, jac, drift, np.broadcast_to(self._phi_t, phi.shape).copy())

    def _evaluate_one(self, q, v, t, targets, coef: np.ndarray) -> Rows:
        """:meth:`_evaluate_planar` for one sample in a dozen numpy calls (the simulator's inner loop).

        The terms' phases e = exp(i A q), times the rows of one coefficient array (i A^T for the
        Jacobian, 1 for the value, w^2 for minus the drift, w = A v), give J^T, the point rows and
        the drift in one product with the picking matrix (which holds the terms' constants,
        :meth:`_one_sample_tables`).
        """
        # ndarray.dot rather than @: the same product with less call overhead on these small arrays
        nv = self.model.nv
        phase = np.exp(q.dot(self._exponent))  # exp(i A q); the real part of the exponent is exactly 0
        slid_a, slid_b = self._slid_a, self._slid_b
        if len(slid_a):
            phase[slid_a] *= q[self._slid_index]
        if v is None:
            out = (coef[: nv + 1] * phase).view(float).dot(self._weights_T) + self._constant[: nv + 1]
            drift = np.zeros(self.nrows)
        else:
            w = v.dot(self._phase_T)
            np.multiply(w, w, out=coef[nv + 1])  # the drift of a term is -w^2 times its value
            if len(slid_b):
                coef[nv + 1, slid_b] = -2j * w[slid_b] * v[self._slid_index]
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

    def _evaluate_batch(self, q, v, t, targets, coef: np.ndarray) -> Rows:
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
        slid_a, slid_b = self._slid_a, self._slid_b
        if len(slid_a):  # a slid term's e q_s column; its e column has no value (coef[nv] is 0 there)
            phase[:, slid_a] *= q[:, self._slid_index]
        weights = self._weights_T
        n_phase = phase.shape[1]
        jac_t = (coef[:nv] * phase[:, None, :]).view(float).reshape(n * nv, 2 * n_phase) @ weights
        jac_t = jac_t.reshape(n, nv, self.nrows) + self._constant[:nv]
        value = phase * coef[nv] if len(slid_a) else phase
        phi = value.view(float) @ weights + (q @ self._linear_T + self._constant[nv])
        if v is None:
            drift = np.zeros((n, self.nrows))
        else:
            w = v @ self._phase_T
            drift_coef = w * w + 0j
            if len(slid_b):  # the product rule's 2 i w v_s on a slid term's e column
                drift_coef[:, slid_b] = -2j * w[:, slid_b] * v[:, self._slid_index]
            drift = (drift_coef * phase).view(float) @ weights
            np.negative(drift, out=drift)
        n0 = self.n_constraint_rows
        if targets is None:
            if t:
                phi -= t * self._rate_all
        else:
            phi[:, n0:] += self._offset - np.asarray(targets, dtype=float)
        if len(self._wrapped):
            phi[:, self._wrapped] = wrap_angle(phi[:, self._wrapped])
        # J transposed in memory (a column-major view per sample)
        return Rows(phi, np.swapaxes(jac_t, 1, 2), drift, np.broadcast_to(self._phi_t, phi.shape).copy())

    def residual(self, q: np.ndarray, t: float = 0.0, targets: ArrayLike | None = None) -> np.ndarray:
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
