"""``load()``: the PASIBOT Pinocchio model with its loop-closure constraints and ``q0``."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin

from pasibot_pin import constraints
from pasibot_pin.errors import DesignError, ParameterError
from pasibot_pin.model import placements
from pasibot_pin.model.assembly import check_full_turn
from pasibot_pin.model.closure import assemble, mobility
from pasibot_pin.model.description import (  # noqa: F401 (planar_root_joint, ROOT_JOINT_NAME: re-exported)
    ROOT_JOINT_NAME,
    Loop,
    build_tree,
    loop_table,
    planar_root_joint,
    render_urdf,
    shape_soles,
    sides,
)
from pasibot_pin.model.params import (
    MASS_RULES,
    Geometry,
    MassModel,
    check_legs,
)
from pasibot_pin.model.paths import urdf_path
from pasibot_pin.model.spatial import Footprint
from pasibot_pin.model.variants import Variant, get_variant

INERTIA_MODES = ("point", "uniform")


EXTENSION_BARS: dict[str, tuple[str, int]] = {
    "l8_stabiliser": ("l8", 8),
    "l9": ("l9", 9),
    "l10": ("l10", 10),
    "l11": ("l11", 11),
    "foot_bar": ("foot_bar", 10),
}
"""The parallel extension's bars: link -> (mass key, length index) (the foot bar is as long as L10)."""


def _link_inertias(masses: MassModel, geometry: Geometry, variant: str | Variant, mode: str) -> dict[str, pin.Inertia]:
    """Inertia of every massive link (without side prefix, and ``hip``) in its own frame."""
    if mode not in INERTIA_MODES:
        raise ParameterError(f"unknown inertia mode {mode!r}; valid: {', '.join(INERTIA_MODES)}")

    def rod(mass: float, length: float, com_x: float) -> pin.Inertia:
        rot = np.zeros((3, 3))
        if mode == "uniform":
            i_perp = mass * length**2 / 12.0
            rot = np.diag([0.0, i_perp, i_perp])
        return pin.Inertia(mass, np.array([com_x, 0.0, 0.0]), rot)

    bars = {
        "l1_crank": ("l1", 1),
        "l2_coupler": ("l2", 2),
        "l3_rocker": ("l3", 3),
        "l4": ("l4", 4),
        "l5_shank": ("l5", 5),
        "l6": ("l6", 6),
        "l7": ("l7", 7),
    }
    spec = get_variant(variant)
    if spec.extension:
        bars.update(EXTENSION_BARS)
    out = {}
    for link, (key, index) in bars.items():
        length = geometry.length(index)
        out[link] = rod(masses.links[key], length, length / 2)
    if spec.extension:
        out["slider"] = pin.Inertia(masses.links["slider"], np.zeros(3), np.zeros((3, 3)))
    toe, heel = geometry.foot_extent(variant)
    out["foot"] = rod(masses.foot, toe + heel, masses.foot_com)
    hip_com = np.array([geometry.length(0) + masses.hip_com[0], 0.0, -geometry.length(13) + masses.hip_com[1]])
    hip_rot = np.zeros((3, 3))
    if mode == "uniform":  # a solid box the size of the hip's visual
        a, c = geometry.length(0) + 4 * geometry.L, geometry.length(13) + 2 * geometry.L
        b = 2 * geometry.hip_half_width
        hip_rot = masses.hip / 12.0 * np.diag([b**2 + c**2, a**2 + c**2, a**2 + b**2])
    out["hip"] = pin.Inertia(masses.hip, hip_com, hip_rot)
    return out


def apply_masses(
    model: pin.Model, masses: MassModel, geometry: Geometry, variant: str, legs: int, inertia: str = "point"
) -> None:
    """Set every joint's inertia of ``model`` from ``masses`` (in place).

    Links merged by fixed joints (the rigid foot, marker frames) are summed into their
    parent joint's body, so the result does not depend on how the URDF was split.
    """
    per_link = _link_inertias(masses, geometry, variant, inertia)
    for j in range(model.njoints):
        model.inertias[j] = pin.Inertia.Zero()
    for link, inertia_local in per_link.items():
        names = ["hip"] if link == "hip" else [f"{side}_{link}" for side in sides(legs)]
        for name in names:
            frame = model.frames[model.getFrameId(name, pin.FrameType.BODY)]
            if frame.parentJoint == 0:
                continue  # fixed hip of the one-leg model: its mass is carried by the world
            model.inertias[frame.parentJoint] += frame.placement.act(inertia_local)


@dataclass
class PasibotRobot:
    """A loaded PASIBOT: Pinocchio models, loop constraints, actuation and a closed ``q0``.

    Attributes:
        variant: ``rigid``, ``parallel`` or ``spring``.
        spec: the variant's record (cut joints, actuation, springs, extension, sole).
        legs: 1 (hip fixed to the world, the leg frame) or 2 (planar floating hip).
        geometry: leg geometry.
        masses: mass model in use.
        inertia: ``point`` (the seed's point masses) or ``uniform`` (uniform rods).
        model: Pinocchio model of the open tree.
        data: its data.
        visual_model: visual geometry (primitives coloured by group); ``None`` when loaded
            with ``visuals=False``.
        collision_model: collision geometry (``None`` likewise).
        loops: the cut joints, one :class:`~pasibot_pin.model.description.Loop` each.
        constraint_models: one ``RigidConstraintModel`` per loop, then the stance-foot weld
            (two legs only).
        stance: the welded foot's side (``right``) or ``None`` for one leg.
        actuated_joints: the crank joint names (right first).
        spring_joints: the ankle joint names of the ``spring`` variant.
        q0: a configuration that satisfies every constraint: right crank at 180 deg,
            left crank pi apart, hip level, swing foot level.
        urdf: the URDF text the model was built from.

    """

    variant: str
    legs: int
    geometry: Geometry
    masses: MassModel
    inertia: str
    model: pin.Model
    data: pin.Data
    visual_model: pin.GeometryModel | None
    collision_model: pin.GeometryModel | None
    loops: list[Loop]
    spec: Variant
    constraint_models: list[pin.RigidConstraintModel] = field(default_factory=list)
    stance: str | None = None
    actuated_joints: list[str] = field(default_factory=list)
    spring_joints: list[str] = field(default_factory=list)
    q0: np.ndarray = field(default_factory=lambda: np.zeros(0))
    urdf: str = ""

    @property
    def loop_constraints(self) -> list[pin.RigidConstraintModel]:
        """The loop-closure constraint models (without the weld)."""
        return self.constraint_models[: len(self.loops)]

    @property
    def weld(self) -> pin.RigidConstraintModel | None:
        """The stance-foot weld, if any."""
        extra = self.constraint_models[len(self.loops) :]
        return extra[0] if extra else None

    @property
    def floating(self) -> bool:
        """True when the hip is a planar floating base (two legs)."""
        return self.legs == 2

    def idx_v(self, joint: str) -> int:
        """Velocity index of a one-dof joint by name."""
        if not self.model.existJointName(joint):
            raise ParameterError(f"unknown joint {joint!r}")
        return self.model.joints[self.model.getJointId(joint)].idx_v

    def idx_q(self, joint: str) -> int:
        """Configuration index of a one-dof joint by name."""
        if not self.model.existJointName(joint):
            raise ParameterError(f"unknown joint {joint!r}")
        return self.model.joints[self.model.getJointId(joint)].idx_q

    def frame_id(self, name: str) -> int:
        """Frame index by name, with a clear error."""
        if not self.model.existFrame(name):
            raise ParameterError(f"unknown frame {name!r}")
        return self.model.getFrameId(name)

    def weld_foot(self, side: str, q: np.ndarray) -> pin.RigidConstraintModel:
        """A weld of ``side``'s foot to the ground at its pose in ``q``, sole level.

        The target keeps the foot's x and z from ``q`` and sets its pitch to zero.
        """
        if not self.floating:
            raise ParameterError("the one-leg model has a fixed hip: it needs no foot weld")
        if side not in sides(self.legs):
            raise ParameterError(f"unknown side {side!r}; valid: {', '.join(sides(self.legs))}")
        pin.framesForwardKinematics(self.model, self.data, q)
        position = self.data.oMf[self.frame_id(f"{side}_foot")].translation.copy()
        target = pin.SE3(np.eye(3), position)
        return constraints.weld_constraint(self.model, f"{side}_foot", target, f"{side}_foot_weld")

    def with_stance(self, side: str, q: np.ndarray) -> PasibotRobot:
        """A shallow copy whose weld holds ``side``'s foot where it is in ``q``."""
        return self.with_weld(side, self.weld_foot(side, q))

    def with_weld(self, side: str, weld: pin.RigidConstraintModel) -> PasibotRobot:
        """A shallow copy standing on ``side`` with the stance weld ``weld``."""
        copy = PasibotRobot(**{k: getattr(self, k) for k in self.__dataclass_fields__})
        copy.constraint_models = list(self.loop_constraints) + [weld]
        copy.stance = side
        return copy

    def __repr__(self) -> str:
        """One short line: variant, legs, L, K, nq, nv, loops and stance (``summary()`` says more)."""
        return (
            f"PasibotRobot(variant={self.variant!r}, legs={self.legs}, L={self.geometry.L:g} m, "
            f"K={self.geometry.K:g}, nq={self.model.nq}, nv={self.model.nv}, loops={len(self.loops)}, "
            f"stance={self.stance!r})"
        )

    def summary(self) -> str:
        """A short human-readable description (nq, nv, loops, actuation, mobility)."""
        mob = mobility(self)
        lines = [
            f"PASIBOT variant={self.variant} legs={self.legs} L={self.geometry.L:g} m K={self.geometry.K:g}",
            f"  nq = {self.model.nq}, nv = {self.model.nv}, bodies = {self.model.nbodies - 1}",
            f"  loops ({len(self.loops)}): "
            + ", ".join(f"{lp.name} [{lp.links[0]} | {lp.links[1]}]" for lp in self.loops),
            f"  weld: {self.weld.name if self.weld is not None else 'none (hip fixed to the world)'}",
            f"  actuated joints: {', '.join(self.actuated_joints)}",
            f"  spring joints: {', '.join(self.spring_joints) or 'none'}",
            f"  Gruebler DOF = {mob.grubler} (bodies {mob.moving_bodies}, 1-dof pairs {mob.pairs}, welds {mob.welds})",
            f"  numerical mobility nv - rank(J_c) = {self.model.nv} - {mob.rank} = {mob.numerical}",
            f"  leg-linkage mobility per leg = {mob.leg_linkage}",
            f"  mass model: {self.masses.rule}, inertia: {self.inertia}",
            mass_line(self),
        ]
        return "\n".join(lines)


SEED_MASS_RULES: tuple[str, ...] = ("seed-percentages", "scenario ")
"""Mass models (their ``rule`` or its start) of the seed's robots: the report's percentage rule (hip 25 %
of the 65 kg human) and the seed scenarios' stated bodies (:mod:`pasibot_pin.model.scenario_robots`)."""


def mass_line(robot: PasibotRobot) -> str:
    """The summary's mass line [kg], named for what the robot is.

    "robot mass" for a design's robot (``pasibot info``, ``walk``, the design files), "seed scenario
    mass" for the seed's (:data:`SEED_MASS_RULES`), so that no reader takes one for the other.
    """
    total = total_mass(robot)
    if robot.legs != 2:
        return f"  one leg's mass: {total:.3f} kg (no hip)"
    rule, hip = robot.masses.rule, robot.masses.hip
    if rule.startswith("design"):
        return f"  robot mass: {total:.3f} kg (its moving bodies; the hip {hip:.3f} kg of it)"
    what = "seed scenario mass" if rule.startswith(SEED_MASS_RULES) else "model mass"
    return f"  {what}: {total:.3f} kg ({rule}: the hip {hip:.3f} kg of it; a design's robot has its body_mass there)"


def total_mass(robot: PasibotRobot) -> float:
    """Total mass of the model's moving bodies [kg] (the one-leg model excludes the hip)."""
    return float(sum(robot.model.inertias[j].mass for j in range(1, robot.model.njoints)))


def load(
    variant: str = "spring",
    legs: int = 2,
    *,
    geometry: Geometry | None = None,
    masses: MassModel | None = None,
    mass_rule: str = "seed",
    inertia: str = "point",
    visuals: bool = True,
    footprint: Footprint | None = None,
    **geometry_changes: float,
) -> PasibotRobot:
    """Build the closed-loop PASIBOT model.

    Args:
        variant: ``rigid`` (foot rigid to L5), ``parallel`` (parallel extension) or
            ``spring`` (revolute ankle for a torsion spring). Default ``spring``.
        legs: 1 (one leg, hip fixed: the leg frame is the world) or 2 (biped with a
            planar floating hip and the right foot welded to the ground).
        geometry: leg geometry; default the seed's (L = 0.05 m, K = 2).
        masses: mass model; default from ``mass_rule``.
        mass_rule: ``seed`` (seed Table 7.1.1 percentages of 65 kg) or ``human``
            (example-robot-data's human model fractions).
        inertia: ``point`` (point masses at link mid-points) or ``uniform`` (uniform rods).
        visuals: build the URDF text and the visual and collision models. ``False`` (design
            sweeps) builds the tree from :func:`pasibot_pin.model.placements.tree` (the same
            xacro's translations, mapped: about 50x faster) and leaves ``urdf`` empty and the
            geometry models ``None``.
        footprint: the soles' lateral shape [m] for the visual and collision models
            (:func:`~pasibot_pin.model.description.shape_soles`); ``None``: the xacro's centred plate.
        **geometry_changes: shortcuts for geometry fields and link ratios
            (``L=0.1``, ``K=2.2``, ``r4=9.5``).

    Returns:
        A :class:`PasibotRobot` whose ``q0`` satisfies every constraint.

    Raises:
        ValueError: unknown variant, leg count, mass rule or inertia mode; a non-positive,
            non-finite or out-of-range parameter (:data:`~pasibot_pin.model.params.LENGTH_RANGE`,
            :data:`~pasibot_pin.model.params.RATIO_RANGE`); a mass model lacking a link the
            variant needs; a geometry whose loops cannot assemble at q0 or at some crank angle
            of a full turn (:func:`~pasibot_pin.model.assembly.check_full_turn`).

    """
    spec = get_variant(variant)
    check_legs(legs)
    geometry, masses = _geometry_and_masses(spec.name, geometry, masses, mass_rule, geometry_changes)
    if inertia not in INERTIA_MODES:
        raise ParameterError(f"unknown inertia mode {inertia!r}; valid: {', '.join(INERTIA_MODES)}")
    model, text = _build_tree(spec.name, legs, geometry, masses, inertia, visuals)
    if footprint is not None and visuals:
        text = shape_soles(text, footprint, geometry.L)
    robot = PasibotRobot(
        variant=spec.name,
        legs=legs,
        geometry=geometry,
        masses=masses,
        inertia=inertia,
        model=model,
        data=model.createData(),
        visual_model=pin.buildGeomFromUrdfString(model, text, pin.GeometryType.VISUAL) if visuals else None,
        collision_model=pin.buildGeomFromUrdfString(model, text, pin.GeometryType.COLLISION) if visuals else None,
        loops=loop_table(spec.name, legs),
        constraint_models=[],
        spec=spec,
        actuated_joints=[f"{s}_{j}" for s in sides(legs) for j in spec.actuated_joints],
        spring_joints=[f"{s}_{j}" for s in sides(legs) for j in spec.spring_joints],
        urdf=text,
    )
    robot.constraint_models = [
        constraints.point_constraint(model, lp.frame_a, lp.frame_b, lp.name) for lp in robot.loops
    ]
    _assemble_at_start(robot)
    return robot


def _geometry_and_masses(
    variant: str,
    geometry: Geometry | None,
    masses: MassModel | None,
    mass_rule: str,
    geometry_changes: dict[str, float],
) -> tuple[Geometry, MassModel]:
    """The geometry (with the shortcuts' changes) and the mass model of :func:`load`, checked."""
    geometry = geometry or Geometry()
    if geometry_changes:
        geometry = geometry.with_(**geometry_changes)
    if masses is None:
        if mass_rule not in MASS_RULES:
            raise ParameterError(f"unknown mass_rule {mass_rule!r}; valid: {', '.join(MASS_RULES)}")
        masses = MASS_RULES[mass_rule](geometry, variant)
    masses.check_links(variant)
    return geometry, masses


def _build_tree(
    variant: str, legs: int, geometry: Geometry, masses: MassModel, inertia: str, visuals: bool
) -> tuple[pin.Model, str]:
    """The Pinocchio tree with its masses, and the URDF text it came from (empty without visuals)."""
    text = ""
    if visuals:
        default = geometry == Geometry() and masses == MASS_RULES["seed"](Geometry(), variant)
        path = urdf_path(variant, legs)
        text = path.read_text() if default and path.is_file() else render_urdf(variant, legs, geometry, masses)
        model = build_tree(text, legs)
    else:
        model = placements.tree(variant, legs, geometry)
    model.name = f"pasibot_{variant}_{legs}leg"
    apply_masses(model, masses, geometry, variant, legs, inertia)
    for j in range(model.njoints):
        if not np.all(np.isfinite(model.inertias[j].toDynamicParameters())):
            raise DesignError(
                f"the geometry and masses give a non-finite inertia on joint {model.names[j]!r}; "
                "check the sizes (L, link ratios, sole) and masses"
            )
    return model, text


def _assemble_at_start(robot: PasibotRobot) -> None:
    """Close the loops at theta = pi (``q0``), check a full turn assembles, weld a biped's right foot."""
    q0 = assemble(robot, math.pi)
    check_full_turn(robot.geometry, robot.spec)
    if robot.legs == 2:
        robot.constraint_models.append(robot.weld_foot("right", q0))
        robot.stance = "right"
    robot.q0 = q0
