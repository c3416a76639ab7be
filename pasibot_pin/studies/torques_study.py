"""Crank and ankle torques of the seed's scenarios and the ankle spring fitted to them: pure compute.

- :class:`TorqueSettings` / :func:`scenario_torques`: one scenario under one modelling preset
  (with optional overrides): the inverse dynamics (:func:`pasibot_pin.dynamics.inverse.run_scenario`)
  and the K_e fit (:func:`pasibot_pin.studies.methods.spring_fit.fit_result`).
- :func:`attribution`: K_e as the seed's modelling choices are switched on one at a time, from
  the default model to the ``seed`` preset.
- :func:`torque_survey`: every scenario with the default model and the seed preset, the
  attribution of every dynamic scenario, and multi-step runs (the ``dynamics`` report section).

Nothing here writes files or draws. Units: SI; angles [rad].
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from pasibot_pin.dynamics.inverse import STANCE_RANGE, TorqueResult, crank_grid, inverse_dynamics, run_scenario
from pasibot_pin.errors import DesignError, ParameterError
from pasibot_pin.model.design import check_parameter, design_robot
from pasibot_pin.model.scenarios import (
    PRESETS,
    SCENARIOS,
    SEED_CHOICE_NAMES,
    ModelChoices,
    Scenario,
    get_preset,
    get_scenario,
)
from pasibot_pin.model.variants import get_variant
from pasibot_pin.reprs import short_repr
from pasibot_pin.studies.methods.spring_fit import SpringFit, fit_result

if TYPE_CHECKING:
    from pasibot_pin.model.design import Design

SURVEY_PRESETS: tuple[str, ...] = ("default", "seed")
"""The presets every scenario runs under in :func:`torque_survey`."""

GAIT_SCENARIO: str = "run4"
"""The survey's multi-step run at the seed's fastest speed (every sample written to CSV)."""

SLOW_SCENARIO: str = "run2"
"""The survey's slow multi-step run, for comparison (plotted only)."""

GAIT_STEPS: int = 4
"""Steps (half crank turns) of the survey's multi-step runs: two crank turns."""

GAIT_SAMPLES_PER_STEP: int = 48
"""Crank intervals per step of :data:`GAIT_SCENARIO`; :data:`SLOW_SCENARIO` takes every 4th sample."""

DEFAULT_SAMPLES: int = 61
"""Samples over one stance when :attr:`TorqueSettings.samples` is not given."""

MAX_SAMPLES: int = 100_000
"""Most crank angles one :func:`scenario_torques` run takes (``steps`` x (``samples`` - 1) + 1): memory stays small."""


@dataclass(frozen=True)
class TorqueSettings:
    """One scenario's inverse dynamics and spring fit (the ``pasibot torques`` command's settings).

    Attributes:
        scenario: key of :data:`pasibot_pin.model.scenarios.SCENARIOS`.
        preset: key of :data:`pasibot_pin.model.scenarios.PRESETS`.
        omega: crank speed override [rad/s] (0 = quasi-static); ``None``: the scenario's.
        samples: samples per stance, 2 .. :data:`MAX_SAMPLES`; ``None``: :data:`DEFAULT_SAMPLES`.
            A preset that fixes a fit window (the seed's) runs the window's samples: it takes
            neither ``samples`` nor ``steps`` > 1 (refused rather than silently ignored).
        steps: half crank turns (steps) to run, the stance swapping every step (>= 1).
        swing_foot: override of the preset's swing foot (``level`` or ``square``); ``None``: keep.
        accelerations: override of the acceleration mode (``exact``, ``central``, ``lagged``).
        inertia: override of the inertia model (``point`` or ``uniform``).
        swap_l5_l6: override of the seed's L5/L6 mass swap; ``None``: keep the preset's.
        design: a :class:`~pasibot_pin.model.design.Design` run instead of the scenario's robot:
            its geometry, masses, body, crank speed (unless ``omega``) and motor layout, with the
            default preset's choices (exact accelerations, swing foot level); ``None``: the scenario.

    Raises:
        ValueError: an unknown scenario, preset or choice, ``steps`` < 1, ``samples`` < 2, more
            than :data:`MAX_SAMPLES` crank angles in all, a non-finite ``omega``, or
            ``samples`` / ``steps`` > 1 with a preset's fit window.

    """

    scenario: str = "run1"
    preset: str = "default"
    omega: float | None = None
    design: Design | None = None
    samples: int | None = None
    steps: int = 1
    swing_foot: str | None = None
    accelerations: str | None = None
    inertia: str | None = None
    swap_l5_l6: bool | None = None

    def __post_init__(self) -> None:
        get_scenario(self.scenario)
        choices = self.choices()
        if isinstance(self.steps, bool) or not isinstance(self.steps, int) or self.steps < 1:
            raise ParameterError(f"parameter 'steps' must be an integer >= 1, got {self.steps!r}")
        if self.omega is not None:
            check_parameter("omega", self.omega)  # the design record's crank speeds (0: quasi-static)
        if self.samples is not None:
            if isinstance(self.samples, bool) or not isinstance(self.samples, int) or self.samples < 2:
                raise ParameterError(f"parameter 'samples' must be an integer >= 2, got {self.samples!r}")
            if self.samples > MAX_SAMPLES:
                raise ParameterError(f"parameter 'samples' must be at most {MAX_SAMPLES}, got {self.samples}")
        if choices.fit_thetas is not None:
            if self.samples is not None:
                raise ParameterError(
                    f"parameter 'samples' does not apply to preset {self.preset!r}: it runs its fit window's "
                    f"{len(choices.fit_thetas)} crank angles"
                )
            if self.steps > 1:
                raise ParameterError(
                    f"parameter 'steps' must be 1 with preset {self.preset!r}: its fit window covers one stance"
                )
        total = (self.per_step - 1) * self.steps + 1
        if total > MAX_SAMPLES:
            raise ParameterError(
                f"parameter 'steps' x ('samples' - 1) + 1 = {total} crank angles exceeds {MAX_SAMPLES}; "
                "take fewer steps or samples"
            )

    @property
    def per_step(self) -> int:
        """Samples per stance (``samples`` or :data:`DEFAULT_SAMPLES`)."""
        return DEFAULT_SAMPLES if self.samples is None else int(self.samples)

    def choices(self) -> ModelChoices:
        """The preset's modelling choices with the overrides applied."""
        overrides = {
            "swing_foot": self.swing_foot,
            "accelerations": self.accelerations,
            "inertia": self.inertia,
            "swap_l5_l6": self.swap_l5_l6,
        }
        changes = {k: v for k, v in overrides.items() if v is not None}
        choices = get_preset(self.preset)
        return choices.with_(**changes) if changes else choices


@dataclass(frozen=True)
class ScenarioTorques:
    """One scenario's torques and fitted ankle spring.

    Attributes:
        scenario: the seed scenario (crank speed, body mass and COM).
        preset: name of the modelling preset the choices start from.
        choices: the modelling choices run (the preset with any overrides).
        result: torques and reactions along the motion [N.m, N].
        fit: the linear spring fitted to the stance T_e(beta) (K_e [N.m/rad], beta0 [rad]); ``None`` for a
            design whose variant has no free ankle (its foot is held by the linkage: T_e is zero, nothing to fit).

    """

    __repr__ = short_repr

    scenario: Scenario
    preset: str
    choices: ModelChoices
    result: TorqueResult
    fit: SpringFit | None

    @property
    def spring(self) -> SpringFit:
        """The fitted spring (:attr:`fit`).

        Raises:
            DesignError: the design's variant has no free ankle (no spring was fitted).

        """
        if self.fit is None:
            raise DesignError("parameter 'variant': a design without a free ankle has no ankle spring to fit")
        return self.fit


@dataclass(frozen=True)
class AttributionRow:
    """One row of the K_e attribution.

    Attributes:
        label: the choice switched on (``default model`` for the first row).
        K_e: fitted stiffness with this and every earlier choice on [N.m/rad].
        delta: change from the previous row [N.m/rad].

    """

    label: str
    K_e: float
    delta: float


@dataclass(frozen=True)
class TorqueSurvey:
    """Every scenario under the survey presets, the K_e attribution and two multi-step runs.

    Attributes:
        runs: (scenario name, preset) -> torques and fit, for every scenario and
            :data:`SURVEY_PRESETS` preset, in scenario then preset order.
        quasi_static_clean: the quasi-static scenario's fit under the ``seed-clean`` preset
            (the seed's quasi-static script, which does not swap L5/L6).
        attribution: dynamic scenario name -> its :func:`attribution` rows.
        gait: :data:`GAIT_SCENARIO`, default model, :data:`GAIT_STEPS` steps of
            :data:`GAIT_SAMPLES_PER_STEP` intervals each.
        slow: :data:`SLOW_SCENARIO`, default model, every 4th crank angle of ``gait``.

    """

    __repr__ = short_repr

    runs: Mapping[tuple[str, str], ScenarioTorques]
    quasi_static_clean: SpringFit
    attribution: Mapping[str, list[AttributionRow]]
    gait: TorqueResult
    slow: TorqueResult


def scenario_torques(settings: TorqueSettings | None = None) -> ScenarioTorques:
    """Run one scenario's inverse dynamics and fit the ankle spring.

    With ``steps`` = 1 and a preset that fixes a fit window (the seed's), the window's samples
    are run (right foot welded) and fitted; otherwise ``steps`` x (``samples`` - 1) + 1 crank
    angles from the start of stance, the stance swapping every step, all fitted.

    Args:
        settings: what to run (default :class:`TorqueSettings`: run1, default preset).

    Returns:
        The torques and the fitted spring.

    """
    settings = TorqueSettings() if settings is None else settings
    if settings.design is not None:
        return design_torques(settings)
    scenario = get_scenario(settings.scenario)
    choices = settings.choices()
    thetas = None
    if choices.fit_thetas is None or settings.steps > 1:
        per_step = settings.per_step
        steps = settings.steps
        thetas = crank_grid(STANCE_RANGE[0], STANCE_RANGE[0] + math.pi * steps, (per_step - 1) * steps + 1)
    result = run_scenario(scenario, choices, thetas=thetas, omega=settings.omega)
    window = choices.fit_thetas if thetas is None else None
    fit = fit_result(result, window, warn=False)
    return ScenarioTorques(scenario, settings.preset, choices, result, fit)


def design_torques(settings: TorqueSettings) -> ScenarioTorques:
    """:func:`scenario_torques` of ``settings.design``: its robot, speed and motors; the whole stance fitted.

    The result's ``scenario`` is named ``design`` and carries the design's crank speed, body mass
    and COM (no seed values). A variant without a free ankle (its record's ``free_ankle``) has no
    spring to fit: its ``fit`` is ``None``.
    """
    design = settings.design
    if design is None:
        raise ParameterError("design_torques needs settings.design")
    if settings.preset != "default" or settings.choices() != get_preset("default"):
        raise ParameterError("a --design runs the default modelling choices: no --preset or choice overrides")
    omega = design.omega if settings.omega is None else settings.omega
    steps = settings.steps
    thetas = crank_grid(STANCE_RANGE[0], STANCE_RANGE[0] + math.pi * steps, (settings.per_step - 1) * steps + 1)
    result = inverse_dynamics(design_robot(design, 2), thetas, omega, motors=design.motors)
    scenario = Scenario(
        "design", omega, design.body_mass, design.body_mass, design.body_com_dx, None, None, "design file"
    )
    fit = fit_result(result, None, warn=False) if get_variant(design.variant).free_ankle else None
    return ScenarioTorques(scenario, "default", get_preset("default"), result, fit)


def preset_torques(scenario: Scenario, preset: str, reactions: bool = True) -> ScenarioTorques:
    """One scenario under one preset, on the preset's default samples, fitted on its window.

    Args:
        scenario: the seed scenario.
        preset: key of :data:`pasibot_pin.model.scenarios.PRESETS`.
        reactions: compute the tree-joint reactions too.

    """
    choices = get_preset(preset)
    result = run_scenario(scenario, choices, reactions=reactions)
    return ScenarioTorques(scenario, preset, choices, result, fit_result(result, choices.fit_thetas, warn=False))


def attribution(
    scenario: Scenario, default_K_e: float | None = None, seed_K_e: float | None = None
) -> list[AttributionRow]:
    """K_e as the seed's choices are switched on one at a time, from the default model to the seed preset.

    The choices are switched on cumulatively in the order of
    :data:`pasibot_pin.model.scenarios.SEED_CHOICE_NAMES`; the last row is the ``seed`` preset.

    Args:
        scenario: the seed scenario.
        default_K_e: K_e of the default model [N.m/rad], if already computed.
        seed_K_e: K_e of the seed preset [N.m/rad], if already computed.

    Returns:
        The ``default model`` row, then one row per choice.

    """
    if default_K_e is None:
        default_K_e = preset_torques(scenario, "default", reactions=False).spring.K_e
    seed = PRESETS["seed"]
    choices = PRESETS["default"]
    rows = [AttributionRow("default model", default_K_e, 0.0)]
    previous = default_K_e
    names = list(SEED_CHOICE_NAMES.items())
    for k, (field_name, label) in enumerate(names):
        choices = choices.with_(**{field_name: getattr(seed, field_name)})
        if k == len(names) - 1 and seed_K_e is not None:
            k_e = seed_K_e
        else:
            k_e = fit_result(run_scenario(scenario, choices, reactions=False), choices.fit_thetas, warn=False).K_e
        rows.append(AttributionRow(label, k_e, k_e - previous))
        previous = k_e
    return rows


def torque_survey() -> TorqueSurvey:
    """Every scenario under :data:`SURVEY_PRESETS`, the attribution of each dynamic one, two multi-step runs."""
    runs = {(name, preset): preset_torques(sc, preset) for name, sc in SCENARIOS.items() for preset in SURVEY_PRESETS}
    qs_clean = fit_result(
        run_scenario(SCENARIOS["quasi-static"], PRESETS["seed-clean"], reactions=False), None, warn=False
    )
    dynamic = [n for n in SCENARIOS if not SCENARIOS[n].quasi_static]
    table = {
        n: attribution(SCENARIOS[n], runs[(n, "default")].spring.K_e, runs[(n, "seed")].spring.K_e) for n in dynamic
    }
    n = GAIT_STEPS * GAIT_SAMPLES_PER_STEP + 1
    thetas = crank_grid(STANCE_RANGE[0], STANCE_RANGE[0] + GAIT_STEPS * math.pi, n)
    gait = run_scenario(SCENARIOS[GAIT_SCENARIO], PRESETS["default"], thetas=thetas)
    slow = run_scenario(SCENARIOS[SLOW_SCENARIO], PRESETS["default"], thetas=thetas[::4])
    return TorqueSurvey(runs, qs_clean, table, gait, slow)
