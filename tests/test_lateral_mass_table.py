"""The committed answer to "does a mass the crank moves sideways keep the walker upright?"
(docs/results/lateral_mass.md, ``make lateral-mass``): its count, and one cell walked again."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from pasibot_pin.studies.walking import WalkSettings, walk_design_3d
from pasibot_pin.studies.walking_map3d import walker_base

TABLE = Path(__file__).resolve().parents[1] / "docs" / "results" / "lateral_mass.md"
ROW = re.compile(r"^\| ([\d.]+) \| ([\d.]+) \| ([+-][\d.]+) \| ([\d.]+) \| (\w+) \| (\d+) \| ([\d.]+) \| ([\d.]+) \|$")


def _rows() -> list[tuple]:
    return [m.groups() for line in TABLE.read_text().splitlines() if (m := ROW.match(line))]


def test_the_table_counts_its_walkers():
    rows = _rows()
    walkers = sum(r[4] == "walks" for r in rows)
    assert len(rows) == 48
    assert f"{walkers} of {len(rows)} walk" in TABLE.read_text()
    doc = (TABLE.parents[1] / "floor3d.md").read_text()
    assert f"{walkers} of {len(rows)} walk 6 steps upright" in doc  # the docs quote the table
    best = min(rows, key=lambda r: float(r[6]))  # and its most upright cell
    assert f"stays within {best[6]} deg of roll" in doc and f"`{best[4]}`" in doc


@pytest.mark.slow
def test_the_table_s_most_upright_cell_walks_again_as_written():
    """The cell that rolls least (it hops rather than tips), walked again: the same outcome and steps."""
    rows = _rows()
    best = min(rows, key=lambda r: float(r[6]))
    mass, amplitude, printed, omega = (float(x) for x in best[:4])
    phase = round(printed / (math.pi / 4)) * (math.pi / 4)  # the grid's phase, printed to 4 decimals
    design = walker_base().with_(omega=omega, lateral_mass=mass, lateral_amplitude=amplitude, lateral_phase=phase)
    walk = walk_design_3d(design, WalkSettings(steps=6))
    assert (walk.verdict.outcome, walk.verdict.steps) == (best[4], int(best[5]))
    assert walk.result.max_hip_roll_deg == pytest.approx(float(best[6]), abs=0.01)
    assert walk.result.t[-1] == pytest.approx(float(best[7]), abs=0.01)
    assert math.isclose(phase, math.pi / 2, abs_tol=1e-3)  # a quarter turn ahead of the right crank
