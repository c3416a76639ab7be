"""From a requirement to a design: search the design space for a walker at a given crank speed.

Each candidate is the base design (the ``parallel`` variant by default) with the varied parameters
drawn by Optuna's TPE sampler (its ask-and-tell interface), at the asked crank speed, walked on the
floor (:func:`~pasibot_pin.studies.walking.walk_design`) and judged by the walking verdict. Its
score, lower being better:

- a walker scores by the objective: ``sole`` (the sole's length, toe plus heel [L]), ``energy`` (motor
  work per metre [J/m]) or ``pitch`` (largest |hip pitch| [deg]);
- a design that does not walk scores :data:`FAILED` less the steps it took, so that the sampler
  moves toward designs that walk further, and any walker beats it.

The candidates run on the process pool of :mod:`pasibot_pin.jobs` with :data:`IN_FLIGHT` of them
asked ahead. The sampler is told the results in trial order, whatever order the workers finish
them in, and candidate ``m`` is asked right after candidate ``m - IN_FLIGHT`` is told: the sampler
sees the same history at every ask, so a seed gives the same candidates, count and best walker on
one worker or two, however long each walk takes. Nothing is written here: the caller saves the
best walker (:meth:`WalkerSearchResult.best`).

Units: SI; soles over the crank length L; crank speed [rad/s].
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

from pasibot_pin.errors import InterferenceError, ParameterError
from pasibot_pin.explore.plan import Range, Varied
from pasibot_pin.jobs import Job, run_jobs
from pasibot_pin.model.design import Design
from pasibot_pin.model.variants import get_variant
from pasibot_pin.progress import progress_bar
from pasibot_pin.studies.walking import WalkSettings, walk_design, walk_design_3d

OBJECTIVES: dict[str, str] = {
    "sole": "the shortest sole, toe plus heel [L]",
    "energy": "the least motor work per metre [J/m]",
    "pitch": "the smallest largest |hip pitch| [deg]",
}
"""What a walker is scored by (lower is better)."""

FAILED: float = 1e6
"""A design that does not walk scores this, less the steps it took [-]."""

IN_FLIGHT: int = 4
"""Candidates asked before the first of them is told [-]: fixed, not the worker count, so the search
is the same on any number of workers (two workers stay busy while one waits for a long walk)."""

MAX_BUDGET: int = 10_000
"""Most candidates a search may walk [-]."""

DEFAULT_RANGES: tuple[Range, ...] = (Range("parallel_toe", 3.0, 10.0), Range("parallel_heel", 3.0, 10.0))
"""The sole's extents ahead of and behind joint 13 [L]."""


@dataclass(frozen=True)
class WalkerSearch:
    """What to search for.

    Attributes:
        omega: the crank speed the walker must walk at [rad/s].
        objective: a key of :data:`OBJECTIVES`.
        budget: candidates to walk [-].
        steps: steps each must walk [-].
        ranges: the varied parameters and their bounds.
        base: the design every other parameter is taken from.
        seed: the sampler's seed.
        spatial: walk each candidate on the 3-D floor (:func:`~pasibot_pin.studies.walking.walk_design_3d`):
            the hip free to roll, the soles' footprint, feet and legs that meet ``collided``.

    """

    omega: float
    objective: str = "sole"
    budget: int = 40
    steps: int = 20
    ranges: tuple[Varied, ...] = DEFAULT_RANGES
    base: Design = field(default_factory=lambda: Design(variant="parallel"))
    seed: int = 0
    spatial: bool = False

    def __post_init__(self) -> None:
        self.base.with_(omega=self.omega)  # the design record's range for omega, naming it
        if self.objective not in OBJECTIVES:
            raise ParameterError(f"--objective must be one of {', '.join(OBJECTIVES)}, got {self.objective!r}")
        budget = self.budget
        if isinstance(budget, bool) or not isinstance(budget, int) or not 1 <= budget <= MAX_BUDGET:
            raise ParameterError(f"--budget must be an integer in [1, {MAX_BUDGET}], got {budget!r}")
        if not self.ranges or not all(isinstance(r, Range) for r in self.ranges):
            raise ParameterError("--vary: find-walker varies numeric parameters NAME=LO:HI")

    def design(self, values: dict[str, float]) -> Design:
        """The candidate of ``values`` (name -> value)."""
        return self.base.with_(omega=self.omega, **values)


@dataclass(frozen=True)
class Candidate:
    """One walked candidate: its values, verdict and score."""

    number: int
    values: dict[str, float]
    outcome: str
    steps: int
    score: float
    detail: str = ""

    @property
    def walks(self) -> bool:
        """True when its verdict is ``walks``."""
        return self.outcome == "walks"


@dataclass
class WalkerSearchResult:
    """Every candidate of a search, and its CPU and wall time [s]."""

    search: WalkerSearch
    candidates: list[Candidate]
    wall_s: float = math.nan

    @property
    def walkers(self) -> list[Candidate]:
        """The candidates that walk, best first."""
        return sorted((c for c in self.candidates if c.walks), key=lambda c: c.score)

    def best(self) -> Design | None:
        """The best walker's design, or ``None`` when none walks."""
        walkers = self.walkers
        return self.search.design(walkers[0].values) if walkers else None


def walk_candidate(
    base: dict, omega: float, values: dict[str, float], steps: int, objective: str, spatial: bool = False
) -> tuple:
    """Walk one candidate (in a worker): (outcome, steps, score, detail).

    In 3-D, a candidate whose feet or legs would meet (:class:`~pasibot_pin.errors.InterferenceError`,
    refused before its walk) is ``collided``, and one whose sole fields contradict each other (a gap
    outside its sole) is ``refused``: both score :data:`FAILED`.
    """
    try:
        design = Design.from_dict(base).with_(omega=omega, **values)
        settings = WalkSettings(steps=steps)
        v = walk_design_3d(design, settings).verdict if spatial else walk_design(design, settings).verdict
    except InterferenceError as exc:
        return "collided", 0, FAILED, str(exc)
    except ParameterError as exc:  # a drawn combination the record refuses (the range of each is checked before)
        return "refused", 0, FAILED, str(exc)
    if not v.walks:
        return v.outcome, v.steps, FAILED - v.steps, v.detail
    toe, heel = get_variant(design.variant).foot_fields  # the variant's own sole fields
    score = {
        "sole": getattr(design, toe) + getattr(design, heel),
        "energy": v.power_per_metre,
        "pitch": math.degrees(v.max_hip_pitch),
    }[objective]
    return v.outcome, v.steps, float(score), ""


def find_walker(search: WalkerSearch, workers: int = 2, progress: bool = True) -> WalkerSearchResult:
    """Search for a walker (see the module docstring); every candidate is kept in the result.

    Raises:
        MissingExtraError: optuna (the ``sweep`` extra) is not installed.

    """
    import optuna  # deferred: optional extra (optuna)

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    study = optuna.create_study(direction="minimize", sampler=optuna.samplers.TPESampler(seed=search.seed))
    distributions: dict[str, Any] = {
        r.name: optuna.distributions.FloatDistribution(r.low, r.high) for r in search.ranges if isinstance(r, Range)
    }
    base = search.base.to_dict()
    candidates: list[Candidate] = []
    trials: dict[int, Any] = {}
    finished: dict[int, tuple] = {}  # results in finishing order, told in trial order
    bar = progress_bar(search.budget, 0, progress, unit="walk")
    start = time.monotonic()

    def ask() -> Job:
        trial = study.ask(distributions)
        trials[trial.number] = trial
        values = {name: float(v) for name, v in trial.params.items()}
        args = (base, search.omega, values, search.steps, search.objective, search.spatial)
        return Job(1.0, (trial.number, tuple(values.items())), walk_candidate, args)

    def on_done(key, result):
        number, values = key
        finished[number] = (dict(values), result)
        bar.update(1)
        released = []
        while len(candidates) in finished:  # the next in trial order has finished: tell it, ask one more
            told = len(candidates)
            told_values, (outcome, steps, score, detail) = finished.pop(told)
            study.tell(trials.pop(told), score)
            candidates.append(Candidate(told, told_values, outcome, int(steps), float(score), detail))
            if len(candidates) + len(trials) < search.budget:
                released.append(ask())
        return released

    first = [ask() for _ in range(min(IN_FLIGHT, search.budget))]
    try:
        run_jobs(first, on_done, workers=max(1, workers))
    finally:
        bar.close()
    candidates.sort(key=lambda c: c.number)
    return WalkerSearchResult(search, candidates, time.monotonic() - start)
