"""The spring study on a real floor: run a scenario's spring cases with both feet free on the floor.

For a seed scenario, the fitted ankle spring (the inverse-dynamics fit), no spring, half and
twice its stiffness are each simulated by :class:`~pasibot_pin.dynamics.floor.FloorSimulator`
from double support at theta = pi/2 (both feet flat where the geometry puts them, the velocity
that keeps them there). Each case reports what happened: the contact mode of each foot over
time, the landings, step lengths and durations, and the outcome (``walks N steps`` or the
failure and its time). No files, no figures: :mod:`pasibot_pin.report.floor` writes them.

Units: SI, angles [rad].
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.engine3d import Floor3D
from pasibot_pin.dynamics.floor.result3d import Floor3DResult
from pasibot_pin.dynamics.floor.run import FloorResult
from pasibot_pin.dynamics.floor.settings import FloorSettings
from pasibot_pin.dynamics.spring_energy import AnkleSpring
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.coordinates import SIDES
from pasibot_pin.model.design import design_robot
from pasibot_pin.model.scenarios import get_scenario
from pasibot_pin.model.spatial import Footprint
from pasibot_pin.model.variants import get_variant
from pasibot_pin.studies.spring_study import SPRING_CASES, design_inputs, scenario_inputs

if TYPE_CHECKING:
    from pasibot_pin.model.design import Design

MAX_DURATION: float = 600.0
"""The longest floor run a study accepts [s] (10 minutes of simulated walking)."""


@dataclass(frozen=True)
class FloorStudySettings:
    """What to simulate on the floor.

    Attributes:
        scenario: ``quasi-static`` is refused (the cranks must turn); ``run1`` .. ``run4`` or ``1`` .. ``4``.
        duration: simulated time of each case [s].
        mu: sole-floor Coulomb friction [-].
        dt: time step [s].
        cases: all four spring cases, or the fitted spring only.
        design: a :class:`~pasibot_pin.model.design.Design` walked instead of the scenario's robot
            (its geometry, masses, body, crank speed and spring:
            :func:`~pasibot_pin.studies.spring_study.design_inputs`).
        spatial: run each case on the 3-D floor (:class:`~pasibot_pin.dynamics.floor.engine3d.Floor3D`:
            the hip free to roll and yaw; the design's soles, else the centred plate), stopping at its verdict.

    """

    scenario: str = "run1"
    duration: float = 10.0
    mu: float = 0.8
    dt: float = 1e-3
    cases: bool = True
    design: Design | None = None
    spatial: bool = False

    def __post_init__(self) -> None:
        if self.design is not None:
            if self.design.omega <= 0:
                raise ParameterError("the design does not walk (omega = 0): set its crank speed 'omega' > 0")
        else:
            scenario = get_scenario(self.scenario)  # names an unknown scenario
            if scenario.omega <= 0:
                raise ParameterError(f"scenario {scenario.name!r} does not walk (omega = 0): pick run1 .. run4")
        if not (math.isfinite(self.duration) and 0 < self.duration <= MAX_DURATION):
            raise ParameterError(f"parameter 'duration' must be in (0, {MAX_DURATION:g}] s, got {self.duration!r}")
        FloorSettings(mu=self.mu, dt=self.dt)  # names a bad mu or dt before any work


@dataclass
class FloorCase:
    """One spring case on the floor: its label, spring and run (planar, or 3-D with ``settings.spatial``)."""

    label: str
    spring: AnkleSpring | None
    result: FloorResult | Floor3DResult


@dataclass
class FloorStudy:
    """A scenario's spring cases on the floor.

    Attributes:
        scenario: the scenario's name.
        omega: crank speed [rad/s].
        fit: the fitted spring (``None`` for a design without ankle springs).
        cases: one :class:`FloorCase` per spring case, fitted first.
        settings: the settings used.

    """

    scenario: str
    omega: float
    fit: AnkleSpring | None
    cases: list[FloorCase] = field(default_factory=list)
    settings: FloorStudySettings | None = None

    def case(self, label: str) -> FloorCase:
        """The case called ``label`` (``fitted``, ``no spring``, ``half K_e``, ``twice K_e``)."""
        return next(c for c in self.cases if c.label == label)


def floor_study(settings: FloorStudySettings, on_case: Callable[[FloorCase], None] | None = None) -> FloorStudy:
    """Simulate the scenario's spring cases on the floor (see the module docstring).

    A design without ankle springs (``rigid``, ``parallel``) is one case, ``design``: the design as
    it is, its motors and crank speed.
    """
    design = settings.design
    if design is not None and not get_variant(design.variant).free_ankle:
        return _springless_design(settings, design, on_case)
    inputs = scenario_inputs(settings.scenario) if design is None else design_inputs(design)
    study = FloorStudy(inputs.name, inputs.omega, inputs.fit, settings=settings)
    cases = SPRING_CASES if settings.cases else SPRING_CASES[:1]
    motors = "two" if design is None else design.motors
    for label, factor in cases:
        spring = inputs.fit.scaled(factor)  # one definition, weld and floor: K_e scaled, damper kept
        floor = FloorSettings(omega=inputs.omega, spring=spring, mu=settings.mu, dt=settings.dt, motors=motors)
        case = FloorCase(label, spring, _run_case(inputs.robot, floor, settings))
        study.cases.append(case)
        if on_case is not None:
            on_case(case)
    return study


def _springless_design(
    settings: FloorStudySettings, design: Design, on_case: Callable[[FloorCase], None] | None
) -> FloorStudy:
    """The one case of a design without ankle springs (``settings.design``)."""
    robot = design_robot(design, 2, visuals=False)
    floor = FloorSettings(omega=design.omega, mu=settings.mu, dt=settings.dt, motors=design.motors)
    study = FloorStudy("design", design.omega, None, settings=settings)
    case = FloorCase("design", None, _run_case(robot, floor, settings))
    study.cases.append(case)
    if on_case is not None:
        on_case(case)
    return study


def _run_case(robot, floor: FloorSettings, settings: FloorStudySettings) -> FloorResult | Floor3DResult:
    """One case's run: the planar floor, or the 3-D floor with the design's soles (else the centred plate)."""
    if not settings.spatial:
        return FloorSimulator(robot, floor).run(settings.duration)
    design = settings.design
    footprint = design.footprint() if design is not None else Footprint.centred(robot.geometry.L)
    return Floor3D(FloorSimulator(robot, floor), footprint).run(settings.duration)


def floor3d_columns(result: Floor3DResult) -> dict[str, np.ndarray]:
    """The CSV columns of a 3-D floor run.

    t [s], the hip's x, y, z [m], roll, pitch and yaw [deg], and each foot's normal force [N] (its
    sole corners summed).
    """
    half = result.normal.shape[1] // 2  # the right foot's corners first
    return {
        "t": result.t,
        "hip_x_m": result.hip[:, 0],
        "hip_y_m": result.hip[:, 1],
        "hip_z_m": result.hip[:, 2],
        "hip_roll_deg": np.degrees(result.roll),
        "hip_pitch_deg": np.degrees(result.pitch),
        "hip_yaw_deg": np.degrees(result.yaw),
        f"{SIDES[0]}_Fn": result.normal[:, :half].sum(axis=1),
        f"{SIDES[1]}_Fn": result.normal[:, half:].sum(axis=1),
    }


def floor_columns(result: FloorResult) -> dict[str, np.ndarray]:
    """The CSV columns of a floor run.

    t [s], hip_pitch_deg, hip_z_m, the contact mode of each foot (``right_mode``, ``left_mode``),
    then the heel and toe normal and tangential forces [N], the friction use |F_t|/F_n and the
    crank torques [N.m].
    """
    cols: dict[str, np.ndarray] = {
        "t": result.t,
        "hip_pitch_deg": np.degrees(result.hip_pitch),
        "hip_z_m": result.q[:, 1],
    }
    for side in SIDES:
        cols[f"{side}_mode"] = np.array(result.modes[side], dtype=object)
    use = result.friction_use()
    for k, name in enumerate(f"{side}_{point}" for side in SIDES for point in ("heel", "toe")):
        cols[f"{name}_Fn"] = result.normal[:, k]
        cols[f"{name}_Ft"] = result.tangential[:, k]
        cols[f"{name}_friction_use"] = use[:, k]
    names = SIDES if result.motor_torque.shape[1] == len(SIDES) else ("motor",)
    for k, name in enumerate(names):
        cols[f"{name}_crank_torque"] = result.motor_torque[:, k]
    return cols


def case_summary(case: FloorCase) -> str:
    """One line: the case and its walking verdict (outcome, steps, advance, largest hip pitch)."""
    res = case.result
    if isinstance(res, Floor3DResult):
        return f"  3-D floor, {case.label:10s}: {res.summary()}"
    if res.verdict is not None:
        return f"  floor, {case.label:10s}: {res.verdict.summary()}"
    pitch = math.degrees(float(np.max(np.abs(res.hip_pitch)))) if len(res.t) else 0.0
    return f"  floor, {case.label:10s}: {res.outcome}; max |hip pitch| {pitch:.1f} deg"
