"""The README's pictures, drawn by the library, not by hand: each writer draws into the path it is given.

``make docs-figures`` (``tools/docs_figures.py``) writes them into ``docs/``.

- :func:`write_variants_figure`: ``docs/variants.png``, the three variants (two legs) at q0;
- :func:`write_gait_gif`: ``docs/gait.gif``, the ``analyze`` walk's stick GIF, smaller;
- :func:`write_walker_gif`: ``docs/walking.gif``, a walker walking on the floor (the README's hero);
- :func:`write_kinematics_figure`: ``docs/kinematics.png``, the parallel leg's foot paths over a
  crank turn beside the spring biped walking three steps;
- :func:`write_torques_figure`: ``docs/torques.png``, run 2's torques against the stance ankle
  angle with the fitted spring, the default model beside the seed preset;
- :func:`write_simulation_figure`: ``docs/simulation.png``, run 1's hip pitch with the fitted, no,
  half and twice the stiffness beside its (K_e, beta0) sweep;
- :func:`write_walking_map_figure`: ``docs/walking_map.png``, the walking map's outcomes, drawn from
  the committed ``docs/results/walking_map.csv`` (``make walking-map`` computes that table).

``tests/test_docs_figures.py`` redraws each and compares it with the committed file.
"""

from __future__ import annotations

from pathlib import Path

from pasibot_pin.errors import ParameterError
from pasibot_pin.kinematics.gait import prescribed_gait
from pasibot_pin.kinematics.leg import crank_grid, leg_cycle
from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.model.params import VARIANTS
from pasibot_pin.model.robot import load
from pasibot_pin.report import animation
from pasibot_pin.report.files import save_figure_file
from pasibot_pin.report.walking import write_walk_animation
from pasibot_pin.studies.simulation_study import scenario_study
from pasibot_pin.studies.torques_study import TorqueSettings, scenario_torques
from pasibot_pin.studies.walking import WalkSettings, walk_design
from pasibot_pin.studies.walking_map import load_map
from pasibot_pin.viz.plots import plot_robot
from pasibot_pin.viz.plots_dynamics import plot_torques_vs_beta
from pasibot_pin.viz.plots_gait import plot_gait, plot_leg_paths
from pasibot_pin.viz.plots_simulation import plot_hip_pitch, plot_spring_sweep
from pasibot_pin.viz.plots_walking import walking_map_figure

DOCS_DPI: int = 100
"""The resolution of the README's pictures [dots per inch], the report's."""
GIF_DPI: int = 60
"""The resolution of ``docs/gait.gif`` [dots per inch]: 384 x 300 pixels, smaller than the report's
(:data:`pasibot_pin.report.animation.GIF_DPI`)."""


def _save(fig, path: Path) -> Path:
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast

    try:
        save_figure_file(fig, Path(path), DOCS_DPI)
    finally:
        plt.close(fig)
    return Path(path)


def _subplots(*args, **kwargs):
    import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

    matplotlib.use("Agg")
    from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

    return subplots(*args, **kwargs)


def write_variants_figure(path: Path) -> Path:
    """``docs/variants.png``: rigid, parallel and spring (two legs) at their q0, side by side."""
    fig, axes = _subplots(1, len(VARIANTS), figsize=(10, 5))
    for ax, variant in zip(axes, VARIANTS):
        plot_robot(load(variant, 2), ax=ax)
    return _save(fig, path)


def write_kinematics_figure(path: Path) -> Path:
    """``docs/kinematics.png``: the parallel leg's foot paths (leg frame) | the spring biped's three steps."""
    fig, axes = _subplots(1, 2, figsize=(11.5, 4.6))
    plot_leg_paths(leg_cycle(load("parallel", 1), crank_grid()), ax=axes[0])
    plot_gait(prescribed_gait(load("spring", 2), 3, 36), ax=axes[1], snapshots=4, points=("ankle",))
    return _save(fig, path)


def write_simulation_figure(path: Path, scenario: str = "run1") -> Path:
    """``docs/simulation.png``: the scenario's hip pitch for its four springs | its (K_e, beta0) sweep."""
    study = scenario_study(scenario).study
    fig, axes = _subplots(1, 2, figsize=(12, 4.8))
    plot_hip_pitch(study.runs, ax=axes[0])
    axes[0].set_title(f"{scenario} ({study.omega:g} rad/s): hip pitch, hip free (x: fell)")
    fitted = (study.fitted.stiffness, study.fitted.rest_angle)
    if study.sweep_stiffness is None or study.sweep_rest is None or study.sweep_excursion is None:
        raise ParameterError(f"the {scenario} study has no spring sweep to draw")
    plot_spring_sweep(
        study.sweep_stiffness, study.sweep_rest, study.sweep_excursion, fitted=fitted, best=study.best, ax=axes[1]
    )
    axes[1].set_title(f"{study.sweep_method} sweep: max |hip pitch|")
    return _save(fig, path)


def write_gait_gif(path: Path) -> Path:
    """``docs/gait.gif``: the stick GIF of ``pasibot analyze``'s walk (its frames), at :data:`GIF_DPI`."""
    return animation.write_gait_gif(Path(path), dpi=GIF_DPI)


WALKER_GIF_FPS: float = 8.0
"""Frames per second of simulated time of ``docs/walking.gif`` [1/s]."""


def write_walker_gif(path: Path) -> Path:
    """``docs/walking.gif``: the long-soled parallel walker (4.5 L soles, 2 rad/s) walking four steps on the floor."""
    design = Design(variant="parallel", parallel_toe=4.5, parallel_heel=4.5, omega=2.0)
    robot = design_robot(design, 2, visuals=False)
    walk = walk_design(design, WalkSettings(steps=4), robot)
    write_walk_animation(walk, robot, gif=Path(path), fps=WALKER_GIF_FPS, dpi=GIF_DPI)
    return Path(path)


def write_torques_figure(path: Path, scenario: str = "run2") -> Path:
    """``docs/torques.png``: T_a, T_e, T_a', T_e' against beta with the fit, default model | seed preset."""
    fig, axes = _subplots(1, 2, figsize=(13, 4.5))
    for ax, preset in zip(axes, ("default", "seed")):
        run = scenario_torques(TorqueSettings(scenario=scenario, preset=preset))
        plot_torques_vs_beta(run.result, run.fit, ax=ax, title=f"{run.scenario.description} [{preset}]")
    return _save(fig, path)


def write_walking_map_figure(path: Path) -> Path:
    """``docs/walking_map.png``: the committed walking map (:func:`.plots_walking.walking_map_figure`)."""
    import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

    matplotlib.use("Agg")

    return _save(walking_map_figure(load_map()), path)


DOCS_PICTURES = (
    (write_variants_figure, "variants.png"),
    (write_gait_gif, "gait.gif"),
    (write_walker_gif, "walking.gif"),
    (write_kinematics_figure, "kinematics.png"),
    (write_torques_figure, "torques.png"),
    (write_simulation_figure, "simulation.png"),
    (write_walking_map_figure, "walking_map.png"),
)
"""Every README picture and the function that draws it."""
