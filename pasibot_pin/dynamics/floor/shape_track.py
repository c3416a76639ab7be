"""The linkage's shape along the crank schedule: the floor step's loops and cranks, solved ahead in closed form.

With its cranks driven, each leg of PASIBOT has no freedom left: the loops fix every leg
coordinate as a function of the leg's crank angle. Of the floor step's unknowns
(:mod:`pasibot_pin.dynamics.floor`) only a few are left to the dynamics: the hip (x, z, pitch)
and a free ankle (the spring variant's foot, a leaf of the tree). The coordinates split in two:

* the **free** ones F, whose columns the bilateral rows leave zero on the manifold (a loop row is
  the world difference of two points of one tree: moving the hip moves both alike, and a free
  ankle is in no row);
* the **shape** S, on which the rows are square: J_S (m x m) is invertible away from a dead point.

The step's velocity row J v = -Phi(q, t + h) / h then fixes x_S on its own. The loop rows are
closed at q, and a scalar row E theta = target + c holds the cranks, so

    x_S = J_S^-1 [0; E (theta_(k+1) - theta_k) / h] = T_k (theta_(k+1) - theta_k) / h,

T_k = ds/dtheta (m x 2) the closure's tangent per crank. The projection that follows the step
puts S on the unique closure at t + h, s_(k+1), and moves F by the mass metric's answer
-M_FF^-1 M_FS dS. All of it depends on the crank schedule only, not on the dynamics: this
module computes s_k and T_k for a block of :data:`BLOCK` steps at once, from the exact closed
form and its jets (:func:`~pasibot_pin.model.closure.analytic_motion`, closed to round-off: no
Newton, no linear solve), and the scalar rows' multipliers by virtual work, y = D_k^T r_S with
D_k = T_k E^-1 = J_S^-1 [0; I] (each row's force times the shape's motion per unit of its target).

:meth:`ShapeSplit.of` finds the split from the rows (``None`` where the rows do not have it: the
hip held level, a crank that is not driven); :class:`ShapeTrack` serves one run's steps and
declines a step (``None``: the floor takes its general path) where the state is not on the closed
form's shape (a given start off the manifold, another assembly branch) or the closed form fails.

Units: SI, angles [rad].
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from pasibot_pin.constraints import ConstraintSystem, FloatingForm
from pasibot_pin.dynamics.stance_plan import unwrap_angles
from pasibot_pin.model.closure import analytic_motion, angular_coordinates
from pasibot_pin.model.coordinates import HIP_PITCH, SIDES

if TYPE_CHECKING:
    from pasibot_pin.constraints.planar import PlanarRowBlocks
    from pasibot_pin.model.robot import PasibotRobot

BLOCK = 1024
"""Steps whose shapes one closed-form call computes [-] (its per-call cost is spread over more steps)."""
CHUNK = 128
"""Steps whose contact rows one evaluation computes [-] (larger temporaries cost page faults)."""
FREE_TOL = 1e-9
"""A coordinate is free when no row's Jacobian column exceeds this share of the largest entry [-]."""
MATCH_TOL = 1e-9
"""The state's shape must be the closed form's to this [rad, m] (the loops close to 1e-12 m)."""
JUMP_TOL = 1e-2
"""Largest step of the shape off its tangent, |s_(k+1) - s_k - h x_S| [rad, m] (an assembly branch
switch jumps by far more; a smooth step is O(h^2), below 1e-4)."""

_new = tuple.__new__
"""Builds a named tuple from a tuple of all its fields, without its Python-level ``__new__`` (once per time step)."""


class StepContact(NamedTuple):
    """The contact points' rows of one step, the hip at its origin, unpitched (a :class:`~.constraints.FloatingForm`).

    Attributes:
        start: each point's [i a B, J x_S, J D...] at the step's start shape, complex: its body row
            B turned a right angle by the pitch's sign a (its Jacobian column on the unpitched
            hip's pitch) [m], its speed in the step [m/s] and its motion per unit of each scalar
            row's target [m/rad].
        end: each point's [i a B, J x_S] at the step's end shape (J x_S: its speed after the step,
            less the hip's part).

    """

    start: list[list[complex]]
    end: list[list[complex]]


class TrackStep(NamedTuple):
    """One step of the shape from t to t + h, as full-size vectors (zero on the free coordinates but in E_F).

    Attributes:
        start: s at t (nv,): the state's shape.
        end: s at t + h (nv,): the closed shape after the step.
        columns: P (nv, free + 2 + scalar rows), the columns that the step multiplies by M:
            E_F, the unit columns of the free coordinates; x_S, the shape's velocity in the step
            [rad/s, m/s]; D = J_S^-1 [0; I], the shape's motion per unit of each scalar row's
            target [rad/rad, m/rad]; and s_(k+1) - s_k - h x_S, the projection's move of the
            shape [rad, m].
        columns_t: P^T, contiguous.
        free: the number of free coordinates (P's first columns).
        contact: the points' rows of the step (:class:`StepContact`), or ``None`` (no floating form).

    """

    start: np.ndarray
    end: np.ndarray
    columns: np.ndarray
    columns_t: np.ndarray
    free: int
    contact: StepContact | None = None

    @property
    def velocity(self) -> np.ndarray:
        """x_S (nv,)."""
        return self.columns[:, self.free]

    @property
    def moved(self) -> np.ndarray:
        """s_(k+1) - s_k - h x_S (nv,)."""
        return self.columns[:, -1]

    @property
    def tangent(self) -> np.ndarray:
        """D (nv, scalar rows)."""
        return self.columns[:, self.free + 1 : -1]


@dataclass(frozen=True)
class ShapeSplit:
    """The coordinates the floor's bilateral rows leave free and the shape they fix.

    Attributes:
        free: indices F of the free coordinates (the hip, free ankles).
        shape: indices S of the shape coordinates (m: as many as rows).
        cranks: the right and left crank coordinates.
        crank_of_target: E^-1 (2, scalar rows): theta = E^-1 (targets + c).
        target_offset: c (scalar rows,) [rad].
        legs: (m, 2) masks of the shape coordinates of the right and the left leg.
        angular: (m,) mask of the shape coordinates that are angles.
        at: the free coordinates as an index: a slice where they are contiguous (the hip: views,
            no copies), else ``free``.

    """

    free: np.ndarray
    shape: np.ndarray
    cranks: np.ndarray
    crank_of_target: np.ndarray
    target_offset: np.ndarray
    legs: np.ndarray
    angular: np.ndarray
    at: slice | np.ndarray

    @classmethod
    def of(
        cls, robot: PasibotRobot, rows: ConstraintSystem, q: np.ndarray, targets: np.ndarray, rates: np.ndarray
    ) -> ShapeSplit | None:
        """The split of ``rows`` at a closed ``q`` whose scalar rows' targets are ``targets`` (rates ``rates``).

        ``None`` when the rows do not fix the shape by the cranks alone: a scalar row on another
        coordinate (the hip held level), rows not square on the non-free coordinates, the two
        cranks not turning together pi apart (what the closed form assumes), a coordinate of
        neither leg.
        """
        n0 = rows.n_constraint_rows
        evaluated = rows.evaluate(q, None, 0.0, targets)
        jac = np.asarray(evaluated.jac)
        size = np.abs(jac).max(axis=0)
        free = np.flatnonzero(size <= FREE_TOL * size.max())
        shape = np.flatnonzero(size > FREE_TOL * size.max())
        cranks = np.array([robot.idx_v(f"{side}_j0_crank") for side in SIDES])
        scalar = jac[n0:]
        others = np.setdiff1d(np.arange(jac.shape[1]), cranks)
        if len(shape) != rows.nrows or scalar.shape[0] != len(cranks) or np.abs(scalar[:, others]).max() > 0.0:
            return None
        e = scalar[:, cranks]
        if abs(np.linalg.det(e)) < 1e-12:
            return None
        e_inv = np.linalg.inv(e)
        offset = e @ q[cranks] - evaluated.phi[n0:] - targets
        theta, rate = e_inv @ (targets + offset), e_inv @ rates
        apart = math.remainder(theta[1] - theta[0] - math.pi, 2 * math.pi)
        if abs(apart) > 1e-9 or abs(rate[1] - rate[0]) > 1e-12 * (1.0 + abs(rate[0])):
            return None
        names = _coordinate_joints(robot)
        legs = np.array([[names[int(i)].startswith(f"{side}_") for side in SIDES] for i in shape])
        if not legs.any(axis=1).all():
            return None
        angular = angular_coordinates(robot.model)[shape]
        contiguous = bool(len(free)) and np.array_equal(free, np.arange(free[0], free[0] + len(free)))
        at = slice(int(free[0]), int(free[0]) + len(free)) if contiguous else free
        return cls(free, shape, cranks, e_inv, offset, legs, angular, at)

    def thetas(self, targets: np.ndarray) -> np.ndarray:
        """Crank angles (N, 2) [rad] of the scalar rows' targets (N, scalar rows)."""
        return (targets + self.target_offset) @ self.crank_of_target.T


def _coordinate_joints(robot: PasibotRobot) -> dict[int, str]:
    """The joint name of each velocity coordinate."""
    model = robot.model
    out = {}
    for j in range(1, model.njoints):
        for k in range(model.joints[j].nv):
            out[model.joints[j].idx_v + k] = model.names[j]
    return out


class ShapeTrack:
    """One run's shapes, block by block (see the module docstring).

    Args:
        robot: the two-legged robot.
        split: :meth:`ShapeSplit.of` of the floor's rows.
        targets_at: the scalar rows' targets at times (N,) [s]: (N, scalar rows) [rad].
        h: the run's time step [s].
        points: the contact points' planar rows: with them, each step also carries the points'
            rows with the hip at its origin (:class:`StepContact`) where the free coordinates are
            the hip's and the points ride it rigidly (:attr:`form`).

    Attributes:
        form: the points' :class:`~pasibot_pin.constraints.FloatingForm` on the hip, or ``None``.

    """

    def __init__(
        self,
        robot: PasibotRobot,
        split: ShapeSplit,
        targets_at: Callable[[np.ndarray], np.ndarray],
        h: float,
        points: PlanarRowBlocks | None = None,
    ) -> None:
        self.robot, self.split, self.targets_at, self.h = robot, split, targets_at, h
        self.points = points
        self.form: FloatingForm | None = None
        if points is not None:
            form = points.floating_form(HIP_PITCH)
            if form is not None and [*form.base, form.pitch] == split.free.tolist():
                self.form = form
        self._block: _Block | None = None
        self._declined_until = -math.inf
        self._misses = 0  # blocks declined in a row

    def step(self, t: float, q: np.ndarray) -> TrackStep | None:
        """The shape's step from ``t`` for the state ``q`` (``None``: take the general path)."""
        block = self._block
        if block is not None:
            k = round((t - block.t0) / self.h)
            if 0 <= k < block.length and abs(block.t0 + k * self.h - t) <= 1e-6 * self.h:
                contact = None
                if block.contact is not None:
                    contact = _new(StepContact, (block.contact[0][k], block.contact[1][k]))
                shapes, columns = block.shapes, block.columns
                return _new(TrackStep, (shapes[k], shapes[k + 1], columns[k], block.columns_t[k], block.free, contact))
        if t < self._declined_until:
            return None
        self._block = self._solve_block(t, q)
        if self._block is None:  # the next step tries again, then (a lasting miss) the next block
            self._declined_until = t + (0.5 if not self._misses else BLOCK - 0.5) * self.h
            self._misses += 1
            return None
        self._misses = 0
        return self.step(t, q)

    def _solve_block(self, t: float, q: np.ndarray) -> _Block | None:
        """The shapes from ``t`` on, in ``q``'s turns, up to the first jump; ``None`` when ``q`` is off them."""
        split, h, cut = self.split, self.h, self.split.shape
        times = t + h * np.arange(BLOCK + 1)
        thetas = split.thetas(self.targets_at(times))
        try:
            q_all, v_all, _, _ = analytic_motion(self.robot, thetas[:, 0], 1.0, None)
        except ValueError:  # a loop that cannot assemble in the block: the general path names it
            return None
        shapes = q_all[:, cut]
        unwrap_angles(shapes, split.angular)
        turns = np.round((q[cut] - shapes[0]) * (0.5 / math.pi)) * split.angular
        shapes += (2 * math.pi) * turns
        if not np.abs(q[cut] - shapes[0]).max() <= MATCH_TOL:
            return None
        per_crank = v_all[:, cut, None] * split.legs[None]  # ds/dtheta of each leg (N, m, 2)
        velocities = np.einsum("kic,kc->ki", per_crank[:-1], np.diff(thetas, axis=0) / h)
        moved = shapes[1:] - shapes[:-1] - h * velocities
        off = np.abs(moved).max(axis=1)
        length = int(np.argmax(off > JUMP_TOL)) if (off > JUMP_TOL).any() else BLOCK
        if length == 0:
            return None
        tangents = per_crank[:-1] @ split.crank_of_target  # D = T E^-1
        nv, f = len(q), len(split.free)
        full = np.zeros((BLOCK + 1, nv))
        full[:, cut] = shapes
        columns = np.zeros((BLOCK, nv, f + 2 + tangents.shape[2]))
        columns[:, split.free, np.arange(f)] = 1.0
        columns[:, cut, f], columns[:, cut, f + 1 : -1], columns[:, cut, -1] = velocities, tangents, moved
        contact = None if self.form is None else self._contact(full, columns[:, :, f:-1])
        columns_t = np.ascontiguousarray(columns.transpose(0, 2, 1))
        return _Block(t, full, columns, columns_t, length, f, contact)

    def _contact(self, full: np.ndarray, motions: np.ndarray) -> tuple[list, list]:
        """The lists of :class:`StepContact` for each step of the block.

        One evaluation of the points' terms at every shape gives the body rows and the
        directional derivatives J x_S, J D at each step's start and J x_S at its end.
        """
        points, form = self.points, self.form
        assert points is not None and form is not None
        steps = len(motions)
        # at shape j: the step j's x_S and D, and the step j - 1's x_S
        directions = np.zeros((steps + 1, full.shape[1], motions.shape[2] + 1))
        directions[:-1, :, :-1] = motions
        directions[1:, :, -1] = motions[:, :, 0]
        parts = [
            points.directional(full[i : i + CHUNK + 1], directions[i : i + CHUNK + 1]) for i in range(0, steps, CHUNK)
        ]  # chunks that overlap by one shape
        rows = np.concatenate([part[0][:-1] for part in parts[:-1]] + [parts[-1][0]])
        along = np.concatenate([part[1][:-1] for part in parts[:-1]] + [parts[-1][1]])
        rows = (rows - form.fixed) * (1j * form.turn)
        start = np.concatenate((rows[:-1, :, None], along[:-1, :, :-1]), axis=2)
        end = np.stack((rows[1:], along[1:, :, -1]), axis=2)
        return start.tolist(), end.tolist()


class _Block(NamedTuple):
    """One block of a track.

    Its start time [s], shapes (BLOCK + 1, nv), columns and their transposes, the steps it holds,
    the free coordinates' count and the contact lists of :class:`StepContact` (or ``None``).
    """

    t0: float
    shapes: np.ndarray
    columns: np.ndarray
    columns_t: np.ndarray
    length: int
    free: int
    contact: tuple[list, list] | None
