"""A 3-D walk in perspective: the robot's linkage as lines, its soles as plates, the hip's path.

Drawn from the free-flyer model of the 3-D floor (:func:`~pasibot_pin.model.spatial.free_flyer_model`):
each link is a line from its joint to the next joint and to the frames it carries (where the
loops close), each sole's plates (:func:`~pasibot_pin.model.spatial.sole_boxes`) a filled
rectangle. A few poses of the walk are drawn, the last solid and the earlier ones faint, with the
hip's path over the whole walk. Lengths in metres.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin

from pasibot_pin.files import atomic_path
from pasibot_pin.model.spatial import Footprint, sole_boxes
from pasibot_pin.viz.figure_files import save_figure_file

LEG_COLOURS = {"right": "#1f77b4", "left": "#ff7f0e"}
"""Each leg's colour."""


def _side(name: str) -> str:
    return "left" if name.startswith("left") else "right" if name.startswith("right") else "hip"


def skeleton(model: pin.Model, data: pin.Data, q: np.ndarray) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """The linkage's lines at ``q``: (side, start, end) [m], parent joint to joint, and joint to its frames."""
    pin.framesForwardKinematics(model, data, q)
    lines = []
    for j in range(2, model.njoints):
        parent = model.parents[j]
        side = _side(model.names[j])
        if parent > 1:
            lines.append((side, data.oMi[parent].translation.copy(), data.oMi[j].translation.copy()))
    roots = [j for j in range(2, model.njoints) if model.parents[j] == 1]  # the legs' joints on the hip
    for a in roots:
        for b in roots:
            pair = model.names[a].startswith("right_") and model.names[b] == "left_" + model.names[a][6:]
            if pair:  # the hip's body between a leg's pivot and the other leg's same pivot
                lines.append(("hip", data.oMi[a].translation.copy(), data.oMi[b].translation.copy()))
    for k, frame in enumerate(model.frames):
        j = frame.parentJoint
        if j > 1 and frame.type == pin.FrameType.OP_FRAME:
            lines.append((_side(model.names[j]), data.oMi[j].translation.copy(), data.oMf[k].translation.copy()))
    return lines


def sole_corners(model: pin.Model, data: pin.Data, boxes) -> list[tuple[str, np.ndarray]]:
    """Each sole plate's four corners (side, (4, 3) [m]) at ``data``'s last kinematics (its heel-toe plane)."""
    out = []
    for box in boxes:
        pose = data.oMi[box.joint] * box.placement
        hx, hy, _ = box.half_size
        local = np.array([[hx, hy, 0.0], [-hx, hy, 0.0], [-hx, -hy, 0.0], [hx, -hy, 0.0]])
        out.append((box.side, (pose.rotation @ local.T).T + pose.translation))
    return out


def plot_walk_3d(
    model: pin.Model, q: np.ndarray, footprint: Footprint, poses: int = 3, ax=None, title: str = "", span: float = 1.2
):
    """Draw a 3-D walk in perspective.

    Args:
        model: the free-flyer model the walk ran on.
        q: its configurations over the walk (N, nq).
        footprint: the soles' shape.
        poses: how many poses to draw, evenly spread over the shown part, the last one solid.
        span: the hip's last this much of travel is shown, so that the robot fills the frame [m].
        ax: a 3-D axes to draw on (default: a new figure).
        title: the axes' title.

    Returns:
        The figure.

    """
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # deferred: heavy (matplotlib), keeps the CLI's start fast

    if ax is None:
        from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

        _fig, ax = subplots(figsize=(7.5, 6.0), subplot_kw={"projection": "3d"})
    data = model.createData()
    boxes = sole_boxes(model, q[0], footprint)
    q = q[q[:, 0] >= q[-1, 0] - span]  # the last ``span`` of the walk
    picks = np.unique(np.linspace(0, len(q) - 1, max(1, poses)).astype(int))
    for n, k in enumerate(picks):
        last = n == len(picks) - 1
        alpha = 1.0 if last else 0.25
        for side, a, b in skeleton(model, data, q[k]):
            colour = LEG_COLOURS.get(side, "0.3")
            ax.plot(*np.column_stack((a, b)), color=colour, lw=2.5 if last else 1.0, alpha=alpha)
        for side, corners in sole_corners(model, data, boxes):
            plate = Poly3DCollection([corners], facecolor=LEG_COLOURS[side], edgecolor="k", alpha=0.8 * alpha)
            ax.add_collection3d(plate)
    hip = q[:, :3]
    ax.plot(hip[:, 0], hip[:, 1], hip[:, 2], color="k", lw=1.0, label="hip path")
    ax.plot(hip[:, 0], hip[:, 1], 0.0 * hip[:, 2], color="0.6", lw=0.8, ls="--", label="hip path on the floor")
    lo, hi = hip.min(axis=0), hip.max(axis=0)
    x0, x1 = float(lo[0]) - 0.4, float(hi[0]) + 0.6
    top = float(hi[2]) + 0.1
    ax.set_xlim(x0, x1)
    ax.set_ylim(-0.4, 0.4)
    ax.set_zlim(0.0, top)
    ax.set_box_aspect((x1 - x0, 0.8, top))  # true proportions
    ax.set_proj_type("persp")
    ax.view_init(elev=18, azim=-58)
    ax.set_xlabel("x, forward [m]")
    ax.set_ylabel("y, left [m]")
    ax.set_zlabel("z, up [m]")
    from matplotlib.lines import Line2D  # deferred: heavy (matplotlib), keeps the CLI's start fast

    handles = [Line2D([], [], color=c, lw=2, label=f"{s} leg and sole") for s, c in LEG_COLOURS.items()]
    handles += [Line2D([], [], color="k", lw=1, label="hip path"),
                Line2D([], [], color="0.6", lw=0.8, ls="--", label="hip path on the floor")]  # fmt: skip
    ax.legend(handles=handles, loc="lower left", fontsize=8, frameon=False)
    if title:
        ax.set_title(title, fontsize=10)
    return ax.figure


def save_walk_3d_figure(model: pin.Model, q: np.ndarray, footprint: Footprint, path: Path, title: str = "",
                        dpi: float = 110) -> Path:  # fmt: skip
    """Draw :func:`plot_walk_3d` and write it to ``path`` (PNG), atomically."""
    import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast

    fig = plot_walk_3d(model, q, footprint, title=title)
    with atomic_path(Path(path)) as tmp:
        save_figure_file(fig, tmp, dpi)
    plt.close(fig)
    return Path(path)
