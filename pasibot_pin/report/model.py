"""The model section of the report: summaries of every variant and a side view of each biped.

Each is the default design's robot of its variant (:func:`~pasibot_pin.model.design.design_robot`):
the robot ``pasibot info`` prints and ``pasibot walk`` builds, its ``body_mass`` on the hip.
"""

from __future__ import annotations

from pathlib import Path

from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.model.params import VARIANTS
from pasibot_pin.report.files import save_figure_file, write_text_atomic
from pasibot_pin.report.markdown import figure
from pasibot_pin.viz.plots import plot_robot


def section(out_dir: Path) -> str:
    """Write ``info.txt`` and ``robot_<variant>.png`` into ``out_dir``; return the Markdown section."""
    import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

    matplotlib.use("Agg")

    def robot(variant: str, legs: int, visuals: bool = False):
        return design_robot(Design(variant=variant), legs, visuals=visuals)

    intro = "Each variant's robot as `pasibot info --variant V` prints it (the default design's)."
    sections = ["## Model", "", intro, ""]
    for variant in VARIANTS:
        for legs in (1, 2):
            sections += ["```", robot(variant, legs).summary(), "```", ""]
    write_text_atomic(Path(out_dir) / "info.txt", "\n\n".join(robot(v, 2).summary() for v in VARIANTS) + "\n")
    for variant in VARIANTS:
        fig = plot_robot(robot(variant, 2, visuals=True), legend=True)
        save_figure_file(fig, out_dir / f"robot_{variant}.png")
    sections += [
        figure(
            f"robot_{v}.png",
            f"The {v} biped at its assembled pose q0 (side view [m]; the legend names each link group and symbol).",
        )
        for v in VARIANTS
    ]
    return "\n".join(sections)
