"""Forward simulation with the hip pitch free: does the fitted ankle spring hold the hip at all.

Two studies, both built on :mod:`pasibot_pin.studies.spring_study` and the simulator of
:mod:`pasibot_pin.dynamics.simulator`:

- one scenario walked with the fitted spring, none, half and twice its stiffness
  (:class:`SimulateSettings`, :func:`simulation_setup`, :func:`run_simulation`; ``pasibot simulate``);
  at omega = 0 the answer is the static equilibrium along the stance instead of a walk,
- every seed scenario: the hip excursion of those springs, gravity's toppling stiffness, a
  (K_e, beta0) sweep, and a cross-check of the swing-foot model on the fast scenario
  (:class:`SimulationStudySettings`, :func:`simulation_study`; the ``simulation`` section of
  ``pasibot analyze``).

Also the columns of a run's CSV (:func:`simulation_columns`) and the frames of its animation
(:func:`animation_frames`). Nothing here writes files or draws.

Units: SI; angles [rad].
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from functools import cache as _memo
from functools import partial
from typing import TYPE_CHECKING

import numpy as np

from pasibot_pin.dynamics.simulator import SimulationResult, SimulationSettings, simulate
from pasibot_pin.dynamics.spring_energy import AnkleSpring, critical_foot_damping
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.scenarios import SCENARIOS
from pasibot_pin.reprs import short_repr
from pasibot_pin.studies.methods.statics import StaticEquilibrium, static_equilibrium
from pasibot_pin.studies.spring_study import (
    SPRING_CASES,
    ScenarioInputs,
    SpringStudy,
    assemble_spring_study,
    case_excursion,
    case_of_cell,
    default_dt,
    scenario_inputs,
    scenario_key,
    spring_case,
    standing_pitch,
    sweep_cells,
    sweep_method_for,
    sweep_springs,
    toppling_stiffness,
)

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot
    from pasibot_pin.studies.methods.spring_fit import SpringFit

MIN_STEPS_PER_STANCE: int = 20
"""Fewest integration steps per stance :class:`SimulateSettings` accepts (``dt`` <= stance / 20)."""

MAX_INTEGRATION_STEPS: int = 10_000_000
"""Most integration steps :class:`SimulateSettings` accepts over all its stances."""

MapFunction = Callable[..., Iterable]
"""A ``map``-like callable: ``map_fn(fn, items)`` yields ``fn(item)`` in order (builtin ``map``, a pool's ``map``)."""


# --------------------------------------------------------------------------- one scenario (pasibot simulate)
@dataclass(frozen=True)
class SimulateSettings:
    """One seed scenario walked with the hip pitch free.

    Attributes:
        scenario: seed scenario: ``quasi-static``, ``run1`` .. ``run4`` (or ``1`` .. ``4``).
        steps: stance phases to walk (>= 1).
        stiffness: ankle stiffness K_e [N.m/rad]; ``None``: the inverse-dynamics fit.
        rest_angle: spring rest angle beta0 [rad]; ``None``: the inverse-dynamics fit.
        damping: ankle damping c [N.m.s/rad]; ``None``: critical for the foot with this K_e.
        swing_ankle: ``rest`` (swing foot held at the rest angle) or ``spring`` (integrated).
        dt: integration step [s]; ``None``: :func:`~pasibot_pin.studies.spring_study.default_dt`. At most
            1/:data:`MIN_STEPS_PER_STANCE` of a stance, and at most :data:`MAX_INTEGRATION_STEPS` in all.
        cases: also the cases with no spring, half and twice K_e (else the fitted spring only).
        static_samples: crank angles over one stance for the quasi-static equilibria.

    """

    scenario: str = "1"
    steps: int = 2
    stiffness: float | None = None
    rest_angle: float | None = None
    damping: float | None = None
    swing_ankle: str = "rest"
    dt: float | None = None
    cases: bool = True
    static_samples: int = 19

    def __post_init__(self) -> None:
        if int(self.steps) < 1:
            raise ParameterError(f"parameter 'steps' must be a positive integer, got {self.steps!r}")
        if int(self.static_samples) < 1:
            raise ParameterError(f"parameter 'static_samples' must be a positive integer, got {self.static_samples!r}")
        if self.swing_ankle not in ("rest", "spring"):
            raise ParameterError(f"parameter 'swing_ankle' must be rest or spring, got {self.swing_ankle!r}")
        for name in ("stiffness", "rest_angle", "damping"):
            value = getattr(self, name)
            if value is not None and not math.isfinite(value):
                raise ParameterError(f"parameter {name!r} must be finite, got {value!r}")
        for name in ("stiffness", "damping"):
            value = getattr(self, name)
            if value is not None and value < 0:
                raise ParameterError(f"parameter {name!r} must be >= 0, got {value!r}")
        omega = SCENARIOS[scenario_key(self.scenario)].omega  # ValueError naming the scenarios
        if self.dt is None:
            return
        if not (math.isfinite(self.dt) and self.dt > 0):
            raise ParameterError(f"parameter 'dt' must be a positive integration step [s], got {self.dt!r}")
        if omega > 0:
            stance = math.pi / omega
            if self.dt > stance / MIN_STEPS_PER_STANCE:
                raise ParameterError(
                    f"parameter 'dt' = {self.dt:g} s is too long: a stance of scenario {self.scenario!r} lasts "
                    f"{stance:.3g} s; take dt <= {stance / MIN_STEPS_PER_STANCE:.3g} s"
                )
            if self.steps * stance / self.dt > MAX_INTEGRATION_STEPS:
                raise ParameterError(
                    f"parameter 'dt' = {self.dt:g} s gives {self.steps * stance / self.dt:.3g} integration steps "
                    f"for {self.steps} stance(s); at most {MAX_INTEGRATION_STEPS}"
                )

    @property
    def step(self) -> float:
        """The integration step used [s]: ``dt``, or the default for ``swing_ankle``."""
        return self.dt if self.dt is not None else default_dt(self.swing_ankle)


@dataclass
class SimulationSetup:
    """A scenario ready to simulate: its inverse-dynamics inputs and the spring to use.

    Attributes:
        settings: the settings.
        scenario: robot, crank rate [rad/s] and fitted spring of the scenario.
        spring: the spring of the ``fitted`` case (K_e [N.m/rad], beta0 [rad], c [N.m.s/rad]).

    """

    settings: SimulateSettings
    scenario: ScenarioInputs
    spring: AnkleSpring

    @property
    def quasi_static(self) -> bool:
        """True when the crank rate is 0: answered by static equilibria, no walk."""
        return self.scenario.omega <= 0

    @property
    def cases(self) -> tuple[tuple[str, float], ...]:
        """The spring cases: label and factor on K_e."""
        return SPRING_CASES if self.settings.cases else SPRING_CASES[:1]


@dataclass
class SimulationRun:
    """The outcome of :func:`run_simulation`.

    Attributes:
        setup: what was simulated.
        runs: case label -> walk (dynamic scenarios; empty at omega = 0).
        statics: case label -> static equilibrium path (quasi-static scenario; empty otherwise).

    """

    __repr__ = short_repr

    setup: SimulationSetup
    runs: dict[str, SimulationResult] = field(default_factory=dict)
    statics: dict[str, StaticEquilibrium] = field(default_factory=dict)

    @property
    def fitted(self) -> SimulationResult | None:
        """The walk with the fitted spring (``None`` at omega = 0)."""
        return self.runs.get("fitted")


CaseCallback = Callable[[str, "SimulationResult | StaticEquilibrium"], None]
"""Called with a case label and its outcome as soon as the case is done (progress)."""


def simulation_setup(settings: SimulateSettings) -> SimulationSetup:
    """The scenario's inverse-dynamics inputs and the spring of the ``fitted`` case.

    Raises:
        ValueError: unknown scenario.

    """
    scen = scenario_inputs(settings.scenario)
    k = scen.fit.stiffness if settings.stiffness is None else settings.stiffness
    beta0 = scen.fit.rest_angle if settings.rest_angle is None else settings.rest_angle
    damping = critical_foot_damping(scen.robot, k) if settings.damping is None else settings.damping
    return SimulationSetup(settings, scen, AnkleSpring(k, beta0, damping))


def simulation_cases(setup: SimulationSetup) -> Iterator[tuple[str, SimulationResult | StaticEquilibrium]]:
    """Each spring case of ``setup`` in turn: (label, walk), or (label, static equilibrium) at omega = 0."""
    settings, robot = setup.settings, setup.scenario.robot
    if setup.quasi_static:
        thetas = np.linspace(math.pi / 2, 1.5 * math.pi, settings.static_samples, endpoint=False)
        for label, factor in setup.cases:
            yield label, static_equilibrium(robot, setup.spring.scaled(factor), thetas)
        return
    for label, factor in setup.cases:
        spring = setup.spring.scaled(factor)  # factor 0: no spring
        sim = SimulationSettings(
            omega=setup.scenario.omega,
            spring=spring,
            swing_ankle=settings.swing_ankle,
            dt=settings.step,
            initial_pitch=standing_pitch(robot, spring, math.pi / 2),
        )
        yield label, simulate(robot, sim, steps=settings.steps)


def run_simulation(setup: SimulationSetup, on_case: CaseCallback | None = None) -> SimulationRun:
    """Simulate every spring case of ``setup`` (static equilibria at omega = 0).

    Args:
        setup: from :func:`simulation_setup`.
        on_case: optional progress callback, called with each case's label and outcome.

    Returns:
        The :class:`SimulationRun`.

    """
    result = SimulationRun(setup)
    for label, outcome in simulation_cases(setup):
        if isinstance(outcome, StaticEquilibrium):
            result.statics[label] = outcome
        else:
            result.runs[label] = outcome
        if on_case is not None:
            on_case(label, outcome)
    return result


def simulation_columns(robot: PasibotRobot, result: SimulationResult) -> dict[str, np.ndarray]:
    """A run's time series as CSV columns (SI units, angles [rad]).

    Columns: ``t`` [s], ``theta_right`` (right crank angle), ``hip_pitch``, ``beta_right``,
    ``beta_left`` [rad], ``Ta_right``, ``Ta_left`` (motor torques [N.m]), ``stance_right``
    (1 when the right foot is the stance foot, else 0) and ``swing_sole_height`` [m].
    """
    return {
        "t": result.t,
        "theta_right": result.q[:, robot.idx_q("right_j0_crank")],
        "hip_pitch": result.hip_pitch,
        "beta_right": result.beta[:, 0],
        "beta_left": result.beta[:, 1],
        "Ta_right": result.motor_torque[:, 0],
        "Ta_left": result.motor_torque[:, 1],
        "stance_right": np.array([1.0 if s == "right" else 0.0 for s in result.stance]),
        "swing_sole_height": result.swing_height,
    }


def check_fps(fps: float) -> float:
    """Return ``fps`` if it is a positive finite frame rate [1/s], else raise ``ValueError``."""
    if isinstance(fps, bool) or not isinstance(fps, (int, float)) or not (math.isfinite(fps) and fps > 0):
        raise ParameterError(f"parameter 'fps' must be positive [1/s], got {fps!r}")
    return float(fps)


def animation_frames(result: SimulationResult, fps: float) -> np.ndarray:
    """Rows of ``result.q`` resampled at ``fps`` frames per second of simulated time [1/s] (nearest sample)."""
    check_fps(fps)
    times = np.arange(0.0, result.t[-1] + 1e-12, 1.0 / fps)
    index = np.clip(np.searchsorted(result.t, times), 0, len(result.t) - 1)
    return result.q[index]


# --------------------------------------------------------------------------- every scenario (pasibot analyze)
@dataclass(frozen=True)
class SimulationStudySettings:
    """The study of every seed scenario.

    Attributes:
        scenarios: scenario keys, in report order.
        fast_omega: crank rate [rad/s] above which a scenario counts as fast.
        fast_steps: stance phases walked by a fast scenario.
        slow_steps: stance phases walked by a slow one.
        fast_dt: integration step of a fast scenario [s].
        slow_dt: integration step of a slow one [s].
        static_samples: crank angles over one stance for the static paths.
        check_scenario: scenario of the swing-foot model check (``""``: no check).
        check_dt: integration step of the check's run with the swing foot on its spring [s].
        check_steps: stance phases of that run.

    """

    scenarios: tuple[str, ...] = tuple(SCENARIOS)
    fast_omega: float = 1.0
    fast_steps: int = 4
    slow_steps: int = 2
    fast_dt: float = 0.01
    slow_dt: float = 0.02
    static_samples: int = 10
    check_scenario: str = "run4"
    check_dt: float = 0.002
    check_steps: int = 4


@dataclass
class ScenarioStudy:
    """One scenario of :func:`simulation_study`.

    Attributes:
        study: the spring study (fitted / none / half / twice K_e, the (K_e, beta0) sweep).
        toppling: gravity's toppling stiffness k_g about the stance ankle [N.m/rad].
        spring_fit: the inverse-dynamics fit (:class:`pasibot_pin.studies.methods.spring_fit.SpringFit`, its R^2).

    """

    __repr__ = short_repr

    study: SpringStudy
    toppling: float
    spring_fit: SpringFit

    @property
    def name(self) -> str:
        """The scenario key."""
        return self.study.name


@dataclass
class SwingFootCheck:
    """The fitted walk with the swing foot held at its rest angle vs integrated on its spring.

    Attributes:
        scenario: the scenario's inputs (its robot draws the animation).
        base: the study's fitted run (swing foot at rest angle).
        full: the same walk with the swing foot on its spring.
        gap: largest hip-pitch difference between the two [rad].

    """

    __repr__ = short_repr

    scenario: ScenarioInputs | None
    base: SimulationResult
    full: SimulationResult
    gap: float


@dataclass
class SimulationStudy:
    """The outcome of :func:`simulation_study`.

    Attributes:
        settings: the settings.
        scenarios: one :class:`ScenarioStudy` per scenario, in settings order.
        check: the swing-foot model check (``None`` when not asked for).

    """

    __repr__ = short_repr

    settings: SimulationStudySettings
    scenarios: list[ScenarioStudy]
    check: SwingFootCheck | None = None


# The scenario studies in independent pieces (pool tasks): each spring case, each row of the
# sweep, the swing-foot check's run. A process keeps each scenario's inputs and static-assembly
# cache, so its pieces share them; the results do not depend on which process ran what.
@_memo
def cached_inputs(name: str) -> ScenarioInputs:
    """:func:`~pasibot_pin.studies.spring_study.scenario_inputs`, computed once per process."""
    return scenario_inputs(name)


@_memo
def _static_cache(name: str) -> dict:
    return {}


def _run_options(name: str, settings: SimulationStudySettings) -> dict:
    fast = cached_inputs(name).omega > settings.fast_omega
    return {
        "steps": settings.fast_steps if fast else settings.slow_steps,
        "dt": settings.fast_dt if fast else settings.slow_dt,
        "static_samples": settings.static_samples,
        "cache": _static_cache(name),
    }


def case_task(
    name: str, label: str, settings: SimulationStudySettings
) -> tuple[StaticEquilibrium, SimulationResult | None]:  # noqa: E501
    """One spring case of scenario ``name``: its static path and walk (:func:`~.spring_study.spring_case`)."""
    scen = cached_inputs(name)
    spring = scen.fit.scaled(dict(SPRING_CASES)[label])
    return spring_case(scen.robot, scen.omega, spring, **_run_options(name, settings))


def sweep_shape(name: str) -> tuple[int, int]:
    """(rows = beta0 values, columns = K_e values) of scenario ``name``'s sweep."""
    ks, bs = sweep_springs(cached_inputs(name).fit)
    return len(bs), len(ks)


def sweep_row_task(name: str, row: int, settings: SimulationStudySettings) -> np.ndarray:
    """Row ``row`` (one beta0) of scenario ``name``'s (K_e, beta0) sweep [rad].

    NaN marks a cell whose spring is one of the spring cases': :func:`assemble_scenario` fills
    it from that case instead of computing it again.
    """
    return sweep_rows_task(name, (row,), settings)[0]


def sweep_rows_task(name: str, rows: Sequence[int], settings: SimulationStudySettings) -> list[np.ndarray]:
    """Rows ``rows`` of scenario ``name``'s (K_e, beta0) sweep [rad], as :func:`sweep_row_task` each.

    The cells of all the rows go together to :func:`~pasibot_pin.studies.spring_study.sweep_cells`
    (a dynamic sweep walks them in lockstep: the more, the cheaper each).
    """
    scen = cached_inputs(name)
    ks, bs = sweep_springs(scen.fit)
    method = sweep_method_for(scen.omega)
    out = [np.full(len(ks), np.nan) for _ in rows]
    todo = []
    for r, row in enumerate(rows):
        for j, k in enumerate(ks):
            spring = AnkleSpring(float(k), float(bs[row]), scen.fit.damping)
            if case_of_cell(scen.fit, spring) is None:
                todo.append(((r, j), spring))
    if todo:
        values = sweep_cells(scen.robot, scen.omega, [sp for _, sp in todo], method, **_run_options(name, settings))
        for ((r, j), _), value in zip(todo, values):
            out[r][j] = value
    return out


@dataclass(frozen=True)
class ScenarioMeta:
    """What assembling a scenario's study needs besides its pieces (small: it crosses processes).

    Attributes:
        name: scenario key.
        omega: crank rate [rad/s].
        fit: the inverse-dynamics spring.
        toppling: gravity's toppling stiffness [N.m/rad].
        spring_fit: the full fit.

    """

    name: str
    omega: float
    fit: AnkleSpring
    toppling: float
    spring_fit: SpringFit


def meta_task(name: str) -> ScenarioMeta:
    """Scenario ``name``'s :class:`ScenarioMeta`."""
    scen = cached_inputs(name)
    return ScenarioMeta(name, scen.omega, scen.fit, toppling_stiffness(scen.robot), scen.spring_fit)


def assemble_scenario(meta: ScenarioMeta, cases: dict, rows: list[np.ndarray]) -> ScenarioStudy:
    """A :class:`ScenarioStudy` from its :func:`case_task` (label -> outcome) and :func:`sweep_row_task` results."""
    ks, bs = sweep_springs(meta.fit)
    method = sweep_method_for(meta.omega)
    grid = np.array(rows, dtype=float).reshape(len(bs), len(ks))
    for i, beta0 in enumerate(bs):
        for j, k in enumerate(ks):
            label = case_of_cell(meta.fit, AnkleSpring(float(k), float(beta0), meta.fit.damping))
            if label is not None:
                grid[i, j] = case_excursion(meta.omega if method == "dynamic" else 0.0, *cases[label])
    study = assemble_spring_study(meta.name, meta.omega, meta.fit, cases, ks, bs, grid, method)
    return ScenarioStudy(study, meta.toppling, meta.spring_fit)


def check_settings(settings: SimulationStudySettings) -> SimulationSettings:
    """The check run's settings: the check scenario's fitted walk, swing foot on its spring."""
    scen = cached_inputs(settings.check_scenario)
    fast = scen.omega > settings.fast_omega
    base = SimulationSettings(
        omega=scen.omega,
        spring=scen.fit,
        swing_ankle="rest",
        dt=settings.fast_dt if fast else settings.slow_dt,
        initial_pitch=standing_pitch(scen.robot, scen.fit, math.pi / 2),
    )
    return base.with_(swing_ankle="spring", dt=settings.check_dt)


def check_task(settings: SimulationStudySettings) -> SimulationResult:
    """The swing-foot check's run (independent of the studies: a pool task)."""
    return simulate(cached_inputs(settings.check_scenario).robot, check_settings(settings), steps=settings.check_steps)


def scenario_study(name: str, settings: SimulationStudySettings | None = None) -> ScenarioStudy:
    """One scenario's spring study, toppling stiffness and fit (independent of the others: a pool task)."""
    settings = settings or SimulationStudySettings()
    cases = {label: case_task(name, label, settings) for label, _ in SPRING_CASES}
    rows = sweep_rows_task(name, range(sweep_shape(name)[0]), settings)
    return assemble_scenario(meta_task(name), cases, rows)


def scenario_studies(settings: SimulationStudySettings | None = None, map: MapFunction = map) -> list[ScenarioStudy]:
    """:func:`scenario_study` of every scenario of ``settings``.

    Args:
        settings: the study settings (default :class:`SimulationStudySettings`).
        map: how to map the (independent) scenario studies, e.g. a process pool's ``map``;
            results come back in scenario order, identical to the builtin ``map``.

    """
    settings = settings or SimulationStudySettings()
    return list(map(partial(scenario_study, settings=settings), settings.scenarios))


def swing_foot_check(
    studies: list[ScenarioStudy], settings: SimulationStudySettings | None = None, full: SimulationResult | None = None
) -> SwingFootCheck:
    """Rerun the check scenario's fitted walk with the swing foot integrated on its spring.

    Args:
        studies: the scenario studies (the check scenario's fitted walk is the base).
        settings: the study settings.
        full: the check run if already computed (:func:`check_task`).

    Raises:
        ValueError: the check scenario is not among ``studies`` or has no walk.

    """
    settings = settings or SimulationStudySettings()
    names = [s.name for s in studies]
    if settings.check_scenario not in names:
        raise ParameterError(f"check scenario {settings.check_scenario!r} not studied; studied: {', '.join(names)}")
    base = studies[names.index(settings.check_scenario)].study.runs.get("fitted")
    if base is None:
        raise ParameterError(f"check scenario {settings.check_scenario!r} has no walk (omega = 0)")
    scen = cached_inputs(settings.check_scenario)
    if base.settings is None:
        raise ParameterError(f"check scenario {settings.check_scenario!r}: its walk carries no settings")
    full_settings = base.settings.with_(swing_ankle="spring", dt=settings.check_dt)
    if full is None or full.settings != full_settings:
        full = simulate(scen.robot, full_settings, steps=settings.check_steps)
    return SwingFootCheck(scen, base, full, hip_pitch_gap(base, full))


def hip_pitch_gap(base: SimulationResult, full: SimulationResult) -> float:
    """Largest difference of ``full``'s hip pitch from ``base``'s (interpolated at ``full``'s times) [rad]."""
    return float(np.max(np.abs(np.interp(full.t, base.t, base.hip_pitch) - full.hip_pitch)))


def simulation_study(settings: SimulationStudySettings | None = None, map: MapFunction = map) -> SimulationStudy:
    """Every scenario's spring study and the swing-foot model check.

    Args:
        settings: the study settings (default :class:`SimulationStudySettings`).
        map: how to map the scenario studies (see :func:`scenario_studies`).

    Returns:
        The :class:`SimulationStudy`.

    """
    settings = settings or SimulationStudySettings()
    studies = scenario_studies(settings, map)
    check = swing_foot_check(studies, settings) if settings.check_scenario else None
    return SimulationStudy(settings, studies, check)
