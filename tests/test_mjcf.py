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


def _mujoco_floor_run(robot, spring, omega, mu, q0, duration):
    """MuJoCo on the floor from ``q0`` at rest: loaded points (n, 4) and hip pitch (n,) every ms, rear toe x (n,)."""
    options = MjcfOptions(
        spring.stiffness if spring else 0.0,
        spring.rest_angle if spring else math.pi / 2,
        spring.damping if spring else 0.0,
        mu=mu,
    )
    model, data = _model(robot, options, q_weld=q0)
    data.qpos[:] = q0
    data.qpos[1] += options.sole_radius  # the capsules' bottoms on the floor, where our points are
    start = np.array([q0[robot.idx_q(m)] for m in robot.actuated_joints])
    lag = options.kv * omega / options.kp
    loaded, pitch, toe_x = [], [], []
    soles = [model.geom(f"{side}_sole").id for side in ("right", "left")]
    every = round(1e-3 / options.timestep)
    for k in range(round(duration / options.timestep)):
        data.ctrl[:] = start + omega * data.time + lag
        mujoco.mj_step(model, data)
        if (k + 1) % every:
            continue
        row = np.zeros(4, dtype=bool)
        for i in range(data.ncon):
            c = data.contact[i]
            for s, (side, gid) in enumerate(zip(("right", "left"), soles)):
                if gid in (c.geom1, c.geom2):
                    heel, toe = data.site(f"{side}_heel").xpos, data.site(f"{side}_toe").xpos
                    along = np.dot(c.pos - heel, toe - heel) / np.dot(toe - heel, toe - heel)
                    row[2 * s + (1 if along >= 0.5 else 0)] = True
        loaded.append(row)
        pitch.append(data.qpos[2])
        toe_x.append(data.site("left_toe").xpos[0])
    return np.array(loaded), np.array(pitch), np.array(toe_x)


def test_mujoco_on_the_floor_run1_spring_cases():
    """Run 1's four spring cases on the floor, ours against MuJoCo from the same consistent start.

    What agrees: which points carry load (fitted, half, twice: the front heel and the rear toe;
    no spring: all four) in >= 95 % (ours) and 99 % (MuJoCo) of the samples, the outcome (neither falls, no landing) and
    the hip pitch (within 0.3 deg). What differs: our modes call the rear foot ``sliding`` most of
    the time (its toe slides ~1.3 mm in 0.5 s with the fitted spring) where MuJoCo's rear toe
    moves < 0.1 mm (its soft contact takes the cranks' motion up as elastic creep, or our
    Anitescu cone lets the point slide: not resolved yet), so the mode strings, which contain
    ``sliding``, are compared through the loaded points only.
    """
    from pasibot_pin.dynamics.floor import LOAD_TOL, FloorSettings, FloorSimulator

    inputs = spring_study.scenario_inputs("run1")
    robot, duration = inputs.robot, 0.5
    for label, factor in spring_study.SPRING_CASES:
        spring = inputs.fit.scaled(factor) if factor > 0 else None
        sim = FloorSimulator(robot, FloorSettings(omega=inputs.omega, spring=spring))
        ours = sim.run(duration)
        assert ours.start is not None and not ours.failed and not ours.landings, label
        loaded, pitch, toe_x = _mujoco_floor_run(robot, spring, inputs.omega, sim.settings.mu, ours.start.q, duration)
        n = min(len(loaded), len(ours.t))
        ours_loaded = ours.normal[:n] > LOAD_TOL
        expected = [True, True, True, True] if spring is None else [True, False, False, True]
        assert np.mean(np.all(ours_loaded == expected, axis=1)) >= 0.95, label  # the cranks' start: ~15 ms
        assert np.mean(np.all(loaded[:n] == expected, axis=1)) >= 0.99, label
        assert np.degrees(np.max(np.abs(pitch))) < 60 and np.degrees(np.max(np.abs(ours.hip_pitch))) < 60
        assert np.degrees(np.max(np.abs(np.abs(pitch[:n]) - np.abs(ours.hip_pitch[:n])))) < 0.3, label
        # not asserted (they differ): our rear toe slides ~1.3 mm in 0.5 s (fitted), MuJoCo's < 0.1 mm
