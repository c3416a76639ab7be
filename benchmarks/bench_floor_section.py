"""Benchmark: the CPU time of ``pasibot analyze``'s floor section, job by job (``report.floor.FloorPlan``).

The floor section is four ``floor: case`` jobs (run 1's spring cases, each weld against floor:
:func:`~pasibot_pin.studies.weld_vs_floor.compare_case`, whose floor run steps the contact
QP about 2,900 times) and one ``floor: static`` job (runs 2-4's quasi-static answers). Each
repetition runs them one at a time in a fresh child process, as ``benchmarks/bench_demo.py
--breakdown`` does (run 1's inputs computed before the clock starts, as the analysis's other
sections have by then), and times each job by the process CPU time (``time.process_time``);
the best of ``--repeat`` repetitions is printed per job, with the floor runs' QP solves split
into the exact active-set ones and proxsuite's.

Run: ``.venv/bin/python benchmarks/bench_floor_section.py [--repeat 3]``. Any checkout's venv
runs it on its own code (``/path/to/other/.venv/bin/python benchmarks/bench_floor_section.py``),
so a before/after pair is two commands in the same session.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def one_run() -> dict[str, float]:
    """Every job of the floor section once, here: CPU [s] per job key, and the QP counts."""
    from pasibot_pin.report.floor import FloorPlan
    from pasibot_pin.studies.simulation_study import cached_inputs

    try:  # absent before the exact active-set solve: then every QP is proxsuite's
        from pasibot_pin.dynamics.floor import qp as floor_qp
    except ImportError:
        floor_qp = None
    solvers: list = []
    if floor_qp is not None:
        init = floor_qp.ContactQP.__init__

        def counted(self, *args, **kwargs):
            init(self, *args, **kwargs)
            solvers.append(self)

        floor_qp.ContactQP.__init__ = counted
    cached_inputs("run1")
    out: dict[str, float] = {}
    with tempfile.TemporaryDirectory(prefix="pasibot-bench-floor-") as folder:
        plan = FloorPlan(Path(folder))
        for job in plan.jobs():
            start = time.process_time()
            job.fn(*job.args)
            out[" ".join(job.key)] = time.process_time() - start
    out["QP solves: exact"] = float(sum(s.fast for s in solvers))
    out["QP solves: proxsuite"] = float(sum(s.fallback for s in solvers))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="repetitions (best of) [-]")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(one_run()))
        return
    runs = []
    for _ in range(max(1, args.repeat)):
        done = subprocess.run([sys.executable, __file__, "--child"], check=True, capture_output=True, text=True)
        runs.append(json.loads(done.stdout.strip().splitlines()[-1]))
    keys = [k for k in runs[0] if not k.startswith("QP")]
    best = {k: min(r[k] for r in runs) for k in keys}
    for k in keys:
        print(f"{k:28s} {best[k]:6.2f} s CPU (best of {len(runs)})")
    cases = sum(v for k, v in best.items() if k.startswith("case"))
    print(f"{'floor: case (sum)':28s} {cases:6.2f} s")
    print(f"{'floor section (sum)':28s} {sum(best.values()):6.2f} s")
    fast, slow = runs[0]["QP solves: exact"], runs[0]["QP solves: proxsuite"]
    print(f"QP solves of the floor runs: {fast:.0f} exact active-set, {slow:.0f} proxsuite")


if __name__ == "__main__":
    main()
