"""The ground a foot stands on: its height, normal and friction at a point.

A :class:`Ground` is a plane through the origin: the flat floor (:meth:`Ground.flat`) or a slope
that rises along +x by a given angle (:meth:`Ground.slope`, uphill positive), with at most one
step edge on it (:meth:`Ground.step`): at ``step_at`` along the ground its height jumps by
``step_height`` (up positive). It gives a point's gap (its signed distance above the tread under it,
negative inside) and the contact frame: the normal and two tangents, the first along the slope's
fall line (+x on the flat floor), the second across it (+y). Both floors take their contact rows
from here: the planar one (:meth:`Ground.planar_gaps`, :attr:`Ground.turn`) in its general and its
tracked step, the 3-D one (:mod:`pasibot_pin.dynamics.floor.engine3d`, :meth:`Ground.gap`).

The step edge is its two treads only: the height is a step function of the position along the
ground, the tread under a point is the one it is over, and the normal is the treads' normal. The riser
is not a contact surface: a contact point that crosses it below the upper tread has hit the riser,
and :meth:`Ground.riser_hit` names it (a walk ``tripped``: the planar floor stops there). Between heel
and toe the sole is not a contact either, so the edge's corner may lie inside a sole that
straddles it, by less than ``|step_height|`` (its two ends stand on the two treads): the model is
for steps small against the foot.

Units: SI, lengths [m], angles [rad].
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from pasibot_pin.errors import ParameterError

MAX_MU = 10.0
"""Largest Coulomb friction coefficient a sole and a ground may have [-] (every mu's one range)."""
MAX_SLOPE = math.radians(20.0)
"""Steepest slope a ground may have [rad] (every slope's one range: the floor's settings, the CLI's --slope)."""
MAX_STEP_HEIGHT = 0.2
"""Highest step edge, up or down, a ground may have [m] (every step height's one range)."""
MAX_STEP_AT = 1000.0
"""Farthest a step edge may be from the origin along the ground, either way [m]."""
RISER_DEPTH = 1e-5
"""A contact point more than this below the tread it is over has come through the riser [m] (the
step's contact rows leave a point at most about 1e-6 m inside a tread)."""


def check_mu(mu: object) -> float:
    """``mu`` as a float if it is a friction coefficient in [0, :data:`MAX_MU`], else one line naming it."""
    if isinstance(mu, bool) or not isinstance(mu, numbers.Real) or not (0.0 <= float(mu) <= MAX_MU):  # NaN fails
        raise ParameterError(f"parameter 'mu' must be a friction coefficient in [0, {MAX_MU:g}], got {mu!r}")
    return float(mu)


@dataclass(frozen=True)
class Ground:
    """A planar ground through the origin, with at most one step edge (see the module docstring).

    Attributes:
        angle: its slope, rising along +x [rad] (0: the flat floor).
        mu: Coulomb friction between a sole and the ground [-].
        step_at: where the step edge is, along the ground from the origin [m].
        step_height: how far the ground rises there [m] (negative: a step down; 0: no step).

    """

    angle: float = 0.0
    mu: float = 0.8
    step_at: float = 0.0
    step_height: float = 0.0

    def __post_init__(self) -> None:
        if not (isinstance(self.angle, (int, float)) and abs(self.angle) <= MAX_SLOPE):
            raise ParameterError(
                f"parameter 'slope' = {self.angle!r} rad is outside [-{MAX_SLOPE:.4g}, {MAX_SLOPE:.4g}] "
                f"(+-{math.degrees(MAX_SLOPE):g} deg)"
            )
        check_mu(self.mu)
        check_step(self.step_height, self.step_at)

    @classmethod
    def flat(cls, mu: float = 0.8) -> Ground:
        """The flat floor, z = 0."""
        return cls(0.0, mu)

    @classmethod
    def slope(cls, degrees: float, mu: float = 0.8) -> Ground:
        """A slope of ``degrees`` [deg], uphill along +x."""
        return cls(math.radians(float(degrees)), mu)

    @classmethod
    def step(cls, height: float, at: float, mu: float = 0.8) -> Ground:
        """The flat floor with a step edge ``height`` [m] high (down if negative) at x = ``at`` [m]."""
        return cls(0.0, mu, float(at), float(height))

    @property
    def has_step(self) -> bool:
        """True when the ground has a step edge (a height other than 0)."""
        return self.step_height != 0.0

    @property
    def turn(self) -> complex:
        """The planar ground's frame, e^(-i angle): a world point x + i z times it is along + i across [-]."""
        return complex(math.cos(self.angle), -math.sin(self.angle))

    def rise(self, along: float) -> float:
        """The tread's height at ``along`` [m] along the ground: ``step_height`` past the edge, else 0 [m]."""
        return self.step_height if along >= self.step_at else 0.0

    def world(self, along: float, across: float = 0.0) -> tuple[float, float]:
        """The world (x, z) [m] of the point ``along`` the ground and ``across`` it (up its normal) [m]."""
        c, s = math.cos(self.angle), math.sin(self.angle)
        return along * c - across * s, along * s + across * c

    def treads(self, x_start: float, x_end: float) -> list[tuple[float, float, float]]:
        """The treads under the world's ``x_start`` to ``x_end`` [m]: (along from, along to, height) each [m].

        One tread on a plain ground; two where the step edge lies between (the riser joins them at
        ``step_at``, along the normal). The ends are where the treads' surface reaches those x.
        """
        if not (math.isfinite(x_start) and math.isfinite(x_end) and x_end > x_start):
            raise ParameterError(f"parameters 'x_start', 'x_end' must be finite and increasing, got {x_start}, {x_end}")
        start, end = self._along(x_start), self._along(x_end)
        if self.has_step and start < self.step_at < end:
            return [(start, self.step_at, 0.0), (self.step_at, end, self.step_height)]
        return [(start, end, self.rise(start))]

    def _along(self, x: float) -> float:
        """Where the tread under the world's ``x`` [m] is, along the ground [m] (x = a cos - rise(a) sin)."""
        c, s = math.cos(self.angle), math.sin(self.angle)
        return (x + self.rise(x / c) * s) / c

    def height(self, x: float) -> float:
        """The ground's height z [m] under the world's ``x`` [m] (the tread it is over)."""
        along = self._along(x)
        return self.world(along, self.rise(along))[1]

    def surface(self, x_start: float, x_end: float) -> np.ndarray:
        """The ground's line in the x-z plane under the world's ``x_start`` to ``x_end`` [m]: (k, 2) (x, z) [m].

        Its treads (:meth:`treads`), joined by the riser where there is a step edge: what a side view draws.
        """
        points = []
        for a, b, height in self.treads(x_start, x_end):
            points += [self.world(a, height), self.world(b, height)]
        return np.array(points)

    def planar_gaps(self, rows: np.ndarray) -> np.ndarray:
        """Each planar point's gap above its tread (rows: along + i across the ground, complex (k,) [m]) (k,) [m]."""
        if not self.has_step:
            return rows.imag
        return rows.imag - np.where(rows.real >= self.step_at, self.step_height, 0.0)

    def riser_hit(self, gaps: list[float]) -> int | None:
        """The first point that came through the riser, or None (``gaps``: each point's gap after a step [m]).

        The contact rows keep every point on its tread (to about 1e-6 m): only a point that crossed the
        edge below the upper tread is more than :data:`RISER_DEPTH` inside one.
        """
        if self.has_step:
            for k, gap in enumerate(gaps):
                if gap < -RISER_DEPTH:
                    return k
        return None

    @property
    def normal(self) -> np.ndarray:
        """The outward unit normal (3,) [-]."""
        return np.array([-math.sin(self.angle), 0.0, math.cos(self.angle)])

    @property
    def tangents(self) -> np.ndarray:
        """Two unit tangents (2, 3): along the fall line (uphill, +x on the flat) and across it (+y) [-]."""
        return np.array([[math.cos(self.angle), 0.0, math.sin(self.angle)], [0.0, 1.0, 0.0]])

    def frame(self) -> np.ndarray:
        """The contact frame (3, 3): rows normal, first tangent, second tangent [-]."""
        return np.vstack((self.normal, self.tangents))

    def gap(self, points: np.ndarray) -> np.ndarray:
        """Each point's signed distance above the tread under it (points (k, 3) [m]) (k,) [m]."""
        points = np.asarray(points, dtype=float)
        if not self.has_step:
            return points @ self.normal
        along = points @ self.tangents[0]
        return points @ self.normal - np.where(along >= self.step_at, self.step_height, 0.0)


def check_step(height: object, at: object) -> tuple[float, float]:
    """A step edge's (height, position) [m] as floats, or one line naming the parameter out of its range."""
    out = []
    for name, value, limit in (("step_height", height, MAX_STEP_HEIGHT), ("step_at", at, MAX_STEP_AT)):
        if isinstance(value, bool) or not isinstance(value, numbers.Real) or not abs(float(value)) <= limit:
            raise ParameterError(f"parameter {name!r} must be a length in [-{limit:g}, {limit:g}] m, got {value!r}")
        out.append(float(value))
    return out[0], out[1]
