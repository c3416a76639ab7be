"""Matplotlib figures. Each function takes ``ax=None`` and returns the figure; none calls show()."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot

GROUP_COLOURS = {
    "hoeken": "#f28c1a",
    "pantograph": "#2673d9",
    "extension": "#33b24d",
    "foot": "#404040",
    "hip": "#9a9aa6",
}

GROUND_LINE_COLOUR = "#8b5a2b"
"""Colour of the ground's line in the side views (the plots, the stick animation)."""


def link_group(link: str) -> str:
    """Colour group of a link name: hoeken, pantograph, extension, foot or hip."""
    name = link.split("_", 1)[-1] if link.startswith(("right_", "left_")) else link
    if name.startswith(("l1_", "l2_", "l3_")):
        return "hoeken"
    if name.startswith(("l4", "l5", "l6", "l7")):
        return "pantograph"
    if name.startswith(("l8", "l9", "l10", "l11", "slider", "foot_bar")):
        return "extension"
    if name.startswith(("foot", "toe", "heel")):
        return "foot"
    return "hip"


def figure_axes(ax=None, figsize: tuple[float, float] = (5, 7)):
    """(figure, axes): ``ax`` and its figure, or a new figure of ``figsize`` [in] when ``ax`` is None.

    A new figure is laid out by :class:`~pasibot_pin.viz.plots_layout.MarginLayout` (labels, titles
    and legends stay inside it) with :func:`~pasibot_pin.viz.plots_layout.fewer_ticks`.
    """
    if ax is None:
        from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

        fig, ax = subplots(figsize=figsize)
        return fig, ax
    return ax.figure, ax


def robot_segments(robot: PasibotRobot, q: np.ndarray) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """Bars of the robot at ``q`` as (group, start, end) in world x-z [m].

    A bar joins a link's origin to every joint or marker frame placed on that link.
    """
    model, data = robot.model, robot.data
    pin.framesForwardKinematics(model, data, q)
    segments = []
    for fid, frame in enumerate(model.frames):
        if frame.type not in (pin.FrameType.JOINT, pin.FrameType.FIXED_JOINT) or frame.parentFrame == 0:
            continue
        parent = model.frames[frame.parentFrame]
        if parent.type != pin.FrameType.BODY or parent.name == "hip":
            continue
        a = data.oMf[frame.parentFrame].translation[[0, 2]]
        b = data.oMf[fid].translation[[0, 2]]
        if np.linalg.norm(b - a) > 1e-9:
            segments.append((link_group(parent.name), a, b))
    for side in ("right", "left"):
        if model.existFrame(f"{side}_toe"):
            toe = data.oMf[model.getFrameId(f"{side}_toe")].translation[[0, 2]]
            heel = data.oMf[model.getFrameId(f"{side}_heel")].translation[[0, 2]]
            segments.append(("foot", heel, toe))
    return segments


GROUP_LABELS = {
    "hoeken": "Hoeken linkage (crank, coupler, rocker)",
    "pantograph": "pantograph (thigh, shank)",
    "extension": "parallel extension",
    "foot": "foot (heel to toe)",
    "hip": "hip",
}
"""The legend's name of each link group of :data:`GROUP_COLOURS`."""


def robot_legend(ax, groups, pivots: bool, ground: bool, extra: Sequence = ()) -> None:
    """A legend below ``ax`` naming every symbol :func:`plot_robot` drew: link groups, pivots, hip, ground.

    ``extra``: more legend handles (matplotlib artists with a label) the caller drew, listed last.
    """
    from matplotlib.lines import Line2D  # deferred: heavy (matplotlib), keeps the CLI's start fast

    handles = [
        Line2D([], [], color=GROUP_COLOURS[g], lw=3, label=GROUP_LABELS[g]) for g in GROUP_COLOURS if g in groups
    ]
    if pivots:
        label = "fixed pivots on the hip (crank j0, j3, j8)"
        handles.append(Line2D([], [], color=GROUP_COLOURS["hip"], marker="s", ls="", ms=7, label=label))
    handles.append(Line2D([], [], color="k", marker="+", ls="", ms=10, label="hip frame (body origin)"))
    if ground:
        handles.append(Line2D([], [], color=GROUND_LINE_COLOUR, lw=1, label="ground z = 0"))
    handles += list(extra)
    ax.legend(handles=handles, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2)


def plot_robot(
    robot: PasibotRobot,
    q: np.ndarray | None = None,
    ax=None,
    ground: bool = True,
    alpha: float = 1.0,
    legend: bool = False,
):
    """Side view (x forward, z up) of the robot at ``q`` (default ``robot.q0``).

    Args:
        robot: a loaded robot.
        q: configuration (default ``robot.q0``).
        ax: axes to draw on (default: a new figure).
        ground: draw the ground line z = 0 (two-legged robots).
        alpha: line opacity.
        legend: name every symbol in a legend below the axes (:func:`robot_legend`).

    Returns:
        The matplotlib figure.

    """
    from matplotlib.collections import LineCollection  # deferred: heavy (matplotlib), keeps the CLI's start fast

    fig, ax = figure_axes(ax)
    q = robot.q0 if q is None else q
    model, data = robot.model, robot.data
    segments = robot_segments(robot, q)
    if segments:  # one collection, drawn in the segments' order (one artist per link costs ~30x more)
        links = LineCollection(
            [(a, b) for _, a, b in segments],
            colors=[GROUP_COLOURS[group] for group, _, _ in segments],
            linewidths=[4 if group == "foot" else 2.5 for group, _, _ in segments],
            alpha=alpha,
            capstyle="round",
        )
        ax.add_collection(links, autolim=True)
        ax.autoscale_view()
    pin.framesForwardKinematics(model, data, q)
    hip = [data.oMf[model.getFrameId(n)].translation[[0, 2]] for n in ("hip",)]
    pivots = []
    for side in ("right", "left"):
        for joint in ("j0_crank", "j3", "j8_l6"):
            name = f"{side}_{joint}"
            if model.existJointName(name):
                pivots.append(data.oMi[model.getJointId(name)].translation[[0, 2]])
    if pivots:
        pts = np.array(pivots)
        ax.plot(pts[:, 0], pts[:, 1], "s", color=GROUP_COLOURS["hip"], ms=7, alpha=alpha)
    if ground and robot.floating:
        xs = ax.get_xlim()
        ax.axhline(0.0, color=GROUND_LINE_COLOUR, lw=1)
        ax.set_xlim(xs)
    ax.plot(*hip[0], "k+", ms=10)
    if legend:
        robot_legend(ax, {group for group, _, _ in segments}, bool(pivots), ground and robot.floating)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")
    ax.set_title(f"PASIBOT {robot.variant}, {robot.legs} leg{'s' if robot.legs > 1 else ''}")
    ax.grid(True, alpha=0.3)
    return fig
