"""Checks of the walking map's rows shared by tests/test_walking_map.py and tests/test_designs_twin.py."""

from __future__ import annotations

import math

from pasibot_pin.studies.walking_map import MapCell

SHORT_STEPS = 3
"""Steps of a walker's re-simulation: the fewest whose verdict can be ``walks`` (the advance band is judged over
3) [-]."""


def check_walker(v, cell: MapCell | None) -> None:
    """The verdict ``v`` of a walker's first :data:`SHORT_STEPS`: it walks them, with a hip pitch no larger than
    its 20-step row's (``cell``; ``None``: the sweep's walker, whose row tests/test_walking_map.py's sweep test
    checks). A walker re-simulated for fewer steps runs the same trajectory up to its last step."""
    assert v.outcome == "walks" and v.steps == SHORT_STEPS, v.summary()
    if cell is not None:
        assert math.degrees(v.max_hip_pitch) <= cell.max_hip_pitch_deg + 1e-9
