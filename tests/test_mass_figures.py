"""One mass per robot, said as what it is: ``pasibot info`` prints the robot's mass and its hip's share.
The seed's robot (``load``) has the report's 25 % of 65 kg on the hip; a design's robot has its
``body_mass`` there instead, so the two differ by exactly that (issue 34)."""

from __future__ import annotations

import re

import pytest

from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.model.robot import load


def _printed(summary: str) -> tuple[float, float]:
    m = re.search(r"robot mass: ([\d.]+) kg \(its moving bodies; the hip ([\d.]+) kg of it\)", summary)
    assert m, summary
    return float(m.group(1)), float(m.group(2))


def test_info_says_the_robot_mass_and_the_hip_share_of_the_seed_and_of_a_design():
    seed_total, seed_hip = _printed(load("spring", 2).summary())
    assert seed_hip == pytest.approx(0.25 * 65.0)  # the report's hip: 25 % of the 65 kg human reference
    design = Design(variant="spring")
    total, hip = _printed(design_robot(design, 2, visuals=False).summary())
    assert hip == pytest.approx(design.body_mass)
    assert seed_total - total == pytest.approx(seed_hip - hip, abs=2e-3)  # the legs are the same: the hip differs
    assert total < design.total_mass  # the human reference is not the robot's mass
