"""Does the fitted ankle spring hold the hip? Statics, the spring study and the seed's scenarios.

Built on the simulator of :mod:`pasibot_pin.dynamics.simulator`:

- :func:`static_equilibrium`: the hip pitch where the robot stands still at each crank angle
  (cranks held, swing foot at the spring's rest angle): the omega -> 0 answer, with its
  stability (d^2V/dpitch^2).
- :func:`toppling_stiffness`: gravity's negative stiffness k_g = g sum m_i (z_i - z_ankle) about
  the stance ankle; a spring must exceed it to hold the hip at all.
- :func:`spring_study`: the hip-pitch excursion with the fitted spring, none, half and twice the
  stiffness, and a (K_e, beta0) sweep for the most level hip.
- :func:`scenario_inputs`: robot, crank rate and fitted spring of a seed scenario, from the
  inverse dynamics (:mod:`pasibot_pin.dynamics.inverse`, :mod:`pasibot_pin.studies.spring_fit`).

Units: SI; angles [rad].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin

from pasibot_pin.constraints import ConstraintSystem, coordinate
from pasibot_pin.dynamics.simulator import (
    AnkleSpring,
    BipedSimulator,
    SimulationResult,
    SimulationSettings,
    _check_finite,
    _other,
    critical_foot_damping,
    simulate,
)


# --------------------------------------------------------------------------- statics (the omega -> 0 limit)
@dataclass
class StaticEquilibrium:
    """Hip pitch at static equilibrium along the crank cycle (cranks still, swing foot at rest angle).

    Attributes:
        theta: right crank angles (n,) [rad].
        hip_pitch: equilibrium hip pitch (n,) [rad]; NaN where there is none within the search range.
        stiffness: d(holding torque)/d(pitch) at the equilibrium, i.e. d^2V/dpitch^2 (n,)
            [N.m/rad]: positive when the equilibrium is stable, negative when the robot falls away.
        found: True where an equilibrium was found.

    """

    theta: np.ndarray
    hip_pitch: np.ndarray
    stiffness: np.ndarray
    found: np.ndarray

    @property
    def max_excursion(self) -> float:
        """Largest |equilibrium hip pitch| [rad] (inf when some crank angle has no stable equilibrium)."""
        if not np.all(self.found) or np.any(self.stiffness <= 0):
            return math.inf
        return float(np.max(np.abs(self.hip_pitch)))


class StaticProblem:
    """The hip-holding torque as a function of the hip pitch, at one crank angle.

    Cranks locked at ``theta``, swing ankle at the rest angle, stance foot welded flat.
    ``cache`` (a dict) lets several springs share the work that does not depend on the
    stiffness: the assembly at each crank angle, and per (crank angle, rest angle) the
    constraint system and the projections onto it (the same start and pitch give the same q;
    only the torque, from the spring forces, differs).
    """

    def __init__(self, robot, spring: AnkleSpring | None, theta: float, cache: dict | None = None):
        spring = spring if spring is not None else AnkleSpring(0.0, math.pi / 2)
        settings = SimulationSettings(omega=0.0, spring=spring, hip="level", swing_ankle="rest", theta0=theta)
        self.robot = robot
        self.sim = BipedSimulator(robot, settings)
        key = round(float(theta), 12)
        shared_key = ("system", key, float(spring.rest_angle))
        if cache is not None and shared_key in cache:
            self.q_level, self.cset, self.targets, self.projections = cache[shared_key]
            self.row = self.cset.nrows - 1
            return
        if cache is not None and key in cache:
            q_level, stance, weld = cache[key]
        else:
            q_level, _, stance = self.sim.initial_state()
            weld = self.sim.ground_weld(stance, q_level)
            if cache is not None:
                cache[key] = (q_level, stance, weld)
        self.q_level = q_level.copy()
        swing = _other(stance)
        self.q_level[self.sim.ankles[swing]] = math.pi / 2 - spring.rest_angle
        # one system per crank angle: the swing ankle's rest angle and the hip pitch are targets of their
        # rows (offset 0, so a target t gives the residual q_i - t, the same bits as an offset t)
        system_key = ("rows", key)
        if cache is not None and system_key in cache:
            self.cset = cache[system_key]
        else:
            coords = [c.at(0.0) if c.name == f"{swing}_j13_ankle" else c for c in self.sim.coordinate_rows(stance)]
            coords = [c for c in coords if c.name != "hip_pitch"]
            cmodels = list(robot.loop_constraints) + [weld]
            rows = [*coords, coordinate("hip_pitch", 2)]  # the hip-pitch row is last
            self.cset = ConstraintSystem(robot.model, robot.data, cmodels, rows, robot.geometry.L)
            if cache is not None:
                cache[system_key] = self.cset
        self.targets = self.cset.targets(0.0)
        self.targets[self.cset.labels.index(f"{swing}_j13_ankle") - self.cset.n_constraint_rows] = (
            math.pi / 2 - spring.rest_angle
        )
        self.row = self.cset.nrows - 1
        self.projections: dict = {}
        if cache is not None:
            cache[shared_key] = (self.q_level, self.cset, self.targets, self.projections)

    def torque(self, pitch: float, q_guess=None) -> tuple[float, np.ndarray]:
        """The hip-holding torque [N.m] at hip pitch ``pitch`` [rad], and the static q it solved.

        ``q_guess``: the Newton start (default: the level pose at this crank angle).

        At rest the system is square (nv rows: loops, weld, cranks, swing ankle, hip), so J a = 0
        gives a = 0 and M a + h = tau + J^T lambda reduces to J^T lambda = g(q) - tau_spring(q): the
        hip row's multiplier is x . (g - tau_spring) with J x = e_hip. x . g and x on the ankles
        depend on q only and are kept with the projection (shared by every stiffness).
        """
        q = self.q_level if q_guess is None else np.array(q_guess, dtype=float)
        key = (float(pitch), q.tobytes())
        entry = self.projections.get(key)
        if entry is None:
            targets = self.targets.copy()
            targets[-1] = pitch
            q = self.cset.project(q, 0.0, targets=targets, metric="mass", max_iter=20)
            entry = self.projections[key] = (q.copy(), *self._hip_row(q, self.cset.last_rows.jac))
        q, x_gravity, x_ankles = entry
        # tau_spring on an ankle coordinate is -T = K_e (beta - beta0) (damping: no rate at rest)
        spring = self.sim.settings.spring
        hold = x_gravity
        for i, x_i in x_ankles:
            hold -= x_i * spring.stiffness * ((math.pi / 2 - q[i]) - spring.rest_angle)
        return float(hold), q.copy()

    def _hip_row(self, q: np.ndarray, jac: np.ndarray) -> tuple[float, tuple[tuple[int, float], ...]]:
        """The hip row's multiplier map: x . g(q) and x on each ankle coordinate, for J x = e_hip."""
        model, data = self.robot.model, self.robot.data
        unit = np.zeros(self.cset.nrows)
        unit[self.row] = 1.0
        x = np.linalg.solve(jac, unit)
        gravity = pin.computeGeneralizedGravity(model, data, q)
        return float(x.dot(gravity)), tuple((i, float(x[i])) for i in self.sim.ankles.values())


def static_hip_torque(robot, spring: AnkleSpring | None, theta: float, pitch: float, q_guess=None):
    """Torque needed on the hip pitch to hold the robot still at crank angle ``theta`` and ``pitch``.

    The cranks are locked (the motor holds them), the swing ankle sits at the spring's rest
    angle, the stance foot (from ``theta``) is welded flat. Zero at a static equilibrium.

    Returns:
        (torque [N.m], q).

    """
    return StaticProblem(robot, spring, theta).torque(pitch, q_guess)


def static_equilibrium(
    robot,
    spring: AnkleSpring | None,
    thetas: Sequence[float],
    search: float = math.radians(30.0),
    cache: dict | None = None,
) -> StaticEquilibrium:
    """Equilibrium hip pitch at each crank angle (the quasi-static limit omega -> 0).

    For each crank angle, the hip-holding torque tau(pitch) of :func:`static_hip_torque` is
    driven to zero by the secant method from pitch = 0, within +-``search`` [rad]. ``cache``
    (a dict, filled on first use) shares the assembly of each crank angle between calls.
    """
    thetas = np.asarray(thetas, dtype=float)
    pitch = np.full(len(thetas), np.nan)
    stiff = np.full(len(thetas), np.nan)
    found = np.zeros(len(thetas), dtype=bool)
    for k, theta in enumerate(thetas):
        try:
            problem = StaticProblem(robot, spring, float(theta), cache)
            p0, p1 = 0.0, 1e-3
            f0, q = problem.torque(p0)
            f1, q = problem.torque(p1, q)
            for _ in range(30):
                if f1 == f0:
                    break
                p2 = p1 - f1 * (p1 - p0) / (f1 - f0)
                if abs(p2) > search:
                    break
                p0, f0 = p1, f1
                p1 = p2
                f1, q = problem.torque(p1, q)
                if abs(p1 - p0) < 1e-12:
                    break
            if abs(f1) < 1e-8 and abs(p1) <= search:
                eps = 1e-5
                fp = problem.torque(p1 + eps, q)[0]
                fm = problem.torque(p1 - eps, q)[0]
                pitch[k], stiff[k], found[k] = p1, (fp - fm) / (2 * eps), True
        except ValueError:
            continue
    return StaticEquilibrium(thetas, pitch, stiff, found)


# --------------------------------------------------------------------------- the spring study
SPRING_CASES: tuple[tuple[str, float], ...] = (
    ("fitted", 1.0),
    ("no spring", 0.0),
    ("half K_e", 0.5),
    ("twice K_e", 2.0),
)
"""The stiffness cases of the study: label and factor on the fitted K_e."""

SWEEP_FACTORS: tuple[float, ...] = (0.8, 1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0)
"""Default sweep of K_e, as factors on the fitted stiffness."""
SWEEP_OFFSETS_DEG: tuple[float, ...] = (-6.0, -3.0, 0.0, 3.0, 6.0)
"""Default sweep of beta0, as offsets from the fitted rest angle [deg]."""


def default_dt(swing_ankle: str) -> float:
    """Integration step [s]: 10 ms with the swing foot at rest angle, 2 ms with its 100 Hz spring mode."""
    return 0.01 if swing_ankle == "rest" else 0.002


def standing_pitch(robot, spring: AnkleSpring | None, theta0: float, cache: dict | None = None) -> float:
    """The hip pitch where the robot stands still at crank angle ``theta0`` [rad] (0 if none is stable).

    ``cache``: the static solves' assembly cache (see :func:`static_equilibrium`; the same answer).
    """
    eq = static_equilibrium(robot, spring, [theta0], cache=cache)
    if eq.found[0] and eq.stiffness[0] > 0:
        return float(eq.hip_pitch[0])
    return 0.0


@dataclass
class SpringStudy:
    """Does the spring hold the hip? One scenario, several springs.

    Attributes:
        name: scenario label.
        omega: crank rate [rad/s] (0: quasi-static, answered by static equilibria).
        fitted: the inverse-dynamics spring.
        excursion: case label -> largest |hip pitch| [rad] (inf: fell / no stable equilibrium).
        runs: case label -> SimulationResult (dynamic scenarios).
        statics: case label -> StaticEquilibrium (always computed: the omega -> 0 reference).
        sweep_stiffness: K_e grid [N.m/rad].
        sweep_rest: beta0 grid [rad].
        sweep_excursion: (len(sweep_rest), len(sweep_stiffness)) largest |hip pitch| [rad].
        sweep_method: ``dynamic`` or ``static``.
        best: the most level (K_e, beta0) of the sweep.

    """

    name: str
    omega: float
    fitted: AnkleSpring
    excursion: dict[str, float] = field(default_factory=dict)
    runs: dict[str, SimulationResult] = field(default_factory=dict)
    statics: dict[str, StaticEquilibrium] = field(default_factory=dict)
    sweep_stiffness: np.ndarray | None = None
    sweep_rest: np.ndarray | None = None
    sweep_excursion: np.ndarray | None = None
    sweep_method: str = ""
    best: tuple[float, float] | None = None


def _run_excursion(res: SimulationResult) -> float:
    return math.inf if res.fell else res.max_hip_excursion


def _walk_settings(omega: float, spring: AnkleSpring, swing_ankle: str, dt: float, pitch: float) -> SimulationSettings:
    return SimulationSettings(omega=omega, spring=spring, swing_ankle=swing_ankle, dt=dt, initial_pitch=pitch)


def _standing_pitch_of(eq: StaticEquilibrium) -> float:
    """:func:`standing_pitch` read from a static path whose first crank angle is pi/2 (the same solve)."""
    if eq.found[0] and eq.stiffness[0] > 0:
        return float(eq.hip_pitch[0])
    return 0.0


def _static_thetas(static_samples: int) -> np.ndarray:
    return np.linspace(math.pi / 2, 1.5 * math.pi, static_samples, endpoint=False)


def spring_case(
    robot,
    omega: float,
    spring: AnkleSpring,
    steps: int = 2,
    swing_ankle: str = "rest",
    dt: float | None = None,
    static_samples: int = 19,
    cache: dict | None = None,
) -> tuple[StaticEquilibrium, SimulationResult | None]:
    """One spring of :func:`spring_study`: its static path and, for omega > 0, its walk.

    The walk starts at :func:`standing_pitch`, read from the static path's first crank angle
    (pi/2: the same solve). ``cache`` is the static solves' assembly cache (see
    :func:`static_equilibrium`).
    """
    dt = default_dt(swing_ankle) if dt is None else dt
    thetas = _static_thetas(static_samples)
    static = static_equilibrium(robot, spring, thetas, cache=cache)
    if omega <= 0:
        return static, None
    settings = _walk_settings(omega, spring, swing_ankle, dt, _standing_pitch_of(static))
    return static, simulate(robot, settings, steps=steps)


def sweep_springs(fitted: AnkleSpring, sweep_stiffness=None, sweep_rest=None) -> tuple[np.ndarray, np.ndarray]:
    """The (K_e, beta0) grids of :func:`spring_study` [N.m/rad], [rad]."""
    ks = fitted.stiffness * np.array(SWEEP_FACTORS) if sweep_stiffness is None else np.asarray(sweep_stiffness)
    bs = fitted.rest_angle + np.radians(SWEEP_OFFSETS_DEG) if sweep_rest is None else np.asarray(sweep_rest)
    return ks, bs


def sweep_method_for(omega: float, sweep_method: str | None = None) -> str:
    """The sweep method of :func:`spring_study` (static for omega <= 0.1 rad/s, dynamic above)."""
    method = sweep_method or ("static" if omega <= 0.1 else "dynamic")
    if method not in ("static", "dynamic"):
        raise ValueError(f"unknown sweep_method {method!r}; valid: static, dynamic")
    if method == "dynamic" and omega <= 0:
        raise ValueError("a dynamic sweep needs omega > 0")
    return method


def sweep_cells(
    robot,
    omega: float,
    springs: Sequence[AnkleSpring],
    method: str,
    steps: int = 2,
    swing_ankle: str = "rest",
    dt: float | None = None,
    static_samples: int = 19,
    cache: dict | None = None,
) -> np.ndarray:
    """Cells of the (K_e, beta0) sweep, one per spring: the largest |hip pitch| [rad] (inf: fell / none stable).

    A static sweep solves every spring's equilibria together
    (:func:`~pasibot_pin.studies.static_batch.static_equilibria`); a dynamic one with the swing foot
    at its rest angle walks every spring together
    (:func:`~pasibot_pin.dynamics.lockstep.simulate_many`: the same walks as :func:`simulate`, to
    round-off), each from its :func:`standing_pitch`.
    """
    dt = default_dt(swing_ankle) if dt is None else dt
    if method == "static":  # every spring and crank angle at once (the same secant, batched)
        from pasibot_pin.studies.static_batch import static_equilibria

        thetas = _static_thetas(static_samples)
        return np.array([eq.max_excursion for eq in static_equilibria(robot, springs, thetas, cache=cache)])
    settings = [
        _walk_settings(omega, sp, swing_ankle, dt, standing_pitch(robot, sp, math.pi / 2, cache)) for sp in springs
    ]
    if swing_ankle == "rest" and settings:
        from pasibot_pin.dynamics.lockstep import simulate_many

        runs = simulate_many(robot, settings, steps)
    else:
        runs = [simulate(robot, st, steps=steps) for st in settings]
    return np.array([_run_excursion(run) for run in runs], dtype=float)


def case_excursion(omega: float, static: StaticEquilibrium, run: SimulationResult | None) -> float:
    """A spring case's excursion: its walk's (omega > 0) or its static path's (omega = 0) [rad]."""
    return _run_excursion(run) if omega > 0 else static.max_excursion


def assemble_spring_study(
    name: str,
    omega: float,
    fitted: AnkleSpring,
    cases: dict[str, tuple[StaticEquilibrium, SimulationResult | None]],
    ks: np.ndarray,
    bs: np.ndarray,
    grid: np.ndarray | None,
    method: str,
) -> SpringStudy:
    """A :class:`SpringStudy` from its spring cases (label -> (static path, walk)) and its sweep grid."""
    study = SpringStudy(name=name, omega=omega, fitted=fitted)
    for label, _ in SPRING_CASES:
        static, run = cases[label]
        study.statics[label] = static
        if run is not None:
            study.runs[label] = run
        study.excursion[label] = case_excursion(omega, static, run)
    if grid is not None:
        study.sweep_stiffness, study.sweep_rest, study.sweep_excursion, study.sweep_method = ks, bs, grid, method
        if np.any(np.isfinite(grid)):
            i, j = np.unravel_index(int(np.argmin(grid)), grid.shape)
            study.best = (float(ks[j]), float(bs[i]))
    return study


def case_of_cell(fitted: AnkleSpring, spring: AnkleSpring) -> str | None:
    """The spring case whose spring is exactly ``spring`` (its sweep cell repeats that case), or None."""
    for label, factor in SPRING_CASES:
        if fitted.scaled(factor) == spring:
            return label
    return None


def spring_study(
    robot,
    omega: float,
    fitted: AnkleSpring,
    name: str = "",
    steps: int = 2,
    swing_ankle: str = "rest",
    dt: float | None = None,
    sweep_stiffness: Sequence[float] | None = None,
    sweep_rest: Sequence[float] | None = None,
    sweep_method: str | None = None,
    static_samples: int = 19,
) -> SpringStudy:
    """Hip-pitch excursion with the fitted spring, none, half and twice the stiffness; and a sweep.

    Args:
        robot: the scenario's robot (``spring``, two legs, the scenario's masses).
        omega: crank rate [rad/s]; 0 answers with static equilibria only.
        fitted: the inverse-dynamics spring (K_e, beta0, damping).
        name: label.
        steps: stance phases to walk per run.
        swing_ankle: ``rest`` or ``spring`` (see :class:`SimulationSettings`).
        dt: integration step [s] (default :func:`default_dt`).
        sweep_stiffness: K_e grid [N.m/rad] (default :data:`SWEEP_FACTORS` times the fit);
            empty: no sweep.
        sweep_rest: beta0 grid [rad] (default the fit + :data:`SWEEP_OFFSETS_DEG`).
        sweep_method: ``dynamic`` (a walk per pair) or ``static`` (the equilibrium path,
            omega -> 0); default static for omega <= 0.1 rad/s, dynamic above.
        static_samples: crank angles over one stance for the static paths.

    Returns:
        The :class:`SpringStudy`. The pieces (:func:`spring_case`, :func:`sweep_cells`,
        :func:`assemble_spring_study`) can also run apart, e.g. on a process pool; a sweep cell
        whose spring is one of the cases' is not computed again.

    """
    _check_finite("omega", omega, 0.0)
    dt = default_dt(swing_ankle) if dt is None else dt
    cache: dict = {}
    common = {"steps": steps, "swing_ankle": swing_ankle, "dt": dt, "static_samples": static_samples, "cache": cache}
    cases = {label: spring_case(robot, omega, fitted.scaled(f), **common) for label, f in SPRING_CASES}
    ks, bs = sweep_springs(fitted, sweep_stiffness, sweep_rest)
    grid, method = None, ""
    if len(ks) and len(bs):
        method = sweep_method_for(omega, sweep_method)
        grid = np.full((len(bs), len(ks)), math.inf)
        todo = []
        for i, beta0 in enumerate(bs):
            for j, k in enumerate(ks):
                spring = AnkleSpring(float(k), float(beta0), fitted.damping)
                label = case_of_cell(fitted, spring)
                if label is not None:
                    grid[i, j] = case_excursion(omega if method == "dynamic" else 0.0, *cases[label])
                else:
                    todo.append(((i, j), spring))
        if todo:
            values = sweep_cells(robot, omega, [sp for _, sp in todo], method, **common)
            for (cell, _), value in zip(todo, values):
                grid[cell] = value
    return assemble_spring_study(name, omega, fitted, cases, ks, bs, grid, method)


# --------------------------------------------------------------------------- the seed's scenarios
@dataclass
class ScenarioInputs:
    """What a simulation of a seed scenario needs, from the inverse dynamics.

    Attributes:
        name: scenario key (``quasi-static``, ``run1`` ... ``run4``).
        omega: crank rate [rad/s].
        robot: the scenario's robot (its body mass and COM).
        fit: the inverse-dynamics spring (K_e, beta0) with the foot's critical damping.
        spring_fit: the full fit (:class:`pasibot_pin.studies.spring_fit.SpringFit`: R^2, residuals).

    """

    name: str
    omega: float
    robot: object
    fit: AnkleSpring
    spring_fit: object


def scenario_key(name: str) -> str:
    """``1`` -> ``run1``; ``quasi-static`` and ``runN`` unchanged (ValueError for unknown ones)."""
    from pasibot_pin.model.scenarios import get_scenario

    return get_scenario(name).name


def scenario_inputs(name: str, preset: str = "default", damping: float | None = None) -> ScenarioInputs:
    """Robot, crank rate and fitted spring of a seed scenario (inverse dynamics of :mod:`pasibot_pin.dynamics.inverse`).

    Args:
        name: ``quasi-static``, ``run1`` .. ``run4`` (or ``1`` .. ``4``).
        preset: modelling choices of the inverse dynamics (``default``, ``seed``, ``seed-clean``).
        damping: ankle damping [N.m.s/rad] (default :func:`critical_foot_damping` of the fit).

    """
    from pasibot_pin.dynamics.inverse import run_scenario, scenario_robot
    from pasibot_pin.model.scenarios import get_preset, get_scenario
    from pasibot_pin.studies.spring_fit import fit_result

    key = scenario_key(name)
    scenario, choices = get_scenario(key), get_preset(preset)
    result = run_scenario(scenario, choices)
    fit = fit_result(result, choices.fit_thetas, warn=False)
    robot = scenario_robot(scenario, choices)
    c = critical_foot_damping(robot, fit.K_e) if damping is None else damping
    return ScenarioInputs(key, scenario.omega, robot, AnkleSpring(fit.K_e, fit.beta0, c), fit)


def design_inputs(design) -> ScenarioInputs:
    """What a simulation of a :class:`~pasibot_pin.model.design.Design` needs (named ``design``).

    Its two-legged robot, crank speed, and ankle spring: the design's K_e and beta0 where it sets
    them, else the stance fit of its inverse dynamics; the damping is the design's
    (:func:`~pasibot_pin.studies.spring_fit.design_spring`).
    """
    from pasibot_pin.dynamics.inverse import STANCE_RANGE, crank_grid, inverse_dynamics
    from pasibot_pin.model.design import design_robot
    from pasibot_pin.studies.spring_fit import design_spring, fit_result

    robot = design_robot(design, 2)
    result = inverse_dynamics(robot, crank_grid(*STANCE_RANGE, 61), design.omega, stance="right", reactions=False)
    fit = fit_result(result, None, warn=False)
    spring = design_spring(design, robot)
    if spring is None:
        raise ValueError(f"the design's variant {design.variant!r} has no ankle spring to simulate")
    return ScenarioInputs("design", design.omega, robot, spring, fit)


def toppling_stiffness(robot, theta: float = math.pi) -> float:
    """Gravity's negative stiffness about the stance ankle, g sum m_i (z_i - z_ankle) [N.m/rad].

    Everything above the stance foot, rotated rigidly about the ankle by d(pitch), loses
    potential energy 0.5 k_g d(pitch)^2: the spring must be stiffer than k_g to hold the hip
    at all, and the static margin is K_e - k_g. Evaluated with the hip level at crank angle
    ``theta`` (default mid-stance).
    """
    from pasibot_pin.model.closure import assemble

    stance = "right" if (theta - math.pi / 2) % (2 * math.pi) < math.pi else "left"
    q = assemble(robot, theta, stance=stance)
    model, data = robot.model, robot.data
    com = pin.centerOfMass(model, data, q)
    total = sum(model.inertias[j].mass for j in range(1, model.njoints))
    foot = model.getJointId(f"{stance}_j13_ankle")
    m_foot = model.inertias[foot].mass
    foot_com = data.oMi[foot].act(model.inertias[foot].lever)
    pin.framesForwardKinematics(model, data, q)
    z_ankle = data.oMf[robot.frame_id(f"{stance}_foot")].translation[2]
    g = float(np.linalg.norm(model.gravity.linear))
    return float(g * (total * com[2] - m_foot * foot_com[2] - (total - m_foot) * z_ankle))
