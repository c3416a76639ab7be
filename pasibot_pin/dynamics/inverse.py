"""Constrained inverse dynamics of the ``spring`` biped: crank and ankle torques, reactions.

The robot follows a prescribed motion (DESIGN §5, §6): the stance foot is welded flat to the
ground, the hip stays level (pitch 0), the swing foot stays level (or rigid at 90 deg to its
shank), and both cranks turn at constant omega, pi apart. Each stance of a sweep is done in
one batch (its constant parts, :class:`_StancePlan`, are set up once and cached):

1. q, v and a of every sample from the closed form of the legs on second-order jets
   (:func:`pasibot_pin.model.closure.analytic_motion`: exact to round-off, no Jacobian solve),
   checked by one batched evaluation of the in-plane rows of the loop closures and the weld plus
   the four prescribed coordinates; only where they do not close does a batched Newton on
   [c(q); s(q) - s*] polish q, and then v and a come from the exact Jacobians and drift terms
   (``ConstraintSystem.motion_many``); v = a = 0 when quasi-static,
2. tau = ``pin.rnea(q, v, a)`` of every sample by the batched planar inverse dynamics
   (:mod:`pasibot_pin.dynamics.planar_id`: the bodies' wrenches m (a_c - g), I_yy alpha summed
   over each joint's subtree; no per-sample call; equal to Pinocchio's rnea to round-off),
3. the split tau = S^T u + J_c^T lambda with u = [T_a, T_a', tau_ankle, tau_ankle'] (the
   actuated cranks and the two ankles, stance first) and lambda the in-plane constraint forces:
   one square 19 x 19 solve per sample, so the passive joints carry no torque,
4. every tree joint's reaction (the force and moment the parent body applies to the child): the
   same subtree sums minus the constraint forces on the subtree (what ``pin.rnea(q, v, a, fext)``
   transmits).

Torques are reported as generalised forces of theta (stance crank), beta = pi/2 - q_ankle
(the angle from the forward foot to the shank), theta' and beta': T_a = u[0], T_e = -u[2].
A positive T_e is a counter-clockwise torque of the foot on the shank.

The seed's own method uses second differences of the COM positions (0.1 rad apart) as
accelerations. It is available as ``accelerations="central"`` / ``"lagged"`` (the seed uses
each value one sample late): then tau is that of the point masses' inertial forces m_i (a_i - g)
(rnea(q, 0, 0, fext) with the forces -m_i a_i as external forces).

Units: SI; angles [rad]; torques [N.m]; forces [N].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from functools import lru_cache

import numpy as np
import pinocchio as pin

from pasibot_pin.constraints import ConstraintSystem, coupling, frame_rows, is_weld, planar_rows
from pasibot_pin.constraints.planar import PlanarRowBlocks
from pasibot_pin.dynamics.newton_euler import TreeLayout, tree_layout
from pasibot_pin.dynamics.planar_id import PlanarInverseDynamics, planar_inverse_dynamics
from pasibot_pin.model import closure
from pasibot_pin.model.closure import Prescribed, frame_pitch, hip_pitch, joint_coordinate
from pasibot_pin.model.coordinates import other
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


def stance_side(theta_right: float) -> str:
    """The stance leg for a right-crank angle: right while theta_R is in [pi/2, 3 pi/2) (mod 2 pi)."""
    phase = (theta_right - math.pi / 2) % (2 * math.pi)
    return "right" if phase < math.pi else "left"


def sweep_stances(thetas: np.ndarray, stance: str = "auto") -> list[str]:
    """The stance side of every sample of a sweep of right-crank angles.

    ``auto``: :func:`stance_side` (a touchdown angle pi/2 + k pi starts the new stance), except
    that a sweep that *ends* exactly at a touchdown keeps its last stance there: a grid over one
    stance, theta in [pi/2, 3 pi/2] inclusive, is one stance (double support at both ends).
    """
    if stance != "auto":
        return [stance] * len(thetas)
    right = np.remainder(np.asarray(thetas, dtype=float) - math.pi / 2, 2 * math.pi) < math.pi  # stance_side
    sides = ["right" if r else "left" for r in right.tolist()]
    if len(sides) > 1 and sides[-1] != sides[-2]:
        turns = (thetas[-1] - math.pi / 2) / math.pi
        if abs(turns - round(turns)) < 1e-9:
            sides[-1] = sides[-2]
    return sides


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


_ANKLE_ENDS: dict[tuple[int, str], tuple[pin.Model, PlanarRowBlocks]] = {}


def _ankle_ends(robot: PasibotRobot, side: str) -> PlanarRowBlocks:
    """The shank frame's pitch and the toe and heel positions of ``side``, as planar rows (cached)."""
    cache = _ANKLE_ENDS
    key = (id(robot.model), side)
    if key not in cache or cache[key][0] is not robot.model:
        model = robot.model
        frames = [robot.frame_id(f"{side}_{name}") for name in ("l5_shank", "toe", "heel")]
        if len(cache) >= 32:
            cache.pop(next(iter(cache)))
        cache[key] = (model, frame_rows(model, frames, [1, 2], [0]))  # keeps the model alive
    return cache[key][1]


def ankle_angles(robot: PasibotRobot, q: np.ndarray, side: str) -> np.ndarray:
    """Beta of ``side`` for configurations q (N, nq): from the forward foot (heel -> toe) to the shank [rad].

    With a spring ankle it is pi/2 - q_ankle; otherwise it is read from the frames
    (pi/2 for the rigid foot; the parallel extension's foot follows the stabiliser).
    """
    q = np.atleast_2d(q)
    if robot.spec.free_ankle:
        return math.pi / 2 - q[:, robot.idx_q(f"{side}_{robot.spec.spring_joints[0]}")]
    ends = _ankle_ends(robot, side)
    points, pitch = ends.positions(q), q @ ends.pitch_A.T + ends.pitch_a0
    up = pitch[:, 0] + math.pi  # ankle -> knee is minus the shank's x axis
    sole = np.angle(points[:, 0] - points[:, 1])
    diff = up - sole
    return diff - 2 * math.pi * np.round(diff / (2 * math.pi))  # math.remainder, elementwise


def ankle_angle(robot: PasibotRobot, q: np.ndarray, side: str) -> float:
    """Beta of ``side`` at one configuration [rad] (:func:`ankle_angles`)."""
    return float(ankle_angles(robot, q, side)[0])


# --------------------------------------------------------------------------- one stance, set up once
@dataclass
class _StancePlan:
    """Everything of one stance of a sweep that does not change from sample to sample (cached).

    Attributes:
        robot: the robot standing on ``side`` with the stance weld.
        rows: the square constraint system (loops, weld, prescribed coordinates).
        s_matrix: the actuation S (n_u, nv).
        actuated: the column of each row of S (S selects coordinates); passive: the other columns.
        coupling: the motor-coupling rows C (n_c, nv) (constant).
        tree: the batched Newton-Euler layout (COMs, joint origins, constraint ends).
        planar: the batched planar inverse dynamics on ``tree`` (torques and reactions).
        angular: mask of the angle coordinates (unwrapped along a sweep).
        weld_rows: the weld's rows of lambda; cut_rows: generic name of every loop -> its rows.
        joint_names: generic name of every tree joint 2 .. njoints - 1 -> its index.
        model_copy: the model as the plan was made (a plan is stale once the model changes).

    """

    robot: PasibotRobot
    rows: ConstraintSystem
    s_matrix: np.ndarray
    actuated: np.ndarray
    passive: np.ndarray
    coupling: np.ndarray
    tree: TreeLayout
    planar: PlanarInverseDynamics
    angular: np.ndarray
    weld_rows: slice
    cut_rows: dict[str, slice]
    joint_names: dict[str, int]
    model_copy: pin.Model


_PLANS: dict[tuple, tuple[pin.Model, _StancePlan]] = {}


def _stance_plan(robot: PasibotRobot, side: str, swing_foot: str, layout: MotorLayout, stance_x: float) -> _StancePlan:
    """The :class:`_StancePlan` of ``robot`` standing on ``side`` with its ankle at x = ``stance_x`` [m]."""
    model = robot.model
    key = (id(model), side, swing_foot, layout.name, float(stance_x))
    cached = _PLANS.get(key)
    if cached is not None and cached[0] is model and cached[1].model_copy == model:
        return cached[1]
    rs = robot.with_weld(side, closure.stance_weld(robot, side, stance_x))
    rows = closure.system(rs, rs.constraint_models, _prescriptions(rs, side, swing_foot))
    coupling_rows = closure.system(rs, [], _couplings(rs, layout))
    weld_rows, cut_rows = slice(0, 0), {}
    for cm, rows_of in zip(rs.constraint_models, planar_rows(rs.constraint_models)):
        if is_weld(cm):
            weld_rows = rows_of
        else:
            cut_rows[_generic(cm.name, side)] = rows_of
    tree = tree_layout(model, rs.constraint_models)
    s_matrix = _actuation(rs, side, layout)
    entry = _StancePlan(
        robot=rs,
        rows=rows,
        s_matrix=s_matrix,
        actuated=np.argmax(s_matrix, axis=1),
        passive=np.nonzero(~s_matrix.any(axis=0))[0],
        coupling=coupling_rows.jacobian(pin.neutral(model)).reshape(-1, model.nv),
        tree=tree,
        planar=planar_inverse_dynamics(model, tree),
        angular=closure.angular_coordinates(model),
        weld_rows=weld_rows,
        cut_rows=cut_rows,
        joint_names={_generic(model.names[j], side): j for j in range(2, model.njoints)},
        model_copy=pin.Model(model),
    )
    if len(_PLANS) >= 32:
        _PLANS.pop(next(iter(_PLANS)))
    _PLANS[key] = (model, entry)  # keeps the model alive: no id reuse
    return entry


def _split(tau: np.ndarray, jac_t: np.ndarray, actuated: np.ndarray, passive: np.ndarray):
    """Solve tau = S^T u + J^T lambda for a batch, S selecting the ``actuated`` coordinates.

    The passive coordinates carry no actuator: J_P^T lambda = tau_P is square (one solve per
    sample, nv - n_u unknowns), then u = tau_A - J_A^T lambda.

    Args:
        tau: joint torques (N, nv) [N.m, N].
        jac_t: J^T (N, nv, m) of the constraint rows (m = nv - n_u).
        actuated: the coordinate of each actuator, in the order of u (n_u,).
        passive: the other coordinates (nv - n_u,).

    Returns:
        (u (N, n_u), lambda (N, m)).

    Raises:
        ValueError: when J_P^T is not square or singular (the actuators cannot hold the motion).

    """
    if jac_t.shape[2] != len(passive):
        n_unknowns = jac_t.shape[2] + len(actuated)
        raise ValueError(f"split: {n_unknowns} unknowns for nv = {jac_t.shape[1]}; the system must be square")
    try:
        lam = np.linalg.solve(jac_t[:, passive], tau[:, passive, None])
    except np.linalg.LinAlgError as err:
        raise ValueError("split: [S^T J_c^T] is singular at this pose") from err
    if not np.all(np.isfinite(lam)):
        raise ValueError("split: the actuator and constraint forces are not finite")
    return tau[:, actuated] - (jac_t[:, actuated] @ lam)[:, :, 0], lam[:, :, 0]


# --------------------------------------------------------------------------- trajectory
def _segments(sides: list[str]) -> list[tuple[int, int]]:
    """(start, stop) of each run of samples with the same stance side."""
    bounds = [0] + [k for k in range(1, len(sides)) if sides[k] != sides[k - 1]] + [len(sides)]
    return list(zip(bounds[:-1], bounds[1:]))


def _shift(delta: float, free: list[float]) -> np.ndarray:
    """Move both crank targets by ``delta`` [rad], the held rows not."""
    return np.array([delta, delta] + [0.0] * len(free))


def _stance_guess(robot, thetas, swing_pitch, side, stance_x, angular) -> np.ndarray:
    """The analytic assembly along ``thetas``, q (N, nq), closed to round-off (a batched Newton checks it).

    The angles are unwrapped along the sweep, as a continuation would carry them.
    """
    guess, _ = closure.analytic_configurations(robot, thetas, None, 0.0, swing_pitch, side, stance_x)
    _unwrap(guess, angular)
    return guess


def _unwrap(q: np.ndarray, angular: np.ndarray) -> None:
    """Unwrap the angle columns of q (N, nq) along the sweep, in place (as ``np.unwrap``: steps below pi)."""
    if len(q) < 2:
        return
    turns = np.round(np.diff(q[:, angular], axis=0) * (0.5 / math.pi))  # whole turns between samples
    if turns.any():
        q[1:, angular] -= (2 * math.pi) * np.cumsum(turns, axis=0)


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
    cut_names: list[str] = []  # in the first stance's order (the columns of the CSV)
    joint_names: list[str] = []
    cut_forces = joint_forces = np.zeros((n, 0, 3))
    sides_used = sweep_stances(thetas, stance)

    spec = robot.spec
    free = [0.0, 0.0] if spec.free_ankle else []  # hip pitch and swing foot held (spring variant)
    swing_pitch = 0.0 if swing_foot == "level" else None
    n_motor = len(layout.motors)
    transmission = np.zeros(n)
    rates = np.array([omega, omega, *free])
    stance_x = 0.0
    previous = None  # (rows, last q) of the previous stance
    for i0, i1 in _segments(sides_used):
        side, th = sides_used[i0], thetas[i0:i1]
        if previous is not None:  # the landing foot becomes the stance foot where it lands
            switch = math.pi / 2 + math.pi * math.floor((th[0] - math.pi / 2) / math.pi)
            q_land = previous[0].project(previous[1], targets=[switch, switch + math.pi, *free])
            pin.framesForwardKinematics(model, robot.data, q_land)
            stance_x = float(robot.data.oMf[robot.frame_id(f"{side}_foot")].translation[0])
        plan = _stance_plan(robot, side, swing_foot, layout, stance_x)
        rs, rows, tree = plan.robot, plan.rows, plan.tree
        # q, v and a of the whole stance from the closed form and its exact time derivatives (jets);
        # one batched evaluation of the rows checks the closure (Newton polishes only if it is open)
        guess, v, a, _ = closure.analytic_motion(rs, th, omega, swing_pitch, side, stance_x)
        _unwrap(guess, plan.angular)
        targets = np.column_stack([th, th + math.pi] + [np.full(th.size, f) for f in free])
        q, closed = rows.project_many(guess, targets)
        if not np.array_equal(q, guess):  # polished: v and a by the constraint core at the new q
            v, a, _ = rows.motion_many(q, rates, np.zeros_like(rates), closed.jac)
        if mode in ("central", "lagged"):
            offsets = (-1, 0, 1) if mode == "central" else (0, 1, 2)
            coms = []
            for j in offsets:
                shifted = th + j * step
                if j == 0:
                    qj = q
                else:
                    shifted_guess = _stance_guess(rs, shifted, swing_pitch, side, stance_x, plan.angular)
                    qj = rows.project_many(shifted_guess, targets + _shift(j * step, free))[0]
                coms.append(tree.coms.positions(qj))
            com_acc = (coms[2] - 2 * coms[1] + coms[0]) / (step / omega) ** 2
            com_pos, alpha = coms[offsets.index(0)], None  # point masses: gravity and the inertial forces -m a
        else:
            com_pos, com_acc, alpha = tree.body_motion(q, v, a)
        # every sample's tau = rnea(q, v, a) from the bodies' wrenches, summed over each joint's subtree
        wrench = plan.planar.wrenches(q, com_pos, com_acc, alpha)
        tau = plan.planar.torques(q, wrench)
        # the split tau = S^T u + J_c^T lambda + C^T lambda_C: one square solve per sample
        nc = rows.n_constraint_rows
        jac_t = np.swapaxes(closed.jac, 1, 2)[:, :, :nc]  # J_c^T (N, nv, nc), contiguous in memory
        if len(plan.coupling):
            coupling_t = np.broadcast_to(plan.coupling.T, (th.size,) + plan.coupling.T.shape)
            jac_t = np.concatenate((jac_t, coupling_t), 2)
        u, lam_all = _split(tau, jac_t, plan.actuated, plan.passive)
        lam = lam_all[:, :nc]
        seg = slice(i0, i1)
        out["beta"][seg], out["beta_swing"][seg] = ankle_angles(rs, q, side), ankle_angles(rs, q, other(side))
        out["Ta"][seg] = u[:, 0]
        if n_motor == 2:
            out["Ta_swing"][seg] = u[:, 1]
        else:
            transmission[seg] = lam_all[:, nc]
        if spec.free_ankle:
            out["Te"][seg], out["Te_swing"][seg] = -u[:, n_motor], -u[:, n_motor + 1]
        qs[seg], vs[seg], accs[seg], taus[seg] = q, v, a, tau
        ground[seg] = lam[:, plan.weld_rows]
        if i0 == 0:
            cut_names, cut_forces = list(plan.cut_rows), np.zeros((n, len(plan.cut_rows), 2))
        for k, name in enumerate(cut_names):
            cut_forces[seg, k] = lam[:, plan.cut_rows[name]]
        if reactions:
            reac = plan.planar.reactions(q, wrench, lam)
            if i0 == 0:
                joint_names, joint_forces = list(plan.joint_names), np.zeros((n, len(plan.joint_names), 3))
            joint_forces[seg] = reac[:, [plan.joint_names[name] for name in joint_names]]
        previous = (rows, q[-1])

    stance_crank = np.where(np.array(sides_used) == "right", thetas, thetas + math.pi)
    theta_stance = math.pi / 2 + np.remainder(stance_crank - math.pi / 2, 2 * math.pi)  # wrap_stance
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
        cuts={name: cut_forces[:, k] for k, name in enumerate(cut_names)},
        joints={name: joint_forces[:, k] for k, name in enumerate(joint_names)},
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
