"""Foot paths of one leg and multi-step biped gaits, with their CSV rows: pure compute.

- :class:`GaitSettings` / :func:`gait_run`: one leg over one crank turn (:class:`LegRun`) or the
  biped on its prescribed gait over several steps (:class:`BipedRun`) (the ``pasibot gait`` command).
- :class:`KinematicsSettings` / :func:`kinematics_survey`: the leg of every variant, the K sweep,
  the open-chain Jacobian and the biped gaits (the ``kinematics`` section of ``pasibot analyze``).
- :data:`LEG_COLUMNS` / :func:`leg_rows` and :func:`gait_columns` / :func:`gait_rows`: the CSV
  header and rows of a leg cycle and of a gait.

Built on :mod:`pasibot_pin.kinematics.leg` and :mod:`pasibot_pin.kinematics.gait`. Nothing here
writes files or draws. Units: SI; angles [rad] unless a name ends in ``_deg``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pasibot_pin.errors import ParameterError
from pasibot_pin.kinematics import leg as kin
from pasibot_pin.kinematics import path_metrics
from pasibot_pin.kinematics.gait import FOOT_MODES, MAX_GAIT_SAMPLES, Gait, gait_and_advances
from pasibot_pin.model.design import check_parameter, design_robot
from pasibot_pin.model.params import VARIANTS
from pasibot_pin.model.robot import load
from pasibot_pin.reprs import short_repr

if TYPE_CHECKING:
    from pasibot_pin.model.design import Design
    from pasibot_pin.model.robot import PasibotRobot

LEG_COLUMNS: tuple[str, ...] = (
    "theta",
    "ankle_x",
    "ankle_z",
    "toe_x",
    "toe_z",
    "heel_x",
    "heel_z",
    "foot_pitch",
    "ankle_vx",
    "ankle_vz",
    "ankle_ax",
    "ankle_az",
    "stance",
)
"""CSV columns for one leg: [rad], [m], [rad], [m/s], [m/s^2]; ``stance`` is 1 in 90..270 deg."""

GAIT_POINTS: tuple[tuple[str, str], ...] = (("ankle", "foot"), ("toe", "toe"), ("heel", "heel"))
"""Gait CSV points: (column prefix, frame suffix after ``right_``/``left_``)."""

SPEED_ANGLES_DEG: tuple[float, float, float] = (90.0, 180.0, 270.0)
"""Crank angles at which the ankle's forward speed is reported [deg]."""


# --------------------------------------------------------------------------- CSV rows
def gait_columns() -> list[str]:
    """CSV columns for the biped gait (world frame, [rad], [s], [m])."""
    cols = ["theta", "theta_left", "t", "step", "stance", "hip_x", "hip_z", "hip_pitch"]
    for side in ("right", "left"):
        cols += [f"{side}_{p}_{axis}" for p, _ in GAIT_POINTS for axis in ("x", "z")]
        cols.append(f"{side}_foot_pitch")
    return cols


def leg_rows(cycle: kin.LegCycle) -> list[list]:
    """CSV rows (:data:`LEG_COLUMNS`) of a leg cycle.

    Args:
        cycle: a leg cycle computed with ``omega`` (velocities and accelerations present).

    Returns:
        One row per sample: floats, and ``stance`` as 0/1.

    """
    stance = cycle.in_stance()
    velocity, acceleration = cycle.ankle_velocity, cycle.ankle_acceleration
    if velocity is None or acceleration is None:
        raise ParameterError("the leg cycle was sampled without omega: no ankle velocity or acceleration")
    rows = []
    for k in range(len(cycle.theta)):
        rows.append(
            [
                float(cycle.theta[k]),
                *map(float, cycle.ankle[k]),
                *map(float, cycle.toe[k]),
                *map(float, cycle.heel[k]),
                float(cycle.foot_pitch[k]),
                *map(float, velocity[k]),
                *map(float, acceleration[k]),
                int(stance[k]),
            ]
        )
    return rows


def gait_rows(w: Gait) -> list[list]:
    """CSV rows (:func:`gait_columns`) of a gait.

    Args:
        w: the gait; ``t`` is NaN when it has no crank rate.

    Returns:
        One row per sample: floats, ``step`` as int and ``stance`` as ``right``/``left``.

    """
    frames = ["hip"] + [f"{side}_{frame}" for side in ("right", "left") for _, frame in GAIT_POINTS]
    xz = w.frames_xz(frames)
    hip_pitch = w.pitch("hip")
    pitch = {side: w.pitch(f"{side}_foot") for side in ("right", "left")}
    t = w.t if w.t is not None else np.full(w.n, np.nan)
    rows = []
    for k in range(w.n):
        row = [
            float(w.theta[k]),
            float(w.theta[k] + math.pi),
            float(t[k]),
            int(w.step[k]),
            w.stance[k],
            *map(float, xz["hip"][k]),
            float(hip_pitch[k]),
        ]
        for side in ("right", "left"):
            for _, frame in GAIT_POINTS:
                row += list(map(float, xz[f"{side}_{frame}"][k]))
            row.append(float(pitch[side][k]))
        rows.append(row)
    return rows


# --------------------------------------------------------------------------- one run
def samples(span_deg: float, step_deg: float) -> int:
    """Number of crank intervals of ``step_deg`` in ``span_deg``.

    Args:
        span_deg: the crank span [deg] (360 for one turn, 180 for one step).
        step_deg: the crank increment [deg].

    Raises:
        ValueError: ``step_deg`` not positive, not dividing the span into >= 2 samples, or
            giving more than :data:`~pasibot_pin.kinematics.gait.MAX_GAIT_SAMPLES` of them.

    """
    if not math.isfinite(step_deg) or step_deg <= 0.0:
        raise ParameterError(f"parameter '--step-deg' must be a positive crank increment [deg], got {step_deg!r}")
    count = span_deg / step_deg
    if count > MAX_GAIT_SAMPLES:
        raise ParameterError(
            f"parameter '--step-deg' = {step_deg:g} deg gives {count:.3g} samples per {span_deg:g} deg; "
            f"at most {MAX_GAIT_SAMPLES} (take a step of at least {span_deg / MAX_GAIT_SAMPLES:g} deg)"
        )
    n = round(count)
    if n < 2 or abs(count - n) > 1e-9 * count:
        raise ParameterError(
            f"parameter '--step-deg' = {step_deg:g} deg must divide {span_deg:g} deg into >= 2 samples"
        )
    return n


@dataclass(frozen=True)
class LegRun:
    """One leg over one crank turn, in the leg frame.

    Attributes:
        variant: the leg variant.
        L: crank length [m].
        omega: crank rate [rad/s].
        cycle: the sampled cycle (positions, velocities, accelerations).
        metrics: straight-line quality of the ankle path (extremes refined on the closure manifold).
        speed_ratios: ankle forward speed / (L omega) at :data:`SPEED_ANGLES_DEG` (3,) [-].

    """

    __repr__ = short_repr

    variant: str
    L: float
    omega: float
    cycle: kin.LegCycle
    metrics: path_metrics.StraightLineMetrics
    speed_ratios: np.ndarray


@dataclass(frozen=True)
class BipedRun:
    """The biped on its prescribed gait over several steps, in the world frame.

    Attributes:
        variant: the leg variant.
        foot: stance contact, ``flat``, ``point`` or ``toe``.
        steps: steps (half crank turns).
        samples_per_step: crank intervals per step.
        L: crank length [m].
        gait: the sampled gait.
        hip_advance: hip x travel of each step, start to next start (steps,) [m] (:func:`step_advances`).
        hip_height_ptp: peak-to-peak hip height [m].
        hip_pitch: hip pitch at every sample (N,) [rad].
        max_residual: largest closure residual [m or rad].
        max_jump: largest pose jump at an exchange, 0 without exchanges [m or rad].

    """

    __repr__ = short_repr

    variant: str
    foot: str
    steps: int
    samples_per_step: int
    L: float
    gait: Gait
    hip_advance: np.ndarray
    hip_height_ptp: float
    hip_pitch: np.ndarray
    max_residual: float
    max_jump: float


def leg_run(robot: PasibotRobot, step_deg: float = 5.0, omega: float = 0.1) -> LegRun:
    """One crank turn of a one-leg robot, sampled every ``step_deg``.

    Args:
        robot: a one-leg robot (``load(variant, 1)``).
        step_deg: crank increment [deg]; must divide 360 deg.
        omega: crank rate [rad/s].

    Raises:
        ValueError: a bad ``step_deg`` (see :func:`samples`).

    """
    n = samples(360.0, step_deg)
    cycle = kin.leg_cycle(robot, kin.crank_grid(2 * math.pi / n), omega=omega)
    metrics = path_metrics.straight_line_metrics(robot, cycle=cycle)  # the same turn, sampled once (1 deg steps)
    L = robot.geometry.L
    speed_cycle = kin.leg_cycle(robot, np.radians(list(SPEED_ANGLES_DEG)), omega=omega)
    assert speed_cycle.ankle_velocity is not None  # sampled with omega
    speeds = speed_cycle.ankle_velocity[:, 0]
    return LegRun(robot.variant, L, omega, cycle, metrics, speeds / (L * omega))


def biped_run(
    robot: PasibotRobot, steps: int = 2, step_deg: float = 5.0, omega: float = 0.1, foot: str = "flat"
) -> BipedRun:
    """The biped on its prescribed gait, ``steps`` steps from right touch-down, sampled every ``step_deg``.

    Args:
        robot: a two-leg robot (``load(variant, 2)``).
        steps: steps (half crank turns), >= 1.
        step_deg: crank increment [deg]; must divide 180 deg.
        omega: crank rate [rad/s] (time stamps).
        foot: stance contact, ``flat``, ``point`` or ``toe``.

    Raises:
        ValueError: a bad ``step_deg``, ``steps`` or ``foot``, or a pose where the loops cannot close.

    """
    sps = samples(180.0, step_deg)
    # each step's advance from its start to the next step's start (same phase: just after an exchange),
    # read off one gait of a step more (gait_and_advances: the same numbers as prescribed_gait and step_advances)
    w, advances = gait_and_advances(robot, steps, sps, omega=omega, foot=foot)
    hip = w.hip_path()
    return BipedRun(
        variant=robot.variant,
        foot=w.foot,
        steps=steps,
        samples_per_step=sps,
        L=robot.geometry.L,
        gait=w,
        hip_advance=advances,
        hip_height_ptp=float(np.ptp(hip[:, 1])),
        hip_pitch=w.pitch(),
        max_residual=float(w.residual.max()),
        max_jump=max(w.exchange_jump) if w.exchange_jump else 0.0,
    )


@dataclass(frozen=True)
class GaitSettings:
    """One gait run (the ``pasibot gait`` command's settings).

    Attributes:
        variant: leg variant (see :data:`pasibot_pin.model.params.VARIANTS`).
        legs: 1 (one crank turn in the leg frame) or 2 (the biped gait).
        steps: steps of the gait with 2 legs (``None``: 2); must be ``None`` with 1 leg.
        step_deg: crank increment between samples [deg].
        omega: crank rate [rad/s].
        foot: stance contact with 2 legs: ``flat``, ``point`` or ``toe`` (``None``: ``flat``);
            must be ``None`` with 1 leg.
        design: a :class:`~pasibot_pin.model.design.Design` whose robot steps (its variant replaces
            ``variant``); ``None``: the seed design of ``variant``.

    Raises:
        ValueError: ``legs`` not 1 or 2, ``omega`` not a positive number, ``steps`` or
            ``foot`` given with 1 leg, an unknown ``foot``, ``steps`` < 1, a bad ``step_deg``,
            or more than :data:`~pasibot_pin.kinematics.gait.MAX_GAIT_SAMPLES` samples: all
            checked here, before any work.

    """

    variant: str = "spring"
    legs: int = 1
    steps: int | None = None
    step_deg: float = 5.0
    omega: float = 0.1
    foot: str | None = None
    design: Design | None = None

    def __post_init__(self) -> None:
        if self.legs not in (1, 2):
            raise ParameterError(f"parameter '--legs' must be 1 or 2, got {self.legs!r}")
        check_parameter("omega", self.omega, low_open=True)  # the design record's crank speeds, > 0
        if self.legs == 1:
            if self.steps is not None:
                raise ParameterError("parameter '--steps' applies to --legs 2; --legs 1 samples one crank turn")
            if self.foot is not None:
                raise ParameterError("parameter '--foot' applies to --legs 2; --legs 1 has no stance contact")
            samples(360.0, self.step_deg)
            return
        if self.foot is not None and self.foot not in FOOT_MODES:
            raise ParameterError(f"parameter '--foot' must be one of {', '.join(FOOT_MODES)}, got {self.foot!r}")
        steps = self.gait_steps
        if isinstance(steps, bool) or not isinstance(steps, int) or steps < 1:
            raise ParameterError(f"parameter '--steps' must be an integer >= 1, got {steps!r}")
        total = steps * samples(180.0, self.step_deg) + 1
        if total > MAX_GAIT_SAMPLES:
            raise ParameterError(
                f"parameters '--steps' and '--step-deg' give {total} samples; at most {MAX_GAIT_SAMPLES}"
            )

    @property
    def gait_steps(self) -> int:
        """Steps of the gait with 2 legs (``steps`` or 2)."""
        return 2 if self.steps is None else self.steps


def gait_run(settings: GaitSettings) -> LegRun | BipedRun:
    """Run :class:`GaitSettings`: a :class:`LegRun` with 1 leg, a :class:`BipedRun` with 2.

    Raises:
        ValueError: an unknown variant, ``steps`` given with 1 leg, or a bad ``step_deg``,
            ``steps`` or ``foot``.

    """
    if settings.design is None:
        robot = load(settings.variant, settings.legs)
    else:
        robot = design_robot(settings.design, settings.legs)
    if settings.legs == 1:
        if settings.steps is not None:
            raise ParameterError("parameter '--steps' applies to --legs 2; --legs 1 samples one crank turn")
        return leg_run(robot, settings.step_deg, settings.omega)
    return biped_run(robot, settings.gait_steps, settings.step_deg, settings.omega, settings.foot or "flat")


# --------------------------------------------------------------------------- the survey
def _default_gait_cases() -> tuple[tuple[str, str], ...]:
    return tuple((v, "flat") for v in VARIANTS) + (("rigid", "point"), ("rigid", "toe"))


@dataclass(frozen=True)
class KinematicsSettings:
    """The kinematics survey (the ``kinematics`` section of ``pasibot analyze``).

    Attributes:
        variants: leg variants sampled one leg each.
        omega: crank rate [rad/s].
        leg_step_deg: crank increment of the one-leg cycles [deg].
        k_values: frame ratios K = L0 / L of the K sweep.
        k_variant: leg variant of the K sweep.
        jacobian_variant: leg variant of the open-chain Jacobian.
        jacobian_theta: crank angle of the open-chain Jacobian [rad].
        gait_steps: steps of every biped gait.
        gait_step_deg: crank increment of the gaits [deg].
        gait_cases: (variant, foot) of every biped gait.

    """

    variants: tuple[str, ...] = tuple(VARIANTS)
    omega: float = 0.1
    leg_step_deg: float = 1.0
    k_values: tuple[float, ...] = (1.8, 2.0, 2.2)
    k_variant: str = "rigid"
    jacobian_variant: str = "rigid"
    jacobian_theta: float = math.pi
    gait_steps: int = 4
    gait_step_deg: float = 5.0
    gait_cases: tuple[tuple[str, str], ...] = _default_gait_cases()


@dataclass(frozen=True)
class KinematicsSurvey:
    """Results of :func:`kinematics_survey`.

    Attributes:
        settings: the settings run.
        legs: variant -> one leg over one crank turn, in ``settings.variants`` order.
        sweep: leg cycles and metrics for every K of ``settings.k_values``.
        jacobian: 6x4 geometric Jacobian of the open chain theta1, theta2, theta4, theta6 at the
            ankle, rows v_x, v_y, v_z [m/s per rad/s], omega_x, omega_y, omega_z [rad/s per rad/s].
        gaits: one biped gait per ``settings.gait_cases`` entry.

    """

    __repr__ = short_repr

    settings: KinematicsSettings
    legs: dict[str, LegRun]
    sweep: path_metrics.KSweep
    jacobian: np.ndarray
    gaits: list[BipedRun]


def kinematics_survey(settings: KinematicsSettings | None = None) -> KinematicsSurvey:
    """Leg paths of every variant, the K sweep, the open-chain Jacobian and the biped gaits.

    Args:
        settings: what to run; ``None``: :class:`KinematicsSettings` defaults.

    """
    s = KinematicsSettings() if settings is None else settings
    robots: dict[tuple[str, int], PasibotRobot] = {}

    def robot_of(variant: str, legs: int) -> PasibotRobot:  # each robot loaded once (the gaits only read it)
        if (variant, legs) not in robots:
            robots[variant, legs] = load(variant, legs)
        return robots[variant, legs]

    legs = {v: leg_run(robot_of(v, 1), s.leg_step_deg, s.omega) for v in s.variants}
    sweep = path_metrics.k_sweep(s.k_values, variant=s.k_variant)
    robot = robot_of(s.jacobian_variant, 1)
    jacobian = kin.open_chain_jacobian(robot, kin.configuration_at(robot, s.jacobian_theta))
    gaits = [biped_run(robot_of(v, 2), s.gait_steps, s.gait_step_deg, s.omega, foot) for v, foot in s.gait_cases]
    return KinematicsSurvey(s, legs, sweep, jacobian, gaits)
