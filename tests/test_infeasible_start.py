"""A start pose that already breaks a limit is its own outcome, `infeasible_start`, decided at the start and
naming the rule, its value and its limit: in the judge, `walk`, `sweep --floor` and `find-walker` (issue 34)."""

from __future__ import annotations

import json
import math

import pytest

from pasibot_pin.__main__ import main
from pasibot_pin.dynamics.verdict import FAILURES, OUTCOMES, FootSample, GaitCriteria, GaitJudge, GaitSample
from pasibot_pin.model.design import Design

RIGID = Design(variant="rigid", foot_toe=6.0, foot_heel=6.0, omega=2.0)
"""The walking map's rigid 6 L design: its feet, square to the shanks, tilt the hip past 10 deg as it settles."""


def _start(pitch: float, foot_pitch: float = 0.0, loaded: bool = True, on_point: bool = False) -> GaitSample:
    feet = (FootSample(loaded, 0.0, foot_pitch, 0.0, 0.0, on_point), FootSample(True, 0.2, 0.0, 0.0, 0.0, False))
    return GaitSample(0.0, 0.0, pitch, feet)


def _judge(start: GaitSample) -> GaitJudge:
    return GaitJudge(2.0, 0.05, 380.0, GaitCriteria(), start)


def _decided(judge: GaitJudge):
    verdict = judge.verdict(0.0)
    return verdict, next(m for m in verdict.margins if m.decided)


def test_a_start_past_the_hip_pitch_limit_is_decided_at_once_with_its_value():
    limit = GaitCriteria().max_hip_pitch
    judge = _judge(_start(-(limit + 0.1)))
    assert judge.decided and judge.outcome == "infeasible_start" and "infeasible_start" in OUTCOMES
    verdict, margin = _decided(judge)
    assert verdict.decided_at == 0.0 and verdict.steps == 0 and not verdict.walks and verdict.failed
    assert margin.rule == "hip_pitch" and margin.value == pytest.approx(math.degrees(limit + 0.1))
    assert f"{math.degrees(-(limit + 0.1)):+.1f} deg" in verdict.detail and "hip pitch" in verdict.detail


def test_a_foot_standing_on_a_point_past_the_roll_limit_is_decided_at_once():
    limit = GaitCriteria().roll_limit
    verdict, margin = _decided(_judge(_start(0.05, foot_pitch=limit + 0.05, on_point=True)))
    assert verdict.outcome == "infeasible_start" and margin.rule == "foot_roll"
    assert verdict.max_hip_pitch == pytest.approx(0.05)  # the start's pitch counts, though within its limit
    assert margin.value == pytest.approx(math.degrees(limit + 0.05)) and "right foot" in verdict.detail


@pytest.mark.parametrize(
    "start",
    [
        _start(0.5 * GaitCriteria().max_hip_pitch),  # within the limit
        _start(0.0, foot_pitch=1.0, on_point=True, loaded=False),  # a tilted foot in the air bears nothing
        _start(0.0, foot_pitch=1.0, on_point=False),  # flat on heel and toe: its pitch is the floor's
    ],
)
def test_a_start_within_the_limits_is_not_decided(start):
    assert not _judge(start).decided and "infeasible_start" in FAILURES


@pytest.mark.slow
def test_walk_reports_the_rigid_designs_start_with_the_pitch_it_settles_into(tmp_path, capsys):
    """The value named is the settled start's pitch, computed here by the floor's own start, apart from the walk."""
    from pasibot_pin.dynamics.floor.engine import FloorSimulator
    from pasibot_pin.model.coordinates import HIP_PITCH
    from pasibot_pin.model.design import design_robot
    from pasibot_pin.studies.walking import WalkSettings, floor_settings

    path = RIGID.save(tmp_path / "rigid.toml")
    assert main(["walk", "--design", str(path), "--steps", "4", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["outcome"] == "infeasible_start" and out["decided_at_s"] == 0.0 and out["steps"] == 0
    robot = design_robot(RIGID, 2, visuals=False)
    start = FloorSimulator(robot, floor_settings(RIGID, WalkSettings(steps=4), robot)).start_state()
    pitch = math.degrees(start.q[HIP_PITCH])
    assert abs(pitch) > math.degrees(GaitCriteria().max_hip_pitch)
    margin = next(m for m in out["margins"] if m["decided"])
    assert margin["rule"] == "hip_pitch" and margin["value"] == pytest.approx(abs(pitch), abs=1e-9)
    assert f"{pitch:+.1f} deg" in out["detail"]
    assert main(["walk", "--design", str(path), "--steps", "4"]) == 0
    assert "infeasible_start at t = 0.000 s" in capsys.readouterr().out


@pytest.mark.slow
def test_sweep_floor_and_find_walker_record_the_outcome(tmp_path):
    from pasibot_pin.explore.find_walker import FAILED, walk_candidate
    from pasibot_pin.explore.plan import Range, SweepPlan
    from pasibot_pin.explore.sweep import run_sweep

    plan = SweepPlan(ranges=(Range("foot_toe", 6.0, 6.5),), n=2, seed=0, base=RIGID, floor=3)
    table = run_sweep(plan, tmp_path / "sweep", workers=1, progress=False).table
    assert table.column("floor_outcome").to_pylist() == ["infeasible_start"] * 2
    outcome, steps, score, detail = walk_candidate(RIGID.to_dict(), 2.0, {"foot_heel": 6.0}, 3, "sole")
    assert (outcome, steps, score) == ("infeasible_start", 0, FAILED) and "start pose" in detail
