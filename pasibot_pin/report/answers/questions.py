"""The designer's questions the README answers, as reproducible optimisation plans.

1. *Which designs (geometry, spring, sole, body COM) minimise the peak crank torque while keeping
   the seed design's stride?* :func:`seed_stride_plan`: NSGA-II over the frame ratio K, the
   pantograph links L4, L5, L6, the sole and the body COM; objectives: peak crank torque (min) and
   CoP margin (max); constraint: the stride within :data:`STRIDE_TOLERANCE` of the seed's. With
   ``straight=True`` the stance path must also stay as straight as :data:`STRAIGHTNESS_FACTOR`
   times the seed's (a hip that does not bob).
2. *Does any spring design walk on the floor?* The walking map (:mod:`pasibot_pin.studies.walking_map`)
   walks every variant with its fitted spring; :func:`floor_plan` searches the spring itself:
   NSGA-II over spring designs on the floor (:data:`FLOOR_RANGES`: the spring's stiffness, rest
   angle and damping, the sole up to 10 L each side, K, the body COM and the crank speed), each
   asked to walk :data:`FLOOR_STEPS` steps and judged by the walking verdict
   (:mod:`pasibot_pin.dynamics.verdict`), maximising the steps walked and the time to the verdict.

The answers quoted in the README are the designs in ``docs/results/``: ``make answers``
(``tools/answers.py``) runs :func:`run_question_one` and :func:`run_floor_question` and writes their designs,
tables, figures and :func:`summary_text` there; the package reads them back (:func:`answer_path`,
:func:`read_summary`) and never writes them. ``tests/test_questions.py`` evaluates them again and checks
every quoted number and every constraint.
"""

from __future__ import annotations

import json
from collections import Counter
from pathlib import Path

import numpy as np

from pasibot_pin.explore.optimize import Constraint, Objective, OptimizePlan, run_optimize
from pasibot_pin.explore.plan import Range
from pasibot_pin.explore.sweep import design_of_row
from pasibot_pin.model.design import Design
from pasibot_pin.model.paths import result_path
from pasibot_pin.model.scenarios import get_scenario
from pasibot_pin.studies.design_metrics import path_metrics

STRIDE_TOLERANCE: float = 0.01
"""Largest relative change of the stride from the seed design's [-]."""

STRAIGHTNESS_FACTOR: float = 2.0
"""With ``straight=True``: the stance ankle's straightness stays below this multiple of the seed's [-]."""

QUESTION_RANGES: tuple[Range, ...] = (
    Range("K", 1.7, 2.6),
    Range("r4", 8.0, 10.0),
    Range("r5", 16.0, 20.0),
    Range("r6", 5.0, 7.0),
    Range("foot_toe", 1.0, 3.0),
    Range("foot_heel", 0.3, 1.5),
    Range("body_com_dx", -0.05, 0.05),
)
"""The varied parameters: geometry (K, L4, L5, L6 over L), the sole (over L) and the body COM [m]."""

FLOOR_RANGES: tuple[Range, ...] = (
    Range("spring_stiffness", 0.0, 1500.0),
    Range("spring_rest_angle", 0.8, 2.2),
    Range("spring_damping", 0.0, 30.0),
    Range("foot_toe", 1.0, 10.0),
    Range("foot_heel", 0.3, 10.0),
    Range("K", 1.8, 2.4),
    Range("body_com_dx", -0.1, 0.3),
    Range("omega", 1.0, 8.0),
)
"""Question 2's varied parameters: the ankle spring [N.m/rad, rad, N.m.s/rad], the sole [L], K, the body
COM [m], the crank speed [rad/s] (the walking map's soles and speeds; 0.5 rad/s walks are the slowest)."""

FLOOR_STEPS: int = 6
"""How many steps each design of question 2 is asked to walk on the floor [-]."""

SUMMARY = "answers_summary.json"
"""The figures the report quotes from the runs' tables (:func:`summarize_tables`), as JSON beside the answers
(``docs/results/``, packaged in the wheel): ``pasibot analyze`` reads them without pyarrow."""


def seed_stride_plan(straight: bool = False, trials: int = 600, population: int = 40, seed: int = 0) -> OptimizePlan:
    """Question 1 as an :class:`~pasibot_pin.explore.optimize.OptimizePlan` (see the module's notes)."""
    base = Design()
    reference = path_metrics(base)
    stride = reference["stride_m"]
    constraints = [
        Constraint("stride_m", ">=", stride * (1 - STRIDE_TOLERANCE)),
        Constraint("stride_m", "<=", stride * (1 + STRIDE_TOLERANCE)),
    ]
    if straight:
        constraints.append(Constraint("straightness_m", "<=", STRAIGHTNESS_FACTOR * reference["straightness_m"]))
    return OptimizePlan(
        ranges=QUESTION_RANGES,
        objectives=(Objective("peak_crank_torque_Nm", "min"), Objective("cop_margin_m", "max")),
        constraints=tuple(constraints),
        trials=trials,
        population=population,
        seed=seed,
        base=base,
    )


def floor_plan(trials: int = 120, population: int = 24, seed: int = 0) -> OptimizePlan:
    """Question 2 as an :class:`~pasibot_pin.explore.optimize.OptimizePlan` (see the module's notes).

    The base is the fast seed run's body (run 4: 20 kg) on the spring variant.
    """
    run4 = get_scenario("run4")
    return OptimizePlan(
        ranges=FLOOR_RANGES,
        objectives=(Objective("floor_steps", "max"), Objective("floor_time_s", "max")),
        trials=trials,
        population=population,
        seed=seed,
        base=Design(omega=run4.omega, body_mass=run4.body_mass),
        floor=FLOOR_STEPS,
    )


FLOOR_TABLE = "floor_springs.parquet"
"""Question 2's table, beside question 1's (``docs/results/``; the tables are not packaged)."""


def answer_name(straight: bool, suffix: str = ".toml") -> str:
    """The file name of question 1's answer: its design (``.toml``) or its run's table (``.parquet``).

    ``straight``: the run with the straightness constraint.
    """
    stem = "least_torque_seed_stride_straight" if straight else "least_torque_seed_stride"
    return f"{stem}{suffix}"


def answer_path(straight: bool) -> Path:
    """Question 1's committed answer design (read only: :func:`~pasibot_pin.model.paths.result_path`)."""
    return result_path(answer_name(straight))


def floor_summary(rows: list[dict]) -> dict:
    """Question 2's summary from its table's rows (the fields of the report's ``FloorAnswer``).

    Args:
        rows: one dict per design, with ``index``, ``feasible``, ``floor_time_s`` [s], ``floor_steps`` and
            ``floor_outcome``.

    Returns:
        ``trials``, ``walkers``, ``best_time`` [s], ``best_steps``, ``most_steps`` (the best design: the
        most steps, then the longest run), ``outcomes`` (each outcome's count; ``infeasible``: a design
        that cannot be built or turned), ``best_index`` and ``best_outcome``.

    """
    walked = [r for r in rows if r["feasible"]]
    best = max(walked, key=lambda r: (r["floor_steps"], r["floor_time_s"]))
    outcomes = Counter(r["floor_outcome"] if r["feasible"] else "infeasible" for r in rows)
    return {
        "trials": len(rows),
        "walkers": outcomes.get("walks", 0),
        "best_time": float(best["floor_time_s"]),
        "best_steps": int(best["floor_steps"]),
        "most_steps": int(max(r["floor_steps"] for r in walked)),
        "outcomes": dict(outcomes.most_common()),
        "best_index": int(best["index"]),
        "best_outcome": str(best["floor_outcome"]),
    }


def summarize_tables(folder: Path) -> dict:
    """The figures the report quotes, from the runs' Parquet tables in ``folder`` (needs pyarrow).

    Args:
        folder: where the runs' tables are (:func:`answer_name` ``.parquet`` and :data:`FLOOR_TABLE`:
            ``docs/results/`` of a source checkout).

    Returns:
        ``designs_explored`` (rows of question 1's two runs), ``best_cop_margin_m`` (the best CoP
        margin of any feasible design of them [m]) and ``floor`` (question 2's :func:`floor_summary`).

    """
    import pyarrow.parquet as pq  # deferred: optional extra (pyarrow)

    folder = Path(folder)
    columns = ["feasible", "cop_margin_m"]
    tables = [pq.read_table(folder / answer_name(s, ".parquet"), columns=columns) for s in (False, True)]
    margins = np.concatenate([t.filter(t.column("feasible")).column("cop_margin_m").to_numpy() for t in tables])
    floor = floor_summary(pq.read_table(folder / FLOOR_TABLE).to_pylist())
    return {
        "designs_explored": int(sum(t.num_rows for t in tables)),
        "best_cop_margin_m": float(np.max(margins)),
        "floor": floor,
    }


def summary_text(summary: dict) -> str:
    """:func:`summarize_tables`'s figures as the text of :data:`SUMMARY` (sorted JSON, two-space indent)."""
    return json.dumps(summary, indent=2, sort_keys=True) + "\n"


def read_summary() -> dict:
    """The committed :data:`SUMMARY` (no pyarrow needed)."""
    return json.loads(result_path(SUMMARY).read_text())


def run_question_one(
    straight: bool, folder: Path, workers: int | None = None, force: bool = False
) -> tuple[Design, Path]:
    """Run question 1 into ``folder``: (its least-torque design, the run's table [a Parquet file in ``folder``]).

    Raises:
        ValueError: no design of the run satisfies the constraints.

    """
    result = run_optimize(seed_stride_plan(straight), folder, workers=workers, force=force, progress=False)
    if not result.pareto:
        raise ValueError("no design satisfies the constraints")
    return design_of_row(result.table, result.pareto[0]), Path(result.results)  # the front sorted by peak torque


def run_floor_question(folder: Path, workers: int | None = None) -> Path:
    """Run question 2 into ``folder``: the run's table (a Parquet file in ``folder``)."""
    return Path(run_optimize(floor_plan(), folder, workers=workers, force=True, progress=True).results)
