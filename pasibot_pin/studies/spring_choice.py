"""Which ankle spring to build? The smallest K_e that keeps the welded hip within a stated pitch.

The definition (stated once, quoted by the report's answers box):

* the robot of a seed scenario (default run 1: body 16 kg, 0.1 rad/s), stance foot welded flat,
  the swing foot at the spring's rest angle;
* quasi-static: the cranks held at :data:`STATIC_SAMPLES` crank angles along the stance, the hip
  pitch at its stable equilibrium (:func:`~pasibot_pin.studies.methods.static_batch.static_equilibria`);
* the **recommended spring** is the smallest stiffness K_e [N.m/rad], over rest angles beta0 of the
  fit +- 6 deg (every :data:`REST_STEP_DEG`), whose equilibrium |hip pitch| stays within
  :data:`MAX_PITCH` at every crank angle, found by bisection on K_e to :data:`STIFFNESS_TOL`;
* its **margin** is K_e - k_g over gravity's toppling stiffness k_g = g sum m (z - z_ankle)
  (:func:`~pasibot_pin.studies.spring_study.toppling_stiffness`); the fitted K_e's margin is
  given beside it.

It answers the weld's quasi-static question only: a walk (hip inertia, landings) swings further,
and a real floor may roll the foot (:mod:`pasibot_pin.studies.floor_static`).

Units: SI; angles [rad].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pasibot_pin.dynamics.spring_energy import AnkleSpring
from pasibot_pin.reprs import short_repr
from pasibot_pin.studies.methods.static_batch import static_equilibria
from pasibot_pin.studies.spring_study import scenario_inputs, toppling_stiffness

MAX_PITCH = math.radians(20.0)
"""The stated limit on the welded hip's quasi-static |pitch| [rad] (20 deg)."""
REST_STEP_DEG = 1.5
"""Spacing of the rest angles tried, fit - 6 .. fit + 6 deg [deg]."""
STIFFNESS_TOL = 0.5
"""Bisection tolerance on K_e [N.m/rad]."""
STATIC_SAMPLES = 19
"""Crank angles along the stance where the hip must hold [-]."""
HIGHEST_FACTOR = 4.0
"""The stiffest spring tried, as a factor on the fitted K_e [-]."""


@dataclass(frozen=True)
class SpringChoice:
    """The recommended ankle spring of a scenario (see the module docstring).

    Attributes:
        scenario: the seed scenario.
        stiffness: recommended K_e [N.m/rad] (the smallest that holds, to :data:`STIFFNESS_TOL`).
        rest_angle: its rest angle beta0 [rad].
        max_pitch: its largest quasi-static |hip pitch| along the stance [rad].
        limit: the stated limit on |hip pitch| [rad].
        toppling: gravity's toppling stiffness k_g [N.m/rad].
        fitted_stiffness: the inverse-dynamics fit's K_e [N.m/rad].
        fitted_rest_angle: the fit's beta0 [rad].

    """

    __repr__ = short_repr

    scenario: str
    stiffness: float
    rest_angle: float
    max_pitch: float
    limit: float
    toppling: float
    fitted_stiffness: float
    fitted_rest_angle: float

    @property
    def margin(self) -> float:
        """K_e - k_g [N.m/rad]: the static margin over gravity's toppling stiffness."""
        return self.stiffness - self.toppling

    @property
    def fitted_margin(self) -> float:
        """The fitted spring's K_e - k_g [N.m/rad]."""
        return self.fitted_stiffness - self.toppling


def _excursions(robot, stiffness: np.ndarray, rests: np.ndarray, damping: float, cache: dict) -> np.ndarray:
    """Largest quasi-static |hip pitch| [rad] of each (K_e, beta0) pair (inf: no stable equilibrium)."""
    thetas = np.linspace(math.pi / 2, 1.5 * math.pi, STATIC_SAMPLES, endpoint=False)
    springs = [AnkleSpring(float(k), float(b), damping) for k, b in zip(stiffness, rests)]
    return np.array([eq.max_excursion for eq in static_equilibria(robot, springs, thetas, cache=cache)])


def recommended_spring(scenario: str = "run1", limit: float = MAX_PITCH) -> SpringChoice:
    """The smallest K_e (and its beta0) holding the welded hip within ``limit`` quasi-statically.

    Args:
        scenario: a seed scenario (its robot and fitted spring, :func:`~.spring_study.scenario_inputs`).
        limit: the largest |hip pitch| allowed at any crank angle of the stance [rad].

    Returns:
        The :class:`SpringChoice`.

    Raises:
        ValueError: no spring up to :data:`HIGHEST_FACTOR` times the fit holds within ``limit``.

    """
    inputs = scenario_inputs(scenario)
    fit, robot = inputs.fit, inputs.robot
    cache: dict = {}
    k_g = toppling_stiffness(robot)
    rests = fit.rest_angle + np.radians(np.arange(-6.0, 6.0 + 1e-9, REST_STEP_DEG))
    low = np.full(len(rests), min(k_g, fit.stiffness))  # below k_g nothing is stable
    high = np.full(len(rests), HIGHEST_FACTOR * fit.stiffness)
    holds = _excursions(robot, high, rests, fit.damping, cache) <= limit
    if not np.any(holds):
        raise ValueError(f"no spring up to {HIGHEST_FACTOR:g} x the fit holds {scenario}'s hip within the limit")
    rests, low, high = rests[holds], low[holds], high[holds]
    while np.max(high - low) > STIFFNESS_TOL:  # every rest angle bisected together
        mid = 0.5 * (low + high)
        ok = _excursions(robot, mid, rests, fit.damping, cache) <= limit
        high, low = np.where(ok, mid, high), np.where(ok, low, mid)
    best = int(np.argmin(high))
    pitch = _excursions(robot, high[best : best + 1], rests[best : best + 1], fit.damping, cache)[0]
    return SpringChoice(
        scenario=scenario,
        stiffness=float(high[best]),
        rest_angle=float(rests[best]),
        max_pitch=float(pitch),
        limit=float(limit),
        toppling=float(k_g),
        fitted_stiffness=float(fit.stiffness),
        fitted_rest_angle=float(fit.rest_angle),
    )
