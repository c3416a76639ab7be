"""Energy per step: motor power, positive and negative work, the ankle spring, cost of transport.

A step is one stance phase: the stance crank turns from pi/2 to 3 pi/2 at constant omega,
the stance foot welded (docs/reference.md §5). Along it:

* each actuator's power is its generalised force times its rate (cranks: T_a theta_dot;
  ankles: T_e beta_dot, beta = pi/2 - q_ankle); by virtual power their sum is the rate of
  kinetic plus potential energy (the constraint forces do no work),
* the integrals use Gauss-Legendre nodes in the crank angle (dt = d theta / omega): the
  net work is exact to round-off for the smooth power; positive and negative work
  integrate a clipped power and converge more slowly (about 1e-4 relative with 48 nodes),
* the ankle spring is the fitted line T_s = -K_e (beta - beta0) (:mod:`pasibot_pin.studies.methods.spring_fit`).
  Its energy 1/2 K_e (beta - beta0)^2 is stored and released; what T_e needs beyond it is
  the residual ankle work,
* a single motor for both cranks (:mod:`pasibot_pin.studies.single_motor`) gives T_a + T_a'; its
  positive work is below the two motors' sum when one crank brakes while the other drives,
* the cost of transport is a work per step over (total weight x the advance per step over a whole
  stride, :func:`~pasibot_pin.kinematics.gait.stride_advance`: for every variant, a positive distance).

The ``parallel`` variant (the seed's parallel extension) has 2 actuators for 2 degrees of
freedom (cranks only; its foot is held parallel by the linkage). Its torques come from the same
:func:`pasibot_pin.dynamics.inverse.inverse_dynamics` as every variant's (the variant's record
says what is prescribed and actuated; the split tau = S^T u + J_c^T lambda is
:func:`pasibot_pin.constraints.split_torques`).
Its masses follow :func:`pasibot_pin.model.params.percentage_mass_model`: the extension links
(L8, L9, L10, L11, the foot bar, a slider one crank long) get the thigh's mass per unit
length (6.5 kg over 1.175 m = 5.53 kg/m), about 10 kg per leg; the body mass and COM are the
scenario's, as for the ``spring`` variant.

Units: SI; work [J]; power [W]; cost of transport dimensionless.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from pasibot_pin.dynamics.inverse import inverse_dynamics
from pasibot_pin.errors import ParameterError
from pasibot_pin.kinematics.gait import stride_advance
from pasibot_pin.model.coordinates import HIP_PITCH, HIP_X, other
from pasibot_pin.model.design import check_parameter
from pasibot_pin.model.params import GRAVITY
from pasibot_pin.model.robot import PasibotRobot, total_mass
from pasibot_pin.model.scenario_robots import scenario_robot
from pasibot_pin.model.scenarios import DEFAULT_BODY_MASS, PRESETS, Scenario
from pasibot_pin.reprs import short_repr
from pasibot_pin.studies.methods.spring_fit import fit_spring

if TYPE_CHECKING:
    from pasibot_pin.dynamics.inverse import TorqueResult
    from pasibot_pin.studies.methods.spring_fit import SpringFit

STEP_START: float = math.pi / 2
"""Stance crank angle where a step starts [rad]."""
STEP_END: float = 3 * math.pi / 2
"""Stance crank angle where it ends [rad]."""
NODES: int = 48
"""Default Gauss-Legendre nodes per step."""


def gauss_legendre(a: float, b: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [a, b]."""
    if n < 2:
        raise ParameterError(f"parameter 'nodes' must be >= 2, got {n!r}")
    x, w = np.polynomial.legendre.leggauss(int(n))
    half = 0.5 * (b - a)
    return 0.5 * (a + b) + half * x, half * w


# --------------------------------------------------------------------------- robots
def variant_robot(variant: str, body_mass: float, body_com_dx: float = 0.0) -> PasibotRobot:
    """A two-legged robot of ``variant`` with the percentage-rule masses and this body [kg, m].

    The rule is :func:`pasibot_pin.model.params.percentage_mass_model` (for ``parallel`` its
    extension links get the thigh's mass per unit length); the body (hip) mass and its COM
    offset ahead of joint 8 replace the rule's. The same robot as
    :func:`pasibot_pin.model.scenario_robots.scenario_robot` with the default modelling choices.
    """
    if not (math.isfinite(body_mass) and body_mass > 0):
        raise ParameterError(f"parameter 'body_mass' must be positive [kg], got {body_mass!r}")
    scenario = Scenario("body", 0.0, float(body_mass), float(body_mass), float(body_com_dx), None, None, "body")
    return scenario_robot(scenario, PRESETS["default"], variant)


# --------------------------------------------------------------------------- power and energy
def actuator_powers(robot: PasibotRobot, result) -> dict[str, np.ndarray]:
    """Power of each actuator along ``result`` [W] (positive: the actuator gives energy).

    Keys ``crank_stance``, ``crank_swing`` and, for the ``spring`` variant, ``ankle_stance``,
    ``ankle_swing``.
    """
    n = len(result.t)
    out = {k: np.zeros(n) for k in ("crank_stance", "crank_swing")}
    spring = robot.spec.free_ankle
    if spring:
        out.update({k: np.zeros(n) for k in ("ankle_stance", "ankle_swing")})
    for k in range(n):
        side = result.stance[k]
        swing = other(side)
        v = result.v[k]
        out["crank_stance"][k] = result.Ta[k] * v[robot.idx_v(f"{side}_j0_crank")]
        out["crank_swing"][k] = result.Ta_swing[k] * v[robot.idx_v(f"{swing}_j0_crank")]
        if spring:  # beta_dot = -q_ankle_dot
            out["ankle_stance"][k] = -result.Te[k] * v[robot.idx_v(f"{side}_j13_ankle")]
            out["ankle_swing"][k] = -result.Te_swing[k] * v[robot.idx_v(f"{swing}_j13_ankle")]
    return out


def mechanical_energy(robot: PasibotRobot, q: np.ndarray, v: np.ndarray) -> tuple[float, float]:
    """(kinetic, potential) energy at (q, v) [J]; the potential is zero at z = 0."""
    model, data = robot.model, robot.data
    kinetic = float(pin.computeKineticEnergy(model, data, q, v))
    potential = float(pin.computePotentialEnergy(model, data, q))
    return kinetic, potential


@dataclass
class StepEnergy:
    """Work and energy over one step (one stance phase) at constant crank speed.

    Attributes:
        variant: ``spring`` or ``parallel``.
        omega: crank speed [rad/s].
        total_mass: robot mass [kg].
        distance: the hip's advance per step over a whole stride [m]
            (:func:`~pasibot_pin.kinematics.gait.stride_advance`; 8 L with a level hip).
        duration: step time (pi / omega) [s].
        crank: net, positive and negative work of the two crank motors (each counted alone) [J].
        single: net, positive and negative work of one motor driving both cranks [J].
        ankle: net, positive and negative work of the two ankle actuators (zeros for parallel) [J].
        spring: K_e [N.m/rad], beta0 [rad], energy stored and released by the stance spring [J],
            and the residual stance-ankle work beyond the spring: net, positive [J] (spring only).
        energy_start, energy_end: kinetic + potential at the step's ends [J].
        single_peak, single_rms: single-motor torque peak and RMS over the step [N.m].
        cot: cost of transport by work definition: ``motors`` (positive work of the two crank
            motors), ``single`` (one motor), ``actuators`` (cranks + ankles, no spring),
            ``motors+residual`` (cranks + ankle work the spring cannot give; spring only) [-].

    """

    __repr__ = short_repr

    variant: str
    omega: float
    total_mass: float
    distance: float
    duration: float
    crank: tuple[float, float, float]
    single: tuple[float, float, float]
    ankle: tuple[float, float, float]
    energy_start: float
    energy_end: float
    single_peak: float
    single_rms: float
    spring: dict[str, float] = field(default_factory=dict)
    cot: dict[str, float] = field(default_factory=dict)

    @property
    def net_work(self) -> float:
        """Net work of every actuator over the step [J] (= energy_end - energy_start)."""
        return self.crank[0] + self.ankle[0]

    @property
    def delta_energy(self) -> float:
        """Change of kinetic + potential energy over the step [J]."""
        return self.energy_end - self.energy_start

    def row(self) -> dict[str, float | str]:
        """One flat table row (SI units)."""
        out: dict[str, float | str] = {
            "variant": self.variant,
            "omega": self.omega,
            "mass": self.total_mass,
            "distance": self.distance,
            "speed": self.distance / self.duration,
            "W_crank_net": self.crank[0],
            "W_crank_pos": self.crank[1],
            "W_crank_neg": self.crank[2],
            "W_single_pos": self.single[1],
            "W_single_neg": self.single[2],
            "W_ankle_net": self.ankle[0],
            "W_ankle_pos": self.ankle[1],
            "dE": self.delta_energy,
            "single_peak": self.single_peak,
            "single_rms": self.single_rms,
        }
        out.update({f"spring_{k}": v for k, v in self.spring.items()})
        out.update({f"cot_{k}": v for k, v in self.cot.items()})
        return out


def _split(values: np.ndarray, weights: np.ndarray, omega: float) -> tuple[float, float, float]:
    dt = weights / omega
    return float(dt @ values), float(dt @ np.maximum(values, 0.0)), float(dt @ np.minimum(values, 0.0))


def _step_energy(robot: PasibotRobot, result, weights, omega, variant, fit=None) -> StepEnergy:
    """Integrate the powers of ``result`` (rows 1..-2 are the nodes; rows 0 and -1 the step ends)."""
    powers = {k: p[1:-1] for k, p in actuator_powers(robot, result).items()}
    crank_each = [_split(powers[k], weights, omega) for k in ("crank_stance", "crank_swing")]
    crank = tuple(a + b for a, b in zip(*crank_each))
    single_power = powers["crank_stance"] + powers["crank_swing"]  # (T_a + T_a') omega
    single = _split(single_power, weights, omega)
    single_torque = (result.Ta + result.Ta_swing)[1:-1]
    duration = float(np.sum(weights)) / omega
    rms = math.sqrt(float(weights @ single_torque**2) / float(np.sum(weights)))
    ankle = (0.0, 0.0, 0.0)
    spring: dict[str, float] = {}
    if "ankle_stance" in powers:
        ankle_each = [_split(powers[k], weights, omega) for k in ("ankle_stance", "ankle_swing")]
        ankle = tuple(a + b for a, b in zip(*ankle_each))
        if fit is not None:
            beta_dot = -np.array([v[robot.idx_v(f"{s}_j13_ankle")] for v, s in zip(result.v, result.stance)])[1:-1]
            beta = result.beta[1:-1]
            p_spring = fit.torque(beta) * beta_dot
            p_resid = powers["ankle_stance"] - p_spring
            stored, released = -_split(p_spring, weights, omega)[2], _split(p_spring, weights, omega)[1]
            resid = _split(p_resid, weights, omega)
            spring = {
                "K_e": fit.K_e,
                "beta0": fit.beta0,
                "stored": stored,
                "released": released,
                "residual_net": resid[0],
                "residual_pos": resid[1] + ankle_each[1][1],  # with the swing ankle's positive work
            }
    energies = [sum(mechanical_energy(robot, result.q[i], result.v[i])) for i in (0, -1)]
    mass = total_mass(robot)
    distance = float(result.q[-1][HIP_X] - result.q[0][HIP_X])
    if abs(result.q[-1][HIP_PITCH] - result.q[0][HIP_PITCH]) > 1e-9:
        # the body rocks within the step (a rigid foot, square to its shank): the step's own hip
        # travel is not its advance; measure it over a whole stride, where the rocking cancels
        distance = stride_advance(robot)
    weight_distance = mass * GRAVITY * distance
    cot = {
        "motors": crank[1] / weight_distance,
        "single": single[1] / weight_distance,
        "actuators": (crank[1] + ankle[1]) / weight_distance,
    }
    if spring:
        cot["motors+residual"] = (crank[1] + spring["residual_pos"]) / weight_distance
    return StepEnergy(
        variant=variant,
        omega=omega,
        total_mass=mass,
        distance=distance,
        duration=duration,
        crank=crank,
        single=single,
        ankle=ankle,
        energy_start=energies[0],
        energy_end=energies[1],
        single_peak=float(np.max(np.abs(single_torque))),
        single_rms=rms,
        spring=spring,
        cot=cot,
    )


def step_energy(
    variant: str,
    omega: float,
    body_mass: float = DEFAULT_BODY_MASS,
    body_com_dx: float = 0.0,
    nodes: int = NODES,
    theta_end: float = STEP_END,
    fit: bool = True,
) -> tuple[StepEnergy, TorqueResult]:
    """Energy over one step of a biped of ``variant`` (default modelling choices).

    Args:
        variant: ``rigid``, ``parallel`` or ``spring``.
        omega: crank speed [rad/s], > 0.
        body_mass: body (hip) mass [kg].
        body_com_dx: body COM ahead of joint 8 [m].
        nodes: Gauss-Legendre nodes.
        theta_end: stance crank angle where the integration stops (3 pi/2: a full step) [rad].
        fit: with a spring ankle, fit the spring (K_e, beta0) on 61 uniform samples of the
            same stance and speed.

    Returns:
        (StepEnergy, the TorqueResult at [start, nodes..., end]).

    """
    omega = check_parameter("omega", omega, low_open=True)  # > 0: a quasi-static step takes forever
    if not (STEP_START < theta_end <= STEP_END):
        raise ParameterError(f"parameter 'theta_end' must be in (pi/2, 3 pi/2] [rad], got {theta_end!r}")
    return robot_step_energy(variant_robot(variant, body_mass, body_com_dx), omega, nodes, theta_end, fit)


def robot_step_energy(
    robot: PasibotRobot,
    omega: float,
    nodes: int = NODES,
    theta_end: float = STEP_END,
    fit: bool | SpringFit = True,
    motors: str = "two",
) -> tuple[StepEnergy, TorqueResult]:
    """Energy over one step of a given two-legged robot (the work of :func:`step_energy`).

    Args:
        robot: a two-legged robot of any variant (e.g. a design's).
        omega: crank speed [rad/s], > 0.
        nodes: Gauss-Legendre nodes.
        theta_end: stance crank angle where the integration stops [rad].
        fit: with a spring ankle: ``True`` fits the spring (K_e, beta0) on 61 uniform samples
            of the same stance and speed; a :class:`~pasibot_pin.studies.methods.spring_fit.SpringFit`
            is used as given; ``False`` leaves the spring out.
        motors: ``two`` or ``one`` (the inverse dynamics' motor layout).

    Returns:
        (StepEnergy, the TorqueResult at [start, nodes..., end]).

    """
    th, w = gauss_legendre(STEP_START, theta_end, nodes)
    thetas = np.concatenate(([STEP_START], th, [theta_end]))
    result = inverse_dynamics(robot, thetas, omega, stance="right", reactions=False, motors=motors)
    spring_fit = None
    if robot.spec.free_ankle and fit is True:  # K_e, beta0 on 61 uniform samples of the right stance, ends included
        uniform = inverse_dynamics(robot, np.linspace(STEP_START, STEP_END, 61), omega, stance="right", reactions=False)
        spring_fit = fit_spring(uniform.beta, uniform.Te, warn=False)
    elif robot.spec.free_ankle and not isinstance(fit, bool):
        spring_fit = fit
    return _step_energy(robot, result, w, omega, robot.variant, spring_fit), result


def spring_step_energy(omega: float, *args, **kwargs) -> tuple[StepEnergy, TorqueResult]:
    """:func:`step_energy` of the ``spring`` biped."""
    return step_energy("spring", omega, *args, **kwargs)


def parallel_step_energy(omega: float, *args, **kwargs) -> tuple[StepEnergy, TorqueResult]:
    """:func:`step_energy` of the ``parallel`` biped (no spring to fit)."""
    return step_energy("parallel", omega, *args, **kwargs)


def omega_table(
    omegas: Sequence[float],
    body_mass: float = DEFAULT_BODY_MASS,
    body_com_dx: float = 0.0,
    nodes: int = NODES,
    variants: Sequence[str] = ("spring", "parallel"),
) -> list[StepEnergy]:
    """Energy per step of each variant at each crank speed (same body mass and COM) [rad/s]."""
    return [step_energy(v, omega, body_mass, body_com_dx, nodes)[0] for omega in omegas for v in variants]


def format_table(rows: Sequence[StepEnergy]) -> str:
    """A Markdown table of :func:`omega_table` rows."""
    head = (
        "| variant | omega [rad/s] | mass [kg] | step [m] | W+ motors [J] | W- motors [J] | W+ one motor [J] "
        "| W+ ankles [J] | spring stored/released [J] | peak / RMS one motor [N.m] | CoT motors [-] "
        "| CoT one motor [-] | CoT actuators [-] |"
    )
    lines = [head, "|" + "---|" * 13]
    for r in rows:
        spring = f"{r.spring['stored']:.3f} / {r.spring['released']:.3f}" if r.spring else "-"
        ankle = f"{r.ankle[1]:.3f}" if r.spring or any(r.ankle) else "-"
        lines.append(
            f"| {r.variant} | {r.omega:g} | {r.total_mass:.2f} | {r.distance:.4f} | {r.crank[1]:.4f} | "
            f"{r.crank[2]:.4f} | {r.single[1]:.4f} | {ankle} | {spring} | {r.single_peak:.2f} / {r.single_rms:.2f} | "
            f"{r.cot['motors']:.4f} | {r.cot['single']:.4f} | {r.cot['actuators']:.4f} |"
        )
    return "\n".join(lines)
