"""The MuJoCo twin of a walk (studies/twin/mujoco_walk.py) against ours (studies/walking.py).

Independent reference: MuJoCo on the exported model (compliant contacts, its own solver), from
the same start, with the same crank schedule and the same verdict. Both engines judged by the
one :class:`~pasibot_pin.dynamics.verdict.GaitJudge`.
"""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest

from pasibot_pin.errors import MissingExtraError
from pasibot_pin.model.coordinates import HIP_Z
from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.studies.walking import WalkSettings, walk_design

mujoco = pytest.importorskip("mujoco")

from pasibot_pin.studies.twin.mujoco_walk import MJ_WALK, mujoco_options, walk_in_mujoco  # noqa: E402

pytestmark = [pytest.mark.mujoco, pytest.mark.slow]

STEPS = 4
"""Steps of each walk judged here [-]."""


def test_the_seeds_parallel_feet_fail_alike_in_both_engines():
    """The seed's parallel design at 1 rad/s falls in ours (|hip pitch| past 10 deg at 2.26 s):
    MuJoCo's twin falls too (at 2.21 s), with no step taken in either."""
    design = Design(variant="parallel", omega=1.0)
    robot = design_robot(design, 2, visuals=False)
    settings = WalkSettings(steps=STEPS)
    ours = walk_design(design, settings, robot).verdict
    theirs = walk_in_mujoco(design, settings, robot).verdict
    assert ours.outcome == "fell" and theirs.outcome == "fell", (ours.summary(), theirs.summary())
    assert ours.steps == theirs.steps == 0
    assert abs(theirs.decided_at - ours.decided_at) < 0.2


SPRING_ON_AXIS = Design(variant="spring", foot_toe=3.0, foot_heel=3.0, omega=1.0, spring_stiffness=3000.0)
"""A foot whose point mass lies on its ankle axis (toe = heel), with a stiff spring."""


def _spring_run(options, steps: int = 2000) -> tuple[bool, int]:
    """MuJoCo on :data:`SPRING_ON_AXIS` from our start, cranks held: (state finite, bad-qacc warnings)."""
    from pasibot_pin.dynamics.floor.engine import FloorSimulator
    from pasibot_pin.model.mjcf import to_mjcf
    from pasibot_pin.studies.walking import floor_settings

    robot = design_robot(SPRING_ON_AXIS, 2, visuals=False)
    settings = WalkSettings(steps=STEPS)
    q0 = FloorSimulator(robot, floor_settings(SPRING_ON_AXIS, settings, robot)).start_state().q
    options = mujoco_options(SPRING_ON_AXIS, settings, robot, options)
    model = mujoco.MjModel.from_xml_string(to_mjcf(robot, options, q_weld=q0))
    data = mujoco.MjData(model)
    data.qpos[:] = q0
    data.qpos[HIP_Z] += options.sole_radius
    for _ in range(steps):
        mujoco.mj_step(model, data)
    finite = bool(np.all(np.isfinite(data.qpos)) and np.all(np.isfinite(data.qvel)))
    return finite, int(data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number)


def test_a_foot_mass_on_its_ankle_axis_runs_in_mujoco(monkeypatch, tmp_path):
    """toe = heel puts the foot's point mass on the ankle axis: no inertia about it. With the
    export's old fixed bound (1e-8 kg.m^2) MuJoCo breaks at once (a bad acceleration, reset);
    with the default (:func:`~pasibot_pin.model.mjcf.stable_boundinertia`) 0.2 s run clean, and
    the twin judges the walk like ours (both: fell at the first sample, the settled start leans
    13 deg), never ``diverged``."""
    from dataclasses import replace

    monkeypatch.chdir(tmp_path)  # MuJoCo logs its warning to MUJOCO_LOG.TXT in the working directory
    assert _spring_run(replace(MJ_WALK, boundinertia=1e-8))[1] > 0
    assert _spring_run(MJ_WALK) == (True, 0)
    settings = WalkSettings(steps=STEPS)
    theirs = walk_in_mujoco(SPRING_ON_AXIS, settings).verdict
    ours = walk_design(SPRING_ON_AXIS, settings).verdict
    assert theirs.outcome != "diverged" and math.isfinite(theirs.max_hip_pitch)
    assert theirs.outcome == ours.outcome
    assert math.degrees(theirs.max_hip_pitch) == pytest.approx(math.degrees(ours.max_hip_pitch), abs=0.5)


def test_without_mujoco_the_twin_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "mujoco", None)  # import mujoco now raises ImportError
    with pytest.raises(MissingExtraError, match=r"pip install 'pasibot-pin\[mujoco\]'"):
        walk_in_mujoco(Design(variant="parallel", omega=1.0), WalkSettings(steps=STEPS))
