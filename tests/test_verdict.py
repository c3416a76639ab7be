"""The walking verdict on synthetic walks whose answer is known by construction (no simulation)."""

import math

import pytest

from pasibot_pin.dynamics.verdict import FootSample, GaitCriteria, GaitJudge, GaitSample
from pasibot_pin.errors import ParameterError

L = 0.05
OMEGA = 2.0
PERIOD = math.pi / OMEGA
WEIGHT = 500.0
DT = 1e-3


def foot(loaded, x, normal=0.0, slip=0.0, pitch=0.0, on_point=False):
    return FootSample(loaded=loaded, x=x, pitch=pitch, normal=normal if loaded else 0.0, slip=slip, on_point=on_point)


def ideal_walk(
    duration, advance=8.0, air=0.4, pitch=lambda t: 0.0, slip=0.0, power=(10.0, 0.0), land_short=None, short_by=0.5
):
    """Feet that alternate: each swings for ``air`` of a period and lands ``2 advance`` L ahead of where it stood.

    The hip moves at advance L per period. The right foot stands first; the left swings in the first period.
    """
    samples = []
    stands = {0: 0.0, 1: -advance * L}
    n = round(duration / DT)
    for k in range(n + 1):
        t = k * DT
        step, phase = divmod(t / PERIOD, 1.0)
        swing = 1 - int(step) % 2  # the left foot swings in period 0, the right in period 1, ...
        feet = []
        for i in (0, 1):
            moving = i == swing and phase < air
            if i == swing and phase >= air:
                landed = stands[i] + 2 * advance * L
                if land_short is not None and step >= land_short:
                    landed = stands[i] + short_by * L
                x = landed
            else:
                x = stands[i]
            feet.append(foot(not moving, x, WEIGHT if not moving else 0.0, slip if not moving else 0.0))
        if phase + DT / PERIOD >= 1.0:  # end of the period: the swing foot's stand moves
            stands[swing] = feet[swing].x
        samples.append(GaitSample(t, advance * L * t / PERIOD, pitch(t), tuple(feet), power))
    return samples


def judge_of(samples, **criteria):
    judge = GaitJudge(OMEGA, L, WEIGHT, GaitCriteria(**criteria), samples[0])
    for s in samples[1:]:
        if judge.update(s):
            break
    return judge.verdict(samples[-1].t)


def test_an_ideal_walk_walks_and_its_figures_are_the_closed_form():
    verdict = judge_of(ideal_walk(12 * PERIOD), steps=8)
    assert verdict.outcome == "walks" and verdict.steps == 8
    # the 8th landing: the swing of period k lands at k + air periods (dwell added)
    assert verdict.decided_at == pytest.approx(7 * PERIOD + 0.4 * PERIOD + 0.01, abs=2 * DT)
    assert verdict.advance_per_step == pytest.approx(1.0, abs=1e-3)
    # positive work of a constant 10 W motor over whole strides, over weight x advance
    strides = verdict.step_times[-1] - verdict.step_times[1]
    assert verdict.motor_energy_j == pytest.approx(10.0 * strides, rel=1e-3)
    assert verdict.cost_of_transport == pytest.approx(10.0 * strides / (WEIGHT * verdict.stride_advance_m), rel=1e-3)
    assert verdict.stride_advance_m == pytest.approx(8 * L * (verdict.steps - 2), rel=1e-3)


def test_a_hip_pitch_past_the_limit_is_a_fall_at_that_time():
    verdict = judge_of(ideal_walk(6 * PERIOD, pitch=lambda t: 0.05 * t), steps=20)
    assert verdict.outcome == "fell"
    assert verdict.decided_at == pytest.approx(math.radians(10) / 0.05, abs=2 * DT)


def test_a_foot_put_down_where_it_stood_hopped():
    verdict = judge_of(ideal_walk(10 * PERIOD, land_short=3), steps=20)
    assert verdict.outcome == "hopped" and "landed" in verdict.detail
    assert verdict.decided_at == pytest.approx(3 * PERIOD + 0.4 * PERIOD + 0.01, abs=2 * DT)


def test_a_foot_put_down_behind_where_it_stood_stepped_back():
    """Issue 34: "hopped" was also given for a foot landing behind where it stood; that is its own outcome."""
    verdict = judge_of(ideal_walk(10 * PERIOD, land_short=3, short_by=-1.5), steps=20)
    assert verdict.outcome == "stepped_back" and "landed -1.50 L from where it stood" in verdict.detail
    assert verdict.decided_at == pytest.approx(3 * PERIOD + 0.4 * PERIOD + 0.01, abs=2 * DT)
    assert [m.rule for m in verdict.margins if m.decided] == ["landing"]


def test_no_landing_for_two_periods_stalled():
    still = [GaitSample(k * DT, 0.0, 0.0, (foot(True, 0.0, 250), foot(True, -0.4, 250))) for k in range(4000)]
    verdict = judge_of(still, steps=20)
    assert verdict.outcome == "stalled" and verdict.decided_at == pytest.approx(2 * PERIOD, abs=2 * DT)


def test_a_sliding_stance_foot_slipped_once_past_the_limit():
    # the stance foot slides 2 cm/s: 5 mm after 0.25 s of a judged stance
    verdict = judge_of(ideal_walk(6 * PERIOD, slip=0.02), steps=20)
    assert verdict.outcome == "slipped"
    assert verdict.max_slip_m == pytest.approx(0.005, abs=0.02 * 2 * DT)


def test_an_advance_outside_the_band_is_named():
    short = judge_of(ideal_walk(12 * PERIOD, advance=6.0), steps=8)  # 75 % of 8 L per step
    assert short.outcome == "stalled" and "75 %" in short.detail
    assert short.advance_per_step == pytest.approx(0.75, abs=1e-3)


def test_a_run_shorter_than_two_periods_is_undecided_not_stalled():
    verdict = judge_of(ideal_walk(1.5 * PERIOD), steps=20)
    assert verdict.outcome == "undecided" and not verdict.failed and not verdict.walks


def test_a_short_flight_of_one_foot_is_a_bounce_not_a_hop():
    samples = ideal_walk(6 * PERIOD)
    bounced = []
    for s in samples:  # the stance foot leaves the floor for 30 ms at mid-period 2 and comes back
        t = s.t / PERIOD
        if 2.5 < t < 2.5 + 0.03 / PERIOD:
            right, left = s.feet
            feet = (right, foot(False, left.x)) if right.loaded else (foot(False, right.x), left)
            s = GaitSample(s.t, s.hip_x, s.hip_pitch, feet)
        bounced.append(s)
    verdict = judge_of(bounced, steps=4)
    assert verdict.outcome == "walks"


@pytest.mark.parametrize(
    ("name", "value"),
    [("steps", 0), ("steps", 1.5), ("steps", True), ("max_hip_pitch", float("nan")), ("slip_per_step", -1.0)],
)
def test_bad_criteria_name_the_parameter(name, value):
    with pytest.raises(ParameterError, match=name):
        GaitCriteria(**{name: value})
