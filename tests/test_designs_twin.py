"""Every committed design in designs/ gives the same walking outcome in MuJoCo, on our own export.

Both engines start from the same consistent state, turn the cranks on the same schedule and feed
the same verdict (`dynamics/verdict.py`). Walkers are compared over 3 steps here (the fewest whose
verdict can be walks; the committed table is their 20-step verdict, checked by
`test_walking_map.py`): the same outcome, steps within one, the hip's advance within 5 %, the
largest hip pitch within 2 deg. A non-walker must fail the same way in both. Where the catalog
records that the twin differs (`designs_catalog.TWIN_OUTCOMES`: the fastest walker, which slides
past the 5 mm limit in MuJoCo), the twin must give that recorded outcome, and ours still walks.
"""

import math
from pathlib import Path

import pytest

pytest.importorskip("mujoco")

from pasibot_pin.model.design import design_robot, load_design  # noqa: E402
from pasibot_pin.report.designs_catalog import pick_designs, sweep_rows  # noqa: E402
from pasibot_pin.studies.twin.mujoco_walk import walk_in_mujoco  # noqa: E402
from pasibot_pin.studies.walking import WalkSettings, walk_design  # noqa: E402
from pasibot_pin.studies.walking_map import load_map  # noqa: E402

pytestmark = [pytest.mark.mujoco, pytest.mark.slow]

DESIGNS = sorted((Path(__file__).resolve().parents[1] / "designs").glob("*.toml"))
STEPS = 3


def test_there_are_designs_and_a_fast_walker_among_them():
    assert len(DESIGNS) >= 3
    assert any(load_design(p).omega >= 2.0 for p in DESIGNS)


@pytest.mark.parametrize("path", DESIGNS, ids=lambda p: p.stem)
def test_mujoco_gives_the_same_outcome(path):
    design = load_design(path)
    robot = design_robot(design, 2, visuals=False)
    settings = WalkSettings(steps=STEPS)
    ours = walk_design(design, settings, robot).verdict
    twin = walk_in_mujoco(design, settings, robot).verdict
    recorded = {e.name: e.twin_outcome for e in pick_designs(load_map(), sweep_rows())}[path.stem]
    if recorded:  # a disagreement the catalog states: the twin gives it, ours walks
        assert ours.walks and twin.outcome == recorded, (ours.summary(), twin.summary())
        return
    assert twin.outcome == ours.outcome, (ours.summary(), twin.summary())
    assert abs(twin.steps - ours.steps) <= 1
    if ours.walks:
        assert twin.advance_m == pytest.approx(ours.advance_m, rel=0.05)
        assert abs(math.degrees(twin.max_hip_pitch - ours.max_hip_pitch)) <= 2.0
