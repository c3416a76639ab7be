"""Analytic assembly of one leg: joint positions and tree joint angles for a crank angle.

This gives :mod:`pasibot_pin.model.closure` a starting point on the right branch (coupler below
the line 1-3, knee forward, slider behind joint 4) and names the loop that cannot close
when the geometry is impossible. Newton's method on the Pinocchio model then refines it.

Every function takes one crank angle or an array of them (shape (N,)): a point is then an
array (N, 2) and a joint angle an array (N,), so a whole crank sweep is assembled in a few
numpy calls.

Coordinates are the leg frame of docs/reference.md §4: origin at the crank pivot 0, x towards the
rocker pivot 3, z up; units [m]; angles [rad], counter-clockwise positive.
"""

from __future__ import annotations

import math

import numpy as np

from pasibot_pin.caches import PerObjectCache
from pasibot_pin.errors import AssemblyError, ParameterError
from pasibot_pin.model import jet
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


LOOP_FIELDS: dict[str, tuple[str, ...]] = {
    "j2": ("K", "r1", "r2", "r3"),
    "j5": ("K", "r1", "r2", "r3", "r4", "r6", "r7", "r13"),
    "j4 (stabiliser)": ("K", "r1", "r2", "r3", "r8", "r12"),
    "j11": ("r4", "r8", "r9", "r10"),
    "j13": ("r5", "r9", "r10", "r11"),
}
"""Per loop of :func:`leg_points`, the design fields of the links that place its pivots and form its two
sides: the frame ratio K and the link ratios r1 .. r13 (each a length over the crank length L, the design
file's ``K`` and ``[ratios]``): the fields a user changes to make that loop close."""


def loop_fields(loop: str) -> tuple[str, ...]:
    """The design fields (``K``, ``r1`` .. ``r13``) the closure of ``loop`` depends on (all of them if unknown)."""
    return LOOP_FIELDS.get(loop, ("K", *(f"r{k}" for k in range(1, 14))))


def _fields_text(loop: str) -> str:
    names = loop_fields(loop)
    return f"change {', '.join(names[:-1])} or {names[-1]} (the design file's K and [ratios], in L)"


def _check_meet(d, r1: float, r2: float, loop: str, theta) -> None:
    """Raise :class:`~pasibot_pin.errors.AssemblyError` where two circles do not meet.

    It names ``loop``, the first such crank angle, and the design fields to change.
    """
    bad = ~((abs(r1 - r2) < d) & (d < r1 + r2))
    if np.any(bad):
        th = _first_bad(theta, bad)
        d_bad = float(np.atleast_1d(d)[np.argmax(np.atleast_1d(bad))])
        raise AssemblyError(
            f"loop {loop} cannot assemble at crank angle {math.degrees(th):.3f} deg "
            f"(theta = {th:.6f} rad): distance {d_bad:.6g} m between its pivots is outside "
            f"[{abs(r1 - r2):.6g}, {r1 + r2:.6g}] m; {_fields_text(loop)}",
            loop_fields(loop),
        )


def circle_meet(c1, r1: float, c2, r2: float, left: bool, loop: str, theta):
    """Intersection of two circles, on the left (or right) of the line c1 -> c2, on complex points x + i z [m].

    The points may be scalars, arrays (N,) or jets. With d = c2 - c1 and s = |d|^2 the point is
    c1 + d (alpha +- i beta), alpha = a / |d| = 1/2 + (r1^2 - r2^2) / (2 s) and beta = h / |d| =
    sqrt(r1^2 / s - alpha^2): no square root of s, few operations (each one is the chain rule for jets).

    Raises:
        DesignError: naming ``loop`` and the (first) crank angle where the circles do not meet.

    """
    d_vec = c2 - c1
    s = jet.abs2(d_vec)
    _check_meet(np.sqrt(jet.value(s)), r1, r2, loop, jet.value(theta))
    inv_s = 1.0 / s
    alpha = 0.5 + (0.5 * (r1**2 - r2**2)) * inv_s
    inner = r1**2 * inv_s - alpha * alpha
    if isinstance(inner, jet.Jet):
        inner.v = np.maximum(inner.v, 0.0)
    else:
        inner = np.maximum(inner, 0.0)
    beta = jet.sqrt(inner)
    # left of c1 -> c2 is the direction turned by +90 deg: i d
    return c1 + d_vec * (alpha + 1j * beta if left else alpha - 1j * beta)


def _complex(point: Point):
    """(..., 2) points as complex x + i z."""
    point = np.asarray(point, dtype=float)
    return point[..., 0] + 1j * point[..., 1]


def _real(point) -> Point:
    """Complex x + i z points as (..., 2) arrays."""
    point = np.asarray(point)
    return np.stack((point.real, point.imag), axis=-1)


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
        DesignError: when a loop cannot assemble (named, with the crank angle).

    """
    theta = np.asarray(theta, dtype=float)
    points = leg_points_complex(theta, geometry, variant)
    return {k: _real(np.broadcast_to(v, theta.shape)) for k, v in points.items()}


def leg_points_complex(theta, geometry: Geometry | None = None, variant: str | Variant = "spring") -> dict:
    """:func:`leg_points` as complex numbers x + i z (arrays like ``theta``) [m]: the one closed form.

    ``theta`` may be a :class:`~pasibot_pin.model.jet.Jet` (theta, theta_dot, theta_ddot): the
    points are then jets too, with their exact velocities and accelerations.

    Raises:
        DesignError: when a loop cannot assemble (named, with the crank angle).

    """
    g = geometry or Geometry()
    spec = get_variant(variant)
    if not isinstance(theta, jet.Jet):
        theta = np.asarray(theta, dtype=float)
    bare = jet.value(theta)
    if not np.all(np.isfinite(bare)):
        raise ParameterError(f"crank angle theta must be finite, got {_first_bad(bare, ~np.isfinite(bare))!r}")
    length = _lengths(g)
    p: dict = {}
    p["p0"] = 0j
    p["p3"] = complex(length[0], 0.0)
    p["p8"] = complex(length[0], -length[13])
    p["p1"] = length[1] * jet.exp_i(theta)
    # Joint 2: coupler hangs below the line 1-3 (right of 1 -> 3).
    p["p2"] = circle_meet(p["p1"], length[2] / 2, p["p3"], length[3], False, "j2", theta)
    # 2 is the coupler's mid-point (|p2 - p1| = L2 / 2 by construction): 4 = 2 p2 - p1
    p["p4"] = 2.0 * p["p2"] - p["p1"]
    # Joint 5: knee forward, left of 4 -> 8; its circle about 4 has radius L4 - L7.
    p["p5"] = circle_meet(p["p4"], length[4] - length[7], p["p8"], length[6], True, "j5", theta)
    u4 = (p["p5"] - p["p4"]) * (1.0 / (length[4] - length[7]))
    p["p6"] = p["p4"] + length[4] * u4
    # Joint 7: pantograph parallelogram 5-6-7-8, so |p7 - p6| = |p8 - p5| = L6.
    p["p7"] = p["p8"] + (p["p6"] - p["p5"])
    u5 = (p["p7"] - p["p6"]) * (1.0 / length[6])
    p["p13"] = p["p6"] + length[5] * u5
    if spec.extension:
        _extension_points(p, theta, g, length, u4, u5)
    return p


_LENGTHS: PerObjectCache[list[float]] = PerObjectCache()


def _lengths(g: Geometry) -> list[float]:
    """L0 .. L13 [m] (cached per geometry object; a Geometry is frozen)."""
    return _LENGTHS.get(g, lambda: [g.length(k) for k in range(14)])


def _extension_points(p: dict, theta, g: Geometry, length: list[float], u4, u5) -> None:
    """The parallel extension's points 9, 10, 11, 12 (complex), added to ``p``."""
    dz = p["p4"].imag + length[12]
    l8 = length[8]
    bad = np.abs(jet.value(dz)) >= l8
    if np.any(bad):
        th = _first_bad(jet.value(theta), bad)
        dz_bad = float(np.atleast_1d(np.abs(jet.value(dz)))[np.argmax(np.atleast_1d(bad))])
        raise AssemblyError(
            f"loop j4 (stabiliser) cannot assemble at crank angle {math.degrees(th):.3f} deg: "
            f"joint 4 is {dz_bad:.6g} m from the slider line, more than the link r8 x L = {l8:.6g} m; "
            + _fields_text("j4 (stabiliser)"),
            loop_fields("j4 (stabiliser)"),
        )
    p["p10"] = (p["p4"].real - jet.sqrt(l8**2 - dz * dz)) - 1j * length[12]
    u8 = (p["p4"] - p["p10"]) / l8
    p["p9"] = p["p10"] + (l8 / 2) * u8
    p["p11"] = p["p9"] + length[9] * u4
    p["p12"] = p["p11"] + length[11] * u5
    r = g.ratios
    if r["r9"] != r["r4"] or r["r8"] != 2 * r["r10"]:
        # 4-6-11-9 is no parallelogram: joint 11 is where L9 (from 9) meets L10 (from 6),
        # on the side nearer the parallelogram's point
        p["p11"] = _nearer(p["p9"], length[9], p["p6"], length[10], p["p11"], "j11", theta)
    if r["r11"] != r["r5"] or r["r9"] != r["r4"] or r["r8"] != 2 * r["r10"]:
        # 6-11-12-13 is no parallelogram: joint 12 is where L11 (from 11) meets the foot bar (from 13)
        guess = p["p11"] + length[11] * u5
        p["p12"] = _nearer(p["p11"], length[11], p["p13"], length[10], guess, "j13", theta)


FULL_TURN_SAMPLES: int = 720
"""Crank angles (every 0.5 deg) at which :func:`check_full_turn` assembles the leg."""


def check_full_turn(geometry: Geometry | None = None, variant: str | Variant = "spring") -> None:
    """Raise :class:`~pasibot_pin.errors.AssemblyError` unless one leg of ``variant`` assembles over a full turn.

    The analytic assembly (:func:`leg_points`) is tried every 0.5 deg. With the seed's link
    ratios the frame ratio K must lie in about (1.491, 3.0).

    Raises:
        AssemblyError: naming the loop, the first crank angle where it cannot close, and the design
            fields (K, r1 .. r13, in L) to change (its ``fields``).

    """
    g = geometry or Geometry()
    theta = np.linspace(0.0, 2 * math.pi, FULL_TURN_SAMPLES, endpoint=False)
    try:
        leg_points(theta, g, variant)
    except AssemblyError as err:
        raise AssemblyError(f"the crank cannot make a full turn with K = {g.K:g}: {err}", err.fields) from None


def _nearer(c1, r1: float, c2, r2: float, guess, loop: str, theta):
    """The intersection (complex) of two circles nearer to ``guess``, per sample (ValueError naming ``loop``)."""
    left = circle_meet(c1, r1, c2, r2, True, loop, theta)
    right = circle_meet(c1, r1, c2, r2, False, loop, theta)
    use_left = np.abs(jet.value(left - guess)) <= np.abs(jet.value(right - guess))
    return jet.where(use_left, left, right)


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


def joint_angles_from_points(p: dict, theta, variant: str | Variant = "spring", foot_angle=None):
    """:func:`leg_joint_angles` from the points of :func:`leg_points` (or :func:`leg_points_complex`)."""
    spec = get_variant(variant)
    theta = np.asarray(theta, dtype=float)
    q = joint_angles_complex(_as_complex(p), theta, spec, foot_angle)
    if theta.ndim == 0:
        return {k: float(v) for k, v in q.items()}
    return {k: np.broadcast_to(v, theta.shape).astype(float) for k, v in q.items()}


def _as_complex(p: dict) -> dict:
    """Points as complex x + i z, whether given so or as (..., 2) arrays."""
    return {k: v if np.iscomplexobj(v) else _complex(v) for k, v in p.items()}


def _dir(a, b):
    """Direction of a -> b for complex points or jets [rad] (the same arithmetic as :func:`_angle`)."""
    return jet.angle(b - a)


def joint_angles_complex(p: dict, theta, variant: str | Variant = "spring", foot_angle=None) -> dict:
    """Tree joint coordinates of one leg from complex points (:func:`leg_points_complex`) [rad, m].

    Values are arrays like the points (or scalars, or jets for jet points); ``j0_crank`` is
    ``theta`` itself. ``foot_angle`` (spring ankle) as in :func:`leg_joint_angles`; an array may
    hold NaN where the foot stays square to its shank (ankle coordinate 0).
    """
    spec = get_variant(variant)
    wrap = jet.wrap
    a12 = _dir(p["p1"], p["p4"])
    a46 = _dir(p["p4"], p["p6"])
    a613 = _dir(p["p6"], p["p13"])
    q = {
        "j0_crank": theta,
        "j1": wrap(a12 - theta),
        "j3": _dir(p["p3"], p["p2"]),
        "j4": wrap(a46 - a12),
        "j6": wrap(a613 - a46),
        "j8_l6": _dir(p["p8"], p["p5"]),
        "j8_l7": _dir(p["p8"], p["p7"]),
    }
    if spec.sole == "ankle":
        target = a613 + math.pi / 2 if foot_angle is None else foot_angle
        ankle = wrap(target - a613 - math.pi / 2)
        square = np.isnan(foot_angle) if foot_angle is not None and np.ndim(foot_angle) else None
        if square is not None and square.any():  # NaN entries: the foot square to its shank
            ankle = jet.where(square, 0.0, ankle)
        q["j13_ankle"] = ankle
    if spec.extension:
        a104 = _dir(p["p10"], p["p4"])
        a911 = _dir(p["p9"], p["p11"])
        a1112 = _dir(p["p11"], p["p12"])
        q["j10_slide"] = p["p10"].real
        q["j10"] = a104
        q["j9"] = wrap(a911 - a104)
        q["j11"] = wrap(a1112 - a911)
        q["j12"] = wrap(_dir(p["p12"], p["p13"]) - a1112)
        q["j6_l10"] = wrap(_dir(p["p6"], p["p11"]) - a46)
    return q


def sole_angle_from_points(p: dict, variant: str | Variant = "spring"):
    """Direction of the sole (heel -> toe) in the leg frame for a fixed-foot variant [rad], from its points.

    ``p``: the points of :func:`leg_points` (or complex ones). ``rigid`` (and ``spring`` with the foot
    square to the shank): shank direction + 90 deg. ``parallel``: the direction of the stabiliser
    10 -> 4. A float for scalar points, an array (N,) for arrays.
    """
    if get_variant(variant).sole == "stabiliser":
        out = _angle_any(p["p10"], p["p4"])
    else:
        out = _angle_any(p["p6"], p["p13"]) + math.pi / 2
    return float(out) if not isinstance(out, jet.Jet) and np.ndim(out) == 0 else out


def _angle_any(a, b):
    """Direction of a -> b for complex points, jets or (..., 2) arrays [rad]."""
    if isinstance(a, jet.Jet) or isinstance(b, jet.Jet) or np.iscomplexobj(a) or np.iscomplexobj(b):
        return _dir(a, b)
    return _angle(a, b)


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
