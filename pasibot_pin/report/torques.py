"""Files and the Markdown section of the torque analysis (:mod:`pasibot_pin.studies.torques_study`).

- :func:`write_result_csv`, :func:`write_beta_plot`: one scenario's samples and figure.
- :func:`section`: the ``dynamics`` section of ``pasibot analyze``: every scenario with the
  default model and the seed preset (CSVs, torque plots, K_e table), the attribution of the
  seed's K_e to its modelling choices, and two crank turns of run4.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from pasibot_pin.model.scenarios import SCENARIOS, SEED_CHOICE_NAMES
from pasibot_pin.report.files import save_figure_file, write_columns_csv
from pasibot_pin.report.markdown import Section, figure
from pasibot_pin.studies.torques_study import SURVEY_PRESETS, torque_survey
from pasibot_pin.viz.plots_dynamics import plot_stiffness_table, plot_torques_vs_beta, plot_torques_vs_time


def write_result_csv(path: Path, result) -> None:
    """Write a :class:`~pasibot_pin.dynamics.inverse.TorqueResult` as CSV (SI units, full precision).

    Args:
        path: output file; its folder is created.
        result: the torques (columns of :meth:`~pasibot_pin.dynamics.inverse.TorqueResult.columns`).

    """
    write_columns_csv(path, result.columns())


def write_beta_plot(path: Path, run) -> None:
    """Write the torques against beta with the fitted spring of one scenario as an image (at the report's resolution).

    Args:
        path: output image; its folder is created.
        run: a :class:`~pasibot_pin.studies.torques_study.ScenarioTorques`.

    """
    import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast

    fig = plot_torques_vs_beta(run.result, run.fit, title=f"{run.scenario.description} [{run.preset}]")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    save_figure_file(fig, path)
    plt.close(fig)


def _attribution_lines(attribution: dict) -> list[str]:
    """The attribution table: one column pair (K_e, delta) per dynamic scenario."""
    names = list(attribution)
    lines = [
        "### Where the seed's K_e comes from",
        "",
        "Each row switches one more of the seed's choices on (cumulative, top to bottom); the last row is the "
        "`seed` preset. Delta = the change that choice makes [N.m/rad].",
        "",
        "| choice | " + " | ".join(f"{n} K_e [N.m/rad] | {n} delta [N.m/rad]" for n in names) + " |",
        "|---|" + "---|---|" * len(names),
    ]
    for k, row in enumerate(attribution[names[0]]):
        cells = " | ".join(f"{attribution[n][k].K_e:.2f} | {attribution[n][k].delta:+.2f}" for n in names)
        lines.append(f"| {row.label} | {cells} |")
    return [*lines, ""]


def section(out_dir: Path) -> str:
    """Run the torque survey; write its CSVs and figures into ``out_dir/dynamics``; return the Markdown section.

    Args:
        out_dir: the analysis folder (the files go to its ``dynamics`` subfolder).

    Returns:
        The ``## Torques and the ankle spring`` section of ``report.md`` (image links relative to ``out_dir``).

    """
    return build(out_dir).markdown


def _stiffness_figures(survey, sub: Path) -> tuple[list[str], list[str]]:
    """Each scenario's CSVs, torque-against-beta panels and K_e table row; the stiffness figure.

    Returns:
        The table's rows (one per scenario) and the fits' warnings.

    """
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast

    from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

    lines, warnings_text = [], []
    table: dict[str, list] = {"default": [], "seed preset": [], "seed stored": []}
    grid, axes = subplots(len(SCENARIOS), 2, figsize=(13, 4 * len(SCENARIOS)))
    for row, (name, scenario) in enumerate(SCENARIOS.items()):
        for col, preset in enumerate(SURVEY_PRESETS):
            run = survey.runs[(name, preset)]
            write_result_csv(sub / f"torques_{name}_{preset}.csv", run.result)
            plot_torques_vs_beta(run.result, run.fit, ax=axes[row, col], title=f"{scenario.description} [{preset}]")
            if run.spring.warning:
                warnings_text.append(f"- {name} [{preset}]: {run.spring.warning}")
        d, s = survey.runs[(name, "default")].spring, survey.runs[(name, "seed")].spring
        stored = "-" if scenario.seed_K_e is None else f"{scenario.seed_K_e:.2f}"
        clean = "-" if scenario.seed_K_e_clean is None else f"{scenario.seed_K_e_clean:.2f}"
        lines.append(
            f"| {name} | {scenario.omega:g} | {scenario.body_mass:g} | {d.K_e:.2f} | {d.r2:.3f} | "
            f"{math.degrees(d.beta0):.1f} | {s.K_e:.2f} | {stored} | {clean} |"
        )
        table["default"].append(d.K_e)
        table["seed preset"].append(s.K_e)
        table["seed stored"].append(scenario.seed_K_e)
    save_figure_file(grid, sub / "torques_vs_beta.png")
    plt.close(grid)
    fig = plot_stiffness_table(list(SCENARIOS), table, title="ankle stiffness per scenario")
    save_figure_file(fig, sub / "stiffness.png")
    plt.close(fig)
    return lines, warnings_text


def _two_turns_figure(survey, sub: Path) -> None:
    """Run 4's two crank turns as CSV; the torques over time of run 4 and run 2."""
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast

    from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

    write_result_csv(sub / "torques_run4_two_turns.csv", survey.gait)
    fig, (ax1, ax2) = subplots(2, 1, figsize=(10, 8))
    plot_torques_vs_time(survey.gait, ax=ax1, title="run4 (5 rad/s, 20 kg), default model, two crank turns")
    plot_torques_vs_time(survey.slow, ax=ax2, title="run2 (0.1 rad/s, 16 kg), default model, two crank turns")
    save_figure_file(fig, sub / "torques_vs_time.png")
    plt.close(fig)


def _summary_facts(survey) -> dict:
    """What the report's summary quotes: K_e of the dynamic runs, run 4's R^2, the fit window's share."""
    dynamic = [n for n in SCENARIOS if n in dict(survey.attribution)]
    window = {
        n: row.delta for n in dynamic for row in survey.attribution[n] if row.label == SEED_CHOICE_NAMES["fit_thetas"]
    }
    return {
        "default": [survey.runs[(n, "default")].spring.K_e for n in dynamic],
        "seed_preset": [survey.runs[(n, "seed")].spring.K_e for n in dynamic],
        "seed_stored": [SCENARIOS[n].seed_K_e for n in dynamic],
        "run4_r2": survey.runs[("run4", "default")].spring.r2,
        "window_delta": window,
    }


def build(out_dir: Path):
    """:func:`section` with the facts the report's summary quotes (:class:`~pasibot_pin.report.markdown.Section`)."""
    import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

    matplotlib.use("Agg")

    survey = torque_survey()
    sub = out_dir / "dynamics"
    sub.mkdir(parents=True, exist_ok=True)
    lines = [
        "## Torques and the ankle spring (constrained RNEA)",
        "",
        "Stance foot welded flat, hip level, cranks at constant omega pi apart; torques are generalised forces "
        "of theta, beta, theta', beta' (beta = angle from the forward foot to the shank). "
        "`default`: exact masses, swing foot level, exact accelerations, fit over the whole stance "
        "theta in [90, 270] deg. `seed`: every choice of the seed's MATLAB code (docs/reference.md §5).",
        "",
        "| seed scenario | omega [rad/s] | body [kg] | K_e default [N.m/rad] | R^2 [-] | beta0 [deg] | "
        "K_e seed preset [N.m/rad] | seed stored [N.m/rad] | seed without swap/lag [N.m/rad] |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    scenario_lines, warnings_text = _stiffness_figures(survey, sub)
    lines += scenario_lines
    lines += [
        "",
        "The seed's quasi-static script does not swap the L5/L6 masses (its dynamic script does): its model is the "
        f"`seed-clean` preset here, K_e = {survey.quasi_static_clean.K_e:.2f} N.m/rad at omega = 0 "
        "(the seed's text: about 330).",
        "",
        figure(
            "dynamics/stiffness.png",
            "Fitted ankle stiffness K_e [N.m/rad] per scenario: default model, seed preset, the seed's stored values.",
        ),
    ]
    if warnings_text:
        lines += ["Fit warnings:", *warnings_text, ""]
    lines += _attribution_lines(dict(survey.attribution))

    walk = survey.gait
    _two_turns_figure(survey, sub)
    lines += [
        figure(
            "dynamics/torques_vs_beta.png",
            "Crank and ankle torques [N.m] against the stance ankle angle beta [deg], one row per scenario, with the "
            "least-squares spring line: default model (left), seed preset (right).",
        ),
        figure(
            "dynamics/torques_vs_time.png",
            "Crank and ankle torques [N.m] over two crank turns (four steps): run4 at 5 rad/s (top), run2 at "
            "0.1 rad/s (bottom).",
        ),
        f"Two crank turns of run4 (four steps, {len(walk)} samples): peak |T_a| = {float(np.max(np.abs(walk.Ta))):.2f} "
        f"N.m, peak |T_e| = {float(np.max(np.abs(walk.Te))):.1f} N.m. CSVs: `dynamics/torques_<scenario>_<preset>.csv` "
        "(columns t, theta, beta, Ta, Te, Ta_swing, Te_swing, then reactions).",
    ]
    facts = _summary_facts(survey)
    return Section("\n".join(lines), facts)
