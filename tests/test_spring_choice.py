"""The recommended spring (studies/spring_choice.py): the smallest K_e holding the welded hip within the limit.

Checked against the quasi-static equilibria it is built on: the recommended spring holds, and a
spring a tolerance softer at every rest angle tried does not; its margin is K_e - k_g.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pasibot_pin.dynamics.spring_energy import AnkleSpring
from pasibot_pin.studies import spring_choice
from pasibot_pin.studies.methods.static_batch import static_equilibria
from pasibot_pin.studies.spring_study import scenario_inputs, toppling_stiffness


@pytest.fixture(scope="module")
def choice():
    return spring_choice.recommended_spring("run1")


def _largest(robot, springs):
    thetas = np.linspace(math.pi / 2, 1.5 * math.pi, spring_choice.STATIC_SAMPLES, endpoint=False)
    return np.array([eq.max_excursion for eq in static_equilibria(robot, springs, thetas)])


def test_the_recommended_spring_is_the_smallest_that_holds(choice):
    inputs = scenario_inputs("run1")
    fit = inputs.fit
    assert choice.max_pitch <= choice.limit == spring_choice.MAX_PITCH
    held = _largest(inputs.robot, [AnkleSpring(choice.stiffness, choice.rest_angle, fit.damping)])[0]
    assert held == pytest.approx(choice.max_pitch, abs=1e-9)
    rests = fit.rest_angle + np.radians(np.arange(-6.0, 6.0 + 1e-9, spring_choice.REST_STEP_DEG))
    softer = choice.stiffness - spring_choice.STIFFNESS_TOL
    assert np.all(_largest(inputs.robot, [AnkleSpring(softer, b, fit.damping) for b in rests]) > choice.limit)
    # stiffer than gravity's toppling stiffness, and stiffer than the fit (which does not hold at all)
    assert choice.toppling == pytest.approx(toppling_stiffness(inputs.robot), rel=1e-12)
    assert choice.margin == pytest.approx(choice.stiffness - choice.toppling)
    assert choice.stiffness > choice.fitted_stiffness > choice.toppling


def test_an_unreachable_limit_is_refused():
    with pytest.raises(ValueError, match="no spring"):
        spring_choice.recommended_spring("run1", limit=math.radians(1.0))
