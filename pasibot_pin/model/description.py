"""The robot description: xacro to URDF, and the table of cut joints (loops).

The URDF is a strict tree. Each cut revolute joint ``N`` of a leg is a pair of marker frames
``<side>_loop_jN_a`` and ``<side>_loop_jN_b`` that must coincide; :mod:`pasibot_pin.model.robot`
turns every pair into a Pinocchio constraint model.
"""

from __future__ import annotations

import copy
import functools
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from pasibot_pin.errors import ParameterError
from pasibot_pin.files import write_text_atomic
from pasibot_pin.model.coordinates import SIDES
from pasibot_pin.model.params import Geometry, MassModel, check_legs, check_variant, percentage_mass_model
from pasibot_pin.model.paths import URDF_DIR, XACRO_PATH, urdf_path
from pasibot_pin.model.spatial import CENTRED_SOLE, Footprint, lateral_sign
from pasibot_pin.model.variants import VARIANT_RECORDS, Variant, get_variant

CUT_JOINTS: dict[str, tuple[int, ...]] = {name: v.cut_joints for name, v in VARIANT_RECORDS.items()}
"""Seed joint numbers cut open in each variant (seed §5; docs/reference.md §4 for the extension): from the records."""

CUT_BODIES: dict[int, tuple[str, str]] = {
    2: ("l2_coupler", "l3_rocker"),
    5: ("l4", "l6"),
    7: ("l5_shank", "l7"),
    4: ("l2_coupler", "l8_stabiliser"),
    11: ("l9", "l10"),
    13: ("l5_shank", "foot_bar"),
}
"""The two links each cut joint connects (side a, side b), without the leg prefix."""


ROOT_JOINT_NAME = "hip_planar"
"""The biped's root joint: the hip's planar floating joint."""


def planar_root_joint() -> pin.JointModelComposite:
    """Planar floating joint in the x-z plane: PX, PZ, then rotation about -y.

    The pitch is counter-clockwise positive seen from the robot's right side, as every
    revolute joint of the model. (``JointModelPlanar`` is the x-y plane: the wrong plane.)
    """
    joint = pin.JointModelComposite(3)
    joint.addJoint(pin.JointModelPX())
    joint.addJoint(pin.JointModelPZ())
    joint.addJoint(pin.JointModelRevoluteUnaligned(np.array([0.0, -1.0, 0.0])))
    return joint


def build_tree(text: str, legs: int) -> pin.Model:
    """The Pinocchio tree of URDF ``text``: with :func:`planar_root_joint` for the biped, fixed hip for one leg."""
    if legs == 2:
        return pin.buildModelFromXML(text, planar_root_joint(), ROOT_JOINT_NAME)
    return pin.buildModelFromXML(text)


def sides(legs: int) -> tuple[str, ...]:
    """Leg prefixes of a robot with ``legs`` legs: ``('right',)`` or ``('right', 'left')``."""
    return ("right",) if check_legs(legs) == 1 else ("right", "left")


@dataclass(frozen=True)
class Loop:
    """One cut revolute joint: two frames whose origins must coincide.

    Attributes:
        name: ``<side>_j<N>``, e.g. ``right_j2``.
        side: ``right`` or ``left``.
        joint: the seed's joint number.
        frame_a: marker frame on the first link.
        frame_b: marker frame on the second link.
        links: the two links the joint connects.

    """

    name: str
    side: str
    joint: int
    frame_a: str
    frame_b: str
    links: tuple[str, str]


def loop_table(variant: str | Variant = "spring", legs: int = 2) -> list[Loop]:
    """The cut joints of a robot, one :class:`Loop` each, right leg first."""
    spec = get_variant(variant)
    table = []
    for side in sides(legs):
        for joint in spec.cut_joints:
            link_a, link_b = CUT_BODIES[joint]
            table.append(
                Loop(
                    name=f"{side}_j{joint}",
                    side=side,
                    joint=joint,
                    frame_a=f"{side}_loop_j{joint}_a",
                    frame_b=f"{side}_loop_j{joint}_b",
                    links=(f"{side}_{link_a}", f"{side}_{link_b}"),
                )
            )
    return table


def xacro_arguments(
    variant: str = "spring",
    legs: int = 2,
    geometry: Geometry | None = None,
    masses: MassModel | None = None,
    inertia: str = "point",
) -> dict[str, str]:
    """Every xacro argument for a parameter set, as strings (``repr`` of floats).

    ``inertia``: ``point`` (the seed's point masses, zero rotational inertia) or ``uniform``
    (rods, the hip a box: the inertias :func:`pasibot_pin.model.robot.load` gives).
    """
    if inertia not in ("point", "uniform"):
        raise ParameterError(f"parameter 'inertia' must be 'point' or 'uniform', got {inertia!r}")
    check_variant(variant)
    check_legs(legs)
    geometry = geometry or Geometry()
    masses = masses or percentage_mass_model(geometry, variant)
    toe, heel = geometry.foot_extent(variant)
    args = {
        "variant": variant,
        "legs": str(legs),
        "L": repr(float(geometry.L)),
        "K": repr(float(geometry.K)),
        "foot_toe": repr(toe),
        "foot_heel": repr(heel),
        "hip_half_width": repr(float(geometry.hip_half_width)),
        "m_hip": repr(float(masses.hip)),
        "hip_com_x": repr(float(masses.hip_com[0])),
        "hip_com_z": repr(float(masses.hip_com[1])),
        "m_foot": repr(float(masses.foot)),
        "foot_com": repr(float(masses.foot_com)),
        "inertia": inertia,
    }
    args.update({key: repr(float(value)) for key, value in geometry.ratios.items()})
    args.update({f"m_{key}": repr(float(value)) for key, value in masses.links.items()})
    return args


def render_urdf(
    variant: str = "spring",
    legs: int = 2,
    geometry: Geometry | None = None,
    masses: MassModel | None = None,
    inertia: str = "point",
) -> str:
    """Render the xacro source to URDF text (no ROS needed).

    Args:
        variant: ``rigid``, ``parallel`` or ``spring``.
        legs: 1 (fixed hip) or 2 (biped).
        geometry: leg geometry (default: the seed's).
        masses: mass model (default: the seed's percentage rule).
        inertia: ``point`` masses (zero rotational inertia) or ``uniform`` rods [kg.m^2 in the file].

    Returns:
        The URDF as a string. The xacro banner names the source relative to the
        repository, so the text does not depend on where the package is installed.
        The text of the last :data:`RENDER_CACHE` distinct argument sets is kept (xacro takes
        tens of milliseconds; a study loads the same design many times).

    """
    mappings = xacro_arguments(variant, legs, geometry, masses, inertia)
    return _render(tuple(sorted(mappings.items())))


RENDER_CACHE = 64
"""How many rendered URDF texts :func:`render_urdf` keeps (one per distinct xacro argument set)."""


@functools.lru_cache(maxsize=RENDER_CACHE)
def _render(mappings: tuple[tuple[str, str], ...]) -> str:
    """The xacro source processed with ``mappings`` (sorted (name, value) pairs), as URDF text."""
    import xacro  # deferred: heavy (xacro), keeps the CLI's start fast

    document = xacro.process_file(str(XACRO_PATH), mappings=dict(mappings))
    text = document.toprettyxml(indent="  ")
    return text.replace(str(XACRO_PATH), "urdf/pasibot.urdf.xacro")


def write_urdf(path: Path, text: str, force: bool = False) -> Path:
    """Write ``text`` to ``path`` (through a temporary file); refuse to overwrite a different file unless ``force``."""
    path = Path(path)
    if path.is_dir():
        raise ParameterError(f"{path} is a folder; give a file name")
    if path.exists() and not force and path.read_text() != text:
        raise FileExistsError(f"{path} exists and differs; pass force=True (--force) to overwrite it")
    return write_text_atomic(path, text)


def is_installed_package_dir(path: Path) -> bool:
    """True when ``path`` lies inside an installed distribution (a ``site-packages`` or ``dist-packages`` folder)."""
    return any(part in ("site-packages", "dist-packages") for part in Path(path).resolve().parts)


def render_default_urdfs(out_dir: Path | None = None, force: bool = True) -> list[Path]:
    """Render the default URDFs (every variant, one and two legs) into ``out_dir``.

    Args:
        out_dir: target folder; ``None``: the package's own ``urdf/`` folder of a source checkout.
        force: overwrite files that differ.

    Raises:
        ValueError: ``out_dir`` is ``None`` and the package is installed (its ``urdf/`` folder is
            inside ``site-packages``): name a folder of your own instead.

    """
    if out_dir is None:
        if is_installed_package_dir(URDF_DIR):
            raise ParameterError(
                f"the default URDFs belong to the installed package ({URDF_DIR}); it is not rewritten: "
                "write them elsewhere with --out FOLDER (Python: render_default_urdfs(out_dir=...))"
            )
        out_dir = URDF_DIR
    out_dir = Path(out_dir)
    written = []
    for variant in VARIANT_RECORDS:
        for legs in (1, 2):
            target = out_dir / urdf_path(variant, legs).name
            written.append(write_urdf(target, render_urdf(variant, legs), force=force))
    return written


SOLE_WIDTH = 2.0 * CENTRED_SOLE
"""The xacro's sole width over L (``foot_width``; a test reads it there): the centred plate [-]."""


def shape_soles(text: str, footprint: Footprint, L: float) -> str:
    """The URDF ``text`` with each foot's sole drawn as ``footprint``'s bands (a plate or a comb's prongs).

    The xacro draws one centred box per foot, :data:`SOLE_WIDTH` L wide. Each band becomes a box of
    its own, as long and as thick as that one, spanning the band across the leg's plane: the right
    foot's midline side is +y of its frame, the left foot's -y (the feet's y axes are the hip's).
    The visual and the collision geometry both change; the tree, masses and frames do not. A
    footprint that is the xacro's own plate returns ``text`` unchanged.

    Args:
        text: URDF text rendered from the xacro (:func:`render_urdf`), one or two legs.
        footprint: the soles' lateral shape [m].
        L: the crank length [m] (the xacro's plate is :data:`SOLE_WIDTH` L wide).

    """
    plate = Footprint.centred(L).bands
    if len(footprint.bands) == 1 and np.allclose(footprint.bands, plate, rtol=0.0, atol=1e-12):
        return text
    root = ET.fromstring(text)
    for link in root.iter("link"):
        side = link.get("name", "").removesuffix("_foot")
        if side not in SIDES or link.get("name") != f"{side}_foot":
            continue
        sign = lateral_sign(side)
        for tag in ("visual", "collision"):
            elements = link.findall(tag)
            template = elements[0]
            for element in elements:
                link.remove(element)
            for inner, outer in footprint.bands:
                link.append(_band_element(template, sign * 0.5 * (inner - outer), inner + outer))
    ET.indent(root, space="  ")
    return '<?xml version="1.0" ?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _band_element(template: ET.Element, y: float, width: float) -> ET.Element:
    """A copy of a foot's ``visual``/``collision`` element moved to ``y`` [m] and ``width`` [m] wide."""
    element = copy.deepcopy(template)
    origin, box = element.find("origin"), element.find("geometry/box")
    if origin is None or box is None:
        raise ParameterError("the URDF's foot geometry is not an origin and a box; cannot shape its sole")
    x, _, z = origin.get("xyz", "0 0 0").split()
    origin.set("xyz", f"{x} {y + 0.0!r} {z}")  # + 0.0: no "-0.0"
    length, _, thickness = box.get("size", "0 0 0").split()
    box.set("size", f"{length} {max(width, 1e-4)!r} {thickness}")
    return element
