"""Multi-objective design optimisation: Optuna's NSGA-II over the design record, with constraints.

Each trial is a design: the base design with the varied parameters drawn by the sampler (trial 0
is the base design itself, when it lies inside the ranges). Its
metrics (:func:`~pasibot_pin.studies.design_metrics.design_metrics`) give the objectives (e.g.
``peak_crank_torque_Nm:min``) and the constraints (e.g. ``cop_margin_m>=0``, ``stride_m>=0.45``).
Optuna's constrained NSGA-II prefers feasible trials; a design that cannot be built is a failed
trial. A generation's trials are asked together and evaluated on the executor of the sweep
(:mod:`~pasibot_pin.explore.executors`), so a pool and a Dask cluster give the same trials.

The study lives in ``OUT/optuna.log`` (Optuna's journal file) and the rows in the run's table
(:mod:`~pasibot_pin.explore.store`), both written as trials finish: an interrupted run continues
where it stopped (a trial asked but not finished is evaluated again), and the same command with
more ``--trials`` continues a finished one. The trials already done are kept as they were; the
sampler of a resumed run starts its random stream afresh, so its later generations are not those
an uninterrupted run would have drawn (an uninterrupted run is reproducible bit for bit, on any
executor).
"""

from __future__ import annotations

import math
import re
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pasibot_pin.errors import ParameterError
from pasibot_pin.explore.executors import check_workers, run_tasks
from pasibot_pin.explore.plan import DEFAULT_RANGES, Choice, Varied, check_floor, range_record
from pasibot_pin.explore.store import ResultStore
from pasibot_pin.explore.sweep import evaluate_designs, floor_columns
from pasibot_pin.model.design import Design
from pasibot_pin.progress import progress_bar
from pasibot_pin.reprs import short_repr
from pasibot_pin.studies.design_metrics import ALL_METRICS, warm_caches

STUDY_NAME = "pasibot"
STORAGE = "optuna.log"


@dataclass(frozen=True)
class Objective:
    """A metric to minimise or maximise."""

    metric: str
    sense: str = "min"

    def __post_init__(self) -> None:
        if self.metric not in ALL_METRICS:
            raise ParameterError(f"--objective {self.metric!r}: unknown metric; valid: {', '.join(ALL_METRICS)}")
        if self.sense not in ("min", "max"):
            raise ParameterError(f"--objective {self.metric}:{self.sense}: the sense must be min or max")

    def text(self) -> str:
        """``METRIC:SENSE``."""
        return f"{self.metric}:{self.sense}"


def parse_objective(text: str) -> Objective:
    """An :class:`Objective` from ``METRIC[:min|max]`` (default: the metric's usual sense)."""
    name, _, sense = str(text).partition(":")
    default = ALL_METRICS[name].sense if name in ALL_METRICS else "min"
    return Objective(name, sense or default or "min")


@dataclass(frozen=True)
class Constraint:
    """``metric >= bound`` or ``metric <= bound``; violated by ``violation(value) > 0``."""

    metric: str
    op: str
    bound: float

    def __post_init__(self) -> None:
        if self.metric not in ALL_METRICS:
            raise ParameterError(f"--constraint {self.metric!r}: unknown metric; valid: {', '.join(ALL_METRICS)}")
        if self.op not in (">=", "<="):
            raise ParameterError(f"--constraint {self.text()}: use >= or <=")
        if not math.isfinite(self.bound):
            raise ParameterError(f"--constraint {self.metric}: the bound must be a finite number, got {self.bound!r}")

    def violation(self, value: float) -> float:
        """How far ``value`` is on the wrong side of the bound (<= 0: satisfied)."""
        if not math.isfinite(value):
            return math.inf
        return self.bound - value if self.op == ">=" else value - self.bound

    def text(self) -> str:
        """``METRIC>=BOUND``."""
        return f"{self.metric}{self.op}{self.bound:g}"


def parse_constraint(text: str) -> Constraint:
    """A :class:`Constraint` from ``METRIC>=BOUND`` or ``METRIC<=BOUND``."""
    match = re.fullmatch(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*(>=|<=)\s*(\S+)\s*", str(text))
    if match is None:
        raise ParameterError(f"--constraint {text!r}: write METRIC>=BOUND or METRIC<=BOUND, e.g. cop_margin_m>=0")
    try:
        bound = float(match.group(3))
    except ValueError:
        raise ParameterError(f"--constraint {text!r}: the bound must be a number") from None
    return Constraint(match.group(1), match.group(2), bound)


@dataclass(frozen=True)
class OptimizePlan:
    """An optimisation run.

    Attributes:
        ranges: the varied parameters and their bounds.
        objectives: one or more objectives.
        constraints: constraints on the metrics.
        trials: the number of designs evaluated.
        population: NSGA-II's population (designs per generation).
        seed: the sampler's seed.
        base: the design every other parameter is taken from.
        floor: also walk every design this many steps on the floor (``None``: no; slower).

    """

    ranges: tuple[Varied, ...] = DEFAULT_RANGES
    objectives: tuple[Objective, ...] = (Objective("peak_crank_torque_Nm", "min"),)
    constraints: tuple[Constraint, ...] = ()
    trials: int = 200
    population: int = 20
    seed: int = 0
    base: Design = field(default_factory=Design)
    floor: int | None = None

    def __post_init__(self) -> None:
        check_floor(self.floor)
        for name, value, low in (("trials", self.trials, 1), ("population", self.population, 2)):
            if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= 1_000_000:
                raise ParameterError(f"parameter {name!r} must be an integer in [{low}, 1e6], got {value!r}")
        if not self.objectives:
            raise ParameterError("an optimisation needs at least one --objective")
        if not self.ranges:
            raise ParameterError("an optimisation needs at least one --vary NAME=LO:HI")
        for attr in ("ranges", "objectives", "constraints"):
            object.__setattr__(self, attr, tuple(getattr(self, attr)))

    @property
    def names(self) -> tuple[str, ...]:
        """The varied parameters."""
        return tuple(r.name for r in self.ranges)

    def to_dict(self) -> dict:
        """A JSON-able record (``plan.json``)."""
        return {
            "ranges": [range_record(r) for r in self.ranges],
            "objectives": [o.text() for o in self.objectives],
            "constraints": [c.text() for c in self.constraints],
            "trials": self.trials,
            "population": self.population,
            "seed": self.seed,
            "base": self.base.to_dict(),
            "floor": self.floor,
        }

    def violations(self, row: dict) -> list[float]:
        """Each constraint's violation for a table row (<= 0: satisfied)."""
        return [c.violation(float(row[c.metric])) for c in self.constraints]


@dataclass
class OptimizeResult:
    """What an optimisation produced: the folder, plan, table, trials evaluated now, Pareto rows."""

    __repr__ = short_repr

    folder: Path
    plan: OptimizePlan
    table: object
    evaluated: int
    pareto: list[int]
    results: Path


def _storage(folder: Path):
    """The study's storage: Optuna's journal file ``optuna.log`` (appends only, fast, survives a crash)."""
    from optuna.storages import JournalStorage  # deferred: optional extra (optuna)
    from optuna.storages.journal import JournalFileBackend  # deferred: optional extra (optuna)

    return JournalStorage(JournalFileBackend(str(folder / STORAGE)))


def _sampler(plan: OptimizePlan):
    import optuna  # deferred: optional extra (optuna)

    warnings.filterwarnings("ignore", category=optuna.exceptions.ExperimentalWarning)
    return optuna.samplers.NSGAIISampler(
        population_size=plan.population,
        seed=plan.seed,
        constraints_func=(lambda t: t.user_attrs["violations"]) if plan.constraints else None,
    )


def run_optimize(
    plan: OptimizePlan,
    folder: Path,
    *,
    workers: int | None = None,
    dask: str | None = None,
    force: bool = False,
    csv: bool = False,
    progress: bool = True,
    on_generation: Callable[[int, int], None] | None = None,
) -> OptimizeResult:
    """Run (or continue) an optimisation in ``folder``.

    Args:
        plan: the optimisation.
        folder: the run's folder (created; resumed when it holds the same plan).
        workers: processes (default one per core).
        dask: ``None``, ``"local"`` or a Dask scheduler address.
        force: start over in a folder that holds another run or other files.
        csv: also write ``results.csv``.
        progress: show a progress bar with the ETA.
        on_generation: called with (trials done, trials) after each generation.

    Returns:
        An :class:`OptimizeResult`.

    """
    workers = check_workers(workers)
    folder = Path(folder)
    record = {k: v for k, v in plan.to_dict().items() if k != "trials"}  # more trials continue the same run
    store = ResultStore(
        folder, {"kind": "optimize", **record}, plan.trials, force=force, extra=floor_columns(plan.floor)
    )
    study = _open_study(plan, folder)
    done_before = len(store.done)
    bar = progress_bar(plan.trials, done_before, progress)
    trials = _Trials(study, plan, store, bar, workers, dask)
    warm_caches(plan.base)  # forked workers inherit it
    try:
        trials.finish_interrupted()
        while len(store.done) < plan.trials:
            trials.run_generation()
            if on_generation is not None:
                on_generation(len(store.done), plan.trials)
    finally:
        store.flush()
        bar.close()
    results = store.finish(csv=csv)
    table = store.table()
    return OptimizeResult(folder, plan, table, len(store.done) - done_before, pareto_rows(table, plan), results)


def _open_study(plan: OptimizePlan, folder: Path):
    """The Optuna study of ``folder`` (created or loaded); a new one's trial 0 is the base design, when it may be."""
    import optuna  # deferred: optional extra (optuna)

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    study = optuna.create_study(
        study_name=STUDY_NAME,
        storage=_storage(folder),
        sampler=_sampler(plan),
        directions=["minimize" if o.sense == "min" else "maximize" for o in plan.objectives],
        load_if_exists=True,
    )
    base_values = {r.name: plan.base.values()[r.name] for r in plan.ranges}
    inside = all(_inside(r, v) for r, v in zip(plan.ranges, base_values.values()))
    if not study.trials and inside:
        study.enqueue_trial(base_values)  # trial 0 is the base design: the front is never worse than it
    return study


class _Trials:
    """A study's trials on the executor: asked a generation at a time, evaluated, told, saved to the store."""

    def __init__(self, study, plan: OptimizePlan, store: ResultStore, bar, workers: int, dask: str | None):
        self.study, self.plan, self.store, self.bar = study, plan, store, bar
        self.workers, self.dask = workers, dask
        self.base = plan.base.to_dict()
        self.ids: dict[int, int] = {}  # trial number -> storage id

    def finish_interrupted(self) -> None:
        """Trials asked but never finished (an interrupted run): told from the table, or evaluated again."""
        import optuna  # deferred: optional extra (optuna)

        running = self.study.get_trials(deepcopy=False, states=(optuna.trial.TrialState.RUNNING,))
        table_rows = {int(r["index"]): r for r in self.store.table().to_pylist()} if running else {}
        again = []
        self.ids.update({t.number: t._trial_id for t in running})
        for t in running:
            if t.number in table_rows:  # finished and saved, not yet told
                _tell_row(self.study, self.plan, table_rows[t.number], t._trial_id)
            elif all(n in t.params for n in self.plan.names):
                again.append((t.number, [t.params[n] for n in self.plan.names]))
            else:  # stopped while its parameters were drawn: nothing to evaluate; a new trial takes its place
                self.study.tell(t.number, state=optuna.trial.TrialState.FAIL)
        if again:
            self.evaluate(again)

    def run_generation(self) -> None:
        """Ask the sampler for the next generation (at most the trials left) and evaluate it."""
        size = min(self.plan.population, self.plan.trials - len(self.store.done))
        asked = [self.study.ask() for _ in range(size)]
        self.ids.update({t.number: t._trial_id for t in asked})
        self.evaluate([(t.number, [_suggest(t, r) for r in self.plan.ranges]) for t in asked])

    def evaluate(self, items: list[tuple[int, list[float | str]]]) -> None:
        """Evaluate (trial number, values) items, one design per task: a generation spreads over the workers."""
        tasks = [(self.base, self.plan.names, [item], self.plan.floor) for item in items]
        run_tasks(evaluate_designs, tasks, self.tell, workers=self.workers, dask=self.dask)

    def tell(self, rows: list[dict]) -> None:
        """Tell the study the finished rows, and save them."""
        for row in rows:
            _tell_row(self.study, self.plan, row, self.ids[int(row["index"])])
        self.store.add(rows)
        self.bar.update(len(rows))


def _suggest(trial, r: Varied) -> float | str:
    """The trial's value of one varied parameter (a float in a :class:`Range`, a value of a :class:`Choice`)."""
    if isinstance(r, Choice):
        return trial.suggest_categorical(r.name, list(r.values))
    return trial.suggest_float(r.name, r.low, r.high)


def _inside(r: Varied, value) -> bool:
    """The base design's ``value`` lies in ``r`` (it may be trial 0)."""
    if isinstance(r, Choice):
        return value in r.values
    return value is not None and r.low <= value <= r.high


def _tell_row(study, plan: OptimizePlan, row: dict, trial_id: int) -> None:
    """Tell the study a trial's result: its objectives and constraint violations, or a failure."""
    import optuna  # deferred: optional extra (optuna)

    number = int(row["index"])
    if row["feasible"]:
        optuna.trial.Trial(study, trial_id).set_user_attr("violations", plan.violations(row))
        study.tell(number, [float(row[o.metric]) for o in plan.objectives], skip_if_finished=True)
    else:
        study.tell(number, state=optuna.trial.TrialState.FAIL, skip_if_finished=True)


def pareto_rows(table, plan: OptimizePlan) -> list[int]:
    """Rows of the feasible, constraint-satisfying designs no other such design beats in every objective.

    Sorted by the first objective.
    """
    rows = table.to_pylist()
    ok = [i for i, r in enumerate(rows) if r["feasible"] and all(v <= 0 for v in plan.violations(r))]
    if not ok:
        return []
    signs = np.array([1.0 if o.sense == "min" else -1.0 for o in plan.objectives])
    values = np.array([[float(rows[i][o.metric]) for o in plan.objectives] for i in ok]).reshape(len(ok), -1) * signs
    front, seen = [], set()
    for a, i in enumerate(ok):
        beaten = np.any(np.all(values <= values[a], axis=1) & np.any(values < values[a], axis=1))
        key = tuple(values[a])
        if not beaten and key not in seen:  # NSGA-II may draw the same design twice: listed once
            front.append(i)
            seen.add(key)
    return sorted(front, key=lambda i: signs[0] * float(rows[i][plan.objectives[0].metric]))


def objectives_of(texts: Sequence[str] | None) -> tuple[Objective, ...]:
    """The ``--objective`` options, or minimal peak crank torque."""
    return tuple(parse_objective(t) for t in texts) if texts else (Objective("peak_crank_torque_Nm", "min"),)
