"""What a 3-D floor run returns (:class:`Floor3DResult`), one sample per step, and the judge's sums of corners.

Units: SI, angles [rad] unless a name says deg.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pasibot_pin.dynamics.verdict import TIP_LIMIT, Verdict

CLEARANCE_EVERY = 5
"""The soles' clearance is measured every this many steps (5 ms at 1 ms: a sole moves ~5 mm) [-]."""


@dataclass
class Floor3DResult:
    """A 3-D floor run, one sample per step.

    Attributes:
        t: times [s] (n,).
        q: free-flyer configurations (n, nq).
        hip: the hip's x, y, z [m] (n, 3).
        roll, pitch, yaw: the hip's attitude [rad] (n,) (pitch: the planar convention).
        normal: each corner's normal force [N] (n, corners).
        verdict: the walk's :class:`~pasibot_pin.dynamics.verdict.Verdict` (``tipped`` among its outcomes).
        max_hip_roll_deg: largest |roll| [deg].
        yaw_per_step_deg: the hip's yaw at the end over the steps taken [deg/step].
        lateral_drift_m: the hip's y at the end [m].
        roll_margin_deg: the tip limit less the largest |roll| [deg] (negative: tipped).
        fallback: QP solves answered by proxsuite (the rest exactly: held, by the active set; free, by NNLS).
        min_sole_clearance_m: the least distance between the two feet's sole plates over the walk,
            every :data:`CLEARANCE_EVERY` steps [m] (negative: they intersected, ``collided``).
        leg_clearance_m: the least lateral gap between a leg and the other leg's links
            (:func:`~pasibot_pin.model.spatial.leg_clearance`, the same all walk long) [m].
        u_end: the velocity at the last sample, in world-aligned root coordinates.
        lateral_y: the lateral mass's place on its slider [m] (n,), ``None`` without one; ``q`` and
            ``u_end`` are the robot's own coordinates, without it.
        settled_at_s: when the gait settled and its steps began to be repeated rather than simulated
            (:mod:`~pasibot_pin.dynamics.floor.repeat3d`) [s]; NaN: every step simulated.

    """

    t: np.ndarray
    q: np.ndarray
    hip: np.ndarray
    roll: np.ndarray
    pitch: np.ndarray
    yaw: np.ndarray
    normal: np.ndarray
    verdict: Verdict
    max_hip_roll_deg: float
    yaw_per_step_deg: float
    lateral_drift_m: float
    roll_margin_deg: float
    fallback: int
    min_sole_clearance_m: float
    leg_clearance_m: float = math.nan
    u_end: np.ndarray | None = None
    lateral_y: np.ndarray | None = None
    settled_at_s: float = math.nan

    def summary(self) -> str:
        """One line: the verdict, then the sideways figures."""
        return (
            f"{self.verdict.summary()}; 3-D: max |roll| {self.max_hip_roll_deg:.2f} deg "
            f"(limit {math.degrees(TIP_LIMIT):g}), yaw {self.yaw_per_step_deg:+.3f} deg/step, "
            f"lateral drift {1000 * self.lateral_drift_m:+.1f} mm, "
            f"soles {1000 * self.min_sole_clearance_m:.1f} mm apart, legs {1000 * self.leg_clearance_m:.1f} mm"
        )


def floor3d_result(
    t: np.ndarray,
    q: np.ndarray,
    normal: np.ndarray,
    attitude: np.ndarray,
    verdict: Verdict,
    clearance: float,
    fallback: int,
    leg_clearance_m: float,
) -> Floor3DResult:
    """A run's :class:`Floor3DResult` from its samples and figures.

    Args:
        t: times [s] (n,).
        q: configurations (n, nq).
        normal: each corner's normal force [N] (n, corners).
        attitude: the hip's roll, pitch and yaw [rad] (n, 3).
        verdict: the walk's verdict.
        clearance: the soles' least distance over the walk [m].
        fallback: the QP solves proxsuite answered.
        leg_clearance_m: the legs' least lateral gap [m].

    """
    roll, pitch, yaw = attitude.T
    max_roll = float(np.degrees(np.max(np.abs(roll))))
    steps = max(1, verdict.steps)
    return Floor3DResult(
        t=t,
        q=q,
        hip=q[:, :3].copy(),
        roll=roll,
        pitch=pitch,
        yaw=yaw,
        normal=normal,
        verdict=verdict,
        max_hip_roll_deg=max_roll,
        yaw_per_step_deg=float(np.degrees(yaw[-1])) / steps,
        lateral_drift_m=float(q[-1, 1]),
        roll_margin_deg=math.degrees(TIP_LIMIT) - max_roll,
        fallback=fallback,
        min_sole_clearance_m=clearance,
        leg_clearance_m=leg_clearance_m,
    )


def group_sums(values: list[float], k: int) -> list[float]:
    """The sum of each run of k (1 or 2) values as floats, numpy's ``sum`` to the bit: 0 + a (+ b), zeros' signs too."""
    if k == 1:
        return [0.0 + a for a in values]
    return [0.0 + a + b for a, b in zip(values[::2], values[1::2])]


def group_minima(values: list[float], k: int) -> list[float]:
    """The least of each run of k (1 or 2) values as floats, numpy's ``min`` to the bit (NaN kept, its zero pick)."""
    if k == 1:
        return values
    return [a if a < b or a != a else b for a, b in zip(values[::2], values[1::2])]
