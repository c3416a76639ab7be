"""Loop closure: planar residuals and Jacobians, Newton assembly, motion on the manifold.

The constraints c(q) = 0 are the in-plane rows of the robot's constraint models: x and z of
each cut-joint point coincidence (world axes), plus x, z and pitch of the stance-foot weld.
The out-of-plane rows are identically zero and are dropped, so every linear system here has
full row rank away from singular poses.

Prescribed coordinates s(q) = s* (crank angles, hip pitch, swing-foot pitch) complete the
system: Newton on [c; s - s*] gives q, [J_c; J_s] v = [0; s_dot*] gives v and
[J_c; J_s] a = [-Jdot_c v; s_ddot* - Jdot_s v] gives a.

Angles [rad], lengths [m].
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from . import constraints
from .assembly import leg_joint_angles, leg_points, sole_angle
from .description import sides

RESIDUAL_TOL = 1e-12
"""Newton stops when every residual row is below this [m or rad]."""


# --------------------------------------------------------------------------- kinematics of a point
def _point_on_joint(model: pin.Model, data: pin.Data, joint: int, placement: pin.SE3, need_drift: bool):
    """World pose, world-axes Jacobian (6 x nv) and drift of a frame fixed on ``joint``.

    The drift is the classical acceleration of the point and the angular acceleration,
    world axes, at zero joint acceleration (call ``forwardKinematics(q, v, 0)`` first).
    """
    oMc = data.oMi[joint] * placement
    if joint == 0:
        return oMc, np.zeros((6, model.nv)), np.zeros(6)
    j_local = pin.getJointJacobian(model, data, joint, pin.ReferenceFrame.LOCAL)
    j_c = placement.toActionMatrixInverse() @ j_local
    rot = oMc.rotation
    jac = np.vstack((rot @ j_c[:3], rot @ j_c[3:]))
    drift = np.zeros(6)
    if need_drift:
        v_c = placement.actInv(data.v[joint])
        a_c = placement.actInv(data.a[joint])
        drift[:3] = rot @ (a_c.linear + np.cross(v_c.angular, v_c.linear))
        drift[3:] = rot @ a_c.angular
    return oMc, jac, drift


def planar_pitch(rotation: np.ndarray) -> float:
    """Counter-clockwise angle of a frame's x axis in the x-z plane [rad] (atan2, signed)."""
    return math.atan2(rotation[2, 0], rotation[0, 0])


def _wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


# --------------------------------------------------------------------------- prescriptions
@dataclass(frozen=True)
class Prescribed:
    """A scalar coordinate s(q) to be prescribed: a joint coordinate or a frame's pitch.

    Attributes:
        name: label (joint or frame name).
        kind: ``joint`` (s = q[index]) or ``pitch`` (s = planar pitch of frame ``index``).
        index: velocity/configuration index for ``joint``; frame id for ``pitch``.

    """

    name: str
    kind: str
    index: int


def joint_coordinate(robot, joint: str) -> Prescribed:
    """Prescribe the coordinate of a one-dof joint (``right_j0_crank``, ``hip_planar`` pitch...)."""
    return Prescribed(joint, "joint", robot.idx_v(joint))


def hip_pitch(robot) -> Prescribed:
    """Prescribe the hip pitch (third coordinate of the planar floating hip)."""
    if not robot.floating:
        raise ValueError("the one-leg model has a fixed hip: its pitch cannot be prescribed")
    return Prescribed("hip_pitch", "joint", 2)


def frame_pitch(robot, frame: str) -> Prescribed:
    """Prescribe the pitch of a frame in the world (e.g. ``left_foot``: the swing foot)."""
    return Prescribed(frame, "pitch", robot.frame_id(frame))


def _prescribed_rows(robot, q, prescribed: Sequence[Prescribed], need_drift: bool):
    model, data = robot.model, robot.data
    values, jac, drift = np.zeros(len(prescribed)), np.zeros((len(prescribed), model.nv)), np.zeros(len(prescribed))
    for row, p in enumerate(prescribed):
        if p.kind == "joint":
            values[row] = q[p.index]
            jac[row, p.index] = 1.0
        else:
            frame = model.frames[p.index]
            oMf, j6, d6 = _point_on_joint(model, data, frame.parentJoint, frame.placement, need_drift)
            values[row] = planar_pitch(oMf.rotation)
            jac[row] = -j6[4]  # rotation about -y is counter-clockwise
            drift[row] = -d6[4]
    return values, jac, drift


# --------------------------------------------------------------------------- constraints
def row_labels(robot, cmodels=None) -> list[str]:
    """Names of the in-plane constraint rows (``right_j2.x``, ..., ``right_foot_weld.pitch``)."""
    cmodels = robot.constraint_models if cmodels is None else cmodels
    labels = []
    for cm in cmodels:
        axes = ("x", "z", "pitch") if constraints.is_weld(cm) else ("x", "z")
        labels += [f"{cm.name}.{a}" for a in axes]
    return labels


_CACHE_SIZE = 32


def _cached_constraint_datas(robot, cmodels):
    """Constraint datas and in-plane row selection for a list of constraint models (cached)."""
    cache = robot.__dict__.setdefault("_closure_cache", {})
    key = tuple(id(cm) for cm in cmodels)
    entry = cache.get(key)
    if entry is None:
        # Keep the models referenced so their ids cannot be reused while cached.
        index, sign = constraints.inplane_rows(cmodels)
        entry = (list(cmodels), constraints.create_datas(cmodels), index, sign)
        if len(cache) >= _CACHE_SIZE:
            cache.pop(next(iter(cache)))
        cache[key] = entry
    return entry


def _fast_constraint_rows(robot, q, cmodels):
    """Residual and Jacobian through Pinocchio's C++ constraint Jacobian (no drift)."""
    model, data = robot.model, robot.data
    cmodels, cdatas, index, sign = _cached_constraint_datas(robot, cmodels)
    jac, oMc = constraints.stacked_jacobian(model, data, cmodels, cdatas, q)
    res = []
    for cm, (oMc1, oMc2) in zip(cmodels, oMc):
        dp = oMc1.translation - oMc2.translation
        res += [dp[0], dp[2]]
        if constraints.is_weld(cm):
            res.append(_wrap(planar_pitch(oMc1.rotation) - planar_pitch(oMc2.rotation)))
    return np.array(res), jac[index] * sign, np.zeros(len(res))


def _constraint_rows(robot, q, v, cmodels, need_drift: bool):
    model, data = robot.model, robot.data
    if not need_drift and len(cmodels) > 0:
        return _fast_constraint_rows(robot, q, cmodels)
    if need_drift:
        pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
    else:
        pin.forwardKinematics(model, data, q)
    pin.computeJointJacobians(model, data, q)
    res, jac, drift = [], [], []
    for cm in cmodels:
        o1, j1, d1 = _point_on_joint(model, data, cm.joint1_id, cm.joint1_placement, need_drift)
        o2, j2, d2 = _point_on_joint(model, data, cm.joint2_id, cm.joint2_placement, need_drift)
        dp = o1.translation - o2.translation
        res += [dp[0], dp[2]]
        jac += [j1[0] - j2[0], j1[2] - j2[2]]
        drift += [d1[0] - d2[0], d1[2] - d2[2]]
        if constraints.is_weld(cm):
            res.append(_wrap(planar_pitch(o1.rotation) - planar_pitch(o2.rotation)))
            jac.append(-(j1[4] - j2[4]))
            drift.append(-(d1[4] - d2[4]))
    nrows = len(res)
    return np.array(res), np.array(jac).reshape(nrows, model.nv), np.array(drift)


def constraint_residual(robot, q: np.ndarray, cmodels=None) -> np.ndarray:
    """In-plane constraint residuals c(q) [m, rad], one row per label of :func:`row_labels`."""
    cmodels = robot.constraint_models if cmodels is None else cmodels
    return _constraint_rows(robot, q, None, cmodels, False)[0]


def constraint_jacobian(robot, q: np.ndarray, cmodels=None) -> np.ndarray:
    """Jacobian dc/dq of the in-plane constraint rows (rows x nv), world axes."""
    cmodels = robot.constraint_models if cmodels is None else cmodels
    return _constraint_rows(robot, q, None, cmodels, False)[1]


def constraint_drift(robot, q: np.ndarray, v: np.ndarray, cmodels=None) -> np.ndarray:
    """Jdot_c(q, v) v: the constraint acceleration at zero joint acceleration [m/s^2, rad/s^2]."""
    cmodels = robot.constraint_models if cmodels is None else cmodels
    return _constraint_rows(robot, q, v, cmodels, True)[2]


# --------------------------------------------------------------------------- Newton
def default_prescriptions(robot, stance: str | None = None) -> list[Prescribed]:
    """The coordinates that, with the constraints, fix the pose of ``robot``.

    One leg: the crank (and, for ``spring``, the ankle coordinate). Two legs: both cranks;
    for ``spring`` also the hip pitch and the swing foot's pitch.
    """
    out = [joint_coordinate(robot, j) for j in robot.actuated_joints]
    if robot.variant == "spring":
        if robot.floating:
            stance = stance or robot.stance or "right"
            swing = [s for s in sides(robot.legs) if s != stance][0]
            out += [hip_pitch(robot), frame_pitch(robot, f"{swing}_foot")]
        else:
            out += [joint_coordinate(robot, j) for j in robot.spring_joints]
    return out


def solve_configuration(
    robot,
    q_guess: np.ndarray,
    prescribed: Sequence[Prescribed] | None = None,
    targets: Iterable[float] | None = None,
    cmodels=None,
    tol: float = RESIDUAL_TOL,
    max_iter: int = 50,
) -> np.ndarray:
    """Newton's method on [c(q); s(q) - s*] from a warm start.

    Args:
        robot: a loaded robot.
        q_guess: starting configuration (a previous sample's q).
        prescribed: prescribed coordinates (default :func:`default_prescriptions`).
        targets: their values s* (default: their values at ``q_guess``).
        cmodels: constraint models (default: the robot's).
        tol: convergence threshold on every row [m, rad].
        max_iter: iteration limit.

    Returns:
        q satisfying every constraint and prescription to ``tol``.

    Raises:
        ValueError: when Newton does not converge (a loop that cannot assemble), naming
            the worst constraint row and the crank angles.

    """
    model = robot.model
    cmodels = robot.constraint_models if cmodels is None else cmodels
    prescribed = default_prescriptions(robot) if prescribed is None else list(prescribed)
    q = np.array(q_guess, dtype=float)
    if q.shape != (model.nq,) or not np.all(np.isfinite(q)):
        raise ValueError(f"q_guess must be a finite vector of size nq = {model.nq}")
    _constraint_rows(robot, q, None, cmodels, False)  # kinematics at q_guess, for frame pitches
    s_values = _prescribed_rows(robot, q, prescribed, False)[0]
    targets = s_values.copy() if targets is None else np.asarray(list(targets), dtype=float)
    if targets.shape != (len(prescribed),) or not np.all(np.isfinite(targets)):
        raise ValueError(f"targets must be {len(prescribed)} finite values for {[p.name for p in prescribed]}")
    residual = None
    for _ in range(max_iter):
        c, jc, _ = _constraint_rows(robot, q, None, cmodels, False)
        s, js, _ = _prescribed_rows(robot, q, prescribed, False)
        ds = np.array([_wrap(a - b) if p.kind == "pitch" else a - b for p, a, b in zip(prescribed, s, targets)])
        residual = np.concatenate((c, ds))
        if np.max(np.abs(residual)) < tol:
            return q
        jac = np.vstack((jc, js))
        step = np.linalg.lstsq(jac, -residual, rcond=None)[0]
        largest = np.max(np.abs(step))
        if largest > 0.5:  # keep far-off starts from jumping to another assembly branch
            step *= 0.5 / largest
        q = pin.integrate(model, q, step)
    labels = row_labels(robot, cmodels) + [f"prescribed {p.name}" for p in prescribed]
    worst = int(np.argmax(np.abs(residual)))
    cranks = ", ".join(f"{j} = {math.degrees(q[robot.idx_q(j)]):.3f} deg" for j in robot.actuated_joints)
    raise ValueError(
        f"loop closure failed: constraint {labels[worst]} keeps a residual of {abs(residual[worst]):.3e} "
        f"after {max_iter} Newton iterations ({cranks}); the loop cannot assemble there"
    )


def solve_velocity(robot, q, prescribed, rates, cmodels=None) -> np.ndarray:
    """V on the constraint manifold: [J_c; J_s] v = [0; s_dot*]."""
    cmodels = robot.constraint_models if cmodels is None else cmodels
    _, jc, _ = _constraint_rows(robot, q, None, cmodels, False)
    _, js, _ = _prescribed_rows(robot, q, prescribed, False)
    rhs = np.concatenate((np.zeros(jc.shape[0]), np.asarray(rates, dtype=float)))
    return _solve_square(np.vstack((jc, js)), rhs, "velocity")


def solve_acceleration(robot, q, v, prescribed, accelerations, cmodels=None) -> np.ndarray:
    """A on the manifold: [J_c; J_s] a = [-Jdot_c v; s_ddot* - Jdot_s v]."""
    cmodels = robot.constraint_models if cmodels is None else cmodels
    _, jc, dc = _constraint_rows(robot, q, v, cmodels, True)
    _, js, ds = _prescribed_rows(robot, q, prescribed, True)
    rhs = np.concatenate((-dc, np.asarray(accelerations, dtype=float) - ds))
    return _solve_square(np.vstack((jc, js)), rhs, "acceleration")


def _solve_square(matrix: np.ndarray, rhs: np.ndarray, what: str) -> np.ndarray:
    if matrix.shape[0] != matrix.shape[1]:
        raise ValueError(
            f"{what}: constraints plus prescriptions give {matrix.shape[0]} rows for nv = {matrix.shape[1]}; "
            "prescribe exactly the free coordinates"
        )
    try:
        sol = np.linalg.solve(matrix, rhs)
    except np.linalg.LinAlgError as err:
        raise ValueError(f"{what}: singular pose, the constraint Jacobian lost rank") from err
    if not np.all(np.isfinite(sol)):
        raise ValueError(f"{what}: singular pose, the solution is not finite")
    return sol


# --------------------------------------------------------------------------- assembly
def assemble(
    robot,
    theta: float,
    theta_left: float | None = None,
    hip_pitch_value: float = 0.0,
    swing_foot_pitch: float = 0.0,
    stance: str | None = None,
    ankle_x: float = 0.0,
) -> np.ndarray:
    """A closed configuration for given crank angles, from the analytic assembly plus Newton.

    Args:
        robot: a loaded robot.
        theta: right crank angle [rad].
        theta_left: left crank angle [rad] (default ``theta + pi``).
        hip_pitch_value: hip pitch for the ``spring`` biped [rad].
        swing_foot_pitch: swing-foot pitch for the ``spring`` biped [rad].
        stance: the welded foot (two legs; default the robot's stance or ``right``).
        ankle_x: world x of the stance ankle [m] (its z is 0: the sole is on the ground).

    Returns:
        q with every constraint residual below :data:`RESIDUAL_TOL`.

    Raises:
        ValueError: a loop that cannot assemble at these crank angles (named).

    """
    for name, value in (("theta", theta), ("theta_left", theta_left), ("hip_pitch", hip_pitch_value)):
        if value is not None and not math.isfinite(value):
            raise ValueError(f"parameter {name!r} must be finite, got {value!r}")
    model = robot.model
    g, variant = robot.geometry, robot.variant
    thetas = {"right": float(theta), "left": float(theta + math.pi if theta_left is None else theta_left)}
    q = pin.neutral(model)
    stance = stance or robot.stance or "right"
    pitch = 0.0
    if robot.floating:
        if variant == "spring":
            pitch = hip_pitch_value
        else:
            pitch = -sole_angle(thetas[stance], g, variant)
    for side in sides(robot.legs):
        foot_angle = None
        if variant == "spring":
            if not robot.floating:
                foot_angle = 0.0
            elif side == stance:
                foot_angle = -pitch
            else:
                foot_angle = swing_foot_pitch - pitch
        for joint, value in leg_joint_angles(thetas[side], g, variant, foot_angle).items():
            q[robot.idx_q(f"{side}_{joint}")] = value
    cmodels = list(robot.loop_constraints)
    if robot.floating:
        ankle = leg_points(thetas[stance], g, variant)["p13"]
        c, s = math.cos(pitch), math.sin(pitch)
        hip_xz = np.array([ankle_x, 0.0]) - np.array([c * ankle[0] - s * ankle[1], s * ankle[0] + c * ankle[1]])
        q[:3] = [hip_xz[0], hip_xz[1], pitch]
        y = robot.geometry.hip_half_width * (-1 if stance == "right" else 1)
        weld = constraints.weld_constraint(
            model, f"{stance}_foot", pin.SE3(np.eye(3), np.array([ankle_x, y, 0.0])), f"{stance}_foot_weld"
        )
        cmodels.append(weld)
    prescribed = default_prescriptions(robot, stance)
    return solve_configuration(robot, q, prescribed, None, cmodels)


# --------------------------------------------------------------------------- mobility
@dataclass(frozen=True)
class Mobility:
    """Degrees of freedom by Grübler's count and numerically.

    Attributes:
        grubler: 3 * moving bodies - 2 * (one-dof pairs) - 3 * welds (planar Grübler).
        numerical: nv - rank(J_c) at the configuration.
        rank: rank of the in-plane constraint Jacobian.
        moving_bodies: moving rigid bodies of the model (fixed links merged).
        pairs: one-dof lower pairs: tree revolute/prismatic joints plus cut joints.
        welds: foot welds.
        leg_linkage: mobility of one leg's linkage alone (hip fixed, ankle excluded).

    """

    grubler: int
    numerical: int
    rank: int
    moving_bodies: int
    pairs: int
    welds: int
    leg_linkage: int


def mobility(robot, q: np.ndarray | None = None) -> Mobility:
    """Grübler's DOF from the model's topology next to nv - rank(J_c) at ``q`` (default q0)."""
    model = robot.model
    q = robot.q0 if q is None or len(q) == 0 else q
    if q is None or len(q) == 0:
        q = pin.neutral(model)
    moving = model.njoints - 1
    tree_pairs = sum(1 for j in model.joints[1:] if j.nv == 1)
    cuts = len(robot.loops)
    welds = sum(1 for cm in robot.constraint_models if constraints.is_weld(cm))
    # The planar floating hip (3 dof) constrains nothing: it adds no term.
    grubler = 3 * moving - 2 * (tree_pairs + cuts) - 3 * welds
    jac = constraint_jacobian(robot, q)
    sv = np.linalg.svd(jac, compute_uv=False)
    rank = int(np.sum(sv > 1e-9 * max(sv.max(), 1.0)))
    # One leg's linkage: moving links and pairs, the spring foot and its ankle excluded.
    leg_joints = [j for j in range(1, model.njoints) if model.names[j].startswith("right_")]
    leg_joints = [j for j in leg_joints if model.names[j] != "right_j13_ankle"]
    leg_cuts = sum(1 for lp in robot.loops if lp.side == "right")
    leg = 3 * len(leg_joints) - 2 * (len(leg_joints) + leg_cuts)
    return Mobility(grubler, model.nv - rank, rank, moving, tree_pairs + cuts, welds, leg)


# --------------------------------------------------------------------------- sweeps
def crank_sweep(robot, thetas: Sequence[float], **assemble_kwargs) -> np.ndarray:
    """Closed configurations along a sequence of right-crank angles, warm-started.

    The first sample comes from :func:`assemble`; each next one from Newton started at
    the previous solution, with the crank targets moved (continuation keeps the branch).
    The stance foot stays the one of the first sample.

    Returns:
        Array (len(thetas), nq).

    """
    thetas = np.asarray(thetas, dtype=float)
    if not np.all(np.isfinite(thetas)):
        raise ValueError("crank angles theta must be finite")
    out = np.zeros((len(thetas), robot.model.nq))
    q = assemble(robot, float(thetas[0]), **assemble_kwargs)
    stance = assemble_kwargs.get("stance") or robot.stance or "right"
    cmodels = list(robot.loop_constraints)
    if robot.floating:
        cmodels.append(robot.with_stance(stance, q).weld)
    prescribed = default_prescriptions(robot, stance)
    _constraint_rows(robot, q, None, cmodels, False)  # kinematics at q, for frame pitches
    base_targets = _prescribed_rows(robot, q, prescribed, False)[0]
    out[0] = q
    for k in range(1, len(thetas)):
        targets = base_targets.copy()
        for row, p in enumerate(prescribed):
            if p.kind == "joint" and p.name in robot.actuated_joints:
                targets[row] = base_targets[row] + (thetas[k] - thetas[0])
        q = solve_configuration(robot, q, prescribed, targets, cmodels)
        out[k] = q
    return out
