"""Animations as files: the walk as meshcat HTML and stick GIF.

- :func:`export_animation`: a simulated run (:mod:`pasibot_pin.studies.simulation_study`) as a
  one-file meshcat HTML page and/or a stick GIF.
- :func:`section`: the ``animation`` section of ``pasibot analyze``: ``gait.html`` (3-D,
  meshcat) and ``gait.gif`` (2-D stick figure) of the prescribed gait.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from pasibot_pin.files import PART_MARKER, write_text_atomic
from pasibot_pin.model.closure import constraint_residual
from pasibot_pin.model.robot import load
from pasibot_pin.report.markdown import figure
from pasibot_pin.studies.simulation_study import animation_frames
from pasibot_pin.viz.animation import save_gif
from pasibot_pin.viz.viewer import WalkViewer, build_walk_scene, export_html, gait_trajectory, reaction_forces

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot

VARIANT = "spring"
"""Leg variant of the ``analyze`` animation."""
STEPS = 2
"""Steps (half crank turns) of the ``analyze`` animation."""
SAMPLES_PER_STEP = 30
"""Animation frames per step."""
FPS = 30.0
"""HTML frames per second [1/s]."""
GIF_STRIDE = 2
"""The GIF keeps every ``GIF_STRIDE``-th frame, played at ``FPS / GIF_STRIDE`` (the HTML's speed)."""
GIF_DPI = 80
"""Resolution of ``gait.gif`` [dots per inch] (512 x 400 pixels)."""
PLAYBACK_OMEGA = math.pi * FPS / SAMPLES_PER_STEP
"""The crank speed at which the animation plays [rad/s] (its arrows' inverse dynamics)."""


def _gif(robot: PasibotRobot, q, ground, path: Path, dpi: int):
    """The stick GIF of the walk ``q`` with its ``ground`` reaction track (every :data:`GIF_STRIDE`-th frame); its q."""
    qs = q[::GIF_STRIDE]
    ground = type(ground)(ground.points[::GIF_STRIDE], ground.forces[::GIF_STRIDE], ground.scale, ground.colour)
    times = np.arange(len(q))[::GIF_STRIDE] / FPS
    save_gif(robot, qs, path, fps=FPS / GIF_STRIDE, dpi=dpi, force=True, forces={"ground": ground}, times=times)
    return qs


def write_gait_gif(path: Path, dpi: int = GIF_DPI) -> Path:
    """The ``analyze`` walk's stick GIF alone (no HTML written), at ``dpi`` [dots per inch]."""
    robot = load(VARIANT, legs=2)
    walk = gait_trajectory(robot, steps=STEPS, samples_per_step=SAMPLES_PER_STEP)
    ground = reaction_forces(robot, walk, omega=PLAYBACK_OMEGA)["ground"]
    _gif(robot, walk.q, ground, Path(path), dpi)
    return Path(path)


SIMULATION_TITLE = "simulated walk, hip pitch free, stance foot welded"
"""The title of a simulated walk's GIF and of its page's title bar."""


def export_animation(
    robot: PasibotRobot, result, html: Path | None = None, gif: Path | None = None, fps: float = 20.0
) -> list[Path]:
    """Write a simulated walk as a one-file meshcat HTML page and/or as a stick GIF.

    The frames are the simulated configurations resampled at ``fps`` (real time, see
    :func:`~pasibot_pin.studies.simulation_study.animation_frames`). Existing files are
    overwritten: checking them is the caller's job.

    Args:
        robot: the simulated robot.
        result: the :class:`~pasibot_pin.dynamics.simulator.SimulationResult`.
        html: HTML file to write (``None``: none).
        gif: GIF file to write (``None``: none).
        fps: animation frames per second of simulated time [1/s].

    Returns:
        The files written (GIF first).

    """
    frames = animation_frames(result, fps)
    title = SIMULATION_TITLE
    written = []
    if gif is not None:
        written.append(save_gif(robot, frames, gif, fps=fps, force=True, title=title))
    if html is not None:
        viewer = WalkViewer(robot, offline=True)
        try:
            build_walk_scene(viewer, frames, fps, title=title)
            text = viewer.static_html()
        finally:
            viewer.close()

        if PART_MARKER in Path(html).name:  # the caller writes to a temporary name already
            Path(html).write_text(text, encoding="utf-8")
        else:
            write_text_atomic(html, text)
        written.append(html)
    return written


def section(out_dir: Path) -> str:
    """``pasibot analyze`` section "animation": write ``gait.html`` and ``gait.gif`` into ``out_dir``.

    Returns:
        The Markdown section.

    """
    robot = load(VARIANT, legs=2)
    export = export_html(
        out_dir / "gait.html",
        robot,
        steps=STEPS,
        samples_per_step=SAMPLES_PER_STEP,
        fps=FPS,
        force=True,
        reactions=PLAYBACK_OMEGA,
    )
    gif_qs = _gif(robot, export.q, export.forces["ground"], out_dir / "gait.gif", GIF_DPI)
    worst = max(float(np.abs(constraint_residual(robot, q, robot.loop_constraints)).max()) for q in export.q)
    return "\n".join(
        [
            "## Watch it walk",
            "",
            f"The {VARIANT} biped walks {STEPS} steps (one step per half crank turn; the stance foot is welded flat).",
            f"[gait.html](gait.html) is one self-contained page (meshcat, {len(export.q)} frames at {FPS:g} fps,"
            " looping; open it in any browser, add `#t=1.0` to the address to pause at 1 s).",
            f"Largest loop-closure residual over the exported frames: {worst:.1e} m.",
            f"Arrows (from the constrained inverse dynamics at the playback crank speed {PLAYBACK_OMEGA:.3f} rad/s):"
            " magenta, the ground reaction through the centre of pressure (0.5 mm/N); yellow, the force"
            " on the first link of each cut joint (the largest drawn 0.15 m long).",
            "",
            figure(
                "gait.gif",
                f"The walk as a 2-D stick animation ({len(gif_qs)} frames at {FPS / GIF_STRIDE:g} fps): the ground, "
                "the stance foot's contact points and the ground reaction.",
            ),
        ]
    )
