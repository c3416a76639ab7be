"""The per-step decay of a perturbation in direct iteration of a step map, to check a multiplier against.

Units: the state's own units throughout.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from pasibot_pin.errors import ParameterError
from pasibot_pin.studies.methods.poincare import StepMap, _count, _Counted, _state

__all__ = ["decay_rate"]


def decay_rate(
    step_map: StepMap,
    x_star: Sequence[float] | np.ndarray,
    dx: Sequence[float] | np.ndarray,
    steps: int = 20,
    *,
    skip: int = 0,
) -> float:
    """Per-step decay factor of a perturbation in direct iteration (compare with ``|λ_dominant|``).

    Iterates ``x_k = F^k(x* + dx)`` and fits ``log |x_k - x*| = a + k log r`` by least squares over
    ``k = skip .. steps``; returns ``r``. For a complex dominant pair the norm oscillates about the
    envelope ``|λ|^k`` and the fit averages it out over several turns (the error falls like
    ``1/steps``: for a far-from-normal map expect a few per cent at 20-30 steps). Pick ``|dx|`` small enough to
    stay linear and large enough that ``|dx| r^steps`` stays above the map's numerical noise.

    Args:
        step_map: the map ``F``.
        x_star: the fixed point (state units).
        dx: the initial perturbation (state units), non-zero.
        steps: steps iterated (>= 2).
        skip: leading steps left out of the fit (transients of the faster modes).

    Returns:
        The fitted factor ``r`` [-] (< 1: the perturbation decays).

    Raises:
        SimulationError: the map failed during the iteration (the perturbation was too large).
        ParameterError: bad arguments.

    """
    x_star = _state(x_star, "x_star")
    dx = _state(dx, "dx")
    if dx.shape != x_star.shape or not np.any(dx):
        raise ParameterError(f"dx must be a non-zero vector of {x_star.size} components, got {dx}")
    steps = _count(steps, "steps")
    if steps < 2 or isinstance(skip, bool) or not isinstance(skip, (int, np.integer)) or not 0 <= skip <= steps - 2:
        raise ParameterError(f"need steps >= 2 and 0 <= skip <= steps - 2, got steps={steps}, skip={skip!r}")
    f = _Counted(step_map, x_star.size)
    x = x_star + dx
    norms = [float(np.linalg.norm(dx))]
    for _ in range(steps):
        x = f(x)
        norms.append(float(np.linalg.norm(x - x_star)))
    k = np.arange(steps + 1)[skip:]
    logs = np.log(np.maximum(np.array(norms[skip:]), np.finfo(float).tiny))
    slope = np.polyfit(k, logs, 1)[0]
    return float(math.exp(slope))
