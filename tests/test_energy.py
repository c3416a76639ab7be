"""Energy per step: work of the actuators = change of kinetic + potential energy (computed here with
crba and the bodies' heights), spring energy in closed form, step length 8L, parallel mass rule."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from report_checks import assert_reads_like_a_report, links

from pasibot_pin.dynamics.inverse import inverse_dynamics
from pasibot_pin.model.scenario_robots import scenario_robot
from pasibot_pin.model.scenarios import PRESETS, Scenario
from pasibot_pin.studies import energy

G = 9.81


def _mechanical_energy(robot, q, v):
    """1/2 v^T M v (crba) + sum m_i g z_i (each body's COM height)."""
    model, data = robot.model, robot.model.createData()
    mass_matrix = pin.crba(model, data, q)
    mass_matrix = np.triu(mass_matrix) + np.triu(mass_matrix, 1).T
    pin.forwardKinematics(model, data, q)
    potential = sum(
        model.inertias[j].mass * G * data.oMi[j].act(model.inertias[j].lever)[2] for j in range(1, model.njoints)
    )
    return 0.5 * v @ mass_matrix @ v + potential


def _spring_power(robot, res):
    """Sum of generalised force times rate: cranks (theta) and ankles (beta = pi/2 - q_ankle)."""
    power = np.zeros(len(res.t))
    for k, side in enumerate(res.stance):
        swing = "left" if side == "right" else "right"
        v = res.v[k]
        power[k] = (
            res.Ta[k] * v[robot.idx_v(f"{side}_j0_crank")]
            + res.Ta_swing[k] * v[robot.idx_v(f"{swing}_j0_crank")]
            - res.Te[k] * v[robot.idx_v(f"{side}_j13_ankle")]
            - res.Te_swing[k] * v[robot.idx_v(f"{swing}_j13_ankle")]
        )
    return power


@pytest.mark.parametrize("omega", [1.0, 5.0])
def test_spring_work_equals_energy_change_over_part_of_a_step(omega):
    scenario = Scenario("t", omega, 20.0, 20.0, 0.30, None, None, "test")
    robot = scenario_robot(scenario, PRESETS["default"])
    a, b = math.pi / 2, math.pi
    x, w = np.polynomial.legendre.leggauss(40)
    nodes, weights = 0.5 * (a + b) + 0.5 * (b - a) * x, 0.5 * (b - a) * w
    res = inverse_dynamics(robot, np.concatenate(([a], nodes, [b])), omega, stance="right")
    work = float(weights @ _spring_power(robot, res)[1:-1]) / omega
    d_energy = _mechanical_energy(robot, res.q[-1], res.v[-1]) - _mechanical_energy(robot, res.q[0], res.v[0])
    assert abs(d_energy) > 1.0
    assert abs(work - d_energy) <= 1e-6 * abs(d_energy)
    # the module's own integration agrees
    step, _ = energy.spring_step_energy(omega, 20.0, 0.30, theta_end=b, fit=False)
    assert step.net_work == pytest.approx(work, rel=1e-9)
    assert step.delta_energy == pytest.approx(d_energy, rel=1e-9)


def test_full_step_balance_spring_energy_and_cot():
    omega = 5.0
    step, res = energy.spring_step_energy(omega, 20.0, 0.30)
    robot = scenario_robot(Scenario("t", omega, 20.0, 20.0, 0.30, None, None, "t"), PRESETS["default"])
    d_energy = _mechanical_energy(robot, res.q[-1], res.v[-1]) - _mechanical_energy(robot, res.q[0], res.v[0])
    gross = step.crank[1] - step.crank[2] + step.ankle[1] - step.ankle[2]
    assert gross > 1.0
    assert abs(step.net_work - d_energy) <= 1e-6 * gross
    assert step.crank[0] == pytest.approx(step.crank[1] + step.crank[2], abs=1e-9)
    # one motor: positive work never exceeds the two motors' (they can exchange power through the transmission)
    assert step.single[1] <= step.crank[1] + 1e-9 and step.single[0] == pytest.approx(step.crank[0], abs=1e-9)
    # spring energy in closed form: stored - released = V(beta_end) - V(beta_start), V = K/2 (beta - beta0)^2
    k_e, beta0 = step.spring["K_e"], step.spring["beta0"]
    dv = 0.5 * k_e * ((res.beta[-1] - beta0) ** 2 - (res.beta[0] - beta0) ** 2)
    assert step.spring["stored"] - step.spring["released"] == pytest.approx(dv, rel=1e-6, abs=1e-9)
    # the hip advances one stroke, 8 L, per step; CoT = work / (m g d)
    assert step.distance == pytest.approx(8 * 0.05, abs=1e-9)
    mass = sum(robot.model.inertias[j].mass for j in range(1, robot.model.njoints))
    assert step.cot["motors"] == pytest.approx(step.crank[1] / (mass * G * 0.4), rel=1e-12)
    # positive work converges with the node count
    finer, _ = energy.spring_step_energy(omega, 20.0, 0.30, nodes=96, fit=False)
    assert finer.crank[1] == pytest.approx(step.crank[1], rel=2e-3)


def test_parallel_work_equals_energy_change_and_static_ground_wrench():
    robot = energy.variant_robot("parallel", 16.0, 0.0)
    omega = 5.0
    step, res = energy.parallel_step_energy(omega, 16.0, 0.0, theta_end=math.pi)
    d_energy = _mechanical_energy(robot, res.q[-1], res.v[-1]) - _mechanical_energy(robot, res.q[0], res.v[0])
    assert abs(d_energy) > 1.0
    assert abs(step.net_work - d_energy) <= 1e-6 * abs(d_energy)
    # quasi-static: the weld carries the weight, with its moment about the foot frame
    static = inverse_dynamics(robot, [math.pi / 2, math.pi, 4.0], 0.0, stance="right")
    model, data = robot.model, robot.model.createData()
    for k in range(3):
        q = static.q[k]
        pin.framesForwardKinematics(model, data, q)
        masses = np.array([model.inertias[j].mass for j in range(1, model.njoints)])
        xs = np.array([data.oMi[j].act(model.inertias[j].lever)[0] for j in range(1, model.njoints)])
        ankle_x = data.oMf[model.getFrameId("right_foot")].translation[0]
        weight = masses.sum() * G
        expected = [0.0, weight, G * masses @ (xs - ankle_x)]
        assert np.allclose(static.ground[k], expected, atol=1e-9 * weight)


def test_parallel_mass_rule_extension_has_thigh_density():
    spring = energy.variant_robot("spring", 16.0)
    parallel = energy.variant_robot("parallel", 16.0)
    L = 0.05
    density = 0.10 * 65.0 / ((1 + 5 + 2.5 + 9 + 6) * L)  # thigh mass over L1+L2+L3+L4+L6 [kg/m]
    extension = (4.2 + 9 + 2.1 + 18 + 2.1 + 1.0) * L  # L8, L9, L10, L11, foot bar (L10), slider (L)

    def total(r):
        return sum(r.model.inertias[j].mass for j in range(1, r.model.njoints))

    assert total(parallel) - total(spring) == pytest.approx(2 * density * extension, rel=1e-12)


def test_energy_errors():
    with pytest.raises(ValueError, match="omega"):
        energy.spring_step_energy(0.0)
    with pytest.raises(ValueError, match="theta_end"):
        energy.parallel_step_energy(1.0, theta_end=4 * math.pi)
    with pytest.raises(ValueError, match="body_mass"):
        energy.variant_robot("parallel", -1.0)


@pytest.mark.slow
@pytest.mark.integration
def test_analyze_step_contact_energy(analyzed):
    """The ``contact_energy`` step of ``pasibot analyze`` (as the plain install wrote it): its section, tables, CSVs
    and figures."""
    import csv

    text, out = analyzed.section("Beyond the report: contact, one motor, energy"), analyzed.folder
    for scenario in ("quasi-static", "run1", "run2", "run3", "run4"):
        for variant in ("spring", "parallel"):
            assert f"| {scenario} ({variant}) |" in text
            assert (out / "contact_energy" / f"contact_{variant}_{scenario}.png").stat().st_size > 10_000
    assert "first failure" in text and ": slip." in text
    rows = list(csv.DictReader((out / "contact_energy" / "energy.csv").open()))
    assert {r["variant"] for r in rows} == {"spring", "parallel"} and len(rows) == 10
    for r in rows:  # the table's CoT is its positive work over weight x distance
        assert float(r["cot_motors"]) == pytest.approx(
            float(r["W_crank_pos_J"]) / (float(r["mass_kg"]) * G * float(r["distance_m"])), rel=1e-9
        )
    for name in ("single_motor_run4.png", "cost_of_transport.png", "power_spring_5.png", "single_motor_run4.csv"):
        assert (out / "contact_energy" / name).exists()
    assert_reads_like_a_report(out, text, 13, shared=True)  # every figure linked with a caption, units on every column
    own = {f"contact_energy/{p.name}" for p in (out / "contact_energy").glob("*.png")}
    assert len(own) >= 13 and own <= links(text)  # the step's folder holds only figures this section links


def test_the_rigid_variant_advances_over_a_stride_and_its_cost_of_transport_is_positive():
    """The rigid variant's last sample of a prescribed gait is pitched ~30 deg (before the exchange): measured
    start to start, its hip advances every step, and the cost of transport is positive."""
    import pasibot_pin as pp
    from pasibot_pin.kinematics.gait import prescribed_gait, stride_advance

    robot = pp.load("rigid", 2)
    w = prescribed_gait(robot, 5, 30)  # an independent sampling, two strides, start to start
    hip = w.hip_path()
    per_step = (hip[4 * 30, 0] - hip[0, 0]) / 4
    assert stride_advance(robot) == pytest.approx(per_step, rel=1e-9) and per_step > 0
    step, _ = energy.robot_step_energy(robot, 1.0, nodes=12)
    assert step.distance == pytest.approx(per_step, rel=1e-9)
    assert step.cot["motors"] > 0 and step.cot["single"] > 0
    for variant in ("spring", "parallel"):  # a level hip: the linkage's stroke, 8 L
        assert stride_advance(pp.load(variant, 2)) == pytest.approx(8 * 0.05, abs=1e-9)
