"""The contact QP on a few free motions with many cone rows, exactly: a least-distance problem solved by NNLS.

The 3-D floor's step leaves, once the loops and cranks are eliminated (:func:`floating_qp`),

    min_x  1/2 x^T H x + g^T x   s.t.   C x >= l

on the hip's six freedoms (and a free ankle's), with four pyramid rows at each sole corner: 32
rows on six unknowns, most of them redundant when a foot is flat. With H = L L^T and u = L^T x
the QP is the projection of u_0 = -L^-1 g onto the polyhedron G u >= l (G = C L^-T): with
w = u - u_0, the least-distance program

    min ||w||   s.t.   G w >= d,   d = l - G u_0.

Lawson and Hanson (*Solving Least Squares Problems*, 1974, ch. 23) solve it through one
non-negative least squares problem: with E = [G^T; d^T] ((n+1) x k) and f = (0, ..., 0, 1),
v = argmin_{v >= 0} ||E v - f|| and r = E v - f give w = -r_{1:n} / r_{n+1} and the row
multipliers v / (-r_{n+1}) >= 0 (w = G^T z). SciPy's ``nnls`` (an active-set method) finds the
active rows exactly, where an interior-point or ADMM solver stops at its tolerance: the step map
is then smooth to round-off, which the Floquet multipliers' finite differences need.

The motion u is unique; the impulses z are not when rows are redundant. Of those that give it,
the least-norm one on the touching rows is taken when it is >= 0 (each cone edge an equal stiff
spring, as :func:`~pasibot_pin.dynamics.floor.qp.free_qp` does: Menabrea's least work), else
NNLS's own (a vertex of the set).

Units: as the caller's.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from pasibot_pin.dynamics.floor.qp import SIGN_TOL, TOUCH_TOL, reduced_qp

GRAM_TOL = 1e-12
"""Largest relative residual of the least-norm split through the rows' Gram matrix before the SVD is asked [-]."""
FEASIBLE_TOL = 1e-9
"""Largest violation of a cone row by the NNLS answer, relative to the row's scale, before proxsuite is asked [-]."""

# a vector's max and min (NaN if any) by the ufuncs themselves, without the array methods' Python wrapping
_largest, _smallest = np.maximum.reduce, np.minimum.reduce
_SCIPY: dict[str, Callable] = {}
"""SciPy's routines by name, once imported (:func:`_scipy`)."""


def ldp_free_qp(
    hessian: np.ndarray, g: np.ndarray, c_in: np.ndarray, lower: np.ndarray
) -> tuple[np.ndarray, np.ndarray] | None:
    """The QP min 1/2 x^T H x + g^T x s.t. C x >= l, exactly, by a least-distance NNLS (module docstring).

    Args:
        hessian: H (n, n), symmetric positive definite.
        g: linear term (n,).
        c_in: the cone rows C (k, n).
        lower: l (k,).

    Returns:
        (x, z) with H x + g = C^T z, z >= 0, C x >= l; ``None`` when H is not positive definite
        or NNLS does not give a feasible answer (left to proxsuite).

    """
    n = len(g)
    to_u = cholesky_inverse(hessian)  # L^-1: u = L^T x
    if to_u is None:
        return None
    u_0 = -to_u.dot(g)
    rows = c_in.dot(to_u.T)  # G = C L^-T (k, n)
    e = np.empty((n + 1, len(lower)))  # NNLS's E = [G^T; d^T]
    e[:n] = rows.T
    need = np.subtract(lower, rows.dot(u_0), out=e[n])  # d
    high, low = float(_largest(need)), float(_smallest(need))
    scale = 1.0 + max(high, -low)  # 1 + max |d|
    if high <= 0.0:  # u_0 meets every row: no impulse
        w, z = np.zeros(n), np.zeros(len(lower))
    else:
        f = np.zeros(n + 1)
        f[n] = 1.0
        try:
            v, _ = _scipy("optimize", "nnls")(e, f)
        except RuntimeError:  # NNLS's iteration limit
            return None
        r = e.dot(v) - f
        last = float(r[n])
        if not -last > 0.0:  # an infeasible program (cannot happen on a floor: moving up meets every row)
            return None
        w, z = r[:n] / -last, v / -last  # -r / r_n: the same rounding
    slack = rows.dot(w) - need
    if not (all(map(math.isfinite, w.tolist())) and _smallest(slack) >= -FEASIBLE_TOL * scale):
        return None
    touching = (slack <= TOUCH_TOL).nonzero()[0]
    if len(touching) and np.logical_or.reduce(z):
        least = _least_norm(rows[touching], w)
        lowest = float(_smallest(least))
        if lowest >= -SIGN_TOL * (1.0 + max(float(_largest(least)), -lowest)):
            z = np.zeros(len(lower))
            z[touching] = np.maximum(least, 0.0)
    x = to_u.T.dot(u_0 + w)
    return x, z


def _least_norm(rows: np.ndarray, w: np.ndarray) -> np.ndarray:
    """The least-norm z with rows^T z = w: z = rows y, (rows^T rows) y = w (Cholesky), or by SVD when rank-deficient."""
    y = solve_spd(rows.T.dot(rows), w)
    if y is not None:
        z = rows.dot(y)
        tol = GRAM_TOL * (1.0 + max(map(abs, w.tolist())))  # w is finite (ldp_free_qp checked it)
        if all(abs(r) <= tol for r in (rows.T.dot(z) - w).tolist()):  # NaN: not close
            return z
    return np.linalg.lstsq(rows.T, w, rcond=None)[0]


def _scipy(module: str, name: str) -> Callable:
    """SciPy's ``name`` from ``scipy.optimize`` or ``scipy.linalg.lapack``, looked up once (asked every step)."""
    found = _SCIPY.get(name)
    if found is None:
        if module == "optimize":
            from scipy import optimize as source  # deferred: heavy (scipy), keeps the CLI's start fast
        else:
            from scipy.linalg import lapack as source  # deferred: heavy (scipy), keeps the CLI's start fast
        found = _SCIPY[name] = getattr(source, name)
    return found


def cholesky_inverse(matrix: np.ndarray) -> np.ndarray | None:
    """L^-1 of the Cholesky factor L (lower) of a small SPD matrix, by LAPACK directly; ``None`` when not SPD.

    On the 6 x 6 systems of a step, ``numpy.linalg``'s per-call cost (its error-state context and
    generalised ufunc) is several times LAPACK's own work.
    """
    factor, info = _scipy("lapack", "dpotrf")(matrix, lower=1, clean=1)
    if info != 0:
        return None
    inverse, info = _scipy("lapack", "dtrtri")(factor, lower=1)
    return inverse if info == 0 else None


def solve_spd(matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray | None:
    """Solve A x = b for a small SPD A (LAPACK's posv, Cholesky); ``None`` when A is not positive definite."""
    _, x, info = _scipy("lapack", "dposv")(matrix, rhs, lower=1)
    return x if info == 0 else None


def floating_qp(
    hessian: np.ndarray,
    g: np.ndarray,
    a_eq: np.ndarray,
    b_eq: np.ndarray,
    c_in: np.ndarray,
    lower: np.ndarray,
    root: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """The contact QP of a floating robot whose equality rows leave its root free, exactly.

    min 1/2 x^T H x + g^T x s.t. A x = b, C x >= l, where A's first ``root`` columns are zero
    (the loops and cranks act on the legs, not on the free hip). With x = (x_r, x_L), the rows
    A_L x_L = b fix the legs' velocities on their own when A_L is square (the cranks driven, no
    free ankle): x_L = A_L^-1 b, and the QP is on the root's ``root`` unknowns alone,
    :func:`ldp_free_qp` with H_rr, g_r + H_rL x_L, C_r and l - C_L x_L. Otherwise the legs'
    remaining freedoms join the root's through :func:`~pasibot_pin.dynamics.floor.qp.reduced_qp`.
    The equality multipliers solve A_L^T y = (H x + g - C^T z)_L.

    Args:
        hessian: H (n, n), symmetric positive definite.
        g: linear term (n,).
        a_eq: A (m, n), zero on the first ``root`` columns.
        b_eq: b (m,).
        c_in: the cone rows C (k, n).
        lower: l (k,).
        root: the root's unknowns, the first columns (6 for a free flyer).

    Returns:
        (x, y, z) as :func:`~pasibot_pin.dynamics.floor.qp.reduced_qp`'s; ``None`` when it does not solve.

    """
    from scipy.linalg import lapack  # deferred: heavy (scipy), keeps the CLI's start fast

    legs = a_eq[:, root:]
    if legs.shape[0] != legs.shape[1]:  # a free ankle: the general elimination
        return reduced_qp(hessian, g, a_eq, b_eq, c_in, lower, solver=ldp_free_qp)
    _, _, x_legs, info = lapack.dgesv(legs, b_eq)
    if info != 0:  # singular: a dead point of the linkage
        return None
    found = ldp_free_qp(
        hessian[:root, :root],
        g[:root] + hessian[:root, root:] @ x_legs,
        c_in[:, :root],
        lower - c_in[:, root:] @ x_legs,
    )
    if found is None:
        return None
    x_root, z = found
    x = np.concatenate((x_root, x_legs))
    residual = hessian[root:] @ x + g[root:] - c_in[:, root:].T @ z
    _, _, y, info = lapack.dgesv(legs.T, residual)
    return (x, y, z) if info == 0 else None
