"""Forward dynamics of the spring biped (simulate, spring_study): constraint rows, statics, energy, drift, impacts.

Expected values come from independent computations written here: finite differences of the
constraint residual, finite differences of the potential energy along the constraint
manifold (static multipliers), Pinocchio's own kinetic/potential energy and centre of mass,
a null-space formula for the impact, and Carnot's theorem for the energy it dissipates.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
import scipy.linalg as sl

from pasibot_pin import constraints
from pasibot_pin.constraints import ConstraintSystem, coordinate
from pasibot_pin.dynamics.simulator import BipedSimulator, SimulationSettings, simulate
from pasibot_pin.dynamics.spring_energy import AnkleSpring, foot_pose, mass_matrix
from pasibot_pin.model.closure import assemble, hip_pitch, joint_coordinate, solve_configuration
from pasibot_pin.studies.methods.statics import static_equilibrium
from pasibot_pin.studies.spring_study import toppling_stiffness

G = 9.81


def _system(robot, cmodels, scalars=()):
    return ConstraintSystem(robot.model, robot.data, cmodels, scalars, robot.geometry.L)


def _rows(cset, q, v, t):
    rows = cset.evaluate(q, v, t)
    return rows.phi, rows.jac, rows.drift, rows.phi_t


@pytest.fixture(scope="module")
def spring2(robots):
    return robots[("spring", 2)]


def _energy(robot, q, v, spring):
    """Kinetic + gravity + spring energy [J], from Pinocchio's energy and centre-of-mass routines."""
    model, data = robot.model, robot.data
    kinetic = pin.computeKineticEnergy(model, data, q, v)
    com = pin.centerOfMass(model, data, q)
    mass = sum(model.inertias[j].mass for j in range(1, model.njoints))
    elastic = 0.0
    for side in ("right", "left"):
        beta = math.pi / 2 - q[robot.idx_q(f"{side}_j13_ankle")]
        elastic += 0.5 * spring.stiffness * (beta - spring.rest_angle) ** 2
    return kinetic + mass * G * com[2] + elastic, kinetic


def test_constraint_rows_match_finite_differences(spring2):
    robot = spring2
    rng = np.random.default_rng(3)
    coords = [coordinate("right_j0_crank", robot.idx_v("right_j0_crank"), 1.0, 0.7)]
    cset = _system(robot, robot.constraint_models, coords)
    q = robot.q0 + 0.05 * rng.normal(size=robot.model.nv)
    v = rng.normal(size=robot.model.nv)
    phi, jac, drift, phi_t = _rows(cset, q, v, 0.3)
    assert phi.shape == (15 + 1,) and jac.shape == (16, robot.model.nv)
    eps = 1e-6
    fd_jac = np.column_stack(
        [
            (_rows(cset, q + eps * e, None, 0.3)[0] - _rows(cset, q - eps * e, None, 0.3)[0]) / (2 * eps)
            for e in np.eye(19)
        ]
    )
    assert np.max(np.abs(fd_jac - jac)) < 1e-7
    # drift = d/ds [J(q + s v)] v
    fd_drift = (_rows(cset, q + eps * v, None, 0)[1] - _rows(cset, q - eps * v, None, 0)[1]) @ v / (2 * eps)
    assert np.max(np.abs(fd_drift - drift)) < 1e-6
    # the rheonomic row: q_crank - (1.0 + 0.7 t)
    assert phi[-1] == pytest.approx(q[robot.idx_q("right_j0_crank")] - 1.0 - 0.7 * 0.3, abs=1e-15)
    assert phi_t[-1] == -0.7 and np.all(phi_t[:-1] == 0)
    assert np.linalg.matrix_rank(jac) == 16, "the in-plane rows have full row rank"


def test_kkt_accelerations_match_pinocchio_constraint_dynamics(spring2):
    """Our KKT solve against Pinocchio's constraintDynamics (proximal, mu > 0) on loops + weld."""
    robot = spring2
    spring = AnkleSpring(300.0, math.radians(75.0), 0.5)
    sim = BipedSimulator(robot, SimulationSettings(omega=0.0, motor="free", spring=spring, theta0=2.5))
    q, _, stance = sim.initial_state()
    cset = sim.constraint_set(stance, robot.with_stance(stance, q).weld)
    assert not cset.scalars, "free motor, free hip: only Pinocchio constraint models"
    rng = np.random.default_rng(1)
    v = cset.impulse(q, rng.normal(size=robot.model.nv), 0.0)[0]  # a consistent velocity
    a, _, _ = sim.acceleration(cset, 0.0, q, v)
    tau = sim.forces(0.0, q, v)
    a_pin = constraints.proximal_forward_dynamics(robot.model, robot.model.createData(), cset.cmodels, q, v, tau)
    assert np.max(np.abs(a)) > 10.0
    assert np.max(np.abs(a_pin - a)) < 1e-9 * np.max(np.abs(a))


def test_impulse_matches_pinocchio_impulse_dynamics_for_the_foot_weld(spring2):
    """Pinocchio's impulseDynamics (contact models, proximal) on the weld alone: same v+ as our KKT impulse."""
    robot = spring2
    q = robot.q0
    v = np.random.default_rng(2).normal(size=robot.model.nv)
    weld_only = _system(robot, [robot.weld])
    v_plus, _ = weld_only.impulse(q, v, 0.0)
    v_pin = constraints.proximal_impulse(robot.model, robot.model.createData(), [robot.weld], q, v, mu=1e-10)
    assert np.max(np.abs(v_plus - v)) > 0.1, "the weld must change the velocity"
    assert np.max(np.abs(v_pin - v_plus)) < 1e-5 * np.max(np.abs(v_plus))


def test_static_multipliers_are_gradients_of_the_potential(spring2):
    """At rest with cranks, hip and swing ankle locked, each lock's multiplier is dV/ds."""
    robot = spring2
    spring = AnkleSpring(331.0, math.radians(72.0))
    theta = 2.9
    settings = SimulationSettings(omega=0.0, spring=spring, hip="level", swing_ankle="rest", theta0=theta)
    sim = BipedSimulator(robot, settings)
    q, v, stance = sim.initial_state()
    assert stance == "right" and np.allclose(v, 0)
    cset = sim.constraint_set(stance, sim.ground_weld(stance, q))
    a, lam, phi = sim.acceleration(cset, 0.0, q, v)
    assert np.max(np.abs(phi)) < 1e-10 and np.max(np.abs(a)) < 1e-9, "fully locked: nothing moves"
    labels = cset.labels
    stance_robot = robot.with_stance(stance, q)
    prescribed = [joint_coordinate(stance_robot, j) for j in ("right_j0_crank", "left_j0_crank")]
    prescribed += [hip_pitch(stance_robot), joint_coordinate(stance_robot, "left_j13_ankle")]
    base = np.array([q[p.index] for p in prescribed])

    def potential(qq):
        return _energy(robot, qq, np.zeros(19), spring)[0]

    eps = 1e-5
    for k, name in enumerate(["right_j0_crank", "left_j0_crank", "hip_pitch", "left_j13_ankle"]):
        step = np.zeros(4)
        step[k] = eps
        qp = solve_configuration(stance_robot, q, prescribed, base + step)
        qm = solve_configuration(stance_robot, q, prescribed, base - step)
        dv_ds = (potential(qp) - potential(qm)) / (2 * eps)
        assert lam[labels.index(name)] == pytest.approx(dv_ds, rel=1e-5, abs=1e-6), name


def test_hip_lock_torque_is_gravity_moment_minus_spring(spring2):
    """Hip held level at rest: lambda_hip = g sum m_i (x_i - x_ankle) - T_e (docs/reference.md §5 check)."""
    robot = spring2
    spring = AnkleSpring(331.0, math.radians(72.0))
    sim = BipedSimulator(
        robot, SimulationSettings(omega=0.0, spring=spring, hip="level", swing_ankle="rest", theta0=3.6)
    )
    q, v, stance = sim.initial_state()
    cset = sim.constraint_set(stance, sim.ground_weld(stance, q))
    lam = sim.acceleration(cset, 0.0, q, v)[1]
    model, data = robot.model, robot.data
    com = pin.centerOfMass(model, data, q)
    total = sum(model.inertias[j].mass for j in range(1, model.njoints))
    foot_joint = model.getJointId("right_j13_ankle")
    foot_com = data.oMi[foot_joint].act(model.inertias[foot_joint].lever)
    m_foot = model.inertias[foot_joint].mass
    pin.framesForwardKinematics(model, data, q)
    ankle_x = data.oMf[robot.frame_id("right_foot")].translation[0]
    moment = G * (total * com[0] - m_foot * foot_com[0] - (total - m_foot) * ankle_x)
    beta = math.pi / 2 - q[robot.idx_q("right_j13_ankle")]
    spring_torque = -spring.stiffness * (beta - spring.rest_angle)
    assert lam[cset.labels.index("hip_pitch")] == pytest.approx(moment - spring_torque, rel=1e-9, abs=1e-9)


@pytest.mark.parametrize(
    ("motor", "duration", "dt"),
    # Cranks free: after ~0.25 s they whip up to ~30 rad/s, so fixed-step RK4 needs a finer step
    # (1.25e-4 s gives ~3e-8 relative drift over 1 s; 5e-4 s would lose ~3e-5).
    [("rheonomic", 1.0, 1e-3), ("free", 1.0, 1.25e-4)],
    ids=["cranks-locked-1s", "cranks-free-1s"],
)
@pytest.mark.slow
def test_energy_is_conserved_without_motor_damping_or_impact(spring2, motor, duration, dt):
    robot = spring2
    spring = AnkleSpring(300.0, math.radians(70.0), 0.0)  # not at equilibrium: the hip swings ~25 deg
    settings = SimulationSettings(omega=0.0, motor=motor, spring=spring, dt=dt, theta0=math.pi)
    res = simulate(robot, settings, duration=duration)
    assert not res.fell and res.t[-1] == pytest.approx(duration)
    energies = np.array([_energy(robot, q, v, spring) for q, v in zip(res.q, res.v)])
    total, kinetic = energies[:, 0], energies[:, 1]
    assert kinetic.max() > 1.0, "the test must move something"
    assert res.max_hip_excursion > math.radians(2.0)
    assert np.max(np.abs(total - total[0])) / abs(total[0]) < 1e-6
    assert np.max(np.abs(total - total[0])) < 1e-4 * kinetic.max()
    assert res.max_drift < 1e-8, "constraint drift per step, before projection [m]"
    # after projection the stored states satisfy every constraint
    cset = BipedSimulator(robot, settings).constraint_set("right", robot.with_stance("right", res.q[0]).weld)
    assert max(np.max(np.abs(cset.residual(q, t))) for q, t in zip(res.q[::50], res.t[::50])) < 1e-10


def test_impact_velocity_is_the_mass_weighted_projection_and_dissipates(spring2):
    robot = spring2
    spring = AnkleSpring(331.0, math.radians(75.0), 1.0)
    # the right stance is 0.1 rad of crank from its end: the left foot is about to land
    settings = SimulationSettings(omega=2.0, spring=spring, dt=2e-3, theta0=1.5 * math.pi - 0.1)
    sim = BipedSimulator(robot, settings)
    res = sim.run(duration=0.05)
    q, v, t = res.q[-1], res.v[-1], res.t[-1]
    new = sim.constraint_set("left", sim.ground_weld("left", q))
    q = new.project(q, t, metric="mass")  # onto the new set: we test the velocity jump alone
    v_plus, lam = new.impulse(q, v, t)
    _, jac, _, phi_t = _rows(new, q, None, t)
    assert np.max(np.abs(jac @ v_plus + phi_t)) < 1e-10
    mass = mass_matrix(robot, q)
    # independent: v+ = N (N^T M N)^-1 N^T M v- + particular solution; here Phi_t is not zero
    # (the motor rows), so write v = v_p + N z with J v_p = -Phi_t
    v_p = np.linalg.lstsq(jac, -phi_t, rcond=None)[0]
    null = sl.null_space(jac)
    z = np.linalg.solve(null.T @ mass @ null, null.T @ mass @ (v - v_p))
    assert np.max(np.abs(v_p + null @ z - v_plus)) < 1e-9
    # impulse balance M (v+ - v-) = J^T Lambda
    assert np.max(np.abs(mass @ (v_plus - v) - jac.T @ lam)) < 1e-9
    # with the motor locked (Phi_t = 0) the kinetic energy cannot rise; Carnot: the loss is
    # the kinetic energy of the lost velocity
    locked = new.with_scalars([c.at(q[c.index]) for c in new.scalars])
    v_minus = v
    v_l, _ = locked.impulse(q, v_minus, t)
    ke = 0.5 * v_minus @ mass @ v_minus
    ke_l = 0.5 * v_l @ mass @ v_l
    dv = v_minus - v_l
    assert ke_l <= ke + 1e-12
    assert ke - ke_l == pytest.approx(0.5 * dv @ mass @ dv, rel=1e-8, abs=1e-12)
    assert ke - ke_l > 1e-4, "the impact must dissipate something"


def test_walk_switches_stance_and_lands_on_the_ground(spring2):
    robot = spring2
    spring = AnkleSpring(331.0, math.radians(75.0), 1.0)
    settings = SimulationSettings(omega=5.0, spring=spring, swing_ankle="rest", dt=1e-2)
    res = simulate(robot, settings, steps=3)
    assert not res.fell, res.message
    assert [imp.side for imp in res.impacts] == ["left", "right"]
    assert res.impacts[0].t == pytest.approx(math.pi / 5.0)
    assert res.stance[0] == "right" and res.stance[-1] == "right" and "left" in res.stance
    assert res.t[-1] == pytest.approx(3 * math.pi / 5.0)
    sim = BipedSimulator(robot, settings)
    for imp in res.impacts:
        k = int(np.argmin(np.abs(res.t - imp.t - 1e-6) + (res.t <= imp.t) * 1e9))
        _, z, pitch = foot_pose(robot, res.q[k], imp.side)
        assert abs(z) < 1e-9 and abs(pitch) < 1e-9, "the landed foot is welded flat on the ground"
        # the post-impact velocity satisfies the new constraints (motor rows included)
        cset = sim.constraint_set(imp.side, sim.ground_weld(imp.side, res.q[k]))
        _, jac, _, phi_t = _rows(cset, res.q[k], None, res.t[k])
        assert np.max(np.abs(jac @ res.v[k] + phi_t)) < 1e-9
    # motor rows: the cranks follow theta0 + omega t exactly
    crank = res.q[:, robot.idx_q("right_j0_crank")]
    assert np.max(np.abs(crank - (math.pi / 2 + 5.0 * res.t))) < 1e-10
    assert sim.settings.omega == 5.0


@pytest.mark.parametrize(
    ("changes", "word"),
    [
        ({"motor": "servo"}, "motor"),
        ({"hip": "loose"}, "hip"),
        ({"dt": 0.0}, "dt"),
        ({"integrator": "verlet"}, "integrator"),
        ({"omega": float("nan")}, "omega"),
    ],
)
def test_bad_settings_raise(changes, word):
    with pytest.raises(ValueError, match=word):
        SimulationSettings(**changes)


def test_bad_inputs_raise(robots):
    with pytest.raises(ValueError, match="stiffness"):
        AnkleSpring(-1.0, 1.2)
    with pytest.raises(ValueError, match="variant 'spring'"):
        BipedSimulator(robots[("rigid", 2)], SimulationSettings())
    sim = BipedSimulator(robots[("spring", 2)], SimulationSettings(omega=0.0))
    with pytest.raises(ValueError, match="omega"):
        sim.run(steps=2)
    with pytest.raises(ValueError, match="exactly one"):
        sim.run()


def test_static_equilibrium_stands_still_and_its_stability_sign_is_right(spring2):
    robot = spring2
    theta = 2.8
    spring = AnkleSpring(331.0, math.radians(72.0), 1.0)
    for spr, stable in ((spring, True), (spring.scaled(0.0), False)):
        eq = static_equilibrium(robot, spr, [theta])
        assert eq.found[0]
        assert (eq.stiffness[0] > 0) == stable
        # start the (cranks locked) simulation there, nudged by 1 mrad
        settings = SimulationSettings(
            omega=0.0,
            spring=spr,
            swing_ankle="rest",
            theta0=theta,
            dt=5e-3,
            initial_pitch=float(eq.hip_pitch[0]),
        )
        still = simulate(robot, settings, duration=0.3)
        assert np.max(np.abs(still.hip_pitch - eq.hip_pitch[0])) < 1e-7, "at equilibrium nothing moves"
        nudged = simulate(robot, settings.with_(initial_pitch=float(eq.hip_pitch[0]) + 1e-3), duration=1.5)
        away = np.max(np.abs(nudged.hip_pitch - eq.hip_pitch[0]))
        if stable:
            assert away < 1.5e-3, "a stable equilibrium keeps a small nudge small"
        else:
            assert away > 1e-2, "with no spring the nudge grows: the robot falls"


# --------------------------------------------------------------------------- with the inverse dynamics
def test_static_stability_margin_is_spring_minus_gravity_moment_of_height(spring2):
    """Rigid rotation about the stance ankle: d2V/dpitch2 = K_e - g sum m_i (z_i - z_ankle)."""
    robot = spring2
    theta = 3.3
    spring = AnkleSpring(400.0, math.radians(72.0))
    eq = static_equilibrium(robot, spring, [theta])
    assert eq.found[0]
    q = assemble(robot, theta, hip_pitch_value=float(eq.hip_pitch[0]))
    q[robot.idx_q("left_j13_ankle")] = math.pi / 2 - spring.rest_angle
    model, data = robot.model, robot.data
    com = pin.centerOfMass(model, data, q)
    total = sum(model.inertias[j].mass for j in range(1, model.njoints))
    foot = model.getJointId("right_j13_ankle")
    m_foot = model.inertias[foot].mass
    foot_com = data.oMi[foot].act(model.inertias[foot].lever)
    pin.framesForwardKinematics(model, data, q)
    z_ankle = data.oMf[robot.frame_id("right_foot")].translation[2]
    gravity_stiffness = G * (total * com[2] - m_foot * foot_com[2] - (total - m_foot) * z_ankle)
    assert 250.0 < gravity_stiffness < 350.0
    assert eq.stiffness[0] == pytest.approx(spring.stiffness - gravity_stiffness, rel=1e-4)
    # the module's k_g, hip level at this crank angle, against the same sum written here
    q_level = assemble(robot, theta)
    com = pin.centerOfMass(model, data, q_level)
    foot_com = data.oMi[foot].act(model.inertias[foot].lever)
    pin.framesForwardKinematics(model, data, q_level)
    z_ankle = data.oMf[robot.frame_id("right_foot")].translation[2]
    k_g = G * (total * com[2] - m_foot * foot_com[2] - (total - m_foot) * z_ankle)
    assert toppling_stiffness(robot, theta) == pytest.approx(k_g, rel=1e-12)


def _inverse_feedforward(robot, result, h):
    """Feed-forward torques of the inverse dynamics on the RK4 stage grid t = k h / 2."""
    taus = np.zeros((len(result.t), robot.model.nv))
    taus[:, robot.idx_v("right_j0_crank")] = result.Ta
    taus[:, robot.idx_v("left_j0_crank")] = result.Ta_swing
    taus[:, robot.idx_v("right_j13_ankle")] = -result.Te  # T_e acts on beta = pi/2 - q_ankle
    taus[:, robot.idx_v("left_j13_ankle")] = -result.Te_swing

    def feedforward(t, q, v):
        k = int(round(t / (h / 2)))
        assert abs(k * h / 2 - t) < 1e-9, "stage times are on the grid"
        return taus[k]

    return feedforward


def test_forward_of_inverse_dynamics_is_the_identity():
    """Scenario 4 (omega = 5 rad/s): the inverse-dynamics crank and ankle torques, applied as pure
    feed-forward (no servo) with the hip pitch held level, reproduce the prescribed walk over one
    step to 1e-6 rad, and the hip needs no holding torque."""
    from pasibot_pin.dynamics.inverse import inverse_dynamics
    from pasibot_pin.model.scenario_robots import scenario_robot
    from pasibot_pin.model.scenarios import PRESETS, SCENARIOS

    scenario = SCENARIOS["run4"]
    robot = scenario_robot(scenario, PRESETS["default"])
    omega = scenario.omega
    duration = math.pi / omega  # one step: right stance, theta from pi/2 to 3 pi/2
    n = 500
    h = duration / n
    thetas = math.pi / 2 + omega * (h / 2) * np.arange(2 * n + 1)
    ideal = inverse_dynamics(robot, thetas, omega, swing_foot="level", stance="right")
    settings = SimulationSettings(
        omega=omega,
        motor="free",
        hip="level",
        swing_ankle="spring",
        spring=None,
        feedforward=_inverse_feedforward(robot, ideal, h),
        dt=h,
    )
    res = BipedSimulator(robot, settings).run(duration=duration, q0=ideal.q[0], v0=ideal.v[0], stance="right")
    assert not res.fell and len(res.t) == n + 1
    assert np.max(np.abs(res.t - ideal.t[::2])) < 1e-12
    angles = [i for i in range(robot.model.nq) if i not in (0, 1)]  # every coordinate but hip x, z [m]
    assert np.max(np.abs(res.q[:, angles] - ideal.q[::2, angles])) < 1e-6
    assert np.max(np.abs(res.q[:, :2] - ideal.q[::2, :2])) < 1e-6  # hip x, z [m]
    # the cranks turned at omega with no servo, the swing foot stayed level
    crank = res.q[:, robot.idx_q("right_j0_crank")]
    assert np.max(np.abs(crank - (math.pi / 2 + omega * res.t))) < 1e-6
    swing_pitch = [foot_pose(robot, q, "left")[2] for q in res.q[::25]]
    assert np.max(np.abs(swing_pitch)) < 1e-6
    # the hip lock carries nothing: T_e holds the hip exactly (a large T_e error would show here)
    assert np.max(np.abs(ideal.Te)) > 50.0
    assert np.max(np.abs(res.hip_torque)) < 1e-4
    # and the motion is not trivial: the free coordinates moved a lot
    assert np.ptp(res.beta[:, 0]) > math.radians(10.0)
    # with the motor as a rheonomic constraint and only the ankle torques fed forward, the
    # motor rows' multipliers are the inverse dynamics' crank torques
    ankles_only = _inverse_feedforward(robot, ideal, h)

    def ankle_torques(t, q, v):
        tau = ankles_only(t, q, v).copy()
        tau[[robot.idx_v("right_j0_crank"), robot.idx_v("left_j0_crank")]] = 0.0
        return tau

    driven = BipedSimulator(robot, settings.with_(motor="rheonomic", feedforward=ankle_torques)).run(
        duration=duration, q0=ideal.q[0], v0=ideal.v[0], stance="right"
    )
    assert np.max(np.abs(driven.q[:, angles] - ideal.q[::2, angles])) < 1e-6
    assert np.max(np.abs(driven.motor_torque[:, 0] - ideal.Ta[::2])) < 1e-6 * np.max(np.abs(ideal.Ta))
    assert np.max(np.abs(driven.motor_torque[:, 1] - ideal.Ta_swing[::2])) < 1e-6 * np.max(np.abs(ideal.Ta))


@pytest.mark.slow
def test_without_spring_the_hip_falls_sooner_and_further_in_every_scenario():
    """Per seed scenario: the no-spring robot passes 60 deg of hip pitch sooner than the fitted one, and
    up to that moment the fitted spring keeps the hip closer to level. Windows: 4 s of walking at
    0.1 rad/s (cranks locked for the quasi-static run), four steps at 5 rad/s."""
    from pasibot_pin.model.scenarios import SCENARIOS
    from pasibot_pin.studies.spring_study import scenario_inputs, standing_pitch

    for name in SCENARIOS:
        scen = scenario_inputs(name)
        runs = {}
        for label, factor in (("fitted", 1.0), ("none", 0.0)):
            spring = scen.fit.scaled(factor)
            settings = SimulationSettings(
                omega=scen.omega,
                spring=spring,
                swing_ankle="rest",
                dt=0.01 if scen.omega > 1 else 0.02,
                initial_pitch=standing_pitch(scen.robot, spring, math.pi / 2),
            )
            duration = 4 * math.pi / scen.omega if scen.omega > 1 else 4.0
            runs[label] = simulate(scen.robot, settings, duration=duration)
        none, fitted = runs["none"], runs["fitted"]
        assert none.fell, f"{name}: without a spring the robot falls"
        t_fall = none.t[-1]
        assert not fitted.fell or fitted.t[-1] > t_fall, name
        before = fitted.t <= t_fall
        assert np.max(np.abs(fitted.hip_pitch[before])) < none.max_hip_excursion, name


@pytest.mark.slow
def test_simulate_command_writes_plots_csv_and_gif(tmp_path, capsys):
    from pasibot_pin.__main__ import main

    out = tmp_path / "sim"
    argv = ["simulate", "--ground", "weld", "--scenario", "4", "--steps", "1", "--no-cases", "--dt", "0.02"]
    argv += ["--gif", "--out", str(out)]
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "scenario run4" in text and "max |hip pitch|" in text
    for name in ("simulation_run4.png", "simulation_run4.csv", "simulation_run4.gif"):
        assert (out / name).stat().st_size > 1000, name
    table = np.genfromtxt(out / "simulation_run4.csv", delimiter=",", names=True)
    assert "hip_pitch_rad" in table.dtype.names and "Ta_right_Nm" in table.dtype.names
    assert "swing_sole_height_m" in table.dtype.names
    assert table["t_s"][-1] == pytest.approx(math.pi / 5.0)
    assert np.all(np.abs(table["theta_right_rad"] - (math.pi / 2 + 5.0 * table["t_s"])) < 1e-9)
    assert main(argv) == 2, "existing files are kept without --force"
    assert "--force" in capsys.readouterr().err
    assert main(argv + ["--force"]) == 0
    assert main(["simulate", "--ground", "weld", "--scenario", "9", "--out", str(out)]) == 2
    assert "unknown scenario" in capsys.readouterr().err
    quasi = ["simulate", "--ground", "weld", "--scenario", "quasi-static", "--no-cases", "--out", str(out)]
    assert main(quasi) == 0
    assert "equilibrium" in capsys.readouterr().out
    assert (out / "simulation_quasi-static.png").exists()


def test_lockstep_walks_equal_the_single_walks():
    """simulate_many (the dynamic sweep's lockstep walks) gives simulate's walk for each spring: a
    standing fitted walk, a stiffer one with another rest angle, and a falling one without spring,
    over two stances at 5 rad/s (a touchdown in between)."""
    from pasibot_pin.dynamics.lockstep import simulate_many
    from pasibot_pin.studies.spring_study import scenario_inputs, standing_pitch

    scen = scenario_inputs("run4")
    springs = [scen.fit, AnkleSpring(2.5 * scen.fit.stiffness, scen.fit.rest_angle + 0.05, 1.0), scen.fit.scaled(0.0)]
    settings = [
        SimulationSettings(
            omega=scen.omega, spring=sp, swing_ankle="rest", dt=0.01, initial_pitch=standing_pitch(scen.robot, sp, 1.6)
        )
        for sp in springs
    ]
    many = simulate_many(scen.robot, settings, steps=2)
    assert [run.fell for run in many] == [False, False, True]
    for run, s in zip(many, settings):
        one = simulate(scen.robot, s, steps=2)
        assert (one.fell, one.message, one.stance) == (run.fell, run.message, run.stance)
        assert run.t == pytest.approx(one.t, abs=1e-12)
        for name in ("q", "v", "motor_torque", "swing_height"):
            scale = np.max(np.abs(getattr(one, name)))
            assert np.max(np.abs(getattr(run, name) - getattr(one, name))) < 1e-9 * scale, name
        assert len(run.impacts) == len(one.impacts)
        for a, b in zip(run.impacts, one.impacts):
            assert (a.t, a.side) == (b.t, b.side)
            assert a.kinetic_after == pytest.approx(b.kinetic_after, rel=1e-9)
    with pytest.raises(ValueError, match="differ only"):
        simulate_many(scen.robot, [settings[0], settings[1].with_(dt=0.02)], steps=1)


def test_batched_static_equilibria_equal_the_one_angle_path():
    """static_equilibria (the static sweep's cells, all at once) finds the same equilibria as
    static_equilibrium angle by angle: where, the pitch, and the stability; no spring, a softer one
    with another rest angle, a stiffer one (angles with and without an equilibrium)."""
    from pasibot_pin.studies.methods.static_batch import static_equilibria
    from pasibot_pin.studies.spring_study import scenario_inputs

    scen = scenario_inputs("run2")
    fit = scen.fit
    springs = [fit.scaled(0.0), AnkleSpring(0.8 * fit.stiffness, fit.rest_angle - math.radians(6)), fit.scaled(1.25)]
    thetas = np.linspace(math.pi / 2, 1.5 * math.pi, 6, endpoint=False)
    many = static_equilibria(scen.robot, springs, thetas)
    found = np.concatenate([eq.found for eq in many])
    assert found.any() and not found.all()  # both kinds of answers are compared
    for spring, eq in zip(springs, many):
        one = static_equilibrium(scen.robot, spring, thetas)
        assert np.array_equal(one.found, eq.found)
        assert np.allclose(eq.hip_pitch[one.found], one.hip_pitch[one.found], rtol=0, atol=1e-10)
        assert np.allclose(eq.stiffness[one.found], one.stiffness[one.found], rtol=1e-6)
