"""Every call to Pinocchio's constraint API lives here (it changes between major versions).

Tested with PyPI ``pin`` 4.1.0. The loop closures are ``RigidConstraintModel`` CONTACT_3D
point coincidences in ``LOCAL_WORLD_ALIGNED``; the stance-foot weld is CONTACT_6D against
the world. The models are the *description* of each constraint (which two frames, which
type); :class:`pasibot_pin.constraints.ConstraintSystem` evaluates their in-plane rows (x and
z for a point; x, z and the pitch for a weld): the out-of-plane rows are identically zero.

Pinocchio's own constrained algorithms (``getConstraintsJacobian``, ``constraintDynamics``,
``impulseDynamics``) are wrapped here as independent references for the tests.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from pasibot_pin.errors import ParameterError

POINT_ROWS: tuple[int, ...] = (0, 2)
"""In-plane rows of a CONTACT_3D constraint (x, z)."""
WELD_ROWS: tuple[int, ...] = (0, 2, 4)
"""In-plane rows of a CONTACT_6D constraint (x, z, rotation about y)."""


def point_constraint(model: pin.Model, frame_a: str, frame_b: str, name: str) -> pin.RigidConstraintModel:
    """A point-coincidence (cut revolute joint) between the origins of two frames.

    Args:
        model: the Pinocchio model.
        frame_a: frame on the first link.
        frame_b: frame on the second link.
        name: constraint name (``right_j2`` ...).

    Returns:
        A CONTACT_3D ``RigidConstraintModel`` in ``LOCAL_WORLD_ALIGNED``.

    """
    fa = model.frames[model.getFrameId(frame_a)]
    fb = model.frames[model.getFrameId(frame_b)]
    cmodel = pin.RigidConstraintModel(
        pin.ContactType.CONTACT_3D,
        model,
        fa.parentJoint,
        fa.placement,
        fb.parentJoint,
        fb.placement,
        pin.ReferenceFrame.LOCAL_WORLD_ALIGNED,
    )
    cmodel.name = name
    return cmodel


def weld_constraint(model: pin.Model, frame: str, target: pin.SE3, name: str) -> pin.RigidConstraintModel:
    """A weld of ``frame`` to the world at placement ``target`` (CONTACT_6D, LOCAL_WORLD_ALIGNED)."""
    f = model.frames[model.getFrameId(frame)]
    cmodel = pin.RigidConstraintModel(
        pin.ContactType.CONTACT_6D,
        model,
        f.parentJoint,
        f.placement,
        0,
        target,
        pin.ReferenceFrame.LOCAL_WORLD_ALIGNED,
    )
    cmodel.name = name
    return cmodel


def ground_point_constraint(model: pin.Model, frame: str, position: np.ndarray, name: str) -> pin.RigidConstraintModel:
    """A pin joint between the origin of ``frame`` and a fixed world point (CONTACT_3D).

    Used for the seed's point-foot (ankle pinned) and toe-pinned biped postures: the
    point is held, its rotation is free.

    Args:
        model: the Pinocchio model.
        frame: the pinned frame (``right_foot``, ``left_toe`` ...).
        position: world position of the pin [m] (3-vector).
        name: constraint name.

    Returns:
        A CONTACT_3D ``RigidConstraintModel`` in ``LOCAL_WORLD_ALIGNED`` against the world.

    """
    f = model.frames[model.getFrameId(frame)]
    cmodel = pin.RigidConstraintModel(
        pin.ContactType.CONTACT_3D,
        model,
        f.parentJoint,
        f.placement,
        0,
        pin.SE3(np.eye(3), np.asarray(position, dtype=float).reshape(3)),
        pin.ReferenceFrame.LOCAL_WORLD_ALIGNED,
    )
    cmodel.name = name
    return cmodel


def is_weld(cmodel: pin.RigidConstraintModel) -> bool:
    """True for a CONTACT_6D constraint."""
    return cmodel.type == pin.ContactType.CONTACT_6D


def planar_rows(cmodels: list[pin.RigidConstraintModel]) -> list[slice]:
    """Where each constraint model's in-plane rows sit in our stacked rows (one definition for all).

    A point constraint has two rows (x, z of p1 - p2), a weld three (x, z, then the pitch): the
    order of :func:`inplane_rows`, of ``ConstraintSystem`` and of every multiplier vector.
    """
    out, row = [], 0
    for cm in cmodels:
        size = len(WELD_ROWS) if is_weld(cm) else len(POINT_ROWS)
        out.append(slice(row, row + size))
        row += size
    return out


def constraint_size(cmodel: pin.RigidConstraintModel) -> int:
    """Number of rows of a constraint model (3 for CONTACT_3D, 6 for CONTACT_6D)."""
    return int(cmodel.residualSize())


def create_datas(cmodels: list[pin.RigidConstraintModel]) -> list[pin.RigidConstraintData]:
    """One ``RigidConstraintData`` per constraint model."""
    return [cm.createData() for cm in cmodels]


def pinocchio_constraint_jacobian(
    model: pin.Model, data: pin.Data, cmodels: list[pin.RigidConstraintModel], q: np.ndarray
) -> np.ndarray:
    """Pinocchio's own full constraint Jacobian (all rows, 3 per point, 6 per weld).

    Used to cross-check the planar Jacobians of :mod:`pasibot_pin.model.closure`. Note: in pin 4.1
    ``getConstraintJacobian`` reads the frame placements stored by ``calc``; without that call
    it silently returns the Jacobian of a stale pose.
    """
    cdatas = create_datas(cmodels)
    pin.initConstraintDynamics(model, data, cmodels, cdatas)
    pin.forwardKinematics(model, data, q)
    pin.computeJointJacobians(model, data, q)
    for cmodel, cdata in zip(cmodels, cdatas):
        cmodel.calc(model, data, cdata)  # sets the constraint frames' placements for this q
    rows = sum(constraint_size(cm) for cm in cmodels)
    jac = np.zeros((rows, model.nv))
    start = 0
    for cmodel, cdata in zip(cmodels, cdatas):
        size = constraint_size(cmodel)
        jac[start : start + size] = pin.getConstraintJacobian(model, data, cmodel, cdata)
        start += size
    return jac


def model_key(cmodel: pin.RigidConstraintModel) -> tuple:
    """A hashable key of what a constraint model constrains: its type, joints and placements.

    Two models with equal keys give the same rows, so caches keyed by it are shared between
    equal models built anew (e.g. the same weld for every call of an analysis).
    """
    return (
        int(cmodel.type),
        int(cmodel.joint1_id),
        int(cmodel.joint2_id),
        cmodel.joint1_placement.homogeneous.tobytes(),
        cmodel.joint2_placement.homogeneous.tobytes(),
        cmodel.name,
    )


def anchor_points(cmodel: pin.RigidConstraintModel) -> tuple[tuple[int, pin.SE3], tuple[int, pin.SE3]]:
    """The two frames a constraint model ties together: ((joint1, placement1), (joint2, placement2)).

    Joint 0 is the world (the weld's target placement).
    """
    first = (int(cmodel.joint1_id), cmodel.joint1_placement.copy())
    second = (int(cmodel.joint2_id), cmodel.joint2_placement.copy())
    return first, second


def proximal_forward_dynamics(
    model: pin.Model,
    data: pin.Data,
    cmodels: list[pin.RigidConstraintModel],
    q: np.ndarray,
    v: np.ndarray,
    tau: np.ndarray,
    mu: float = 1e-10,
    accuracy: float = 1e-13,
    max_iter: int = 100,
) -> np.ndarray:
    """Pinocchio's own constrained forward dynamics (``constraintDynamics``) with proximal settings.

    The planar 3-D contacts make the stacked constraint Jacobian rank-deficient, so ``mu`` must
    be positive (with mu = 0 pin 4.1 returns NaN). Used to cross-check the simulator's KKT solve.

    Returns:
        The joint accelerations (nv,).

    """
    if not mu > 0:
        raise ParameterError(f"parameter 'mu' must be positive (rank-deficient planar contacts), got {mu!r}")
    cdatas = create_datas(cmodels)
    pin.initConstraintDynamics(model, data, cmodels, cdatas)
    settings = pin.ProximalSettings(accuracy, mu, max_iter)
    return np.array(pin.constraintDynamics(model, data, q, v, tau, cmodels, cdatas, settings))


def inplane_rows(cmodels: list[pin.RigidConstraintModel]) -> tuple[np.ndarray, np.ndarray]:
    """Row indices and signs that pick the in-plane rows of Pinocchio's stacked constraint Jacobian.

    x and z of each CONTACT_3D / CONTACT_6D, and minus the rotation about y of each weld (its
    pitch is counter-clockwise, about -y): the rows of :mod:`pasibot_pin.model.closure`.
    """
    index, sign, offset = [], [], 0
    for cm in cmodels:
        if is_weld(cm):
            index += [offset + r for r in WELD_ROWS]
            sign += [1.0, 1.0, -1.0]
        else:
            index += [offset + r for r in POINT_ROWS]
            sign += [1.0, 1.0]
        offset += constraint_size(cm)
    return np.array(index), np.array(sign)[:, None]


def proximal_impulse(
    model: pin.Model,
    data: pin.Data,
    cmodels: list[pin.RigidConstraintModel],
    q: np.ndarray,
    v_before: np.ndarray,
    mu: float = 1e-10,
    accuracy: float = 1e-13,
    max_iter: int = 100,
) -> np.ndarray:
    """Pinocchio's own inelastic impact (``impulseDynamics``, restitution 0) with proximal settings.

    Like :func:`proximal_forward_dynamics`, ``mu`` must be positive for the planar 3-D contacts.
    Used to cross-check the simulator's KKT impulse. Checked with pin 4.1.0: it agrees for a weld
    to the world (joint2 = 0), but for a constraint between two moving bodies (a cut loop joint)
    its post-impact velocity violates that constraint (J v+ ~ 0.5 m/s for v- ~ 1), so the
    simulator's impulse is a KKT solve on its own rows (``ConstraintSystem.impulse``).

    Returns:
        The velocity after the impact (nv,).

    """
    if not mu > 0:
        raise ParameterError(f"parameter 'mu' must be positive (rank-deficient planar contacts), got {mu!r}")
    cdatas = create_datas(cmodels)
    pin.initConstraintDynamics(model, data, cmodels, cdatas)
    settings = pin.ProximalSettings(accuracy, mu, max_iter)
    return np.array(pin.impulseDynamics(model, data, q, v_before, cmodels, cdatas, 0.0, settings))
