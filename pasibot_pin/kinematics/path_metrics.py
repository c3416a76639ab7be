"""One leg's straight-line metrics and the K sweep (seed §4, §5).

:func:`straight_line_metrics` gives the stance stroke, the ankle band, the straightness
deviation, the swing lift, the crank-angle span near the ground and the foot pitch of a one-leg
robot, each extreme refined on the closure manifold (golden section, bisection);
:func:`k_sweep` repeats the leg cycle and the metrics for several frame ratios K (seed Fig 4.2.4).
Points (x, z) [m]; angles [rad].
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from pasibot_pin.constraints import planar_pitch
from pasibot_pin.errors import ParameterError
from pasibot_pin.kinematics.leg import (
    STANCE,
    LegCycle,
    check_one_leg,
    configuration_at,
    crank_grid,
    frame_xz,
    leg_cycle,
)
from pasibot_pin.model.robot import load
from pasibot_pin.reprs import short_repr

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot

__all__ = ["KSweep", "StraightLineMetrics", "k_sweep", "straight_line_metrics"]


@dataclass(frozen=True)
class StraightLineMetrics:
    """Straight-line quality of the ankle path (docs/reference.md §4 reference values in brackets).

    Attributes:
        L: crank length [m].
        ground_z: ankle height at touch-down (theta = 90 deg), the ground line [m] (-28 L).
        lowest_z: lowest ankle height over the turn [m] (-28 L for K = 2).
        stroke: ankle x travel over stance, x(90 deg) - x(270 deg) [m] (8 L).
        ankle_band: peak-to-peak ankle height over stance [m] (0.0195 L).
        deviation: largest distance of the stance ankle from the chord 90 -> 270 deg [m].
        deviation_theta: crank angles of the stance peaks [rad] (128.7 and 231.3 deg).
        lift: largest ankle height above the ground line [m] (1.798 L).
        lift_theta: crank angle of the largest lift [rad] (0).
        tolerance: height tolerance used for the ground span [m].
        ground_span: crank-angle span of the contiguous interval, around the path's lowest
            point, where the ankle is within ``tolerance`` of its lowest height [rad].
        ground_interval: its first and last crank angle [rad] (the first may be negative).
        stance_pitch_max: largest |foot pitch| over stance [rad] (parallel: < 0.12 deg).
        stance_pitch_range: lowest and highest foot pitch over stance [rad].
        pitch_at_zero: foot pitch at theta = 0 [rad] (parallel: about -12.4 deg).

    """

    __repr__ = short_repr

    L: float
    ground_z: float
    lowest_z: float
    stroke: float
    ankle_band: float
    deviation: float
    deviation_theta: tuple[float, float]
    lift: float
    lift_theta: float
    tolerance: float
    ground_span: float
    ground_interval: tuple[float, float]
    stance_pitch_max: float
    stance_pitch_range: tuple[float, float]
    pitch_at_zero: float

    def in_L(self) -> dict[str, float]:
        """The length metrics in units of L and the angles in degrees (for printouts)."""
        return {
            "stroke/L": self.stroke / self.L,
            "ankle_band/L": self.ankle_band / self.L,
            "deviation/L": self.deviation / self.L,
            "lift/L": self.lift / self.L,
            "lift_theta_deg": math.degrees(self.lift_theta),
            "tolerance/L": self.tolerance / self.L,
            "ground_span_deg": math.degrees(self.ground_span),
            "stance_pitch_max_deg": math.degrees(self.stance_pitch_max),
            "pitch_at_zero_deg": math.degrees(self.pitch_at_zero),
        }


def _golden_max(func: Callable[[float], float], a: float, b: float, tol: float = 1e-10) -> tuple[float, float]:
    """Maximum of a unimodal function on [a, b] by golden-section search: (argmax, max)."""
    ratio = (math.sqrt(5.0) - 1.0) / 2.0
    c, d = b - ratio * (b - a), a + ratio * (b - a)
    fc, fd = func(c), func(d)
    while b - a > tol:
        if fc > fd:
            b, d, fd = d, c, fc
            c = b - ratio * (b - a)
            fc = func(c)
        else:
            a, c, fc = c, d, fd
            d = a + ratio * (b - a)
            fd = func(d)
    x = (a + b) / 2
    return x, func(x)


def _bisect(func: Callable[[float], float], a: float, b: float, tol: float = 1e-12) -> float:
    """Root of ``func`` on [a, b] (a sign change) by bisection."""
    fa = func(a)
    for _ in range(200):
        m = (a + b) / 2
        fm = func(m)
        if (fm > 0) == (fa > 0):
            a, fa = m, fm
        else:
            b = m
        if b - a < tol:
            break
    return (a + b) / 2


class _AnkleProbe:
    """Ankle position and foot pitch at any crank angle, warm-started from the nearest sample."""

    def __init__(self, robot: PasibotRobot, cycle: LegCycle):
        self.robot, self.cycle = robot, cycle
        self.wrapped = np.mod(cycle.theta, 2 * math.pi)

    def q(self, theta: float) -> np.ndarray:
        diff = np.abs(np.angle(np.exp(1j * (self.wrapped - theta))))
        k = int(np.argmin(diff))
        guess = self.cycle.q[k].copy()
        guess[self.robot.idx_q("right_j0_crank")] = self.cycle.theta[k] + _wrap(theta - self.cycle.theta[k])
        return configuration_at(self.robot, self.cycle.theta[k] + _wrap(theta - self.cycle.theta[k]), guess)

    def z(self, theta: float) -> float:
        return float(frame_xz(self.robot, self.q(theta))[1])

    def pitch(self, theta: float) -> float:
        pin.framesForwardKinematics(self.robot.model, self.robot.data, self.q(theta))
        return planar_pitch(self.robot.data.oMf[self.robot.frame_id("right_foot")].rotation)


def _wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


def straight_line_metrics(
    robot: PasibotRobot,
    tolerance: float | None = None,
    step: float = math.radians(1.0),
    cycle: LegCycle | None = None,
) -> StraightLineMetrics:
    """Stroke, band, deviation, lift, ground span and foot pitch of a one-leg robot.

    Extremes and ground crossings are refined beyond the sampling (golden section and
    bisection on the closure manifold), so the numbers do not depend on ``step``.

    Args:
        robot: a one-leg robot.
        tolerance: height above the path's lowest point counted as "on the ground" for the
            span [m] (default 0.02 L, just above the stance band 0.0195 L; a tolerance below
            the band gives only the piece of stance around the lowest sample).
        step: sampling step of the crank turn before refinement [rad].
        cycle: ``robot``'s :func:`~pasibot_pin.kinematics.leg.leg_cycle` over ``crank_grid(step)`` if the
            caller has it (with or without ``omega``: its poses are the same), so it is not sampled again;
            a cycle of another robot or other crank angles is not used.

    Returns:
        The :class:`StraightLineMetrics`.

    """
    check_one_leg(robot)
    L = robot.geometry.L
    tolerance = 0.02 * L if tolerance is None else float(tolerance)
    if not math.isfinite(tolerance) or tolerance <= 0.0:
        raise ParameterError(f"parameter 'tolerance' must be a positive height [m], got {tolerance!r}")
    grid = crank_grid(step)
    if cycle is None or cycle.robot is not robot or not np.array_equal(cycle.theta, grid):
        cycle = leg_cycle(robot, grid)
    probe = _AnkleProbe(robot, cycle)
    p90, p270 = frame_xz(robot, probe.q(STANCE[0])), frame_xz(robot, probe.q(STANCE[1]))
    ground = float(p90[1])
    peaks = _deviation_peaks(robot, probe, cycle, p90, p270, step)
    band = _stance_band(probe, cycle, ground, float(p270[1]), step)
    lift_theta, z_top = _highest_swing(probe, cycle, step)
    lowest, (start, end) = _ground_interval(probe, cycle, ground, tolerance)
    pitch_lo, pitch_hi = _stance_pitch_range(probe, cycle, step)
    pin.framesForwardKinematics(robot.model, robot.data, probe.q(0.0))
    pitch0 = planar_pitch(robot.data.oMf[robot.frame_id("right_foot")].rotation)
    return StraightLineMetrics(
        L=L,
        ground_z=ground,
        lowest_z=lowest,
        stroke=float(p90[0] - p270[0]),
        ankle_band=float(band),
        deviation=float(max(p[1] for p in peaks)),
        deviation_theta=(peaks[0][0], peaks[1][0]),
        lift=float(z_top - ground),
        lift_theta=float(_wrap(lift_theta)),
        tolerance=tolerance,
        ground_span=float(end - start),
        ground_interval=(float(start), float(end)),
        stance_pitch_max=float(max(abs(pitch_hi), abs(pitch_lo))),
        stance_pitch_range=(float(pitch_lo), float(pitch_hi)),
        pitch_at_zero=float(pitch0),
    )


def _deviation_peaks(
    robot: PasibotRobot, probe: _AnkleProbe, cycle: LegCycle, p90, p270, step: float
) -> list[tuple[float, float]]:
    """(crank angle, distance) of the stance ankle's farthest point from the chord 90 -> 270 deg, each half."""
    chord = (p270 - p90) / np.linalg.norm(p270 - p90)
    normal = np.array([-chord[1], chord[0]])

    def distance(theta: float) -> float:
        return float(abs(np.dot(frame_xz(robot, probe.q(theta)) - p90, normal)))

    stance = cycle.in_stance()
    rel = np.abs((cycle.ankle - p90) @ normal)
    peaks = []
    for lo, hi in ((STANCE[0], math.pi), (math.pi, STANCE[1])):
        inside = stance & (np.mod(cycle.theta, 2 * math.pi) >= lo) & (np.mod(cycle.theta, 2 * math.pi) <= hi)
        k = int(np.argmax(np.where(inside, rel, -1.0)))
        th = float(np.mod(cycle.theta[k], 2 * math.pi))
        peaks.append(_golden_max(distance, max(lo, th - step), min(hi, th + step)))
    return peaks


def _stance_window(cycle: LegCycle, k: int, step: float) -> tuple[float, float]:
    """The crank window of +- ``step`` around stance sample ``k``, inside stance [rad]."""
    th_stance = np.mod(cycle.theta[cycle.in_stance()], 2 * math.pi)
    return max(STANCE[0], th_stance[k] - step), min(STANCE[1], th_stance[k] + step)


def _stance_band(probe: _AnkleProbe, cycle: LegCycle, ground: float, z270: float, step: float) -> float:
    """Highest minus lowest stance height of the ankle (the ends are sampled exactly) [m]."""
    z_stance = cycle.ankle[cycle.in_stance(), 1]
    k_hi, k_lo = int(np.argmax(z_stance)), int(np.argmin(z_stance))
    z_hi = _golden_max(probe.z, *_stance_window(cycle, k_hi, step))[1]
    z_lo = -_golden_max(lambda t: -probe.z(t), *_stance_window(cycle, k_lo, step))[1]
    return z_hi - min(z_lo, ground, z270)


def _highest_swing(probe: _AnkleProbe, cycle: LegCycle, step: float) -> tuple[float, float]:
    """(crank angle, height) of the ankle's highest point over the turn [rad, m]."""
    k = int(np.argmax(cycle.ankle[:, 1]))
    th = float(cycle.theta[k])
    return _golden_max(probe.z, th - step, th + step)


def _ground_interval(
    probe: _AnkleProbe, cycle: LegCycle, ground: float, tolerance: float
) -> tuple[float, tuple[float, float]]:
    """The lowest height and the contiguous crank interval around it where the ankle is within ``tolerance``."""
    wrapped = np.mod(cycle.theta, 2 * math.pi)
    order = np.unique(np.round(wrapped, 12), return_index=True)[1]
    w, zw = wrapped[order], cycle.ankle[order, 1]
    k_low = int(np.argmin(zw))
    lowest = min(float(zw[k_low]), ground)
    low = zw - lowest < tolerance
    n = len(w)
    if low.all():
        return lowest, (0.0, 2 * math.pi)
    i = k_low
    while low[(i - 1) % n]:
        i -= 1
    j = k_low
    while low[(j + 1) % n]:
        j += 1

    def above(theta: float) -> float:
        return probe.z(theta) - lowest - tolerance

    a0, a1 = float(w[(i - 1) % n]), float(w[i % n])
    b0, b1 = float(w[j % n]), float(w[(j + 1) % n])
    start = _bisect(above, a0, a1 if a1 > a0 else a1 + 2 * math.pi)
    end = _bisect(above, b0, b1 if b1 > b0 else b1 + 2 * math.pi)
    start = start - 2 * math.pi if i < 0 else start
    end = end + 2 * math.pi if end < start else end
    return lowest, (start, end)


def _signed_pitch(probe: _AnkleProbe, sign: float, theta: float) -> float:
    return sign * probe.pitch(theta)


def _stance_pitch_range(probe: _AnkleProbe, cycle: LegCycle, step: float) -> tuple[float, float]:
    """The lowest and highest foot pitch over stance, refined around the sampled extremes [rad]."""
    pitch_stance = cycle.foot_pitch[cycle.in_stance()]
    extremes = []
    for sign in (1.0, -1.0):  # refine the highest and the lowest stance pitch
        k = int(np.argmax(sign * pitch_stance))
        lo, hi = _stance_window(cycle, k, step)
        extremes.append(sign * _golden_max(functools.partial(_signed_pitch, probe, sign), lo, hi)[1])
    return min(extremes[1], float(pitch_stance.min())), max(extremes[0], float(pitch_stance.max()))


# --------------------------------------------------------------------------- K sweep
@dataclass
class KSweep:
    """Leg cycles for several frame ratios K (seed Fig 4.2.4).

    Attributes:
        variant: the leg variant.
        K: the ratios (n,).
        cycles: one :class:`LegCycle` per K.
        metrics: one :class:`StraightLineMetrics` per K.

    """

    __repr__ = short_repr

    variant: str
    K: np.ndarray
    cycles: list[LegCycle] = field(default_factory=list)
    metrics: list[StraightLineMetrics] = field(default_factory=list)


def k_sweep(
    K_values: Sequence[float] = (1.8, 2.0, 2.2),
    variant: str = "rigid",
    step: float = math.radians(2.0),
    **load_kwargs,
) -> KSweep:
    """Leg cycles and metrics of a one-leg robot for several K = L0 / L.

    Args:
        K_values: frame ratios to compare.
        variant: leg variant.
        step: crank sampling step [rad].
        **load_kwargs: passed to :func:`pasibot_pin.load` (``L=...``).

    Raises:
        ValueError: an empty list, a non-positive K, or a K at which a loop cannot close
            (named by the foundation's assembly).

    """
    ks = np.asarray(list(K_values), dtype=float)
    if ks.size == 0 or not np.all(np.isfinite(ks)) or np.any(ks <= 0):
        raise ParameterError(f"parameter 'K_values' must be positive finite ratios, got {list(K_values)!r}")
    out = KSweep(variant, ks)
    for k in ks:
        robot = load(variant, 1, K=float(k), **load_kwargs)
        out.cycles.append(leg_cycle(robot, crank_grid(step)))
        out.metrics.append(straight_line_metrics(robot, step=step, cycle=out.cycles[-1]))  # sampled once
    return out
