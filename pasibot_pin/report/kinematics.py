"""Files, printouts and the Markdown section of the kinematics study (:mod:`pasibot_pin.studies.kinematics_study`).

- :func:`write_rows_csv`, :func:`write_leg_csv`, :func:`write_walk_csv`: samples as CSV.
- :func:`write_leg_plot`, :func:`write_walk_plot`: figures of :mod:`pasibot_pin.viz.plots_gait`.
- :func:`leg_summary`, :func:`walk_summary`: the ``pasibot gait`` printouts.
- :func:`section`: the ``kinematics`` section of ``pasibot analyze``.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from pasibot_pin.report.files import FIGURE_DPI, save_figure_file, writing
from pasibot_pin.report.markdown import Section, figure, figure_links
from pasibot_pin.studies.kinematics_study import (
    LEG_COLUMNS,
    BipedRun,
    KinematicsSurvey,
    LegRun,
    gait_columns,
    gait_rows,
    kinematics_survey,
    leg_rows,
)
from pasibot_pin.units import with_unit
from pasibot_pin.viz.plots_gait import plot_foot_pitch, plot_gait, plot_gait_hip, plot_k_sweep, plot_leg_summary


# --------------------------------------------------------------------------- files
def write_rows_csv(path: Path, columns: list[str] | tuple[str, ...], rows: np.ndarray | list) -> None:
    """Write rows under a header; floats at full precision, other cells (int, str) as they are.

    Args:
        path: output file; its folder is created.
        columns: the column names (SI values); the header adds their units (``theta`` -> ``theta_rad``).
        rows: one sequence of cells per row.

    """
    with writing(Path(path)) as tmp, tmp.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow([with_unit(name) for name in columns])
        for row in rows:
            writer.writerow([repr(float(x)) if isinstance(x, (float, np.floating)) else x for x in row])


def write_leg_csv(path: Path, run: LegRun) -> None:
    """Write a leg run's samples (columns :data:`~pasibot_pin.studies.kinematics_study.LEG_COLUMNS`)."""
    write_rows_csv(path, LEG_COLUMNS, leg_rows(run.cycle))


def write_walk_csv(path: Path, run: BipedRun) -> None:
    """Write a walk's samples (columns :func:`~pasibot_pin.studies.kinematics_study.gait_columns`)."""
    write_rows_csv(path, gait_columns(), gait_rows(run.gait))


def _save(fig, path: Path, dpi: int = FIGURE_DPI) -> None:
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    save_figure_file(fig, path, dpi)
    plt.close(fig)


def _pyplot():
    import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast

    return plt


def write_leg_plot(path: Path, run: LegRun, dpi: int = FIGURE_DPI) -> None:
    """Write the leg summary figure (paths, foot pitch, ankle velocity and acceleration).

    Args:
        path: output image (.png, .pdf, .svg); its folder is created.
        run: the leg run.
        dpi: resolution [dots per inch].

    """
    _pyplot()

    _save(plot_leg_summary(run.cycle), path, dpi)


def write_walk_plot(path: Path, run: BipedRun, figsize: tuple[float, float] = (11, 10), dpi: int = FIGURE_DPI) -> None:
    """Write the walk figure: the feet and hip paths above the hip height and pitch.

    Args:
        path: output image (.png, .pdf, .svg); its folder is created.
        run: the walk run.
        figsize: figure size [in].
        dpi: resolution [dots per inch].

    """
    _pyplot()
    from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

    fig, axes = subplots(2, 1, figsize=figsize, gridspec_kw={"height_ratios": [3, 1]})
    plot_gait(run.gait, ax=axes[0])
    plot_gait_hip(run.gait, ax=axes[1])
    _save(fig, path, dpi)


# --------------------------------------------------------------------------- printouts
def leg_summary(run: LegRun) -> str:
    """The ``pasibot gait --legs 1`` printout: sample count, straight-line metrics, ankle speeds."""
    lines = [f"PASIBOT {run.variant}, one leg, {len(run.cycle.theta)} samples, omega = {run.omega:g} rad/s"]
    lines += [f"  {key:22s} {value:.6g}" for key, value in run.metrics.in_L().items()]
    lines.append("  ankle v_x / (L omega) at 90, 180, 270 deg: " + ", ".join(f"{v:.6f}" for v in run.speed_ratios))
    return "\n".join(lines)


def walk_summary(run: BipedRun) -> str:
    """The ``pasibot gait --legs 2`` printout: hip advance, height and pitch, closure, exchange jumps."""
    w = run.gait
    lines = [
        f"PASIBOT {run.variant}, two legs, foot = {run.foot}, {run.steps} step(s), {w.n} samples",
        f"  hip advance per step / L: {', '.join(f'{d / run.L:.6f}' for d in run.hip_advance)}",
        f"  hip height peak-to-peak / L: {run.hip_height_ptp / run.L:.6f}",
        f"  hip pitch range [deg]: {np.degrees(run.hip_pitch.min()):.4f} .. {np.degrees(run.hip_pitch.max()):.4f}",
        f"  largest closure residual: {run.max_residual:.2e}",
    ]
    if run.max_jump > 1e-9:
        lines.append(f"  pose jump at the exchanges (the new stance foot lands tilted): {run.max_jump:.4f}")
    return "\n".join(lines)


# --------------------------------------------------------------------------- the section
def walk_name(run: BipedRun) -> str:
    """File stem of a survey walk: ``walk_<variant>``, with ``_<foot>`` unless the foot is flat."""
    return f"walk_{run.variant}" if run.foot == "flat" else f"walk_{run.variant}_{run.foot}"


def _leg_rows(result: KinematicsSurvey) -> list[str]:
    """The one-leg table's rows (one per variant), then the K sweep's table."""
    s = result.settings
    lines = []
    for variant, run in result.legs.items():
        m = run.metrics.in_L()
        lines.append(
            f"| {variant} | {m['stroke/L']:.6f} | {m['ankle_band/L']:.6f} | {m['lift/L']:.6f} "
            f"| {m['ground_span_deg']:.3f} | {m['stance_pitch_max_deg']:.4f} | {m['pitch_at_zero_deg']:.3f} "
            f"| {' / '.join(f'{v:.6f}' for v in run.speed_ratios)} |"
        )
    lines += ["", f"K sweep ({s.k_variant}; seed Fig 4.2.4):", "", "| K [-] | stroke [L] | ankle band [L] | lift [L] |"]
    lines.append("|---|---|---|---|")
    for K, met in zip(result.sweep.K, result.sweep.metrics):
        d = met.in_L()
        lines.append(f"| {K:g} | {d['stroke/L']:.4f} | {d['ankle_band/L']:.4f} | {d['lift/L']:.4f} |")
    return lines


def _walk_rows(result: KinematicsSurvey) -> list[str]:
    """The biped walks' table rows: advance, hip height and pitch, closure residual, pose jump."""
    lines = []
    for walk in result.gaits:
        pitch = np.degrees(walk.hip_pitch)
        lines.append(
            f"| {walk.variant} | {walk.foot} | {', '.join(f'{a:.4f}' for a in walk.hip_advance / walk.L)} "
            f"| {walk.hip_height_ptp / walk.L:.5f} | {pitch.min():.3f} .. {pitch.max():.3f} "
            f"| {walk.max_residual:.1e} | {walk.max_jump:.4f} |"
        )
    return lines


SHOWN_LEG = "parallel"
"""The leg whose four panels the section shows (a report's choice, not a variant's property); the others are linked."""


def _markdown(result: KinematicsSurvey) -> str:
    s = result.settings
    ks = ", ".join(f"{k:g}" for k in result.sweep.K)
    lines = [
        "## Kinematics (seed §4, §5)",
        "",
        "One leg in the leg frame (origin at the crank pivot, x forward, z up), crank every "
        f"{s.leg_step_deg:g} deg, ω = {s.omega:g} rad/s. Extremes refined on the closure manifold. "
        "Ground-span tolerance 0.02 L.",
        "",
        "| variant | stroke [L] | ankle band [L] | lift [L] | ground span [deg] | stance foot pitch max [deg] "
        "| foot pitch at θ=0 [deg] | v_x at 90/180/270 deg [Lω] |",
        "|---|---|---|---|---|---|---|---|",
    ]
    lines += _leg_rows(result)
    lines += [
        "",
        "6x4 geometric Jacobian of the open chain θ1, θ2, θ4, θ6 (joint 0 to the ankle) at "
        f"θ = {np.degrees(s.jacobian_theta):g} deg, rows v_x, v_y, v_z [m/s per rad/s], ω_x, ω_y, ω_z:",
        "",
        "```",
        np.array2string(result.jacobian, precision=5, suppress_small=True),
        "```",
        "",
        figure(
            f"kinematics_leg_{SHOWN_LEG}.png",
            f"One {SHOWN_LEG} leg over a crank turn (leg frame): ankle, toe and heel paths [m], foot pitch [deg], "
            "ankle velocity [m/s] and acceleration [m/s^2].",
        ),
        figure_links(
            [
                (f"kinematics_leg_{v}.png", f"the same four panels for the {v} leg")
                for v in result.legs
                if v != SHOWN_LEG
            ]
            + [
                ("foot_pitch.png", "foot pitch [deg] of every variant over a crank turn"),
                ("k_sweep.png", f"ankle paths [m] for K = {ks} (seed Fig 4.2.4)"),
            ],
            "More figures of the leg:",
        ),
        f"Biped walks (world frame, {s.gait_steps} steps, {s.gait_step_deg:g} deg per sample; hip = the crank axis):",
        "",
        "| variant | foot | hip advance per step [L] | hip height p-p [L] | hip pitch [deg] | max closure residual "
        "[m] | pose jump at exchange [m or rad] |",
        "|---|---|---|---|---|---|---|",
    ]
    lines += _walk_rows(result)
    lines += [
        "",
        "With a flat-welded rigid foot the hip must pitch with the shank and the pose jumps at every exchange "
        "(the seed's reason for the parallel extension); the rigid advance per step is therefore not 8 L. "
        "The `point` (ankle pinned) and `toe` (toe pinned) rows are the seed's Figs 4.2.7 and 4.2.8, "
        "hip level.",
        "",
        figure(
            "walk_spring.png",
            f"The spring biped walking {s.gait_steps} steps (world frame): feet and hip paths [m] above the hip "
            "height and pitch.",
        ),
        figure_links(
            [
                (f"{walk_name(run)}.png", f"the {run.variant} biped, foot {run.foot}")
                for run in result.gaits
                if walk_name(run) != "walk_spring"
            ],
            "The other walks of the table, as the same figure:",
        ),
    ]
    return "\n".join(lines)


def section(out_dir: Path) -> str:
    """Run the kinematics survey with default settings; write its files into ``out_dir``; return the section.

    Writes ``kinematics_leg_<variant>.png/.csv``, ``foot_pitch.png``, ``k_sweep.png``,
    ``walk_<variant>.png/.csv`` and the seed's ``walk_rigid_point.png/.csv`` and
    ``walk_rigid_toe.png/.csv``.

    Args:
        out_dir: the analysis folder (created if missing).

    Returns:
        The ``## Kinematics`` section of ``report.md`` (image links relative to ``out_dir``).

    """
    return _write(out_dir)[0]


def _write(out_dir: Path):
    _pyplot()

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    result = kinematics_survey()
    for variant, run in result.legs.items():
        write_leg_csv(out_dir / f"kinematics_leg_{variant}.csv", run)
        write_leg_plot(out_dir / f"kinematics_leg_{variant}.png", run)
    _save(plot_foot_pitch({v: run.cycle for v, run in result.legs.items()}), out_dir / "foot_pitch.png")
    _save(plot_k_sweep(result.sweep), out_dir / "k_sweep.png")
    for walk in result.gaits:
        write_walk_csv(out_dir / f"{walk_name(walk)}.csv", walk)
        write_walk_plot(out_dir / f"{walk_name(walk)}.png", walk, figsize=(12, 10))
    return _markdown(result), result


def build(out_dir: Path):
    """:func:`section` with the facts the report's summary quotes (:class:`~pasibot_pin.report.markdown.Section`)."""
    markdown, result = _write(out_dir)
    spring = result.legs["spring"].metrics.in_L()
    facts = {
        "stroke_L": spring["stroke/L"],
        "band_L": spring["ankle_band/L"],
        "parallel_pitch_deg": result.legs["parallel"].metrics.in_L()["stance_pitch_max_deg"],
        "rigid_pitch_deg": result.legs["rigid"].metrics.in_L()["stance_pitch_max_deg"],
    }
    return Section(markdown, facts)
