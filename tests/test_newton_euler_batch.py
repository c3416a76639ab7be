"""The batched planar Newton-Euler (dynamics/newton_euler.py) against Pinocchio, one sample at a time.

Independent reference: ``pin.rnea(q, v, a, fext)`` with the constraint forces written as
joint-local ``pin.Force`` s, whose ``data.f[j]`` is the force the parent transmits through
joint j. The identity holds at any state, on the manifold or not, and for any multipliers.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import pasibot_pin as pp
from pasibot_pin.constraints import anchor_points, is_weld
from pasibot_pin.dynamics.newton_euler import batch_rnea, tree_layout


def _pinocchio_reactions(model, data, q, v, a, cmodels, lam):
    """(njoints, 3) Fx, Fz [N] and CCW moment [N.m] of each parent on its child, from data.f."""
    pin.forwardKinematics(model, data, q)
    fext = [pin.Force.Zero() for _ in range(model.njoints)]
    r = 0
    for cm in cmodels:
        weld = is_weld(cm)
        for (joint, placement), sign in zip(anchor_points(cm), (1.0, -1.0)):
            if joint == 0:
                continue
            rot = data.oMi[joint].rotation
            f_local = rot.T @ (sign * np.array([lam[r], 0.0, lam[r + 1]]))
            m_local = np.cross(placement.translation, f_local)
            if weld:  # a counter-clockwise moment is about -y
                m_local = m_local + rot.T @ np.array([0.0, -sign * lam[r + 2], 0.0])
            fext[joint] = fext[joint] + pin.Force(f_local, m_local)
        r += 3 if weld else 2
    pin.rnea(model, data, q, v, a, fext)
    out = np.zeros((model.njoints, 3))
    for j in range(1, model.njoints):
        rot = data.oMi[j].rotation
        lin = rot @ data.f[j].linear
        out[j] = lin[0], lin[2], -(rot @ data.f[j].angular)[1]
    return out


@pytest.mark.parametrize("variant", pp.VARIANTS)
@pytest.mark.parametrize("inertia", ["point", "uniform"])
def test_reactions_and_torques_equal_pinocchio_at_random_states(variant, inertia):
    robot = pp.load(variant, 2, inertia=inertia)
    model, data = robot.model, robot.model.createData()
    rng = np.random.default_rng(7)
    n = 5
    q = robot.q0 + 0.05 * rng.normal(size=(n, model.nq))  # off the manifold: the identity holds anywhere
    v, a = rng.normal(size=(n, model.nv)), rng.normal(size=(n, model.nv))
    cmodels = robot.constraint_models
    m = sum(3 if is_weld(cm) else 2 for cm in cmodels)
    lam = 50.0 * rng.normal(size=(n, m))
    tree = tree_layout(model, cmodels)
    pos, acc, alpha = tree.body_motion(q, v, a)
    ours = tree.reactions(q, pos, acc, alpha, lam)
    tau = batch_rnea(model, q, v, a)
    for k in range(n):
        ref = _pinocchio_reactions(model, data, q[k], v[k], a[k], cmodels, lam[k])
        scale = np.max(np.abs(ref))
        np.testing.assert_allclose(ours[k, 1:], ref[1:], atol=1e-10 * scale)
        np.testing.assert_allclose(tau[k], pin.rnea(model, data, q[k], v[k], a[k]), rtol=1e-12, atol=1e-9)
        # the COM accelerations by directional derivatives against Pinocchio's classical accelerations
        pin.forwardKinematics(model, data, q[k], v[k], a[k])
        for j in range(1, model.njoints):
            lever = model.inertias[j].lever
            spatial_v = data.v[j]
            spatial_a = data.a[j]
            lin = spatial_a.linear + np.cross(spatial_a.angular, lever)
            vel = spatial_v.linear + np.cross(spatial_v.angular, lever)
            lin = lin + np.cross(spatial_v.angular, vel)
            world = data.oMi[j].rotation @ lin
            assert abs(acc[k, j - 1] - complex(world[0], world[2])) < 1e-9 * max(1.0, abs(world).max())


def test_model_with_changed_masses_gets_a_new_layout():
    robot = pp.load("spring", 2)
    model = pin.Model(robot.model)
    first = tree_layout(model, robot.constraint_models)
    model.inertias[3] = pin.Inertia.FromSphere(2.0, 0.01)
    second = tree_layout(model, robot.constraint_models)
    assert second is not first and second.mass[2] == pytest.approx(2.0)
