"""The planar tree's layout (dynamics/newton_euler.py) against Pinocchio, one sample at a time.

The bodies' motion of the layout (COM accelerations) against Pinocchio's classical
accelerations; :func:`_pinocchio_reactions` is the reference of the joint reactions:
``pin.rnea(q, v, a, fext)`` with the constraint forces written as joint-local ``pin.Force`` s,
whose ``data.f[j]`` is the force the parent transmits through joint j (used by
``tests/test_planar_id.py``, which checks the batched torques and reactions with it).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import pasibot_pin as pp
from pasibot_pin.constraints import anchor_points, is_weld
from pasibot_pin.dynamics.newton_euler import tree_layout


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


def random_states(variant: str, inertia: str, n: int, seed: int, v_scale: float = 1.0, a_scale: float = 1.0):
    """A two-leg robot, a fresh Data, and n samples (q, v, a) near q0 but off the manifold (the
    identities tested hold anywhere); and the generator, for more draws."""
    robot = pp.load(variant, 2, inertia=inertia)
    model = robot.model
    rng = np.random.default_rng(seed)
    q = robot.q0 + 0.05 * rng.normal(size=(n, model.nq))
    v, a = v_scale * rng.normal(size=(n, model.nv)), a_scale * rng.normal(size=(n, model.nv))
    return robot, model.createData(), q, v, a, rng


@pytest.mark.parametrize("variant", pp.VARIANTS)
@pytest.mark.parametrize("inertia", ["point", "uniform"])
def test_com_accelerations_equal_pinocchio_at_random_states(variant, inertia):
    n = 5
    robot, data, q, v, a, _ = random_states(variant, inertia, n, seed=7)
    model = robot.model
    tree = tree_layout(model, robot.constraint_models)
    pos, acc, alpha = tree.body_motion(q, v, a)
    for k in range(n):
        pin.forwardKinematics(model, data, q[k], v[k], a[k])
        for j in range(1, model.njoints):
            lever = model.inertias[j].lever
            spatial_v, spatial_a = data.v[j], data.a[j]
            vel = spatial_v.linear + np.cross(spatial_v.angular, lever)
            lin = spatial_a.linear + np.cross(spatial_a.angular, lever) + np.cross(spatial_v.angular, vel)
            world = data.oMi[j].rotation @ lin
            assert abs(acc[k, j - 1] - complex(world[0], world[2])) < 1e-9 * max(1.0, abs(world).max())
            com = data.oMi[j].act(lever)
            assert abs(pos[k, j - 1] - complex(com[0], com[2])) < 1e-12
            alpha_world = data.oMi[j].rotation @ spatial_a.angular
            assert abs(alpha[k, j - 1] + alpha_world[1]) < 1e-9 * max(1.0, abs(alpha_world).max())


def test_model_with_changed_masses_gets_a_new_layout():
    robot = pp.load("spring", 2)
    model = pin.Model(robot.model)
    first = tree_layout(model, robot.constraint_models)
    model.inertias[3] = pin.Inertia.FromSphere(2.0, 0.01)
    second = tree_layout(model, robot.constraint_models)
    assert second is not first and second.mass[2] == pytest.approx(2.0)
