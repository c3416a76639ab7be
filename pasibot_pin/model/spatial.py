"""The biped in three dimensions: a free-flyer hip, and the soles' footprint as contact corners.

The planar biped (:mod:`pasibot_pin.model.robot`) has the hip's x, z and pitch as its root. Its
legs already sit in their own planes, at y = -/+ ``hip_half_width`` (right, left), every leg
joint turning about the hip's y axis. :func:`free_flyer_model` copies that tree under Pinocchio's
``JointModelFreeFlyer`` (x, y, z and a unit quaternion; velocity: the hip's spatial velocity in its
own frame), so the loops stay in the legs' planes and nothing of the legs is written twice.

:class:`Footprint` is a sole's lateral shape: one rectangle or several prongs (a comb), each a
lateral band measured from the leg's plane, positive toward the midline. Its corners, with the
foot's heel and toe, are the contact points of the 3-D floor (:func:`corner_frames` adds them to
the model as frames on the foot).

Units: SI, lengths [m], angles [rad].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import coal
import numpy as np
import pinocchio as pin

from pasibot_pin.errors import InterferenceError, ParameterError
from pasibot_pin.model.coordinates import SIDES

FREE_FLYER_NAME = "hip_free_flyer"
"""The 3-D biped's root joint."""
NQ_ROOT, NV_ROOT = 7, 6
"""Sizes of the free-flyer root in q (x, y, z, quaternion x, y, z, w) and in v."""
PLANAR_NQ_ROOT = 3
"""Size of the planar root (x, z, pitch) in q and v."""
CENTRED_SOLE = 0.6
"""The default sole's reach each side of its leg's plane over L: the xacro's 1.2 L wide plate [-]."""
SOLE_POINTS: tuple[str, ...] = ("heel", "toe")
"""A foot's contact points along its sole, heel first and toe last: each is the frame ``<side>_<point>`` of
the robot description (the xacro's ``foot`` macro). The planar floor's contact points; with the
footprint's lateral offsets, the 3-D floor's corners (:attr:`Footprint.points`)."""


@dataclass(frozen=True)
class Footprint:
    """The sole's lateral shape, the same for both feet (mirrored about the midline).

    Attributes:
        bands: each prong's lateral band (inner reach, outer reach) from the leg's plane [m]:
            the prong spans from ``outer`` outside the plane to ``inner`` toward the midline.
            One band is a plain rectangular sole; several are a comb whose prongs may
            interleave with the other foot's.
        points: the sole's contact points along the foot, heel first and toe last, each a frame
            ``<side>_<point>`` of the robot (default :data:`SOLE_POINTS`): a contact point is added
            here, once, for the planar floor's general and tracked steps, its judge and the 3-D corners.

    """

    bands: tuple[tuple[float, float], ...]
    points: tuple[str, ...] = SOLE_POINTS

    def __post_init__(self) -> None:
        if not self.bands:
            raise ParameterError("parameter 'sole': a footprint needs at least one band")
        if len(self.points) < 2 or len(set(self.points)) != len(self.points):
            raise ParameterError(f"parameter 'points' must name two or more distinct sole frames, got {self.points!r}")
        for inner, outer in self.bands:
            for name, value in (("sole_inner", inner), ("sole_outer", outer)):
                if not math.isfinite(value):
                    raise ParameterError(f"parameter {name!r} must be finite, got {value!r}")
            if inner + outer < 0.0:
                raise ParameterError(f"parameter 'sole_inner' + 'sole_outer' must be >= 0, got {inner:g} + {outer:g}")

    @classmethod
    def plate(cls, inner: float, outer: float) -> Footprint:
        """One rectangular sole reaching ``inner`` toward the midline and ``outer`` away from it [m]."""
        return cls(((float(inner), float(outer)),))

    @classmethod
    def centred(cls, L: float) -> Footprint:
        """The default sole: a plate reaching :data:`CENTRED_SOLE` L each side of its leg's plane (``L`` [m])."""
        return cls.plate(CENTRED_SOLE * L, CENTRED_SOLE * L)

    @property
    def contact_offsets(self) -> tuple[float, ...]:
        """The lateral offsets of the corners that touch a flat ground [m]: the outermost and the innermost.

        A sole's height above a plane is affine across the leg's plane, so no corner between these
        two ever touches first, and a force at one is a share of forces at these two (the same
        wrench and the same friction pyramid, a pyramid being a cone): the walk is the same with
        these alone (tests/test_floor3d.py), and a comb's QP has half the rows.
        """
        offsets = self.offsets
        low, high = min(offsets), max(offsets)
        return (low,) if high - low < 1e-12 else (low, high)

    @property
    def offsets(self) -> tuple[float, ...]:
        """The corners' lateral offsets from the leg's plane, toward the midline positive [m] (no duplicates)."""
        out: list[float] = []
        for inner, outer in self.bands:
            for y in (-outer, inner):
                if not any(abs(y - seen) < 1e-12 for seen in out):
                    out.append(y)
        return tuple(out)


def lateral_sign(side: str) -> float:
    """+1 when the midline lies toward +y of ``side``'s leg plane (the right leg, at y < 0), else -1."""
    return 1.0 if side == SIDES[0] else -1.0


LATERAL_JOINT = "lateral_mass"
"""The joint (a slider along the hip's y axis) of the mass the crank moves sideways."""


@dataclass(frozen=True)
class LateralMass:
    """A share of the body moved sideways by the crank, as single-motor walkers rock.

    The mass slides along the hip's y axis through the hip's origin, at
    ``y = amplitude sin(theta + phase)``, theta the right crank's angle (so at the crank speed:
    one sideways cycle per stride). It is part of the body on the hip, not added to it: the planar
    model (which cannot see y) is unchanged, and with no amplitude the 3-D model is too.

    Attributes:
        mass: the moved mass [kg] (at most the body's).
        amplitude: its sideways reach each side of the midline [m].
        phase: its phase ahead of the right crank [rad].

    """

    mass: float
    amplitude: float
    phase: float = 0.0

    def __post_init__(self) -> None:
        for name, value in (("lateral_mass", self.mass), ("lateral_amplitude", self.amplitude)):
            if not (math.isfinite(value) and value >= 0.0):
                raise ParameterError(f"parameter {name!r} must be finite and >= 0, got {value!r}")
        if not math.isfinite(self.phase):
            raise ParameterError(f"parameter 'lateral_phase' must be finite, got {self.phase!r}")

    def position(self, crank: float) -> tuple[float, float, float]:
        """(y [m], dy/dtheta [m/rad], d2y/dtheta2 [m/rad^2]) at the right crank's angle ``crank`` [rad]."""
        angle = crank + self.phase
        a = self.amplitude
        return a * math.sin(angle), a * math.cos(angle), -a * math.sin(angle)


def free_flyer_model(planar: pin.Model, lateral_mass: float = 0.0) -> pin.Model:
    """The planar biped's tree under a free-flyer root (same bodies, joints, frames and inertias).

    Args:
        planar: the two-legged model with the planar root (:func:`~pasibot_pin.model.description.planar_root_joint`).
        lateral_mass: a share of the hip's mass [kg] moved to a slider along the hip's y axis
            (:data:`LATERAL_JOINT`, the model's last joint, so the legs' coordinates keep their place);
            the hip keeps the rest. 0: no slider.

    Returns:
        A new model: joint 1 the free flyer carrying the hip's inertia, then every leg joint in
        the same order, so q[7:] and v[6:] are the planar q[3:] and v[3:] (then the slider's one).

    Raises:
        ParameterError: a lateral mass above the hip's.

    """
    if planar.joints[1].nq != PLANAR_NQ_ROOT:
        raise ParameterError("free_flyer_model needs the two-legged model with its planar floating hip")
    model = pin.Model()
    model.name = planar.name + "_3d"
    model.gravity = planar.gravity
    ids = {0: 0}
    for j in range(1, planar.njoints):
        joint = pin.JointModelFreeFlyer() if j == 1 else planar.joints[j]
        name = FREE_FLYER_NAME if j == 1 else planar.names[j]
        kwargs = {}
        if j > 1:
            kwargs = dict(
                max_effort=planar.effortLimit[planar.joints[j].idx_v : planar.joints[j].idx_v + joint.nv],
                max_velocity=planar.velocityLimit[planar.joints[j].idx_v : planar.joints[j].idx_v + joint.nv],
                min_config=planar.lowerPositionLimit[planar.joints[j].idx_q : planar.joints[j].idx_q + joint.nq],
                max_config=planar.upperPositionLimit[planar.joints[j].idx_q : planar.joints[j].idx_q + joint.nq],
            )
        ids[j] = model.addJoint(ids[planar.parents[j]], joint, planar.jointPlacements[j], name, **kwargs)
        model.appendBodyToJoint(ids[j], planar.inertias[j], pin.SE3.Identity())
    for frame in planar.frames:
        if frame.name == "universe":
            continue
        # frames keep their order, so a frame's parent frame keeps its id
        model.addFrame(
            pin.Frame(frame.name, ids[frame.parentJoint], frame.parentFrame, frame.placement, frame.type), False
        )
    if lateral_mass > 0.0:
        _add_slider(model, lateral_mass)
    return model


def _add_slider(model: pin.Model, mass: float) -> None:
    """Move ``mass`` [kg] of the hip (a point at its origin) onto a slider along its y axis (in place)."""
    hip = model.inertias[1]
    if mass >= hip.mass:
        raise ParameterError(f"parameter 'lateral_mass' = {mass:g} kg must be less than the hip's {hip.mass:g} kg")
    point = pin.Inertia(mass, np.zeros(3), np.zeros((3, 3)))
    model.inertias[1] = pin.Inertia.FromDynamicParameters(hip.toDynamicParameters() - point.toDynamicParameters())
    joint = model.addJoint(1, pin.JointModelPY(), pin.SE3.Identity(), LATERAL_JOINT)
    model.appendBodyToJoint(joint, point, pin.SE3.Identity())


def corner_frames(model: pin.Model, q: np.ndarray, footprint: Footprint) -> list[int]:
    """Add each foot's sole corners to ``model`` as frames; their ids, right heel first.

    The corners lie at each of the sole's points (:attr:`Footprint.points`: its frames ``<side>_heel``
    and ``<side>_toe``), moved across the leg's plane by each of the footprint's contact offsets
    (:attr:`Footprint.contact_offsets`, toward the midline positive). Order: side, then the sole's
    points, then offset.

    Args:
        model: the free-flyer model (changed in place).
        q: a configuration of it (the corners are rigid on the foot: any one serves).
        footprint: the soles' shape.

    """
    data = model.createData()
    pin.forwardKinematics(model, data, q)
    pin.updateFramePlacements(model, data)
    ids = []
    for side in SIDES:
        sign = lateral_sign(side)
        for point in footprint.points:
            base = model.getFrameId(f"{side}_{point}")
            parent = model.frames[base].parentJoint
            world = data.oMf[base]
            hip = data.oMi[1]
            for k, offset in enumerate(footprint.contact_offsets):
                # across the leg's plane: the hip's y axis (every leg joint turns about it)
                position = world.translation + hip.rotation[:, 1] * (sign * offset)
                placement = data.oMi[parent].actInv(pin.SE3(world.rotation, position))
                name = f"{side}_{point}_corner{k}"
                ids.append(model.addFrame(pin.Frame(name, parent, base, placement, pin.FrameType.OP_FRAME), False))
    return ids


class CornerJacobians:
    """The corners' world positions and their frame Jacobians' linear rows, all corners at once.

    Pinocchio's ``getFrameJacobian`` (LOCAL_WORLD_ALIGNED) of a frame at p on joint j is the joint
    Jacobians' (``computeJointJacobians``, world axes) on j's support, their linear rows less
    p x (angular rows), and zero elsewhere: here that same arithmetic for every corner in a few
    array operations, equal to Pinocchio's bit for bit, where a call per corner costs more than the work.

    Args:
        model: the model holding the corners' frames.
        frames: the corners' frame ids (:func:`corner_frames`).
        axes: the world axes (0, 1, 2: x, y, z) of the linear rows to give, in order (a contact frame
            that is a permutation of the world's: the flat ground's normal, along and across are z, x, y).

    """

    def __init__(self, model: pin.Model, frames: list[int], axes: tuple[int, ...] = (0, 1, 2)) -> None:
        self.frames = list(frames)
        self.columns = np.zeros((len(frames), 1, model.nv), dtype=bool)  # each corner's support
        for k, frame in enumerate(frames):
            for joint in list(model.supports[model.frames[frame].parentJoint])[1:]:  # the universe has no column
                start = model.joints[joint].idx_v
                self.columns[k, 0, start : start + model.joints[joint].nv] = True
        self.axes = np.array(axes, dtype=int)
        # (p x w)_a = p_(a+1) w_(a+2) - p_(a+2) w_(a+1), every row a at once: p's two factors, and the world
        # Jacobian's rows a, then w_(a+2) and w_(a+1) (the angular rows, 3 on)
        self._factors = np.concatenate(((self.axes + 1) % 3, (self.axes + 2) % 3))
        self._rows = np.concatenate((self.axes, 3 + (self.axes + 2) % 3, 3 + (self.axes + 1) % 3))

    def __call__(self, model: pin.Model, data: pin.Data, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The corners' positions (k, 3) [m] and their Jacobians' linear rows on ``axes`` (k, len(axes), nv) at ``q``.

        Runs ``computeJointJacobians`` and updates the corners' placements in ``data``.
        """
        pin.computeJointJacobians(model, data, q)
        k, a = len(self.frames), len(self.axes)  # corners, rows
        points = np.array([pin.updateFramePlacement(model, data, frame).translation for frame in self.frames])
        world = data.J.take(self._rows, axis=0)  # (3 a, nv): the rows a, then the angular factors
        terms = points.take(self._factors, axis=1).reshape(k, 2, a, 1) * world[a:].reshape(2, a, -1)
        jac = np.zeros((k, a, model.nv))  # C order: its reshape to (k a, nv) is a view
        np.copyto(jac, world[:a] - (terms[:, 0] - terms[:, 1]), where=self.columns)
        return points, jac


def planar_to_spatial(q: np.ndarray) -> np.ndarray:
    """A planar configuration (x, z, pitch, legs) as a free-flyer one (x, 0, z, quaternion, legs).

    The planar pitch turns about -y (counter-clockwise seen from the right).
    """
    q = np.asarray(q, dtype=float)
    quat = pin.Quaternion(pin.utils.rpyToMatrix(0.0, -float(q[2]), 0.0)).coeffs()
    return np.concatenate(([q[0], 0.0, q[1]], quat, q[PLANAR_NQ_ROOT:]))


def planar_velocity_to_spatial(v: np.ndarray) -> np.ndarray:
    """A planar velocity (x', z', pitch', legs) in the 3-D floor's world-aligned root coordinates.

    The root's six are the hip's linear velocity and angular velocity, both in world axes.
    """
    v = np.asarray(v, dtype=float)
    return np.concatenate(([v[0], 0.0, v[1], 0.0, -v[2], 0.0], v[PLANAR_NQ_ROOT:]))


def roll_pitch_yaw(q: np.ndarray) -> tuple[float, float, float]:
    """The hip's roll (about x), pitch (planar convention: nose up positive) and yaw (about z) [rad]."""
    rotation = pin.Quaternion(np.asarray(q[3:7], dtype=float)).normalized().toRotationMatrix()
    roll, pitch, yaw = pin.rpy.matrixToRpy(rotation)
    return float(roll), float(-pitch), float(yaw)


BAR_RADIUS = 0.08
"""The bars' radius over L (the xacro's ``bar_radius``; a test reads it there) [-]."""

LEG_HALF_DEPTH = 2.0 * BAR_RADIUS
"""A leg's half depth across its plane over L: its widest part, the slider block, is 4 bar radii deep [-]."""


def check_interference(footprint: Footprint, geometry, sole_clearance: float) -> None:
    """Refuse feet or legs that meet: a one-line error naming the fields, before any work.

    Args:
        footprint: the soles' lateral shape.
        geometry: the robot's geometry (its ``hip_half_width`` and ``L`` [m]).
        sole_clearance: the least distance between the two soles at the start [m] (negative: they intersect).

    Raises:
        InterferenceError: a leg reaches into the other leg's links, or the soles intersect.

    """
    legs = leg_clearance(footprint, geometry.hip_half_width, geometry.L)
    if legs < 0.0:
        raise InterferenceError(
            f"parameters 'hip_half_width', 'sole_inner': a leg meets the other leg by {-1000 * legs:.1f} mm "
            "(its sole reaches into the other leg's links, or the legs' planes are too close)"
        )
    if sole_clearance < 0.0:
        raise InterferenceError(
            "parameter 'sole_inner': the two soles intersect at the start: "
            "a plate past the midline meets the other foot's (cut a gap: sole_gap_from, sole_gap_to)"
        )


def leg_clearance(footprint: Footprint, hip_half_width: float, L: float) -> float:
    """The least lateral gap between one leg and the other [m] (negative: they interfere).

    Each leg's links stay in the slab :data:`LEG_HALF_DEPTH` L deep on each side of its plane, and
    the slabs are parallel (the tree is rigid across the planes). So two gaps decide it, the same
    at every instant of a walk: slab to slab, ``2 hip_half_width - 2 depth``, and a sole's inner
    reach to the other leg's slab, ``2 hip_half_width - depth - inner``. Sole against sole is
    measured on the walk itself (their boxes move). The gaps are lower bounds: parts offset fore
    and aft may pass.

    Args:
        footprint: each sole's bands [m].
        hip_half_width: each leg's plane from the midline [m].
        L: the crank length [m].

    """
    depth = LEG_HALF_DEPTH * L
    reach = max(inner for inner, _ in footprint.bands)
    return min(2.0 * hip_half_width - 2.0 * depth, 2.0 * hip_half_width - depth - reach)


SOLE_HALF_THICKNESS = 0.002
"""Half the thickness of a sole's plate [m]: its boxes span this on each side of the heel-toe line."""


@dataclass(frozen=True)
class SoleBox:
    """One plate of a sole (one band of the footprint) as a box on its foot.

    Attributes:
        side: ``right`` or ``left``.
        band: the band's index in the footprint.
        joint: the foot's joint (the box rides on its body).
        placement: the box's centre and axes in that joint's frame (x heel to toe, y toward the midline).
        half_size: its half lengths along its axes [m] (3,).

    """

    side: str
    band: int
    joint: int
    placement: pin.SE3
    half_size: np.ndarray


def sole_boxes(model: pin.Model, q: np.ndarray, footprint: Footprint) -> list[SoleBox]:
    """Each foot's sole as boxes, one per band: heel to toe, across the band, :data:`SOLE_HALF_THICKNESS` thick.

    The box's mid-plane holds the heel-toe line; the band runs across the leg's plane along the
    hip's y axis (every leg joint turns about it). ``model`` is the planar or the free-flyer biped,
    ``q`` a configuration of it (the boxes are rigid on the feet: any one serves).
    """
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    hip_y = data.oMi[1].rotation[:, 1]
    boxes = []
    for side in SIDES:
        toe, heel = (model.frames[model.getFrameId(f"{side}_{point}")] for point in ("toe", "heel"))
        if toe.parentJoint != heel.parentJoint:
            raise ParameterError(f"the {side} toe and heel are on different bodies")
        joint = int(toe.parentJoint)
        along = toe.placement.translation - heel.placement.translation
        length = float(np.linalg.norm(along))
        along = along / length
        across = data.oMi[joint].rotation.T @ hip_y * lateral_sign(side)  # toward the midline, in the foot's axes
        axes = np.column_stack((along, across, np.cross(along, across)))
        middle = 0.5 * (toe.placement.translation + heel.placement.translation)
        for k, (inner, outer) in enumerate(footprint.bands):
            half = np.array([0.5 * length, max(0.5 * (inner + outer), 1e-4), SOLE_HALF_THICKNESS])
            boxes.append(SoleBox(side, k, joint, pin.SE3(axes, middle + across * 0.5 * (inner - outer)), half))
    return boxes


def sole_geometry(model: pin.Model, q: np.ndarray, footprint: Footprint) -> tuple[pin.GeometryModel, pin.GeometryData]:
    """The soles' boxes (:func:`sole_boxes`) as Pinocchio collision objects, each right-left pair a collision pair."""
    geometry = pin.GeometryModel()
    ids: dict[str, list[int]] = {side: [] for side in SIDES}
    for box in sole_boxes(model, q, footprint):
        shape = coal.Box(*(2.0 * box.half_size))
        ids[box.side].append(
            geometry.addGeometryObject(
                pin.GeometryObject(f"{box.side}_sole{box.band}", box.joint, box.placement, shape)
            )
        )
    for a in ids[SIDES[0]]:
        for b in ids[SIDES[1]]:
            geometry.addCollisionPair(pin.CollisionPair(a, b))
    return geometry, pin.GeometryData(geometry)
