# Which conventions Pinocchio 4.1's constraint API follows for the planar closed-loop biped, each checked against an
# independent finite-difference reference built from the joint placements alone (data.oMi after forwardKinematics).
#
# Findings recorded here (a test fails if one of them stops being true):
# - getConstraintsJacobian (CONTACT_3D / CONTACT_6D, LOCAL_WORLD_ALIGNED) rows 0, 2 are d(p1 - p2)/dq in world axes,
#   weld row 4 is minus the pitch rate (pitch about -y); the out-of-plane rows are identically zero.
# - constraintDynamics enforces the CLASSICAL second derivative of p1 - p2 (world axes) for a CONTACT_3D between two
#   moving bodies, on and off the velocity manifold (no missing Coriolis term, no rotating-frame convention); a KKT
#   with the spatial convention (no omega x v_p) would be off by ~340 rad/s^2 at the 5 rad/s state, so this is sharp.
# - the CONTACT_6D weld's linear rows use the SPATIAL acceleration of the foot frame: off the velocity manifold they
#   violate the classical second derivative by exactly omega_foot x v_point (zero when the weld holds in velocity).
# - Baumgarte gains default to Kp = Kd = 0 (position residuals are not fed back); with gains, c'' = -Kp c - Kd c'
#   in world axes (checked on the CONTACT_3D loops).
# - the out-of-plane rows and the proximal mu (1e-10 .. 1e-3) do not change the accelerations (mu = 0 gives NaN).
# - with the same constraint set and a consistent state, an independent in-plane KKT solve agrees with
#   constraintDynamics to ~1e-9 (two legs, hip still or rotating; one leg, fixed hip; v = 0 or cranks at 5 rad/s).
# - the 100+ rad/s^2 gap of the simulator is its rheonomic crank rows (motor="rheonomic"; the hip and swing-ankle
#   locks act alike), which are not Pinocchio constraint models: it is there at omega = 0 too, and vanishes when
#   their multipliers (the motor torques) are applied as joint torques, or with motor="free".
# - computeJointJacobiansTimeVariation is WRONG for the translation columns (PX, PZ) of the composite planar hip:
#   it returns omega x e_x, omega x e_z instead of 0 (world-fixed axes). A drift built from data.dJ is off by
#   omega_hip x v_hip for rows against the world (weld), the error cancels in two-body loop rows.
#   forwardKinematics(q, v, 0) (joint bias accelerations of the composite) is right.
# - impulseDynamics uses only the first body's velocity: for a two-body loop J (v+ - v-) = -v_c1, so v+ violates
#   the loop; for the weld to the world (joint2 = 0) it equals the KKT impulse.
from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import pasibot_pin as pp
from pasibot_pin.model.closure import hip_pitch, joint_coordinate, solve_velocity

MU = 1e-10
CRANK_RATE = 5.0
THETA = 2.5  # a generic right-crank angle [rad] (at q0, 180 deg, each loop's two bodies turn alike)


@pytest.fixture(scope="module")
def biped():
    return pp.load("spring", 2)


@pytest.fixture(scope="module")
def one_leg():
    return pp.load("rigid", 1)


# --------------------------------------------------------------------------- independent references
def _is_weld(cm):
    return cm.type == pin.ContactType.CONTACT_6D


def _pitch(rotation):
    return math.atan2(rotation[2, 0], rotation[0, 0])  # counter-clockwise about -y


def _ends(data, cm):
    o1 = data.oMi[cm.joint1_id] * cm.joint1_placement if cm.joint1_id else cm.joint1_placement
    o2 = data.oMi[cm.joint2_id] * cm.joint2_placement if cm.joint2_id else cm.joint2_placement
    return o1, o2


def _residual(model, data, cms, q):
    """In-plane rows from placements only: x, z of p1 - p2 (and pitch1 - pitch2 for a weld)."""
    pin.forwardKinematics(model, data, q)
    out = []
    for cm in cms:
        o1, o2 = _ends(data, cm)
        dp = o1.translation - o2.translation
        out += [dp[0], dp[2]]
        if _is_weld(cm):
            out.append(math.remainder(_pitch(o1.rotation) - _pitch(o2.rotation), 2 * math.pi))
    return np.array(out)


def _second_derivative(model, data, cms, q, v, a, h=5e-4):
    """d^2/dt^2 c(q(t)) at t = 0 along q(t) = q (+) (t v + t^2 a / 2), fourth-order central differences."""
    f = [
        _residual(model, data, cms, pin.integrate(model, q, t * v + 0.5 * t * t * a)) for t in (-2 * h, -h, 0, h, 2 * h)
    ]
    return (-f[0] + 16 * f[1] - 30 * f[2] + 16 * f[3] - f[4]) / (12 * h * h)


def _drift(model, data, cms, q, v):
    """Jdot v: the classical second derivative at zero joint acceleration."""
    return _second_derivative(model, data, cms, q, v, np.zeros(model.nv))


def _jacobian_fd(model, data, cms, q, eps=1e-6):
    cols = [
        (
            _residual(model, data, cms, pin.integrate(model, q, eps * e))
            - _residual(model, data, cms, pin.integrate(model, q, -eps * e))
        )
        / (2 * eps)
        for e in np.eye(model.nv)
    ]
    return np.column_stack(cols)


def _inplane_rows(cms):
    index, sign, offset = [], [], 0
    for cm in cms:
        if _is_weld(cm):
            index += [offset, offset + 2, offset + 4]
            sign += [1.0, 1.0, -1.0]
        else:
            index += [offset, offset + 2]
            sign += [1.0, 1.0]
        offset += cm.residualSize()
    return np.array(index), np.array(sign)


def _pin_jacobian(model, data, cms, q):
    cdatas = [cm.createData() for cm in cms]
    pin.computeJointJacobians(model, data, q)
    for cm, cd in zip(cms, cdatas):
        cm.calc(model, data, cd)
    return pin.getConstraintsJacobian(model, data, cms, cdatas)


def _constraint_dynamics(model, cms, q, v, tau, mu=MU):
    data = model.createData()
    cdatas = [cm.createData() for cm in cms]
    pin.initConstraintDynamics(model, data, cms, cdatas)
    a = pin.constraintDynamics(model, data, q, v, tau, cms, cdatas, pin.ProximalSettings(1e-13, mu, 100))
    return np.array(a), cdatas


def _kkt(mass, jac, top, bottom):
    nv, m = mass.shape[0], jac.shape[0]
    kkt = np.block([[mass, jac.T], [jac, np.zeros((m, m))]])
    sol = np.linalg.solve(kkt, np.concatenate((top, bottom)))
    return sol[:nv], -sol[nv:]


def _mass(model, data, q):
    mass = pin.crba(model, data, q)
    return np.triu(mass) + np.triu(mass, 1).T


def _reference_acceleration(model, cms, q, v, tau, extra_rows=None):
    """[M J^T; J 0][a; mu] = [tau - h; -Jdot v], in-plane rows, Jdot v by finite differences of the placements."""
    data = model.createData()
    jac = _jacobian_fd(model, data, cms, q)
    rows, sign = _inplane_rows(cms)
    analytic = _pin_jacobian(model, data, cms, q)[rows] * sign[:, None]
    assert np.max(np.abs(analytic - jac)) < 1e-8  # checked, then used: central differences lose ~1e-6 in the KKT
    jac = analytic
    drift = _drift(model, data, cms, q, v)
    if extra_rows is not None:  # coordinate rows q_i = offset + rate t (no drift)
        jac = np.vstack((jac, extra_rows))
        drift = np.concatenate((drift, np.zeros(len(extra_rows))))
    h = pin.nonLinearEffects(model, data, q, v)
    return _kkt(_mass(model, data, q), jac, tau - h, -drift)


def _prescribed(robot):
    """Velocity indices that, with the constraints, fix the pose: cranks (+ hip pitch and swing ankle for two legs)."""
    model = robot.model
    names = ["right_j0_crank", "left_j0_crank", "left_j13_ankle"] if robot.model.nv > 10 else ["right_j0_crank"]
    index = [model.joints[model.getJointId(n)].idx_v for n in names]
    return index[:2] + [2] + index[2:] if len(index) > 1 else index  # hip pitch: third coordinate of the hip


_POSES: dict = {}


def _closed_pose(robot, theta=THETA):
    """Newton (crank continuation from q0) on [c(q); q_s - s*]: right crank at theta, left at theta + pi."""
    key = (id(robot), theta)
    if key in _POSES:
        return _POSES[key].copy()
    model, data, cms = robot.model, robot.model.createData(), robot.constraint_models
    index = _prescribed(robot)
    selector = np.eye(model.nv)[index]
    rows, sign = _inplane_rows(cms)
    q = robot.q0.copy()
    start = q[index].copy()
    for step in range(1, 9):
        target = start.copy()
        target[: min(2, len(index))] += (theta - start[0]) * step / 8
        for _ in range(30):
            res = np.concatenate((_residual(model, data, cms, q), q[index] - target))
            if np.max(np.abs(res)) < 1e-13:
                break
            jac = np.vstack((_pin_jacobian(model, data, cms, q)[rows] * sign[:, None], selector))
            q = pin.integrate(model, q, np.linalg.solve(jac, -res))
        assert np.max(np.abs(res)) < 1e-12
    _POSES[key] = q.copy()
    return q


def _biped_state(robot, crank_rate, hip_rate=0.0):
    """A closed pose and v on the velocity manifold: cranks at crank_rate, hip pitch at hip_rate, swing ankle still."""
    prescribed = [
        joint_coordinate(robot, "right_j0_crank"),
        joint_coordinate(robot, "left_j0_crank"),
        hip_pitch(robot),
        joint_coordinate(robot, "left_j13_ankle"),
    ]
    q = _closed_pose(robot)
    return q, solve_velocity(robot, q, prescribed, [crank_rate, crank_rate, hip_rate, 0.0])


def _one_leg_state(robot, crank_rate):
    q = _closed_pose(robot)
    return q, solve_velocity(robot, q, [joint_coordinate(robot, "right_j0_crank")], [crank_rate])


def _world_point_velocity(model, data, joint, placement, q, v):
    """World angular velocity of ``joint`` and the classical velocity of its point ``placement`` (world axes)."""
    pin.forwardKinematics(model, data, q, v)
    ov = data.oMi[joint].act(data.v[joint])
    p = (data.oMi[joint] * placement).translation
    return ov.angular, ov.linear + np.cross(ov.angular, p)


# --------------------------------------------------------------------------- 4. Jacobian rows and frames
@pytest.mark.parametrize("which", ["biped", "one_leg"])
def test_constraint_jacobian_rows_are_world_axes_derivatives_of_p1_minus_p2(which, biped, one_leg):
    robot = biped if which == "biped" else one_leg
    model, data, cms = robot.model, robot.model.createData(), robot.constraint_models
    q = _closed_pose(robot) + 0.05 * np.random.default_rng(0).normal(size=model.nv)  # off the manifold too
    assert np.max(np.abs(_residual(model, data, cms, q))) > 1e-3
    full = _pin_jacobian(model, data, cms, q)
    index, sign = _inplane_rows(cms)
    assert np.max(np.abs(full[index] * sign[:, None] - _jacobian_fd(model, data, cms, q))) < 1e-8
    out_of_plane = np.setdiff1d(np.arange(full.shape[0]), index)
    assert np.max(np.abs(full[out_of_plane])) < 1e-12


# --------------------------------------------------------------------------- 3. Baumgarte
def test_baumgarte_gains_default_to_zero_and_residuals_are_not_fed_back(biped):
    model, data = biped.model, biped.model.createData()
    for cm in biped.constraint_models:
        assert cm.m_baumgarte_parameters.Kp == 0.0 and cm.m_baumgarte_parameters.Kd == 0.0
    loops = [cm for cm in biped.constraint_models if not _is_weld(cm)]
    rng = np.random.default_rng(1)
    q = _closed_pose(biped) + 0.02 * rng.normal(size=model.nv)
    v = rng.normal(size=model.nv)
    c = _residual(model, data, loops, q)
    jac = _jacobian_fd(model, data, loops, q)
    assert np.max(np.abs(c)) > 1e-3 and np.max(np.abs(jac @ v)) > 0.1
    a, _ = _constraint_dynamics(model, loops, q, v, np.zeros(model.nv))
    c_ddot = _second_derivative(model, data, loops, q, v, a)
    assert np.max(np.abs(c_ddot)) < 1e-6, "default gains: c'' = 0 whatever the position and velocity residuals"
    kp, kd = 100.0, 20.0
    stabilised = []
    for cm in loops:  # copies: the robot's models keep their zero gains
        copy = pin.RigidConstraintModel(
            cm.type, model, cm.joint1_id, cm.joint1_placement, cm.joint2_id, cm.joint2_placement, cm.reference_frame
        )
        copy.setBaumgarteCorrectorParameters(pin.BaumgarteCorrectorParameters(kp, kd))
        stabilised.append(copy)
    a, _ = _constraint_dynamics(model, stabilised, q, v, np.zeros(model.nv))
    c_ddot = _second_derivative(model, data, loops, q, v, a)
    assert np.max(np.abs(c_ddot + kp * c + kd * (jac @ v))) < 1e-6, "world-axes Baumgarte: c'' = -Kp c - Kd c'"
    assert all(cm.m_baumgarte_parameters.Kp == 0.0 for cm in biped.constraint_models)


# --------------------------------------------------------------------------- 1. drift of a two-body CONTACT_3D
@pytest.mark.parametrize("hip_rate", [0.0, 2.0])
def test_constraint_dynamics_enforces_the_classical_relative_acceleration(hip_rate, biped):
    model, data, cms = biped.model, biped.model.createData(), biped.constraint_models
    q, v = _biped_state(biped, CRANK_RATE, hip_rate)
    assert np.max(np.abs(_jacobian_fd(model, data, cms, q) @ v)) < 1e-8, "a consistent state"
    a, cdatas = _constraint_dynamics(model, cms, q, v, np.zeros(model.nv))
    assert np.max(np.abs(a)) > 50.0
    assert np.max(np.abs(_second_derivative(model, data, cms, q, v, a))) < 1e-6
    # Pinocchio's stored drift (contact1 - contact2 acceleration drift, world axes) is the classical Jdot v
    drift = _drift(model, data, cms, q, v)
    stored = []
    for cm, cd in zip(cms, cdatas):
        lin = cd.contact1_acceleration_drift.linear - cd.contact2_acceleration_drift.linear
        stored += [lin[0], lin[2]]
        if _is_weld(cm):
            stored.append(-(cd.contact1_acceleration_drift.angular[1] - cd.contact2_acceleration_drift.angular[1]))
    assert np.max(np.abs(np.array(stored) - drift)) < 1e-6
    # the spatial convention (a_lin + alpha x p, no omega x v_p) would differ by omega1 x v1 - omega2 x v2 at each
    # loop point (zero for the still foot), and its KKT solution by several rad/s^2: the check above discriminates
    coriolis = []
    for cm in cms:
        w1, v1 = _world_point_velocity(model, data, cm.joint1_id, cm.joint1_placement, q, v)
        w2, v2 = np.zeros(3), np.zeros(3)
        if cm.joint2_id:
            w2, v2 = _world_point_velocity(model, data, cm.joint2_id, cm.joint2_placement, q, v)
        term = np.cross(w1, v1) - np.cross(w2, v2)
        coriolis += [term[0], term[2]] + ([0.0] if _is_weld(cm) else [])
    coriolis = np.array(coriolis)
    assert np.max(np.abs(coriolis)) > 1.0
    tau = np.zeros(model.nv)
    mass, h = _mass(model, data, q), pin.nonLinearEffects(model, data, q, v)
    jac = _jacobian_fd(model, data, cms, q)
    a_spatial, _ = _kkt(mass, jac, tau - h, -(drift - coriolis))
    assert np.max(np.abs(a_spatial - a)) > 1.0


def test_two_body_contact_3d_is_classical_even_off_the_velocity_manifold(biped, one_leg):
    for robot in (biped, one_leg):
        model, data = robot.model, robot.model.createData()
        loops = [cm for cm in robot.constraint_models if not _is_weld(cm)]
        q = _closed_pose(robot)
        v = 3.0 * np.random.default_rng(2).normal(size=model.nv)
        assert np.max(np.abs(_jacobian_fd(model, data, loops, q) @ v)) > 1.0
        a, _ = _constraint_dynamics(model, loops, q, v, np.zeros(model.nv))
        assert np.max(np.abs(_second_derivative(model, data, loops, q, v, a))) < 1e-6


# --------------------------------------------------------------------------- 5. the weld's rows, mu, out-of-plane rows
def test_weld_linear_rows_use_the_spatial_acceleration_off_the_velocity_manifold(biped):
    model, data, cms = biped.model, biped.model.createData(), biped.constraint_models
    weld = cms[-1]
    assert _is_weld(weld) and weld.joint2_id == 0
    q = _closed_pose(biped)
    v = 3.0 * np.random.default_rng(3).normal(size=model.nv)  # the foot moves and turns
    a, _ = _constraint_dynamics(model, cms, q, v, np.zeros(model.nv))
    c_ddot = _second_derivative(model, data, cms, q, v, a)
    omega, v_point = _world_point_velocity(model, data, weld.joint1_id, weld.joint1_placement, q, v)
    spatial_term = np.cross(omega, v_point)[[0, 2]]
    assert np.max(np.abs(spatial_term)) > 1.0
    assert np.max(np.abs(c_ddot[-3:-1] - spatial_term)) < 1e-5, "weld x, z: classical violated by omega x v_p"
    assert abs(c_ddot[-1]) < 1e-6, "weld pitch row: fine"
    assert np.max(np.abs(c_ddot[:-3])) < 1e-6, "loop rows: classical"
    # on the manifold the foot is still (omega = v_p = 0): the two conventions coincide
    q, v = _biped_state(biped, CRANK_RATE, 2.0)
    omega, v_point = _world_point_velocity(model, data, weld.joint1_id, weld.joint1_placement, q, v)
    assert np.max(np.abs(omega)) < 1e-12 and np.max(np.abs(v_point)) < 1e-12


def test_out_of_plane_rows_and_proximal_mu_do_not_change_the_acceleration(biped):
    model, cms = biped.model, biped.constraint_models
    q, v = _biped_state(biped, CRANK_RATE, 2.0)
    tau = np.zeros(model.nv)
    a_ref, _ = _constraint_dynamics(model, cms, q, v, tau, MU)
    for mu in (1e-6, 1e-3):
        assert np.max(np.abs(_constraint_dynamics(model, cms, q, v, tau, mu)[0] - a_ref)) < 1e-9 * np.max(np.abs(a_ref))
    assert np.all(np.isnan(_constraint_dynamics(model, cms, q, v, tau, 0.0)[0])), "mu = 0: rank-deficient, NaN"


# --------------------------------------------------------------------------- same constraints: the two solves agree
@pytest.mark.parametrize(
    "which, crank_rate, hip_rate",
    [
        ("biped", 0.0, 0.0),
        ("biped", CRANK_RATE, 0.0),
        ("biped", CRANK_RATE, 2.0),
        ("one_leg", 0.0, 0.0),
        ("one_leg", CRANK_RATE, 0.0),
    ],
)
def test_independent_kkt_matches_constraint_dynamics(which, crank_rate, hip_rate, biped, one_leg):
    robot = biped if which == "biped" else one_leg
    model, cms = robot.model, robot.constraint_models
    if which == "biped":
        q, v = _biped_state(robot, crank_rate, hip_rate)
    else:
        q, v = _one_leg_state(robot, crank_rate)
    tau = np.zeros(model.nv)
    a_kkt, _ = _reference_acceleration(model, cms, q, v, tau)
    a_pin, _ = _constraint_dynamics(model, cms, q, v, tau)
    assert np.max(np.abs(a_kkt)) > 10.0
    assert np.max(np.abs(a_pin - a_kkt)) < 1e-7 * np.max(np.abs(a_kkt))


# --------------------------------------------------------------------------- the reported 100+ rad/s^2 gap
@pytest.mark.parametrize("omega", [CRANK_RATE, 0.0])
def test_reported_gap_is_the_simulators_coordinate_rows_not_a_drift_convention(omega, biped):
    from pasibot_pin.dynamics.simulator import BipedSimulator, SimulationSettings

    model = biped.model
    # motor="rheonomic": two extra rows q_crank = theta0 + omega t that no Pinocchio constraint model carries
    sim = BipedSimulator(biped, SimulationSettings(omega=omega, motor="rheonomic", hip="free", swing_ankle="spring"))
    q, v, stance = sim.initial_state()
    weld = sim.ground_weld(stance, q)
    cmodels = [cm for cm in biped.constraint_models if not _is_weld(cm)] + [weld]
    a_sim = np.asarray(sim.acceleration(sim.constraint_set(stance, weld), 0.0, q, v)[0])
    tau = sim.forces(0.0, q, v)
    a_pin, _ = _constraint_dynamics(model, cmodels, q, v, tau)
    assert np.max(np.abs(a_sim - a_pin)) > 100.0, "the gap, with or without crank velocity"
    # our independent KKT with the same two crank rows reproduces the simulator
    rows = np.zeros((2, model.nv))
    for k, name in enumerate(("right_j0_crank", "left_j0_crank")):
        rows[k, model.joints[model.getJointId(name)].idx_v] = 1.0
    a_ref, lam = _reference_acceleration(model, cmodels, q, v, tau, rows)
    assert np.max(np.abs(a_ref - a_sim)) < 1e-7 * np.max(np.abs(a_sim))
    # the motor torques (multipliers of the crank rows) applied as joint torques close the gap
    a_pin, _ = _constraint_dynamics(model, cmodels, q, v, tau + rows.T @ lam[-2:])
    assert np.max(np.abs(a_sim - a_pin)) < 1e-8 * np.max(np.abs(a_sim))
    # and without them (free motor) the simulator and constraintDynamics agree directly
    free = BipedSimulator(biped, SimulationSettings(omega=omega, motor="free"))
    a_free = np.asarray(free.acceleration(free.constraint_set(stance, weld), 0.0, q, v)[0])
    a_pin, _ = _constraint_dynamics(model, cmodels, q, v, free.forces(0.0, q, v))
    assert np.max(np.abs(a_free - a_pin)) < 1e-8 * np.max(np.abs(a_free))


# --------------------------------------------------------------------------- 2. dJ of the composite hip
def _dj_fd(model, data, q, v, eps=1e-6):
    pin.computeJointJacobians(model, data, pin.integrate(model, q, eps * v))
    plus = data.J.copy()
    pin.computeJointJacobians(model, data, pin.integrate(model, q, -eps * v))
    return (plus - data.J) / (2 * eps)


def test_jacobian_time_variation_is_wrong_for_the_composite_hip_translation_columns(biped, one_leg):
    model, data = biped.model, biped.model.createData()
    assert model.joints[1].shortname() == "JointModelComposite"
    q = biped.q0 + 0.1 * np.random.default_rng(4).normal(size=model.nv)
    v = np.random.default_rng(5).normal(size=model.nv)
    pin.computeJointJacobiansTimeVariation(model, data, q, v)
    dj = data.dJ.copy()
    fd = _dj_fd(model, data, q, v)
    assert np.max(np.abs(fd[:, 2:] - dj[:, 2:])) < 1e-7, "pitch and every leg column: right"
    assert np.max(np.abs(fd[:, :2])) < 1e-9, "PX, PZ axes are fixed in the world"
    omega = np.array([0.0, -v[2], 0.0])  # the hip pitch turns about -y
    assert np.allclose(dj[:3, 0], np.cross(omega, [1.0, 0.0, 0.0]), atol=1e-12)
    assert np.allclose(dj[:3, 1], np.cross(omega, [0.0, 0.0, 1.0]), atol=1e-12)
    # hence a drift from data.dJ is off by omega x v_hip for every point: (-pitch_rate v_z, pitch_rate v_x)
    error = (dj - fd)[:3] @ v
    assert np.allclose(error, np.cross(omega, [v[0], 0.0, v[1]]), atol=1e-6) and np.max(np.abs(error)) > 0.1
    # hip not turning: right
    v_still = v.copy()
    v_still[2] = 0.0
    pin.computeJointJacobiansTimeVariation(model, data, q, v_still)
    assert np.max(np.abs(data.dJ - _dj_fd(model, data, q, v_still))) < 1e-7
    # the composite's bias acceleration is right: the hip origin has no classical acceleration at zero ddq
    pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
    hip = pin.getClassicalAcceleration(model, data, 1, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
    assert np.max(np.abs(hip.linear)) < 1e-12
    # one leg, fixed hip (no composite): right
    model, data = one_leg.model, one_leg.model.createData()
    q, v = one_leg.q0, np.random.default_rng(6).normal(size=model.nv)
    pin.computeJointJacobiansTimeVariation(model, data, q, v)
    assert np.max(np.abs(data.dJ - _dj_fd(model, data, q, v))) < 1e-7


def test_dj_drift_error_cancels_in_loop_rows_but_not_in_the_weld(biped):
    model, data, cms = biped.model, biped.model.createData(), biped.constraint_models
    q, v = _biped_state(biped, CRANK_RATE, 2.0)
    pin.computeJointJacobiansTimeVariation(model, data, q, v)
    dj, jw = data.dJ.copy(), data.J.copy()
    drift = []
    for cm in cms:  # Jdot v of p1 - p2 from data.dJ: d/dt (J_lin + J_ang x p) v = dJ_lin v - p x dJ_ang v + w x v_p
        rows = np.zeros(3)
        for joint, placement, sign in (
            (cm.joint1_id, cm.joint1_placement, 1.0),
            (cm.joint2_id, cm.joint2_placement, -1.0),
        ):
            if joint == 0:
                continue
            support = np.zeros(model.nv)
            for s in (s for s in model.supports[joint] if s != 0):
                support[model.joints[s].idx_v : model.joints[s].idx_v + model.joints[s].nv] = 1.0
            p = (data.oMi[joint] * placement).translation
            w = jw[3:] @ (support * v)
            v_p = jw[:3] @ (support * v) + np.cross(w, p)
            rows += sign * (dj[:3] @ (support * v) + np.cross(dj[3:] @ (support * v), p) + np.cross(w, v_p))
        drift += [rows[0], rows[2]]
        if _is_weld(cm):
            drift.append(0.0)  # angular rows: not compared
    error = np.array(drift) - _drift(model, data, cms, q, v)
    assert np.max(np.abs(error[:-3])) < 1e-6, "loop rows: the hip error cancels in p1 - p2"
    hip_velocity = v[:2]  # world x, z of the hip origin
    expected = np.array([-v[2] * hip_velocity[1], v[2] * hip_velocity[0]])  # omega x v_hip, omega = (0, -pitch rate, 0)
    assert np.max(np.abs(error[-3:-1] - expected)) < 1e-6 and np.max(np.abs(expected)) > 0.1


# --------------------------------------------------------------------------- impulseDynamics
def test_impulse_dynamics_uses_only_the_first_bodys_velocity(biped):
    model, data = biped.model, biped.model.createData()
    loops = [cm for cm in biped.constraint_models if not _is_weld(cm)]
    q, v = _biped_state(biped, CRANK_RATE, 2.0)
    cdatas = [cm.createData() for cm in loops]
    pin.initConstraintDynamics(model, data, loops, cdatas)
    settings = pin.ProximalSettings(1e-13, MU, 100)
    v_plus = np.array(pin.impulseDynamics(model, data, q, v, loops, cdatas, 0.0, settings))
    full = _pin_jacobian(model, model.createData(), loops, q)
    assert np.max(np.abs(full @ v)) < 1e-12, "v already satisfies the loops: the true impulse is zero"
    assert np.max(np.abs(v_plus - v)) > 1.0 and np.max(np.abs(full @ v_plus)) > 0.1
    v_c1 = np.concatenate(
        [_world_point_velocity(model, data, cm.joint1_id, cm.joint1_placement, q, v)[1] for cm in loops]
    )
    assert np.max(np.abs(full @ (v_plus - v) + v_c1)) < 1e-8, "J (v+ - v-) = -v_c1: joint2's velocity ignored"
    # a weld to the world (joint2 = 0): the KKT impulse [M J^T; J 0][v+; mu] = [M v-; 0]
    weld = [biped.constraint_models[-1]]
    v_minus = np.random.default_rng(7).normal(size=model.nv)
    cdatas = [cm.createData() for cm in weld]
    pin.initConstraintDynamics(model, data, weld, cdatas)
    v_pin = np.array(pin.impulseDynamics(model, data, q, v_minus, weld, cdatas, 0.0, settings))
    mass = _mass(model, data, q)
    v_kkt, _ = _kkt(mass, _jacobian_fd(model, data, weld, q), mass @ v_minus, np.zeros(3))
    assert np.max(np.abs(v_kkt - v_minus)) > 0.1
    assert np.max(np.abs(v_pin - v_kkt)) < 1e-6 * np.max(np.abs(v_kkt))
