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
from pasibot_pin.dynamics.floor.run import LOAD_TOL
from pasibot_pin.model.description import sides
from pasibot_pin.model.design import Design
from pasibot_pin.model.mjcf import MjcfOptions, to_mjcf
from pasibot_pin.studies import spring_study

pytestmark = [pytest.mark.mujoco]


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
    cranks = robot.q0[[robot.idx_q(m) for m in robot.actuated_joints]]  # once, not at each of the 100 000 steps
    for k in range(100_000):  # 10 s at 0.1 ms
        data.ctrl[:] = cranks + 0.1 * data.time
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


CRANK_RAMP = 0.5
"""Both engines start the cranks smoothly: their rate rises from 0 to omega over this long [s]
(:func:`crank_advance`), slower than the double support's own sway (~0.3 s in ours), so neither
engine gets an impulsive start that rings the stiff four-bar of the two feet."""
MJ_SETTLE_MAX = 2.0
"""MuJoCo's own settling, cranks held, stops at rest (1e-6) or after this long [s]."""
MJ_FLOOR = MjcfOptions(
    actuator="constraint",  # rigid rheonomic cranks, as ours: a servo's compliance relieves the squeeze
    noslip_iterations=30,  # hard friction: a stuck point stays put
    planar_noslip=True,  # ... and reaches Coulomb's cone mu F_n along x (not mu / 2)
    contact_solref=(1e-3, 1.0),  # a floor 20 x stiffer than MuJoCo's default (0.02 s)
    contact_solimp=(0.9999, 0.9999, 0.001),
)
"""MuJoCo's floor for the comparison with our rigid contacts: crank drives as stiff equality
constraints, hard Coulomb friction, a stiff floor, MuJoCo's 0.1 ms step (the fitted case's slide
converges towards ours, 0.896 s: 0.892, 0.886, 0.886 s for floor time constants 5, 2, 1 ms;
0.849, 0.869, 0.886, 0.892 s for steps 0.5, 0.25, 0.1, 0.05 ms; docs/floor.md)."""
MJ_SINK = 1e-6
"""MuJoCo starts this far [m] into its floor, so its contacts carry the weight from the first step.
Started exactly on it, the first step falls freely and the landing slides the toe by ~0.1 mm,
which, in the near-singular double support, changes the squeeze by tens of N: a 1e-13 m change
of the start height then moves the fitted case's slide between 0.67 s, 0.75 s and never."""


def _mujoco_floor_run(robot, spring, omega, mu, q0, duration):
    """MuJoCo (:data:`MJ_FLOOR`) on the floor from ``q0``, sampled every ms.

    MuJoCo first settles into its floor with the cranks held (velocities damped as our settling
    does, until nothing moves faster than 1e-6), so it too starts at rest; then its cranks follow
    theta0 + omega advance (:func:`crank_advance`, the same ramp as ours).

    Returns loaded points (n, 4), each foot's mode by our own rule (:meth:`FloorSimulator.modes`,
    a loaded point slides when its material point at the contact moves faster than SLIP_TOL),
    the hip pitch (n,), the friction use |F_t| / F_n (n, 4) and the x of the heel and toe sites
    (n, 4) [m], columns right heel, right toe, left heel, left toe.
    """
    from dataclasses import replace

    from pasibot_pin.dynamics.floor.engine import SETTLE_DAMPING, FloorSimulator
    from pasibot_pin.dynamics.floor.settings import FloorSettings, crank_advance
    from pasibot_pin.model.coordinates import SIDES

    options = replace(MJ_FLOOR, spring_stiffness=spring.stiffness, spring_rest_angle=spring.rest_angle)
    options = replace(options, spring_damping=spring.damping, mu=mu)
    model, data = _model(robot, options, q_weld=q0)
    data.qpos[:] = q0
    data.qpos[1] += options.sole_radius - MJ_SINK  # the capsules' bottoms just into the floor, where our points are
    cranks = np.array([q0[robot.idx_q(m)] for m in robot.actuated_joints])
    drives = [model.equality(f"{m}_drive").id for m in robot.actuated_joints]
    model.eq_data[drives, 0] = cranks
    for k in range(round(MJ_SETTLE_MAX / options.timestep)):
        mujoco.mj_step(model, data)
        data.qvel[:] *= 1.0 - SETTLE_DAMPING * options.timestep
        if k * options.timestep > 0.01 and np.max(np.abs(data.qvel)) < 1e-6:
            break
    t0 = data.time
    rule = FloorSimulator(robot, FloorSettings(omega=omega, spring=spring, mu=mu))
    soles = [model.geom(f"{side}_sole").id for side in SIDES]
    points = [f"{side}_{point}" for side in SIDES for point in ("heel", "toe")]
    loaded, modes, pitch, use, along = [], [], [], [], []
    force, jacp = np.zeros(6), np.zeros((3, model.nv))
    every = round(1e-3 / options.timestep)
    for k in range(round(duration / options.timestep)):
        model.eq_data[drives, 0] = cranks + omega * crank_advance(data.time - t0, CRANK_RAMP)[0]
        mujoco.mj_step(model, data)
        if (k + 1) % every:
            continue
        normal, slip, tangential = np.zeros(4), np.zeros(4), np.zeros(4)
        for i in range(data.ncon):
            c = data.contact[i]
            for s, (side, gid) in enumerate(zip(SIDES, soles)):
                if gid in (c.geom1, c.geom2):
                    heel, toe = data.site(f"{side}_heel").xpos, data.site(f"{side}_toe").xpos
                    j = 2 * s + int(np.dot(c.pos - heel, toe - heel) >= 0.5 * np.dot(toe - heel, toe - heel))
                    mujoco.mj_contactForce(model, data, i, force)
                    mujoco.mj_jac(model, data, jacp, None, c.pos, model.geom_bodyid[gid])
                    normal[j] += force[0]
                    tangential[j] += (c.frame.reshape(3, 3).T @ force[:3])[0]  # world x
                    slip[j] = max(slip[j], abs(float(jacp[0] @ data.qvel)))  # the sole's point at the contact
        loaded.append(normal > LOAD_TOL)
        mode = rule.modes(normal, slip)
        modes.append((mode["right"], mode["left"]))
        pitch.append(data.qpos[2])
        use.append(np.abs(tangential) / np.where(normal > LOAD_TOL, normal, np.inf))
        along.append([data.site(p).xpos[0] for p in points])
    return np.array(loaded), modes, np.array(pitch), np.array(use), np.array(along)


DWELL = 0.01
"""Mode blips shorter than this [s] are merged into the mode before them, in both engines
(:func:`mode_runs`): ten time constants of MuJoCo's floor (:data:`MJ_FLOOR`). (None occurs
today: the raw sequences agree too.)"""


def test_mujoco_on_the_floor_run1_spring_cases():
    """Run 1's four spring cases on the floor for 1 s, ours against MuJoCo, both from rest.

    Both start at rest (ours: the consistent start; MuJoCo: settled from it into its floor) and
    start the cranks with the same smooth ramp (:data:`CRANK_RAMP`); MuJoCo's cranks are rigid
    and its friction hard Coulomb (:data:`MJ_FLOOR`). Each foot's mode sequence, run-length
    encoded after the same dwell filter (:data:`DWELL`), is the same in both engines for all
    four cases, over the whole second:

    - fitted and twice K_e: the front foot on its heel throughout; the rear foot on its toe, then
      sliding to the end (the rising crank turns the squeeze between the feet until the rear
      toe's friction reaches its cone): the slide starts within 0.05 s (fitted: 0.896 s ours,
      0.886 s MuJoCo; twice: 0.721 and 0.700 s), both at friction use mu;
    - half K_e: the front heel and the rear toe throughout;
    - no spring: both feet flat, then the rear foot sliding. Both soles flat under turning cranks
      is over-constrained (six contact rows, five free coordinates): the rear foot slides off the
      mismatch from the start, by the same amount in both (0.51 mm ours, 0.49 mm MuJoCo by 1 s,
      asserted within 10 %); it passes the slip threshold (0.1 mm/s) later in MuJoCo (0.45 s
      against 0.31 s), whose front foot gives ~10 um first (ours < 1 um).

    Also agreed: which points carry load (>= 95 % of the samples), the outcome (neither falls
    nor lands) and the hip pitch (within 0.3 deg).
    """
    from pasibot_pin.dynamics.floor.engine import FloorSimulator
    from pasibot_pin.dynamics.floor.run import mode_runs
    from pasibot_pin.dynamics.floor.settings import FloorSettings
    from pasibot_pin.model.coordinates import SIDES

    inputs = spring_study.scenario_inputs("run1")
    robot, duration = inputs.robot, 1.0
    expected_rear = {"no spring": ["flat", "sliding"], "half K_e": ["toe"]}
    for label, factor in spring_study.SPRING_CASES:
        spring = inputs.fit.scaled(factor)  # the study's case: K_e scaled, the damper kept
        sim = FloorSimulator(robot, FloorSettings(omega=inputs.omega, spring=spring, crank_ramp=CRANK_RAMP))
        ours = sim.run(duration)
        assert ours.start is not None and not ours.failed and not ours.landings, label
        mu = sim.settings.mu
        loaded, modes, pitch, use, along = _mujoco_floor_run(robot, spring, inputs.omega, mu, ours.start.q, duration)
        n = len(ours.t)
        assert len(loaded) == n == round(duration / sim.settings.dt), label
        expected = [True, True, True, True] if factor == 0 else [True, False, False, True]
        assert np.mean(np.all((ours.normal > LOAD_TOL) == expected, axis=1)) >= 0.95, label
        assert np.mean(np.all(loaded == expected, axis=1)) >= 0.95, label
        assert np.degrees(np.max(np.abs(pitch))) < 60 and np.degrees(np.max(np.abs(ours.hip_pitch))) < 60
        assert np.degrees(np.max(np.abs(pitch - ours.hip_pitch))) < 0.3, label
        runs = {}
        for i, side in enumerate(SIDES):
            ours_runs = mode_runs(ours.modes[side], sim.settings.dt, DWELL)
            mj_runs = mode_runs([m[i] for m in modes], sim.settings.dt, DWELL)
            assert [m for m, _ in ours_runs] == [m for m, _ in mj_runs], (label, side, ours_runs, mj_runs)
            runs[side] = ours_runs, mj_runs
        assert [m for m, _ in runs["right"][0]] == ["flat" if factor == 0 else "heel"], label
        assert [m for m, _ in runs["left"][0]] == expected_rear.get(label, ["toe", "sliding"]), label
        if len(runs["left"][0]) < 2:
            continue
        slide_ours, slide_mj = runs["left"][0][1][1], runs["left"][1][1][1]
        if factor == 0:  # the rear foot slides off the same mismatch; the front one stays (ours) or gives ~10 um
            ours_along = np.array([sim.contact_rows(q)[1] for q in ours.q])
            moved_ours, moved_mj = ours_along[-1] - ours.start.along, along[-1] - along[0]
            assert moved_mj[2] == pytest.approx(moved_ours[2], rel=0.1) and moved_ours[2] > 4e-4, label
            assert np.max(np.abs(moved_ours[:2])) < 1e-6 and np.max(np.abs(moved_mj[:2])) < 2e-5, label
            assert 0.0 < slide_mj - slide_ours < 0.2, label
            continue
        assert abs(slide_ours - slide_mj) < 0.05, (label, slide_ours, slide_mj)
        assert np.max(use[:, 3]) == pytest.approx(mu, rel=0.01), label  # the rear toe slides at the cone
        assert np.max(ours.friction_use()[:, 3]) == pytest.approx(mu, rel=1e-6), label


def test_planar_noslip_needs_noslip_and_doubles_the_written_friction():
    robot = pp.load("spring", 2)
    with pytest.raises(ValueError, match="'planar_noslip'"):
        MjcfOptions(planar_noslip=True)
    with pytest.raises(ValueError, match="'contact_solref'"):
        MjcfOptions(contact_solref=(1e-4, 1.0))
    model, _ = _model(robot, MjcfOptions(mu=0.7, noslip_iterations=5, planar_noslip=True, actuator="constraint"))
    assert model.geom_friction[model.geom("right_sole").id][0] == pytest.approx(1.4)
    assert model.nu == 0 and model.neq == len(robot.loops) + len(robot.actuated_joints)


EXPORTS = [
    MjcfOptions(),
    MjcfOptions(actuator="velocity", kv=7.0, floor=False, timestep=2e-4),
    MjcfOptions(actuator="constraint", noslip_iterations=5, planar_noslip=True, mu=0.6),
    MjcfOptions(actuator="none", boundinertia=1e-6, spring_stiffness=300.0, spring_rest_angle=1.3, spring_damping=0.5),
    MjcfOptions(weld_foot="left", spring_stiffness=3000.0, solref=(2e-3, 0.9), contact_solimp=(0.95, 0.99, 0.002)),
]


@pytest.mark.parametrize("variant", pp.VARIANTS)
@pytest.mark.parametrize("legs", [1, 2])
@pytest.mark.parametrize("k", range(len(EXPORTS)))
def test_every_export_option_reaches_mujocos_model(variant, legs, k):
    """Each option, read back from MuJoCo's compiled model; the geometry against Pinocchio's frames."""
    options = EXPORTS[k]
    robot = pp.load(variant, legs)
    if options.weld_foot and legs == 1:
        with pytest.raises(ValueError, match="no foot to weld"):
            to_mjcf(robot, options)
        return
    q = robot.q0.copy()  # a weld, keyframe and crank drives off q0 (the loops left open): all follow q_weld
    q[robot.idx_q(robot.actuated_joints[0])] += 0.1
    if legs == 2:
        q[0] += 0.05
    model, data = _model(robot, options, q_weld=q)
    assert model.opt.timestep == options.timestep and model.opt.noslip_iterations == options.noslip_iterations
    np.testing.assert_allclose(model.opt.gravity, robot.model.gravity.linear, atol=0)
    bound = options.boundinertia
    bound = max(1e-8, options.spring_stiffness * options.timestep**2 / 0.1) if bound is None else bound
    assert np.min(model.body_inertia[1:]) >= bound * (1 - 1e-12)
    key = model.key("home").id
    np.testing.assert_allclose(model.key_qpos[key], q, atol=0)
    motors = robot.actuated_joints
    crank_q = np.array([q[robot.idx_q(m)] for m in motors])
    # the cranks: servos, drives, or nothing
    eq_joint = [i for i in range(model.neq) if model.eq_type[i] == mujoco.mjtEq.mjEQ_JOINT]
    if options.actuator == "position":
        assert model.nu == len(motors)
        np.testing.assert_allclose(model.key_ctrl[key], crank_q, atol=0)
        np.testing.assert_allclose(model.actuator_gainprm[:, 0], options.kp)
        np.testing.assert_allclose(model.actuator_biasprm[:, 1:3], [[-options.kp, -options.kv]] * len(motors))
    elif options.actuator == "velocity":
        assert model.nu == len(motors)
        np.testing.assert_allclose(model.key_ctrl[key], 0.0, atol=0)
        np.testing.assert_allclose(model.actuator_gainprm[:, 0], options.kv)
    else:
        assert model.nu == 0
    if options.actuator == "position" or options.actuator == "velocity":
        assert [model.joint(model.actuator_trnid[i, 0]).name for i in range(model.nu)] == motors
    if options.actuator == "constraint":
        assert [model.joint(model.eq_obj1id[i]).name for i in eq_joint] == motors
        np.testing.assert_allclose([model.eq_data[i, 0] for i in eq_joint], crank_q, atol=0)
    else:
        assert not eq_joint
    # the loops and the weld
    connects = [model.equality(i).name for i in range(model.neq) if model.eq_type[i] == mujoco.mjtEq.mjEQ_CONNECT]
    assert connects == [loop.name for loop in robot.loops]
    welds = [i for i in range(model.neq) if model.eq_type[i] == mujoco.mjtEq.mjEQ_WELD]
    assert len(welds) == (options.weld_foot is not None)
    np.testing.assert_allclose(model.eq_solref, [options.solref] * model.neq)
    np.testing.assert_allclose(model.eq_solimp[:, :3], [options.solimp] * model.neq)
    pdata = robot.model.createData()
    pin.framesForwardKinematics(robot.model, pdata, q)
    mujoco.mj_resetDataKeyframe(model, data, key)
    mujoco.mj_forward(model, data)
    if options.weld_foot:
        foot = pdata.oMf[robot.frame_id(f"{options.weld_foot}_foot")]
        anchor = data.site(f"{options.weld_foot}_foot_anchor")
        np.testing.assert_allclose(anchor.xpos, foot.translation, atol=1e-12)
        np.testing.assert_allclose(anchor.xmat.reshape(3, 3), foot.rotation, atol=1e-12)
    # the ankle springs
    for name in robot.spring_joints:
        joint = model.joint(name)
        assert model.jnt_stiffness[joint.id] == options.spring_stiffness
        assert model.qpos_spring[joint.qposadr[0]] == pytest.approx(math.pi / 2 - options.spring_rest_angle, abs=1e-15)
        assert model.dof_damping[joint.dofadr[0]] == options.spring_damping
    assert np.count_nonzero(model.jnt_stiffness) == (len(robot.spring_joints) if options.spring_stiffness else 0)
    # the soles (heel to toe, the only geoms that collide) and the floor
    friction = options.mu * (2.0 if options.planar_noslip else 1.0)
    colliding = {model.geom(i).name for i in range(model.ngeom) if model.geom_contype[i]}
    assert colliding == {f"{side}_sole" for side in sides(robot.legs)} | ({"floor"} if options.floor else set())
    for side in sides(robot.legs):
        sole = model.geom(f"{side}_sole")
        heel, toe = (pdata.oMf[robot.frame_id(f"{side}_{p}")].translation for p in ("heel", "toe"))
        np.testing.assert_allclose(data.geom(sole.id).xpos, (heel + toe) / 2, atol=1e-12)
        assert sole.size[0] == options.sole_radius and sole.size[1] == pytest.approx(np.linalg.norm(toe - heel) / 2)
        assert sole.friction[0] == pytest.approx(friction, rel=1e-15) and sole.condim[0] == 3
        np.testing.assert_allclose(sole.solref, options.contact_solref)
        np.testing.assert_allclose(sole.solimp[:3], options.contact_solimp)
    assert model.geom("floor").friction[0] == pytest.approx(friction, rel=1e-15)
