"""The batched planar inverse dynamics (dynamics/planar_id.py) against Pinocchio's rnea.

Independent reference: ``pin.rnea(q, v, a)`` one sample at a time for the torques, and
``pin.rnea(q, v, a, fext)`` with the constraint forces as external forces (``data.f[j]``) for
the joint reactions (the helper of ``test_newton_euler_batch.py``). Checked at random states off
the manifold, and along prescribed motions through ``inverse_dynamics`` for every variant and both
motor layouts at random crank angles and rates, where the split is redone from Pinocchio's tau.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from test_newton_euler_batch import _pinocchio_reactions, random_states

import pasibot_pin as pp
from pasibot_pin.constraints import is_weld
from pasibot_pin.dynamics import inverse as dynamics
from pasibot_pin.dynamics.newton_euler import tree_layout
from pasibot_pin.dynamics.planar_id import planar_inverse_dynamics
from pasibot_pin.dynamics.stance_plan import stance_plan
from pasibot_pin.model import scenarios
from pasibot_pin.model.scenario_robots import scenario_robot
from pasibot_pin.model.variants import get_motor_layout

RTOL = 1e-9
"""Relative to the largest entry of the reference [-]."""


def split_torques_many(tau: np.ndarray, s_matrix: np.ndarray, jac: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The reference split: tau = S^T u + J^T lambda solved whole, [S^T J^T] (N, nv, nv) -> (u, lambda)."""
    n = len(tau)
    mat = np.concatenate((np.broadcast_to(s_matrix.T, (n,) + s_matrix.T.shape), np.swapaxes(jac, 1, 2)), axis=2)
    x = np.linalg.solve(mat, tau[..., None])[..., 0]
    return x[:, : s_matrix.shape[0]], x[:, s_matrix.shape[0] :]


def _close(ours: np.ndarray, ref: np.ndarray) -> None:
    scale = float(np.max(np.abs(ref)))
    assert scale > 1.0  # a real check: the reference is not trivially zero
    np.testing.assert_allclose(ours, ref, rtol=0.0, atol=RTOL * scale)


@pytest.mark.parametrize("variant", pp.VARIANTS)
@pytest.mark.parametrize("inertia", ["point", "uniform"])
def test_torques_and_reactions_equal_pinocchio_at_random_states(variant, inertia):
    n = 4
    robot, data, q, v, a, rng = random_states(variant, inertia, n, seed=11, v_scale=3.0, a_scale=30.0)
    model = robot.model
    cmodels = robot.constraint_models
    lam = 50.0 * rng.normal(size=(n, sum(3 if is_weld(cm) else 2 for cm in cmodels)))
    tree = tree_layout(model, cmodels)
    planar = planar_inverse_dynamics(model, tree)
    assert planar.sliders  # the floating hip slides in x and z
    if variant == "parallel":
        assert len(planar.turning_col) == 2  # each leg's stabiliser slider turns with the leg
    wrench = planar.wrenches(q, *tree.body_motion(q, v, a))
    tau = planar.torques(q, wrench)
    reac = planar.reactions(q, wrench, lam)
    for k in range(n):
        _close(tau[k], pin.rnea(model, data, q[k], v[k], a[k]))
        _close(reac[k, 1:], _pinocchio_reactions(model, data, q[k], v[k], a[k], cmodels, lam[k])[1:])


@pytest.mark.parametrize("variant", pp.VARIANTS)
@pytest.mark.parametrize("motors", ["two", "one"])
def test_inverse_dynamics_equals_rnea_and_the_split_of_its_tau(variant, motors):
    """Along a prescribed motion: tau is rnea's, and u, lambda and every reaction follow from it."""
    rng = np.random.default_rng({"rigid": 1, "parallel": 2, "spring": 3}[variant] + (10 if motors == "one" else 0))
    robot = scenario_robot(scenarios.SCENARIOS["run4"], scenarios.PRESETS["default"], variant)
    thetas = np.sort(rng.uniform(math.pi / 2, 3 * math.pi / 2, 5))
    omega = float(rng.uniform(1.0, 8.0))
    res = dynamics.inverse_dynamics(robot, thetas, omega, stance="right", motors=motors)
    model, data = robot.model, robot.model.createData()
    ref_tau = np.array([pin.rnea(model, data, res.q[k], res.v[k], res.a[k]) for k in range(len(thetas))])
    _close(res.tau, ref_tau)
    # the split of Pinocchio's tau on the same rows (the existing path), then the reactions by fext
    layout = get_motor_layout(motors)
    plan = stance_plan(robot, "right", "level", layout, 0.0)
    jac = plan.rows.evaluate(res.q).jac
    nc = plan.rows.n_constraint_rows
    coupling = np.broadcast_to(plan.coupling, (len(thetas),) + plan.coupling.shape)
    u, lam_all = split_torques_many(ref_tau, plan.s_matrix, np.concatenate((jac[:, :nc], coupling), 1))
    _close(res.Ta, u[:, 0])
    if robot.spec.free_ankle:
        _close(res.Te, -u[:, len(layout.motors)])
    lam = lam_all[:, :nc]
    _close(res.ground, lam[:, plan.weld_rows])
    cmodels = plan.robot.constraint_models
    for k in range(len(thetas)):
        ref = _pinocchio_reactions(model, data, res.q[k], res.v[k], res.a[k], cmodels, lam[k])
        ours = np.array([res.joints[name][k] for name in plan.joint_names])
        _close(ours, ref[list(plan.joint_names.values())])
