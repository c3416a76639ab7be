"""Benchmark: what a new process pays to build design robots (every ``pasibot`` command and test worker does).

Each round starts a fresh Python that imports :mod:`pasibot_pin.model.design`, then builds the default design of
every variant (``design_robot(Design(variant=v), 2, visuals=False)``: the fast tree, from the placement map on
the disk cache, :mod:`pasibot_pin.model.placements`), and reports the CPU of the import and of the robots. Beside
each round, this process measures ``bench_demo.py``'s reference workload (bare ``pin.rnea`` calls on the spring
biped). :data:`REPEAT` rounds; prints each figure's median and the robots' CPU over the reference's, a ratio the
machine's speed changes far less than seconds.

The cache is warmed by a first process (not counted). Run: ``.venv/bin/python benchmarks/bench_start.py``.
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys

from bench_demo import REFERENCE_CALLS, reference

REPEAT = 5
"""Fresh processes measured."""

CHILD = """
import json, time
start = time.process_time()
from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.model.params import VARIANTS
imported = time.process_time()
robots = [design_robot(Design(variant=v), 2, visuals=False) for v in VARIANTS]
print(json.dumps({"import": imported - start, "robots": time.process_time() - imported, "n": len(robots)}))
"""


def one_process() -> dict:
    """The figures of one fresh process [s], and the reference workload's, measured here right after [s]."""
    done = subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True, check=True)
    return {**json.loads(done.stdout.splitlines()[-1]), "reference": reference()}


def main() -> None:
    subprocess.run([sys.executable, "-c", CHILD], capture_output=True, check=True)  # warms the maps' disk cache
    rounds = [one_process() for _ in range(REPEAT)]
    median = {key: statistics.median(r[key] for r in rounds) for key in ("import", "robots", "reference")}
    ratios = [r["robots"] / r["reference"] for r in rounds]
    print(f"{REPEAT} fresh processes, CPU time, medians")
    print(f"import pasibot_pin.model.design : {median['import']:.3f} s")
    print(f"{rounds[0]['n']} design robots (one per variant) : {median['robots']:.3f} s")
    print(f"reference ({REFERENCE_CALLS:,} bare pin.rnea)  : {median['reference']:.3f} s")
    print(f"robots / reference: {statistics.median(ratios):.3f}   (rounds {min(ratios):.3f}-{max(ratios):.3f})")


if __name__ == "__main__":
    main()
