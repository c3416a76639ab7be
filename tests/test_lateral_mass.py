"""A share of the body moved sideways by the crank (issue 32: "a lateral mass moved by the crank").

The mass is taken from the hip onto a slider along its y axis (:func:`free_flyer_model`), so the
model's mass and, with the slider centred, its centre of mass and kinetic energy are the robot's
without it. On the 3-D floor the slider follows ``amplitude sin(theta + phase)`` of the right
crank. In flight nothing outside pushes sideways, so the whole robot's centre of mass (Pinocchio's,
over every body) keeps a straight line while the mass swings and the hip swings the other way.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.engine3d import Floor3D
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import design_robot, load_design
from pasibot_pin.model.spatial import LATERAL_JOINT, Footprint, LateralMass, free_flyer_model, planar_to_spatial
from pasibot_pin.studies.walking import WalkSettings, floor_settings

FAST = Path(__file__).resolve().parents[1] / "designs" / "map_top_speed_parallel_sole6L_omega3.toml"


def _robot():
    design = load_design(FAST)
    return design, design_robot(design, 2, visuals=False)


def test_the_slider_takes_its_mass_from_the_hip():
    _, robot = _robot()
    plain, moved = free_flyer_model(robot.model), free_flyer_model(robot.model, 5.0)
    assert moved.nq == plain.nq + 1 and moved.names[-1] == LATERAL_JOINT
    total = [sum(m.inertias[j].mass for j in range(m.njoints)) for m in (plain, moved)]
    assert total[1] == pytest.approx(total[0], rel=1e-14)
    rng = np.random.default_rng(3)
    for _ in range(5):
        q = planar_to_spatial(robot.q0)
        q[7:] += rng.uniform(-0.3, 0.3, q.size - 7)
        q[3:7] = pin.Quaternion(pin.rpy.rpyToMatrix(*rng.uniform(-0.4, 0.4, 3))).coeffs()
        v = rng.normal(size=plain.nv)
        q5, v5 = np.append(q, 0.0), np.append(v, 0.0)  # the slider centred and still
        c0 = pin.centerOfMass(plain, plain.createData(), q)
        c1 = pin.centerOfMass(moved, moved.createData(), q5)
        np.testing.assert_allclose(c1, c0, atol=1e-12)
        e0 = pin.computeKineticEnergy(plain, plain.createData(), q, v)
        e1 = pin.computeKineticEnergy(moved, moved.createData(), q5, v5)
        assert e1 == pytest.approx(e0, rel=1e-12)
        # moved out by y: the centre of mass moves by mass/total y along the hip's y axis
        q5[-1] = 0.2
        c2 = pin.centerOfMass(moved, moved.createData(), q5)
        hip_y = pin.Quaternion(q[3:7]).toRotationMatrix()[:, 1]
        np.testing.assert_allclose(c2 - c0, 5.0 / total[0] * 0.2 * hip_y, atol=1e-12)


@pytest.mark.slow
def test_in_flight_the_centre_of_mass_keeps_its_line_while_the_mass_swings():
    """Dropped from 1.5 m above its start, the robot flies 0.4 s with its cranks turning and the
    mass swinging 0.15 m: the centre of mass's y stays on its line (Newton) within 0.1 mm, while the
    hip moves the other way by centimetres."""
    design, robot = _robot()
    settings = floor_settings(design, WalkSettings(), robot)
    lateral = LateralMass(10.0, 0.15, 0.3)
    engine = Floor3D(FloorSimulator(robot, settings), Footprint.centred(design.L), lateral=lateral)
    q, u, _ = engine.start()
    q[2] += 1.5
    run = engine.run(0.4, q0=q, u0=u, stop_on_verdict=False)
    assert run.lateral_y is not None and np.ptp(run.lateral_y) > 0.05
    assert np.abs(run.normal).max() == 0.0  # in flight all along
    model = engine.model
    data = model.createData()
    com = np.array([pin.centerOfMass(model, data, np.append(qk, y)) for qk, y in zip(run.q, run.lateral_y)])
    t = run.t
    line = com[0, 1] + (com[1, 1] - com[0, 1]) / (t[1] - t[0]) * t  # the start's lateral velocity
    assert np.abs(com[:, 1] - line).max() < 1e-4
    assert np.ptp(run.hip[:, 1]) > 0.01  # the hip itself swings, against the mass
    # and vertically: free fall, less the step's own error (velocity first, then position: + g h t / 2 exactly)
    h = t[1] - t[0]
    fall = com[0, 2] + (com[1, 2] - com[0, 2]) / h * t - 0.5 * 9.81 * t**2
    assert np.abs(com[:, 2] - fall - 0.5 * 9.81 * h * t).max() < 1e-4


def test_the_slider_follows_its_crank():
    design, robot = _robot()
    settings = floor_settings(design, WalkSettings(), robot)
    lateral = LateralMass(8.0, 0.1, -0.7)
    engine = Floor3D(FloorSimulator(robot, settings), Footprint.centred(design.L), lateral=lateral)
    run = engine.run(0.3)
    crank = engine.model.joints[engine.model.getJointId(robot.actuated_joints[0])].idx_q
    expected = 0.1 * np.sin(run.q[:, crank] + -0.7)
    np.testing.assert_allclose(run.lateral_y, expected, atol=1e-9)
    assert np.ptp(run.q[:, crank]) > 0.1


@pytest.mark.parametrize(
    ("changes", "name"),
    [
        ({"lateral_mass": 20.0, "lateral_amplitude": 2.0}, "lateral_mass"),  # more than the 16 kg body
        ({"lateral_mass": 5.0}, "lateral_amplitude"),
        ({"lateral_mass": -1.0, "lateral_amplitude": 2.0}, "lateral_mass"),
        ({"lateral_mass": 5.0, "lateral_amplitude": math.inf}, "lateral_amplitude"),
    ],
)
def test_bad_lateral_fields_are_one_line_naming_the_field(changes, name):
    design, _ = _robot()
    with pytest.raises(ParameterError, match=name):  # by the record itself, before any robot is built
        design.with_(**changes)


def test_walk_3d_with_a_bad_lateral_mass_is_refused_before_work(tmp_path, capsys):
    from pasibot_pin.__main__ import main

    design, _ = _robot()
    path = tmp_path / "d.toml"
    design.save(path)
    path.write_text(path.read_text().replace("omega =", "lateral_mass = 30.0\nlateral_amplitude = 2.0\nomega ="))
    assert main(["walk", "--3d", "--design", str(path), "--steps", "3"]) == 2
    err = capsys.readouterr().err
    assert "lateral_mass" in err and len(err.strip().splitlines()) == 1


def test_the_twin_refuses_a_lateral_mass_before_any_work(tmp_path, capsys):
    """The MuJoCo export has no slider: a design with a lateral mass is one line naming the field."""
    from pasibot_pin.__main__ import main
    from pasibot_pin.errors import DesignError
    from pasibot_pin.model.mjcf import check_twin

    design, _ = _robot()
    moved = design.with_(lateral_mass=5.0, lateral_amplitude=2.0)
    with pytest.raises(DesignError, match="lateral_mass"):
        check_twin(moved)
    check_twin(design)  # none: fine
    path = moved.save(tmp_path / "d.toml")
    out = tmp_path / "d.xml"
    assert main(["export-mjcf", "--3d", "--design", str(path), "--out", str(out)]) == 2
    assert "lateral_mass" in capsys.readouterr().err and not out.exists()
