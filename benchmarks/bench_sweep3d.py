"""Benchmark: a 3-D walking sweep (``pasibot sweep --floor 20 --3d``), wall and CPU time per design.

Runs :func:`pasibot_pin.explore.sweep.run_sweep` with every design walked up to 20 steps on the 3-D
floor (free hip, the designs' soles), on a local process pool, in two design spaces:

* ``default``: the sweep's default ranges around the seed's design (centred soles: nearly every
  design tips within its first steps, so this is the sweep's fixed cost per design);
* ``comb``: around the comb-soled walker of ``designs/3d/`` (``--vary omega=1:4
  parallel_toe=3:8 parallel_heel=3:8``): many designs walk all 20 steps, which is the cost that
  matters.

Prints, for each, the wall and CPU time, how many designs walk, the CPU per design and the wall time
that 200 designs would take at the same rate. Goal (issue 32): 200 designs < 10 min wall on 2 cores.

Run: ``.venv/bin/python benchmarks/bench_sweep3d.py [--n 20] [--workers 2] [--space comb|default|both]``.
"""

from __future__ import annotations

import argparse
import math
import os
import resource
import tempfile
import time

from pasibot_pin.explore.plan import Range, SweepPlan
from pasibot_pin.explore.store import column
from pasibot_pin.explore.sweep import run_sweep
from pasibot_pin.model.design import load_design

COMB = "designs/3d/upright_fastest_comb0.6L_omega2.toml"
COMB_RANGES = (Range("omega", 1.0, 4.0), Range("parallel_toe", 3.0, 8.0), Range("parallel_heel", 3.0, 8.0))
GOAL_DESIGNS, GOAL_WALL = 200, 600.0


def one(space: str, n: int, workers: int) -> dict:
    """One sweep of ``n`` designs in ``space``: its wall and CPU time [s] and how many walk."""
    if space == "comb":
        plan = SweepPlan(n=n, base=load_design(COMB), ranges=COMB_RANGES, floor=20, spatial=True)
    else:
        plan = SweepPlan(n=n, floor=20, spatial=True)
    before = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        result = run_sweep(plan, os.path.join(tmp, "run"), workers=workers, progress=False)
        wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = sum(a.ru_utime + a.ru_stime - b.ru_utime - b.ru_stime for a, b in zip(after, before))
    walks = column(result.table, "floor_walks").astype(float)
    walkers = int(sum(w for w in walks if not math.isnan(w)))
    return {"space": space, "n": n, "wall": wall, "cpu": cpu, "walkers": walkers}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=20)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--space", choices=("comb", "default", "both"), default="both")
    args = parser.parse_args()
    print(f"machine: {os.cpu_count()} cores; {args.workers} workers; load {os.getloadavg()[0]:.1f}")
    for space in ("default", "comb") if args.space == "both" else (args.space,):
        r = one(space, args.n, args.workers)
        scaled = r["wall"] * GOAL_DESIGNS / r["n"]
        print(
            f"{space:8s} {r['n']:4d} designs, {r['walkers']} walk 20 steps: {r['wall']:6.1f} s wall, "
            f"{r['cpu']:6.1f} s CPU ({r['cpu'] / r['n']:.1f} s per design); {GOAL_DESIGNS} designs at this rate: "
            f"{scaled / 60:.1f} min wall (goal < {GOAL_WALL / 60:.0f})"
        )


if __name__ == "__main__":
    main()
