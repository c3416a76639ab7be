"""Time ``make demo`` (``pasibot analyze``) and say on what machine: the only source of the docs' timings.

Runs ``pasibot analyze --out TMP --force`` once in a child process and prints its wall time, the CPU
time of the child and its workers, and the machine: CPU model, core count, architecture, Python and
Pinocchio versions, and the load average when it started (other work on the machine slows it).
``--write docs/timings.md`` writes that page (``make timings``); the README and docs quote no other
timing (``tests/test_readme_numbers.py`` checks).

``--no-demo`` skips the timed demo (with ``--breakdown``, only the serial run below).

The demo's CPU is also printed over a fixed reference workload timed in this process just before
(:func:`reference`: ``REFERENCE_CALLS`` bare ``pin.rnea`` on the spring biped), so a regression shows
as a ratio that depends on the machine far less than seconds do. Less, not nothing: one commit's ratio
differs between processor models (259dc77's analysis: 20 s of CPU on an Intel Xeon, about 36x by issue
33's account; 47-56x on an AMD EPYC, 2026-11-28).
Two revisions are compared in pairs on one machine, in one session (``farm-bench --vs``).

``--fresh`` also times ``make demo`` in a fresh clone of this checkout (the venv, the plain install
and the analysis: what a newcomer waits for), and ``--write`` puts it in the page.

``--breakdown`` then runs the same analysis once more, in this process and one job at a time,
and prints where its CPU goes: each section (the simulation and floor sections per kind of
piece), and the figures (``save_figure_file``: drawing and PNG writing; the figures' plotting calls
before it are counted in their section) and the GIFs (``save_gif``, whole). The serial run's total
is close to the pool's CPU less the second worker's imports.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def machine() -> str:
    """One line naming the machine."""
    import pinocchio

    model = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as handle:
            model = next(line.split(":", 1)[1].strip() for line in handle if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return (
        f"{os.cpu_count()}-core {platform.machine()} ({model}), {platform.system()}, "
        f"Python {platform.python_version()}, Pinocchio {pinocchio.__version__}"
    )


def measure() -> dict:
    """Run the demo once: wall and CPU time [s], the machine, the load average at the start."""
    load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="pasibot-demo-") as out:
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        subprocess.run(
            [sys.executable, "-m", "pasibot_pin", "analyze", "--out", out, "--force"],
            check=True,
            stdout=subprocess.DEVNULL,
        )
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {"wall": wall, "cpu": cpu, "machine": machine(), "load": load, "date": time.strftime("%Y-%m-%d")}


REFERENCE_CALLS = 200_000
"""Bare ``pin.rnea`` calls of the reference workload [-]."""


def reference() -> float:
    """CPU seconds of the reference workload: :data:`REFERENCE_CALLS` ``pin.rnea`` on the spring biped (nv = 19)."""
    import numpy as np
    import pinocchio as pin

    import pasibot_pin as pp

    robot = pp.load("spring", 2, visuals=False)
    model, data = robot.model, robot.model.createData()
    rng = np.random.default_rng(0)
    v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
    start = time.process_time()
    for _ in range(REFERENCE_CALLS):
        pin.rnea(model, data, robot.q0, v, a)
    return time.process_time() - start


def fresh_demo() -> dict:
    """``make demo`` in a fresh clone of this checkout's HEAD: its wall time [s], install included."""
    root = Path(__file__).resolve().parents[1]
    with tempfile.TemporaryDirectory(prefix="pasibot-fresh-") as folder:
        clone = Path(folder) / "main"
        subprocess.run(["git", "clone", "--quiet", str(root), str(clone)], check=True)
        start = time.perf_counter()
        subprocess.run(["make", "demo"], cwd=clone, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        return {"fresh_wall": time.perf_counter() - start}


def breakdown() -> str:
    """Run the analysis serially here; the CPU [s] of each section and of the figures and GIFs, as text."""
    import argparse
    import functools
    import heapq
    import importlib
    import itertools

    from pasibot_pin import jobs
    from pasibot_pin.cli import analyze

    per_job: list[tuple[float, object]] = []
    drawing = {"figure": [0, 0.0], "gif": [0, 0.0]}

    def serial(queue, on_done, workers=None, preload=()):  # run_jobs' order, one job at a time, timed
        order, ready = itertools.count(), []
        for job in queue:
            heapq.heappush(ready, (-job.estimate, next(order), job))
        while ready:
            job = heapq.heappop(ready)[2]
            start = time.process_time()
            result = job.fn(*job.args)
            per_job.append((time.process_time() - start, job.key))
            for new in on_done(job.key, result) or ():
                heapq.heappush(ready, (-new.estimate, next(order), new))

    def metered(fn, kind):
        @functools.wraps(fn)
        def wrapper(*args, **kwargs):
            start = time.process_time()
            try:
                return fn(*args, **kwargs)
            finally:
                drawing[kind][0] += 1
                drawing[kind][1] += time.process_time() - start

        return wrapper

    import pasibot_pin.report.files as files_module
    import pasibot_pin.viz.animation as animation_module

    savers = {"save_figure_file": metered(files_module.save_figure_file, "figure")}
    savers["save_gif"] = metered(animation_module.save_gif, "gif")
    files_module.save_figure_file, animation_module.save_gif = savers["save_figure_file"], savers["save_gif"]
    for name, _ in analyze.STEPS:  # the sections import the savers by name
        module = importlib.import_module(f"pasibot_pin.report.{dict(analyze.STEPS)[name]}")
        for attr, wrapper in savers.items():
            if hasattr(module, attr):
                setattr(module, attr, wrapper)
    jobs.run_jobs, pool_run_jobs = serial, jobs.run_jobs
    start = time.process_time()
    try:
        with tempfile.TemporaryDirectory(prefix="pasibot-breakdown-") as out, contextlib.redirect_stdout(io.StringIO()):
            analyze.run(argparse.Namespace(out=Path(out), force=True))
    finally:
        jobs.run_jobs = pool_run_jobs
    total = time.process_time() - start
    groups: dict[str, float] = {}
    for cpu, key in per_job:
        inner = key[1] if len(key) > 1 else None
        name = inner if key[0] == "step" else f"{key[0]}: {inner[0]}" if isinstance(inner, tuple) else key[0]
        groups[name] = groups.get(name, 0.0) + cpu
    lines = [f"serial run in this process: {total:.1f} s CPU, {len(per_job)} jobs"]
    lines += [f"  {name:28s} {cpu:6.1f} s" for name, cpu in sorted(groups.items(), key=lambda g: -g[1])]
    for kind, (count, cpu) in drawing.items():
        lines.append(f"  {kind + 's':28s} {cpu:6.1f} s ({count} written; inside the sections above)")
    return "\n".join(lines)


def page(m: dict) -> str:
    """docs/timings.md for one measurement."""
    fresh = ""
    if "fresh_wall" in m:
        fresh = f"| `make demo` from a fresh clone (venv, plain install, analysis) | {m['fresh_wall']:.0f} | - |\n"
    return f"""# Timings

Measured by `make timings` (`benchmarks/bench_demo.py`); no other page quotes a time.

| what | wall [s] | CPU [s] |
|---|---|---|
| `make demo` (`pasibot analyze`, 2 worker processes) | {m["wall"]:.0f} | {m["cpu"]:.0f} |
{fresh}
The analysis's CPU is {m["cpu"] / m["reference"]:.0f}x the reference workload of `benchmarks/bench_demo.py`
({REFERENCE_CALLS:,} bare `pin.rnea` calls on the spring biped: {m["reference"]:.2f} s here), a ratio that
depends on the machine far less than seconds do (not on the code alone, though: two revisions are compared in
pairs, on one machine).

Measured on a {m["machine"]}, on {m["date"]}, with a load average of {m["load"]:.1f} when it started
(the machine was shared: other work makes the wall time longer, the CPU time much less so).
"""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", type=Path, default=None, help="write the timings page to this file")
    parser.add_argument("--breakdown", action="store_true", help="also the CPU per section, figures and GIFs")
    parser.add_argument("--no-demo", action="store_true", help="skip the timed demo (with --breakdown: that only)")
    parser.add_argument("--fresh", action="store_true", help="also time `make demo` in a fresh clone, install included")
    args = parser.parse_args()
    if args.no_demo and args.write is not None:
        parser.error("--write needs the demo's timing: drop --no-demo")
    if not args.no_demo:
        m = measure()
        m["reference"] = reference()
        print(f"make demo: {m['wall']:.1f} s wall, {m['cpu']:.1f} s CPU on a {m['machine']} (load {m['load']:.1f})")
        print(f"reference workload: {m['reference']:.2f} s CPU; the demo's CPU is {m['cpu'] / m['reference']:.1f}x it")
        if args.fresh:
            m.update(fresh_demo())
            print(f"make demo from a fresh clone: {m['fresh_wall']:.0f} s wall, install included")
    if args.breakdown:
        print(breakdown())
    if args.write is not None:
        args.write.write_text(page(m), encoding="utf-8")
        print(f"wrote {args.write}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
