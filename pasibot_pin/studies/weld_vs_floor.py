"""The spring study on the floor: weld and floor side by side, for the seed's runs 1-4.

For each scenario and each spring case (fitted, no spring, half and twice K_e):

- **weld** (:mod:`pasibot_pin.dynamics.simulator`): the stance foot welded flat, the swing foot
  at the spring's rest angle, the hip starting at its standing pitch; the largest hip pitch over
  ``duration`` (or the time it fell), and the quasi-static answer: the largest equilibrium hip
  pitch along the stance (cranks held), ``inf`` where some crank angle has no stable equilibrium;
  beside it the floor's quasi-static answer (:mod:`pasibot_pin.studies.floor_static`: whether the
  sole holds that equilibrium flat, or the foot rolls onto its heel or toe).
- **floor** (:mod:`pasibot_pin.dynamics.floor`): both feet on the floor from a consistent start
  (:meth:`~pasibot_pin.dynamics.floor.FloorSimulator.start_state`); how it stands at theta0 with
  the cranks held (the floor's quasi-static answer: the settled hip pitch and contact modes, or
  that it cannot stand), then the run over ``duration``: outcome, largest hip pitch, landings.

No files: :mod:`pasibot_pin.report.floor` writes the table and the figure.

Units: SI, angles [rad].
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.settings import FloorSettings
from pasibot_pin.dynamics.simulator import SimulationSettings, simulate
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.coordinates import HIP_PITCH
from pasibot_pin.model.scenarios import get_scenario
from pasibot_pin.studies.floor_static import FloorStatic, FloorStaticSweep, floor_static_path, stance_thetas
from pasibot_pin.studies.spring_study import SPRING_CASES, scenario_inputs

WALKING_SCENARIOS: tuple[str, ...] = ("run1", "run2", "run3", "run4")
"""The seed's walking runs."""


@dataclass(frozen=True)
class FloorSpringSettings:
    """What to compare.

    Attributes:
        scenarios: runs (``run1`` .. ``run4``).
        duration: simulated time of each run, weld and floor [s].
        mu: sole-floor Coulomb friction [-].
        dt: the floor's time step [s] (the weld uses 10 ms with the swing foot at rest angle).
        static_samples: crank angles over one stance for the quasi-static paths (the weld
            sweep's 19 by default: the same crank angles, the same numbers).

    """

    scenarios: tuple[str, ...] = WALKING_SCENARIOS
    duration: float = 2.0
    mu: float = 0.8
    dt: float = 1e-3
    static_samples: int = 19

    def __post_init__(self) -> None:
        keys = tuple(get_scenario(s).name for s in self.scenarios)  # names an unknown scenario
        if not keys or any(get_scenario(k).omega <= 0 for k in keys):
            raise ParameterError(f"parameter 'scenarios' must name walking runs (run1 .. run4), got {self.scenarios!r}")
        object.__setattr__(self, "scenarios", keys)
        if not (math.isfinite(self.duration) and 0 < self.duration <= 600):
            raise ParameterError(f"parameter 'duration' must be in (0, 600] s, got {self.duration!r}")
        if int(self.static_samples) < 1:
            raise ParameterError(f"parameter 'static_samples' must be >= 1, got {self.static_samples!r}")
        FloorSettings(mu=self.mu, dt=self.dt)  # names a bad mu or dt before any work


@dataclass
class CaseComparison:
    """One spring case of one scenario, weld against floor.

    Attributes:
        scenario: ``run1`` .. ``run4``.
        case: ``fitted``, ``no spring``, ``half K_e``, ``twice K_e``.
        stiffness: K_e [N.m/rad].
        weld_max_pitch: largest |hip pitch| of the welded run [rad].
        weld_fell_at: when the welded run fell [s] (NaN: it did not).
        weld_static: largest |equilibrium hip pitch| along the stance, cranks held [rad] (inf: none stable).
        floor_static: the floor's quasi-static answer (:class:`~pasibot_pin.studies.floor_static.FloorStatic`).
        floor_start: ``flat`` (the flat double support holds), ``settled`` or ``none`` (it cannot stand).
        floor_start_pitch: hip pitch of the floor's start [rad].
        floor_start_modes: ``right/left`` contact modes at the start.
        floor_max_pitch: largest |hip pitch| of the floor run [rad].
        floor_outcome: the floor run's outcome line.
        floor_failed: True when the floor run stopped on a failure.
        floor_end: the floor run's last time [s].
        floor_landings: landings (touchdowns of a foot from the air) in the floor run.

    """

    scenario: str
    case: str
    stiffness: float
    weld_max_pitch: float
    weld_fell_at: float
    weld_static: float
    floor_static: FloorStatic
    floor_start: str
    floor_start_pitch: float
    floor_start_modes: str
    floor_max_pitch: float
    floor_outcome: str
    floor_failed: bool
    floor_end: float
    floor_landings: int


@dataclass
class FloorSpringStudy:
    """Every scenario's spring cases, weld against floor (one :class:`CaseComparison` each)."""

    settings: FloorSpringSettings
    rows: list[CaseComparison] = field(default_factory=list)

    def row(self, scenario: str, case: str) -> CaseComparison:
        """The row of ``scenario`` and ``case``."""
        return next(r for r in self.rows if r.scenario == scenario and r.case == case)


def compare_case(
    inputs, label: str, factor: float, settings: FloorSpringSettings, cache: dict | None = None
) -> CaseComparison:
    """Weld and floor for one spring case of a scenario (``inputs``: :func:`scenario_inputs`).

    ``cache``: the quasi-static solves' cache, shared by the cases of one scenario.
    """
    robot, omega = inputs.robot, inputs.omega
    # one spring per case, weld and floor alike: K_e scaled, the rest angle (the welded swing foot is
    # held at it) and the ankle damper kept, so "no spring" is the damper alone in both
    spring = inputs.fit.scaled(factor)
    quasi = floor_static_path(robot, spring, stance_thetas(settings.static_samples), settings.mu, cache)
    static = quasi.weld
    pitch0 = float(static.hip_pitch[0]) if static.found[0] and static.stiffness[0] > 0 else 0.0
    weld = simulate(
        robot,
        SimulationSettings(omega=omega, spring=spring, swing_ankle="rest", dt=0.01, initial_pitch=pitch0),
        duration=settings.duration,
    )
    sim = FloorSimulator(robot, FloorSettings(omega=omega, spring=spring, mu=settings.mu, dt=settings.dt))
    res = sim.run(settings.duration)
    if res.start is not None:
        start, start_pitch = res.start.kind, float(res.start.q[HIP_PITCH])
        modes = f"{res.start.modes['right']}/{res.start.modes['left']}"
    else:
        start, start_pitch, modes = "none", 0.0, "-"
    return CaseComparison(
        scenario=inputs.name,
        case=label,
        stiffness=spring.stiffness,
        weld_max_pitch=weld.max_hip_excursion,
        weld_fell_at=float(weld.t[-1]) if weld.fell else math.nan,
        weld_static=static.max_excursion,
        floor_static=quasi,
        floor_start=start,
        floor_start_pitch=start_pitch,
        floor_start_modes=modes,
        floor_max_pitch=float(np.max(np.abs(res.hip_pitch))) if len(res.t) else 0.0,
        floor_outcome=res.verdict.short() if res.verdict is not None else res.outcome,
        floor_failed=res.failed,
        floor_end=float(res.t[-1]) if len(res.t) else 0.0,
        floor_landings=len(res.landings),
    )


def floor_spring_study(
    settings: FloorSpringSettings | None = None,
    cases: Sequence[tuple[str, float]] = SPRING_CASES,
    on_row: Callable[[CaseComparison], None] | None = None,
) -> FloorSpringStudy:
    """Weld against floor for every scenario and spring case (see the module docstring)."""
    settings = settings or FloorSpringSettings()
    study = FloorSpringStudy(settings)
    for scenario in settings.scenarios:
        inputs = scenario_inputs(scenario)
        cache: dict = {}
        for label, factor in cases:
            row = compare_case(inputs, label, factor, settings, cache)
            study.rows.append(row)
            if on_row is not None:
                on_row(row)
    return study


def quasi_static_of(study: FloorSpringStudy) -> list[FloorStaticSweep]:
    """The study's quasi-static answers, one :class:`FloorStaticSweep` per scenario (its cases, no grid)."""
    out: dict[str, FloorStaticSweep] = {}
    for row in study.rows:
        spring = row.floor_static.spring
        if spring is None:
            raise ParameterError(f"{row.scenario} {row.case}: a floor-static answer without its spring")
        sweep = out.setdefault(row.scenario, FloorStaticSweep(row.scenario, spring))
        sweep.cases[row.case] = row.floor_static
    return list(out.values())
