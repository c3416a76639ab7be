"""The frontal ZMP of a planar walk: Pinocchio's RNEA on the free-flyer model against a point-mass balance
of each leg's centre of mass (second differences of positions), and the issue's independent figures."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from pasibot_pin.model.design import design_robot, load_design
from pasibot_pin.model.spatial import free_flyer_model
from pasibot_pin.studies.frontal_zmp import frontal_zmp, ground_wrench
from pasibot_pin.studies.walking import WalkSettings, walk_design

FAST = "designs/map_top_speed_parallel_sole6L_omega3.toml"


@pytest.fixture(scope="module")
def fast_walk():
    """The fast walker's 4-step planar walk, walked once for the module (its tests share one xdist worker)."""
    design = load_design(FAST)
    robot = design_robot(design, 2, visuals=False)
    return design, robot, walk_design(design, WalkSettings(steps=4), robot)


def _leg_weights(model, data, q, side):
    """A leg's (or the hip's: ``side`` "hip") mass and its centre of mass height (the planar model)."""
    pin.forwardKinematics(model, data, q)
    mass, moment = 0.0, 0.0
    for j in range(1, model.njoints):
        owner = model.names[j].split("_")[0] if model.names[j].split("_")[0] in ("right", "left") else "hip"
        if owner == side:
            inertia = model.inertias[j]
            mass += inertia.mass
            moment += inertia.mass * data.oMi[j].act(inertia.lever)[2]
    return mass, moment / mass


@pytest.mark.slow
def test_ground_wrench_against_each_legs_weight_balance(fast_walk):
    """Planar motion: every body stays in its leg's plane (y = -/+ w, the hip's at 0), so the ZMP's y is
    w (F_left - F_right) / F with F = m (z'' + g) per leg and the hip; the heights' second differences
    give z'' (positions only), RNEA the wrench from q, v and the step's acceleration."""
    _, robot, walk = fast_walk
    result, model = walk.result, robot.model
    data = model.createData()
    spatial = free_flyer_model(model)
    spatial_data = spatial.createData()
    h, w, g = float(result.t[2] - result.t[1]), robot.geometry.hip_half_width, 9.81
    checked = 0
    for k in range(500, len(result.t) - 1, 97):
        if any(len({result.modes[side][j] for j in (k - 1, k, k + 1)}) > 1 for side in ("right", "left")):
            continue  # a contact event here: an impulse, no acceleration
        a = (result.v[k + 1] - result.v[k]) / h  # q+ = q + h v+: the steps' own acceleration
        wrench = ground_wrench(spatial, spatial_data, result.q[k], result.v[k], a)
        forces = {}
        for part in ("right", "left", "hip"):
            heights = [_leg_weights(model, data, result.q[j], part) for j in (k - 1, k, k + 1)]
            accel = (heights[2][1] - 2 * heights[1][1] + heights[0][1]) / h**2
            forces[part] = heights[0][0] * (accel + g)
        assert wrench[2] == pytest.approx(sum(forces.values()), rel=2e-3)  # the vertical force balance
        y_balance = w * (forces["left"] - forces["right"]) / sum(forces.values())
        assert wrench[3] / wrench[2] == pytest.approx(y_balance, abs=5e-4)
        checked += 1
    assert checked >= 20


@pytest.mark.slow
def test_fast_walkers_zmp_leaves_a_centred_sole(fast_walk):
    """The issue's independent figures for the fast walker: in right stance the lateral ZMP runs from about
    -17 to +7 mm of the midline, 53-77 mm outside a 0.06 m sole centred on the leg's plane."""
    design, robot, walk = fast_walk
    zmp = frontal_zmp(robot, walk.result, design.footprint(), max_samples=100_000)
    right = zmp.y[[s == "right" for s in zmp.stance]]
    assert -0.025 < right.min() < -0.012 and 0.004 < right.max() < 0.011
    assert -0.085 < zmp.min_margin < -0.050
    left = zmp.y[[s == "left" for s in zmp.stance]]
    assert left.max() == pytest.approx(-right.min(), abs=3e-3)  # the gait is symmetric
    wide = frontal_zmp(robot, walk.result, design.with_(sole_inner=2.6, sole_gap_from=0.6, sole_gap_to=2.2).footprint())
    assert wide.min_margin > 0.0  # a prong 3 cm past the midline holds it
    assert np.all(np.isfinite(zmp.margin))


@pytest.mark.slow
def test_the_floor_metrics_carry_the_frontal_margin_as_a_sideways_filter(fast_walk):
    """design_metrics(floor=N) on flat ground carries the walk's least frontal ZMP margin (frontal_zmp's,
    one definition): negative on the fast walker's centred 6 cm plates, which tip in 3-D; larger with a
    prong past the midline, which walks upright; NaN on a slope (the ZMP is the flat ground's)."""
    from pasibot_pin.studies import design_metrics as dm

    design, robot, walk = fast_walk
    plates = dm.design_metrics(design, floor=4)
    margin = plates["floor_frontal_zmp_margin_mm"]
    assert margin == pytest.approx(1e3 * frontal_zmp(robot, walk.result, design.footprint()).min_margin, abs=1e-9)
    assert margin < 0.0
    assert plates.row()["floor_frontal_zmp_margin_mm"] == margin
    comb = dm.design_metrics(design.with_(sole_inner=2.6, sole_gap_from=0.6, sole_gap_to=2.2), floor=4)
    assert comb["floor_frontal_zmp_margin_mm"] > margin
    assert math.isnan(dm.design_metrics(design, floor=2, slope=0.02)["floor_frontal_zmp_margin_mm"])
