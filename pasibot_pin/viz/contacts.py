"""Where each foot touches the ground along a trajectory, for the 3-D viewer and the GIF.

:func:`foot_contacts` reads the contact from the geometry alone: a sole point (heel or toe) whose
height above the ground (the plane z = 0, or the walk's :class:`~pasibot_pin.dynamics.floor.ground.Ground`:
a slope, a step edge) is within :data:`CONTACT_TOLERANCE` touches it. Each foot's mode
per frame is then ``flat`` (heel and toe down), ``heel``, ``toe``, ``air`` or ``below ground`` (a
point under the plane: the welded model's swing foot can pass through the ground). A simulation
that knows more (``sliding`` on the floor) passes its own modes to the viewer and the GIF instead.

Lengths [m]; angles [rad].
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from pasibot_pin.model.spatial import SOLE_POINTS

if TYPE_CHECKING:
    from pasibot_pin.dynamics.floor.ground import Ground
    from pasibot_pin.model.robot import PasibotRobot

CONTACT_TOLERANCE = 1e-3
"""A sole point this close to the ground [m] touches it."""

POINTS = (SOLE_POINTS[0], SOLE_POINTS[-1])
"""The sole's two ends of each foot, heel and toe (frames ``<side>_heel`` and ``<side>_toe``;
:data:`~pasibot_pin.model.spatial.SOLE_POINTS`)."""


@dataclass(frozen=True)
class FootContacts:
    """Sole points and contact modes along a trajectory.

    Attributes:
        points: side -> (N, 2, 3) world positions of heel and toe [m].
        touching: side -> (N, 2) heel/toe within :data:`CONTACT_TOLERANCE` of the ground.
        heights: side -> (N, 2) heel/toe height above the ground [m] (over the tread under it).
        modes: side -> the foot's mode at each frame.
        crank: (N,) right crank angle theta [rad] (the seed's theta: measured from joint 0 -> joint 3).

    """

    points: dict[str, np.ndarray]
    touching: dict[str, np.ndarray]
    heights: dict[str, np.ndarray]
    modes: dict[str, list[str]]
    crank: np.ndarray


def mode_of(heel_z: float, toe_z: float, tol: float = CONTACT_TOLERANCE) -> str:
    """A foot's mode from its heel and toe heights [m]."""
    if min(heel_z, toe_z) < -tol:
        return "below ground"
    heel, toe = abs(heel_z) <= tol, abs(toe_z) <= tol
    return "flat" if heel and toe else "heel" if heel else "toe" if toe else "air"


def foot_contacts(
    robot: PasibotRobot, qs: np.ndarray, tol: float = CONTACT_TOLERANCE, ground: Ground | None = None
) -> FootContacts:
    """Heel and toe of every foot, which of them touch the ground, and each foot's mode, per row of ``qs``.

    Args:
        robot: the robot.
        qs: configurations (N, nq).
        tol: a point this close to the ground touches it [m].
        ground: the ground (default the flat floor z = 0): heights are over the tread under each point.

    """
    qs = np.atleast_2d(np.asarray(qs, dtype=float))
    sides = [s for s in ("right", "left") if robot.model.existFrame(f"{s}_heel")]
    ids = {s: [robot.frame_id(f"{s}_{p}") for p in POINTS] for s in sides}
    points = {s: np.zeros((len(qs), 2, 3)) for s in sides}
    data = robot.model.createData()
    for k, q in enumerate(qs):
        pin.framesForwardKinematics(robot.model, data, q)
        for s in sides:
            for i, fid in enumerate(ids[s]):
                points[s][k, i] = data.oMf[fid].translation
    if ground is None:
        heights = {s: points[s][:, :, 2].copy() for s in sides}
    else:
        heights = {s: ground.gap(points[s].reshape(-1, 3)).reshape(-1, 2) for s in sides}
    touching = {s: np.abs(heights[s]) <= tol for s in sides}
    modes = {s: [mode_of(h[0], h[1], tol) for h in heights[s]] for s in sides}
    crank = qs[:, robot.model.joints[robot.model.getJointId("right_j0_crank")].idx_q].copy()
    return FootContacts(points, touching, heights, modes, crank)
