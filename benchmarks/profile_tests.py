"""Where the test suite's CPU goes: each test's CPU time, its subprocesses' included, costliest first.

Runs ``python -m pytest -q`` (the suite as ``make test`` runs it: pyproject's addopts, xdist's
workers) with this file loaded as a plugin (``-p profile_tests``). Each worker records, per test,
its wall time and its CPU time: the worker's own and that of the subprocesses it waited for in the
meantime (``getrusage``: a command run by the test, a pool's workers, a notebook's kernel), and
writes them to a JSON file per worker. Then prints the run's wall time, the CPU of every worker
(and how busy each was), the machine's busy core-seconds over the run (Linux's ``/proc/stat``: what
the per-test figures cannot see, such as the renderer and GPU processes of a browser, which the
browser's own process never reaps), and the costliest test modules and tests.

A test's subprocesses count when they are reaped: a process started in one test and waited for in
another (the plain install's ``analyze``) counts where it was waited for. CPU time depends far less
on the machine's load than wall time does, but two runs are compared on one machine, in one session.

``python benchmarks/profile_tests.py [--top N] [--modules N] [-- PYTEST_ARGS...]``; for instance
``-- -m "not slow and not integration and not browser and not mujoco and not network"`` (the fast tier).
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

OUT_ENV = "PASIBOT_PROFILE_TESTS_DIR"
"""Environment variable: the folder where each worker writes its record (set by :func:`main`)."""

_started: dict[str, tuple[float, float]] = {}
_records: list[tuple[str, float, float]] = []
_START = time.monotonic()


def _cpu() -> float:
    """CPU time [s] of this process and of the children it has waited for."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def pytest_runtest_logstart(nodeid, location):
    """A test starts (its setup included)."""
    _started[nodeid] = (time.monotonic(), _cpu())


def pytest_runtest_logfinish(nodeid, location):
    """A test ends (its teardown included): record its wall and CPU time [s]."""
    wall, cpu = _started.pop(nodeid)
    _records.append((nodeid, time.monotonic() - wall, _cpu() - cpu))


def pytest_sessionfinish(session):
    """Write this process's record (a worker's, or the only process's) where :func:`main` reads it.

    xdist's controller hears every test's start and end too, but runs none: it writes nothing.
    """
    folder = os.environ.get(OUT_ENV)
    config = session.config
    controller = not hasattr(config, "workerinput") and bool(getattr(config.option, "numprocesses", None))
    if not folder or not _records or controller:
        return
    worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
    record = {"span": time.monotonic() - _START, "cpu": _cpu(), "tests": _records}
    Path(folder, f"{worker}.json").write_text(json.dumps(record))


def _collected_id(nodeid: str) -> str:
    """The node id without xdist's ``@group`` suffix (as ``tests/conftest.py``'s ``collected_id``; a group's name holds
    no ``]`` or ``::``)."""
    base, at, group = nodeid.rpartition("@")
    return base if at and "]" not in group and "::" not in group else nodeid


def machine_busy(stat: str | None = None) -> float | None:
    """The machine's busy CPU time since boot [core-s]: every CPU's time but idle and I/O wait.

    Args:
        stat: the text of ``/proc/stat`` (default: read it; ``None`` where there is none, off Linux).
    """
    if stat is None:
        try:
            stat = Path("/proc/stat").read_text()
        except OSError:
            return None
    fields = [int(x) for x in stat.split("\n", 1)[0].split()[1:]]  # the "cpu" line, in clock ticks
    idle, iowait = fields[3], fields[4] if len(fields) > 4 else 0
    return (sum(fields[:8]) - idle - iowait) / os.sysconf("SC_CLK_TCK")  # guest time is in user already


def report(folder: Path, wall: float, top: int, modules: int, machine: float | None = None) -> str:
    """The workers' records in ``folder`` as text; ``machine``: the machine's busy core-seconds over the run."""
    workers = {p.stem: json.loads(p.read_text()) for p in sorted(folder.glob("*.json"))}
    if not workers:
        return "no test ran"
    tests = [(cpu, w, _collected_id(n)) for r in workers.values() for n, w, cpu in r["tests"]]
    total = sum(cpu for cpu, _, _ in tests)
    by_module: collections.Counter = collections.Counter()
    for cpu, _, name in tests:
        by_module[name.split("::", 1)[0]] += cpu
    lines = [f"pytest: {wall:.1f} s wall, {len(tests)} tests, {total:.1f} s CPU in the tests"]
    for name, r in workers.items():
        busy = sum(w for _, w, _ in r["tests"]) / r["span"] if r["span"] > 0 else 0.0
        lines.append(f"  {name}: {r['cpu']:.1f} s CPU over {r['span']:.1f} s, in tests {100 * busy:.0f} % of it")
    if machine is not None:
        cores = os.cpu_count() or 1
        share = 100 * machine / (cores * wall) if wall > 0 else 0.0
        lines.append(
            f"machine: {machine:.1f} core-s busy over the run ({share:.0f} % of {cores} cores), "
            f"{machine - total:.1f} core-s more than the tests counted (workers' start-up and collection, other "
            "processes on the machine, and the processes no test waited for: a browser's renderers)"
        )
    lines += ["", f"modules by CPU [s] (top {modules}):"]
    lines += [f"  {cpu:7.1f}  {name}" for name, cpu in by_module.most_common(modules)]
    lines += ["", f"tests by CPU [s] (top {top}; wall [s] beside):"]
    lines += [f"  {cpu:7.1f} {w:7.1f}  {name}" for cpu, w, name in sorted(tests, reverse=True)[:top]]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--top", type=int, default=30, help="tests listed, costliest first (default 30)")
    parser.add_argument("--modules", type=int, default=20, help="test modules listed (default 20)")
    parser.add_argument("pytest_args", nargs="*", help="passed to pytest (after --)")
    args = parser.parse_args(argv)
    root = Path(__file__).resolve().parents[1]
    with tempfile.TemporaryDirectory(prefix="pasibot-profile-tests-") as folder:
        path = os.pathsep.join(p for p in (str(Path(__file__).parent), os.environ.get("PYTHONPATH")) if p)
        env = dict(os.environ, PYTHONPATH=path, **{OUT_ENV: folder})
        start, busy = time.monotonic(), machine_busy()
        done = subprocess.run(
            [sys.executable, "-m", "pytest", "-q", "-p", "profile_tests", *args.pytest_args], cwd=root, env=env
        )
        after = machine_busy()
        machine = None if busy is None or after is None else after - busy
        print(report(Path(folder), time.monotonic() - start, args.top, args.modules, machine))
    return done.returncode


if __name__ == "__main__":
    sys.exit(main())
