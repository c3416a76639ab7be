"""The 3-D walking map: its comb feet never meet (closed form against coal's boxes), its cells are the
3-D walk's, its table round-trips, and the committed map's smallest reach is what its rows say."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from pasibot_pin.dynamics.verdict import OUTCOMES
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import design_robot
from pasibot_pin.model.spatial import planar_to_spatial
from pasibot_pin.studies.walking_map3d import (
    COMB_CLEARANCE,
    Map3DCell,
    WalkingMap3D,
    comb_fields,
    load_map3d,
    map3d_design,
    save_map3d,
    walker_base,
)

ROOT = Path(__file__).resolve().parents[1]
MAP = ROOT / "docs" / "results" / "walking_map3d.csv"


@pytest.mark.parametrize("reach", [0.2, 0.6, 1.2])
def test_comb_soles_interleave_with_the_stated_clearance(reach):
    """Closed form: the prongs sit COMB_CLEARANCE apart across the midline, the other foot's prong
    COMB_CLEARANCE beside the plate; coal's distance between the two feet's boxes is the least of these."""
    from pasibot_pin.dynamics.floor.engine import FloorSimulator
    from pasibot_pin.dynamics.floor.engine3d import Floor3D
    from pasibot_pin.studies.walking import WalkSettings, floor_settings

    design = map3d_design("comb", reach, 3.0)
    half = design.hip_half_width
    f = comb_fields(reach)
    assert f["sole_inner"] - half == pytest.approx(reach)  # the prong's reach past the midline
    left_prong = (half - f["sole_inner"], half - f["sole_gap_to"])  # y of the left prong [L]
    right_prong = (f["sole_gap_to"] - half, f["sole_inner"] - half)
    right_plate_edge = -half + f["sole_gap_from"]
    assert right_prong[0] - left_prong[1] == pytest.approx(COMB_CLEARANCE)
    assert left_prong[0] - right_plate_edge >= COMB_CLEARANCE - 1e-12
    robot = design_robot(design, 2, visuals=False)
    engine = Floor3D(FloorSimulator(robot, floor_settings(design, WalkSettings(steps=2), robot)), design.footprint())
    q = planar_to_spatial(engine.planar.initial_state()[0])
    assert engine.sole_clearance(q) == pytest.approx(COMB_CLEARANCE * design.L, abs=1e-9)


def test_a_comb_that_leaves_no_plate_is_refused_by_name():
    with pytest.raises(ParameterError, match="reach"):
        comb_fields(0.05)
    with pytest.raises(ParameterError, match="reach"):
        comb_fields(3.9)
    with pytest.raises(ParameterError, match="feet"):
        map3d_design("stilts", 1.0, 1.0)


def test_the_map_walker_is_the_committed_fastest_walker_but_for_its_feet():
    from pasibot_pin.model.design import load_design

    fast = load_design(ROOT / "designs" / "map_top_speed_parallel_sole6L_omega3.toml")
    assert walker_base().with_(omega=3.0) == fast
    narrow = map3d_design("narrow", 1.0, 3.0)
    assert narrow.hip_half_width == 1.0 and narrow.sole_inner == fast.sole_inner


def test_the_table_round_trips_and_the_smallest_reach_reads_both_engines(tmp_path):
    nan = math.nan
    cells = [
        Map3DCell("comb", 0.2, 1.0, "tipped", "roll", 1.0, 0, 0.1, 12.0, 0.01, 1.0, "tipped", 0, 0.1, 14.0, 1.0),
        Map3DCell("comb", 0.4, 1.0, "walks", "", 9.0, 6, 2.3, 0.5, 0.01, 1.0, "slipped", 2, 0.8, 5.0, 1.0),
        Map3DCell("comb", 0.6, 1.0, "walks", "", 9.0, 6, 2.3, 0.1, 0.01, 1.0, "walks", 6, 2.3, 0.2, 1.0),
        Map3DCell("comb", 0.2, 3.0, "tipped", "roll", 1.0, 0, 0.1, 12.0, 0.01, 1.0),
        Map3DCell("narrow", 1.0, 3.0, "refused", "meet", nan, 0, nan, nan, nan, 0.0),
    ]
    wmap = WalkingMap3D(cells, 6)
    back = load_map3d(save_map3d(wmap, tmp_path / "m.csv"))
    assert back.steps == 6 and len(back.cells) == 5
    for a, b in zip(cells, back.cells):
        for x, y in zip(a.__dict__.values(), b.__dict__.values()):
            assert x == y or (isinstance(x, float) and math.isnan(x) and math.isnan(y))
    reach = back.smallest_reach()
    assert reach[1.0] == 0.6 and math.isnan(reach[3.0])


@pytest.mark.skipif(not MAP.is_file(), reason="the 3-D map is not committed yet")
def test_the_committed_map_has_every_cell_and_no_comb_past_the_limit():
    wmap = load_map3d(MAP)
    keys = {(c.feet, c.value, c.omega) for c in wmap.cells}
    assert len(keys) == len(wmap.cells)
    for c in wmap.cells:
        assert c.outcome in OUTCOMES  # the judge's own list
        if c.walks:
            assert c.steps == wmap.steps and c.max_hip_roll_deg < 10.0
            assert c.min_sole_clearance_m > 0.0
    # the planar walker's own plates (the narrow family's widest spacing) tip at every speed
    assert all(
        c.outcome == "tipped" for c in wmap.family("narrow") if c.value == max(x.value for x in wmap.family("narrow"))
    )


@pytest.mark.slow
def test_a_cell_is_its_design_walked_in_3d():
    """walk_cell_3d's figures are walk_design_3d's of map3d_design (no twin)."""
    from pasibot_pin.studies.walking import WalkSettings, walk_design_3d
    from pasibot_pin.studies.walking_map3d import walk_cell_3d

    cell = walk_cell_3d("comb", 0.8, 3.0, steps=3, twin=False)
    walk = walk_design_3d(map3d_design("comb", 0.8, 3.0), WalkSettings(steps=3))
    assert cell.outcome == walk.verdict.outcome == "walks"
    # proxsuite's warm start carries over between runs in one process: equal to round-off, not bit for bit
    assert cell.advance_m == pytest.approx(walk.verdict.advance_m, abs=1e-9)
    assert cell.max_hip_roll_deg == pytest.approx(walk.result.max_hip_roll_deg, abs=1e-6)
    assert cell.twin_outcome == "" and np.isnan(cell.twin_steps)


def test_the_docs_quote_the_committed_3d_map():
    """docs/floor3d.md's figures are the committed map's (one source for every number)."""
    wmap = load_map3d(MAP)
    text = (ROOT / "docs" / "floor3d.md").read_text(encoding="utf-8")
    comb, narrow = wmap.family("comb"), wmap.family("narrow")
    assert f"{sum(c.walks for c in comb)} of the {len(comb)} cells walk upright" in text
    assert f"{sum(c.walks for c in narrow)} of {len(narrow)} cells walk" in text
    reach = wmap.smallest_reach()
    assert {w: reach[w] for w in (0.5, 1.0, 2.0)} == dict.fromkeys((0.5, 1.0, 2.0), 0.2)
    assert reach[3.0] == 1.2 and "at 3 rad/s is 1.2 L" in text
    assert "from 0.2 L (1 cm) past the midline, in both engines" in text
    ours_at_3 = min(c.value for c in comb if c.omega == 3.0 and c.walks)
    assert f"At 3 rad/s our floor walks from {ours_at_3:g} L" in text
    assert max(c.max_hip_roll_deg for c in comb if c.walks) < 0.01 and "below 0.01 deg" in text
    twin_misses = sorted((c.value, c.omega) for c in comb if c.omega < 3.0 and c.twin_outcome != "walks")
    assert twin_misses == [(0.4, 2.0)] and "at 0.4 L and 2 rad/s" in text
