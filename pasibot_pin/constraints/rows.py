"""The rows of the constraint core as data: scalar rows, evaluated rows, frame rows, tolerances.

A :class:`CoordinateRow` (a linear combination of coordinates) or a :class:`PitchRow` (a frame's
world pitch), each minus its target offset + rate t, are the scalar rows a
:class:`~pasibot_pin.constraints.system.ConstraintSystem` adds after its constraint models' rows;
:class:`Rows` holds the rows evaluated at (q, v, t). :func:`frame_rows` builds the planar rows of
frames outside a system (contact points, a sole's pose) on the exact planar kinematics
(:func:`planar_kinematics`, cached per model). Newton's tolerances (:data:`RELATIVE_TOL`,
:data:`ANGLE_TOL`) and step limit are here too.

Units: SI, angles [rad].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from pasibot_pin.caches import PerObjectCache
from pasibot_pin.constraints.planar import PlanarKinematics, PlanarRowBlocks
from pasibot_pin.errors import ParameterError

_PLANAR: PerObjectCache[PlanarKinematics | None] = PerObjectCache()


def planar_kinematics(model: pin.Model) -> PlanarKinematics | None:
    """The exact planar kinematics of ``model`` (cached), or ``None`` when the model is not planar."""
    return _PLANAR.get(model, lambda: _planar_or_none(model))


def _planar_or_none(model: pin.Model) -> PlanarKinematics | None:
    try:
        return PlanarKinematics(model)
    except ValueError:
        return None


RELATIVE_TOL = 2e-11
"""Newton stops when every length row is below RELATIVE_TOL * length_scale (1e-12 m at L = 0.05 m)."""
ANGLE_TOL = 1e-12
"""... and every angle row below this [rad]."""
STEP_LIMIT = 0.5
"""Largest Newton step component [rad or m/L]: keeps far-off starts on their assembly branch."""


def planar_pitch(rotation: np.ndarray) -> float:
    """Counter-clockwise angle of a frame's x axis in the x-z plane [rad] (atan2, signed)."""
    return math.atan2(rotation[2, 0], rotation[0, 0])


# --------------------------------------------------------------------------- scalar rows (data)
@dataclass(frozen=True)
class CoordinateRow:
    """A linear coordinate row: sum_k c_k q[i_k] - (offset + rate t) = 0.

    Prescribed joint angles, the hip pitch held level, the cranks turning at omega, and the
    one-motor coupling q_L - q_R - pi = 0 are all of this kind.

    Attributes:
        name: label (``right_j0_crank``, ``hip_pitch``, ``crank_coupling``).
        terms: ((velocity index, coefficient), ...); nq == nv for every PASIBOT model.
        offset: target at t = 0 [rad or m].
        rate: its time derivative [rad/s or m/s].

    """

    name: str
    terms: tuple[tuple[int, float], ...]
    offset: float = 0.0
    rate: float = 0.0

    @property
    def index(self) -> int:
        """The coordinate index of a one-term row."""
        if len(self.terms) != 1:
            raise ParameterError(f"row {self.name!r} combines {len(self.terms)} coordinates: it has no single index")
        return self.terms[0][0]

    def at(self, offset: float, rate: float = 0.0) -> CoordinateRow:
        """The same row with another target."""
        return CoordinateRow(self.name, self.terms, float(offset), float(rate))


@dataclass(frozen=True)
class PitchRow:
    """A frame's world pitch: pitch(frame) - (offset + rate t) = 0 (wrapped to (-pi, pi]).

    Attributes:
        name: label (the frame name).
        frame: Pinocchio frame index.
        offset: target at t = 0 [rad].
        rate: its time derivative [rad/s].

    """

    name: str
    frame: int
    offset: float = 0.0
    rate: float = 0.0

    def at(self, offset: float, rate: float = 0.0) -> PitchRow:
        """The same row with another target."""
        return PitchRow(self.name, self.frame, float(offset), float(rate))


ScalarRow = CoordinateRow | PitchRow


def coordinate(name: str, index: int, offset: float = 0.0, rate: float = 0.0) -> CoordinateRow:
    """One coordinate q[index] = offset + rate t."""
    return CoordinateRow(name, ((int(index), 1.0),), float(offset), float(rate))


def coupling(name: str, index: int, minus: int, offset: float) -> CoordinateRow:
    """Two coordinates locked together: q[index] - q[minus] = offset (one motor for two cranks)."""
    return CoordinateRow(name, ((int(index), 1.0), (int(minus), -1.0)), float(offset))


@dataclass
class Rows:
    """The rows evaluated at (q, v, t).

    Attributes:
        phi: residual Phi(q, t) (m,) [m, rad].
        jac: Jacobian dPhi/dq (m, nv).
        drift: J_dot v (m,) [m/s^2, rad/s^2] (zeros without v).
        phi_t: dPhi/dt (m,) [m/s, rad/s].

    """

    phi: np.ndarray
    jac: np.ndarray
    drift: np.ndarray
    phi_t: np.ndarray


class Projection(NamedTuple):
    """What :meth:`ConstraintSystem.project_rows` computed.

    Attributes:
        q: the closed configuration (nq,).
        rows: the rows evaluated at ``q`` (residual below the tolerance, J, no drift).
        initial_residual: the largest |Phi| at the start configuration [m, rad].

    """

    q: np.ndarray
    rows: Rows
    initial_residual: float


def cross_rows(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross product of two (n, 3) arrays (np.cross is slow on small arrays)."""
    return np.column_stack(
        (
            a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1],
            a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
            a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0],
        )
    )


def wrap_angle(angle: np.ndarray | float):
    """An angle (or an array of them) wrapped to [-pi, pi) [rad]."""
    return np.remainder(np.asarray(angle) + math.pi, 2 * math.pi) - math.pi


def frame_rows(
    model: pin.Model, frames: Sequence[int], points: Sequence[int], pitches: Sequence[int] = ()
) -> PlanarRowBlocks:
    """Planar rows of frames of ``model``: the world position of each of ``points``, the pitch of ``pitches``.

    The public way to build rows outside a :class:`ConstraintSystem` (contact points, a sole's
    pose): the same exact planar kinematics (complex products, batched over leading axes of q).

    Args:
        model: a planar model (every rotation about y).
        frames: frame ids.
        points: indices into ``frames`` whose world (x, z) rows are wanted, in this order.
        pitches: indices into ``frames`` whose world pitch rows are wanted.

    Returns:
        :class:`~pasibot_pin.constraints.planar.PlanarRowBlocks`: ``evaluate(q)`` gives the points as
        x + i z [m], their Jacobian and the pitch rows [rad].

    Raises:
        ParameterError: the model is not planar.

    """
    kin = planar_kinematics(model)
    if kin is None:
        raise ParameterError("frame_rows needs a planar model (every rotation about y)")
    placed = [model.frames[int(f)] for f in frames]
    ends = kin.ends(
        np.array([f.parentJoint for f in placed]),
        np.array([f.placement.translation for f in placed]).reshape(-1, 3),
        np.array([f.placement.rotation for f in placed]).reshape(-1, 3, 3),
    )
    return PlanarRowBlocks(ends, [(int(k), -1) for k in points], [(int(k), -1) for k in pitches])
