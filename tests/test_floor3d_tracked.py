"""The 3-D floor's fast path: the least-distance contact QP (NNLS) and the tracked step.

* :func:`ldp_free_qp` against proxsuite on the same QPs, and against the QP's own optimality
  conditions (stationarity, signs, feasibility, complementarity); a redundant support gets the
  least-norm split of its impulses.
* :func:`floating_qp` (the legs' velocities from the square bilateral rows, the QP on the root)
  against the general elimination (:func:`reduced_qp`, QR of the rows) with proxsuite.
* The tracked 3-D step (the legs' shape known ahead) against the general step (Newton projection
  on every coordinate): the same walk, to a third-order term, for a rigid walker and for the
  spring biped whose free ankles join the hip among the unknowns.
"""

from __future__ import annotations

import numpy as np
import pytest

from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.engine3d import Floor3D
from pasibot_pin.dynamics.floor.ldp import floating_qp, ldp_free_qp
from pasibot_pin.dynamics.floor.qp import proxsuite_free_qp, reduced_qp
from pasibot_pin.dynamics.floor.settings import FloorSettings
from pasibot_pin.model.design import design_robot, load_design
from pasibot_pin.model.spatial import Footprint
from pasibot_pin.studies.spring_study import scenario_inputs
from pasibot_pin.studies.walking import WalkSettings, floor_settings

COMB = "designs/3d/upright_fastest_comb0.6L_omega2.toml"


def _pyramid_qp(rng: np.random.Generator, n: int = 6, corners: int = 8, mu: float = 0.8):
    """A contact-like QP: H SPD, four pyramid rows n +- mu t_k per corner, feasible, bounds that bind some rows."""
    a = rng.normal(size=(n, n))
    hessian = a @ a.T + n * np.eye(n)
    normal, t1, t2 = (rng.normal(size=(corners, n)) for _ in range(3))
    cone = np.concatenate([normal + mu * t1, normal - mu * t1, normal + mu * t2, normal - mu * t2])
    inside = rng.normal(size=n)  # a point that meets every row: the floor always has one (moving up)
    lower = cone @ inside - np.tile(rng.uniform(0.0, 0.5, corners), 4)
    return hessian, rng.normal(size=n) * 20.0, cone, lower


@pytest.mark.parametrize("seed", range(12))
def test_ldp_is_the_qp_optimum(seed):
    """NNLS's answer meets the QP's optimality conditions to round-off and is proxsuite's optimum."""
    hessian, g, cone, lower = _pyramid_qp(np.random.default_rng(seed))
    x, z = ldp_free_qp(hessian, g, cone, lower)
    slack = cone @ x - lower
    scale = 1.0 + np.abs(lower).max()
    np.testing.assert_allclose(hessian @ x + g, cone.T @ z, atol=1e-9 * (1.0 + np.abs(g).max()))
    assert z.min() >= 0.0
    assert slack.min() >= -1e-10 * scale
    assert np.abs(z * slack).max() <= 1e-9 * scale * (1.0 + z.max())
    x_ref, _ = proxsuite_free_qp(hessian, g, cone, lower)
    np.testing.assert_allclose(x, x_ref, atol=1e-6 * (1.0 + np.abs(x_ref).max()))


def test_ldp_without_binding_rows_is_the_free_minimum():
    """Rows that the unconstrained minimum meets carry nothing: x = -H^-1 g, z = 0."""
    rng = np.random.default_rng(3)
    hessian, g, cone, _ = _pyramid_qp(rng)
    x, z = ldp_free_qp(hessian, g, cone, np.full(len(cone), -1e9))
    np.testing.assert_allclose(x, -np.linalg.solve(hessian, g), rtol=1e-12)
    assert not z.any()


def test_a_redundant_support_gets_the_least_norm_split():
    """The same row twice (two corners that push alike): the impulse is shared equally, not put on one."""
    hessian = np.diag([2.0, 3.0])
    g = np.array([4.0, -1.0])  # the free minimum x = (-2, 1/3) breaks x0 >= 0
    cone = np.array([[1.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    x, z = ldp_free_qp(hessian, g, cone, np.array([0.0, 0.0, -10.0]))
    np.testing.assert_allclose(x, [0.0, 1.0 / 3.0], atol=1e-14)
    np.testing.assert_allclose(z, [2.0, 2.0, 0.0], atol=1e-12)  # H x + g = (4, 0) = C^T z, least norm


@pytest.mark.parametrize("seed", range(6))
def test_floating_qp_is_the_general_elimination(seed):
    """Square rows on the legs (the root free): the same x, y, z as QR elimination with proxsuite."""
    rng = np.random.default_rng(seed)
    root, legs = 6, 9
    n = root + legs
    a = rng.normal(size=(n, n))
    hessian = a @ a.T + n * np.eye(n)
    g = rng.normal(size=n) * 5.0
    a_eq = np.zeros((legs, n))
    a_eq[:, root:] = rng.normal(size=(legs, legs)) + 3.0 * np.eye(legs)
    b_eq = rng.normal(size=legs)
    _, _, cone, _ = _pyramid_qp(rng, n=n)
    inside = np.concatenate((rng.normal(size=root), np.linalg.solve(a_eq[:, root:], b_eq)))  # meets A x = b
    lower = cone @ inside - np.tile(rng.uniform(0.0, 0.5, len(cone) // 4), 4)
    x, y, z = floating_qp(hessian, g, a_eq, b_eq, cone, lower, root)
    x_ref, y_ref, _ = reduced_qp(hessian, g, a_eq, b_eq, cone, lower, solver=proxsuite_free_qp)
    np.testing.assert_allclose(a_eq @ x, b_eq, atol=1e-12)
    np.testing.assert_allclose(hessian @ x + g, a_eq.T @ y + cone.T @ z, atol=1e-9 * (1.0 + np.abs(g).max()))
    np.testing.assert_allclose(x, x_ref, atol=1e-6)
    np.testing.assert_allclose(y, y_ref, atol=1e-4 * (1.0 + np.abs(y_ref).max()))


def _both_steps(robot, settings, footprint, duration):
    """The same run with the tracked step and with the general step alone; the general steps the tracked run took."""
    runs, general = {}, {}
    for tracked in (True, False):
        engine = Floor3D(FloorSimulator(robot, settings), footprint)
        engine.tracked = tracked
        calls = [0]
        step = engine.step

        def counted(*args, _step=step, _calls=calls):
            _calls[0] += 1
            return _step(*args)

        engine.step = counted
        runs[tracked] = engine.run(duration, stop_on_verdict=False)
        general[tracked] = calls[0]
    return runs[True], runs[False], general[True]


@pytest.mark.slow
def test_the_tracked_3d_walk_is_the_general_walk():
    """A comb walker, 1.2 s (its first steps): tracked and general agree to a third-order term."""
    design = load_design(COMB)
    robot = design_robot(design, 2, visuals=False)
    fast, slow, general_steps = _both_steps(
        robot, floor_settings(design, WalkSettings(), robot), design.footprint(), 1.2
    )
    assert general_steps == 0  # every step tracked
    assert fast.verdict.outcome == slow.verdict.outcome and fast.verdict.steps == slow.verdict.steps
    assert np.abs(fast.hip - slow.hip).max() < 1e-6
    assert max(np.abs(fast.roll - slow.roll).max(), np.abs(fast.pitch - slow.pitch).max()) < 1e-6
    np.testing.assert_allclose(fast.q[:, 7:], slow.q[:, 7:], atol=1e-8)  # the legs: on the closed shape both
    assert fast.normal.sum(axis=1).max() > 100.0  # the feet carry the robot
    # a rigid contact's force answers a gap's 1e-8 m by ~1 N: the samples agree to 1 %, their impulse closer
    np.testing.assert_allclose(fast.normal.sum(axis=1), slow.normal.sum(axis=1), rtol=1e-2, atol=1.0)
    assert fast.normal.sum() == pytest.approx(slow.normal.sum(), rel=1e-5)


@pytest.mark.slow
def test_the_tracked_step_keeps_a_free_ankle_among_the_unknowns():
    """The seed's spring biped (free ankles on springs) on centred plates: tracked and general agree."""
    inputs = scenario_inputs("run1")
    settings = FloorSettings(omega=inputs.omega, spring=inputs.fit, dt=1e-3, motors="two")
    fast, slow, general_steps = _both_steps(inputs.robot, settings, Footprint.centred(inputs.robot.geometry.L), 0.6)
    assert general_steps == 0
    engine = Floor3D(FloorSimulator(inputs.robot, settings), Footprint.centred(inputs.robot.geometry.L))
    track = engine.spatial_track(1e-3)
    assert track is not None and len(track.free) > 6  # the ankles are unknowns with the hip
    assert fast.verdict.outcome == slow.verdict.outcome
    assert np.abs(fast.hip - slow.hip).max() < 1e-6
    np.testing.assert_allclose(fast.q[:, 7:], slow.q[:, 7:], atol=1e-6)
