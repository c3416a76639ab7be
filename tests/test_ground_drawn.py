"""The walk's own ground is what the pictures draw: a slope and a step edge in the GIF and on the page.

Before, the stick GIF drew the flat floor z = 0 under a walk up a slope (the robot climbed above
its ground line, and no sole was marked as down), and the meshcat page a flat slab. Here the
simulation says where the soles are down (its contact modes), and the drawings are checked
against it: the contacts read on the walk's ground, the GIF's ground line and the page's slabs
all lie under the soles the floor holds, and the flat floor z = 0 does not (so the checks can fail).
"""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pytest
from meshcat_checks import decode_commands
from pinocchio import neutral as pin_neutral

from pasibot_pin.dynamics.floor.ground import Ground
from pasibot_pin.model.design import design_robot, load_design
from pasibot_pin.studies.walking import WalkSettings, walk_design
from pasibot_pin.viz import viewer
from pasibot_pin.viz.animation import stick_animation
from pasibot_pin.viz.contacts import foot_contacts
from pasibot_pin.viz.plots import GROUND_LINE_COLOUR

matplotlib.use("Agg")

FAST = "designs/map_top_speed_parallel_sole6L_omega3.toml"
SLOPE = math.radians(8.0)
STEP_HEIGHT, STEP_AT = 0.005, 0.2  # a step up that the right sole straddles, heel below and toe on the upper tread
HELD = 1e-5
"""A sole point the floor holds is this close to the tread under it [m] (its rows keep it within about 1e-6 m)."""


def test_the_surface_is_the_ground_in_closed_form():
    """On a slope of angle a the line is z = x tan a; a step edge adds the riser, ``step_height`` along the normal."""
    a = math.radians(7.0)
    line = Ground(a).surface(-0.5, 2.0)
    assert line[:, 0] == pytest.approx([-0.5, 2.0], abs=1e-12)
    assert line[:, 1] == pytest.approx(np.tan(a) * line[:, 0], abs=1e-12)
    flat = Ground.step(0.03, 0.4).surface(-1.0, 1.5)
    assert flat == pytest.approx(np.array([[-1.0, 0.0], [0.4, 0.0], [0.4, 0.03], [1.5, 0.03]]), abs=1e-12)
    tilted = Ground(a, 0.8, 0.4, -0.02).surface(-1.0, 1.5)
    assert len(tilted) == 4 and tilted[[0, -1], 0] == pytest.approx([-1.0, 1.5], abs=1e-12)
    riser = tilted[2] - tilted[1]
    assert riser == pytest.approx([0.02 * math.sin(a), -0.02 * math.cos(a)], abs=1e-12)
    assert tilted[1] == pytest.approx([0.4 * math.cos(a), 0.4 * math.sin(a)], abs=1e-12)
    assert Ground.step(0.03, 5.0).surface(-1.0, 1.0) == pytest.approx(np.array([[-1.0, 0.0], [1.0, 0.0]]))
    assert Ground(a).height(0.7) == pytest.approx(0.7 * math.tan(a), abs=1e-12)
    assert [Ground.step(0.03, 0.4).height(x) for x in (0.3, 0.5)] == [0.0, 0.03]
    # on the tilted step: the upper tread's line is the slope's lifted by 0.02 / cos(a), downward here
    assert Ground(a, 0.8, 0.4, -0.02).height(1.2) == pytest.approx(1.2 * math.tan(a) - 0.02 / math.cos(a), abs=1e-12)


@pytest.fixture(scope="module", params=["slope", "step"])
def walked(request):
    """(robot with visuals, walk) of the 3 rad/s map design up an 8 deg slope, or over a 5 mm step up."""
    design = load_design(FAST)
    robot = design_robot(design, 2, visuals=True)
    settings = (
        WalkSettings(steps=3, slope=SLOPE)
        if request.param == "slope"
        else WalkSettings(steps=3, step_height=STEP_HEIGHT, step_at=STEP_AT)
    )
    return robot, walk_design(design, settings, robot)


def _held(walk, side: str) -> np.ndarray:
    """The samples where the floor holds ``side``'s sole flat (heel and toe sticking)."""
    return np.flatnonzero(np.array(walk.result.modes[side]) == "flat")


def _held_points(robot, walk, every: int = 1) -> np.ndarray:
    """Every held sole point (k, 3) [m] at every ``every``-th held sample, read from the walk's configurations."""
    contacts = foot_contacts(robot, walk.result.q, ground=walk.settings.ground)
    return np.concatenate([contacts.points[s][_held(walk, s)[::every]].reshape(-1, 3) for s in ("right", "left")])


@pytest.mark.slow  # the module's two walks: about 2.6 s of CPU
def test_contacts_are_read_on_the_walks_ground(walked):
    robot, walk = walked
    ground = walk.settings.ground
    on_ground = foot_contacts(robot, walk.result.q, ground=ground)
    on_plane = foot_contacts(robot, walk.result.q)  # the flat floor z = 0: the old reading
    assert len(_held(walk, "right")) > 20
    for side in ("right", "left"):
        held = _held(walk, side)
        assert np.abs(on_ground.heights[side][held]).max(initial=0.0) < HELD
        assert all(on_ground.modes[side][k] == "flat" for k in held)
    points = _held_points(robot, walk)
    assert np.abs(points[:, 2]).max() > 4e-3  # the plane z = 0 misses the held soles by millimetres or more
    assert any(mode != "flat" for k in _held(walk, "right") for mode in [on_plane.modes["right"][k]])
    if ground.has_step:  # some held points stand on the upper tread
        assert (points[:, 0] >= STEP_AT).any() and (points[:, 0] < STEP_AT).any()


def _distance_to_polyline(points: np.ndarray, line: np.ndarray) -> np.ndarray:
    """Each point's (k, 2) distance to the polyline (m, 2) [m]."""
    best = np.full(len(points), np.inf)
    for a, b in zip(line[:-1], line[1:]):
        d = b - a
        t = np.clip(((points - a) @ d) / (d @ d), 0.0, 1.0)
        best = np.minimum(best, np.linalg.norm(points - (a + t[:, None] * d), axis=1))
    return best


@pytest.mark.slow  # the module's two walks: about 2.6 s of CPU
def test_the_gifs_ground_line_is_under_the_held_soles(walked):
    import matplotlib.pyplot as plt

    robot, walk = walked
    anim = stick_animation(robot, walk.result.q[::25], ground=walk.settings.ground)
    ax = anim._fig.axes[0]
    anim._fig.canvas.draw()  # its first frame (an animation never drawn warns when it is deleted)
    drawn = [line for line in ax.lines if line.get_color() == GROUND_LINE_COLOUR]
    assert len(drawn) == 1
    line = np.column_stack(drawn[0].get_data())
    points = _held_points(robot, walk, every=5)[:, [0, 2]]
    assert line[:, 0].min() < points[:, 0].min() and line[:, 0].max() > points[:, 0].max()  # under the whole walk
    assert _distance_to_polyline(points, line).max() < HELD
    flat_floor = np.array([[line[0, 0], 0.0], [line[-1, 0], 0.0]])
    assert _distance_to_polyline(points, flat_floor).max() > 4e-3
    plt.close(anim._fig)


@pytest.mark.slow  # the module's two walks: about 2.6 s of CPU
def test_the_pages_slabs_lie_under_the_held_soles(walked):
    """Each tread's slab is turned by the slope, and its top face is the URDF's sole depth under the held soles."""
    robot, walk = walked
    ground = walk.settings.ground
    page = viewer.WalkViewer(robot, offline=True)
    try:
        viewer.build_walk_scene(page, walk.result.q[::50], 20.0, ground=ground)
        html = page.static_html()
    finally:
        page.close()
    transforms = {c["path"]: c["matrix"] for c in decode_commands(html) if c["type"] == "set_transform"}
    names = ["ground", "ground_upper"] if ground.has_step else ["ground"]
    slabs = [np.array(transforms[f"/meshcat/{viewer.ROOT}/{name}"]).reshape(4, 4).T for name in names]
    assert f"/meshcat/{viewer.ROOT}/ground_upper" in transforms if ground.has_step else True
    normal = np.array([-math.sin(ground.angle), 0.0, math.cos(ground.angle)])
    along = np.array([math.cos(ground.angle), 0.0, math.sin(ground.angle)])
    for slab in slabs:
        assert slab[:3, 0] == pytest.approx(along, abs=1e-7) and slab[:3, 2] == pytest.approx(normal, abs=1e-7)
    depth = viewer.GROUND_THICKNESS / 2 + viewer.sole_depth(robot)
    for point in _held_points(robot, walk, every=5):
        slab = slabs[int(ground.has_step and point @ along >= ground.step_at)]
        assert normal @ (point - slab[:3, 3]) == pytest.approx(depth, abs=1e-5)


def test_the_3d_pages_slab_is_turned_by_the_slope():
    """The 3-D page's slab: its top face parallel to the slope and as far under the ground's plane as on the flat."""
    from pasibot_pin.model.spatial import free_flyer_model
    from pasibot_pin.viz.walk3d import walk3d_html

    design = load_design("designs/3d/upright_fastest_comb0.6L_omega2.toml")
    robot = design_robot(design, 2, visuals=True)
    model = free_flyer_model(robot.model)
    q = np.repeat(pin_neutral(model)[None], 3, axis=0)
    q[:, 0] = [0.0, 0.4, 0.8]  # the hip moves along x

    def slab(ground):
        html = walk3d_html(robot, model, q, design.footprint(), 20.0, "t", ground)
        matrix = next(
            c["matrix"] for c in decode_commands(html) if c["type"] == "set_transform" and c["path"].endswith("/ground")
        )
        return np.array(matrix).reshape(4, 4).T

    flat, tilted = slab(None), slab(Ground(SLOPE))
    assert flat[:3, :3] == pytest.approx(np.eye(3)) and flat[0, 3] == pytest.approx(0.4)
    normal = np.array([-math.sin(SLOPE), 0.0, math.cos(SLOPE)])
    assert tilted[:3, 2] == pytest.approx(normal, abs=1e-7) and tilted[:3, 1] == pytest.approx([0.0, 1.0, 0.0])
    assert normal @ tilted[:3, 3] == pytest.approx(flat[2, 3], abs=1e-7)  # as far below the ground's plane
    assert tilted[0, 3] == pytest.approx(0.4 - flat[2, 3] * math.sin(SLOPE), abs=1e-7)  # under the walk's middle
