"""Every variant and motor layout on the floor, judged by the one verdict; the walk command."""

import json
import math

import numpy as np
import pytest

from pasibot_pin.__main__ import main
from pasibot_pin.dynamics.verdict import LINKAGE_ADVANCE_PER_STEP, OUTCOMES
from pasibot_pin.model.design import Design
from pasibot_pin.studies.walking import WalkSettings, walk_design

WALKER = Design(variant="parallel", parallel_toe=4.5, parallel_heel=4.5, omega=2.0)
"""The parallel extension with 4.5 L soles each side: it walks (at 1 rad/s in MuJoCo, shared DESIGN.md §8b)."""


@pytest.fixture(scope="module")
def walks():
    """The walker with two motors and with one, 4 steps each."""
    return {motors: walk_design(WALKER.with_(motors=motors), WalkSettings(steps=4)) for motors in ("two", "one")}


@pytest.mark.slow
def test_the_long_soled_parallel_design_walks_at_the_linkages_own_advance(walks):
    walk = walks["two"]
    v = walk.verdict
    assert v.outcome == "walks" and v.steps == 4
    # closed form: the linkage advances the hip 8 L per step (16 L per crank turn)
    assert v.advance_per_step == pytest.approx(1.0, abs=0.05)
    steps = np.diff(v.step_x)  # the feet alternate: consecutive landings are 8 L apart
    assert np.allclose(steps, LINKAGE_ADVANCE_PER_STEP * WALKER.L, rtol=0.05)
    assert np.allclose(np.diff(v.step_times), math.pi / WALKER.omega, rtol=0.02)  # a step per half crank turn
    assert v.max_hip_pitch < math.radians(1.0) and v.max_slip_m < 0.005
    assert v.cost_of_transport > 0 and v.power_per_metre > 0


@pytest.mark.slow
def test_the_readme_quotes_the_walker(walks):
    import re
    from pathlib import Path

    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text(encoding="utf-8")
    found = re.search(r"walks at\s+(\S+) rad/s, its hip at (\d+) % of the linkage's own 8 L per step", readme)
    assert found, "the README's walker sentence changed shape"
    v = walks["two"].verdict
    assert float(found.group(1)) == WALKER.omega and int(found.group(2)) == round(100 * v.advance_per_step)


@pytest.mark.slow
def test_one_motor_moves_the_robot_as_two_and_carries_their_sum(walks):
    """The cranks are prescribed either way: the motion is the same; the coupled cranks' one motor
    carries the sum of the two motors' torques (virtual work over the rigid coupling)."""
    two, one = walks["two"].result, walks["one"].result
    n = min(len(two.t), len(one.t))
    assert np.max(np.abs(two.q[:n] - one.q[:n])) < 1e-6
    assert one.motor_torque.shape[1] == 1 and two.motor_torque.shape[1] == 2
    total = two.motor_torque[:n].sum(axis=1)
    assert np.max(np.abs(one.motor_torque[:n, 0] - total)) < 1e-3 * np.max(np.abs(total))


@pytest.mark.parametrize(
    "design",
    [
        Design(variant="rigid", omega=1.0),
        Design(variant="rigid", foot_toe=6.0, foot_heel=6.0, omega=5.0),  # its feet tilt: one touches, at a point
        Design(variant="parallel", omega=1.0),
        Design(variant="spring", foot_toe=3.0, foot_heel=3.0, omega=1.0, spring_stiffness=3000.0),
        Design(variant="spring", foot_toe=4.0, foot_heel=4.0, omega=1.0, spring_stiffness=3000.0),
    ],
    ids=["rigid", "rigid-sole6-fast", "parallel-seed", "spring-toe=heel=3", "spring-toe=heel=4"],
)
def test_every_variant_gets_a_verdict_from_a_consistent_start(design):
    """No design fails at t = 0: the start closes every loop with no sole point below the floor,
    and a failure is an outcome with its time, never an exception or NaN."""
    from pasibot_pin.dynamics.floor.engine import FloorSimulator
    from pasibot_pin.model.design import design_robot

    robot = design_robot(design, 2, visuals=False)
    walk = walk_design(design, WalkSettings(steps=2), robot)
    v, result = walk.verdict, walk.result
    assert v.outcome in OUTCOMES and v.outcome != "diverged", v.summary()
    assert np.all(np.isfinite(result.q)) and len(result.t) >= 1
    sim = FloorSimulator(robot, walk.settings)
    q0, v0 = sim.initial_state() if result.start is None else (result.start.q, result.start.v)
    loops = sim.bilateral.evaluate(q0).phi[: sim.bilateral.n_constraint_rows]
    assert np.max(np.abs(loops)) < 1e-10 * design.L  # every loop closed at the start
    gaps = sim.contact_rows(q0)[0]
    assert np.all(gaps > -1e-9 * design.L)  # no sole point below the floor


@pytest.mark.slow
def test_walk_command_json_has_the_answer(tmp_path, capsys):
    design = tmp_path / "walker.toml"
    WALKER.save(design)
    assert main(["walk", "--design", str(design), "--steps", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("outcome", "steps", "advance_m", "max_hip_pitch_deg", "simulated_s"):
        assert key in out, key
    assert out["outcome"] == "walks" and out["steps"] == 3 and out["advance_m"] > 0.3


@pytest.mark.parametrize(
    ("argv", "names"),
    [
        (["--steps", "0"], "--steps"),
        (["--steps", "nan"], "--steps"),
        (["--steps", "-3"], "--steps"),
        (["--omega", "nan"], "--omega"),
        (["--omega", "1e300"], "--omega"),
        (["--design", "/nonexistent/d.toml"], "design"),
        (["--gif", "--out", "/proc/pasibot"], "/proc/pasibot"),
    ],
)
def test_walk_bad_flags_are_one_line_before_any_work(argv, names, capsys, monkeypatch):
    import pasibot_pin.studies.walking as walking

    def no_work(*args, **kwargs):
        raise AssertionError("the walk started before the flags were checked")

    monkeypatch.setattr(walking, "walk_design", no_work)
    assert main(["walk", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and names in err and "Traceback" not in err


def test_simulate_on_the_floor_takes_every_variant_and_motor_layout(tmp_path, capsys):
    """``simulate --ground floor --design F`` runs a design without ankle springs as itself, one motor or two."""
    for variant, motors in (("parallel", "one"), ("rigid", "two")):
        design = tmp_path / f"{variant}.toml"
        Design(variant=variant, omega=2.0, motors=motors).save(design)
        argv = ["simulate", "--ground", "floor", "--design", str(design), "--duration", "0.5", "--no-cases"]
        assert main([*argv, "--out", str(tmp_path / variant)]) == 0
        out = capsys.readouterr().out
        assert "floor, design" in out and "steps" in out
        header = (tmp_path / variant / "floor_design.csv").read_text().splitlines()[0]
        assert ("motor_crank_torque" in header) == (motors == "one")


def test_walk_stability_of_a_design_that_falls_is_an_outcome_not_an_error(capsys):
    """--stability on a design that does not walk: the command succeeds and says there is no gait."""
    argv = ["walk", "--variant", "parallel", "--omega", "2", "--steps", "3", "--stability", "--json"]
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["outcome"] != "walks" and out["multipliers"] is None and out["stable"] is False


def test_a_walk_with_no_sample_writes_no_animation_and_says_so(tmp_path):
    """Every outcome is an outcome: a run that diverged before its first sample has nothing to draw, and
    write_walk_animation returns no file instead of an IndexError (issue 34); nothing asked, nothing done."""
    import dataclasses

    from pasibot_pin.model.design import design_robot
    from pasibot_pin.report.walking import write_walk_animation

    design = Design(variant="parallel", parallel_toe=6.0, parallel_heel=6.0, omega=3.0)
    robot = design_robot(design, 2, visuals=False)
    walk = walk_design(design, WalkSettings(steps=1), robot)
    empty = dataclasses.replace(walk, result=dataclasses.replace(walk.result, t=walk.result.t[:0], q=walk.result.q[:0]))
    assert write_walk_animation(empty, robot, gif=tmp_path / "a.gif") == []
    assert write_walk_animation(walk, robot) == []
    assert not list(tmp_path.iterdir())
