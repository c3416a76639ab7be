"""The ground a foot stands on: its height, normal and friction at a point.

A :class:`Ground` is a plane through the origin: the flat floor (:meth:`Ground.flat`) or a slope
that rises along +x by a given angle (:meth:`Ground.slope`, uphill positive). It gives a point's
gap (its signed distance above the plane, negative inside) and the contact frame: the normal and
two tangents, the first along the slope's fall line (+x on the flat floor), the second across it
(+y). The 3-D floor (:mod:`pasibot_pin.dynamics.floor.engine3d`) takes its contact rows from here.

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


def check_mu(mu: object) -> float:
    """``mu`` as a float if it is a friction coefficient in [0, :data:`MAX_MU`], else one line naming it."""
    if isinstance(mu, bool) or not isinstance(mu, numbers.Real) or not (0.0 <= float(mu) <= MAX_MU):  # NaN fails
        raise ParameterError(f"parameter 'mu' must be a friction coefficient in [0, {MAX_MU:g}], got {mu!r}")
    return float(mu)


@dataclass(frozen=True)
class Ground:
    """A planar ground through the origin.

    Attributes:
        angle: its slope, rising along +x [rad] (0: the flat floor).
        mu: Coulomb friction between a sole and the ground [-].

    """

    angle: float = 0.0
    mu: float = 0.8

    def __post_init__(self) -> None:
        if not (isinstance(self.angle, (int, float)) and abs(self.angle) <= MAX_SLOPE):
            raise ParameterError(
                f"parameter 'slope' = {self.angle!r} rad is outside [-{MAX_SLOPE:.4g}, {MAX_SLOPE:.4g}] "
                f"(+-{math.degrees(MAX_SLOPE):g} deg)"
            )
        check_mu(self.mu)

    @classmethod
    def flat(cls, mu: float = 0.8) -> Ground:
        """The flat floor, z = 0."""
        return cls(0.0, mu)

    @classmethod
    def slope(cls, degrees: float, mu: float = 0.8) -> Ground:
        """A slope of ``degrees`` [deg], uphill along +x."""
        return cls(math.radians(float(degrees)), mu)

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
        """Each point's signed distance above the ground (points (k, 3) [m]) (k,) [m]."""
        return np.asarray(points, dtype=float) @ self.normal
