"""The quasi-static spring study on the floor (studies/floor_static.py), checked by independent routes.

- In single-support statics the centre of pressure is the centre of mass projected on the floor,
  and the normal forces carry the weight: the heel/toe forces (least squares on the floor's
  contact rows) against pin.centerOfMass and the summed masses.
- The floor's time-stepping simulator (a proxsuite QP per step, a massive swing foot on its
  spring), started at a found flat equilibrium with the cranks held, stays there with the same
  heel and toe forces; started where the study says the foot rolls onto its toe, it does.
- Where the floor holds the foot flat, its answer is the weld's.
- The committed tables (docs/floor_springs.md, docs/floor_quasi_static.csv) are what the code
  computes (run 1), and bad input is one line naming the parameter.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.settings import FloorSettings
from pasibot_pin.dynamics.spring_energy import foot_pose
from pasibot_pin.model.robot import total_mass
from pasibot_pin.studies.floor_static import (
    floor_static_path,
    floor_static_study,
    floor_static_sweep,
    stance_thetas,
)
from pasibot_pin.studies.spring_study import scenario_inputs

pytestmark = [pytest.mark.slow]  # its module fixture is the quasi-static study of runs 1-4

ROOT = Path(__file__).resolve().parents[1]
G = 9.81


@pytest.fixture(scope="module")
def run1_twice():
    """Run 1 with twice the fitted K_e: the weld's equilibrium is flat on the floor all along the stance."""
    inputs = scenario_inputs("run1")
    spring = inputs.fit.scaled(2.0)
    return inputs, spring, floor_static_path(inputs.robot, spring, stance_thetas(19))


def test_the_centre_of_pressure_is_the_centre_of_mass_and_the_floor_carries_the_weight(run1_twice):
    inputs, _, path = run1_twice
    robot = inputs.robot
    data = robot.model.createData()
    weight = total_mass(robot) * G
    assert path.status == ["flat"] * len(path.theta)
    for k, q in enumerate(path.configurations):
        com = pin.centerOfMass(robot.model, data, q)
        ankle_x = foot_pose(robot, q, "right")[0]
        assert path.cop[k] == pytest.approx(com[0] - ankle_x, abs=1e-7)  # [m]
        assert path.heel_force[k] + path.toe_force[k] == pytest.approx(weight, rel=1e-7)
        assert path.residual[k] < 1e-7  # an equilibrium of the floor's contact model too
        assert path.friction_use[k] < 1e-9  # single support: the floor pushes straight up
        assert -0.025 <= path.cop[k] <= 0.075  # inside the sole (heel 25 mm behind, toe 75 mm ahead)


@pytest.mark.slow
def test_where_the_floor_holds_the_foot_flat_its_answer_is_the_welds(run1_twice, study4):
    _, _, path = run1_twice
    assert path.holds and path.excursion == path.weld_excursion
    assert path.verdict() == f"{math.degrees(path.weld_excursion):.1f} deg"
    held = [c for s in study4 for row in s.cells for c in row if c.holds]
    assert held  # some cells hold
    for cell in held:
        assert cell.excursion == cell.weld_excursion
    for cell in (c for s in study4 for row in s.cells for c in row):
        if not math.isfinite(cell.weld_excursion):
            assert not math.isfinite(cell.excursion)  # the floor never holds what the weld cannot


@pytest.mark.parametrize("k", [4, 9, 14])
def test_a_floor_simulation_started_at_a_flat_equilibrium_stays_there(run1_twice, k):
    """Cranks held at the crank angle, 0.3 s of the floor simulator from the found equilibrium at rest."""
    inputs, spring, path = run1_twice
    robot = inputs.robot
    sim = FloorSimulator(robot, FloorSettings(omega=0.0, spring=spring, theta0=float(path.theta[k]), dt=1e-3))
    q = path.configurations[k]
    res = sim.run(0.3, q, np.zeros(robot.model.nv))
    assert not res.failed
    assert set(res.modes["right"]) == {"flat"} and set(res.modes["left"]) == {"air"}
    # the simulated swing foot hangs on its spring (the statics hold it at its rest angle): < 1e-3 deg
    assert np.max(np.abs(np.degrees(res.hip_pitch - q[2]))) < 1e-3
    assert np.max(np.abs(res.v[-1])) < 1e-4
    np.testing.assert_allclose(res.normal[-1][:2], [path.heel_force[k], path.toe_force[k]], atol=0.05)  # [N]


def test_where_the_study_says_the_foot_rolls_onto_its_toe_the_simulated_foot_does():
    """Run 4's fitted spring: the weld holds the hip within 17 deg, but the centre of mass is ahead of the toe."""
    inputs = scenario_inputs("run4")
    path = floor_static_path(inputs.robot, inputs.fit, stance_thetas(19))
    k = 9
    assert path.status[k] == "toe" and path.cop[k] > 0.075 and path.toe_force[k] > 0 > path.heel_force[k]
    assert math.isfinite(path.weld_excursion) and not path.holds
    sim = FloorSimulator(inputs.robot, FloorSettings(omega=0.0, spring=inputs.fit, theta0=float(path.theta[k])))
    res = sim.run(0.02, path.configurations[k], np.zeros(inputs.robot.model.nv))
    assert res.modes["right"][0] == "toe"  # the heel lifts at once
    assert "flat" not in res.modes["right"]


@pytest.mark.slow
def test_docs_floor_springs_shows_the_maps_the_code_computes(study4):
    from pasibot_pin.report.floor_static import map_table

    page = (ROOT / "docs" / "floor_springs.md").read_text(encoding="utf-8")
    for sweep in study4:
        for line in map_table(sweep):
            assert line in page


def test_bad_input_is_one_line_naming_the_parameter():
    inputs = scenario_inputs("run1")
    with pytest.raises(ValueError, match="'mu'"):
        floor_static_path(inputs.robot, inputs.fit, [math.pi], mu=-0.1)
    with pytest.raises(ValueError, match="'thetas'"):
        floor_static_path(inputs.robot, inputs.fit, [])
    with pytest.raises(ValueError, match="'sweep_stiffness'"):
        floor_static_sweep("run1", sweep_stiffness=[])
    with pytest.raises(ValueError, match="'sweep_rest'"):
        floor_static_sweep("run1", sweep_rest=[float("nan")])
    with pytest.raises(ValueError, match="'static_samples'"):
        floor_static_study(static_samples=0)
    with pytest.raises(ValueError, match="'scenarios'"):
        floor_static_study(scenarios=())


def test_simulate_study_refuses_a_negative_mu_in_one_line(tmp_path, capsys):
    from pasibot_pin.__main__ import main

    assert main(["simulate", "--study", "--mu", "-1", "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err.strip()
    assert "mu" in err and "\n" not in err and "Traceback" not in err
    assert not (tmp_path / "x").exists()


@pytest.fixture(scope="module")
def study4():
    """The quasi-static study of runs 1-4: spring cases and K_e x beta0 sweeps."""
    return floor_static_study()


@pytest.mark.slow
def test_readme_quasi_static_floor_paragraph_is_what_the_study_computes(study4):
    import re

    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    found = re.search(
        r"the cranks held at (\d+) crank angles along the stance, the swing foot in\s+the air\), a welded foot holds "
        r"the hip at every crank angle in (\d+) of the (\d+) \(K_e, β0\) cells of the\s+spring sweep of runs 1–4, "
        r"but a real sole holds that equilibrium flat in only (\d+), all in run 1 \(the\s+fitted β0, K_e from (\d+) "
        r"N\.m/rad up: largest hip pitch ([0-9.]+)–([0-9.]+)°\)\..*?Run 4's fitted spring, which the weld holds "
        r"within ([0-9.]+)°, keeps the centre of mass ahead\s+of the toe at every crank angle",
        readme,
        re.S,
    )
    assert found, "the README's quasi-static floor paragraph changed shape"
    samples, weld, total, floor, k_min, low, high, run4 = found.groups()
    cells = [(s, c) for s in study4 for row in s.cells for c in row]
    assert int(samples) == len(cells[0][1].theta)
    assert int(total) == len(cells)
    assert int(weld) == sum(math.isfinite(c.weld_excursion) for _, c in cells)
    held = [(s, c) for s, c in cells if c.holds]
    assert int(floor) == len(held) and {s.scenario for s, _ in held} == {"run1"}
    assert all(c.spring.rest_angle == s.fitted.rest_angle for s, c in held)
    assert int(k_min) == round(min(c.spring.stiffness for _, c in held))
    pitches = [math.degrees(c.excursion) for _, c in held]
    assert (float(low), float(high)) == (round(min(pitches), 1), round(max(pitches), 1))
    fitted4 = study4[3].cases["fitted"]
    assert study4[3].scenario == "run4" and float(run4) == round(math.degrees(fitted4.weld_excursion), 1)
    assert set(fitted4.status) == {"toe"}


def test_the_committed_quasi_static_csv_is_what_the_study_computes(study4):
    """docs/floor_quasi_static.csv (make floor-springs), every run and cell, against the code."""
    from pasibot_pin.report.floor_static import cell_rows

    with (ROOT / "docs" / "floor_quasi_static.csv").open() as handle:
        committed = list(csv.DictReader(handle))
    computed = cell_rows(study4)
    assert len(committed) == len(computed) == 160
    for old, new in zip(committed, computed):
        for key, value in new.items():
            if key in ("run", "floor: first failure", "floor: crank angles held flat [-]") or not value:
                assert old[key] == value, key
            else:
                assert float(old[key]) == pytest.approx(float(value), rel=1e-6, abs=1e-6), key
