"""Where a comb sole's bridge can go: how high it must arch over the other foot's prong, from a 3-D walk.

A comb sole (:class:`~pasibot_pin.model.spatial.Footprint` with several bands) is lateral bands that run
the foot's length, a gap between each two; the other foot's prong walks in that gap. A buildable
foot joins its bands by a bridge across each gap, at the heel end or at the toe end. The bridge
must clear the other foot's prong wherever that prong passes under it.

:func:`bridge_need` replays a 3-D walk's configurations: at every ``every``-th sample, each box of
the other foot's sole (:func:`~pasibot_pin.model.spatial.sole_boxes`, its eight corners) is put in
this foot's sole frame (x heel to toe, y toward the midline from the leg's plane, z up from the
sole's mid-plane). Where the box overlaps a bridge's footprint (the gap across, ``length`` along the
foot from its heel or its toe), the bridge must rise above the box's top. The answer is the largest
such height over the walk at each end, for either foot: the lowest height the bridge's underside can
have and meet none of the heights the other sole filled there (0: it may lie on the sole).

Units: SI [m].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from pasibot_pin.model.spatial import SOLE_HALF_THICKNESS, Footprint, sole_boxes

BRIDGE_LENGTH = 0.02
"""How long a bridge is along the foot [m] (a 2 cm bar across the gap)."""

CHECK_EVERY = 5
"""The walk's samples are checked every this many (5 ms at 1 ms: a sole moves ~5 mm) [-]."""


@dataclass(frozen=True)
class BridgeNeed:
    """How high a comb's bridge must arch at each end of the sole over a walk.

    Attributes:
        heel_m: at the heel end: the lowest height above the sole's mid-plane [m] at which the bridge's
            underside meets nothing of the other foot over the walk (0: it may lie on the sole).
        toe_m: the same at the toe end [m].
        gap_m: the gaps' widths across the foot [m] (the bridge's span).
        length_m: the bridge's length along the foot [m].

    """

    heel_m: float
    toe_m: float
    gap_m: tuple[float, ...]
    length_m: float

    @property
    def best_end(self) -> str:
        """The end that needs the lower arch (``heel`` or ``toe``)."""
        return "heel" if self.heel_m <= self.toe_m else "toe"

    def summary(self) -> str:
        """One line: the arch each end needs."""
        return (
            f"a {1000 * self.length_m:.0f} mm bridge across the sole's gap clears the other foot "
            f"arching {1000 * self.heel_m:.1f} mm at the heel end, {1000 * self.toe_m:.1f} mm at the toe end "
            f"(build it at the {self.best_end})"
        )


def sole_frames(model: pin.Model, q: np.ndarray, footprint: Footprint) -> dict[str, tuple[int, pin.SE3]]:
    """Each foot's sole frame on its joint: origin midway heel to toe on the leg's plane, x toe-ward, y midline-ward."""
    out = {}
    for box in sole_boxes(model, q, footprint):
        if box.band == 0:
            inner, outer = footprint.bands[0]
            origin = box.placement.translation - box.placement.rotation[:, 1] * 0.5 * (inner - outer)
            out[box.side] = (box.joint, pin.SE3(box.placement.rotation, origin))
    return out


def bridge_need(
    model: pin.Model,
    qs: np.ndarray,
    footprint: Footprint,
    length: float = BRIDGE_LENGTH,
    every: int = CHECK_EVERY,
) -> BridgeNeed | None:
    """The arch a bridge needs at each end of the sole over the walk ``qs`` (module docstring).

    Args:
        model: the free-flyer biped (:func:`~pasibot_pin.model.spatial.free_flyer_model`).
        qs: its configurations along the walk (n, nq).
        footprint: the soles' lateral shape.
        length: the bridge's length along the foot [m].
        every: check every this many samples.

    Returns:
        :class:`BridgeNeed`, or ``None`` for a sole of one band (no gap to bridge).

    """
    bands = sorted(footprint.bands, key=lambda band: band[0] - band[1])  # (inner, outer): [-outer, inner] across
    gaps = [(a[0], -b[1]) for a, b in zip(bands[:-1], bands[1:]) if -b[1] > a[0]]
    if not gaps:
        return None
    boxes = sole_boxes(model, qs[0], footprint)
    frames = sole_frames(model, qs[0], footprint)
    data = model.createData()
    half = float(boxes[0].half_size[0])  # half the sole's length
    ends = {"heel": (-half, -half + length), "toe": (half - length, half)}
    taken: dict[str, list[tuple[float, float]]] = {end: [] for end in ends}  # heights the other sole fills
    for q in qs[::every]:
        pin.forwardKinematics(model, data, q)
        for side, (joint, frame) in frames.items():
            world = data.oMi[joint] * frame
            up = 1.0 if world.rotation[2, 2] >= 0.0 else -1.0  # the sole frame's z toward the sky
            for box in (b for b in boxes if b.side != side):
                placed = data.oMi[box.joint] * box.placement
                center = (placed.translation - world.translation) @ world.rotation
                axes = world.rotation.T @ placed.rotation  # the box's axes in the sole frame (columns)
                center[2] *= up
                axes[2] *= up
                for end, slab in ends.items():
                    heights = _heights_over(center, axes, box.half_size, slab, gaps)
                    if heights is not None:
                        taken[end].append(heights)
    heel, toe = (lowest_free(taken[end], SOLE_HALF_THICKNESS) for end in ("heel", "toe"))
    return BridgeNeed(float(heel), float(toe), tuple(float(high - low) for low, high in gaps), length)


def _heights_over(
    center: np.ndarray, axes: np.ndarray, half: np.ndarray, slab: tuple[float, float], gaps: list[tuple[float, float]]
) -> tuple[float, float] | None:
    """The heights (z range) a box fills over the slab x0 <= x <= x1 within a gap across, or ``None`` (none there).

    The box is its long axis (its first, half length ``half[0]``) swept by its two short half sizes:
    along the axis x, y and z are affine, so the part over the slab is one interval of the axis.
    """
    spread = np.abs(axes[:, 1:]) @ half[1:]  # the short sides' extent along x, y, z
    direction = axes[:, 0]
    low, high = -half[0], half[0]
    x0, x1 = slab[0] - spread[0], slab[1] + spread[0]
    if abs(direction[0]) < 1e-12:
        if not x0 <= center[0] <= x1:
            return None
    else:
        a, b = sorted(((x0 - center[0]) / direction[0], (x1 - center[0]) / direction[0]))
        low, high = max(low, a), min(high, b)
        if low > high:
            return None
    ys = sorted((center[1] + low * direction[1], center[1] + high * direction[1]))
    if not any(ys[1] + spread[1] > g0 and ys[0] - spread[1] < g1 for g0, g1 in gaps):
        return None
    zs = sorted((center[2] + low * direction[2], center[2] + high * direction[2]))
    return zs[0] - spread[2], zs[1] + spread[2]


def lowest_free(taken: list[tuple[float, float]], half: float) -> float:
    """The lowest bottom z >= 0 [m] of a bar ``2 half`` thick that meets none of the ``taken`` height ranges [m]."""
    z = 0.0
    for low, high in sorted(taken):
        if low - z >= 2.0 * half:  # the bar fits below this range
            break
        z = max(z, high)
    return z
