"""Benchmark: one floor step against one welded RK4 step, and the wall time of 10 s on the floor.

Measured in one run, on run 1 with the fitted ankle spring (the ``spring`` biped, nv = 19):

1. one step of :class:`~pasibot_pin.dynamics.simulator.BipedSimulator` (stance foot welded,
   RK4 with projection and velocity impulse, its 2 ms step);
2. one step of :class:`~pasibot_pin.dynamics.floor.FloorSimulator` (the contact QP,
   :mod:`~pasibot_pin.dynamics.floor.qp`; implicit springs, projection, its 1 ms step) from the
   consistent start with the cranks turning, heel and toe contacts active; per step and per
   simulated second;
3. ``FloorSimulator.run(10.0)`` from the consistent start (settling included): its wall time
   and outcome (goals: a floor step <= 2 x the welded step; 10 s simulated < 10 s wall).

Run: ``.venv/bin/python benchmarks/bench_floor.py`` (or ``make bench``).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from bench_dynamics import best_time  # noqa: E402  (one timing rule for every benchmark)

from pasibot_pin.dynamics import simulator as simulate
from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.dynamics.floor.settings import FloorSettings
from pasibot_pin.studies import spring_study

WELD_DT = 2e-3
"""The welded simulator's step here [s] (its spring-swing default)."""
DURATION = 10.0
"""Simulated time of the floor run [s]."""


def main() -> None:
    inputs = spring_study.scenario_inputs("run1")
    weld = simulate.BipedSimulator(
        inputs.robot, simulate.SimulationSettings(omega=inputs.omega, spring=inputs.fit, dt=WELD_DT)
    )
    q0, v0, stance = weld.initial_state()
    cset = weld.constraint_set(stance, weld.ground_weld(stance, q0))
    t_weld = best_time(lambda: weld.step(cset, 0.0, q0, v0, WELD_DT), repeat=50)

    floor = FloorSimulator(inputs.robot, FloorSettings(omega=inputs.omega, spring=inputs.fit))
    start = floor.start_state()
    h = floor.settings.dt
    fq, fv, *_ = floor.step(0.0, start.q, start.v, h)  # the cranks turning, heel and toe loaded
    t_floor = best_time(lambda: floor.step(h, fq, fv, h), repeat=50)

    begin = time.perf_counter()
    res = floor.run(DURATION)
    wall = time.perf_counter() - begin
    simulated = float(res.t[-1]) if len(res.t) else 0.0

    print(f"one welded RK4 step ({WELD_DT * 1e3:g} ms)      : {t_weld * 1e6:8.1f} us")
    print(f"one floor step ({h * 1e3:g} ms, QP + projection) : {t_floor * 1e6:8.1f} us")
    print(f"floor step / welded step           : {t_floor / t_weld:8.2f}   (goal <= 2)")
    print(
        f"floor / welded per simulated second: {(t_floor / h) / (t_weld / WELD_DT):8.2f}   "
        f"(the floor takes {WELD_DT / h:g} steps per welded step)"
    )
    print(
        f"floor run of {DURATION:g} s (consistent start included): {wall:6.2f} s wall for {simulated:.3f} s simulated "
        f"({res.outcome}); {wall / max(simulated, h) * DURATION:6.2f} s wall per {DURATION:g} s   (goal < {DURATION:g})"
    )


if __name__ == "__main__":
    main()
