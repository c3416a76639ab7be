"""The MJCF export against the Pinocchio model, and MuJoCo against our simulator (welded stance foot).

MuJoCo is an independent engine: its own kinematics, its own constraint solver (soft
constraints) and its own integrator. Geometry and masses must agree to round-off; the welded
run 1 simulations (fitted spring, and no spring: the fall) to 1 deg of hip pitch and 3 % of
crank torque.
"""

from __future__ import annotations

import math

import mujoco  # the [mujoco] extra: make test installs it, and this file never skips
import numpy as np
import pinocchio as pin
import pytest

import pasibot_pin as pp
from pasibot_pin.__main__ import main
from pasibot_pin.dynamics import simulator as simulate
from pasibot_pin.model.design import Design
from pasibot_pin.model.mjcf import MjcfOptions, to_mjcf
from pasibot_pin.studies import spring_study


def _model(robot, options=None, q_weld=None):
    model = mujoco.MjModel.from_xml_string(to_mjcf(robot, options, q_weld))
    return model, mujoco.MjData(model)


def _loop_error(robot, data) -> float:
    return max(float(np.linalg.norm(data.site(lp.frame_a).xpos - data.site(lp.frame_b).xpos)) for lp in robot.loops)


@pytest.mark.parametrize("variant", pp.VARIANTS)
@pytest.mark.parametrize("legs", [1, 2])
def test_every_frame_mass_and_loop_matches_pinocchio(variant, legs):
    robot = pp.load(variant, legs)
    model, data = _model(robot, MjcfOptions(weld_foot="right" if legs == 2 else None))
    assert model.nq == robot.model.nq and model.nv == robot.model.nv
    mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)  # the home keyframe is q0
    mujoco.mj_forward(model, data)
    np.testing.assert_allclose(data.qpos, robot.q0, atol=0)
    pdata = robot.model.createData()
    pin.framesForwardKinematics(robot.model, pdata, robot.q0)
    for k, frame in enumerate(robot.model.frames):
        if frame.type == pin.FrameType.BODY and frame.parentJoint > 0:
            np.testing.assert_allclose(data.site(frame.name).xpos, pdata.oMf[k].translation, atol=1e-12)
            np.testing.assert_allclose(data.site(frame.name).xmat.reshape(3, 3), pdata.oMf[k].rotation, atol=1e-12)
    assert sum(model.body_mass) == pytest.approx(sum(i.mass for i in robot.model.inertias), rel=1e-12)
    assert _loop_error(robot, data) < 1e-12  # the keyframe closes every loop
    assert model.neq == len(robot.loops) + (1 if legs == 2 else 0)
    assert model.nu == len(robot.actuated_joints)


def test_bad_options_are_named():
    with pytest.raises(ValueError, match="'mu'"):
        MjcfOptions(mu=-1.0)
    with pytest.raises(ValueError, match="'actuator'"):
        MjcfOptions(actuator="torque")
    with pytest.raises(ValueError, match="'weld_foot'"):
        MjcfOptions(weld_foot="middle")
    with pytest.raises(ValueError, match="'spring_rest_angle'"):
        MjcfOptions(spring_rest_angle=float("nan"))


def _welded_pair(factor: float, duration: float):
    """(ours, mujoco) traces of run 1 with the fitted spring times ``factor``, the stance foot welded."""
    inputs = spring_study.scenario_inputs("run1")
    spring = inputs.fit.scaled(factor) if factor > 0 else None
    sim = simulate.BipedSimulator(inputs.robot, simulate.SimulationSettings(omega=inputs.omega, spring=spring))
    ours = sim.run(duration=duration)
    q0, v0, stance = sim.initial_state()
    options = MjcfOptions(
        spring_stiffness=spring.stiffness if spring else 0.0,
        spring_rest_angle=spring.rest_angle if spring else math.pi / 2,
        spring_damping=spring.damping if spring else 0.0,
        weld_foot=stance,
        floor=False,
    )
    model, data = _model(inputs.robot, options, q_weld=q0)
    data.qpos[:], data.qvel[:] = q0, v0
    start = np.array([q0[inputs.robot.idx_q(m)] for m in inputs.robot.actuated_joints])
    lag = options.kv * inputs.omega / options.kp  # the servo's steady lag on a ramp
    t, pitch, torque, loop = [], [], [], 0.0
    while data.time < ours.t[-1]:
        data.ctrl[:] = start + inputs.omega * data.time + lag
        mujoco.mj_step(model, data)
        t.append(data.time)
        pitch.append(data.qpos[2])
        torque.append(data.actuator_force[0])
        if len(t) % 50 == 0:
            loop = max(loop, _loop_error(inputs.robot, data))
    return ours, np.array(t), np.array(pitch), np.array(torque), loop


@pytest.mark.parametrize(("factor", "duration"), [(1.0, 1.5), (0.0, 2.0)])
def test_mujoco_reproduces_the_welded_simulation(factor, duration):
    ours, t, pitch, torque, loop = _welded_pair(factor, duration)
    if factor == 0.0:
        assert ours.fell  # no spring: the hip falls, in both engines
    ours_pitch = np.interp(t, ours.t, ours.hip_pitch)
    assert np.degrees(np.max(np.abs(ours_pitch - pitch))) < 1.0
    late = t > 0.1  # after the servo has caught the ramp
    peak_ours, peak_mj = np.max(np.abs(ours.motor_torque[:, 0])), np.max(np.abs(torque[late]))
    assert peak_mj == pytest.approx(peak_ours, rel=0.03)
    assert loop < 1e-4


def test_loops_stay_closed_through_ten_seconds_on_the_floor():
    robot = pp.load("spring", 2)
    model, data = _model(robot, MjcfOptions(spring_stiffness=306.45, spring_rest_angle=1.3073, spring_damping=1.0))
    mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)
    worst = 0.0
    for k in range(100_000):  # 10 s at 0.1 ms
        data.ctrl[:] = robot.q0[[robot.idx_q(m) for m in robot.actuated_joints]] + 0.1 * data.time
        mujoco.mj_step(model, data)
        if k % 200 == 0:
            worst = max(worst, _loop_error(robot, data))
    assert data.time == pytest.approx(10.0, abs=1e-3)
    assert np.all(np.isfinite(data.qpos)) and worst < 1e-4


def test_export_mjcf_command_uses_the_design_and_refuses_to_overwrite(tmp_path, capsys):
    out = tmp_path / "pasibot.xml"
    design = tmp_path / "d.toml"
    Design(variant="spring", spring_stiffness=400.0, spring_rest_angle=1.2, body_mass=20.0).save(design)
    assert main(["export-mjcf", "--out", str(out), "--design", str(design)]) == 0
    assert "K_e = 400.00" in capsys.readouterr().out
    model = mujoco.MjModel.from_xml_path(str(out))
    ankle = model.joint("right_j13_ankle")
    assert model.jnt_stiffness[ankle.id] == 400.0 and model.qpos_spring[ankle.qposadr[0]] == pytest.approx(
        math.pi / 2 - 1.2
    )
    assert model.body("hip_planar_body").mass[0] == pytest.approx(20.0)
    assert main(["export-mjcf", "--out", str(out)]) == 2
    assert "exists" in capsys.readouterr().err
    assert main(["export-mjcf", "--out", str(out), "--force", "--variant", "rigid", "--legs", "1"]) == 0
    assert mujoco.MjModel.from_xml_path(str(out)).nq == 7
