"""Does it walk? One walking verdict, defined once, for any engine that simulates the biped on a floor.

PASIBOT's gait is forced: the cranks turn at omega, a step takes pi / omega, and the linkage
itself advances the hip 16 L per crank turn (8 L per step). A simulation (ours,
:mod:`pasibot_pin.dynamics.floor`, or MuJoCo on the exported model) feeds a :class:`GaitJudge`
one :class:`GaitSample` per time step; the judge decides the outcome as soon as it is decided and
the simulation stops there.

Outcomes (:data:`OUTCOMES`):

* ``walks``: :attr:`GaitCriteria.steps` steps, each a landing at least :attr:`GaitCriteria.step_advance`
  L ahead of where that foot last stood; |hip pitch| never above :attr:`GaitCriteria.max_hip_pitch`;
  no weight-bearing foot slipping more than :attr:`GaitCriteria.slip_per_step` in one stance; and
  the hip's advance per step, over whole strides, within :attr:`GaitCriteria.advance_tolerance` of
  the linkage's own 8 L.
* a named failure, with the time it was decided:

  - ``fell``: |hip pitch| passed the limit;
  - ``rolled``: a foot standing on its heel or toe alone pitched past :attr:`GaitCriteria.roll_limit`;
  - ``slipped``: a weight-bearing foot slid more than the limit in one stance, or the hip advanced
    more than the linkage allows (the feet slid backwards);
  - ``stalled``: no step for two step periods, or the hip's advance per step short of the band;
  - ``hopped``: a foot landed less than :attr:`GaitCriteria.step_advance` L ahead of where it stood
    (it was lifted and put down, not stepped), or both feet left the floor;
  - ``stepped_back``: a foot landed behind where it stood (the linkage carried it forward, the
    body's pitch put it down behind);
  - ``tipped``: (3-D floor only) the hip rolled past :data:`TIP_LIMIT` sideways;
  - ``collided``: (3-D floor only) a sole passed through the other foot's sole;
  - ``tripped``: (a ground with a step edge) a heel or toe hit the step's riser
    (:meth:`~pasibot_pin.dynamics.floor.ground.Ground.riser_hit`);
  - ``diverged``: the numerics broke (a :class:`~pasibot_pin.errors.SimulationError`);
  - ``infeasible_start``: the start pose (settled on the floor before the cranks turn) already breaks
    the hip-pitch or a foot's roll limit; decided at the start, naming the rule, its value and its limit.

* ``undecided``: the run ended (its given duration) before any of the above was decided, less
  than two step periods in (so even ``stalled`` cannot be told), or it was asked for fewer than
  :data:`MIN_STRIDE_STEPS` steps and took them (too few for a whole stride: the advance, and what the
  next step does, are not known); a run that long or longer without its steps has ``stalled``.

The step, the advance and the cost of transport are defined here once, over whole strides
(an even number of steps, so both legs count alike), for every variant.

Units: SI, angles [rad] (degrees only in :meth:`Verdict.summary`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from pasibot_pin.dynamics.margins import Margin
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.coordinates import SIDES

OUTCOMES: tuple[str, ...] = (
    "walks",
    "fell",
    "rolled",
    "slipped",
    "stalled",
    "hopped",
    "stepped_back",
    "tipped",
    "collided",
    "tripped",
    "diverged",
    "infeasible_start",
    "undecided",
)
"""Every outcome a walk can have: ``walks``, a failure, or ``undecided`` (a run cut shorter than the walk needs)."""

FAILURES: tuple[str, ...] = tuple(o for o in OUTCOMES if o not in ("walks", "undecided"))
"""The outcomes that are failures."""


TIP_LIMIT = math.radians(10.0)
"""A 3-D walk whose hip rolls past this is ``tipped`` [rad]."""
TIP_GRACE = 0.5
"""A 3-D walk whose hip rolls past :data:`TIP_LIMIT` within this long [s] of a failure the planar rules
decided (a foot that slips or lands early as the body tips) is ``tipped``: the roll is the cause."""
REVISABLE: tuple[str, ...] = ("rolled", "slipped", "stalled", "hopped")
"""The failures a roll past the limit soon after may turn into ``tipped``."""

MIN_STRIDE_STEPS = 3
"""The advance band is checked over whole strides, which needs at least this many judged steps [-]."""

LINKAGE_ADVANCE_PER_STEP = 8.0
"""The linkage's own hip advance per step (half a crank turn), in crank lengths L [-]."""


@dataclass(frozen=True)
class GaitCriteria:
    """What counts as walking.

    Attributes:
        steps: steps to walk [-].
        step_advance: a landing is a step when it is at least this far ahead of where that foot
            last stood [L].
        max_hip_pitch: largest |hip pitch| of a walk [rad].
        roll_limit: a foot on its heel or toe alone has rolled past this sole pitch [rad].
        slip_per_step: largest slide of a weight-bearing foot in one stance [m].
        advance_tolerance: the hip's advance per step may differ from 8 L by this share [-].
        bearing_share: a foot is the stance foot, whose slide counts, when its normal force exceeds this share
            of the weight (the trailing foot of a double support may scuff as it unloads) [-].
        dwell: a contact (or flight) lasting less than this is a blip and ignored [s].
        grace_steps: the first this many step periods settle the start: landings there are not judged [-].
        flight_limit: both feet in the air for longer than this is a hop [s].
        bounce_share: a foot back on the floor after a flight shorter than this share of a step
            period bounced (it was not swung): neither a step nor a hop [-].

    """

    steps: int = 20
    step_advance: float = 2.0
    max_hip_pitch: float = math.radians(10.0)
    roll_limit: float = math.radians(30.0)
    slip_per_step: float = 0.005
    advance_tolerance: float = 0.10
    bearing_share: float = 0.5
    dwell: float = 0.01
    grace_steps: float = 0.5
    flight_limit: float = 0.02
    bounce_share: float = 0.1

    def __post_init__(self) -> None:
        integer = isinstance(self.steps, (int, np.integer)) and not isinstance(self.steps, bool)
        if not integer or not 1 <= self.steps <= 10_000:
            raise ParameterError(f"parameter 'steps' must be an integer in [1, 10000], got {self.steps!r}")
        for name, low, high in (
            ("step_advance", 0.0, 100.0),
            ("max_hip_pitch", 0.0, math.pi),
            ("roll_limit", 0.0, math.pi),
            ("slip_per_step", 0.0, 10.0),
            ("advance_tolerance", 0.0, 10.0),
            ("bearing_share", 0.0, 1.0),
            ("dwell", 0.0, 10.0),
            ("grace_steps", 0.0, 100.0),
            ("flight_limit", 0.0, 100.0),
            ("bounce_share", 0.0, 1.0),
        ):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and low <= value <= high):
                raise ParameterError(f"parameter {name!r} must be a number in [{low:g}, {high:g}], got {value!r}")


class FootSample(NamedTuple):
    """One foot at one instant (a named tuple: the floor builds two per time step).

    Attributes:
        loaded: the floor pushes on it (heel, toe or both).
        x: where it stands: the middle of its heel and toe [m].
        pitch: the sole's pitch (toe up positive) [rad].
        normal: the floor's normal force on it [N].
        slip: the largest tangential speed of its loaded points [m/s].
        on_point: it stands on its heel or its toe alone.

    """

    loaded: bool
    x: float
    pitch: float
    normal: float
    slip: float
    on_point: bool


class GaitSample(NamedTuple):
    """The biped at one instant, as the judge needs it (a named tuple: one per time step).

    Attributes:
        t: time [s].
        hip_x: the hip's forward position [m].
        hip_pitch: [rad].
        feet: the right and left :class:`FootSample`.
        motor_power: each motor's power [W] (torque times crank rate).

    """

    t: float
    hip_x: float
    hip_pitch: float
    feet: tuple[FootSample, FootSample]
    motor_power: tuple[float, ...] = (0.0, 0.0)


@dataclass
class Verdict:
    """The outcome of a walk on the floor and its figures.

    Attributes:
        outcome: one of :data:`OUTCOMES`.
        detail: what decided it, in words (empty for ``walks``).
        decided_at: the time the outcome was decided [s].
        steps: steps taken [-].
        step_times: when each step landed [s].
        step_x: where each step landed [m].
        step_sides: which foot made each step.
        advance_m: the hip's forward displacement over the whole run [m].
        stride_advance_m: the hip's advance from the first judged step to the last, over whole strides [m].
        advance_per_step: that advance per step over the linkage's own 8 L [-] (nan before three steps).
        max_hip_pitch: largest |hip pitch| [rad].
        max_slip_m: the largest slide of a weight-bearing foot in one stance [m].
        motor_energy_j: positive work of the crank motors over the judged strides [J].
        cost_of_transport: that work over (weight x stride advance) [-] (nan without a stride).
        power_per_metre: that work over the stride advance [J/m] (nan without a stride).
        mean_motor_power_w: that work over the strides' duration [W] (nan without a stride).
        simulated_s: simulated time [s].
        margins: each rule's value, limit and margin (:class:`~.margins.Margin`); the one that decided the
            outcome is marked.

    """

    outcome: str
    detail: str
    decided_at: float
    steps: int
    step_times: list[float]
    step_x: list[float]
    step_sides: list[str]
    advance_m: float
    stride_advance_m: float
    advance_per_step: float
    max_hip_pitch: float
    max_slip_m: float
    motor_energy_j: float
    cost_of_transport: float
    power_per_metre: float
    mean_motor_power_w: float
    simulated_s: float
    margins: list[Margin] = field(default_factory=list)

    @property
    def walks(self) -> bool:
        """True when the outcome is ``walks``."""
        return self.outcome == "walks"

    @property
    def failed(self) -> bool:
        """True when the outcome is a failure (:data:`FAILURES`)."""
        return self.outcome in FAILURES

    def short(self) -> str:
        """The outcome in a few words: ``walks``, or the outcome and when it was decided."""
        return "walks" if self.walks else f"{self.outcome} at {self.decided_at:.2f} s"

    def summary(self) -> str:
        """One line: the outcome, the steps, the advance and the largest hip pitch."""
        head = "walks" if self.walks else f"{self.outcome} at t = {self.decided_at:.3f} s ({self.detail})"
        return (
            f"{head}: {self.steps} step{'' if self.steps == 1 else 's'}, advance {self.advance_m:.3f} m, "
            f"max |hip pitch| {math.degrees(self.max_hip_pitch):.2f} deg, in {self.simulated_s:.3f} s"
        )

    def margins_text(self) -> str:
        """One line: every rule's value against its limit, the deciding one and the near ones marked."""
        return "; ".join(m.text() for m in self.margins)

    def __repr__(self) -> str:
        return f"Verdict({self.summary()!r})"


@dataclass
class _Foot:
    """The judge's running state of one foot."""

    stand: float  # where it last stood [m]
    loaded: bool = False  # its debounced contact state
    pending_since: float | None = None  # when the raw state first differed from ``loaded``
    air_since: float | None = None  # when it last left the floor
    stance_slip: float = 0.0  # slide while bearing weight in the current stance [m]


@dataclass
class GaitJudge:
    """Feeds on :class:`GaitSample` s and decides the :class:`Verdict` as soon as it is decided.

    Args:
        omega: crank rate [rad/s] (> 0: a step takes pi / omega).
        crank_length: L [m].
        weight: the robot's weight [N].
        criteria: :class:`GaitCriteria`.
        start: the first sample (the feet's stands are taken from it).

    """

    omega: float
    crank_length: float
    weight: float
    criteria: GaitCriteria
    start: GaitSample
    outcome: str = ""
    detail: str = ""
    decided_at: float = math.nan
    _feet: list[_Foot] = field(default_factory=list)
    _steps: list[tuple[float, str, float, float]] = field(default_factory=list)  # t, side, x, hip x
    _energy: list[float] = field(default_factory=list)  # cumulative positive motor work at each step [J]
    _work: float = 0.0
    _t: float = 0.0
    _hip_x: float = 0.0
    _max_pitch: float = 0.0
    _max_slip: float = 0.0
    _flight_since: float | None = None
    max_roll: float = 0.0
    rule: str = ""  # the rule that decided the outcome
    _longest_flight: float = 0.0
    _least_landing: float = math.inf  # the shortest judged landing ahead of where the foot stood [L]
    _shortest_swing: float = math.inf  # the shortest flight of a foot that counted as a landing [s]
    _max_foot_roll: float = 0.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.omega) and self.omega > 0):
            raise ParameterError(f"parameter 'omega' must be a crank rate > 0 [rad/s] to walk, got {self.omega!r}")
        self.period = math.pi / self.omega
        self._grace = self.criteria.grace_steps * self.period  # landings before start.t + this are not judged [s]
        self._bearing = self.criteria.bearing_share * self.weight  # a stance foot's normal force passes this [N]
        self._feet = [_Foot(stand=f.x, loaded=f.loaded) for f in self.start.feet]
        self._t = self.start.t
        self._hip_x = self.start.hip_x
        self._last_progress = self.start.t
        self._judge_start()

    def _judge_start(self) -> None:
        """``infeasible_start``: the start pose already breaks the hip-pitch limit or a foot's roll limit."""
        c, start = self.criteria, self.start
        rules = [("hip_pitch", "_max_pitch", "its hip pitch", start.hip_pitch, c.max_hip_pitch)]
        rules += [("foot_roll", "_max_foot_roll", f"the {side} foot, on a heel or toe alone, pitched", foot.pitch,
                   c.roll_limit) for side, foot in zip(SIDES, start.feet) if foot.loaded and foot.on_point]  # fmt: skip
        for rule, worst, what, value, limit in rules:
            if abs(value) > limit and not self.outcome:
                self._max_pitch = abs(start.hip_pitch)  # the start's pitch counts, whichever rule decides
                setattr(self, worst, abs(value))
                detail = f"the start pose breaks a limit: {what} {math.degrees(value):+.1f} deg, past"
                self._decide("infeasible_start", start.t, f"{detail} {math.degrees(limit):.0f} deg", rule)

    @property
    def decided(self) -> bool:
        """True once the outcome is known (the simulation may stop)."""
        return bool(self.outcome)

    def _decide(self, outcome: str, t: float, detail: str, rule: str = "") -> None:
        if not self.outcome:
            self.outcome, self.decided_at, self.detail, self.rule = outcome, t, detail, rule

    def diverged(self, t: float, detail: str) -> None:
        """The simulation broke at ``t`` [s] (a :class:`~pasibot_pin.errors.SimulationError`)."""
        self._decide("diverged", t, detail)

    def collided(self, t: float, detail: str) -> None:
        """A 3-D walk's soles passed through each other at ``t`` [s] (:mod:`pasibot_pin.dynamics.floor.engine3d`)."""
        self._decide("collided", t, detail)

    def tripped(self, t: float, detail: str) -> None:
        """A heel or toe hit a step's riser at ``t`` [s] (:mod:`pasibot_pin.dynamics.floor.ground`)."""
        self._decide("tripped", t, detail, "riser")

    def roll(self, t: float, roll: float) -> None:
        """Take the 3-D hip's roll [rad] at ``t`` [s]: past :data:`TIP_LIMIT` the walk is ``tipped``.

        Also where a planar rule decided a failure less than :data:`TIP_GRACE` before (the body
        tipping makes a foot slip or land early): the detail then names that rule too. Engines that
        call this stop on :meth:`final`, not on :attr:`decided`.
        """
        self.max_roll = max(self.max_roll, abs(roll))
        if abs(roll) <= TIP_LIMIT:
            return
        detail = f"the hip rolled {math.degrees(roll):+.1f} deg sideways"
        if not self.outcome:
            self._decide("tipped", t, detail, "hip_roll")
        elif self.outcome in REVISABLE and t - self.decided_at <= TIP_GRACE:
            detail += f"; {t - self.decided_at:.3f} s after it {self.outcome} ({self.detail})"
            self.outcome, self.decided_at, self.detail, self.rule = "tipped", t, detail, "hip_roll"

    def final(self, t: float) -> bool:
        """True once the outcome is decided and no roll can change it any more (a 3-D run may stop)."""
        return bool(self.outcome) and (self.outcome not in REVISABLE or t - self.decided_at > TIP_GRACE)

    def update(self, sample: GaitSample) -> bool:
        """Take one sample (in time order); True once the outcome is decided."""
        if self.outcome:
            return True
        c, t = self.criteria, sample.t
        h = t - self._t
        self._t = t
        self._hip_x = sample.hip_x
        self._work += h * sum([0.0 if p < 0.0 else p for p in sample.motor_power])  # each max(p, 0), summed
        pitch = abs(sample.hip_pitch)
        if pitch > self._max_pitch:
            self._max_pitch = pitch
        if not math.isfinite(sample.hip_pitch + sample.hip_x):
            self._decide("diverged", t, "the state is not finite")
        elif pitch > c.max_hip_pitch:
            self._decide("fell", t, f"|hip pitch| passed {math.degrees(c.max_hip_pitch):.0f} deg", "hip_pitch")
        judged = t - self.start.t > self._grace
        for i, foot in enumerate(sample.feet):
            self._foot(i, foot, sample, h, judged)
        if any([f.loaded for f in sample.feet]):
            self._flight_since = None
        else:
            self._flight(sample, judged)
        if not self.outcome and sample.t - self._last_progress > 2.0 * self.period:
            self._decide("stalled", sample.t, f"no step in {2.0 * self.period:.2f} s (two step periods)", "steps")
        if not self.outcome and len(self._steps) >= c.steps:
            self._final_advance(sample.t)
        return bool(self.outcome)

    def _foot(self, i: int, foot: FootSample, sample: GaitSample, h: float, judged: bool) -> None:
        state, loaded = self._feet[i], foot.loaded
        if loaded and foot.on_point:
            self._max_foot_roll = max(self._max_foot_roll, abs(foot.pitch))
            if abs(foot.pitch) > self.criteria.roll_limit:
                rolled = f"the {SIDES[i]} foot rolled past {math.degrees(self.criteria.roll_limit):.0f} deg"
                self._decide("rolled", sample.t, rolled, "foot_roll")
        if judged and loaded and foot.normal > self._bearing:
            state.stance_slip += h * foot.slip
            self._max_slip = max(self._max_slip, state.stance_slip)
            if state.stance_slip > self.criteria.slip_per_step:
                slid = f"the {SIDES[i]} foot slid {1e3 * state.stance_slip:.1f} mm in one stance"
                self._decide("slipped", sample.t, slid, "slide")
        # debounce: a change of contact counts once it has lasted ``dwell``
        if loaded == state.loaded:
            state.pending_since = None
            return
        c, side = self.criteria, SIDES[i]
        if state.pending_since is None:
            state.pending_since = sample.t
        if sample.t - state.pending_since + 1e-12 < c.dwell:
            return
        state.loaded = foot.loaded
        if not foot.loaded:  # lift-off
            state.air_since = state.pending_since
            return
        state.stance_slip = 0.0
        if state.air_since is not None and state.pending_since - state.air_since < c.bounce_share * self.period:
            return  # a bounce (a short flight of a foot that was down): neither a step nor a hop
        ahead = (foot.x - state.stand) / self.crank_length
        if judged:
            self._least_landing = min(self._least_landing, ahead)
            if state.air_since is not None:
                self._shortest_swing = min(self._shortest_swing, state.pending_since - state.air_since)
        if ahead >= c.step_advance:
            self._steps.append((state.pending_since, side, foot.x, sample.hip_x))
            self._energy.append(self._work)
            self._last_progress = sample.t
        elif judged:
            outcome = "stepped_back" if ahead < 0 else "hopped"
            self._decide(outcome, sample.t, f"the {side} foot landed {ahead:.2f} L from where it stood", "landing")
        state.stand = foot.x

    def _flight(self, sample: GaitSample, judged: bool) -> None:
        """Both feet are in the air at ``sample``: a flight longer than the limit is a hop."""
        if self._flight_since is None:
            self._flight_since = sample.t
        if judged:
            self._longest_flight = max(self._longest_flight, sample.t - self._flight_since)
        if judged and sample.t - self._flight_since > self.criteria.flight_limit:
            self._decide("hopped", sample.t, "both feet left the floor", "flight")

    def _stride_window(self) -> tuple[int, int] | None:
        """The first and last judged step indices spanning whole strides (an even number of steps)."""
        judged = [k for k, s in enumerate(self._steps) if s[0] - self.start.t > self.criteria.grace_steps * self.period]
        if len(judged) < MIN_STRIDE_STEPS:
            return None
        first, last = judged[0], judged[-1]
        if (last - first) % 2:
            last -= 1
        return (first, last) if last > first else None

    def _final_advance(self, t: float) -> None:
        window = self._stride_window()
        ratio = self._advance_ratio(window)
        tol = self.criteria.advance_tolerance
        if math.isnan(ratio) and self.criteria.steps < MIN_STRIDE_STEPS:  # it may fall at its next step
            few = f"{len(self._steps)} steps taken: a verdict needs {MIN_STRIDE_STEPS} (a whole stride for the advance)"
            self._decide("undecided", t, few, "steps")
        elif math.isnan(ratio):
            self._decide("stalled", t, "too few judged steps to measure the advance", "steps")
        elif ratio < 1.0 - tol:
            self._decide(
                "stalled", t, f"the hip advanced {100 * ratio:.0f} % of the linkage's 8 L per step", "advance_low"
            )
        elif ratio > 1.0 + tol:
            self._decide(
                "slipped", t, f"the hip advanced {100 * ratio:.0f} % of the linkage's 8 L per step", "advance_high"
            )
        else:
            self._decide("walks", t, "")

    def _advance_ratio(self, window: tuple[int, int] | None) -> float:
        if window is None:
            return math.nan
        first, last = window
        advance = self._steps[last][3] - self._steps[first][3]
        return advance / ((last - first) * LINKAGE_ADVANCE_PER_STEP * self.crank_length)

    def verdict(self, t_end: float | None = None) -> Verdict:
        """The verdict so far (a run that ended undecided is ``stalled`` unless it took its steps)."""
        t_end = self._t if t_end is None else t_end
        if not self.outcome:
            if len(self._steps) >= self.criteria.steps:
                self._final_advance(t_end)
            elif t_end - self.start.t < 2.0 * self.period:
                early = f"the run ended {t_end - self.start.t:.3f} s in, before two step periods"
                self._decide("undecided", t_end, early)
            else:
                short = f"{len(self._steps)} of {self.criteria.steps} steps by the end of the run"
                self._decide("stalled", t_end, short, "steps")
        window = self._stride_window()
        advance, energy, duration = math.nan, math.nan, math.nan
        if window is not None:
            first, last = window
            advance = self._steps[last][3] - self._steps[first][3]
            energy = self._energy[last] - self._energy[first]
            duration = self._steps[last][0] - self._steps[first][0]
        usable = advance > 0
        return Verdict(
            outcome=self.outcome,
            detail=self.detail,
            decided_at=self.decided_at,
            steps=len(self._steps),
            step_times=[s[0] for s in self._steps],
            step_x=[s[2] for s in self._steps],
            step_sides=[s[1] for s in self._steps],
            advance_m=self._hip_x - self.start.hip_x,
            stride_advance_m=0.0 if math.isnan(advance) else advance,
            advance_per_step=self._advance_ratio(window),
            max_hip_pitch=self._max_pitch,
            max_slip_m=self._max_slip,
            motor_energy_j=0.0 if math.isnan(energy) else energy,
            cost_of_transport=energy / (self.weight * advance) if usable else math.nan,
            power_per_metre=energy / advance if usable else math.nan,
            mean_motor_power_w=energy / duration if usable and duration > 0 else math.nan,
            simulated_s=t_end - self.start.t,
            margins=self.margins(window),
        )

    def margins(self, window: tuple[int, int] | None = None) -> list[Margin]:
        """Each rule's worst value so far against its limit (:class:`~.margins.Margin`), the deciding one marked."""
        c, ratio, inf = self.criteria, self._advance_ratio(window), math.inf
        rows = [
            ("hip_pitch", math.degrees(self._max_pitch), math.degrees(c.max_hip_pitch), "deg", "max"),
            ("slide", 1e3 * self._max_slip, 1e3 * c.slip_per_step, "mm", "max"),
            ("advance_low", ratio, 1.0 - c.advance_tolerance, "of 8 L per step", "min"),
            ("advance_high", ratio, 1.0 + c.advance_tolerance, "of 8 L per step", "max"),
            ("flight", self._longest_flight, c.flight_limit, "s", "max"),
            ("landing", self._least_landing if self._least_landing < inf else math.nan, c.step_advance, "L", "min"),
            ("swing", self._shortest_swing if self._shortest_swing < inf else math.nan,
             c.bounce_share * self.period, "s", "min"),
            ("foot_roll", math.degrees(self._max_foot_roll), math.degrees(c.roll_limit), "deg", "max"),
            ("steps", float(len(self._steps)), float(c.steps), "steps", "min"),
        ]  # fmt: skip
        if self.max_roll:
            rows.append(("hip_roll", math.degrees(self.max_roll), math.degrees(TIP_LIMIT), "deg", "max"))
        band = {"advance_low": c.advance_tolerance, "advance_high": c.advance_tolerance}
        return [
            Margin(rule, value, limit, unit, sense, rule == self.rule, band.get(rule, math.nan))
            for rule, value, limit, unit, sense in rows
        ]


JudgeFactory = Callable[[GaitSample], GaitJudge]
"""What a floor run takes as its judge: built from the run's first sample, it observes the walk
(``update`` each sample, ``diverged`` when a step fails, ``verdict`` at the end). The engines build
:class:`GaitJudge` s by default; pass ``functools.partial(GaitJudge, omega, L, weight, criteria)`` or
a subclass to observe more."""
