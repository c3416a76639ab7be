"""Benchmark: a design sweep, designs per second, memory as the sweep grows.

Runs ``pasibot sweep``'s library call (:func:`pasibot_pin.explore.sweep.run_sweep`) on the default
ranges (Latin hypercube around the seed design: K, L4, L5, sole, body COM and mass), with every
metric (path, torques, spring fit, contact, energy), into a temporary folder, on a local process
pool of ``--workers`` processes; then the same with 5x fewer designs. Prints wall time, CPU time of
the main process and the workers, designs per second, and the largest resident memory of the main
process and of any worker, for both sizes: flat memory means results stream to disk.

Goal (issue 13): 1,000 designs < 60 s wall on 2 cores; 10,000 < 10 min.

Run: ``.venv/bin/python benchmarks/bench_sweep.py [--n 1000] [--workers 2]``.
"""

from __future__ import annotations

import argparse
import os
import resource
import tempfile
import time

from pasibot_pin.explore.plan import SweepPlan
from pasibot_pin.explore.sweep import run_sweep


def one(n: int, workers: int) -> dict:
    before = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        result = run_sweep(SweepPlan(n=n), os.path.join(tmp, "run"), workers=workers, progress=False)
        wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = sum(a.ru_utime + a.ru_stime - b.ru_utime - b.ru_stime for a, b in zip(after, before))
    return {
        "n": n,
        "wall": wall,
        "cpu": cpu,
        "feasible": result.feasible,
        "rss_main_MB": after[0].ru_maxrss / 1024,
        "rss_worker_MB": after[1].ru_maxrss / 1024,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=1000)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    print(f"machine: {os.cpu_count()} cores; {args.workers} workers")
    for n in (max(1, args.n // 5), args.n):
        r = one(n, args.workers)
        print(
            f"{r['n']:6d} designs: {r['wall']:6.1f} s wall, {r['cpu']:6.1f} s CPU, "
            f"{r['n'] / r['wall']:5.1f} designs/s, "
            f"{r['feasible']} feasible; max RSS main {r['rss_main_MB']:.0f} MB, worker {r['rss_worker_MB']:.0f} MB"
        )
    print(f"goal: {args.n} designs < 60 s wall on 2 cores (scaled to 1000: {r['wall'] * 1000 / args.n:.1f} s)")


if __name__ == "__main__":
    main()
