"""Heel/toe contact: quasi-static balance against masses computed here, QP vs closed-form feasibility,
infeasible contact reported (not raised), tip events, errors."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from pasibot_pin.dynamics.inverse import inverse_dynamics
from pasibot_pin.model.scenario_robots import scenario_robot
from pasibot_pin.model.scenarios import get_preset, get_scenario
from pasibot_pin.studies import contact

G = 9.81


@pytest.fixture(scope="module")
def quasi_static():
    """Quasi-static right stance of the default spring biped: (robot, torques, contact)."""
    scenario, choices = get_scenario("quasi-static"), get_preset("default")
    robot = scenario_robot(scenario, choices)
    thetas = np.linspace(math.pi / 2, 3 * math.pi / 2, 41)
    torques = inverse_dynamics(robot, thetas, 0.0, stance="right")
    return robot, torques, contact.contact_along(robot, torques, mu=0.6)


def _mass_and_com_x(robot, q):
    """Total mass and COM x from the bodies' masses and world COM positions (no pin.centerOfMass)."""
    model, data = robot.model, robot.model.createData()
    pin.forwardKinematics(model, data, q)
    masses = np.array([model.inertias[j].mass for j in range(1, model.njoints)])
    xs = np.array([data.oMi[j].act(model.inertias[j].lever)[0] for j in range(1, model.njoints)])
    return masses.sum(), float(masses @ xs / masses.sum())


def _ankle_and_ends(robot, q, side="right"):
    model, data = robot.model, robot.model.createData()
    pin.framesForwardKinematics(model, data, q)
    return [float(data.oMf[model.getFrameId(f"{side}_{n}")].translation[0]) for n in ("foot", "heel", "toe")]


def test_quasi_static_forces_sum_to_weight_and_cop_is_com(quasi_static):
    robot, torques, res = quasi_static
    feasible = np.flatnonzero(res.feasible)
    assert feasible.size >= 5, "the CoP must be inside the sole around mid-stance"
    for k in feasible:
        q = torques.q[k]
        mass, com_x = _mass_and_com_x(robot, q)
        weight = mass * G
        fz = res.heel_force[k, 1] + res.toe_force[k, 1]
        assert abs(fz - weight) <= 1e-9 * weight
        assert abs(res.heel_force[k, 0] + res.toe_force[k, 0]) <= 1e-9 * weight
        _, x_heel, x_toe = _ankle_and_ends(robot, q)
        cop_from_forces = (res.heel_force[k, 1] * x_heel + res.toe_force[k, 1] * x_toe) / fz
        assert abs(cop_from_forces - com_x) <= 1e-9 * abs(x_toe - x_heel)
        assert abs(res.cop_x[k] - com_x) <= 1e-9 * abs(x_toe - x_heel)
        assert res.heel_force[k, 1] >= -1e-9 and res.toe_force[k, 1] >= -1e-9


def test_quasi_static_ground_wrench_is_gravity_wrench(quasi_static):
    """The weld's wrench equals the robot's gravity wrench about the stance ankle (cranks and springs are internal)."""
    robot, torques, _ = quasi_static
    for k in range(0, len(torques), 5):
        q = torques.q[k]
        mass, com_x = _mass_and_com_x(robot, q)
        ankle_x, _, _ = _ankle_and_ends(robot, q)
        expected = np.array([0.0, mass * G, mass * G * (com_x - ankle_x)])  # CCW moment of the ground on the foot
        assert np.allclose(torques.ground[k], expected, rtol=0, atol=1e-9 * mass * G)


def test_cop_outside_sole_is_a_tip_with_the_first_time(quasi_static):
    robot, torques, res = quasi_static
    for k in range(len(res)):
        mass, com_x = _mass_and_com_x(robot, torques.q[k])
        ankle_x, x_heel, x_toe = _ankle_and_ends(robot, torques.q[k])
        inside = x_heel <= com_x <= x_toe
        assert bool(res.feasible[k]) == inside
        if com_x < x_heel:
            assert res.reasons[k] == ("tip-heel",)
        if com_x > x_toe:
            assert res.reasons[k] == ("tip-toe",)
    first = res.first_failure()
    assert first is not None and first[0] == res.t[np.flatnonzero(~res.feasible)[0]]
    # the CoP enters the sole over the heel, then leaves it over the toe: crossings where com x = edge
    events = res.tip_events()
    assert [(e["edge"], e["direction"]) for e in events] == [("heel", "enters"), ("toe", "leaves")]
    for ev in events:
        assert ev["x"] == pytest.approx(-0.025 if ev["edge"] == "heel" else 0.075, abs=1e-12)


def test_low_friction_reported_as_slip_with_first_time_not_a_crash():
    """mu = 0.01 at 5 rad/s on a long what-if sole: the first failing sample is the first with |Fx| > 0.01 Fz."""
    scenario, choices = get_scenario("run4"), get_preset("default")
    robot = scenario_robot(scenario, choices)
    thetas = np.linspace(math.pi / 2, 3 * math.pi / 2, 31)
    torques = inverse_dynamics(robot, thetas, scenario.omega, stance="right")
    res = contact.contact_along(robot, torques, mu=0.01, sole=(-1.0, 1.0))
    ratio = np.abs(torques.ground[:, 0]) / torques.ground[:, 1]
    assert np.all(torques.ground[:, 1] > 0)
    slipping = ratio > 0.01
    assert slipping.any() and not slipping.all()
    assert np.array_equal(~res.feasible, slipping)
    first = res.first_failure()
    k = int(np.flatnonzero(slipping)[0])
    assert first == (pytest.approx(torques.t[k]), pytest.approx(torques.theta[k]), ("slip",))
    assert np.all(np.isfinite(res.heel_force)) and np.all(np.isfinite(res.toe_force))
    assert "first failure" in res.summary()
    # the default 10 cm sole with mu = 0.01: still reported, never raised
    res2 = contact.contact_along(robot, torques, mu=0.01)
    assert not res2.all_feasible and res2.first_failure() is not None


def test_qp_feasibility_matches_closed_form_on_random_wrenches():
    rng = np.random.default_rng(3)
    s_heel, s_toe = -0.025, 0.075
    agree = 0
    for _ in range(300):
        mu = rng.uniform(0.05, 1.0)
        pitch = rng.uniform(-0.3, 0.3)
        fn = rng.uniform(-50, 400)
        ft = rng.uniform(-1.2, 1.2) * mu * abs(fn)
        s_cop = rng.uniform(-0.06, 0.11)
        t, n = np.array([math.cos(pitch), math.sin(pitch)]), np.array([-math.sin(pitch), math.cos(pitch)])
        force = ft * t + fn * n
        wrench = [force[0], force[1], s_cop * fn]
        sol = contact.distribute(wrench, s_heel, s_toe, mu, pitch)
        margin = 1e-6
        expect = fn > 0 and s_heel + margin < s_cop < s_toe - margin and abs(ft) < mu * fn * (1 - margin)
        clear_fail = fn < 0 or s_cop < s_heel - margin or s_cop > s_toe + margin or abs(ft) > mu * abs(fn) * (1 + 1e-3)
        if expect:
            assert sol.feasible
            f = sol.forces
            assert np.allclose(f.sum(axis=0), force, atol=1e-9 * max(abs(fn), 1.0))
            s = np.array([s_heel, s_toe])
            assert abs(s @ (f @ n) - s_cop * fn) <= 1e-9 * max(abs(fn), 1.0)
            assert np.all(f @ n >= -1e-9) and np.all(np.abs(f @ t) <= mu * (f @ n) + 1e-9)
            assert sol.s_cop == pytest.approx(s_cop, abs=1e-12)
            agree += 1
        elif clear_fail:
            assert not sol.feasible and sol.reasons
            agree += 1
    assert agree > 250


def _cone_rows(t, n, mu):
    """The heel and toe cones as rows C (6, 4), C f <= 0, written here from the cone's definition."""
    rows = np.zeros((6, 4))
    for k in range(2):
        rows[3 * k : 3 * k + 3, 2 * k : 2 * k + 2] = [t - mu * n, -t - mu * n, -n]
    return rows


@pytest.mark.parametrize("regularisation", [1e-9, pytest.param(1e-2, marks=pytest.mark.slow)])  # 1e-2: ~1.6 s of CPU
def test_the_cone_qp_is_proxsuites_answer_and_meets_the_kkt_conditions(regularisation):
    """contact.cone_qp (by the cones' faces) against proxsuite run to 1e-12 on random tipping and slipping
    problems shaped as distribute's best effort: in the cones, KKT (H f + g + C_A^T lam = 0, lam >= 0 by
    nnls), a cost no higher than proxsuite's, and, where the Hessian is well conditioned, the same forces.
    (At distribute's 1e-9 the heel and toe may pull against each other at almost no cost: proxsuite's
    1e-12 leaves them a few N off.)"""
    import proxsuite
    from scipy.optimize import nnls

    rng, compared, problems = np.random.default_rng(7), 0, 100 if regularisation > 1e-6 else 40
    for _ in range(problems):  # proxsuite takes its time on the ill-conditioned
        mu, pitch = rng.uniform(0.05, 1.0), rng.uniform(-0.3, 0.3)
        t, n = np.array([math.cos(pitch), math.sin(pitch)]), np.array([-math.sin(pitch), math.cos(pitch)])
        s_heel, s_toe = -rng.uniform(0.01, 0.1), rng.uniform(0.01, 0.2)
        a_eq = np.array([[1.0, 0, 1, 0], [0, 1.0, 0, 1], [*(s_heel * n), *(s_toe * n)]])
        aw = np.diag([1.0, 10.0, 1e-3 / (s_toe - s_heel)]) @ a_eq
        wrench = rng.normal(size=3) * [100.0, 300.0, 10.0]
        hess, g = (
            aw.T @ aw + regularisation * np.eye(4),
            -aw.T @ (np.diag([1.0, 10.0, 1e-3 / (s_toe - s_heel)]) @ wrench),
        )
        f = contact.cone_qp(hess, g, t, n, mu)
        rows = _cone_rows(t, n, mu)
        scale = 1.0 + np.abs(f).max()
        assert np.max(rows @ f) <= 1e-11 * scale  # in both cones
        active = np.abs(rows @ f) <= 1e-9 * scale
        lam = nnls(rows[active].T, -(hess @ f + g))[0] if active.any() else np.zeros(0)  # KKT, lam >= 0
        assert np.allclose(rows[active].T @ lam, -(hess @ f + g), atol=1e-6 * (1.0 + np.abs(g).max()))
        other = proxsuite.proxqp.dense.solve(
            H=hess, g=g, C=rows, l=np.full(6, -1e20), u=np.zeros(6), eps_abs=1e-12, eps_rel=0.0, max_iter=20_000
        )
        if other.info.status != proxsuite.proxqp.QPSolverOutput.PROXQP_SOLVED:
            continue  # no answer to compare with (the KKT check above stands alone)
        compared += 1
        x = np.array(other.x)
        cost = [0.5 * y @ hess @ y + g @ y for y in (f, x)]
        assert cost[0] <= cost[1] + 1e-11 * (1.0 + np.abs(g).max()) * (1.0 + np.abs(x).max())  # x: cones to 1e-12
        if regularisation > 1e-6:
            assert np.allclose(f, x, atol=1e-6 * (1.0 + np.abs(x).max()))
    assert compared >= problems // 2


def test_regularised_norm_splits_the_friction_evenly_when_cones_allow():
    sol = contact.distribute([10.0, 200.0, 0.025 * 200.0], -0.025, 0.075, 0.5)
    assert sol.feasible
    assert sol.forces[0, 0] == pytest.approx(5.0, abs=1e-7) and sol.forces[1, 0] == pytest.approx(5.0, abs=1e-7)
    assert sol.forces[0, 1] == pytest.approx(100.0, abs=1e-7) and sol.forces[1, 1] == pytest.approx(100.0, abs=1e-7)


def test_errors_name_the_parameter():
    with pytest.raises(ValueError, match="mu"):
        contact.distribute([0, 1, 0], -0.1, 0.1, -0.5)
    with pytest.raises(ValueError, match="wrench"):
        contact.distribute([0, math.nan, 0], -0.1, 0.1, 0.5)
    with pytest.raises(ValueError, match="s_heel"):
        contact.distribute([0, 1, 0], 0.1, -0.1, 0.5)
    sol = contact.distribute([0.0, -10.0, 0.0], -0.1, 0.1, 0.5)
    assert not sol.feasible and sol.reasons == ("lift-off",) and sol.mu_needed == math.inf


def test_contact_cli_writes_csv_and_plot_and_keeps_files(tmp_path, capsys):
    import csv as csv_mod

    from pasibot_pin.__main__ import main

    out_csv, out_png = tmp_path / "c.csv", tmp_path / "c.png"
    args = ["contact", "--scenario", "quasi-static", "--samples", "20", "--csv", str(out_csv), "--plot", str(out_png)]
    assert main(args) == 0
    text = capsys.readouterr().out
    assert "samples feasible" in text and "first failure" in text
    rows = list(csv_mod.DictReader(out_csv.open()))
    assert len(rows) == 20 and {"t_s", "theta_rad", "heel_Fz_N", "toe_Fz_N", "My_Nm", "s_cop_m"} <= set(rows[0])
    assert {"mu_needed", "feasible"} <= set(rows[0])  # dimensionless: no unit
    # where feasible, heel + toe carry the demanded Fz
    for row in rows:
        if float(row["feasible"]):
            assert float(row["heel_Fz_N"]) + float(row["toe_Fz_N"]) == pytest.approx(float(row["Fz_N"]), rel=1e-9)
    assert out_png.stat().st_size > 10_000
    assert main(args) == 2 and "--force" in capsys.readouterr().err
    assert main(["contact", "--mu", "-1", "--samples", "5"]) == 2
    assert "--mu must be in [0, 10]" in capsys.readouterr().err


def test_energy_cli_table(tmp_path, capsys):
    from pasibot_pin.__main__ import main

    out_csv = tmp_path / "e.csv"
    assert main(["energy", "--omegas", "5", "--nodes", "16", "--flywheel", "20", "--csv", str(out_csv)]) == 0
    text = capsys.readouterr().out
    assert "| spring | 5 |" in text and "| parallel | 5 |" in text and "speed fluctuation" in text
    assert out_csv.read_text().count("\n") == 3
    header = out_csv.read_text().splitlines()[0].split(",")
    assert {"omega_rad_s", "mass_kg", "W_crank_pos_J", "single_peak_Nm", "cot_motors"} <= set(header)
    assert main(["energy", "--variants", "wheel"]) == 2 and "wheel" in capsys.readouterr().err


def test_parallel_quasi_static_contact_uses_its_longer_sole():
    """Parallel variant: sole 2.6 L behind, 1.5 L ahead of joint 13 (reference.md §4); feasible iff the COM is on it."""
    torques, res = contact.scenario_contact("quasi-static", mu=0.6, samples=24, variant="parallel")
    from pasibot_pin.studies.energy import variant_robot

    robot = variant_robot("parallel", 16.0, 0.0)
    L = 0.05
    assert np.allclose(res.s_heel, -2.6 * L, atol=1e-12) and np.allclose(res.s_toe, 1.5 * L, atol=1e-12)
    for k in range(len(res)):
        mass, com_x = _mass_and_com_x(robot, torques.q[k])
        ankle_x, _, _ = _ankle_and_ends(robot, torques.q[k])
        assert bool(res.feasible[k]) == (-2.6 * L <= com_x - ankle_x <= 1.5 * L)
        assert res.s_cop[k] == pytest.approx(com_x - ankle_x, abs=1e-9)
        if res.feasible[k]:
            assert res.heel_force[k, 1] + res.toe_force[k, 1] == pytest.approx(mass * G, rel=1e-9)
    assert res.feasible.any() and not res.feasible.all()
    with pytest.raises(ValueError, match="variant"):
        contact.scenario_contact("run1", variant="wheel")


def test_contact_command_and_report_count_the_same_samples(capsys):
    """One definition of the stance grid: the command's default is the report's (13/60 for run 1)."""
    from pasibot_pin.__main__ import main
    from pasibot_pin.studies.contact import CONTACT_SAMPLES, scenario_contact
    from pasibot_pin.studies.contact_energy_study import ContactEnergySettings

    assert ContactEnergySettings().contact_samples == CONTACT_SAMPLES
    _, res = scenario_contact("run1")
    n_ok = int(np.sum(res.feasible))
    assert main(["contact", "--scenario", "run1"]) == 0
    line = [s for s in capsys.readouterr().out.splitlines() if "samples feasible" in s][0]
    assert line.endswith(f" {n_ok}/{CONTACT_SAMPLES} samples feasible") and len(res) == CONTACT_SAMPLES
