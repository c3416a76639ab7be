"""Forward dynamics of the walking ``spring`` biped, hip pitch free.

Does the fitted ankle spring hold the hip? The seed fits K_e by inverse dynamics with the hip
forced level and never lets it go. Here the hip pitch is free and the robot is integrated.

Model (docs/reference.md §6):

- State (q, v) of the Pinocchio model of ``pp.load("spring", 2)`` (nq = nv = 19).
- Holonomic constraints Phi(q, t) = 0, in-plane rows only (full row rank):
  the six loop closures and the stance-foot weld (x, z, pitch), then *coordinate rows*
  q_i - (offset + rate t) = 0: the motor (each crank follows theta0 + omega t, the left one
  pi ahead), optionally the hip pitch held level, optionally the swing ankle held at the
  spring's rest angle.
- The motor is a **rheonomic constraint** (``motor="rheonomic"``): the crank rate is exactly
  omega and the motor torque is that row's Lagrange multiplier. It adds no stiff servo mode,
  so the step is set by the physics alone. ``motor="free"`` leaves the cranks to the applied
  torques (feed-forward only, zero by default).
- Generalised forces: the ankle springs T = -K_e (beta - beta0) - c beta_dot on
  beta = pi/2 - q_ankle (so the torque on the ankle coordinate is -T), plus an optional
  feed-forward tau_ff(t, q, v) [N.m].
- Dynamics by one KKT solve per evaluation: [M J^T; J 0] [a; mu] = [tau - h; -Jdot v],
  lambda = -mu is the constraint force (J^T lambda is its generalised force), M from
  ``pin.crba``, h from ``pin.nonLinearEffects``.
- Fixed-step RK4 (default) or semi-implicit Euler. After every step q is projected back on
  Phi(q, t) = 0 by Newton (minimum M-norm corrections) and v on J v + Phi_t = 0 (the
  M-orthogonal projection, the same solve as an impact). The largest residual before
  projection is the per-step drift; it is recorded.
- Walking: at each half crank turn (right crank at pi/2 + k pi) the swing foot lands. Its
  weld is placed at the foot's x, on the ground z = 0, sole level; q is projected onto the
  new constraint set (the landing mismatch, foot height and pitch, is recorded) and v
  jumps by the inelastic impulse [M J^T; J 0][v+; mu] = [M v-; -Phi_t].

Swing ankle: ``swing_ankle="spring"`` integrates the swing foot on its spring. The foot is a
point mass 2.5 cm ahead of the ankle, so it is a ~100 Hz oscillator that sets the step
(RK4 needs dt < ~4 ms). ``swing_ankle="rest"`` is the massless-foot limit: the unloaded
foot sits at the spring's rest angle (error m_f g d / K_e ~ 1e-3 rad); the only free
coordinate left is the hip pitch and much longer steps are accurate.

Units: SI; angles [rad].
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from pasibot_pin import constraints
from pasibot_pin.constraints import ConstraintSystem, CoordinateRow, coordinate
from pasibot_pin.dynamics.spring_energy import (
    AnkleSpring,
    ankle_indices,
    check_finite,
    foot_pose,
    sole_height,
    spring_forces,
    total_energy,
)
from pasibot_pin.errors import ParameterError, SimulationError
from pasibot_pin.model.closure import assemble, hip_pitch, joint_coordinate, solve_velocity
from pasibot_pin.model.coordinates import HIP_PITCH, other
from pasibot_pin.reprs import short_repr

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot

MOTOR_MODES: tuple[str, ...] = ("rheonomic", "free")
HIP_MODES: tuple[str, ...] = ("free", "level")
SWING_ANKLE_MODES: tuple[str, ...] = ("spring", "rest")
INTEGRATORS: tuple[str, ...] = ("rk4", "euler")

Feedforward = Callable[[float, np.ndarray, np.ndarray], np.ndarray]
"""tau_ff(t [s], q, v) -> generalised force vector (nv,) [N.m or N]."""


# --------------------------------------------------------------------------- settings and result
@dataclass(frozen=True)
class SimulationSettings:
    """How to simulate.

    Attributes:
        omega: crank rate [rad/s] (the motor's, for ``motor="rheonomic"``; the nominal one,
            which schedules the touchdowns, otherwise).
        spring: the ankle springs (``None``: free ankles).
        motor: ``rheonomic`` (cranks follow theta0 + omega t exactly) or ``free``.
        hip: ``free`` (pitch free: the question) or ``level`` (pitch held at 0).
        swing_ankle: ``spring`` (swing foot integrated on its spring) or ``rest`` (held at the
            spring's rest angle: the massless-foot limit).
        dt: largest integration step [s].
        integrator: ``rk4`` or ``euler`` (semi-implicit).
        theta0: initial right crank angle [rad] (default pi/2: the right foot just landed).
        initial_pitch: hip pitch at t = 0 [rad] (the hip starts still at this pitch; see
            :func:`pasibot_pin.studies.methods.statics.static_equilibrium` for the pitch where it stands still).
        feedforward: extra generalised force tau_ff(t, q, v) (nv,) or ``None``.
        fall_limit: the run stops (``fell``) when |hip pitch| exceeds this [rad].
        record_every: keep one sample every this many steps.

    """

    omega: float = 0.1
    spring: AnkleSpring | None = None
    motor: str = "rheonomic"
    hip: str = "free"
    swing_ankle: str = "spring"
    dt: float = 2e-3
    integrator: str = "rk4"
    theta0: float = math.pi / 2
    initial_pitch: float = 0.0
    feedforward: Feedforward | None = None
    fall_limit: float = math.radians(60.0)
    record_every: int = 1

    def __post_init__(self) -> None:
        for name, valid in (
            ("motor", MOTOR_MODES),
            ("hip", HIP_MODES),
            ("swing_ankle", SWING_ANKLE_MODES),
            ("integrator", INTEGRATORS),
        ):
            if getattr(self, name) not in valid:
                raise ParameterError(f"unknown {name} {getattr(self, name)!r}; valid: {', '.join(valid)}")
        check_finite("omega", self.omega)
        check_finite("theta0", self.theta0)
        check_finite("initial_pitch", self.initial_pitch)
        if not (math.isfinite(self.dt) and self.dt > 0):
            raise ParameterError(f"parameter 'dt' must be a positive finite step [s], got {self.dt!r}")
        if not (math.isfinite(self.fall_limit) and self.fall_limit > 0):
            raise ParameterError(f"parameter 'fall_limit' must be positive [rad], got {self.fall_limit!r}")
        if int(self.record_every) < 1:
            raise ParameterError(f"parameter 'record_every' must be >= 1, got {self.record_every!r}")
        if self.swing_ankle == "rest" and self.spring is None:
            raise ParameterError("swing_ankle='rest' needs a spring (its rest angle)")

    def with_(self, **changes) -> SimulationSettings:
        """Copy with some fields changed."""
        return replace(self, **changes)


@dataclass
class Impact:
    """One touchdown.

    Attributes:
        t: time [s].
        side: the landing foot.
        height: the landing sole's ankle height above the ground just before [m].
        pitch: its sole pitch just before [rad].
        kinetic_before: kinetic energy before [J] (after the position projection).
        kinetic_after: kinetic energy after [J].

    """

    t: float
    side: str
    height: float
    pitch: float
    kinetic_before: float
    kinetic_after: float


@dataclass
class SimulationResult:
    """Samples of a run.

    Attributes:
        t: times (n,) [s].
        q: configurations (n, nq).
        v: velocities (n, nv).
        hip_pitch: hip pitch (n,) [rad].
        beta: ankle angles beta (n, 2) [rad], columns right, left.
        motor_torque: crank torques (n, 2) [N.m], right, left (multipliers of the motor rows,
            or the feed-forward for ``motor="free"``).
        hip_torque: torque holding the hip level (n,) [N.m] (zero when the hip is free).
        stance: stance side per sample (n,) (``right``/``left``).
        drift: largest constraint residual before each projection (n,) [m, rad].
        swing_height: lowest swing-sole point (n,) [m].
        impacts: touchdowns.
        fell: True when |hip pitch| passed the fall limit (the run stopped there).
        message: why the run stopped early, or ``""``.
        settings: the settings used.

    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    hip_pitch: np.ndarray
    beta: np.ndarray
    motor_torque: np.ndarray
    hip_torque: np.ndarray
    stance: list[str]
    drift: np.ndarray
    swing_height: np.ndarray
    impacts: list[Impact] = field(default_factory=list)
    fell: bool = False
    message: str = ""
    settings: SimulationSettings | None = None

    __repr__ = short_repr

    @property
    def max_hip_excursion(self) -> float:
        """Largest |hip pitch| over the run [rad]."""
        return float(np.max(np.abs(self.hip_pitch)))

    @property
    def max_drift(self) -> float:
        """Largest per-step constraint residual before projection [m, rad]."""
        return float(np.max(self.drift)) if len(self.drift) else 0.0


# --------------------------------------------------------------------------- the simulator
class BipedSimulator:
    """Integrates the constrained dynamics of the ``spring`` biped (see the module docstring).

    Args:
        robot: ``pp.load("spring", 2)`` (or a copy with other masses).
        settings: the simulation settings.

    """

    def __init__(self, robot: PasibotRobot, settings: SimulationSettings):
        if not robot.spec.free_ankle or robot.legs != 2:
            raise ParameterError(
                "the simulator needs a two-legged robot with spring ankles (variant 'spring'), "
                f"got variant={robot.variant!r} legs={robot.legs}"
            )
        if robot.model.nq != robot.model.nv:
            raise ParameterError("the simulator assumes nq == nv (revolute/prismatic joints only)")
        self.robot = robot
        self.settings = settings
        self.cranks = {side: robot.idx_v(f"{side}_j0_crank") for side in ("right", "left")}
        self.ankles = ankle_indices(robot)
        self.soles = {side: (robot.frame_id(f"{side}_toe"), robot.frame_id(f"{side}_heel")) for side in self.ankles}

    # ---- constraint sets
    def coordinate_rows(self, stance: str) -> list[CoordinateRow]:
        """The coordinate rows for a stance side: motor, hip lock and swing-ankle lock."""
        s = self.settings
        rows = []
        if s.motor == "rheonomic":
            rows += [
                coordinate("right_j0_crank", self.cranks["right"], s.theta0, s.omega),
                coordinate("left_j0_crank", self.cranks["left"], s.theta0 + math.pi, s.omega),
            ]
        if s.hip == "level":
            rows.append(coordinate("hip_pitch", HIP_PITCH, 0.0, 0.0))
        if s.swing_ankle == "rest" and s.spring is not None:  # the settings' check: "rest" has a spring
            swing = other(stance)
            rows.append(coordinate(f"{swing}_j13_ankle", self.ankles[swing], math.pi / 2 - s.spring.rest_angle))
        return rows

    def constraint_set(self, stance: str, weld: pin.RigidConstraintModel) -> ConstraintSystem:
        """Loops + ``weld`` + the coordinate rows of ``stance``."""
        robot = self.robot
        cmodels = list(robot.loop_constraints) + [weld]
        return ConstraintSystem(robot.model, robot.data, cmodels, self.coordinate_rows(stance), robot.geometry.L)

    def ground_weld(self, side: str, q: np.ndarray) -> pin.RigidConstraintModel:
        """A weld of ``side``'s foot at its x in ``q``, on the ground (z = 0), sole level."""
        model, data = self.robot.model, self.robot.data
        pin.forwardKinematics(model, data, q)
        pos = pin.updateFramePlacement(model, data, self.robot.frame_id(f"{side}_foot")).translation.copy()
        pos[2] = 0.0
        return constraints.weld_constraint(model, f"{side}_foot", pin.SE3(np.eye(3), pos), f"{side}_foot_weld")

    # ---- dynamics
    def forces(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Applied generalised forces: springs plus feed-forward (nv,)."""
        tau = spring_forces(self.robot, self.settings.spring, q, v, self.ankles)
        if self.settings.feedforward is not None:
            ff = np.asarray(self.settings.feedforward(t, q, v), dtype=float)
            if ff.shape != tau.shape or not np.all(np.isfinite(ff)):
                raise ParameterError(f"feedforward must return a finite vector of size nv = {len(tau)}")
            tau = tau + ff
        return tau

    def acceleration(self, cset: ConstraintSystem, t: float, q: np.ndarray, v: np.ndarray, mass_ready: bool = False):
        """Constrained forward dynamics: returns (a, lambda, phi).

        ``mass_ready``: the robot's data already holds M(q) (see :meth:`ConstraintSystem.forward_dynamics`).
        """
        a, lam, rows = cset.forward_dynamics(q, v, self.forces(t, q, v), t, mass_ready)
        return a, lam, rows.phi

    def step(self, cset: ConstraintSystem, t: float, q: np.ndarray, v: np.ndarray, h: float, mass_ready: bool = False):
        """One integration step of length h; returns (q, v, lambda at the start, drift before projection).

        ``mass_ready``: the robot's data holds M(q) of this ``q`` (the previous step's velocity projection
        ended there): the first stage reuses it. The step leaves M(q_new) in the data.
        """
        a1, lam, _ = self.acceleration(cset, t, q, v, mass_ready)
        if self.settings.integrator == "euler":
            v_new = v + h * a1
            q_new = q + h * v_new
        else:
            half = h / 2
            v2 = v + half * a1
            a2 = self.acceleration(cset, t + half, q + half * v, v2)[0]
            v3 = v + half * a2
            a3 = self.acceleration(cset, t + half, q + half * v2, v3)[0]
            v4 = v + h * a3
            a4 = self.acceleration(cset, t + h, q + h * v3, v4)[0]
            q_new = q + h / 6 * ((v + v4) + 2 * (v2 + v3))
            v_new = v + h / 6 * ((a1 + a4) + 2 * (a2 + a3))
        q_new, rows, initial_residual = cset.project_rows(q_new, t + h, metric="mass", max_iter=20)
        v_new, _ = cset.impulse(q_new, v_new, t + h, rows)
        return q_new, v_new, lam, initial_residual

    # ---- initial state
    def initial_state(self, stance: str | None = None) -> tuple[np.ndarray, np.ndarray, str]:
        """A consistent start: cranks at theta0 (left pi ahead), hip still at ``initial_pitch``, stance foot flat.

        The swing ankle starts at the spring's rest angle (square to the shank without a
        spring); every free coordinate starts at rest except the cranks (rate omega).
        """
        s = self.settings
        if stance is None:
            phase = (s.theta0 - math.pi / 2) % (2 * math.pi)
            stance = "right" if phase < math.pi - 1e-9 else "left"
        q = assemble(self.robot, s.theta0, hip_pitch_value=s.initial_pitch, stance=stance)
        swing = other(stance)
        beta0 = s.spring.rest_angle if s.spring is not None else math.pi / 2
        q[self.ankles[swing]] = math.pi / 2 - beta0
        robot = self.robot.with_stance(stance, q)
        prescribed = [joint_coordinate(robot, j) for j in robot.actuated_joints]
        prescribed += [hip_pitch(robot), joint_coordinate(robot, f"{swing}_j13_ankle")]
        rate = s.omega if s.motor == "rheonomic" else 0.0
        v = solve_velocity(robot, q, prescribed, [rate, rate, 0.0, 0.0])
        return q, v, stance

    # ---- run
    def run(
        self,
        steps: int | None = None,
        duration: float | None = None,
        q0: np.ndarray | None = None,
        v0: np.ndarray | None = None,
        stance: str | None = None,
    ) -> SimulationResult:
        """Integrate.

        Args:
            steps: number of stance phases to run (a touchdown ends each but the last).
            duration: instead of ``steps``: simulate this long [s] on one stance foot.
            q0: initial configuration (default :meth:`initial_state`).
            v0: initial velocity (default :meth:`initial_state`).
            stance: the initial stance foot (default from theta0).

        Returns:
            The recorded :class:`SimulationResult`.

        """
        ends = self._phase_ends(steps, duration)
        q_init, v_init, stance0 = self.initial_state(stance)
        q = q_init if q0 is None else np.array(q0, dtype=float)
        v = v_init if v0 is None else np.array(v0, dtype=float)
        run = _Run(self, stance or stance0, q, v)
        for phase, t_end in enumerate(ends):
            run.integrate_phase(t_end)
            if run.fell:
                break
            if phase < len(ends) - 1:  # touchdown of the swing foot
                run.touchdown()
                if run.fell:
                    break
        run.last_sample()
        return self.result(run.rec, run.impacts, run.fell, run.message)

    def _phase_ends(self, steps: int | None, duration: float | None) -> list[float]:
        """The end of each stance phase [s]: touchdowns as the right crank reaches pi/2 + k pi, or ``duration``."""
        s = self.settings
        if (steps is None) == (duration is None):
            raise ParameterError("give exactly one of 'steps' (stance phases) or 'duration' (one stance)")
        if duration is not None:
            return [check_finite("duration", duration, 0.0)]
        assert steps is not None  # one of the two is given (checked above)
        if int(steps) != steps or steps < 1:
            raise ParameterError(f"parameter 'steps' must be a positive integer, got {steps!r}")
        if not s.omega > 0:
            raise ParameterError(f"walking needs a positive crank rate 'omega', got {s.omega!r}")
        k0 = math.floor((s.theta0 - math.pi / 2) / math.pi + 1e-9) + 1
        return [(math.pi / 2 + (k0 + i) * math.pi - s.theta0) / s.omega for i in range(int(steps))]

    def result(self, rec: dict[str, list], impacts: list[Impact], fell: bool, message: str) -> SimulationResult:
        """The :class:`SimulationResult` of recorded samples.

        ``rec`` holds lists ``t``, ``q``, ``v``, ``lam`` (right motor, left motor, hip lock torques),
        ``stance``, ``drift`` and ``swing`` (the swing sole's height).
        """
        qs = np.array(rec["q"])
        betas = np.column_stack([math.pi / 2 - qs[:, self.ankles[side]] for side in ("right", "left")])
        lam = np.array(rec["lam"])
        return SimulationResult(
            t=np.array(rec["t"]),
            q=qs,
            v=np.array(rec["v"]),
            hip_pitch=qs[:, HIP_PITCH].copy(),
            beta=betas,
            motor_torque=lam[:, :2],
            hip_torque=lam[:, 2],
            stance=rec["stance"],
            drift=np.array(rec["drift"]),
            swing_height=np.array(rec["swing"]),
            impacts=impacts,
            fell=fell,
            message=message,
            settings=self.settings,
        )

    def _multiplier_rows(self, cset: ConstraintSystem) -> list[int | None]:
        """Row indices of the right motor, left motor and hip-lock multipliers (None if absent)."""
        out: list[int | None] = []
        for name in ("right_j0_crank", "left_j0_crank", "hip_pitch"):
            out.append(cset.labels.index(name) if name in cset.labels else None)
        return out


def simulate(
    robot: PasibotRobot, settings: SimulationSettings, steps: int | None = None, duration: float | None = None, **kwargs
):
    """Shortcut: ``BipedSimulator(robot, settings).run(steps, duration, **kwargs)``."""
    return BipedSimulator(robot, settings).run(steps=steps, duration=duration, **kwargs)


class _Run:
    """One run of :meth:`BipedSimulator.run`: the state, the current stance's rows and what is recorded."""

    def __init__(self, sim: BipedSimulator, stance: str, q: np.ndarray, v: np.ndarray):
        self.sim, self.s, self.stance = sim, sim.settings, stance
        self.cset = sim.constraint_set(stance, sim.ground_weld(stance, q))
        self.q = self.cset.project(q, 0.0, metric="mass", max_iter=20)
        self.v, _ = self.cset.impulse(self.q, v, 0.0)
        self.rec: dict[str, list] = {k: [] for k in ("t", "q", "v", "lam", "stance", "drift", "swing")}
        self.labels_index = sim._multiplier_rows(self.cset)
        self.t, self.count, self.last_drift = 0.0, 0, 0.0
        self.impacts: list[Impact] = []
        self.fell, self.message = False, ""

    def record(self, lam: np.ndarray) -> None:
        """The sample at the current (t, q, v): the motor and hip-lock torques from ``lam``, the swing sole's height."""
        sim, s, rec, q, v = self.sim, self.s, self.rec, self.q, self.v
        rec["t"].append(self.t)
        rec["q"].append(q.copy())
        rec["v"].append(v.copy())
        tau_m = np.zeros(3)
        for k, idx in enumerate(self.labels_index):
            if idx is not None:
                tau_m[k] = lam[idx]
        if s.motor == "free" and s.feedforward is not None:
            ff = s.feedforward(self.t, q, v)
            tau_m[0], tau_m[1] = ff[sim.cranks["right"]], ff[sim.cranks["left"]]
        rec["lam"].append(tau_m)
        rec["stance"].append(self.stance)
        rec["drift"].append(self.last_drift)
        swing = other(self.stance)
        rec["swing"].append(sole_height(sim.robot, q, swing, sim.soles[swing]))

    def integrate_phase(self, t_end: float) -> None:
        """Steps of equal length (at most ``dt``) up to ``t_end``; stops at a failed step or a fall."""
        s = self.s
        # M(q) of the last velocity projection stays in the data for the next step's first stage, unless a
        # feed-forward (which might use the robot's data) runs in between
        reuse, mass_ready = s.feedforward is None, False
        n = max(1, math.ceil((t_end - self.t) / s.dt - 1e-9))
        h = (t_end - self.t) / n
        for _ in range(n):
            try:
                q_new, v_new, lam, drift = self.sim.step(self.cset, self.t, self.q, self.v, h, mass_ready)
            except SimulationError as err:
                self.fell, self.message = True, f"stopped at t = {self.t:.3f} s: {err}"
                return
            if self.count % s.record_every == 0:
                self.record(lam)
            self.count += 1
            self.q, self.v, self.t, self.last_drift = q_new, v_new, self.t + h, drift
            mass_ready = reuse
            if abs(self.q[HIP_PITCH]) > s.fall_limit:
                self.fell = True
                self.message = f"fell: |hip pitch| passed {math.degrees(s.fall_limit):.0f} deg at t = {self.t:.3f} s"
                return

    def touchdown(self) -> None:
        """The swing foot lands flat: the new stance's rows, a projection onto them, the inelastic impact."""
        sim, t = self.sim, self.t
        self.record(sim.acceleration(self.cset, t, self.q, self.v)[1])
        side = other(self.stance)
        x, z, pitch = foot_pose(sim.robot, self.q, side)
        weld = sim.ground_weld(side, self.q)
        self.stance = side
        self.cset = cset = sim.constraint_set(side, weld)
        self.labels_index = sim._multiplier_rows(cset)
        land = cset
        if self.s.swing_ankle == "spring":  # the lifting foot keeps its ankle angle through the landing
            lifting = sim.ankles[other(side)]
            land = cset.with_scalars([*cset.scalars, coordinate("lifting_ankle", lifting, self.q[lifting])])
        try:
            self.q = land.project(self.q, t, metric="mass", max_iter=20)
        except ValueError as err:
            self.fell, self.message = True, f"landing failed at t = {t:.3f} s: {err}"
            return
        ke_before = total_energy(sim.robot, self.q, self.v)["kinetic"]
        self.v, _ = cset.impulse(self.q, self.v, t)
        self.impacts.append(Impact(t, side, z, pitch, ke_before, total_energy(sim.robot, self.q, self.v)["kinetic"]))

    def last_sample(self) -> None:
        """The final sample (unless a failed step already recorded this time), its multipliers zero if they fail."""
        if not self.fell or not self.rec["t"] or self.rec["t"][-1] < self.t:
            try:
                lam = self.sim.acceleration(self.cset, self.t, self.q, self.v)[1]
            except ValueError:
                lam = np.zeros(self.cset.nrows)
            self.record(lam)
