"""The 3-D floor: the free-flyer model against the planar one, its world-aligned dynamics against
Pinocchio's ABA, the planar walk reproduced with the lateral freedoms held, and a walker that tips.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.engine3d import Floor3D
from pasibot_pin.dynamics.floor.ground import Ground
from pasibot_pin.dynamics.verdict import FAILURES, TIP_LIMIT
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import Design, design_robot, load_design
from pasibot_pin.model.spatial import Footprint, free_flyer_model, planar_to_spatial, roll_pitch_yaw
from pasibot_pin.studies.walking import WalkSettings, floor_settings, walk_design_3d

FAST = "designs/map_top_speed_parallel_sole6L_omega3.toml"


@pytest.fixture(scope="module")
def walker():
    """The fast planar walker's robot and floor settings, built once for this module's tests."""
    design = load_design(FAST)
    robot = design_robot(design, 2, visuals=False)
    return robot, floor_settings(design, WalkSettings(), robot)


def _random_planar(robot, rng):
    q = robot.q0.copy()
    q[:3] = rng.uniform(-0.5, 0.5, 3)
    q[3:] += rng.uniform(-0.3, 0.3, q.size - 3)
    return q, rng.normal(size=robot.model.nv)


def test_free_flyer_model_is_the_planar_tree(walker):
    """Same frames everywhere, same mass, same kinetic energy for the same motion."""
    robot, _ = walker
    model = free_flyer_model(robot.model)
    assert model.nq == robot.model.nq + 4 and model.nv == robot.model.nv + 3
    rng = np.random.default_rng(3)
    d2, d3 = robot.model.createData(), model.createData()
    for _ in range(5):
        q, v = _random_planar(robot, rng)
        q3 = planar_to_spatial(q)
        pin.framesForwardKinematics(robot.model, d2, q)
        pin.framesForwardKinematics(model, d3, q3)
        worst = max(np.abs(d2.oMf[k].homogeneous - d3.oMf[k].homogeneous).max() for k in range(len(model.frames)))
        assert worst < 1e-12
        # the free flyer's velocity is local: linear R^T (x', 0, z'), angular (0, -pitch', 0)
        rotation = d3.oMi[1].rotation
        v3 = np.concatenate((rotation.T @ [v[0], 0.0, v[1]], [0.0, -v[2], 0.0], v[3:]))
        e2 = pin.computeKineticEnergy(robot.model, d2, q, v)
        e3 = pin.computeKineticEnergy(model, d3, q3, v3)
        assert e3 == pytest.approx(e2, rel=1e-12)
        assert roll_pitch_yaw(q3)[1] == pytest.approx(q[2], abs=1e-14)


def test_world_aligned_dynamics_match_aba(walker):
    """The engine's M and b in world axes give the free body's acceleration that ABA gives in local axes."""
    robot, settings = walker
    engine = Floor3D(FloorSimulator(robot, settings), Footprint.plate(0.03, 0.03))
    model = engine.model
    rng = np.random.default_rng(5)
    for _ in range(4):
        q = pin.randomConfiguration(model, -np.ones(model.nq), np.ones(model.nq))
        q[7:] = robot.q0[3:] + rng.uniform(-0.2, 0.2, model.nq - 7)
        u = rng.normal(size=model.nv)
        tau = rng.normal(size=model.nv)
        mass, bias, turned = engine._mass_and_bias(q, u)
        rotation = pin.Quaternion(q[3:7]).normalized().toRotationMatrix()  # the free flyer's, from its quaternion
        np.testing.assert_allclose(turned, rotation, atol=1e-15)
        transform = np.eye(model.nv)  # v = T u: Pinocchio's local root velocity from the world-aligned one
        transform[:3, :3] = transform[3:6, 3:6] = rotation.T
        du = np.linalg.solve(mass, transform.T @ tau - bias)
        v = transform @ u
        a = pin.aba(model, model.createData(), q, v, tau)  # local axes
        linear = rotation @ (a[:3] + np.cross(v[3:6], v[:3]))  # p'' in world axes
        angular = rotation @ a[3:6]
        np.testing.assert_allclose(du[:3], linear, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(du[3:6], angular, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(du[6:], a[6:], rtol=1e-9, atol=1e-9)


def held_and_planar(robot, settings, duration: float):
    """The 3-D walk held upright on soles of no width, and the planar general step's walk: (3-D, planar).

    Asserts that they are the same walk: the times, the hip's x, z and pitch within 1e-7, the verdict and steps.
    """
    planar = FloorSimulator(robot, settings)
    planar._shape_split = lambda: None  # the general step on every coordinate, as the held 3-D step
    flat = planar.run(duration)
    engine = Floor3D(FloorSimulator(robot, settings), Footprint.plate(0.0, 0.0), hold_lateral=True)
    spatial = engine.run(duration, stop_on_verdict=False)
    n = len(flat.t)
    np.testing.assert_allclose(spatial.t[1 : n + 1], flat.t, atol=1e-12)
    assert np.abs(spatial.q[1 : n + 1, 0] - flat.q[:, 0]).max() < 1e-7
    assert np.abs(spatial.q[1 : n + 1, 2] - flat.q[:, 1]).max() < 1e-7
    assert np.abs(spatial.pitch[1 : n + 1] - flat.q[:, 2]).max() < 1e-7
    assert (spatial.verdict.outcome, spatial.verdict.steps) == (flat.verdict.outcome, flat.verdict.steps)
    return spatial, flat


@pytest.mark.slow
def test_held_3d_walk_is_the_planar_walk(walker):
    """With y, roll and yaw held and soles of no width, 5 s of the 3-D walk are the planar walk's.

    Against the planar floor's general step (the same scheme): the hip's x, z and pitch within
    1e-7 m / 1e-7 rad; the planar run's default (tracked) step differs from its own general step by
    a third-order term, about 4e-6 over these 5 s.
    """
    robot, settings = walker
    spatial, flat = held_and_planar(robot, settings, 5.0)
    n = len(flat.t)
    assert np.abs(spatial.q[:, 1]).max() < 1e-12 and spatial.max_hip_roll_deg < 1e-9
    assert spatial.verdict.steps >= 3
    tracked = FloorSimulator(robot, settings).run(5.0)
    assert tracked.verdict.outcome == spatial.verdict.outcome
    assert np.abs(spatial.q[1 : n + 1, 0] - tracked.q[:, 0]).max() < 1e-4


@pytest.mark.slow
def test_centred_soles_tip_and_soles_past_the_midline_stay_upright(walker):
    """The fast walker on 0.06 m soles centred on its leg planes falls sideways in its first single
    support; a comb whose inner prong reaches 3 cm past the midline (beside the other foot's, never
    over it) keeps the hip within a degree of upright (the issue's independent MuJoCo model found
    the same of plates: roll past 10 deg at 0.52 s, and <= 0.5 deg 3 cm past the midline)."""
    robot, settings = walker
    centred = Floor3D(FloorSimulator(robot, settings), Footprint.plate(0.03, 0.03)).run(1.5)
    assert centred.verdict.outcome == "tipped"
    assert centred.max_hip_roll_deg > math.degrees(TIP_LIMIT)
    assert centred.verdict.decided_at < 1.2
    half_width = robot.geometry.hip_half_width
    comb = Footprint(((0.03, 0.03), (half_width + 0.03, -(half_width + 0.01))))
    wide = Floor3D(FloorSimulator(robot, settings), comb).run(1.5)
    assert wide.verdict.outcome not in FAILURES
    assert wide.max_hip_roll_deg < 1.0


def test_tipped_outcome_past_the_limit(walker):
    """A hip started rolled past the limit is ``tipped`` at the first step."""
    robot, settings = walker
    engine = Floor3D(FloorSimulator(robot, settings), Footprint.plate(0.03, 0.03))
    q, u, _ = engine.start()
    rotation = pin.utils.rpyToMatrix(TIP_LIMIT * 1.5, 0.0, 0.0) @ pin.Quaternion(q[3:7]).toRotationMatrix()
    q[3:7] = pin.Quaternion(rotation).coeffs()
    q[2] += 0.3  # clear of the floor
    result = engine.run(0.01, q0=q, u0=u)
    assert result.verdict.outcome == "tipped"
    assert result.max_hip_roll_deg > math.degrees(TIP_LIMIT)


def test_ground_frame_and_errors():
    """A slope's frame is orthonormal, its normal tilts back by the angle; bad values are refused by name."""
    for degrees in (0.0, 5.0, -12.0):
        ground = Ground.slope(degrees)
        frame = ground.frame()
        np.testing.assert_allclose(frame @ frame.T, np.eye(3), atol=1e-15)
        assert math.degrees(math.atan2(-ground.normal[0], ground.normal[2])) == pytest.approx(degrees)
        uphill = ground.tangents[0] * 2.0
        assert ground.gap(uphill[None])[0] == pytest.approx(0.0, abs=1e-15)
    assert Ground.flat().gap(np.array([[0.3, -0.2, 0.05]]))[0] == 0.05
    with pytest.raises(ParameterError, match="slope"):
        Ground.slope(45.0)
    with pytest.raises(ParameterError, match="mu"):
        Ground(0.0, -1.0)
    with pytest.raises(ParameterError, match="sole_inner"):
        Footprint.plate(-0.05, 0.01)
    with pytest.raises(ParameterError, match="sole_inner"):
        Footprint.plate(float("nan"), 0.01)


def test_design_lateral_fields():
    """sole_inner, sole_outer and hip_half_width are design fields in L; their defaults are the seed's robot."""
    from pasibot_pin.model.design import Design
    from pasibot_pin.model.params import Geometry

    design = Design()
    assert design.geometry().hip_half_width == Geometry().hip_half_width == 0.1
    assert design.footprint() == Footprint.plate(0.6 * design.L, 0.6 * design.L)
    wide = design.with_(sole_inner=2.6, hip_half_width=1.5, L=0.04)
    assert wide.footprint().bands == ((2.6 * 0.04, 0.6 * 0.04),)
    assert wide.geometry().hip_half_width == pytest.approx(0.06)
    for name, value in (("sole_inner", -0.1), ("sole_outer", 11.0), ("hip_half_width", 0.0)):
        with pytest.raises(ParameterError, match=name):
            design.with_(**{name: value})


def test_sole_clearance_at_the_start(walker):
    """At the start (both feet flat, side by side) the plates' clearance is the gap between their bands across
    the midline (closed form); a plate past the midline intersects the other's; a comb whose inner prong
    passes the midline beside the other foot's does not."""
    robot, settings = walker
    w = robot.geometry.hip_half_width
    for inner, expected in ((0.03, 2 * (w - 0.03)), (w - 0.01, 0.02)):
        engine = Floor3D(FloorSimulator(robot, settings), Footprint.plate(inner, 0.03))
        q, _, _ = engine.start()
        assert engine.sole_clearance(q) == pytest.approx(expected, abs=1e-9)
    crossing = Floor3D(FloorSimulator(robot, settings), Footprint.plate(w + 0.03, 0.03))
    q, _, _ = crossing.start()
    assert crossing.sole_clearance(q) < 0.0
    comb = Floor3D(FloorSimulator(robot, settings), Footprint(((0.03, 0.03), (w + 0.03, -(w + 0.01)))))
    q, _, _ = comb.start()
    assert comb.sole_clearance(q) == pytest.approx(0.02, abs=1e-9)  # the prongs at +10..30 mm and -30..-10 mm


@pytest.mark.slow
def test_walk_3d_command(capsys):
    """``walk --3d`` prints the verdict and the roll; --json has the sideways figures; overlapping soles: one line."""
    import json

    from pasibot_pin.__main__ import main

    assert main(["walk", "--design", FAST, "--3d", "--steps", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["model"] == "3d" and out["outcome"] == "tipped"
    assert out["max_hip_roll_deg"] > math.degrees(TIP_LIMIT)
    assert out["roll_margin_deg"] == pytest.approx(math.degrees(TIP_LIMIT) - out["max_hip_roll_deg"])
    for key in ("yaw_per_step_deg", "lateral_drift_m"):
        assert math.isfinite(out[key])
    assert out["settled_at_s"] is None  # a walk that tips never repeats itself (strict JSON: no NaN)
    steps_per_turn = 2.0 * math.pi / out["omega_rad_s"] / out["dt_s"]  # the run's own step divides the crank turn
    assert steps_per_turn == pytest.approx(round(steps_per_turn), abs=1e-9)
    with pytest.raises(ParameterError, match="sole_inner"):
        from pasibot_pin.model.design import load_design
        from pasibot_pin.studies.walking import walk_design_3d

        walk_design_3d(load_design(FAST).with_(sole_inner=2.6))


def test_a_slip_as_the_body_tips_is_tipped():
    """A planar rule's failure followed within TIP_GRACE by a roll past the limit is ``tipped``, naming both;
    later, or after a walk, the first outcome stands."""
    from pasibot_pin.dynamics.verdict import TIP_GRACE, FootSample, GaitCriteria, GaitJudge, GaitSample

    foot = FootSample(True, 0.0, 0.0, 100.0, 0.0, False)
    start = GaitSample(0.0, 0.0, 0.0, (foot, foot), (0.0, 0.0))

    def judge_after(outcome: str) -> GaitJudge:
        judge = GaitJudge(3.0, 0.05, 500.0, GaitCriteria(), start)
        judge.outcome, judge.decided_at, judge.detail = outcome, 1.0, "the left foot slid"
        return judge

    judge = judge_after("slipped")
    assert not judge.final(1.0 + TIP_GRACE / 2)
    judge.roll(1.0 + TIP_GRACE / 2, -1.2 * TIP_LIMIT)
    assert judge.outcome == "tipped" and "slipped" in judge.detail and judge.final(1.0 + TIP_GRACE / 2)
    late = judge_after("slipped")
    late.roll(1.0 + 1.5 * TIP_GRACE, 1.2 * TIP_LIMIT)
    assert late.outcome == "slipped" and late.final(1.0 + 1.5 * TIP_GRACE)
    walked = judge_after("walks")
    walked.roll(1.1, 1.2 * TIP_LIMIT)
    assert walked.outcome == "walks"
    assert walked.max_roll == pytest.approx(1.2 * TIP_LIMIT)


def test_comb_design_fields():
    """sole_gap_from/to cut the sole into a plate and an inner prong; a gap outside the sole is refused by name."""
    from pasibot_pin.model.design import Design

    design = Design(L=0.05, sole_inner=2.6, sole_gap_from=0.6, sole_gap_to=2.2)
    np.testing.assert_allclose(design.footprint().bands, ((0.03, 0.03), (0.13, -0.11)), atol=1e-15)
    with pytest.raises(ParameterError, match="sole_gap_from"):
        Design(sole_inner=2.0, sole_gap_from=1.0, sole_gap_to=2.5)
    with pytest.raises(ParameterError, match="sole_gap_from"):
        Design(sole_gap_from=0.5, sole_gap_to=0.2)


def test_3d_export_is_the_3d_model(walker):
    """The 3-D MJCF: a free joint, the same sites as our frames at the start, the soles' boxes over the
    footprint's bands, and the loops closed by the home keyframe."""
    import mujoco  # the [mujoco] extra: make test installs it, and this test never skips

    from pasibot_pin.model.mjcf import MjcfOptions, spatial_qpos, to_mjcf

    robot, _ = walker
    half_width = robot.geometry.hip_half_width
    comb = Footprint(((0.03, 0.03), (half_width + 0.03, -(half_width + 0.01))))
    model = mujoco.MjModel.from_xml_string(to_mjcf(robot, MjcfOptions(footprint=comb)))
    data = mujoco.MjData(model)
    assert model.nq == robot.model.nq + 4 and model.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE
    mujoco.mj_resetDataKeyframe(model, data, 0)
    np.testing.assert_allclose(data.qpos, spatial_qpos(robot.q0), atol=1e-15)
    mujoco.mj_forward(model, data)
    engine_model = free_flyer_model(robot.model)
    engine_data = engine_model.createData()
    pin.framesForwardKinematics(engine_model, engine_data, planar_to_spatial(robot.q0))
    for name in ("right_heel", "right_toe", "left_heel", "left_toe"):
        np.testing.assert_allclose(
            data.site(name).xpos, engine_data.oMf[engine_model.getFrameId(name)].translation, atol=1e-12
        )
    for loop in robot.loops:
        np.testing.assert_allclose(data.site(loop.frame_a).xpos, data.site(loop.frame_b).xpos, atol=1e-9)
    for side, plane in (("right", -half_width), ("left", half_width)):
        toward = -np.sign(plane)
        for k, (inner, outer) in enumerate(comb.bands):
            geom = model.geom(f"{side}_sole{k}").id
            centre, half = data.geom_xpos[geom][1], model.geom_size[geom][1]
            low, high = sorted((plane - toward * outer, plane + toward * inner))
            assert centre - half == pytest.approx(low, abs=1e-12) and centre + half == pytest.approx(high, abs=1e-12)


DESIGNS = Path(__file__).resolve().parents[1] / "designs"


def _planar_outcomes() -> dict[str, str]:
    """Each committed design's planar outcome, as designs/README.md's table states it."""
    return {
        line.split("](")[0][3:]: line.split("|")[5].strip()
        for line in (DESIGNS / "README.md").read_text(encoding="utf-8").splitlines()
        if line.startswith("| [")
    }


@pytest.mark.slow
@pytest.mark.mujoco
@pytest.mark.parametrize("name", sorted(_planar_outcomes()))
def test_every_design_in_3d_and_its_twin(name):
    """Each design in designs/ on its default soles (0.6 L each side of its leg's plane): our 3-D outcome
    equals MuJoCo's on ``export-mjcf --3d``, decided within 0.25 s of it; every planar walker is tipped
    (the README's 3-D answer)."""
    from pasibot_pin.model.design import load_design
    from pasibot_pin.studies.twin.mujoco_walk import walk_in_mujoco
    from pasibot_pin.studies.walking import walk_design_3d

    design = load_design(DESIGNS / f"{name}.toml")
    robot = design_robot(design, 2, visuals=False)  # built once for both engines (each would build its own)
    ours = walk_design_3d(design, WalkSettings(steps=20), robot)
    twin = walk_in_mujoco(design, WalkSettings(steps=20), robot, spatial=True)
    assert ours.verdict.outcome == twin.verdict.outcome, (ours.verdict.summary(), twin.verdict.summary())
    assert abs(ours.verdict.decided_at - twin.verdict.decided_at) < 0.25
    if _planar_outcomes()[name] == "walks":
        assert ours.verdict.outcome == "tipped"


@pytest.mark.slow
def test_walk_3d_page(tmp_path, capsys):
    """``walk --3d --html`` writes one page whose title names the outcome and the roll, atomically; a step edge
    with --3d is refused in one line."""
    from pasibot_pin.__main__ import main

    assert main(["walk", "--design", FAST, "--3d", "--steps", "2", "--html", "--out", str(tmp_path)]) == 0
    page = (tmp_path / "walk_map_top_speed_parallel_sole6L_omega3.html").read_text(encoding="utf-8")
    assert "<title>parallel in 3-D, 3 rad/s: tipped" in page and "max roll 10.0 deg" in page
    assert len(page) > 100_000  # the scene and its frames, base64 in the page
    assert not list(tmp_path.glob(".*.part-*"))  # no temporary file left (the .pasibot marker says whose folder)
    capsys.readouterr()
    assert main(["walk", "--design", FAST, "--3d", "--step-height", "0.01", "--step-at", "0.3"]) == 2
    err = capsys.readouterr().err
    assert "--step-height" in err and "--3d" in err and len(err.strip().splitlines()) == 1


def test_export_mjcf_3d_command(tmp_path, capsys):
    """``export-mjcf --3d`` writes a MuJoCo model with a free joint and the design's soles; --legs 1 is one line."""
    import mujoco  # the [mujoco] extra: make test installs it, and this test never skips

    from pasibot_pin.__main__ import main

    out = tmp_path / "walker.xml"
    assert main(["export-mjcf", "--design", FAST, "--3d", "--out", str(out)]) == 0
    model = mujoco.MjModel.from_xml_path(str(out))
    assert model.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE
    assert {model.geom(k).name for k in range(model.ngeom)} >= {"right_sole0", "left_sole0"}
    capsys.readouterr()
    assert main(["export-mjcf", "--3d", "--legs", "1", "--out", str(tmp_path / "one.xml")]) == 2
    err = capsys.readouterr().err
    assert "--3d" in err and len(err.strip().splitlines()) == 1 and not (tmp_path / "one.xml").exists()


def test_leg_clearance_is_the_slabs_gap_and_reads_the_bar_radius_of_the_xacro():
    """The legs' lateral slabs (their bars' depth, from the xacro) and a sole's inner reach: closed form."""
    import re

    from pasibot_pin.model.spatial import BAR_RADIUS, LEG_HALF_DEPTH, Footprint, leg_clearance

    xacro = (Path(__file__).resolve().parents[1] / "urdf" / "pasibot.urdf.xacro").read_text()
    assert float(re.search(r'name="bar_radius" value="\$\{([0-9.]+) \* L\}"', xacro).group(1)) == BAR_RADIUS
    L, half = 0.05, 0.1
    depth = LEG_HALF_DEPTH * L
    assert leg_clearance(Footprint.plate(0.03, 0.03), half, L) == pytest.approx(2 * half - depth - 0.03)  # sole to leg
    assert leg_clearance(Footprint.plate(0.0, 0.03), half, L) == pytest.approx(2 * half - 2 * depth)  # leg to leg
    # a prong 6 cm past the midline: 4 cm from the other plane, less the other leg's half depth
    assert leg_clearance(Footprint(((-0.01, 0.03), (0.16, -0.11))), half, L) == pytest.approx(0.04 - depth)
    assert leg_clearance(Footprint.plate(0.03, 0.03), 0.005, L) < 0


def test_legs_that_meet_are_refused_before_any_work():
    # a prong 1.9 L past the midline clears the other foot's plate but not the other leg's links
    design = Design(variant="parallel", parallel_toe=6.0, parallel_heel=6.0, omega=3.0,
                    sole_inner=3.9, sole_gap_from=0.0, sole_gap_to=2.1)  # fmt: skip
    with pytest.raises(ParameterError, match="hip_half_width"):
        walk_design_3d(design, WalkSettings(steps=2))


@pytest.mark.slow
def test_design_metrics_and_sweep_walk_in_3d(tmp_path, capsys):
    """design_metrics(floor, spatial=True) is the 3-D walk's verdict and roll; feet that meet are the outcome
    ``collided``; `sweep --3d` needs --floor (one line, nothing written)."""
    from pasibot_pin.__main__ import main
    from pasibot_pin.studies.design_metrics import design_metrics

    comb = load_design(FAST).with_(sole_inner=3.0, sole_gap_from=0.6, sole_gap_to=2.1)
    metrics = design_metrics(comb, floor=3, spatial=True)
    walk = walk_design_3d(comb, WalkSettings(steps=3))
    assert metrics.floor_outcome == walk.verdict.outcome == "walks"
    assert metrics["floor_max_hip_roll_deg"] == pytest.approx(walk.result.max_hip_roll_deg, abs=1e-6)
    assert metrics.row()["floor_min_sole_clearance_mm"] == pytest.approx(1e3 * walk.result.min_sole_clearance_m)
    tipped = design_metrics(load_design(FAST), floor=2, spatial=True)
    assert tipped.floor_outcome == "tipped" and tipped["floor_max_hip_roll_deg"] > math.degrees(TIP_LIMIT)
    assert design_metrics(load_design(FAST).with_(sole_inner=2.6), floor=2, spatial=True).floor_outcome == "collided"
    assert "floor_max_hip_roll_deg" not in design_metrics(comb, floor=1).row()  # the planar table is as before
    out = tmp_path / "sweep"
    assert main(["sweep", "--vary", "sole_inner=0.6:1.0", "--n", "2", "--3d", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "--floor" in err and len(err.strip().splitlines()) == 1 and not out.exists()


def test_a_comb_walks_the_same_on_its_outer_corners_alone(monkeypatch):
    """Contact at the extreme lateral corners only (``Footprint.contact_offsets``) against every
    corner of the comb's prongs: the same motion (the QP's velocity is unique; its impulses are
    shared differently), the hip within 1e-8 m / rad over 0.6 s of a comb walker's start."""
    design = load_design(FAST).with_(sole_inner=2.6, sole_gap_from=0.6, sole_gap_to=2.1)
    footprint = design.footprint()
    assert len(footprint.offsets) == 4 and footprint.contact_offsets == (min(footprint.offsets), max(footprint.offsets))
    robot = design_robot(design, 2, visuals=False)
    settings = floor_settings(design, WalkSettings(), robot)
    hull = Floor3D(FloorSimulator(robot, settings), footprint).run(0.6, stop_on_verdict=False)
    monkeypatch.setattr(Footprint, "contact_offsets", property(lambda self: self.offsets))
    every = Floor3D(FloorSimulator(robot, settings), footprint)
    assert every.n_corners == 2 * hull.normal.shape[1]
    full = every.run(0.6, stop_on_verdict=False)
    assert np.abs(full.hip - hull.hip).max() < 1e-8
    assert np.abs(full.roll - hull.roll).max() < 1e-8 and np.abs(full.pitch - hull.pitch).max() < 1e-8
    # the same total load (its split between the feet in double support is statically indeterminate)
    np.testing.assert_allclose(hull.normal.sum(axis=1), full.normal.sum(axis=1), rtol=1e-6, atol=1e-6)
