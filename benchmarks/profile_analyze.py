"""Where ``pasibot analyze``'s CPU goes: a profile of every job in its worker, and of the parent.

Runs ``pasibot analyze --out TMP --force`` once in a child process with ``PASIBOT_PROFILE_DIR`` set
(:data:`pasibot_pin.jobs.PROFILE_ENV`: each pool job runs under cProfile in its worker and dumps
``<job key>.prof``, its CPU time in ``<job key>.json``), the parent itself under cProfile. Then prints
the run's wall and CPU time [s], and per job, costliest first, its CPU time [s] and its top functions
by cumulative time (pstats: cProfile's clock, wall time [s]), then the parent's.

``--top N`` functions per job (default 10); ``--keep DIR`` keeps the profiles (and the report) in DIR.
Profiling slows the run down (about 1.5x, more in Python-heavy code such as drawing): compare the
jobs with each other, or with another profiled run, not with an unprofiled one.
"""

from __future__ import annotations

import argparse
import cProfile
import io
import json
import os
import pstats
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PARENT = "parent.prof"
"""The parent's profile, next to the jobs' folder."""


def child(out: str, prof: str) -> int:
    """In the child process: ``pasibot analyze --out OUT --force`` under cProfile, dumped to ``prof``."""
    sys.argv = ["pasibot", "analyze", "--out", out, "--force"]  # as the command runs (the package reads argv[0])
    from pasibot_pin.__main__ import main

    profile = cProfile.Profile()
    cpu = time.process_time()
    try:
        return profile.runcall(main, ["analyze", "--out", out, "--force"])
    finally:
        profile.dump_stats(prof)
        Path(prof).with_suffix(".json").write_text(json.dumps({"cpu_s": time.process_time() - cpu}))


def run(folder: Path) -> dict:
    """Run the profiled analysis into ``folder``; its wall and CPU time [s] (parent and workers)."""
    env = dict(os.environ, PASIBOT_PROFILE_DIR=str(folder / "jobs"))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(
        [sys.executable, __file__, "--child", str(folder / "out"), str(folder / PARENT)],
        check=True,
        env=env,
        stdout=subprocess.DEVNULL,
    )
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return {"wall": wall, "cpu": (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)}


def top(path: Path, n: int) -> tuple[float, str]:
    """A profile's CPU time [s] (from its ``.json``) and its ``n`` top functions by cumulative time, as text."""
    text = io.StringIO()
    stats = pstats.Stats(str(path), stream=text)
    stats.strip_dirs().sort_stats("cumulative").print_stats(n)
    lines = text.getvalue().splitlines()
    head = next(i for i, line in enumerate(lines) if line.lstrip().startswith("ncalls"))
    cpu = json.loads(path.with_suffix(".json").read_text())["cpu_s"]
    return cpu, "\n".join(line for line in lines[head:] if line.strip())


def report(folder: Path, n: int, times: dict) -> str:
    """The profiles of ``folder`` as text: the totals, each job costliest first, then the parent."""
    jobs = sorted((folder / "jobs").glob("*.prof"))
    profiles = sorted(((*top(p, n), p.stem) for p in jobs), key=lambda x: -x[0])
    parent_cpu, parent_text = top(folder / PARENT, n)
    total = sum(cpu for cpu, _, _ in profiles)
    lines = [
        f"analyze (profiled): {times['wall']:.1f} s wall, {times['cpu']:.1f} s CPU (parent and workers); "
        f"{len(profiles)} jobs: {total:.1f} s CPU in all, the parent {parent_cpu:.1f} s",
        "",
        "jobs by CPU [s]:",
        *(f"  {cpu:7.2f}  {name}" for cpu, _, name in profiles),
    ]
    for cpu, text, name in profiles:
        lines += ["", f"== job {name}: {cpu:.2f} s CPU", text]
    lines += ["", f"== parent: {parent_cpu:.2f} s CPU", parent_text]
    return "\n".join(lines)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--top", type=int, default=10, help="functions per job, by cumulative time (default 10)")
    parser.add_argument("--keep", type=Path, default=None, help="keep the profiles and the report in this folder")
    parser.add_argument("--child", nargs=2, metavar=("OUT", "PROF"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        return child(*args.child)
    if args.keep is not None:
        args.keep.mkdir(parents=True, exist_ok=True)
        print(report(args.keep, args.top, run(args.keep)))
        return 0
    with tempfile.TemporaryDirectory(prefix="pasibot-profile-") as folder:
        print(report(Path(folder), args.top, run(Path(folder))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
