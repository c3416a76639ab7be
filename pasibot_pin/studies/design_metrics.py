"""What a designer needs to know about one design: path, torques, spring, contact, energy.

:func:`design_metrics` takes a :class:`~pasibot_pin.model.design.Design` and returns a
:class:`DesignMetrics`: one value per entry of :data:`METRICS` (names carry their unit), or, for
a design that cannot work, the reason, never an exception. It is the row a design sweep or an
optimiser records (:mod:`pasibot_pin.studies.sweep`).

How each number is computed (one stance of the two-legged robot, right foot held flat, the
crank at the design's speed; the other crank is pi ahead, so one stance covers a full turn of
each crank):

* path (one leg, analytic assembly, :data:`PATH_SAMPLES` crank angles per turn): ``stride_m``
  and ``step_height_m`` are the horizontal and vertical extents of the ankle (joint 13) path
  over one crank turn; ``straightness_m`` is the largest distance of the stance ankle
  (theta in [pi/2, 3 pi/2]) from the chord of its ends; ``foot_level_err_deg`` is the largest
  |pitch| of the sole over stance as the linkage carries it (square to the shank for ``rigid``
  and ``spring``; the stabiliser's direction for ``parallel``); ``transmission_deg`` is the
  smallest distance of any loop to its singular (tangent) configuration over the turn;
* torques (constrained inverse dynamics, :data:`STANCE_SAMPLES` uniform samples):
  ``peak_crank_torque_Nm`` is the largest |torque| of any crank motor (of the one motor for
  ``motors = "one"``); ``rms_crank_torque_Nm`` its root mean square over the step time
  (Gauss-Legendre nodes, the energy's);
* spring: ``K_e_Nm_per_rad`` is the design's K_e, or the stance fit of the ankle torque; the
  margin ``K_e_margin_Nm_per_rad`` is K_e minus gravity's toppling stiffness about the stance
  ankle at mid-stance (:func:`~pasibot_pin.studies.spring_study.toppling_stiffness`);
* contact (the ground wrench on the stance sole split between heel and toe):
  ``cop_margin_m`` is the smallest signed distance of the centre of pressure to the nearer sole
  edge over stance (negative: the CoP leaves the sole, the foot rolls); ``friction_needed`` the
  largest |F_t| / F_n;
* energy (:func:`~pasibot_pin.studies.energy.robot_step_energy`): ``energy_per_step_J`` is the
  positive work of the crank motors over one step; ``cost_of_transport`` that work over
  (weight x distance walked in the step).

Infeasible designs (``feasible`` false, every metric NaN, ``reason`` says why, ``failure`` names
the kind): ``invalid`` (a combination the geometry rejects, e.g. L4 not longer than L7),
``assembly`` (a loop cannot close somewhere on the turn), ``singular`` (a loop within
:data:`SINGULAR_DEG` of a dead point, or a constraint Jacobian that loses rank), ``branch`` (the
solved configuration left the assembly branch: knee forward, coupler below the line 1-3),
``lift-off`` (the stance foot would have to be pulled down: the ground's normal force is not
positive somewhere in the stance, typically at high crank speed) and ``non-finite``.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from pasibot_pin.dynamics.inverse import STANCE_RANGE, crank_grid, inverse_dynamics
from pasibot_pin.errors import DesignError, InterferenceError, ParameterError
from pasibot_pin.model.assembly import leg_joint_angles, leg_points, sole_angle_from_points, transmission_angles, wrap
from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.model.placements import placement_map
from pasibot_pin.model.variants import get_motor_layout, get_variant
from pasibot_pin.reprs import short_repr
from pasibot_pin.studies.contact import cop_metrics, sole_geometry
from pasibot_pin.studies.energy import STEP_END, STEP_START, gauss_legendre, robot_step_energy
from pasibot_pin.studies.frontal_zmp import frontal_zmp
from pasibot_pin.studies.methods.spring_fit import fit_spring
from pasibot_pin.studies.motor_load import MotorLoad, motor_load
from pasibot_pin.studies.spring_study import toppling_stiffness
from pasibot_pin.studies.walking import WalkSettings, walk_design, walk_design_3d

if TYPE_CHECKING:
    from pasibot_pin.model.robot import PasibotRobot

PATH_SAMPLES: int = 1440
"""Crank angles per turn of the path metrics (every 0.25 deg)."""

STANCE_SAMPLES: int = 61
"""Uniform crank samples of the stance, both ends included (the spring fit's grid)."""

SINGULAR_DEG: float = 1.0
"""A loop closer than this to its dead point [deg] makes the design ``singular``."""

BRANCH_TOL: float = 1e-6
"""Largest knee-angle gap [rad] between the solved and the analytic configuration."""


@dataclass(frozen=True)
class MetricSpec:
    """One metric column: its name (with the unit in it), unit and meaning."""

    name: str
    unit: str
    doc: str
    sense: str = ""  # "min" / "max": the direction a designer usually wants, "" when neither


METRICS: Mapping[str, MetricSpec] = {
    m.name: m
    for m in (
        MetricSpec("stride_m", "m", "horizontal extent of the ankle path over one crank turn", "max"),
        MetricSpec("step_height_m", "m", "vertical extent of the ankle path over one crank turn"),
        MetricSpec("straightness_m", "m", "largest distance of the stance ankle from its chord", "min"),
        MetricSpec("foot_level_err_deg", "deg", "largest |sole pitch| over stance, as the linkage carries it", "min"),
        MetricSpec("transmission_deg", "deg", "smallest distance of a loop to its dead point over the turn", "max"),
        MetricSpec("peak_crank_torque_Nm", "N.m", "largest |crank motor torque| over the step", "min"),
        MetricSpec("rms_crank_torque_Nm", "N.m", "root mean square crank motor torque over the step", "min"),
        MetricSpec("energy_per_step_J", "J", "positive work of the crank motors over one step", "min"),
        MetricSpec("cost_of_transport", "-", "that work / (weight x distance of the step)", "min"),
        MetricSpec("K_e_Nm_per_rad", "N.m/rad", "ankle spring stiffness (the design's, or fitted)"),
        MetricSpec("K_e_margin_Nm_per_rad", "N.m/rad", "K_e minus gravity's toppling stiffness", "max"),
        MetricSpec("cop_margin_m", "m", "smallest distance of the CoP inside the sole over stance", "max"),
        MetricSpec("friction_needed", "-", "largest |F_t| / F_n over stance", "min"),
    )
}
"""Every metric of :class:`DesignMetrics`, by column name."""

FLOOR_METRICS: Mapping[str, MetricSpec] = {
    m.name: m
    for m in (
        MetricSpec("floor_walks", "-", "1 when the walking verdict is walks, else 0", "max"),
        MetricSpec("floor_steps", "-", "steps walked on the floor (landings at least 2 L ahead)", "max"),
        MetricSpec("floor_time_s", "s", "time the walking verdict was decided (its failure, or its last step)", "max"),
        MetricSpec("floor_advance_m", "m", "the hip's forward displacement on the floor", "max"),
        MetricSpec("floor_max_hip_pitch_deg", "deg", "largest |hip pitch| on the floor", "min"),
        MetricSpec("floor_max_slip_mm", "mm", "largest slide of a weight-bearing foot in one stance", "min"),
        MetricSpec("floor_cost_of_transport", "-", "motor positive work over weight x advance (whole strides)", "min"),
        MetricSpec("floor_energy_per_m_J", "J/m", "motor positive work per metre (whole strides)", "min"),
        MetricSpec("floor_motor_torque_peak_Nm", "N.m", "99th percentile of |crank torque| between exchanges", "min"),
        MetricSpec("floor_motor_torque_rms_Nm", "N.m", "RMS crank torque between foot exchanges", "min"),
        MetricSpec("floor_motor_power_peak_W", "W", "99th percentile of a crank's power between exchanges", "min"),
        MetricSpec("floor_exchange_impulse_Nms", "N.m.s", "largest crank impulse at a foot exchange", "min"),
    )
}
"""The optional floor-walk metrics (``design_metrics(design, floor=STEPS)``: the walking verdict of
:func:`~pasibot_pin.studies.walking.walk_design`), plus the outcome string ``floor_outcome``."""

FLOOR3D_METRICS: Mapping[str, MetricSpec] = {
    m.name: m
    for m in (
        MetricSpec("floor_max_hip_roll_deg", "deg", "largest |hip roll| on the 3-D floor", "min"),
        MetricSpec("floor_min_sole_clearance_mm", "mm", "least gap between the soles in the 3-D walk", "max"),
    )
}
"""The 3-D floor's extra metrics (``design_metrics(design, floor=STEPS, spatial=True)``:
:func:`~pasibot_pin.studies.walking.walk_design_3d`)."""

FLOOR_PLANAR_METRICS: Mapping[str, MetricSpec] = {
    m.name: m
    for m in (
        MetricSpec(
            "floor_frontal_zmp_margin_mm",
            "mm",
            "least frontal ZMP margin inside the stance sole over the planar walk (negative: it tips sideways)",
            "max",
        ),
    )
}
"""The planar floor's sideways filter (``design_metrics(design, floor=STEPS)`` on flat ground:
:func:`~pasibot_pin.studies.frontal_zmp.frontal_zmp` of the walk on the design's soles), a cheap
screen before a 3-D walk."""

MAX_FLOOR_STEPS = 1000
"""Most steps a design may be asked to walk in a table [-]."""

ALL_METRICS: Mapping[str, MetricSpec] = {**METRICS, **FLOOR_METRICS, **FLOOR3D_METRICS, **FLOOR_PLANAR_METRICS}
"""Every metric a table may hold, an objective, a constraint or a ranking may name."""

FAILURES: tuple[str, ...] = ("", "invalid", "assembly", "singular", "branch", "lift-off", "non-finite")
"""The kinds of infeasibility (``""``: feasible)."""
WALKABLE_FAILURES: tuple[str, ...] = ("lift-off",)
"""Kinds of infeasibility whose linkage still turns: such a design is walked on the floor all the same
(the floor has no held hip: its verdict is the answer the inverse dynamics cannot give)."""


@dataclass(frozen=True)
class DesignMetrics:
    """The metrics of one design.

    Attributes:
        values: ``{metric name: value}`` for every entry of :data:`METRICS` (NaN when infeasible).
        feasible: the design assembles, turns and stays off its dead points and branch.
        failure: the kind of infeasibility (:data:`FAILURES`), ``""`` when feasible.
        reason: a one-line explanation, ``""`` when feasible.

    """

    values: Mapping[str, float] = field(default_factory=dict)
    feasible: bool = True
    failure: str = ""
    reason: str = ""
    floor_outcome: str | None = None

    __repr__ = short_repr

    def row(self) -> dict[str, float | str | bool]:
        """The metrics (and the floor's, when simulated), then ``feasible``, ``failure`` and ``reason``."""
        out: dict[str, float | str | bool] = {k: float(self.values.get(k, math.nan)) for k in METRICS}
        if self.floor_outcome is not None:
            out.update({k: float(self.values.get(k, math.nan)) for k in FLOOR_METRICS})
            out.update({k: float(self.values[k]) for k in FLOOR3D_METRICS if k in self.values})  # a 3-D walk's
            out.update({k: float(self.values[k]) for k in FLOOR_PLANAR_METRICS if k in self.values})  # a planar one's
            out["floor_outcome"] = self.floor_outcome
        return {**out, "feasible": self.feasible, "failure": self.failure, "reason": self.reason}

    def __getitem__(self, name: str) -> float:
        return self.values[name]


class Infeasible(Exception):
    """A design that cannot work: ``kind`` is one of :data:`FAILURES`."""

    def __init__(self, kind: str, reason: str):
        super().__init__(reason)
        self.kind = kind


def infeasible(kind: str, reason: str) -> DesignMetrics:
    """The metrics of a design that cannot work (every value NaN)."""
    return DesignMetrics({k: math.nan for k in METRICS}, False, kind, " ".join(str(reason).split()))


# --------------------------------------------------------------------------- the pieces
def path_metrics(design: Design, samples: int = PATH_SAMPLES) -> dict[str, float]:
    """Stride, step height, straightness, foot level and transmission from the analytic assembly.

    Raises:
        Infeasible: ``assembly`` (a loop cannot close) or ``singular`` (a dead point).

    """
    try:
        geometry = design.geometry()
    except ValueError as err:
        raise Infeasible("invalid", str(err)) from None
    turn = np.linspace(0.0, 2 * math.pi, samples, endpoint=False)
    stance = np.linspace(math.pi / 2, 3 * math.pi / 2, samples // 2 + 1)  # both ends exact
    try:
        p_turn = leg_points(turn, geometry, design.variant)
        p_stance = leg_points(stance, geometry, design.variant)
    except ValueError as err:
        raise Infeasible("assembly", str(err)) from None
    gamma = transmission_angles(p_turn, design.variant)
    distance = {k: np.minimum(g, math.pi - g) for k, g in gamma.items()}
    worst_loop = min(distance, key=lambda k: float(distance[k].min()))
    transmission = float(distance[worst_loop].min())
    if math.degrees(transmission) < SINGULAR_DEG:
        th = float(turn[int(np.argmin(distance[worst_loop]))])
        raise Infeasible(
            "singular",
            f"loop {worst_loop} is {math.degrees(transmission):.3g} deg from its dead point at crank angle "
            f"{math.degrees(th):.1f} deg (limit {SINGULAR_DEG:g} deg)",
        )
    ankle = p_turn["p13"]
    a = p_stance["p13"]
    chord = a[-1] - a[0]
    normal = np.array([-chord[1], chord[0]]) / np.linalg.norm(chord)
    pitch = wrap(sole_angle_from_points(p_stance, design.variant))
    return {
        "stride_m": float(np.ptp(ankle[:, 0])),
        "step_height_m": float(np.ptp(ankle[:, 1])),
        "straightness_m": float(np.max(np.abs((a - a[0]) @ normal))),
        "foot_level_err_deg": math.degrees(float(np.max(np.abs(pitch)))),
        "transmission_deg": math.degrees(transmission),
    }


def _check_branch(robot: PasibotRobot, result) -> None:
    """Raise ``Infeasible('branch')`` if a solved knee angle differs from the analytic assembly's."""
    q = np.asarray(result.q)
    for side, offset in (("right", 0.0), ("left", math.pi)):
        analytic = leg_joint_angles(np.asarray(result.theta_right) + offset, robot.geometry, robot.spec)["j4"]
        solved = q[:, robot.idx_q(f"{side}_j4")]
        gap = np.abs(np.angle(np.exp(1j * (solved - analytic))))
        if float(gap.max()) > BRANCH_TOL:
            k = int(np.argmax(gap))
            raise Infeasible(
                "branch",
                f"the {side} knee left the assembly branch by {math.degrees(float(gap[k])):.3g} deg at crank "
                f"angle {math.degrees(float(result.theta_right[k] + offset)) % 360:.1f} deg",
            )


def dynamic_metrics(design: Design, robot: PasibotRobot | None = None) -> dict[str, float]:
    """Torque, spring, contact and energy metrics of one design (see the module's notes).

    Args:
        design: the design.
        robot: its two-legged robot, if already loaded (:func:`~pasibot_pin.model.design.design_robot`).

    Raises:
        Infeasible: ``assembly``, ``singular`` or ``branch``.

    """
    try:
        robot = design_robot(design, 2, visuals=False) if robot is None else robot
        omega = design.omega
        uniform = inverse_dynamics(
            robot,
            crank_grid(*STANCE_RANGE, STANCE_SAMPLES),
            omega,
            stance="right",
            reactions=False,
            motors=design.motors,
        )
        _check_branch(robot, uniform)
        fit = None
        stiffness = design.spring_stiffness
        if robot.spec.free_ankle:
            fit = fit_spring(uniform.beta, uniform.Te, warn=False)
            stiffness = fit.K_e if stiffness is None else stiffness
        energy, nodes = robot_step_energy(
            robot, max(omega, 1e-3), fit=fit if fit is not None else False, motors=design.motors
        )
        _x, _z, pitch, s_heel, s_toe = sole_geometry(robot, uniform.q[0], "right")  # welded: one sole pose
        _s_cop, margin, mu_needed = cop_metrics(uniform.ground, s_heel, s_toe, pitch)
        pulled = ~np.isfinite(mu_needed)
        if pulled.any():
            k = int(np.argmax(pulled))
            raise Infeasible(
                "lift-off",
                f"the ground would pull the stance foot down at crank angle "
                f"{math.degrees(float(uniform.theta_right[k])):.1f} deg (normal force {uniform.ground[k, 1]:.3g} N)",
            )
        topple = toppling_stiffness(robot) if robot.spec.free_ankle else math.nan
    except Infeasible:
        raise
    except (ValueError, np.linalg.LinAlgError, RuntimeError) as err:
        text = str(err)
        kind = "assembly" if "assemble" in text or "cannot close" in text or "full turn" in text else "singular"
        raise Infeasible(kind, text.splitlines()[0] if text else type(err).__name__) from None
    # a motor drives the stance crank for one step and the swing crank for the next (two motors),
    # or both cranks every step (one motor: its torque is Ta, Ta_swing is zero)
    motors = len(get_motor_layout(design.motors).motors)
    crank = np.abs(np.column_stack((uniform.Ta, uniform.Ta_swing))[:, :motors])
    node_torque = np.column_stack((nodes.Ta, nodes.Ta_swing))[1:-1, :motors]
    weights = _gl_weights(len(node_torque))
    rms = math.sqrt(float(np.mean(weights @ node_torque**2)) / float(weights.sum()))
    k_e = math.nan if stiffness is None else float(stiffness)
    return {
        "peak_crank_torque_Nm": float(crank.max()),
        "rms_crank_torque_Nm": rms,
        "energy_per_step_J": float(energy.crank[1]),
        "cost_of_transport": float(energy.cot["motors"]),
        "K_e_Nm_per_rad": k_e,
        "K_e_margin_Nm_per_rad": k_e - topple,
        "cop_margin_m": float(np.min(margin)),
        "friction_needed": float(np.max(mu_needed)),
    }


def _gl_weights(n: int) -> np.ndarray:
    return gauss_legendre(STEP_START, STEP_END, n)[1]


def warm_caches(design: Design) -> None:
    """Build what every evaluation of ``design``'s variant reuses (the tree's placement map, ~2 s).

    Call it before forking workers: they inherit it instead of each building their own.
    """
    placement_map(get_variant(design.variant).name, 2)


def floor_metrics(
    design: Design, steps: int, robot: PasibotRobot | None = None, spatial: bool = False, slope: float = 0.0
) -> tuple[dict[str, float], str]:
    """The design walking ``steps`` steps on the floor: :data:`FLOOR_METRICS` and the outcome.

    :func:`~pasibot_pin.studies.walking.walk_design`: both feet on the floor from a consistent
    start, the cranks at the design's speed, stopped as soon as the verdict is decided. With
    ``spatial``, :func:`~pasibot_pin.studies.walking.walk_design_3d` on the 3-D floor, plus
    :data:`FLOOR3D_METRICS`; soles or legs that meet at the start are the outcome ``collided``.
    ``slope``: the ground's angle, uphill positive [rad] (the planar floor's; 0: flat).
    """
    extra: dict[str, float] = {}
    load: MotorLoad | None = None  # the 3-D run records no motor torque
    if spatial:
        try:
            walk3d = walk_design_3d(design, WalkSettings(steps=steps, slope=slope), robot)
        except InterferenceError:  # the feet or legs meet before the walk: nothing walked
            values = dict.fromkeys(FLOOR_METRICS, math.nan)
            values.update(floor_walks=0.0, floor_steps=0.0, floor_time_s=0.0)
            values.update(dict.fromkeys(FLOOR3D_METRICS, math.nan))
            return values, "collided"
        v = walk3d.verdict
        extra = {
            "floor_max_hip_roll_deg": walk3d.result.max_hip_roll_deg,
            "floor_min_sole_clearance_mm": 1e3 * walk3d.result.min_sole_clearance_m,
        }
    else:
        robot = design_robot(design, 2, visuals=False) if robot is None else robot
        walk = walk_design(design, WalkSettings(steps=steps, slope=slope), robot)
        v = walk.verdict
        load = motor_load(walk.result, walk.omega, walk.settings.crank_ramp)
        extra = {"floor_frontal_zmp_margin_mm": math.nan if slope else _frontal_margin_mm(design, robot, walk.result)}
    values = {
        "floor_walks": float(v.walks),
        "floor_steps": float(v.steps),
        "floor_time_s": float(v.decided_at),
        "floor_advance_m": float(v.advance_m),
        "floor_max_hip_pitch_deg": math.degrees(v.max_hip_pitch),
        "floor_max_slip_mm": 1e3 * v.max_slip_m,
        "floor_cost_of_transport": float(v.cost_of_transport),
        "floor_energy_per_m_J": float(v.power_per_metre),
        "floor_motor_torque_peak_Nm": math.nan if load is None else load.torque_peak_Nm,
        "floor_motor_torque_rms_Nm": math.nan if load is None else load.torque_rms_Nm,
        "floor_motor_power_peak_W": math.nan if load is None else load.power_peak_W,
        "floor_exchange_impulse_Nms": math.nan if load is None else load.exchange_impulse_Nms,
    }
    return {**values, **extra}, v.outcome


def _frontal_margin_mm(design: Design, robot: PasibotRobot, result) -> float:
    """The planar walk's least frontal ZMP margin on the design's soles [mm].

    NaN without a single support, or where the sole fields describe no footprint.
    """
    try:
        footprint = design.footprint()
    except DesignError:
        return math.nan
    return 1e3 * frontal_zmp(robot, result, footprint).min_margin


def check_floor_steps(floor: int | None, name: str = "floor") -> int | None:
    """``floor`` if ``None`` or a step count in [1, :data:`MAX_FLOOR_STEPS`], else a ParameterError naming ``name``."""
    if floor is None:
        return None
    if isinstance(floor, bool) or not isinstance(floor, (int, np.integer)) or not 1 <= floor <= MAX_FLOOR_STEPS:
        raise ParameterError(f"{name} must be a number of steps in [1, {MAX_FLOOR_STEPS}], got {floor!r}")
    return int(floor)


def design_metrics(
    design: Design, floor: int | None = None, spatial: bool = False, slope: float = 0.0
) -> DesignMetrics:
    """Every metric of :data:`METRICS` for one design; an infeasible design is recorded, not raised.

    Args:
        design: the design (:class:`~pasibot_pin.model.design.Design`).
        floor: also walk it this many steps on the floor (:func:`floor_metrics`; slower).
        spatial: walk it on the 3-D floor (:data:`FLOOR3D_METRICS` too; about four times slower).
        slope: walk it up (positive) or down a slope of this angle [rad] (the planar floor; 0: flat).

    Returns:
        :class:`DesignMetrics`: the values, or the failure kind and reason.

    """
    if not isinstance(design, Design):
        raise TypeError(f"parameter 'design' must be a Design, got {type(design).__name__}")
    check_floor_steps(floor, "parameter 'floor'")
    outcome = None
    failure: Infeasible | None = None
    values: dict[str, float] = {}
    floor_values: dict[str, float] = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            values = path_metrics(design)
            values.update(dynamic_metrics(design))
        except Infeasible as err:
            failure = err
        if floor is not None and (failure is None or failure.kind in WALKABLE_FAILURES):
            floor_values, outcome = floor_metrics(design, floor, spatial=spatial, slope=slope)
            values.update(floor_values)
    if failure is not None:
        out = infeasible(failure.kind, str(failure))
        if floor is None:
            return out
        return DesignMetrics({**out.values, **floor_values}, False, out.failure, out.reason, outcome or "")
    springless = not get_variant(design.variant).free_ankle  # K_e is NaN by definition
    bad = [
        k
        for k, v in values.items()
        if not math.isfinite(v)
        and not (springless and k.startswith("K_e"))
        and k not in FLOOR_METRICS
        and k not in FLOOR3D_METRICS
        and k not in FLOOR_PLANAR_METRICS
    ]
    if bad:
        return infeasible("non-finite", f"non-finite {', '.join(bad)}")
    names = (
        *METRICS,
        *(FLOOR_METRICS if floor else ()),
        *(FLOOR3D_METRICS if floor and spatial else ()),
        *(FLOOR_PLANAR_METRICS if floor and not spatial else ()),
    )
    return DesignMetrics({k: values[k] for k in names}, floor_outcome=outcome)


def pareto_mask(x: np.ndarray, y: np.ndarray, senses: tuple[str, str] = ("min", "max")) -> np.ndarray:
    """True for the points no other point beats in both ``x`` and ``y`` (NaN points are never on it)."""
    sx = 1.0 if senses[0] == "min" else -1.0
    sy = 1.0 if senses[1] == "min" else -1.0
    a, b = sx * np.asarray(x, dtype=float), sy * np.asarray(y, dtype=float)
    ok = np.isfinite(a) & np.isfinite(b)
    mask = np.zeros(len(a), dtype=bool)
    idx = np.flatnonzero(ok)
    order = idx[np.lexsort((b[idx], a[idx]))]  # by a, then b
    best = math.inf
    for i in order:
        if b[i] < best:
            mask[i] = True
            best = b[i]
    return mask
