"""Constrained inverse dynamics: virtual power, quasi-static moment, seed K_e, swaps, errors."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from closed_form import leg

from pasibot_pin.dynamics import inverse as dynamics
from pasibot_pin.model import scenarios
from pasibot_pin.model.scenario_robots import scenario_robot
from pasibot_pin.studies.methods import spring_fit as spring

L = 0.05
G = 9.81


# --------------------------------------------------------------------------- virtual power
@pytest.mark.parametrize("swing_foot", ["level", "square"])
def test_virtual_power_equals_rate_of_energy(swing_foot):
    """Sum of u * joint rate = d/dt (kinetic + potential energy), energies from Pinocchio."""
    scenario = scenarios.SCENARIOS["run4"]
    choices = scenarios.PRESETS["default"].with_(swing_foot=swing_foot)
    robot = scenario_robot(scenario, choices)
    omega, delta = scenario.omega, 1e-4
    for theta in (1.8, 2.7, 3.6, 4.5):
        res = dynamics.inverse_dynamics(robot, [theta - delta, theta, theta + delta], omega, swing_foot=swing_foot)
        model, data = robot.model, robot.data
        energy = [
            pin.computeKineticEnergy(model, data, res.q[k], res.v[k])
            + pin.computePotentialEnergy(model, data, res.q[k])
            for k in (0, 2)
        ]
        d_energy = (energy[1] - energy[0]) / (2 * delta / omega)
        v = res.v[1]
        ankle_st, ankle_sw = robot.idx_v("right_j13_ankle"), robot.idx_v("left_j13_ankle")
        # T_e is the generalised force of beta = pi/2 - q_ankle: beta_dot = -q_ankle_dot
        power = res.Ta[1] * omega + res.Ta_swing[1] * omega - res.Te[1] * v[ankle_st] - res.Te_swing[1] * v[ankle_sw]
        assert abs(power) > 1.0  # a real test: the power is not trivially zero at 5 rad/s
        assert power == pytest.approx(d_energy, rel=1e-6, abs=1e-6)


@pytest.mark.parametrize("variant", ["rigid", "parallel", "spring"])
@pytest.mark.parametrize("motors", ["two", "one"])
def test_one_inverse_dynamics_for_every_variant_and_motor_layout(variant, motors):
    """Virtual power for every variant and both motor layouts: the actuators' power is dE/dt.

    One motor: its torque times omega (plus the ankles) is the whole input, and it equals the
    two motors' sum T_a + T_a' (both cranks turn at omega); the transmission carries T_a'.
    """
    scenario = scenarios.SCENARIOS["run4"]
    robot = scenario_robot(scenario, scenarios.PRESETS["default"], variant)
    omega, delta, theta = scenario.omega, 1e-4, 2.4
    thetas = [theta - delta, theta, theta + delta]
    res = dynamics.inverse_dynamics(robot, thetas, omega, stance="right", motors=motors)
    model, data = robot.model, robot.data
    energy = [
        pin.computeKineticEnergy(model, data, res.q[k], res.v[k]) + pin.computePotentialEnergy(model, data, res.q[k])
        for k in (0, 2)
    ]
    d_energy = (energy[1] - energy[0]) / (2 * delta / omega)
    v = res.v[1]
    power = (res.Ta[1] + res.Ta_swing[1]) * omega
    for side, te in (("right", res.Te[1]), ("left", res.Te_swing[1])):
        if robot.spec.free_ankle:
            power -= te * v[robot.idx_v(f"{side}_j13_ankle")]
        else:
            assert te == 0.0
    assert abs(power) > 1.0
    assert power == pytest.approx(d_energy, rel=1e-6, abs=1e-6)
    if motors == "one":
        two = dynamics.inverse_dynamics(robot, thetas, omega, stance="right")
        np.testing.assert_allclose(res.Ta, two.Ta + two.Ta_swing, rtol=1e-9)
        np.testing.assert_allclose(res.transmission, two.Ta_swing, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(res.Te, two.Te, rtol=1e-9, atol=1e-9)
    if variant == "rigid":
        np.testing.assert_allclose(res.beta, math.pi / 2, atol=1e-9)  # the foot is square to the shank


# --------------------------------------------------------------------------- quasi-static
def _gravity_moment(theta: float, body_mass: float, body_dx: float) -> float:
    """g * sum m_i (x_i - x_ankle) of everything above the stance ankle, from closed-form points."""
    thigh = {1: 1.0, 2: 5.0, 3: 2.5, 4: 9.0, 6: 6.0}
    shank = {5: 18.0, 7: 6.0}
    masses = {i: 6.5 * r / 23.5 for i, r in thigh.items()} | {i: 3.25 * r / 24.0 for i, r in shank.items()}
    ends = {1: (0, 1), 2: (1, 4), 3: (3, 2), 4: (4, 6), 5: (6, 13), 6: (8, 5), 7: (8, 7)}
    st, sw = leg(theta), leg(theta + math.pi)
    x0 = st[13].real
    moment = body_mass * ((st[8].real + body_dx / L) - x0)
    for p in (st, sw):
        moment += sum(masses[i] * ((p[a].real + p[b].real) / 2 - x0) for i, (a, b) in ends.items())
    moment += 1.3 * (sw[13].real + 0.5 - x0)  # swing foot level, COM 0.5 L ahead of its ankle
    return G * moment * L


def test_quasi_static_te_is_the_gravity_moment_about_the_stance_ankle():
    scenario = scenarios.SCENARIOS["run2"]  # body 16 kg, COM 0.30 m ahead of joint 8
    thetas = np.linspace(1.6, 4.7, 7)
    res = dynamics.run_scenario(scenario, scenarios.PRESETS["default"], thetas=thetas, omega=0.0)
    expected = [_gravity_moment(th, 16.0, 0.30) for th in thetas]
    np.testing.assert_allclose(res.Te, expected, rtol=1e-9, atol=1e-9)
    assert res.accelerations == "none"
    np.testing.assert_array_equal(res.v, 0.0)


# --------------------------------------------------------------------------- the seed's numbers
SEED_STORED = {"run1": 331.05, "run2": 331.05, "run3": 453.21, "run4": 424.22}
SEED_CLEAN = {"run1": 332.05, "run2": 332.05, "run3": 454.20, "run4": 395.74}


@pytest.mark.parametrize(("preset", "table"), [("seed", SEED_STORED), ("seed-clean", SEED_CLEAN)])
def test_seed_preset_reproduces_stored_stiffness(preset, table):
    choices = scenarios.get_preset(preset)
    for name, k_e in table.items():
        res = dynamics.run_scenario(scenarios.get_scenario(name), choices)
        fit = spring.fit_result(res, choices.fit_thetas, warn=False)
        assert fit.samples == 23
        assert fit.K_e == pytest.approx(k_e, rel=1e-3), name


def test_seed_window_beta_range():
    """The seed's 23 samples span beta 76.8 to 59.4 deg (docs/reference.md §5)."""
    res = dynamics.run_scenario(scenarios.SCENARIOS["run1"], scenarios.PRESETS["seed"])
    assert math.degrees(res.beta[0]) == pytest.approx(76.8, abs=0.05)
    assert math.degrees(res.beta[-1]) == pytest.approx(59.4, abs=0.05)


def test_run4_fit_is_flagged_nonlinear():
    res = dynamics.run_scenario(scenarios.SCENARIOS["run4"], scenarios.PRESETS["seed-clean"])
    with pytest.warns(spring.LowFitQualityWarning):
        fit = spring.fit_result(res, scenarios.SEED_FIT_THETAS)
    assert fit.r2 < 0.7 and fit.warning


# --------------------------------------------------------------------------- stance swaps, rows
def test_full_cycle_swaps_stance_and_repeats_each_step():
    """Over two turns the legs swap every half turn; every step gives the same torques."""
    robot = scenario_robot(scenarios.SCENARIOS["run1"], scenarios.PRESETS["default"])
    thetas = math.pi / 2 + np.arange(0, 32) * (math.pi / 8)  # 4 steps, 8 samples each
    res = dynamics.inverse_dynamics(robot, thetas, 5.0)
    assert res.stance[:8] == ["right"] * 8 and res.stance[8:16] == ["left"] * 8
    np.testing.assert_allclose(res.theta[8:16], res.theta[:8], atol=1e-12)
    for name in ("Ta", "Te", "Ta_swing", "Te_swing", "beta"):
        arr = getattr(res, name)
        for step in (1, 2, 3):
            np.testing.assert_allclose(arr[8 * step : 8 * step + 8], arr[:8], rtol=1e-9, atol=1e-9)
    # the robot walks: each new stance ankle is one stroke (8 L) ahead, on the ground
    pin.framesForwardKinematics(robot.model, robot.data, res.q[8])
    ankle = robot.data.oMf[robot.frame_id("left_foot")].translation
    assert ankle[0] == pytest.approx(8 * L, abs=2e-4) and abs(ankle[2]) < 1e-3


def test_uniform_rods_change_the_dynamic_torques_only():
    scenario = scenarios.SCENARIOS["run4"]
    point = dynamics.run_scenario(scenario, scenarios.PRESETS["default"], thetas=[2.0, 3.0])
    rods = dynamics.run_scenario(scenario, scenarios.PRESETS["default"].with_(inertia="uniform"), thetas=[2.0, 3.0])
    assert np.max(np.abs(rods.Ta - point.Ta)) > 1e-3
    static_p = dynamics.run_scenario(scenario, scenarios.PRESETS["default"], thetas=[2.0, 3.0], omega=0.0)
    static_r = dynamics.run_scenario(
        scenario, scenarios.PRESETS["default"].with_(inertia="uniform"), thetas=[2.0, 3.0], omega=0.0
    )
    np.testing.assert_allclose(static_r.Te, static_p.Te, rtol=1e-10)


# --------------------------------------------------------------------------- bad input
def test_bad_input_is_named():
    robot = scenario_robot(scenarios.SCENARIOS["run1"], scenarios.PRESETS["default"])
    with pytest.raises(ValueError, match="omega"):
        dynamics.inverse_dynamics(robot, [2.0, 2.1], -1.0)
    with pytest.raises(ValueError, match="omega"):
        dynamics.run_scenario(scenarios.SCENARIOS["run1"], scenarios.PRESETS["default"], omega=float("nan"))
    with pytest.raises(ValueError, match="fit_thetas"):
        dynamics.check_fit_window([0.5, 1.0])
    with pytest.raises(ValueError, match="fit_thetas"):
        dynamics.run_scenario(scenarios.SCENARIOS["run1"], scenarios.PRESETS["seed"].with_(fit_thetas=(5.5, 5.6)))
    with pytest.raises(ValueError, match="unknown scenario 'run9'"):
        scenarios.get_scenario("run9")
    with pytest.raises(ValueError, match="unknown preset 'matlab'"):
        scenarios.get_preset("matlab")
    with pytest.raises(ValueError, match="accelerations"):
        scenarios.ModelChoices(accelerations="forward")
    with pytest.raises(ValueError, match="swing_foot"):
        dynamics.inverse_dynamics(robot, [2.0], 1.0, swing_foot="tilted")


def test_torques_cli_prints_stiffness_and_writes_csv(tmp_path, capsys):
    import csv

    from pasibot_pin.__main__ import main

    out = tmp_path / "t.csv"
    assert main(["torques", "--scenario", "run3", "--preset", "seed", "--csv", str(out)]) == 0
    text = capsys.readouterr().out
    k_e = float(text.split("K_e = ")[1].split(" N.m/rad")[0])
    assert k_e == pytest.approx(453.21, rel=1e-3)
    with out.open() as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == 23
    for column in ("t_s", "theta_rad", "beta_rad", "Ta_Nm", "Te_Nm", "Ta_swing_Nm", "Te_swing_Nm", "ground_Fx_N"):
        assert column in rows[0]
    assert float(rows[0]["theta_rad"]) == pytest.approx(2.6) and float(rows[1]["t_s"]) == pytest.approx(1.0)
    assert all(name == "stance_right" or name.rsplit("_", 1)[-1] in ("s", "rad", "Nm", "N") for name in rows[0])
    assert main(["torques", "--scenario", "run3", "--csv", str(out)]) == 2  # no overwrite without --force
    assert main(["torques", "--scenario", "run9"]) == 2
    assert "unknown scenario" in capsys.readouterr().err


@pytest.mark.parametrize("scenario", ["run1", "run4"])
def test_one_k_e_whichever_way_it_is_asked(scenario, capsys):
    """The command line's grid over one stance ([pi/2, 3 pi/2], both ends) is one stance: its K_e
    is the library's run_scenario (the README's), and the header says the crank speed used."""
    from pasibot_pin.__main__ import main

    choices = scenarios.PRESETS["default"]
    library = spring.fit_result(dynamics.run_scenario(scenarios.SCENARIOS[scenario], choices), None, warn=False)
    assert main(["torques", "--scenario", scenario]) == 0
    text = capsys.readouterr().out
    assert sum(line.startswith("K_e = ") for line in text.splitlines()) == 1  # printed once
    assert float(text.split("K_e = ")[1].split(" N.m/rad")[0]) == pytest.approx(library.K_e, abs=0.005)
    assert main(["torques", "--scenario", scenario, "--omega", "5"]) == 0
    assert "at omega = 5 rad/s" in capsys.readouterr().out.splitlines()[0]


def test_a_sweep_ending_at_touchdown_keeps_its_stance_but_one_crossing_it_swaps():
    one = dynamics.sweep_stances(np.linspace(math.pi / 2, 3 * math.pi / 2, 5))
    assert one == ["right"] * 5
    two = dynamics.sweep_stances(np.linspace(math.pi / 2, 5 * math.pi / 2, 9))
    assert two == ["right"] * 4 + ["left"] * 5
