"""The 2-D stick animation: a GIF with one frame per configuration, drawn in the group colours."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from pasibot_pin.kinematics.gait import prescribed_gait
from pasibot_pin.viz import animation

STEPS, SAMPLES, FPS, DPI = 1, 8, 10.0, 50


@pytest.fixture(scope="module")
def gait(robots):
    return prescribed_gait(robots[("spring", 2)], steps=STEPS, samples_per_step=SAMPLES)


@pytest.fixture(scope="module")
def gif(gait, tmp_path_factory):
    out = tmp_path_factory.mktemp("gif") / "walk.gif"
    animation.save_gif(gait.robot, gait.q, out, fps=FPS, dpi=DPI)
    return out


def frames_rgb(path):
    im = Image.open(path)
    out = []
    for k in range(im.n_frames):
        im.seek(k)
        out.append(np.asarray(im.convert("RGB")).astype(int))
    return im, out


def test_gif_has_one_frame_per_configuration(gif):
    im, frames = frames_rgb(gif)
    assert im.format == "GIF"
    assert im.n_frames == STEPS * SAMPLES + 1
    assert im.size == (round(6.4 * DPI), round(5.0 * DPI))
    assert im.info["duration"] == pytest.approx(1000.0 / FPS, abs=10)
    for a, b in zip(frames, frames[1:]):
        assert np.abs(a - b).max(axis=2).astype(bool).sum() > 50  # every frame moves


def test_gif_draws_the_links_in_group_colours(gif):
    _, frames = frames_rgb(gif)
    rgb = frames[len(frames) // 2].reshape(-1, 3)
    hoeken = np.abs(rgb - [0xF2, 0x8C, 0x1A]).max(axis=1) < 30
    pantograph = np.abs(rgb - [0x26, 0x73, 0xD9]).max(axis=1) < 30
    assert hoeken.sum() > 20 and pantograph.sum() > 200  # (the caption row above the axes leaves a little less room)


def test_ankle_paths_match_the_gait(gait):
    paths = animation.ankle_paths_xz(gait.robot, gait.q)
    for side in ("right", "left"):
        np.testing.assert_allclose(paths[side], gait.positions(f"{side}_foot")[:, [0, 2]], atol=1e-12)
    # the right foot is in stance during the first step: it does not move
    assert np.ptp(paths["right"], axis=0).max() < 1e-9
    assert np.ptp(paths["left"][:, 0]) > 0.2


def test_save_gif_refuses_to_overwrite_and_bad_input(gait, tmp_path):
    out = tmp_path / "mine.gif"
    out.write_bytes(b"keep")
    with pytest.raises(FileExistsError):
        animation.save_gif(gait.robot, gait.q, out)
    assert out.read_bytes() == b"keep"
    with pytest.raises(ValueError, match="qs"):
        animation.save_gif(gait.robot, gait.q[:1], tmp_path / "a.gif")
    with pytest.raises(ValueError, match="qs"):
        animation.save_gif(gait.robot, gait.q[:, :5], tmp_path / "a.gif")
    with pytest.raises(ValueError, match="fps"):
        animation.save_gif(gait.robot, gait.q, tmp_path / "a.gif", fps=-1.0)
    with pytest.raises(ValueError, match="out"):
        animation.save_gif(gait.robot, gait.q, tmp_path / "a.png")


def test_the_caption_and_the_legend_do_not_overlap(gait):
    """The clock (top left, inside the axes) and the legend (a band under the x label) keep apart, and
    both stay inside the figure, at every frame's text (checked on the artists' extents, not pixels)."""
    import matplotlib.pyplot as plt
    from matplotlib.text import Text

    for qs in (gait.q, gait.q[:3]):  # a narrow scene (a gait) and a narrower one (three frames)
        fig, update, moving = animation._stick_scene(gait.robot, qs, FPS)
        try:
            ax = fig.axes[0]
            legend, clock = ax.get_legend(), next(a for a in moving if isinstance(a, Text))
            fig.canvas.draw()
            renderer = fig.canvas.get_renderer()
            for k in range(len(qs)):
                update(k)
                box, key = clock.get_window_extent(renderer), legend.get_window_extent(renderer)
                assert clock.get_text() and not box.overlaps(key)
                assert key.y1 < ax.get_window_extent(renderer).y0  # the legend is under the axes
                assert key.y1 < ax.xaxis.label.get_window_extent(renderer).y0  # and under the x label
                assert fig.bbox.contains(key.x0, key.y0) and fig.bbox.contains(key.x1, key.y1)
        finally:
            plt.close(fig)


def test_a_gif_with_its_progress_bar_is_the_same_gif(gait, gif, tmp_path, capsys):
    """``progress=True`` counts the frames on stderr (tqdm's bar, or the plain one without the extra) and writes the
    same file."""
    import re

    capsys.readouterr()
    out = tmp_path / "shown.gif"
    animation.save_gif(gait.robot, gait.q, out, fps=FPS, dpi=DPI, progress=True)
    counts = [int(n) for n in re.findall(r"(\d+)/\d+ (?:\[|frames)", capsys.readouterr().err)]
    assert counts and counts[-1] == len(gait.q)
    assert out.read_bytes() == gif.read_bytes()
