"""Benchmark: the CPU of the ``simulation`` section's compute (spring cases, sweep rows, the check).

Runs every piece of :class:`~pasibot_pin.report.simulation.SimulationPlan` that computes (the
``case``, ``row`` and ``check`` jobs, not the figures nor the animation) serially in this process,
after warming the scenario inputs (:func:`~pasibot_pin.studies.simulation_study.cached_inputs`,
the inverse dynamics: not this section's work), and prints the process CPU time of each kind.

``--save FILE`` stores every answer (static paths, walks, sweep rows) in an ``.npz``; ``--compare
FILE`` compares this run's answers with a stored file: the largest relative change per kind (0
when bit for bit), so a speed change can be checked to give the same numbers.

Run: ``.venv/bin/python benchmarks/bench_studies.py [--repeat N] [--save F | --compare F]``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from pasibot_pin.model.scenarios import SCENARIOS
from pasibot_pin.studies import simulation_study as sim
from pasibot_pin.studies.spring_study import SPRING_CASES


def _answers(key: tuple, result) -> dict[str, np.ndarray]:
    """The arrays of one job's result, under names starting with the job's key."""
    name = "/".join(str(k) for k in key)
    out: dict[str, np.ndarray] = {}
    if key[0] == "row":
        for i, row in enumerate(result):
            out[f"{name}/{i}"] = np.asarray(row, dtype=float)
        return out
    static, run = result if key[0] == "case" else (None, result)
    if static is not None:
        out[f"{name}/static_pitch"] = static.hip_pitch
        out[f"{name}/static_stiffness"] = static.stiffness
    if run is not None:
        out[f"{name}/t"] = run.t
        out[f"{name}/q"] = run.q
        out[f"{name}/v"] = run.v
        out[f"{name}/motor_torque"] = run.motor_torque
        out[f"{name}/drift"] = run.drift
        out[f"{name}/swing_height"] = run.swing_height
    return out


def run_pieces(settings: sim.SimulationStudySettings) -> tuple[dict[str, float], dict[str, np.ndarray]]:
    """Every case, row and check job once, serially: CPU [s] per kind and the answers."""
    cpu = {"case": 0.0, "row": 0.0, "check": 0.0}
    cpu.update({f"{kind} {name}": 0.0 for name in settings.scenarios for kind in ("case", "row")})
    answers: dict[str, np.ndarray] = {}
    jobs = []
    for name in settings.scenarios:
        jobs += [(("case", name, label), sim.case_task, (name, label, settings)) for label, _ in SPRING_CASES]
        rows = tuple(range(sim.sweep_shape(name)[0]))
        jobs.append((("row", name), sim.sweep_rows_task, (name, rows, settings)))
    jobs.append((("check",), sim.check_task, (settings,)))
    for key, fn, args in jobs:
        start = time.process_time()
        result = fn(*args)
        cpu[key[0]] += time.process_time() - start
        if len(key) > 1:
            cpu[f"{key[0]} {key[1]}"] += time.process_time() - start
        answers.update(_answers(key, result))
    return cpu, answers


def compare(answers: dict[str, np.ndarray], stored: dict[str, np.ndarray]) -> dict[str, float]:
    """Largest relative change per kind of array (inf where the shapes or the finite entries differ)."""
    worst: dict[str, float] = {}
    for name in sorted(set(answers) | set(stored)):
        kind = name.split("/")[0] + "/" + name.rsplit("/", 1)[-1] if name.count("/") > 2 else name.split("/")[0]
        a, b = answers.get(name), stored.get(name)
        if a is None or b is None or a.shape != b.shape or not np.array_equal(np.isfinite(a), np.isfinite(b)):
            change = np.inf
        else:
            fin = np.isfinite(a)
            scale = max(float(np.max(np.abs(b[fin]), initial=0.0)), 1e-300)
            change = float(np.max(np.abs(a[fin] - b[fin]), initial=0.0)) / scale
        worst[kind] = max(worst.get(kind, 0.0), change)
    return worst


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=1, help="runs; the best CPU per kind is printed")
    parser.add_argument("--save", type=Path, default=None, help="store the answers in this .npz")
    parser.add_argument("--compare", type=Path, default=None, help="compare the answers with this .npz")
    args = parser.parse_args()
    settings = sim.SimulationStudySettings()
    for name in SCENARIOS:
        sim.cached_inputs(name)  # the inverse dynamics and fits: not this section's compute
    best: dict[str, float] = {}
    answers: dict[str, np.ndarray] = {}
    for _ in range(max(1, args.repeat)):
        sim._static_cache.cache_clear()  # each repeat starts as a fresh worker would
        cpu, answers = run_pieces(settings)
        best = {k: min(best.get(k, np.inf), v) for k, v in cpu.items()}
    total = best["case"] + best["row"]
    print(f"simulation section compute, serial, best of {max(1, args.repeat)} (process CPU):")
    for kind, value in best.items():
        print(f"  {kind:18s} {value:6.2f} s")
    print(f"  {'cases + rows':18s} {total:6.2f} s")
    if args.save is not None:
        np.savez_compressed(args.save, **answers)
        print(f"saved {len(answers)} arrays to {args.save}")
    if args.compare is not None:
        with np.load(args.compare) as data:
            stored = {k: data[k] for k in data.files}
        for kind, change in compare(answers, stored).items():
            print(f"  {kind:32s} largest relative change {change:.3e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
