"""One walk judged twice (studies.walking.walk_design_shown): the longer walk is walk_design's, the shorter one
is what a run of its own steps gives, from the same simulation (the report's animation and Answers share it)."""

import numpy as np
import pytest

from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.studies.walking import WalkSettings, walk_design, walk_design_shown


def _same_walk_alone(design, whole, part, steps, shown, robot):
    """Both walks against walk_design run alone: the whole one bit for bit, the shown one to the time step's change."""
    alone = walk_design(design, WalkSettings(steps=steps), robot)
    assert whole.verdict.summary() == alone.verdict.summary()
    assert np.array_equal(whole.result.q, alone.result.q)  # the same run, the same time step
    short = walk_design(design, WalkSettings(steps=shown), robot)
    v, w = part.verdict, short.verdict
    assert (v.outcome, v.steps, v.short()) == (w.outcome, w.steps, w.short())
    assert v.advance_m == pytest.approx(w.advance_m, abs=2e-3)
    assert v.max_hip_pitch == pytest.approx(w.max_hip_pitch, abs=2e-4)
    assert np.allclose(v.step_times, w.step_times, atol=2 * whole.dt)
    # the shown run stops where the short run stopped (within a step or two), on the whole run's samples
    assert abs(part.result.t[-1] - short.result.t[-1]) <= 2 * whole.dt
    n = len(part.result.t)
    assert np.array_equal(part.result.q, whole.result.q[:n]) and part.result.verdict is v
    assert len(part.result.modes["right"]) == n == len(part.result.normal)
    assert all(t <= part.result.t[-1] for t, *_ in part.result.landings)


def test_a_fall_before_the_shown_steps_is_the_short_walks_verdict_too():
    """The seed's sole at 2 rad/s falls after one step: the 2-step walk cut from a 4-step one falls at the same time."""
    design = Design(variant="parallel", omega=2.0)
    robot = design_robot(design, 2, visuals=False)
    whole, part = walk_design_shown(design, WalkSettings(steps=4), 2, robot)
    assert whole.verdict.outcome == part.verdict.outcome == "fell"
    assert part.verdict.decided_at == whole.verdict.decided_at  # the same samples decided both
    _same_walk_alone(design, whole, part, 4, 2, robot)


@pytest.mark.slow
def test_the_recommended_walkers_four_steps_from_its_six():
    """The report's animation (4 steps) cut from the Answers box's walk (6 steps): walks, as a 4-step walk does."""
    from pasibot_pin.studies.walking_map3d import recommended_walker

    design = recommended_walker()
    robot = design_robot(design, 2, visuals=False)
    whole, part = walk_design_shown(design, WalkSettings(steps=6), 4, robot)
    assert whole.verdict.walks and part.verdict.walks and part.verdict.steps == 4 < whole.verdict.steps
    _same_walk_alone(design, whole, part, 6, 4, robot)


@pytest.mark.parametrize("shown", [0, 5, 2.0])
def test_the_shown_steps_are_checked(shown):
    with pytest.raises(ParameterError, match="'shown'"):
        walk_design_shown(Design(variant="parallel", omega=2.0), WalkSettings(steps=4), shown)
