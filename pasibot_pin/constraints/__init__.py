"""The constraint core: one system for loops, foot welds, prescribed coordinates and couplings.

:mod:`.pinocchio_models` builds Pinocchio's constraint models (and wraps Pinocchio's own
constrained algorithms as references); :mod:`.system` evaluates every row and solves on the
manifold; :func:`frame_rows` builds the planar rows of frames outside a system (contact points,
a sole's pose). No other module builds rows or calls Pinocchio's constraint or Jacobian API.

The public API is what ``__all__`` lists; :class:`~.planar.PlanarRowBlocks` is what
:func:`frame_rows` returns.
"""

from pasibot_pin.constraints.pinocchio_models import (
    anchor_points,
    constraint_size,
    create_datas,
    ground_point_constraint,
    inplane_rows,
    is_weld,
    model_key,
    pinocchio_constraint_jacobian,
    planar_rows,
    point_constraint,
    proximal_forward_dynamics,
    proximal_impulse,
    weld_constraint,
)
from pasibot_pin.constraints.planar import FloatingForm
from pasibot_pin.constraints.system import (
    ANGLE_TOL,
    RELATIVE_TOL,
    ConstraintSystem,
    CoordinateRow,
    PitchRow,
    Rows,
    ScalarRow,
    coordinate,
    coupling,
    frame_jacobian,
    frame_rows,
    planar_pitch,
    split_torques,
    symmetric_mass_matrix,
)

__all__ = [
    "ANGLE_TOL",
    "RELATIVE_TOL",
    "ConstraintSystem",
    "FloatingForm",
    "CoordinateRow",
    "PitchRow",
    "Rows",
    "ScalarRow",
    "anchor_points",
    "constraint_size",
    "coordinate",
    "coupling",
    "create_datas",
    "frame_jacobian",
    "frame_rows",
    "ground_point_constraint",
    "inplane_rows",
    "is_weld",
    "planar_rows",
    "model_key",
    "planar_pitch",
    "pinocchio_constraint_jacobian",
    "point_constraint",
    "proximal_forward_dynamics",
    "proximal_impulse",
    "split_torques",
    "symmetric_mass_matrix",
    "weld_constraint",
]
