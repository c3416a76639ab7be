"""Gait stability by shooting on a Poincaré map: studies.methods.poincare, validated on Garcia et al.'s simplest walker.

References typed in below (not produced by this package):

* [G98] M. Garcia, A. Chatterjee, A. Ruina, M. Coleman, "The simplest walking model: stability,
  complexity, and scaling", J. Biomech. Eng. 120(2):281-288 (1998). The numbers are those of the
  authors' own simulation code for the paper (header "All code by Mariano Garcia
  (msg5@cornell.edu), 1998 ... This simulation was used to produce results for the paper",
  distributed by the Ruina lab, Cornell): "initial conditions gam=0.009 long step to 1e-10,
  loc = -0.19120868949940 +/- 0.55633363687106i, theta1 = 0.20031090049483,
  theta1dot = -0.19983247291764".
* [B13] P. A. Bhounsule, ``simplestwalker.m`` (25 August 2013), code accompanying "Numerical
  accuracy of two benchmark models of walking: the rimless spoked wheel and the simplest walker",
  DCDIS-B 21:137-148 (2014): stable root at gamma = 0.009
  ``zstar = [0.200310900563820 -0.199832473025474 0.400621801127640 -0.015822999949030]``,
  step time ``t = 3.882``.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pytest

from pasibot_pin.errors import (
    DivergedError,
    NoFixedPointError,
    ParameterError,
    PasibotError,
    SimulationError,
)
from pasibot_pin.studies.methods.decay import decay_rate
from pasibot_pin.studies.methods.poincare import (
    BasinEstimate,
    FixedPoint,
    basin_estimate,
    fd_jacobian,
    find_fixed_point,
    multipliers,
)

pytest.importorskip("scipy")
from pasibot_pin.studies.methods.simplest_walker import FallError, SimplestWalker  # noqa: E402

# [G98] (Garcia's code for the paper), gamma = 0.009, stable long-period gait
G98_THETA = 0.20031090049483
G98_THETA_DOT = -0.19983247291764
G98_MULTIPLIER = complex(-0.19120868949940, 0.55633363687106)
G98_FD_STEP = 1e-5  # see test_garcia_multipliers_computed_the_papers_way
# [B13]
B13_STATE = (0.200310900563820, -0.199832473025474, 0.400621801127640, -0.015822999949030)
B13_PERIOD = 3.882


def sig6(value: float, reference: float) -> bool:
    """``value`` equals ``reference`` to 6 significant digits (relative error < 5e-7)."""
    return abs(value - reference) <= 5e-7 * abs(reference)


@pytest.fixture(scope="module")
def walker() -> SimplestWalker:
    return SimplestWalker(gamma=0.009)


@pytest.fixture(scope="module")
def garcia(walker) -> FixedPoint:
    return find_fixed_point(walker.step, [0.2, -0.2], tol=1e-11)


# --------------------------------------------------------------------------- Garcia et al. 1998
def test_garcia_fixed_point_matches_published(walker, garcia):
    theta, theta_dot = garcia.x
    assert sig6(theta, G98_THETA) and sig6(theta_dot, G98_THETA_DOT)
    assert theta == pytest.approx(G98_THETA, rel=1e-8) and theta_dot == pytest.approx(G98_THETA_DOT, rel=1e-8)
    assert garcia.residual <= 1e-11 and garcia.iterations <= 6
    full = walker.on_section(garcia.x)  # phi = 2 theta, phi' = (1 - cos 2 theta) theta'
    for mine, published in zip(full, B13_STATE):
        assert mine == pytest.approx(published, rel=1e-8)
    assert walker.period(garcia.x) == pytest.approx(B13_PERIOD, abs=5e-4)


def test_garcia_multipliers_computed_the_papers_way(walker, garcia):
    # Garcia's published multipliers are reproduced to 6 significant digits by forward differences
    # with an absolute step of 1e-5 on the reduced map (theta, theta') -- the O(h) bias of that
    # scheme (~1e-3) is in the published digits; central differences remove it (next test).
    lam = multipliers(walker.step, garcia.x, fd_step=G98_FD_STEP, scale=1.0, scheme="forward")
    upper = lam[np.argmax(lam.imag)]
    assert sig6(upper.real, G98_MULTIPLIER.real) and sig6(upper.imag, G98_MULTIPLIER.imag)
    assert np.conj(lam[np.argmin(lam.imag)]) == pytest.approx(upper, abs=1e-12)


def variational_jacobian(walker: SimplestWalker, z: np.ndarray) -> np.ndarray:
    """DF of the reduced map by the variational equations and the saltation matrix (no differencing)."""
    from scipy.integrate import solve_ivp

    gam = walker.gamma

    def rhs(t, big):
        th, dth, ph, _ = big[:4]
        s, c = math.sin(th - gam), math.cos(th - gam)
        a = np.array(
            [
                [0, 1, 0, 0],
                [c, 0, 0, 0],
                [0, 0, 0, 1],
                [c + s * math.sin(ph), 2 * dth * math.sin(ph), math.cos(ph) * (dth**2 - c), 0],
            ]
        )
        return np.concatenate([walker.rhs(t, big[:4]), (a @ big[4:].reshape(4, 4)).ravel()])

    y0 = walker.on_section(z)
    period = walker.period(z)
    sol = solve_ivp(rhs, (0, period), np.concatenate([y0, np.eye(4).ravel()]), method="DOP853", rtol=1e-13, atol=1e-13)
    before, phi_flow = sol.y[:4, -1], sol.y[4:, -1].reshape(4, 4)
    f, grad_h = walker.rhs(0.0, before), np.array([-2.0, 0.0, 1.0, 0.0])  # h = phi - 2 theta
    saltation = np.eye(4) - np.outer(f, grad_h) / (grad_h @ f)
    th, dth = before[:2]
    c, s = math.cos(2 * th), math.sin(2 * th)
    impact_rows = np.array([[-1.0, 0, 0, 0], [-2 * s * dth, c, 0, 0]])  # d(theta+, theta'+)/d(state-)
    embed = np.array([[1, 0], [0, 1], [2, 0], [2 * math.sin(2 * z[0]) * z[1], 1 - math.cos(2 * z[0])]])
    return impact_rows @ saltation @ phi_flow @ embed


def test_garcia_multipliers_accurate(walker, garcia):
    exact = np.sort_complex(np.linalg.eigvals(variational_jacobian(walker, garcia.x)))
    assert np.sort_complex(garcia.multipliers) == pytest.approx(exact, abs=1e-7)
    assert garcia.stable and abs(garcia.dominant) == pytest.approx(0.589113, abs=2e-6)
    assert abs(garcia.dominant.imag) > 0.5  # a complex pair, as published
    # the published pair carries the forward-difference bias: same to 2-3 digits, same verdict
    assert abs(garcia.multipliers[np.argmax(garcia.multipliers.imag)] - G98_MULTIPLIER) < 2e-3
    assert "stable" in repr(garcia) and "0.589113" in repr(garcia)


def test_full_state_map_has_two_trivial_multipliers(walker, garcia):
    # Garcia et al. linearise the map of (theta, theta', phi, phi'): its image is the 2-D heel-strike
    # manifold, so two multipliers are 0 and the other two are the reduced map's.
    lam = multipliers(walker.step_full, walker.on_section(garcia.x), fd_step=1e-6)
    assert np.sort_complex(lam[:2]) == pytest.approx(np.sort_complex(garcia.multipliers), abs=1e-6)
    assert np.all(np.abs(lam[2:]) < 1e-6)


def test_decay_in_direct_simulation_matches_dominant_multiplier(walker, garcia):
    # the map is far from normal (a 1e-3 kick in theta grows 7-fold in the first step) and its
    # dominant pair turns ~1.9 rad per step, so |x_k - x*| oscillates about |lambda|^k: the fit
    # over 30 steps lands within 1 %
    rate = decay_rate(walker.step, garcia.x, [1e-3, 0.0], steps=30, skip=4)
    assert rate == pytest.approx(garcia.spectral_radius, rel=0.015)


def test_walker_basin_along_stance_angle(walker, garcia):
    # the stance angle theta (PASIBOT: the hip pitch) kicked alone: 3 mrad still returns, 10 mrad falls
    basin = basin_estimate(
        walker.step, garcia.x, 0, perturbations=[0.001, 0.003, 0.01], steps=30, tol=1e-4, bisections=3
    )
    assert basin.returned[:3] == (True, True, False) and basin.bracketed
    assert 0.003 <= basin.returning < basin.failing <= 0.003 + 0.007 / 4


def test_walker_falls_with_a_typed_error(walker):
    with pytest.raises(FallError, match="fell|no heel strike"):
        walker.step([0.2, -0.05])  # too slow to vault over the stance leg: falls back
    assert issubclass(FallError, SimulationError)
    with pytest.raises(NoFixedPointError, match="initial guess"):
        find_fixed_point(walker.step, [0.2, -0.05])
    with pytest.raises(ParameterError, match="gamma"):
        SimplestWalker(gamma=float("nan"))


# --------------------------------------------------------------------------- maps with known answers
def rotation_scaling(rho: float, angle: float) -> np.ndarray:
    return rho * np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])


def affine_map(a: np.ndarray, x_star: np.ndarray):
    return lambda x: x_star + a @ (np.asarray(x) - x_star)


def test_linear_map_multipliers_recovered():
    rng = np.random.default_rng(3)
    block = np.zeros((4, 4))
    block[:2, :2] = rotation_scaling(0.7, 1.0)
    block[2, 2], block[3, 3] = -0.95, 0.2
    basis = rng.normal(size=(4, 4))
    a = basis @ block @ np.linalg.inv(basis)  # eigenvalues 0.7 e^{+-i}, -0.95, 0.2
    x_star = np.array([0.3, -1.0, 2.0, 0.5])
    fp = find_fixed_point(affine_map(a, x_star), x_star + [0.2, 0.1, -0.3, 0.05], tol=1e-12)
    assert fp.x == pytest.approx(x_star, abs=1e-12) and fp.iterations <= 2
    expected = [-0.95, 0.7 * np.exp(1j), 0.7 * np.exp(-1j), 0.2]
    assert np.sort_complex(fp.multipliers) == pytest.approx(np.sort_complex(expected), abs=1e-8)
    assert fp.dominant == pytest.approx(-0.95, abs=1e-8) and fp.stable
    assert fd_jacobian(affine_map(a, x_star), x_star) == pytest.approx(a, abs=1e-8)
    unstable = find_fixed_point(affine_map(np.diag([1.5, 0.5]), np.zeros(2)), [0.1, 0.1])
    assert not unstable.stable and unstable.dominant == pytest.approx(1.5)


def test_relax_steps_take_a_deadbeat_map_to_its_fixed_point_before_newton():
    """x <- F(x) first: a deadbeat map (F constant near x*) is solved in one step, so Newton only
    differentiates there (n + 2 calls with forward differences); an unstable map's plain step is
    refused (it raises |F(x) - x|) and Newton finds the same point as without it."""
    x_star = np.array([0.3, -1.0, 2.0])
    deadbeat = find_fixed_point(affine_map(np.zeros((3, 3)), x_star), x_star + 0.1, relax_steps=2, scheme="forward")
    assert deadbeat.iterations == 0 and deadbeat.evaluations == 3 + 2
    assert deadbeat.x == pytest.approx(x_star, abs=1e-12) and np.max(np.abs(deadbeat.multipliers)) < 1e-8
    unstable = affine_map(np.diag([1.5, 0.5, -2.0]), x_star)
    plain = find_fixed_point(unstable, x_star + 0.1, tol=1e-12)
    relaxed = find_fixed_point(unstable, x_star + 0.1, tol=1e-12, relax_steps=3)
    assert relaxed.x == pytest.approx(plain.x, abs=1e-12) and relaxed.evaluations == plain.evaluations + 1
    with pytest.raises(ParameterError, match="relax_steps"):
        find_fixed_point(unstable, x_star, relax_steps=-1)


def jumpy(x):
    """A contraction to 0 (factor 0.5) plus a jitter of 1e-3 far finer than the differences: not smooth."""
    x = np.asarray(x, dtype=float)
    return 0.5 * x + 1e-3 * np.sin(1e7 * x)


def test_stall_ratio_gives_up_on_a_stalling_newton_and_leaves_a_smooth_one_alone():
    """A staircase map makes Newton stall at the size of its jumps: with ``stall_ratio`` it gives up
    at its second iteration, in fewer map calls than the full budget; a smooth map's solve (which
    converges superlinearly) is the same with it and without it."""
    plain, early = counting(jumpy), counting(jumpy)
    for f, ratio in ((plain, None), (early, 0.5)):
        with pytest.raises(NoFixedPointError) as err:
            find_fixed_point(f, [0.3, -0.2], max_iter=6, fd_step=1e-3, scheme="forward", stall_ratio=ratio)
    assert "stalls at iteration 2" in str(err.value)
    assert early.calls < plain.calls
    a = np.array([[0.6, 0.2], [-0.1, 0.4]])
    smooth = [find_fixed_point(cubic, [0.3, 0.2], tol=1e-12, stall_ratio=r) for r in (None, 0.5)]
    assert smooth[0].x == pytest.approx(smooth[1].x, abs=0) and smooth[0].evaluations == smooth[1].evaluations
    linear = find_fixed_point(affine_map(a, np.ones(2)), [0.5, 2.0], tol=1e-12, stall_ratio=0.5)
    assert linear.x == pytest.approx(np.ones(2), abs=1e-10)
    with pytest.raises(ParameterError, match="stall_ratio"):
        find_fixed_point(cubic, [0.3, 0.2], stall_ratio=1.5)


def cubic(x):
    """0.5 x + x^3 per component (first), fixed point 0 with basin |x| < 1/sqrt(2); raises when far."""
    x = np.asarray(x, dtype=float)
    if np.any(np.abs(x) > 10.0):
        raise DivergedError("left the box")
    return np.array([0.5 * x[0] + x[0] ** 3, 0.3 * x[1]])


def test_basin_brackets_the_true_boundary():
    boundary = 1.0 / math.sqrt(2.0)  # the unstable fixed point of 0.5 x + x^3
    basin = basin_estimate(cubic, [0.0, 0.0], 0, perturbations=[0.1, 0.3, 0.5, 0.9, 1.5], steps=200, tol=1e-9)
    assert isinstance(basin, BasinEstimate) and basin.bracketed
    assert basin.returning < boundary <= basin.failing
    assert basin.failing - basin.returning <= 0.4 / 2**12 + 1e-15
    assert basin.tried[:4] == (0.1, 0.3, 0.5, 0.9) and basin.returned[:4] == (True, True, True, False)
    every = basin_estimate(cubic, [0.0, 0.0], 1, perturbations=[0.5, 5.0], steps=100, tol=1e-9)
    assert not every.bracketed and every.returning == 5.0 and every.failing == math.inf
    # x -> x^2: basin |x| < 1; x = 1 is a fixed point itself, so it never returns
    square = basin_estimate(lambda x: np.asarray(x) ** 2, [0.0], 0, perturbations=[0.5, 1.0], steps=50, tol=1e-6)
    assert square.failing == 1.0 and 1.0 - 0.5 / 2**12 <= square.returning < 1.0


def test_decay_rate_of_linear_maps():
    assert decay_rate(affine_map(np.diag([0.8, 0.3]), np.zeros(2)), [0, 0], [1.0, 1.0], 30, skip=5) == pytest.approx(
        0.8, rel=1e-3
    )
    a = rotation_scaling(0.6, 2.0)
    assert decay_rate(affine_map(a, np.ones(2)), [1, 1], [1e-3, 0.0], 20) == pytest.approx(0.6, rel=1e-9)


# --------------------------------------------------------------------------- failures
def counting(step_map):
    """``step_map`` with a call counter (``wrapped.calls``)."""

    def wrapped(x):
        wrapped.calls += 1
        return step_map(x)

    wrapped.calls = 0
    return wrapped


def test_no_fixed_point_is_a_typed_error_quickly():
    start = time.perf_counter()
    shift = counting(lambda x: np.asarray(x) + 1.0)  # F(x) - x = 1 everywhere
    with pytest.raises(NoFixedPointError, match="no progress"):
        find_fixed_point(shift, [0.0, 0.0])
    assert shift.calls <= 1 + 4 + 11  # F(x0), one Jacobian, one failed line search
    square_plus_one = counting(lambda x: np.asarray(x) ** 2 + 1.0)  # x^2 - x + 1 > 0: no real fixed point
    with pytest.raises(NoFixedPointError):
        find_fixed_point(square_plus_one, [3.0], max_iter=50)
    assert square_plus_one.calls <= 50 * (2 + 12) + 3
    wavy = counting(lambda x: np.asarray(x) + 1.0 + 0.5 * np.sin(3 * np.asarray(x)))  # F(x) - x >= 0.5
    with pytest.raises(NoFixedPointError, match="max_evaluations|did not converge|no progress"):
        find_fixed_point(wavy, [0.0], max_iter=7)
    assert wavy.calls <= 7 * (2 + 12) + 3
    capped = counting(lambda x: np.asarray(x) + 1.0 + 0.5 * np.sin(3 * np.asarray(x)))
    with pytest.raises(NoFixedPointError, match="max_evaluations|no progress"):
        find_fixed_point(capped, [0.0], max_evaluations=6)
    assert capped.calls <= 6
    assert time.perf_counter() - start < 1.0
    assert issubclass(NoFixedPointError, SimulationError) and issubclass(NoFixedPointError, PasibotError)


def test_map_failing_inside_the_jacobian():
    def brittle(x):
        x = np.asarray(x, dtype=float)
        if x[1] > 0.5 + 1e-9:
            raise DivergedError("the walker fell")
        return 0.5 * x + 0.25

    # the fixed point is (0.5, 0.5): the +h probe of component 1 fails
    with pytest.raises(NoFixedPointError, match="component 1") as info:
        find_fixed_point(brittle, [0.4, 0.5])
    assert isinstance(info.value.__cause__, DivergedError)
    with pytest.raises(DivergedError, match="differentiating along component 1"):
        fd_jacobian(brittle, [0.5, 0.5])
    with pytest.raises(SimulationError):
        multipliers(brittle, [0.5, 0.5])
    with pytest.raises(NoFixedPointError, match="initial guess"):
        find_fixed_point(brittle, [0.0, 0.9])


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"tol": 0.0}, "tol"),
        ({"tol": -1e-9}, "tol"),
        ({"tol": float("nan")}, "tol"),
        ({"max_iter": 0}, "max_iter"),
        ({"max_iter": -2}, "max_iter"),
        ({"max_iter": 2.5}, "max_iter"),
        ({"fd_step": 0.0}, "fd_step"),
        ({"scale": [1.0, -1.0]}, "scale"),
        ({"max_evaluations": 0}, "max_evaluations"),
    ],
)
def test_bad_parameters_name_the_parameter(kwargs, name):
    with pytest.raises(ParameterError, match=name):
        find_fixed_point(lambda x: 0.5 * np.asarray(x), [0.1, 0.2], **kwargs)


def test_bad_inputs_name_the_parameter():
    half = lambda x: 0.5 * np.asarray(x)  # noqa: E731
    with pytest.raises(ParameterError, match="x0"):
        find_fixed_point(half, [0.1, float("nan")])
    with pytest.raises(ParameterError, match="x0"):
        find_fixed_point(half, [])
    with pytest.raises(ParameterError, match="perturbations"):
        basin_estimate(half, [0.0, 0.0], 0, perturbations=[0.2, 0.1])
    with pytest.raises(ParameterError, match="direction"):
        basin_estimate(half, [0.0, 0.0], 5, perturbations=[0.1])
    with pytest.raises(ParameterError, match="dx"):
        decay_rate(half, [0.0, 0.0], [0.0, 0.0])
    with pytest.raises(ParameterError, match="scheme"):
        fd_jacobian(half, [0.0, 0.0], scheme="backward")
    with pytest.raises(ParameterError, match="3 components"):
        find_fixed_point(lambda x: np.zeros(2), [0.0, 0.0, 0.0])
