"""The soles' lateral shape in the URDF, the viewer and ``build-urdf``: a plate or a comb's prongs.

The design's fields (``sole_inner``, ``sole_outer``, ``sole_gap_from``, ``sole_gap_to``, in L) are
read straight from the TOML here; the URDF's boxes (parsed by yourdfpy) must span them, and the
collision boxes Pinocchio places in the world must sit where :func:`~pasibot_pin.model.spatial.sole_boxes`
(the 3-D floor's and the MJCF's plates, from the model's frames) puts them.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import tomllib

from pasibot_pin.model.description import render_urdf, shape_soles
from pasibot_pin.model.design import Design, design_robot, load_design
from pasibot_pin.model.spatial import Footprint, sole_boxes

ROOT = Path(__file__).resolve().parents[1]
COMB = ROOT / "designs" / "3d" / "upright_fastest_comb0.6L_omega2.toml"


def _expected_spans(path: Path) -> list[tuple[float, float]]:
    """The sole's lateral spans from the leg's plane, toward the midline positive [m], from the file's fields."""
    fields = tomllib.loads(path.read_text())
    L = fields["L"]
    inner, outer = fields["sole_inner"] * L, fields["sole_outer"] * L
    gap = (fields.get("sole_gap_from", 0.0) * L, fields.get("sole_gap_to", 0.0) * L)
    if gap == (0.0, 0.0):
        return [(-outer, inner)]
    return [(-outer, gap[0]), (gap[1], inner)]


@pytest.mark.slow  # about 1.8 s of CPU
def test_build_urdf_draws_the_comb_prongs(tmp_path):
    """``build-urdf --design`` of the comb walker: each foot's boxes span the file's bands, mirrored."""
    import yourdfpy  # deferred: yourdfpy is the independent URDF reader of this test

    out = tmp_path / "comb.urdf"
    res = subprocess.run(
        [sys.executable, "-m", "pasibot_pin", "build-urdf", "--design", str(COMB), "--out", str(out)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert res.returncode == 0, res.stderr
    urdf = yourdfpy.URDF.load(str(out), load_meshes=False, build_scene_graph=False)
    expected = sorted(_expected_spans(COMB))
    assert len(expected) == 2  # the committed walker is a comb
    for side, toward_midline in (("right", 1.0), ("left", -1.0)):
        link = urdf.link_map[f"{side}_foot"]
        for shapes in (link.visuals, link.collisions):
            spans = []
            for shape in shapes:
                y, width = shape.origin[1, 3], shape.geometry.box.size[1]
                lo, hi = sorted((toward_midline * (y - width / 2), toward_midline * (y + width / 2)))
                spans.append((lo, hi))
            np.testing.assert_allclose(sorted(spans), expected, atol=1e-12)
            # the length and thickness are the xacro's sole's
            fields = tomllib.loads(COMB.read_text())
            assert fields["variant"] == "parallel"  # its sole is the parallel extension's
            for shape in shapes:
                length = (fields["parallel_toe"] + fields["parallel_heel"]) * fields["L"]
                assert shape.geometry.box.size[0] == pytest.approx(length, rel=1e-12)


def test_the_robot_s_collision_boxes_sit_where_the_floor_s_plates_are():
    """Pinocchio's collision boxes of the design's robot (from the shaped URDF) against ``sole_boxes`` at q0."""
    design = load_design(COMB)
    robot = design_robot(design)
    model, q = robot.model, robot.q0
    data, gdata = model.createData(), robot.collision_model.createData()
    pin.updateGeometryPlacements(model, data, robot.collision_model, gdata, q)
    urdf_y = {}
    for k, obj in enumerate(robot.collision_model.geometryObjects):
        side = obj.name.rsplit("_", 1)[0].removesuffix("_foot")
        if obj.name.rsplit("_", 1)[0] == f"{side}_foot":
            urdf_y.setdefault(side, []).append((gdata.oMg[k].translation[1], 2 * obj.geometry.halfSide[1]))
    frames = {}
    for box in sole_boxes(model, q, design.footprint()):
        world = data.oMi[box.joint] * box.placement
        frames.setdefault(box.side, []).append((world.translation[1], 2 * box.half_size[1]))
    assert set(urdf_y) == {"right", "left"}
    for side in ("right", "left"):
        np.testing.assert_allclose(sorted(urdf_y[side]), sorted(frames[side]), atol=1e-9)


def test_a_plain_plate_leaves_the_rendered_urdf_as_it_was():
    """The xacro's own 1.2 L plate: the text is the committed rendering, byte for byte."""
    design = Design()
    text = render_urdf(design.variant, 2, design.geometry(), design.masses(), design.inertia)
    assert shape_soles(text, design.footprint(), design.L) == text
    wide = shape_soles(text, Footprint.plate(0.05, 0.01), design.L)
    assert wide != text and wide.count("<box") == text.count("<box")  # one box per foot, moved and resized


def test_the_viewer_s_visual_model_has_a_box_per_prong():
    """The meshcat viewer draws the robot's visual model: the comb's feet have two boxes each."""
    robot = design_robot(load_design(COMB))
    names = [o.name for o in robot.visual_model.geometryObjects]
    feet = [name for name in names if name.rsplit("_", 1)[0] in ("right_foot", "left_foot")]
    assert len(feet) == 4, feet


def test_the_xacro_s_sole_width_is_the_centred_plate():
    """The xacro's ``foot_width`` (read in its source) is the design's default sole, both reaches."""
    import re

    from pasibot_pin.model.description import SOLE_WIDTH
    from pasibot_pin.model.paths import XACRO_PATH

    text = XACRO_PATH.read_text()
    match = re.search(r'name="foot_width" value="\$\{([0-9.]+) \* L\}"', text)
    assert match is not None
    assert float(match.group(1)) == SOLE_WIDTH == Design().sole_inner + Design().sole_outer
