"""A design sweep: every design of a plan, its metrics, one table, its figures, the best designs.

:func:`run_sweep` evaluates the designs of a :class:`~pasibot_pin.explore.plan.SweepPlan` with
:func:`~pasibot_pin.studies.design_metrics.design_metrics` on an executor
(:mod:`~pasibot_pin.explore.executors`), streams the rows to disk and resumes an interrupted run
(:mod:`~pasibot_pin.explore.store`). :func:`write_figures` draws the Pareto front and the
sensitivity map; :func:`export_best` writes the best designs as design files, URDF and MJCF.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pasibot_pin.errors import ParameterError
from pasibot_pin.explore.executors import check_workers, run_tasks
from pasibot_pin.explore.plan import SweepPlan
from pasibot_pin.explore.store import RESULTS, RESULTS_CSV, ResultStore, column, design_row, parameter_names
from pasibot_pin.files import atomic_path, write_text_atomic
from pasibot_pin.model.description import render_urdf, shape_soles
from pasibot_pin.model.design import CHOICES, Design, design_robot
from pasibot_pin.model.mjcf import MjcfOptions, to_mjcf
from pasibot_pin.progress import progress_bar
from pasibot_pin.reprs import short_repr
from pasibot_pin.studies.design_metrics import (
    ALL_METRICS,
    FLOOR3D_METRICS,
    FLOOR_METRICS,
    FLOOR_PLANAR_METRICS,
    DesignMetrics,
    design_metrics,
    infeasible,
    pareto_mask,  # noqa: F401 (re-exported)
    warm_caches,
)
from pasibot_pin.studies.methods.spring_fit import design_spring
from pasibot_pin.studies.walking import MIN_OMEGA, SEARCH_BUDGET, check_walk_budget, walk_cost, walk_duration
from pasibot_pin.viz.figure_files import save_figure_file
from pasibot_pin.viz.plots_sweep import plot_pareto, plot_sensitivity

CHUNK: int = 4
"""Designs per task (a task's result comes back as one piece)."""


def evaluate_designs(
    base: dict,
    names: Sequence[str],
    items: Sequence[tuple[int, Sequence[float | str]]],
    floor: int | None = None,
    spatial: bool = False,
    slope: float = 0.0,
) -> list[dict]:
    """Rows of ``items`` (index, values of ``names``) on the ``base`` design; runs in a worker.

    A value is a number, or a string for a categorical parameter (``variant="parallel"``).
    A design the record rejects (a value outside its bounds) is an ``invalid`` row, not an error.
    ``floor``: also walk each design this many steps on the floor (``spatial``: the 3-D floor; ``slope``:
    up a slope of this angle [rad]).
    """
    base_design = Design.from_dict(base)
    rows = []
    for index, values in items:
        changes = {name: v if isinstance(v, str) else float(v) for name, v in zip(names, values)}
        try:
            design = base_design.with_(**changes)
        except ValueError as err:
            bad = infeasible("invalid", str(err))
            if floor is not None:
                bad = DesignMetrics(bad.values, False, bad.failure, bad.reason, "")
            rows.append(design_row(index, {**base_design.values(), **changes}, bad.row()))
            continue
        rows.append(design_row(index, design.values(), design_metrics(design, floor, spatial, slope).row()))
    return rows


def floor_columns(floor: int | None, spatial: bool = False) -> dict[str, str]:
    """The table's extra columns with a floor simulation (name -> kind), none without."""
    if floor is None:
        return {}
    extra = FLOOR3D_METRICS if spatial else FLOOR_PLANAR_METRICS
    return {**dict.fromkeys(FLOOR_METRICS, "float"), **dict.fromkeys(extra, "float"), "floor_outcome": "str"}


@dataclass
class SweepResult:
    """What a sweep produced.

    Attributes:
        folder: the run's folder.
        plan: its plan.
        table: every row (a pyarrow Table, sorted by ``index``).
        evaluated: designs evaluated by this call (the others were on disk already).
        results: path of ``results.parquet``.

    """

    __repr__ = short_repr

    folder: Path
    plan: SweepPlan
    table: object
    evaluated: int
    results: Path

    @property
    def feasible(self) -> int:
        """The number of feasible designs."""
        return int(np.sum(column(self.table, "feasible")))


def task_cost(plan: SweepPlan, designs: Sequence[Sequence[float | str]]) -> float:
    """A task's expected cost, to run the costly ones first.

    1 per design [-], or with a floor walk the simulated time a walk of ``plan.floor`` steps may
    need [s] (it grows as 1 / omega).
    """
    if not plan.floor:
        return float(len(designs))
    index = plan.names.index("omega") if "omega" in plan.names else None
    omegas = [plan.base.omega if index is None else float(values[index]) for values in designs]
    return sum(walk_duration(max(omega, MIN_OMEGA), plan.floor) for omega in omegas)


def run_sweep(
    plan: SweepPlan,
    folder: Path,
    *,
    workers: int | None = None,
    dask: str | None = None,
    force: bool = False,
    csv: bool = False,
    progress: bool = True,
    chunk: int | None = None,
    on_progress: Callable[[int, int], None] | None = None,
) -> SweepResult:
    """Evaluate every design of ``plan`` into ``folder``; resume what an earlier run left.

    Args:
        plan: the designs.
        folder: the run's folder (created; resumed when it holds the same plan).
        workers: processes (default one per core).
        dask: ``None``, ``"local"`` or a Dask scheduler address (:func:`~pasibot_pin.explore.executors.run_tasks`).
        force: start over in a folder that holds another run or other files.
        csv: also write ``results.csv``.
        progress: show a progress bar (tqdm) with the ETA.
        chunk: designs per task (default :data:`CHUNK`; 1 with a floor walk).
        on_progress: called with (done, total) after each finished task.

    Returns:
        A :class:`SweepResult`.

    Raises:
        FileExistsError: ``folder`` holds another run or other files and ``force`` is false.

    """
    if chunk is None:
        chunk = 1 if plan.floor else CHUNK  # a walk outweighs a task's overhead: one per task, balanced by cost
    if isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1:
        raise ParameterError(f"parameter 'chunk' must be a positive integer, got {chunk!r}")
    workers = check_workers(workers)
    points = plan.points()
    if plan.floor:  # bound the walks' work before any of it
        index = plan.names.index("omega") if "omega" in plan.names else None
        omegas = [plan.base.omega if index is None else float(plan.values(row)[index]) for row in points]
        cost = sum(walk_cost(w, plan.floor, spatial=plan.spatial) for w in omegas)
        check_walk_budget(cost, f"--floor {plan.floor} for {len(points)} designs", SEARCH_BUDGET)
    store = ResultStore(
        Path(folder),
        {"kind": "sweep", **plan.to_dict()},
        len(points),
        force=force,
        extra=floor_columns(plan.floor, plan.spatial),
    )
    todo = [(i, plan.values(row)) for i, row in enumerate(points) if i not in store.done]
    tasks = [
        (plan.base.to_dict(), plan.names, todo[k : k + chunk], plan.floor, plan.spatial, plan.slope)
        for k in range(0, len(todo), chunk)
    ]
    costs = [task_cost(plan, [values for _, values in task[2]]) for task in tasks]
    bar = progress_bar(len(points), len(points) - len(todo), progress)

    def on_result(rows: list[dict]) -> None:
        store.add(rows)
        bar.update(len(rows))
        if on_progress is not None:
            on_progress(len(store.done), len(points))

    warm_caches(plan.base)  # forked workers inherit it
    try:
        run_tasks(evaluate_designs, tasks, on_result, workers=workers, dask=dask, costs=costs)
    finally:
        store.flush()  # every finished design is kept, even when interrupted
        bar.close()
    results = Path(folder) / RESULTS
    if todo or not results.is_file() or (csv and not (Path(folder) / RESULTS_CSV).is_file()):
        results = store.finish(csv=csv)  # a complete run's table is never rewritten
    return SweepResult(Path(folder), plan, store.table(), len(todo), results)


# --------------------------------------------------------------------------- after the run
PLAIN_OBJECTIVES = ("peak_crank_torque_Nm", "stride_m")
"""``pareto.png``'s axes for a sweep without a floor walk: the welded walk's peak crank torque and stride."""

FLOOR_OBJECTIVES = ("floor_motor_torque_peak_Nm", "floor_energy_per_m_J")
"""``pareto.png``'s axes for a walking sweep (``--floor``): the motor's peak on the floor and its energy per metre,
both to be low; only the designs that walk can be on the front."""


@dataclass(frozen=True)
class WalksOnTheFloor:
    """The constraint of a walking sweep's front: ``floor_walks`` = 1 (the walking verdict is ``walks``)."""

    metric: str = "floor_walks"

    def violation(self, value: float) -> float:
        """0 for a walker, 1 otherwise (NaN: not walked) [-]."""
        return 0.0 if value >= 1.0 else 1.0

    def text(self) -> str:
        """In the figure's legend."""
        return "walks on the floor"


def pareto_axes(table, objectives: tuple[str, str] | None, constraints: Sequence = ()) -> tuple[tuple[str, str], tuple]:
    """``pareto.png``'s (x and y metrics, constraints).

    ``objectives`` when given; else the floor's (:data:`FLOOR_OBJECTIVES`, walkers only) when the table has a
    walk on the floor, else :data:`PLAIN_OBJECTIVES`.
    """
    if objectives is not None:
        return (objectives[0], objectives[1]), tuple(constraints)
    if "floor_walks" in table.column_names and all(m in table.column_names for m in FLOOR_OBJECTIVES):
        return FLOOR_OBJECTIVES, (*constraints, WalksOnTheFloor())
    return PLAIN_OBJECTIVES, tuple(constraints)


def write_figures(
    table, folder: Path, varied: Sequence[str], objectives: tuple[str, str] | None = None, constraints: Sequence = ()
) -> list[Path]:
    """``pareto.png`` and ``sensitivity.png`` of a results table into ``folder``.

    ``constraints``: an optimisation's ``--constraint``s; designs that violate one are greyed, off the front.
    Without ``objectives`` the front's axes are :func:`pareto_axes`' (a walking sweep's are the floor's).
    The sensitivity map ranks the numeric parameters of ``varied`` only (a varied variant is a column of strings).
    """
    import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

    varied = [name for name in varied if name not in CHOICES]

    matplotlib.use("Agg")

    written = []
    axes, shown = pareto_axes(table, objectives, constraints)
    figures = (
        ("pareto.png", lambda: plot_pareto(table, *axes, constraints=shown)),
        ("sensitivity.png", lambda: plot_sensitivity(table, varied)),
    )
    for name, draw in figures:
        fig = draw()
        with atomic_path(Path(folder) / name) as tmp:
            save_figure_file(fig, tmp, 120)
        matplotlib.pyplot.close(fig)
        written.append(Path(folder) / name)
    return written


def best_rows(table, by: str, sense: str = "min", count: int = 5, where: Callable | None = None) -> list[int]:
    """Row numbers of the ``count`` best feasible designs by metric ``by`` (``sense`` min or max).

    In a walking sweep (a ``floor_walks`` column) the designs that walk come first.
    """
    if by not in ALL_METRICS:
        raise ParameterError(f"parameter 'by': unknown metric {by!r}; valid: {', '.join(ALL_METRICS)}")
    values = column(table, by).astype(float)
    ok = column(table, "feasible").astype(bool) & np.isfinite(values)
    if where is not None:
        ok &= np.asarray(where(table), dtype=bool)
    idx = np.flatnonzero(ok)
    key = values[idx] if sense == "min" else -values[idx]
    if "floor_walks" in table.column_names:  # a walking sweep: the walkers first, each group by the metric
        walks = np.nan_to_num(column(table, "floor_walks").astype(float))[idx]
        return [int(i) for i in idx[np.lexsort((key, -walks))][:count]]
    return [int(i) for i in idx[np.argsort(key, kind="stable")][:count]]


def design_of_row(table, row: int):
    """The :class:`~pasibot_pin.model.design.Design` of one table row.

    A parameter the table has no column for (a table written before the parameter existed) keeps
    the design record's default.
    """
    values = {}
    present = set(table.column_names)
    for name in parameter_names():
        if name not in present:
            continue
        value = table.column(name)[row].as_py()
        values[name] = None if isinstance(value, float) and math.isnan(value) else value
    return Design.from_dict(values)


def export_best(table, rows: Sequence[int], folder: Path) -> list[Path]:
    """Write each row's design as ``NN_index<i>.toml``, ``.urdf`` and ``.xml`` (MJCF) into ``folder``."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for rank, row in enumerate(rows, start=1):
        design = design_of_row(table, row)
        stem = folder / f"{rank:02d}_index{int(table.column('index')[row].as_py())}"
        written.append(design.save(stem.with_suffix(".toml"), force=True))
        text = render_urdf(design.variant, 2, design.geometry(), design.masses(), design.inertia)
        text = shape_soles(text, design.footprint(), design.L)  # the design's soles (a plate or a comb)
        written.append(write_text_atomic(stem.with_suffix(".urdf"), text))
        robot = design_robot(design, 2)
        spring = design_spring(design, robot)
        springs = (
            {}
            if spring is None
            else {
                "spring_stiffness": spring.stiffness,
                "spring_rest_angle": spring.rest_angle,
                "spring_damping": spring.damping,
            }
        )
        written.append(write_text_atomic(stem.with_suffix(".xml"), to_mjcf(robot, MjcfOptions(**springs))))
    return written
