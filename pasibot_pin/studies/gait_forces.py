"""The forces of a prescribed (kinematic) gait, for the viewer to draw: the ground's and the cut joints'.

The 3-D viewer (:mod:`pasibot_pin.viz.viewer`) only draws; the physics of what it draws is here:
the gait itself (:func:`gait_trajectory`), the quasi-static ground force through the centre of
mass (:func:`quasi_static_ground_force`) and, at a crank speed, the ground reaction through the
centre of pressure and every cut joint's force by inverse dynamics (:func:`gait_reaction_forces`).
Each force is a pair (application points (N, 3) [m], force vectors (N, 3) [N]) in the world frame.

Units: SI [m, N, rad/s].
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from pasibot_pin.dynamics.inverse import inverse_dynamics
from pasibot_pin.errors import ParameterError, SimulationError
from pasibot_pin.kinematics.gait import Gait, prescribed_gait
from pasibot_pin.model.coordinates import SIDES, other

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot

__all__ = ["PointForces", "quasi_static_ground_force", "gait_reaction_forces", "gait_trajectory"]

PointForces = tuple[np.ndarray, np.ndarray]
"""(application points (N, 3) [m], force vectors (N, 3) [N]), world frame."""


def gait_trajectory(robot: PasibotRobot, steps: int = 2, samples_per_step: int = 30) -> Gait:
    """The gait to show: :func:`pasibot_pin.kinematics.gait.prescribed_gait` (stance exchange every half crank turn)."""
    return prescribed_gait(robot, steps=steps, samples_per_step=samples_per_step)


def quasi_static_ground_force(robot: PasibotRobot, qs: np.ndarray, stance: Sequence[str]) -> PointForces:
    """The ground's total force on the robot when it walks slowly (omega -> 0), per frame.

    With negligible accelerations the only external forces are gravity and the ground, so the
    ground pushes up with the whole weight, along the vertical through the centre of mass (the
    centre of pressure lies below the COM). The point is on the ground (z = 0) below the COM, in
    the stance leg's plane.

    Args:
        robot: a two-legged robot.
        qs: configurations (N, nq).
        stance: the stance side at each frame (``'right'`` / ``'left'``), e.g. ``gait.stance``.

    Returns:
        (points, forces (0, 0, m g)) [m, N].

    """
    qs = np.atleast_2d(np.asarray(qs, dtype=float))
    if len(stance) != len(qs) or any(s not in SIDES for s in stance):
        raise ParameterError("parameter 'stance' must give 'right' or 'left' for every frame")
    data = robot.model.createData()
    mass = sum(inertia.mass for inertia in robot.model.inertias)
    weight = mass * float(np.linalg.norm(robot.model.gravity.linear))
    points = np.zeros((len(qs), 3))
    for k, q in enumerate(qs):
        com = pin.centerOfMass(robot.model, data, q)
        pin.framesForwardKinematics(robot.model, data, q)
        points[k] = [com[0], data.oMf[robot.frame_id(f"{stance[k]}_foot")].translation[1], 0.0]
    return points, np.tile([0.0, 0.0, weight], (len(qs), 1))


def gait_reaction_forces(robot: PasibotRobot, gait: Gait, omega: float = 0.0) -> dict[str, PointForces]:
    """Ground reaction and cut-joint forces along a gait, from :func:`pasibot_pin.dynamics.inverse_dynamics`.

    The ground's in-plane wrench on the stance foot (Fx, Fz and the moment about the ankle) is one
    force through the centre of pressure, on the ground. Each cut joint's force on the first link
    of its pair acts at the joint.

    Args:
        robot: the two-legged robot.
        gait: a :class:`pasibot_pin.kinematics.gait.Gait` of that robot (flat feet).
        omega: crank speed [rad/s]; 0 = quasi-static.

    Returns:
        ``{'ground': ..., 'stance_j2': ..., 'swing_j5': ...}``: (points, forces) [m, N].

    Raises:
        SimulationError: no vertical ground reaction at a frame (the centre of pressure is undefined).

    """
    res = inverse_dynamics(robot, gait.theta, omega)
    data = robot.model.createData()
    n = len(gait.q)
    ground_points, ground_forces = np.zeros((n, 3)), np.zeros((n, 3))
    cut_points = {name: np.zeros((n, 3)) for name in res.cuts}
    for k, q in enumerate(gait.q):
        pin.framesForwardKinematics(robot.model, data, q)
        side = res.stance[k]
        fx, fz, moment = res.ground[k]
        if not abs(fz) > 1e-9:
            raise SimulationError(f"no vertical ground reaction at frame {k}: the centre of pressure is undefined")
        ankle = data.oMf[robot.frame_id(f"{side}_foot")].translation
        ground_points[k] = [ankle[0] + moment / fz, ankle[1], 0.0]
        ground_forces[k] = [fx, 0.0, fz]
        for name in res.cuts:
            role, joint = name.split("_", 1)
            leg = side if role == "stance" else other(side)
            cut_points[name][k] = data.oMf[robot.frame_id(f"{leg}_loop_{joint}_a")].translation
    out = {"ground": (ground_points, ground_forces)}
    for name, f in res.cuts.items():
        out[name] = (cut_points[name], np.column_stack([f[:, 0], np.zeros(n), f[:, 1]]))
    return out
