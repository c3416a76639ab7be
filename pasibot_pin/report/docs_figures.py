"""The README's pictures, drawn by the library (``make docs-figures``), not by hand.

:func:`write_torques_figure` draws ``docs/torques.png``: run 2's torques against the stance ankle
angle with the fitted spring, the default model beside the seed preset.
"""

from __future__ import annotations

from pathlib import Path

DOCS_DPI: int = 100
"""The resolution of the README's pictures [dots per inch], the report's."""


def write_torques_figure(path: Path, scenario: str = "run2") -> Path:
    """``docs/torques.png``: T_a, T_e, T_a', T_e' against beta with the fit, default model | seed preset."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from pasibot_pin.report.files import save_figure_file
    from pasibot_pin.studies.torques_study import TorqueSettings, scenario_torques
    from pasibot_pin.viz.plots_dynamics import plot_torques_vs_beta
    from pasibot_pin.viz.plots_layout import subplots

    fig, axes = subplots(1, 2, figsize=(13, 4.5))
    for ax, preset in zip(axes, ("default", "seed")):
        run = scenario_torques(TorqueSettings(scenario=scenario, preset=preset))
        plot_torques_vs_beta(run.result, run.fit, ax=ax, title=f"{run.scenario.description} [{preset}]")
    try:
        save_figure_file(fig, Path(path), DOCS_DPI)
    finally:
        plt.close(fig)
    return Path(path)


def main() -> None:
    """Draw the README's generated pictures into ``docs/``."""
    docs = Path(__file__).resolve().parents[2] / "docs"
    print(write_torques_figure(docs / "torques.png"))


if __name__ == "__main__":
    main()
