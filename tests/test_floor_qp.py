"""The floor step's contact QP (dynamics/floor/qp.py): the exact active-set solve and its proxsuite fallback.

Independent references: a QP whose answer is known in closed form (H = I, one equality and
bound rows: x_i = max(-g_i, l_i)), the KKT conditions checked directly on the floor's own QPs,
and a floor run with every QP left to proxsuite (the solver before the active-set step).
"""

from __future__ import annotations

import numpy as np
import pytest

import pasibot_pin as pp
from pasibot_pin.dynamics.floor import qp as floor_qp
from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.qp import ContactQP
from pasibot_pin.dynamics.floor.settings import FloorSettings
from pasibot_pin.studies import spring_study


@pytest.fixture(scope="module")
def robot():
    return pp.load("spring", 2)


def _box_qp(nv: int):
    """min 1/2 |x|^2 + g.x, x_0 = 0.3, x_i >= l_i on rows 1..4: x_i = max(-g_i, l_i), z_i = max(0, l_i + g_i)."""
    rng = np.random.default_rng(3)
    g = rng.normal(size=nv)
    a_eq = np.eye(nv)[:1]
    b_eq = np.array([0.3])
    c_in = np.eye(nv)[1:5]
    lower = np.array([-g[1] + 0.2, -g[2] - 0.2, -g[3] + 0.05, -g[4] - 0.4])  # rows 1 and 3 bind
    x = -g.copy()
    x[0] = 0.3
    x[1:5] = np.maximum(-g[1:5], lower)
    z = np.maximum(0.0, lower + g[1:5])
    y = np.array([0.3 + g[0]])
    return (np.eye(nv), g, a_eq, b_eq, c_in, lower), (x, y, z)


def test_the_exact_step_and_proxsuite_give_the_closed_form_answer(robot):
    args, (x, y, z) = _box_qp(robot.model.nv)
    qp = ContactQP(robot.model)
    first = qp.solve(*args)  # no active set yet: proxsuite
    assert (qp.fast, qp.fallback) == (0, 1)
    assert qp.active == [0, 2]
    second = qp.solve(*args)  # from the active set: the exact KKT solve
    assert (qp.fast, qp.fallback) == (1, 1)
    third = floor_qp.reduced_qp(*args)  # every subset of the bound rows on the free coordinates
    for got, tol in ((first, 1e-8), (second, 1e-12), (third, 1e-12)):
        np.testing.assert_allclose(got[0], x, atol=tol)
        np.testing.assert_allclose(got[1], y, atol=tol)
        np.testing.assert_allclose(got[2], z, atol=tol)


def test_a_wrong_guess_is_corrected_or_left_to_proxsuite(robot):
    args, (x, _, z) = _box_qp(robot.model.nv)
    for guess in ([], [0, 1, 2, 3], [1, 3]):  # too few, too many, the complement
        qp = ContactQP(robot.model)
        qp.active = list(guess)
        got = qp.solve(*args)
        np.testing.assert_allclose(got[0], x, atol=1e-8)
        np.testing.assert_allclose(got[2], z, atol=1e-8)
        assert qp.fast + qp.fallback == 1
    qp = ContactQP(robot.model, redundant=[[0, 2]])  # a declared group that is not redundant here:
    qp.active = [0, 2]  # leaving either row out violates it: proxsuite (too many freedoms for reduced_qp)
    qp.solve(*args)
    assert (qp.fast, qp.fallback) == (0, 1)
    assert qp._reduced([0, 1], 2, 0) == [0, 1] and qp._reduced([0, 1, 3], 2, 0) is None  # more rows than freedoms
    assert qp._reduced([0, 2, 3], 3, 0) == [2, 3] and qp._reduced([0, 2, 3], 3, 1) == [0, 3]  # one row of the group out
    assert qp._reduced([0, 2, 3], 3, 2) is None  # no third choice in a group of two
    lower = args[5].copy()
    lower[1] = -args[1][2]  # row 1 met with equality at the answer, its multiplier zero
    touching = (*args[:5], lower)
    for redundant in ([[0, 1]], []):  # a group met with equality: the motion is the same exact step
        qp = ContactQP(robot.model, redundant=redundant)
        qp.active = [0, 2]
        np.testing.assert_allclose(qp.solve(*touching)[0], x, atol=1e-12)
        assert (qp.fast, qp.fallback) == (1, 0)


def _kkt_error(args, out) -> dict[str, float]:
    hessian, g, a_eq, b_eq, c_in, lower = args
    x, y, z = out
    slack = c_in @ x - lower
    return {
        "stationarity": float(np.max(np.abs(hessian @ x + g - a_eq.T @ y - c_in.T @ z))),
        "equality": float(np.max(np.abs(a_eq @ x - b_eq), initial=0.0)),
        "feasibility": float(max(0.0, -slack.min())),
        "sign": float(max(0.0, -z.min())),
        "complementarity": float(np.max(np.abs(z * slack))),
    }


def _record_solves(monkeypatch) -> list:
    """Every (QP, answer) a :class:`ContactQP` gives from now on, in a list that fills as they come.

    A QP on the free coordinates (``solve_free``) is kept as one with no equality rows.
    """
    seen: list = []
    solve, solve_free = ContactQP.solve, ContactQP.solve_free

    def recording(self, *args):
        out = solve(self, *args)
        seen.append((args, out))
        return out

    def recording_free(self, hessian, g, c_in, lower, extra):
        x, z, shift = solve_free(self, hessian, g, c_in, lower, extra)
        n = len(g)  # the floor's cone rows run on past the free coordinates: the QP reads n entries
        qp = (np.array(hessian), np.array(g), np.zeros((0, n)), np.zeros(0), np.array(c_in)[:, :n], np.array(lower))
        seen.append((qp, (np.array(x), np.zeros(0), np.array(z))))
        np.testing.assert_allclose(qp[0] @ shift, extra, atol=1e-12 * (1.0 + np.abs(extra).max()))
        return x, z, shift

    monkeypatch.setattr(ContactQP, "solve", recording)
    monkeypatch.setattr(ContactQP, "solve_free", recording_free)
    return seen


def _proxsuite_only(monkeypatch) -> None:
    """From now on every floor step takes the general path (the QP on every coordinate, Newton's
    projection) and leaves its QP to proxsuite: the floor before the exact solves and the shape track."""
    monkeypatch.setattr(FloorSimulator, "_shape_split", lambda self: None)
    monkeypatch.setattr(floor_qp.ContactQP, "_active_set", lambda self, *args: None)
    monkeypatch.setattr(floor_qp, "reduced_qp", lambda *args: None)


def _assert_kkt(seen: list, tol: float) -> None:
    """Each recorded answer meets its QP's KKT conditions: rows to 1e-9, bounds and complementarity to ``tol``."""
    for args, out in seen:
        err = _kkt_error(args, out)
        scale = 1.0 + float(np.max(np.abs(args[1])))
        assert err["stationarity"] < 1e-8 * scale and err["equality"] < 1e-9
        assert err["feasibility"] < tol and err["sign"] == 0.0 and err["complementarity"] < tol


def test_floor_steps_meet_the_kkt_conditions_and_mostly_take_the_exact_step(monkeypatch):
    """Every QP of a floor run (fitted spring, cranks turning, heel and toe contacts changing) is solved."""
    inputs = spring_study.scenario_inputs("run1")
    seen = _record_solves(monkeypatch)
    sim = FloorSimulator(inputs.robot, FloorSettings(omega=inputs.omega, spring=inputs.fit))
    q0, v0 = sim.initial_state()  # the flat start: the preload throws the feet, modes change
    res = sim.run(0.15, q0, v0)
    assert len(res.t) == 150 and len(set(res.modes["right"])) > 1
    assert sim._qp.fast > 0.8 * len(res.t) and len(seen) == 150
    _assert_kkt(seen, 1e-9)


def test_a_floor_run_is_proxsuites_run_to_its_tolerance(monkeypatch):
    """The same run with every QP left to proxsuite (the solver before): the same modes, q to 1e-7."""
    inputs = spring_study.scenario_inputs("run1")
    settings = FloorSettings(omega=inputs.omega, spring=inputs.fit)
    sim = FloorSimulator(inputs.robot, settings)
    q0, v0 = sim.initial_state()  # the flat start: the preload throws the feet, modes change
    exact = sim.run(0.1, q0, v0)
    assert sim._qp.fast > 0.8 * len(exact.t)
    _proxsuite_only(monkeypatch)
    sim = FloorSimulator(inputs.robot, settings)
    reference = sim.run(0.1, q0, v0)
    assert sim._qp.fast == 0
    assert exact.modes == reference.modes and exact.outcome == reference.outcome
    assert len(set(reference.modes["right"])) > 1
    np.testing.assert_allclose(exact.q, reference.q, atol=1e-7)
    np.testing.assert_allclose(exact.normal, reference.normal, rtol=1e-6, atol=1e-3)


def test_dependent_rows_give_the_unique_motion_and_the_least_norm_cone_impulses():
    """Cone rows with a dependent one (row 3 = row 1 + row 2), all binding: the least-norm split.

    References: the KKT of the independent rows alone (numpy's dense solve) for the motion, and the
    one-parameter family of multipliers minimised in closed form for the impulses. Then bounds no
    motion meets with equality: the answer is the QP's (the KKT conditions, checked directly).
    """
    rng = np.random.default_rng(7)
    n = 6
    root = rng.normal(size=(n, n))
    hessian = root @ root.T + n * np.eye(n)
    a_eq = rng.normal(size=(2, n))
    cone = rng.normal(size=(2, n))
    c_in = np.vstack((cone, cone[0] + cone[1]))  # the last cone row depends on the two before
    b_eq, lower = rng.normal(size=2), rng.normal(size=3)
    lower[2] = lower[0] + lower[1]  # consistent
    rows = np.vstack((a_eq, c_in))
    # g chosen so that the three rows bind with multipliers (1, 2, 0) at the answer
    kkt = np.block([[hessian, -rows[:4].T], [rows[:4], np.zeros((4, 4))]])
    g = rng.normal(size=n)
    x_free = np.linalg.solve(kkt, np.concatenate((-g, b_eq, lower[:2])))[:n]
    g = a_eq.T @ np.array([0.5, -0.5]) + cone.T @ np.array([1.0, 2.0]) - hessian @ x_free
    x_ref, lam_ref = np.split(np.linalg.solve(kkt, np.concatenate((-g, b_eq, lower[:2]))), [n])
    x, y, z = floor_qp.reduced_qp(hessian, g, a_eq, b_eq, c_in, lower)
    np.testing.assert_allclose(x, x_ref, atol=1e-12)
    np.testing.assert_allclose(hessian @ x + g, a_eq.T @ y + c_in.T @ z, atol=1e-12)
    # every valid split: z_ref + s (-1, -1, 1); its norm is least at s = (z1 + z2 - z3) / 3
    z_ref = np.append(lam_ref[2:], 0.0)
    s = (z_ref[0] + z_ref[1] - z_ref[2]) / 3.0
    np.testing.assert_allclose(z, z_ref + s * np.array([-1.0, -1.0, 1.0]), atol=1e-12)
    inconsistent = lower.copy()
    inconsistent[2] += 0.3  # the three rows cannot all bind: the QP's answer all the same
    out = floor_qp.reduced_qp(hessian, g, a_eq, b_eq, c_in, inconsistent)
    err = _kkt_error((hessian, g, a_eq, b_eq, c_in, inconsistent), out)
    assert max(err.values()) < 1e-10


@pytest.mark.slow
def test_the_flat_double_support_takes_the_exact_step(monkeypatch):
    """The parallel walker's flat double support (both feet flat and sticking: over-constrained).

    Every QP meets the KKT conditions; proxsuite is left at most a few steps; the motion is
    proxsuite's (every QP left to it) to its tolerance, and so is the total normal force (the
    weight and the motion's), while the split between the points is the least-norm one.
    """
    from pasibot_pin.model.design import Design, design_robot
    from pasibot_pin.studies.walking import WalkSettings, floor_settings

    walker = Design(variant="parallel", parallel_toe=4.5, parallel_heel=4.5, omega=1.0)
    robot = design_robot(walker, 2, visuals=False)
    settings = floor_settings(walker, WalkSettings(steps=4), robot)
    seen = _record_solves(monkeypatch)
    sim = FloorSimulator(robot, settings)
    start = sim.start_state()
    exact = sim.run(0.4, start.q, start.v)
    assert exact.modes["left"][:40] == ["flat"] * 40 == exact.modes["right"][:40]
    # the first steps, both feet sticking, the robot rigid with its cranks: equal springs under a rigid
    # body, i.e. normal forces linear in the points' x along the floor, tangential forces all equal
    weight = sim.weight
    for k in range(10):
        along = sim.contact_rows(exact.q[k])[1]
        line = np.polyval(np.polyfit(along, exact.normal[k], 1), along)
        assert np.abs(line - exact.normal[k]).max() < 1e-9 * weight
        assert np.ptp(exact.tangential[k]) < 1e-9 * weight
    assert sim._qp.fallback <= 3 and sim._qp.fast > 390
    assert len(seen) == 401  # the start's rest check and the 400 steps
    _assert_kkt(seen, 1e-8)
    _proxsuite_only(monkeypatch)
    sim = FloorSimulator(robot, settings)
    reference = sim.run(0.4, start.q, start.v)
    assert sim._qp.fast == 0
    np.testing.assert_allclose(exact.q, reference.q, atol=1e-7)
    support = exact.normal.sum(axis=1)  # the total normal force is unique (the robot's weight and motion)
    np.testing.assert_allclose(support, reference.normal.sum(axis=1), rtol=1e-5)


def test_the_small_solves_are_numpys():
    """The closed-form inverses and solves of the free-coordinate QP against LAPACK's, and their singular cases."""
    from pasibot_pin.constraints.solves import inverse_lists

    rng = np.random.default_rng(11)
    for n in (1, 2, 3, 4):
        for _ in range(20):
            a = rng.normal(size=(n, n)) + n * np.eye(n)
            b = rng.normal(size=n)
            np.testing.assert_allclose(inverse_lists(a.tolist()), np.linalg.inv(a), rtol=1e-12, atol=1e-12)
            np.testing.assert_allclose(floor_qp._solve_small(a.tolist(), b.tolist()), np.linalg.solve(a, b), atol=1e-12)
        singular = np.ones((n, n)) if n > 1 else np.zeros((1, 1))
        assert floor_qp._solve_small(singular.tolist(), [1.0] * n) is None
        with pytest.raises(np.linalg.LinAlgError):
            inverse_lists(singular.tolist())


@pytest.mark.slow
def test_the_free_qp_is_the_equality_qp_on_its_free_coordinates():
    """solve_free on the free coordinates against solve on all of them with the others held by equality rows.

    Random QPs whose active sets hold from one to as many rows as unknowns (where the held rows
    alone fix x), each solved cold (every subset) and then warm (from its own active set).
    """
    rng = np.random.default_rng(5)
    n, free = 7, [0, 1, 2]
    sizes = set()
    for _ in range(40):
        root = rng.normal(size=(n, n))
        hessian = root @ root.T + n * np.eye(n)
        g, c_in = rng.normal(size=n), rng.normal(size=(8, n))
        fixed = rng.normal(size=n - len(free))
        inside = np.concatenate((rng.normal(size=len(free)), fixed))  # a feasible point: every row holds there
        lower = c_in @ inside - np.abs(rng.normal(size=8)) * rng.integers(0, 2, 8)  # some rows bind there
        full = ContactQP(pp.load("spring", 2).model)
        x, _, z = full.solve(hessian, g, np.eye(n)[len(free) :], fixed, c_in, lower)
        h_ff, h_fs = hessian[:3, :3], hessian[:3, 3:]
        extra = rng.normal(size=3)
        qp = ContactQP(pp.load("spring", 2).model)
        for _ in range(2):  # cold (every subset), then warm (the active set)
            args = (h_ff, g[:3] + h_fs @ fixed, c_in[:, :3], lower - c_in[:, 3:] @ fixed, extra)
            u, z_free, shift = qp.solve_free(*(a.tolist() for a in args))
            np.testing.assert_allclose(u, x[:3], atol=1e-9)
            np.testing.assert_allclose(z_free, z, atol=1e-9)
            np.testing.assert_allclose(h_ff @ shift, extra, atol=1e-12)
        sizes.add(int(np.count_nonzero(z > 0)))
        assert qp.fast == 2 and qp.fallback == 0
    assert {1, 2, 3} <= sizes
