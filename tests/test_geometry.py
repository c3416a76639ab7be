"""Pinocchio forward kinematics of the closed leg against closed-form geometry (docs/reference.md §4)."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from closed_form import leg

from pasibot_pin.model.closure import assemble, constraint_residual, crank_sweep

FRAMES = {
    4: "right_j4",
    6: "right_j6",
    13: "right_foot",
    2: "right_loop_j2_a",
    5: "right_loop_j5_a",
    7: "right_loop_j7_a",
}


def _xz(robot, q, frame):
    pin.framesForwardKinematics(robot.model, robot.data, q)
    return robot.data.oMf[robot.frame_id(frame)].translation[[0, 2]]


def _c(point: complex, L: float) -> np.ndarray:
    return np.array([point.real, point.imag]) * L


@pytest.mark.parametrize(
    "theta_deg, joint4, ankle",
    [(90, (0, -4), (6, -28)), (180, (2, -4), (2, -28)), (270, (4, -4), (-2, -28))],
)
def test_exact_reference_points(robots, L, theta_deg, joint4, ankle):
    for variant in ("rigid", "spring", "parallel"):
        robot = robots[(variant, 1)]
        q = assemble(robot, math.radians(theta_deg))
        np.testing.assert_allclose(_xz(robot, q, "right_j4"), np.array(joint4) * L, atol=1e-9)
        np.testing.assert_allclose(_xz(robot, q, "right_foot"), np.array(ankle) * L, atol=1e-9)


@pytest.mark.parametrize("variant", ["rigid", "spring", "parallel"])
def test_joint_positions_match_closed_form_over_a_turn(robots, L, variant):
    robot = robots[(variant, 1)]
    thetas = np.radians(np.arange(0.0, 360.0, 7.5))
    qs = crank_sweep(robot, thetas)
    for theta, q in zip(thetas, qs):
        ref = leg(theta)
        for joint, frame in FRAMES.items():
            np.testing.assert_allclose(_xz(robot, q, frame), _c(ref[joint], L), atol=1e-9, err_msg=f"joint {joint}")
        if variant == "rigid":
            np.testing.assert_allclose(_xz(robot, q, "right_toe"), _c(ref["toe"], L), atol=1e-9)
            np.testing.assert_allclose(_xz(robot, q, "right_heel"), _c(ref["heel"], L), atol=1e-9)
        if variant == "parallel":
            for joint, frame in {10: "right_j10", 9: "right_j9", 11: "right_j11", 12: "right_j12"}.items():
                np.testing.assert_allclose(_xz(robot, q, frame), _c(ref[joint], L), atol=1e-9)
            np.testing.assert_allclose(_xz(robot, q, "right_toe"), _c(ref["toe_parallel"], L), atol=1e-9)
            np.testing.assert_allclose(_xz(robot, q, "right_heel"), _c(ref["heel_parallel"], L), atol=1e-9)


def test_pantograph_identity(robots, L):
    """13 = 3*8 - 2*4, whatever the branch of joint 5."""
    robot = robots[("rigid", 1)]
    for q in crank_sweep(robot, np.radians(np.arange(0, 360, 15))):
        p4, p8, p13 = (_xz(robot, q, f) for f in ("right_j4", "right_j8_l6", "right_foot"))
        np.testing.assert_allclose(p13, 3 * p8 - 2 * p4, atol=1e-12)


def test_biped_q0_stands_on_the_right_foot(robots, L):
    """q0: right crank 180 deg, stance ankle at the world origin, hip level 28L above it."""
    for variant in ("rigid", "spring", "parallel"):
        robot = robots[(variant, 2)]
        q = robot.q0
        assert q[robot.idx_q("right_j0_crank")] == pytest.approx(math.pi)
        left = q[robot.idx_q("left_j0_crank")]
        assert math.cos(left - math.pi) == pytest.approx(-1.0)
        np.testing.assert_allclose(_xz(robot, q, "right_foot"), [0.0, 0.0], atol=1e-12)
        pin.framesForwardKinematics(robot.model, robot.data, q)
        sole = robot.data.oMf[robot.frame_id("right_foot")].rotation[:, 0]
        assert abs(sole[2]) < 1e-12, "stance sole must be level"
        assert np.max(np.abs(constraint_residual(robot, q))) < 1e-10
    spring = robots[("spring", 2)]
    np.testing.assert_allclose(_xz(spring, spring.q0, "hip"), [-2 * L, 28 * L], atol=1e-12)
    assert spring.q0[2] == pytest.approx(0.0, abs=1e-14)
