"""Gait stability by shooting on a Poincaré (step-to-step) map.

A periodic gait is a fixed point ``x*`` of its step map ``F``: the state on a section (e.g. just
after heel strike) mapped to the state on the same section one step later. These tools are
engine-agnostic: ``F`` is any callable ``R^n -> R^n`` (a simple model, the floor simulator, a
hardware log fitted to a map). It may raise a :class:`~pasibot_pin.errors.SimulationError`
subclass when the step fails (the walker falls); the tools turn that into an outcome or a typed
error, never a numpy traceback.

* :func:`find_fixed_point`: Newton on ``G(x) = F(x) - x`` with a central-difference Jacobian and a
  backtracking line search, bounded in iterations and map calls; it returns the fixed point with
  the Jacobian ``DF(x*)`` (the linearised return map, the monodromy matrix restricted to the
  section) and its eigenvalues, the Floquet multipliers. The gait is locally (orbitally) stable
  when every multiplier has modulus < 1.
* :func:`multipliers`: the multipliers at a given point alone.
* :func:`basin_estimate`: the largest perturbation along one direction from which the iterated
  map still returns to ``x*``, bracketed by bisection.
* :func:`~pasibot_pin.studies.methods.decay.decay_rate`: the per-step decay factor of a perturbation in
  direct iteration, to be compared with ``|λ_dominant|``.

Units: the state's own units throughout (for a walker: rad and rad/s or their scaled forms);
``tol``, perturbations and ``fd_step * scale`` are in those units per component.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from pasibot_pin.errors import DivergedError, NoFixedPointError, ParameterError, SimulationError

__all__ = [
    "BasinEstimate",
    "FixedPoint",
    "StepMap",
    "basin_estimate",
    "fd_jacobian",
    "find_fixed_point",
    "multipliers",
]

StepMap = Callable[[np.ndarray], np.ndarray]
"""A step (return) map: the state on the section -> the state one section later (same shape)."""

Scheme = Literal["central", "forward"]
"""Finite-difference scheme of the Jacobian."""

ARMIJO: float = 1e-4
"""Sufficient decrease of the line search: accept ``|G(x + a dx)| <= (1 - ARMIJO a) |G(x)|``."""

MIN_STEP: float = 1.0 / 1024.0
"""Smallest line-search fraction ``a`` before Newton gives up (10 halvings)."""


# --------------------------------------------------------------------------- validation
def _state(x: Sequence[float] | np.ndarray, name: str) -> np.ndarray:
    """``x`` as a finite 1-D float array, or :class:`ParameterError` naming ``name``."""
    try:
        arr = np.array(x, dtype=float).reshape(-1)
    except (TypeError, ValueError) as err:
        raise ParameterError(f"{name} must be a vector of numbers, got {x!r}") from err
    if arr.size == 0:
        raise ParameterError(f"{name} must have at least one component")
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name} must be finite, got {arr}")
    return arr


def _positive(value: float, name: str) -> float:
    """``value`` as a float > 0 (finite), or :class:`ParameterError` naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise ParameterError(f"{name} must be a positive number, got {value!r}")
    if not (math.isfinite(value) and value > 0):
        raise ParameterError(f"{name} must be finite and > 0, got {value!r}")
    return float(value)


def _count(value: int, name: str) -> int:
    """``value`` as an int >= 1, or :class:`ParameterError` naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ParameterError(f"{name} must be an integer >= 1, got {value!r}")
    return int(value)


def _steps(x: np.ndarray, fd_step: float, scale: Sequence[float] | np.ndarray | float | None) -> np.ndarray:
    """Per-component finite-difference steps ``fd_step * s_i``, ``s_i = scale_i`` or ``max(|x_i|, 1)``."""
    fd_step = _positive(fd_step, "fd_step")
    if scale is None:
        return fd_step * np.maximum(np.abs(x), 1.0)
    s = np.broadcast_to(np.asarray(scale, dtype=float), x.shape) if np.ndim(scale) == 0 else np.asarray(scale, float)
    if s.shape != x.shape or not np.all(np.isfinite(s)) or np.any(s <= 0):
        raise ParameterError(f"scale must be positive and finite, one per state component ({x.size}), got {scale!r}")
    return fd_step * s


# --------------------------------------------------------------------------- map calls
class _Counted:
    """The step map with a call counter, a budget and output checks."""

    def __init__(self, step_map: StepMap, n: int, budget: int | None = None) -> None:
        self.step_map, self.n, self.budget, self.calls = step_map, n, budget, 0

    def __call__(self, x: np.ndarray) -> np.ndarray:
        if self.budget is not None and self.calls >= self.budget:
            raise NoFixedPointError(f"the step map was called {self.calls} times (max_evaluations) without convergence")
        self.calls += 1
        y = np.asarray(self.step_map(np.array(x, dtype=float)), dtype=float).reshape(-1)
        if y.shape != (self.n,):
            raise ParameterError(f"step_map must return {self.n} components, returned {y.size}")
        if not np.all(np.isfinite(y)):
            raise DivergedError(f"the step map returned a non-finite state {y} from {x}")
        return y


def fd_jacobian(
    step_map: StepMap,
    x: Sequence[float] | np.ndarray,
    *,
    fd_step: float = 1e-6,
    scale: Sequence[float] | np.ndarray | float | None = None,
    scheme: Scheme = "central",
) -> np.ndarray:
    """Finite-difference Jacobian ``DF(x)`` of a step map.

    Central differences (``2 n`` map calls, error ``O(h^2)``) by default; ``scheme="forward"``
    (``n + 1`` calls, error ``O(h)``) reproduces results computed that way (e.g. Garcia et al.'s
    published multipliers, see :mod:`pasibot_pin.studies.methods.simplest_walker`).

    Args:
        step_map: the map ``F``.
        x: the point (state units).
        fd_step: relative step: component ``i`` moves by ``± fd_step * s_i`` [-].
        scale: typical magnitude of each component ``s_i`` (state units); default ``max(|x_i|, 1)``.
        scheme: ``"central"`` or ``"forward"``.

    Returns:
        The ``(n, n)`` matrix ``dF_i/dx_j`` [-, in the state's units ratio].

    Raises:
        SimulationError: the map failed (e.g. the walker fell) at a perturbed point; the message
            names the component and the point.
        ParameterError: bad ``x``, ``fd_step`` or ``scale``.

    """
    x = _state(x, "x")
    if scheme not in ("central", "forward"):
        raise ParameterError(f"scheme must be 'central' or 'forward', got {scheme!r}")
    return _jacobian(_Counted(step_map, x.size), x, _steps(x, fd_step, scale), scheme)


def _jacobian(
    f: _Counted, x: np.ndarray, h: np.ndarray, scheme: Scheme = "central", fx: np.ndarray | None = None
) -> np.ndarray:
    """Finite differences of ``f`` at ``x`` with steps ``h`` (a failure names the component).

    ``fx``: ``f(x)`` when already known (the forward scheme's base point is not evaluated again).
    """
    jac = np.empty((x.size, x.size))
    base = None
    if scheme == "forward":
        base = _differentiating(f, x, None, h) if fx is None else fx
    for j in range(x.size):
        e = np.zeros(x.size)
        e[j] = h[j]
        if base is None:
            jac[:, j] = (_differentiating(f, x + e, j, h) - _differentiating(f, x - e, j, h)) / (2.0 * h[j])
        else:
            jac[:, j] = (_differentiating(f, x + e, j, h) - base) / h[j]
    return jac


def _differentiating(f: _Counted, x: np.ndarray, j: int | None, h: np.ndarray) -> np.ndarray:
    """``f(x)`` while differentiating along component ``j``; a failure says where."""
    try:
        return f(x)
    except NoFixedPointError:
        raise
    except SimulationError as err:
        where = "at the base point" if j is None else f"along component {j} (step {h[j]:.3g})"
        raise _renamed(err, f"the step map failed while differentiating {where}, at x = {x}: {err}") from err


def _renamed(err: SimulationError, message: str) -> SimulationError:
    """An error of ``err``'s kind with ``message`` (the base kind if that one takes other arguments)."""
    try:
        return type(err)(message)
    except TypeError:
        return SimulationError(message)


def _eigen(jac: np.ndarray) -> np.ndarray:
    """Eigenvalues sorted by modulus, descending (ties: by real part, descending, then imaginary)."""
    lam = np.linalg.eigvals(jac).astype(complex)
    order = np.lexsort((-lam.imag, -lam.real, -np.round(np.abs(lam), 12)))
    return lam[order]


def multipliers(
    step_map: StepMap,
    x: Sequence[float] | np.ndarray,
    *,
    fd_step: float = 1e-6,
    scale: Sequence[float] | np.ndarray | float | None = None,
    scheme: Scheme = "central",
) -> np.ndarray:
    """Floquet multipliers at ``x``: eigenvalues of the finite-difference ``DF(x)``, by modulus, descending.

    Args:
        step_map: the map ``F``.
        x: the point, normally a fixed point (state units).
        fd_step: relative finite-difference step [-].
        scale: typical magnitude of each component (state units); default ``max(|x_i|, 1)``.
        scheme: ``"central"`` (default) or ``"forward"`` differences.

    Returns:
        Complex array of the ``n`` multipliers [-].

    Raises:
        SimulationError: the map failed at a perturbed point.
        ParameterError: bad arguments.

    """
    return _eigen(fd_jacobian(step_map, x, fd_step=fd_step, scale=scale, scheme=scheme))


# --------------------------------------------------------------------------- fixed point
@dataclass(frozen=True, repr=False)
class FixedPoint:
    """A fixed point ``x* = F(x*)`` of a step map and its linear stability.

    Attributes:
        x: the fixed point (state units).
        residual: ``max_i |F(x*)_i - x*_i|`` (state units).
        iterations: Newton iterations taken.
        evaluations: step-map calls, the final Jacobian's included.
        jacobian: ``DF(x*)``, the linearised return map (monodromy on the section) [-].
        multipliers: eigenvalues of ``jacobian`` sorted by modulus, descending [-].

    """

    x: np.ndarray
    residual: float
    iterations: int
    evaluations: int
    jacobian: np.ndarray
    multipliers: np.ndarray

    @property
    def dominant(self) -> complex:
        """The multiplier of largest modulus [-]."""
        return complex(self.multipliers[0])

    @property
    def spectral_radius(self) -> float:
        """``|dominant|``: the asymptotic per-step contraction (< 1: stable) [-]."""
        return float(abs(self.multipliers[0]))

    @property
    def stable(self) -> bool:
        """Every multiplier strictly inside the unit circle."""
        return bool(np.all(np.abs(self.multipliers) < 1.0))

    def __repr__(self) -> str:
        x = ", ".join(f"{v:.8g}" for v in self.x)
        lam = ", ".join(_fmt(v) for v in self.multipliers)
        verdict = "stable" if self.stable else "unstable"
        return (
            f"FixedPoint(x=[{x}], residual={self.residual:.2e}, {verdict}, |lambda|max={self.spectral_radius:.6g}, "
            f"multipliers=[{lam}], iterations={self.iterations}, evaluations={self.evaluations})"
        )


def _fmt(z: complex) -> str:
    """A multiplier, short: ``0.5`` or ``-0.19+0.56j``."""
    z = complex(z)
    return f"{z.real:.6g}" if abs(z.imag) < 1e-12 else f"{z.real:.6g}{z.imag:+.6g}j"


def find_fixed_point(
    step_map: StepMap,
    x0: Sequence[float] | np.ndarray,
    *,
    tol: float = 1e-10,
    max_iter: int = 30,
    fd_step: float = 1e-6,
    scale: Sequence[float] | np.ndarray | float | None = None,
    max_evaluations: int | None = None,
    scheme: Scheme = "central",
    relax_steps: int = 0,
    stall_ratio: float | None = None,
) -> FixedPoint:
    """Newton-shoot a fixed point of ``F`` from ``x0``, then linearise there.

    Each iteration solves ``(DF - I) dx = -(F(x) - x)`` (least squares, so a singular ``DF - I``
    gives the minimum-norm step) with ``DF`` by central differences (``2 n`` calls), then
    backtracks ``x + a dx``, ``a = 1, 1/2, ...`` until ``|G|`` decreases enough (a point where the
    map fails counts as no decrease). The cost is bounded: at most ``max_iter`` iterations and
    ``max_evaluations`` map calls.

    Args:
        step_map: the map ``F``; may raise :class:`~pasibot_pin.errors.SimulationError`.
        x0: the initial guess (state units).
        tol: convergence when ``max_i |F(x)_i - x_i| <= tol`` (state units).
        max_iter: most Newton iterations.
        fd_step: relative finite-difference step [-] (component ``i`` moves by ``fd_step * s_i``).
        scale: typical magnitude ``s_i`` of each component (state units); default ``max(|x_i|, 1)``.
        max_evaluations: most map calls; default ``max_iter * (2 n + 12) + 2 n + 1``.
        scheme: the Jacobian's differences, ``"central"`` or ``"forward"`` (``n + 1`` calls instead
            of ``2 n``: for an expensive map whose multipliers are needed to a few digits only).
        relax_steps: at most this many plain iterations ``x <- F(x)`` before Newton, each kept only
            if it lowers ``|F(x) - x|`` (a stable gait's next section is a better guess than its
            last: a deadbeat one is the fixed point itself, and Newton then differentiates once).
        stall_ratio: give up (:class:`~pasibot_pin.errors.NoFixedPointError`) as soon as a Newton
            iteration after the first leaves ``|F(x) - x|`` above this fraction of its value before
            [-] (``None``: never): a smooth map converges superlinearly, so a stalling residual
            says the map is not smooth at the differences' scale and more iterations only cost.

    Returns:
        The :class:`FixedPoint`, with ``DF(x*)`` and its multipliers. When the last Newton step
        moved every component by less than its difference step, the last iteration's ``DF`` is
        kept (differentiating again at ``x*`` would change it by less than the differences' own
        error); the forward scheme reuses the known ``F(x)`` as its base point.

    Raises:
        NoFixedPointError: no convergence within the budget, a stalled line search, or the map
            failed at ``x0`` or while differentiating.
        ParameterError: ``tol`` or ``fd_step`` <= 0, ``max_iter`` < 1, a non-finite ``x0``, bad ``scale``.

    """
    x = _state(x0, "x0")
    tol = _positive(tol, "tol")
    max_iter = _count(max_iter, "max_iter")
    if isinstance(relax_steps, bool) or not isinstance(relax_steps, int) or not 0 <= relax_steps <= 100:
        raise ParameterError(f"relax_steps must be an integer in [0, 100], got {relax_steps!r}")
    n = x.size
    if max_evaluations is None:
        budget = max_iter * (2 * n + 12) + 2 * n + 1
    else:
        budget = _count(max_evaluations, "max_evaluations")
    if scheme not in ("central", "forward"):
        raise ParameterError(f"scheme must be 'central' or 'forward', got {scheme!r}")
    if stall_ratio is not None and not (isinstance(stall_ratio, float) and 0.0 < stall_ratio < 1.0):
        raise ParameterError(f"stall_ratio must be None or a number in (0, 1), got {stall_ratio!r}")
    f = _Counted(step_map, n, budget)
    h = _steps(x, fd_step, scale)
    try:
        x, g, iterations, jac = _newton(f, x, h, tol, max_iter, scheme, relax_steps, stall_ratio)
        if jac is None:
            jac = _jacobian(f, x, h, scheme, fx=g + x)
    except NoFixedPointError:
        raise
    except SimulationError as err:
        raise NoFixedPointError(f"no fixed point: {err}") from err
    return FixedPoint(x, float(np.max(np.abs(g))), iterations, f.calls, jac, _eigen(jac))


def _newton(
    f: _Counted,
    x: np.ndarray,
    h: np.ndarray,
    tol: float,
    max_iter: int,
    scheme: Scheme = "central",
    relax_steps: int = 0,
    stall_ratio: float | None = None,
) -> tuple[np.ndarray, np.ndarray, int, np.ndarray | None]:
    """The damped Newton loop: ``(x*, G(x*), iterations, DF)`` or :class:`NoFixedPointError`.

    ``DF``: the last iteration's Jacobian if its step moved each component less than its difference
    step ``h`` (a new one at ``x*`` would differ by less than their error), else ``None``.
    """
    try:
        g = f(x) - x
    except SimulationError as err:
        raise NoFixedPointError(f"the step map fails at the initial guess x0 = {x}: {err}") from err
    for _ in range(relax_steps):  # x <- F(x) while it helps
        if np.max(np.abs(g)) <= tol:
            break
        x_next = x + g
        try:
            g_next = f(x_next) - x_next
        except NoFixedPointError:
            raise
        except SimulationError:
            break
        if np.linalg.norm(g_next) >= np.linalg.norm(g):
            break
        x, g = x_next, g_next
    jac = None
    for iteration in range(max_iter + 1):
        norm = float(np.linalg.norm(g))
        if np.max(np.abs(g)) <= tol:
            return x, g, iteration, jac
        if iteration == max_iter:
            break
        jac = _jacobian(f, x, h, scheme, fx=g + x)
        dx = np.linalg.lstsq(jac - np.eye(x.size), -g, rcond=None)[0]
        x_new, g = _line_search(f, x, g, dx, norm)
        if not np.all(np.abs(x_new - x) < h):
            jac = None
        x = x_new
        stalled = stall_ratio is not None and iteration >= 1 and np.linalg.norm(g) > stall_ratio * norm
        if stalled and np.max(np.abs(g)) > tol:
            raise NoFixedPointError(
                f"Newton stalls at iteration {iteration + 1}: |F(x) - x| = {np.max(np.abs(g)):.3g} > tol {tol:g}"
                f" (|G| {norm:.3g} -> {np.linalg.norm(g):.3g}) at x = {x}: the map is not smooth there"
            )
    raise NoFixedPointError(
        f"Newton did not converge in {max_iter} iterations: "
        f"|F(x) - x| = {np.max(np.abs(g)):.3g} > tol {tol:g} at x = {x}"
    )


def _line_search(
    f: _Counted, x: np.ndarray, g: np.ndarray, dx: np.ndarray, norm: float
) -> tuple[np.ndarray, np.ndarray]:
    """Backtrack along ``dx`` to a sufficient decrease of ``|G|``, or :class:`NoFixedPointError`."""
    a = 1.0
    while a >= MIN_STEP:
        trial = x + a * dx
        try:
            g_trial = f(trial) - trial
        except NoFixedPointError:
            raise
        except SimulationError:
            a *= 0.5
            continue
        if np.linalg.norm(g_trial) <= (1.0 - ARMIJO * a) * norm:
            return trial, g_trial
        a *= 0.5
    raise NoFixedPointError(
        f"the Newton step makes no progress at x = {x} (|F(x) - x| = {np.max(np.abs(g)):.3g}): "
        "no fixed point near, or the map is not smooth there"
    )


# --------------------------------------------------------------------------- basin
@dataclass(frozen=True)
class BasinEstimate:
    """How far along one direction a perturbation of ``x*`` still returns to the gait.

    Attributes:
        direction: the unit direction of the perturbations (state space).
        returning: largest perturbation amplitude found to return (0 if none did) (state units).
        failing: smallest amplitude found not to return (fell, diverged or still away after
            ``steps`` steps); ``inf`` if every tried amplitude returned (state units).
        tried: every amplitude tried, in order (state units).
        returned: whether each tried amplitude returned.

    """

    direction: np.ndarray
    returning: float
    failing: float
    tried: tuple[float, ...]
    returned: tuple[bool, ...]

    @property
    def bracketed(self) -> bool:
        """The boundary lies in ``(returning, failing]`` (a failing amplitude was found)."""
        return math.isfinite(self.failing)


def _direction(direction: int | Sequence[float] | np.ndarray, n: int) -> np.ndarray:
    """A unit vector: ``e_i`` for an index ``i``, else the given vector normalised."""
    if isinstance(direction, (int, np.integer)) and not isinstance(direction, bool):
        if not -n <= direction < n:
            raise ParameterError(f"direction index {direction} is out of range for a state of {n} components")
        e = np.zeros(n)
        e[direction] = 1.0
        return e
    d = _state(np.asarray(direction, dtype=float), "direction")
    if d.size != n or np.linalg.norm(d) == 0:
        raise ParameterError(f"direction must be an index or a non-zero vector of {n} components, got {direction!r}")
    return d / np.linalg.norm(d)


def _returns(f: _Counted, x_star: np.ndarray, x: np.ndarray, steps: int, tol: float) -> bool:
    """Whether iterating from ``x`` comes within ``tol`` of ``x*`` in ``steps`` steps (a failure: no)."""
    try:
        for _ in range(steps):
            x = f(x)
            if np.linalg.norm(x - x_star) < tol:
                return True
    except SimulationError:
        return False
    return False


def basin_estimate(
    step_map: StepMap,
    x_star: Sequence[float] | np.ndarray,
    direction: int | Sequence[float] | np.ndarray,
    *,
    perturbations: Sequence[float],
    steps: int = 50,
    tol: float = 1e-6,
    bisections: int = 12,
) -> BasinEstimate:
    """The largest perturbation of ``x*`` along ``direction`` that the iterated map brings back.

    The amplitudes are tried in increasing order until one fails; the boundary is then bisected
    ``bisections`` times between the last returning and the first failing amplitude. A start
    returns when ``|F^k(x) - x*| < tol`` for some ``k <= steps``; it fails if the map raises a
    :class:`~pasibot_pin.errors.SimulationError` (the walker falls), diverges, or is still away
    after ``steps`` steps. For PASIBOT the direction is the hip pitch's index. The result is the
    first boundary along the ray: a walker's basin need not be an interval (it can be fractal), so
    an amplitude beyond ``failing`` may return again; a perturbation of the other sign is another
    ray (pass ``-e_i`` as ``direction``).

    Args:
        step_map: the map ``F``.
        x_star: the fixed point (state units).
        direction: a component index (perturb ``x*_i``) or a vector (normalised here).
        perturbations: amplitudes to try, positive and strictly increasing (state units).
        steps: most steps iterated per start.
        tol: return radius, Euclidean (state units).
        bisections: bisection steps between the bracket's ends.

    Returns:
        The :class:`BasinEstimate`: the bracket and every amplitude tried.

    Raises:
        ParameterError: bad arguments (non-increasing perturbations, an out-of-range index...).

    """
    x_star = _state(x_star, "x_star")
    d = _direction(direction, x_star.size)
    amps = np.array([_positive(p, "perturbations") for p in perturbations]) if len(perturbations) else np.array([])
    if amps.size == 0 or np.any(np.diff(amps) <= 0):
        raise ParameterError(
            f"perturbations must be a non-empty, strictly increasing list of amplitudes > 0, got {perturbations!r}"
        )
    steps, tol = _count(steps, "steps"), _positive(tol, "tol")
    bisections = 0 if bisections == 0 else _count(bisections, "bisections")
    f = _Counted(step_map, x_star.size)
    tried: list[float] = []
    returned: list[bool] = []

    def probe(p: float) -> bool:
        ok = _returns(f, x_star, x_star + p * d, steps, tol)
        tried.append(float(p))
        returned.append(ok)
        return ok

    good, bad = 0.0, math.inf
    for p in amps:
        if not probe(p):
            bad = float(p)
            break
        good = float(p)
    for _ in range(bisections if math.isfinite(bad) else 0):
        mid = 0.5 * (good + bad)
        if probe(mid):
            good = mid
        else:
            bad = mid
    return BasinEstimate(d, good, bad, tuple(tried), tuple(returned))
