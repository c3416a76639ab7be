"""A 3-D walk as a GIF: its side view and its view from behind, side by side, one frame per pose.

The side view (x forward, z up) follows the hip along the walk, as the planar GIF does; the view
from behind (y to the left, z up: the robot's left leg on the left) shows what the planar pictures
cannot: the hip's roll, the soles' reach toward the midline and a walker tipping over sideways.
Both draw the linkage as lines (:func:`~pasibot_pin.viz.plots_robot3d.skeleton`: each link from its
joint to the next, and to the frames where the loops close), each sole's plates as filled outlines
(:func:`~pasibot_pin.model.spatial.sole_boxes`) and the ground under the walk (a slope as its line).
The caption gives the time and the hip's roll. Lengths [m], time [s], angles in degrees on the picture.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pinocchio as pin

from pasibot_pin.dynamics.floor.ground import Ground
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.spatial import Footprint, sole_boxes
from pasibot_pin.progress import progress_bar
from pasibot_pin.viz.animation import write_gif
from pasibot_pin.viz.plots import GROUND_LINE_COLOUR
from pasibot_pin.viz.plots_robot3d import LEG_COLOURS, skeleton, sole_corners

HIP_COLOUR = "0.35"
"""Colour of the hip's links."""
SIDE_HALF_WIDTH = 0.9
"""The side view spans the hip's x this much either way [m]."""
MOVING = 2.6
"""The z-order of what moves, above everything still (grid 1.5, ground line 2, spines 2.5): drawn last, as blitting
draws it."""
CAMERA_STEP = SIDE_HALF_WIDTH / 8
"""The side view's camera follows the hip in steps of this [m] (each step redraws the still part)."""
BEHIND_HALF_WIDTH = 0.45
"""The view from behind spans y this much either way of the midline [m]."""


@dataclass
class Walk3DScene:
    """The two views of a 3-D walk, drawn for one pose at a time (:meth:`draw`).

    Args:
        model: the free-flyer model the walk ran on.
        q: its configurations, one per frame (N, nq).
        footprint: the soles' shape.
        times: each frame's time [s] (N,).
        title: the figure's title.
        ground: the ground it walked on (default the flat floor z = 0).
        dpi: the figure's resolution [dots per inch] (9.6 x 4.8 in).

    Attributes:
        figure: the matplotlib figure.
        side, behind: the two axes (x-z and y-z).
        links, soles: per view (``side``, ``behind``), the linkage's LineCollection and the soles' PolyCollection.
        clock: the caption's text.

    """

    model: pin.Model
    q: np.ndarray
    footprint: Footprint
    times: np.ndarray
    title: str = ""
    ground: Ground = field(default_factory=Ground)
    dpi: int = 100
    links: dict = field(default_factory=dict, init=False)
    soles: dict = field(default_factory=dict, init=False)

    def __post_init__(self) -> None:
        import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

        matplotlib.use("Agg")
        from matplotlib.collections import (  # deferred: heavy (matplotlib), keeps the CLI's start fast
            LineCollection,
            PolyCollection,
        )
        from matplotlib.figure import Figure  # deferred: heavy (matplotlib), keeps the CLI's start fast

        self.q = np.atleast_2d(np.asarray(self.q, dtype=float))
        self.times = np.asarray(self.times, dtype=float)
        if self.q.shape[1] != self.model.nq or len(self.times) != len(self.q) or not len(self.q):
            raise ParameterError(
                f"parameters 'q' and 'times' must be (N >= 1, {self.model.nq}) and (N,), "
                f"got {self.q.shape} and {self.times.shape}"
            )
        self.data = self.model.createData()
        self.boxes = sole_boxes(self.model, self.q[0], self.footprint)
        first = skeleton(self.model, self.data, self.q[0])
        colours = [LEG_COLOURS.get(side, HIP_COLOUR) for side, _, _ in first]
        plates = [LEG_COLOURS[box.side] for box in self.boxes]
        self.figure = Figure(figsize=(9.6, 4.8), dpi=self.dpi)
        grid = self.figure.add_gridspec(1, 2, width_ratios=(2.0, 1.0), left=0.07, right=0.98, bottom=0.12, top=0.86)
        self.side, self.behind = self.figure.add_subplot(grid[0]), self.figure.add_subplot(grid[1])
        top = float(np.max(self.q[:, 2])) + 0.45
        for name, ax in (("side", self.side), ("behind", self.behind)):
            self.links[name] = LineCollection([], colors=colours, linewidths=2.0, capstyle="round", zorder=3)
            self.soles[name] = PolyCollection(
                [], facecolors=plates, edgecolors="k", linewidths=0.6, alpha=0.8, zorder=MOVING
            )
            ax.add_collection(self.soles[name])
            ax.add_collection(self.links[name])
            ax.set_aspect("equal")
            ax.grid(True, alpha=0.3)
            ax.set_ylabel("z, up [m]")
        self.side.set_xlabel("x, forward [m]")
        self.behind.set_xlabel("y, left [m]")
        self.side.set_title("side view", fontsize=9)
        self.behind.set_title("from behind", fontsize=9)
        low = self.ground.height(float(self.q[:, 0].min()) - SIDE_HALF_WIDTH)
        high = self.ground.height(float(self.q[:, 0].max()) + SIDE_HALF_WIDTH)
        bottom = min(low, high, 0.0) - 0.05
        for ax in (self.side, self.behind):
            ax.set_ylim(bottom, max(top, bottom + 0.5))
        self.behind.set_xlim(BEHIND_HALF_WIDTH, -BEHIND_HALF_WIDTH)  # y to the left: seen from behind
        xs = self.q[:, 0]
        surface = self.ground.surface(float(xs.min()) - 2 * SIDE_HALF_WIDTH, float(xs.max()) + 2 * SIDE_HALF_WIDTH)
        self.side.plot(surface[:, 0], surface[:, 1], color=GROUND_LINE_COLOUR, lw=1.2)
        (self.floor_behind,) = self.behind.plot([], [], color=GROUND_LINE_COLOUR, lw=1.2, zorder=MOVING)
        (self.hip_path,) = self.side.plot([], [], color="k", lw=0.8, label="hip path", zorder=MOVING)
        self.clock = self.side.text(0.02, 0.96, "", transform=self.side.transAxes, va="top", family="monospace")
        self.clock.set_fontsize(8)
        self.figure.suptitle(self.title, fontsize=10)

    def draw(self, k: int) -> None:
        """Pose both views at frame ``k``."""
        q = self.q[k]
        lines = skeleton(self.model, self.data, q)
        corners = sole_corners(self.model, self.data, self.boxes)
        for name, axes in (("side", [0, 2]), ("behind", [1, 2])):
            self.links[name].set_segments([np.array([a[axes], b[axes]]) for _, a, b in lines])
            self.soles[name].set_verts([c[:, axes] for _, c in corners])
        x = float(q[0])
        centre = round(x / CAMERA_STEP) * CAMERA_STEP  # the camera moves in steps: the still part is redrawn at each
        self.side.set_xlim(centre - SIDE_HALF_WIDTH, centre + SIDE_HALF_WIDTH)
        self.hip_path.set_data(self.q[: k + 1, 0], self.q[: k + 1, 2])
        self.floor_behind.set_data([BEHIND_HALF_WIDTH, -BEHIND_HALF_WIDTH], [self.ground.height(x)] * 2)
        roll = math.degrees(hip_roll(q))
        self.clock.set_text(f"t = {self.times[k]:5.2f} s   hip roll {roll:+6.2f} deg")

    def frames(self, blit: bool = True, progress: bool = False) -> list[np.ndarray]:
        """Every frame as an RGBA array (height, width, 4).

        With ``blit`` the still part (axes, ticks, labels, the ground's line) is drawn once per camera
        position and the moving artists over it; without, every frame is drawn whole (the same pixels).
        ``progress``: a bar over the frames on stderr.
        """
        from matplotlib.backends.backend_agg import (  # deferred: heavy (matplotlib), keeps the CLI's start fast
            FigureCanvasAgg,
        )

        canvas = FigureCanvasAgg(self.figure)
        moving = [*self.soles.values(), *self.links.values(), self.hip_path, self.floor_behind, self.clock]
        moving.sort(key=lambda a: (a.get_zorder(), a.axes.get_children().index(a)))  # each axes' own drawing order
        for artist in moving:
            artist.set_animated(blit)
        out, limits, background = [], None, None
        bar = progress_bar(len(self.q), 0, progress, unit="frame")
        for k in range(len(self.q)):
            self.draw(k)
            if not blit:
                canvas.draw()
            else:
                if self.side.get_xlim() != limits:  # the camera moved: the still part again
                    limits = self.side.get_xlim()
                    canvas.draw()
                    background = canvas.copy_from_bbox(self.figure.bbox)
                canvas.restore_region(background)
                for artist in moving:
                    artist.axes.draw_artist(artist)
            out.append(np.asarray(canvas.buffer_rgba()).copy())
            bar.update(1)
        bar.close()
        return out


def hip_roll(q: np.ndarray) -> float:
    """The hip's roll [rad] of a free-flyer configuration (its roll-pitch-yaw angles' roll, as the 3-D floor's)."""
    rotation = pin.Quaternion(np.asarray(q[3:7], dtype=float)).toRotationMatrix()
    return float(pin.rpy.matrixToRpy(rotation)[0])


def save_walk3d_gif(
    model: pin.Model,
    q: np.ndarray,
    footprint: Footprint,
    out: Path | str,
    fps: float = 20.0,
    times: np.ndarray | None = None,
    title: str = "",
    ground: Ground | None = None,
    dpi: int = 100,
    progress: bool = False,
) -> Path:
    """Write a 3-D walk's two views as a GIF (:class:`Walk3DScene`), one frame per row of ``q``, atomically.

    Args:
        model: the free-flyer model the walk ran on.
        q: the frames' configurations (N, nq).
        footprint: the soles' shape.
        out: the GIF file (``.gif``).
        fps: frames per second [1/s].
        times: each frame's time for the caption [s] (default k / fps).
        title: the figure's title.
        ground: the ground it walked on (default the flat floor).
        dpi: resolution [dots per inch] of the 9.6 x 4.8 in figure.
        progress: a progress bar over the frames on stderr.

    Returns:
        The path written.

    """
    if not (isinstance(fps, (int, float)) and math.isfinite(fps) and fps > 0):
        raise ParameterError(f"parameter 'fps' must be a positive frame rate [1/s], got {fps!r}")
    q = np.atleast_2d(np.asarray(q, dtype=float))
    times = np.arange(len(q)) / fps if times is None else np.asarray(times, dtype=float)
    scene = Walk3DScene(model, q, footprint, times, title, Ground() if ground is None else ground, dpi)
    return write_gif(scene.frames(progress=progress), Path(out), fps)
