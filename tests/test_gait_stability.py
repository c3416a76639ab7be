"""PASIBOT's gait as a fixed point of its step-to-step map (the shooting is checked on Garcia's
simplest walker in test_poincare.py); here the map itself and what its multipliers predict."""

import math

import numpy as np
import pytest

from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.studies.gait_stability import GaitMap, StabilitySettings, gait_stability, section_state
from pasibot_pin.studies.walking import WalkSettings, walk_design

pytestmark = [pytest.mark.slow]

WALKER = Design(variant="parallel", parallel_toe=4.5, parallel_heel=4.5, omega=2.0)


@pytest.fixture(scope="module")
def shot():
    robot = design_robot(WALKER, 2, visuals=False)
    walk = walk_design(WALKER, WalkSettings(steps=StabilitySettings().warmup_steps), robot)  # walked once
    stability = gait_stability(WALKER, walk, StabilitySettings(basin_kicks=(0.05, 0.5), basin_steps=2), robot)
    return robot, walk, stability


def test_the_fixed_point_maps_onto_itself_and_the_gait_is_stable(shot):
    robot, walk, stability = shot
    point = stability.fixed_point
    assert point.residual <= StabilitySettings().tol
    gait_map = GaitMap(robot, walk.settings)
    gait_map.guess = section_state(gait_map, walk)[1]
    again = gait_map(point.x)  # an independent evaluation of the map at x*
    assert np.max(np.abs(again - point.x)) <= 10 * StabilitySettings().tol
    assert stability.stable and len(stability.multipliers) == gait_map.size == 5
    # the section's hip height is the linkage's: the crank axis 28 L above the flat stance sole
    assert point.x[0] == pytest.approx(28 * WALKER.L, abs=1e-5)


def test_the_dominant_multiplier_predicts_the_decay_of_a_kick_in_direct_simulation(shot):
    """A flat stance foot pins the hip: the forced gait is deadbeat (every |lambda| tiny), and a
    small kick at the section is gone one step later, to the same order as |lambda_dominant|."""
    robot, walk, stability = shot
    point = stability.fixed_point
    gait_map = GaitMap(robot, walk.settings)
    gait_map.guess = section_state(gait_map, walk)[1]
    kick = np.zeros(point.x.size)
    kick[4] = 0.01  # hip pitch rate [rad/s]
    after = gait_map(point.x + kick) - point.x
    predicted = point.jacobian @ kick
    radius = abs(point.dominant)
    assert radius < 1e-3  # deadbeat
    assert np.linalg.norm(after) <= max(10 * radius * np.linalg.norm(kick), 1e-8)
    assert np.linalg.norm(after - predicted) <= 1e-6


def test_the_basin_brackets_a_kick_the_walk_survives(shot):
    _, _, stability = shot
    basin = stability.basin
    assert basin is not None and basin.returning >= 0.05
    assert basin.returning < basin.failing or math.isinf(basin.failing)
    assert "stable" in stability.summary()


@pytest.mark.slow
def test_walk_stability_with_the_default_steps_shoots_the_same_gait(shot):
    """`walk --stability` warms up over the walk's own 20 steps, so its Newton guess has cranks that
    turned ten times: the gait it shoots is the one shot from a 4-step warm-up (issue 34)."""
    robot, _, short = shot
    long_walk = walk_design(WALKER, WalkSettings(), robot)  # the default steps
    assert long_walk.verdict.walks and long_walk.verdict.steps == WalkSettings().steps
    gait_map = GaitMap(robot, long_walk.settings)
    _, guess = section_state(gait_map, long_walk)
    assert np.max(np.abs(guess[gait_map.sim.motor_index])) > 20 * math.pi  # many turns behind it
    stability = gait_stability(WALKER, long_walk, StabilitySettings(basin_kicks=()), robot)
    assert stability.fixed_point.residual <= StabilitySettings().tol
    assert np.allclose(stability.fixed_point.x, short.fixed_point.x, atol=1e-5)
    assert stability.stable
