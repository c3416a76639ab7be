"""Constrained inverse dynamics of the ``spring`` biped: crank and ankle torques, reactions.

The robot follows a prescribed motion (docs/reference.md §5, §6): the stance foot is welded flat to the
ground, the hip stays level (pitch 0), the swing foot stays level (or rigid at 90 deg to its
shank), and both cranks turn at constant omega, pi apart. Each stance of a sweep is done in
one batch (its constant parts, :class:`~pasibot_pin.dynamics.stance_plan.StancePlan`, are set up once and cached):

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
from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

from pasibot_pin.constraints import ConstraintSystem, split_torques
from pasibot_pin.dynamics.stance_plan import StancePlan, ankle_angles, stance_plan, unwrap_angles
from pasibot_pin.errors import ParameterError
from pasibot_pin.model import closure
from pasibot_pin.model.coordinates import other
from pasibot_pin.model.design import check_parameter
from pasibot_pin.model.robot import PasibotRobot
from pasibot_pin.model.scenario_robots import scenario_robot
from pasibot_pin.model.scenarios import ACCELERATION_MODES, SWING_FOOT_MODES, ModelChoices, Scenario
from pasibot_pin.model.variants import MotorLayout, get_motor_layout

STANCE_RANGE: tuple[float, float] = (math.pi / 2, 3 * math.pi / 2)
"""Stance phase of a leg: crank angle theta in [pi/2, 3 pi/2] [rad] (docs/reference.md §4)."""

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


def check_omega(omega: float) -> float:
    """``omega`` [rad/s] if it lies in the design record's range of crank speeds, else a ParameterError naming it.

    The range is ``SPECS["omega"]`` (:func:`~pasibot_pin.model.design.check_parameter`): 0 (quasi-static) to its top.
    """
    return check_parameter("omega", float(omega))


def check_fit_window(thetas: Sequence[float]) -> np.ndarray:
    """Validate a fit window of stance-crank angles [rad]: inside stance (+- :data:`STANCE_MARGIN`)."""
    arr = np.asarray(thetas, dtype=float).reshape(-1)
    if arr.size < 2 or not np.all(np.isfinite(arr)):
        raise ParameterError("parameter 'fit_thetas' needs at least two finite crank angles [rad]")
    lo, hi = STANCE_RANGE[0] - STANCE_MARGIN, STANCE_RANGE[1] + STANCE_MARGIN
    bad = arr[(arr < lo - 1e-9) | (arr > hi + 1e-9)]
    if bad.size:
        raise ParameterError(
            f"parameter 'fit_thetas': {bad[0]:.4f} rad ({math.degrees(bad[0]):.1f} deg) is outside stance "
            f"[{lo:.4f}, {hi:.4f}] rad (theta in [pi/2, 3 pi/2] +- {STANCE_MARGIN} rad)"
        )
    return arr


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


# --------------------------------------------------------------------------- trajectory
def _segments(sides: list[str]) -> list[tuple[int, int]]:
    """(start, stop) of each run of samples with the same stance side."""
    bounds = [0] + [k for k in range(1, len(sides)) if sides[k] != sides[k - 1]] + [len(sides)]
    return list(zip(bounds[:-1], bounds[1:]))


def _shift(delta: float, free: list[float]) -> np.ndarray:
    """Move both crank targets by ``delta`` [rad], the held rows not."""
    return np.array([delta, delta] + [0.0] * len(free))


def _stance_guess(robot: PasibotRobot, thetas, swing_pitch, side, stance_x, angular) -> np.ndarray:
    """The analytic assembly along ``thetas``, q (N, nq), closed to round-off (a batched Newton checks it).

    The angles are unwrapped along the sweep, as a continuation would carry them.
    """
    guess, _ = closure.analytic_configurations(robot, thetas, None, 0.0, swing_pitch, side, stance_x)
    unwrap_angles(guess, angular)
    return guess


def crank_grid(start: float, stop: float, samples: int) -> np.ndarray:
    """``samples`` right-crank angles from ``start`` to ``stop`` inclusive [rad]."""
    if samples < 2:
        raise ParameterError(f"parameter 'samples' must be >= 2, got {samples!r}")
    return np.linspace(start, stop, int(samples))


def inverse_dynamics(
    robot: PasibotRobot,
    thetas: ArrayLike,
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
    thetas = _check_sweep(robot, thetas, omega, swing_foot, accelerations, stance, step)
    mode = "none" if omega == 0.0 else accelerations  # quasi-static: v = a = 0
    sides_used = sweep_stances(thetas, stance)
    sweep = _Sweep(robot, thetas, omega, swing_foot, layout)
    columns = _Columns(len(thetas), robot.model.nq, robot.model.nv, len(layout.motors))
    stance_x, previous = 0.0, None  # previous: (rows, last q) of the previous stance
    for i0, i1 in _segments(sides_used):
        side, th = sides_used[i0], thetas[i0:i1]
        if previous is not None:
            stance_x = sweep.landing_x(previous, th[0], side)
        plan = stance_plan(robot, side, swing_foot, layout, stance_x)
        q, v, a, jac = sweep.stance_motion(plan, th, side, stance_x)
        com_pos, com_acc, alpha = sweep.body_motion(plan, q, v, a, th, side, stance_x, mode, step)
        # every sample's tau = rnea(q, v, a) from the bodies' wrenches, summed over each joint's subtree
        wrench = plan.planar.wrenches(q, com_pos, com_acc, alpha)
        tau = plan.planar.torques(q, wrench)
        u, lam_all = _split_stance(plan, tau, jac)
        columns.store(slice(i0, i1), plan, side, (q, v, a, tau), u, lam_all)
        if reactions:
            lam = lam_all[:, : plan.rows.n_constraint_rows]  # the constraint forces, without the coupling's
            columns.store_reactions(slice(i0, i1), plan, plan.planar.reactions(q, wrench, lam))
        previous = (plan.rows, q[-1])
    return columns.result(thetas, sides_used, omega, mode, swing_foot, layout.name)


def _check_sweep(
    robot: PasibotRobot,
    thetas: ArrayLike,
    omega: float,
    swing_foot: str,
    accelerations: str,
    stance: str,
    step: float,
) -> np.ndarray:
    """The crank angles of a sweep as an array, once every argument of :func:`inverse_dynamics` is checked."""
    if robot.legs != 2:
        raise ParameterError(f"inverse_dynamics needs a two-legged robot (load(..., legs=2)), got legs={robot.legs}")
    if swing_foot not in SWING_FOOT_MODES:
        raise ParameterError(f"unknown swing_foot {swing_foot!r}; valid: {', '.join(SWING_FOOT_MODES)}")
    if accelerations not in ACCELERATION_MODES:
        raise ParameterError(f"unknown accelerations {accelerations!r}; valid: {', '.join(ACCELERATION_MODES)}")
    if stance not in ("auto", "right", "left"):
        raise ParameterError(f"unknown stance {stance!r}; valid: auto, right, left")
    if not (math.isfinite(step) and step > 0):
        raise ParameterError(f"parameter 'step' must be a positive angle [rad], got {step!r}")
    arr = np.asarray(thetas, dtype=float).reshape(-1)
    if arr.size < 1 or not np.all(np.isfinite(arr)):
        raise ParameterError("parameter 'thetas' must be a non-empty sequence of finite crank angles [rad]")
    if arr.size > 1 and np.any(np.diff(arr) <= 0):
        raise ParameterError("parameter 'thetas' must be strictly increasing")
    if accelerations != "exact" and robot.inertia != "point" and omega > 0:
        raise ParameterError("difference accelerations need point masses (inertia='point')")
    return arr


class _Sweep:
    """What every stance of one sweep shares: the robot, crank speed, the held rows and their rates."""

    def __init__(self, robot: PasibotRobot, thetas: np.ndarray, omega: float, swing_foot: str, layout: MotorLayout):
        self.robot, self.omega = robot, omega
        self.free = [0.0, 0.0] if robot.spec.free_ankle else []  # hip pitch and swing foot held (spring variant)
        self.swing_pitch = 0.0 if swing_foot == "level" else None
        self.rates = np.array([omega, omega, *self.free])

    def targets(self, th: np.ndarray) -> np.ndarray:
        """The prescribed rows' targets (N, n_s): both cranks, pi apart, then the held rows."""
        return np.column_stack([th, th + math.pi] + [np.full(th.size, f) for f in self.free])

    def landing_x(self, previous: tuple[ConstraintSystem, np.ndarray], theta: float, side: str) -> float:
        """Where the landing foot (the new stance foot) stands: its ankle's x at the switch [m]."""
        robot = self.robot
        switch = math.pi / 2 + math.pi * math.floor((theta - math.pi / 2) / math.pi)
        q_land = previous[0].project(previous[1], targets=[switch, switch + math.pi, *self.free])
        pin.framesForwardKinematics(robot.model, robot.data, q_land)
        return float(robot.data.oMf[robot.frame_id(f"{side}_foot")].translation[0])

    def stance_motion(self, plan: StancePlan, th: np.ndarray, side: str, stance_x: float):
        """q, v, a and the rows' Jacobian of a whole stance (N samples).

        From the closed form and its exact time derivatives (jets); one batched evaluation of the
        rows checks the closure, and only if it is open does Newton polish q (then v and a come
        from the constraint core at the new q).
        """
        guess, v, a, _ = closure.analytic_motion(plan.robot, th, self.omega, self.swing_pitch, side, stance_x)
        unwrap_angles(guess, plan.angular)
        q, closed = plan.rows.project_many(guess, self.targets(th))
        if not np.array_equal(q, guess):
            v, a, _ = plan.rows.motion_many(q, self.rates, np.zeros_like(self.rates), closed.jac)
        return q, v, a, closed.jac

    def body_motion(self, plan, q, v, a, th, side, stance_x, mode: str, step: float):
        """COM positions and accelerations, angular accelerations (``None``: point masses) of every body.

        ``exact`` (and quasi-static): the tree's body motion at (q, v, a). ``central``/``lagged``: the
        seed's second differences of the COM positions, crank step ``step`` (point masses: gravity and
        the inertial forces -m a).
        """
        if mode not in ("central", "lagged"):
            return plan.tree.body_motion(q, v, a)
        offsets = (-1, 0, 1) if mode == "central" else (0, 1, 2)
        coms = []
        for j in offsets:
            if j == 0:
                qj = q
            else:
                guess = _stance_guess(plan.robot, th + j * step, self.swing_pitch, side, stance_x, plan.angular)
                qj = plan.rows.project_many(guess, self.targets(th) + _shift(j * step, self.free))[0]
            coms.append(plan.tree.coms.positions(qj))
        com_acc = (coms[2] - 2 * coms[1] + coms[0]) / (step / self.omega) ** 2
        return coms[offsets.index(0)], com_acc, None


def _split_stance(plan: StancePlan, tau: np.ndarray, jac: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The split tau = S^T u + J_c^T lambda + C^T lambda_C of a stance: one square solve per sample."""
    nc = plan.rows.n_constraint_rows
    rows = jac[:, :nc]
    if len(plan.coupling):
        rows = np.concatenate((rows, np.broadcast_to(plan.coupling, (len(tau),) + plan.coupling.shape)), 1)
    return split_torques(tau, plan.s_matrix, rows)


class _Columns:
    """The columns of a :class:`TorqueResult`, filled stance by stance."""

    def __init__(self, n: int, nq: int, nv: int, n_motor: int):
        self.n, self.n_motor = n, n_motor
        self.out = {k: np.zeros(n) for k in ("beta", "beta_swing", "Ta", "Te", "Ta_swing", "Te_swing")}
        self.q, self.v, self.a, self.tau = np.zeros((n, nq)), np.zeros((n, nv)), np.zeros((n, nv)), np.zeros((n, nv))
        self.ground, self.transmission = np.zeros((n, 3)), np.zeros(n)
        self.cut_names: list[str] = []  # in the first stance's order (the columns of the CSV)
        self.joint_names: list[str] = []
        self.cut_forces = self.joint_forces = np.zeros((n, 0, 3))

    def store(self, seg: slice, plan: StancePlan, side: str, motion, u: np.ndarray, lam_all: np.ndarray) -> None:
        """One stance's ankle angles, torques, motion, ground and cut-joint forces."""
        out, rs, nc, n_motor = self.out, plan.robot, plan.rows.n_constraint_rows, self.n_motor
        q = motion[0]
        out["beta"][seg], out["beta_swing"][seg] = ankle_angles(rs, q, side), ankle_angles(rs, q, other(side))
        out["Ta"][seg] = u[:, 0]
        if n_motor == 2:
            out["Ta_swing"][seg] = u[:, 1]
        else:
            self.transmission[seg] = lam_all[:, nc]
        if rs.spec.free_ankle:
            out["Te"][seg], out["Te_swing"][seg] = -u[:, n_motor], -u[:, n_motor + 1]
        self.q[seg], self.v[seg], self.a[seg], self.tau[seg] = motion
        lam = lam_all[:, :nc]
        self.ground[seg] = lam[:, plan.weld_rows]
        if seg.start == 0:
            self.cut_names, self.cut_forces = list(plan.cut_rows), np.zeros((self.n, len(plan.cut_rows), 2))
        for k, name in enumerate(self.cut_names):
            self.cut_forces[seg, k] = lam[:, plan.cut_rows[name]]

    def store_reactions(self, seg: slice, plan: StancePlan, reac: np.ndarray) -> None:
        """One stance's tree-joint reactions (N, njoints, 3), in the first stance's joint order."""
        if seg.start == 0:
            self.joint_names = list(plan.joint_names)
            self.joint_forces = np.zeros((self.n, len(plan.joint_names), 3))
        self.joint_forces[seg] = reac[:, [plan.joint_names[name] for name in self.joint_names]]

    def result(self, thetas, sides_used, omega: float, mode: str, swing_foot: str, motors: str) -> TorqueResult:
        """The :class:`TorqueResult` of the filled columns."""
        stance_crank = np.where(np.array(sides_used) == "right", thetas, thetas + math.pi)
        theta_stance = math.pi / 2 + np.remainder(stance_crank - math.pi / 2, 2 * math.pi)  # in [pi/2, 5 pi/2)
        return TorqueResult(
            t=(thetas - thetas[0]) / (omega if omega > 0 else 1.0),
            theta_right=thetas,
            theta=theta_stance,
            stance=sides_used,
            q=self.q,
            v=self.v,
            a=self.a,
            tau=self.tau,
            ground=self.ground,
            cuts={name: self.cut_forces[:, k] for k, name in enumerate(self.cut_names)},
            joints={name: self.joint_forces[:, k] for k, name in enumerate(self.joint_names)},
            omega=omega,
            accelerations=mode,
            swing_foot=swing_foot,
            motors=motors,
            transmission=self.transmission,
            **self.out,
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
    thetas: ArrayLike | None = None,
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
