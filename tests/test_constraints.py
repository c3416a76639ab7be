"""The constraint core: residual, Jacobian and drift of every row, for every variant.

Each quantity is checked two independent ways at random *moving* states (q off the manifold,
random v, the hip rotating):

* finite differences of the residual (Jacobian) and of J(q(s)) v along s (drift);
* Pinocchio's own stacked constraint Jacobian (``getConstraintsJacobian``), in-plane rows;
* the projections (q, v, a) solve what they claim, and the KKT forward dynamics satisfies
  M a + h = tau + J^T lambda with J a = -J_dot v.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import pasibot_pin as pp
from pasibot_pin import constraints
from pasibot_pin.constraints import ConstraintSystem, PitchRow, coordinate, coupling
from pasibot_pin.model import closure

MODELS = [(v, legs) for v in pp.VARIANTS for legs in (1, 2)]


def _scalars(robot):
    """Time-dependent cranks, a pitch row, and (biped) the hip and the one-motor coupling."""
    rows = [coordinate("right_j0_crank", robot.idx_v("right_j0_crank"), 1.0, 0.7)]
    foot = "left_foot" if robot.floating else "right_foot"  # the right foot of the biped is welded
    rows.append(PitchRow(foot, robot.frame_id(foot), 0.1, -0.3))
    if robot.floating:
        rows.append(coordinate("hip_pitch", 2, 0.05, 0.2))
        rows.append(coupling("crank_coupling", robot.idx_v("left_j0_crank"), robot.idx_v("right_j0_crank"), math.pi))
    return rows


def _system(robot):
    return ConstraintSystem(robot.model, robot.model.createData(), robot.constraint_models, _scalars(robot), 0.05)


def _moving_state(robot, seed):
    rng = np.random.default_rng(seed)
    q = pin.integrate(robot.model, robot.q0, 0.05 * rng.normal(size=robot.model.nv))
    v = rng.normal(size=robot.model.nv)
    if robot.floating:
        v[2] = 1.5  # the hip rotates
    return q, v


@pytest.mark.parametrize("key", MODELS, ids=[f"{v}-{n}" for v, n in MODELS])
def test_jacobian_drift_and_time_derivative_match_finite_differences(robots, key):
    robot = robots[key]
    cs = _system(robot)
    model = robot.model
    for seed in range(3):
        q, v = _moving_state(robot, seed)
        t = 0.3
        rows = cs.evaluate(q, v, t)
        eps = 1e-6
        fd_jac = np.column_stack(
            [
                (cs.residual(pin.integrate(model, q, eps * e), t) - cs.residual(pin.integrate(model, q, -eps * e), t))
                / (2 * eps)
                for e in np.eye(model.nv)
            ]
        )
        assert np.max(np.abs(fd_jac - rows.jac)) < 1e-7
        # drift: d/ds [J(q + s v)] v at s = 0 (nq == nv and the joints are all 1-dof or additive)
        fd_drift = (cs.jacobian(q + eps * v) - cs.jacobian(q - eps * v)) @ v / (2 * eps)
        assert np.max(np.abs(fd_drift - rows.drift)) < 1e-5 * max(1.0, np.max(np.abs(rows.drift)))
        assert np.max(np.abs(rows.drift)) > 1e-2, "a moving state has a drift"
        # the rheonomic rows: d Phi / dt
        fd_t = (cs.residual(q, t + eps) - cs.residual(q, t - eps)) / (2 * eps)
        np.testing.assert_allclose(rows.phi_t, fd_t, atol=1e-8)


@pytest.mark.parametrize("key", MODELS, ids=[f"{v}-{n}" for v, n in MODELS])
def test_planar_kinematics_equal_pinocchios_kinematics(robots, key):
    """The exact planar evaluation (default) against Pinocchio's joint Jacobians and classical accelerations."""
    robot = robots[key]
    fast = _system(robot)
    ref = ConstraintSystem(
        robot.model, robot.model.createData(), robot.constraint_models, _scalars(robot), 0.05, kinematics="pinocchio"
    )
    assert fast._planar_ends is not None and ref._planar_ends is None
    for seed in range(3):
        q, v = _moving_state(robot, 20 + seed)
        a, b = fast.evaluate(q, v, 0.4), ref.evaluate(q, v, 0.4)
        np.testing.assert_allclose(a.phi, b.phi, atol=1e-13)
        np.testing.assert_allclose(a.jac, b.jac, atol=1e-12)
        np.testing.assert_allclose(a.drift, b.drift, atol=1e-10 * max(1.0, np.max(np.abs(b.drift))))
        np.testing.assert_allclose(a.phi_t, b.phi_t, atol=0)


@pytest.mark.parametrize("key", MODELS, ids=[f"{v}-{n}" for v, n in MODELS])
def test_one_sample_evaluation_equals_the_batched_one(robots, key):
    """One sample (the simulator's fast path, terms merged per pitch) against a batch of one, with and
    without v, at the rows' own targets and at given ones."""
    robot = robots[key]
    cs = _system(robot)
    q, v = _moving_state(robot, 40)
    targets = cs.targets(0.7) + 0.01
    for vel, tgt in ((v, None), (None, None), (v, targets), (None, targets)):
        one = cs.evaluate(q, vel, 0.7, tgt)
        batch = cs.evaluate(q[None], None if vel is None else vel[None], 0.7, None if tgt is None else tgt[None])
        assert one.phi.shape == (cs.nrows,) and one.jac.shape == (cs.nrows, robot.model.nv)
        np.testing.assert_allclose(one.phi, batch.phi[0], atol=1e-14)
        np.testing.assert_allclose(one.jac, batch.jac[0], atol=1e-14)
        np.testing.assert_allclose(one.drift, batch.drift[0], atol=1e-13 * max(1.0, np.max(np.abs(batch.drift))))
        np.testing.assert_allclose(one.phi_t, batch.phi_t[0], atol=0)
    assert np.max(np.abs(one.phi)) > 1e-3, "an off-manifold state has a residual"


@pytest.mark.parametrize("key", MODELS, ids=[f"{v}-{n}" for v, n in MODELS])
def test_constraint_rows_match_pinocchios_constraint_jacobian(robots, key):
    robot = robots[key]
    cs = _system(robot)
    q, _ = _moving_state(robot, 7)
    full = constraints.pinocchio_constraint_jacobian(robot.model, robot.model.createData(), robot.constraint_models, q)
    index, sign = constraints.inplane_rows(robot.constraint_models)
    np.testing.assert_allclose(full[index] * sign, cs.constraint_jacobian(q), atol=1e-12)
    # the rows we drop are identically zero (planar model)
    dropped = np.setdiff1d(np.arange(full.shape[0]), index)
    assert np.max(np.abs(full[dropped])) < 1e-12


@pytest.mark.parametrize("key", MODELS, ids=[f"{v}-{n}" for v, n in MODELS])
def test_projections_solve_their_systems(robots, key):
    robot = robots[key]
    prescribed = closure.default_prescriptions(robot)
    cs = ConstraintSystem(robot.model, robot.model.createData(), robot.constraint_models, prescribed, robot.geometry.L)
    targets = closure.prescribed_values(robot, robot.q0, prescribed) + 0.05
    q_guess, _ = _moving_state(robot, 11)
    q = cs.project(q_guess, targets=targets)
    rows = cs.evaluate(q, None, 0.0, targets)
    assert np.max(np.abs(rows.phi)) < 1e-10 * robot.geometry.L / 0.05
    assert np.linalg.matrix_rank(rows.jac) == robot.model.nv, "constraints + prescriptions fix the pose"
    rates = np.linspace(1.0, 2.0, len(prescribed))
    v = cs.velocity(q, rates=rates)
    np.testing.assert_allclose(rows.jac @ v, np.r_[np.zeros(cs.n_constraint_rows), rates], atol=1e-10)
    acc = np.linspace(-1.0, 1.0, len(prescribed))
    a = cs.acceleration(q, v, accelerations=acc)
    drift = cs.evaluate(q, v).drift
    np.testing.assert_allclose(rows.jac @ a + drift, np.r_[np.zeros(cs.n_constraint_rows), acc], atol=1e-8)
    # second-order check of the acceleration: c(q(t)) stays 0 along q(t) = q + v t + a t^2/2
    h = 1e-3
    c = [cs.residual(q + v * s + 0.5 * a * s * s, 0.0, targets)[: cs.n_constraint_rows] for s in (-h, 0.0, h)]
    assert np.max(np.abs((c[0] - 2 * c[1] + c[2]) / h**2)) < 1e-3 * max(1.0, np.max(np.abs(a)))


def test_forward_dynamics_is_a_kkt_solution_and_impulse_projects(robots):
    robot = robots[("spring", 2)]
    cs = _system(robot)
    q = cs.project(robot.q0, 0.2)
    v_minus = np.random.default_rng(3).normal(size=robot.model.nv)
    v, impulse = cs.impulse(q, v_minus, 0.2)
    rows = cs.evaluate(q, v, 0.2)
    np.testing.assert_allclose(rows.jac @ v, -rows.phi_t, atol=1e-10)
    # the jump is M-orthogonal to the manifold: M (v+ - v-) = J^T Lambda, M from crba
    data = robot.model.createData()
    mass = pin.crba(robot.model, data, q)
    mass = np.triu(mass) + np.triu(mass, 1).T
    np.testing.assert_allclose(mass @ (v - v_minus), rows.jac.T @ impulse, atol=1e-9)
    tau = np.random.default_rng(4).normal(size=robot.model.nv)
    a, lam, rows = cs.forward_dynamics(q, v, tau, 0.2)
    data = robot.model.createData()
    rnea = pin.rnea(robot.model, data, q, v, a)
    np.testing.assert_allclose(rnea, tau + rows.jac.T @ lam, atol=1e-8)
    np.testing.assert_allclose(rows.jac @ a, -rows.drift, atol=1e-8)


@pytest.mark.parametrize("variant", pp.VARIANTS)
def test_batched_projection_and_motion_equal_one_sample_at_a_time(robots, variant):
    robot = robots[(variant, 2)]
    prescribed = closure.default_prescriptions(robot)
    cs = closure.system(robot, None, prescribed)
    thetas = np.linspace(1.7, 4.2, 7)
    targets = np.array([closure.prescribed_values(robot, robot.q0, prescribed)] * len(thetas))
    targets[:, 0], targets[:, 1] = thetas, thetas + math.pi
    guesses, _ = closure.analytic_configurations(robot, thetas)
    qs, rows = cs.project_many(guesses + 1e-4, targets)  # from a perturbed start: Newton has work to do
    rates = np.linspace(0.5, 1.5, len(prescribed))
    vs, accs, _ = cs.motion_many(qs, rates, -rates)
    for k in range(len(thetas)):
        q = cs.project(guesses[k] + 1e-4, targets=targets[k])
        np.testing.assert_allclose(qs[k], q, atol=1e-11)
        np.testing.assert_allclose(rows.jac[k], cs.jacobian(q), atol=1e-12)
        v, a, _ = cs.motion(q, rates, -rates)
        np.testing.assert_allclose(vs[k], v, rtol=1e-10, atol=1e-10)
        np.testing.assert_allclose(accs[k], a, rtol=1e-9, atol=1e-9)


def test_one_motor_coupling_row_and_errors(robots):
    robot = robots[("spring", 2)]
    cs = ConstraintSystem(robot.model, robot.data, [], [coupling("c", 4, 5, 1.0)])
    q = np.zeros(robot.model.nq)
    q[4], q[5] = 3.0, 1.5
    assert cs.residual(q)[0] == pytest.approx(0.5)
    assert cs.jacobian(q)[0, 4] == 1.0 and cs.jacobian(q)[0, 5] == -1.0
    with pytest.raises(ValueError, match="single index"):
        _ = coupling("c", 4, 5, 1.0).index
    with pytest.raises(TypeError, match="neither"):
        ConstraintSystem(robot.model, robot.data, [], ["not a row"])
    far = ConstraintSystem(robot.model, robot.data, robot.constraint_models, [coordinate("x", 0, 100.0)])
    with pytest.raises(ValueError, match="cannot assemble"):
        far.project(robot.q0, max_iter=3)


@pytest.mark.parametrize("key", MODELS, ids=[f"{v}-{n}" for v, n in MODELS])
def test_frame_rows_of_one_sample_equal_the_batched_ones(robots, key):
    """frame_rows' one-sample path (terms summed per phase, slider terms by the product rule, the
    floor's contact rows every step) against a batch of one, and its Jacobian against finite differences."""
    from pasibot_pin.constraints import frame_rows

    robot = robots[key]
    model = robot.model
    frames = [f for f in range(model.nframes) if model.frames[f].parentJoint > 0][::7]
    rows = frame_rows(model, frames, range(len(frames)), range(len(frames)))
    q, _ = _moving_state(robot, 7)
    one, batch = rows.evaluate(q), rows.evaluate(q[None])
    for a, b in zip((one[0], one[1], one[3]), (batch[0], batch[1], batch[3])):
        np.testing.assert_allclose(a, b[0], atol=1e-14)
    eps = 1e-6
    fd = np.column_stack(
        [(rows.evaluate(q + eps * e)[0] - rows.evaluate(q - eps * e)[0]) / (2 * eps) for e in np.eye(model.nv)]
    )
    np.testing.assert_allclose(one[1], fd, atol=1e-8)


@pytest.mark.parametrize("key", MODELS, ids=[f"{v}-{n}" for v, n in MODELS])
def test_the_mass_matrix_is_symmetric_bit_for_bit_and_new(robots, key):
    """``symmetric_mass_matrix`` is pin.crba's answer: both triangles, exact copies, a fresh array each call."""
    robot = robots[key]
    model, data = robot.model, robot.model.createData()
    q, _ = _moving_state(robot, 3)
    mass = constraints.symmetric_mass_matrix(model, data, q)
    assert np.array_equal(mass, mass.T) and np.abs(np.tril(mass, -1)).max() > 0.0
    np.testing.assert_allclose(np.triu(mass), np.triu(pin.crba(model, model.createData(), q)), rtol=0, atol=0)
    again = constraints.symmetric_mass_matrix(model, data, q + 0.1)
    assert not np.shares_memory(mass, again) and not np.array_equal(mass, again)
