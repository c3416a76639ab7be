"""PASIBOT's gait as a fixed point of its step-to-step map (the shooting is checked on Garcia's
simplest walker in test_poincare.py); here the map itself and what its multipliers predict."""

import json
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


FASTEST = "designs/fastest_parallel_toe4.4L_heel6.3L_omega7.61.toml"


def _own_crossings(gait_map: GaitMap, walk) -> np.ndarray:
    """The walk's own section states at every step (right then left leg at mid-stance, mirrored),
    interpolated between the two samples around each crossing: data that the shooting never saw."""
    from pasibot_pin.studies.gait_stability import SECTION_THETA

    r, s = walk.result, walk.settings
    half_turns = (s.theta0 + walk.omega * (r.t - 0.5 * s.crank_ramp) - SECTION_THETA) / math.pi
    crossed = np.flatnonzero((r.t[1:] > s.crank_ramp) & (np.floor(half_turns[1:]) > np.floor(half_turns[:-1]))) + 1
    states = []
    for i, k in enumerate(crossed):
        f = (np.ceil(half_turns[k - 1]) - half_turns[k - 1]) / (half_turns[k] - half_turns[k - 1])
        x = gait_map.state((1 - f) * r.q[k - 1] + f * r.q[k], (1 - f) * r.v[k - 1] + f * r.v[k])
        states.append(gait_map.mirrored(x) if i % 2 else x)
    return np.array(states)


@pytest.mark.slow
def test_walk_stability_of_the_fastest_walker_with_the_defaults(capsys, monkeypatch):
    """Issue 34: `walk --stability` on the fastest walker, defaults (its CPU time is benchmarks/bench_stability.py's,
    not a test's: machines differ 2-3x). Its step map jumps
    (a rocking foot's landings split between time steps), so Newton stalls and the map is fitted to
    simulated steps (Newton gives up as soon as an iteration stalls).
    The dominant multiplier agrees with two estimates the fit never saw: the same
    least-squares fit on the 20 steps of the walk itself, and the decay of a large kick in direct simulation.
    The walk itself is the command's own (kept as it passes by, not walked a second time)."""
    from pasibot_pin.__main__ import main
    from pasibot_pin.model.design import load_design
    from pasibot_pin.studies import walking
    from pasibot_pin.studies.methods.decay import decay_rate
    from pasibot_pin.studies.methods.map_fit import fit_affine_map

    walked: list = []

    def kept(design, settings, robot, progress=False):
        walked.append((design, settings, walk := walk_design(design, settings, robot, progress=progress)))
        return walk

    monkeypatch.setattr(walking, "walk_design", kept)
    assert main(["walk", "--design", FASTEST, "--stability", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["outcome"] == "walks" and out["stable"] is True
    assert out["stability_method"].startswith("least-squares fit") and "Newton" in out["stability_newton_note"]
    assert "stalls at iteration 2" in out["stability_newton_note"]  # given up early, not after its whole budget
    radius = max(math.hypot(*z) for z in out["multipliers"])
    low, high = out["dominant_multiplier_spread"]
    assert 0.5 < radius < 1.0 and low <= radius + 1e-9 and high < 1.0

    ((design, settings, walk),) = walked  # the command walked once: this design, with the defaults
    assert design == load_design(FASTEST) and settings == WalkSettings()
    robot = design_robot(design, 2, visuals=False)
    gait_map = GaitMap(robot, walk.settings)
    _, gait_map.guess = section_state(gait_map, walk)
    own = _own_crossings(gait_map, walk)
    assert len(own) >= WalkSettings().steps - 2
    walked = max(abs(np.linalg.eigvals(fit_affine_map(own[:-1], own[1:])[1])))
    assert walked == pytest.approx(radius, abs=0.1)
    x_star = own.mean(axis=0)
    kick = np.zeros(gait_map.size)
    kick[4] = 0.2  # hip pitch rate [rad/s], some 100 times the steps' jitter
    assert decay_rate(gait_map, x_star, kick, steps=12) == pytest.approx(radius, abs=0.1)
