"""Design optimisation (Optuna NSGA-II): constraints, Pareto front, resume, executors."""

from __future__ import annotations

import pytest

from pasibot_pin.explore.optimize import (
    Objective,
    OptimizePlan,
    pareto_rows,
    parse_constraint,
    parse_objective,
    run_optimize,
)
from pasibot_pin.explore.plan import Range
from tests.test_sweep import bits

pytest.importorskip("optuna")

PLAN = OptimizePlan(
    ranges=(Range("K", 1.8, 2.4), Range("foot_toe", 1.0, 3.0)),
    objectives=(Objective("peak_crank_torque_Nm", "min"), Objective("cop_margin_m", "max")),
    constraints=(parse_constraint("stride_m>=0.45"),),
    trials=12,
    population=6,
    seed=1,
)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    return run_optimize(PLAN, tmp_path_factory.mktemp("opt"), workers=1, progress=False)


@pytest.mark.slow
def test_every_trial_is_a_row_and_the_front_respects_the_constraint(reference):
    import optuna

    assert reference.table.num_rows == PLAN.trials and reference.evaluated == PLAN.trials
    rows = reference.table.to_pylist()
    assert reference.pareto
    for i in reference.pareto:
        assert rows[i]["stride_m"] >= 0.45
    # no feasible, constraint-satisfying row beats a front row in both objectives
    ok = [r for r in rows if r["feasible"] and r["stride_m"] >= 0.45]
    for i in reference.pareto:
        p = rows[i]
        assert not any(
            r["peak_crank_torque_Nm"] <= p["peak_crank_torque_Nm"]
            and r["cop_margin_m"] >= p["cop_margin_m"]
            and (r["peak_crank_torque_Nm"] < p["peak_crank_torque_Nm"] or r["cop_margin_m"] > p["cop_margin_m"])
            for r in ok
        )
    from pasibot_pin.explore.optimize import _storage

    study = optuna.load_study(study_name="pasibot", storage=_storage(reference.folder))
    finished = [t for t in study.trials if t.state.is_finished()]
    assert len(finished) == PLAN.trials
    for t in finished:  # the study saw the same numbers as the table
        if t.values is not None:
            assert t.values[0] == rows[t.number]["peak_crank_torque_Nm"]
            assert t.user_attrs["violations"][0] == pytest.approx(0.45 - rows[t.number]["stride_m"])


@pytest.mark.slow
def test_interrupted_optimisation_keeps_its_trials_and_continues(tmp_path, reference):
    def stop(done, total):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_optimize(PLAN, tmp_path, workers=1, progress=False, on_generation=stop)
    again = run_optimize(PLAN, tmp_path, workers=1, progress=False)
    assert again.evaluated == PLAN.trials - PLAN.population and again.table.num_rows == PLAN.trials
    first = list(range(PLAN.population))  # the first generation is the uninterrupted run's
    assert bits(again.table.take(first)) == bits(reference.table.take(first))


@pytest.mark.slow
def test_a_process_pool_gives_the_same_trials_bit_for_bit(tmp_path, reference):
    out = run_optimize(PLAN, tmp_path, workers=2, progress=False)
    assert bits(out.table) == bits(reference.table)


@pytest.mark.slow
def test_more_trials_continue_a_finished_run(tmp_path):
    small = OptimizePlan(**{**PLAN.__dict__, "trials": 6})
    run_optimize(small, tmp_path, workers=1, progress=False)
    more = run_optimize(OptimizePlan(**{**PLAN.__dict__, "trials": 9}), tmp_path, workers=1, progress=False)
    assert more.evaluated == 3 and more.table.num_rows == 9


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("stride>0", "METRIC>=BOUND"),
        ("speed>=1", "unknown metric"),
        ("stride_m>=x", "number"),
        ("stride_m>=inf", "finite"),
    ],
)
def test_bad_constraints_are_named(text, message):
    with pytest.raises(ValueError, match=message):
        parse_constraint(text)


def test_objectives_take_the_metric_usual_sense():
    assert parse_objective("cop_margin_m").sense == "max"
    assert parse_objective("peak_crank_torque_Nm").sense == "min"
    with pytest.raises(ValueError, match="unknown metric"):
        parse_objective("speed")
    with pytest.raises(ValueError, match="min or max"):
        parse_objective("stride_m:up")


def test_pareto_rows_of_a_table(reference):
    assert pareto_rows(reference.table, PLAN) == reference.pareto


def test_the_pareto_figure_draws_only_constraint_satisfying_designs_on_its_front():
    """A design that violates ``--constraint`` is greyed and never on the drawn front, even where it would
    dominate; the drawn front is the optimiser's own (``pareto_rows``) on the same objectives."""
    import matplotlib.pyplot as plt
    import numpy as np
    import pyarrow as pa

    from pasibot_pin.viz.plots_sweep import pareto_masks, plot_pareto

    torque = [1.0, 2.0, 3.0, 4.0, 2.5, 0.5]
    margin = [0.9, 0.5, 0.8, 0.1, 0.2, 0.95]  # rows 0 and 5 would be best, but violate the constraint
    stride = [0.40, 0.46, 0.47, 0.50, 0.46, 0.30]
    feasible = [True, True, True, True, True, False]
    table = pa.table({"peak_crank_torque_Nm": torque, "cop_margin_m": margin, "stride_m": stride, "feasible": feasible})
    plan = OptimizePlan(
        ranges=PLAN.ranges, objectives=PLAN.objectives, constraints=PLAN.constraints, trials=1, population=2, seed=1
    )
    ok, good, front = pareto_masks(table, "peak_crank_torque_Nm", "cop_margin_m", plan.constraints)
    assert ok.tolist() == feasible and good.tolist() == [False, True, True, True, True, False]
    assert np.flatnonzero(front).tolist() == sorted(pareto_rows(table, plan)) == [1, 2]
    fig = plot_pareto(table, "peak_crank_torque_Nm", "cop_margin_m", constraints=plan.constraints)
    try:
        ax = fig.axes[0]
        line = next(ln for ln in ax.lines if ln.get_label() == "Pareto front")
        assert sorted(line.get_xdata().tolist()) == [2.0, 3.0]
        labels = ax.get_legend_handles_labels()[1]
        assert labels[0] == "violate stride_m>=0.45 (1)"  # row 0; row 5 is not even feasible
        assert labels[1] == "feasible designs within the constraints (4 of 6)"
        grey = ax.collections[0].get_offsets()
        assert grey.tolist() == [[1.0, 0.9]]
    finally:
        plt.close(fig)


def test_a_trial_stopped_while_its_parameters_were_drawn_does_not_block_the_resume(tmp_path):
    """Ctrl-C between two suggestions leaves a running trial with some parameters missing in the journal:
    the run resumes (the trial is failed, a new one takes its place) instead of a KeyError (issue 34)."""
    import optuna

    from pasibot_pin.explore.optimize import STUDY_NAME, _storage

    small = OptimizePlan(**{**PLAN.__dict__, "trials": 3})
    run_optimize(OptimizePlan(**{**PLAN.__dict__, "trials": 2}), tmp_path, workers=1, progress=False)
    study = optuna.load_study(study_name=STUDY_NAME, storage=_storage(tmp_path))
    half = study.ask()
    first = small.ranges[0]
    half.suggest_float(first.name, first.low, first.high)  # the second parameter never drawn
    resumed = run_optimize(small, tmp_path, workers=1, progress=False)
    assert resumed.table.num_rows == 3
    states = [t.state for t in optuna.load_study(study_name=STUDY_NAME, storage=_storage(tmp_path)).trials]
    assert optuna.trial.TrialState.FAIL in states
