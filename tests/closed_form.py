"""Closed-form PASIBOT leg geometry, written for the tests only (independent of the package).

Points are complex numbers x + i*z in the leg frame, in units of the crank length L
(DESIGN.md §4). Nothing here imports pasibot_pin.
"""

from __future__ import annotations

import cmath
import math

K = 2.0


def _meet(centre_a: complex, radius_a: float, centre_b: complex, radius_b: float) -> tuple[complex, complex]:
    """Both intersections of two circles, (left of a->b, right of a->b)."""
    axis = centre_b - centre_a
    d = abs(axis)
    along = (radius_a**2 - radius_b**2 + d**2) / (2 * d)
    height = math.sqrt(radius_a**2 - along**2)
    unit = axis / d
    base = centre_a + along * unit
    return base + 1j * unit * height, base - 1j * unit * height


def leg(theta: float, k: float = K) -> dict[int | str, complex]:
    """Seed joints 0..13, toe/heel of the rigid foot, and the extension points, in units of L."""
    p: dict[int | str, complex] = {0: 0j, 3: complex(k, 0)}
    p[1] = cmath.exp(1j * theta)
    # joint 2: |2-1| = 2.5, |2-3| = 2.5, below the line 1-3 (the right-hand intersection of 1 -> 3)
    p[2] = _meet(p[1], 2.5, p[3], 2.5)[1]
    p[4] = p[1] + 2 * (p[2] - p[1])
    p[8] = p[3] - 12j
    # joint 5: |5-4| = 3, |5-8| = 6, knee forward (larger x)
    p[5] = max(_meet(p[4], 3.0, p[8], 6.0), key=lambda z: z.real)
    p[6] = p[4] + 3 * (p[5] - p[4])
    p[7] = p[8] + (p[6] - p[5])
    p[13] = p[6] + 3 * (p[7] - p[6])
    u = (p[13] - p[6]) / abs(p[13] - p[6])
    p["toe"] = p[13] + 1.5 * (1j * u)  # R(+90 deg) u
    p["heel"] = p[13] + 0.5 * (-1j * u)  # R(-90 deg) u
    # parallel extension: slider 10 on z = -4, behind 4, |10-4| = 4.2
    dz = p[4].imag + 4
    p[10] = complex(p[4].real - math.sqrt(4.2**2 - dz**2), -4)
    p[9] = (p[4] + p[10]) / 2
    p[11] = p[9] + (p[6] - p[4])
    p[12] = p[11] + (p[13] - p[6])
    f = (p[13] - p[12]) / abs(p[13] - p[12])
    p["toe_parallel"] = p[13] + 1.5 * f
    p["heel_parallel"] = p[13] - 2.6 * f
    return p
