"""Independent cross-check: the seed's Newton-Euler free-body method (A.F = b), written here.

Everything below the imports is computed from the closed-form joint positions of
``tests/closed_form.py`` (no pasibot_pin import there) and the mass rule of seed Tab 7.1.1:
link point masses at mid-points, accelerations from a 7-point finite-difference stencil in
the crank angle. Each body gives 3 equations (forces, moment about its COM); the unknowns
are the joint forces of both legs and the four torques. The result must agree with
``pasibot_pin.dynamics.inverse`` (constrained RNEA) to 1e-8 relative.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from closed_form import leg

L = 0.05
G = 9.81
TOTAL = 65.0
THIGH = {1: 1.0, 2: 5.0, 3: 2.5, 4: 9.0, 6: 6.0}
SHANK = {5: 18.0, 7: 6.0}
FOOT_MASS = 1.3
FOOT_COM = 0.5 * L  # uniform sole from heel (0.5 L behind) to toe (1.5 L ahead)

LINK_MASS = {i: 0.10 * TOTAL * r / sum(THIGH.values()) for i, r in THIGH.items()}
LINK_MASS.update({i: 0.05 * TOTAL * r / sum(SHANK.values()) for i, r in SHANK.items()})

# Bodies of one leg: name -> (COM as a function of the points, mass)
LINK_ENDS = {"L1": (0, 1), "L2": (1, 4), "L3": (3, 2), "L4": (4, 6), "L5": (6, 13), "L6": (8, 5), "L7": (8, 7)}
LINK_INDEX = {"L1": 1, "L2": 2, "L3": 3, "L4": 4, "L5": 5, "L6": 6, "L7": 7}
# Joints of one leg: name -> (point, body receiving +F, body receiving -F). F = force of the second on the first.
JOINTS = {
    "j0": (0, "L1", "body"),
    "j1": (1, "L2", "L1"),
    "j2": (2, "L2", "L3"),
    "j3": (3, "L3", "body"),
    "j4": (4, "L4", "L2"),
    "j5": (5, "L4", "L6"),
    "j6": (6, "L5", "L4"),
    "j7": (7, "L5", "L7"),
    "j8_l6": (8, "L6", "body"),
    "j8_l7": (8, "L7", "body"),
    "j13": (13, "foot", "L5"),
}

STENCIL = np.array([1 / 90, -3 / 20, 3 / 2, -49 / 18, 3 / 2, -3 / 20, 1 / 90])


def world_points(theta: float, swing_foot: str) -> dict[tuple[str, object], np.ndarray]:
    """Joint points and COMs [m] of the stance (right, crank theta) and swing (left, theta + pi) legs.

    Hip level, stance ankle at the origin (the world frame is the leg frame shifted).
    """
    legs = {"st": leg(theta), "sw": leg(theta + math.pi)}
    origin = legs["st"][13]
    pts = {}
    for tag, p in legs.items():
        for key, z in p.items():
            if isinstance(key, int):
                pts[(tag, key)] = np.array([(z - origin).real, (z - origin).imag]) * L
        for name, (a, b) in LINK_ENDS.items():
            pts[(tag, name)] = (pts[(tag, a)] + pts[(tag, b)]) / 2
        if swing_foot == "level":
            direction = np.array([1.0, 0.0])
        else:
            u = (p[13] - p[6]) / abs(p[13] - p[6]) * 1j
            direction = np.array([u.real, u.imag])
        pts[(tag, "foot")] = pts[(tag, 13)] + FOOT_COM * direction
    return pts


def com_accelerations(theta: float, omega: float, swing_foot: str, body_dx: float, h: float = 1e-2):
    samples = [world_points(theta + (k - 3) * h, swing_foot) for k in range(7)]
    acc = {}
    for key in samples[0]:
        acc[key] = omega**2 * sum(c * s[key] for c, s in zip(STENCIL, samples)) / h**2
    acc["body"] = acc[("st", 8)]  # the body translates with joint 8 (hip level)
    return acc


def free_body_solve(theta: float, omega: float, body_mass: float, body_dx: float, swing_foot: str = "level"):
    """Solve the 48 x 48 free-body system; return torques and joint forces (x, z) [N.m, N]."""
    pts = world_points(theta, swing_foot)
    acc = com_accelerations(theta, omega, swing_foot, body_dx)
    body_com = pts[("st", 8)] + np.array([body_dx, 0.0])
    # unknowns: per leg 11 joint forces (x, z) then T_a, T_e
    unknowns = [(tag, j, c) for tag in ("st", "sw") for j in JOINTS for c in (0, 1)]
    unknowns += [("st", "Ta", 0), ("st", "Te", 0), ("sw", "Ta", 0), ("sw", "Te", 0)]
    col = {u: k for k, u in enumerate(unknowns)}
    bodies = [(tag, name) for tag in ("st", "sw") for name in LINK_ENDS] + [("sw", "foot"), ("x", "body")]
    row = {b: 3 * k for k, b in enumerate(bodies)}
    n = len(unknowns)
    assert 3 * len(bodies) == n == 48
    a_mat, b_vec = np.zeros((n, n)), np.zeros(n)

    def com_of(body):
        return body_com if body[1] == "body" else pts[body]

    def mass_of(body):
        if body[1] == "body":
            return body_mass
        if body[1] == "foot":
            return FOOT_MASS
        return LINK_MASS[LINK_INDEX[body[1]]]

    def add_force(body, joint_key, point, sign):
        if body not in row:  # the stance foot is the ground
            return
        r, c = row[body], com_of(body)
        arm = point - c
        for comp in (0, 1):
            k = col[joint_key + (comp,)]
            a_mat[r + comp, k] += sign
        # moment (CCW) of F about the COM: arm_x F_z - arm_z F_x
        a_mat[r + 2, col[joint_key + (0,)]] += -sign * arm[1]
        a_mat[r + 2, col[joint_key + (1,)]] += sign * arm[0]

    for tag in ("st", "sw"):
        for j, (p, first, second) in JOINTS.items():
            point = pts[(tag, p)]
            b1 = ("x", "body") if first == "body" else (tag, first)
            b2 = ("x", "body") if second == "body" else (tag, second)
            add_force(b1, (tag, j), point, 1.0)
            add_force(b2, (tag, j), point, -1.0)
        # torques: T_a on L1 (+) and the body (-); T_e on L5 (+) and the foot (-)
        a_mat[row[(tag, "L1")] + 2, col[(tag, "Ta", 0)]] += 1.0
        a_mat[row[("x", "body")] + 2, col[(tag, "Ta", 0)]] -= 1.0
        a_mat[row[(tag, "L5")] + 2, col[(tag, "Te", 0)]] += 1.0
        if (tag, "foot") in row:
            a_mat[row[(tag, "foot")] + 2, col[(tag, "Te", 0)]] -= 1.0
    for body, r in row.items():
        m = mass_of(body)
        a_body = acc["body"] if body[1] == "body" else acc[body]
        b_vec[r : r + 2] = m * a_body - m * np.array([0.0, -G])
    sol = np.linalg.solve(a_mat, b_vec)
    out = {k: sol[col[u]] for k, u in (("Ta", ("st", "Ta", 0)), ("Te", ("st", "Te", 0)))}
    out["Ta_swing"], out["Te_swing"] = sol[col[("sw", "Ta", 0)]], sol[col[("sw", "Te", 0)]]
    forces = {(tag, j): sol[[col[(tag, j, 0)], col[(tag, j, 1)]]] for tag in ("st", "sw") for j in JOINTS}
    return out, forces


@pytest.fixture(scope="module")
def run4_results():
    from pasibot_pin.dynamics import inverse as dynamics
    from pasibot_pin.model import scenarios

    thetas = np.array([1.7, 2.4, 3.1, 3.9, 4.6])
    out = {}
    for swing_foot in ("level", "square"):
        choices = scenarios.PRESETS["default"].with_(swing_foot=swing_foot)
        out[swing_foot] = dynamics.run_scenario(scenarios.SCENARIOS["run4"], choices, thetas=thetas)
    return thetas, out


def _close(ours, ref, scale):
    np.testing.assert_allclose(ours, ref, rtol=1e-8, atol=1e-8 * scale)


@pytest.mark.parametrize("swing_foot", ["level", "square"])
def test_torques_and_reactions_match_free_body_solve(run4_results, swing_foot):
    thetas, results = run4_results
    res = results[swing_foot]
    # map our generic reaction names to the free-body joints (force of parent on child / on frame_a)
    tree = {"j0_crank": ("j0", 1), "j1": ("j1", 1), "j3": ("j3", 1), "j4": ("j4", 1), "j6": ("j6", 1)}
    tree.update({"j8_l6": ("j8_l6", 1), "j8_l7": ("j8_l7", 1), "j13_ankle": ("j13", 1)})
    cuts = {"j2": "j2", "j5": "j5", "j7": "j7"}
    for k, theta in enumerate(thetas):
        ref, forces = free_body_solve(theta, 5.0, 20.0, 0.30, swing_foot)
        scale = max(abs(ref["Ta"]), abs(ref["Te"]), 1.0)
        for name in ("Ta", "Te", "Ta_swing", "Te_swing"):
            _close(getattr(res, name)[k], ref[name], scale)
        fscale = max(np.abs(f).max() for f in forces.values())
        for tag, generic in (("st", "stance"), ("sw", "swing")):
            for ours, (theirs, sign) in tree.items():
                _close(res.joints[f"{generic}_{ours}"][k, :2], sign * forces[(tag, theirs)], fscale)
            for ours, theirs in cuts.items():
                _close(res.cuts[f"{generic}_{ours}"][k], forces[(tag, theirs)], fscale)
            # the crank joint's moment is the motor torque, the ankle's is -T_e
            _close(res.joints[f"{generic}_j0_crank"][k, 2], ref["Ta" if tag == "st" else "Ta_swing"], scale)
            _close(res.joints[f"{generic}_j13_ankle"][k, 2], -ref["Te" if tag == "st" else "Te_swing"], scale)
        # ground on the stance foot: the foot is at rest, so ground = -(force of L5 on foot) - weight
        ground_ref = -forces[("st", "j13")] + np.array([0.0, FOOT_MASS * G])
        _close(res.ground[k, :2], ground_ref, fscale)
        _close(res.ground[k, 2], ref["Te"] + FOOT_MASS * G * FOOT_COM, scale)


def test_passive_tree_joints_carry_no_moment(run4_results):
    _, results = run4_results
    res = results["level"]
    for generic in ("stance", "swing"):
        for joint in ("j1", "j3", "j4", "j6", "j8_l6", "j8_l7"):
            assert np.max(np.abs(res.joints[f"{generic}_{joint}"][:, 2])) < 1e-9


def test_free_body_solve_fails_with_wrong_masses(run4_results):
    """The comparison can fail: a 1 kg heavier body changes T_e by far more than the tolerance."""
    thetas, results = run4_results
    ref, _ = free_body_solve(thetas[2], 5.0, 21.0, 0.30, "level")
    assert abs(results["level"].Te[2] - ref["Te"]) > 1e-3 * abs(ref["Te"])
