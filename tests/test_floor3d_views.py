"""The 3-D floor's per-step judge view (``Floor3D._view``: Python floats for soles of one or two contact corners
per point) is the stacked view (``Floor3D._views_of``, numpy, which a repeated period's steps use) bit for bit:
heights, x along the ground, speeds and loads, on the flat floor and on a slope, with and without the gaps given."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.engine3d import Floor3D
from pasibot_pin.model.design import design_robot, load_design
from pasibot_pin.model.spatial import Footprint
from pasibot_pin.studies.walking import WalkSettings, floor_settings

FAST = "designs/map_top_speed_parallel_sole6L_omega3.toml"


@pytest.mark.parametrize("slope_deg", [0.0, 4.0])
@pytest.mark.parametrize("footprint", [Footprint.plate(0.0, 0.0), Footprint.plate(0.03, 0.05)], ids=["1", "2"])
def test_the_step_view_is_the_stacked_view(footprint, slope_deg):
    design = load_design(FAST)
    robot = design_robot(design, 2, visuals=False)
    settings = floor_settings(design, WalkSettings(slope=math.radians(slope_deg)), robot)
    floor = Floor3D(FloorSimulator(robot, settings), footprint)
    assert floor.per_point == len(footprint.contact_offsets) in (1, 2)
    q0, u0, _ = floor.start()
    rng = np.random.default_rng(11)
    for _ in range(4):
        q = pin.integrate(floor.model, q0, 0.05 * rng.standard_normal(floor.model.nv))
        points, jac, gap = floor.contact(q)
        velocity = jac @ (u0 + rng.standard_normal(floor.model.nv))
        normal = np.where(rng.random(len(points)) < 0.5, 0.0, rng.random(len(points)) * 100.0)
        normal[0] = -0.0  # a signed zero: the sums keep numpy's sign
        for given in (None, gap):
            (heights, xs, speeds), loads = floor._view(points, velocity, normal, given)
            stacked = floor._views_of(points[None], velocity[None], normal[None], given)
            for ours, theirs in zip((heights, xs, speeds, loads), stacked):
                assert [math.copysign(1.0, a) for a in ours] == [math.copysign(1.0, b) for b in theirs[0].tolist()]
                assert ours == theirs[0].tolist()
