"""What the 3-D viewer draws besides the robot's meshes: colours, markers, paths and force arrows.

The robot's visuals coloured by group (the colours of :data:`pasibot_pin.viz.plots.GROUP_COLOURS`,
so the 3-D view and the 2-D plots agree; the hip see-through), the joint and contact markers of a
trajectory, the feet's and hip's paths, and force arrows (:class:`ForceArrows`). The forces' physics
is :mod:`pasibot_pin.studies.gait_forces`; here they become arrows.

Lengths [m], forces [N].
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from pasibot_pin.errors import ParameterError
from pasibot_pin.studies.gait_forces import gait_reaction_forces, quasi_static_ground_force
from pasibot_pin.viz.contacts import foot_contacts
from pasibot_pin.viz.plots import GROUP_COLOURS, link_group

if TYPE_CHECKING:
    from pasibot_pin.dynamics.floor.ground import Ground
    from pasibot_pin.model.robot import PasibotRobot

PATH_COLOURS: dict[str, str] = {"right": "#d62728", "left": "#8e44ad", "hip": "#555555"}
"""Colours of the foot-path (ankle) and hip traces."""

GROUND_COLOUR = "#cfc8b8"
FORCE_COLOUR = "#e6007e"
CUT_FORCE_COLOUR = "#ffd400"

JOINT_COLOUR = "#222222"
CONTACT_COLOUR = "#1a9e3a"
HIP_OPACITY = 0.25
"""Opacity of the hip body: it would hide the far leg's linkage."""
JOINT_RADIUS = 0.012
"""Radius of the joint markers [m]."""
CONTACT_RADIUS = 0.02
"""Radius of the contact-point markers [m]."""


def rgba(colour: str) -> np.ndarray:
    """'#rrggbb' -> RGBA floats in [0, 1]."""
    value = colour.lstrip("#")
    return np.array([int(value[i : i + 2], 16) / 255.0 for i in (0, 2, 4)] + [1.0])


def hex_int(colour: str) -> int:
    """'#rrggbb' -> 0xrrggbb."""
    return int(colour.lstrip("#"), 16)


def visuals_of(robot: PasibotRobot) -> pin.GeometryModel:
    """The robot's visual model; ValueError for a robot loaded with ``visuals=False`` (nothing to draw)."""
    if robot.visual_model is None:
        raise ParameterError("parameter 'robot' has no visuals: load it with visuals=True to draw it")
    return robot.visual_model


def coloured_visual_model(robot: PasibotRobot) -> pin.GeometryModel:
    """A copy of the robot's visual model with every object coloured by its link's group.

    The group (hoeken, pantograph, extension, foot, hip) comes from
    :func:`pasibot_pin.viz.plots.link_group`, the colours from :data:`GROUP_COLOURS`, so the
    3-D view and the 2-D plots agree.
    """
    visual = visuals_of(robot).copy()
    for obj in visual.geometryObjects:
        group = link_group(robot.model.frames[obj.parentFrame].name)
        obj.meshColor = rgba(GROUP_COLOURS[group])
        if group == "hip":  # see-through: the far leg's linkage shows behind it
            obj.meshColor[3] = HIP_OPACITY
    return visual


def marker_paths(
    robot: PasibotRobot,
    qs: np.ndarray,
    modes: Mapping[str, Sequence[str]] | None = None,
    ground: Ground | None = None,
) -> dict:
    """Positions of the joint and contact markers along a trajectory.

    Args:
        robot: the robot.
        qs: configurations (N, nq).
        modes: each foot's contact mode per frame (default: from the geometry,
            :func:`pasibot_pin.viz.contacts.foot_contacts`).
        ground: the ground the contacts are read on (default the flat floor z = 0).

    Returns:
        ``{node: (positions (N, 3) [m], shown (N,) bool)}``: ``joints/<joint>`` for every joint and
        cut joint, ``contacts/<side>_<heel|toe>`` shown where that point touches the ground.

    """
    qs = check_trajectory(robot, qs)
    model, data = robot.model, robot.model.createData()
    joints = {model.names[j]: j for j in range(1, model.njoints)}
    cuts = {f.name: robot.frame_id(f.name) for f in model.frames if "_loop_" in f.name and f.name.endswith("_a")}
    out = {f"joints/{name}": np.zeros((len(qs), 3)) for name in [*joints, *cuts]}
    for k, q in enumerate(qs):
        pin.framesForwardKinematics(model, data, q)
        for name, j in joints.items():
            out[f"joints/{name}"][k] = data.oMi[j].translation
        for name, fid in cuts.items():
            out[f"joints/{name}"][k] = data.oMf[fid].translation
    paths = {node: (pos, np.ones(len(qs), bool)) for node, pos in out.items()}
    contacts = foot_contacts(robot, qs, ground=ground)
    for side, points in contacts.points.items():
        for i, point in enumerate(("heel", "toe")):
            shown = contacts.touching[side][:, i]
            if modes is not None:
                shown = np.array([m not in ("air",) for m in modes[side]]) & shown
            paths[f"contacts/{side}_{point}"] = (points[:, i].copy(), shown)
    return paths


def mark_transform(position: np.ndarray, shown: bool) -> np.ndarray:
    """A marker's pose (4x4) at ``position`` [m]; a hidden one shrunk to nothing."""
    T = np.eye(4)
    T[:3, 3] = position
    if not shown:  # hidden: shrunk to nothing (meshcat animates transforms, not visibility)
        T[:3, :3] *= 1e-6
    return T


def sole_depth(robot: PasibotRobot) -> float:
    """How far the foot visuals reach below their sole plane (the foot frame's z = 0) [m]."""
    depth = 0.0
    for obj in visuals_of(robot).geometryObjects:
        if not robot.model.frames[obj.parentFrame].name.endswith("_foot"):
            continue
        half = getattr(obj.geometry, "halfSide", None)
        if half is None:
            continue
        corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * half
        in_foot = robot.model.frames[obj.parentFrame].placement.inverse() * obj.placement  # placement: joint frame
        z = (corners @ in_foot.rotation.T + in_foot.translation)[:, 2]
        depth = max(depth, -float(z.min()))
    return depth


def frame_paths(robot: PasibotRobot, qs: np.ndarray, frames: Sequence[str]) -> dict[str, np.ndarray]:
    """World positions of ``frames`` over a trajectory: ``{frame: (N, 3)}`` [m]."""
    qs = check_trajectory(robot, qs)
    ids = {name: robot.frame_id(name) for name in frames}
    out = {name: np.zeros((len(qs), 3)) for name in frames}
    data = robot.model.createData()
    for k, q in enumerate(qs):
        pin.framesForwardKinematics(robot.model, data, q)
        for name, fid in ids.items():
            out[name][k] = data.oMf[fid].translation
    return out


def foot_paths(robot: PasibotRobot, qs: np.ndarray) -> dict[str, np.ndarray]:
    """Ankle paths of every leg over a trajectory: ``{'right': (N, 3), 'left': (N, 3)}`` [m]."""
    sides = [s for s in ("right", "left") if robot.model.existFrame(f"{s}_foot")]
    paths = frame_paths(robot, qs, [f"{s}_foot" for s in sides])
    return {s: paths[f"{s}_foot"] for s in sides}


def check_trajectory(robot: PasibotRobot, qs) -> np.ndarray:
    """``qs`` as an (N, nq) array of finite configurations of ``robot``, else ValueError naming it."""
    qs = np.atleast_2d(np.asarray(qs, dtype=float))
    if qs.ndim != 2 or qs.shape[1] != robot.model.nq or len(qs) == 0:
        raise ParameterError(f"parameter 'qs' must have shape (N, {robot.model.nq}), got {np.shape(qs)}")
    if not np.all(np.isfinite(qs)):
        raise ParameterError("parameter 'qs' contains non-finite values")
    return qs


def check_fps(fps: float) -> float:
    """``fps`` as a float if it is a positive frame rate [1/s], else ValueError naming it."""
    if not (isinstance(fps, (int, float)) and math.isfinite(fps) and fps > 0):
        raise ParameterError(f"parameter 'fps' must be a positive frame rate [1/s], got {fps!r}")
    return float(fps)


def arrow_transform(point: np.ndarray, force: np.ndarray, scale: float) -> tuple[np.ndarray, float]:
    """Pose (4x4, unit scale) that points the arrow's local x along ``force``, and its length [m]."""
    length = float(np.linalg.norm(force)) * scale
    T = np.eye(4)
    T[:3, 3] = point
    if length > 0.0:
        x = force / np.linalg.norm(force)
        helper = np.array([0.0, 0.0, 1.0]) if abs(x[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
        y = np.cross(helper, x)
        y /= np.linalg.norm(y)
        T[:3, :3] = np.column_stack([x, y, np.cross(x, y)])
    return T, length


@dataclass
class ForceArrows:
    """A force to draw as an arrow at each frame of a trajectory.

    Attributes:
        points: application points (N, 3) [m], world frame.
        forces: force vectors (N, 3) [N], world frame.
        scale: arrow length per newton [m/N].
        colour: '#rrggbb'.

    """

    points: np.ndarray
    forces: np.ndarray
    scale: float
    colour: str = FORCE_COLOUR

    def __post_init__(self) -> None:
        self.points = np.asarray(self.points, dtype=float)
        self.forces = np.asarray(self.forces, dtype=float)
        if self.points.ndim != 2 or self.points.shape[1] != 3 or self.forces.shape != self.points.shape:
            raise ParameterError("ForceArrows: parameters 'points' and 'forces' must both have shape (N, 3)")
        if not (np.all(np.isfinite(self.points)) and np.all(np.isfinite(self.forces))):
            raise ParameterError("ForceArrows: parameters 'points' and 'forces' must be finite")
        if not (math.isfinite(self.scale) and self.scale > 0):
            raise ParameterError(f"ForceArrows: parameter 'scale' must be a positive [m/N], got {self.scale}")


def quasi_static_ground_reaction(
    robot: PasibotRobot, qs: np.ndarray, stance: Sequence[str], scale: float = 5e-4
) -> ForceArrows:
    """The arrow of the quasi-static ground force (:func:`pasibot_pin.studies.gait_forces.quasi_static_ground_force`).

    The ground pushes up with the whole weight, along the vertical through the centre of mass; the
    arrow starts on the ground below the COM, in the stance leg's plane, ``scale`` [m/N] long per newton.
    """
    return ForceArrows(*quasi_static_ground_force(robot, check_trajectory(robot, qs), stance), scale)


def reaction_forces(
    robot: PasibotRobot, gait, omega: float = 0.0, ground_scale: float = 5e-4, cut_scale: float | None = None
) -> dict[str, ForceArrows]:
    """Arrows of the ground reaction and the cut-joint forces along a gait, at crank speed ``omega`` [rad/s].

    The forces come from :func:`pasibot_pin.studies.gait_forces.gait_reaction_forces` (inverse
    dynamics): the ground's through the centre of pressure, each cut joint's at the joint.

    Args:
        robot: the two-legged robot.
        gait: a :class:`pasibot_pin.kinematics.gait.Gait` of that robot (flat feet).
        omega: crank speed [rad/s]; 0 = quasi-static.
        ground_scale: arrow length per newton of the ground reaction [m/N].
        cut_scale: arrow length per newton of the cut forces [m/N]; default: the largest
            cut force is drawn 0.15 m long.

    Returns:
        ``{'ground': ..., 'stance_j2': ..., 'swing_j5': ...}`` :class:`ForceArrows` objects.

    """
    forces = gait_reaction_forces(robot, gait, omega)
    ground = forces.pop("ground")
    arrows = {"ground": ForceArrows(*ground, ground_scale)}
    largest = max(float(np.linalg.norm(f, axis=1).max()) for _, f in forces.values()) if forces else 0.0
    if cut_scale is None:
        cut_scale = 0.15 / largest if largest > 0 else 1.0
    for name, (points, f) in forces.items():
        arrows[name] = ForceArrows(points, f, cut_scale, colour=CUT_FORCE_COLOUR)
    return arrows
