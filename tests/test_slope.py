"""The ground seam of the planar floor: a slope (issue 35). A 0 deg slope is the flat floor bit for bit; on
a slope the robot's start stands on the ground; held still, friction carries the weight's share along the
ground, W sin(alpha), against W cos(alpha) across it (statics, independent of the engine)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.settings import FloorSettings
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.studies.walking import WalkSettings, walk_design

FAST = Design(variant="parallel", parallel_toe=6.0, parallel_heel=6.0, omega=3.0)


@pytest.mark.slow  # about 1.8 s of CPU: two 3-step walks
def test_a_zero_slope_is_the_flat_floor_bit_for_bit():
    robot = design_robot(FAST, 2, visuals=False)
    flat = walk_design(FAST, WalkSettings(steps=3), robot).result
    zero = walk_design(FAST, WalkSettings(steps=3, slope=0.0), robot).result
    assert np.array_equal(flat.q, zero.q) and np.array_equal(flat.motor_torque, zero.motor_torque)


@pytest.mark.parametrize("degrees", [-5.0, 4.0])
def test_held_still_on_a_slope_friction_carries_the_weight_along_the_ground(degrees):
    robot = design_robot(Design(variant="parallel", parallel_toe=4.5, parallel_heel=4.5), 2, visuals=False)
    alpha = math.radians(degrees)
    sim = FloorSimulator(robot, FloorSettings(omega=0.0, slope=alpha, dt=1e-3))
    q0, v0 = sim.initial_state()
    gap = sim.contact_rows(q0)[0]
    assert gap.min() == pytest.approx(0.0, abs=1e-9)  # the start stands on the sloped ground
    run = sim.run(1.0, q0, v0)
    last = slice(-200, None)
    normal = run.normal[last].sum(axis=1).mean()
    along = run.tangential[last].sum(axis=1).mean()
    assert normal == pytest.approx(sim.weight * math.cos(alpha), rel=1e-3)
    assert abs(along) == pytest.approx(sim.weight * abs(math.sin(alpha)), rel=1e-3)
    assert np.all(np.abs(run.v[last, :3]) < 1e-6)  # at rest on it


def test_a_slope_past_the_limit_is_refused_by_name(capsys):
    from pasibot_pin.__main__ import main

    with pytest.raises(ParameterError, match="slope"):
        FloorSettings(slope=math.radians(30.0))
    assert main(["walk", "--slope", "25"]) == 2
    assert "--slope" in capsys.readouterr().err
    assert main(["walk", "--slope", "3", "--3d", "--step-height", "0.01", "--step-at", "1"]) == 2


@pytest.mark.slow
def test_walk_uphill_and_downhill():
    for degrees in (-3.0, 3.0):
        v = walk_design(FAST, WalkSettings(steps=4, slope=math.radians(degrees))).verdict
        assert v.walks and v.advance_per_step == pytest.approx(1.0, abs=0.05)  # along the ground, 8 L a step


@pytest.mark.slow
def test_on_a_slope_the_tracked_step_is_the_general_step():
    """The tracked step (the legs' shape known ahead, the contact rows turned by the hip's pitch) reads
    the ground's frame as the general step does: 5 s up a 5 deg slope, the hip within 1e-6 m / rad of
    the general step's (their difference on the flat floor is the same order), the same verdict."""
    from pasibot_pin.studies.walking import floor_settings
    from pasibot_pin.studies.walking_map3d import walker_base

    design = walker_base().with_(omega=1.0)
    robot = design_robot(design, 2, visuals=False)
    settings = floor_settings(design, WalkSettings(slope=math.radians(5.0)), robot)
    _, tracked, general = tracked_and_general(robot, settings, 5.0)
    n = min(len(tracked.t), len(general.t))
    assert n > 4000
    assert np.abs(tracked.q[:n, :3] - general.q[:n, :3]).max() < 1e-6
    assert tracked.verdict.outcome == general.verdict.outcome
    assert tracked.verdict.steps == general.verdict.steps


def tracked_and_general(robot, settings, duration: float):
    """One run twice, by the tracked step and by the general step on every coordinate [s]: (tracked simulator,
    its run, the general run). The tracked step is checked to have run."""
    tracked_sim = FloorSimulator(robot, settings)
    tracked = tracked_sim.run(duration)
    assert tracked_sim._shape_split() is not None  # the tracked step ran
    general_sim = FloorSimulator(robot, settings)
    general_sim._shape_split = lambda: None  # the general step on every coordinate
    return tracked_sim, tracked, general_sim.run(duration)
