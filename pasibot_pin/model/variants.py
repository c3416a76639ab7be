"""The leg variants and motor layouts as records (data only).

A :class:`Variant` says what a leg of that variant is made of: which seed joints are cut to
make the URDF a tree, which joints are driven, which carry a spring, whether the parallel
extension (stabiliser L8, L9, L10, L11, slider, foot bar) is present, how the sole is held
and which frame is the ankle on the open chain. Code asks the record, never the name: the
only place a variant's name decides anything is the table :data:`VARIANT_RECORDS` below.

A :class:`MotorLayout` says how the cranks are driven: one motor each, or one motor for both
with the coupling q_L - q_R - pi = 0 as one more constraint row.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from pasibot_pin.errors import ParameterError

SOLE_MODES: tuple[str, ...] = ("square", "stabiliser", "ankle")
"""How the sole is held: ``square`` to the shank (rigid foot), parallel to the ``stabiliser``
L8, or on a revolute ``ankle`` (free, sprung)."""


@dataclass(frozen=True)
class Variant:
    """One leg variant of the seed, as data.

    Attributes:
        name: ``rigid``, ``parallel`` or ``spring``.
        description: one line for reports.
        cut_joints: seed joint numbers cut open to make the tree (each a point-coincidence loop).
        actuated_joints: driven joints of one leg, without the side prefix.
        spring_joints: joints carrying a torsion spring (a free ankle), without the side prefix.
        extension: the parallel extension is present (links l8..l11, slider, foot bar).
        sole: how the sole is held (one of :data:`SOLE_MODES`).
        ankle_frame: the frame at joint 13 carried by the open chain j0-j1-j4-j6, without side.
        foot_fields: the :class:`~pasibot_pin.model.params.Geometry` fields of toe and heel over L.

    """

    name: str
    description: str
    cut_joints: tuple[int, ...]
    actuated_joints: tuple[str, ...] = ("j0_crank",)
    spring_joints: tuple[str, ...] = ()
    extension: bool = False
    sole: str = "square"
    ankle_frame: str = "foot"
    foot_fields: tuple[str, str] = ("foot_toe", "foot_heel")

    def __post_init__(self) -> None:
        if self.sole not in SOLE_MODES:
            raise ParameterError(f"unknown sole mode {self.sole!r}; valid: {', '.join(SOLE_MODES)}")

    @property
    def free_ankle(self) -> bool:
        """True when the foot turns on its own joint: its pitch must be prescribed or simulated."""
        return bool(self.spring_joints)


VARIANT_RECORDS: Mapping[str, Variant] = {
    "rigid": Variant(
        "rigid",
        "foot rigidly square to the shank L5 (seed §4.2)",
        cut_joints=(2, 5, 7),
    ),
    "parallel": Variant(
        "parallel",
        "parallel extension: the foot stays parallel to the stabiliser L8 (seed §4.3)",
        cut_joints=(2, 5, 7, 4, 11, 13),
        extension=True,
        sole="stabiliser",
        ankle_frame="loop_j13_a",
        foot_fields=("parallel_toe", "parallel_heel"),
    ),
    "spring": Variant(
        "spring",
        "revolute ankle with a torsion spring, no extension (seed §7)",
        cut_joints=(2, 5, 7),
        spring_joints=("j13_ankle",),
        sole="ankle",
    ),
}
"""Every variant, by name (the only place a name decides anything)."""


def get_variant(variant: str | Variant) -> Variant:
    """The record of ``variant`` (a name or a record); ValueError naming the valid ones."""
    if isinstance(variant, Variant):
        return variant
    if variant not in VARIANT_RECORDS:
        raise ParameterError(f"unknown variant {variant!r}; valid variants: {', '.join(VARIANT_RECORDS)}")
    return VARIANT_RECORDS[variant]


@dataclass(frozen=True)
class MotorLayout:
    """How the cranks are driven.

    Attributes:
        name: ``two`` (one motor per crank) or ``one`` (one motor drives both).
        motors: the driven crank(s) of a biped, with side prefix.
        couplings: (joint, minus joint, offset [rad]) rows q[joint] - q[minus] = offset.

    """

    name: str
    motors: tuple[str, ...]
    couplings: tuple[tuple[str, str, float], ...] = ()


MOTOR_LAYOUTS: Mapping[str, MotorLayout] = {
    "two": MotorLayout("two", ("right_j0_crank", "left_j0_crank")),
    "one": MotorLayout("one", ("right_j0_crank",), (("left_j0_crank", "right_j0_crank", math.pi),)),
}
"""The motor layouts, by name."""


def get_motor_layout(name: str | MotorLayout) -> MotorLayout:
    """The motor layout called ``name``; ValueError naming the valid ones."""
    if isinstance(name, MotorLayout):
        return name
    if name not in MOTOR_LAYOUTS:
        raise ParameterError(f"unknown motor layout {name!r}; valid: {', '.join(MOTOR_LAYOUTS)}")
    return MOTOR_LAYOUTS[name]
