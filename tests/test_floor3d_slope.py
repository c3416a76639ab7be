"""The 3-D floor on a slope: the planar floor's ground, walked with the hip free to roll.

* Held upright (y, roll, yaw held) on soles of no width, the 3-D walk up a 3 deg slope is the
  planar floor's general step on the same slope: hip x, z and pitch within 1e-7, the same verdict.
* ``walk --3d --slope`` and ``sweep --floor N --3d --slope`` take it; a step edge in 3-D is refused
  by name before any work.
"""

from __future__ import annotations

import json
import math

import pytest

from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.engine3d import Floor3D
from pasibot_pin.errors import ParameterError
from pasibot_pin.explore.plan import SweepPlan
from pasibot_pin.model.design import design_robot, load_design
from pasibot_pin.model.spatial import Footprint
from pasibot_pin.studies.walking import WalkSettings, floor_settings
from tests.test_floor3d import held_and_planar

FAST = "designs/map_top_speed_parallel_sole6L_omega3.toml"


@pytest.mark.slow
@pytest.mark.parametrize("degrees", [3.0, -3.0])
def test_held_3d_walk_on_a_slope_is_the_planar_walk(degrees):
    design = load_design(FAST)
    robot = design_robot(design, 2, visuals=False)
    settings = floor_settings(design, WalkSettings(slope=math.radians(degrees)), robot)
    engine = Floor3D(FloorSimulator(robot, settings), Footprint.plate(0.0, 0.0), hold_lateral=True)
    assert engine.ground.angle == pytest.approx(math.radians(degrees))  # the planar settings' ground
    spatial, sloped = held_and_planar(robot, settings, 2.5)
    assert spatial.verdict.advance_m == pytest.approx(sloped.verdict.advance_m, abs=1e-7)  # along the slope
    assert abs(sloped.q[-1, 1] - sloped.q[0, 1]) > 0.01  # it did climb (or descend)


def test_walk_3d_on_a_slope_and_a_step_refused(capsys):
    from pasibot_pin.__main__ import main

    assert main(["walk", "--design", FAST, "--3d", "--slope", "2", "--steps", "2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["model"] == "3d" and out["outcome"] == "tipped"  # its centred plates tip uphill too
    assert out["settled_at_s"] is None
    assert main(["walk", "--design", FAST, "--3d", "--step-height", "0.01", "--step-at", "1"]) == 2
    err = capsys.readouterr().err
    assert "--step-height" in err and len(err.strip().splitlines()) == 1
    with pytest.raises(ParameterError, match="step_height"):
        robot = design_robot(load_design(FAST), 2, visuals=False)
        settings = floor_settings(load_design(FAST), WalkSettings(step_height=0.01, step_at=1.0), robot)
        Floor3D(FloorSimulator(robot, settings), Footprint.centred(0.05))


def test_a_3d_sweep_takes_a_slope_with_its_floor():
    plan = SweepPlan(n=2, floor=2, spatial=True, slope=math.radians(2.0))
    assert plan.spatial and plan.slope > 0.0
    with pytest.raises(ParameterError, match="--floor"):
        SweepPlan(n=2, slope=math.radians(2.0))
