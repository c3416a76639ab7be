"""The walk's judge is an observer the floor engines are given (issue 35: the engine does not build its
own evaluation): a judge passed in sees every sample and decides the verdict the default one decides."""

from __future__ import annotations

import functools
from pathlib import Path

import pytest

from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.verdict import GaitCriteria, GaitJudge
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import design_robot, load_design
from pasibot_pin.studies.walking import WalkSettings, floor_settings

FAST = Path(__file__).resolve().parents[1] / "designs" / "map_top_speed_parallel_sole6L_omega3.toml"


class CountingJudge(GaitJudge):
    """A judge that also counts what it is shown."""

    samples = 0

    def update(self, sample):
        CountingJudge.samples += 1
        return super().update(sample)


def _sim():
    design = load_design(FAST)
    robot = design_robot(design, 2, visuals=False)
    return FloorSimulator(robot, floor_settings(design, WalkSettings(), robot))


def test_a_judge_passed_in_sees_every_sample_and_gives_the_default_verdict():
    sim = _sim()
    default = sim.run(1.5)
    CountingJudge.samples = 0
    s = sim.settings
    judged = sim.run(
        1.5, judge=functools.partial(CountingJudge, s.omega, sim.robot.geometry.L, sim.weight, GaitCriteria())
    )
    assert CountingJudge.samples == len(judged.t) == len(default.t)
    a, b = judged.verdict, default.verdict
    assert (a.outcome, a.steps, a.detail) == (b.outcome, b.steps, b.detail)
    assert a.advance_m == pytest.approx(b.advance_m, rel=1e-12) and a.max_hip_pitch == pytest.approx(b.max_hip_pitch)
    # a stricter judge, the same run: its own verdict (a pitch limit the walk passes at once)
    strict = _sim().run(1.5, judge=sim.judge_of(GaitCriteria(max_hip_pitch=1e-6)), stop_on_verdict=True)
    assert strict.verdict.outcome == "fell" and strict.t[-1] < 1.5


def test_a_judge_and_criteria_together_are_refused():
    sim = _sim()
    with pytest.raises(ParameterError, match="judge"):
        sim.run(0.1, judge=sim.judge_of(), criteria=GaitCriteria())
