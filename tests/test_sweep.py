"""Design sweeps: the table, resume after an interruption, executors bit for bit, bad input."""

from __future__ import annotations

import json

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from pasibot_pin.explore.plan import Choice, Range, SweepPlan, parse_range
from pasibot_pin.explore.store import parameter_names
from pasibot_pin.explore.sweep import best_rows, design_of_row, run_sweep
from pasibot_pin.model.design import load_design
from pasibot_pin.studies.design_metrics import METRICS, design_metrics, pareto_mask


def bits(table) -> bytes:
    """The table as Arrow IPC bytes: equal bytes are equal bits (NaN included)."""
    sink = pa.BufferOutputStream()
    with pa.ipc.new_stream(sink, table.schema) as writer:
        writer.write_table(table)
    return sink.getvalue().to_pybytes()


PLAN = SweepPlan(ranges=(Range("K", 1.7, 2.5), Range("foot_toe", 1.0, 2.5)), n=6, seed=3)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The plan run in this process, in one go."""
    folder = tmp_path_factory.mktemp("ref")
    return run_sweep(PLAN, folder, workers=1, progress=False)


@pytest.mark.slow  # the module's reference sweep: about 2 s of CPU
def test_table_has_every_parameter_and_metric(reference):
    names = reference.table.column_names
    assert names[0] == "index"
    assert names[1 : 1 + len(parameter_names())] == parameter_names()  # named as in the design record
    for metric in METRICS:
        assert metric in names
    assert reference.table.num_rows == PLAN.n
    assert json.loads((reference.folder / "plan.json").read_text())["n"] == PLAN.n
    # each row is the design's own metrics, and its parameters rebuild the design
    row = 2
    design = design_of_row(reference.table, row)
    assert design == PLAN.design(PLAN.points()[row])
    metrics = design_metrics(design).row()
    for name in METRICS:
        got = reference.table.column(name)[row].as_py()
        assert got == metrics[name] or (np.isnan(got) and np.isnan(metrics[name]))


@pytest.mark.slow  # the module's reference sweep: about 2 s of CPU
def test_interrupted_sweep_resumes_to_the_same_table(tmp_path, reference):
    calls = []

    def stop_after_two(done, total):
        calls.append(done)
        if len(calls) == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_sweep(PLAN, tmp_path, workers=1, progress=False, chunk=1, on_progress=stop_after_two)
    parts = list((tmp_path / "parts").glob("part-*.parquet"))
    kept = sum(pq.read_table(p).num_rows for p in parts)
    assert kept == 2 and not (tmp_path / "results.parquet").exists()
    assert not list(tmp_path.rglob("*.tmp"))  # no half file
    again = run_sweep(PLAN, tmp_path, workers=2, progress=False)
    assert again.evaluated == PLAN.n - 2
    assert bits(again.table) == bits(reference.table)  # bit for bit
    # complete: nothing to do, nothing rewritten
    stamp = (tmp_path / "results.parquet").stat().st_mtime_ns
    third = run_sweep(PLAN, tmp_path, workers=1, progress=False)
    assert third.evaluated == 0 and (tmp_path / "results.parquet").stat().st_mtime_ns == stamp


@pytest.mark.slow  # the module's reference sweep: about 2 s of CPU
def test_another_plan_in_the_same_folder_needs_force(tmp_path, reference):
    other = SweepPlan(ranges=PLAN.ranges, n=PLAN.n, seed=PLAN.seed + 1)
    with pytest.raises(FileExistsError, match="different run"):
        run_sweep(other, reference.folder, workers=1, progress=False)
    (tmp_path / "mine.txt").write_text("a user's file")
    with pytest.raises(FileExistsError, match="not empty"):
        run_sweep(PLAN, tmp_path, workers=1, progress=False)
    out = run_sweep(PLAN, tmp_path, workers=1, progress=False, force=True)
    assert bits(out.table) == bits(reference.table) and (tmp_path / "mine.txt").read_text() == "a user's file"


@pytest.mark.slow
def test_dask_local_cluster_gives_the_same_table_bit_for_bit(tmp_path, reference):
    pytest.importorskip("distributed")
    out = run_sweep(PLAN, tmp_path, workers=2, dask="local", progress=False)
    assert bits(out.table) == bits(reference.table)


def test_grid_and_hypercube_plans():
    grid = SweepPlan(ranges=(Range("K", 1.8, 2.2), Range("r4", 8.0, 10.0)), n=9, method="grid").points()
    assert grid.shape == (9, 2) and sorted(set(grid[:, 0])) == [1.8, 2.0, 2.2]
    lhs = SweepPlan(ranges=PLAN.ranges, n=50, seed=1).points()
    for k, r in enumerate(PLAN.ranges):  # one point in each of the n strata of every parameter
        strata = np.floor((lhs[:, k] - r.low) / (r.high - r.low) * 50).astype(int)
        assert sorted(strata) == list(range(50))
    assert np.array_equal(lhs, SweepPlan(ranges=PLAN.ranges, n=50, seed=1).points())


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("Q=1:2", "unknown"),
        ("K=2.4:1.8", "low bound"),
        ("K=nan:2", "finite"),
        ("K=0.5:2", "outside"),
        ("K1:2", "NAME=LO:HI"),
        ("variant=1:2", "categorical"),
        ("variant=parallel,hovercraft", "not among its values"),
        ("variant=parallel,parallel", "twice"),
        ("variant=", "at least one value"),
    ],
)
def test_bad_ranges_are_named(text, message):
    with pytest.raises(ValueError, match=message):
        parse_range(text)


def test_pareto_front_by_brute_force():
    rng = np.random.default_rng(0)
    x, y = rng.random(200), rng.random(200)
    x[5] = np.nan
    mask = pareto_mask(x, y, ("min", "max"))
    for i in range(200):
        beaten = np.any((x <= x[i]) & (y >= y[i]) & ((x < x[i]) | (y > y[i])))
        assert mask[i] == (np.isfinite(x[i]) and not beaten)


@pytest.mark.slow  # the module's reference sweep: about 2 s of CPU
def test_best_rows_are_sorted_and_feasible(reference):
    rows = best_rows(reference.table, "peak_crank_torque_Nm", "min", 3)
    values = [reference.table.column("peak_crank_torque_Nm")[r].as_py() for r in rows]
    assert values == sorted(values)
    assert all(reference.table.column("feasible")[r].as_py() for r in rows)


@pytest.mark.slow
def test_cli_sweep_writes_table_figures_and_best_designs(tmp_path, capsys):
    """In this process (``main``): tests/test_cli_signals.py runs ``pasibot sweep`` as its own process (its workers,
    its exit codes), tests/test_wheel_install.py from the installed console script."""
    from pasibot_pin.__main__ import main

    out = tmp_path / "run"
    args = ["sweep", "--n", "4", "--vary", "K=1.8:2.2", "--out", str(out), "--csv", "--best", "2", "--no-progress"]
    assert main(args) == 0, capsys.readouterr().err
    for name in ("results.parquet", "results.csv", "pareto.png", "sensitivity.png", "plan.json"):
        assert (out / name).is_file(), name
    best = sorted((out / "best").iterdir())
    assert [p.suffix for p in best] == [".toml", ".urdf", ".xml"] * 2
    design = load_design(best[0])
    assert 1.8 <= design.K <= 2.2
    capsys.readouterr()
    again = main(["sweep", "--n", "5", "--vary", "K=1.8:2.2", "--out", str(out), "--no-progress"])
    err = capsys.readouterr().err
    assert again == 2 and "different run" in err and err.count("\n") == 1


@pytest.mark.parametrize(
    "args",
    [
        ["--vary", "Q=1:2"],
        ["--vary", "K=2.4:1.8"],
        ["--vary", "K=nan:2"],
        ["--vary", "variant=parallel,wheel"],
        ["--n", "0"],
        ["--workers", "0"],
        ["--by", "speed"],
        ["--dask", "tcp://127.0.0.1:1"],
    ],
)
def test_cli_bad_input_is_one_line_before_any_work(tmp_path, args, capsys):
    """In this process (``main``), as the test above."""
    from pasibot_pin.__main__ import main

    out = tmp_path / "never"
    try:
        code = main(["sweep", "--out", str(out), *args])
    except SystemExit as stop:  # argparse's own refusals
        code = stop.code
    err = capsys.readouterr().err
    assert code == 2
    assert err.startswith("pasibot sweep: error:") and err.count("\n") == 1
    assert "Traceback" not in err and not out.exists()


VARIANTS = Choice("variant", ("parallel", "spring", "rigid"))


def test_a_choice_is_parsed_and_round_trips_through_the_plan_record():
    assert parse_range("variant=parallel, spring,rigid") == VARIANTS
    assert parse_range("motors=one").values == ("one",)
    plan = SweepPlan(ranges=(VARIANTS, Range("omega", 0.2, 10.0)), n=7, seed=4)
    again = SweepPlan.from_dict(json.loads(json.dumps(plan.to_dict())))
    assert again == plan and np.array_equal(again.points(), plan.points())


def test_hypercube_draws_the_variants_in_equal_shares_and_grid_takes_each():
    plan = SweepPlan(ranges=(Range("omega", 0.2, 10.0), VARIANTS, Range("parallel_toe", 0.1, 10.0)), n=30, seed=5)
    points = plan.points()
    values = [plan.values(p) for p in points]
    names = [v[1] for v in values]
    assert sorted(set(names)) == sorted(VARIANTS.values)
    assert all(names.count(v) == 10 for v in VARIANTS.values)  # one LHS stratum per value
    for k in (0, 2):  # the numeric columns keep one point per stratum
        r = plan.ranges[k]
        assert sorted(np.floor((points[:, k] - r.low) / (r.high - r.low) * 30).astype(int)) == list(range(30))
    designs = [plan.design(p) for p in points]
    assert [d.variant for d in designs] == names and all(d.omega == v[0] for d, v in zip(designs, values))
    grid = SweepPlan(ranges=(VARIANTS, Range("omega", 1.0, 3.0)), n=9, method="grid")
    cells = {(v, w) for v, w in map(grid.values, grid.points())}
    assert cells == {(v, w) for v in VARIANTS.values for w in (1.0, 2.0, 3.0)}


@pytest.mark.slow
def test_sweep_over_variants_records_each_variant_and_the_walking_outcome(tmp_path):
    """Three variants on the floor for 2 steps at 3 rad/s: each row is its own design's walk, re-simulated."""
    from pasibot_pin.model.design import Design
    from pasibot_pin.studies.walking import WalkSettings, walk_design

    plan = SweepPlan(ranges=(VARIANTS, Range("foot_toe", 1.0, 2.0)), n=3, seed=0, base=Design(omega=3.0), floor=2)
    table = run_sweep(plan, tmp_path, workers=1, progress=False).table
    assert sorted(table.column("variant").to_pylist()) == sorted(VARIANTS.values)
    for row in range(3):
        design = design_of_row(table, row)
        assert design.variant == table.column("variant")[row].as_py()
        verdict = walk_design(design, WalkSettings(steps=2)).verdict
        assert table.column("floor_outcome")[row].as_py() == verdict.outcome
        assert table.column("floor_steps")[row].as_py() == verdict.steps


def test_a_walking_sweep_runs_its_slow_walks_first():
    """A task's cost: 1 per design without a floor walk; with one, the simulated time its walk may
    need, (steps + 3) pi / omega plus the ramp, so the two workers finish together."""
    import math

    from pasibot_pin.explore.sweep import task_cost
    from pasibot_pin.studies.walking import RAMP_MAX

    assert task_cost(PLAN, [[2.0, 1.5], [2.1, 2.0]]) == 2.0
    walking = SweepPlan(ranges=(Range("omega", 0.5, 5.0), Choice("variant", ("parallel",))), n=4, seed=1, floor=20)
    slow, fast = task_cost(walking, [[0.5, "parallel"]]), task_cost(walking, [[5.0, "parallel"]])
    assert slow == pytest.approx(23 * math.pi / 0.5 + RAMP_MAX) and fast == pytest.approx(23 * math.pi / 5.0 + RAMP_MAX)
    fixed = SweepPlan(ranges=(Range("K", 1.7, 2.5),), n=2, floor=3)
    assert task_cost(fixed, [[2.0]]) == pytest.approx(6 * math.pi / fixed.base.omega + RAMP_MAX)


@pytest.mark.slow  # writes the sweep's figures: about 2 s of CPU
def test_a_walking_sweeps_pareto_figure_uses_the_floor_columns_and_walkers_only(tmp_path):
    """Issue 34: with floor columns, pareto.png plots the motor's peak on the floor against its energy per metre,
    and only walkers can be on the front: a non-walker better in both is greyed, not on it."""
    from pasibot_pin.explore.sweep import FLOOR_OBJECTIVES, PLAIN_OBJECTIVES, pareto_axes, write_figures
    from pasibot_pin.viz.plots_sweep import pareto_masks

    torque = [30.0, 20.0, 40.0, 10.0, 35.0]  # row 4 is behind row 0 in both
    energy = [50.0, 60.0, 40.0, 10.0, 55.0]  # row 3 is best in both, but does not walk
    table = pa.table(
        {
            "feasible": [True] * 5,
            "floor_walks": [1.0, 1.0, 1.0, 0.0, 1.0],
            "floor_motor_torque_peak_Nm": torque,
            "floor_energy_per_m_J": energy,
            "peak_crank_torque_Nm": [1.0, 2.0, 3.0, 4.0, 5.0],
            "stride_m": [1.0, 2.0, 3.0, 4.0, 5.0],
            "cop_margin_m": [0.0] * 5,
            "K": [1.8, 1.9, 2.0, 2.1, 2.2],
        }
    )
    axes, constraints = pareto_axes(table, None)
    assert axes == FLOOR_OBJECTIVES and len(constraints) == 1
    _, walkers, front = pareto_masks(table, *axes, constraints)
    assert walkers.tolist() == [True, True, True, False, True]
    # by hand: among the walkers, a row is on the front when no other walker is at least as low in both
    by_hand = [
        w and not any(o != i and walkers[o] and torque[o] <= torque[i] and energy[o] <= energy[i] for o in range(5))
        for i, w in enumerate(walkers)
    ]
    assert front.tolist() == by_hand == [True, True, True, False, False]
    assert pareto_axes(table.drop(["floor_walks"]), None) == (PLAIN_OBJECTIVES, ())
    assert pareto_axes(table, ("K", "stride_m")) == (("K", "stride_m"), ())
    assert [p.name for p in write_figures(table, tmp_path, ["K"])] == ["pareto.png", "sensitivity.png"]
