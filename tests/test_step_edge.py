"""The third ground of the planar floor: a step edge (issue 35). Its treads are the only contact
surfaces, written once (``Ground.planar_gaps``) for the general step, the tracked step and the judge.

A 0-height step, or one far ahead, is the flat floor bit for bit; a walk wholly past a step is the
flat walk raised by its height; climbing a small step lifts the centre of mass by the step's height
(Pinocchio's centre of mass, independent of the contact rows) while the motors' work pays the
kinetic and potential energy and some dissipation (>= 0); a toe that crosses the edge below the upper
tread has ``tripped`` (its height measured on a flat floor, independently of the riser check).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from pasibot_pin.__main__ import main
from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.ground import MAX_STEP_HEIGHT, Ground
from pasibot_pin.dynamics.floor.settings import FloorSettings
from pasibot_pin.dynamics.verdict import FAILURES
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.studies.walking import WalkSettings, floor_settings, walk_design
from tests.test_slope import tracked_and_general

FAST = Design(variant="parallel", parallel_toe=6.0, parallel_heel=6.0, omega=3.0)
CLIMB = (0.002, 0.35)
"""A 2 mm step up at x = 0.35 m: past the start's feet (its front toe at 0.3 m), crossed by every
swinging heel and toe above it [m]."""


@pytest.fixture(scope="module")
def robot():
    return design_robot(FAST, 2, visuals=False)


@pytest.fixture(scope="module")
def flat3(robot):
    """Three steps on the flat floor."""
    return walk_design(FAST, WalkSettings(steps=3), robot)


@pytest.mark.slow
def test_a_step_of_height_zero_or_far_ahead_is_the_flat_floor_bit_for_bit(robot, flat3):
    flat = flat3.result
    for height, at in ((0.0, 0.5), (0.01, 100.0)):  # the second runs the step's rows, every tread at 0
        other = walk_design(FAST, WalkSettings(steps=3, step_height=height, step_at=at), robot).result
        assert np.array_equal(flat.q, other.q) and np.array_equal(flat.motor_torque, other.motor_torque)
        assert np.array_equal(flat.normal, other.normal)


@pytest.mark.slow
def test_a_walk_wholly_past_a_step_is_the_flat_walk_raised_by_its_height(robot, flat3):
    height, flat = 0.01, flat3
    high = walk_design(FAST, WalkSettings(steps=3, step_height=height, step_at=-100.0), robot)
    assert high.verdict.outcome == flat.verdict.outcome and high.verdict.steps == flat.verdict.steps
    raised = flat.result.q.copy()
    raised[:, 1] += height
    assert np.abs(high.result.q - raised).max() < 1e-9
    assert np.abs(high.result.normal - flat.result.normal).max() < 1e-6 * flat.result.normal.max()


def _energy(robot, result):
    """(motor work, kinetic energy change, centre of mass rise [m], its potential energy change) [J]."""
    model = robot.model
    data = model.createData()
    cranks = [model.joints[model.getJointId(n)].idx_v for n in robot.actuated_joints]
    mass = sum(model.inertias[j].mass for j in range(model.njoints))
    power = (result.motor_torque[:, : len(cranks)] * result.v[:, cranks]).sum(axis=1)
    work = float(power[1:].sum() * (result.t[1] - result.t[0]))  # each sample: its step's impulse over h
    kinetic = [pin.computeKineticEnergy(model, data, result.q[k], result.v[k]) for k in (0, -1)]
    rise = float(pin.centerOfMass(model, data, result.q[-1])[2] - pin.centerOfMass(model, data, result.q[0])[2])
    return work, kinetic[1] - kinetic[0], rise, mass * float(np.linalg.norm(model.gravity.linear)) * rise


@pytest.mark.slow
def test_climbing_a_small_step_lifts_the_robot_by_its_height_and_makes_no_energy(robot):
    height, at = CLIMB
    flat = walk_design(FAST, WalkSettings(steps=6), robot)
    climb = walk_design(FAST, WalkSettings(steps=6, step_height=height, step_at=at), robot)
    assert flat.verdict.walks and climb.verdict.walks, climb.verdict.summary()
    assert min(climb.result.start.along) < at  # it started below the step ...
    feet = FloorSimulator(robot, climb.settings).contact_rows(climb.result.q[-1])[1]
    assert feet.min() > at  # ... and ends with every heel and toe past it
    energies = {}
    for name, walk in (("flat", flat), ("climb", climb)):
        work, kinetic, rise, potential = energies[name] = _energy(robot, walk.result)
        assert work - kinetic - potential >= -1e-6 * abs(work), (name, work, kinetic, potential)  # dissipation >= 0
    assert energies["climb"][2] - energies["flat"][2] == pytest.approx(height, rel=1e-3)
    assert energies["climb"][0] > energies["flat"][0]  # the motors paid for the climb


@pytest.mark.slow
def test_on_a_step_the_tracked_step_is_the_general_step(robot):
    """2.5 s onto the 2 mm step (both feet reach the upper tread): the hip within 1e-6 m / rad of the general step's."""
    height, at = CLIMB
    settings = floor_settings(FAST, WalkSettings(step_height=height, step_at=at), robot)
    tracked_sim, tracked, general = tracked_and_general(robot, settings, 2.5)
    n = min(len(tracked.t), len(general.t))
    assert n > 2000
    assert np.abs(tracked.q[:n, :3] - general.q[:n, :3]).max() < 1e-6
    on_top = tracked_sim.contact_rows(tracked.q[n - 1])[1] > at
    assert on_top.sum() >= 2 and tracked.touchdowns == general.touchdowns


def test_a_toe_that_crosses_the_edge_below_the_upper_tread_has_tripped(robot):
    height, at = 0.02, 0.5
    walk = walk_design(FAST, WalkSettings(steps=6, step_height=height, step_at=at), robot)
    verdict = walk.verdict
    assert verdict.outcome == "tripped" and "tripped" in FAILURES and "riser" in verdict.detail
    assert walk.result.stopped and "riser" in walk.result.stop_reason
    # measured on a flat floor (no riser check): one point crossed x = at between the last two samples,
    # below the upper tread
    flat = FloorSimulator(robot, floor_settings(FAST, WalkSettings(), robot))
    z_before, x_before, *_ = flat.contact_rows(walk.result.q[-2])
    z_after, x_after, *_ = flat.contact_rows(walk.result.q[-1])
    crossed = (x_before < at) & (x_after >= at)
    assert crossed.any() and np.all(z_after[crossed] < height)


def test_the_ground_of_a_step_gives_each_point_the_tread_under_it():
    ground = Ground.step(0.01, 0.5)
    points = np.array([[0.4, 0.0, 0.003], [0.5, 0.2, 0.013], [0.6, 0.0, 0.01]])
    assert ground.gap(points) == pytest.approx([0.003, 0.003, 0.0], abs=1e-15)
    assert ground.planar_gaps(points[:, 0] + 1j * points[:, 2]) == pytest.approx([0.003, 0.003, 0.0], abs=1e-15)
    assert ground.riser_hit([0.0, -0.004]) == 1 and Ground.flat().riser_hit([-0.004]) is None
    assert FloorSettings(step_height=0.01, step_at=0.5).ground == ground


def test_a_step_out_of_range_is_refused_by_name(capsys):
    for bad in (MAX_STEP_HEIGHT * 1.01, float("nan")):
        with pytest.raises(ParameterError, match="step_height"):
            FloorSettings(step_height=bad)
        with pytest.raises(ParameterError, match="step_height"):
            WalkSettings(step_height=bad)
    with pytest.raises(ParameterError, match="step_at"):
        Ground.step(0.01, 1e4)
    assert main(["walk", "--step-height", "0.5"]) == 2
    err = capsys.readouterr().err
    assert "--step-height" in err and len(err.strip().splitlines()) == 1
    assert main(["walk", "--step-height", "0.01", "--3d", "--omega", "3", "--steps", "4"]) == 2
    assert "--step-height" in capsys.readouterr().err
