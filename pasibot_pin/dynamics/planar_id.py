"""Batched planar inverse dynamics of the tree: joint torques and joint reactions, no per-sample call.

PASIBOT moves in the x-z plane and every joint turns about y (or slides in the plane, the
floating hip), so a body's inertial wrench reduces to the in-plane force and the moment about y:

    f_b = m_b (a_cb - g),   n_b = I_yy,b alpha_b   (about the COM, counter-clockwise)

(the out-of-plane terms, gyroscopic ones included, point along x or z: they do no work on a
joint about y and never reach its torque). The wrench the parent transmits through joint j to
its subtree is the subtree sum of the body wrenches, moved to the joint origin o_j:

    F_j = sum_{b in sub(j)} f_b,   M_j = sum_{b in sub(j)} [(c_b - o_j) x f_b + n_b]

and the joint torque is its virtual power per unit joint rate, tau_k = dphi_j/dq_k M_j for a
revolute coordinate k of joint j (phi: the body pitch, linear in q) and tau_k = Re(conj(do_j/dq_k)
F_j) for a slider (the hip's x and z). For every sample at once this is a few array products
with the constant subtree-incidence matrix (:class:`~pasibot_pin.dynamics.newton_euler.TreeLayout`):
what ``pin.rnea(q, v, a)`` gives, to round-off (``tests/test_planar_id.py``). The joint reactions
are the same sums minus the constraint forces on the subtree (what ``pin.rnea(q, v, a, fext)``
transmits, :meth:`PlanarInverseDynamics.reactions`).

Units: SI; forces [N], moments and torques [N.m].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from pasibot_pin.constraints.system import planar_kinematics
from pasibot_pin.dynamics.newton_euler import TreeLayout
from pasibot_pin.errors import ParameterError


def _cross(r: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Counter-clockwise moment r x F of complex points and forces (x + i z) [N.m]."""
    return (np.conj(r) * f).imag


@dataclass(frozen=True)
class SubtreeWrenches:
    """The inertial wrench each joint transmits to its subtree, for a batch of samples.

    Attributes:
        force: F_j (N, J) complex x + i z [N], joints 1 .. njoints - 1.
        moment: M_j about the joint origin (N, J), counter-clockwise [N.m].
        origin: the joint origins o_j (N, J) complex [m].

    """

    force: np.ndarray
    moment: np.ndarray
    origin: np.ndarray


@dataclass(frozen=True)
class PlanarInverseDynamics:
    """Joint torques and reactions of a planar tree from its bodies' motion (see the module docstring).

    Attributes:
        tree: the bodies, joint origins, constraint ends and subtree incidence.
        rate: (J, nv) dphi_j/dq_k of the coordinates k of joint j itself (its revolute part).
        slide_conj: (J, nv) complex conj(do_j/dq_k) of the sliders k of joint j that no joint turns
            (the floating hip's x and z).
        sliders: True when ``slide_conj`` has an entry.
        turning: the sliders turned by joints above them (the parallel extension's): their
            direction exp(i A q) C (T,), pitch rows A (T, nv), joint index (T,) into J, column (T,).

    """

    tree: TreeLayout
    rate: np.ndarray
    slide_conj: np.ndarray
    sliders: bool
    turning_c: np.ndarray
    turning_A: np.ndarray
    turning_joint: np.ndarray
    turning_col: np.ndarray

    def wrenches(
        self, q: np.ndarray, com_pos: np.ndarray, com_acc: np.ndarray, alpha: np.ndarray | None
    ) -> SubtreeWrenches:
        """The inertial subtree wrenches of a batch.

        Args:
            q: configurations (N, nq).
            com_pos: COM positions (N, J), complex x + i z [m].
            com_acc: COM accelerations (N, J), complex [m/s^2].
            alpha: angular accelerations (N, J) [rad/s^2], or None (no rotational inertia term).

        """
        tree = self.tree
        force = tree.mass * (com_acc - tree.gravity)  # (N, J) inertial force of each body
        moment = _cross(com_pos, force)
        if alpha is not None:
            moment = moment + tree.inertia_y * alpha
        f_sub = force @ tree.below.T
        origin = tree.origins.positions(q)
        return SubtreeWrenches(f_sub, moment @ tree.below.T - _cross(origin, f_sub), origin)

    def torques(self, q: np.ndarray, wrench: SubtreeWrenches) -> np.ndarray:
        """The joint torques (N, nv) [N.m, N] at q (N, nq): ``pin.rnea(q, v, a)`` of the wrenches' motion."""
        tau = wrench.moment @ self.rate
        if self.sliders:
            tau += (wrench.force @ self.slide_conj).real
        if len(self.turning_col):
            direction = self.turning_c * np.exp(1j * (q @ self.turning_A.T))  # (N, T) do_j/dq_k
            tau[:, self.turning_col] += (np.conj(direction) * wrench.force[:, self.turning_joint]).real
        return tau

    def reactions(self, q: np.ndarray, wrench: SubtreeWrenches, lam: np.ndarray) -> np.ndarray:
        """Force of each parent on its child at every joint, (N, njoints, 3): Fx, Fz [N], CCW moment [N.m].

        Args:
            q: configurations (N, nq).
            wrench: the inertial subtree wrenches (:meth:`wrenches`).
            lam: the constraint multipliers (N, m): in-plane rows of the constraint models, in order.

        """
        tree = self.tree
        f_sub, m_sub = wrench.force, wrench.moment
        if tree.ends is not None:
            p_end = tree.ends.positions(q)  # (N, E)
            f_end = tree.end_sign * (lam[:, tree.end_rx] + 1j * lam[:, tree.end_rz])
            mu = np.where(tree.end_rm >= 0, tree.end_sign * lam[:, np.maximum(tree.end_rm, 0)], 0.0)
            f_ends = f_end @ tree.ends_below.T
            f_sub = f_sub - f_ends
            m_sub = m_sub - ((_cross(p_end, f_end) + mu) @ tree.ends_below.T - _cross(wrench.origin, f_ends))
        out = np.zeros((len(q), len(tree.mass) + 1, 3))
        out[:, 1:, 0], out[:, 1:, 1] = f_sub.real, f_sub.imag
        out[:, 1:, 2] = m_sub
        return out


def planar_inverse_dynamics(model: pin.Model, tree: TreeLayout) -> PlanarInverseDynamics:
    """The :class:`PlanarInverseDynamics` of ``model`` (its :func:`~.newton_euler.tree_layout` ``tree``).

    Raises:
        ValueError: a model that is not planar.

    """
    kin = planar_kinematics(model)
    if kin is None:
        raise ParameterError("the planar inverse dynamics needs a planar model (every rotation about y)")
    n_joints, nv = model.njoints - 1, model.nv
    rate = np.zeros((n_joints, nv))
    slide_conj = np.zeros((n_joints, nv), dtype=complex)
    turning: list[tuple[complex, np.ndarray, int, int]] = []
    for j in range(1, model.njoints):
        joint = model.joints[j]
        own = range(joint.idx_v, joint.idx_v + joint.nv)
        rate[j - 1, own] = kin.joint_A[j, own]
        for t in kin.joint_terms[j]:
            k = kin.terms_slider[t]
            if k not in own:  # a fixed offset, or an ancestor's slider
                continue
            c = complex(*kin.terms_c[t]) * np.exp(1j * kin.terms_a0[t])
            if np.any(kin.terms_A[t] != 0.0):
                turning.append((c, np.array(kin.terms_A[t], dtype=float), j - 1, k))
            else:
                slide_conj[j - 1, k] += np.conj(c)
    cols = [k for *_, k in turning]
    if len(set(cols)) != len(cols):
        raise ParameterError("the planar inverse dynamics needs one term per turning slider")
    return PlanarInverseDynamics(
        tree,
        rate,
        slide_conj,
        bool(np.any(slide_conj != 0.0)),
        turning_c=np.array([c for c, *_ in turning], dtype=complex),
        turning_A=np.array([a for _, a, *_ in turning], dtype=float).reshape(len(turning), nv),
        turning_joint=np.array([j for _, _, j, _ in turning], dtype=int),
        turning_col=np.array(cols, dtype=int),
    )
