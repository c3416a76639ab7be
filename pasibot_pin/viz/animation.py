"""2-D side-view stick animation of the walking biped (matplotlib), saved as a GIF.

Every bar of both legs is drawn in its group colour (:data:`pasibot_pin.viz.plots.GROUP_COLOURS`),
seen from the robot's right side (x forward, z up). The full ankle paths of both feet are
drawn faintly, and the part already walked is drawn boldly. One GIF frame per configuration.

Lengths [m], time [s].
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pinocchio as pin

from pasibot_pin.viz.plots import GROUP_COLOURS, robot_segments

PATH_COLOURS: dict[str, str] = {"right": "#d62728", "left": "#8e44ad"}
"""Colours of the ankle paths (the same as the 3-D viewer's)."""


def _check(robot, qs) -> np.ndarray:
    qs = np.atleast_2d(np.asarray(qs, dtype=float))
    if qs.ndim != 2 or qs.shape[1] != robot.model.nq or len(qs) < 2:
        raise ValueError(f"parameter 'qs' must have shape (N >= 2, {robot.model.nq}), got {np.shape(qs)}")
    if not np.all(np.isfinite(qs)):
        raise ValueError("parameter 'qs' contains non-finite values")
    return qs


def ankle_paths_xz(robot, qs: np.ndarray) -> dict[str, np.ndarray]:
    """World (x, z) of each leg's ankle (frame ``<side>_foot``) at every row of ``qs`` [m]."""
    qs = _check(robot, qs)
    sides = [s for s in ("right", "left") if robot.model.existFrame(f"{s}_foot")]
    out = {s: np.zeros((len(qs), 2)) for s in sides}
    data = robot.model.createData()
    for k, q in enumerate(qs):
        pin.framesForwardKinematics(robot.model, data, q)
        for s in sides:
            out[s][k] = data.oMf[robot.frame_id(f"{s}_foot")].translation[[0, 2]]
    return out


def stick_animation(robot, qs: np.ndarray, fps: float = 20.0, ax=None, title: str | None = None):
    """A matplotlib ``FuncAnimation`` of the robot along ``qs``, one frame per row.

    Args:
        robot: a loaded robot (one or two legs).
        qs: configurations (N, nq), N >= 2.
        fps: frames per second [1/s] (sets the frame interval and the time label).
        ax: axes to draw on (default: a new figure).
        title: figure title (default: variant and number of legs).

    Returns:
        The animation; its figure is ``anim._fig`` (also ``ax.figure``).

    """
    import matplotlib.pyplot as plt
    from matplotlib.animation import FuncAnimation
    from matplotlib.collections import LineCollection

    qs = _check(robot, qs)
    if not (isinstance(fps, (int, float)) and math.isfinite(fps) and fps > 0):
        raise ValueError(f"parameter 'fps' must be a positive frame rate [1/s], got {fps!r}")
    if ax is None:
        fig, ax = plt.subplots(figsize=(6.4, 5.0))
    else:
        fig = ax.figure
    frames = [robot_segments(robot, q) for q in qs]
    counts = {len(f) for f in frames}
    if len(counts) != 1:
        raise ValueError("the robot's bar count changes along 'qs'; cannot animate")
    colours = [GROUP_COLOURS[group] for group, _, _ in frames[0]]
    widths = [4.0 if group == "foot" else 2.2 for group, _, _ in frames[0]]
    segments = [np.array([[a, b] for _, a, b in f]) for f in frames]
    everything = np.concatenate([s.reshape(-1, 2) for s in segments])
    lo, hi = everything.min(axis=0), everything.max(axis=0)
    margin = 0.08 * float(max(hi - lo))
    lo[1] = min(lo[1], 0.0)
    ax.set_xlim(lo[0] - margin, hi[0] + margin)
    ax.set_ylim(lo[1] - margin, hi[1] + margin)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")
    ax.grid(True, alpha=0.3)
    ax.set_title(title or f"PASIBOT {robot.variant}, {robot.legs} leg{'s' if robot.legs > 1 else ''}")
    if robot.floating:
        ax.axhline(0.0, color="#8b5a2b", lw=1.2)
    paths = ankle_paths_xz(robot, qs)
    trails = {}
    for side, xz in paths.items():
        ax.plot(xz[:, 0], xz[:, 1], color=PATH_COLOURS[side], lw=0.8, alpha=0.35)
        (trails[side],) = ax.plot([], [], color=PATH_COLOURS[side], lw=1.6, label=f"{side} ankle path")
    bars = LineCollection(segments[0], colors=colours, linewidths=widths, capstyle="round")
    ax.add_collection(bars)
    clock = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", family="monospace")
    if paths:
        ax.legend(loc="upper right", fontsize=8)

    def draw(k: int):
        bars.set_segments(segments[k])
        for side, line in trails.items():
            line.set_data(paths[side][: k + 1, 0], paths[side][: k + 1, 1])
        clock.set_text(f"frame {k + 1}/{len(qs)}  t = {k / fps:5.2f} s")
        return [bars, clock, *trails.values()]

    return FuncAnimation(fig, draw, frames=len(qs), interval=1000.0 / fps, blit=False)


def save_gif(
    robot,
    qs: np.ndarray,
    out: Path | str,
    fps: float = 20.0,
    dpi: int = 80,
    force: bool = False,
    title: str | None = None,
) -> Path:
    """Write the stick animation of ``qs`` as a GIF, one frame per row (Pillow).

    Args:
        robot: a loaded robot.
        qs: configurations (N, nq).
        out: the GIF file.
        fps: frames per second [1/s].
        dpi: resolution [dots per inch] of the 6.4 x 5.0 in figure.
        force: overwrite an existing file.
        title: figure title.

    Returns:
        The path written.

    Raises:
        FileExistsError: ``out`` exists and ``force`` is false.

    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.animation import PillowWriter

    out = Path(out)
    if out.exists() and not force:
        raise FileExistsError(f"{out} exists; pass force=True to overwrite it")
    if out.suffix.lower() != ".gif":
        raise ValueError(f"parameter 'out' must end in .gif, got {out}")
    if not (isinstance(dpi, int) and dpi > 0):
        raise ValueError(f"parameter 'dpi' must be a positive integer, got {dpi!r}")
    anim = stick_animation(robot, qs, fps=fps, title=title)
    out.parent.mkdir(parents=True, exist_ok=True)
    try:
        anim.save(out, writer=PillowWriter(fps=fps), dpi=dpi)
    finally:
        plt.close(anim._fig)
    return out
