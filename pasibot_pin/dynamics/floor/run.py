"""What a floor run records and returns: contact modes, the run's log and its result.

:class:`RunLog` keeps each step's state, forces and contact modes, and stops a fixed-length run
(no walking verdict) when the hip passes the fall limit or a foot rolls over or slips far;
:class:`FloorResult` is the run with its :class:`~pasibot_pin.dynamics.verdict.Verdict`;
:class:`StartState` a consistent start. :func:`foot_mode` names a foot's contact mode and
:func:`mode_runs` run-length encodes a sequence of them.

Units: SI, angles [rad], forces [N].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from pasibot_pin.dynamics.verdict import FootSample, GaitSample, Verdict
from pasibot_pin.errors import ClosureError, DivergedError, SimulationError, SingularPoseError
from pasibot_pin.model.coordinates import HIP_PITCH, SIDES
from pasibot_pin.model.spatial import SOLE_POINTS

MODES = ("flat", *SOLE_POINTS, "sliding", "air")
"""A foot's contact modes: ``flat`` (two or more of its points load), one point's name (it alone loads),
``sliding`` or ``air`` (the default sole's points: :data:`~pasibot_pin.model.spatial.SOLE_POINTS`)."""
LOAD_TOL = 1e-3
"""A contact point carries load when its normal force exceeds this [N] (the QP's impulses are
accurate to about 1e-8 N.s)."""
SLIP_TOL = 1e-4
"""A loaded point slides when its tangential speed exceeds this [m/s]."""
ROLL_LIMIT = math.radians(60.0)
"""A foot standing on its heel or toe alone has rolled over it past this sole pitch [rad]."""
SLIP_LIMIT = 0.02
"""A foot has slipped when its loaded points have slid this far in all while it bore weight [m]."""
BEARING_SHARE = 0.25
"""A foot bears weight when its normal force exceeds this share of the robot's weight (a dragging
swing toe does not count as a slip) [-]."""

_new = tuple.__new__
"""Builds a named tuple from a tuple of its fields without its Python-level ``__new__`` (three per time step)."""


def mode_runs(modes: list[str] | tuple[str, ...], dt: float, dwell: float = 0.0) -> list[tuple[str, float]]:
    """A foot's mode sequence, run-length encoded: (mode, start time [s]) of each run.

    Mode samples every ``dt`` [s] (the first at t = dt). A run shorter than ``dwell`` [s] (a
    blip) is merged into the run before it (a blip at the very start, into the run after it),
    then equal neighbours are joined, so a sequence compares by its lasting modes only.
    """
    runs: list[list] = []  # [mode, first sample, samples]
    for k, mode in enumerate(modes):
        if runs and runs[-1][0] == mode:
            runs[-1][2] += 1
        else:
            runs.append([mode, k, 1])
    short = max(1, round(dwell / dt)) if dwell > 0 else 0
    kept: list[list] = []
    for run in runs:
        if kept and run[2] < short:
            kept[-1][2] += run[2]  # a blip: the mode before it goes on
        elif kept and kept[-1][0] == run[0]:
            kept[-1][2] += run[2]
        elif not kept or kept[-1][2] >= short or kept[-1][1] > 0:
            kept.append(list(run))
        else:  # the first run was a blip: the run after it starts at the beginning
            kept[-1] = [run[0], 0, kept[-1][2] + run[2]]
    return [(mode, (first + 1) * dt) for mode, first, _ in kept]


def point_sample(
    t: float,
    hip: tuple[float, float],
    points: tuple[list[float], list[float], list[float]],
    normal: list[float] | None,
    power: tuple[float, ...],
    names: tuple[str, ...] = SOLE_POINTS,
) -> tuple[GaitSample, list[bool]]:
    """The :class:`~pasibot_pin.dynamics.verdict.GaitSample` at ``t`` from the contact points, and their load flags.

    Args:
        t: time [s].
        hip: the hip's forward position [m] and pitch [rad].
        points: each point's height above the floor [m], x [m] and tangential speed [m/s]
            (the right foot's points, heel to toe, then the left foot's).
        normal: each point's normal force [N]; ``None`` at the start, where a point on the floor
            (within 1e-6 m) counts as loaded.
        power: each motor's power [W].
        names: a foot's points, heel first and toe last (:attr:`~pasibot_pin.model.spatial.Footprint.points`):
            a foot's x is midway between its heel and toe, its pitch along them.

    """
    gaps, xs, slip = points
    if normal is None:
        f_n = [0.0] * len(gaps)
        loaded = [g < 1e-6 for g in gaps]
    else:
        f_n = normal
        loaded = [f > LOAD_TOL for f in f_n]
    n = len(names)
    feet = []
    for heel in range(0, n * len(SIDES), n):
        toe = heel + n - 1
        if n == 2:  # heel and toe alone (the default sole): sum() and max() of two, written out
            on_heel, on_toe = loaded[heel], loaded[toe]
            count = 0 + on_heel + on_toe  # sum(): an int (of numpy booleans too)
            normal_sum = 0.0 + f_n[heel] + f_n[toe]  # sum() of floats, to the bit (0 + -0.0 is 0.0)
            slip_max = max(abs(slip[heel]) if on_heel else 0.0, abs(slip[toe]) if on_toe else 0.0)
        else:
            own = loaded[heel : toe + 1]
            count = sum(own)
            normal_sum = sum(f_n[heel : toe + 1])
            slip_max = max([abs(s) if on else 0.0 for s, on in zip(slip[heel : toe + 1], own)])
        pitch = math.atan2(gaps[toe] - gaps[heel], xs[toe] - xs[heel])
        # FootSample(loaded, x, pitch, normal, slip, on_point)
        feet.append(_new(FootSample, (count > 0, 0.5 * (xs[heel] + xs[toe]), pitch, normal_sum, slip_max, count == 1)))
    return _new(GaitSample, (t, hip[0], hip[1], (feet[0], feet[1]), power)), loaded


def foot_samples(
    heights: np.ndarray, xs: np.ndarray, slip: np.ndarray, normal: np.ndarray, names: tuple[str, ...] = SOLE_POINTS
) -> list[tuple[FootSample, FootSample]]:
    """:func:`point_sample`'s two feet for many samples at once (the same numbers, row by row).

    Args:
        heights: each point's height above the floor (N samples, points) [m]: the right foot's
            points, heel to toe, then the left foot's.
        xs: each point's x (N, points) [m].
        slip: each point's tangential speed (N, points) [m/s].
        normal: each point's normal force (N, points) [N].
        names: a foot's points, heel first and toe last.

    """
    loaded = normal > LOAD_TOL
    n = len(names)
    columns = []
    for i in range(len(SIDES)):
        heel, toe = n * i, n * i + n - 1
        own = slice(heel, toe + 1)
        count = loaded[:, own].sum(axis=1)
        columns.append(
            zip(
                (count > 0).tolist(),
                (0.5 * (xs[:, heel] + xs[:, toe])).tolist(),
                np.arctan2(heights[:, toe] - heights[:, heel], xs[:, toe] - xs[:, heel]).tolist(),
                normal[:, own].sum(axis=1).tolist(),
                np.where(loaded[:, own], np.abs(slip[:, own]), 0.0).max(axis=1).tolist(),
                (count == 1).tolist(),
            )
        )
    return [(FootSample(*right), FootSample(*left)) for right, left in zip(*columns)]


def foot_mode(loaded: list[bool], slip: list[float], foot: int, names: tuple[str, ...] = SOLE_POINTS) -> str:
    """The contact mode of foot ``foot`` (0 right, 1 left) from every point's load flag and tangential speed [m/s].

    ``air`` (no point loads), ``sliding`` (a loaded point slides), ``flat`` (two or more load: the
    sole lies on the floor) or the name of the one point that loads (``names``: a foot's points).
    """
    return _mode(loaded, slip, len(names) * foot, names)


def _mode(loaded: list[bool], slip: list[float], start: int, names: tuple[str, ...]) -> str:
    """:func:`foot_mode` of the foot whose points start at index ``start`` (a loop: two feet per time step)."""
    count, first = 0, start  # the loaded points, the first of them
    for k in range(start, start + len(names)):
        if loaded[k]:
            if abs(slip[k]) > SLIP_TOL:
                return "sliding"
            if not count:
                first = k
            count += 1
    if not count:
        return "air"
    return "flat" if count > 1 else names[first - start]


@dataclass
class FloorResult:
    """Samples of a floor run, one per step, and its walking verdict.

    Attributes:
        t: times [s].
        q, v: configurations and velocities.
        hip_pitch: [rad].
        modes: contact mode of each foot per sample, ``{"right": [...], "left": [...]}`` (:data:`MODES`).
        normal, tangential: contact forces (n, points) [N], columns the right foot's points (heel to toe),
            then the left's (right heel, right toe, left heel, left toe).
        motor_torque: torque of each motor (n, motors) [N.m]: right and left crank, or the one motor.
        touchdowns: (t, side, point) of every point that starts to carry load after carrying none.
        landings: (t, side, x) of every landing of a foot from the air, steps and hops alike [m].
        outcome: the verdict's outcome (:data:`~pasibot_pin.dynamics.verdict.OUTCOMES`); ``stood``
            with the cranks held (no walk to judge) and ``diverged`` if a held run broke.
        failed: True when the outcome is a failure (:data:`~pasibot_pin.dynamics.verdict.FAILURES`).
        stop_reason: why the run ended, in words (a failure and its time, or the run's length).
        stopped: the run ended early on a failure (a step that broke, a fall, a roll, a slip) [-].
        verdict: the :class:`~pasibot_pin.dynamics.verdict.Verdict` (``None`` with the cranks held).
        start: the consistent start it began from (``None`` for a given or ``flat`` start).
        start_kind: ``flat`` (geometric double support), ``settled`` (:meth:`FloorSimulator.start_state`)
            or ``given``.
        start_note: why a ``consistent`` start fell back to ``flat`` (the robot cannot stand at
            theta0: no static state holds it), else ``""``.
        points: a foot's contact points, heel to toe (the force columns' order within a foot).

    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    hip_pitch: np.ndarray
    modes: dict[str, list[str]]
    normal: np.ndarray
    tangential: np.ndarray
    motor_torque: np.ndarray
    touchdowns: list[tuple[float, str, str]] = field(default_factory=list)
    landings: list[tuple[float, str, float]] = field(default_factory=list)
    outcome: str = ""
    failed: bool = False
    stop_reason: str = ""
    stopped: bool = False
    verdict: Verdict | None = None
    start: StartState | None = None
    start_kind: str = ""
    start_note: str = ""
    points: tuple[str, ...] = SOLE_POINTS

    def __repr__(self) -> str:
        head = self.verdict.summary() if self.verdict is not None else f"{self.outcome}: {self.stop_reason}"
        return f"FloorResult({len(self.t)} samples, start {self.start_kind}: {head})"

    @property
    def steps(self) -> list[tuple[float, str, float]]:
        """(t, side, x) of every step the verdict counted [s, -, m]."""
        v = self.verdict
        return [] if v is None else list(zip(v.step_times, v.step_sides, v.step_x))

    def step_lengths(self) -> np.ndarray:
        """The distance from each step's landing to the one before [m]."""
        return np.diff([x for *_, x in self.steps])

    def step_durations(self) -> np.ndarray:
        """Time from one step to the next [s]."""
        return np.diff([t for t, *_ in self.steps])

    def friction_use(self) -> np.ndarray:
        """|F_t| / F_n of each point (n, 4) [-] (0 where the point carries no load)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            use = np.abs(self.tangential) / self.normal
        return np.where(self.normal > 0, use, 0.0)

    def until(self, t_end: float, verdict: Verdict) -> FloorResult:
        """The run as it stood at ``t_end`` [s], judged by ``verdict``: its samples, touchdowns and landings to then.

        A longer run's first part, as a shorter run that had stopped at ``t_end`` would hold it (the
        verdict of a judge that heard only those samples, e.g. one asking fewer steps).
        """
        n = int(np.searchsorted(self.t, t_end, side="right"))
        return replace(
            self,
            t=self.t[:n],
            q=self.q[:n],
            v=self.v[:n],
            hip_pitch=self.hip_pitch[:n],
            modes={side: modes[:n] for side, modes in self.modes.items()},
            normal=self.normal[:n],
            tangential=self.tangential[:n],
            motor_torque=self.motor_torque[:n],
            touchdowns=[x for x in self.touchdowns if x[0] <= t_end],
            landings=[x for x in self.landings if x[0] <= t_end],
            outcome=verdict.outcome,
            failed=verdict.failed,
            stop_reason=f"ran {float(self.t[n - 1]) if n else 0.0:.3f} s",
            stopped=False,
            verdict=verdict,
        )


@dataclass
class StartState:
    """A consistent start (:meth:`FloorSimulator.start_state`).

    Attributes:
        q, v: configuration and velocity (v = 0: at rest).
        kind: ``flat`` (the geometric double support holds) or ``settled`` (the springs engaged).
        settle_time: how long the settling took [s] (0 for ``flat``).
        normal, tangential: contact forces holding it (4,) [N]: right heel, right toe, left heel, left toe.
        modes: each foot's contact mode.
        loop_residual: largest loop-closure residual [m].
        gaps: heights of the four points above the floor [m].
        along: their x [m].

    """

    q: np.ndarray
    v: np.ndarray
    kind: str
    settle_time: float
    normal: np.ndarray
    tangential: np.ndarray
    modes: dict[str, str]
    loop_residual: float
    gaps: np.ndarray
    along: np.ndarray

    @property
    def friction_use(self) -> float:
        """The largest |F_t| / F_n of a loaded point [-]."""
        loaded = self.normal > LOAD_TOL
        return float(np.max(np.abs(self.tangential[loaded]) / self.normal[loaded])) if loaded.any() else 0.0


class RunLog:
    """What a floor run records at each step, and when a run without a verdict stops.

    The stops (the hip past the fall limit, a foot rolled over its heel or toe past
    :data:`ROLL_LIMIT`, a weight-bearing foot slid :data:`SLIP_LIMIT`, a step that failed) end a
    fixed-length run (``stop_on_verdict=False``); the walking verdict is the judge's.
    """

    def __init__(
        self, weight: float, fall_limit: float, nq: int, n_motors: int, names: tuple[str, ...] = SOLE_POINTS
    ) -> None:
        """A log for one run.

        Args:
            weight: the robot's weight [N].
            fall_limit: |hip pitch| that ends a run without a verdict [rad].
            nq: configuration size.
            n_motors: motors (columns of the motor torque).
            names: a foot's contact points, heel to toe.

        """
        self.weight, self.fall_limit = weight, fall_limit
        self.nq, self.n_motors, self.names = nq, n_motors, tuple(names)
        self.rec: dict[str, list] = {k: [] for k in ("t", "q", "v", "normal", "tangential", "motor")}
        self.modes: dict[str, list[str]] = {side: [] for side in SIDES}
        self.touchdowns: list[tuple[float, str, str]] = []
        self.landings: list[tuple[float, str, float]] = []
        self.loaded_before = [False] * (len(self.names) * len(SIDES))
        self.air_before = [True] * len(SIDES)
        self.slid = [0.0] * len(SIDES)
        self.stop_reason = ""
        self._bearing = BEARING_SHARE * weight  # a foot's normal force above this bears weight [N]
        self._mode_lists = [self.modes[side] for side in SIDES]

    def stop_on(self, err: SimulationError, t: float) -> None:
        """A step failed at ``t`` [s]: the cause named by the error's type."""
        if isinstance(err, ClosureError):
            cause = "a loop cannot close"
        elif isinstance(err, (DivergedError, SingularPoseError)):
            cause = "the simulation diverged"
        else:
            cause = "the contact problem failed"
        self.stop_reason = f"{cause} at t = {t:.3f} s ({err})"

    def record(
        self, t: float, q: np.ndarray, v: np.ndarray, sample: GaitSample, force: tuple, loaded: list, slip: list
    ) -> None:
        """Keep the step's state, forces (normal, tangential, motor torques), modes, touchdowns and landings.

        ``loaded`` and ``slip``: each point's load flag and tangential speed [m/s] (as the sample's).
        """
        rec = self.rec
        times = rec["t"]
        h = t - (times[-1] if times else 0.0)
        names, n, before = self.names, len(self.names), self.loaded_before
        if loaded != before:  # the same flags: no point starts to load
            for k, now in enumerate(loaded):
                if now and not before[k]:
                    self.touchdowns.append((t, SIDES[k // n], names[k % n]))
        air_before, slid = self.air_before, self.slid
        for i, (side, foot, modes) in enumerate(zip(SIDES, sample.feet, self._mode_lists)):
            mode = _mode(loaded, slip, n * i, names)
            modes.append(mode)
            if foot.loaded and air_before[i] and t > h:
                self.landings.append((t, side, foot.x))
            air_before[i] = not foot.loaded
            if foot.normal > self._bearing:
                slid[i] += h * foot.slip
            if mode in names and abs(foot.pitch) > ROLL_LIMIT:
                self.stop_reason = f"the {side} foot rolled over its {mode} at t = {t:.3f} s"
            if slid[i] > SLIP_LIMIT:
                self.stop_reason = f"the {side} foot slipped {1e3 * slid[i]:.0f} mm by t = {t:.3f} s"
        self.loaded_before = loaded
        times.append(t)
        rec["q"].append(q)
        rec["v"].append(v)
        normal, tangential, motor = force  # flat: floats, no container per step
        rec["normal"].extend(normal)
        rec["tangential"].extend(tangential)
        rec["motor"].extend(motor)

    def stopped(self, t: float, q: np.ndarray) -> bool:
        """True when a run without a verdict stops here (see the class docstring)."""
        limit = self.fall_limit
        if abs(q[HIP_PITCH]) > limit and not self.stop_reason:
            self.stop_reason = f"fell: |hip pitch| passed {math.degrees(limit):.0f} deg at t = {t:.3f} s"
        return bool(self.stop_reason)

    def result(self, verdict: Verdict | None, begin, start_kind: str, note: str) -> FloorResult:
        """The :class:`FloorResult` of the run."""
        rec, nq, n_motors = self.rec, self.nq, self.n_motors
        qs = np.array(rec["q"]).reshape(-1, nq)
        t_end = rec["t"][-1] if rec["t"] else 0.0
        if verdict is not None:
            outcome, failed = verdict.outcome, verdict.failed
        else:  # cranks held: no walk to judge
            outcome, failed = ("diverged" if self.stop_reason else "stood"), bool(self.stop_reason)
        return FloorResult(
            t=np.array(rec["t"]),
            q=qs,
            v=np.array(rec["v"]).reshape(qs.shape),
            hip_pitch=qs[:, HIP_PITCH].copy(),
            modes=self.modes,
            normal=np.array(rec["normal"]).reshape(-1, len(self.names) * len(SIDES)),
            tangential=np.array(rec["tangential"]).reshape(-1, len(self.names) * len(SIDES)),
            motor_torque=np.array(rec["motor"]).reshape(-1, n_motors),
            touchdowns=self.touchdowns,
            landings=self.landings,
            outcome=outcome,
            failed=failed,
            stop_reason=self.stop_reason or f"ran {t_end:.3f} s",
            stopped=bool(self.stop_reason),
            verdict=verdict,
            start=begin,
            start_kind=start_kind,
            start_note=note,
            points=self.names,
        )
