"""Does a design walk? Put it on the floor, turn its cranks, and judge the walk.

:func:`walk_design` builds the design's two-legged robot (its variant, motor layout, sole,
masses, ankle spring where it has one), starts it from a consistent state on the floor
(:meth:`~pasibot_pin.dynamics.floor.FloorSimulator.start_state`), turns the cranks at the
design's speed after a smooth ramp, and stops as soon as the walking verdict
(:mod:`pasibot_pin.dynamics.verdict`) is decided: ``walks`` after its steps, or the first failure.
A design that does not walk is an outcome, never an exception; a design whose linkage cannot
be built at all raises :class:`~pasibot_pin.errors.DesignError` before any simulation.

:data:`WALK_MU`, the crank ramp and the time step are the defaults of every walking answer (the
``walk`` command, the floor metrics of a design, walking sweeps, the MuJoCo twin).

Units: SI, angles [rad].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.engine3d import Floor3D
from pasibot_pin.dynamics.floor.ground import Ground, check_mu, check_step
from pasibot_pin.dynamics.floor.result3d import Floor3DResult
from pasibot_pin.dynamics.floor.run import FloorResult
from pasibot_pin.dynamics.floor.settings import FloorSettings
from pasibot_pin.dynamics.verdict import GaitCriteria, Verdict
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import MIN_WALK_OMEGA, check_parameter, design_robot
from pasibot_pin.model.params import SOLE_FLOOR_MU
from pasibot_pin.progress import progress_bar
from pasibot_pin.studies.methods.spring_fit import design_spring

WALK_MU = SOLE_FLOOR_MU
"""Sole-floor Coulomb friction of a walk [-] (the project's one sole-floor friction)."""
RAMP_SHARE = 0.25
"""The cranks reach their speed over this share of a step period (pi / omega) [-]..."""
RAMP_MAX = 1.0
"""... but over at most this long [s]."""
MIN_OMEGA = MIN_WALK_OMEGA
"""The slowest crank speed a walk is simulated at [rad/s] (the design record's :data:`MIN_WALK_OMEGA`)."""
STEPS_PER_PERIOD = 1000
"""The time step is at most a step period over this, ..."""
DT_RANGE = (5e-4, 1e-3)
"""... and within this range [s]."""


def walk_dt(omega: float) -> float:
    """The default time step of a walk at crank speed ``omega`` [rad/s]: [s].

    A step period pi / omega over :data:`STEPS_PER_PERIOD`, within :data:`DT_RANGE`: slow walks
    are quasi-static and take longer steps, fast ones shorter.
    """
    low, high = DT_RANGE
    return min(high, max(low, math.pi / omega / STEPS_PER_PERIOD))


@dataclass(frozen=True)
class WalkSettings:
    """How to put a design on the floor.

    Attributes:
        steps: steps to walk before the verdict is ``walks`` [-].
        mu: sole-floor friction [-].
        dt: time step [s] (``None``: :func:`walk_dt` of the design's speed).
        criteria: the verdict's other thresholds (its ``steps`` is replaced by ``steps``).
        slope: the ground's angle, uphill positive [rad] (the planar floor; 0: flat, as every walk so far).
        step_height: a step edge on the ground, up positive [m] (the planar floor; 0: none).
        step_at: where the step edge is, along the ground from the origin [m] (the world's x: the
            start stands where the linkage puts it at theta0, ``StartState.along`` its heels and toes).

    """

    steps: int = 20
    mu: float = WALK_MU
    dt: float | None = None
    criteria: GaitCriteria = GaitCriteria()
    slope: float = 0.0
    step_height: float = 0.0
    step_at: float = 0.0

    def __post_init__(self) -> None:
        check_step(self.step_height, self.step_at)
        integer = isinstance(self.steps, int) and not isinstance(self.steps, bool)
        if not integer or not 1 <= self.steps <= 10_000:
            raise ParameterError(f"parameter 'steps' must be an integer in [1, 10000], got {self.steps!r}")
        check_mu(self.mu)
        if self.dt is not None and not (
            isinstance(self.dt, (int, float)) and math.isfinite(self.dt) and 1e-5 <= self.dt <= 1e-2
        ):
            raise ParameterError(f"parameter 'dt' must be a time step in [1e-05, 0.01] s, got {self.dt!r}")

    def judged_by(self) -> GaitCriteria:
        """The verdict's criteria with this walk's step count."""
        return replace(self.criteria, steps=self.steps)


@dataclass
class DesignWalk:
    """A design on the floor: its verdict and the run.

    Attributes:
        verdict: the :class:`~pasibot_pin.dynamics.verdict.Verdict`.
        result: the floor run (every sample).
        omega: crank speed [rad/s].
        dt: the time step used [s].
        settings: the :class:`FloorSettings` of the run.

    """

    verdict: Verdict
    result: FloorResult
    omega: float
    dt: float
    settings: FloorSettings

    def __repr__(self) -> str:
        return f"DesignWalk(omega={self.omega:g} rad/s, dt={self.dt:g} s: {self.verdict.summary()})"


def walk_duration(omega: float, steps: int) -> float:
    """The longest a walk of ``steps`` steps may need [s]: its steps, the ramp and two spare periods."""
    return (steps + 3) * math.pi / omega + RAMP_MAX


WALK_BUDGET: int = 2_000_000
"""Most time steps one command may simulate, planar steps counted once and 3-D ones :data:`SPATIAL_COST` times [-]
(about 8 minutes of CPU on the planar floor)."""

STEP_CPU: float = 2.5e-4
"""A planar floor step's CPU time, for the estimate in words [s] (``benchmarks/bench_floor3d.py``)."""

SPATIAL_COST: float = 4.0
"""A 3-D floor step's cost in planar steps [-] (3.4 in `benchmarks/bench_floor3d.py`, the tracked 3-D step)."""

SEARCH_BUDGET: int = 100_000_000
"""Most time steps a sweep or a search may simulate over all its designs [-] (about 7 hours of CPU)."""


def walk_cost(omega: float, steps: int, walks: int = 1, spatial: bool = False) -> float:
    """Planar-equivalent time steps of ``walks`` walks of ``steps`` steps at ``omega`` [rad/s], at most [-]."""
    omega = max(float(omega), MIN_OMEGA)
    return walks * math.ceil(walk_duration(omega, steps) / walk_dt(omega)) * (SPATIAL_COST if spatial else 1.0)


def check_walk_budget(cost: float, what: str, limit: int = WALK_BUDGET) -> None:
    """Refuse, before any work, a command whose walks need more than ``limit`` time steps.

    Args:
        cost: the walks' cost (:func:`walk_cost`, summed) [planar time steps].
        what: the walks in the user's words, naming the flags (``--steps 1000 at --omega 0.5``).
        limit: :data:`WALK_BUDGET` for one walk, :data:`SEARCH_BUDGET` for a sweep or a search.

    Raises:
        ParameterError: one line with the estimate and the limit.

    """
    if cost > limit:
        minutes = cost * STEP_CPU / 60.0
        raise ParameterError(
            f"{what}: {cost:.2g} time steps (about {minutes:.0f} min of CPU), past the limit of {limit:.0e}; "
            f"ask fewer steps, a faster crank{' or fewer designs' if limit == SEARCH_BUDGET else ''}"
        )


def floor_settings(design, settings: WalkSettings, robot) -> FloorSettings:
    """The :class:`FloorSettings` of ``design``'s walk: its speed, spring, motors; the ramp and step."""
    omega = check_parameter("omega", design.omega, low=MIN_WALK_OMEGA)  # a walk's range: the record's, from 0.05
    spring = design_spring(design, robot)
    dt = walk_dt(omega) if settings.dt is None else settings.dt
    ramp = min(RAMP_MAX, RAMP_SHARE * math.pi / omega)
    return FloorSettings(
        omega=omega, spring=spring, crank_ramp=ramp, mu=settings.mu, dt=dt, motors=design.motors,
        fall_limit=math.pi / 2, slope=settings.slope, step_height=settings.step_height, step_at=settings.step_at,
    )  # fmt: skip


class ProgressJudge:
    """A walk's judge that also moves a progress bar, one tick per simulated second.

    It hears every sample the judge hears and passes it on; everything else (the verdict, a
    divergence, a trip, the 3-D floor's roll) is the judge's own.

    Args:
        judge: the walk's judge (:class:`~pasibot_pin.dynamics.verdict.GaitJudge`).
        bar: a progress bar over the run's simulated seconds (:func:`~pasibot_pin.progress.progress_bar`).

    """

    def __init__(self, judge, bar) -> None:
        self.judge, self.bar, self.shown = judge, bar, 0

    def update(self, sample) -> bool:
        """Move the bar to the sample's whole second; the judge's answer (the walk decided)."""
        second = int(sample.t)
        if second > self.shown:
            self.bar.update(second - self.shown)
            self.shown = second
        return self.judge.update(sample)

    def __getattr__(self, name: str):
        return getattr(self.judge, name)


def _judged(judge_of, settings: WalkSettings, duration: float, progress: bool):
    """The run's judge factory and its bar (``None``: no bar, the default judge by the settings' criteria)."""
    if not progress:
        return {"criteria": settings.judged_by()}, None
    bar = progress_bar(math.ceil(duration), 0, True, unit="simulated second")
    return {"judge": lambda first: ProgressJudge(judge_of(settings.judged_by())(first), bar)}, bar


def _finish(bar) -> None:
    """Close the walk's bar at the time it reached (a verdict stops the walk early: that time is the whole)."""
    if bar is None:
        return
    if getattr(bar, "total", None) is not None and hasattr(bar, "refresh"):  # tqdm's
        bar.total = bar.n
        bar.refresh()
    bar.close()


def walk_design(design, settings: WalkSettings | None = None, robot=None, progress: bool = False) -> DesignWalk:
    """Put ``design`` on the floor and judge its walk (see the module docstring).

    Args:
        design: a :class:`~pasibot_pin.model.design.Design`.
        settings: :class:`WalkSettings` (default: 20 steps).
        robot: its two-legged robot, if already built.
        progress: show a progress bar over the simulated seconds on stderr.

    Returns:
        :class:`DesignWalk`; a walk that fails is its verdict, not an exception.

    Raises:
        ParameterError: bad settings or a crank speed below :data:`MIN_OMEGA`.
        DesignError: the design cannot be built.

    """
    settings = WalkSettings() if settings is None else settings
    robot = design_robot(design, 2, visuals=False) if robot is None else robot
    floor = floor_settings(design, settings, robot)
    sim = FloorSimulator(robot, floor)
    duration = walk_duration(design.omega, settings.steps)
    judged, bar = _judged(sim.judge_of, settings, duration, progress)
    try:
        result = sim.run(duration, stop_on_verdict=True, **judged)
    finally:
        _finish(bar)
    assert result.verdict is not None  # omega > 0
    return DesignWalk(result.verdict, result, design.omega, floor.dt, floor)


class ShownJudge:
    """Judges one walk twice: by its own step count (it decides when the run stops) and by fewer steps.

    The shorter judge hears the same samples until it decides, or until the time a run of its own
    steps would have ended (:func:`walk_duration`); what it decided then is the verdict that
    shorter walk would have had, and ``shown_at`` [s] the time that run would have stopped at.

    Args:
        walk: the walk's :class:`~pasibot_pin.dynamics.verdict.GaitJudge`.
        shown: the judge of the fewer steps (the same robot and criteria but ``steps``).
        shown_end: the last time the shorter run would have simulated [s].

    """

    def __init__(self, walk, shown, shown_end: float) -> None:
        self.walk, self.shown, self.shown_end = walk, shown, shown_end
        self.shown_at: float | None = None
        self.shown_verdict: Verdict | None = None

    def _close_shown(self, t: float) -> None:
        if self.shown_at is None:
            self.shown_at, self.shown_verdict = t, self.shown.verdict(t)

    def update(self, sample) -> bool:
        """Take one sample; True once the walk's own outcome is decided."""
        if self.shown_at is None and (self.shown.update(sample) or sample.t >= self.shown_end - 1e-9):
            self._close_shown(sample.t)
        return self.walk.update(sample)

    def diverged(self, t: float, detail: str) -> None:
        """The simulation broke at ``t`` [s]: both judges hear it."""
        for judge in (self.shown, self.walk):
            judge.diverged(t, detail)
        self._close_shown(t)

    def tripped(self, t: float, detail: str) -> None:
        """A point hit a step's riser at ``t`` [s]: both judges hear it."""
        for judge in (self.shown, self.walk):
            judge.tripped(t, detail)
        self._close_shown(t)

    def verdict(self, t_end: float) -> Verdict:
        """The walk's own verdict at the run's end ``t_end`` [s] (the shorter one closed then if still open)."""
        self._close_shown(t_end)
        return self.walk.verdict(t_end)


def walk_design_shown(design, settings: WalkSettings, shown: int, robot=None) -> tuple[DesignWalk, DesignWalk]:
    """:func:`walk_design`, and the walk of its first ``shown`` steps from the same run (one simulation).

    The shorter walk is judged by its own step count as :func:`walk_design` would judge it and its run
    cut where that walk would have stopped (:meth:`~pasibot_pin.dynamics.floor.run.FloorResult.until`).
    Its samples are the longer run's: the time step of a run divides its whole duration, so a run of
    ``shown`` steps alone takes steps shorter by about one part in a thousand.

    Returns:
        (the walk of ``settings.steps`` steps, the walk of ``shown`` steps).

    Raises:
        ParameterError: ``shown`` not in [1, ``settings.steps``]; as :func:`walk_design`.

    """
    if not (isinstance(shown, int) and 1 <= shown <= settings.steps):
        raise ParameterError(f"parameter 'shown' must be an integer in [1, {settings.steps}] steps, got {shown!r}")
    robot = design_robot(design, 2, visuals=False) if robot is None else robot
    floor = floor_settings(design, settings, robot)
    sim = FloorSimulator(robot, floor)
    judges: list[ShownJudge] = []

    def judge(first):
        both = ShownJudge(
            sim.judge_of(settings.judged_by())(first),
            sim.judge_of(replace(settings, steps=shown).judged_by())(first),
            walk_duration(design.omega, shown),
        )
        judges.append(both)
        return both

    result = sim.run(walk_duration(design.omega, settings.steps), judge=judge, stop_on_verdict=True)
    shown_at, shown_verdict = judges[0].shown_at, judges[0].shown_verdict
    assert result.verdict is not None and shown_at is not None and shown_verdict is not None  # omega > 0
    return (
        DesignWalk(result.verdict, result, design.omega, floor.dt, floor),
        DesignWalk(shown_verdict, result.until(shown_at, shown_verdict), design.omega, floor.dt, floor),
    )


@dataclass
class DesignWalk3D:
    """A design on the 3-D floor: its verdict, the run and its sideways figures.

    Attributes:
        verdict: the :class:`~pasibot_pin.dynamics.verdict.Verdict` (``tipped`` among its outcomes).
        result: the 3-D run (:class:`~pasibot_pin.dynamics.floor.engine3d.Floor3DResult`).
        omega: crank speed [rad/s].
        dt: the time step used [s].
        ground: the ground it walked on (:class:`~pasibot_pin.dynamics.floor.ground.Ground`: its slope, friction).

    """

    verdict: Verdict
    result: Floor3DResult
    omega: float
    dt: float
    ground: Ground = field(default_factory=Ground)

    def figures(self) -> dict[str, float]:
        """Largest |roll| [deg], its tip margin [deg], yaw per step [deg], lateral drift [m], clearances [m].

        ``settled_at_s``: when the gait began to repeat itself (:mod:`.repeat3d`) [s]; NaN: never.
        """
        r = self.result
        return {
            "max_hip_roll_deg": r.max_hip_roll_deg,
            "roll_margin_deg": r.roll_margin_deg,
            "yaw_per_step_deg": r.yaw_per_step_deg,
            "lateral_drift_m": r.lateral_drift_m,
            "min_sole_clearance_m": r.min_sole_clearance_m,
            "leg_clearance_m": r.leg_clearance_m,
            "settled_at_s": r.settled_at_s,
        }


def walk_design_3d(design, settings: WalkSettings | None = None, robot=None, progress: bool = False) -> DesignWalk3D:
    """Put ``design`` on the 3-D floor (free hip, its soles' footprint) and judge its walk.

    The same start, cranks, ramp and time step as :func:`walk_design`; the soles are
    ``design.footprint()`` and the legs sit at ``design.hip_half_width``. ``progress``: a
    progress bar over the simulated seconds on stderr.

    Raises:
        ParameterError: bad settings, a crank speed below :data:`MIN_OMEGA`, or soles that overlap
            at the start (naming ``sole_inner``).
        DesignError: the design cannot be built.

    """
    settings = WalkSettings() if settings is None else settings
    robot = design_robot(design, 2, visuals=False) if robot is None else robot
    floor = floor_settings(design, settings, robot)
    engine = Floor3D(FloorSimulator(robot, floor), design.footprint(), floor.ground, lateral=design.lateral())
    duration = walk_duration(design.omega, settings.steps)
    judged, bar = _judged(engine.planar.judge_of, settings, duration, progress)
    try:
        result = engine.run(duration, **judged)
    finally:
        _finish(bar)
    return DesignWalk3D(result.verdict, result, design.omega, engine.time_grid(duration)[0], floor.ground)
