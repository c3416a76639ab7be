"""Model sizes, mobility by two counts, and the mass rules."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from importlib.metadata import distribution

import numpy as np
import pinocchio as pin
import pytest
from conftest import ALL_MODELS

import pasibot_pin as pp
from pasibot_pin.model.closure import crank_sweep, mobility
from pasibot_pin.model.params import human_description_fractions, percentage_mass_model


def _size(robots, variant, legs):
    model = robots[(variant, legs)].model
    return model.nq, model.nv


# One line per model pins nq and nv (docs/reference.md §2).
def test_size_rigid_1leg(robots):
    assert _size(robots, "rigid", 1) == (7, 7)  # noqa: E704


def test_size_rigid_2leg(robots):
    assert _size(robots, "rigid", 2) == (17, 17)  # noqa: E704


def test_size_parallel_1leg(robots):
    assert _size(robots, "parallel", 1) == (13, 13)  # noqa: E704


def test_size_parallel_2leg(robots):
    assert _size(robots, "parallel", 2) == (29, 29)  # noqa: E704


def test_size_spring_1leg(robots):
    assert _size(robots, "spring", 1) == (8, 8)  # noqa: E704


def test_size_spring_2leg(robots):
    assert _size(robots, "spring", 2) == (19, 19)  # noqa: E704


def expected_mobility(variant: str, legs: int) -> int:
    """docs/reference.md §4: 1 per leg linkage, +1 per spring ankle, +3 floating hip, -3 stance weld."""
    per_leg = 1 + (1 if variant == "spring" else 0)
    return legs * per_leg + (3 - 3 if legs == 2 else 0)


@pytest.mark.parametrize("variant, legs", ALL_MODELS)
def test_mobility_by_grubler_and_by_rank(robots, variant, legs):
    robot = robots[(variant, legs)]
    for q in crank_sweep(robot, np.radians([10.0, 100.0, 200.0, 300.0])):
        mob = mobility(robot, q)
        assert mob.grubler == expected_mobility(variant, legs)
        assert mob.numerical == expected_mobility(variant, legs)
        assert mob.leg_linkage == 1


def test_grubler_matches_the_seed_for_the_plain_leg(robots):
    """Seed §3.4: m = 8 bodies with the frame, C1 = 10 pairs -> DOF 1."""
    mob = mobility(robots[("rigid", 1)])
    assert (mob.moving_bodies + 1, mob.pairs) == (8, 10)
    assert 3 * (8 - 1) - 2 * 10 == mob.grubler


def test_parallel_extension_counts(robots):
    """The real model counts the slider, L10 and the foot bar as bodies (14 with the frame, 19
    pairs); the seed counts m = 12, C1 = 16. Both give one degree of freedom."""
    mob = mobility(robots[("parallel", 1)])
    assert (mob.moving_bodies + 1, mob.pairs) == (14, 19)
    assert 3 * (14 - 1) - 2 * 19 == 1 == 3 * (12 - 1) - 2 * 16


def test_mass_rule_reproduces_seed_table_7_1_2():
    masses = percentage_mass_model()
    table = {"l1": 0.3, "l2": 1.4, "l3": 0.7, "l4": 2.5, "l5": 2.4, "l6": 1.7, "l7": 0.8}
    for link, kg in table.items():
        assert round(masses.links[link], 1) == pytest.approx(kg), link
    assert round(masses.foot, 1) == pytest.approx(1.3)
    assert round(masses.hip) == 16
    # thigh 10 % of 65 kg shared by length over L1, L2, L3, L4, L6 (lengths 1, 5, 2.5, 9, 6 L)
    assert masses.links["l4"] == pytest.approx(6.5 * 9 / 23.5, rel=1e-15)
    # the modelled masses sum to about 38 kg, not the 65 kg the seed claims
    legs = sum(masses.links[k] for k in ("l1", "l2", "l3", "l4", "l5", "l6", "l7")) + masses.foot
    assert masses.hip + 2 * legs == pytest.approx(38.35)


def test_loaded_biped_total_mass(robots):
    robot = robots[("spring", 2)]
    total = sum(robot.model.inertias[j].mass for j in range(1, robot.model.njoints))
    assert total == pytest.approx(38.35, rel=1e-12)


def test_human_rule_reads_example_robot_data():
    files = [f for f in distribution("example-robot-data").files if str(f).endswith("human.urdf")]
    root = ET.parse(files[0].locate()).getroot()
    mass = {
        link.get("name"): float(link.find("inertial/mass").get("value"))
        for link in root.findall("link")
        if link.find("inertial/mass") is not None
    }
    total = sum(mass.values())
    fractions = human_description_fractions()
    assert fractions["hip"] == pytest.approx(mass["middle_pelvis"] / total)
    assert fractions["thigh"] == pytest.approx(0.123, abs=5e-4)
    assert fractions["shank"] == pytest.approx(0.048, abs=5e-4)
    assert fractions["foot"] == pytest.approx(0.012, abs=5e-4)
    human = pp.load("spring", 2, mass_rule="human")
    assert human.masses.hip == pytest.approx(65 * mass["middle_pelvis"] / total)


def test_uniform_inertia_option_adds_rotational_inertia():
    point = pp.load("rigid", 1)
    rods = pp.load("rigid", 1, inertia="uniform")
    crank = point.model.getJointId("right_j0_crank")
    L = point.geometry.L
    m1 = point.masses.links["l1"]
    # about its joint: point mass at L/2 -> m L^2/4; uniform rod -> m L^2/3
    i_point = point.model.inertias[crank]
    assert i_point.inertia[1, 1] + i_point.mass * (L / 2) ** 2 == pytest.approx(m1 * L**2 / 4)
    i_rod = rods.model.inertias[crank]
    assert i_rod.inertia[1, 1] + i_rod.mass * (L / 2) ** 2 == pytest.approx(m1 * L**2 / 3)


def test_load_works_from_any_directory(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    robot = pp.load("parallel", 1)
    assert robot.model.nq == 13
    assert pp.URDF_PATH.is_file() and pp.XACRO_PATH.is_file()
    assert all(isinstance(d, str) for d in pp.PACKAGE_DIRS)


def test_custom_geometry_renders_and_closes():
    robot = pp.load("rigid", 1, L=0.1, r13=12.5)
    pin.framesForwardKinematics(robot.model, robot.data, robot.q0)
    assert robot.data.oMf[robot.frame_id("right_j8_l6")].translation[2] == pytest.approx(-1.25)
