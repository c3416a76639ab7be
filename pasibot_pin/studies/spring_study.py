"""Does the fitted ankle spring hold the hip? Statics, the spring study and the seed's scenarios.

Built on the simulator of :mod:`pasibot_pin.dynamics.simulator`:

- the hip pitch where the robot stands still at each crank angle (the omega -> 0 answer):
  :func:`~pasibot_pin.studies.methods.statics.static_equilibrium`.
- :func:`toppling_stiffness`: gravity's negative stiffness k_g = g sum m_i (z_i - z_ankle) about
  the stance ankle; a spring must exceed it to hold the hip at all.
- :func:`spring_study`: the hip-pitch excursion with the fitted spring, none, half and twice the
  stiffness, and a (K_e, beta0) sweep for the most level hip.
- :func:`scenario_inputs`: robot, crank rate and fitted spring of a seed scenario, from the
  inverse dynamics (:mod:`pasibot_pin.dynamics.inverse`, :mod:`pasibot_pin.studies.methods.spring_fit`).

Units: SI; angles [rad].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import pinocchio as pin

from pasibot_pin.dynamics.inverse import STANCE_RANGE, crank_grid, inverse_dynamics, run_scenario
from pasibot_pin.dynamics.lockstep import simulate_many
from pasibot_pin.dynamics.simulator import SimulationResult, SimulationSettings, simulate
from pasibot_pin.dynamics.spring_energy import AnkleSpring, critical_foot_damping
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.closure import assemble
from pasibot_pin.model.design import check_parameter, design_robot
from pasibot_pin.model.scenario_robots import scenario_robot
from pasibot_pin.model.scenarios import get_preset, get_scenario
from pasibot_pin.reprs import short_repr
from pasibot_pin.studies.methods.spring_fit import design_spring, fit_result
from pasibot_pin.studies.methods.static_batch import static_equilibria
from pasibot_pin.studies.methods.statics import StaticEquilibrium, static_equilibrium

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot
    from pasibot_pin.studies.methods.spring_fit import SpringFit

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


def standing_pitch(robot: PasibotRobot, spring: AnkleSpring | None, theta0: float, cache: dict | None = None) -> float:
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

    __repr__ = short_repr

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


def _run_settings(omega: float, spring: AnkleSpring, swing_ankle: str, dt: float, pitch: float) -> SimulationSettings:
    return SimulationSettings(omega=omega, spring=spring, swing_ankle=swing_ankle, dt=dt, initial_pitch=pitch)


def _standing_pitch_of(eq: StaticEquilibrium) -> float:
    """:func:`standing_pitch` read from a static path whose first crank angle is pi/2 (the same solve)."""
    if eq.found[0] and eq.stiffness[0] > 0:
        return float(eq.hip_pitch[0])
    return 0.0


def _static_thetas(static_samples: int) -> np.ndarray:
    return np.linspace(math.pi / 2, 1.5 * math.pi, static_samples, endpoint=False)


def spring_case(
    robot: PasibotRobot,
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
    settings = _run_settings(omega, spring, swing_ankle, dt, _standing_pitch_of(static))
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
        raise ParameterError(f"unknown sweep_method {method!r}; valid: static, dynamic")
    if method == "dynamic" and omega <= 0:
        raise ParameterError("a dynamic sweep needs omega > 0")
    return method


def sweep_cells(
    robot: PasibotRobot,
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
    (:func:`~pasibot_pin.studies.methods.static_batch.static_equilibria`); a dynamic one with the swing foot
    at its rest angle walks every spring together
    (:func:`~pasibot_pin.dynamics.lockstep.simulate_many`: the same walks as :func:`simulate`, to
    round-off), each from its :func:`standing_pitch`.
    """
    dt = default_dt(swing_ankle) if dt is None else dt
    if method == "static":  # every spring and crank angle at once (the same secant, batched)
        thetas = _static_thetas(static_samples)
        return np.array([eq.max_excursion for eq in static_equilibria(robot, springs, thetas, cache=cache)])
    settings = [
        _run_settings(omega, sp, swing_ankle, dt, standing_pitch(robot, sp, math.pi / 2, cache)) for sp in springs
    ]
    if swing_ankle == "rest" and settings:
        runs = simulate_many(robot, settings, steps)
    else:
        runs = [simulate(robot, st, steps=steps) for st in settings]
    return np.array([_run_excursion(run) for run in runs], dtype=float)


def case_excursion(omega: float, static: StaticEquilibrium, run: SimulationResult | None) -> float:
    """A spring case's excursion: its walk's (omega > 0) or its static path's (omega = 0) [rad]."""
    return _run_excursion(run) if omega > 0 and run is not None else static.max_excursion


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
    robot: PasibotRobot,
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
    check_parameter("omega", omega)  # the design record's crank speeds (0: the static answer only)
    dt = default_dt(swing_ankle) if dt is None else dt
    cache: dict = {}
    common: dict[str, Any] = {
        "steps": steps,
        "swing_ankle": swing_ankle,
        "dt": dt,
        "static_samples": static_samples,
        "cache": cache,
    }
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
        spring_fit: the full fit (:class:`pasibot_pin.studies.methods.spring_fit.SpringFit`: R^2, residuals).

    """

    name: str
    omega: float
    robot: PasibotRobot
    fit: AnkleSpring
    spring_fit: SpringFit


def scenario_key(name: str) -> str:
    """``1`` -> ``run1``; ``quasi-static`` and ``runN`` unchanged (ValueError for unknown ones)."""
    return get_scenario(name).name


def scenario_inputs(name: str, preset: str = "default", damping: float | None = None) -> ScenarioInputs:
    """Robot, crank rate and fitted spring of a seed scenario (inverse dynamics of :mod:`pasibot_pin.dynamics.inverse`).

    Args:
        name: ``quasi-static``, ``run1`` .. ``run4`` (or ``1`` .. ``4``).
        preset: modelling choices of the inverse dynamics (``default``, ``seed``, ``seed-clean``).
        damping: ankle damping [N.m.s/rad] (default :func:`critical_foot_damping` of the fit).

    """
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
    (:func:`~pasibot_pin.studies.methods.spring_fit.design_spring`).
    """
    robot = design_robot(design, 2)
    result = inverse_dynamics(robot, crank_grid(*STANCE_RANGE, 61), design.omega, stance="right", reactions=False)
    fit = fit_result(result, None, warn=False)
    spring = design_spring(design, robot)
    if spring is None:
        raise ParameterError(f"the design's variant {design.variant!r} has no ankle spring to simulate")
    return ScenarioInputs("design", design.omega, robot, spring, fit)


def toppling_stiffness(robot: PasibotRobot, theta: float = math.pi) -> float:
    """Gravity's negative stiffness about the stance ankle, g sum m_i (z_i - z_ankle) [N.m/rad].

    Everything above the stance foot, rotated rigidly about the ankle by d(pitch), loses
    potential energy 0.5 k_g d(pitch)^2: the spring must be stiffer than k_g to hold the hip
    at all, and the static margin is K_e - k_g. Evaluated with the hip level at crank angle
    ``theta`` (default mid-stance).
    """
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
