"""Closure: residuals over full turns, branch continuity, Jacobians, motion on the manifold."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from conftest import ALL_MODELS

from pasibot_pin import constraints
from pasibot_pin.model.closure import (
    assemble,
    constraint_drift,
    constraint_jacobian,
    constraint_residual,
    crank_sweep,
    default_prescriptions,
    row_labels,
    solve_acceleration,
    solve_configuration,
    solve_velocity,
)

THETAS = np.radians(np.arange(360) + 0.5)


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _xz(robot, q, frame):
    pin.framesForwardKinematics(robot.model, robot.data, q)
    return robot.data.oMf[robot.frame_id(frame)].translation[[0, 2]]


@pytest.mark.parametrize("variant, legs", ALL_MODELS)
def test_residual_below_1e10_at_360_crank_angles_without_branch_flip(robots, variant, legs):
    robot = robots[(variant, legs)]
    qs = crank_sweep(robot, THETAS)
    worst = max(np.max(np.abs(constraint_residual(robot, q))) for q in qs)
    assert worst < 1e-10
    # Branch: coupler below the line 1-3 and knee forward (joint 5 left of 4 -> 8) at every sample.
    for q in qs:
        for side in ("right", "left")[:legs]:
            p1, p2, p3 = (_xz(robot, q, f"{side}_{f}") for f in ("j1", "loop_j2_a", "j3"))
            p4, p5, p8 = (_xz(robot, q, f"{side}_{f}") for f in ("j4", "loop_j5_a", "j8_l6"))
            assert _cross(p3 - p1, p2 - p1) < 0, "coupler flipped above the line 1-3"
            assert _cross(p8 - p4, p5 - p4) > 0, "knee flipped backward"
    # Continuity: 1 deg apart, no joint coordinate jumps (a branch flip moves some by > 0.3 rad).
    steps = np.abs(np.diff(qs, axis=0))
    assert steps.max() < 0.1


@pytest.mark.parametrize("variant, legs", ALL_MODELS)
def test_planar_jacobian_matches_pinocchio_constraint_jacobian(robots, variant, legs):
    robot = robots[(variant, legs)]
    q = crank_sweep(robot, [math.pi, 2.1])[-1]
    ours = constraint_jacobian(robot, q)
    full = constraints.pinocchio_constraint_jacobian(robot.model, robot.data, robot.constraint_models, q)
    rows, start = [], 0
    for cm in robot.constraint_models:
        if constraints.is_weld(cm):
            picked = [start + 0, start + 2, start + 4]
        else:
            picked = [start + 0, start + 2]
        rows += picked
        # the out-of-plane rows are identically zero
        other = [start + r for r in range(constraints.constraint_size(cm)) if start + r not in picked]
        assert np.abs(full[other]).max() < 1e-12
        start += constraints.constraint_size(cm)
    pinocchio_rows = full[rows]
    # Pinocchio's weld angular row is about +y; ours is the counter-clockwise pitch (about -y).
    signs = np.array([-1.0 if label.endswith(".pitch") else 1.0 for label in row_labels(robot)])
    np.testing.assert_allclose(ours, signs[:, None] * pinocchio_rows, atol=1e-12)


@pytest.mark.parametrize("variant, legs", ALL_MODELS)
def test_jacobian_matches_finite_differences(robots, variant, legs):
    robot = robots[(variant, legs)]
    rng = np.random.default_rng(3)
    q = crank_sweep(robot, [math.pi, 2.4])[-1] + 0.05 * rng.standard_normal(robot.model.nq)
    jac = constraint_jacobian(robot, q)
    h = 1e-6
    fd = np.zeros_like(jac)
    for k in range(robot.model.nv):
        dq = np.zeros(robot.model.nv)
        dq[k] = h
        plus = constraint_residual(robot, pin.integrate(robot.model, q, dq))
        minus = constraint_residual(robot, pin.integrate(robot.model, q, -dq))
        fd[:, k] = (plus - minus) / (2 * h)
    np.testing.assert_allclose(jac, fd, atol=1e-8)


@pytest.mark.parametrize("variant, legs", [("rigid", 1), ("parallel", 1), ("spring", 2), ("parallel", 2)])
def test_velocity_and_acceleration_on_the_manifold_match_finite_differences(robots, variant, legs):
    """theta(t) = theta0 + w t + 0.5 al t^2: v, a from the Jacobians vs differences of q(t)."""
    robot = robots[(variant, legs)]
    theta0, w, al, h = 2.2, 0.7, 0.3, 1e-4
    times = np.array([-2 * h, -h, 0.0, h, 2 * h])
    qs = crank_sweep(robot, theta0 + w * times + 0.5 * al * times**2)
    q = qs[2]
    prescribed = default_prescriptions(robot)
    n = len(prescribed)
    rates = np.zeros(n)
    accels = np.zeros(n)
    for k, p in enumerate(prescribed):
        if p.name in robot.actuated_joints:
            rates[k], accels[k] = w, al
    v = solve_velocity(robot, q, prescribed, rates)
    a = solve_acceleration(robot, q, v, prescribed, accels)
    v_fd = pin.difference(robot.model, qs[1], qs[3]) / (2 * h)
    a_fd = (pin.difference(robot.model, q, qs[3]) + pin.difference(robot.model, q, qs[1])) / h**2
    np.testing.assert_allclose(v, v_fd, atol=1e-6 * max(1, np.abs(v).max()))
    np.testing.assert_allclose(a, a_fd, atol=2e-4 * max(1, np.abs(a).max()))
    # the constraints hold to first and second order
    assert np.abs(constraint_jacobian(robot, q) @ v).max() < 1e-12
    drift = constraint_drift(robot, q, v)
    assert np.abs(constraint_jacobian(robot, q) @ a + drift).max() < 1e-10


def test_drift_matches_finite_difference_of_jacobian(robots):
    robot = robots[("spring", 2)]
    q = robot.q0
    rng = np.random.default_rng(0)
    v = rng.standard_normal(robot.model.nv)
    h = 1e-6
    jdot = (
        constraint_jacobian(robot, pin.integrate(robot.model, q, h * v))
        - constraint_jacobian(robot, pin.integrate(robot.model, q, -h * v))
    ) / (2 * h)
    np.testing.assert_allclose(constraint_drift(robot, q, v), jdot @ v, atol=1e-6)


def test_assemble_reproduces_the_other_stance(robots, L):
    """Standing on the left foot: the left ankle is at the world origin, hip level."""
    robot = robots[("spring", 2)]
    q = assemble(robot, 0.0, stance="left")
    np.testing.assert_allclose(_xz(robot, q, "left_foot"), [0, 0], atol=1e-12)
    assert q[2] == pytest.approx(0.0, abs=1e-14)
    assert np.abs(constraint_residual(robot, q, robot.loop_constraints)).max() < 1e-12


def test_default_targets_are_read_at_the_guess_not_from_stale_data(robots):
    """The swing-foot pitch target defaults to its value at q_guess, whatever was computed before."""
    robot = robots[("spring", 2)]
    q_tilted = assemble(robot, math.pi, swing_foot_pitch=0.3)
    assemble(robot, 2.0)  # leaves the data at another pose
    q = solve_configuration(robot, q_tilted)
    pin.framesForwardKinematics(robot.model, robot.data, q)
    sole = robot.data.oMf[robot.frame_id("left_foot")].rotation[:, 0]
    assert math.atan2(sole[2], sole[0]) == pytest.approx(0.3, abs=1e-12)
