"""A settled 3-D gait repeats itself: once a crank period brings the state back, the rest of the walk is known.

On flat ground the 3-D floor (:mod:`~pasibot_pin.dynamics.floor.engine3d`) is the same
everywhere and in every heading, and its free run steps on a grid that divides the crank period
(:meth:`~pasibot_pin.dynamics.floor.engine3d.Floor3D.time_grid`), so the cranks' schedule repeats
every N steps. If the state at step k is the state at step k - N moved by a horizontal motion g of
the floor (a turn psi about the vertical and a shift; the cranks one turn on), then every later step
is its predecessor N steps back moved by g: the gait is a relative periodic orbit, and simulating
it again would only redo the last period's arithmetic.

:class:`SettledGait` keeps the last period's steps (:class:`PeriodStep`), compares each new state
with the one a period before, and when every coordinate but the floor's motion agrees within
:data:`REPEAT_TOL` it returns g (:class:`FloorMotion`). From then on :meth:`SettledGait.replay`
serves the next steps: the step a period back, moved by g, stored back (so the period after that is
moved by g again). The judge hears every step, as in the simulation.

The friction pyramid's edges are fixed in the world, so a turned gait is exactly the same only
where its friction stays inside the pyramid; the turns of a settled walker are a few 1e-7 rad per
period, and ``tests/test_floor3d_repeat.py`` holds the repeated walk to the simulated one.

Units: SI, angles [rad].
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from pasibot_pin.dynamics.floor.settings import step_count

REPEAT_TOL = 1e-9
"""Largest difference of the state and the state a period back moved by the floor's motion, per
coordinate [m, rad, m/s, rad/s], for the gait to count as settled (settled walkers repeat to 1e-10)."""

NQ_ROOT, NV_ROOT = 7, 6
"""The free-flyer root's configuration (x, y, z, quaternion) and velocity sizes [-]."""


def period_grid(duration: float, dt: float, omega: float, most: int) -> tuple[float, int]:
    """A time step of at most ``dt`` [s] dividing the crank period 2 pi / omega, and the steps to cover ``duration``.

    Args:
        duration: the run's length [s].
        dt: the longest time step [s].
        omega: the cranks' speed [rad/s], > 0.
        most: the most steps a run may take.

    Returns:
        (h [s], steps): the crank schedule repeats every 2 pi / (omega h) steps on the grid, an even number.

    """
    half = math.pi / omega  # whole steps in half a period too: a step map's run of one walking step ends on the grid
    h = half / step_count(half, dt, most)
    return h, step_count(duration, h, most)


class PeriodStep(NamedTuple):
    """What one step leaves: the state and what the judge reads of it (or a period's steps, stacked on a first axis).

    Attributes:
        q: configuration (nq,) (the free-flyer root first).
        u: velocity (nv,), the root's world-aligned.
        normal: each corner's normal force [N] (k,).
        power: each motor's power [W] (motors,).
        points: each corner's world position [m] (k, 3).
        velocity: each corner's velocity in the ground's frame (normal, along, across) [m/s] (k, 3).
        attitude: the hip's roll, pitch and yaw (:func:`~pasibot_pin.model.spatial.roll_pitch_yaw`) [rad] (3,):
            a turn about the vertical adds to the yaw alone.
        clearance: the soles' least distance [m] where it was measured, else NaN (a rigid motion keeps it).

    """

    q: np.ndarray
    u: np.ndarray
    normal: np.ndarray
    power: np.ndarray
    points: np.ndarray
    velocity: np.ndarray
    attitude: np.ndarray
    clearance: float | np.ndarray = math.nan


class Replayed(NamedTuple):
    """One repeated step as the run needs it: the state, the judge's view, and the clearance if known.

    Attributes:
        q, u: configuration and velocity.
        normal: each corner's normal force [N].
        power: each motor's power [W].
        feet: the judge's right and left :class:`~pasibot_pin.dynamics.verdict.FootSample`
            (:meth:`~pasibot_pin.dynamics.floor.engine3d.Floor3D.views`).
        attitude: roll, pitch, yaw [rad].
        clearance: the soles' least distance [m], NaN where not yet measured.

    """

    q: np.ndarray
    u: np.ndarray
    normal: np.ndarray
    power: tuple[float, ...]
    feet: tuple
    attitude: tuple[float, float, float]
    clearance: float


class FloorMotion(NamedTuple):
    """A horizontal motion of the flat floor: a turn psi about the vertical, then a shift, and the legs' whole turns.

    Attributes:
        psi: the turn [rad].
        cos, sin: of psi [-].
        half: cos and sin of psi / 2 (the turn as a quaternion) [-].
        shift: the horizontal shift (x, y) [m].
        turns: what each configuration coordinate gains (nq,): whole turns of the legs' angles, 0 elsewhere [rad].

    """

    psi: float
    cos: float
    sin: float
    half: tuple[float, float]
    shift: tuple[float, float]
    turns: np.ndarray

    def apply(self, step: PeriodStep) -> PeriodStep:
        """``step`` (or a period's steps, stacked) moved: its forces, powers, roll, pitch and clearance kept."""
        c, s = self.cos, self.sin
        q, u = self.state(step)
        turn = np.array([[c, s], [-s, c]])  # (x, y) rows times this: turned
        points = step.points.copy()
        points[..., :2] = step.points[..., :2] @ turn + self.shift
        velocity = step.velocity.copy()  # (normal, along, across): the flat floor's (z, x, y)
        velocity[..., 1:] = step.velocity[..., 1:] @ turn
        attitude = step.attitude.copy()
        yaw = step.attitude[..., 2] + self.psi
        attitude[..., 2] = yaw - (2.0 * math.pi) * np.round(yaw / (2.0 * math.pi))
        return step._replace(q=q, u=u, points=points, velocity=velocity, attitude=attitude)

    def state(self, step: PeriodStep) -> tuple[np.ndarray, np.ndarray]:
        """The configuration and velocity of ``step`` (or stacked steps) moved: :meth:`apply`'s (q, u) alone."""
        c, s = self.cos, self.sin
        q = step.q + self.turns
        x, y = step.q[..., 0], step.q[..., 1]
        q[..., 0], q[..., 1] = c * x - s * y + self.shift[0], s * x + c * y + self.shift[1]
        qx, qy, qz, qw = (step.q[..., i] for i in range(3, 7))
        hc, hs = self.half  # the turn's quaternion (0, 0, hs, hc) times the hip's
        q[..., 3], q[..., 4] = hc * qx - hs * qy, hc * qy + hs * qx
        q[..., 5], q[..., 6] = hc * qz + hs * qw, hc * qw - hs * qz
        u = step.u.copy()
        for i in (0, 3):  # the hip's linear and angular velocity, turned
            a, b = step.u[..., i], step.u[..., i + 1]
            u[..., i], u[..., i + 1] = c * a - s * b, s * a + c * b
        return q, u


def motion_between(before: np.ndarray, after: np.ndarray, angular: np.ndarray) -> FloorMotion:
    """The floor's motion that brings the configuration ``before`` nearest to ``after``.

    The turn is the relative rotation's about the vertical, the shift the hip's horizontal
    displacement left by it, and the legs' angles gain the whole turns they made (``angular``:
    mask (nq,) of the legs' angular coordinates).
    """
    relative = _rotation(after) @ _rotation(before).T
    psi = math.atan2(relative[1, 0], relative[0, 0])
    c, s = math.cos(psi), math.sin(psi)
    shift = (float(after[0]) - (c * before[0] - s * before[1]), float(after[1]) - (s * before[0] + c * before[1]))
    turns = np.where(angular, np.round((after - before) / (2.0 * math.pi)) * (2.0 * math.pi), 0.0)
    return FloorMotion(psi, c, s, (math.cos(0.5 * psi), math.sin(0.5 * psi)), shift, turns)


def _difference(a: tuple[np.ndarray, np.ndarray], b: PeriodStep) -> float:
    """The largest difference of a state (q, u) and a step's, a quaternion and its negative the same."""
    q = np.abs(a[0] - b.q)
    q[3:7] = np.minimum(q[3:7], np.abs(a[0][3:7] + b.q[3:7]))
    return max(float(q.max()), float(np.abs(a[1] - b.u).max()))


def _rotation(q: np.ndarray) -> np.ndarray:
    return pin.Quaternion(np.asarray(q[3:7], dtype=float)).normalized().toRotationMatrix()


class SettledGait:
    """Watches a run for a gait that repeats every period up to the floor's motion, then repeats it.

    Args:
        period: the crank period in steps N [-].
        first: the first step whose state may be compared (the cranks' ramp over, with a period
            before it also past the ramp) [-].
        angular: mask (nq,) of the legs' angular coordinates (whole turns are the same shape).
        views: the judge's feet in a period's stacked steps, one pair per step (the run's).

    Attributes:
        motion: the floor's motion per period once the gait has settled, else ``None``.

    """

    def __init__(self, period: int, first: int, angular: np.ndarray, views: Callable[[PeriodStep], list]) -> None:
        self.period, self.first, self.angular, self.views = period, max(first, period), angular, views
        self._steps: list[PeriodStep | None] = [None] * period
        self._k = 0
        self.motion: FloorMotion | None = None
        self._stack: PeriodStep | None = None  # the period being repeated, and its views
        self._rows: list[Replayed] = []

    def push(self, step: PeriodStep) -> bool:
        """Keep the next simulated step; ``True`` when it shows the gait settled (:attr:`motion` is set)."""
        self._k += 1
        slot = self._k % self.period
        before, self._steps[slot] = self._steps[slot], step
        if self._k < self.first or before is None:
            return False
        motion = motion_between(before.q, step.q, self.angular)
        if _difference(motion.state(before), step) <= REPEAT_TOL:
            self.motion = motion
            first = self._k + 1  # the last period, oldest first
            steps = [self._steps[(first + j) % self.period] for j in range(self.period)]
            self._stack = PeriodStep(*(np.array(field, dtype=float) for field in zip(*steps)))
            self._j = self.period
            return True
        return False

    def measured(self, clearance: float) -> None:
        """Keep the soles' clearance [m] measured at the step :meth:`replay` gave last (the periods after reuse it)."""
        assert self._stack is not None
        self._stack.clearance[self._j - 1] = clearance  # type: ignore[index]

    def replay(self) -> Replayed:
        """The next step: the step a period back moved by :attr:`motion` (a whole period at a time)."""
        assert self.motion is not None and self._stack is not None, "replay() before the gait settled"
        if self._j == self.period:
            self._stack = self.motion.apply(self._stack)
            self._rows = self._replayed(self._stack)
            self._j = 0
        row = self._rows[self._j]
        self._j += 1
        clearance = float(self._stack.clearance[self._j - 1])  # type: ignore[index]
        return row if clearance == row.clearance or math.isnan(clearance) else row._replace(clearance=clearance)

    def _replayed(self, stack: PeriodStep) -> list[Replayed]:
        views = self.views(stack)
        power = stack.power.tolist()
        attitude = stack.attitude.tolist()
        clearance = stack.clearance.tolist()  # type: ignore[union-attr]
        return [
            Replayed(
                stack.q[j], stack.u[j], stack.normal[j], tuple(power[j]), views[j], tuple(attitude[j]), clearance[j]
            )
            for j in range(self.period)
        ]
