"""A settled 3-D gait repeated rather than simulated (:mod:`pasibot_pin.dynamics.floor.repeat3d`).

* The free run's time step divides the crank period; the held run keeps the planar floor's grid.
* A floor motion (a turn about the vertical and a shift) moves a state as Pinocchio moves the robot:
  the corners of the moved configuration are the moved corners (forward kinematics, independent of
  :meth:`FloorMotion.apply`), the hip's rotation is Rz(psi) R, and a motion is found back from two states.
* A repeated period's feet, batched, are :func:`point_sample`'s bit for bit.
* The comb walker repeated from the step its gait settled is the comb walker simulated step by step:
  the same verdict, and every sample (hip, attitude, legs, the heel and toe loads, the clearance) equal
  to round-off; a walker that tips never settles.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.engine3d import Floor3D
from pasibot_pin.dynamics.floor.repeat3d import PeriodStep, motion_between
from pasibot_pin.dynamics.floor.run import LOAD_TOL, foot_samples, point_sample
from pasibot_pin.model.design import design_robot, load_design
from pasibot_pin.model.spatial import roll_pitch_yaw
from pasibot_pin.studies.walking import WalkSettings, floor_settings, walk_duration

COMB = "designs/3d/upright_fastest_comb0.6L_omega2.toml"


def _engine(design, hold: bool = False) -> Floor3D:
    robot = design_robot(design, 2, visuals=False)
    settings = floor_settings(design, WalkSettings(), robot)
    return Floor3D(FloorSimulator(robot, settings), design.footprint(), hold_lateral=hold, lateral=design.lateral())


@pytest.fixture(scope="module")
def comb() -> Floor3D:
    return _engine(load_design(COMB))


@pytest.mark.parametrize("duration", [0.37, 5.0, 41.3])
def test_the_free_grid_divides_the_crank_period(comb, duration):
    """h <= dt, pi / (omega h) whole (a walking step too), and the steps cover the duration (by less than one step)."""
    h, n = comb.time_grid(duration)
    steps_per_step = math.pi / comb.settings.omega / h
    assert h <= comb.settings.dt
    assert steps_per_step == pytest.approx(round(steps_per_step), abs=1e-9)
    assert duration <= n * h + 1e-12 < duration + h


def test_the_held_grid_is_the_planar_floors():
    """Held upright, the 3-D floor steps as the planar floor does: the duration in whole steps of at most dt."""
    held = _engine(load_design(COMB), hold=True)
    h, n = held.time_grid(5.0)
    assert n == math.ceil(5.0 / held.settings.dt - 1e-9) and h * n == pytest.approx(5.0, rel=1e-15)


def _turned(psi: float) -> np.ndarray:
    c, s = math.cos(psi), math.sin(psi)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def test_a_floor_motion_moves_the_robot_as_pinocchio_does(comb):
    """Apply a turn and a shift to a walking state: the moved corners are those of the moved configuration."""
    q, u, _ = comb.start()
    rng = np.random.default_rng(4)
    q = q.copy()
    q[3:7] = pin.Quaternion(pin.rpy.rpyToMatrix(0.03, -0.05, 0.4)).coeffs()  # some attitude
    u = u + rng.normal(scale=0.1, size=len(u))
    points, jac, _ = comb.contact(q)
    attitude = np.array(roll_pitch_yaw(q))
    step = PeriodStep(q.copy(), u.copy(), np.zeros(len(points)), np.zeros(2), points.copy(), jac @ u, attitude)
    psi, shift = 0.7, np.array([0.31, -0.12])
    target = q.copy()
    target[:2] = _turned(psi)[:2, :2] @ q[:2] + shift
    target[3:7] = pin.Quaternion(_turned(psi) @ pin.Quaternion(q[3:7]).toRotationMatrix()).coeffs()
    angular = np.zeros(len(q), dtype=bool)
    motion = motion_between(q, target, angular)
    assert motion.psi == pytest.approx(psi, abs=1e-12)
    moved = motion.apply(step)
    np.testing.assert_allclose(moved.q[:3], target[:3], atol=1e-12)
    rotation = pin.Quaternion(moved.q[3:7]).toRotationMatrix()
    np.testing.assert_allclose(rotation, _turned(psi) @ pin.Quaternion(q[3:7]).toRotationMatrix(), atol=1e-12)
    points_moved, jac_moved, _ = comb.contact(moved.q)  # forward kinematics of the moved configuration
    np.testing.assert_allclose(moved.points, points_moved, atol=1e-12)
    np.testing.assert_allclose(moved.velocity, jac_moved @ moved.u, atol=1e-12)
    np.testing.assert_allclose(moved.attitude, roll_pitch_yaw(moved.q), atol=1e-12)
    # a period's steps stacked move as each one alone
    stacked = PeriodStep(*(np.array([a, a]) for a in step))
    np.testing.assert_array_equal(motion.apply(stacked).points[1], moved.points)
    np.testing.assert_array_equal(motion.apply(stacked).q[0], moved.q)


@pytest.mark.slow
def test_a_settled_walk_repeated_is_the_walk_simulated():
    """The comb walker, 5 steps: repeated from the step it settled, every sample is the simulated one's."""
    design = load_design(COMB)
    settings = WalkSettings(steps=5)
    runs = {}
    for repeats in (True, False):
        engine = _engine(design)
        engine.repeats = repeats
        runs[repeats] = engine.run(walk_duration(design.omega, 5), criteria=settings.judged_by())
    fast, slow = runs[True], runs[False]
    period = 2.0 * math.pi / design.omega
    assert math.isnan(slow.settled_at_s) and fast.settled_at_s < 2.0 * period  # a period after the ramp
    assert fast.verdict.outcome == slow.verdict.outcome == "walks" and fast.verdict.steps == slow.verdict.steps
    assert fast.verdict.decided_at == slow.verdict.decided_at
    np.testing.assert_array_equal(fast.t, slow.t)
    np.testing.assert_allclose(fast.hip, slow.hip, atol=1e-8)
    for name in ("roll", "pitch", "yaw"):
        np.testing.assert_allclose(getattr(fast, name), getattr(slow, name), atol=1e-9)
    np.testing.assert_allclose(fast.q[:, 7:], slow.q[:, 7:], atol=1e-8)
    # each heel's and toe's load (what the judge reads): a flat sole's split among its corners is its own
    k = _engine(design).per_point
    np.testing.assert_allclose(
        fast.normal.reshape(len(fast.t), -1, k).sum(axis=2),
        slow.normal.reshape(len(slow.t), -1, k).sum(axis=2),
        atol=0.1,
    )
    assert fast.verdict.advance_m == pytest.approx(slow.verdict.advance_m, abs=1e-8)
    for name in ("max_hip_roll_deg", "yaw_per_step_deg", "lateral_drift_m", "min_sole_clearance_m"):
        assert getattr(fast, name) == pytest.approx(getattr(slow, name), abs=1e-7)


def test_a_walker_that_tips_never_settles():
    """Centred plates tip at the first single support: no period repeats, every step simulated."""
    design = load_design(COMB).with_(sole_inner=0.6, sole_outer=0.6, sole_gap_from=0.0, sole_gap_to=0.0)
    settings = WalkSettings(steps=4)
    result = _engine(design).run(walk_duration(design.omega, 4), criteria=settings.judged_by())
    assert result.verdict.outcome == "tipped" and math.isnan(result.settled_at_s)


@pytest.mark.parametrize("names", [("heel", "toe"), ("heel", "mid", "toe")])
def test_the_batched_feet_are_point_sample_s(names):
    """foot_samples (a repeated period's feet at once) is point_sample's, bit for bit, loads at the limit too."""
    rng = np.random.default_rng(len(names))
    n, points = 2000, 2 * len(names)
    heights = np.where(rng.random((n, points)) < 0.3, 0.0, rng.normal(scale=0.01, size=(n, points)))
    xs, slip = rng.normal(size=(n, points)), rng.normal(size=(n, points))
    normal = np.where(rng.random((n, points)) < 0.4, 0.0, np.abs(rng.normal(scale=100.0, size=(n, points))))
    normal[rng.random((n, points)) < 0.05] = LOAD_TOL  # exactly at the load threshold: not loaded
    batched = foot_samples(heights, xs, slip, normal, names)
    for j in range(n):
        view = (heights[j].tolist(), xs[j].tolist(), slip[j].tolist())
        sample, _ = point_sample(0.0, (0.0, 0.0), view, normal[j].tolist(), (0.0, 0.0), names)
        assert sample.feet == batched[j]
