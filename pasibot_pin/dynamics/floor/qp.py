"""The floor step's contact QP: an exact active-set solve from the last step's contacts, proxsuite otherwise.

The QP of one floor step (:mod:`pasibot_pin.dynamics.floor`) is

    min_x  1/2 x^T H x + g^T x   s.t.   A x = b,   C x >= l

(x the velocity after the step, A the bilateral rows, C the friction-cone rows). Its solution x
is unique (H is the mass matrix plus the implicit springs: positive definite). Between two
steps the set of active cone rows (the contact mode) rarely changes, so :class:`ContactQP`
first solves the KKT system of the last step's active set exactly,

    [H  -E^T] [x]   [-g]
    [E    0 ] [λ] = [ r],   E = [A; C_W], r = [b; l_W],

with Pinocchio's ``forwardDynamics`` (:func:`~pasibot_pin.constraints.system.kkt_solve`: Cholesky
factors of H and of E H^-1 E^T), and keeps that
answer only if it *is* the QP's solution:
every active cone multiplier >= 0, every other cone row satisfied (to :data:`FEASIBILITY_TOL`),
the rows met to :data:`RESIDUAL_TOL`. A negative multiplier drops its row, a violated row joins
the set, and the solve repeats (at most :data:`MAX_PASSES` times).

Where the active rows are redundant the multipliers are not unique. A flat foot that sticks at
heel and toe has four cone rows on a body of three freedoms: one row is left out (the KKT above
on the other three). Both feet flat and sticking (the flat double support) hold six such rows
of rank three on the three freedoms the loops and cranks leave: the motion is unique, the
impulses are not. There :func:`reduced_qp` solves the QP exactly on those few freedoms
and takes, of the impulses that produce the motion, the one of least norm in the cone rows
(each cone edge an equal stiff spring: the least-work split of a statically indeterminate
support). A cone row's impulse is z = (n +- t / mu) / 2, so the norm is the sum of
(n^2 + t^2 / mu^2) / 2 over the points; while both feet stick and the loops and the cranks
leave the robot a rigid body (the parallel and rigid variants), the normal impulses come out
linear in the points' position along the floor, as under a rigid body on equal springs, and the
tangential ones equal.
Where the last active set does not settle (the first step, a change of contact that the passes
do not follow), :func:`reduced_qp` solves the QP exactly in the same way;
proxsuite (cold start) only where it cannot (more than :data:`MAX_FREE` freedoms).

:meth:`ContactQP.solve_free` is the same QP written on the free coordinates alone (no equality
rows: the floor's shape track has solved them, :mod:`pasibot_pin.dynamics.floor.shape_track`): the
same passes, their KKT through H^-1 on three unknowns, and :func:`free_qp` (the core of
:func:`reduced_qp`) where they do not settle.
On run 1's floor runs (2 s, four spring cases) proxsuite at its eps_abs = 1e-10 differs from
itself at 1e-12 by as much as it differs from the exact answer (q 6e-9, forces 1e-4 N), while
the exact answer and proxsuite at 1e-12 agree to q 3e-11.

Units: as the caller's (the floor step: x [m/s, rad/s], multipliers [N.s, N.m.s]).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from itertools import combinations
from operator import mul

import numpy as np
import pinocchio as pin
import proxsuite

from pasibot_pin.constraints.solves import inverse_lists
from pasibot_pin.constraints.system import kkt_solve
from pasibot_pin.errors import ContactSolveError, ParameterError

QP_ATTEMPTS: tuple[tuple[float, int], ...] = ((1e-10, 300), (1e-9, 3_000), (1e-8, 100_000))
"""(eps_abs, max_iter) of proxsuite, tried in turn until the contact QP solves (the first nearly always does, in
~20 iterations; a degenerate double support that does not is retried looser at once rather than iterated 10^4 times)."""
MAX_PASSES = 4
"""Active-set passes (one KKT solve each) before the step falls back to proxsuite."""
MAX_FREE = 6
"""Most freedoms (unknowns less equality rows) on which :func:`reduced_qp` tries every subset of cone rows
(247 subsets of 8 rows at 6); beyond, proxsuite."""
MAX_CHOICES = 16
"""Choices of the row each fully active redundant group leaves out (4 rows per flat foot, two feet)."""
FEASIBILITY_TOL = 1e-11
"""A cone row outside the active set may miss its bound by this much [m/s] (a touchdown speed
error of 1e-11 m/s, i.e. 1e-14 m of penetration per millisecond step)."""
RESIDUAL_TOL = 1e-10
"""Largest residual of the active rows in the exact solve (proxsuite's eps_abs) [m/s, rad/s]."""
SIGN_TOL = 1e-12
"""A least-norm cone impulse this far below zero, relative to the largest, is round-off (set to 0) [-]."""
TOUCH_TOL = 1e-9
"""A cone row that its bound holds to this [m/s] touches: it may carry impulse in the least-norm split."""
UNBOUNDED = 1e20
"""proxsuite's upper bound of a cone row (no upper bound)."""


class ContactQP:
    """The contact QP of successive floor steps (see the module docstring).

    Args:
        model: the Pinocchio model (its ``forwardDynamics`` solves the KKT systems, in a data of
            the QP's own).
        redundant: groups of cone rows that are linearly dependent when all are active (a flat
            foot whose heel and toe both stick: four rows on a body of three freedoms).

    Attributes:
        active: indices of the cone rows active at the last solve (``None`` before the first).
        fast: solves answered exactly (the active-set step, or :func:`reduced_qp`).
        fallback: solves answered by proxsuite (more than :data:`MAX_FREE` freedoms, or no subset qualified).
        order: the choice of the rows left out of redundant groups that solved the last step (tried
            first next time: a flat foot keeps its choice while it sticks).

    """

    def __init__(self, model: pin.Model, redundant: Sequence[Sequence[int]] = ()) -> None:
        self.model, self.data = model, pin.Data(model)
        self.redundant = [frozenset(group) for group in redundant]
        if sum(map(len, self.redundant)) != len(frozenset().union(*self.redundant)):
            raise ParameterError("parameter 'redundant': the groups of cone rows must be disjoint")
        self._groups = [(group, sorted(group)) for group in self.redundant]
        self.active: list[int] | None = None
        self.fast = 0
        self.fallback = 0
        self.order = 0  # the choice of left-out rows that solved the last step: tried first at the next

    def solve(
        self,
        hessian: np.ndarray,
        g: np.ndarray,
        a_eq: np.ndarray,
        b_eq: np.ndarray,
        c_in: np.ndarray,
        lower: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The QP's solution and multipliers.

        Args:
            hessian: H (n, n), symmetric positive definite, zero outside the model's mass-matrix pattern.
            g: linear term (n,).
            a_eq: equality rows A (m, n), full row rank (any memory order).
            b_eq: their right-hand side (m,).
            c_in: inequality rows C (k, n).
            lower: their lower bounds (k,).

        Returns:
            (x, y, z): the solution (n,), the equality multipliers (m,) and the inequality ones
            (k,) >= 0, signed so that H x + g = A^T y + C^T z.

        Raises:
            ValueError: proxsuite did not solve the QP.

        """
        out = None if self.active is None else self._active_set(hessian, g, a_eq, b_eq, c_in, lower)
        if out is None and hessian.shape[0] - len(b_eq) <= MAX_FREE:
            out = reduced_qp(hessian, g, a_eq, b_eq, c_in, lower)  # every subset: dependent rows too
            if out is not None:
                self.active = np.flatnonzero(out[2] > 0.0).tolist()
        if out is not None:
            self.fast += 1
            return out
        x, y, z = self._proxsuite(hessian, g, a_eq, b_eq, c_in, lower)
        self.fallback += 1
        self.active = np.flatnonzero(z > 0.0).tolist()
        return x, y, z

    def _reduced(self, active: list[int], n_free: int, order: int) -> list[int] | None:
        """``active`` with one row left out of each redundant group it holds whole, or ``None``.

        A flat foot that sticks at heel and toe has four cone rows on a body of three freedoms:
        the motion is unique, the split of its force between the rows is not. Any three rows
        whose multipliers come out non-negative give the QP's solution (the fourth, inactive,
        holds with equality). ``order`` picks which row each group leaves out (0, 1, ...).
        """
        rows = list(active)
        present = set(rows)  # the groups are disjoint: a removal leaves the others' test alone
        for group, members in self._groups:
            if group <= present:
                rows.remove(members[order % len(members)])
                order //= len(members)
        if len(rows) > n_free or order:
            return None
        return rows

    def solve_free(
        self,
        hessian: list[list[float]],
        g: list[float],
        c_in: list[list[float]],
        lower: list[float],
        extra: list[float],
    ) -> tuple[list[float], list[float], list[float]]:
        """The QP without equality rows, min 1/2 x^T H x + g^T x s.t. C x >= l, on few freedoms, in Python floats.

        The floor's QP on the coordinates its bilateral rows leave free (the hip, a free ankle):
        the same warm-started active set as :meth:`solve` (the last step's rows, each redundant
        group reduced), its KKT through H^-1 on lists (three unknowns and eight rows for the
        biped: numpy's per-call cost would exceed the arithmetic), then :func:`free_qp` (every
        subset) and proxsuite where the passes do not settle.

        Args:
            hessian: H (n, n), symmetric positive definite, as lists.
            g: linear term (n,).
            c_in: inequality rows C (k, n), as lists; a row may run on past its n-th entry (the
                floor passes its cone rows whole), the rest is not read.
            lower: their lower bounds (k,).
            extra: one more right-hand side (n,) to solve with H (the floor's projection).

        Returns:
            (x, z, H^-1 extra) as lists: the solution, the cone multipliers (>= 0) with H x + g = C^T z.

        Raises:
            numpy.linalg.LinAlgError: H is singular (the caller takes another path).

        """
        n = len(g)
        inverse = inverse_lists(hessian)
        shift = [sum(map(mul, row, extra)) for row in inverse]
        out = None
        if self.active is not None and self._reduced(self.active, n, 0) is not None:
            out = self._first_order(_free_kkt(hessian, inverse, g, c_in, lower), n)
        if out is not None:
            self.fast += 1
            return out[0], out[1], shift
        arrays = np.array(hessian), np.array(g), np.array(c_in)[:, :n].reshape(len(lower), n), np.array(lower)
        found = free_qp(*arrays)
        if found is not None:
            self.fast += 1
            self.active = np.flatnonzero(found[1] > 0.0).tolist()
            return found[0].tolist(), found[1].tolist(), shift
        x, _, z = self._proxsuite(arrays[0], arrays[1], np.zeros((0, n)), np.zeros(0), arrays[2], arrays[3])
        self.fallback += 1
        self.active = np.flatnonzero(z > 0.0).tolist()
        return x.tolist(), z.tolist(), shift

    def _active_set(self, hessian, g, a_eq, b_eq, c_in, lower):
        """The exact solve from the last active set, or ``None`` (no active set found)."""
        n, m = hessian.shape[0], len(b_eq)
        if self._reduced(list(self.active or []), n - m, 0) is None:  # over-constrained (a flat double support)
            return None
        self.data.M[:] = hessian  # forwardDynamics factorises data.M (its upper triangle, the tree's pattern)
        self.data.nle[:] = 0.0

        def kkt(rows: list[int]):
            e_rows = np.concatenate((a_eq, c_in[rows]))
            rhs = np.concatenate((b_eq, lower[rows]))
            try:  # H x - E^T lam = -g, E x = r
                x, lam = kkt_solve(self.model, self.data, -g, e_rows, -rhs)
            except ValueError:  # singular, or not finite
                return None
            accurate = bool(np.abs(e_rows @ x - rhs).max() <= RESIDUAL_TOL)  # also NaN
            return x, lam[m:].tolist(), lam[:m].copy(), accurate, (c_in @ x - lower).tolist()

        out = self._first_order(kkt, n - m)
        return None if out is None else (out[0], out[2], np.array(out[1]))

    def _first_order(self, kkt, n_free):
        """The passes from the last active set, each choice of left-out rows in turn: (x, z, y) or ``None``."""
        active = list(self.active or [])
        out = self._passes(list(active), self.order, n_free, kkt)  # nearly always
        if out is not None:
            return out
        for order in range(MAX_CHOICES):
            if order != self.order:
                out = self._passes(list(active), order, n_free, kkt)
                if out is not None:
                    self.order = order
                    return out
        return None

    def _passes(self, active, order, n_free, kkt):
        """Active-set passes from ``active`` (redundant groups reduced by ``order``), or ``None``.

        ``kkt(rows)`` solves the KKT system with the cone rows ``rows`` held: (x, their
        multipliers (a list), the equality multipliers or None, whether the held rows are met to
        :data:`RESIDUAL_TOL`, every cone row's slack C x - l (a list)), or ``None`` (singular).
        """
        for _ in range(MAX_PASSES):
            solved = self._reduced(active, n_free, order)
            if solved is None:
                return None
            out = kkt(solved)
            if out is None:
                return None
            x, z_active, y, accurate, slack = out
            if solved:
                least = min(z_active)
                if least < 0.0:
                    active.remove(solved[z_active.index(least)])
                    continue
            for row in solved:
                slack[row] = math.inf
            least = min(slack)
            if least < -FEASIBILITY_TOL:
                worst = slack.index(least)
                if worst in active:  # a row left out of its group is violated: another choice
                    return None
                active.append(worst)
                continue
            if not accurate:
                return None
            z = [0.0] * len(slack)
            for row, value in zip(solved, z_active):
                z[row] = value
            self.active = active
            return x, z, y
        return None

    @staticmethod
    def _proxsuite(hessian, g, a_eq, b_eq, c_in, lower):
        return proxsuite_qp(hessian, g, a_eq, b_eq, c_in, lower)


def proxsuite_qp(
    hessian: np.ndarray, g: np.ndarray, a_eq: np.ndarray, b_eq: np.ndarray, c_in: np.ndarray, lower: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The contact QP by proxsuite's dense solver, cold, with :data:`QP_ATTEMPTS` (a hard step gets more iterations).

    Returns:
        (x, y, z) signed as :meth:`ContactQP.solve`'s: H x + g = A^T y + C^T z, z >= 0.

    Raises:
        ContactSolveError: no attempt solved it.

    """
    for eps, max_iter in QP_ATTEMPTS:
        result = proxsuite.proxqp.dense.solve(
            H=hessian,
            g=g,
            A=a_eq,
            b=b_eq,
            C=c_in,
            l=lower,
            u=np.full(len(lower), UNBOUNDED),
            eps_abs=eps,
            max_iter=max_iter,
        )
        if result.info.status == proxsuite.proxqp.QPSolverOutput.PROXQP_SOLVED:
            break
    else:
        raise ContactSolveError(f"the contact QP did not solve ({result.info.status})")
    return np.array(result.x), -np.array(result.y), -np.array(result.z)


def _free_kkt(
    hessian: list[list[float]], inverse: list[list[float]], g: list[float], c_in: list[list[float]], lower: list[float]
):
    """``kkt(rows)`` of :meth:`ContactQP._passes` for the QP without equality rows, in Python floats.

    As many held rows W as unknowns fix x on their own, x = C_W^-1 l_W, and their multipliers
    follow from H x + g = C_W^T z_W. Fewer: x = x_0 + H^-1 C_W^T z_W with x_0 = -H^-1 g and
    (C_W H^-1 C_W^T) z_W = l_W - C_W x_0, the columns H^-1 C_j^T formed as a pass first holds
    row j. A row of ``c_in`` is read to its n-th entry.
    """
    n = len(g)
    pulled: dict[int, list[float]] = {}
    unheld: list[list[float]] = []  # x_0, formed when a pass first holds fewer rows than unknowns

    def start() -> list[float]:
        if not unheld:
            unheld.append([-sum(map(mul, row, g)) for row in inverse])
        return unheld[0]

    def toward(j: int) -> list[float]:
        column = pulled.get(j)
        if column is None:
            c = c_in[j]
            column = pulled[j] = [sum(map(mul, row, c)) for row in inverse]
        return column

    def kkt(rows: list[int]):
        if len(rows) == n:  # square: the held rows alone fix x
            try:
                held_inverse = inverse_lists([c_in[i][:n] for i in rows])
            except np.linalg.LinAlgError:  # dependent rows
                return None
            bounds = [lower[i] for i in rows]
            x = [sum(map(mul, row, bounds)) for row in held_inverse]
            pushed = [sum(map(mul, row, x)) + b for row, b in zip(hessian, g)]  # H x + g = C_W^T z_W
            z_w = [sum(map(mul, column, pushed)) for column in zip(*held_inverse)]
        elif rows:
            x_0 = start()
            columns = [toward(j) for j in rows]
            held = [[sum(map(mul, c_in[i], column)) for column in columns] for i in rows]
            solved = _solve_small(held, [lower[i] - sum(map(mul, c_in[i], x_0)) for i in rows])
            if solved is None:  # dependent rows
                return None
            z_w = solved
            x = list(x_0)
            for z, column in zip(z_w, columns):
                x = [a + z * b for a, b in zip(x, column)]
        else:
            x, z_w = start(), []
        slack = [sum(map(mul, c, x)) - bound for c, bound in zip(c_in, lower)]
        if not math.isfinite(sum(slack) + sum(x)):
            return None
        accurate = all([abs(slack[i]) <= RESIDUAL_TOL for i in rows])
        return x, z_w, None, accurate, slack

    return kkt


def _solve_small(matrix: list[list[float]], rhs: list[float]) -> list[float] | None:
    """Solve a small square system given as lists (cofactors up to 3 x 3); ``None`` when singular."""
    try:
        return [sum(map(mul, row, rhs)) for row in inverse_lists(matrix)]
    except np.linalg.LinAlgError:
        return None


def equality_space(a_eq: np.ndarray, b_eq: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The motions that meet the equality rows A x = b: (Q_1, R_1, N, x_A).

    From the QR factors of A^T = [Q_1 Q_2] [R_1; 0]: x = x_A + N w for any w, x_A = Q_1 R_1^-T b
    and N = Q_2 (an orthonormal basis of A's null space). A must have full row rank.
    """
    q, r = np.linalg.qr(a_eq.T, mode="complete")
    m = a_eq.shape[0]
    q_1, r_1 = q[:, :m], r[:m]
    return q_1, r_1, q[:, m:], q_1 @ np.linalg.solve(r_1.T, b_eq)


_SUBSETS: dict[tuple[int, int], list[np.ndarray]] = {}
"""The row subsets :func:`reduced_qp` tries, per (rows, freedoms): arrays (count, size), smallest first."""


def _subsets(k: int, free: int) -> list[np.ndarray]:
    key = (k, free)
    if key not in _SUBSETS:
        _SUBSETS[key] = [
            np.array(list(combinations(range(k), size)), dtype=int).reshape(-1, size)
            for size in range(1, min(k, free) + 1)
        ]
    return _SUBSETS[key]


def reduced_qp(
    hessian: np.ndarray,
    g: np.ndarray,
    a_eq: np.ndarray,
    b_eq: np.ndarray,
    c_in: np.ndarray,
    lower: np.ndarray,
    solver: Callable[..., tuple[np.ndarray, np.ndarray] | None] | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """The contact QP exactly, on the few freedoms the equality rows leave, for rows that may be dependent.

    The motions that meet A x = b are x = x_A + N w (:func:`equality_space`; w has n - m
    components, three for the two-legged biped with its cranks driven). With H_r = N^T H N = L L^T
    and u = L^T w, the QP is the projection of u_0 = -L^-1 N^T (H x_A + g) onto the polyhedron
    G u >= d (G = C N L^-T, d = l - C x_A). The projection is u_0 + G_S^T mu for the subset S of
    independent rows that hold with equality, mu >= 0, every row met: every subset of at most
    n - m rows is tried at once (a batched solve; 92 subsets for 8 cone rows and 3 freedoms),
    and the first that qualifies gives the unique u. Of the cone impulses z >= 0 that give it
    (G^T z = u - u_0 on the rows that touch), the least-norm one is taken when it is >= 0 (each
    cone edge an equal stiff spring: the least-work split of a statically indeterminate
    support, Menabrea), else the subset's mu. The equality multipliers follow from
    A^T y = H x + g - C^T z.

    Args:
        hessian: H (n, n), symmetric positive definite.
        g: linear term (n,).
        a_eq: A (m, n), full row rank.
        b_eq: b (m,).
        c_in: the cone rows C (k, n).
        lower: l (k,).

        solver: the QP on the free motions, ``solver(H_r, g_r, C_r, l_r) -> (w, z) or None``:
            :func:`free_qp` (every subset, exact; the default) or :func:`proxsuite_free_qp` (many rows).

    Returns:
        (x, y, z) signed so that H x + g = A^T y + C^T z, z >= 0; ``None`` when no subset
        qualifies (left to proxsuite).

    """
    q_1, r_1, null, x_a = equality_space(a_eq, b_eq)
    base = hessian @ x_a + g
    found = (solver or free_qp)(null.T @ hessian @ null, null.T @ base, c_in @ null, lower - c_in @ x_a)
    if found is None:
        return None
    w, z = found
    x = x_a + null @ w
    y = np.linalg.solve(r_1, q_1.T @ (base + hessian @ (x - x_a) - c_in.T @ z))
    return x, y, z


def proxsuite_free_qp(
    hessian: np.ndarray, g: np.ndarray, c_in: np.ndarray, lower: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The QP min 1/2 x^T H x + g^T x s.t. C x >= l by proxsuite (:func:`proxsuite_qp`): (x, z >= 0).

    For :func:`reduced_qp` where the rows are too many for :func:`free_qp`'s subsets (the 3-D
    floor: four pyramid rows at each sole corner).
    """
    x, _, z = proxsuite_qp(hessian, g, np.zeros((0, len(g))), np.zeros(0), c_in, lower)
    return x, z


def free_qp(
    hessian: np.ndarray, g: np.ndarray, c_in: np.ndarray, lower: np.ndarray
) -> tuple[np.ndarray, np.ndarray] | None:
    """The QP min 1/2 x^T H x + g^T x s.t. C x >= l, exactly, on a few freedoms, rows perhaps dependent.

    With H = L L^T and u = L^T x, the QP is the projection of u_0 = -L^-1 g onto the polyhedron
    G u >= l (G = C L^-T). The projection is u_0 + G_S^T mu for the subset S of independent rows
    that hold with equality, mu >= 0, every row met: every subset of at most n rows is tried at
    once (a batched solve; 92 subsets for 8 cone rows and 3 freedoms), and the first that
    qualifies gives the unique u. Of the cone impulses z >= 0 that give it (G^T z = u - u_0 on
    the rows that touch), the least-norm one is taken when it is >= 0 (each cone edge an equal
    stiff spring: the least-work split of a statically indeterminate support, Menabrea), else
    the subset's mu.

    Args:
        hessian: H (n, n), symmetric positive definite.
        g: linear term (n,).
        c_in: the cone rows C (k, n).
        lower: l (k,).

    Returns:
        (x, z) with H x + g = C^T z, z >= 0; ``None`` when no subset qualifies (left to proxsuite).

    """
    free = len(g)
    try:
        chol = np.linalg.cholesky(hessian)
    except np.linalg.LinAlgError:
        return None
    u_0 = -np.linalg.solve(chol, g)
    to_w = np.linalg.inv(chol).T  # x = L^-T u
    rows = c_in @ to_w  # G (k, free)
    rhs = lower  # d
    need = rhs - rows @ u_0  # G_S mu' = d_S - G_S u_0 on a subset
    slack_0 = -need
    found = None
    if slack_0.min() >= -FEASIBILITY_TOL:
        found = (np.zeros(0, dtype=int), np.zeros(0))
    for subset in _subsets(len(lower), free) if found is None else ():
        g_s = rows[subset]  # (count, size, free)
        gram = g_s @ np.swapaxes(g_s, 1, 2)
        ok = np.abs(np.linalg.det(gram)) > 1e-12
        if not ok.any():
            continue
        subset, g_s = subset[ok], g_s[ok]
        mu = np.linalg.solve(gram[ok], need[subset][..., None])[..., 0]
        u = u_0 + np.einsum("csf,cs->cf", g_s, mu)
        slack = u @ rows.T - rhs
        good = (mu.min(axis=1) >= -SIGN_TOL * (1.0 + np.abs(mu).max(axis=1))) & (slack.min(axis=1) >= -FEASIBILITY_TOL)
        if good.any():
            pick = int(np.argmax(good))
            found = (subset[pick], np.maximum(mu[pick], 0.0))
            break
    if found is None:
        return None
    subset, mu = found
    u = u_0 + rows[subset].T @ mu
    slack = rows @ u - rhs
    touching = np.flatnonzero(slack <= TOUCH_TOL)
    z = np.zeros(len(lower))
    if len(touching):
        least = np.linalg.lstsq(rows[touching].T, u - u_0, rcond=None)[0]
        if _signed(least):
            z[touching] = np.maximum(least, 0.0)
        else:
            z[subset] = mu
    x = to_w @ u
    if not np.all(np.isfinite(x)):
        return None
    return x, z


def _signed(z: np.ndarray) -> bool:
    """True when no impulse is below zero beyond round-off (:data:`SIGN_TOL`)."""
    return not len(z) or float(z.min()) >= -SIGN_TOL * (1.0 + float(np.abs(z).max()))
