"""The fast full sample: the closed form's exact motion (jets), the batched rows, the split by virtual power.

Each new path against an independent one: the jets against finite differences of the closed
form and against the constraint core's exact projections (J v = [0; s_dot], J a = [-J_dot v; 0]);
the batched rows against the one-sample evaluation; the torques against virtual power (the
constraint forces do no work) and against the sweep when the closure is polished by Newton.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import pasibot_pin as pp
from pasibot_pin.dynamics import inverse as dynamics
from pasibot_pin.dynamics import stance_plan
from pasibot_pin.model import closure, jet, scenarios
from pasibot_pin.model.scenario_robots import scenario_robot

OMEGA = 5.0
THETAS = np.linspace(math.pi / 2, 3 * math.pi / 2, 23)


def _wrapped(diff: np.ndarray) -> np.ndarray:
    return np.angle(np.exp(1j * diff))


# --------------------------------------------------------------------------- jets
@pytest.mark.parametrize(
    "func",
    [jet.sqrt, lambda z: jet.cabs(z + 0.3j), lambda z: jet.abs2(z + 0.3j), lambda z: jet.angle(z + 0.3j), jet.exp_i],
)
def test_each_jet_function_has_the_derivatives_of_finite_differences(func):
    """x(t) = 1.3 + 0.4 t + 0.2 t^2 through each function: value, rate and acceleration at t = 0.7."""
    t, h = 0.7, 1e-4

    def path(time):
        return 1.3 + 0.4 * time + 0.2 * time**2

    out = func(jet.Jet(np.array([path(t)]), np.array([0.4 + 0.4 * t]), np.array([0.4])))
    plain = [func(np.array([path(t + k * h)]))[0] for k in (-1, 0, 1)]
    assert out.v[0] == pytest.approx(plain[1], rel=1e-14)
    assert out.d[0] == pytest.approx((plain[2] - plain[0]) / (2 * h), rel=1e-7)
    assert out.dd[0] == pytest.approx((plain[2] - 2 * plain[1] + plain[0]) / h**2, rel=1e-5)


def test_jet_division_and_products_follow_the_chain_rule():
    x = jet.Jet(np.array([2.0]), np.array([0.5]), np.array([-0.3]))
    y = jet.Jet(np.array([1.5]), np.array([-0.2]), np.array([0.7]))
    q = x / y
    # (x / y) y = x: the product rule undoes the quotient rule
    back = q * y
    for part in ("v", "d", "dd"):
        assert getattr(back, part)[0] == pytest.approx(getattr(x, part)[0], rel=1e-14)


@pytest.mark.parametrize("variant", ["rigid", "parallel", "spring"])
@pytest.mark.parametrize("swing_pitch", [0.0, None])
def test_closed_form_motion_equals_finite_differences_and_the_constraint_core(variant, swing_pitch):
    robot = pp.load(variant, 2)
    q, v, a, weld = closure.analytic_motion(robot, THETAS, OMEGA, swing_pitch, "right", 0.2)
    q0, weld0 = closure.analytic_configurations(robot, THETAS, None, 0.0, swing_pitch, "right", 0.2)
    assert np.array_equal(q, q0) and weld is weld0
    # finite differences of the closed form along the crank angle (angles compared wrapped)
    h = 1e-3
    qp = closure.analytic_configurations(robot, THETAS + h, None, 0.0, swing_pitch, "right", 0.2)[0]
    qm = closure.analytic_configurations(robot, THETAS - h, None, 0.0, swing_pitch, "right", 0.2)[0]
    angular = closure.angular_coordinates(robot.model)
    up, down = qp - q, q - qm
    up[:, angular], down[:, angular] = _wrapped(up[:, angular]), _wrapped(down[:, angular])
    v_fd = (up + down) / (2 * h) * OMEGA
    a_fd = (up - down) / h**2 * OMEGA**2
    assert np.max(np.abs(v - v_fd)) < 1e-5 * np.max(np.abs(v))
    assert np.max(np.abs(a - a_fd)) < 1e-4 * np.max(np.abs(a))
    # the constraint core's exact projections at the same q
    rs = robot.with_weld("right", weld)
    swing_foot = "level" if swing_pitch is not None else "square"
    rows = closure.system(rs, rs.constraint_models, stance_plan.prescriptions(rs, "right", swing_foot))
    free = [0.0, 0.0] if robot.spec.free_ankle else []
    rates = np.array([OMEGA, OMEGA, *free])
    v_core, a_core, _ = rows.motion_many(q, rates, np.zeros_like(rates))
    assert np.max(np.abs(v - v_core)) < 1e-11 * np.max(np.abs(v))
    assert np.max(np.abs(a - a_core)) < 1e-11 * np.max(np.abs(a))
    assert np.max(np.abs(rows.residual(q[5], targets=[THETAS[5], THETAS[5] + math.pi, *free]))) < 1e-12


def test_closed_form_motion_at_rest_is_zero():
    robot = pp.load("spring", 2)
    _, v, a, _ = closure.analytic_motion(robot, THETAS, 0.0)
    assert not v.any() and not a.any()


# --------------------------------------------------------------------------- batched rows
def test_batched_rows_equal_the_one_sample_evaluation():
    robot = pp.load("spring", 2)
    q, v, _, weld = closure.analytic_motion(robot, THETAS, OMEGA)
    rs = robot.with_weld("right", weld)
    rows = closure.system(rs, rs.constraint_models, stance_plan.prescriptions(rs, "right", "level"))
    rng = np.random.default_rng(3)
    q = q + 0.01 * rng.standard_normal(q.shape)  # off the manifold: every row is non-zero
    targets = rng.standard_normal((len(q), len(rows.scalars)))
    batch = rows.evaluate(q, v, targets=targets)
    for k in range(len(q)):
        one = rows.evaluate(q[k], v[k], targets=targets[k])
        assert np.allclose(batch.phi[k], one.phi, rtol=0, atol=1e-13)
        assert np.allclose(batch.jac[k], one.jac, rtol=0, atol=1e-13)
        assert np.allclose(batch.drift[k], one.drift, rtol=0, atol=1e-11)


# --------------------------------------------------------------------------- torques
@pytest.mark.parametrize("variant", ["rigid", "parallel", "spring"])
@pytest.mark.parametrize("motors", ["two", "one"])
def test_actuator_power_equals_the_power_of_the_rnea_torques(variant, motors):
    """Virtual power: v^T tau = u . (S v) + lambda_C (C v); the constraint forces do no work (J_c v = 0)."""
    robot = scenario_robot(scenarios.SCENARIOS["run4"], scenarios.PRESETS["default"], variant)
    res = dynamics.inverse_dynamics(robot, THETAS, OMEGA, stance="right", motors=motors)
    rs = robot.with_weld("right", closure.stance_weld(robot, "right"))
    layout = dynamics.get_motor_layout(motors)
    joints = stance_plan.actuated_joints(rs, "right", layout)
    rate = {name: res.v[:, rs.idx_v(name)] for name in joints}
    n_motor = len(layout.motors)
    power = res.Ta * rate[joints[0]]
    if n_motor == 2:
        power = power + res.Ta_swing * rate[joints[1]]
    else:  # the coupling q_L - q_R - pi = 0 delivers the transmission torque to the left crank
        power = power + res.transmission * (res.v[:, rs.idx_v("left_j0_crank")] - res.v[:, rs.idx_v("right_j0_crank")])
    if robot.spec.free_ankle:  # T_e is the generalised force of beta = pi/2 - q_ankle
        power = power - res.Te * rate[joints[n_motor]] - res.Te_swing * rate[joints[n_motor + 1]]
    reference = np.einsum("ni,ni->n", res.v, res.tau)
    assert np.max(np.abs(reference)) > 1.0
    assert np.allclose(power, reference, rtol=0, atol=1e-9 * np.max(np.abs(reference)))


def test_a_polished_closure_gives_the_same_torques(monkeypatch):
    """A guess 1e-9 off the manifold goes through Newton and the constraint core's v and a: same answer."""
    robot = scenario_robot(scenarios.SCENARIOS["run4"], scenarios.PRESETS["default"])
    exact = dynamics.inverse_dynamics(robot, THETAS, OMEGA, stance="right")
    original = closure.analytic_motion

    def nudged(*args, **kwargs):
        q, v, a, weld = original(*args, **kwargs)
        return q + 1e-9, v, a, weld

    monkeypatch.setattr(closure, "analytic_motion", nudged)
    polished = dynamics.inverse_dynamics(robot, THETAS, OMEGA, stance="right")
    assert not np.array_equal(polished.q, exact.q)
    for name in ("Ta", "Te", "Ta_swing", "Te_swing", "ground"):
        ref = getattr(exact, name)
        assert np.allclose(getattr(polished, name), ref, rtol=0, atol=1e-9 * np.max(np.abs(ref))), name
