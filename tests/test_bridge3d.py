"""A comb sole's bridge (:mod:`pasibot_pin.studies.bridge3d`): how high it must arch over the other foot.

* ``lowest_free`` against hand-worked height ranges.
* On a walk of the comb walker, a bridge box placed where :func:`bridge_need` says (the toe end, its
  underside at the answer) meets none of the other foot's sole boxes at any checked sample, by coal's
  distances (Pinocchio's geometry, independent of the swept-axis arithmetic); 5 mm lower it meets one.
* A plain plate has no gap: no bridge.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from pasibot_pin.model.design import design_robot, load_design
from pasibot_pin.model.spatial import SOLE_HALF_THICKNESS, Footprint, free_flyer_model, sole_boxes
from pasibot_pin.studies.bridge3d import BRIDGE_LENGTH, CHECK_EVERY, bridge_need, lowest_free, sole_frames
from pasibot_pin.studies.walking import WalkSettings, walk_design_3d

COMB = "designs/3d/upright_fastest_comb0.6L_omega2.toml"


def test_lowest_free_by_hand():
    t = 0.002
    assert lowest_free([], t) == 0.0
    assert lowest_free([(-t, t)], t) == t  # on top of a flat plate
    assert lowest_free([(-t, t), (0.010, 0.012)], t) == t  # fits in the 8 mm between
    assert lowest_free([(0.010, 0.012), (-t, t), (0.0045, 0.05)], t) == 0.05  # 2.5 mm: too thin a slot


@pytest.fixture(scope="module")
def walk():
    design = load_design(COMB)
    robot = design_robot(design, 2, visuals=False)
    result = walk_design_3d(design, WalkSettings(steps=2), robot).result
    return design, free_flyer_model(robot.model), result.q


def _hits(model, qs, footprint, height: float) -> bool:
    """A bridge box at the right foot's toe end, its underside ``height`` above the sole: does it meet the left sole?"""
    frames = sole_frames(model, qs[0], footprint)
    joint, frame = frames["right"]
    data = model.createData()
    pin.forwardKinematics(model, data, qs[0])
    up = 1.0 if (data.oMi[joint] * frame).rotation[2, 2] >= 0.0 else -1.0
    (inner, _), (_, outer) = sorted(footprint.bands, key=lambda b: b[0] - b[1])
    gap = (inner, -outer)
    half_length = float(sole_boxes(model, qs[0], footprint)[0].half_size[0])
    centre = np.array([half_length - 0.5 * BRIDGE_LENGTH, 0.5 * sum(gap), up * (height + SOLE_HALF_THICKNESS)])
    half = np.array([0.5 * BRIDGE_LENGTH, 0.5 * (gap[1] - gap[0]), SOLE_HALF_THICKNESS])
    geometry = pin.GeometryModel()
    import coal  # deferred: the test's own collision shapes

    bridge = geometry.addGeometryObject(
        pin.GeometryObject("bridge", joint, frame * pin.SE3(np.eye(3), centre), coal.Box(*(2.0 * half)))
    )
    for box in sole_boxes(model, qs[0], footprint):
        if box.side == "left":
            other = geometry.addGeometryObject(
                pin.GeometryObject(f"left{box.band}", box.joint, box.placement, coal.Box(*(2.0 * box.half_size)))
            )
            geometry.addCollisionPair(pin.CollisionPair(bridge, other))
    gdata = pin.GeometryData(geometry)
    for q in qs[::CHECK_EVERY]:
        pin.updateGeometryPlacements(model, data, geometry, gdata, q)
        pin.computeDistances(geometry, gdata)
        if min(r.min_distance for r in gdata.distanceResults) < -1e-9:
            return True
    return False


@pytest.mark.slow
def test_the_bridge_clears_the_other_foot_where_it_says_and_not_lower(walk):
    design, model, qs = walk
    footprint = design.footprint()
    need = bridge_need(model, qs, footprint)
    assert need is not None and need.best_end == "toe" and 0.0 < need.toe_m < need.heel_m
    assert need.gap_m[0] == pytest.approx((design.sole_gap_to - design.sole_gap_from) * design.L)
    assert not _hits(model, qs, footprint, need.toe_m + 1e-4)
    assert _hits(model, qs, footprint, need.toe_m - 0.005)


@pytest.mark.slow
def test_a_plate_needs_no_bridge(walk):
    design, model, qs = walk
    assert bridge_need(model, qs[:10], Footprint.centred(design.L)) is None


@pytest.mark.slow
def test_the_docs_quote_the_committed_walker_s_bridge(walk):
    """docs/floor3d.md's arch heights are bridge_need's on the committed comb walker (one source for every number)."""
    from pathlib import Path

    design, model, qs = walk
    need = bridge_need(model, qs, design.footprint())
    text = (Path(__file__).resolve().parents[1] / "docs" / "floor3d.md").read_text(encoding="utf-8")
    quote = f"toe end must arch {1000 * need.toe_m:.1f} mm above the sole, at the heel end {1000 * need.heel_m:.1f} mm"
    assert quote in " ".join(text.split())
