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
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

from pasibot_pin import constraints
from pasibot_pin.caches import PerObjectCache
from pasibot_pin.constraints import ConstraintSystem, CoordinateRow, PitchRow, ScalarRow
from pasibot_pin.errors import ClosureError, ParameterError
from pasibot_pin.model import jet
from pasibot_pin.model.assembly import joint_angles_complex, leg_points_complex, sole_angle_from_points
from pasibot_pin.model.coordinates import HIP_PITCH
from pasibot_pin.model.description import sides

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot

RESIDUAL_TOL = 1e-12
"""Largest constraint residual of a closed configuration at the default L = 0.05 m [m, rad]
(the Newton tolerance is relative to L: see :data:`pasibot_pin.constraints.RELATIVE_TOL`)."""

Prescribed = ScalarRow
"""A prescribed scalar coordinate: a joint coordinate (:class:`CoordinateRow`) or a frame's pitch
(:class:`PitchRow`)."""


def joint_coordinate(robot: PasibotRobot, joint: str) -> CoordinateRow:
    """Prescribe the coordinate of a one-dof joint (``right_j0_crank``, ``right_j13_ankle`` ...)."""
    return constraints.coordinate(joint, robot.idx_v(joint))


def hip_pitch(robot: PasibotRobot) -> CoordinateRow:
    """Prescribe the hip pitch (third coordinate of the planar floating hip)."""
    if not robot.floating:
        raise ParameterError("the one-leg model has a fixed hip: its pitch cannot be prescribed")
    return constraints.coordinate("hip_pitch", HIP_PITCH)


def frame_pitch(robot: PasibotRobot, frame: str) -> PitchRow:
    """Prescribe the pitch of a frame in the world (e.g. ``left_foot``: the swing foot)."""
    return PitchRow(frame, robot.frame_id(frame))


def is_crank(robot: PasibotRobot, row: Prescribed) -> bool:
    """True for the prescribed coordinate of an actuated crank."""
    return isinstance(row, CoordinateRow) and row.name in robot.actuated_joints


_SYSTEMS: PerObjectCache[ConstraintSystem] = PerObjectCache()
_ANGULAR: PerObjectCache[np.ndarray] = PerObjectCache()


def system(robot: PasibotRobot, cmodels=None, prescribed: Sequence[Prescribed] = ()) -> ConstraintSystem:
    """The :class:`~pasibot_pin.constraints.ConstraintSystem` of ``robot`` (cached per model and rows).

    Args:
        robot: a loaded robot.
        cmodels: constraint models (default: the robot's loops and weld).
        prescribed: scalar rows after the constraint rows.

    """
    cmodels = robot.constraint_models if cmodels is None else cmodels
    # shared by the shallow copies of a robot (with_stance, with_weld): keyed by its model (and its data,
    # which the system holds); equal constraint models share an entry
    key = (id(robot.data), tuple(constraints.model_key(cm) for cm in cmodels), tuple(prescribed))
    return _SYSTEMS.get(
        robot.model, lambda: ConstraintSystem(robot.model, robot.data, cmodels, prescribed, robot.geometry.L), key
    )


def row_labels(robot: PasibotRobot, cmodels=None) -> list[str]:
    """Names of the in-plane constraint rows (``right_j2.x``, ..., ``right_foot_weld.pitch``)."""
    return system(robot, cmodels).labels


def constraint_residual(robot: PasibotRobot, q: np.ndarray, cmodels=None) -> np.ndarray:
    """In-plane constraint residuals c(q) [m, rad], one row per label of :func:`row_labels`."""
    return system(robot, cmodels).residual(q)


def constraint_jacobian(robot: PasibotRobot, q: np.ndarray, cmodels=None) -> np.ndarray:
    """Jacobian dc/dq of the in-plane constraint rows (rows x nv), world axes."""
    return system(robot, cmodels).jacobian(q)


def constraint_drift(robot: PasibotRobot, q: np.ndarray, v: np.ndarray, cmodels=None) -> np.ndarray:
    """Jdot_c(q, v) v: the constraint acceleration at zero joint acceleration [m/s^2, rad/s^2]."""
    return system(robot, cmodels).drift(q, v)


# --------------------------------------------------------------------------- Newton
def default_prescriptions(robot: PasibotRobot, stance: str | None = None) -> list[Prescribed]:
    """The coordinates that, with the constraints, fix the pose of ``robot``.

    One leg: the crank (and, for ``spring``, the ankle coordinate). Two legs: both cranks;
    for ``spring`` also the hip pitch and the swing foot's pitch.
    """
    out: list[Prescribed] = [joint_coordinate(robot, j) for j in robot.actuated_joints]
    if robot.spec.free_ankle:
        if robot.floating:
            stance = stance or robot.stance or "right"
            swing = [s for s in sides(robot.legs) if s != stance][0]
            out += [hip_pitch(robot), frame_pitch(robot, f"{swing}_foot")]
        else:
            out += [joint_coordinate(robot, j) for j in robot.spring_joints]
    return out


def solve_configuration(
    robot: PasibotRobot,
    q_guess: np.ndarray,
    prescribed: Sequence[Prescribed] | None = None,
    targets: Iterable[float] | None = None,
    cmodels=None,
    max_iter: int = 50,
) -> np.ndarray:
    """Newton's method on [c(q); s(q) - s*] from a warm start.

    Args:
        robot: a loaded robot.
        q_guess: starting configuration (a previous sample's q).
        prescribed: prescribed coordinates (default :func:`default_prescriptions`).
        targets: their values s* (default: their values at ``q_guess``).
        cmodels: constraint models (default: the robot's).
        max_iter: iteration limit.

    Returns:
        q satisfying every constraint and prescription (tolerance relative to L).

    Raises:
        ValueError: when Newton does not converge (a loop that cannot assemble), naming
            the worst constraint row and the crank angles.

    """
    model = robot.model
    prescribed = default_prescriptions(robot) if prescribed is None else list(prescribed)
    q = np.array(q_guess, dtype=float)
    if q.shape != (model.nq,) or not np.all(np.isfinite(q)):
        raise ParameterError(f"q_guess must be a finite vector of size nq = {model.nq}")
    sys_ = system(robot, cmodels, prescribed)
    if targets is None:
        targets = prescribed_values(robot, q, prescribed)
    targets = np.asarray(list(targets), dtype=float)
    if targets.shape != (len(prescribed),) or not np.all(np.isfinite(targets)):
        raise ParameterError(f"targets must be {len(prescribed)} finite values for {[p.name for p in prescribed]}")
    try:
        return sys_.project(q, targets=targets, max_iter=max_iter)
    except ValueError as err:
        cranks = ", ".join(
            f"{p.name} = {math.degrees(float(t)):.3f} deg" for p, t in zip(prescribed, targets) if is_crank(robot, p)
        )
        raise type(err)(f"{err} ({cranks})") from None


def prescribed_values(robot: PasibotRobot, q: np.ndarray, prescribed: Sequence[Prescribed]) -> np.ndarray:
    """The values s(q) of prescribed coordinates at ``q`` [rad, m]."""
    sys_ = system(robot, [], prescribed)
    return sys_.residual(q, targets=np.zeros(len(prescribed)))


def solve_velocity(robot: PasibotRobot, q, prescribed, rates, cmodels=None) -> np.ndarray:
    """V on the constraint manifold: [J_c; J_s] v = [0; s_dot*]."""
    return system(robot, cmodels, prescribed).velocity(q, rates=rates)


def solve_acceleration(robot: PasibotRobot, q, v, prescribed, accelerations, cmodels=None) -> np.ndarray:
    """A on the manifold: [J_c; J_s] a = [-Jdot_c v; s_ddot* - Jdot_s v]."""
    return system(robot, cmodels, prescribed).acceleration(q, v, accelerations=accelerations)


# --------------------------------------------------------------------------- assembly
def angular_coordinates(model: pin.Model) -> np.ndarray:
    """Mask (nq,) of the coordinates that are angles (revolute joints, the hip pitch) [bool] (cached)."""
    return _ANGULAR.get(model, lambda: _angular_mask(model))


def _angular_mask(model: pin.Model) -> np.ndarray:
    mask = np.ones(model.nq, dtype=bool)
    for joint in model.joints[1:]:
        subjoints = joint.extract().joints if joint.shortname() == "JointModelComposite" else [joint]
        index = joint.idx_q
        for sub in subjoints:
            name = sub.shortname()
            if "Prismatic" in name or name in ("JointModelPX", "JointModelPY", "JointModelPZ"):
                mask[index] = False
            index += sub.nq
    return mask


@dataclass(frozen=True)
class _AssemblyPlan:
    """What :func:`analytic_configurations` needs of a model, looked up once (per model)."""

    neutral: np.ndarray
    columns: dict[str, dict[str, int]]  # side -> joint name without the side -> q column


_PLANS: PerObjectCache[_AssemblyPlan] = PerObjectCache()
_WELDS: PerObjectCache[pin.RigidConstraintModel] = PerObjectCache()


def _assembly_plan(robot: PasibotRobot) -> _AssemblyPlan:
    """The :class:`_AssemblyPlan` of ``robot``'s model (cached; the entry keeps the model alive)."""
    return _PLANS.get(robot.model, lambda: _make_assembly_plan(robot))


def _make_assembly_plan(robot: PasibotRobot) -> _AssemblyPlan:
    model = robot.model
    columns: dict[str, dict[str, int]] = {side: {} for side in sides(robot.legs)}
    for j in range(1, model.njoints):
        side, _, rest = model.names[j].partition("_")
        if side in columns and model.joints[j].nq == 1:
            columns[side][rest] = model.joints[j].idx_q
    return _AssemblyPlan(np.array(pin.neutral(model)), columns)


def stance_weld(robot: PasibotRobot, stance: str, ankle_x: float = 0.0) -> pin.RigidConstraintModel:
    """The weld of ``stance``'s foot flat on the ground, its ankle at world x = ``ankle_x`` [m] (cached).

    The same object is returned for the same model, stance and ``ankle_x``: do not modify it.
    """
    model = robot.model
    y = robot.geometry.hip_half_width * (-1 if stance == "right" else 1)
    return _WELDS.get(
        model,
        lambda: constraints.weld_constraint(
            model, f"{stance}_foot", pin.SE3(np.eye(3), np.array([ankle_x, y, 0.0])), f"{stance}_foot_weld"
        ),
        (stance, float(ankle_x), float(y)),
    )


def analytic_configurations(
    robot: PasibotRobot,
    thetas,
    theta_left=None,
    hip_pitch_value: float = 0.0,
    swing_foot_pitch: float | None = 0.0,
    stance: str | None = None,
    ankle_x: float = 0.0,
) -> tuple[np.ndarray, pin.RigidConstraintModel | None]:
    """Configurations from the analytic assembly alone, one per crank angle (closed to round-off).

    Vectorised: the leg points of every sample and both legs come from one call of the closed
    form (:func:`~pasibot_pin.model.assembly.leg_points_complex`), the joint columns and the
    weld are looked up once per model.

    Args:
        robot: a loaded robot.
        thetas: right crank angles (N,) [rad].
        theta_left: left crank angles (N,) [rad] (default ``thetas + pi``).
        hip_pitch_value: hip pitch for the ``spring`` biped [rad].
        swing_foot_pitch: swing-foot pitch for the ``spring`` biped [rad]; ``None`` keeps the
            swing foot square to its shank (ankle coordinate 0).
        stance: the welded foot (two legs; default the robot's stance or ``right``).
        ankle_x: world x of the stance ankle [m] (its z is 0: the sole is on the ground).

    Returns:
        (q (N, nq), the stance weld for a floating robot or ``None``).

    Raises:
        ValueError: a loop that cannot assemble at one of the crank angles (named).

    """
    thetas = np.atleast_1d(np.asarray(thetas, dtype=float))
    for name, value in (("theta", thetas), ("theta_left", theta_left), ("hip_pitch", hip_pitch_value)):
        if value is not None and not np.all(np.isfinite(value)):
            raise ParameterError(f"parameter {name!r} must be finite, got {value!r}")
    left = thetas + math.pi
    if theta_left is not None:
        left = np.broadcast_to(np.asarray(theta_left, dtype=float), thetas.shape)
    q = np.tile(_assembly_plan(robot).neutral, (len(thetas), 1))
    weld = _closed_form(robot, thetas, left, (q,), hip_pitch_value, swing_foot_pitch, stance, ankle_x)
    return q, weld


def analytic_motion(
    robot: PasibotRobot,
    thetas,
    omega: float,
    swing_foot_pitch: float | None = 0.0,
    stance: str | None = None,
    ankle_x: float = 0.0,
    hip_pitch_value: float = 0.0,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, pin.RigidConstraintModel | None]:
    """q, v and a along a crank sweep from the closed form and its exact time derivatives.

    Both cranks turn at ``omega`` (the left one pi ahead); the prescribed hip pitch and swing-foot
    pitch are held. The closed form of :func:`analytic_configurations` is evaluated on
    :class:`~pasibot_pin.model.jet.Jet` s (theta, omega, 0): every coordinate comes with its
    velocity dq/dt = q'(theta) omega and acceleration q''(theta) omega^2, exactly (the chain
    rule through the circle intersections; no Jacobian solve, no finite differences).

    Args:
        robot: a loaded robot.
        thetas: right crank angles (N,) [rad].
        omega: crank speed [rad/s].
        swing_foot_pitch: swing-foot pitch for the ``spring`` biped [rad] (``None``: square).
        stance: the welded foot (default the robot's stance or ``right``).
        ankle_x: world x of the stance ankle [m].
        hip_pitch_value: hip pitch for the ``spring`` biped [rad].

    Returns:
        (q (N, nq), v (N, nv), a (N, nv), the stance weld or ``None``).

    Raises:
        ValueError: a loop that cannot assemble at one of the crank angles (named).

    """
    thetas = np.atleast_1d(np.asarray(thetas, dtype=float))
    if not np.all(np.isfinite(thetas)) or not math.isfinite(omega):
        raise ParameterError("parameters 'thetas' and 'omega' must be finite")
    n = len(thetas)
    q = np.tile(_assembly_plan(robot).neutral, (n, 1))
    v, a = np.zeros((n, robot.model.nv)), np.zeros((n, robot.model.nv))
    right, left = jet.Jet(thetas, float(omega), 0.0), jet.Jet(thetas + math.pi, float(omega), 0.0)
    weld = _closed_form(robot, right, left, (q, v, a), hip_pitch_value, swing_foot_pitch, stance, ankle_x)
    return q, v, a, weld


def _column(robot: PasibotRobot, plan: _AssemblyPlan, side: str, joint: str) -> int:
    """The q column of ``side``'s ``joint`` (a name without the side)."""
    columns = plan.columns[side]
    return columns[joint] if joint in columns else robot.idx_q(f"{side}_{joint}")


def _put(out: tuple[np.ndarray, ...], column: int, value) -> None:
    """Write a coordinate (array or jet) into column ``column`` of q (and v, a for a jet)."""
    if isinstance(value, jet.Jet):
        out[0][:, column] = value.v
        if len(out) > 1:
            out[1][:, column], out[2][:, column] = value.d, value.dd
    else:
        out[0][:, column] = value


def _closed_form(robot: PasibotRobot, right, left, out, hip_pitch_value, swing_foot_pitch, stance, ankle_x):
    """Fill ``out`` = (q,) or (q, v, a) from the closed form at crank angles (arrays or jets); the weld.

    Every leg's samples go through one call of the closed form and one of the joint angles
    (arrays of all legs end to end), and each of q, v, a is written with one assignment per leg.
    """
    g, variant = robot.geometry, robot.spec
    plan = _assembly_plan(robot)
    n = len(jet.value(right))
    legs = sides(robot.legs)
    angles = {"right": right, "left": left}
    stance = stance or robot.stance or "right"
    both: jet.Jet | np.ndarray
    if isinstance(right, jet.Jet):
        both = jet.Jet(np.concatenate([angles[side].v for side in legs]), right.d, right.dd)
    else:
        both = np.concatenate([angles[side] for side in legs])
    every = leg_points_complex(both, g, variant)
    stance_part = slice(n * legs.index(stance), n * (legs.index(stance) + 1)) if stance in legs else slice(0, n)
    pitch = np.zeros(n)
    if robot.floating:
        if variant.free_ankle:
            pitch[:] = hip_pitch_value
        else:
            stance_points = {k: v[stance_part] if isinstance(v, jet.Jet) or np.ndim(v) else v for k, v in every.items()}
            pitch = -sole_angle_from_points(stance_points, variant)
    foot_angle: float | np.ndarray | None = None
    if variant.free_ankle:
        if not robot.floating:
            foot_angle = 0.0
        else:
            swing = np.full(n, np.nan) if swing_foot_pitch is None else swing_foot_pitch - pitch
            foot_angle = np.concatenate([-pitch if side == stance else swing for side in legs])
    coordinates = joint_angles_complex(every, both, variant, foot_angle)
    names = list(coordinates)
    columns = [[_column(robot, plan, side, name) for name in names] for side in legs]
    for part, target in enumerate(out):
        values = np.empty((len(names), len(legs) * n))
        for row, name in enumerate(names):
            value = coordinates[name]
            if isinstance(value, jet.Jet):
                values[row] = (value.v, value.d, value.dd)[part]
            else:
                values[row] = value if part == 0 else 0.0
        for i in range(len(legs)):
            target[:, columns[i]] = values[:, i * n : (i + 1) * n].T
    if not robot.floating:
        return None
    ankle = every["p13"][stance_part] * jet.exp_i(pitch)  # the ankle turned by the hip pitch
    _put(out, 0, ankle_x - ankle.real)
    _put(out, 1, -ankle.imag)
    _put(out, 2, pitch)
    return stance_weld(robot, stance, ankle_x)


def assemble(
    robot: PasibotRobot,
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
            raise ParameterError(f"parameter {name!r} must be finite, got {value!r}")
    stance = stance or robot.stance or "right"
    q, weld = analytic_configurations(
        robot,
        [float(theta)],
        None if theta_left is None else [float(theta_left)],
        hip_pitch_value,
        swing_foot_pitch,
        stance,
        ankle_x,
    )
    cmodels = list(robot.loop_constraints) + ([weld] if weld is not None else [])
    prescribed = default_prescriptions(robot, stance)
    return solve_configuration(robot, q[0], prescribed, None, cmodels)


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


def mobility(robot: PasibotRobot, q: np.ndarray | None = None) -> Mobility:
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
def crank_sweep(robot: PasibotRobot, thetas: ArrayLike, **assemble_kwargs) -> np.ndarray:
    """Closed configurations along a sequence of right-crank angles, warm-started.

    The first sample comes from :func:`assemble`; each next one from Newton started at
    the previous solution, with the crank targets moved (continuation keeps the branch).
    The stance foot stays the one of the first sample.

    Returns:
        Array (len(thetas), nq).

    """
    thetas = np.asarray(thetas, dtype=float)
    if not np.all(np.isfinite(thetas)):
        raise ParameterError("crank angles theta must be finite")
    out = np.zeros((len(thetas), robot.model.nq))
    q = assemble(robot, float(thetas[0]), **assemble_kwargs)
    stance = assemble_kwargs.get("stance") or robot.stance or "right"
    cmodels = list(robot.loop_constraints)
    if robot.floating:
        cmodels.append(robot.with_stance(stance, q).weld)
    prescribed = default_prescriptions(robot, stance)
    base_targets = prescribed_values(robot, q, prescribed)
    out[0] = q
    for k in range(1, len(thetas)):
        targets = base_targets.copy()
        for row, p in enumerate(prescribed):
            if is_crank(robot, p):
                targets[row] = base_targets[row] + (thetas[k] - thetas[0])
        q = solve_configuration(robot, q, prescribed, targets, cmodels)
        out[k] = q
    _check_branch(robot, thetas, out, assemble_kwargs.get("theta_left"))
    return out


BRANCH_TOL = 1e-6
"""Largest gap [rad] between a swept leg joint and the analytic assembly's branch (:func:`crank_sweep`)."""


def _check_branch(robot: PasibotRobot, thetas: np.ndarray, qs: np.ndarray, theta_left: float | None) -> None:
    """Raise ``ValueError`` where a sweep left the analytic assembly's branch (knee forward, coupler below).

    The leg linkage has one degree of freedom per leg: every leg joint but the ankle spring is a
    function of the crank angle on a given branch, so comparing them detects a branch switch.
    """
    left = None if theta_left is None else theta_left + (thetas - thetas[0])
    try:
        ref, _ = analytic_configurations(robot, thetas, left)
    except ValueError:
        return  # the analytic assembly fails somewhere: Newton's own errors name the loop
    model = robot.model
    columns = [
        model.joints[j].idx_q
        for j in range(1, model.njoints)
        if model.joints[j].nq == 1
        and model.names[j] not in robot.spring_joints
        and model.names[j].split("_", 1)[0] in sides(robot.legs)
        and angular_coordinates(model)[model.joints[j].idx_q]
    ]
    gap = np.abs(np.angle(np.exp(1j * (qs[:, columns] - ref[:, columns]))))
    switched = gap.max(axis=1) > BRANCH_TOL
    if np.any(switched):
        k = int(np.argmax(switched))
        joint = model.names[[j for j in range(1, model.njoints) if model.joints[j].nq == 1][0]]
        for j in range(1, model.njoints):
            if model.joints[j].nq == 1 and model.joints[j].idx_q == columns[int(np.argmax(gap[k]))]:
                joint = model.names[j]
        raise ClosureError(
            f"the crank sweep switched assembly branch (knee or coupler flipped, {joint} off by "
            f"{math.degrees(gap[k].max()):.1f} deg) at crank angle {math.degrees(thetas[k]):.3f} deg; "
            f"K = {robot.geometry.K:g} is near the end of the range where the crank turns fully: "
            "take a larger K or finer crank steps"
        )
