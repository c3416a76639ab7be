"""A 3-D walk as a one-file meshcat page: the robot on its free hip, its soles' plates, the ground.

The robot's visual geometry is the URDF's, on the free-flyer model of the 3-D floor
(:func:`~pasibot_pin.model.spatial.free_flyer_model`: the same links), plus each sole's plates
(:func:`~pasibot_pin.model.spatial.sole_boxes`); every frame of the walk poses them, so the page
shows the roll, the yaw and the sideways drift the planar pages cannot. The title bar names the
outcome and the largest roll.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from pasibot_pin.errors import ParameterError
from pasibot_pin.model.spatial import SOLE_HALF_THICKNESS, Footprint, sole_boxes
from pasibot_pin.viz.meshcat_page import finish_page
from pasibot_pin.viz.meshcat_scene import OfflineWindow

if TYPE_CHECKING:
    from pasibot_pin.dynamics.floor.ground import Ground

SOLE_RGBA = np.array([0.15, 0.15, 0.15, 1.0])
"""The soles' colour [-]."""


def walk3d_html(
    robot,
    model: pin.Model,
    q: np.ndarray,
    footprint: Footprint,
    fps: float,
    title: str,
    ground: Ground | None = None,
) -> str:
    """The page of a 3-D walk.

    Args:
        robot: the two-legged robot, loaded with its visuals (its URDF text).
        model: the free-flyer model the walk ran on.
        q: the frames' configurations (N, model.nq).
        footprint: the soles' shape.
        fps: frames per second [1/s].
        title: the page's title.
        ground: the ground it walked on (its slope tilts the ground's slab); ``None``: the flat floor.

    Raises:
        ValueError: a robot loaded without visuals (no URDF text).

    """
    import coal  # deferred: heavy (coal), keeps the CLI's start fast
    import meshcat  # deferred: heavy (meshcat), keeps the CLI's start fast
    import meshcat.geometry as g  # deferred: heavy (meshcat), keeps the CLI's start fast
    from meshcat.animation import Animation  # deferred: heavy (meshcat), keeps the CLI's start fast

    if not robot.urdf:
        raise ParameterError("parameter 'robot': load it with visuals=True (the page draws its URDF's links)")
    visual = pin.buildGeomFromUrdfString(model, robot.urdf, pin.GeometryType.VISUAL)
    for box in sole_boxes(model, q[0], footprint):
        obj = pin.GeometryObject(f"{box.side}_sole{box.band}", box.joint, box.placement, coal.Box(*(2 * box.half_size)))
        obj.meshColor = SOLE_RGBA
        visual.addGeometryObject(obj)
    data, gdata = model.createData(), visual.createData()
    viewer = meshcat.Visualizer(window=OfflineWindow())
    _ground_slab(viewer, q[:, 0], ground)
    nodes = []
    for obj in visual.geometryObjects:
        node = f"robot/{obj.name}"
        shape = obj.geometry
        if isinstance(shape, coal.Box):
            geometry = g.Box(list(2 * shape.halfSide))
        elif isinstance(shape, coal.Cylinder):
            geometry = g.Cylinder(2 * shape.halfLength, shape.radius)
        elif isinstance(shape, coal.Sphere):
            geometry = g.Sphere(shape.radius)
        else:
            continue
        color = int(255 * obj.meshColor[0]) << 16 | int(255 * obj.meshColor[1]) << 8 | int(255 * obj.meshColor[2])
        viewer[node].set_object(geometry, g.MeshLambertMaterial(color=color))
        nodes.append((node, visual.getGeometryId(obj.name), isinstance(shape, coal.Cylinder)))
    animation = Animation(default_framerate=fps)
    turn = np.eye(4)
    turn[:3, :3] = pin.utils.rpyToMatrix(np.pi / 2, 0.0, 0.0)  # meshcat's cylinders run along y, coal's along z
    for k, configuration in enumerate(q):
        pin.forwardKinematics(model, data, configuration)
        pin.updateGeometryPlacements(model, data, visual, gdata)
        with animation.at_frame(viewer, k) as frame:
            for node, gid, cylinder in nodes:
                pose = gdata.oMg[gid].homogeneous
                frame[node].set_transform(pose @ turn if cylinder else pose)
            hip = [float(configuration[0]), float(configuration[1]), 0.0]
            frame["/Cameras/default"].set_transform(_translation(hip))  # the camera follows the hip
    viewer["/Grid"].set_property("visible", False)
    viewer["/Axes"].set_property("visible", False)
    # in perspective from ahead and to the left of the hip, following it (meshcat's camera frame: y up)
    start = q[0, :3]
    viewer["/Cameras/default"].set_transform(_translation([float(start[0]), float(start[1]), 0.0]))
    viewer["/Cameras/default/rotated/<object>"].set_property("position", [2.2, 1.2, 1.6])
    viewer.set_animation(animation, play=True, repetitions=1000)
    page = finish_page(viewer.static_html(), None)
    return page.replace("<title>MeshCat</title>", f"<title>{title}</title>", 1)


def _ground_slab(viewer, xs: np.ndarray, ground: Ground | None) -> None:
    """The ground's slab under the hip's ``xs`` [m]: its top face under the ground's plane, turned by the slope."""
    import meshcat.geometry as g  # deferred: heavy (meshcat), keeps the CLI's start fast

    slab = g.Box([float(xs.max() - xs.min()) + 2.0, 1.5, 0.01])
    viewer["ground"].set_object(slab, g.MeshLambertMaterial(color=0xD8D8CC))
    pose = _translation([0.5 * float(xs.max() + xs.min()), 0.0, -0.005 - SOLE_HALF_THICKNESS])
    if ground is not None and ground.angle:  # the slab along the slope: its top face the ground's plane, lowered
        pose[:3, :3] = pin.utils.rotate("y", -ground.angle)
        x, z = ground.world(float(pose[0, 3]) / math.cos(ground.angle), float(pose[2, 3]))
        pose[:3, 3] = [x, 0.0, z]
    viewer["ground"].set_transform(pose)


def _translation(p) -> np.ndarray:
    out = np.eye(4)
    out[:3, 3] = p
    return out
