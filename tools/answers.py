"""``make answers``: run the design-exploration questions again and write their answers into ``docs/results/``.

Question 1 (twice: with and without the straight-path constraint) writes its least-torque design (``.toml``) and
its run's table (``.parquet``), and ``pareto.png`` and ``sensitivity.png``; question 2 writes its table
(``floor_springs.parquet``); then ``answers_summary.json``, the figures the report quotes from the tables.
``--floor-only``: question 2 alone (and the summary). The questions are ``pasibot_pin.report.answers.questions``'s.
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
from pathlib import Path

from pasibot_pin.explore.sweep import write_figures
from pasibot_pin.report.answers.questions import (
    FLOOR_TABLE,
    QUESTION_RANGES,
    SUMMARY,
    answer_name,
    run_floor_question,
    run_question_one,
    summarize_tables,
    summary_text,
)

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "docs" / "results"


def question_one(workers: int | None) -> None:
    """Question 1, both runs: the designs, the tables, the figures of the first run."""
    import pyarrow.parquet as pq  # the [sweep] extra

    with tempfile.TemporaryDirectory() as tmp:
        for straight in (False, True):
            design, table = run_question_one(straight, Path(tmp) / str(straight), workers=workers)
            design.save(RESULTS / answer_name(straight), force=True)
            shutil.copyfile(table, RESULTS / answer_name(straight, ".parquet"))
            print(f"{answer_name(straight)}: K = {design.K:.4g}")
    table = pq.read_table(RESULTS / answer_name(False, ".parquet"))
    for path in write_figures(table, RESULTS, [r.name for r in QUESTION_RANGES]):
        print(path)


def main(argv: list[str] | None = None) -> int:
    """Run the questions (``--floor-only``: question 2) and write the summary."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--floor-only", action="store_true", help="only question 2 (the spring designs on the floor)")
    parser.add_argument("--workers", type=int, default=None, help="worker processes (default: one per core)")
    args = parser.parse_args(argv)
    RESULTS.mkdir(parents=True, exist_ok=True)
    if not args.floor_only:
        question_one(args.workers)
    with tempfile.TemporaryDirectory() as tmp:
        shutil.copyfile(run_floor_question(Path(tmp) / "floor", workers=args.workers), RESULTS / FLOOR_TABLE)
    print(RESULTS / FLOOR_TABLE)
    (RESULTS / SUMMARY).write_text(summary_text(summarize_tables(RESULTS)))
    print(RESULTS / SUMMARY)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
