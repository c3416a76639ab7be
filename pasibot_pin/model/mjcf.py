"""MJCF export: the same robot for MuJoCo users (and an independent engine to check ours against).

The MJCF is written from the loaded Pinocchio model, so it has exactly its tree, joint
placements, masses and COMs, whatever the variant and parameters:

* one ``<body>`` per Pinocchio joint, nested as the tree (the same depth-first order, so
  MuJoCo's ``qpos`` is Pinocchio's ``q``); the planar floating hip is two slides (x, z) and a
  hinge about +y; every revolute joint a hinge about its axis (-y);
* every frame that matters (the cut-joint markers, feet, toes and heels) as a ``<site>``;
* the loop closures as ``<equality><connect site1 site2>`` at the cut joints;
* optionally a stance-foot weld (``<equality><weld>`` of the foot's site to a world site);
* the ankle springs as joint ``stiffness`` about ``springref`` = pi/2 - beta0, with ``damping``;
* the crank motors: a position servo (``ctrl`` = the crank angle) or a velocity servo;
* each sole as a capsule from heel to toe (the only geoms that collide) and a floor plane
  with Coulomb friction ``mu``.

Point masses have no rotational inertia; MuJoCo needs some, so ``boundinertia`` gives every
body at least ``1e-8`` kg.m^2 (a torque error below 1e-6 N.m at the accelerations here), or
more with a stiff ankle spring: a foot whose point mass lies on its own ankle axis (``foot_toe
= foot_heel``) has no inertia about it but that bound, and MuJoCo's explicit spring term then
blows up at t = 0 (K_e h^2 / I = 3 for K_e = 3000 N.m/rad at 0.1 ms). The default bound is
:func:`stable_boundinertia` (K_e h^2 / I <= 0.1; 3e-4 kg.m^2 there, a torque error below 1e-2
N.m, and 3e-5 kg.m^2 for the seed's ~300 N.m/rad springs).

Units: SI, angles [rad].
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from pasibot_pin.errors import DesignError, ParameterError
from pasibot_pin.model.description import sides
from pasibot_pin.model.spatial import FREE_FLYER_NAME, Footprint, planar_to_spatial, sole_boxes

if TYPE_CHECKING:
    from pasibot_pin.model.design import Design
    from pasibot_pin.model.robot import PasibotRobot

ACTUATORS: tuple[str, ...] = ("position", "velocity", "constraint", "none")


@dataclass(frozen=True)
class MjcfOptions:
    """What goes into the MJCF beyond the robot itself.

    Attributes:
        spring_stiffness: ankle spring K_e [N.m/rad] (0: no spring).
        spring_rest_angle: its rest angle beta0, forward foot to shank [rad].
        spring_damping: ankle damping [N.m.s/rad].
        actuator: ``position`` (servo on the crank angle), ``velocity`` (servo on its rate),
            ``constraint`` (each crank held on its angle by an ``equality joint`` named
            ``<crank>_drive``, as stiff as the loops: set ``model.eq_data[id, 0]`` to the angle
            each step; a rheonomic crank like ours, without a servo's compliance: kp = 5000
            N.m/rad lets a crank give 1-3 mrad under its 5-13 N.m, which relieves most of the squeeze
            of a foot standing on heel and toe) or ``none``.
        kp: position gain [N.m/rad]. The crank alone has a tiny inertia: with MuJoCo's explicit
            position term, kp dt^2 must stay small (5000 N.m/rad at 0.1 ms is stable; 2e4 at
            0.25 ms is not). A servo on theta0 + omega t lags by kv omega / kp: add it to ``ctrl``.
        kv: velocity gain [N.m.s/rad] (the position servo's damping, or the velocity servo's gain).
        weld_foot: ``right``/``left`` to weld that foot where it stands in ``q_weld``, or ``None``.
        floor: a floor plane the soles touch (``False``: no contact at all, e.g. with a welded foot).
        mu: sole-floor Coulomb friction [-].
        sole_radius: radius of the sole capsules [m].
        timestep: MuJoCo's step [s].
        noslip_iterations: MuJoCo's no-slip post-solve (0: off). MuJoCo's friction is soft: a
            contact inside its cone creeps (about 2 mm/s here, where our Coulomb contacts stick
            exactly); a few no-slip iterations make the friction hard, so that a stuck point stays
            put and only a point at its cone slides (what ``tests/test_mjcf.py`` compares modes with).
        planar_noslip: write the sole-floor friction coefficient as 2 mu (needs no-slip
            iterations). MuJoCo's no-slip solver on its pyramidal cone keeps each tangent
            direction's pair of edges at its share of the normal force, half of it with condim
            3, so along one direction the friction reaches only mu / 2 (a stuck point of the
            robot slides at friction use 0.40 for mu = 0.8). For motion in the x-z plane, 2 mu
            makes the x friction reach mu F_n, Coulomb's cone.
        solref: (time constant [s], damping ratio) of the equality constraints.
        solimp: MuJoCo's impedance (d0, dwidth, width) of the equality constraints: near 1 is
            near a hard constraint (MuJoCo's default 0.9 lets the loops give way enough to change
            the hip's fall by tens of percent: the spring and gravity nearly cancel here).
        contact_solref: (time constant [s], damping ratio) of the sole-floor contacts (MuJoCo's
            default (0.02, 1): a soft floor); the time constant must be >= 2 timesteps.
        contact_solimp: impedance (d0, dwidth, width) of the sole-floor contacts (MuJoCo's
            default (0.9, 0.95, 0.001)).
        slope: the floor plane's slope, rising along +x (uphill positive) [rad]; gravity stays vertical,
            as on our planar floor's sloped ground (0: the flat floor; less than pi/2 in size: a plane).
        footprint: the 3-D export (``None``: the planar one): the hip a ``freejoint`` named
            :data:`~pasibot_pin.model.spatial.FREE_FLYER_NAME` (qpos: x, y, z, quaternion w x y z,
            then the legs), each sole a box per band of this
            :class:`~pasibot_pin.model.spatial.Footprint` (``<side>_sole<k>``, ``sole_radius`` thick
            on each side of the heel-toe line) instead of the capsule.
        boundinertia: the least principal inertia of every body [kg.m^2] (MuJoCo's compiler
            ``boundinertia``; ``None``: :func:`stable_boundinertia` of the spring and the step).
            A point mass on its own joint axis (a foot with ``foot_toe = foot_heel``) has no
            inertia about it: with an ankle spring K_e the foot's own mode has a rate
            sqrt(K_e / I), which MuJoCo's explicit spring term cannot step unless K_e h^2 / I
            is small.

    """

    spring_stiffness: float = 0.0
    spring_rest_angle: float = math.pi / 2
    spring_damping: float = 0.0
    actuator: str = "position"
    kp: float = 5.0e3
    kv: float = 20.0
    weld_foot: str | None = None
    floor: bool = True
    mu: float = 0.8
    sole_radius: float = 0.002
    timestep: float = 1e-4
    noslip_iterations: int = 0
    solref: tuple[float, float] = (1e-3, 1.0)
    solimp: tuple[float, float, float] = (0.9999, 0.9999, 0.001)
    planar_noslip: bool = False
    contact_solref: tuple[float, float] = (0.02, 1.0)
    contact_solimp: tuple[float, float, float] = (0.9, 0.95, 0.001)
    boundinertia: float | None = None
    footprint: Footprint | None = None
    slope: float = 0.0

    def __post_init__(self) -> None:
        for name in ("spring_stiffness", "spring_damping", "kp", "kv", "mu", "sole_radius", "timestep", "boundinertia"):
            value = getattr(self, name)
            if name == "boundinertia" and value is None:
                continue
            if not (math.isfinite(value) and value >= 0):
                raise ParameterError(f"parameter {name!r} must be a finite number >= 0, got {value!r}")
        if not (isinstance(self.noslip_iterations, int) and 0 <= self.noslip_iterations <= 1000):
            raise ParameterError(
                f"parameter 'noslip_iterations' must be an integer in [0, 1000], got {self.noslip_iterations!r}"
            )
        if self.timestep <= 0 or self.sole_radius <= 0:
            raise ParameterError("parameters 'timestep' and 'sole_radius' must be positive")
        if not math.isfinite(self.spring_rest_angle):
            raise ParameterError(f"parameter 'spring_rest_angle' must be finite, got {self.spring_rest_angle!r}")
        if not (isinstance(self.slope, (int, float)) and abs(self.slope) < 0.5 * math.pi):  # NaN fails
            raise ParameterError(f"parameter 'slope' must be an angle in (-pi/2, pi/2) rad, got {self.slope!r}")
        if self.planar_noslip and not self.noslip_iterations:
            raise ParameterError("parameter 'planar_noslip' needs noslip_iterations > 0")
        if not (math.isfinite(self.contact_solref[0]) and self.contact_solref[0] >= 2 * self.timestep):
            raise ParameterError(
                f"parameter 'contact_solref' must have a time constant >= 2 timesteps, got {self.contact_solref!r}"
            )
        if self.actuator not in ACTUATORS:
            raise ParameterError(f"parameter 'actuator' must be one of {', '.join(ACTUATORS)}, got {self.actuator!r}")
        if self.footprint is not None and self.weld_foot is not None:
            raise ParameterError("parameter 'weld_foot': the 3-D export (footprint) has no foot weld")
        if self.weld_foot not in (None, "right", "left"):
            raise ParameterError(f"parameter 'weld_foot' must be right, left or None, got {self.weld_foot!r}")


MIN_BOUNDINERTIA = 1e-8
"""The least principal inertia of any exported body [kg.m^2]."""
SPRING_STEP_RATIO = 0.1
"""The largest K_e h^2 / I the export allows a body on a spring joint (:func:`stable_boundinertia`) [-]."""


def check_twin(design: Design) -> None:
    """Refuse, before any work, a design the MuJoCo export cannot model.

    Raises:
        DesignError: a lateral mass moved by the crank (``lateral_mass``): the export has no slider
            and MuJoCo's joint equalities are polynomials, not ``amplitude sin(theta + phase)``.

    """
    if design.lateral() is not None:
        raise DesignError(
            "parameter 'lateral_mass': the MuJoCo twin does not model a mass moved by the crank; "
            "walk it on our 3-D floor (pasibot walk --3d)"
        )


def stable_boundinertia(spring_stiffness: float, timestep: float) -> float:
    """The least body inertia [kg.m^2] that keeps a torsion spring stable at MuJoCo's step.

    A body of inertia I on a spring K [N.m/rad] stepped by h [s] with MuJoCo's explicit spring
    term is stable for K h^2 / I < 4 (symplectic Euler); this keeps K h^2 / I at most
    :data:`SPRING_STEP_RATIO`, and never below :data:`MIN_BOUNDINERTIA`.

    Args:
        spring_stiffness: K_e [N.m/rad].
        timestep: MuJoCo's step h [s].

    """
    return max(MIN_BOUNDINERTIA, spring_stiffness * timestep**2 / SPRING_STEP_RATIO)


def _vec(values) -> str:
    return " ".join(repr(float(x)) for x in values)


def _quat(rotation: np.ndarray) -> str:
    q = pin.Quaternion(rotation)  # MuJoCo: w x y z
    return _vec((q.w, q.x, q.y, q.z))


def _pose(element: ET.Element, placement: pin.SE3) -> None:
    element.set("pos", _vec(placement.translation))
    if not np.allclose(placement.rotation, np.eye(3), atol=1e-15):
        element.set("quat", _quat(placement.rotation))


def _hinge_axis(joint) -> np.ndarray:
    kind = joint.shortname()
    if kind == "JointModelRevoluteUnaligned":
        return np.array(joint.extract().axis)
    if kind in ("JointModelRY", "JointModelRX", "JointModelRZ"):
        return np.eye(3)["XYZ".index(kind[-1])]
    raise ValueError(f"joint kind {kind} has no MJCF hinge")


def _joints(body: ET.Element, model: pin.Model, j: int) -> list[ET.Element]:
    """Add the MJCF joints of Pinocchio joint ``j`` to ``body``; returns them."""
    joint, name = model.joints[j], model.names[j]
    subjoints = joint.extract().joints if joint.shortname() == "JointModelComposite" else [joint]
    elements = []
    for k, sub in enumerate(subjoints):
        kind = sub.shortname()
        sub_name = name if len(subjoints) == 1 else f"{name}_{k}"
        if kind in ("JointModelPX", "JointModelPY", "JointModelPZ"):
            axis = np.eye(3)["XYZ".index(kind[-1])]
            elements.append(ET.SubElement(body, "joint", name=sub_name, type="slide", axis=_vec(axis)))
        elif kind == "JointModelPrismaticUnaligned":
            elements.append(ET.SubElement(body, "joint", name=sub_name, type="slide", axis=_vec(sub.extract().axis)))
        else:
            elements.append(ET.SubElement(body, "joint", name=sub_name, type="hinge", axis=_vec(_hinge_axis(sub))))
    return elements


def _inertial(body: ET.Element, inertia: pin.Inertia) -> None:
    i = inertia.inertia
    if inertia.mass <= 0:
        return
    ET.SubElement(
        body,
        "inertial",
        pos=_vec(inertia.lever),
        mass=repr(float(inertia.mass)),
        fullinertia=_vec((i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2])),
    )


def _sole_friction(options: MjcfOptions) -> str:
    """The sole-floor ``friction`` attribute: sliding (mu, or 2 mu with ``planar_noslip``), torsional, rolling."""
    return f"{options.mu * (2.0 if options.planar_noslip else 1.0)!r} 0.005 0.0001"


def to_mjcf(robot: PasibotRobot, options: MjcfOptions | None = None, q_weld: np.ndarray | None = None) -> str:
    """The MJCF text of ``robot`` (any variant, one or two legs).

    Args:
        robot: a loaded robot (:func:`pasibot_pin.load`).
        options: springs, actuators, weld, floor (:class:`MjcfOptions`).
        q_weld: the configuration whose foot pose the weld keeps (default ``robot.q0``).

    Returns:
        The MJCF document.

    """
    options = options or MjcfOptions()
    q_home = robot.q0 if q_weld is None else np.asarray(q_weld, dtype=float)
    root = ET.Element("mujoco", model=f"pasibot_{robot.variant}_{robot.legs}leg")
    _add_settings(root, robot.model, options)
    world = _add_world(root, options)
    if options.footprint is not None and not robot.floating:
        raise ParameterError("parameter 'footprint': the 3-D export needs the two-legged robot with its floating hip")
    bodies, joints = _add_bodies(world, robot.model, free_root=options.footprint is not None)
    if options.footprint is None:
        _add_soles(bodies, robot, options)
    else:
        _add_sole_boxes(bodies, robot, options, options.footprint)
    _set_ankle_springs(joints, robot, options)
    equality = ET.SubElement(root, "equality")
    _add_loop_closures(equality, robot)
    if options.weld_foot is not None:
        _add_foot_weld(world, equality, robot, options.weld_foot, q_home)
    _add_home_keyframe(root, robot, options, q_home)
    if options.actuator == "constraint":
        _add_crank_drives(equality, robot, q_home)
    if options.actuator in ("position", "velocity"):
        _add_crank_servos(root, robot, options)
    ET.indent(root)
    return ET.tostring(root, encoding="unicode") + "\n"


def _add_settings(root: ET.Element, model: pin.Model, options: MjcfOptions) -> None:
    """The compiler (radians, ``boundinertia``), the step, gravity and integrator, the defaults."""
    bound = options.boundinertia
    if bound is None:
        bound = stable_boundinertia(options.spring_stiffness, options.timestep)
    ET.SubElement(
        root, "compiler", angle="radian", autolimits="true", inertiafromgeom="false", boundinertia=repr(float(bound))
    )
    option = ET.SubElement(
        root, "option", timestep=repr(options.timestep), gravity=_vec(model.gravity.linear), integrator="implicitfast"
    )
    if options.noslip_iterations:
        option.set("noslip_iterations", str(options.noslip_iterations))
    default = ET.SubElement(root, "default")
    ET.SubElement(default, "geom", contype="0", conaffinity="0", rgba="0.6 0.6 0.7 1")
    ET.SubElement(default, "equality", solref=_vec(options.solref), solimp=_vec(options.solimp))


def _add_world(root: ET.Element, options: MjcfOptions) -> ET.Element:
    """The ``worldbody``: a light and the floor plane (colliding with the soles only when ``options.floor``)."""
    world = ET.SubElement(root, "worldbody")
    ET.SubElement(world, "light", pos="0 -2 3", dir="0 1 -1")
    floor = ET.SubElement(
        world,
        "geom",
        name="floor",
        type="plane",
        size="20 2 0.1",
        contype="1" if options.floor else "0",
        conaffinity="1" if options.floor else "0",
        friction=_sole_friction(options),
        rgba="0.85 0.85 0.8 1",
    )
    if options.slope:  # the plane's normal, (-sin, 0, cos) of the slope: it rises along +x
        floor.set("zaxis", _vec(np.array([-math.sin(options.slope), 0.0, math.cos(options.slope)])))
    return world


def _add_bodies(
    world: ET.Element, model: pin.Model, free_root: bool = False
) -> tuple[dict[int, ET.Element], dict[str, ET.Element]]:
    """One body per Pinocchio joint, nested as the tree: its joints, inertia, link sticks and frame sites.

    ``free_root``: the root body's joint is a ``freejoint`` (the 3-D export), not the planar hip's.

    Returns:
        The bodies by Pinocchio joint index (0: the world) and the MJCF joints by name.

    """
    bodies: dict[int, ET.Element] = {0: world}
    joints: dict[str, ET.Element] = {}
    frames_by_joint: dict[int, list[pin.Frame]] = {}
    for frame in model.frames:
        if frame.type == pin.FrameType.BODY and frame.parentJoint > 0:
            frames_by_joint.setdefault(int(frame.parentJoint), []).append(frame)
    for j in range(1, model.njoints):
        body = ET.SubElement(bodies[model.parents[j]], "body", name=f"{model.names[j]}_body")
        _pose(body, model.jointPlacements[j])
        if free_root and j == 1:
            joints[FREE_FLYER_NAME] = ET.SubElement(body, "freejoint", name=FREE_FLYER_NAME)
        else:
            joints.update((element.attrib["name"], element) for element in _joints(body, model, j))
        _inertial(body, model.inertias[j])
        for child in [k for k in range(j + 1, model.njoints) if model.parents[k] == j]:
            end = model.jointPlacements[child].translation
            if np.linalg.norm(end) > 1e-9:  # a visual stick along the link (no mass, no contact)
                ET.SubElement(body, "geom", type="capsule", fromto=_vec((0, 0, 0, *end)), size="0.004", group="1")
        for frame in frames_by_joint.get(j, []):
            site = ET.SubElement(body, "site", name=frame.name, size="0.003")
            _pose(site, frame.placement)
        bodies[j] = body
    return bodies, joints


def _add_soles(bodies: dict[int, ET.Element], robot: PasibotRobot, options: MjcfOptions) -> None:
    """A capsule from heel to toe on each foot body: the only geoms that collide (with the floor)."""
    model = robot.model
    for side in sides(robot.legs):
        toe, heel = (model.frames[robot.frame_id(f"{side}_{p}")] for p in ("toe", "heel"))
        if toe.parentJoint != heel.parentJoint:
            raise DesignError(f"the {side} toe and heel are on different bodies")
        ET.SubElement(
            bodies[int(toe.parentJoint)],
            "geom",
            name=f"{side}_sole",
            type="capsule",
            fromto=_vec((*heel.placement.translation, *toe.placement.translation)),
            size=repr(options.sole_radius),
        ).attrib.update(_sole_contact(options))


def _sole_contact(options: MjcfOptions) -> dict[str, str]:
    """A sole geom's contact attributes (the capsule's and the boxes'): it touches the floor, not itself."""
    return {
        "contype": "1",
        "conaffinity": "0",
        "condim": "3",
        "friction": _sole_friction(options),
        "solref": _vec(options.contact_solref),
        "solimp": _vec(options.contact_solimp),
        "rgba": "0.2 0.2 0.2 1",
    }


def _add_sole_boxes(
    bodies: dict[int, ET.Element], robot: PasibotRobot, options: MjcfOptions, footprint: Footprint
) -> None:
    """Each foot's sole as boxes, one per band of ``footprint`` (:func:`~pasibot_pin.model.spatial.sole_boxes`).

    Their half thickness is ``options.sole_radius`` (the capsule's), so the contacts sit where the capsule's do.
    """
    for box in sole_boxes(robot.model, robot.q0, footprint):
        element = ET.SubElement(
            bodies[box.joint],
            "geom",
            name=f"{box.side}_sole{box.band}",
            type="box",
            size=_vec((box.half_size[0], box.half_size[1], options.sole_radius)),
        )
        element.attrib.update(_sole_contact(options))
        _pose(element, box.placement)


def spatial_qpos(q: np.ndarray) -> np.ndarray:
    """A planar configuration as the 3-D export's ``qpos``: x, y, z, quaternion w x y z, the legs."""
    q3 = planar_to_spatial(q)
    return np.concatenate((q3[:3], [q3[6]], q3[3:6], q3[7:]))


def _set_ankle_springs(joints: dict[str, ET.Element], robot: PasibotRobot, options: MjcfOptions) -> None:
    """The ankle springs as joint stiffness: ``springref`` where beta = beta0 (q = pi/2 - beta), and damping."""
    for name in robot.spring_joints:
        joint = joints[name]
        joint.set("stiffness", repr(float(options.spring_stiffness)))
        joint.set("springref", repr(math.pi / 2 - options.spring_rest_angle))
        joint.set("damping", repr(float(options.spring_damping)))


def _add_loop_closures(equality: ET.Element, robot: PasibotRobot) -> None:
    """Each loop closure as a ``connect`` of its two cut-joint sites."""
    for loop in robot.loops:
        ET.SubElement(equality, "connect", name=loop.name, site1=loop.frame_a, site2=loop.frame_b)


def _add_foot_weld(world: ET.Element, equality: ET.Element, robot: PasibotRobot, foot: str, q: np.ndarray) -> None:
    """Weld ``foot`` (``right``/``left``) to a world site where it stands in configuration ``q``."""
    if not robot.floating:
        raise ParameterError("the one-leg model has a fixed hip: it has no foot to weld")
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, q)
    anchor = ET.SubElement(world, "site", name=f"{foot}_foot_anchor", size="0.003")
    _pose(anchor, data.oMf[robot.frame_id(f"{foot}_foot")])
    ET.SubElement(equality, "weld", name=f"{foot}_foot_weld", site1=f"{foot}_foot", site2=f"{foot}_foot_anchor")


def _add_home_keyframe(root: ET.Element, robot: PasibotRobot, options: MjcfOptions, q_home: np.ndarray) -> None:
    """The ``home`` keyframe: ``q_home`` (it closes every loop; MuJoCo's qpos0 = 0 does not) and the servos' ctrl."""
    keyframe = ET.SubElement(root, "keyframe")
    qpos = q_home if options.footprint is None else spatial_qpos(q_home)
    home = ET.SubElement(keyframe, "key", name="home", qpos=_vec(qpos))
    motors = robot.actuated_joints
    if options.actuator == "position" and motors:
        home.set("ctrl", _vec([q_home[robot.idx_q(motor)] for motor in motors]))
    elif options.actuator == "velocity" and motors:
        home.set("ctrl", _vec([0.0] * len(motors)))


def _add_crank_drives(equality: ET.Element, robot: PasibotRobot, q_home: np.ndarray) -> None:
    """Each crank held on its angle by an ``equality joint`` ``<crank>_drive`` (starting at ``q_home``'s)."""
    for motor in robot.actuated_joints:  # q - qpos0 = polycoef[0] (qpos0 = 0: no joint ref)
        polycoef = _vec((q_home[robot.idx_q(motor)], 0, 0, 0, 0))
        ET.SubElement(equality, "joint", name=f"{motor}_drive", joint1=motor, polycoef=polycoef)


def _add_crank_servos(root: ET.Element, robot: PasibotRobot, options: MjcfOptions) -> None:
    """A position or velocity servo on each crank (no ``actuator`` element without cranks)."""
    if not robot.actuated_joints:
        return
    actuators = ET.SubElement(root, "actuator")
    for motor in robot.actuated_joints:
        if options.actuator == "position":
            ET.SubElement(actuators, "position", name=motor, joint=motor, kp=repr(options.kp), kv=repr(options.kv))
        else:
            ET.SubElement(actuators, "velocity", name=motor, joint=motor, kv=repr(options.kv))
