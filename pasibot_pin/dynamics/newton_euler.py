"""The planar tree's layout for Newton-Euler: bodies, joint origins, constraint ends, subtrees.

For a batch of samples (q, v, a) of a planar model, every body's centre of mass moves as
c(q) = a point of the exact planar kinematics (:mod:`pasibot_pin.constraints.planar`), so its
acceleration is J_c a + J_dot_c v, and its pitch is linear in q, so its angular
acceleration is A a. With these, the force and moment that joint j's parent applies to the
subtree below j follow from the subtree's Newton-Euler balance, in the world x-z plane:

    F_j = sum_{k in sub(j)} m_k (a_k - g) - sum_{e in sub(j)} f_e
    M_j = sum_{k in sub(j)} [(c_k - o_j) x m_k (a_k - g) + I_k alpha_k]
          - sum_{e in sub(j)} [(p_e - o_j) x f_e + mu_e]

with f_e, mu_e the external (constraint) forces and moments at points p_e, and r x F =
r_x F_z - r_z F_x the counter-clockwise moment (seen from the right side, about -y). This is
the force ``pin.rnea(q, v, a, fext)`` transmits through joint j (``data.f[j]``). The sums are
evaluated, for every sample at once, by :mod:`pasibot_pin.dynamics.planar_id` on the layout
kept here (:class:`TreeLayout`, :func:`tree_layout`).

Units: SI; forces [N], moments [N.m].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from pasibot_pin.caches import PerObjectCache
from pasibot_pin.constraints import anchor_points, is_weld, model_key, planar_rows
from pasibot_pin.constraints.planar import PlanarRowBlocks
from pasibot_pin.constraints.system import planar_kinematics
from pasibot_pin.errors import ParameterError


@dataclass
class TreeLayout:
    """The bodies, joint origins and constraint ends of a planar model, and who is below whom.

    Attributes:
        mass: mass of each joint's body (J,) [kg], joints 1..njoints-1.
        inertia_y: its rotational inertia about the y axis through its COM (J,) [kg.m^2].
        coms: the COM points (position, Jacobian, drift in one evaluation).
        origins: the joint origins.
        ends: the constraint ends on moving bodies (J_e, sign, lambda rows).
        below: (J, J) 1 where body k is in the subtree of joint j.
        ends_below: (J, E) 1 where constraint end e is on a body of the subtree of joint j.
        gravity: world gravity as x + i z [m/s^2].

    """

    mass: np.ndarray
    inertia_y: np.ndarray
    coms: PlanarRowBlocks
    origins: PlanarRowBlocks
    ends: PlanarRowBlocks | None
    end_sign: np.ndarray
    end_rx: np.ndarray
    end_rz: np.ndarray
    end_rm: np.ndarray
    below: np.ndarray
    ends_below: np.ndarray
    gravity: complex

    def body_motion(self, q: np.ndarray, v: np.ndarray, a: np.ndarray):
        """COM positions and accelerations (N, J) complex, angular accelerations (N, J) [m, m/s^2, rad/s^2]."""
        pos, acc = self.coms.motion(q, v, a)
        alpha = a @ self.coms.pitch_A.T
        return pos, acc, alpha


_LAYOUTS: PerObjectCache[TreeLayout] = PerObjectCache()


def tree_layout(model: pin.Model, cmodels) -> TreeLayout:
    """The :class:`TreeLayout` of ``model`` with constraint models ``cmodels``.

    Cached per model, constraint models and the model's current inertias (a model whose
    masses are changed in place gets a new layout).
    """
    joints = list(range(1, model.njoints))
    inertias = np.array([model.inertias[j].toDynamicParameters() for j in joints])
    # only the ends on moving bodies matter: a weld's world target (where the foot stands) does not
    ends_key = tuple(k[:4] + (k[4] if k[2] != 0 else b"",) for k in map(model_key, cmodels))
    return _LAYOUTS.get(model, lambda: _build_tree_layout(model, cmodels), (ends_key, inertias.tobytes()))


def _build_tree_layout(model: pin.Model, cmodels) -> TreeLayout:
    """The :class:`TreeLayout` of ``model`` with ``cmodels``, built (see :func:`tree_layout`)."""
    joints = list(range(1, model.njoints))
    kin = planar_kinematics(model)
    if kin is None:
        raise ParameterError("the batched Newton-Euler needs a planar model (every rotation about y)")
    eye = np.eye(3)
    mass = np.array([model.inertias[j].mass for j in joints])
    inertia_y = np.array([model.inertias[j].inertia[1, 1] for j in joints])
    levers = np.array([model.inertias[j].lever for j in joints]).reshape(-1, 3)
    rots = np.repeat(eye[None], len(joints), axis=0)
    single = [(k, -1) for k in range(len(joints))]
    coms = PlanarRowBlocks(kin.ends(np.array(joints), levers, rots), single, single)
    origins = PlanarRowBlocks(kin.ends(np.array(joints), np.zeros((len(joints), 3)), rots), single, [])
    supports = [set(int(s) for s in model.supports[j]) for j in range(model.njoints)]
    below = np.array([[1.0 if j in supports[k] else 0.0 for k in joints] for j in joints])
    end_joint, end_trans, sign, rx, rz, rm = [], [], [], [], [], []
    for cm, rows in zip(cmodels, planar_rows(cmodels)):
        for (joint, placement), sgn in zip(anchor_points(cm), (1.0, -1.0)):
            if joint == 0:
                continue
            end_joint.append(joint)
            end_trans.append(np.array(placement.translation))
            sign.append(sgn)
            rx.append(rows.start)
            rz.append(rows.start + 1)
            rm.append(rows.start + 2 if is_weld(cm) else -1)
    ends = None
    ends_below = np.zeros((len(joints), 0))
    if end_joint:
        ej = np.array(end_joint, dtype=int)
        end_points = kin.ends(ej, np.array(end_trans), np.repeat(eye[None], len(ej), axis=0))
        ends = PlanarRowBlocks(end_points, [(e, -1) for e in range(len(ej))], [])
        ends_below = np.array([[1.0 if j in supports[int(e)] else 0.0 for e in ej] for j in joints])
    g = model.gravity.linear
    return TreeLayout(
        mass=mass,
        inertia_y=inertia_y,
        coms=coms,
        origins=origins,
        ends=ends,
        end_sign=np.array(sign),
        end_rx=np.array(rx, dtype=int),
        end_rz=np.array(rz, dtype=int),
        end_rm=np.array(rm, dtype=int),
        below=below,
        ends_below=ends_below,
        gravity=complex(g[0], g[2]),
    )
