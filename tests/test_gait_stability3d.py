"""The 3-D gait as a fixed point of its step map: it holds the planar gait (the symmetric walker's 3-D
gait is the planar one), its Jacobian predicts a sideways kick in direct simulation, and `walk --3d
--stability` gives its nine multipliers."""

from __future__ import annotations

import json

import numpy as np
import pytest

from pasibot_pin.model.design import design_robot
from pasibot_pin.studies.gait_stability3d import LABELS_3D, GaitMap3D, gait_stability_3d
from pasibot_pin.studies.walking import WalkSettings, floor_settings
from pasibot_pin.studies.walking_map3d import map3d_design

COMB = map3d_design("comb", 1.2, 3.0)

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def shot():
    robot = design_robot(COMB, 2, visuals=False)
    return robot, gait_stability_3d(COMB, robot=robot)


def test_the_3d_fixed_point_is_the_planar_gait_with_the_hip_upright(shot):
    _, stability = shot
    point = stability.fixed_point
    assert point.residual <= 1e-6 and len(stability.multipliers) == len(LABELS_3D) == 9
    x = point.x
    assert x[0] == pytest.approx(28 * COMB.L, abs=1e-3)  # the crank axis 28 L above the flat stance sole
    assert abs(x[1]) < 1e-4  # upright: its roll at mid-stance
    assert abs(x[4]) < 0.01 and abs(x[8]) < 0.01  # little sideways and yaw rate [m/s, rad/s]
    planar = stability.planar_x  # shot apart, on the planar floor
    assert x[[0, 2, 3, 5]] == pytest.approx(planar[[0, 1, 2, 3]], abs=2e-3)
    assert x[7] == pytest.approx(-planar[4], abs=2e-2)  # the pitch axis rate is minus the planar pitch rate
    assert stability.stable and abs(stability.multipliers[0]) < 0.5


def test_the_jacobian_predicts_a_sideways_kick(shot):
    """A kick of the hip's sideways velocity and roll rate at the fixed point: one step later the
    deviation is DF times the kick (direct simulation against the linearisation)."""
    robot, stability = shot
    point = stability.fixed_point
    gait_map = GaitMap3D(robot, floor_settings(COMB, WalkSettings(steps=4), robot), COMB.footprint())
    gait_map.start_from(stability.planar_x)
    kick = np.zeros(9)
    kick[4], kick[6] = 0.002, 0.002
    after = gait_map(point.x + kick) - gait_map(point.x)
    assert np.linalg.norm(after - point.jacobian @ kick) <= 0.2 * np.linalg.norm(kick) + 1e-6


def test_walk_3d_stability_json(capsys):
    from pasibot_pin.__main__ import main

    argv = ["walk", "--variant", "parallel", "--omega", "3", "--steps", "2", "--3d", "--stability", "--json"]
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["outcome"] == "tipped" and out["multipliers"] is None and "no periodic gait" in out["stability_note"]
