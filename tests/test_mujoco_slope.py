"""A slope in the MuJoCo export (``export-mjcf --slope DEG``) and its twin walk (issue 35).

Independent reference: MuJoCo compiles the tilted plane itself (its geom frame is read back, not our
string), and walks the exported robot up and down a slope with its own contacts and solver; our planar
floor walks the same design on the same ground (its rows turned into the ground's frame). Both are
judged by the one :class:`~pasibot_pin.dynamics.verdict.GaitJudge`, along the ground.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pasibot_pin.__main__ import main
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.studies.walking import WalkSettings, walk_design

mujoco = pytest.importorskip("mujoco")

from pasibot_pin.studies.twin.mujoco_walk import walk_in_mujoco  # noqa: E402

pytestmark = [pytest.mark.mujoco]

WALKER = Design(variant="parallel", parallel_toe=4.5, parallel_heel=4.5, omega=1.0)
"""The long-soled parallel walker (4.5 L soles each side, 1 rad/s): flat, it walks 1.174 m in 3 steps in ours."""


@pytest.mark.parametrize("degrees", [5.0, -8.0])
def test_export_mjcf_tilts_the_floor_plane(tmp_path, capsys, degrees):
    out = tmp_path / "slope.xml"
    assert main(["export-mjcf", "--out", str(out), "--variant", "parallel", "--slope", f"{degrees:g}"]) == 0
    assert f"{degrees:g} deg slope" in capsys.readouterr().out
    model = mujoco.MjModel.from_xml_path(str(out))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    normal = data.geom_xmat[model.geom("floor").id].reshape(3, 3)[:, 2]  # the plane's z axis, compiled by MuJoCo
    alpha = math.radians(degrees)
    assert normal == pytest.approx([-math.sin(alpha), 0.0, math.cos(alpha)], abs=1e-12)
    assert np.allclose(model.opt.gravity, [0.0, 0.0, -9.81])  # gravity stays vertical


def test_export_mjcf_slope_is_bounded_and_planar(tmp_path, capsys):
    out = tmp_path / "slope.xml"
    assert main(["export-mjcf", "--out", str(out), "--slope", "25"]) == 2
    err = capsys.readouterr().err
    assert "--slope" in err and len(err.strip().splitlines()) == 1 and not out.exists()
    assert main(["export-mjcf", "--out", str(out), "--slope", "3", "--3d"]) == 2
    assert "--slope" in capsys.readouterr().err and not out.exists()
    with pytest.raises(ParameterError, match="step_height"):
        walk_in_mujoco(WALKER, WalkSettings(steps=3, step_height=0.01, step_at=1.0))


@pytest.mark.slow
def test_up_a_slope_mujoco_and_our_floor_agree_on_the_walk():
    """3 steps up 3 deg (about 20 s of CPU): both walk, the same steps, the advance along the ground
    within 1 % of ours and decided within 20 ms of ours (measured: 1.181 and 1.180 m, 9.813 and 9.817 s;
    the flat walk advances 1.174 m, so the slope is seen)."""
    robot = design_robot(WALKER, 2, visuals=False)
    settings = WalkSettings(steps=3, slope=math.radians(3.0))
    ours = walk_design(WALKER, settings, robot).verdict
    twin = walk_in_mujoco(WALKER, settings, robot)
    theirs = twin.verdict
    assert ours.outcome == theirs.outcome == "walks", (ours.summary(), theirs.summary())
    assert ours.steps == theirs.steps
    assert theirs.advance_m == pytest.approx(ours.advance_m, rel=0.01)
    assert abs(theirs.decided_at - ours.decided_at) < 0.02
    assert twin.options.slope == settings.slope and twin.max_crank_error < 1e-3
