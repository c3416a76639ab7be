"""``pasibot analyze``'s walking section: the report's first section after the Answers box.

It answers "does it walk?" as the README does (:func:`~pasibot_pin.report.answers.walking.walking_paragraph`
on the committed walking map), draws the map (``walking_map.png``) and animates a walker that walks:
the recommended walker (:func:`~pasibot_pin.studies.walking_map3d.recommended_walker`, the Answers box's
"what to build") on the planar floor, its camera following the hip (``walk_recommended.gif``). The
report names files of its own folder only (no link into ``docs/``, which an installed package has not).
"""

from __future__ import annotations

from pathlib import Path

from pasibot_pin.model.design import design_robot
from pasibot_pin.report.answers import BUILD_STEPS, recommended_lines
from pasibot_pin.report.answers.walking import walking_answer, walking_paragraph
from pasibot_pin.report.markdown import Section, figure
from pasibot_pin.report.walking import write_walk_animation
from pasibot_pin.studies.walking import WalkSettings, walk_design_shown
from pasibot_pin.studies.walking_map import load_map
from pasibot_pin.studies.walking_map3d import recommended_walker
from pasibot_pin.viz.plots_walking import save_walking_map_figure

MAP_PNG = "walking_map.png"
"""The walking map's picture in the report's folder."""

WALK_GIF = "walk_recommended.gif"
"""The recommended walker's animation in the report's folder."""

SHOWN_STEPS = 4
"""Steps of the animated walk (two strides) [-]."""

GIF_FPS = 10.0
"""Frames per second of simulated time of the animation [1/s] (half of ``walk --gif``'s: the report's cost)."""


def section(out_dir: Path) -> str:
    """Write ``walking_map.png`` and ``walk_recommended.gif`` into ``out_dir``; the Markdown section.

    Returns:
        The ``## Does it walk?`` section.

    """
    return build(out_dir).markdown


def build(out_dir: Path) -> Section:
    """:func:`section`, and the Answers box's lines on the recommended walker from the same walk.

    The recommended walker walks once, :data:`~pasibot_pin.report.answers.BUILD_STEPS` steps (the Answers
    box's "what to build" and its motor: :func:`~pasibot_pin.report.answers.recommended_lines`); the
    animation shows its first :data:`SHOWN_STEPS` (:func:`~pasibot_pin.studies.walking.walk_design_shown`).

    Returns:
        The section; its facts ``build`` and ``motor`` are those two lines of the box.

    """
    out_dir = Path(out_dir)
    wmap = load_map()
    save_walking_map_figure(wmap, out_dir / MAP_PNG, dpi=100)
    design = recommended_walker()
    robot = design_robot(design, 2, visuals=False)
    whole, walk = walk_design_shown(design, WalkSettings(steps=BUILD_STEPS), SHOWN_STEPS, robot)
    build_line, motor_line = recommended_lines(design, whole)
    gif = write_walk_animation(walk, robot, gif=out_dir / WALK_GIF, fps=GIF_FPS)
    animation = (
        figure(
            WALK_GIF,
            f"The recommended walker on the floor (the planar model: the hip free to pitch, not to roll), "
            f"{design.omega:g} rad/s, {SHOWN_STEPS} steps: {walk.verdict.short()}. The camera follows the hip; "
            "the legend names every arrow and marker.",
        )
        if gif
        else f"The recommended walker did not walk here: {walk.verdict.summary()}."
    )
    text = "\n".join(
        [
            "## Does it walk?",
            "",
            walking_paragraph(walking_answer(wmap)),
            "",
            figure(
                MAP_PNG,
                "The walking map: the walking verdict over the sole each side of the ankle [L] x crank speed "
                "[rad/s], per variant.",
            ),
            "",
            animation,
        ]
    )
    return Section(text, {"build": build_line, "motor": motor_line})
