"""Benchmark: the CPU of the ``simulation`` section's compute (spring cases, sweep rows, the check).

Runs every job of :class:`~pasibot_pin.report.simulation.SimulationPlan` that computes (its spring
cases, sweep rows and check; not the figures nor the animation) serially in this process,
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


def _answers(key: tuple, result) -> dict[str, np.ndarray]:
    """The arrays of one job's result, under names starting with the piece's kind and scenario."""
    out: dict[str, np.ndarray] = {}
    if key[0] == "cases":
        for (name, label), outcome in zip(key[1], result):
            out.update(_answers(("case", name, label), outcome))
        return out
    if key[0] == "rows":
        for row, values in zip(key[2], result):
            out.update(_answers(("row", key[1], row), values))
        return out
    name = "/".join(str(k) for k in key)
    if key[0] == "row":
        out[name] = np.asarray(result, dtype=float)
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


KINDS = {"case": "case", "cases": "case", "row": "row", "rows": "row", "check": "check"}
"""The plan's computing jobs by kind (its ``meta`` jobs, fits already cached, are left out)."""


def run_pieces(settings: sim.SimulationStudySettings) -> tuple[dict[str, float], dict[str, np.ndarray]]:
    """Every computing job of the section's plan once, serially: CPU [s] per kind and the answers."""
    from pasibot_pin.report.simulation import SimulationPlan

    cpu = {"case": 0.0, "row": 0.0, "check": 0.0}
    answers: dict[str, np.ndarray] = {}
    jobs = [job for job in SimulationPlan(Path("unused"), settings).jobs() if job.key[0] in KINDS]
    for job in jobs:
        start = time.process_time()
        result = job.fn(*job.args)
        used = time.process_time() - start
        kind = KINDS[job.key[0]]
        cpu[kind] += used
        inner = job.key[1] if len(job.key) > 1 else ""
        label = f"{kind} {inner if isinstance(inner, str) else 'slow scenarios'}"
        cpu[label] = cpu.get(label, 0.0) + used
        answers.update(_answers(job.key, result))
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
