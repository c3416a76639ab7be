"""Benchmark: the CPU time of ``pasibot walk --stability`` on the fastest walker, with the default steps.

Runs ``walk --design designs/fastest_*.toml --stability --json`` in this process (its modules imported
before the clock starts; the walk, the section state, Newton's attempt and the fitted step map are
timed) and prints its CPU time [s] and that time over the reference workload of
``benchmarks/bench_demo.py`` (:func:`bench_demo.reference`, ``pin.rnea`` on the spring biped, timed
here just before), so a regression shows as a ratio that depends on the machine far less than seconds do
(machines differ 2-3x in seconds; the tests assert no time). Issue 34's goal: under 30 s of CPU.

Run: ``.venv/bin/python benchmarks/bench_stability.py [--repeat N]`` (or ``make bench``).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from bench_demo import REFERENCE_CALLS, reference  # noqa: E402  (one reference workload for every ratio)

ROOT = Path(__file__).resolve().parents[1]
GOAL_CPU = 30.0
"""Issue 34's goal for ``walk --stability`` on the fastest walker [s of CPU]."""


def fastest() -> Path:
    """The fastest walker's design file in ``designs/`` (its name starts with ``fastest_``)."""
    found = sorted((ROOT / "designs").glob("fastest_*.toml"))
    if len(found) != 1:
        raise SystemExit(f"expected one designs/fastest_*.toml, found {len(found)}")
    return found[0]


def one_run(design: Path) -> tuple[float, dict]:
    """``walk --stability --json`` once, here: its CPU time [s] and its JSON."""
    from pasibot_pin.__main__ import main as pasibot

    out = io.StringIO()
    start = time.process_time()
    with contextlib.redirect_stdout(out):
        code = pasibot(["walk", "--design", str(design), "--stability", "--json"])
    cpu = time.process_time() - start
    if code != 0:
        raise SystemExit(f"pasibot walk --stability exited {code}")
    return cpu, json.loads(out.getvalue())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=1, help="repetitions (best of) [-]")
    args = parser.parse_args()
    design = fastest()
    import pasibot_pin.__main__  # noqa: F401  (imported before the clock starts)

    ref = reference()
    runs = [one_run(design) for _ in range(max(1, args.repeat))]
    cpu = min(c for c, _ in runs)
    record = runs[0][1]
    radius = max((abs(complex(*z)) for z in record.get("multipliers") or ()), default=float("nan"))
    print(f"reference workload ({REFERENCE_CALLS:,} pin.rnea) : {ref:6.2f} s CPU")
    print(f"walk --stability on {design.name}: {cpu:6.2f} s CPU (best of {len(runs)})   (goal < {GOAL_CPU:g} s)")
    print(f"ratio to the reference workload     : {cpu / ref:6.1f}x")
    print(f"verdict {record.get('outcome')}, stable {record.get('stable')}, largest |multiplier| {radius:.3f}")


if __name__ == "__main__":
    main()
