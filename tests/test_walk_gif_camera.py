"""``walk --gif``'s camera follows the robot: every frame's bars are inside its view, the view as tall
as the robot, and the GIF is at least 640 px wide (issue 34)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from PIL import Image  # noqa: E402

from pasibot_pin.model.design import Design, design_robot  # noqa: E402
from pasibot_pin.report.walking import write_walk_animation  # noqa: E402
from pasibot_pin.studies.walking import WalkSettings, walk_design  # noqa: E402
from pasibot_pin.viz import animation  # noqa: E402

DESIGN = Design(variant="parallel", omega=3.0, parallel_toe=6.0, parallel_heel=6.0)


def _walk():
    robot = design_robot(DESIGN, 2, visuals=False)
    return walk_design(DESIGN, WalkSettings(steps=3), robot), robot


@pytest.mark.slow
def test_the_followed_view_holds_every_frame_and_moves_with_the_walk():
    walk, robot = _walk()
    qs = walk.result.q[:: max(1, len(walk.result.q) // 40)]
    fig, update, _moving = animation._stick_scene(robot, qs, 20.0, follow=True)
    try:
        ax = fig.axes[0]
        segments = [np.array([(a, b) for _g, a, b in animation.robot_segments(robot, q)]) for q in qs]
        lefts = []
        for k, bars in enumerate(segments):
            update(k)
            x0, x1 = ax.get_xlim()
            y0, y1 = ax.get_ylim()
            assert x0 <= bars[:, :, 0].min() and bars[:, :, 0].max() <= x1, k
            height = bars[:, :, 1].max() - min(bars[:, :, 1].min(), 0.0)
            assert height >= 0.5 * (y1 - y0)  # the robot fills at least half the view's height
            lefts.append(x0)
        advance = segments[-1][:, :, 0].mean() - segments[0][:, :, 0].mean()
        assert advance > 0.5 and lefts[-1] - lefts[0] > 0.5 * advance  # the view moved with the robot
    finally:
        plt.close(fig)


@pytest.mark.slow
def test_the_walk_gif_is_at_least_640_px_wide(tmp_path):
    walk, robot = _walk()
    (gif,) = write_walk_animation(walk, robot, gif=tmp_path / "walk.gif", fps=5.0)
    with Image.open(gif) as image:
        assert image.size[0] >= 640
