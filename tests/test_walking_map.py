"""The walking map, its answer and the found designs: the committed table re-simulates, the docs quote the code.

The map's table (docs/results/walking_map.csv) records 20-step verdicts. A cell that fails stops at
its failure, so re-simulating it with the same 20 steps is cheap and must give the same outcome, steps
and time. A walker re-simulated for fewer steps runs the same trajectory up to its last step: it must
walk those steps, with a hip pitch no larger than the 20-step run's largest. The full 20-step check of
every committed design is ``python tools/designs_catalog.py --check`` (offline, minutes).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest
from map_checks import SHORT_STEPS, check_walker

from pasibot_pin.model.design import Design, load_design
from pasibot_pin.report.answers.walking import walking_answer, walking_markdown, walking_paragraph
from pasibot_pin.report.designs_catalog import catalog_markdown, pick_designs, sweep_rows
from pasibot_pin.studies.walking import WalkSettings, walk_design
from pasibot_pin.studies.walking_map import (
    MAP_CSV,
    MapCell,
    WalkingMap,
    load_map,
    map_design,
    save_map,
)

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def wmap() -> WalkingMap:
    return load_map()


def raw_rows() -> list[dict]:
    """The committed table read with the csv module alone (an independent reading)."""
    lines = MAP_CSV.read_text().splitlines()
    return list(csv.DictReader(line for line in lines if not line.startswith("#")))


def resimulate(cell: MapCell, steps: int):
    return walk_design(map_design(cell.variant, cell.sole, cell.omega), WalkSettings(steps=steps)).verdict


def check_cell(cell: MapCell, steps: int) -> None:
    """A failure re-simulates to its outcome, steps and time; a walker walks its first steps no worse."""
    if cell.walks:
        check_walker(resimulate(cell, SHORT_STEPS), cell)
    else:
        v = resimulate(cell, steps)
        assert (v.outcome, v.steps) == (cell.outcome, cell.steps)
        assert v.decided_at == pytest.approx(cell.decided_at_s, abs=1e-9)


def test_map_design_makes_a_symmetric_sole_on_the_variant_s_own_foot():
    p = map_design("parallel", 4.5, 2.0)
    assert (p.variant, p.parallel_toe, p.parallel_heel, p.omega) == ("parallel", 4.5, 4.5, 2.0)
    for variant in ("rigid", "spring"):
        d = map_design(variant, 6.0, 1.0)
        assert (d.variant, d.foot_toe, d.foot_heel, d.omega) == (variant, 6.0, 6.0, 1.0)
        assert d.spring_stiffness is None  # the spring variant keeps its fitted spring


def test_every_cell_s_design_has_its_sole_on_the_variant_s_own_foot(wmap):
    """Each committed cell rebuilds to a design whose sole (the geometry's extent of its variant, in metres) is the
    cell's on both sides of the ankle, the other foot's fields left at the seed's: the map's cells are the same
    designs whatever code picks the sole's fields (before issue 35 a name test, now the variant's record)."""
    seed = Design()
    for cell in wmap.cells:
        d = map_design(cell.variant, cell.sole, cell.omega)
        L = d.L
        assert d.geometry().foot_extent(cell.variant) == pytest.approx((cell.sole * L, cell.sole * L), rel=1e-15)
        changed = {k for k, v in d.values().items() if v != seed.values()[k] and v == v}
        assert changed <= {"variant", "omega", "foot_toe", "foot_heel", "parallel_toe", "parallel_heel"}
        assert len(changed & {"foot_toe", "foot_heel", "parallel_toe", "parallel_heel"}) <= 2


def test_csv_round_trip(tmp_path, wmap):
    path = save_map(wmap, tmp_path / "map.csv")
    again = load_map(path)
    assert again.steps == wmap.steps and again.twin_note == wmap.twin_note
    for a, b in zip(again.cells, wmap.cells):
        for name, x in vars(a).items():
            y = getattr(b, name)
            assert x == y or (isinstance(x, float) and math.isnan(x) and math.isnan(y)), name


def test_committed_map_covers_the_grid(wmap):
    rows = raw_rows()
    keys = {(r["variant"], float(r["sole"]), float(r["omega"])) for r in rows}
    assert len(keys) == len(rows) == len(wmap.variants) * len(wmap.soles) * len(wmap.omegas)
    assert wmap.steps == 20
    from pasibot_pin.dynamics.verdict import OUTCOMES

    assert {r["outcome"] for r in rows} <= {*OUTCOMES, "infeasible"}


def test_answer_figures_match_an_independent_count(wmap):
    """Which variants walk, the smallest sole per speed, the fastest and least-energy walkers, from the raw rows."""
    a = walking_answer(wmap)
    rows = raw_rows()
    walkers = [r for r in rows if r["outcome"] == "walks"]
    for variant, n in a.walkers.items():
        assert n == sum(r["variant"] == variant for r in walkers)
    for omega, (sole, variants) in a.smallest_sole.items():
        here = [r for r in walkers if float(r["omega"]) == omega]
        assert sole == min(float(r["sole"]) for r in here)
        assert set(variants) == {r["variant"] for r in here if float(r["sole"]) == sole}
    if walkers:
        assert a.fastest.omega == max(float(r["omega"]) for r in walkers)
        assert a.least_energy.energy_per_m_J == min(float(r["energy_per_m_J"]) for r in walkers)
    spring_fails = [r for r in rows if r["variant"] == "spring" and r["outcome"] != "walks"]
    assert sum(a.failures.get("spring", {}).values()) == len(spring_fails)


def test_docs_and_readme_quote_the_answer(wmap):
    paragraph = walking_paragraph(walking_answer(wmap))
    assert paragraph in (ROOT / "docs" / "walking.md").read_text()
    assert paragraph in (ROOT / "README.md").read_text()
    assert walking_markdown(wmap) in (ROOT / "docs" / "walking.md").read_text()


@pytest.mark.slow
def test_a_sample_of_cells_re_simulates_to_the_table(wmap):
    """Every variant's first failing cell at the fastest speed, and the fastest walker (fewer steps)."""
    fast = max(wmap.omegas)
    picked = []
    for variant in wmap.variants:
        fails = [c for c in wmap.cells if c.variant == variant and c.omega == fast and not c.walks]
        picked += fails[:1]
    a = walking_answer(wmap)
    if a.fastest is not None:
        picked.append(a.fastest)
    for cell in picked:
        check_cell(cell, wmap.steps)


DESIGNS_DIR = ROOT / "designs"


def test_designs_folder_is_the_catalog_of_the_map(wmap):
    entries = pick_designs(wmap, sweep_rows())
    assert (DESIGNS_DIR / "README.md").read_text() == catalog_markdown(entries, wmap.steps)
    assert sorted(p.stem for p in DESIGNS_DIR.glob("*.toml")) == sorted(e.name for e in entries)
    for e in entries:
        assert load_design(DESIGNS_DIR / f"{e.name}.toml") == e.design
        assert (DESIGNS_DIR / f"{e.name}.png").stat().st_size > 1000


@pytest.mark.slow
@pytest.mark.parametrize("k", range(6))
def test_each_committed_design_re_simulates_to_its_row(wmap, k):
    """Each committed design is its row's; a failing cell re-simulates to its outcome, steps and time here.

    A walker's first steps are walked by tests/test_designs_twin.py, which walks every committed design
    SHORT_STEPS in our engine anyway (for its twin) and checks the walker's row there (`check_walker`): one
    walk for both checks.
    """
    entries = pick_designs(wmap, sweep_rows())
    if k >= len(entries):
        pytest.skip(f"{len(entries)} designs committed")
    e = entries[k]
    design = load_design(DESIGNS_DIR / f"{e.name}.toml")
    if e.cell is None:  # the sweep's fastest walker (its row: the sweep's test below)
        assert design == e.design
        return
    assert design == map_design(e.cell.variant, e.cell.sole, e.cell.omega)
    if not e.cell.walks:
        check_cell(e.cell, wmap.steps)


def test_walking_map_figure_has_a_panel_per_variant_with_units(wmap):
    import matplotlib.pyplot as plt

    from pasibot_pin.viz.plots_walking import plot_walking_map, walking_map_figure

    fig = walking_map_figure(wmap)
    axes = [ax for ax in fig.axes if ax.get_title()]
    assert [ax.get_title().split(":")[0] for ax in axes] == wmap.variants
    for ax in axes:
        assert "[L]" in ax.get_xlabel() and "[rad/s]" in ax.get_ylabel()
    plt.close(fig)
    one = plot_walking_map(wmap, wmap.variants[0])
    assert one.axes[0].get_title().startswith(wmap.variants[0])
    plt.close(one)


def test_an_interrupted_map_resumes_from_its_partial_file(tmp_path, monkeypatch):
    """A one-cell map streams its cell to the partial CSV; run again, it walks nothing and gives the same cell."""
    from pasibot_pin.studies import walking_map

    partial = tmp_path / "partial.csv"
    grid = {"soles": (1.5,), "omegas": (8.0,), "variants": ("rigid",), "workers": 1, "progress": False}
    first = walking_map.compute_walking_map(**grid, partial=partial)
    assert len(partial.read_text().splitlines()) == 2  # header, one cell
    monkeypatch.setattr(walking_map, "walk_cell", lambda *a: pytest.fail("walked again"))
    again = walking_map.compute_walking_map(**grid, partial=partial)
    assert [c.outcome for c in again.cells] == [c.outcome for c in first.cells]
    assert again.cells[0].decided_at_s == first.cells[0].decided_at_s


def test_the_twin_column_re_simulates_in_mujoco(wmap):
    """Where the twin ran, its outcome is walk_in_mujoco's (the first failing cell at the fastest speed)."""
    from pasibot_pin.studies.walking_map import twin_walker

    ran = [c for c in wmap.cells if c.twin_outcome and c.twin_outcome != "walks"]
    walker = twin_walker()
    if not ran or walker is None:
        pytest.skip(wmap.twin_note or "no twin")
    cell = max(ran, key=lambda c: (c.omega, -c.sole))
    v = walker(map_design(cell.variant, cell.sole, cell.omega), WalkSettings(steps=wmap.steps)).verdict
    assert (v.outcome, float(v.steps)) == (cell.twin_outcome, cell.twin_steps)


@pytest.mark.slow
def test_sweep_paragraph_is_quoted_and_its_fastest_walker_walks():
    """The sweep's paragraph is in docs/walking.md; its fastest walker, re-simulated for fewer steps, walks."""
    from pasibot_pin.report.answers.walking import sweep_paragraph
    from pasibot_pin.report.designs_catalog import fastest_sweep_design

    rows = sweep_rows()
    assert sweep_paragraph(rows) in (ROOT / "docs" / "walking.md").read_text()
    design, row = fastest_sweep_design(rows)
    assert float(row["omega"]) == max(float(r["omega"]) for r in rows if r["floor_outcome"] == "walks")
    assert load_design(ROOT / "docs" / "results" / "fastest_sweep_walker.toml") == design
    v = walk_design(design, WalkSettings(steps=SHORT_STEPS)).verdict
    assert v.outcome == "walks" and v.steps == SHORT_STEPS
    # the design comes back from CSV text (its floats rounded in the last digits): the walk agrees to round-off
    assert math.degrees(v.max_hip_pitch) <= float(row["floor_max_hip_pitch_deg"]) + 1e-3


def test_the_cost_paragraph_is_quoted_and_counts_the_committed_runs(wmap):
    """docs/walking.md's paragraph on where the time goes is the code's, from the committed map and sweep."""
    from pasibot_pin.report.answers.walking import cost_paragraph

    rows = sweep_rows()
    text = cost_paragraph(wmap, rows)
    assert text in (ROOT / "docs" / "walking.md").read_text()
    full = [c for c in wmap.cells if c.steps >= wmap.steps]
    assert f"the {len(full)} cells that took them all" in text
    assert f"the other {len(wmap.cells) - len(full)} are decided" in text


def test_our_engine_walked_again_keeps_the_committed_twin(wmap):
    """``--compute --keep-twin``: the twin's columns and note come back cell by cell, our columns stay ours."""
    from dataclasses import replace

    from pasibot_pin.studies.walking_map import WalkingMap, with_twin_of

    ours = WalkingMap(
        [replace(c, twin_outcome="", twin_steps=math.nan, twin_detail="", cpu_s=1.0) for c in reversed(wmap.cells)],
        wmap.steps,
        "",
    )
    merged = with_twin_of(ours, wmap)
    assert merged.twin_note == wmap.twin_note
    by_key = {(c.variant, c.sole, c.omega): c for c in wmap.cells}
    assert len(merged.cells) == len(wmap.cells)
    for cell in merged.cells:
        old = by_key[(cell.variant, cell.sole, cell.omega)]
        assert (cell.twin_outcome, cell.twin_detail) == (old.twin_outcome, old.twin_detail)
        assert cell.twin_steps == old.twin_steps or (math.isnan(cell.twin_steps) and math.isnan(old.twin_steps))
        assert cell.cpu_s == 1.0  # ours, not the old map's
