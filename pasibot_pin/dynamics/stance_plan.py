"""One stance of a crank sweep, set up once: its rows, actuation, couplings and Newton-Euler layout.

:func:`stance_plan` gathers what :func:`pasibot_pin.dynamics.inverse.inverse_dynamics` needs of a
robot standing on one foot that does not change from sample to sample (cached per model, stance,
swing-foot mode, motor layout and where the stance foot stands): the square constraint system
(loops, the stance weld, the prescribed coordinates of the variant's record), the actuation S,
the motor coupling rows, the tree's layout. :func:`actuation` and :func:`couplings` are the
variant's actuators and a motor layout's coupling rows on any robot (``studies.single_motor``
splits with them too); :func:`ankle_angles` reads beta, the angle from the forward foot to the shank.

Units: SI; angles [rad].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from pasibot_pin.caches import PerObjectCache
from pasibot_pin.constraints import ConstraintSystem, CoordinateRow, coupling, frame_rows, is_weld, planar_rows
from pasibot_pin.constraints.planar import PlanarRowBlocks
from pasibot_pin.dynamics.newton_euler import TreeLayout, tree_layout
from pasibot_pin.dynamics.planar_id import PlanarInverseDynamics, planar_inverse_dynamics
from pasibot_pin.model import closure
from pasibot_pin.model.closure import Prescribed, frame_pitch, hip_pitch, joint_coordinate
from pasibot_pin.model.coordinates import other
from pasibot_pin.model.robot import PasibotRobot
from pasibot_pin.model.variants import MotorLayout, get_motor_layout

__all__ = [
    "StancePlan",
    "actuated_joints",
    "actuation",
    "ankle_angles",
    "couplings",
    "prescriptions",
    "stance_plan",
    "unwrap_angles",
]


def _generic(name: str, stance: str) -> str:
    side, rest = name.split("_", 1)
    return ("stance_" if side == stance else "swing_") + rest


def prescriptions(robot: PasibotRobot, stance: str, swing_foot: str) -> list[Prescribed]:
    """Both cranks; with a free ankle (the variant's record) also the hip pitch and the swing foot."""
    rows: list[Prescribed] = [joint_coordinate(robot, j) for j in robot.actuated_joints]
    if robot.spec.free_ankle:
        swing = other(stance)
        ankle = f"{swing}_{robot.spec.spring_joints[0]}"
        last = frame_pitch(robot, f"{swing}_foot") if swing_foot == "level" else joint_coordinate(robot, ankle)
        rows += [hip_pitch(robot), last]
    return rows


def actuated_joints(robot: PasibotRobot, stance: str, layout: MotorLayout) -> list[str]:
    """The actuated joints, in the order of u: the motor(s), then the stance and swing spring joints.

    Two motors: stance crank, swing crank. One motor: the layout's motor (the right crank).
    """
    swing = other(stance)
    if len(layout.motors) == 2:
        motors = [f"{stance}_j0_crank", f"{swing}_j0_crank"]
    else:
        motors = list(layout.motors)
    return motors + [f"{side}_{j}" for side in (stance, swing) for j in robot.spec.spring_joints]


def actuation(robot: PasibotRobot, stance: str, layout: MotorLayout | str = "two") -> np.ndarray:
    """The actuation S (n_u x nv) of ``robot`` on ``stance``: one row per joint of :func:`actuated_joints`."""
    joints = actuated_joints(robot, stance, get_motor_layout(layout))
    s = np.zeros((len(joints), robot.model.nv))
    for row, joint in enumerate(joints):
        s[row, robot.idx_v(joint)] = 1.0
    return s


def couplings(robot: PasibotRobot, layout: MotorLayout) -> list[CoordinateRow]:
    """The layout's coupling rows (one motor: q_L - q_R - pi = 0) on ``robot``."""
    return [coupling(f"{a}-{b}", robot.idx_v(a), robot.idx_v(b), offset) for a, b, offset in layout.couplings]


_ANKLE_ENDS: PerObjectCache[PlanarRowBlocks] = PerObjectCache()


def _ankle_ends(robot: PasibotRobot, side: str) -> PlanarRowBlocks:
    """The shank frame's pitch and the toe and heel positions of ``side``, as planar rows (cached)."""

    def build() -> PlanarRowBlocks:
        frames = [robot.frame_id(f"{side}_{name}") for name in ("l5_shank", "toe", "heel")]
        return frame_rows(robot.model, frames, [1, 2], [0])

    return _ANKLE_ENDS.get(robot.model, build, side)


def ankle_angles(robot: PasibotRobot, q: np.ndarray, side: str) -> np.ndarray:
    """Beta of ``side`` for configurations q (N, nq): from the forward foot (heel -> toe) to the shank [rad].

    With a spring ankle it is pi/2 - q_ankle; otherwise it is read from the frames
    (pi/2 for the rigid foot; the parallel extension's foot follows the stabiliser).
    """
    q = np.atleast_2d(q)
    if robot.spec.free_ankle:
        return math.pi / 2 - q[:, robot.idx_q(f"{side}_{robot.spec.spring_joints[0]}")]
    ends = _ankle_ends(robot, side)
    points, pitch = ends.positions(q), q @ ends.pitch_A.T + ends.pitch_a0
    up = pitch[:, 0] + math.pi  # ankle -> knee is minus the shank's x axis
    sole = np.angle(points[:, 0] - points[:, 1])
    diff = up - sole
    return diff - 2 * math.pi * np.round(diff / (2 * math.pi))  # math.remainder, elementwise


@dataclass
class StancePlan:
    """Everything of one stance of a sweep that does not change from sample to sample (cached).

    Attributes:
        robot: the robot standing on ``side`` with the stance weld.
        rows: the square constraint system (loops, weld, prescribed coordinates).
        s_matrix: the actuation S (n_u, nv).
        coupling: the motor-coupling rows C (n_c, nv) (constant).
        tree: the batched Newton-Euler layout (COMs, joint origins, constraint ends).
        planar: the batched planar inverse dynamics on ``tree`` (torques and reactions).
        angular: mask of the angle coordinates (unwrapped along a sweep).
        weld_rows: the weld's rows of lambda; cut_rows: generic name of every loop -> its rows.
        joint_names: generic name of every tree joint 2 .. njoints - 1 -> its index.
        model_copy: the model as the plan was made (a plan is stale once the model changes).

    """

    robot: PasibotRobot
    rows: ConstraintSystem
    s_matrix: np.ndarray
    coupling: np.ndarray
    tree: TreeLayout
    planar: PlanarInverseDynamics
    angular: np.ndarray
    weld_rows: slice
    cut_rows: dict[str, slice]
    joint_names: dict[str, int]
    model_copy: pin.Model


_PLANS: PerObjectCache[StancePlan] = PerObjectCache()


def stance_plan(robot: PasibotRobot, side: str, swing_foot: str, layout: MotorLayout, stance_x: float) -> StancePlan:
    """The :class:`StancePlan` of ``robot`` standing on ``side`` with its ankle at x = ``stance_x`` [m]."""
    return _PLANS.get(
        robot.model,
        lambda: _make_stance_plan(robot, side, swing_foot, layout, stance_x),
        (side, swing_foot, layout.name, float(stance_x)),
        fresh=lambda plan: plan.model_copy == robot.model,  # a plan is stale once the model changed in place
    )


def _make_stance_plan(
    robot: PasibotRobot, side: str, swing_foot: str, layout: MotorLayout, stance_x: float
) -> StancePlan:
    model = robot.model
    rs = robot.with_weld(side, closure.stance_weld(robot, side, stance_x))
    rows = closure.system(rs, rs.constraint_models, prescriptions(rs, side, swing_foot))
    coupling_rows = closure.system(rs, [], couplings(rs, layout))
    weld_rows, cut_rows = slice(0, 0), {}
    for cm, rows_of in zip(rs.constraint_models, planar_rows(rs.constraint_models)):
        if is_weld(cm):
            weld_rows = rows_of
        else:
            cut_rows[_generic(cm.name, side)] = rows_of
    tree = tree_layout(model, rs.constraint_models)
    s_matrix = actuation(rs, side, layout)
    return StancePlan(
        robot=rs,
        rows=rows,
        s_matrix=s_matrix,
        coupling=coupling_rows.jacobian(pin.neutral(model)).reshape(-1, model.nv),
        tree=tree,
        planar=planar_inverse_dynamics(model, tree),
        angular=closure.angular_coordinates(model),
        weld_rows=weld_rows,
        cut_rows=cut_rows,
        joint_names={_generic(model.names[j], side): j for j in range(2, model.njoints)},
        model_copy=pin.Model(model),
    )


def unwrap_angles(q: np.ndarray, angular: np.ndarray) -> None:
    """Unwrap the angle columns of q (N, nq) along the sweep, in place (as ``np.unwrap``: steps below pi)."""
    if len(q) < 2:
        return
    turns = np.round(np.diff(q[:, angular], axis=0) * (0.5 / math.pi))  # whole turns between samples
    if turns.any():
        q[1:, angular] -= (2 * math.pi) * np.cumsum(turns, axis=0)
