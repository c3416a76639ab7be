"""Constrained inverse dynamics of the ``spring`` biped: crank and ankle torques, reactions.

The robot follows a prescribed motion (DESIGN §5, §6): the stance foot is welded flat to the
ground, the hip stays level (pitch 0), the swing foot stays level (or rigid at 90 deg to its
shank), and both cranks turn at constant omega, pi apart. Per sample:

1. q on the constraint manifold by Newton on [c(q); s(q) - s*] (square, factored; the
   in-plane rows of the loop closures and the weld, plus the four prescribed coordinates),
2. v and a from :func:`pasibot_pin.model.closure.solve_velocity` / ``solve_acceleration``
   (exact Jacobians and drift terms), or v = a = 0 (quasi-static),
3. tau = ``pin.rnea(q, v, a)``,
4. the split tau = S^T u + J_c^T lambda with u = [T_a, T_a', tau_ankle, tau_ankle'] (the
   actuated cranks and the two ankles, stance first) and lambda the in-plane constraint forces:
   one square 19 x 19 solve, so the passive joints carry no torque,
5. ``pin.rnea(q, v, a, fext)`` with the constraint forces as external forces gives every tree
   joint's reaction (the force and moment the parent body applies to the child).

Torques are reported as generalised forces of theta (stance crank), beta = pi/2 - q_ankle
(the angle from the forward foot to the shank), theta' and beta': T_a = u[0], T_e = -u[2].
A positive T_e is a counter-clockwise torque of the foot on the shank.

The seed's own method uses second differences of the COM positions (0.1 rad apart) as
accelerations. It is available as ``accelerations="central"`` / ``"lagged"`` (the seed uses
each value one sample late): then tau = rnea(q, 0, 0, fext) with the inertial forces
-m_i a_i of the point masses as external forces.

Units: SI; angles [rad]; torques [N.m]; forces [N].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from functools import lru_cache

import numpy as np
import pinocchio as pin

from pasibot_pin.constraints import coupling, is_weld, split_torques
from pasibot_pin.model import closure
from pasibot_pin.model.closure import Prescribed, frame_pitch, hip_pitch, joint_coordinate
from pasibot_pin.model.params import Geometry, MassModel, percentage_mass_model
from pasibot_pin.model.robot import PasibotRobot, apply_masses, load
from pasibot_pin.model.scenarios import (
    ACCELERATION_MODES,
    SEED_ROUNDED_LINK_MASSES,
    SWING_FOOT_MODES,
    ModelChoices,
    Scenario,
    seed_foot_com,
)
from pasibot_pin.model.variants import MotorLayout, get_motor_layout

STANCE_RANGE: tuple[float, float] = (math.pi / 2, 3 * math.pi / 2)
"""Stance phase of a leg: crank angle theta in [pi/2, 3 pi/2] [rad] (DESIGN §4)."""

STANCE_MARGIN: float = 0.1
"""How far a fit window may reach past the ends of stance [rad]. The seed's last fit sample,
4.8 rad, is 0.088 rad past 3 pi/2: it keeps the right foot welded that long."""


def other(side: str) -> str:
    """The other leg."""
    return "left" if side == "right" else "right"


def stance_side(theta_right: float) -> str:
    """The stance leg for a right-crank angle: right while theta_R is in [pi/2, 3 pi/2) (mod 2 pi)."""
    phase = (theta_right - math.pi / 2) % (2 * math.pi)
    return "right" if phase < math.pi else "left"


def wrap_stance(theta: float) -> float:
    """A stance crank angle mapped to [pi/2, 5 pi/2) [rad]."""
    return math.pi / 2 + (theta - math.pi / 2) % (2 * math.pi)


def check_omega(omega: float) -> float:
    """Return ``omega`` [rad/s] if it is finite and >= 0, else raise ValueError naming it."""
    omega = float(omega)
    if not math.isfinite(omega) or omega < 0:
        raise ValueError(f"parameter 'omega' must be a finite crank speed >= 0 [rad/s], got {omega!r}")
    return omega


def check_fit_window(thetas: Sequence[float]) -> np.ndarray:
    """Validate a fit window of stance-crank angles [rad]: inside stance (+- :data:`STANCE_MARGIN`)."""
    arr = np.asarray(thetas, dtype=float).reshape(-1)
    if arr.size < 2 or not np.all(np.isfinite(arr)):
        raise ValueError("parameter 'fit_thetas' needs at least two finite crank angles [rad]")
    lo, hi = STANCE_RANGE[0] - STANCE_MARGIN, STANCE_RANGE[1] + STANCE_MARGIN
    bad = arr[(arr < lo - 1e-9) | (arr > hi + 1e-9)]
    if bad.size:
        raise ValueError(
            f"parameter 'fit_thetas': {bad[0]:.4f} rad ({math.degrees(bad[0]):.1f} deg) is outside stance "
            f"[{lo:.4f}, {hi:.4f}] rad (theta in [pi/2, 3 pi/2] +- {STANCE_MARGIN} rad)"
        )
    return arr


# --------------------------------------------------------------------------- robots for scenarios
@lru_cache(maxsize=4)
def _base_robot(variant: str, inertia: str) -> PasibotRobot:
    return load(variant, 2, inertia=inertia)


def scenario_masses(
    scenario: Scenario, choices: ModelChoices, geometry: Geometry | None = None, variant: str = "spring"
) -> MassModel:
    """The mass model of ``scenario`` under ``choices`` for ``variant`` [kg, m]."""
    geometry = geometry or Geometry()
    base = percentage_mass_model(geometry, variant)
    links = dict(base.links)
    hip = scenario.body_mass
    foot = base.foot
    if choices.masses == "rounded":
        links.update(SEED_ROUNDED_LINK_MASSES)
        hip = scenario.seed_body_mass
        foot = 1.3
    if choices.swap_l5_l6:
        links["l5"], links["l6"] = links["l6"], links["l5"]
    toe, heel = geometry.foot_extent(variant)
    foot_com = seed_foot_com(toe, heel) if choices.seed_foot else base.foot_com
    return MassModel(
        hip=hip,
        links=links,
        foot=foot,
        foot_com=foot_com,
        hip_com=(scenario.body_com_dx, 0.0),
        rule=f"scenario {scenario.name}, masses {choices.masses}" + (", L5/L6 swapped" if choices.swap_l5_l6 else ""),
    )


def scenario_robot(scenario: Scenario, choices: ModelChoices, variant: str = "spring") -> PasibotRobot:
    """The default biped of ``variant`` with the masses of ``scenario`` under ``choices`` (a copy)."""
    base = _base_robot(variant, choices.inertia)
    masses = scenario_masses(scenario, choices, base.geometry, variant)
    model = pin.Model(base.model)
    apply_masses(model, masses, base.geometry, variant, 2, choices.inertia)
    return replace(
        base, model=model, data=model.createData(), masses=masses, constraint_models=list(base.constraint_models)
    )


# --------------------------------------------------------------------------- results
@dataclass
class TorqueResult:
    """Torques and reactions along a prescribed motion, one row per sample.

    Attributes:
        t: time [s] (for omega = 0: crank progress in rad, read as seconds at 1 rad/s).
        theta_right: right crank angle [rad].
        theta: stance crank angle, in [pi/2, 5 pi/2) [rad].
        stance: stance side per sample.
        beta: stance ankle angle, forward foot to shank [rad].
        beta_swing: swing ankle angle [rad].
        Ta, Te, Ta_swing, Te_swing: generalised forces of theta, beta, theta', beta' [N.m]
            (Te, Te_swing are zero without a spring ankle; with one motor, Ta is the motor's
            torque on the right crank shaft and Ta_swing is zero).
        q, v, a: the motion (N x nq, N x nv, N x nv).
        tau: rnea torques (N x nv) [N.m, N].
        ground: ground reaction on the stance foot at its ankle: Fx, Fz [N], CCW moment [N.m].
        cuts: cut joint -> (N x 2) force on the first link of the pair (x, z) [N]; names are
            generic (``stance_j2``, ``swing_j5`` ...).
        joints: tree joint (generic name) -> (N x 3): force of the parent on the child (x, z) [N]
            and CCW moment about the joint [N.m].
        omega: crank speed [rad/s].
        accelerations: ``exact``, ``central``, ``lagged`` or ``none`` (quasi-static).
        swing_foot: ``level`` or ``square``.
        motors: ``two`` or ``one`` (:data:`pasibot_pin.model.variants.MOTOR_LAYOUTS`).
        transmission: with one motor, the torque the coupling delivers to the left crank [N.m].

    """

    t: np.ndarray
    theta_right: np.ndarray
    theta: np.ndarray
    stance: list[str]
    beta: np.ndarray
    beta_swing: np.ndarray
    Ta: np.ndarray
    Te: np.ndarray
    Ta_swing: np.ndarray
    Te_swing: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    tau: np.ndarray
    ground: np.ndarray
    cuts: dict[str, np.ndarray] = field(default_factory=dict)
    joints: dict[str, np.ndarray] = field(default_factory=dict)
    omega: float = 0.0
    accelerations: str = "exact"
    swing_foot: str = "level"
    motors: str = "two"
    transmission: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.t)

    def columns(self) -> dict[str, np.ndarray]:
        """The CSV columns (SI units): t, theta, beta, Ta, Te, Ta_swing, Te_swing, then more."""
        cols = {
            "t": self.t,
            "theta": self.theta,
            "beta": self.beta,
            "Ta": self.Ta,
            "Te": self.Te,
            "Ta_swing": self.Ta_swing,
            "Te_swing": self.Te_swing,
            "theta_right": self.theta_right,
            "stance_right": np.array([1.0 if s == "right" else 0.0 for s in self.stance]),
            "beta_swing": self.beta_swing,
            "ground_Fx": self.ground[:, 0],
            "ground_Fz": self.ground[:, 1],
            "ground_M": self.ground[:, 2],
        }
        for name, arr in self.cuts.items():
            cols[f"{name}_Fx"], cols[f"{name}_Fz"] = arr[:, 0], arr[:, 1]
        for name, arr in self.joints.items():
            cols[f"{name}_Fx"], cols[f"{name}_Fz"], cols[f"{name}_M"] = arr[:, 0], arr[:, 1], arr[:, 2]
        return cols


# --------------------------------------------------------------------------- per-sample pieces
def _generic(name: str, stance: str) -> str:
    side, rest = name.split("_", 1)
    return ("stance_" if side == stance else "swing_") + rest


def _prescriptions(robot: PasibotRobot, stance: str, swing_foot: str) -> list[Prescribed]:
    """Both cranks; with a free ankle (the variant's record) also the hip pitch and the swing foot."""
    rows = [joint_coordinate(robot, j) for j in robot.actuated_joints]
    if robot.spec.free_ankle:
        swing = other(stance)
        ankle = f"{swing}_{robot.spec.spring_joints[0]}"
        last = frame_pitch(robot, f"{swing}_foot") if swing_foot == "level" else joint_coordinate(robot, ankle)
        rows += [hip_pitch(robot), last]
    return rows


def _actuated(robot: PasibotRobot, stance: str, layout: MotorLayout) -> list[str]:
    """The actuated joints, in the order of u: the motor(s), then the stance and swing spring joints.

    Two motors: stance crank, swing crank. One motor: the layout's motor (the right crank).
    """
    swing = other(stance)
    if len(layout.motors) == 2:
        motors = [f"{stance}_j0_crank", f"{swing}_j0_crank"]
    else:
        motors = list(layout.motors)
    return motors + [f"{side}_{j}" for side in (stance, swing) for j in robot.spec.spring_joints]


def _actuation(robot: PasibotRobot, stance: str, layout: MotorLayout | str = "two") -> np.ndarray:
    """S (n_u x nv): one row per actuated joint of :func:`_actuated`."""
    joints = _actuated(robot, stance, get_motor_layout(layout))
    s = np.zeros((len(joints), robot.model.nv))
    for row, joint in enumerate(joints):
        s[row, robot.idx_v(joint)] = 1.0
    return s


def _couplings(robot: PasibotRobot, layout: MotorLayout) -> list:
    """The layout's coupling rows (one motor: q_L - q_R - pi = 0) on ``robot``."""
    return [coupling(f"{a}-{b}", robot.idx_v(a), robot.idx_v(b), offset) for a, b, offset in layout.couplings]


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def constraint_fext(robot: PasibotRobot, q: np.ndarray, cmodels, lam: np.ndarray, fext: list[pin.Force] | None = None):
    """External forces (joint-local ``pin.Force`` list) equivalent to J_c^T lambda (in-plane rows).

    A point constraint's (lambda_x, lambda_z) acts on its first frame, the opposite on its
    second; a weld's third row is a counter-clockwise moment on the welded body.
    """
    model, data = robot.model, robot.data
    pin.forwardKinematics(model, data, q)
    joints, unique, inverse, trans, sign, row_x, row_z, row_m = _fext_layout(robot, cmodels)
    lam = np.asarray(lam, dtype=float)
    force = np.zeros((len(joints), 3))
    force[:, 0], force[:, 2] = sign * lam[row_x], sign * lam[row_z]
    moment_y = np.where(row_m >= 0, -sign * lam[np.maximum(row_m, 0)], 0.0)
    rot = np.array([data.oMi[j].rotation for j in unique])[inverse]  # (E, 3, 3)
    f_local = np.einsum("eji,ej->ei", rot, force)  # R^T f
    m_local = np.cross(trans, f_local) + rot[:, 1, :] * moment_y[:, None]  # R^T (0, m_y, 0)
    wrench = np.zeros((model.njoints, 6))
    np.add.at(wrench, joints, np.hstack((f_local, m_local)))
    out = [pin.Force(w[:3], w[3:]) for w in wrench]
    if fext is not None:
        out = [f + g for f, g in zip(fext, out)]
    return out


def _fext_layout(robot: PasibotRobot, cmodels):
    """Per constraint end on a moving joint: joint, local point, sign and the rows of its lambda (cached)."""
    cache = robot.__dict__.setdefault("_fext_cache", {})
    key = (id(robot.model), tuple(id(cm) for cm in cmodels))
    if key in cache:
        return cache[key][1]
    joints, trans, sign, row_x, row_z, row_m = [], [], [], [], [], []
    r = 0
    for cm in cmodels:
        weld = is_weld(cm)
        for joint, placement, sgn in (
            (cm.joint1_id, cm.joint1_placement, 1.0),
            (cm.joint2_id, cm.joint2_placement, -1.0),
        ):
            if joint == 0:
                continue
            joints.append(int(joint))
            trans.append(np.array(placement.translation))
            sign.append(sgn)
            row_x.append(r)
            row_z.append(r + 1)
            row_m.append(r + 2 if weld else -1)
        r += 3 if weld else 2
    unique, inverse = np.unique(joints, return_inverse=True)
    layout = (
        np.array(joints, dtype=int),
        [int(j) for j in unique],
        inverse.reshape(-1),
        np.array(trans).reshape(-1, 3),
        np.array(sign),
        np.array(row_x, dtype=int),
        np.array(row_z, dtype=int),
        np.array(row_m, dtype=int),
    )
    cache[key] = (list(cmodels), layout)  # the entry keeps the models alive: no id reuse
    return layout


def ankle_angle(robot: PasibotRobot, q: np.ndarray, side: str) -> float:
    """Beta of ``side``: the angle from the forward foot (sole, heel -> toe) to the shank (ankle -> knee) [rad].

    With a spring ankle it is pi/2 - q_ankle; otherwise it is read from the frames at ``q``
    (pi/2 for the rigid foot; the parallel extension's foot follows the stabiliser).
    """
    if robot.spec.free_ankle:
        return math.pi / 2 - q[robot.idx_q(f"{side}_{robot.spec.spring_joints[0]}")]
    model, data = robot.model, robot.data
    pin.forwardKinematics(model, data, q)
    shank = pin.updateFramePlacement(model, data, robot.frame_id(f"{side}_l5_shank")).rotation
    toe = pin.updateFramePlacement(model, data, robot.frame_id(f"{side}_toe")).translation
    heel = pin.updateFramePlacement(model, data, robot.frame_id(f"{side}_heel")).translation
    up = math.atan2(-shank[2, 0], -shank[0, 0])  # ankle -> knee is minus the shank's x axis
    sole = math.atan2(toe[2] - heel[2], toe[0] - heel[0])
    return math.remainder(up - sole, 2 * math.pi)


def com_positions(robot: PasibotRobot, q: np.ndarray) -> np.ndarray:
    """World COM of every joint's body (njoints x 3) [m] (row 0 unused)."""
    model, data = robot.model, robot.data
    pin.forwardKinematics(model, data, q)
    out = np.zeros((model.njoints, 3))
    for j in range(1, model.njoints):
        out[j] = data.oMi[j].act(model.inertias[j].lever)
    return out


def inertial_fext(robot: PasibotRobot, q: np.ndarray, com_acc: np.ndarray) -> list[pin.Force]:
    """The point masses' inertial forces -m_i a_i (world COM accelerations, njoints x 3) as joint-local forces."""
    model, data = robot.model, robot.data
    pin.forwardKinematics(model, data, q)
    fext = [pin.Force.Zero() for _ in range(model.njoints)]
    for j in range(1, model.njoints):
        inertia = model.inertias[j]
        if inertia.mass == 0.0:
            continue
        f_local = data.oMi[j].rotation.T @ (-inertia.mass * com_acc[j])
        fext[j] = pin.Force(f_local, _cross(inertia.lever, f_local))
    return fext


def joint_reactions(robot: PasibotRobot, q, v, a, fext) -> np.ndarray:
    """Force of each parent on its child at every tree joint: (njoints x 3) Fx, Fz [N], CCW moment [N.m].

    From ``pin.rnea(q, v, a, fext)`` with every external force (constraint forces included):
    ``data.f[j]`` is the spatial force transmitted through joint j, at its origin.
    """
    model, data = robot.model, robot.data
    pin.forwardKinematics(model, data, q)
    pin.rnea(model, data, q, v, a, fext)
    joints = range(1, model.njoints)
    rot = np.array([data.oMi[j].rotation for j in joints])  # (J, 3, 3)
    wrench = np.array([data.f[j].vector for j in joints])  # (J, 6): linear, angular in the joint frame
    lin = np.einsum("jik,jk->ji", rot, wrench[:, :3])
    ang_y = np.einsum("jk,jk->j", rot[:, 1, :], wrench[:, 3:])
    out = np.zeros((model.njoints, 3))
    out[1:, 0], out[1:, 1], out[1:, 2] = lin[:, 0], lin[:, 2], -ang_y
    return out


# --------------------------------------------------------------------------- trajectory
def crank_grid(start: float, stop: float, samples: int) -> np.ndarray:
    """``samples`` right-crank angles from ``start`` to ``stop`` inclusive [rad]."""
    if samples < 2:
        raise ValueError(f"parameter 'samples' must be >= 2, got {samples!r}")
    return np.linspace(start, stop, int(samples))


def inverse_dynamics(
    robot: PasibotRobot,
    thetas: Sequence[float],
    omega: float,
    *,
    swing_foot: str = "level",
    accelerations: str = "exact",
    step: float = 0.1,
    stance: str = "auto",
    reactions: bool = True,
    motors: str | MotorLayout = "two",
) -> TorqueResult:
    """Constrained inverse dynamics along a crank sweep, for every variant and motor layout.

    What is prescribed and what is actuated comes from the variant's record: both cranks
    always; with a free (spring) ankle also the hip pitch and the swing foot, and the two
    ankles are actuated (their torques are what a spring must give). With ``motors="one"``
    one motor drives the right crank and the coupling q_L - q_R - pi = 0 is a constraint row:
    its multiplier is the torque the transmission delivers to the left crank.

    Args:
        robot: a two-legged robot of any variant (e.g. :func:`scenario_robot`).
        thetas: right-crank angles, increasing [rad]; the left crank is pi ahead.
        omega: crank speed [rad/s]; 0 = quasi-static (v = a = 0).
        swing_foot: ``level`` (pitch 0) or ``square`` (swing ankle at 0: foot at 90 deg to its shank).
        accelerations: ``exact`` (closure derivatives), ``central`` or ``lagged`` (second
            differences of the COM positions, crank step ``step``; lagged = the seed's).
        step: crank step of the differences [rad].
        stance: ``auto`` (stance swaps every half turn), ``right`` or ``left`` (held throughout).
        reactions: compute the tree-joint reactions (``joints``); off saves time when only
            the torques are needed.
        motors: ``two`` (one per crank) or ``one`` (one motor, cranks coupled pi apart).

    Returns:
        A :class:`TorqueResult`.

    Raises:
        ValueError: bad omega, mode, thetas; a pose where the loops cannot close.

    """
    omega = check_omega(omega)
    layout = get_motor_layout(motors)
    if robot.legs != 2:
        raise ValueError(f"inverse_dynamics needs a two-legged robot (load(..., legs=2)), got legs={robot.legs}")
    if swing_foot not in SWING_FOOT_MODES:
        raise ValueError(f"unknown swing_foot {swing_foot!r}; valid: {', '.join(SWING_FOOT_MODES)}")
    if accelerations not in ACCELERATION_MODES:
        raise ValueError(f"unknown accelerations {accelerations!r}; valid: {', '.join(ACCELERATION_MODES)}")
    if stance not in ("auto", "right", "left"):
        raise ValueError(f"unknown stance {stance!r}; valid: auto, right, left")
    if not (math.isfinite(step) and step > 0):
        raise ValueError(f"parameter 'step' must be a positive angle [rad], got {step!r}")
    thetas = np.asarray(thetas, dtype=float).reshape(-1)
    if thetas.size < 1 or not np.all(np.isfinite(thetas)):
        raise ValueError("parameter 'thetas' must be a non-empty sequence of finite crank angles [rad]")
    if thetas.size > 1 and np.any(np.diff(thetas) <= 0):
        raise ValueError("parameter 'thetas' must be strictly increasing")
    if accelerations != "exact" and robot.inertia != "point" and omega > 0:
        raise ValueError("difference accelerations need point masses (inertia='point')")

    model = robot.model
    n, nv = thetas.size, model.nv
    quasi_static = omega == 0.0
    mode = "none" if quasi_static else accelerations
    out = {k: np.zeros(n) for k in ("beta", "beta_swing", "Ta", "Te", "Ta_swing", "Te_swing")}
    qs, vs, accs, taus = np.zeros((n, model.nq)), np.zeros((n, nv)), np.zeros((n, nv)), np.zeros((n, nv))
    ground = np.zeros((n, 3))
    cuts: dict[str, np.ndarray] = {}
    joints: dict[str, np.ndarray] = {}
    sides_used: list[str] = []

    spec = robot.spec
    free = [0.0, 0.0] if spec.free_ankle else []  # hip pitch and swing foot held (spring variant)
    n_motor = len(layout.motors)
    transmission = np.zeros(n)
    current = None
    q_prev = None
    theta_prev, predictor = 0.0, None
    rs = rows = s_matrix = prescribed = coupling_jac = None
    cut_rows: list[tuple[str, int, bool]] = []
    joint_names: list[tuple[int, str]] = []
    stance_x = 0.0
    for k, theta in enumerate(thetas):
        side = stance_side(theta) if stance == "auto" else stance
        if side != current:
            if q_prev is not None:  # the landing foot becomes the stance foot where it lands
                switch = math.pi / 2 + math.pi * math.floor((theta - math.pi / 2) / math.pi)
                q_land = rows.project(q_prev, targets=[switch, switch + math.pi, *free])
                pin.framesForwardKinematics(model, rs.data, q_land)
                stance_x = float(rs.data.oMf[rs.frame_id(f"{side}_foot")].translation[0])
            q_start = closure.assemble(robot, float(theta), stance=side, ankle_x=stance_x)
            rs = robot.with_stance(side, q_start)
            prescribed = _prescriptions(rs, side, swing_foot)
            rows = closure.system(rs, rs.constraint_models, prescribed)
            s_matrix = _actuation(rs, side, layout)
            # the motor couplings are constraint rows of the force split (constant Jacobian)
            coupling_jac = closure.system(rs, [], _couplings(rs, layout)).jacobian(q_start)
            q_prev, theta_prev, predictor = q_start, theta, None
            current = side
            # generic names (stance_/swing_) of the cut rows and tree joints, once per stance
            cut_rows, r = [], 0
            for cm in rs.constraint_models:
                cut_rows.append((_generic(cm.name, side), r, is_weld(cm)))
                r += 3 if is_weld(cm) else 2
            joint_names = [(j, _generic(model.names[j], side)) for j in range(2, model.njoints)]
        targets = [theta, theta + math.pi, *free]
        guess = q_prev
        if predictor is not None:  # first-order predictor along the manifold: dq/dtheta (theta - theta_prev)
            guess = pin.integrate(model, q_prev, predictor * (theta - theta_prev))
        q = rows.project(guess, targets=targets)
        q_prev, theta_prev = q, theta
        cms = rs.constraint_models
        if quasi_static:
            v = a = np.zeros(nv)
            jac = rows.last_rows.jac
        else:
            v, a, jac = rows.motion(q, [omega, omega, *free], [0.0] * len(targets), rows.last_rows.jac)
        if mode in ("central", "lagged"):
            offsets = (-1, 0, 1) if mode == "central" else (0, 1, 2)
            coms = []
            for j in offsets:
                qj = q if j == 0 else rows.project(q, targets=[theta + j * step, theta + j * step + math.pi, *free])
                coms.append(com_positions(rs, qj))
            dt = step / omega
            com_acc = (coms[2] - 2 * coms[1] + coms[0]) / dt**2
            fext_inertia = inertial_fext(rs, q, com_acc)
            tau = pin.rnea(model, rs.data, q, np.zeros(nv), np.zeros(nv), fext_inertia)
            v_id = a_id = np.zeros(nv)
        else:
            fext_inertia = None
            tau = pin.rnea(model, rs.data, q, v, a)
            v_id, a_id = v, a
        nc = rows.n_constraint_rows
        u, lam_all = split_torques(tau, s_matrix, np.vstack((jac[:nc], coupling_jac)))
        lam = lam_all[:nc]
        if not quasi_static:
            predictor = v / omega
        if reactions:
            fext = constraint_fext(rs, q, cms, lam, fext_inertia)
            reac = joint_reactions(rs, q, v_id, a_id, fext)

        swing = other(side)
        out["beta"][k], out["beta_swing"][k] = ankle_angle(rs, q, side), ankle_angle(rs, q, swing)
        out["Ta"][k] = u[0]
        if n_motor == 2:
            out["Ta_swing"][k] = u[1]
        else:
            transmission[k] = lam_all[nc]
        if spec.free_ankle:
            out["Te"][k], out["Te_swing"][k] = -u[n_motor], -u[n_motor + 1]
        qs[k], vs[k], accs[k], taus[k] = q, v, a, tau
        for name, r, weld in cut_rows:
            if weld:
                ground[k] = lam[r : r + 3]
            else:
                cuts.setdefault(name, np.zeros((n, 2)))[k] = lam[r : r + 2]
        if reactions:
            for j, name in joint_names:
                joints.setdefault(name, np.zeros((n, 3)))[k] = reac[j]
        sides_used.append(side)

    theta_stance = np.array([wrap_stance(th if s == "right" else th + math.pi) for th, s in zip(thetas, sides_used)])
    t = (thetas - thetas[0]) / (omega if omega > 0 else 1.0)
    return TorqueResult(
        t=t,
        theta_right=thetas,
        theta=theta_stance,
        stance=sides_used,
        q=qs,
        v=vs,
        a=accs,
        tau=taus,
        ground=ground,
        cuts=cuts,
        joints=joints,
        omega=omega,
        accelerations=mode,
        swing_foot=swing_foot,
        motors=layout.name,
        transmission=transmission,
        **out,
    )


# --------------------------------------------------------------------------- scenarios
def default_thetas(choices: ModelChoices, samples: int = 61) -> np.ndarray:
    """The right-crank samples of a run: the seed window if the choices fix one, else one stance [rad]."""
    if choices.fit_thetas is not None:
        return check_fit_window(choices.fit_thetas)
    return crank_grid(STANCE_RANGE[0], STANCE_RANGE[1], samples)


def run_scenario(
    scenario: Scenario,
    choices: ModelChoices,
    thetas: Sequence[float] | None = None,
    omega: float | None = None,
    reactions: bool = True,
) -> TorqueResult:
    """Inverse dynamics of one scenario under one set of modelling choices.

    Args:
        scenario: crank speed, body mass and COM.
        choices: the modelling choices (a preset or a variation).
        thetas: right-crank samples [rad] (default :func:`default_thetas`: one stance
            theta in [pi/2, 3 pi/2], or the choices' window, with the right foot welded
            throughout, as the seed does); given samples swap the stance every half turn.
        omega: override the scenario's crank speed [rad/s].
        reactions: compute the tree-joint reactions.

    """
    omega = check_omega(scenario.omega if omega is None else omega)
    robot = scenario_robot(scenario, choices)
    held = thetas is None  # one stance (or the seed window): the right foot stays welded, as in the seed
    thetas = default_thetas(choices) if thetas is None else np.asarray(thetas, dtype=float)
    return inverse_dynamics(
        robot,
        thetas,
        omega,
        swing_foot=choices.swing_foot,
        accelerations=choices.accelerations,
        step=choices.step,
        stance="right" if held else "auto",
        reactions=reactions,
    )
