"""The frontal zero-moment point of a planar walk: would the robot stay upright sideways.

The planar floor holds the hip in the sagittal plane, so nothing in a planar walk says whether the
soles could carry the roll moment the motion needs. Replayed on the free-flyer model
(:func:`~pasibot_pin.model.spatial.free_flyer_model`), each sample's motion (q, v and the
acceleration from central differences of v) asks Pinocchio's RNEA for the wrench the ground must
supply; its zero-moment point's lateral position is

    y_zmp = n_x / f_z     (n the moment about the world origin, f the force; a flat ground at z = 0).

In single support the ground can supply it only under the stance sole: its lateral band, from
``sole_outer`` outside the leg's plane to ``sole_inner`` toward the midline. The margin is how far
inside that band the ZMP stays (negative: outside, the body must roll). A cheap filter before a
3-D walk: a walk whose margin is negative tips on plates of that width, unless it is dynamic enough
to recover.

Units: SI; the margin [m] (printouts in mm).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from pasibot_pin.model.coordinates import SIDES
from pasibot_pin.model.spatial import (
    NV_ROOT,
    Footprint,
    free_flyer_model,
    lateral_sign,
    planar_to_spatial,
    planar_velocity_to_spatial,
)


@dataclass(frozen=True)
class FrontalZmp:
    """The lateral ZMP over a planar walk's single supports.

    Attributes:
        t: the single-support samples' times [s].
        stance: their stance side (``right``/``left``).
        y: the lateral ZMP there, from the midline, +y to the left [m].
        margin: each sample's distance inside the stance sole's band [m] (negative: outside).
        min_margin: the least margin [m] (``nan`` without a single support).

    """

    t: np.ndarray
    stance: list[str]
    y: np.ndarray
    margin: np.ndarray
    min_margin: float

    def summary(self) -> str:
        """One line: the ZMP's range in each stance and the least margin [mm]."""
        if not len(self.t):
            return "frontal ZMP: no single support to judge"
        parts = []
        for side in SIDES:
            ys = self.y[[s == side for s in self.stance]]
            if len(ys):
                parts.append(f"{side} stance {1000 * ys.min():+.1f} to {1000 * ys.max():+.1f} mm")
        where = ", ".join(parts)
        return f"frontal ZMP ({where} of the midline): margin {1000 * self.min_margin:+.1f} mm to the sole's edge"


def ground_wrench(model: pin.Model, data: pin.Data, q2: np.ndarray, v2: np.ndarray, a2: np.ndarray) -> np.ndarray:
    """The wrench the ground supplies for a planar motion, on the free-flyer ``model``: (f, n about the origin) (6,).

    ``q2``, ``v2``, ``a2`` are the planar configuration, velocity and acceleration.
    """
    q = planar_to_spatial(q2)
    rotation = pin.Quaternion(q[3:7]).toRotationMatrix()
    u, du = planar_velocity_to_spatial(v2), planar_velocity_to_spatial(a2)
    v, a = u.copy(), du.copy()
    v[:3], v[3:6] = rotation.T @ u[:3], rotation.T @ u[3:6]
    a[:3], a[3:6] = rotation.T @ du[:3], rotation.T @ du[3:6]
    a[:3] -= np.cross(v[3:6], v[:3])  # the local acceleration of a world-axes one
    tau = pin.rnea(model, data, q, v, a)
    force, moment = rotation @ tau[:3], rotation @ tau[3:NV_ROOT]
    return np.concatenate((force, moment + np.cross(q[:3], force)))


MAX_SAMPLES = 4000
"""A run longer than this many samples is judged on every n-th of them (the margin moves little in a few ms)."""


def frontal_zmp(robot, result, footprint: Footprint, max_samples: int = MAX_SAMPLES) -> FrontalZmp:
    """The lateral ZMP of a planar floor run over its single supports (see the module docstring).

    Args:
        robot: the two-legged robot of the run.
        result: a :class:`~pasibot_pin.dynamics.floor.run.FloorResult` (its q, v and contact modes).
        footprint: the soles' lateral shape (a design's ``footprint()``): its widest band's reach.
        max_samples: judge at most about this many samples, evenly spread.

    """
    model = free_flyer_model(robot.model)
    data = model.createData()
    t, q, v = result.t, result.q, result.v
    w = robot.geometry.hip_half_width
    inner = max(band[0] for band in footprint.bands)
    outer = max(band[1] for band in footprint.bands)
    times, stances, ys, margins = [], [], [], []
    every = max(1, len(t) // max_samples)
    for k in range(1, len(t) - 1, every):
        loaded = [result.modes[side][k] != "air" for side in SIDES]
        around = [result.modes[side][j] != "air" for side in SIDES for j in (k - 1, k + 1)]
        if sum(loaded) != 1 or sum(around) != 2:  # single support here and at both neighbours
            continue
        side = SIDES[loaded.index(True)]
        a = (v[k + 1] - v[k - 1]) / (t[k + 1] - t[k - 1])
        wrench = ground_wrench(model, data, q[k], v[k], a)
        if wrench[2] <= 0.0:
            continue
        y = wrench[3] / wrench[2]
        plane = -lateral_sign(side) * w  # the right leg's plane at -w, the left's at +w
        toward = lateral_sign(side)  # toward the midline
        low, high = sorted((plane - toward * outer, plane + toward * inner))
        times.append(t[k])
        stances.append(side)
        ys.append(y)
        margins.append(min(y - low, high - y))
    margin = np.array(margins)
    return FrontalZmp(np.array(times), stances, np.array(ys), margin, float(margin.min()) if len(margin) else math.nan)
