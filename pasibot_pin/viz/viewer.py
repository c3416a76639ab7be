"""Browser 3-D viewer: the walking biped in meshcat, live or as one self-contained HTML file.

:class:`WalkViewer` wraps Pinocchio's ``MeshcatVisualizer``. It draws the robot's visuals
coloured by group (the colours of :data:`pasibot_pin.viz.plots.GROUP_COLOURS`), a ground slab
whose top is the plane z = 0, the foot paths of a walk as lines, and optional force arrows.
The hip body is drawn transparent (:data:`HIP_OPACITY`) so the far leg's linkage shows through it;
every joint is marked by a small sphere, and the sole points touching the ground by green ones
(:mod:`pasibot_pin.viz.contacts`). It plays a walk live (:meth:`WalkViewer.play`) or stores it as
a meshcat ``Animation`` (:meth:`WalkViewer.set_walk_animation`), which :meth:`WalkViewer.static_html` embeds into one
HTML file that plays offline (:func:`export_html`).

The viewer only draws. Its parts: the server, listening on 127.0.0.1 only
(:mod:`pasibot_pin.viz.meshcat_server`; pass ``zmq_url=`` to reuse a ``meshcat-server`` you
started yourself, its binding is then yours); the exported page's edits, its title bar and the
``#t=SECONDS`` seek script (:mod:`pasibot_pin.viz.meshcat_page`); the colours, markers, paths and
force arrows (:mod:`pasibot_pin.viz.viewer_scene`). The walk and the forces it shows are computed
in :mod:`pasibot_pin.studies.gait_forces`.

Lengths [m], forces [N], time [s].
"""

from __future__ import annotations

import contextlib
import io
import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from pasibot_pin.errors import ParameterError
from pasibot_pin.files import write_text_atomic
from pasibot_pin.model.coordinates import HIP_X
from pasibot_pin.model.robot import load
from pasibot_pin.studies.gait_forces import gait_trajectory
from pasibot_pin.viz.contacts import foot_contacts
from pasibot_pin.viz.meshcat_page import SEEK_SCRIPT, Hud, command_type, finish_page
from pasibot_pin.viz.meshcat_scene import OfflineWindow
from pasibot_pin.viz.meshcat_server import LOOPBACK, ServerProcess, check_meshcat_server, start_server
from pasibot_pin.viz.viewer_scene import (
    CONTACT_COLOUR,
    CONTACT_RADIUS,
    CUT_FORCE_COLOUR,
    FORCE_COLOUR,
    GROUND_COLOUR,
    HIP_OPACITY,
    JOINT_COLOUR,
    JOINT_RADIUS,
    PATH_COLOURS,
    ForceArrows,
    arrow_transform,
    check_fps,
    check_trajectory,
    coloured_visual_model,
    foot_paths,
    frame_paths,
    hex_int,
    mark_transform,
    marker_paths,
    quasi_static_ground_reaction,
    reaction_forces,
    sole_depth,
)

if TYPE_CHECKING:
    from pasibot_pin.dynamics.floor.ground import Ground
    from pasibot_pin.kinematics.gait import Gait
    from pasibot_pin.model.robot import PasibotRobot

__all__ = [
    "CONTACT_COLOUR",
    "CUT_FORCE_COLOUR",
    "FORCE_COLOUR",
    "HIP_OPACITY",
    "LOOPBACK",
    "ROOT",
    "SEEK_SCRIPT",
    "Export",
    "ForceArrows",
    "Hud",
    "ServerProcess",
    "WalkViewer",
    "build_walk_scene",
    "check_meshcat_server",
    "command_type",
    "coloured_visual_model",
    "export_html",
    "foot_paths",
    "frame_paths",
    "marker_paths",
    "quasi_static_ground_reaction",
    "reaction_forces",
    "sole_depth",
    "start_server",
    "gait_trajectory",
]

ROOT = "pasibot"
"""Root node of the robot in the meshcat scene."""

GROUND_THICKNESS = 0.01
"""Thickness of the ground slab [m]."""

LOOP_REPETITIONS = 1_000_000
"""Repetitions of the exported animation (it loops for as long as anyone watches)."""


@dataclass
class WalkViewer:
    """The robot in a meshcat scene, with ground, foot paths, force arrows and animation.

    Args:
        robot: a loaded robot (:func:`pasibot_pin.load`).
        zmq_url: reuse a running ``meshcat-server`` at this address; ``None`` starts a
            server of our own bound to 127.0.0.1 (:func:`start_server`).
        open: open the page in the default web browser.
        offline: keep the scene in this process, with no server and no live page
            (:class:`~pasibot_pin.viz.meshcat_scene.OfflineWindow`): for writing
            :meth:`static_html` only (what :func:`export_html` does).

    """

    robot: PasibotRobot
    zmq_url: str | None = None
    open: bool = False
    offline: bool = False
    server: ServerProcess | None = field(init=False, default=None)

    def __post_init__(self) -> None:
        import meshcat  # deferred: heavy (meshcat), keeps the CLI's start fast

        from pasibot_pin.viz.pin_meshcat import (  # deferred: heavy (meshcat), keeps the CLI's start fast
            MeshcatVisualizer,
        )

        if self.offline:
            if self.zmq_url is not None or self.open:
                raise ParameterError("an offline viewer has no server: pass neither 'zmq_url' nor open=True")
            self.meshcat = meshcat.Visualizer(window=OfflineWindow())
        elif self.zmq_url is None:
            self.server = start_server()
            self.zmq_url = self.server.zmq_url
        elif not isinstance(self.zmq_url, str) or not self.zmq_url.startswith(("tcp://", "ipc://")):
            raise ParameterError(f"parameter 'zmq_url' must look like tcp://HOST:PORT, got {self.zmq_url!r}")
        else:
            check_meshcat_server(self.zmq_url)
        if not self.offline:
            with contextlib.redirect_stdout(io.StringIO()):  # meshcat prints its URL; ``url`` has it
                self.meshcat = meshcat.Visualizer(zmq_url=self.zmq_url)
        self.visual_model = coloured_visual_model(self.robot)
        self.viz = MeshcatVisualizer(
            self.robot.model, self.robot.collision_model, self.visual_model, data=self.robot.model.createData()
        )
        self.viz.initViewer(viewer=self.meshcat, open=False)
        self.viz.loadViewerModel(rootNodeName=ROOT)
        self.meshcat["/Grid"].set_property("visible", False)
        self.meshcat["/Axes"].set_property("visible", False)
        self.forces: dict[str, ForceArrows] = {}
        self.marks: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        self.hud: Hud | None = None
        self.follow: np.ndarray | None = None  # the scene's shift per animation frame (N, 4, 4): the hip mid-view
        self.display(self.robot.q0)
        if self.open:
            self.meshcat.open()

    # ---- basics

    @property
    def url(self) -> str:
        """Address of the viewer page."""
        return self.meshcat.url()

    def jupyter_cell(self, height: int = 500):
        """The live viewer as an inline notebook cell (an IPython HTML object)."""
        return self.meshcat.jupyter_cell(height=height)

    def display(self, q: np.ndarray) -> None:
        """Place the robot at configuration ``q``."""
        self.viz.display(check_trajectory(self.robot, q)[0])

    def show_robot(self, visible: bool = True) -> None:
        """Show or hide the robot's visuals, joint and contact markers (the ground, paths and arrows stay)."""
        for node in ("visuals", "joints", "contacts"):
            self.meshcat[f"{ROOT}/{node}"].set_property("visible", bool(visible))

    def visual_poses(self, q: np.ndarray) -> dict[str, np.ndarray]:
        """World pose (4x4) of every visual node at ``q``, as sent to the viewer."""
        q = check_trajectory(self.robot, q)[0]
        data, gdata = self.viz.data, self.viz.visual_data
        pin.forwardKinematics(self.robot.model, data, q)
        pin.updateGeometryPlacements(self.robot.model, data, self.visual_model, gdata)
        out = {}
        for gid, obj in enumerate(self.visual_model.geometryObjects):
            T = gdata.oMg[gid].homogeneous.copy()
            T[:3, :3] = T[:3, :3] @ np.diag(obj.meshScale)
            out[self.viz.getViewerNodeName(obj, pin.GeometryType.VISUAL)] = T
        return out

    # ---- static scene

    def add_ground(
        self, x_range: tuple[float, float], width: float = 0.6, top: float | None = None, ground: Ground | None = None
    ) -> None:
        """A ground slab spanning ``x_range`` [m] and ``width`` across [m]: one per tread of ``ground``.

        Args:
            x_range: (start, end) of the slab along x [m].
            width: extent across (y) [m].
            top: height of its top face over the contact surface [m]; default minus :func:`sole_depth`:
                the URDF's foot box hangs below the sole (the contact plane), so the slab sits under it
                instead of hiding the stance foot.
            ground: the walk's ground (:class:`~pasibot_pin.dynamics.floor.ground.Ground`): a slope tilts
                the slab, a step edge makes two (nodes ``ground`` and ``ground_upper``); ``None``: the flat floor.

        """
        import meshcat.geometry as mg  # deferred: heavy (meshcat), keeps the CLI's start fast

        x0, x1 = float(x_range[0]), float(x_range[1])
        if not (math.isfinite(x0) and math.isfinite(x1) and x1 > x0):
            raise ParameterError(f"parameter 'x_range' must be an increasing pair of finite x [m], got {x_range!r}")
        if not width > 0:
            raise ParameterError(f"parameter 'width' must be > 0 m, got {width!r}")
        top = -sole_depth(self.robot) if top is None else float(top)
        material = mg.MeshLambertMaterial(color=hex_int(GROUND_COLOUR))
        treads = [(x0, x1, 0.0)] if ground is None else ground.treads(x0, x1)
        angle = 0.0 if ground is None else ground.angle
        for k, (a, b, height) in enumerate(treads):
            node = self.meshcat[f"{ROOT}/ground" + ("_upper" if k else "")]
            node.set_object(mg.Box([b - a, width, GROUND_THICKNESS]), material)
            T = np.eye(4)
            if angle:
                T[:3, :3] = pin.utils.rotate("y", -angle)  # the slab's x along the ground, rising by its angle
            if ground is None:
                T[:3, 3] = [(a + b) / 2, 0.0, top - GROUND_THICKNESS / 2]
            else:
                x, z = ground.world((a + b) / 2, height + top - GROUND_THICKNESS / 2)
                T[:3, 3] = [x, 0.0, z]
            node.set_transform(T)

    def add_path(self, name: str, points: np.ndarray, colour: str) -> None:
        """A polyline through ``points`` (N, 3) [m], world frame."""
        import meshcat.geometry as mg  # deferred: heavy (meshcat), keeps the CLI's start fast

        points = np.asarray(points, dtype=float)
        if points.ndim != 2 or points.shape[1] != 3 or len(points) < 2 or not np.all(np.isfinite(points)):
            raise ParameterError(f"parameter 'points' of path {name!r} must be finite with shape (N >= 2, 3)")
        line = mg.Line(mg.PointsGeometry(points.T.astype(np.float32)), mg.LineBasicMaterial(color=hex_int(colour)))
        self.meshcat[f"{ROOT}/paths/{name}"].set_object(line)

    def add_foot_paths(self, qs: np.ndarray) -> dict[str, np.ndarray]:
        """Draw the ankle path of each leg (and the hip path of a biped) over ``qs``; returns them [m]."""
        paths = foot_paths(self.robot, qs)
        if self.robot.floating:
            paths["hip"] = frame_paths(self.robot, qs, ["hip"])["hip"]
        for name, pts in paths.items():
            self.add_path(name, pts, PATH_COLOURS[name])
        return paths

    def add_markers(
        self, qs: np.ndarray, modes: Mapping[str, Sequence[str]] | None = None, ground: Ground | None = None
    ) -> None:
        """Joint markers (dark spheres) and contact points (green spheres) along ``qs`` (see :func:`marker_paths`)."""
        import meshcat.geometry as mg  # deferred: heavy (meshcat), keeps the CLI's start fast

        self.marks = marker_paths(self.robot, qs, modes, ground)
        joint = mg.MeshLambertMaterial(color=hex_int(JOINT_COLOUR))
        contact = mg.MeshLambertMaterial(color=hex_int(CONTACT_COLOUR))
        for node, (positions, shown) in self.marks.items():
            is_joint = node.startswith("joints/")
            sphere = mg.Sphere(JOINT_RADIUS if is_joint else CONTACT_RADIUS)
            self.meshcat[f"{ROOT}/{node}"].set_object(sphere, joint if is_joint else contact)
            self.meshcat[f"{ROOT}/{node}"].set_transform(mark_transform(positions[0], shown[0]))

    def add_force(self, name: str, arrows: ForceArrows) -> None:
        """An arrow (unit length along its local x, stretched per frame) for a force (one arrow per frame)."""
        import meshcat.geometry as mg  # deferred: heavy (meshcat), keeps the CLI's start fast

        if not isinstance(arrows, ForceArrows):
            raise ParameterError("parameter 'arrows' must be a ForceArrows")
        material = mg.MeshLambertMaterial(color=hex_int(arrows.colour))
        radius = 0.006
        y_to_x = np.array([[0.0, 1.0, 0.0, 0.0], [-1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]])

        def along_x(geometry, centre):
            T = y_to_x.copy()
            T[0, 3] = centre
            # meshcat writes this matrix row by row; three.js reads it column by column.
            return type("AlongX", (type(geometry),), {"intrinsic_transform": lambda self: T.T})

        shaft = mg.Cylinder(0.8, radius)
        shaft.__class__ = along_x(shaft, 0.4)
        head = mg.Cylinder(0.2, radiusTop=0.0, radiusBottom=2.5 * radius)
        head.__class__ = along_x(head, 0.9)
        node = self.meshcat[f"{ROOT}/forces/{name}"]
        node["shaft"].set_object(shaft, material)
        node["head"].set_object(head, material)
        self.forces[name] = arrows
        self._place_force(node, arrows, 0)

    @staticmethod
    def _place_force(node, arrows: ForceArrows, k: int) -> None:
        T, length = arrow_transform(arrows.points[k], arrows.forces[k], arrows.scale)
        T[:3, 0] *= max(length, 1e-6)
        node.set_transform(T)

    def set_side_camera(self, qs: np.ndarray, distance: float | None = None, follow: bool = False) -> None:
        """Look at the walk from the robot's right side (from -y), centred on its bounding box.

        Args:
            qs: the trajectory to frame (N, nq).
            distance: camera distance from the walk's centre [m]; default fits the walk.
            follow: keep the hip in the middle of the view in every animation frame (a robot on the floor
                only): the distance then fits the robot, not the whole walk (:attr:`follow`).

        """
        qs = check_trajectory(self.robot, qs)
        corners, widths = [], []
        for q in qs[:: max(1, len(qs) // 20)]:
            frame = np.array([T[:3, 3] for T in self.visual_poses(q).values()])
            corners += list(frame)
            widths.append(float(np.ptp(frame[:, 0])))
        pts = np.array(corners)
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        lo[2] = min(lo[2], 0.0)
        centre = (lo + hi) / 2
        extent = float(max(hi[0] - lo[0], hi[2] - lo[2]))
        self.follow = None
        if follow and self.robot.floating:
            extent = float(max(max(widths), hi[2] - lo[2]))
            shifts = np.repeat(np.eye(4)[None], len(qs), axis=0)
            shifts[:, 0, 3] = -qs[:, HIP_X]
            shifts[:, 1:3, 3] = -centre[1:3]
            self.follow = shifts
            centre[0] = float(qs[0, HIP_X])
        distance = 0.8 * extent + 0.25 if distance is None else float(distance)
        if not distance > 0:
            raise ParameterError(f"parameter 'distance' must be > 0 m, got {distance!r}")
        # meshcat's orbit controls always aim at the scene origin: shift the robot's root
        # node so that the walk's centre sits there (poses below the root stay world poses).
        T = np.eye(4)
        T[:3, 3] = -centre
        self.meshcat[ROOT].set_transform(T)
        # The camera's own frame is three.js's y-up frame: (x, z, -y) of ours.
        self.meshcat["/Cameras/default/rotated/<object>"].set_property("position", [0.0, 0.0, distance])

    # ---- motion

    def play(self, qs: np.ndarray, fps: float = 30.0, repetitions: int = 1) -> None:
        """Play a trajectory live, frame by frame at ``fps`` [1/s] (blocks for its duration)."""
        qs = check_trajectory(self.robot, qs)
        fps = check_fps(fps)
        if not (isinstance(repetitions, int) and repetitions >= 1):
            raise ParameterError(f"parameter 'repetitions' must be an integer >= 1, got {repetitions!r}")
        start = time.monotonic()
        for rep in range(repetitions):
            for k, q in enumerate(qs):
                self.viz.display(q)
                for name, arrows in self.forces.items():
                    self._place_force(self.meshcat[f"{ROOT}/forces/{name}"], arrows, k)
                for node, (positions, shown) in self.marks.items():
                    self.meshcat[f"{ROOT}/{node}"].set_transform(mark_transform(positions[k], shown[k]))
                wait = start + (rep * len(qs) + k + 1) / fps - time.monotonic()
                if wait > 0:
                    time.sleep(wait)

    def walk_animation(self, qs: np.ndarray, fps: float = 30.0):
        """A meshcat ``Animation`` of the trajectory: one keyframe per row of ``qs``, at ``fps``."""
        from meshcat.animation import Animation  # deferred: heavy (meshcat), keeps the CLI's start fast

        qs = check_trajectory(self.robot, qs)
        fps = check_fps(fps)
        for name, arrows in self.forces.items():
            if len(arrows.points) != len(qs):
                raise ParameterError(f"force {name!r} has {len(arrows.points)} frames, the trajectory {len(qs)}")
        anim = Animation(default_framerate=fps)
        for k, q in enumerate(qs):
            with anim.at_frame(self.meshcat, k) as frame:
                for node, T in self.visual_poses(q).items():
                    frame[node].set_transform(T)
                for name, arrows in self.forces.items():
                    T, length = arrow_transform(arrows.points[k], arrows.forces[k], arrows.scale)
                    frame[f"{ROOT}/forces/{name}"].set_transform(T)
                    frame[f"{ROOT}/forces/{name}"].set_property("scale", "vector3", [max(length, 1e-6), 1.0, 1.0])
                if self.follow is not None and len(self.follow) == len(qs):
                    frame[ROOT].set_transform(self.follow[k])
                for node, (positions, shown) in self.marks.items():
                    if len(positions) == len(qs):  # an animation frame carries position and scale apart
                        frame[f"{ROOT}/{node}"].set_transform(mark_transform(positions[k], True))
                        size = 1.0 if shown[k] else 1e-6
                        frame[f"{ROOT}/{node}"].set_property("scale", "vector3", [size, size, size])
        return anim

    def set_walk_animation(self, qs: np.ndarray, fps: float = 30.0, repetitions: int = 1, play: bool = True):
        """Store the trajectory in the scene as a meshcat animation (what :meth:`static_html` embeds)."""
        if not (isinstance(repetitions, int) and repetitions >= 1):
            raise ParameterError(f"parameter 'repetitions' must be an integer >= 1, got {repetitions!r}")
        anim = self.walk_animation(qs, fps)
        self.meshcat.set_animation(anim, play=play, repetitions=repetitions)
        return anim

    def static_html(self) -> str:
        """The whole scene, with its animation, as one self-contained HTML page.

        meshcat's page replays the scene tree's commands in tree order, and the animation sits
        on the root node, so it would come first and the nodes' static poses after it. The
        animation command is moved to the end here, and the title bar and the ``#t=`` seek
        script are added (:func:`pasibot_pin.viz.meshcat_page.finish_page`).
        """
        return finish_page(self.meshcat.static_html(), self.hud)

    def close(self) -> None:
        """Stop our server (a reused ``meshcat-server`` keeps running)."""
        if self.server is not None:
            self.server.close()


# --------------------------------------------------------------------------- walks and export


@dataclass
class Export:
    """What :func:`export_html` wrote.

    Attributes:
        path: the HTML file.
        q: configuration of every animation frame (N, nq); frame k is shown at time k / fps.
        fps: frames per second of the animation [1/s].
        gait: the gait the frames come from.
        paths: the drawn traces ``{name: (N, 3)}`` [m].
        forces: the drawn force arrows ``{name: ForceArrows}``.

    """

    path: Path
    q: np.ndarray
    fps: float
    gait: Gait
    paths: dict[str, np.ndarray]
    forces: dict = field(default_factory=dict)

    @property
    def duration(self) -> float:
        """Length of one play of the animation [s]."""
        return (len(self.q) - 1) / self.fps


def build_walk_scene(
    viewer: WalkViewer,
    qs: np.ndarray,
    fps: float,
    forces: Mapping[str, ForceArrows] | None = None,
    play: bool = True,
    repetitions: int = LOOP_REPETITIONS,
    title: str | None = None,
    times: np.ndarray | None = None,
    modes: Mapping[str, Sequence[str]] | None = None,
    follow: bool = False,
    ground: Ground | None = None,
) -> dict[str, np.ndarray]:
    """Ground, foot paths, joint and contact markers, forces, side camera, title bar and the walk animation.

    Args:
        viewer: the viewer to fill.
        qs: the walk (N, nq).
        fps: animation frames per second [1/s].
        forces: optional force arrows (one row per frame).
        play: start the animation as soon as the page has it.
        repetitions: plays of the animation (default: loops practically forever).
        title: the title bar's text (default: the variant); the bar also shows time, crank angle, modes.
        times: each frame's time for the title bar [s] (default: the animation's, k / fps).
        modes: each foot's contact mode per frame (default: from the geometry).
        follow: the camera follows the hip (:meth:`WalkViewer.set_side_camera`).
        ground: the walk's ground (a slope, a step edge: :meth:`WalkViewer.add_ground`); ``None``: the flat floor.

    Returns:
        The drawn traces ``{name: (N, 3)}`` [m].

    """
    paths = viewer.add_foot_paths(qs)
    xs = np.concatenate([p[:, 0] for p in paths.values()])
    margin = 0.4
    viewer.add_ground((float(xs.min()) - margin, float(xs.max()) + margin), ground=ground)
    for name, arrows in (forces or {}).items():
        viewer.add_force(name, arrows)
    viewer.add_markers(qs, modes, ground)
    viewer.set_side_camera(qs, follow=follow)
    viewer.display(qs[0])
    viewer.set_walk_animation(qs, fps=fps, repetitions=repetitions, play=play)
    if viewer.robot.floating:
        contacts = foot_contacts(viewer.robot, qs, ground=ground)
        viewer.hud = Hud(
            title=title or f"PASIBOT {viewer.robot.variant} biped",
            fps=fps,
            t=np.arange(len(qs)) / fps if times is None else np.asarray(times, dtype=float),
            theta=contacts.crank,
            modes={s: list(m) for s, m in (modes or contacts.modes).items()},
        )
    return paths


def export_html(
    out: Path | str,
    robot: PasibotRobot | None = None,
    *,
    variant: str = "spring",
    steps: int = 2,
    samples_per_step: int = 30,
    fps: float = 30.0,
    force: bool = False,
    show_robot: bool = True,
    forces: Mapping[str, ForceArrows] | None = None,
    ground_reaction: bool = False,
    reactions: float | None = None,
    zmq_url: str | None = None,
) -> Export:
    """Write one self-contained HTML file with the walk animated in meshcat.

    Args:
        out: the HTML file to write.
        robot: a two-legged robot; ``None`` loads ``variant``.
        variant: leg variant when ``robot`` is ``None``.
        steps: number of steps (half crank turns).
        samples_per_step: animation frames per step.
        fps: animation frames per second [1/s].
        force: overwrite an existing file.
        show_robot: ``False`` hides the robot (ground and paths only; a reference picture).
        forces: optional force arrows, one :class:`ForceArrows` per name, one row per frame.
        ground_reaction: add the quasi-static ground reaction arrow
            (:func:`quasi_static_ground_reaction`, 0.5 mm per N).
        reactions: crank speed [rad/s] at which to draw the ground reaction and the cut-joint
            forces of :func:`reaction_forces` (``spring`` only); ``None``: none.
        zmq_url: build the scene on a running meshcat server (default: in this process, no server).

    Returns:
        The :class:`Export`.

    Raises:
        FileExistsError: ``out`` exists and ``force`` is false.
        ValueError: bad arguments.

    """
    out = Path(out)
    if out.exists() and not force:
        raise FileExistsError(f"{out} exists; pass force=True (--force) to overwrite it")
    if out.suffix.lower() not in (".html", ".htm"):
        raise ParameterError(f"parameter 'out' must end in .html, got {out}")
    fps = check_fps(fps)
    if robot is None:
        robot = load(variant, legs=2)
    gait = gait_trajectory(robot, steps=steps, samples_per_step=samples_per_step)
    if ground_reaction:
        forces = {**(forces or {}), "ground": quasi_static_ground_reaction(robot, gait.q, gait.stance)}
    if reactions is not None:
        forces = {**(forces or {}), **reaction_forces(robot, gait, omega=reactions)}
    viewer = WalkViewer(robot, zmq_url=zmq_url, offline=zmq_url is None)
    try:
        plural = "" if steps == 1 else "s"
        title = f"PASIBOT {robot.variant} biped, {steps} step{plural} (prescribed gait, stance sole welded flat)"
        paths = build_walk_scene(viewer, gait.q, fps, forces, title=title)
        viewer.show_robot(show_robot)
        if not show_robot:  # a reference picture: no title bar either
            viewer.hud = None
        html = viewer.static_html()
    finally:
        viewer.close()

    write_text_atomic(out, html)
    return Export(path=out, q=gait.q.copy(), fps=fps, gait=gait, paths=paths, forces=dict(forces or {}))
