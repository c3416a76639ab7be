"""The fitted fixed point (studies/methods/map_fit.py) on maps whose answer is known in closed form:
an affine map (exact), and the same map with small jumps, where Newton stalls and the fit does not."""

import cmath

import numpy as np
import pytest

from pasibot_pin.errors import DivergedError, NoFixedPointError, ParameterError
from pasibot_pin.studies.methods.map_fit import fit_affine_map, fit_fixed_point
from pasibot_pin.studies.methods.poincare import find_fixed_point

RADIUS, ANGLE = 0.9, 2.4  # the dominant pair, as PASIBOT's fastest walker's: a slow, turning decay
X_STAR = np.array([1.4, 0.02, 1.08, 0.016, -0.04])


def _matrix() -> np.ndarray:
    """A 5x5 map with eigenvalues 0.9 e^(+-2.4 i), 0.5, 0.2, 0.05 in a non-orthogonal basis."""
    block = RADIUS * np.array([[np.cos(ANGLE), -np.sin(ANGLE)], [np.sin(ANGLE), np.cos(ANGLE)]])
    diag = np.zeros((5, 5))
    diag[:2, :2] = block
    diag[2, 2], diag[3, 3], diag[4, 4] = 0.5, 0.2, 0.05
    basis = np.eye(5) + 0.3 * np.triu(np.ones((5, 5)), 1)
    return basis @ diag @ np.linalg.inv(basis)


A = _matrix()


def affine(x: np.ndarray) -> np.ndarray:
    return X_STAR + A @ (x - X_STAR)


def jumpy(x: np.ndarray, size: float = 3e-3, width: float = 1.2e-3) -> np.ndarray:
    """The affine map plus jumps of ``size`` each time x[2] crosses a multiple of ``width`` (a sawtooth
    of zero mean, like a landing that moves from one time step to the next)."""
    saw = (x[2] / width) % 1.0 - 0.5
    return affine(x) + size * saw * np.array([0.0, 0.1, 1.0, 0.1, -0.7])


def test_an_affine_map_is_fitted_exactly():
    point = fit_fixed_point(affine, X_STAR + 0.01, steps=30)
    assert np.allclose(point.x, X_STAR, atol=1e-9)
    assert np.allclose(point.jacobian, A, atol=1e-7)
    expected = sorted([RADIUS, RADIUS, 0.5, 0.2, 0.05], reverse=True)
    assert np.allclose(np.abs(point.multipliers), expected, atol=1e-7)
    assert point.dominant == pytest.approx(cmath.rect(RADIUS, ANGLE), abs=1e-7) or point.dominant == pytest.approx(
        cmath.rect(RADIUS, -ANGLE), abs=1e-7
    )
    assert np.max(point.jitter) < 1e-9
    assert point.spread == pytest.approx((RADIUS, RADIUS), abs=1e-6)
    assert point.stable and point.iterations == 0 and point.evaluations == 30


def test_newton_stalls_on_the_jumps_and_the_fit_finds_the_averaged_map():
    start = X_STAR + np.array([0.0, 0.0, 0.02, 0.0, 0.03])
    with pytest.raises(NoFixedPointError):
        find_fixed_point(jumpy, start, tol=1e-6, max_iter=4, fd_step=1e-3, scheme="forward")
    kick = np.array([0.0, 0.0, 0.0, 0.0, 0.05])
    point = fit_fixed_point(jumpy, start, steps=60, kick=kick)
    # the jumps are a zero-mean disturbance of at most 1.5e-3 per step in x[2]
    assert abs(point.spectral_radius - RADIUS) < 0.05
    assert np.max(np.abs(point.x - X_STAR)) < 3e-3
    assert 1e-4 < point.jitter[2] < 3e-3
    assert point.spread[0] <= point.spread[1] and point.spread[0] > 0.7
    assert point.cloud > 0


def test_fit_affine_map_recovers_a_known_map_from_pairs():
    rng = np.random.default_rng(1)
    before = rng.standard_normal((12, 3))
    jac = np.array([[0.5, 0.1, 0.0], [0.0, -0.3, 0.2], [0.1, 0.0, 0.8]])
    c, fitted, residual = fit_affine_map(before, 0.7 + before @ jac.T)
    assert np.allclose(fitted, jac) and np.allclose(c, 0.7) and np.max(np.abs(residual)) < 1e-12


def test_a_map_that_fails_is_no_fixed_point_and_bad_arguments_are_refused():
    def falls(x):
        if x[0] > 1.0:
            raise DivergedError("fell")
        return 2.0 * x

    with pytest.raises(NoFixedPointError, match="failed after"):
        fit_fixed_point(falls, np.array([0.01, 0.0]), steps=30)
    with pytest.raises(ParameterError, match="fit_steps"):
        fit_fixed_point(affine, X_STAR, steps=5)
    with pytest.raises(ParameterError, match="x0"):
        fit_fixed_point(affine, X_STAR * np.nan, steps=30)
    with pytest.raises(ParameterError, match="pairs"):
        fit_affine_map(np.zeros((3, 5)), np.zeros((3, 5)))
