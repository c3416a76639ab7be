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

The answers quoted in the README are the designs in ``docs/results/`` (written by
:func:`write_answer`); ``tests/test_questions.py`` evaluates them again and checks every quoted
number and every constraint.
"""

from __future__ import annotations

import argparse
import json
import shutil
import tempfile
from collections import Counter
from pathlib import Path

import numpy as np

from pasibot_pin.explore.optimize import Constraint, Objective, OptimizePlan, run_optimize
from pasibot_pin.explore.plan import Range
from pasibot_pin.explore.sweep import design_of_row, write_figures
from pasibot_pin.model.design import Design
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

RESULTS_DIR = Path(__file__).resolve().parents[2] / "docs" / "results"
"""Where the answers of a source checkout are kept (the designs, the runs' Parquet tables, the figures)."""

SUMMARY = "answers_summary.json"
"""The figures the report quotes from the runs' tables (:func:`summarize_tables`), as JSON in
:data:`RESULTS_DIR`: ``pasibot analyze`` reads them without pyarrow."""


def _answers_dir() -> Path:
    # Installed wheel: the answer designs and the summary are packaged as pasibot_pin/results
    # (pyproject's force-include; the Parquet tables and figures stay in the repository).
    # Source checkout or editable install: docs/results.
    packaged = Path(__file__).resolve().parents[1] / "results"
    return packaged if (packaged / SUMMARY).is_file() else RESULTS_DIR


ANSWERS_DIR: Path = _answers_dir()
"""Where the answer designs (``.toml``) and :data:`SUMMARY` are read: the wheel's copy, else :data:`RESULTS_DIR`."""


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
"""Question 2's table in :data:`RESULTS_DIR`."""


def answer_path(straight: bool, suffix: str = ".toml") -> Path:
    """Question 1's answer: its design (``.toml``, in :data:`ANSWERS_DIR`) or the run's table (``.parquet``).

    ``straight``: the run with the straightness constraint.
    """
    stem = "least_torque_seed_stride_straight" if straight else "least_torque_seed_stride"
    return (ANSWERS_DIR if suffix == ".toml" else RESULTS_DIR) / f"{stem}{suffix}"


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


def summarize_tables() -> dict:
    """The figures the report quotes, from the runs' Parquet tables in :data:`RESULTS_DIR` (needs pyarrow).

    Returns:
        ``designs_explored`` (rows of question 1's two runs), ``best_cop_margin_m`` (the best CoP
        margin of any feasible design of them [m]) and ``floor`` (question 2's :func:`floor_summary`).

    """
    import pyarrow.parquet as pq  # deferred: optional extra (pyarrow)

    tables = [pq.read_table(answer_path(s, ".parquet"), columns=["feasible", "cop_margin_m"]) for s in (False, True)]
    margins = np.concatenate([t.filter(t.column("feasible")).column("cop_margin_m").to_numpy() for t in tables])
    floor = floor_summary(pq.read_table(RESULTS_DIR / FLOOR_TABLE).to_pylist())
    return {
        "designs_explored": int(sum(t.num_rows for t in tables)),
        "best_cop_margin_m": float(np.max(margins)),
        "floor": floor,
    }


def write_summary() -> Path:
    """Write :func:`summarize_tables` to :data:`RESULTS_DIR` / :data:`SUMMARY` (``make answers`` does)."""
    path = RESULTS_DIR / SUMMARY
    path.write_text(json.dumps(summarize_tables(), indent=2, sort_keys=True) + "\n")
    return path


def read_summary() -> dict:
    """:data:`SUMMARY` as written by :func:`write_summary` (no pyarrow needed)."""
    return json.loads((ANSWERS_DIR / SUMMARY).read_text())


def write_answer(straight: bool, folder: Path, workers: int | None = None, force: bool = False) -> Design:
    """Run question 1 into ``folder``; save its least-torque design and its table as :func:`answer_path`."""
    result = run_optimize(seed_stride_plan(straight), folder, workers=workers, force=force, progress=False)
    if not result.pareto:
        raise ValueError("no design satisfies the constraints")
    design = design_of_row(result.table, result.pareto[0])  # the front sorted by peak torque
    RESULTS_DIR.mkdir(parents=True, exist_ok=True)
    design.save(answer_path(straight), force=True)
    shutil.copyfile(result.results, answer_path(straight, ".parquet"))
    return design


def write_floor_answer(folder: Path, workers: int | None = None) -> Path:
    """Run question 2 into ``folder``; copy its table to :data:`RESULTS_DIR` / :data:`FLOOR_TABLE`."""
    result = run_optimize(floor_plan(), folder, workers=workers, force=True, progress=True)
    shutil.copyfile(result.results, RESULTS_DIR / FLOOR_TABLE)
    return RESULTS_DIR / FLOOR_TABLE


def main(argv: list[str] | None = None) -> None:
    """Run the questions again (``make answers``): docs/results/*.toml, *.parquet, pareto.png, the summary.

    ``--floor-only``: question 2 alone (and the summary).
    """
    parser = argparse.ArgumentParser(description="run the design-exploration questions again (docs/results/)")
    parser.add_argument("--floor-only", action="store_true", help="only question 2 (the spring designs on the floor)")
    parser.add_argument("--workers", type=int, default=None, help="worker processes (default: one per core)")
    args = parser.parse_args(argv)
    if not args.floor_only:
        _question_one(args.workers)
    with tempfile.TemporaryDirectory() as tmp:
        print(write_floor_answer(Path(tmp) / "floor", workers=args.workers))
    print(write_summary())


def _question_one(workers: int | None) -> None:
    import pyarrow.parquet as pq  # deferred: optional extra (pyarrow)

    with tempfile.TemporaryDirectory() as tmp:
        for straight in (False, True):
            design = write_answer(straight, Path(tmp) / str(straight), workers=workers)
            print(f"{answer_path(straight)}: K = {design.K:.4g}")
    table = pq.read_table(answer_path(False, ".parquet"))
    for path in write_figures(table, RESULTS_DIR, [r.name for r in QUESTION_RANGES]):
        print(path)


if __name__ == "__main__":
    main()
