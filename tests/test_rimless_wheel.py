"""The floor's contact step and impacts on the rimless wheel (McGeer; Coleman, Chatterjee and Ruina):
the periodic roll and its step map's slope against the closed form, on a slope of 0.08 rad."""

from __future__ import annotations

import math

import pytest

from pasibot_pin.errors import NoFixedPointError, ParameterError
from pasibot_pin.studies.methods.rimless_wheel import RimlessWheel, WheelStepper, check


def test_closed_form_is_the_issues_figure():
    """cot(2 alpha) sqrt(4 (g/l) sin(alpha) sin(gamma)) for 8 spokes, 1 m, 0.08 rad; cos^2(2 alpha) = 1/2."""
    rate, slope = RimlessWheel().closed_form()
    assert rate == pytest.approx(1.09546, abs=5e-6)
    assert slope == pytest.approx(0.5, abs=1e-15)


@pytest.mark.slow
def test_a_stride_conserves_energy_between_landings_and_loses_it_at_them():
    """From mid-stance, the rate just after the next landing is cos(2 alpha) times the rate the hub reaches
    falling from mid-stance to the landing (energy conserved in between), to O(h)."""
    wheel = RimlessWheel(dt=1e-4)
    g, a, gamma = 9.81, wheel.alpha, wheel.slope
    mid = 0.9
    before = math.sqrt(mid**2 + 2 * g / wheel.length * (math.cos(gamma) - math.cos(a + gamma)))
    _, landing = WheelStepper(wheel).stride(mid)
    assert landing == pytest.approx(math.cos(2 * a) * before, rel=1e-3)


@pytest.mark.slow
def test_periodic_roll_and_its_slope_match_the_closed_form():
    """The fixed point's landing rate to 1e-3 (its O(h) at h = 0.1 ms: 1.0947 against 1.09546, so 1.095 to
    4 digits) and the step map's slope cos^2(2 alpha) = 0.5 to 2e-3 (0.4994)."""
    found = check(RimlessWheel(dt=1e-4), bracket=(0.5, 0.6))
    assert found.landing_rate == pytest.approx(found.closed_rate, rel=1e-3)
    assert f"{found.landing_rate:.4g}" == f"{found.closed_rate:.4g}"
    assert found.slope == pytest.approx(found.closed_slope, abs=2e-3)


@pytest.mark.slow
def test_bad_wheels_and_brackets_are_refused():
    with pytest.raises(ParameterError, match="spokes"):
        RimlessWheel(spokes=2)
    with pytest.raises(ParameterError, match="slope"):
        RimlessWheel(slope=-0.1)
    # F(x) - x at the bracket's ends: -0.07 and -0.12 rad/s at a 1 ms step (-0.07 and -0.11 at 0.1 ms)
    with pytest.raises(NoFixedPointError, match="no fixed point"):
        check(RimlessWheel(dt=1e-3), bracket=(0.7, 0.8))
