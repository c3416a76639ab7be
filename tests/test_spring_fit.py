"""Spring fit: K_e = -slope, beta0, R^2 and residuals against independent computations."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from pasibot_pin.dynamics import inverse as dynamics
from pasibot_pin.model import scenarios
from pasibot_pin.studies.methods import spring_fit as spring


def test_exact_line_is_recovered():
    beta = np.linspace(1.0, 1.4, 23)
    torque = -331.05 * (beta - math.radians(70.0))
    fit = spring.fit_spring(beta, torque)
    assert fit.K_e == pytest.approx(331.05, rel=1e-12)
    assert fit.beta0 == pytest.approx(math.radians(70.0), rel=1e-12)
    assert fit.r2 == pytest.approx(1.0, abs=1e-12)
    assert fit.max_residual < 1e-10 and fit.samples == 23
    assert fit.torque(fit.beta0) == pytest.approx(0.0, abs=1e-9)


def test_noisy_fit_matches_numpy_polyfit_and_corrcoef():
    rng = np.random.default_rng(3)
    beta = np.sort(rng.uniform(1.0, 1.4, 40))
    torque = -250.0 * (beta - 1.2) + rng.normal(scale=3.0, size=beta.size) + 5.0 * np.sin(9 * beta)
    fit = spring.fit_spring(beta, torque)
    slope, intercept = np.polyfit(beta, torque, 1)
    assert fit.K_e == pytest.approx(-slope, rel=1e-10)
    assert fit.beta0 == pytest.approx(-intercept / slope, rel=1e-10)
    assert fit.r2 == pytest.approx(np.corrcoef(beta, torque)[0, 1] ** 2, rel=1e-10)
    np.testing.assert_allclose(fit.residual, torque - np.polyval([slope, intercept], beta), atol=1e-9)
    assert fit.rms_residual == pytest.approx(np.sqrt(np.mean(fit.residual**2)))


def test_low_r2_warns_and_records_the_warning():
    beta = np.linspace(1.0, 1.4, 30)
    torque = 100 * np.sin(30 * beta) - 10 * beta
    with pytest.warns(spring.LowFitQualityWarning, match="not meaningful"):
        fit = spring.fit_spring(beta, torque)
    assert fit.r2 < spring.LOW_R2 and "R^2" in fit.warning and "WARNING" in fit.summary()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        quiet = spring.fit_spring(beta, torque, warn=False)
    assert quiet.warning


def test_bad_fit_input():
    with pytest.raises(ValueError, match="constant"):
        spring.fit_spring([1.0, 1.0, 1.0], [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="differ in length"):
        spring.fit_spring([1.0, 2.0], [1.0])
    with pytest.raises(ValueError, match="finite"):
        spring.fit_spring([1.0, float("nan")], [1.0, 2.0])


def test_fit_window_must_be_samples_inside_stance():
    res = dynamics.run_scenario(scenarios.SCENARIOS["run1"], scenarios.PRESETS["seed"])
    fit_all = spring.fit_result(res, None)
    fit_win = spring.fit_result(res, scenarios.SEED_FIT_THETAS)
    assert fit_all.K_e == pytest.approx(fit_win.K_e)  # the seed run holds exactly its window
    with pytest.raises(ValueError, match="not a sample"):
        spring.fit_result(res, [2.65, 3.0])
    with pytest.raises(ValueError, match="outside stance"):
        spring.fit_result(res, [0.2, 3.0])


def test_stiffness_is_the_slope_of_the_gravity_moment():
    """Quasi-statically K_e is minus d(T_e)/d(beta); a heavier body gives a stiffer spring."""
    choices = scenarios.PRESETS["default"]
    light = spring.fit_result(dynamics.run_scenario(scenarios.SCENARIOS["quasi-static"], choices), warn=False)
    heavy_scn = scenarios.Scenario("heavy", 0.0, 30.0, 30.0, 0.0, None, None, "test")
    heavy = spring.fit_result(dynamics.run_scenario(heavy_scn, choices), warn=False)
    assert heavy.K_e > light.K_e > 0
