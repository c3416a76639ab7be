"""``pasibot analyze``: the main job. Runs every analysis into an output folder.

Each analysis is a *step*: a function ``step(out_dir: Path, args) -> str`` that writes its
files into ``out_dir`` and returns a Markdown section for ``report.md``. Steps are listed
in :data:`STEPS`, in report order.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from pathlib import Path


def step_model(out_dir: Path, args: argparse.Namespace) -> str:
    """Model summaries of every variant and a side-view picture of the biped."""
    import matplotlib

    matplotlib.use("Agg")
    from pasibot_pin.model.params import VARIANTS
    from pasibot_pin.model.robot import load
    from pasibot_pin.viz.plots import plot_robot

    sections = ["## Model", ""]
    for variant in VARIANTS:
        for legs in (1, 2):
            robot = load(variant, legs)
            sections += ["```", robot.summary(), "```", ""]
    (out_dir / "info.txt").write_text("\n\n".join(load(v, 2).summary() for v in VARIANTS) + "\n")
    for variant in VARIANTS:
        fig = plot_robot(load(variant, 2))
        fig.savefig(out_dir / f"robot_{variant}.png", dpi=120)
    sections += [f"![{v} biped at q0](robot_{v}.png)" for v in VARIANTS]
    return "\n".join(sections)


def step_animation(out_dir: Path, args: argparse.Namespace) -> str:
    """The walk in 3-D (``gait.html``, meshcat) and as a 2-D stick GIF (``gait.gif``)."""
    from pasibot_pin.cli.export_html import analyze_step

    return analyze_step(out_dir, args)


def step_kinematics(out_dir: Path, args: argparse.Namespace) -> str:
    """Leg paths of every variant, K sweep, biped walks (plots + CSV); see ``commands/gait.py``."""
    from pasibot_pin.cli.gait import analyze_step

    return analyze_step(out_dir, args)


def step_dynamics(out_dir: Path, args: argparse.Namespace) -> str:
    """Torques and the ankle spring of every seed scenario, default model and seed preset (``commands/torques.py``)."""
    from pasibot_pin.cli.torques import analyze_step

    return analyze_step(out_dir, args)


def step_contact_energy(out_dir: Path, args: argparse.Namespace) -> str:
    """Heel/toe contact of every scenario, one motor for both cranks, energy per step (``commands/contact.py``)."""
    from pasibot_pin.cli.contact import analyze_step

    return analyze_step(out_dir, args)


def step_simulation(out_dir: Path, args: argparse.Namespace) -> str:
    """Forward simulation, hip pitch free: does the fitted ankle spring hold the hip (``commands/simulate.py``)."""
    from pasibot_pin.cli.simulate import analyze_step

    return analyze_step(out_dir, args)


STEPS: list[tuple[str, Callable[[Path, argparse.Namespace], str]]] = [
    ("model", step_model),
    ("kinematics", step_kinematics),
    ("animation", step_animation),
    ("dynamics", step_dynamics),
    ("contact_energy", step_contact_energy),
    ("simulation", step_simulation),
]


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser("analyze", help="run the full analysis into an output folder (the main job)")
    p.add_argument("--out", type=Path, default=Path("out"), help="output folder (default out/)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run every step, with progress on stdout, and write ``report.md``."""
    out_dir: Path = args.out
    out_dir.mkdir(parents=True, exist_ok=True)
    parts = ["# PASIBOT analysis", ""]
    for k, (name, step) in enumerate(STEPS, start=1):
        start = time.perf_counter()
        print(f"[{k}/{len(STEPS)}] {name} ...", flush=True)
        parts += [step(out_dir, args), ""]
        print(f"[{k}/{len(STEPS)}] {name} done in {time.perf_counter() - start:.1f} s", flush=True)
    report = out_dir / "report.md"
    report.write_text("\n".join(parts))
    print(f"wrote {report}")
    return 0
