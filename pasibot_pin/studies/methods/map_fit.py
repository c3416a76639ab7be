"""A gait's fixed point and multipliers fitted to simulated steps, where the step map is not smooth.

Newton shooting (:func:`~pasibot_pin.studies.methods.poincare.find_fixed_point`) needs a step map
that is smooth at the scale of its finite differences. A time-stepped floor is not always: when a
rocking foot's heel or toe lands, the step in which it lands splits the impact's impulse between
two time steps, so the map jumps by a small amount (of the order of the time step's share of the
impact) each time a landing moves from one time step to the next. Newton then stalls at the
size of those jumps, and iterating the map does not settle either: the state wanders in a small
cloud around the gait, kicked by the jumps and pulled back by the gait's own contraction.

There the gait is identified the way one identifies a walker from its log of steps: iterate the map
``x_{k+1} = F(x_k)`` a number of steps and fit the affine map ``x_{k+1} = c + A x_k`` to the pairs by
least squares (:func:`fit_fixed_point`). The jumps act on the state like process noise, for which
the least-squares fit of ``A`` is consistent; ``A``'s eigenvalues are the multipliers of the
averaged map, the fixed point of the fit ``x* = (I - A)^-1 c`` is the centre of the cloud, and the
fit's residual (the part of each step that no linear map explains) measures the jumps. The
dominant multiplier is fitted twice more, on the first and the second half of the pairs, and the
two values give its spread.

Units: the state's own units throughout.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from pasibot_pin.errors import NoFixedPointError, ParameterError, SimulationError
from pasibot_pin.studies.methods.poincare import FixedPoint, StepMap

__all__ = ["FittedFixedPoint", "fit_affine_map", "fit_fixed_point"]

MIN_PAIRS_PER_UNKNOWN = 3
"""The fit needs at least this many step pairs per unknown of a row (``n + 1``): each half at least 1.5 [-]."""


@dataclass(frozen=True, repr=False)
class FittedFixedPoint(FixedPoint):
    """A :class:`~pasibot_pin.studies.methods.poincare.FixedPoint` fitted to iterates of the map.

    Attributes (besides the fixed point's):
        jitter: RMS of the fit's residual per component: how far one step lands from the averaged
            map (state units).
        spread: (lowest, highest) ``|dominant multiplier|`` of the fits to each half of the pairs [-].
        iterates: the simulated states ``x_0 .. x_N`` (N + 1, n).

    ``residual`` is ``max_i |F(x*)_i - x*_i|`` of the averaged map, i.e. 0 to round-off; ``iterations`` is 0.

    """

    jitter: np.ndarray | None = None
    spread: tuple[float, float] = (float("nan"), float("nan"))
    iterates: np.ndarray | None = None

    @property
    def cloud(self) -> float:
        """Largest distance of an iterate of the second half from ``x*`` (Euclidean, state units)."""
        assert self.iterates is not None
        half = self.iterates[len(self.iterates) // 2 :]
        return float(np.max(np.linalg.norm(half - self.x, axis=1)))


def fit_affine_map(before: np.ndarray, after: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Least-squares ``after_k = c + A before_k``: (c, A, the residuals (N, n)).

    Args:
        before: states x_k (N, n).
        after: their images F(x_k) (N, n).

    Raises:
        ParameterError: fewer than ``n + 1`` pairs, or shapes that differ.

    """
    before, after = np.atleast_2d(before), np.atleast_2d(after)
    count, n = before.shape
    if after.shape != before.shape or count < n + 1:
        raise ParameterError(f"the fit needs at least {n + 1} pairs of states of one shape, got {count}")
    mean = before.mean(axis=0)
    design = np.hstack((np.ones((count, 1)), before - mean))
    coef = np.linalg.lstsq(design, after, rcond=None)[0]
    jac = coef[1:].T
    return coef[0] - jac @ mean, jac, after - design @ coef


def _dominant(jac: np.ndarray) -> float:
    """``|dominant eigenvalue|`` of ``jac`` [-]."""
    return float(np.max(np.abs(np.linalg.eigvals(jac))))


def fit_fixed_point(
    step_map: StepMap,
    x0: Sequence[float] | np.ndarray,
    steps: int = 30,
    kick: Sequence[float] | np.ndarray | None = None,
) -> FittedFixedPoint:
    """Iterate ``F`` from ``x0 + kick`` for ``steps`` steps and fit the averaged map (module docstring).

    Args:
        step_map: the map ``F``; may raise :class:`~pasibot_pin.errors.SimulationError` (the walker falls).
        x0: a state near the gait (state units).
        steps: map evaluations, at least ``MIN_PAIRS_PER_UNKNOWN (n + 1)`` [-].
        kick: added to ``x0`` before the first step, to excite the gait's slow modes well above the
            jumps (state units); default none.

    Returns:
        The :class:`FittedFixedPoint`: ``x*``, ``A`` and its eigenvalues sorted by modulus, the jitter
        and the dominant multiplier's spread over the two halves.

    Raises:
        NoFixedPointError: the map failed during the iteration (the walk fell), or ``I - A`` is singular.
        ParameterError: too few steps for the state's size, a non-finite ``x0``.

    """
    x = np.array(x0, dtype=float).reshape(-1)
    n = x.size
    if not np.all(np.isfinite(x)):
        raise ParameterError(f"x0 must be finite, got {x}")
    least = MIN_PAIRS_PER_UNKNOWN * (n + 1)
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or not least <= steps <= 10_000:
        raise ParameterError(f"parameter 'fit_steps' must be an integer in [{least}, 10000], got {steps!r}")
    if kick is not None:
        x = x + np.asarray(kick, dtype=float).reshape(n)
    states = [x]
    try:
        for _ in range(int(steps)):
            states.append(np.asarray(step_map(states[-1]), dtype=float).reshape(n))
    except SimulationError as err:
        raise NoFixedPointError(f"the iterated step map failed after {len(states) - 1} steps: {err}") from err
    iterates = np.array(states)
    c, jac, residual = fit_affine_map(iterates[:-1], iterates[1:])
    try:
        x_star = np.linalg.solve(np.eye(n) - jac, c)
    except np.linalg.LinAlgError as err:
        raise NoFixedPointError("the fitted step map has a multiplier 1: no isolated fixed point") from err
    half = len(iterates) // 2
    spread = sorted(
        _dominant(fit_affine_map(part[:-1], part[1:])[1]) for part in (iterates[: half + 1], iterates[half:])
    )
    lam = np.linalg.eigvals(jac)
    lam = lam[np.argsort(-np.abs(lam), kind="stable")]
    gap = float(np.max(np.abs(c + jac @ x_star - x_star)))
    jitter = np.sqrt(np.mean(residual**2, axis=0))
    return FittedFixedPoint(x_star, gap, 0, int(steps), jac, lam, jitter, (spread[0], spread[1]), iterates)
