"""The design-exploration answers: constraints hold, the tables still evaluate the same, the docs quote the code."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest

from pasibot_pin.explore.optimize import pareto_rows
from pasibot_pin.explore.sweep import design_of_row
from pasibot_pin.model.design import Design, load_design
from pasibot_pin.report import design_exploration
from pasibot_pin.report.answers.questions import (
    STRAIGHTNESS_FACTOR,
    STRIDE_TOLERANCE,
    answer_name,
    answer_path,
    seed_stride_plan,
)
from pasibot_pin.studies.design_metrics import METRICS, design_metrics

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "docs" / "results"
"""The answers' folder: the designs, the runs' Parquet tables (``make answers``, tools/answers.py, writes them)."""


def table_path(straight: bool) -> Path:
    return RESULTS / answer_name(straight, ".parquet")


@pytest.fixture(scope="module")
def rows():
    return design_exploration.answers()


@pytest.mark.parametrize("straight", [False, True])
def test_answer_keeps_the_stride_and_lowers_the_peak_torque(straight):
    seed = design_metrics(Design())
    answer = design_metrics(load_design(answer_path(straight)))
    assert abs(answer["stride_m"] / seed["stride_m"] - 1) <= STRIDE_TOLERANCE
    assert answer["peak_crank_torque_Nm"] < seed["peak_crank_torque_Nm"]
    if straight:
        assert answer["straightness_m"] <= STRAIGHTNESS_FACTOR * seed["straightness_m"]


@pytest.mark.parametrize("straight", [False, True])
def test_answer_is_the_least_torque_row_of_its_run(straight):
    table = pq.read_table(table_path(straight))
    plan = seed_stride_plan(straight)
    assert table.num_rows == plan.trials
    front = pareto_rows(table, plan)
    assert design_of_row(table, front[0]) == load_design(answer_path(straight))


@pytest.mark.parametrize("straight", [False, True])
def test_saved_runs_still_evaluate_to_the_same_numbers(straight):
    """If the model changes, these tables are stale: run ``make answers``."""
    table = pq.read_table(table_path(straight))
    feasible = np.flatnonzero(table.column("feasible").to_numpy(zero_copy_only=False))
    for row in np.random.default_rng(int(straight)).choice(feasible, 3, replace=False):
        now = design_metrics(design_of_row(table, int(row)))
        for name in METRICS:
            assert now[name] == pytest.approx(table.column(name)[int(row)].as_py(), rel=1e-9, abs=1e-12), name


def test_docs_quote_the_answer_as_the_code_computes_it(rows):
    text = (ROOT / "docs" / "design_exploration.md").read_text()
    assert design_exploration.markdown(rows) in text
    assert design_exploration.question() in text
    for name in METRICS:
        assert f"`{name}`" in text


def test_report_section_has_units_in_every_column(rows):
    table = design_exploration.markdown(rows).splitlines()[0]
    for title in table.strip("|").split("|")[1:]:
        assert "[" in title and "]" in title


@pytest.mark.slow
def test_floor_answer_is_quoted_and_still_evaluates_the_same():
    """Question 2: the docs quote the code; the best floor run re-simulates to the same verdict."""
    from pasibot_pin.report.answers.questions import FLOOR_STEPS, FLOOR_TABLE, floor_plan

    answer = design_exploration.floor_answer()
    text = (ROOT / "docs" / "design_exploration.md").read_text()
    assert design_exploration.floor_markdown(answer) in text
    table = pq.read_table(RESULTS / FLOOR_TABLE)
    assert table.num_rows == floor_plan().trials == answer.trials
    assert sum(answer.outcomes.values()) == answer.trials
    for r in floor_plan().ranges:  # the table is this plan's run: every range varied, inside its bounds
        values = table.column(r.name).to_numpy(zero_copy_only=False)
        assert r.low <= values.min() < values.max() <= r.high, r.name
    row = [r["index"] for r in table.to_pylist()].index(answer.best_index)
    now = design_metrics(design_of_row(table, row), floor=FLOOR_STEPS)
    assert now.floor_outcome == table.column("floor_outcome")[row].as_py()  # stale: run `make answers`
    assert now["floor_steps"] == answer.best_steps
    assert now["floor_time_s"] == pytest.approx(answer.best_time, abs=1e-9)


def test_readme_quotes_the_verdicts(rows):
    readme = (ROOT / "README.md").read_text()
    for line in design_exploration.markdown(rows).splitlines():
        if line.startswith("* "):
            assert line in readme


def test_summary_the_report_reads_is_the_tables_summary():
    """``analyze`` reads docs/results/answers_summary.json (no pyarrow); it must say what the Parquet tables say."""
    import json

    from pasibot_pin.report.answers.questions import SUMMARY, read_summary, summarize_tables, summary_text

    text = (RESULTS / SUMMARY).read_text()  # stale: run `make answers`
    stored = json.loads(text)
    assert stored == summarize_tables(RESULTS) == read_summary()
    assert summary_text(summarize_tables(RESULTS)) == text  # what tools/answers.py writes, byte for byte
    floor = pq.read_table(RESULTS / "floor_springs.parquet")
    assert stored["floor"]["trials"] == floor.num_rows
    rows = [r for r in floor.to_pylist() if r["feasible"]]
    most = max(r["floor_steps"] for r in rows)  # the best: the most steps, then the longest run
    assert stored["floor"]["best_steps"] == most
    assert stored["floor"]["best_time"] == max(r["floor_time_s"] for r in rows if r["floor_steps"] == most)
    assert stored["designs_explored"] == sum(pq.read_table(table_path(s)).num_rows for s in (False, True))
