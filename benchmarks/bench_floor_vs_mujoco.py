"""Benchmark: simulated seconds per CPU second, our floor against MuJoCo, on the same walker.

The walker: the parallel variant with 4.5 L soles each side at 1 rad/s (it walks in both
engines, ``tests/test_mujoco_walk.py``). Measured in one run, each from the same consistent
start (the flat double support) for :data:`DURATION` simulated seconds, CPU time
(``time.process_time``, so other processes on the machine count less):

1. ours: ``FloorSimulator.run`` with :func:`~pasibot_pin.studies.walking.walk_design`'s settings
   (its own step, ``walk_dt``: 1 ms at 1 rad/s), no verdict stop;
2. MuJoCo, bare: ``mj_step`` on the exported model (:data:`~pasibot_pin.studies.twin.mujoco_walk.MJ_WALK`:
   stiff floor and friction, crank drives as equality constraints) at its own step
   (0.1 ms), the drives set on the crank schedule every step (the least a walk needs);
3. MuJoCo, the twin: the same with the judge's samples (``walk_in_mujoco``'s loop: contact
   forces every step, a verdict sample every ms), for the cost of judging in Python.

:data:`REPEAT` rounds of the three, interleaved (the machine's speed drifts by 2x within minutes):
prints each engine's best rate and the median over the rounds of the ratio ours / MuJoCo (the
walking issue's goal: ours >= 2 x MuJoCo's).

Run: ``.venv/bin/python benchmarks/bench_floor_vs_mujoco.py``.
"""

from __future__ import annotations

import math
import statistics
import time

from pasibot_pin.dynamics.floor.engine import FloorSimulator
from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.studies.twin.mujoco_walk import SAMPLE_DT, _Twin, mujoco_options
from pasibot_pin.studies.walking import WalkSettings, floor_settings

DURATION = 3.0
"""Simulated time of each run [s] (the ramp, double support and most of the first step)."""
REPEAT = 5
"""Rounds of the three runs, interleaved; a rate is the best round's, a ratio the median of the rounds' ratios."""
WALKER = Design(variant="parallel", parallel_toe=4.5, parallel_heel=4.5, omega=1.0)


def ours_rate(robot, settings: WalkSettings) -> tuple[float, float]:
    """(simulated s per CPU s, dt [s]) of our floor simulator on :data:`WALKER`."""
    sim = FloorSimulator(robot, floor_settings(WALKER, settings, robot))
    start = sim.start_state()
    begin = time.process_time()
    sim.run(DURATION, start.q, start.v)
    return DURATION / (time.process_time() - begin), sim.settings.dt


def mujoco_rate(robot, settings: WalkSettings, judged: bool) -> tuple[float, float]:
    """(simulated s per CPU s, dt [s]) of MuJoCo on the exported :data:`WALKER` (bare or judged)."""
    import mujoco

    twin = _Twin(mujoco, robot, WALKER, settings, mujoco_options(WALKER, settings, robot))
    model, data = twin.model, twin.data
    h = float(model.opt.timestep)
    n = math.ceil(DURATION / h - 1e-9)
    every = max(1, round(SAMPLE_DT / h))
    begin = time.process_time()
    if judged:
        for k in range(n):
            twin.step(k * h)
            if (k + 1) % every == 0:
                twin.sample((k + 1) * h)
    else:
        for k in range(n):
            angle, rate = twin.schedule(k * h)
            model.eq_data[twin.drives, 0] = angle + twin.lead * rate
            mujoco.mj_step(model, data)
    return n * h / (time.process_time() - begin), h


def main() -> None:
    robot = design_robot(WALKER, 2, visuals=False)
    settings = WalkSettings(steps=4)
    ours, bare, judged = [], [], []
    for _ in range(REPEAT):  # interleaved: a pair measured back to back sees the same machine
        ours.append(ours_rate(robot, settings))
        bare.append(mujoco_rate(robot, settings, judged=False))
        judged.append(mujoco_rate(robot, settings, judged=True))
    dt, h = ours[0][1], bare[0][1]
    print(f"walker: parallel, 4.5 L soles, omega = 1 rad/s; {DURATION:g} s simulated from the flat double support")
    print(f"{REPEAT} interleaved rounds, CPU time; a rate is the best round's, a ratio the median of the rounds'")
    rows = (
        (f"ours (FloorSimulator, dt {dt * 1e3:g} ms)", ours),
        (f"MuJoCo bare (mj_step, dt {h * 1e3:g} ms)", bare),
        (f"MuJoCo twin (walk_in_mujoco's loop, dt {h * 1e3:g} ms)", judged),
    )
    for label, rates in rows:
        print(f"{label:<46}: {max(r for r, _ in rates):7.3f} simulated s per CPU s")
    for label, rates, goal in (("bare", bare, "   (goal >= 2)"), ("twin", judged, "")):
        ratios = [o / m for (o, _), (m, _) in zip(ours, rates)]
        spread = f"rounds {min(ratios):.2f}-{max(ratios):.2f}"
        print(f"ours / MuJoCo {label}: {statistics.median(ratios):6.2f}   ({spread}){goal}")


if __name__ == "__main__":
    main()
