"""Every verdict carries each rule's value against its limit; the deciding rule is marked; too few
steps cannot be judged (issue 34). The judge is fed synthetic samples: the figures are known exactly."""

from __future__ import annotations

import json
import math

import pytest

from pasibot_pin.dynamics.margins import Margin
from pasibot_pin.dynamics.verdict import MIN_STRIDE_STEPS, FootSample, GaitCriteria, GaitJudge, GaitSample

L = 0.05
OMEGA = 2.0


def _sample(t, hip_x, pitch, feet):
    return GaitSample(t, hip_x, pitch, tuple(feet))


def _foot(x, loaded, normal=0.0, slip=0.0):
    return FootSample(x=x, loaded=loaded, normal=normal, slip=slip, on_point=False, pitch=0.0)


def _judge(steps=20, **criteria):
    start = _sample(0.0, 0.0, 0.0, [_foot(0.0, True, 300), _foot(0.0, True, 300)])
    return GaitJudge(OMEGA, L, 600.0, GaitCriteria(steps=steps, **criteria), start)


def test_a_fall_is_decided_by_the_hip_pitch_rule_with_its_value_and_limit():
    judge = _judge()
    h = 1e-3
    for k in range(1, 400):
        pitch = math.radians(0.03 * k)  # 0.03 deg per ms: past 10 deg at 334 ms
        judge.update(_sample(k * h, 0.0, pitch, [_foot(0.0, True, 300), _foot(0.0, True, 300)]))
        if judge.decided:
            break
    v = judge.verdict()
    assert v.outcome == "fell"
    margins = {m.rule: m for m in v.margins}
    assert margins["hip_pitch"].decided and margins["hip_pitch"].limit == pytest.approx(10.0)
    assert margins["hip_pitch"].value == pytest.approx(0.03 * 334, abs=1e-9) and margins["hip_pitch"].margin < 0
    assert not margins["slide"].decided and margins["slide"].value == 0.0 and margins["slide"].limit == 5.0
    assert [m.rule for m in v.margins if m.decided] == ["hip_pitch"]
    assert "hip_pitch" in v.margins_text() and "(decided)" in v.margins_text()


def test_a_margin_near_its_limit_is_flagged():
    assert Margin("swing", 0.158, 0.157, "s", "min").near
    assert not Margin("swing", 0.9, 0.157, "s", "min").near
    assert Margin("slide", 4.6, 5.0, "mm", "max").margin == pytest.approx(0.4)


def test_a_margins_text_states_a_true_relation_and_no_nan():
    """Past its limit a rule reads ``>`` (or ``<``), not ``<=``; a rule the walk never reached says so, not "nan"."""
    assert Margin("flight", 0.068, 0.02, "s", "max", decided=True).text() == "flight 0.068 > 0.02 s (decided)"
    assert Margin("slide", 1.5, 5.0, "mm", "max").text() == "slide 1.5 <= 5 mm"
    assert Margin("landing", 1.2, 2.0, "L", "min").text().startswith("landing 1.2 < 2 L")
    assert Margin("advance_low", math.nan, 0.9, "of 8 L per step", "min").text() == (
        "advance_low not reached (limit 0.9 of 8 L per step)"
    )


@pytest.mark.slow
def test_too_few_steps_cannot_say_walks():
    """Asked for fewer steps than a stride, the judge says ``undecided`` (it may fall at its next step)."""
    from pasibot_pin.model.design import Design
    from pasibot_pin.studies.walking import WalkSettings, walk_design

    fast = Design(variant="parallel", parallel_toe=6.0, parallel_heel=6.0, omega=3.0)
    for steps in range(1, MIN_STRIDE_STEPS):
        v = walk_design(fast, WalkSettings(steps=steps)).verdict
        assert v.outcome == "undecided" and v.steps == steps and "needs 3" in v.detail
    assert walk_design(fast, WalkSettings(steps=MIN_STRIDE_STEPS)).verdict.walks


@pytest.mark.slow
def test_walk_prints_and_json_has_the_margins(capsys):
    from pathlib import Path

    from pasibot_pin.__main__ import main

    fast = Path(__file__).resolve().parents[1] / "designs" / "map_top_speed_parallel_sole6L_omega3.toml"
    argv = ["walk", "--design", str(fast), "--steps", "3"]
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "margins:" in text and "hip_pitch" in text
    assert main([*argv, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    rules = {m["rule"]: m for m in out["margins"]}
    assert set(rules) >= {"hip_pitch", "slide", "advance_low", "advance_high", "flight", "landing", "swing", "steps"}
    assert rules["steps"]["value"] == 3 and rules["steps"]["limit"] == 3
