"""Every committed design in designs/ gives the same walking outcome in MuJoCo, on our own export.

Both engines start from the same consistent state, turn the cranks on the same schedule and feed
the same verdict (`dynamics/verdict.py`). Walkers are compared over 3 steps here (the fewest whose
verdict can be walks; the committed table is their 20-step verdict, checked by
`test_walking_map.py`): the same outcome, steps within one, the hip's advance within 5 %, the
largest hip pitch within 2 deg. A non-walker must fail the same way in both. Where the catalog
records that the twin differs (`designs_catalog.TWIN_OUTCOMES`: the fastest walker, which slides
past the 5 mm limit in MuJoCo), the twin must give that recorded outcome, and ours still walks;
the note's quoted slide and time are the twin's, and at half the twin's time step it walks (the note says so).

Our 3-step walk of a walker is also its walking-map row's check (`map_checks.check_walker`: it walks its
first steps with a hip pitch no larger than its 20-step row's), so tests/test_walking_map.py walks it no
second time. The twin's own record is checked on each: the drives keep a walker's crank schedule (within 1 mrad,
their lag added), the start is ours, and the trace is one row per sample up to the decision.
"""

import math
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from map_checks import SHORT_STEPS, check_walker

pytest.importorskip("mujoco")

from pasibot_pin.model.design import design_robot, load_design  # noqa: E402
from pasibot_pin.report.designs_catalog import TWIN_NOTES, pick_designs, sweep_rows  # noqa: E402
from pasibot_pin.studies.twin.mujoco_walk import MJ_WALK, walk_in_mujoco  # noqa: E402
from pasibot_pin.studies.walking import WalkSettings, walk_design  # noqa: E402
from pasibot_pin.studies.walking_map import load_map  # noqa: E402

pytestmark = [pytest.mark.mujoco, pytest.mark.slow]

DESIGNS = sorted((Path(__file__).resolve().parents[1] / "designs").glob("*.toml"))
STEPS = SHORT_STEPS


def test_there_are_designs_and_a_fast_walker_among_them():
    assert len(DESIGNS) >= 3
    assert any(load_design(p).omega >= 2.0 for p in DESIGNS)


@pytest.mark.parametrize("path", DESIGNS, ids=lambda p: p.stem)
def test_mujoco_gives_the_same_outcome(path):
    design = load_design(path)
    robot = design_robot(design, 2, visuals=False)
    settings = WalkSettings(steps=STEPS)
    walk = walk_design(design, settings, robot)
    ours = walk.verdict
    walked = walk_in_mujoco(design, settings, robot)
    twin = walked.verdict
    entry = {e.name: e for e in pick_designs(load_map(), sweep_rows())}[path.stem]
    if entry.cell is None or entry.cell.walks:  # a walker's map or sweep row: it walks its first steps
        check_walker(ours, entry.cell)
    assert walked.start_kind == walk.result.start_kind  # both start from the same state
    if ours.walks:  # the drives keep the schedule (their lag added); a slip's jolt can pass 1 mrad
        assert walked.max_crank_error < 1e-3
    n = len(walked.t)
    assert walked.hip_x.shape == walked.hip_pitch.shape == (n,) and walked.loaded.shape == walked.normal.shape == (n, 2)
    assert np.all(np.diff(walked.t) > 0) and walked.t[-1] == pytest.approx(twin.decided_at)
    assert twin.outcome in repr(walked) and len(repr(walked)) < 200
    recorded = entry.twin_outcome
    if recorded:  # a disagreement the catalog states: the twin gives it, ours walks
        assert ours.walks and twin.outcome == recorded, (ours.summary(), twin.summary())
        _check_twin_note(TWIN_NOTES[entry.role], twin, design, settings, robot)
        return
    assert twin.outcome == ours.outcome, (ours.summary(), twin.summary())
    assert abs(twin.steps - ours.steps) <= 1
    if ours.walks:
        assert twin.advance_m == pytest.approx(ours.advance_m, rel=0.05)
        assert abs(math.degrees(twin.max_hip_pitch - ours.max_hip_pitch)) <= 2.0


def _check_twin_note(note: str, twin, design, settings, robot) -> None:
    """The catalog's note on a twin that slips: the slide and the time it quotes are the twin's, and at half
    the twin's time step (the step the note names) the twin walks, as ours: the slip is the limit's edge."""
    side, slid, at = re.search(r"its (left|right) foot slides ([0-9.]+) mm in one stance at ([0-9.]+) s", note).groups()
    assert f"the {side} foot slid {slid} mm in one stance" in twin.summary(), twin.summary()
    assert f"{twin.decided_at:.2f}" == at, twin.summary()
    half = MJ_WALK.timestep / 2
    assert f"half the twin's time step ({half * 1e3:g} ms)" in note
    finer = walk_in_mujoco(design, settings, robot, options=replace(MJ_WALK, timestep=half)).verdict
    assert finer.walks and finer.steps == settings.steps, finer.summary()
