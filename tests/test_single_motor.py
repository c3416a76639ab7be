"""One motor for both cranks: the coupled split equals T_a + T_a' sample by sample; flywheel formulas
against closed forms."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from pasibot_pin.dynamics.inverse import inverse_dynamics, scenario_robot
from pasibot_pin.model.scenarios import get_preset, get_scenario
from pasibot_pin.studies import single_motor as sm


@pytest.fixture(scope="module", params=["quasi-static", "run4"])
def full_turn(request):
    """A full crank turn (two steps, the stance swaps at 3 pi/2) of a scenario: (robot, torques)."""
    scenario, choices = get_scenario(request.param), get_preset("default")
    robot = scenario_robot(scenario, choices)
    thetas = np.linspace(math.pi / 2, 5 * math.pi / 2, 49)[:-1]
    return robot, inverse_dynamics(robot, thetas, scenario.omega)


def test_single_motor_torque_is_sum_of_both_crank_torques(full_turn):
    robot, torques = full_turn
    res = sm.coupled_split(robot, torques)
    both = torques.Ta + torques.Ta_swing
    scale = max(np.max(np.abs(both)), 1.0)
    assert np.max(np.abs(res.motor - both)) <= 1e-9 * scale
    assert set(torques.stance) == {"right", "left"}
    # the transmission drives the left crank with the left crank's two-motor torque
    left = np.where(np.array(torques.stance) == "right", torques.Ta_swing, torques.Ta)
    assert np.max(np.abs(res.transmission - left)) <= 1e-9 * scale
    # the ankles carry the same torques as with two motors
    assert np.allclose(res.ankle[:, 0], torques.Te, atol=1e-9 * max(np.max(np.abs(torques.Te)), 1.0))
    assert np.allclose(res.ankle[:, 1], torques.Te_swing, atol=1e-9 * max(np.max(np.abs(torques.Te)), 1.0))
    assert res.coupling_residual < 1e-9
    assert res.peak() == pytest.approx(np.max(np.abs(both)))


def test_cranks_not_pi_apart_is_refused(full_turn):
    robot, torques = full_turn
    q = torques.q.copy()
    q[:, robot.idx_q("left_j0_crank")] += 0.1
    with pytest.raises(ValueError, match="pi apart"):
        sm.coupled_split(robot, replace(torques, q=q))


def test_rms_closed_form():
    t = np.linspace(0.0, 2 * math.pi, 20001)
    assert sm.rms(t, 3.0 * np.sin(t)) == pytest.approx(3.0 / math.sqrt(2), rel=1e-6)
    assert sm.rms(t, np.full_like(t, -2.0)) == pytest.approx(2.0)


def test_flywheel_against_sinusoidal_load():
    """u = c + A sin(2 theta) over a half turn: mean c, energy swing A (E = A (1 - cos 2 theta) / 2)."""
    theta = np.linspace(0.0, math.pi, 4001)
    c, amp, omega = 1.5, 4.0, 3.0
    torque = c + amp * np.sin(2 * theta)
    for inertia in (2.0, 20.0):
        fw = sm.flywheel(theta, torque, omega, inertia)
        assert fw.mean_torque == pytest.approx(c, rel=1e-6)
        assert fw.energy_swing == pytest.approx(amp, rel=1e-5)
        assert fw.peak_without == pytest.approx(c + amp, rel=1e-6)
        linear = amp / (inertia * omega**2)
        assert fw.speed_fluctuation_linear == pytest.approx(linear, rel=1e-5)
        # exact: w(theta)^2 = w0^2 - 2 E / J, so w_max - w_min = w0 - sqrt(w0^2 - 2 A / J) with w0 ~ omega (1 + delta/2)
        assert fw.speed_fluctuation == pytest.approx(linear, rel=2 * linear + 1e-4)
    j = sm.inertia_for(theta, torque, omega, 0.02)
    assert amp / (j * omega**2) == pytest.approx(0.02, rel=1e-5)
    with pytest.raises(ValueError, match="inertia"):
        sm.flywheel(theta, torque, omega, 0.01)
    with pytest.raises(ValueError, match="omega"):
        sm.flywheel(theta, torque, 0.0, 1.0)


def test_the_motor_operating_point_of_the_study():
    """Peak power = peak torque x omega (speed held); the mean torque is every flywheel's constant torque."""
    from pasibot_pin.studies.contact_energy_study import ContactEnergySettings, single_motor_study

    motor = single_motor_study(ContactEnergySettings(motor_samples=96, flywheels=(5.0, 20.0)))
    assert motor.peak_power == pytest.approx(motor.single.peak() * motor.omega, rel=1e-12)
    for case in motor.flywheels:
        assert case.flywheel.mean_torque == pytest.approx(motor.mean_torque, rel=1e-9)
    assert motor.mean_power == pytest.approx(motor.mean_torque * motor.omega, rel=1e-12)
    # the mean over a step is the motor's net work over that step's crank angle (virtual power)
    assert 0.0 < motor.mean_torque < motor.single.peak()
