"""Exact planar kinematics of constraint points, vectorised: positions, Jacobians and drifts in a few products.

PASIBOT is planar: every joint turns about y or slides in the x-z plane, and every joint
placement is a rotation about y. So the pitch of every frame is linear in q,
phi = a0 + A q, and the world (x, z) of a point is a sum of constant vectors, each turned by
the pitch of the frame that carries it (and, for a slider, times its coordinate):

    p(q) = sum_k R(phi_k(q)) c_k [q_m(k)],   R(phi) = [[cos, -sin], [sin, cos]].

Collecting the terms of every constraint end once turns the residual, the Jacobian and the
drift J_dot v (the second time derivative at zero joint acceleration) into a handful of small
matrix products (:class:`PlanarRowBlocks`), instead of one Python call per body. This is the same model Pinocchio
evaluates (``tests/test_constraints.py`` checks both against each other and against finite
differences); Pinocchio's C++ stays in charge of everything dynamic (rnea, crba).

Pitch is counter-clockwise seen from the robot's right side (about -y). Units: SI, rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from pasibot_pin.errors import ParameterError


def _pitch(rotation: np.ndarray) -> float:
    return math.atan2(rotation[2, 0], rotation[0, 0])


def _is_planar_rotation(rotation: np.ndarray) -> bool:
    return abs(rotation[1, 1] - 1.0) < 1e-12 and abs(rotation[0, 1]) < 1e-12 and abs(rotation[2, 1]) < 1e-12


class PlanarKinematics:
    """The frames of a planar Pinocchio model as linear pitches and sums of turned vectors.

    Args:
        model: a Pinocchio model whose joints are revolute about +-y, prismatic along x or z,
            or a composite of those (the planar floating hip), with placements turning about y.

    Raises:
        ValueError: a joint or placement that is not planar (use the general path instead).

    """

    def __init__(self, model: pin.Model):
        nv = model.nv
        self.nv = nv
        # per joint: pitch (a0, A) and the list of position terms (term indices)
        self.terms_a0: list[float] = []
        self.terms_A: list[np.ndarray] = []
        self.terms_c: list[np.ndarray] = []
        self.terms_slider: list[int] = []  # velocity index multiplying the term, or -1
        self.joint_a0 = np.zeros(model.njoints)
        self.joint_A = np.zeros((model.njoints, nv))
        self.joint_terms: list[list[int]] = [[] for _ in range(model.njoints)]
        for j in range(1, model.njoints):
            parent = model.parents[j]
            placement = model.jointPlacements[j]
            if not _is_planar_rotation(placement.rotation):
                raise ParameterError(f"joint {model.names[j]!r}: its placement does not turn about y")
            a0, A = self.joint_a0[parent], self.joint_A[parent].copy()
            terms = list(self.joint_terms[parent])
            terms.append(self._term(a0, A, placement.translation[[0, 2]], -1))
            a0 += _pitch(placement.rotation)
            joint = model.joints[j]
            subjoints = joint.extract().joints if joint.shortname() == "JointModelComposite" else [joint]
            index = joint.idx_v
            for sub in subjoints:
                a0, A = self._apply(sub, a0, A, terms, index, model.names[j])
                index += 1
            self.joint_a0[j], self.joint_A[j], self.joint_terms[j] = a0, A, terms
        self.terms_a0_arr = np.array(self.terms_a0)
        self.terms_A_arr = np.array(self.terms_A).reshape(-1, nv)
        self.terms_c_arr = np.array(self.terms_c).reshape(-1, 2)
        self.terms_slider_arr = np.array(self.terms_slider, dtype=int)

    def _term(self, a0: float, A: np.ndarray, c: np.ndarray, slider: int) -> int:
        self.terms_a0.append(float(a0))
        self.terms_A.append(np.array(A, dtype=float))
        self.terms_c.append(np.array(c, dtype=float))
        self.terms_slider.append(int(slider))
        return len(self.terms_a0) - 1

    def _apply(self, sub, a0: float, A: np.ndarray, terms: list[int], index: int, name: str):
        kind = sub.shortname()
        if kind in ("JointModelRevoluteUnaligned", "JointModelRY"):
            axis = sub.extract().axis if kind == "JointModelRevoluteUnaligned" else np.array([0.0, 1.0, 0.0])
            if abs(abs(axis[1]) - 1.0) > 1e-12:
                raise ParameterError(f"joint {name!r} does not turn about y")
            A = A.copy()
            A[index] -= axis[1]  # about +y by q is a pitch of -q (pitch is about -y)
            return a0, A
        if kind in ("JointModelPX", "JointModelPZ"):
            c = np.array([1.0, 0.0]) if kind == "JointModelPX" else np.array([0.0, 1.0])
            terms.append(self._term(a0, A, c, index))
            return a0, A
        raise ParameterError(f"joint {name!r} of kind {kind} is not planar")

    def ends(self, joints: np.ndarray, translations: np.ndarray, rotations: np.ndarray) -> PlanarEnds:
        """Precompute the points fixed at ``translations`` on ``joints`` (and their frames' pitch)."""
        return PlanarEnds(self, joints, translations, rotations)


class PlanarEnds:
    """Points (with their frames' pitch) fixed on joints of a :class:`PlanarKinematics`."""

    def __init__(self, kin: PlanarKinematics, joints: np.ndarray, translations: np.ndarray, rotations: np.ndarray):
        nv = kin.nv
        n_ends = len(joints)
        used: dict[int, int] = {}
        a0: list[float] = []
        A: list[np.ndarray] = []
        c: list[np.ndarray] = []
        slider: list[int] = []

        def use(term: int) -> int:
            if term not in used:
                used[term] = len(a0)
                a0.append(kin.terms_a0[term])
                A.append(kin.terms_A[term])
                c.append(kin.terms_c[term])
                slider.append(kin.terms_slider[term])
            return used[term]

        rows: list[list[int]] = []
        self.pitch_a0 = np.zeros(n_ends)
        self.pitch_A = np.zeros((n_ends, nv))
        for e, (joint, t, rot) in enumerate(zip(joints, translations, rotations)):
            joint = int(joint)
            idx = [use(k) for k in kin.joint_terms[joint]]
            # the end's own offset, turned by its joint's pitch (a term of its own, not shared)
            a0.append(kin.joint_a0[joint])
            A.append(kin.joint_A[joint])
            c.append(np.array(t, dtype=float)[[0, 2]])
            slider.append(-1)
            idx.append(len(a0) - 1)
            rows.append(idx)
            self.pitch_a0[e] = kin.joint_a0[joint] + _pitch(rot)
            self.pitch_A[e] = kin.joint_A[joint]
        self.a0 = np.array(a0, dtype=float)
        self.A = np.array(A, dtype=float).reshape(-1, nv)
        self.cx = np.array([v[0] for v in c])
        self.cz = np.array([v[1] for v in c])
        self.slider = np.array(slider, dtype=int)
        self.has_slider = bool(np.any(self.slider >= 0))
        self.S = np.zeros((n_ends, len(a0)))
        for e, idx in enumerate(rows):
            self.S[e, idx] = 1.0


@dataclass(frozen=True)
class PhaseColumns:
    """The moving terms laid out as the phase columns of a one-sample evaluation.

    Terms turned by the same pitch row A (the points of one body) share one phase exp(i A q):
    the plain terms are grouped by their distinct rows. A term a slider scales, C exp(i A q) q_s
    (the pantograph's slide), takes two columns of its own: phase e q_s (its value, with i A as
    its Jacobian's row) and phase e (the product rule: e_s as its Jacobian's row, no value). The
    columns are the distinct plain pitches, then the slid terms' ``a`` columns, then their ``b``
    columns. Built by :meth:`PlanarRowBlocks.phase_columns`; both one-sample paths
    (:class:`PlanarRowBlocks` and :class:`~pasibot_pin.constraints.evaluation.RowSystem`) use it.

    Attributes:
        turn: C = c exp(i a0) of each moving term (K,), complex [m].
        plain: indices of the terms no slider scales.
        slid: indices of the terms a slider scales.
        pitches: the distinct pitch rows A of the plain terms (P, nv).
        group: each plain term's row in ``pitches``.
        slider: each slid term's slider coordinate (a velocity index).
        slid_A: the slid terms' pitch rows (S, nv).
        slid_slide: the slid terms' rows e_s (S, nv).

    """

    turn: np.ndarray
    plain: np.ndarray
    slid: np.ndarray
    pitches: np.ndarray
    group: np.ndarray
    slider: np.ndarray
    slid_A: np.ndarray
    slid_slide: np.ndarray

    @property
    def exponents(self) -> np.ndarray:
        """The rows A of every column (columns, nv): the phases are exp(i A q)."""
        return np.vstack((self.pitches, self.slid_A, self.slid_A))

    @property
    def slid_a(self) -> np.ndarray:
        """The columns of phase e q_s (one per slid term)."""
        return np.arange(len(self.pitches), len(self.pitches) + len(self.slid))

    @property
    def slid_b(self) -> np.ndarray:
        """The columns of phase e (one per slid term)."""
        return self.slid_a + len(self.slid)


class FloatingForm(NamedTuple):
    """Rows of points that ride a planar floating base, as a rigid motion of its body.

    With the base's sliders ``base`` (velocity indices, their Jacobian columns constant) and
    its pitch ``pitch``, every row is

        P(q) = fixed + slide q_base + exp(i turn q_pitch) B(q_body),

    B being the rows at the same body coordinates with the base at its origin, unpitched, less
    ``fixed``. So P at any base pose follows from B in a few complex products, and so does the
    Jacobian: ``slide`` on the sliders, i turn exp(i turn q_pitch) B on the pitch, and
    exp(i turn q_pitch) J_B on the body (:meth:`PlanarRowBlocks.floating_form`).

    Attributes:
        base: the sliders' velocity indices.
        pitch: the pitch's velocity index.
        turn: +1 or -1, the sign of the pitch in every point's angle.
        fixed: (n,) complex [m].
        slide: (n, len(base)) complex, the sliders' Jacobian columns [-].

    """

    base: tuple[int, ...]
    pitch: int
    turn: float
    fixed: np.ndarray
    slide: np.ndarray


class PlanarRowBlocks:
    """The point-coincidence and pitch rows of a constraint system, as complex products.

    A point's world (x, z) is the complex number x + i z, so turning a vector c by phi is
    c exp(i phi) and its derivative is i c exp(i phi). Each point-coincidence row pair is one
    complex row of p_a - p_b, built by the signed selection ``D`` of the ends' terms. Pitch rows
    are linear in q: their Jacobian is constant. Every array may carry leading batch axes
    (q of shape (..., nv)), so many samples are evaluated in one call.

    Args:
        ends: the constraint ends (:class:`PlanarEnds`).
        pairs: (a, b) end indices of each point coincidence (a weld's position rows too); b = -1
            gives the point a itself (its world position, Jacobian and drift).
        pitch_pairs: (a, b) end indices of each weld's pitch row (b may be -1: none).

    Attributes:
        moving_c, moving_a0, moving_AT: the lever (complex), angle offset and pitch map (nv, K)
            of each term some joint turns (what a table of one-sample rows is built from).
        has_sliders: some moving term is scaled by a prismatic coordinate.

    """

    def __init__(self, ends: PlanarEnds, pairs: list[tuple[int, int]], pitch_pairs: list[tuple[int, int]]):
        self.c = ends.cx + 1j * ends.cz
        self.a0, self.A = ends.a0, ends.A
        self.slider = ends.slider
        diff = [ends.S[a] - (ends.S[b] if b >= 0 else 0.0) for a, b in pairs]
        self.D = np.array(diff).reshape(len(pairs), len(self.a0))
        pitch_a0, pitch_A = [], []
        for a, b in pitch_pairs:
            a0 = ends.pitch_a0[a] - (ends.pitch_a0[b] if b >= 0 else 0.0)
            A = ends.pitch_A[a] - (ends.pitch_A[b] if b >= 0 else 0.0)
            pitch_a0.append(a0)
            pitch_A.append(A)
        self.pitch_a0 = np.array(pitch_a0, dtype=float)
        self.pitch_A = np.array(pitch_A, dtype=float).reshape(len(pitch_pairs), self.A.shape[1])
        nv = self.A.shape[1]
        slide = np.zeros((len(self.a0), nv))  # d(slider factor)/dq: a term is c exp(i phi) q[slider], or c exp(i phi)
        for t, col in enumerate(self.slider):
            if col >= 0:
                slide[t, col] = 1.0
        # Terms that no joint turns (A = 0: the root's sliders, constant offsets) are constant or linear
        # in q: they are summed once into ``fixed_rows`` + ``fixed_jac`` q; the others ("moving") are evaluated.
        fixed = ~np.any(self.A != 0.0, axis=1)
        const = self.c * np.exp(1j * self.a0)
        plain = fixed & (self.slider < 0)
        self.fixed_rows = self.D[:, plain] @ const[plain]  # (n,) complex
        self.fixed_jac = self.D[:, fixed & ~plain] @ (const[fixed & ~plain, None] * slide[fixed & ~plain])  # (n, nv)
        moving = ~fixed
        self.D_moving = self.D[:, moving]
        self.moving_c, self.moving_a0 = self.c[moving], self.a0[moving]
        self.moving_AT = self.A[moving].T.copy()
        self._iAT = 1j * self.moving_AT
        self.moving_slide_T = slide[moving].T.copy()
        self._unit = 1.0 - slide[moving].sum(axis=1)  # the factor of a moving term without a slider
        self.has_sliders = bool(np.any(slide[moving]))
        self._DT = self.D_moving.T.astype(complex)  # complex copy: numpy would cast on every product
        self._pitch_AT = self.pitch_A.T.copy()
        # terms turned by the same pitch row (the points of one body) share exp(i A q): the phases are
        # computed once per distinct row, and c exp(i a0) of each term is a constant factor
        rows, group = np.unique(self.moving_AT.T, axis=0, return_inverse=True)
        self._phase_AT = rows.T.copy()  # (nv, distinct pitches)
        self._group = group.reshape(-1)
        self._c_turned = self.moving_c * np.exp(1j * self.moving_a0)
        self._w: np.ndarray | None = None  # the one-sample tables, built at the first one-sample call

    def floating_form(self, pitch: int) -> FloatingForm | None:
        """The rows as a rigid motion of a floating base whose pitch is coordinate ``pitch`` (:class:`FloatingForm`).

        ``None`` unless every term some joint turns is turned by the pitch with one sign, and
        the terms no joint turns are constants or the base's sliders (which turn nothing and
        scale no moving term).
        """
        if not len(self.moving_c):
            return None
        turn = self.moving_AT[pitch]
        base = np.flatnonzero(np.any(self.fixed_jac != 0.0, axis=0))
        if abs(turn[0]) != 1.0 or not np.all(turn == turn[0]) or pitch in base:
            return None
        if np.any(self.moving_AT[base] != 0.0) or np.any(self.moving_slide_T[base] != 0.0):
            return None
        return FloatingForm(
            tuple(int(i) for i in base), pitch, float(turn[0]), self.fixed_rows.copy(), self.fixed_jac[:, base].copy()
        )

    def phase_columns(self) -> PhaseColumns:
        """The moving terms as the phase columns of a one-sample evaluation (:class:`PhaseColumns`)."""
        turn = self.moving_c * np.exp(1j * self.moving_a0)
        slid = np.flatnonzero(self.moving_slide_T.any(axis=0))
        plain = np.setdiff1d(np.arange(len(turn)), slid)
        pitches, group = np.unique(self.moving_AT.T[plain], axis=0, return_inverse=True)
        return PhaseColumns(
            turn=turn,
            plain=plain,
            slid=slid,
            pitches=pitches,
            group=group.reshape(-1),
            slider=np.argmax(self.moving_slide_T[:, slid], axis=0),
            slid_A=self.moving_AT.T[slid],
            slid_slide=self.moving_slide_T.T[slid],
        )

    def _one_sample_tables(self) -> None:
        """Tables of :meth:`_evaluate_one`: each row's terms summed per phase column (:meth:`phase_columns`).

        The rows are W e (W: each term's D C, summed over the terms of one column; e the columns'
        phases) and the Jacobian (W * e) B, B each column's row (i A, or e_s for a ``b`` column).
        """
        cols = self.phase_columns()
        plain, slid, turn = cols.plain, cols.slid, cols.turn
        weights = np.zeros((self.D.shape[0], len(cols.pitches)), dtype=complex)
        np.add.at(weights.T, cols.group, (self.D_moving[:, plain] * turn[plain]).T)
        slid_weights = self.D_moving[:, slid] * turn[slid]
        self._w = np.hstack((weights, slid_weights, slid_weights))  # (n, columns)
        self._exp_A = cols.exponents  # (columns, nv): e = exp(i A q)
        self._b = np.vstack((1j * cols.pitches, 1j * cols.slid_A, cols.slid_slide)).astype(complex)
        self._value = np.concatenate((np.ones(len(cols.pitches) + len(slid)), np.zeros(len(slid)))).astype(complex)
        self._slid_a = cols.slid_a
        self._slid_index = cols.slider

    def _evaluate_one(self, q: np.ndarray):
        """:meth:`evaluate` of one sample without its drift, in a dozen numpy calls."""
        rows, jac = self.rows_and_jacobian(q)
        return rows, jac, None, q.dot(self._pitch_AT) + self.pitch_a0

    def rows_and_jacobian(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The point rows P (n,) and their Jacobian (n, nv) of one sample, complex (no drift, no pitch rows)."""
        if self._w is None:
            self._one_sample_tables()
        phase = np.exp(1j * self._exp_A.dot(q))
        if len(self._slid_a):
            phase[self._slid_a] *= q[self._slid_index]
        weighted = self._w * phase
        rows = weighted.dot(self._value) + self.fixed_jac.dot(q) + self.fixed_rows
        return rows, weighted.dot(self._b) + self.fixed_jac

    def _turned(self, q: np.ndarray):
        """(c exp(i phi), the slider factor or None) of every moving term."""
        angle = q @ self._phase_AT
        phase = np.empty(angle.shape, dtype=complex)
        np.cos(angle, out=phase.real)
        np.sin(angle, out=phase.imag)
        turned = self._c_turned * phase[..., self._group]
        return turned, (q @ self.moving_slide_T + self._unit) if self.has_sliders else None

    def terms(self, q: np.ndarray, v: np.ndarray | None = None):
        """The moving terms' values (..., K), Jacobian transposed (..., nv, K) and drift (..., K) or None, complex.

        A term is c exp(i phi) [times a slider coordinate]; the rows are ``D_moving`` times these,
        plus ``fixed_rows + fixed_jac q`` (whose Jacobian is ``fixed_jac`` and drift zero).
        """
        turned, factor = self._turned(q)
        if factor is not None:
            value = turned * factor
            jac_t = self._iAT * value[..., None, :] + self.moving_slide_T * turned[..., None, :]
        else:
            value = turned
            jac_t = self._iAT * value[..., None, :]
        drift = None
        if v is not None:
            w = v @ self.moving_AT
            drift = value * (-w * w)
            if factor is not None:
                drift += 2j * turned * w * (v @ self.moving_slide_T)
        return value, jac_t, drift

    def positions(self, q: np.ndarray) -> np.ndarray:
        """The rows P (..., n), complex x + i z [m], without their Jacobian."""
        turned, factor = self._turned(q)
        value = turned if factor is None else turned * factor
        return value @ self._DT + q @ self.fixed_jac.T + self.fixed_rows

    def motion(self, q: np.ndarray, v: np.ndarray, a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The rows P and their second time derivative J a + J_dot v (..., n), complex [m, m/s^2].

        Directional derivatives of every term: no Jacobian is formed, so a batch costs O(N K n).
        """
        turned, factor = self._turned(q)
        value = turned if factor is None else turned * factor
        w, alpha = v @ self.moving_AT, a @ self.moving_AT
        acc = value * (1j * alpha - w * w)
        if factor is not None:
            acc += turned * (a @ self.moving_slide_T) + 2j * turned * w * (v @ self.moving_slide_T)
        rows = value @ self._DT + q @ self.fixed_jac.T + self.fixed_rows
        return rows, acc @ self._DT + a @ self.fixed_jac.T

    def directional(self, q: np.ndarray, directions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The rows P (N, n) and their derivatives J d along several directions d at each sample (N, n, d), complex.

        Args:
            q: configurations (N, nv).
            directions: (N, nv, d): the directions at each sample, as columns.

        """
        turned, factor = self._turned(q)
        value = turned if factor is None else turned * factor
        count, nv, d = directions.shape
        flat = np.swapaxes(directions, 1, 2).reshape(count * d, nv)  # one product for every sample's directions
        change = (value[:, None, :] * (1j * (flat @ self.moving_AT)).reshape(count, d, -1)).reshape(count * d, -1)
        if factor is not None:
            change += (turned[:, None, :] * (flat @ self.moving_slide_T).reshape(count, d, -1)).reshape(count * d, -1)
        rows = value @ self._DT + q @ self.fixed_jac.T + self.fixed_rows
        along = (change @ self._DT + flat @ self.fixed_jac.T).reshape(count, d, -1)
        return rows, np.swapaxes(along, 1, 2)

    def evaluate(self, q: np.ndarray, v: np.ndarray | None = None):
        """Complex point rows P (..., n), their Jacobian (..., n, nv), drift (..., n) or None, pitch rows (..., p)."""
        if v is None and np.ndim(q) == 1:
            if self._w is None:
                self._one_sample_tables()
            return self._evaluate_one(np.asarray(q, dtype=float))
        value, jac_t, term_drift = self.terms(q, v)
        rows = value @ self._DT + q @ self.fixed_jac.T + self.fixed_rows
        jac = np.swapaxes(jac_t @ self._DT, -1, -2) + self.fixed_jac
        drift = None if term_drift is None else term_drift @ self._DT
        pitch = q @ self._pitch_AT + self.pitch_a0
        return rows, jac, drift, pitch
