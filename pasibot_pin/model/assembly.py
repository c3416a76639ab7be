"""Analytic assembly of one leg: joint positions and tree joint angles for a crank angle.

This gives :mod:`pasibot_pin.model.closure` a starting point on the right branch (coupler below
the line 1-3, knee forward, slider behind joint 4) and names the loop that cannot close
when the geometry is impossible. Newton's method on the Pinocchio model then refines it.

Every function takes one crank angle or an array of them (shape (N,)): a point is then an
array (N, 2) and a joint angle an array (N,), so a whole crank sweep is assembled in a few
numpy calls.

Coordinates are the leg frame of DESIGN §4: origin at the crank pivot 0, x towards the
rocker pivot 3, z up; units [m]; angles [rad], counter-clockwise positive.
"""

from __future__ import annotations

import math

import numpy as np

from pasibot_pin.model.params import Geometry
from pasibot_pin.model.variants import Variant, get_variant

Point = np.ndarray
"""A point (2,) [m], or an array of points (N, 2) for an array of crank angles."""


def _angle(a: Point, b: Point):
    """Direction of the vector a -> b [rad], counter-clockwise from +x."""
    return np.arctan2(b[..., 1] - a[..., 1], b[..., 0] - a[..., 0])


def wrap(angle):
    """Wrap an angle (or an array of them) to (-pi, pi] [rad]."""
    return np.arctan2(np.sin(angle), np.cos(angle))


def _first_bad(theta, bad) -> float:
    return float(np.atleast_1d(theta)[np.argmax(np.atleast_1d(bad))])


def circle_intersection(c1: Point, r1: float, c2: Point, r2: float, left: bool, loop: str, theta) -> Point:
    """Intersection of two circles, on the left (or right) of the line c1 -> c2.

    Raises:
        ValueError: naming ``loop`` and the (first) crank angle where the circles do not meet.

    """
    d_vec = c2 - c1
    d = np.hypot(d_vec[..., 0], d_vec[..., 1])
    bad = ~((abs(r1 - r2) < d) & (d < r1 + r2))
    if np.any(bad):
        th = _first_bad(theta, bad)
        d_bad = float(np.atleast_1d(d)[np.argmax(np.atleast_1d(bad))])
        raise ValueError(
            f"loop {loop} cannot assemble at crank angle {math.degrees(th):.3f} deg "
            f"(theta = {th:.6f} rad): distance {d_bad:.6g} m between its pivots is outside "
            f"[{abs(r1 - r2):.6g}, {r1 + r2:.6g}] m; check K and the link ratios"
        )
    a = (r1**2 - r2**2 + d**2) / (2 * d)
    h = np.sqrt(np.maximum(r1**2 - a**2, 0.0))
    u = d_vec / d[..., None]
    normal = np.stack((-u[..., 1], u[..., 0]), axis=-1)  # left of c1 -> c2
    return c1 + a[..., None] * u + (h if left else -h)[..., None] * normal


def _unit(vec: Point) -> Point:
    return vec / np.linalg.norm(vec, axis=-1, keepdims=True)


def leg_points(theta, geometry: Geometry | None = None, variant: str | Variant = "spring") -> dict[str, Point]:
    """Joint positions of one leg in the leg frame [m].

    Args:
        theta: crank angle [rad], counter-clockwise from the line 0 -> 3; a float or an
            array (N,).
        geometry: leg geometry.
        variant: adds the parallel-extension points 9, 10, 11, 12 for ``parallel``.

    Returns:
        Points keyed ``'p0'`` .. ``'p13'``: 2-vectors (x, z), or (N, 2) arrays.

    Raises:
        ValueError: when a loop cannot assemble (named, with the crank angle).

    """
    g = geometry or Geometry()
    spec = get_variant(variant)
    theta = np.asarray(theta, dtype=float)
    if not np.all(np.isfinite(theta)):
        raise ValueError(f"crank angle theta must be finite, got {_first_bad(theta, ~np.isfinite(theta))!r}")
    shape = theta.shape + (2,)
    p: dict[str, Point] = {}
    p["p0"] = np.zeros(shape)
    p["p3"] = np.broadcast_to(np.array([g.length(0), 0.0]), shape)
    p["p8"] = np.broadcast_to(np.array([g.length(0), -g.length(13)]), shape)
    p["p1"] = g.length(1) * np.stack((np.cos(theta), np.sin(theta)), axis=-1)
    # Joint 2: coupler hangs below the line 1-3 (right of 1 -> 3).
    p["p2"] = circle_intersection(p["p1"], g.length(2) / 2, p["p3"], g.length(3), False, "j2", theta)
    u2 = _unit(p["p2"] - p["p1"])
    p["p4"] = p["p1"] + g.length(2) * u2
    # Joint 5: knee forward, left of 4 -> 8.
    p["p5"] = circle_intersection(p["p4"], g.length(4) - g.length(7), p["p8"], g.length(6), True, "j5", theta)
    u4 = _unit(p["p5"] - p["p4"])
    p["p6"] = p["p4"] + g.length(4) * u4
    # Joint 7: pantograph parallelogram 5-6-7-8.
    p["p7"] = p["p8"] + (p["p6"] - p["p5"])
    u5 = _unit(p["p7"] - p["p6"])
    p["p13"] = p["p6"] + g.length(5) * u5
    if spec.extension:
        dz = p["p4"][..., 1] + g.length(12)
        l8 = g.length(8)
        bad = np.abs(dz) >= l8
        if np.any(bad):
            th = _first_bad(theta, bad)
            dz_bad = float(np.atleast_1d(np.abs(dz))[np.argmax(np.atleast_1d(bad))])
            raise ValueError(
                f"loop j4 (stabiliser) cannot assemble at crank angle {math.degrees(th):.3f} deg: "
                f"joint 4 is {dz_bad:.6g} m from the slider line, more than L8 = {l8:.6g} m"
            )
        p["p10"] = np.stack((p["p4"][..., 0] - np.sqrt(l8**2 - dz**2), np.full(theta.shape, -g.length(12))), axis=-1)
        u8 = (p["p4"] - p["p10"]) / l8
        p["p9"] = p["p10"] + (l8 / 2) * u8
        p["p11"] = p["p9"] + g.length(9) * u4
        p["p12"] = p["p11"] + g.length(11) * u5
        r = g.ratios
        if r["r9"] != r["r4"] or r["r8"] != 2 * r["r10"]:
            # 4-6-11-9 is no parallelogram: joint 11 is where L9 (from 9) meets L10 (from 6),
            # on the side nearer the parallelogram's point
            p["p11"] = _nearer(p["p9"], g.length(9), p["p6"], g.length(10), p["p11"], "j11", theta)
        if r["r11"] != r["r5"] or r["r9"] != r["r4"] or r["r8"] != 2 * r["r10"]:
            # 6-11-12-13 is no parallelogram: joint 12 is where L11 (from 11) meets the foot bar (from 13)
            guess = p["p11"] + g.length(11) * u5
            p["p12"] = _nearer(p["p11"], g.length(11), p["p13"], g.length(10), guess, "j13", theta)
    return p


FULL_TURN_SAMPLES: int = 720
"""Crank angles (every 0.5 deg) at which :func:`check_full_turn` assembles the leg."""


def check_full_turn(geometry: Geometry | None = None, variant: str | Variant = "spring") -> None:
    """Raise ``ValueError`` unless one leg of ``variant`` assembles at every crank angle of a full turn.

    The analytic assembly (:func:`leg_points`) is tried every 0.5 deg. With the seed's link
    ratios the frame ratio K must lie in about (1.491, 3.0).

    Raises:
        ValueError: naming the loop and the first crank angle where it cannot close.

    """
    g = geometry or Geometry()
    theta = np.linspace(0.0, 2 * math.pi, FULL_TURN_SAMPLES, endpoint=False)
    try:
        leg_points(theta, g, variant)
    except ValueError as err:
        raise ValueError(f"the crank cannot make a full turn with K = {g.K:g}: {err}") from None


def _nearer(c1: Point, r1: float, c2: Point, r2: float, guess: Point, loop: str, theta) -> Point:
    """The intersection of two circles nearer to ``guess`` (per sample); ValueError naming ``loop`` if none."""
    left = circle_intersection(c1, r1, c2, r2, True, loop, theta)
    right = circle_intersection(c1, r1, c2, r2, False, loop, theta)
    use_left = np.linalg.norm(left - guess, axis=-1) <= np.linalg.norm(right - guess, axis=-1)
    return np.where(use_left[..., None], left, right)


def leg_joint_angles(
    theta,
    geometry: Geometry | None = None,
    variant: str | Variant = "spring",
    foot_angle=None,
) -> dict[str, float | np.ndarray]:
    """Tree joint coordinates of one leg (names without the side prefix).

    Args:
        theta: crank angle [rad] (a float or an array (N,)).
        geometry: leg geometry.
        variant: leg variant.
        foot_angle: for ``spring``, the sole's direction in the leg frame [rad] (a float or
            an array like ``theta``; default: perpendicular to the shank, as the rigid foot).

    Returns:
        ``{joint name: coordinate}`` [rad], the slider coordinate in [m]: floats for a float
        ``theta``, arrays (N,) otherwise.

    """
    spec = get_variant(variant)
    theta = np.asarray(theta, dtype=float)
    return joint_angles_from_points(leg_points(theta, geometry, spec), theta, spec, foot_angle)


def joint_angles_from_points(p: dict[str, Point], theta, variant: str | Variant = "spring", foot_angle=None):
    """:func:`leg_joint_angles` from the points of :func:`leg_points` at ``theta`` (computed once)."""
    spec = get_variant(variant)
    theta = np.asarray(theta, dtype=float)
    a12 = _angle(p["p1"], p["p4"])
    a46 = _angle(p["p4"], p["p6"])
    a613 = _angle(p["p6"], p["p13"])
    q = {
        "j0_crank": theta,
        "j1": wrap(a12 - theta),
        "j3": _angle(p["p3"], p["p2"]),
        "j4": wrap(a46 - a12),
        "j6": wrap(a613 - a46),
        "j8_l6": _angle(p["p8"], p["p5"]),
        "j8_l7": _angle(p["p8"], p["p7"]),
    }
    if spec.sole == "ankle":
        target = a613 + math.pi / 2 if foot_angle is None else foot_angle
        q["j13_ankle"] = wrap(target - a613 - math.pi / 2)
    if spec.extension:
        a104 = _angle(p["p10"], p["p4"])
        a911 = _angle(p["p9"], p["p11"])
        a1112 = _angle(p["p11"], p["p12"])
        q["j10_slide"] = p["p10"][..., 0]
        q["j10"] = a104
        q["j9"] = wrap(a911 - a104)
        q["j11"] = wrap(a1112 - a911)
        q["j12"] = wrap(_angle(p["p12"], p["p13"]) - a1112)
        q["j6_l10"] = wrap(_angle(p["p6"], p["p11"]) - a46)
    if theta.ndim == 0:
        return {k: float(v) for k, v in q.items()}
    return {k: np.broadcast_to(v, theta.shape).astype(float) for k, v in q.items()}


def sole_angle(theta, geometry: Geometry | None = None, variant: str | Variant = "spring"):
    """Direction of the sole (heel -> toe) in the leg frame for a fixed-foot variant [rad].

    ``rigid`` (and ``spring`` with the foot square to the shank): shank direction + 90 deg.
    ``parallel``: the direction of the stabiliser 10 -> 4. A float for a float ``theta``,
    an array (N,) for an array.
    """
    return sole_angle_from_points(leg_points(theta, geometry, variant), variant)


def sole_angle_from_points(p: dict[str, Point], variant: str | Variant = "spring"):
    """:func:`sole_angle` from the points of :func:`leg_points` (computed once)."""
    if get_variant(variant).sole == "stabiliser":
        out = _angle(p["p10"], p["p4"])
    else:
        out = _angle(p["p6"], p["p13"]) + math.pi / 2
    return float(out) if np.ndim(out) == 0 else out


def _between(a: Point, b: Point):
    """Angle between the vectors a and b (rows), in [0, pi] [rad]."""
    cross = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    dot = a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]
    return np.abs(np.arctan2(cross, dot))


def transmission_angles(p: dict[str, Point], variant: str | Variant = "spring") -> dict[str, np.ndarray]:
    """Transmission angle of each closed loop, from the points of :func:`leg_points` [rad].

    The angle between the two links that meet at the loop's closing joint: at 0 or pi the two
    circles are tangent, the loop is singular (it locks or may switch branch). The
    *distance to singularity* of a loop is min(gamma, pi - gamma).

    Returns:
        ``{loop: gamma}``: ``j2`` (coupler L2 and rocker L3 at joint 2), ``j5`` (L4 and L6 at the
        knee 5) and, for the parallel extension, ``j4`` (the stabiliser L8 and the normal of the
        slider line at joint 10: 0 or pi when L8 stands square to the slider, its dead point).
        Arrays like the points' first axis.

    """
    out = {
        "j2": _between(p["p1"] - p["p2"], p["p3"] - p["p2"]),
        "j5": _between(p["p4"] - p["p5"], p["p8"] - p["p5"]),
    }
    if get_variant(variant).extension:
        out["j4"] = _between(p["p4"] - p["p10"], np.broadcast_to(np.array([0.0, 1.0]), p["p10"].shape))
    return out
