"""Every walker in designs/3d/ stays upright in 3-D on our floor and in the MuJoCo twin on `export-mjcf --3d`:
the same outcome, steps within one, advance within 5 %, largest roll within 2 deg (issue 32). Its README's
table is the tool's (tools/designs3d.py), and quotes no design that is not there."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pasibot_pin.model.design import design_robot, load_design
from pasibot_pin.studies.walking import WalkSettings, walk_design_3d

FOLDER = Path(__file__).resolve().parents[1] / "designs" / "3d"
WALKERS = sorted(p.stem for p in FOLDER.glob("*.toml"))
STEPS = 3
"""Steps walked here in each engine: the fewest whose verdict can be ``walks`` (a whole stride judged), as in
test_designs_twin.py; each foot lands and takes the weight in turn, so the roll that would tip a walker is
judged at every foot exchange. tools/designs3d.py walked each 20 in both engines for its README (checked above).
Measured: the smallest reach (0.5 rad/s) walks 3 steps in both, 1.173 and 1.174 m; 6 steps cost 2 x the CPU."""


def _rows() -> dict:
    text = (FOLDER / "README.md").read_text(encoding="utf-8")
    return json.loads(text.split("<!-- rows: ")[1].split(" -->")[0])


def test_the_readme_lists_exactly_the_committed_walkers_and_each_walked_both_engines():
    rows = _rows()
    assert sorted(rows) == WALKERS and len(WALKERS) >= 1
    for name, row in rows.items():
        assert row["outcome"] == row["twin_outcome"] == "walks", name
        assert row["steps"] == 20 and abs(row["steps"] - row["twin_steps"]) <= 1
        assert abs(row["advance_m"] - row["twin_advance_m"]) <= 0.05 * row["advance_m"]
        assert abs(row["max_hip_roll_deg"] - row["twin_max_hip_roll_deg"]) <= 2.0
        assert row["min_sole_clearance_mm"] > 0 and row["leg_clearance_mm"] > 0
        assert (FOLDER / f"{name}.png").is_file()


@pytest.mark.slow
@pytest.mark.mujoco
@pytest.mark.parametrize("name", WALKERS)
def test_each_3d_walker_in_both_engines(name):
    pytest.importorskip("mujoco")
    from pasibot_pin.studies.twin.mujoco_walk import walk_in_mujoco

    design = load_design(FOLDER / f"{name}.toml")
    robot = design_robot(design, 2, visuals=False)  # built once for both engines (each would build its own)
    ours = walk_design_3d(design, WalkSettings(steps=STEPS), robot)
    twin = walk_in_mujoco(design, WalkSettings(steps=STEPS), robot, spatial=True)
    assert ours.verdict.outcome == twin.verdict.outcome == "walks", (ours.verdict.summary(), twin.verdict.summary())
    assert abs(ours.verdict.steps - twin.verdict.steps) <= 1
    assert twin.verdict.advance_m == pytest.approx(ours.verdict.advance_m, rel=0.05)
    assert abs(ours.result.max_hip_roll_deg - twin.max_hip_roll_deg) <= 2.0


def test_the_recommended_walker_is_the_committed_fastest_upright_walker():
    """The Answers box's walker to build (studies/walking_map3d.RECOMMENDED) is the file tools/designs3d.py chose."""
    from pasibot_pin.studies.walking_map3d import RECOMMENDED, recommended_walker

    feet, value, omega = RECOMMENDED
    path = FOLDER / f"upright_fastest_{feet}{value:g}L_omega{omega:g}.toml"
    assert path.is_file() and load_design(path) == recommended_walker()
    assert [p.stem for p in FOLDER.glob("upright_fastest_*.toml")] == [path.stem]
