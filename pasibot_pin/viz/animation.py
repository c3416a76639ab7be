"""2-D side-view stick animation of the walking biped (matplotlib), saved as a GIF.

Every bar of both legs is drawn in its group colour (:data:`pasibot_pin.viz.plots.GROUP_COLOURS`),
seen from the robot's right side (x forward, z up). The full ankle paths of both feet are
drawn faintly, and the part already walked is drawn boldly. The ground is a brown line, the sole
points touching it are green dots (:mod:`pasibot_pin.viz.contacts`), optional force arrows (e.g.
the ground reaction) are drawn at their points, and a caption gives the time, the crank angle and
each foot's contact mode. One GIF frame per configuration.

Lengths [m], time [s].
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from pasibot_pin.errors import ParameterError
from pasibot_pin.files import PART_MARKER, atomic_path
from pasibot_pin.progress import progress_bar
from pasibot_pin.viz.contacts import foot_contacts
from pasibot_pin.viz.plots import GROUND_LINE_COLOUR, GROUP_COLOURS, robot_segments

if TYPE_CHECKING:
    from pasibot_pin.dynamics.floor.ground import Ground
    from pasibot_pin.model.robot import PasibotRobot

PATH_COLOURS: dict[str, str] = {"right": "#d62728", "left": "#8e44ad"}
"""Colours of the ankle paths (the same as the 3-D viewer's)."""

CONTACT_COLOUR = "#1a9e3a"
"""Colour of the sole points on the ground (the same as the 3-D viewer's)."""


def _check(robot: PasibotRobot, qs) -> np.ndarray:
    qs = np.atleast_2d(np.asarray(qs, dtype=float))
    if qs.ndim != 2 or qs.shape[1] != robot.model.nq or len(qs) < 2:
        raise ParameterError(f"parameter 'qs' must have shape (N >= 2, {robot.model.nq}), got {np.shape(qs)}")
    if not np.all(np.isfinite(qs)):
        raise ParameterError("parameter 'qs' contains non-finite values")
    return qs


def ankle_paths_xz(robot: PasibotRobot, qs: np.ndarray) -> dict[str, np.ndarray]:
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


LEGEND_BAND = 0.2
"""The figure's bottom share left under the axes of a new stick animation: ticks, the x label, the legend [-]."""


def _bar_frames(robot: PasibotRobot, qs: np.ndarray) -> tuple[list[np.ndarray], list[str], list[float]]:
    """Every frame's bars (n_bars, 2, 2) [m], and each bar's colour (by group) and line width."""
    frames = [robot_segments(robot, q) for q in qs]
    if len({len(f) for f in frames}) != 1:
        raise ParameterError("the robot's bar count changes along 'qs'; cannot animate")
    colours = [GROUP_COLOURS[group] for group, _, _ in frames[0]]
    widths = [4.0 if group == "foot" else 2.2 for group, _, _ in frames[0]]
    return [np.array([[a, b] for _, a, b in f]) for f in frames], colours, widths


def _frame_walk(ax, segments: list[np.ndarray]) -> None:
    """Axes limits around every frame's bars (and the ground z = 0), equal scale, labels and grid."""
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


def _check_fps(fps: float) -> float:
    """``fps`` [1/s] if it is a positive frame rate (ParameterError naming it otherwise)."""
    if not (isinstance(fps, (int, float)) and math.isfinite(fps) and fps > 0):
        raise ParameterError(f"parameter 'fps' must be a positive frame rate [1/s], got {fps!r}")
    return fps


def _follow_window(fig, ax, segments: list[np.ndarray]):
    """The camera of a followed walk: frame ``k`` -> the x limits [m] around the robot's middle.

    The limits' width is the y range's at equal scale in the axes' box; the centre moves in
    sixteenths of that width (each move redraws the still part, so a few dozen over a walk).
    """
    z = np.concatenate([s[:, :, 1].ravel() for s in segments])
    z0, z1 = min(float(z.min()), 0.0), float(z.max())
    y0, y1 = z0 - 0.08 * (z1 - z0), z1 + 0.08 * (z1 - z0)  # the robot's height and the ground, a margin each side
    ax.set_ylim(y0, y1)
    pos = ax.get_position(original=True)  # the box before the equal scale shrinks it
    width_in, height_in = pos.width * fig.get_figwidth(), pos.height * fig.get_figheight()
    width = (y1 - y0) * width_in / height_in  # [m]
    quantum = width / 16.0
    middles = np.array([0.5 * (s[:, :, 0].min() + s[:, :, 0].max()) for s in segments])
    centres = np.round(middles / quantum) * quantum
    ax.set_xlim(centres[0] - 0.5 * width, centres[0] + 0.5 * width)

    def window(k: int) -> tuple[float, float]:
        return float(centres[k] - 0.5 * width), float(centres[k] + 0.5 * width)

    return window


def _force_arrow(ax, colour: str):
    """An empty quiver arrow in ``colour``, drawn in data units (set per frame)."""
    return ax.quiver(
        [0.0], [0.0], [0.0], [0.0], color=colour, angles="xy", scale_units="xy", scale=1.0, width=0.012, zorder=4
    )


def _force_arrows(ax, forces: dict) -> dict:
    """Name -> (force, its empty arrow) for every force, and a legend entry per colour and scale."""
    arrows = {name: (force, _force_arrow(ax, force.colour)) for name, force in forces.items()}
    for colour, scale in sorted({(t.colour, t.scale) for t, _q in arrows.values()}):
        label = f"ground reaction on a foot (0.1 m: {0.1 / scale:.0f} N)"
        ax.plot([], [], marker=r"$\uparrow$", ls="", ms=10, color=colour, label=label)
    return arrows


def _place_legend(ax, fig, own: bool) -> None:
    """The legend below the axes across a figure of our own (away from the clock), else upper right."""
    if own:
        ax.legend(loc="lower center", bbox_to_anchor=(0.5, 0.01), bbox_transform=fig.transFigure, ncol=3, fontsize=8)
    else:
        ax.legend(loc="upper right", fontsize=8)


def _ground_line(ax, segments: list[np.ndarray], ground: Ground | None):
    """The ground's line: z = 0 across the axes on the flat floor, else its treads under the walk (and beyond)."""
    if ground is None or (ground.angle == 0.0 and not ground.has_step):
        return ax.axhline(0.0, color=GROUND_LINE_COLOUR, lw=1.2)
    xs = np.concatenate([s[:, :, 0].ravel() for s in segments])
    reach = float(np.diff(ax.get_xlim())[0]) + 1.0
    surface = ground.surface(float(xs.min()) - reach, float(xs.max()) + reach)
    (line,) = ax.plot(surface[:, 0], surface[:, 1], color=GROUND_LINE_COLOUR, lw=1.2)
    return line


def _stick_scene(
    robot: PasibotRobot,
    qs: np.ndarray,
    fps: float,
    ax=None,
    title: str | None = None,
    forces=None,
    modes=None,
    times=None,
    follow: bool = False,
    ground: Ground | None = None,
):
    """Draw the still part of the stick animation; return (figure, frame updater, moving artists).

    The moving artists (the bars, the ground line, the ankle paths: faint full path and bold
    walked part, the clock and the legend) are listed in the order the axes draw them (z-order,
    then order of creation). ``update(k)`` moves them to frame ``k``, and with ``follow`` the
    view along x with the robot (:func:`_follow_window`: it stays in frame over any walk).
    ``ground``: the walk's ground (``None``: z = 0), drawn and read for the soles' contacts.
    """
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast
    from matplotlib.collections import LineCollection  # deferred: heavy (matplotlib), keeps the CLI's start fast

    qs, fps = _check(robot, qs), _check_fps(fps)
    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(6.4, 5.0))
        fig.subplots_adjust(bottom=LEGEND_BAND)  # the legend's band under the x label, apart from the clock
    else:
        fig = ax.figure
    segments, colours, widths = _bar_frames(robot, qs)
    _frame_walk(ax, segments)
    still = ax.get_xlim()  # the whole walk's view [m], unless the camera follows
    window = _follow_window(fig, ax, segments) if follow else (lambda k: still)
    ax.set_title(title or f"PASIBOT {robot.variant}, {robot.legs} leg{'s' if robot.legs > 1 else ''}")
    lines = [_ground_line(ax, segments, ground)] if robot.floating else []
    paths = ankle_paths_xz(robot, qs)
    trails = {}
    for side, xz in paths.items():
        lines += ax.plot(xz[:, 0], xz[:, 1], color=PATH_COLOURS[side], lw=0.8, alpha=0.35)
        (trails[side],) = ax.plot([], [], color=PATH_COLOURS[side], lw=1.6, label=f"{side} ankle path")
        lines.append(trails[side])
    bars = LineCollection(list(segments[0]), colors=colours, linewidths=widths, capstyle="round")
    ax.add_collection(bars)
    clock = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", family="monospace", fontsize=8)
    marks, contacts = [], None
    if robot.floating:
        contacts = foot_contacts(robot, qs, ground=ground)
        modes = contacts.modes if modes is None else modes
        (dots,) = ax.plot([], [], "o", color=CONTACT_COLOUR, ms=5, zorder=3, label="sole on the ground")
        marks.append(dots)
    arrows = _force_arrows(ax, forces or {})
    times = np.arange(len(qs)) / fps if times is None else np.asarray(times, dtype=float)
    if paths:
        _place_legend(ax, fig, own)
    # everything but the axes frame, ticks and grid moves; drawn in the axes' own order
    children = ax.get_children()
    moving = sorted(
        [bars, *lines, *marks, *(q for _, q in arrows.values()), clock, *([ax.get_legend()] if paths else [])],
        key=lambda a: (a.get_zorder(), children.index(a)),
    )

    def update(k: int):
        ax.set_xlim(window(k))
        bars.set_segments(list(segments[k]))
        for side, line in trails.items():
            line.set_data(paths[side][: k + 1, 0], paths[side][: k + 1, 1])
        text = f"t = {times[k]:5.2f} s"
        if contacts is not None:
            down = np.concatenate([contacts.points[s][k][contacts.touching[s][k]] for s in contacts.points])
            marks[0].set_data(down[:, 0], down[:, 2])
            text += f"  crank {math.degrees(contacts.crank[k]):6.1f} deg\n"
            text += "  ".join(f"{side}: {modes[side][k]}" for side in modes)
        for force, quiver in arrows.values():
            quiver.set_offsets([force.points[k][[0, 2]]])
            quiver.set_UVC([force.forces[k][0] * force.scale], [force.forces[k][2] * force.scale])
        clock.set_text(text)
        return [bars, clock, *trails.values(), *marks, *(q for _, q in arrows.values())]

    return fig, update, moving


def stick_animation(
    robot: PasibotRobot,
    qs: np.ndarray,
    fps: float = 20.0,
    ax=None,
    title: str | None = None,
    ground: Ground | None = None,
):
    """A matplotlib ``FuncAnimation`` of the robot along ``qs``, one frame per row.

    Args:
        robot: a loaded robot (one or two legs).
        qs: configurations (N, nq), N >= 2.
        fps: frames per second [1/s] (sets the frame interval and the time label).
        ax: axes to draw on (default: a new figure).
        title: figure title (default: variant and number of legs).
        ground: the walk's ground (a slope, a step edge), drawn and read for the soles' contacts;
            ``None``: the flat floor z = 0.

    Returns:
        The animation; its figure is ``anim._fig`` (also ``ax.figure``).

    """
    from matplotlib.animation import FuncAnimation  # deferred: heavy (matplotlib), keeps the CLI's start fast

    fig, update, _ = _stick_scene(robot, qs, fps, ax, title, ground=ground)
    return FuncAnimation(fig, update, frames=len(qs), interval=1000.0 / fps, blit=False)


def _clock_painter(fig, clock):
    """Draw the clock's text onto an RGBA frame with Pillow (FreeType), where matplotlib would put it.

    matplotlib lays out and rasterises a text glyph by glyph each frame; Pillow draws the same
    font (the clock's monospace face, at its size in pixels) at the same anchor far faster.
    """
    from matplotlib.colors import to_rgba  # deferred: heavy (matplotlib), keeps the CLI's start fast
    from matplotlib.font_manager import findfont  # deferred: heavy (matplotlib), keeps the CLI's start fast
    from PIL import ImageDraw, ImageFont  # deferred: heavy (PIL), keeps the CLI's start fast

    props = clock.get_fontproperties()
    size = props.get_size_in_points() * fig.dpi / 72.0
    font = ImageFont.truetype(findfont(props), size=size)
    x, y = clock.get_transform().transform(clock.get_position())
    anchor = (float(x), float(fig.bbox.height - y))  # matplotlib's y points up, the image's down
    # a factor, or "normal" (the font's own line gap); matplotlib < 3.11 has no getter (its default is 1.2)
    getter = getattr(clock, "get_linespacing", None)
    linespacing = getter() if getter is not None else getattr(clock, "_linespacing", 1.2)
    spacing = (linespacing - 1.0) * size if isinstance(linespacing, (int, float)) else 0.2 * size
    colour = tuple(round(255 * c) for c in to_rgba(clock.get_color()))

    def paint(image) -> None:
        text = clock.get_text()
        if text:
            ImageDraw.Draw(image).multiline_text(anchor, text, font=font, fill=colour, anchor="la", spacing=spacing)

    return paint


def _frame_arrays(
    robot: PasibotRobot, qs: np.ndarray, fps: float, dpi: int, title: str | None, progress: bool = False, **marks
) -> list[np.ndarray]:
    """The frames of :func:`stick_animation` as RGBA arrays (height, width, 4) of ``dpi`` dots per inch.

    The still part (axes, ticks, labels, grid) is drawn once; each frame restores it and draws
    only the moving artists over it (blitting), in the axes' own drawing order. The legend,
    drawn last and the same in every frame, is rendered once as a transparent layer and
    composited over each frame; the clock's text is drawn last, with Pillow. ``progress``: a bar over
    the frames on stderr.
    """
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast
    from matplotlib.backends.backend_agg import (  # deferred: heavy (matplotlib), keeps the CLI's start fast
        FigureCanvasAgg,
    )
    from matplotlib.text import Text  # deferred: heavy (matplotlib), keeps the CLI's start fast
    from PIL import Image  # deferred: heavy (PIL), keeps the CLI's start fast

    fig, update, moving = _stick_scene(robot, qs, fps, title=title, **marks)
    bar = progress_bar(len(qs), 0, progress, unit="frame")
    try:
        fig.set_dpi(dpi)
        canvas = FigureCanvasAgg(fig)
        for artist in moving:
            artist.set_animated(True)
        canvas.draw()
        background = canvas.copy_from_bbox(fig.bbox)
        renderer = canvas.get_renderer()
        layer = None
        if moving and moving[-1] is fig.axes[0].get_legend():
            renderer.clear()
            moving.pop().draw(renderer)
            layer = Image.fromarray(np.asarray(canvas.buffer_rgba()).copy(), "RGBA")
        clock = next(a for a in moving if isinstance(a, Text))
        moving.remove(clock)
        paint = _clock_painter(fig, clock)
        frames = []
        limits = fig.axes[0].get_xlim()
        for k in range(len(qs)):
            update(k)
            if fig.axes[0].get_xlim() != limits:  # the camera moved (follow): the still part again
                limits = fig.axes[0].get_xlim()
                canvas.draw()
                background = canvas.copy_from_bbox(fig.bbox)
            canvas.restore_region(background)
            for artist in moving:
                artist.draw(renderer)
            image = Image.fromarray(np.asarray(canvas.buffer_rgba()), "RGBA")
            if layer is not None:
                image = Image.alpha_composite(image, layer)
            paint(image)
            frames.append(np.asarray(image))
            bar.update(1)
    finally:
        bar.close()
        plt.close(fig)
    return frames


def stick_frames(
    robot: PasibotRobot, qs: np.ndarray, fps: float = 20.0, dpi: int = 80, title: str | None = None, **marks
) -> list:
    """The frames of :func:`stick_animation` as Pillow images (RGB when opaque), ``dpi`` dots per inch.

    Drawn by blitting over the still part (see :func:`_frame_arrays`).
    """
    from PIL import Image  # deferred: heavy (PIL), keeps the CLI's start fast

    images = []
    for rgba in _frame_arrays(robot, qs, fps, dpi, title, **marks):
        image = Image.fromarray(rgba, "RGBA")
        # opaque frames as RGB (as matplotlib's PillowWriter does: it quantises better for GIF)
        images.append(image if rgba[..., 3].min() < 255 else image.convert("RGB"))
    return images


def save_gif(
    robot: PasibotRobot,
    qs: np.ndarray,
    out: Path | str,
    fps: float = 20.0,
    dpi: int = 80,
    force: bool = False,
    title: str | None = None,
    forces=None,
    modes=None,
    times=None,
    follow: bool = False,
    ground: Ground | None = None,
    progress: bool = False,
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
        forces: arrows to draw, name -> a :class:`ForceArrows` with ``points``, ``forces`` (N, 3), ``scale`` [m/N] and
            ``colour`` (:class:`pasibot_pin.viz.viewer.ForceArrows`), e.g. the ground reaction.
        modes: each foot's contact mode per frame (default: from the geometry).
        times: each frame's time [s] for the caption (default: k / fps).
        follow: the camera follows the robot along x (the view as tall as the walk), else the
            whole walk is in view.
        ground: the walk's ground (:class:`~pasibot_pin.dynamics.floor.ground.Ground`: a slope, a step edge),
            drawn and read for the soles' contacts; ``None``: the flat floor z = 0.
        progress: a progress bar over the frames on stderr.

    Returns:
        The path written.

    Raises:
        FileExistsError: ``out`` exists and ``force`` is false.

    """
    import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

    matplotlib.use("Agg")

    out = Path(out)
    if out.exists() and not force:
        raise FileExistsError(f"{out} exists; pass force=True to overwrite it")
    if out.suffix.lower() != ".gif":
        raise ParameterError(f"parameter 'out' must end in .gif, got {out}")
    if not (isinstance(dpi, int) and dpi > 0):
        raise ParameterError(f"parameter 'dpi' must be a positive integer, got {dpi!r}")
    frames = _frame_arrays(
        robot, qs, fps, dpi, title, progress, forces=forces, modes=modes, times=times, follow=follow, ground=ground
    )
    return write_gif(frames, out, fps)


def write_gif(frames: list[np.ndarray], out: Path, fps: float) -> Path:
    """Write RGBA frames (height, width, 4) as a looping GIF at ``fps`` [1/s], whole or not at all.

    Opaque frames share one palette (:func:`_shared_palette`). ``out`` is written through a temporary
    name and renamed, unless it is a temporary name already (the caller's :func:`~pasibot_pin.files.atomic_path`).
    """
    if not frames:
        raise ParameterError("parameter 'frames': a GIF needs at least one frame")
    if all(f[..., 3].min() == 255 for f in frames):
        images = _shared_palette(frames)
    else:
        from PIL import Image  # deferred: heavy (PIL), keeps the CLI's start fast

        images = [Image.fromarray(f, "RGBA") for f in frames]

    duration = max(1, round(1000 / fps))  # [ms] per frame
    if PART_MARKER in out.name:  # the caller writes to a temporary name already
        images[0].save(out, format="gif", save_all=True, append_images=images[1:], duration=duration, loop=0)
        return out
    with atomic_path(out) as tmp:  # the GIF appears whole under its name, or not at all
        images[0].save(tmp, format="gif", save_all=True, append_images=images[1:], duration=duration, loop=0)
    return out


def _shared_palette(frames: list[np.ndarray]) -> list:
    """Opaque RGBA frames as palette images sharing one adaptive palette (Pillow's, from three frames).

    Pillow would compute a palette per frame; the stick frames share their colours, so one
    palette serves them all. Each colour maps exactly to its nearest palette entry (Pillow's own
    mapping to a given palette goes through a coarse colour cache: white would become grey).
    The colours are keyed by their 24 RGB bits, read in place from the RGBA bytes.
    """
    from PIL import Image  # deferred: heavy (PIL), keeps the CLI's start fast

    h, w = frames[0].shape[:2]
    sample = [frames[0], frames[len(frames) // 2], frames[-1]]
    mosaic = Image.fromarray(np.concatenate([f[..., :3] for f in sample], axis=0), "RGB")
    palette = mosaic.convert("P", palette=Image.Palette.ADAPTIVE).getpalette("RGB")
    entries = np.asarray(palette, dtype=np.int32).reshape(-1, 3)
    packed = np.stack(frames).view("<u4")[..., 0] & 0xFFFFFF  # R + 256 G + 65536 B
    seen = np.zeros(1 << 24, dtype=bool)
    seen[packed] = True
    used = np.flatnonzero(seen)
    colours = np.stack([used & 255, (used >> 8) & 255, used >> 16], axis=1).astype(float)
    # nearest entry: argmin |c - e|^2 = argmin (|e|^2 - 2 c.e), exact in float64 (integers < 2^53)
    lookup = np.zeros(1 << 24, dtype=np.uint8)
    lookup[used] = np.argmin((entries.astype(float) ** 2).sum(axis=1) - 2.0 * colours @ entries.T.astype(float), axis=1)
    index = lookup[packed]
    out = []
    for k in range(len(frames)):
        frame = Image.fromarray(index[k], "P")
        frame.putpalette(palette or [])
        out.append(frame)
    return out
