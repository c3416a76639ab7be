"""The floor simulator: unilateral heel/toe contacts with Coulomb friction (dynamics/floor/engine.py).

Independent references: the total weight (a robot standing still on the floor), free fall and
the momentum balance of an inelastic touchdown (closed form), the friction cone, and MuJoCo on
the exported model (the same robot hops off the floor when the fitted springs release).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest
from report_checks import assert_reads_like_a_report

import pasibot_pin as pp
from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.settings import FloorSettings
from pasibot_pin.model.mjcf import MjcfOptions, to_mjcf
from pasibot_pin.model.robot import total_mass
from pasibot_pin.studies import spring_study

G = 9.81


@pytest.fixture(scope="module")
def robot():
    return pp.load("spring", 2)


def test_standing_still_the_floor_carries_the_weight(robot):
    # cranks held, hip held level, free ankles: both feet flat on the floor hold the rest
    sim = FloorSimulator(robot, FloorSettings(omega=0.0, hip="level", dt=1e-3))
    res = sim.run(0.2)
    assert not res.failed and res.outcome == "stood" and res.verdict is None  # cranks held: no walk to judge
    weight = total_mass(robot) * G
    assert np.sum(res.normal[-1]) == pytest.approx(weight, rel=1e-6)  # vertical balance of the whole robot
    assert res.modes["right"][-1] == "flat" and res.modes["left"][-1] == "flat"
    assert np.max(np.abs(res.v[-1])) < 1e-6
    assert np.all(np.abs(res.tangential) <= sim.settings.mu * res.normal + 1e-9)  # inside the cone
    loops = sim.bilateral.evaluate(res.q[-1]).phi[: sim.bilateral.n_constraint_rows]
    assert np.max(np.abs(loops)) < 1e-8


def test_a_dropped_robot_lands_when_free_fall_says_and_stops_inelastically(robot):
    height = 0.01
    # in free fall gravity strains nothing: the robot keeps its shape and lands on all four points at once
    sim = FloorSimulator(robot, FloorSettings(omega=0.0, hip="level", dt=2e-4))
    q0, v0 = sim.initial_state()
    q0 = q0.copy()
    q0[1] += height  # the hip's z: everything 1 cm up
    res = sim.run(0.08, q0, v0 * 0.0)
    first = min(t for t, _, _ in res.touchdowns)
    assert first == pytest.approx(math.sqrt(2 * height / G), abs=2 * sim.settings.dt)
    k = int(np.searchsorted(res.t, first - 1e-12))  # the step in which the points reach the floor
    gap, _, jn, _ = sim.contact_rows(res.q[k])
    assert np.max(np.abs(gap)) < 1e-9  # they end the step on it ...
    assert np.max(np.abs(jn @ res.v[k + 1])) < 1e-6  # ... and stay: an inelastic touchdown
    # momentum balance over the two steps: the floor's impulse = M (0 - v_z) + M g 2 h (M the total mass)
    mass, h = total_mass(robot), sim.settings.dt
    impulse = np.sum(res.normal[k : k + 2]) * h
    assert abs(res.v[k + 1][1]) < 1e-6
    assert impulse == pytest.approx(mass * (0.0 - res.v[k - 1][1]) + mass * G * 2 * h, rel=1e-3)


@pytest.mark.slow
@pytest.mark.parametrize("factor", [0.0, 1.0])
def test_a_consistent_start_stays_at_rest(factor):
    """Cranks held, the start of :meth:`start_state` is an equilibrium: nothing moves for 0.5 s.

    No spring: the flat double support holds as it is. The fitted spring (preload ~69 N.m at the
    front ankle, which the flat start cannot hold: one step from it moves at ~3 m/s) settles onto
    the front heel and the rear toe. Either way the loops are closed, every force is in its cone,
    the normal forces carry the weight (the masses, summed here), and the modes never change.
    """
    inputs = spring_study.scenario_inputs("run1")
    spring = inputs.fit.scaled(factor) if factor > 0 else None
    sim = FloorSimulator(inputs.robot, FloorSettings(omega=0.0, spring=spring))
    start = sim.start_state()
    q_flat, _ = sim.initial_state()
    flat_speed = sim.rest_forces(q_flat)[2]
    if spring is None:
        assert start.kind == "flat" and flat_speed < 1e-7
    else:
        assert start.kind == "settled" and flat_speed > 0.1  # the flat start is no equilibrium: it would hop
        assert start.modes == {"right": "heel", "left": "toe"}
    weight = total_mass(inputs.robot) * G
    assert start.loop_residual < 1e-8
    assert np.all(start.normal >= -1e-9) and np.sum(start.normal) == pytest.approx(weight, rel=1e-5)
    assert start.friction_use <= sim.settings.mu  # inside the cones
    assert np.all(start.gaps > -1e-9)  # nothing below the floor
    res = sim.run(0.5, start.q, start.v)
    assert not res.failed
    # at rest it stays at rest: the settled foot rocks on its heel by < 1e-5 rad/s (its spring's light damping)
    assert np.max(np.abs(res.v)) < 1e-4
    assert np.max(np.abs(res.q - start.q)) < 1e-5
    for side in ("right", "left"):
        assert set(res.modes[side]) == {start.modes[side]}  # no mode change
    np.testing.assert_allclose(np.sum(res.normal, axis=1), weight, rtol=1e-5)
    loops = sim.bilateral.evaluate(res.q[-1]).phi[: sim.bilateral.n_constraint_rows]
    assert np.max(np.abs(loops)) < 1e-8


def test_bad_settings_are_named():
    with pytest.raises(ValueError, match="'mu'"):
        FloorSettings(mu=-0.1)
    with pytest.raises(ValueError, match="'dt'"):
        FloorSettings(dt=0.0)
    with pytest.raises(ValueError, match="'omega'"):
        FloorSettings(omega=float("nan"))
    with pytest.raises(ValueError, match="'foot_toe'"):  # a sole of zero length
        from pasibot_pin.model.params import Geometry

        Geometry(foot_toe=0.0)
    sim = FloorSimulator(pp.load("spring", 2), FloorSettings())
    q0, v0 = sim.initial_state()
    bad = q0.copy()
    bad[3] = float("nan")
    with pytest.raises(ValueError, match="'q0'"):
        sim.run(0.1, bad, v0)
    with pytest.raises(ValueError, match="'start'"):
        sim.run(0.1, start="standing")
    with pytest.raises(ValueError, match="'duration'"):
        sim.run(float("nan"))


def test_mujoco_agrees_the_fitted_spring_makes_the_robot_hop():
    """Run 1's fitted spring from double support: the preload throws both feet off the floor
    (our time-stepping and MuJoCo's soft contacts agree on when, and on the feet's heights)."""
    inputs = spring_study.scenario_inputs("run1")
    robot, spring = inputs.robot, inputs.fit
    # 0.5 ms: the implicit springs' first-order error moves the feet's heights by ~1.5 mm at 1 ms
    sim = FloorSimulator(robot, FloorSettings(omega=inputs.omega, spring=spring, dt=5e-4))
    q0, v0 = sim.initial_state()  # the flat double support, springs preloaded: not a start it can hold
    ours = sim.run(0.1, q0, v0)
    airborne = [t for t, r, left in zip(ours.t, ours.modes["right"], ours.modes["left"]) if r == left == "air"]
    assert airborne and 0.02 < airborne[0] < 0.07
    options = MjcfOptions(spring.stiffness, spring.rest_angle, spring.damping, mu=sim.settings.mu)
    model = mujoco.MjModel.from_xml_string(to_mjcf(robot, options, q_weld=q0))
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = q0, v0
    start = np.array([q0[robot.idx_q(m)] for m in robot.actuated_joints])
    lag = options.kv * inputs.omega / options.kp
    mj_airborne = None
    while data.time < 0.09:
        data.ctrl[:] = start + inputs.omega * data.time + lag
        mujoco.mj_step(model, data)
        if mj_airborne is None and data.ncon == 0:
            mj_airborne = data.time
    assert mj_airborne is not None and abs(mj_airborne - airborne[0]) < 0.02
    k = int(np.searchsorted(ours.t, 0.09))
    ours_heights = sim.contact_rows(ours.q[k])[0]
    mj_heights = [data.site(f"{side}_{p}").xpos[2] for side in ("right", "left") for p in ("heel", "toe")]
    np.testing.assert_allclose(ours_heights, mj_heights, atol=3e-3)


@pytest.mark.slow
def test_simulate_command_on_the_floor_writes_modes_and_outcomes(tmp_path, capsys):
    """``pasibot simulate`` (floor by default): one outcome line per case, a CSV with t, hip_pitch_deg
    and a contact-mode column per foot, a figure; never over existing files without --force."""
    import csv

    from pasibot_pin.__main__ import main
    from pasibot_pin.dynamics.floor.run import MODES

    out = tmp_path / "sim"
    assert main(["simulate", "--scenario", "4", "--duration", "0.3", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert text.count("floor, ") == 4 and "wrote" in text
    with (out / "floor_run4.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert {"t_s", "hip_pitch_deg", "right_mode", "left_mode", "right_heel_Fn_N"} <= set(rows[0])
    assert {"left_toe_friction_use", "right_crank_torque_Nm", "hip_z_m"} <= set(rows[0])
    assert {r["right_mode"] for r in rows} <= set(MODES) and float(rows[-1]["t_s"]) <= 0.3 + 1e-9
    assert (out / "floor_run4.png").stat().st_size > 10_000
    assert main(["simulate", "--scenario", "4", "--duration", "0.3", "--out", str(out)]) == 2
    assert "exists" in capsys.readouterr().err


@pytest.mark.slow
def test_readme_and_docs_floor_numbers_are_what_the_study_computes():
    """The README's floor paragraph and docs/floor.md's rows for the fitted spring of runs 1-4,
    recomputed by the study (a drift of any printed figure fails here)."""
    import re
    from pathlib import Path

    from pasibot_pin.report.floor import floor_spring_table
    from pasibot_pin.studies.weld_vs_floor import FloorSpringSettings, floor_spring_study

    root = Path(__file__).resolve().parents[1]
    readme = root.joinpath("README.md").read_text(encoding="utf-8")
    doc = root.joinpath("docs", "floor.md").read_text(encoding="utf-8")
    found = re.search(
        r"run 1 stands on its front heel and rear toe at (\S+)° hip\s+pitch and stays within ([0-9.]+)° over "
        r"([0-9.]+) s \(welded: ([0-9.]+)°\), but runs 2–4 cannot stand with the fitted\s+spring: they fall at "
        r"([0-9.]+), ([0-9.]+) and ([0-9.]+) s, where the weld holds ([0-9.]+)°, ([0-9.]+)° and ([0-9.]+)°",
        readme,
    )
    assert found, "the README's floor sentence changed shape"
    start, floor_max, duration, weld_max, *rest = (float(x.replace("−", "-")) for x in found.groups())
    falls, welds = rest[:3], rest[3:]
    settings = FloorSpringSettings(scenarios=("run1", "run2", "run3", "run4"), duration=duration)
    study = floor_spring_study(settings, cases=[("fitted", 1.0)])
    run1 = study.row("run1", "fitted")
    assert run1.floor_start == "settled" and run1.floor_start_modes == "heel/toe"
    assert start == round(math.degrees(run1.floor_start_pitch), 2)
    assert floor_max == round(math.degrees(run1.floor_max_pitch), 1) and not run1.floor_failed
    assert weld_max == round(math.degrees(run1.weld_max_pitch), 1)
    for run, fall, weld in zip(("run2", "run3", "run4"), falls, welds):
        row = study.row(run, "fitted")
        assert row.floor_start == "none" and row.floor_failed  # the verdict names the first failure
        assert fall == round(row.floor_end, 2) and weld == round(math.degrees(row.weld_max_pitch), 1)
    for row in floor_spring_table(study):  # docs/floor.md prints the same rows
        assert "| " + " | ".join(row.values()) + " |" in doc


def test_a_sticking_point_does_not_creep_and_the_cranks_turn_at_omega():
    """Run 1, fitted spring, 0.3 s from the consistent start: the front heel sticks (its friction
    use stays inside the cone), so it must not move along the floor, and the cranks follow
    theta0 + omega t. (The first version counted the crank rate twice in the QP's bilateral rows
    and projected the excess back each step, dragging the stuck heel 1.3 mm in 0.5 s.) The start's
    contact forces are checked against the rigid statics solved independently (least squares of
    gravity minus spring torque on the loop, crank and loaded-point rows)."""
    import pinocchio as pin

    from pasibot_pin.dynamics.spring_energy import spring_forces

    inputs = spring_study.scenario_inputs("run1")
    robot = inputs.robot
    sim = FloorSimulator(robot, FloorSettings(omega=inputs.omega, spring=inputs.fit))
    res = sim.run(0.3)
    start = res.start
    heel = 0  # right heel: the front foot stands on it
    assert start.modes["right"] == "heel" and np.all(res.normal[:, heel] > 1.0)
    assert np.max(res.friction_use()[:, heel]) < 0.9 * sim.settings.mu  # strictly sticking
    along = np.array([sim.contact_rows(q)[1][heel] for q in res.q])
    assert np.max(np.abs(along - start.along[heel])) < 1e-6  # [m]
    for k, side in enumerate(("right", "left")):
        crank = res.q[:, robot.idx_q(f"{side}_j0_crank")]
        np.testing.assert_allclose(crank, sim.settings.theta0 + k * math.pi + inputs.omega * res.t, atol=1e-9)
        np.testing.assert_allclose(res.v[:, robot.idx_v(f"{side}_j0_crank")], inputs.omega, atol=1e-9)
    # rigid statics at the start, cranks held: gravity - spring = J_b^T lambda + J_n^T N + J_t^T T
    held = FloorSimulator(robot, FloorSettings(omega=0.0, spring=inputs.fit))
    rows = held.bilateral.evaluate(start.q, None, 0.0)
    _, _, jn, jt = held.contact_rows(start.q)
    loaded = [0, 3]  # front heel, rear toe
    stack = np.vstack((rows.jac, jn[loaded], jt[loaded]))
    gravity = pin.computeGeneralizedGravity(robot.model, robot.model.createData(), start.q)
    spring = spring_forces(robot, inputs.fit, start.q, np.zeros(robot.model.nv), held.ankles)
    assert np.linalg.matrix_rank(stack) == stack.shape[0]  # determinate: one set of forces
    lam = np.linalg.lstsq(stack.T, gravity - spring, rcond=None)[0]
    m = rows.jac.shape[0]
    np.testing.assert_allclose(lam[m : m + 2], start.normal[loaded], atol=0.05)
    np.testing.assert_allclose(lam[m + 2 :], start.tangential[loaded], atol=0.05)


@pytest.mark.slow
def test_a_smooth_crank_start_follows_its_ramp_and_rings_nothing():
    """``crank_ramp``: the cranks follow theta0 + omega advance(t), the advance's closed form
    (the smoothstep rate integrated), its rate the finite difference of the advance.

    Run 1, fitted spring, 0.5 s ramp: no mode change until the rear toe reaches its cone
    (~0.9 s), the squeeze (the front heel's tangential force) within 30 N of the start's over
    the first 0.5 s, where the impulsive start swings it by > 90 N and slides the rear toe within
    0.2 s. Along the run the contact forces are those of rigid Newton-Euler, solved independently
    (least squares of M a + b - spring on the loop, crank and loaded-point rows, a by central
    differences), to 0.5 N: the squeeze's slow swing from -77 N to +74 N as the cranks turn is the
    rigid double support's own (its smallest singular value is 2 mm: an ill-conditioned four-bar).
    """
    import pinocchio as pin

    from pasibot_pin.dynamics.floor.settings import crank_advance
    from pasibot_pin.dynamics.spring_energy import spring_forces

    ramp = 0.2
    for t in (0.0, 0.05, 0.1, 0.2, 0.3):
        advance, rate = crank_advance(t, ramp)
        x = min(t / ramp, 1.0)
        closed = ramp * (x**3 - x**4 / 2) + max(0.0, t - ramp)  # integral of 3 x^2 - 2 x^3 over t
        assert advance == pytest.approx(closed, abs=1e-15)
        step = 1e-6
        low = max(0.0, t - step)
        fd = (crank_advance(t + step, ramp)[0] - crank_advance(low, ramp)[0]) / (t + step - low)
        assert rate == pytest.approx(fd, abs=1e-6)
    assert crank_advance(0.3, 0.0) == (0.3, 1.0)  # no ramp: t and omega at once
    inputs = spring_study.scenario_inputs("run1")
    robot = inputs.robot
    impulsive = FloorSimulator(robot, FloorSettings(omega=inputs.omega, spring=inputs.fit)).run(0.25)
    assert np.ptp(impulsive.tangential[:, 0]) > 90.0 and "sliding" in impulsive.modes["left"]
    sim = FloorSimulator(robot, FloorSettings(omega=inputs.omega, spring=inputs.fit, crank_ramp=0.5))
    smooth = sim.run(0.85)
    for k, side in enumerate(("right", "left")):
        crank = smooth.q[:, robot.idx_q(f"{side}_j0_crank")]
        advance = np.array([crank_advance(t, 0.5)[0] for t in smooth.t])
        np.testing.assert_allclose(crank, sim.settings.theta0 + k * math.pi + inputs.omega * advance, atol=1e-9)
        assert set(smooth.modes[side]) == {smooth.start.modes[side]}  # front heel, rear toe throughout
    early = smooth.t <= 0.5
    assert np.max(np.abs(smooth.tangential[early, 0] - smooth.start.tangential[0])) < 30.0
    data = robot.model.createData()
    loaded = [0, 3]  # front heel, rear toe
    for t in (0.3, 0.6, 0.84):
        k = int(np.argmin(np.abs(smooth.t - t)))
        q, v = smooth.q[k], smooth.v[k]
        a = (smooth.v[k + 1] - smooth.v[k - 1]) / (smooth.t[k + 1] - smooth.t[k - 1])
        rows = sim.bilateral.evaluate(q, None, smooth.t[k], sim.targets(smooth.t[k]))
        _, _, jn, jt = sim.contact_rows(q)
        stack = np.vstack((rows.jac, jn[loaded], jt[loaded]))
        rhs = pin.rnea(robot.model, data, q, v, a) - spring_forces(robot, inputs.fit, q, v, sim.ankles)
        lam = np.linalg.lstsq(stack.T, rhs, rcond=None)[0]
        m = rows.jac.shape[0]
        np.testing.assert_allclose(lam[m : m + 2], smooth.normal[k, loaded], atol=0.5)
        np.testing.assert_allclose(lam[m + 2 :], smooth.tangential[k, loaded], atol=0.5)
    assert smooth.tangential[-1, 0] > 60.0  # the squeeze has turned: the heel is pushed forward now
    with pytest.raises(ValueError, match="'crank_ramp'"):
        FloorSettings(crank_ramp=-1.0)


def test_mode_runs_merge_blips_shorter_than_the_dwell():
    from pasibot_pin.dynamics.floor.run import mode_runs

    modes = ["sliding"] * 3 + ["toe"] * 40 + ["sliding"] * 5 + ["toe"] * 20 + ["sliding"] * 30
    assert mode_runs(modes, 1e-3) == [
        ("sliding", 1e-3),
        ("toe", pytest.approx(4e-3)),
        ("sliding", pytest.approx(44e-3)),
        ("toe", pytest.approx(49e-3)),
        ("sliding", pytest.approx(69e-3)),
    ]
    # 10 ms: the leading blip joins the run after it, the inner one the run before it
    assert mode_runs(modes, 1e-3, 0.01) == [("toe", 1e-3), ("sliding", pytest.approx(69e-3))]


def test_a_diverging_run_stops_with_its_cause_and_time():
    """Two forced failures stop the run with the cause and the time, never NaN:
    a robot thrown down at 999 m/s passes the speed limit (1000 m/s) when free fall says,
    (1000 - 999) / g = 0.102 s; an absurd spring (1e9 N.m/rad, 1.3 rad from its rest angle, at
    the largest step) throws the feet about: the run stops within its first steps, saying why and when."""
    from pasibot_pin.dynamics.floor.tracked_step import SPEED_LIMIT
    from pasibot_pin.dynamics.spring_energy import AnkleSpring

    robot = pp.load("spring", 2)
    sim = FloorSimulator(robot, FloorSettings(omega=0.0, dt=1e-3))
    q0, v0 = sim.initial_state()
    q0, v0 = q0.copy(), np.zeros_like(v0)
    q0[1] += 200.0  # 200 m up: it never reaches the floor
    v0[1] = -(SPEED_LIMIT - 1.0)
    res = sim.run(1.0, q0, v0)
    assert res.failed and res.outcome == "diverged" and res.stop_reason.startswith("the simulation diverged at t = ")
    t_fail = float(res.stop_reason.split("t = ")[1].split(" s")[0])
    assert t_fail == pytest.approx(1.0 / G, abs=2e-3)
    assert len(res.t) and res.t[-1] <= t_fail + 1e-12
    for array in (res.t, res.q, res.v, res.normal, res.tangential, res.motor_torque, res.hip_pitch):
        assert np.all(np.isfinite(array))
    crazy = FloorSimulator(robot, FloorSettings(spring=AnkleSpring(1e9, 0.0), dt=0.01))
    res = crazy.run(0.5, start="flat")
    import re

    found = re.search(r"(slipped|diverged|failed|fell|rolled).* t = (\d+\.\d{3}) s", res.stop_reason)
    assert res.failed and found and float(found.group(2)) <= 0.05, res.stop_reason
    assert res.verdict.failed and res.verdict.decided_at <= 0.05  # the verdict saw it as early
    assert all(np.all(np.isfinite(a)) for a in (res.t, res.q, res.v, res.normal))


@pytest.mark.slow
def test_simulate_study_command_writes_the_weld_against_floor_table(tmp_path, capsys):
    """``pasibot simulate --ground floor --study``: one printed line per case, the table, CSV and
    figure in --out (the rows those of the library's study); bad input is one line, before any work."""
    import csv

    from pasibot_pin.__main__ import main
    from pasibot_pin.studies.weld_vs_floor import FloorSpringSettings, floor_spring_study

    out = tmp_path / "study"
    assert main(["simulate", "--study", "--scenario", "2", "--duration", "0.05", "--no-cases", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert text.count("run2 fitted") == 1 and text.count("wrote") == 3
    with (out / "floor_springs.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    study = floor_spring_study(FloorSpringSettings(("run2",), 0.05), [("fitted", 1.0)])
    from pasibot_pin.report.floor import outcome_text

    assert len(rows) == 1 and rows[0]["floor: outcome"] == outcome_text(study.rows[0])
    assert rows[0]["floor: outcome"].startswith("undecided: the 0.05 s run is shorter than two steps (31.4 s each")
    assert (out / "floor_springs.png").stat().st_size > 10_000
    for argv, word in (
        (["--study", "--ground", "weld"], "--study"),
        (["--study", "--scenario", "quasi-static"], "scenarios"),
        (["--study", "--scenario", "9"], "scenario"),
        (["--study", "--duration", "-1"], "duration"),
        (["--study", "--scenario", "1", "--duration", "0.05"], "exists"),
    ):
        assert main(["simulate", *argv, "--out", str(out)]) == 2
        err = capsys.readouterr().err.strip()
        assert word in err and "\n" not in err and "Traceback" not in err, err


@pytest.mark.slow
@pytest.mark.integration
def test_analyze_floor_section_links_its_figure_and_states_its_facts(analyzed):
    """``pasibot analyze``'s floor section, as the plain install wrote it: the figure linked, the CSV written, the
    summary's row quoting the CSV's run1 row with the fitted spring (the start, both pitches, the outcome)."""
    import csv

    from pasibot_pin.report.floor_static import case_rows
    from pasibot_pin.studies.floor_static import floor_static_study

    section, out = analyzed.section("The spring study on the floor"), analyzed.folder
    assert "](floor_springs.png)" in section and (out / "floor_springs.csv").is_file()
    assert_reads_like_a_report(out, section, 1, shared=True)
    with (out / "floor_springs.csv").open(encoding="utf-8") as f:
        fitted = next(r for r in csv.DictReader(f) if r["run"] == "run1" and r["spring"] == "fitted")
    (row,) = [line for line in analyzed.section("Summary").splitlines() if "on a real floor (run 1)" in line]
    floor_pitch, weld_pitch = fitted["floor: max pitch in 2 s [deg]"], fitted["weld: max pitch in 2 s [deg]"]
    assert f"the largest hip pitch over 2 s is {floor_pitch}° against {weld_pitch}° welded" in row
    assert f"({fitted['floor: start'].split()[0]})" in row and fitted["floor: outcome"] in row
    # runs 1-4 answered quasi-statically (exact statics), the rows those of the library's study
    quasi = section.split("### Quasi-static")[1]
    for case in case_rows(floor_static_study(("run4",), sweep=False)):
        assert "| " + " | ".join(case.values()) + " |" in quasi
    for run in ("run1", "run2", "run3"):
        assert quasi.count(f"| {run} |") == 4


def test_the_settling_start_is_the_same_simulator_held_at_theta0():
    """The settled start steps this simulator with its cranks held (no second simulator): it stands
    where a simulator built with omega = 0 settles, bit for bit, and the run after it is unchanged by
    the settling (its QP and rows are its own)."""
    from dataclasses import replace

    from pasibot_pin.studies.spring_study import scenario_inputs

    inputs = scenario_inputs("run1")
    settings = FloorSettings(omega=inputs.omega, spring=inputs.fit)
    sim = FloorSimulator(inputs.robot, settings)
    start = sim.start_state()
    assert start.kind == "settled"
    held = FloorSimulator(inputs.robot, replace(settings, omega=0.0)).start_state()  # a robot whose cranks never turn
    np.testing.assert_array_equal(start.q, held.q)
    assert start.settle_time == held.settle_time
    assert not hasattr(sim, "_held_sim")
