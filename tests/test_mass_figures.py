"""One mass per robot, said as what it is (issue 34). ``pasibot info`` prints the robot ``walk`` builds:
the default design's, its ``body_mass`` on the hip. The seed's robots (``load``: the report's 25 % of 65 kg
on the hip; the seed scenarios' stated bodies) carry the seed's masses and say "seed scenario", so no
print shows a second "robot mass"."""

from __future__ import annotations

import re

import pytest

from pasibot_pin.__main__ import main
from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.model.robot import load

ROBOT = r"  robot mass: ([\d.]+) kg \(its moving bodies; the hip ([\d.]+) kg of it\)"
SEED = r"  seed scenario mass: ([\d.]+) kg \(.*: the hip ([\d.]+) kg of it; a design's robot has its body_mass there\)"


def _printed(pattern: str, summary: str) -> tuple[float, float]:
    m = re.search(pattern, summary)
    assert m, summary
    return float(m.group(1)), float(m.group(2))


@pytest.mark.parametrize("variant", ["spring", "rigid", "parallel"])
def test_info_prints_the_robot_walk_builds(variant, capsys):
    """``info --variant V`` is the default design's robot: its mass and hip are the design's, the same sums as
    the walk's robot (``walk`` builds ``Design().with_(variant=V)``)."""
    assert main(["info", "--variant", variant]) == 0
    total, hip = _printed(ROBOT, capsys.readouterr().out)
    design = Design().with_(variant=variant)
    robot = design_robot(design, 2, visuals=False)
    assert hip == pytest.approx(design.body_mass, abs=5e-4)
    assert total == pytest.approx(sum(i.mass for i in robot.model.inertias[1:]), abs=5e-4)
    assert total < design.total_mass  # the human reference is not the robot's mass


def test_a_design_file_s_robot_is_the_robot_info_prints(tmp_path, capsys):
    path = Design(variant="parallel", body_mass=21.5).save(tmp_path / "d.toml")
    assert main(["info", "--design", str(path)]) == 0
    total, hip = _printed(ROBOT, capsys.readouterr().out)
    assert hip == pytest.approx(21.5)
    assert main(["info", "--variant", "parallel"]) == 0
    default_total, default_hip = _printed(ROBOT, capsys.readouterr().out)
    assert total - default_total == pytest.approx(hip - default_hip, abs=2e-3)  # the legs are the same


def test_the_seed_robot_says_seed_scenario_and_differs_only_by_its_hip():
    seed_total, seed_hip = _printed(SEED, load("spring", 2).summary())
    assert "robot mass" not in load("spring", 2).summary()
    assert seed_hip == pytest.approx(0.25 * 65.0)  # the report's hip: 25 % of the 65 kg human reference
    total, hip = _printed(ROBOT, design_robot(Design(variant="spring"), 2, visuals=False).summary())
    assert seed_total - total == pytest.approx(seed_hip - hip, abs=2e-3)  # the legs are the same: the hip differs


def test_a_seed_scenario_s_robot_says_so_with_its_stated_body():
    from pasibot_pin.model.scenario_robots import scenario_robot
    from pasibot_pin.model.scenarios import PRESETS, SCENARIOS

    robot = scenario_robot(SCENARIOS["run3"], PRESETS["default"])
    total, hip = _printed(SEED, robot.summary())
    assert hip == pytest.approx(SCENARIOS["run3"].body_mass)
    assert total == pytest.approx(sum(i.mass for i in robot.model.inertias[1:]), abs=5e-4)
