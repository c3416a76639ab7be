"""The MuJoCo twin's first judged sample is the start pose, not MuJoCo's unset kinematics.

Before its first step MuJoCo has not computed the sites' positions: a judge fed them saw every foot
at x = 0, flat, and could not tell a start that already breaks a limit. On the walking map's rigid
1.5 L cell the pose both engines start from puts a foot on its toe, pitched past the foot-roll limit:
both must say ``infeasible_start``, with the same pitch, decided at once.
"""

from __future__ import annotations

import re

import pytest

pytest.importorskip("mujoco")

pytestmark = pytest.mark.mujoco


def test_the_twin_judges_the_start_pose_it_is_given():
    from pasibot_pin.studies.walking_map import twin_cell, walk_cell

    ours = walk_cell("rigid", 1.5, 2.0, twin=False)
    _, outcome, steps, detail = twin_cell("rigid", 1.5, 2.0)
    assert ours.outcome == outcome == "infeasible_start" and steps == 0
    pitch = [float(m) for m in re.findall(r"pitched (-?[0-9.]+) deg", ours.detail + " " + detail)]
    assert len(pitch) == 2 and abs(pitch[0] - pitch[1]) < 0.1  # the same foot, the same pose
