"""Contact of every seed scenario, one motor for both cranks, energy per step: the study behind ``contact_energy``.

Pure computation, no files and no figures: :func:`contact_sweep` (heel/toe contact of each
scenario and variant, plus an infeasible-friction check), :func:`single_motor_study` (one motor
driving both cranks over a full turn, flywheels), :func:`energy_sweep` (energy per step and cost
of transport over the crank speed), :func:`power_profile` (actuator powers over one step) and
:func:`flywheel_cases` (the single motor's flywheel at each speed and variant). :func:`run`
does the first four with one :class:`ContactEnergySettings`. Units: SI.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pasibot_pin.dynamics.inverse import inverse_dynamics
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import design_robot
from pasibot_pin.model.scenario_robots import scenario_robot
from pasibot_pin.model.scenarios import DEFAULT_BODY_MASS, SCENARIOS, get_preset, get_scenario
from pasibot_pin.reprs import short_repr
from pasibot_pin.studies import energy, single_motor
from pasibot_pin.studies.contact import CONTACT_MU, CONTACT_SAMPLES, ContactResult, scenario_contact

if TYPE_CHECKING:
    from pasibot_pin.dynamics.inverse import TorqueResult
    from pasibot_pin.model.design import Design


@dataclass(frozen=True)
class ContactEnergySettings:
    """Settings of the contact / one-motor / energy study (defaults: the ``pasibot analyze`` step).

    Every function of this module takes ``settings=None`` for these defaults.

    Attributes:
        mu: Coulomb friction coefficient of the contact sweep [-] (rubber on a dry floor, about).
        preset: modelling preset of the contact sweep and the single-motor run.
        contact_samples: crank samples over one right stance (contact sweep).
        variants: leg variants of the contact sweep.
        scenarios: seed scenarios of the contact sweep (default every one).
        slip_scenario: scenario of the infeasible-friction check.
        slip_mu: friction coefficient of that check [-].
        slip_sole: what-if (heel, toe) sole of that check, along the sole from the ankle [m].
        motor_scenario: scenario of the single-motor run (its crank speed and body).
        motor_samples: crank samples over one full turn of the single-motor run.
        flywheels: flywheel inertias on the crank shaft [kg.m^2].
        fluctuation: target crank speed fluctuation for the flywheel sizing [-].
        omegas: crank speeds of the energy table [rad/s].
        energy_variants: leg variants of the energy table.
        body_mass: body (hip) mass of the energy table [kg].
        body_com_dx: body COM ahead of joint 8 [m].
        nodes: Gauss-Legendre nodes per step.
        power_variant: variant of the actuator-power profile.
        power_omega: crank speed of the actuator-power profile [rad/s].
        design: a :class:`~pasibot_pin.model.design.Design` whose energy table is made instead
            (its robot, body and motors at each of ``omegas``); ``None``: the variants.

    """

    mu: float = CONTACT_MU
    preset: str = "default"
    contact_samples: int = CONTACT_SAMPLES
    variants: tuple[str, ...] = ("spring", "parallel")
    scenarios: tuple[str, ...] = tuple(SCENARIOS)
    slip_scenario: str = "run4"
    slip_mu: float = 0.01
    slip_sole: tuple[float, float] = (-1.0, 1.0)
    motor_scenario: str = "run4"
    motor_samples: int = 120
    flywheels: tuple[float, ...] = (1.0, 5.0, 20.0)
    fluctuation: float = 0.05
    omegas: tuple[float, ...] = (0.1, 0.5, 1.0, 2.0, 5.0)
    energy_variants: tuple[str, ...] = ("spring", "parallel")
    body_mass: float = DEFAULT_BODY_MASS
    body_com_dx: float = 0.0
    nodes: int = energy.NODES
    power_variant: str = "spring"
    power_omega: float = 5.0
    design: Design | None = None


# --------------------------------------------------------------------------- contact
@dataclass(frozen=True)
class ScenarioContact:
    """Heel/toe contact of one scenario and variant over one right stance.

    Attributes:
        scenario: scenario name.
        variant: leg variant.
        torques: the inverse-dynamics result (TorqueResult).
        contact: the :class:`ContactResult`.

    """

    __repr__ = short_repr

    scenario: str
    variant: str
    torques: TorqueResult
    contact: ContactResult

    @property
    def label(self) -> str:
        """``"scenario (variant)"``."""
        return f"{self.scenario} ({self.variant})"

    @property
    def max_mu_needed(self) -> float:
        """Largest finite friction coefficient needed over the stance [-] (nan when none is finite)."""
        finite = self.contact.mu_needed[np.isfinite(self.contact.mu_needed)]
        return float(np.max(finite)) if finite.size else math.nan


@dataclass(frozen=True)
class ContactSweep:
    """Contact of every scenario and variant, and the infeasible-friction check.

    Attributes:
        mu: friction coefficient of the sweep [-].
        cases: one :class:`ScenarioContact` per (variant, scenario), variants outer.
        slip: contact of the infeasible-friction check (tiny mu on a what-if sole).

    """

    __repr__ = short_repr

    mu: float
    cases: list[ScenarioContact]
    slip: ContactResult

    def worst_mu(self) -> tuple[float, str]:
        """(largest friction coefficient needed [-], ``"scenario, variant"``); (0, "") when none is positive."""
        worst = (0.0, "")
        for case in self.cases:
            value = case.max_mu_needed
            if value > worst[0]:
                worst = (value, f"{case.scenario}, {case.variant}")
        return worst


def contact_sweep(settings: ContactEnergySettings | None = None) -> ContactSweep:
    """Heel/toe contact of every scenario for every variant (see :func:`scenario_contact`).

    Args:
        settings: friction, preset, samples, scenarios and variants; the slip check's scenario, mu and sole.

    Returns:
        The :class:`ContactSweep`.

    """
    settings = settings or ContactEnergySettings()
    cases = []
    for variant in settings.variants:
        for name in settings.scenarios:
            torques, res = scenario_contact(name, settings.preset, settings.mu, settings.contact_samples, None, variant)
            cases.append(ScenarioContact(name, variant, torques, res))
    _, slip = scenario_contact(
        settings.slip_scenario, settings.preset, settings.slip_mu, settings.contact_samples, settings.slip_sole
    )
    return ContactSweep(mu=settings.mu, cases=cases, slip=slip)


# --------------------------------------------------------------------------- one motor
@dataclass(frozen=True)
class FlywheelCase:
    """The single motor with one flywheel; ``flywheel`` is None when the inertia is too small.

    Attributes:
        inertia: flywheel inertia [kg.m^2].
        flywheel: the :class:`pasibot_pin.studies.single_motor.Flywheel`, or None.
        error: why the inertia is too small ("" when it is not).
        variant: leg variant ("" when not relevant).
        omega: crank speed [rad/s] (nan when not relevant).

    """

    __repr__ = short_repr

    inertia: float
    flywheel: single_motor.Flywheel | None
    error: str = ""
    variant: str = ""
    omega: float = math.nan

    def summary(self) -> str:
        """One line: the motor's constant torque and the speed fluctuation, or why there is none."""
        head = f"  {self.variant:8s} omega {self.omega:g} rad/s:"
        fw = self.flywheel
        if fw is None:
            return f"{head} {self.error}"
        return (
            f"{head} motor {fw.mean_torque:+.3f} N.m constant instead of peak {fw.peak_without:.3f} N.m; "
            f"speed fluctuation {fw.speed_fluctuation * 100:.3f} %"
        )


def _flywheel_case(theta, torque, omega: float, inertia: float, variant: str = "") -> FlywheelCase:
    try:
        return FlywheelCase(inertia, single_motor.flywheel(theta, torque, omega, inertia), "", variant, omega)
    except ValueError as err:
        return FlywheelCase(inertia, None, str(err), variant, omega)


@dataclass(frozen=True)
class SingleMotorStudy:
    """One motor for both cranks over a full turn of one scenario.

    Attributes:
        scenario: scenario name.
        omega: crank speed [rad/s].
        thetas: right crank angles over one turn [rad].
        torques: the two-motor inverse-dynamics result (TorqueResult).
        single: the :class:`pasibot_pin.studies.single_motor.SingleMotorResult`.
        flywheels: one :class:`FlywheelCase` per inertia, over one step.
        fluctuation: target speed fluctuation [-].
        inertia_for_target: flywheel inertia for that fluctuation [kg.m^2].

    """

    __repr__ = short_repr

    scenario: str
    omega: float
    thetas: np.ndarray
    torques: TorqueResult
    single: single_motor.SingleMotorResult
    flywheels: list[FlywheelCase]
    fluctuation: float
    inertia_for_target: float

    @property
    def two_motor_sum(self) -> np.ndarray:
        """T_a + T_a' of the two-motor solution [N.m]."""
        return self.torques.Ta + self.torques.Ta_swing

    @property
    def peak_power(self) -> float:
        """Largest |motor power| u omega over the turn, with no flywheel [W] (the crank speed is held)."""
        return float(np.max(np.abs(self.single.motor))) * self.omega

    @property
    def mean_torque(self) -> float:
        """The motor's mean torque over one step [N.m]: its constant torque with a flywheel of any size."""
        step = slice(0, len(self.thetas) // 2 + 1)
        theta = self.thetas[step]
        return float(np.trapezoid(self.single.motor[step], theta) / (theta[-1] - theta[0]))

    @property
    def mean_power(self) -> float:
        """The motor's mean power, its mean torque times omega [W]."""
        return self.mean_torque * self.omega

    @property
    def max_deviation(self) -> float:
        """Largest |single motor - (T_a + T_a')| over the turn [N.m]."""
        return float(np.max(np.abs(self.single.motor - self.two_motor_sum)))

    def columns(self) -> dict[str, np.ndarray]:
        """CSV columns: right crank angle [rad], right and left crank torques, motor torque [N.m]."""
        return {
            "theta_right": self.thetas,
            "Ta_right": np.where(np.array(self.torques.stance) == "right", self.torques.Ta, self.torques.Ta_swing),
            "Ta_left": self.single.transmission,
            "motor": self.single.motor,
        }


def single_motor_study(settings: ContactEnergySettings | None = None) -> SingleMotorStudy:
    """One motor for both cranks (coupled pi apart) over one full turn, flywheels over one step.

    The torque repeats every half turn (legs swapped), so the flywheels use one step, both ends.

    Args:
        settings: scenario, preset, samples per turn, flywheel inertias and target fluctuation.

    Returns:
        The :class:`SingleMotorStudy`.

    """
    settings = settings or ContactEnergySettings()

    scenario = get_scenario(settings.motor_scenario)
    robot = scenario_robot(scenario, get_preset(settings.preset))
    n = int(settings.motor_samples)
    thetas = np.linspace(math.pi / 2, 5 * math.pi / 2, n + 1)[:-1]
    torques = inverse_dynamics(robot, thetas, scenario.omega)
    single = single_motor.coupled_split(robot, torques)
    step = slice(0, n // 2 + 1)
    th, motor = thetas[step], single.motor[step]
    return SingleMotorStudy(
        scenario=settings.motor_scenario,
        omega=scenario.omega,
        thetas=thetas,
        torques=torques,
        single=single,
        flywheels=[_flywheel_case(th, motor, scenario.omega, j) for j in settings.flywheels],
        fluctuation=settings.fluctuation,
        inertia_for_target=single_motor.inertia_for(th, motor, scenario.omega, settings.fluctuation),
    )


# --------------------------------------------------------------------------- energy
@dataclass(frozen=True)
class EnergySweep:
    """Energy per step of each variant at each crank speed.

    Attributes:
        rows: :class:`pasibot_pin.studies.energy.StepEnergy` rows, speeds outer, variants inner.

    """

    __repr__ = short_repr

    rows: list[energy.StepEnergy]

    @property
    def all_finite(self) -> bool:
        """True when every row's motor cost of transport is finite."""
        return all(math.isfinite(r.cot["motors"]) for r in self.rows)

    def table(self) -> list[dict[str, float | str]]:
        """One dict per row (:meth:`StepEnergy.row`)."""
        return [r.row() for r in self.rows]

    def markdown(self) -> str:
        """The Markdown table (:func:`pasibot_pin.studies.energy.format_table`)."""
        return energy.format_table(self.rows)


def energy_sweep(settings: ContactEnergySettings | None = None) -> EnergySweep:
    """Energy per step over ``settings.omegas`` for ``settings.energy_variants`` (:func:`energy.omega_table`)."""
    settings = settings or ContactEnergySettings()
    if settings.design is not None:
        robot, motors = design_robot(settings.design, 2), settings.design.motors
        rows = [energy.robot_step_energy(robot, w, settings.nodes, motors=motors)[0] for w in settings.omegas]
        return EnergySweep(rows)
    rows = energy.omega_table(
        settings.omegas, settings.body_mass, settings.body_com_dx, settings.nodes, settings.energy_variants
    )
    return EnergySweep(rows)


@dataclass(frozen=True)
class PowerProfile:
    """Actuator powers over one step.

    Attributes:
        variant: leg variant.
        omega: crank speed [rad/s].
        theta: stance crank angles [rad].
        powers: power given by each actuator [W] (:func:`pasibot_pin.studies.energy.actuator_powers`).

    """

    __repr__ = short_repr

    variant: str
    omega: float
    theta: np.ndarray
    powers: dict[str, np.ndarray]


def power_profile(settings: ContactEnergySettings | None = None) -> PowerProfile:
    """Actuator powers of ``settings.power_variant`` at ``settings.power_omega`` over one step (no spring fit)."""
    settings = settings or ContactEnergySettings()
    variant, omega = settings.power_variant, settings.power_omega
    _, res = energy.step_energy(variant, omega, settings.body_mass, settings.body_com_dx, settings.nodes, fit=False)
    powers = energy.actuator_powers(energy.variant_robot(variant, settings.body_mass, settings.body_com_dx), res)
    return PowerProfile(variant, omega, res.theta, powers)


def check_flywheel_inertia(inertia: float) -> float:
    """Return ``inertia`` if it is a positive finite flywheel inertia [kg.m^2], else raise ``ValueError``."""
    if (
        isinstance(inertia, bool)
        or not isinstance(inertia, (int, float))
        or not (math.isfinite(inertia) and inertia > 0)
    ):
        raise ParameterError(f"parameter 'flywheel' must be a positive flywheel inertia [kg.m^2], got {inertia!r}")
    return float(inertia)


def flywheel_cases(
    omegas: Sequence[float],
    variants: Sequence[str],
    inertia: float,
    body_mass: float = DEFAULT_BODY_MASS,
    body_com_dx: float = 0.0,
    nodes: int = energy.NODES,
) -> list[FlywheelCase]:
    """The single motor (T_a + T_a') over one step with a flywheel, per speed (outer) and variant (inner).

    Args:
        omegas: crank speeds [rad/s].
        variants: leg variants.
        inertia: flywheel inertia on the motor shaft [kg.m^2].
        body_mass: body (hip) mass [kg].
        body_com_dx: body COM ahead of joint 8 [m].
        nodes: Gauss-Legendre nodes per step.

    Returns:
        One :class:`FlywheelCase` each; too small an inertia gives ``flywheel=None`` and the reason.

    Raises:
        ValueError: ``inertia`` not a positive finite number (:func:`check_flywheel_inertia`).

    """
    check_flywheel_inertia(inertia)
    cases = []
    for omega in omegas:
        for variant in variants:
            _, res = energy.step_energy(variant, omega, body_mass, body_com_dx, nodes, fit=False)
            cases.append(_flywheel_case(res.theta_right, res.Ta + res.Ta_swing, omega, inertia, variant))
    return cases


# --------------------------------------------------------------------------- all
@dataclass(frozen=True)
class ContactEnergyResult:
    """Everything of the ``contact_energy`` analysis.

    Attributes:
        settings: the settings used.
        contact: the :class:`ContactSweep`.
        motor: the :class:`SingleMotorStudy`.
        energy: the :class:`EnergySweep`.
        power: the :class:`PowerProfile`.

    """

    __repr__ = short_repr

    settings: ContactEnergySettings
    contact: ContactSweep
    motor: SingleMotorStudy
    energy: EnergySweep
    power: PowerProfile


def run(settings: ContactEnergySettings | None = None) -> ContactEnergyResult:
    """Contact sweep, single motor, energy sweep and power profile with one set of settings."""
    settings = settings or ContactEnergySettings()
    return ContactEnergyResult(
        settings=settings,
        contact=contact_sweep(settings),
        motor=single_motor_study(settings),
        energy=energy_sweep(settings),
        power=power_profile(settings),
    )
