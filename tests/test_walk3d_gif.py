"""``walk --3d --gif``: the 3-D walk's side view and view from behind, checked against the walk itself.

The floor's own figures (the hip's roll from its attitude, the corners it loads) are compared with
what the frames draw: the roll in the caption and the tilt of the hip's links seen from behind, and
the soles' plates resting on the drawn ground where the floor loads them.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from PIL import Image

from pasibot_pin.__main__ import main
from pasibot_pin.dynamics.floor.ground import Ground
from pasibot_pin.model.design import design_robot, load_design
from pasibot_pin.model.spatial import free_flyer_model
from pasibot_pin.studies.walking import WalkSettings, walk_design_3d
from pasibot_pin.viz.walk3d_gif import Walk3DScene

pytestmark = pytest.mark.slow  # a 3-D walk each (the module's, the command's): about 1.5 and 3 s of CPU

TIPS = "designs/map_top_speed_parallel_sole6L_omega3.toml"
"""A planar walker that tips over sideways in 3-D at its first single support (within 0.8 s)."""
SLOPE = math.radians(5.0)


@pytest.fixture(scope="module")
def tipping():
    """(model, walk, scene) of the planar walker on the 3-D floor, up a 5 deg slope: it tips within a second."""
    design = load_design(TIPS)
    robot = design_robot(design, 2, visuals=False)
    walk = walk_design_3d(design, WalkSettings(steps=3, slope=SLOPE), robot)
    model = free_flyer_model(robot.model)
    every = 20
    scene = Walk3DScene(model, walk.result.q[::every], design.footprint(), walk.result.t[::every], "t", walk.ground, 60)
    return model, walk, scene, every


def test_the_caption_and_the_view_from_behind_show_the_floors_roll(tipping):
    """The caption's roll is the floor's (its attitude); the hip's links, seen from behind, tilt by it."""
    model, walk, scene, every = tipping
    assert walk.verdict.outcome == "tipped"
    scene.draw(0)  # the links across the hip between mirrored pivots: level at the start (roll 0, any pitch)
    grey = [k for k, colour in enumerate(scene.links["behind"].get_colors()) if tuple(colour[:3]) == (0.35,) * 3]
    across = [k for k in grey if abs(np.diff(scene.links["behind"].get_segments()[k][:, 1])[0]) < 1e-12]
    assert across
    for k in range(len(scene.q)):
        scene.draw(k)
        roll = math.degrees(walk.result.roll[k * every])
        assert f"hip roll {roll:+6.2f} deg" in scene.clock.get_text()
        for i in across:
            (y0, z0), (y1, z1) = scene.links["behind"].get_segments()[i]
            assert math.degrees(math.atan2(z1 - z0, y1 - y0)) == pytest.approx(roll, abs=0.25)
    assert abs(roll) > 8.0  # the last frame drawn, near the 10 deg tip limit: tipping, and seen so


def test_the_soles_are_drawn_at_the_floors_contact_corners(tipping):
    """Each plate's corners are the 3-D floor's contact corners (:func:`corner_frames`, built apart from the plates),
    in both views, and none is drawn inside the slope's ground."""
    from pasibot_pin.model.spatial import corner_frames

    model, walk, scene, every = tipping
    corners_model = model.copy()
    ids = corner_frames(corners_model, walk.result.q[0], scene.footprint)
    data = corners_model.createData()
    for k in range(len(scene.q)):
        scene.draw(k)
        pin.framesForwardKinematics(corners_model, data, scene.q[k])
        corners = np.array([data.oMf[i].translation for i in ids])
        for view, axes in (("side", [0, 2]), ("behind", [1, 2])):
            drawn = np.concatenate([path.vertices[:4] for path in scene.soles[view].get_paths()])
            expected = corners[:, axes]
            nearest = np.min(np.linalg.norm(drawn[:, None, :] - expected[None, :, :], axis=2), axis=1)
            assert nearest.max() < 1e-9  # every drawn corner is a contact corner
        gaps = corners[:, 2] - np.tan(SLOPE) * corners[:, 0]  # height above the slope's line z = x tan(slope)
        assert gaps.min() > -1e-4
    line = scene.side.lines[0].get_xydata()
    np.testing.assert_allclose(line[:, 1], np.tan(SLOPE) * line[:, 0], atol=1e-12)  # the slope drawn
    assert Ground(SLOPE).surface(0.0, 1.0)[1, 1] == pytest.approx(np.tan(SLOPE))


@pytest.mark.integration
def test_walk_3d_gif_command(tmp_path, capsys):
    out = tmp_path / "anim"
    assert main(["walk", "--3d", "--steps", "3", "--gif", "--out", str(out), "--design", TIPS]) == 0
    gif = out / "walk_map_top_speed_parallel_sole6L_omega3.gif"
    assert f"wrote {gif}" in capsys.readouterr().out
    with Image.open(gif) as image:
        assert image.size == (960, 480) and image.n_frames >= 10  # 20 frames a second of a walk that tips at 0.7 s
    assert sorted(p.name for p in out.iterdir() if p.name != ".pasibot") == [gif.name]  # no temporary left


def test_blitted_frames_are_the_frames_drawn_whole(tipping):
    """The GIF draws the still part once per camera position and the moving artists over it: the same pixels as
    drawing every frame whole."""
    model, walk, scene, every = tipping
    picks = slice(None, None, 4)

    def frames(blit: bool):
        again = Walk3DScene(model, scene.q[picks], scene.footprint, scene.times[picks], "t", scene.ground, 60)
        return again.frames(blit=blit)

    whole, blitted = frames(False), frames(True)
    assert len(whole) == len(blitted) >= 8
    for a, b in zip(whole, blitted):
        np.testing.assert_array_equal(a, b)
