"""The model section of the report: summaries of every variant and a side view of each biped."""

from __future__ import annotations

from pathlib import Path

from pasibot_pin.model.params import VARIANTS
from pasibot_pin.model.robot import load
from pasibot_pin.report.files import save_figure_file, write_text_atomic
from pasibot_pin.report.markdown import figure
from pasibot_pin.viz.plots import plot_robot


def section(out_dir: Path) -> str:
    """Write ``info.txt`` and ``robot_<variant>.png`` into ``out_dir``; return the Markdown section."""
    import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

    matplotlib.use("Agg")

    sections = ["## Model", ""]
    for variant in VARIANTS:
        for legs in (1, 2):
            sections += ["```", load(variant, legs).summary(), "```", ""]
    write_text_atomic(Path(out_dir) / "info.txt", "\n\n".join(load(v, 2).summary() for v in VARIANTS) + "\n")
    for variant in VARIANTS:
        fig = plot_robot(load(variant, 2), legend=True)
        save_figure_file(fig, out_dir / f"robot_{variant}.png")
    sections += [
        figure(
            f"robot_{v}.png",
            f"The {v} biped at its assembled pose q0 (side view [m]; the legend names each link group and symbol).",
        )
        for v in VARIANTS
    ]
    return "\n".join(sections)
