"""Forward dynamics of the walking ``spring`` biped, hip pitch free.

Does the fitted ankle spring hold the hip? The seed fits K_e by inverse dynamics with the hip
forced level and never lets it go. Here the hip pitch is free and the robot is integrated.

Model (DESIGN §6):

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

import numpy as np
import pinocchio as pin

from pasibot_pin import constraints
from pasibot_pin.constraints import ConstraintSystem, CoordinateRow, coordinate, symmetric_mass_matrix
from pasibot_pin.errors import SimulationError
from pasibot_pin.model.closure import hip_pitch, joint_coordinate, solve_velocity
from pasibot_pin.model.coordinates import HIP_PITCH, other

MOTOR_MODES: tuple[str, ...] = ("rheonomic", "free")
HIP_MODES: tuple[str, ...] = ("free", "level")
SWING_ANKLE_MODES: tuple[str, ...] = ("spring", "rest")
INTEGRATORS: tuple[str, ...] = ("rk4", "euler")

Feedforward = Callable[[float, np.ndarray, np.ndarray], np.ndarray]
"""tau_ff(t [s], q, v) -> generalised force vector (nv,) [N.m or N]."""


def _check_finite(name: str, value: float, minimum: float | None = None) -> float:
    value = float(value)
    if not math.isfinite(value) or (minimum is not None and value < minimum):
        bound = "" if minimum is None else f" >= {minimum:g}"
        raise ValueError(f"parameter {name!r} must be a finite number{bound}, got {value!r}")
    return value


# --------------------------------------------------------------------------- the spring
@dataclass(frozen=True)
class AnkleSpring:
    """Linear torsion spring (and damper) at each ankle.

    Attributes:
        stiffness: K_e [N.m/rad].
        rest_angle: beta0, the angle from the forward foot to the shank at zero torque [rad].
        damping: c [N.m.s/rad].

    """

    stiffness: float
    rest_angle: float
    damping: float = 0.0

    def __post_init__(self) -> None:
        _check_finite("stiffness", self.stiffness, 0.0)
        _check_finite("rest_angle", self.rest_angle)
        _check_finite("damping", self.damping, 0.0)

    def torque(self, beta: float, beta_dot: float) -> float:
        """T = -K_e (beta - beta0) - c beta_dot [N.m], the generalised force on beta."""
        return -self.stiffness * (beta - self.rest_angle) - self.damping * beta_dot

    def energy(self, beta: float) -> float:
        """Stored energy 0.5 K_e (beta - beta0)^2 [J]."""
        return 0.5 * self.stiffness * (beta - self.rest_angle) ** 2

    def scaled(self, factor: float) -> AnkleSpring:
        """The same spring with the stiffness times ``factor`` (damping and rest angle kept)."""
        return replace(self, stiffness=self.stiffness * _check_finite("factor", factor, 0.0))


def foot_inertia_about_ankle(robot, side: str = "right") -> float:
    """Rotational inertia of a foot about its ankle axis [kg.m^2]."""
    joint = robot.model.getJointId(f"{side}_j13_ankle")
    inertia = robot.model.inertias[joint]
    c = inertia.lever
    return float(inertia.inertia[1, 1] + inertia.mass * (c[0] ** 2 + c[2] ** 2))


def critical_foot_damping(robot, stiffness: float) -> float:
    """The ankle damping that critically damps the unloaded foot on its spring [N.m.s/rad]."""
    return 2.0 * math.sqrt(_check_finite("stiffness", stiffness, 0.0) * foot_inertia_about_ankle(robot))


# --------------------------------------------------------------------------- constraints
def mass_matrix(robot, q: np.ndarray) -> np.ndarray:
    """Joint-space mass matrix M(q) (symmetric) [kg, kg.m, kg.m^2]."""
    return symmetric_mass_matrix(robot.model, robot.data, q)


# --------------------------------------------------------------------------- forces and energy
def ankle_indices(robot) -> dict[str, int]:
    """Velocity index of each ankle joint, by side."""
    return {side: robot.idx_v(f"{side}_j13_ankle") for side in ("right", "left")}


def ankle_beta(robot, q: np.ndarray) -> dict[str, float]:
    """Beta = pi/2 - q_ankle of each ankle [rad]: the angle from the forward foot to the shank."""
    return {side: math.pi / 2 - q[i] for side, i in ankle_indices(robot).items()}


def spring_forces(
    robot, spring: AnkleSpring | None, q: np.ndarray, v: np.ndarray, ankles: dict[str, int] | None = None
) -> np.ndarray:
    """Generalised force of the ankle springs (nv,) [N.m]: -T on each ankle coordinate.

    ``ankles``: :func:`ankle_indices` of ``robot`` if already known.
    """
    tau = np.zeros(robot.model.nv)
    if spring is None:
        return tau
    for i in (ankles or ankle_indices(robot)).values():
        tau[i] = -spring.torque(math.pi / 2 - q[i], -v[i])
    return tau


def total_energy(robot, q: np.ndarray, v: np.ndarray, spring: AnkleSpring | None = None) -> dict[str, float]:
    """Kinetic, gravity-potential (z = 0 reference) and spring energies [J], and their sum."""
    kinetic = float(pin.computeKineticEnergy(robot.model, robot.data, q, v))
    potential = float(pin.computePotentialEnergy(robot.model, robot.data, q))
    elastic = 0.0 if spring is None else sum(spring.energy(b) for b in ankle_beta(robot, q).values())
    return {"kinetic": kinetic, "potential": potential, "spring": elastic, "total": kinetic + potential + elastic}


def foot_pose(robot, q: np.ndarray, side: str) -> tuple[float, float, float]:
    """World x, z [m] of ``side``'s ankle frame and its sole pitch [rad]."""
    model, data = robot.model, robot.data
    pin.forwardKinematics(model, data, q)
    fid = robot.frame_id(f"{side}_foot")
    pose = pin.updateFramePlacement(model, data, fid)
    return float(pose.translation[0]), float(pose.translation[2]), math.atan2(pose.rotation[2, 0], pose.rotation[0, 0])


def sole_height(robot, q: np.ndarray, side: str, frames: tuple[int, int] | None = None) -> float:
    """Lowest z of ``side``'s toe and heel [m] (negative: below the ground).

    ``frames``: the toe and heel frame indices of ``side`` if already known.
    """
    model, data = robot.model, robot.data
    pin.forwardKinematics(model, data, q)
    frames = frames or tuple(robot.frame_id(f"{side}_{p}") for p in ("toe", "heel"))
    return float(min(pin.updateFramePlacement(model, data, f).translation[2] for f in frames))


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
            :func:`pasibot_pin.studies.statics.static_equilibrium` for the pitch where it stands still).
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
                raise ValueError(f"unknown {name} {getattr(self, name)!r}; valid: {', '.join(valid)}")
        _check_finite("omega", self.omega)
        _check_finite("theta0", self.theta0)
        _check_finite("initial_pitch", self.initial_pitch)
        if not (math.isfinite(self.dt) and self.dt > 0):
            raise ValueError(f"parameter 'dt' must be a positive finite step [s], got {self.dt!r}")
        if not (math.isfinite(self.fall_limit) and self.fall_limit > 0):
            raise ValueError(f"parameter 'fall_limit' must be positive [rad], got {self.fall_limit!r}")
        if int(self.record_every) < 1:
            raise ValueError(f"parameter 'record_every' must be >= 1, got {self.record_every!r}")
        if self.swing_ankle == "rest" and self.spring is None:
            raise ValueError("swing_ankle='rest' needs a spring (its rest angle)")

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

    def __init__(self, robot, settings: SimulationSettings):
        if not robot.spec.free_ankle or robot.legs != 2:
            raise ValueError(
                "the simulator needs a two-legged robot with spring ankles (variant 'spring'), "
                f"got variant={robot.variant!r} legs={robot.legs}"
            )
        if robot.model.nq != robot.model.nv:
            raise ValueError("the simulator assumes nq == nv (revolute/prismatic joints only)")
        self.robot = robot
        self.settings = settings
        self.cranks = {side: robot.idx_v(f"{side}_j0_crank") for side in ("right", "left")}
        self.ankles = ankle_indices(robot)
        self._soles = {side: (robot.frame_id(f"{side}_toe"), robot.frame_id(f"{side}_heel")) for side in self.ankles}

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
        if s.swing_ankle == "rest":
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
                raise ValueError(f"feedforward must return a finite vector of size nv = {len(tau)}")
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
        from pasibot_pin.model.closure import assemble

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
            steps: number of stance phases to walk (a touchdown ends each but the last).
            duration: instead of ``steps``: simulate this long [s] on one stance foot.
            q0: initial configuration (default :meth:`initial_state`).
            v0: initial velocity (default :meth:`initial_state`).
            stance: the initial stance foot (default from theta0).

        Returns:
            The recorded :class:`SimulationResult`.

        """
        s = self.settings
        if (steps is None) == (duration is None):
            raise ValueError("give exactly one of 'steps' (walk) or 'duration' (one stance)")
        if steps is not None:
            if int(steps) != steps or steps < 1:
                raise ValueError(f"parameter 'steps' must be a positive integer, got {steps!r}")
            if not s.omega > 0:
                raise ValueError(f"walking needs a positive crank rate 'omega', got {s.omega!r}")
            # touchdowns when the right crank reaches pi/2 + k pi
            k0 = math.floor((s.theta0 - math.pi / 2) / math.pi + 1e-9) + 1
            ends = [(math.pi / 2 + (k0 + i) * math.pi - s.theta0) / s.omega for i in range(int(steps))]
        else:
            _check_finite("duration", duration, 0.0)
            ends = [float(duration)]
        q_init, v_init, stance0 = self.initial_state(stance)
        stance = stance or stance0
        q = q_init if q0 is None else np.array(q0, dtype=float)
        v = v_init if v0 is None else np.array(v0, dtype=float)
        weld = self.ground_weld(stance, q)
        cset = self.constraint_set(stance, weld)
        q = cset.project(q, 0.0, metric="mass", max_iter=20)
        v, _ = cset.impulse(q, v, 0.0)
        rec: dict[str, list] = {k: [] for k in ("t", "q", "v", "lam", "stance", "drift", "swing")}
        labels_index = self._multiplier_rows(cset)

        def record(t, q, v, lam, drift, labels_index):
            rec["t"].append(t)
            rec["q"].append(q.copy())
            rec["v"].append(v.copy())
            tau_m = np.zeros(3)
            for k, idx in enumerate(labels_index):
                if idx is not None:
                    tau_m[k] = lam[idx]
            if s.motor == "free" and s.feedforward is not None:
                ff = self.settings.feedforward(t, q, v)
                tau_m[0], tau_m[1] = ff[self.cranks["right"]], ff[self.cranks["left"]]
            rec["lam"].append(tau_m)
            rec["stance"].append(stance)
            rec["drift"].append(drift)
            swing = other(stance)
            rec["swing"].append(sole_height(self.robot, q, swing, self._soles[swing]))

        t = 0.0
        impacts: list[Impact] = []
        fell, message = False, ""
        count = 0
        last_drift = 0.0
        # M(q) of the last velocity projection stays in the data for the next step's first stage, unless a
        # feed-forward (which might use the robot's data) runs in between
        reuse = s.feedforward is None
        for phase, t_end in enumerate(ends):
            mass_ready = False
            n = max(1, math.ceil((t_end - t) / s.dt - 1e-9))
            h = (t_end - t) / n
            for _ in range(n):
                try:
                    q_new, v_new, lam, drift = self.step(cset, t, q, v, h, mass_ready)
                except SimulationError as err:
                    fell, message = True, f"stopped at t = {t:.3f} s: {err}"
                    break
                if count % s.record_every == 0:
                    record(t, q, v, lam, last_drift, labels_index)
                count += 1
                q, v, t, last_drift = q_new, v_new, t + h, drift
                mass_ready = reuse
                if abs(q[HIP_PITCH]) > s.fall_limit:
                    fell = True
                    message = f"fell: |hip pitch| passed {math.degrees(s.fall_limit):.0f} deg at t = {t:.3f} s"
                    break
            if fell:
                break
            if phase < len(ends) - 1:  # touchdown of the swing foot
                lam = self.acceleration(cset, t, q, v)[1]
                record(t, q, v, lam, last_drift, labels_index)
                side = other(stance)
                x, z, pitch = foot_pose(self.robot, q, side)
                weld = self.ground_weld(side, q)
                stance = side
                cset = self.constraint_set(stance, weld)
                labels_index = self._multiplier_rows(cset)
                land = cset
                if s.swing_ankle == "spring":  # the lifting foot keeps its ankle angle through the landing
                    lifting = self.ankles[other(side)]
                    land = cset.with_scalars([*cset.scalars, coordinate("lifting_ankle", lifting, q[lifting])])
                try:
                    q = land.project(q, t, metric="mass", max_iter=20)
                except ValueError as err:
                    fell, message = True, f"landing failed at t = {t:.3f} s: {err}"
                    break
                ke_before = total_energy(self.robot, q, v)["kinetic"]
                v, _ = cset.impulse(q, v, t)
                impacts.append(Impact(t, side, z, pitch, ke_before, total_energy(self.robot, q, v)["kinetic"]))
        if not fell or not rec["t"] or rec["t"][-1] < t:
            try:
                lam = self.acceleration(cset, t, q, v)[1]
            except ValueError:
                lam = np.zeros(cset.nrows)
            record(t, q, v, lam, last_drift, labels_index)
        return self.result(rec, impacts, fell, message)

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


def simulate(robot, settings: SimulationSettings, steps: int | None = None, duration: float | None = None, **kwargs):
    """Shortcut: ``BipedSimulator(robot, settings).run(steps, duration, **kwargs)``."""
    return BipedSimulator(robot, settings).run(steps=steps, duration=duration, **kwargs)
