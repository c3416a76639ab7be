"""The figures the redesign must not lose, computed through the public API.

``compute()`` returns a flat dict of arrays: K_e per scenario and preset, torque curves and
every reaction, closure residuals and configurations, path metrics, a walk, contact, energy,
the single motor and simulated hip-pitch traces. They were recorded once, before the
constraint core was rewritten, into ``tests/data/golden_figures.npz`` with

    .venv/bin/python tests/golden_figures.py --write

and ``tests/test_regression.py`` recomputes them with today's code and compares. The file is
never rewritten by the tests: a changed figure is a failing test, not a new golden value.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

GOLDEN = Path(__file__).parent / "data" / "golden_figures.npz"

SCENARIO_NAMES = ("quasi-static", "run1", "run2", "run3", "run4")
PRESET_NAMES = ("default", "seed", "seed-clean")


def _api():
    """Today's public API under stable names (the only place to edit when functions move)."""
    from types import SimpleNamespace

    import pasibot_pin as pp
    from pasibot_pin.dynamics import inverse as dynamics
    from pasibot_pin.dynamics import simulator as simulate
    from pasibot_pin.kinematics import gait, path_metrics
    from pasibot_pin.kinematics import leg as kinematics
    from pasibot_pin.model import scenarios
    from pasibot_pin.model.scenario_robots import scenario_robot
    from pasibot_pin.studies import contact, energy, single_motor, spring_study
    from pasibot_pin.studies.methods import spring_fit as spring

    def run_scenario(name, preset):
        return dynamics.run_scenario(scenarios.get_scenario(name), scenarios.get_preset(preset))

    def coupled_split(result):
        robot = scenario_robot(scenarios.get_scenario("run4"), scenarios.get_preset("default"))
        return single_motor.coupled_split(robot, result)

    return SimpleNamespace(
        load=pp.load,
        run_scenario=run_scenario,
        preset=scenarios.get_preset,
        fit_result=spring.fit_result,
        straight_line_metrics=path_metrics.straight_line_metrics,
        leg_cycle=kinematics.leg_cycle,
        crank_grid=kinematics.crank_grid,
        prescribed_gait=gait.prescribed_gait,
        scenario_contact=contact.scenario_contact,
        spring_step_energy=energy.spring_step_energy,
        parallel_step_energy=energy.parallel_step_energy,
        coupled_split=coupled_split,
        scenario_inputs=spring_study.scenario_inputs,
        SimulationSettings=simulate.SimulationSettings,
        simulate=simulate.simulate,
    )


def _torque_curves(out: dict, key: str, result) -> None:
    for name in ("beta", "beta_swing", "Ta", "Te", "Ta_swing", "Te_swing", "theta"):
        out[f"{key}/{name}"] = np.asarray(getattr(result, name), dtype=float)
    out[f"{key}/q"] = result.q
    out[f"{key}/ground"] = result.ground
    for name, arr in result.cuts.items():
        out[f"{key}/cut/{name}"] = arr
    for name, arr in result.joints.items():
        out[f"{key}/joint/{name}"] = arr


def torques(out: dict) -> None:
    """K_e of every scenario under every preset; torque curves and reactions of three runs."""
    api = _api()

    for scenario in SCENARIO_NAMES:
        for preset in PRESET_NAMES:
            result = api.run_scenario(scenario, preset)
            fit = api.fit_result(result, api.preset(preset).fit_thetas, warn=False)
            out[f"K_e/{scenario}/{preset}"] = np.array([fit.K_e, fit.beta0, fit.r2])
            if (scenario, preset) in (("run1", "default"), ("run4", "default"), ("run4", "seed")):
                _torque_curves(out, f"torques/{scenario}/{preset}", result)


def closure_and_paths(out: dict) -> None:
    """q0 of every model; straight-line metrics and a leg cycle of every variant; a walk."""
    api = _api()

    for variant in ("rigid", "parallel", "spring"):
        for legs in (1, 2):
            out[f"q0/{variant}/{legs}"] = api.load(variant, legs).q0
        leg = api.load(variant, 1)
        m = api.straight_line_metrics(leg)
        out[f"metrics/{variant}"] = np.array(
            [
                m.ground_z,
                m.lowest_z,
                m.stroke,
                m.ankle_band,
                m.deviation,
                *m.deviation_theta,
                m.lift,
                m.lift_theta,
                m.ground_span,
                *m.ground_interval,
                m.stance_pitch_max,
                *m.stance_pitch_range,
                m.pitch_at_zero,
            ]
        )
        cycle = api.leg_cycle(leg, api.crank_grid(math.radians(10)), omega=0.1)
        for name in ("ankle", "toe", "heel", "foot_pitch", "ankle_velocity", "ankle_acceleration"):
            out[f"cycle/{variant}/{name}"] = np.asarray(getattr(cycle, name))
        w = api.prescribed_gait(api.load(variant, 2), 2, 12, omega=0.1)
        out[f"walk/{variant}/q"] = w.q


def contact_energy_motor(out: dict) -> None:
    """Heel/toe contact of run 1 (both variants), energy per step, the single motor."""
    api = _api()

    for variant in ("spring", "parallel"):
        torques_result, contact = api.scenario_contact("run1", variant=variant, samples=24)
        for name in ("s_cop", "margin", "mu_needed", "heel_force", "toe_force", "wrench"):
            out[f"contact/{variant}/{name}"] = np.asarray(getattr(contact, name), dtype=float)
        out[f"contact/{variant}/Ta"] = np.asarray(torques_result.Ta)
    step, _ = api.spring_step_energy(0.5, nodes=12)
    par, _ = api.parallel_step_energy(0.5, nodes=12)
    for key, e in (("spring", step), ("parallel", par)):
        out[f"energy/{key}"] = np.array(
            [e.distance, *e.crank, *e.single, *e.ankle, e.energy_start, e.energy_end, e.single_peak, e.single_rms]
            + [e.cot[k] for k in sorted(e.cot)]
            + [e.spring[k] for k in sorted(e.spring)]
        )
    result = api.run_scenario("run4", "default")
    motor = api.coupled_split(result)
    out["single_motor/run4/motor"] = motor.motor
    out["single_motor/run4/transmission"] = motor.transmission


def simulations(out: dict) -> None:
    """Hip-pitch traces: run 1 with the fitted spring (0.4 s), a 3-step walk at 5 rad/s."""
    api = _api()

    inputs = api.scenario_inputs("run1")
    settings = api.SimulationSettings(omega=inputs.omega, spring=inputs.fit, dt=2e-3)
    res = api.simulate(inputs.robot, settings, duration=0.4)
    out["sim/run1/hip_pitch"] = res.hip_pitch
    out["sim/run1/motor_torque"] = res.motor_torque
    inputs = api.scenario_inputs("run4")
    settings = api.SimulationSettings(omega=5.0, spring=inputs.fit, swing_ankle="rest", dt=1e-2)
    res = api.simulate(inputs.robot, settings, steps=3)
    out["sim/walk5/hip_pitch"] = res.hip_pitch
    out["sim/walk5/motor_torque"] = res.motor_torque
    out["sim/walk5/impacts"] = np.array(
        [[i.t, i.height, i.pitch, i.kinetic_before, i.kinetic_after] for i in res.impacts]
    )


GROUPS = {
    "torques": torques,
    "closure_and_paths": closure_and_paths,
    "contact_energy_motor": contact_energy_motor,
    "simulations": simulations,
}


def compute(groups=tuple(GROUPS)) -> dict[str, np.ndarray]:
    """Every figure of the named groups, by key."""
    out: dict[str, np.ndarray] = {}
    for name in groups:
        GROUPS[name](out)
    return {k: np.asarray(v, dtype=float) for k, v in out.items()}


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true", help=f"record the figures into {GOLDEN}")
    args = parser.parse_args()
    sys.path.insert(0, str(Path(__file__).parent))
    figures = compute()
    if args.write:
        if GOLDEN.exists():
            sys.exit(f"{GOLDEN} exists: the golden figures are recorded once; delete it by hand to re-record")
        GOLDEN.parent.mkdir(parents=True, exist_ok=True)
        np.savez_compressed(GOLDEN, **figures)
        print(f"wrote {len(figures)} figures to {GOLDEN}")
    else:
        print(f"{len(figures)} figures")
