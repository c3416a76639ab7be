"""The planar floor's shape track in the 3-D floor's coordinates: the legs known ahead, the hip left to the step.

The legs of the 3-D floor (:mod:`~pasibot_pin.dynamics.floor.engine3d`) keep their planes, and
their coordinates are the planar model's: with the cranks driven, the loops fix every leg
coordinate as a function of the crank angles, whatever the hip does
(:mod:`~pasibot_pin.dynamics.floor.shape_track`). So the 3-D step has as unknowns only the free
coordinates F: the hip's six (world-aligned) and a free ankle. With x = x_S + E_F u (x_S the
shape's velocity in the step), the step's QP is

    H_FF u + [H x_S + g]_F = C_F^T z,   C_F u >= l - C x_S,

the motors' impulses follow by virtual work, y = D^T (H x + g - C^T z) (D the shape's motion per
unit of each crank's target), and the projection puts the legs on the next closed shape and
moves F by the mass metric's -M_FF^-1 [M moved]_F, where ``moved`` = s_(k+1) - s_k - h x_S.
This is the general step's QP, its bilateral rows solved ahead, and its Newton projection
taken to first order in ``moved`` (O(h^2)): the tracked and general walks differ by a third-order term.

:class:`SpatialTrack` maps one planar :class:`~pasibot_pin.dynamics.floor.shape_track.TrackStep` to
the 3-D coordinates (:class:`SpatialShape`).

Units: SI, angles [rad].
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from pasibot_pin.dynamics.floor.shape_track import ShapeTrack, TrackStep
from pasibot_pin.errors import ParameterError

_new = tuple.__new__  # a NamedTuple from its fields' tuple, without the generated __new__'s keyword handling


class SpatialShape(NamedTuple):
    """One tracked step in the 3-D floor's velocity coordinates.

    Attributes:
        velocity: x_S (nv,): the legs' shape velocity in the step, 0 on F [rad/s].
        tangent: D (nv, scalar rows): the shape's motion per unit of each scalar row's target [rad/rad]; the
            transpose of a C-ordered D^T (its rows, D's columns, contiguous).
        moved: s_(k+1) - s_k - h x_S (nv,): the projection's move of the shape [rad].
        end: the legs' configuration after the step (legs,), 0 on a free ankle [rad].

    """

    velocity: np.ndarray
    tangent: np.ndarray
    moved: np.ndarray
    end: np.ndarray


class SpatialTrack:
    """A planar shape track read in 3-D coordinates.

    Args:
        track: the planar floor's shape track (:meth:`FloorSimulator.shape_track`).
        nv: the 3-D model's velocity size (the robot's, no lateral slider).
        root: the 3-D root's velocity size (6) and ``planar_root`` the planar one's (3): a leg
            coordinate i of the planar model is i + root - planar_root in 3-D.
        planar_root: see ``root``.

    Attributes:
        free: the 3-D free velocity indices F: the root's, then the free ankles' (ascending).
        free_legs: the free ankles among the legs' coordinates (indices into the legs).
        rows: the index of F in a vector (a slice, views, when F is the root alone).
        block: the index of M_FF in M.

    """

    def __init__(self, track: ShapeTrack, nv: int, root: int, planar_root: int) -> None:
        split = track.split
        planar_free = split.free.tolist()
        if planar_free[:planar_root] != list(range(planar_root)):
            raise ParameterError("parameter 'track': the planar hip must be free (a held hip has no 3-D track)")
        self.track, self.nv, self.root, self.planar_root = track, nv, root, planar_root
        ankles = [i - planar_root for i in planar_free[planar_root:]]
        self.free_legs = np.array(ankles, dtype=int)
        self.free = np.array(list(range(root)) + [i + root for i in ankles], dtype=int)
        self.rows: slice | np.ndarray = slice(0, root) if not ankles else self.free
        self.block: tuple = (self.rows, self.rows) if not ankles else np.ix_(self.free, self.free)
        self._planar_zeros = np.zeros(planar_root)  # the planar root's rows, read only

    def step(self, t: float, legs: np.ndarray) -> SpatialShape | None:
        """The step from ``t`` with the legs at ``legs`` (planar order) [rad]; ``None``: the general step takes it."""
        planar = np.concatenate((self._planar_zeros, legs))
        shape = self.track.step(t, planar)
        return None if shape is None else self._spatial(shape)

    def _spatial(self, shape: TrackStep) -> SpatialShape:
        cut, free, root, nv = self.planar_root, shape.free, self.root, self.nv
        rows = shape.columns_t  # P^T: x_S, D^T and the move as contiguous rows (the properties' values, copied)
        velocity, moved, tangent_t = np.zeros(nv), np.zeros(nv), np.zeros((len(rows) - free - 2, nv))
        velocity[root:], moved[root:], tangent_t[:, root:] = rows[free, cut:], rows[-1, cut:], rows[free + 1 : -1, cut:]
        return _new(SpatialShape, (velocity, tangent_t.T, moved, shape.end[cut:]))
