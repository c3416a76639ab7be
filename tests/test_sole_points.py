"""The floor's contact points are the foot's (``Footprint.points``), written once (issue 35).

A newcomer who adds a contact point to the sole names its frame in the footprint's points; the
planar floor's general and tracked steps, its contact modes, its log and its judge take it from there.
Checked by adding a third point, at mid-sole, to each foot of a walker: it lies on the line from heel
to toe, so on a flat floor it never touches first and any force there is a share of forces at the
two ends (the same wrench, the same friction cone). The walk must be the two-point walk.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.run import MODES
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.model.spatial import SOLE_POINTS, Footprint
from pasibot_pin.studies.walking import WalkSettings, floor_settings, walk_duration

FAST = Design(variant="parallel", parallel_toe=6.0, parallel_heel=6.0, omega=3.0)


def _with_ball(robot):
    """``robot`` with a frame ``<side>_ball`` midway between each foot's heel and toe (changed in place)."""
    model = robot.model
    for side in ("right", "left"):
        heel, toe = (model.frames[model.getFrameId(f"{side}_{p}")] for p in ("heel", "toe"))
        assert heel.parentJoint == toe.parentJoint
        mid = pin.SE3(heel.placement.rotation, 0.5 * (heel.placement.translation + toe.placement.translation))
        frame = pin.Frame(f"{side}_ball", heel.parentJoint, heel.parentFrame, mid, pin.FrameType.OP_FRAME)
        model.addFrame(frame, False)
    robot.data = model.createData()
    return robot


@pytest.mark.slow
def test_a_third_sole_point_written_once_walks_as_heel_and_toe():
    settings = WalkSettings(steps=3)
    robot = design_robot(FAST, 2, visuals=False)
    floor = floor_settings(FAST, settings, robot)
    duration = walk_duration(FAST.omega, settings.steps)
    two = FloorSimulator(robot, floor).run(duration, criteria=settings.judged_by(), stop_on_verdict=True)
    ball = _with_ball(design_robot(FAST, 2, visuals=False))
    footprint = Footprint(Footprint.centred(ball.geometry.L).bands, ("heel", "ball", "toe"))
    sim = FloorSimulator(ball, floor, footprint)
    three = sim.run(duration, criteria=settings.judged_by(), stop_on_verdict=True)
    assert sim._shape_split() is not None  # the tracked step ran with the third point
    assert three.points == ("heel", "ball", "toe") and three.normal.shape[1] == 6
    assert len(three.t) == len(two.t) and np.abs(three.q - two.q).max() < 1e-9
    assert three.verdict.outcome == two.verdict.outcome == "walks"
    assert three.verdict.steps == two.verdict.steps and three.touchdowns[0][:2] == two.touchdowns[0][:2]
    # the modes agree but where heel and ball load and the toe does not: two points make the sole flat
    differ = [(a, b) for side in two.modes for a, b in zip(two.modes[side], three.modes[side]) if a != b]
    assert len(differ) <= 1e-3 * len(two.t) and all(b == "flat" for _, b in differ)
    total2, total3 = two.normal.sum(axis=1), three.normal.sum(axis=1)
    assert np.abs(total3 - total2).max() < 1e-2 * total2.max()  # the same weight carried, shared otherwise
    assert {point for _, _, point in three.touchdowns} <= {"heel", "ball", "toe"}


def test_the_default_foot_is_heel_and_toe_and_a_footprint_needs_two_distinct_points():
    assert Footprint.centred(0.05).points == SOLE_POINTS == ("heel", "toe")
    assert set(SOLE_POINTS) <= set(MODES)
    for bad in (("heel",), ("toe", "toe")):
        with pytest.raises(ParameterError, match="points"):
            Footprint(((0.03, 0.03),), bad)
