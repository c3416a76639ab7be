"""The floor step on the free coordinates, the linkage's shape known ahead (dynamics/floor/shape_track.py).

Independent references: the planar rows' own Jacobian (the closed form's tangents must solve
J_S D = [0; I]), the rows' residual at the closed-form shapes, and the floor's general path (the
QP on every coordinate and Newton's projection in the mass metric), which a tracked run must
reproduce: the same motion, contact modes, forces and motor torques (the torques by virtual work
against the general path's multipliers).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pasibot_pin.dynamics.floor import shape_track
from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.settings import crank_advance, crank_advances
from pasibot_pin.dynamics.floor.shape_track import ShapeSplit, ShapeTrack
from pasibot_pin.model.coordinates import HIP_PITCH, SIDES
from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.studies.walking import WalkSettings, floor_settings

DESIGNS = {
    "parallel": Design(variant="parallel", parallel_toe=4.5, parallel_heel=4.5, omega=1.0),
    "spring": Design(variant="spring", foot_toe=3.0, foot_heel=1.5, omega=2.0),
    "rigid": Design(variant="rigid", omega=2.0),
    "one motor": Design(variant="parallel", parallel_toe=4.5, parallel_heel=4.5, omega=3.0, motors="one"),
}


@pytest.fixture(scope="module", params=list(DESIGNS))
def case(request):
    design = DESIGNS[request.param]
    robot = design_robot(design, 2, visuals=False)
    settings = floor_settings(design, WalkSettings(steps=4), robot)
    return request.param, robot, settings


def _general(monkeypatch) -> None:
    monkeypatch.setattr(FloorSimulator, "_shape_split", lambda self: None)


def test_the_split_frees_the_hip_and_the_free_ankles(case):
    name, robot, settings = case
    sim = FloorSimulator(robot, settings)
    split = sim._shape_split()
    assert split is not None
    free = [0, 1, 2]
    if name == "spring":  # the spring variant's foot is a leaf on its ankle
        free += [robot.idx_v(f"{side}_j13_ankle") for side in SIDES]
    assert sorted(split.free.tolist()) == sorted(free)
    assert len(split.shape) == sim.bilateral.nrows
    # the free columns vanish at other closed configurations too (not only where the split was found)
    thetas = settings.theta0 + np.linspace(0.3, 5.0, 7)
    q = np.array(
        [
            sim.bilateral.project(qk, 0.0, sim.targets(0.0) + (th - settings.theta0))
            for qk, th in zip(np.repeat(sim.initial_state()[0][None], len(thetas), 0), thetas)
        ]
    )
    q[:, HIP_PITCH] += 0.4  # a pitched hip: the rows' zero set does not move
    for qk, th in zip(q, thetas):
        rows = sim.bilateral.evaluate(qk, None, 0.0, sim.targets(0.0) + (th - settings.theta0))
        assert np.abs(rows.phi).max() < 1e-11
        assert np.abs(rows.jac[:, split.free]).max() < 1e-10


def test_a_held_hip_has_no_split():
    design = DESIGNS["parallel"]
    robot = design_robot(design, 2, visuals=False)
    settings = floor_settings(design, WalkSettings(steps=4), robot)
    from dataclasses import replace

    assert FloorSimulator(robot, replace(settings, hip="level"))._shape_split() is None


def test_the_closed_form_shapes_are_closed_and_their_tangents_solve_the_rows(case, monkeypatch):
    _, robot, settings = case
    monkeypatch.setattr(shape_track, "BLOCK", 250)  # cross blocks, and chunks of the contact rows
    monkeypatch.setattr(shape_track, "CHUNK", 64)
    sim = FloorSimulator(robot, settings)
    split = sim._shape_split()
    q0 = sim.initial_state()[0]
    h = settings.dt
    track = ShapeTrack(robot, split, sim.targets_many, h)
    n0 = sim.bilateral.n_constraint_rows
    identity = np.vstack((np.zeros((n0, sim.bilateral.nrows - n0)), np.eye(sim.bilateral.nrows - n0)))
    q = q0.copy()
    for k in range(600):  # across the ramp and more than two blocks
        t = k * h
        step = track.step(t, q)
        assert step is not None
        np.testing.assert_array_equal(step.start[split.shape], q[split.shape])
        f = step.free
        np.testing.assert_array_equal(step.columns[split.free, :f], np.eye(f))  # E_F
        assert not step.start[split.free].any() and not step.columns[split.free, f:].any()
        if k % 37 == 0:
            rows = sim.bilateral.evaluate(q, None, t, sim.targets(t))
            assert np.abs(rows.phi).max() < 1e-12
            jac_s = rows.jac[:, split.shape]
            np.testing.assert_allclose(jac_s @ step.tangent[split.shape], identity, atol=1e-10)
            # x_S solves the step's velocity row: J_S x_S = -Phi(q, t + h) / h
            ahead = sim.bilateral.evaluate(q, None, t + h, sim.targets(t + h))
            np.testing.assert_allclose(jac_s @ step.velocity[split.shape], -ahead.phi / h, atol=1e-9)
            # the projection's move: the next closed shape less the step's first-order one
            np.testing.assert_allclose(step.moved, step.end - step.start - h * step.velocity, atol=1e-15)
        q = q.copy()
        q[split.shape] = step.end[split.shape]


def test_a_tracked_run_is_the_general_run(case, monkeypatch):
    """Motion, modes, contact forces and motor torques: the shape track against the general path."""
    name, robot, settings = case
    sim = FloorSimulator(robot, settings)
    q0, v0 = sim.initial_state()  # both feet flat, at rest (the spring's preload then throws the feet)
    duration = 0.6
    tracked = sim.run(duration, q0, v0)
    assert sim._shape_split() is not None
    _general(monkeypatch)
    general = FloorSimulator(robot, settings).run(duration, q0, v0)
    assert tracked.modes == general.modes and len(set(tracked.modes["right"])) > 1 or name == "rigid"
    # the same scheme; the projection's metric is M at the step's start (the general path's Newton
    # takes it at q + h v): a third-order difference, 1e-7 rad over the run
    np.testing.assert_allclose(tracked.q, general.q, rtol=0, atol=1e-6)
    # an impact's force is its one step's impulse over h, as sensitive as the touchdown's instant:
    # compare what the run integrates, the floor's impulse and each motor's angular impulse
    h = settings.dt
    weight_impulse = sim.weight * duration
    np.testing.assert_allclose(h * tracked.normal.sum(), h * general.normal.sum(), rtol=0, atol=1e-6 * weight_impulse)
    torque_impulse = h * float(np.abs(general.motor_torque).sum(axis=0).max())
    np.testing.assert_allclose(
        h * tracked.motor_torque.sum(axis=0), h * general.motor_torque.sum(axis=0), rtol=0, atol=1e-5 * torque_impulse
    )
    assert np.median(np.abs(tracked.motor_torque - general.motor_torque)) < 1e-6 * np.abs(general.motor_torque).max()


@pytest.fixture(scope="module")
def walker():
    """The parallel walker's simulator and its consistent start."""
    design = DESIGNS["parallel"]
    robot = design_robot(design, 2, visuals=False)
    sim = FloorSimulator(robot, floor_settings(design, WalkSettings(steps=4), robot))
    return sim, sim.start_state()


def _count_general_steps(monkeypatch) -> list[float]:
    """The start time of every step the floor takes by its general path, from now on."""
    times: list[float] = []
    step = FloorSimulator.step

    def counting(self, *args, **kwargs):
        times.append(args[0])
        return step(self, *args, **kwargs)

    monkeypatch.setattr(FloorSimulator, "step", counting)
    return times


def test_the_track_declines_a_state_off_its_shape(walker, monkeypatch):
    """A start off the closed form's shape takes one general step (its projection closes the loops), then the track."""
    sim, start = walker
    general_steps = _count_general_steps(monkeypatch)
    sim.run(0.05, start.q, start.v)
    assert general_steps == []
    off = start.q.copy()
    off[sim._shape_split().shape[5]] += 1e-6
    sim.run(0.05, off, start.v)
    assert general_steps == [0.0]


def test_a_failing_closed_form_leaves_the_steps_to_the_general_path(walker, monkeypatch):
    sim, start = walker
    tracked = sim.run(0.1, start.q, start.v)

    def failing(*args, **kwargs):
        raise ValueError("loop j5 cannot assemble")

    monkeypatch.setattr(shape_track, "analytic_motion", failing)
    general_steps = _count_general_steps(monkeypatch)
    general = FloorSimulator(sim.robot, sim.settings).run(0.1, start.q, start.v)
    assert len(general_steps) == 100
    np.testing.assert_allclose(tracked.q, general.q, atol=1e-9)


def test_crank_advances_is_crank_advance_at_each_time():
    for ramp in (0.0, 0.3, 1.0):
        times = np.concatenate((np.linspace(-0.1, 2.0, 211), [ramp, math.nextafter(ramp, 0.0)]))
        expected = [crank_advance(float(t), ramp)[0] for t in times]
        np.testing.assert_allclose(crank_advances(times, ramp), expected, rtol=0, atol=1e-15)


def test_a_split_needs_the_cranks_pi_apart():
    design = DESIGNS["parallel"]
    robot = design_robot(design, 2, visuals=False)
    sim = FloorSimulator(robot, floor_settings(design, WalkSettings(steps=4), robot))
    q = sim.initial_state()[0]
    targets = sim.targets(0.0)
    assert ShapeSplit.of(robot, sim.bilateral, q, targets, sim._target_rates) is not None
    assert ShapeSplit.of(robot, sim.bilateral, q, targets, sim._target_rates * np.array([1.0, 2.0])) is None


def _hip_posed(q: np.ndarray, pose: np.ndarray) -> np.ndarray:
    out = q.copy()
    out[:3] = pose
    return out


def test_the_points_ride_the_hip_rigidly(case):
    """The floating form rebuilds the planar rows and their Jacobian at any hip pose from the unposed body rows."""
    name, robot, settings = case
    sim = FloorSimulator(robot, settings)
    points = sim.points
    form = points.floating_form(HIP_PITCH)
    assert form is not None and form.base == (0, 1) and abs(form.turn) == 1.0
    crank = robot.idx_v("right_j0_crank")
    assert points.floating_form(crank) is None  # the crank turns some points only
    rng = np.random.default_rng(3)
    q0 = sim.initial_state()[0]
    for _ in range(5):
        q = q0 + 0.3 * rng.standard_normal(q0.size)
        q[:3] = rng.uniform(-2.0, 2.0, 3)
        rows, jac = points.rows_and_jacobian(q)
        body = points.rows_and_jacobian(_hip_posed(q, np.zeros(3)))
        turn = np.exp(1j * form.turn * q[HIP_PITCH])
        np.testing.assert_allclose(rows, form.fixed + form.slide @ q[:2] + turn * (body[0] - form.fixed), atol=1e-14)
        np.testing.assert_allclose(jac[:, :2], form.slide, atol=0)
        np.testing.assert_allclose(jac[:, 2], 1j * form.turn * turn * (body[0] - form.fixed), atol=1e-14)
        np.testing.assert_allclose(jac[:, 3:], turn * body[1][:, 3:], atol=1e-14)


def test_the_tracked_contact_rows_are_the_planar_rows(case, monkeypatch):
    """The step's cone rows and end points from the track's body rows, against the planar rows at the posed state."""
    name, robot, settings = case
    monkeypatch.setattr(shape_track, "BLOCK", 300)
    monkeypatch.setattr(shape_track, "CHUNK", 64)
    sim = FloorSimulator(robot, settings)
    h = settings.dt
    track, stepper = sim._tracker(h)
    if name == "spring":  # the free ankles are not the hip's: the rows come from the planar rows at each step
        assert track.form is None
        return
    assert track.form is not None
    q = sim.initial_state()[0]
    rng = np.random.default_rng(5)
    for k in range(400):
        step = track.step(k * h, q)
        if k % 23 == 0:
            posed = _hip_posed(step.start, rng.uniform(-1.0, 1.0, 3))
            cone, lower = stepper._floating_cone(posed[:3].tolist(), step.contact.start, h)
            want_cone, want_lower = stepper._cone_rows(posed, step, h)
            np.testing.assert_allclose(cone, want_cone, rtol=0, atol=1e-12)
            np.testing.assert_allclose(lower, want_lower, rtol=0, atol=1e-9)  # gap / h: 1e-12 m over 1 ms
            end = _hip_posed(step.end, rng.uniform(-1.0, 1.0, 3))
            u = rng.standard_normal(3)
            x = step.velocity.copy()
            x[:3] = u
            got = stepper._floating_points(end[:3].tolist(), u.tolist(), step.contact.end)
            np.testing.assert_allclose(got, stepper.rows.lists(end, x), rtol=0, atol=1e-12)
        q = step.end
