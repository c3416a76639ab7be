"""The floor step on the free coordinates, the legs' shape known ahead: a few products, then Python floats.

With the cranks driven, the floor step (:mod:`pasibot_pin.dynamics.floor`) is left with the free
coordinates F (the hip; a free ankle) as unknowns: the shape's velocity x_S, its tangent per
scalar row D and the projection's move are known ahead (:mod:`pasibot_pin.dynamics.floor.shape_track`).
The step is the general step's QP written on F,

    H_FF u + [M x_S - r]_F = C_F^T z,   C_F u >= -gap / h - C x_S,   r = M v - h (b - tau),

then the projection, which puts the shape on the next closed one and moves F by the mass
metric's -M_FF^-1 [M moved]_F, and the motors' multipliers by virtual work,
y = D^T (M x - r) - (C D)^T z with x = x_S + u on F. With P = [E_F, x_S, D, moved] (E_F the
unit columns of F) all the mass terms are P^T M P and P^T r: two Pinocchio calls (``crba``, and
``rnea`` at the acceleration -v / h, which is -(M v - h b) / h) and three products. Every other
quantity has at most eight rows and six columns (the heel and toe cone rows of two feet), so it
is computed on Python floats: numpy's per-call cost inside a simulation loop exceeds that
arithmetic.

The contact rows come from the track where the points ride the floating hip rigidly
(:class:`~pasibot_pin.constraints.FloatingForm`: the block's body rows turned by the hip's pitch,
no kinematics in the step), else from the planar rows at the step's configuration.

Units: SI, angles [rad], impulses [N.s].
"""

from __future__ import annotations

import math
from collections.abc import Callable
from operator import mul
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
import pinocchio as pin

from pasibot_pin.constraints import FloatingForm, symmetric_mass_matrix
from pasibot_pin.constraints.solves import inverse_lists
from pasibot_pin.dynamics.floor.ground import Ground
from pasibot_pin.dynamics.floor.qp import ContactQP
from pasibot_pin.dynamics.floor.shape_track import ShapeSplit, TrackStep
from pasibot_pin.errors import DivergedError, ParameterError

if TYPE_CHECKING:
    from pasibot_pin.constraints.planar import PlanarRowBlocks
    from pasibot_pin.model.robot import PasibotRobot

SPEED_LIMIT = 1e3
"""A velocity component beyond this [m/s, rad/s] means the simulation diverged."""


class StepOut(NamedTuple):
    """One tracked step (:meth:`FreeStepper.step`).

    Attributes:
        q: configuration after the step (nq,).
        v: velocity after the step (nv,).
        normal: each contact point's normal impulse [N.s] (right heel, right toe, left heel, left toe).
        tangential: each point's tangential impulse [N.s].
        motor: each motor's angular impulse [N.m.s].
        points: each point's height [m], x [m] and tangential speed [m/s] after the step.

    """

    q: np.ndarray
    v: np.ndarray
    normal: list[float]
    tangential: list[float]
    motor: list[float]
    points: tuple[list[float], list[float], list[float]]


def check_speed(u: list[float] | np.ndarray) -> None:
    """Raise :class:`~pasibot_pin.errors.DivergedError` where a part of ``u`` passes :data:`SPEED_LIMIT` (or is NaN)."""
    fastest = float(np.max(np.abs(u))) if isinstance(u, np.ndarray) else max(map(abs, u), default=0.0)
    if not fastest <= SPEED_LIMIT:  # also catches NaN
        raise DivergedError(f"the simulation diverged: a velocity reached {fastest:.3g} (limit {SPEED_LIMIT:g})")


class PointRows:
    """The contact points' planar rows and Jacobian, kept for the configuration asked last.

    A step's end is the next one's start: the floor's general step, its tracked step (where the
    rows do not ride the hip) and the judge's sample share one evaluation. The arrays are shared
    with the cache: read them, never write into them.

    Args:
        points: the heel and toe points' planar rows.
        ground: the ground (default the flat floor): the rows are read along it (x) and across it (z),
            turned by its frame e^(-i slope) (1 on the flat floor reads them as they are), and each
            point's gap is above the tread under it.

    """

    def __init__(self, points: PlanarRowBlocks, ground: Ground | None = None) -> None:
        self.points = points
        self.ground = Ground() if ground is None else ground
        self.turn = self.ground.turn
        self._key: bytes | None = None
        self._rows: tuple[np.ndarray, np.ndarray] = (np.zeros(0, dtype=complex), np.zeros((0, 0), dtype=complex))
        self._gaps = np.zeros(0)

    def at(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The rows x + i z (points,) [m] and their Jacobian (points, nv), complex, at ``q``."""
        q = np.asarray(q, dtype=float)
        key = q.tobytes()
        if key != self._key:
            rows, jac = self.points.rows_and_jacobian(q)
            self._rows = (rows, jac) if self.turn == 1.0 else (rows * self.turn, jac * self.turn)
            self._gaps = self.ground.planar_gaps(self._rows[0])
            self._key = key
        return self._rows

    def gaps(self, q: np.ndarray) -> np.ndarray:
        """Each point's gap above the tread under it (points,) [m] at ``q``."""
        self.at(q)
        return self._gaps

    def lists(self, q: np.ndarray, v: np.ndarray) -> tuple[list[float], list[float], list[float]]:
        """Each point's height above its tread [m], x [m] and tangential speed [m/s] at (q, v)."""
        rows, jac = self.at(q)
        return self._gaps.tolist(), rows.real.tolist(), jac.dot(v).real.tolist()


class FreeStepper:
    """The tracked floor step of one simulator (see the module docstring).

    Args:
        robot: the two-legged robot.
        split: the free coordinates and the shape (:class:`~pasibot_pin.dynamics.floor.shape_track.ShapeSplit`).
        rows: the contact points' planar rows, cached (:class:`PointRows`, shared with the floor's general step).
        qp: the simulator's contact QP (its active set carries over between the two kinds of step).
        springs: ``springs(q, h)``: the ankle springs' torque (nv,) [N.m] and their implicit term
            on each ankle's diagonal of H [kg.m^2].
        ankles: the free ankles' velocity indices (their springs' implicit term).
        motor_rows: the scalar rows that are motors (of the rows D spans).
        mu: Coulomb friction [-].
        form: the points' rigid motion with the hip when the free coordinates are the hip's
            (:attr:`~pasibot_pin.dynamics.floor.shape_track.ShapeTrack.form`): the contact rows then come
            from the track's block; ``None``: from the planar rows at each step.

    """

    def __init__(
        self,
        robot: PasibotRobot,
        split: ShapeSplit,
        rows: PointRows,
        qp: ContactQP,
        springs: Callable[[np.ndarray, float], tuple[np.ndarray, float]],
        ankles: list[int],
        motor_rows: list[int],
        mu: float,
        form: FloatingForm | None = None,
    ) -> None:
        self.model, self.data = robot.model, robot.data
        self.split, self.rows, self.qp, self.springs = split, rows, qp, springs
        self.mu, self.motor_rows = mu, motor_rows
        free = split.free.tolist()
        self.sprung = [free.index(i) for i in ankles if i in free]
        self._form = form
        self._turn = 1.0 if form is None else form.turn
        self._ground = complex(rows.turn)  # the ground's frame, e^(-i slope): world points read along and across it
        self._rise = rows.ground.rise if rows.ground.has_step else None  # the treads' height along the ground
        if form is not None:  # the free coordinates, in order, are the base's sliders, then its pitch
            if free != [*form.base, form.pitch]:
                raise ParameterError("parameter 'form': its base and pitch must be the free coordinates, in order")
            self._fixed = form.fixed.tolist()
            self._slide = form.slide.tolist()
            # each point's cone rows' entries on the sliders, Im(slide (1 +- i mu)): constants
            ground = self._ground
            self._slide_cone = [
                tuple([(ground * c * (1.0 + sign * 1j * mu)).imag for c in row] for sign in (1.0, -1.0))
                for row in self._slide
            ]

    def step(self, q: np.ndarray, v: np.ndarray, h: float, shape: TrackStep) -> StepOut | None:
        """One step from (q, v) on ``shape`` (``None`` where H_FF is singular: the general path takes it).

        Raises:
            DivergedError: a free velocity past :data:`SPEED_LIMIT`.

        """
        f, at = shape.free, self.split.at
        mass = symmetric_mass_matrix(self.model, self.data, q)
        r = pin.rnea(self.model, self.data, q, v, v * (-1.0 / h))  # M (-v / h) + b
        tau, stiffness = self.springs(q, h)
        k = shape.columns_t[: f + 1].dot(mass.dot(shape.columns)).tolist()  # P^T M P, its rows on F and x_S
        pr = shape.columns_t.dot(tau - r if stiffness else r).tolist()
        scale = h if stiffness else -h  # P^T (M v - h b + h tau)
        hessian = [row[:f] for row in k[:f]]
        for i in self.sprung:
            hessian[i][i] += stiffness
        g = [k[i][f] - scale * pr[i] for i in range(f)]
        q_free = q[at].tolist()
        contact = shape.contact if self._form is not None else None  # None: the planar rows at q
        if contact is None:
            cone, lower = self._cone_rows(q, shape, h)
        else:
            cone, lower = self._floating_cone(q_free, contact.start, h)
        try:
            u, z, shift = self.qp.solve_free(hessian, g, cone, lower, [row[-1] for row in k[:f]])
        except np.linalg.LinAlgError:  # a free coordinate without inertia (a foot's mass on its ankle axis)
            return None
        check_speed(u)  # x_S is the linkage's own, bounded by the crank speed
        if stiffness and self.sprung:  # the projection's metric is M alone, not H
            shift = self._mass_shift(k, f)
        motor = []
        for j in self.motor_rows:
            c = f + 1 + j
            work = k[f][c] - scale * pr[c] - sum(map(mul, z, [row[c] for row in cone]))  # D^T M x_S: K symmetric
            motor.append(work + sum(map(mul, u, [row[c] for row in k[:f]])))
        x = shape.columns_t[f].copy()  # x_S, contiguous
        x[at] = u
        q_new = shape.end.copy()
        q_free = [a + h * b - c for a, b, c in zip(q_free, u, shift)]
        q_new[at] = q_free
        n_points = len(z) // 2
        normal = [a + b for a, b in zip(z[:n_points], z[n_points:])]
        tangential = [self.mu * (a - b) for a, b in zip(z[:n_points], z[n_points:])]
        if contact is None:
            points = self.rows.lists(q_new, x)
        else:
            points = self._floating_points(q_free, u, contact.end)
        return StepOut(q_new, x, normal, tangential, motor, points)

    @staticmethod
    def _mass_shift(k: list[list[float]], f: int) -> list[float]:
        """M_FF^-1 [M moved]_F (0 where M_FF is singular: as the general projection's least-norm step)."""
        try:
            inverse = inverse_lists([row[:f] for row in k[:f]])
        except np.linalg.LinAlgError:
            return [0.0] * f
        extra = [row[-1] for row in k[:f]]
        return [sum(map(mul, row, extra)) for row in inverse]

    def _cone_rows(self, q: np.ndarray, shape: TrackStep, h: float) -> tuple[list[list[float]], list[float]]:
        """The cone rows on [F, x_S, D] and their bounds, from the planar rows at ``q``."""
        _, jac = self.rows.at(q)
        f, mu = shape.free, self.mu
        jac = np.concatenate((jac[:, self.split.at], jac.dot(shape.columns[:, f:-1])), axis=1)
        cone = np.concatenate((jac.imag + mu * jac.real, jac.imag - mu * jac.real))
        bound = self.rows.gaps(q) * (-1.0 / h)
        return cone.tolist(), (np.concatenate((bound, bound)) - cone[:, f]).tolist()

    def _floating_cone(self, q_free: list[float], start: list[list[complex]], h: float):
        """:meth:`_cone_rows` from the track's body rows, turned by the hip's pitch (no kinematics).

        A cone row's entry on a complex Jacobian entry c is Im(c) +- mu Re(c) = Im(c (1 +- i mu)),
        and the entries on the hip's pitch, x_S and D are each the body's unpitched one turned by
        the pitch (:class:`~pasibot_pin.dynamics.floor.shape_track.StepContact`).
        """
        turn, mu, ground = self._turn, self.mu, self._ground
        *base, pitch = q_free
        e = complex(math.cos(pitch), turn * math.sin(pitch))
        to_body = e * complex(0.0, -turn)  # e B = e (i a B) / (i a)
        plus, minus = ground * e * complex(1.0, mu), ground * e * complex(1.0, -mu)
        upper, lower, bound_up, bound_low = [], [], [], []
        scale, rise = -1.0 / h, self._rise
        for fixed, slide, (cone_up, cone_low), row in zip(self._fixed, self._slide, self._slide_cone, start):
            at = ground * (fixed + sum(map(mul, slide, base)) + to_body * row[0])  # along + i across the ground
            gap = at.imag if rise is None else at.imag - rise(at.real)
            up = [(plus * c).imag for c in row]
            low = [(minus * c).imag for c in row]
            upper.append(cone_up + up)
            lower.append(cone_low + low)
            bound_up.append(gap * scale - up[1])
            bound_low.append(gap * scale - low[1])
        return upper + lower, bound_up + bound_low

    def _floating_points(self, q_free: list[float], u: list[float], end: list[list[complex]]):
        """Each point's height [m], x [m] and tangential speed [m/s] after the step, from the track's body rows."""
        turn, ground, rise = self._turn, self._ground, self._rise
        *base, pitch = q_free
        *rate, spin = u
        e = complex(math.cos(pitch), turn * math.sin(pitch))
        to_body = e * complex(0.0, -turn)
        heights, xs, slip = [], [], []
        for fixed, slide, (spun, along) in zip(self._fixed, self._slide, end):
            at = ground * (fixed + sum(map(mul, slide, base)) + to_body * spun)  # along and across the ground
            heights.append(at.imag if rise is None else at.imag - rise(at.real))
            xs.append(at.real)
            slip.append((ground * (sum(map(mul, slide, rate)) + spin * e * spun + e * along)).real)
        return heights, xs, slip
