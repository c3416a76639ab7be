"""Library-level input checks: parameters are refused with ``ValueError`` naming them, before any work."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pasibot_pin as pp
from pasibot_pin.model import closure


@pytest.mark.parametrize(
    ("changes", "fragment"),
    [
        ({"L": 1e300}, "parameter 'L' = 1e\\+300 m is outside"),
        ({"L": 1e200, "K": 1e200}, "parameter 'L'"),
        ({"foot_toe": 1e300}, "parameter 'foot_toe'"),
        ({"r4": 1e250}, "parameter 'r4'"),
        ({"hip_half_width": 1e300}, "parameter 'hip_half_width'"),
        ({"K": 0.5}, "cannot make a full turn with K = 0.5: loop j5"),
        ({"K": 3.2}, "loop j5 cannot assemble"),
    ],
)
def test_load_refuses_sizes_that_overflow_or_cannot_turn(changes, fragment):
    with pytest.raises(ValueError, match=fragment):
        pp.load("spring", 1, **changes)


def test_geometry_ratios_must_be_a_mapping():
    with pytest.raises(ValueError, match="parameter 'ratios'"):
        pp.Geometry().with_(ratios=1)


@pytest.mark.parametrize("variant", pp.VARIANTS)
def test_mass_model_missing_a_link_is_named(variant):
    masses = pp.percentage_mass_model(variant=variant)
    links = dict(masses.links)
    del links["l4"]
    with pytest.raises(ValueError, match="parameter 'links' of the mass model lacks l4"):
        pp.load(variant, 1, masses=masses.with_(links=links))
    with pytest.raises(ValueError, match="unknown link"):
        masses.with_(links={**masses.links, "l99": 1.0})


@pytest.mark.parametrize("K", [1.6, 2.0, 2.9])
def test_feasible_k_loads(K):
    assert pp.load("rigid", 1, K=K).q0.shape == (pp.load("rigid", 1).model.nq,)


@pytest.mark.parametrize("L", [300.0, 1e4, 1e-11])
def test_newton_tolerance_is_relative_to_L(L):
    """At L = 300 m the absolute 1e-12 m would reject valid designs; at 1e-11 m it would accept a 3 % residual."""
    from pasibot_pin.constraints import RELATIVE_TOL

    robot = pp.load("spring", 2, L=L)
    sys_ = closure.system(robot)
    assert np.any(np.isclose(sys_.tolerance, RELATIVE_TOL * L, rtol=1e-12, atol=0.0))  # length rows scale with L
    residual = np.abs(closure.constraint_residual(robot, robot.q0))
    assert residual.max() <= max(RELATIVE_TOL * L, 1e-12)
    # the same design scaled: the same angles (the closure does not depend on the unit)
    base = pp.load("spring", 2)
    revolute = closure.angular_coordinates(robot.model)
    np.testing.assert_allclose(robot.q0[revolute], base.q0[revolute], atol=1e-8)


@pytest.mark.parametrize(("ratio", "value"), [("r9", 10.0), ("r11", 19.0), ("r10", 2.3)])
def test_parallel_extension_off_parallelogram_assembles(ratio, value):
    robot = pp.load("parallel", 1, **{ratio: value})
    qs = closure.crank_sweep(robot, np.linspace(0.0, 2 * math.pi, 37))
    assert np.all(np.isfinite(qs))
    robot2 = pp.load("parallel", 2, **{ratio: value})
    assert np.abs(closure.constraint_residual(robot2, robot2.q0)).max() < 1e-9


@pytest.mark.parametrize(("ratio", "value"), [("r8", 4.5), ("r4", 9.5)])
def test_parallel_extension_that_cannot_close_names_the_loop(ratio, value):
    with pytest.raises(ValueError, match="loop j11 cannot assemble at crank angle .* distance"):
        pp.load("parallel", 1, **{ratio: value})


@pytest.mark.parametrize("variant", pp.VARIANTS)
def test_branch_switch_near_the_lower_k_is_reported(variant):
    robot = pp.load(variant, 1, K=1.5)
    with pytest.raises(ValueError, match="switched assembly branch"):
        closure.crank_sweep(robot, np.linspace(math.pi / 2, 2.5 * math.pi, 13))
    # finer steps keep the branch
    closure.crank_sweep(robot, np.linspace(math.pi / 2, 2.5 * math.pi, 145))


def test_study_settings_refuse_bad_values_before_work():
    from pasibot_pin.studies.contact_energy_study import check_flywheel_inertia, flywheel_cases
    from pasibot_pin.studies.kinematics_study import GaitSettings
    from pasibot_pin.studies.simulation_study import SimulateSettings, check_fps
    from pasibot_pin.studies.torques_study import TorqueSettings

    with pytest.raises(ValueError, match="parameter 'dt'"):
        SimulateSettings(dt=0.0)
    with pytest.raises(ValueError, match="too long"):
        SimulateSettings(scenario="run4", dt=0.1)
    assert SimulateSettings(dt=None).step == 0.01
    with pytest.raises(ValueError, match="parameter 'fps'"):
        check_fps(0.0)
    with pytest.raises(ValueError, match="parameter 'flywheel'"):
        check_flywheel_inertia(-1.0)
    with pytest.raises(ValueError, match="parameter 'flywheel'"):
        flywheel_cases([1.0], ["spring"], 0.0)
    with pytest.raises(ValueError, match="parameter 'samples'"):
        TorqueSettings(preset="seed", samples=61)
    with pytest.raises(ValueError, match="parameter 'steps'"):
        TorqueSettings(preset="seed", steps=2)
    with pytest.raises(ValueError, match="parameter 'samples'"):
        TorqueSettings(samples=1)
    assert TorqueSettings().per_step == 61
    with pytest.raises(ValueError, match="'--foot'"):
        GaitSettings(legs=1, foot="flat")
    with pytest.raises(ValueError, match="at most"):
        GaitSettings(legs=2, steps=10**9)
    with pytest.raises(ValueError, match="at most"):
        GaitSettings(step_deg=1e-9)
