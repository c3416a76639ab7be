"""A slope in ``design_metrics`` and ``sweep --floor``: one range for every slope, and the energy a
walker spends per metre rises by the work of lifting it (issue 35: the ground seam reaches sweeps)."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from pasibot_pin.__main__ import main
from pasibot_pin.dynamics.floor.ground import MAX_SLOPE, Ground
from pasibot_pin.dynamics.floor.settings import FloorSettings
from pasibot_pin.errors import ParameterError
from pasibot_pin.explore.plan import Range, SweepPlan
from pasibot_pin.model.design import design_robot
from pasibot_pin.studies.walking import WalkSettings, walk_design
from pasibot_pin.studies.walking_map3d import walker_base


def test_every_slope_has_one_range():
    """The ground, the floor's settings, the sweep's plan and the CLI refuse the same angles."""
    edge = MAX_SLOPE * (1 + 1e-9)
    for build in (
        lambda a: Ground(a),
        lambda a: FloorSettings(slope=a),
        lambda a: SweepPlan(ranges=(Range("K", 2.0, 2.2),), n=2, floor=3, slope=a),
    ):
        build(0.999 * MAX_SLOPE)
        with pytest.raises(ParameterError):
            build(edge)
    with pytest.raises(ParameterError, match="--floor"):
        SweepPlan(ranges=(Range("K", 2.0, 2.2),), n=2, slope=0.1)


def test_sweep_slope_bounds_are_one_line(capsys, tmp_path):
    limit = math.degrees(MAX_SLOPE)
    code = main(["sweep", "--vary", "K=2:2.2", "--n", "2", "--floor", "3", "--slope", f"{limit + 1:g}",
                 "--out", str(tmp_path / "s")])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 2 and "--slope" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "s").exists()


STRIDE_STEPS = 4
"""Steps of each walk of the energy balance (a stride between two landings of the right foot). Measured, 4
against 6 steps: the rise per metre within 0.5 % and 2.1 % of tan(3 deg) against 0.5 % and 2.3 %, the
stride dissipating 0.7 to 1.2 J against 0.7 to 1.8 J; 4 steps cost 0.6 x the CPU."""


def _stride_energy(design, degrees: float):
    """(net motor work, kinetic and potential energy change [J], hip advance [m]) between the last two
    landings of the right foot of a :data:`STRIDE_STEPS`-step walk up ``degrees``."""
    walk = walk_design(design, WalkSettings(steps=STRIDE_STEPS, slope=math.radians(degrees)))
    assert walk.verdict.walks, walk.verdict.summary()
    robot = design_robot(design, 2, visuals=False)
    model, r = robot.model, walk.result
    data = model.createData()
    cranks = [model.joints[model.getJointId(n)].idx_v for n in robot.actuated_joints]
    mass = sum(model.inertias[j].mass for j in range(model.njoints))
    t1, t2 = [t for t, side, _ in r.landings if side == "right"][-2:]
    k1, k2 = np.searchsorted(r.t, t1), np.searchsorted(r.t, t2)
    power = (r.motor_torque[:, : len(cranks)] * r.v[:, cranks]).sum(axis=1)  # the motors' power [W]
    work = float(np.sum(power[k1 + 1 : k2 + 1]) * (r.t[1] - r.t[0]))  # each sample: its step's impulse over h
    kinetic = pin.computeKineticEnergy(model, data, r.q[k2], r.v[k2]) - pin.computeKineticEnergy(
        model, data, r.q[k1], r.v[k1]
    )
    height = pin.centerOfMass(model, data, r.q[k2])[2] - pin.centerOfMass(model, data, r.q[k1])[2]
    return work, kinetic, mass * 9.81 * height, float(r.q[k2, 0] - r.q[k1, 0]), mass


@pytest.mark.slow
def test_on_a_slope_the_motors_pay_the_lift_and_no_energy_is_made():
    """Energy balance over a stride (Pinocchio's kinetic energy and centre of mass): the motors' net
    work is the change of kinetic and potential energy plus what the landings dissipate (>= 0), flat,
    up and down 3 deg; and the centre of mass rises by tan(3 deg) per metre of advance (less the flat
    stride's own rise between the two landings)."""
    rises = {}
    for degrees in (0.0, 3.0, -3.0):
        work, kinetic, potential, advance, mass = _stride_energy(walker_base().with_(omega=1.0), degrees)
        dissipated = work - kinetic - potential
        assert dissipated >= -1e-3 * abs(work) - 1e-6, (degrees, work, kinetic, potential)
        rises[degrees] = potential / (mass * 9.81 * advance)
    for degrees in (3.0, -3.0):
        assert rises[degrees] - rises[0.0] == pytest.approx(math.tan(math.radians(degrees)), rel=0.05)


def test_every_friction_coefficient_has_one_range():
    """The ground, the floor's settings, a walk's settings, the contact studies and the CLI's --mu agree."""
    from pasibot_pin.cli.bounds import BOUNDS
    from pasibot_pin.dynamics.floor.ground import MAX_MU
    from pasibot_pin.studies.walking import WalkSettings

    for build in (lambda mu: Ground(0.0, mu), lambda mu: FloorSettings(mu=mu), lambda mu: WalkSettings(mu=mu)):
        build(MAX_MU)
        for bad in (MAX_MU * (1 + 1e-9), -1e-12, math.nan):
            with pytest.raises(ParameterError, match="mu"):
                build(bad)
    assert BOUNDS["walk"]["--mu"].high == MAX_MU


def test_the_floor_s_crank_speed_is_the_record_s():
    """FloorSettings reads omega's range from the design record (0 holds the cranks)."""
    from pasibot_pin.model.design import SPECS

    FloorSettings(omega=0.0)
    FloorSettings(omega=SPECS["omega"].high)
    with pytest.raises(ParameterError, match="omega"):
        FloorSettings(omega=SPECS["omega"].high * 1.001)
