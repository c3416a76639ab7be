"""``pasibot analyze``: the main job. Runs every report section into an output folder.

Each section is ``pasibot_pin.report.<name>.section(out_dir) -> str``: it runs its studies,
writes its files into ``out_dir`` and returns its Markdown for ``report.md``. The simulation
section (the longest) runs in this process with its own process pool; the others run beside
it in one worker process, longest first. ``report.md`` keeps the order of :data:`STEPS`.
"""

from __future__ import annotations

import argparse
import importlib
import multiprocessing
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

STEPS: list[tuple[str, str]] = [
    ("model", "model"),
    ("kinematics", "kinematics"),
    ("animation", "animation"),
    ("dynamics", "torques"),
    ("contact_energy", "contact_energy"),
    ("simulation", "simulation"),
]
"""(step name, report module) in report order."""

SIDE_ORDER: tuple[str, ...] = ("contact_energy", "kinematics", "dynamics", "animation", "model")
"""The steps beside the simulation, longest first (measured: see the closing note of the redesign)."""


def run_step(name: str, out_dir: Path) -> tuple[str, float]:
    """Run one step: (its Markdown section, its wall time [s])."""
    start = time.perf_counter()
    module = importlib.import_module(f"pasibot_pin.report.{dict(STEPS)[name]}")
    return module.section(Path(out_dir)), time.perf_counter() - start


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser("analyze", help="run the full analysis into an output folder (the main job)")
    p.add_argument("--out", type=Path, default=Path("out"), help="output folder (default out/)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run every step (the simulation here, the others beside it) and write ``report.md``."""
    out_dir: Path = args.out
    out_dir.mkdir(parents=True, exist_ok=True)
    sections: dict[str, str] = {}
    with ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("fork")) as pool:
        futures = {name: pool.submit(run_step, name, out_dir) for name in SIDE_ORDER}
        print("[simulation] running here; beside it: " + ", ".join(SIDE_ORDER), flush=True)
        sections["simulation"], seconds = run_step("simulation", out_dir)
        print(f"[simulation] done in {seconds:.1f} s", flush=True)
        for name, future in futures.items():
            sections[name], seconds = future.result()
            print(f"[{name}] done in {seconds:.1f} s", flush=True)
    parts = ["# PASIBOT analysis", ""]
    for name, _ in STEPS:
        parts += [sections[name], ""]
    report = out_dir / "report.md"
    report.write_text("\n".join(parts))
    print(f"wrote {report}")
    return 0
