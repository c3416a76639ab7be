"""Time ``make demo`` (``pasibot analyze``) and say on what machine: the only source of the docs' timings.

Runs ``pasibot analyze --out TMP --force`` once in a child process and prints its wall time, the CPU
time of the child and its workers, and the machine: CPU model, core count, architecture, Python and
Pinocchio versions, and the load average when it started (other work on the machine slows it).
``--write docs/timings.md`` writes that page (``make timings``); the README and docs quote no other
timing (``tests/test_readme_numbers.py`` checks).
"""

from __future__ import annotations

import argparse
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


def page(m: dict) -> str:
    """docs/timings.md for one measurement."""
    return f"""# Timings

Measured by `make timings` (`benchmarks/bench_demo.py`); no other page quotes a time.

| what | wall [s] | CPU [s] |
|---|---|---|
| `make demo` (`pasibot analyze`, 2 worker processes) | {m["wall"]:.0f} | {m["cpu"]:.0f} |

Measured on a {m["machine"]}, on {m["date"]}, with a load average of {m["load"]:.1f} when it started
(the machine was shared: other work makes the wall time longer, the CPU time much less so).
"""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", type=Path, default=None, help="write the timings page to this file")
    args = parser.parse_args()
    m = measure()
    print(f"make demo: {m['wall']:.1f} s wall, {m['cpu']:.1f} s CPU on a {m['machine']} (load {m['load']:.1f})")
    if args.write is not None:
        args.write.write_text(page(m), encoding="utf-8")
        print(f"wrote {args.write}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
