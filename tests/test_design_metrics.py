"""A design's metrics, each against an independent computation; the fast tree against the xacro."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from pasibot_pin.dynamics.inverse import STANCE_RANGE, crank_grid, inverse_dynamics, run_scenario
from pasibot_pin.dynamics.verdict import OUTCOMES
from pasibot_pin.kinematics.leg import crank_grid as turn_grid
from pasibot_pin.kinematics.leg import leg_cycle
from pasibot_pin.kinematics.path_metrics import straight_line_metrics
from pasibot_pin.model import design as design_module
from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.model.robot import load
from pasibot_pin.model.scenarios import PRESETS, SCENARIOS
from pasibot_pin.studies import design_metrics as dm
from pasibot_pin.studies.contact import contact_along
from pasibot_pin.studies.methods.spring_fit import fit_result

SEED = Design()


@pytest.fixture(scope="module")
def seed_metrics():
    return dm.design_metrics(SEED)


def test_every_metric_is_reported_with_its_unit(seed_metrics):
    assert seed_metrics.feasible and seed_metrics.failure == ""
    assert list(seed_metrics.values) == list(dm.METRICS)
    assert all(math.isfinite(v) for v in seed_metrics.values.values())
    for name, spec in dm.METRICS.items():  # the column names carry their unit
        suffix = {"m": "_m", "deg": "_deg", "N.m": "_Nm", "J": "_J", "N.m/rad": "_Nm_per_rad", "-": ""}[spec.unit]
        assert name.endswith(suffix), name


@pytest.mark.parametrize("variant", ["spring", "rigid", "parallel"])
def test_path_metrics_match_the_pinocchio_leg_cycle(variant):
    """Analytic assembly (numpy) against Newton on the Pinocchio one-leg model (frames)."""
    design = SEED.with_(variant=variant)
    fast = dm.path_metrics(design)
    robot = load(variant, 1)
    cycle = leg_cycle(robot, turn_grid(math.radians(0.25)))
    assert fast["stride_m"] == pytest.approx(np.ptp(cycle.ankle[:, 0]), rel=1e-9)
    assert fast["step_height_m"] == pytest.approx(np.ptp(cycle.ankle[:, 1]), rel=1e-9)
    reference = straight_line_metrics(robot)  # refined by golden section on the manifold
    assert fast["straightness_m"] == pytest.approx(reference.deviation, rel=1e-4)
    if variant != "spring":  # the one-leg spring model holds its foot level: nothing to compare
        assert fast["foot_level_err_deg"] == pytest.approx(math.degrees(reference.stance_pitch_max), rel=1e-4)


def test_seed_stride_is_the_ankle_path_extent_in_L(seed_metrics):
    """docs/reference.md §4: the seed's ankle path spans about 9.4 L by 1.8 L (lift) over a turn."""
    L = SEED.L
    assert 9.0 < seed_metrics["stride_m"] / L < 10.0
    assert 1.7 < seed_metrics["step_height_m"] / L < 1.9
    assert seed_metrics["straightness_m"] / L < 0.05


@pytest.mark.parametrize("run", ["run1", "run4"])
def test_spring_stiffness_equals_the_torque_study(run):
    """The design path (design record -> fast tree) against the scenario path (presets -> xacro)."""
    scenario = SCENARIOS[run]
    design = SEED.with_(omega=scenario.omega, body_mass=scenario.body_mass, body_com_dx=scenario.body_com_dx)
    metrics = dm.design_metrics(design)
    study = fit_result(run_scenario(scenario, PRESETS["default"]), None, warn=False)
    assert metrics["K_e_Nm_per_rad"] == pytest.approx(study.K_e, rel=1e-9)


def test_torques_and_contact_on_the_fast_tree_equal_the_xacro_tree():
    design = SEED.with_(K=2.2, r4=9.4, foot_toe=2.0, body_com_dx=0.02, omega=3.0)
    fast, full = design_robot(design, 2, visuals=False), design_robot(design, 2)
    thetas = crank_grid(*STANCE_RANGE, 21)
    a = inverse_dynamics(fast, thetas, design.omega, stance="right", reactions=False)
    b = inverse_dynamics(full, thetas, design.omega, stance="right", reactions=False)
    assert np.allclose(a.Ta, b.Ta, rtol=1e-9, atol=1e-9)
    assert np.allclose(a.Te, b.Te, rtol=1e-9, atol=1e-9)
    metrics = dm.design_metrics(design)
    c = contact_along(full, inverse_dynamics(full, crank_grid(*STANCE_RANGE, 61), design.omega, stance="right"), 0.6)
    assert metrics["peak_crank_torque_Nm"] >= np.max(np.abs(b.Ta)) - 1e-9
    assert metrics["cop_margin_m"] == pytest.approx(np.min(c.margin), rel=1e-9)
    assert metrics["friction_needed"] == pytest.approx(np.max(c.mu_needed), rel=1e-9)


def test_energy_per_step_balances_the_mechanical_energy():
    """Virtual power: the positive minus the negative crank work is the net work = dE - ankle work."""
    from pasibot_pin.studies.energy import robot_step_energy

    design = SEED.with_(omega=2.0)
    robot = design_robot(design, 2, visuals=False)
    energy, _ = robot_step_energy(robot, design.omega)
    metrics = dm.design_metrics(design)
    assert metrics["energy_per_step_J"] == pytest.approx(energy.crank[1], rel=1e-12)
    assert energy.net_work == pytest.approx(energy.delta_energy, abs=1e-6 * abs(energy.crank[1]))


@pytest.mark.parametrize("seed", range(4))
def test_fast_tree_equals_the_rendered_xacro(seed):
    rng = np.random.default_rng(seed)
    variant = ("spring", "rigid", "parallel")[seed % 3]
    r4 = float(rng.uniform(8.8, 9.3))
    design = SEED.with_(
        r9=r4,  # the extension's parallelogram 4-6-11-9 keeps L9 = L4
        variant=variant,
        L=float(rng.uniform(0.02, 0.3)),
        K=float(rng.uniform(1.9, 2.2)),
        r4=r4,
        r13=float(rng.uniform(11.7, 12.3)),
        foot_toe=float(rng.uniform(1, 3)),
    )
    for legs in (1, 2):
        fast = design_robot(design, legs, visuals=False).model
        full = design_robot(design, legs).model
        scale = design.L
        for j in range(full.njoints):
            assert np.allclose(
                fast.jointPlacements[j].homogeneous, full.jointPlacements[j].homogeneous, atol=1e-12 * scale
            )
            assert np.allclose(
                fast.inertias[j].toDynamicParameters(), full.inertias[j].toDynamicParameters(), atol=1e-9
            )
        assert [f.name for f in fast.frames] == [f.name for f in full.frames]
        for a, b in zip(fast.frames, full.frames):
            assert np.allclose(a.placement.homogeneous, b.placement.homogeneous, atol=1e-12 * scale)
        q, v, a = (rng.uniform(-1, 1, full.nq) for _ in range(3))  # every joint is revolute or prismatic
        assert np.allclose(pin.rnea(fast, fast.createData(), q, v, a), pin.rnea(full, full.createData(), q, v, a))


def test_infeasible_designs_are_recorded_not_raised(monkeypatch):
    out = dm.design_metrics(SEED.with_(K=1.3))
    assert not out.feasible and out.failure == "assembly" and "cannot assemble" in out.reason
    assert all(math.isnan(v) for v in out.values.values())
    out = dm.design_metrics(SEED.with_(r4=5.0))  # L4 shorter than L7: the geometry rejects it
    assert out.failure == "invalid" and "r4" in out.reason
    # the seed is 23 deg from a dead point (joint 2): a stricter limit makes it singular
    assert 20 < dm.path_metrics(SEED)["transmission_deg"] < 25
    monkeypatch.setattr(dm, "SINGULAR_DEG", 30.0)
    out = dm.design_metrics(SEED)
    assert out.failure == "singular" and "dead point" in out.reason
    monkeypatch.setattr(dm, "SINGULAR_DEG", 1.0)
    out = dm.design_metrics(SEED.with_(omega=15.5, body_com_dx=-0.1466))  # fast: the ground would pull the foot
    assert out.failure == "lift-off" and "pull" in out.reason
    monkeypatch.setattr(dm, "BRANCH_TOL", -1.0)  # any knee gap at all counts: the check runs
    assert dm.design_metrics(SEED).failure == "branch"


def test_knee_stays_on_its_branch_near_the_lower_K_limit():
    """The fuzzing finding (K near 1.49): the solved knees stay on the assembly branch."""
    out = dm.design_metrics(SEED.with_(K=1.495))
    assert out.failure in ("", "singular"), out.reason


def test_design_record_round_trips_through_a_sweep_row(tmp_path):
    design = SEED.with_(K=2.1, foot_heel=0.7, spring_damping=3.0)
    path = design.save(tmp_path / "d.toml")
    assert design_module.load_design(path) == design


@pytest.mark.slow
def test_floor_metrics_are_the_walking_verdict():
    """The optional floor walk: the table's columns are the verdict of walk_design, one definition."""
    from pasibot_pin.errors import ParameterError
    from pasibot_pin.studies.walking import WalkSettings, walk_design

    design = SEED.with_(omega=5.0, body_mass=20.0)
    out = dm.design_metrics(design, floor=2)
    assert out.feasible and out.floor_outcome
    row = out.row()
    assert list(row)[len(dm.METRICS) : len(dm.METRICS) + len(dm.FLOOR_METRICS) + 2] == [
        *dm.FLOOR_METRICS,
        *dm.FLOOR_PLANAR_METRICS,
        "floor_outcome",
    ]
    verdict = walk_design(design, WalkSettings(steps=2)).verdict
    assert out.floor_outcome == verdict.outcome
    assert out["floor_walks"] == float(verdict.walks) and out["floor_steps"] == verdict.steps
    assert out["floor_time_s"] == pytest.approx(verdict.decided_at, abs=1e-12)
    for bad in (-1, 0, 1.5, True, 10**6):
        with pytest.raises(ParameterError, match="floor"):
            dm.design_metrics(design, floor=bad)


@pytest.mark.slow
def test_a_lift_off_design_is_still_walked_on_the_floor():
    """The inverse dynamics with the hip held level rejects it; the floor (no held hip) still judges it."""
    from pasibot_pin.studies.walking import WalkSettings, walk_design

    design = SEED.with_(omega=15.5, body_com_dx=-0.1466)
    out = dm.design_metrics(design, floor=2)
    assert not out.feasible and out.failure == "lift-off"
    assert all(math.isnan(out[k]) for k in dm.METRICS)
    verdict = walk_design(design, WalkSettings(steps=2)).verdict
    assert out.floor_outcome == verdict.outcome and out.floor_outcome in OUTCOMES
    assert out["floor_steps"] == verdict.steps and out.row()["floor_outcome"] == verdict.outcome
    # an assembly failure has no linkage to walk: no floor outcome
    assert dm.design_metrics(SEED.with_(K=1.3), floor=2).floor_outcome == ""
