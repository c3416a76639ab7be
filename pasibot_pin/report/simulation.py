"""Files and the Markdown section of the forward simulation (:mod:`pasibot_pin.studies.simulation_study`).

- :func:`prepare_outputs`, :func:`write_simulation`: the files of ``pasibot simulate``
  (``simulation_<scenario>.png``, ``.csv`` and optionally ``.gif`` / ``.html``);
  :func:`case_line`: its console line per spring case.
- :func:`study_table`, :func:`run_table`: Markdown tables of the every-scenario study.
- :func:`section`: the ``simulation`` section of ``pasibot analyze``: per seed scenario, the hip
  excursion with the fitted spring, none, half and twice K_e, gravity's toppling stiffness, a
  (K_e, beta0) sweep, the swing-foot model check and an animation of the fast walk.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pasibot_pin.files import check_replaceable
from pasibot_pin.jobs import Job, run_jobs
from pasibot_pin.model.scenarios import SCENARIOS
from pasibot_pin.report.animation import export_animation
from pasibot_pin.report.files import save_figure_file, write_columns_csv
from pasibot_pin.report.markdown import Section, figure, figure_links
from pasibot_pin.studies import simulation_study as sim
from pasibot_pin.studies.methods.statics import StaticEquilibrium
from pasibot_pin.studies.simulation_study import (
    SimulationStudySettings,
    SwingFootCheck,
    cached_inputs,
    hip_pitch_gap,
    simulation_columns,
)
from pasibot_pin.studies.spring_study import SPRING_CASES, SWEEP_OFFSETS_DEG, sweep_method_for
from pasibot_pin.viz.plots_simulation import fall_window, plot_simulation, plot_spring_sweep, plot_static_equilibrium

PLOT_NAME = "simulation_{scenario}.png"
CSV_NAME = "simulation_{scenario}.csv"
GIF_NAME = "simulation_{scenario}.gif"
HTML_NAME = "simulation_{scenario}.html"
ANIMATION_FPS = 20.0
"""Frames per simulated second of the check scenario's animation in ``pasibot analyze``."""
POOL_WORKERS = 2
"""Processes running the scenario studies of :func:`section`."""


# --------------------------------------------------------------------------- pasibot simulate
@dataclass(frozen=True)
class SimulateFiles:
    """The files of one ``pasibot simulate`` run.

    Attributes:
        plot: hip pitch of every case (or the static equilibria at omega = 0).
        csv: the fitted run's time series.
        gif: stick GIF of the fitted run (``None``: not asked for).
        html: meshcat HTML of the fitted run (``None``: not asked for).

    """

    plot: Path
    csv: Path
    gif: Path | None = None
    html: Path | None = None


def prepare_outputs(
    out: Path, scenario: str, gif: bool = False, html: bool = False, force: bool = False
) -> SimulateFiles:
    """Create ``out`` and name the files of scenario ``scenario`` in it.

    Raises:
        FileExistsError: one of them exists and ``force`` is false.

    """
    out = Path(out)
    tag = str(scenario).replace(" ", "_")
    files = SimulateFiles(
        out / PLOT_NAME.format(scenario=tag),
        out / CSV_NAME.format(scenario=tag),
        out / GIF_NAME.format(scenario=tag) if gif else None,
        out / HTML_NAME.format(scenario=tag) if html else None,
    )
    paths = [p for p in (files.plot, files.csv, files.gif, files.html) if p is not None]
    existing = [str(p) for p in paths if os.path.lexists(p)]
    if existing and not force:
        raise FileExistsError(f"{', '.join(existing)} exists; pass --force to overwrite")
    for path in paths:
        check_replaceable(path, "--out")  # --force replaces regular files only
    return files


def write_simulation(files: SimulateFiles, run, fps: float = 20.0) -> list[Path]:
    """Write a :class:`~pasibot_pin.studies.simulation_study.SimulationRun`.

    At omega = 0 only the static-equilibrium plot; otherwise the hip-pitch plot, the fitted
    run's CSV (:func:`~pasibot_pin.studies.simulation_study.simulation_columns`) and the
    animations asked for in ``files`` (``fps`` frames per simulated second [1/s]).

    Returns:
        The animation files written.

    """
    import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast

    if run.setup.quasi_static:
        fig = plot_static_equilibrium(run.statics)
        save_figure_file(fig, files.plot)
        plt.close(fig)
        return []
    robot = run.setup.scenario.robot
    fig = plot_simulation(run.runs, main="fitted", rest_angle=run.setup.spring.rest_angle)
    save_figure_file(fig, files.plot)
    plt.close(fig)
    write_columns_csv(files.csv, simulation_columns(robot, run.fitted))
    return export_animation(robot, run.fitted, files.html, files.gif, fps)


def case_line(label: str, outcome) -> str:
    """One console line per spring case: a walk's excursion and drift, or a static path's largest pitch.

    Args:
        label: the case label (``fitted``, ``no spring``, ...).
        outcome: a :class:`~pasibot_pin.dynamics.simulator.SimulationResult` or, at omega = 0, a
            :class:`~pasibot_pin.studies.methods.statics.StaticEquilibrium`.

    """
    if isinstance(outcome, StaticEquilibrium):
        exc = outcome.max_excursion
        text = "no stable equilibrium" if math.isinf(exc) else f"{math.degrees(exc):.3f} deg"
        return f"  {label:10s} largest equilibrium |hip pitch| = {text}"
    tail = f" ({outcome.message})" if outcome.message else ""
    return (
        f"  {label:10s} max |hip pitch| = {math.degrees(outcome.max_hip_excursion):8.3f} deg, "
        f"max drift before projection = {outcome.max_drift:.1e}{tail}"
    )


# --------------------------------------------------------------------------- pasibot analyze
def _deg(value: float, static: bool = False) -> str:
    if math.isfinite(value):
        return f"{math.degrees(value):.2f}"
    return "no stable eq." if static else "fell"


def study_table(studies: Sequence) -> list[str]:
    """Markdown table of the excursions and the sweep result, one row per scenario.

    Args:
        studies: :class:`~pasibot_pin.studies.simulation_study.ScenarioStudy` per scenario.

    """
    head = "| scenario | omega [rad/s] | fit K_e [N.m/rad] | fit beta0 [deg] | R^2 [-] | k_g [N.m/rad] | "
    head += "K_e - k_g [N.m/rad] | " + " | ".join(f"{label} [deg]" for label, _ in SPRING_CASES)
    head += " | most level (K_e [N.m/rad], beta0 [deg]) | its max abs pitch [deg] |"
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for entry in studies:
        st, k_g, fit = entry.study, entry.toppling, entry.spring_fit
        static = not st.runs
        cells = [
            st.name,
            f"{st.omega:g}",
            f"{st.fitted.stiffness:.1f}",
            f"{math.degrees(st.fitted.rest_angle):.2f}",
            f"{fit.r2:.3f}" if fit is not None else "-",
            f"{k_g:.1f}",
            f"{st.fitted.stiffness - k_g:+.1f}",
        ]
        cells += [_deg(st.excursion[label], static) for label, _ in SPRING_CASES]
        if st.best is not None:
            best = float(np.min(st.sweep_excursion))
            cells += [
                f"({st.best[0]:.0f}, {math.degrees(st.best[1]):.1f}) {st.sweep_method}",
                _deg(best, st.sweep_method == "static"),
            ]
        else:
            cells += [f"none in the {st.sweep_method} sweep", "-"]
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def run_table(studies: Sequence) -> list[str]:
    """Markdown table of every walk: excursion, duration, landing mismatch, swing sole, drift."""
    lines = [
        "| scenario | spring | time step [ms] | max abs hip pitch [deg] | simulated [s] | largest landing height "
        "mismatch [mm] | lowest swing sole [mm] | largest drift per step before projection [m] |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for entry in studies:
        for label, res in entry.study.runs.items():
            landing = f"{1000 * max(abs(i.height) for i in res.impacts):.1f}" if res.impacts else "-"
            pitch = "fell" if res.fell else _deg(res.max_hip_excursion)  # a fall's last pitch is where it was caught
            lines.append(
                f"| {entry.name} | {label} | {1000 * res.settings.dt:g} | {pitch} | "
                f"{res.t[-1]:.2f}{' (fell)' if res.fell else ''} | {landing} | "
                f"{1000 * float(res.swing_height.min()):.1f} | {res.max_drift:.1e} |"
            )
    return lines


def write_scenario_figures(out_dir: Path, study) -> list[tuple[str, str]]:
    """One scenario's figures: hip pitch of the walks, static equilibria, the sweep. Returns (file, caption) pairs.

    Args:
        out_dir: the analysis folder.
        study: the scenario's :class:`~pasibot_pin.studies.spring_study.SpringStudy`.

    """
    import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast

    figures = []
    name = study.name
    if study.runs:
        fig = plot_simulation(study.runs, main="fitted", rest_angle=study.fitted.rest_angle)
        window = fall_window(study.runs)
        if window is None:
            fig.axes[0].set_title(f"{name}: hip pitch, hip free (x: fell; dotted: touchdowns)")
        else:
            fig.axes[0].set_title(f"{name}: the first {window:.2f} s, hip free: where the runs fell (x)")
        save_figure_file(fig, out_dir / f"simulation_{name}.png")
        plt.close(fig)
        falls = (
            ""
            if window is None
            else f"the first {window:.2f} s (top) with every run, each fall marked x at its time, then the whole run "
            "of the springs that held; "
        )
        figures.append(
            (
                f"simulation_{name}.png",
                f"{name}: hip pitch [deg] over time [s] with the fitted, no, half and twice the stiffness: {falls}"
                "ankle angles [deg] and crank torques [N.m] of the fitted run.",
            )
        )
    fig = plot_static_equilibrium(study.statics)
    fig.axes[0].set_title(f"{name}: static equilibrium (omega -> 0); missing: none stable")
    save_figure_file(fig, out_dir / f"simulation_static_{name}.png")
    plt.close(fig)
    figures.append(
        (
            f"simulation_static_{name}.png",
            f"{name}: static equilibrium hip pitch [deg] along the stance crank angle [deg] (the omega -> 0 limit).",
        )
    )
    if study.sweep_excursion is not None:
        fitted = (study.fitted.stiffness, study.fitted.rest_angle)
        fig = plot_spring_sweep(
            study.sweep_stiffness, study.sweep_rest, study.sweep_excursion, fitted=fitted, best=study.best
        )
        fig.axes[0].set_title(f"{name}: {study.sweep_method} sweep of (K_e, beta0)")
        save_figure_file(fig, out_dir / f"simulation_sweep_{name}.png")
        plt.close(fig)
        figures.append(
            (
                f"simulation_sweep_{name}.png",
                f"{name}: largest |hip pitch| [deg] over the {study.sweep_method} sweep of K_e [N.m/rad] and beta0 "
                "[deg]; star: the inverse-dynamics fit, circle: the most level pair.",
            )
        )
    return figures


def write_figures(out_dir: Path, studies: Sequence) -> list[tuple[str, str]]:
    """Per scenario: hip pitch of the walks, static equilibria, the sweep. Returns (file, caption) pairs."""
    return [name for entry in studies for name in write_scenario_figures(out_dir, entry.study)]


def write_check_animation(out_dir: Path, name: str, base) -> str:
    """The animation files of the check scenario's fitted walk ``base``; returns the report's note on them."""
    gif, html = out_dir / GIF_NAME.format(scenario=name), out_dir / HTML_NAME.format(scenario=name)
    try:
        anim = export_animation(cached_inputs(name).robot, base, html=html, gif=gif, fps=ANIMATION_FPS)
    except Exception as err:  # noqa: BLE001 - the viewer is optional here; report why it is missing
        return f"animation not written: {err}"
    captions = {
        ".gif": f"the fitted {name} walk, hip free, as a stick animation ({ANIMATION_FPS:g} frames per simulated "
        "second): ground, contact points, ground reaction",
        ".html": "the same walk in 3-D (meshcat, one self-contained page)",
    }
    return "\n".join(f"- [{p.name}]({p.name}): {captions[p.suffix]}" for p in anim)


# CPU estimates [s] of the pieces (measured on the default analysis; they only order the work:
# longest first). Walks at 0.1 rad/s that do not fall integrate 3142 steps.
_CASE_ESTIMATE = {"fitted": 1.6, "twice K_e": 2.0, "half K_e": 0.2, "no spring": 0.2}
_FAST_CASE_ESTIMATE = 0.3
_ROW_ESTIMATE = {"dynamic": 2.5, "static": 0.3}  # dynamic: the whole sweep, one job
_CHECK_ESTIMATE = 0.8
_FIGURES_ESTIMATE = 1.3
_ANIMATION_ESTIMATE = 1.5


class SimulationPlan:
    """The ``simulation`` section as pool jobs (:mod:`pasibot_pin.jobs`).

    :meth:`jobs` gives the first jobs: per scenario its inputs, each spring case and each sweep
    row, and the swing-foot check's run. :meth:`done` takes each result and releases a
    scenario's figures once its pieces are in, and the animation once the check scenario's
    fitted walk is in. :meth:`markdown` writes the section when everything is done.
    """

    def __init__(self, out_dir: Path, settings=None):
        self.out_dir = Path(out_dir)
        self.settings = settings or SimulationStudySettings()
        self.meta: dict = {}
        self.cases: dict = {name: {} for name in self.settings.scenarios}
        self.rows: dict = {name: {} for name in self.settings.scenarios}
        self.studies: dict = {}
        self.figures: dict = {}
        self.full = None
        self.anim_note = None

    def jobs(self) -> list:
        """The first jobs: inputs, spring cases and sweep rows per scenario, the check."""
        st = self.settings
        out = []
        for name in st.scenarios:
            omega = SCENARIOS[name].omega
            fast = omega > st.fast_omega
            out.append(Job(0.1, ("meta", name), sim.meta_task, (name,)))
            for label, _ in SPRING_CASES:
                estimate = _FAST_CASE_ESTIMATE if fast or omega <= 0 else _CASE_ESTIMATE[label]
                if name == st.check_scenario and label == "fitted":
                    estimate += _ANIMATION_ESTIMATE  # it releases the animation: start it early
                out.append(Job(estimate, ("case", name, label), sim.case_task, (name, label, st)))
            if sweep_method_for(omega) == "dynamic":  # one job: its walks go in lockstep, cheaper together
                rows = tuple(range(len(SWEEP_OFFSETS_DEG)))
                out.append(Job(_ROW_ESTIMATE["dynamic"], ("rows", name, rows), sim.sweep_rows_task, (name, rows, st)))
                continue
            for row in range(len(SWEEP_OFFSETS_DEG)):
                out.append(Job(_ROW_ESTIMATE["static"], ("row", name, row), sim.sweep_row_task, (name, row, st)))
        if st.check_scenario:
            out.append(Job(_CHECK_ESTIMATE, ("check",), sim.check_task, (st,)))
        return out

    def done(self, key, result) -> list:
        """Take a job's result; return the jobs it releases (a scenario's figures, the animation)."""
        kind, name = key[0], key[1] if len(key) > 1 else None
        released = []
        if kind == "meta":
            self.meta[name] = result
        elif kind == "case":
            self.cases[name][key[2]] = result
            if name == self.settings.check_scenario and key[2] == "fitted" and result[1] is not None:
                released.append(
                    Job(
                        _ANIMATION_ESTIMATE, ("animation", name), write_check_animation, (self.out_dir, name, result[1])
                    )
                )
        elif kind == "row":
            self.rows[name][key[2]] = result
        elif kind == "rows":
            self.rows[name].update(zip(key[2], result))
        elif kind == "check":
            self.full = result
        elif kind == "figures":
            self.figures[name] = result
        elif kind == "animation":
            self.anim_note = result
        if kind in ("meta", "case", "row", "rows") and name not in self.studies:
            complete = (
                name in self.meta
                and len(self.cases[name]) == len(SPRING_CASES)
                and len(self.rows[name]) == len(SWEEP_OFFSETS_DEG)
            )
            if complete:
                cases = {label: self.cases[name][label] for label, _ in SPRING_CASES}
                rows = [self.rows[name][i] for i in range(len(SWEEP_OFFSETS_DEG))]
                self.studies[name] = sim.assemble_scenario(self.meta[name], cases, rows)
                released.append(
                    Job(
                        _FIGURES_ESTIMATE,
                        ("figures", name),
                        write_scenario_figures,
                        (self.out_dir, self.studies[name].study),
                    )
                )
        return released

    def markdown(self) -> str:
        """The section, once every job is done."""
        studies = [self.studies[name] for name in self.settings.scenarios]
        figures = [f for name in self.settings.scenarios for f in self.figures[name]]
        check = None
        if self.settings.check_scenario and self.full is not None:
            name = self.settings.check_scenario
            base = self.studies[name].study.runs["fitted"]
            check = SwingFootCheck(None, base, self.full, hip_pitch_gap(base, self.full))
        return section_markdown(self.settings, studies, check, self.anim_note, figures)

    def section(self):
        """:meth:`markdown` and :meth:`facts` as a :class:`~pasibot_pin.report.markdown.Section`."""
        return Section(self.markdown(), self.facts())

    def facts(self) -> dict:
        """The numbers the report's summary quotes (once every job is done).

        ``margin_run1``: fitted K_e − k_g of run1 [N.m/rad]; ``run1_fitted``, ``run23_fitted``: largest
        |hip pitch| with the fitted spring [rad] (inf: fell); ``fall_min``/``fall_max``: the range of fall
        times without a spring over the walking scenarios [s].
        """
        out: dict = {}
        walks = {name: entry for name, entry in self.studies.items() if entry.study.runs}
        if "run1" in self.studies:
            entry = self.studies["run1"]
            out["margin_run1"] = entry.study.fitted.stiffness - entry.toppling
            out["run1_fitted"] = entry.study.excursion["fitted"]
        out["run23_fitted"] = [self.studies[n].study.excursion["fitted"] for n in ("run2", "run3") if n in walks]
        falls = [e.study.runs["no spring"].t[-1] for e in walks.values() if e.study.runs["no spring"].fell]
        if falls:
            out["fall_min"], out["fall_max"] = min(falls), max(falls)
        return out if {"margin_run1", "fall_min"} <= set(out) else {}


def section_markdown(settings, studies: Sequence, check, anim_note: str | None, figures: list[tuple[str, str]]) -> str:
    """The ``simulation`` section's Markdown; ``figures`` are (file, caption) pairs, the first one embedded."""
    main = next((f for f in figures if f[0].startswith("simulation_run")), figures[0] if figures else None)
    shown = [] if main is None else [figure(*main)]
    rest = [f for f in figures if f is not main]
    if rest:
        shown.append(figure_links(rest, "Every scenario's figures:"))
    name, base, full = settings.check_scenario, check.base, check.full
    lines = [
        "## Does the spring work? Forward simulation with the hip pitch free",
        "",
        "The `spring` biped walks with its hip pitch **free**: the cranks follow theta0 + omega t (a rheonomic",
        "motor constraint; its multiplier is the motor torque), each ankle carries T = -K_e (beta - beta0) - c",
        "beta_dot (c critically damps the unloaded foot), the stance foot is welded flat, and at each half crank",
        "turn the swing foot lands (inelastic impulse). Own KKT solve per evaluation, RK4, projection of q and v",
        "every step. The robot starts still at its static equilibrium (level if none is stable). At omega = 0",
        "(quasi-static) the answer is the static equilibrium pitch along the stance (cranks held).",
        "",
        "k_g = g sum m_i (z_i - z_ankle) is gravity's toppling stiffness about the stance ankle (hip level,",
        "mid-stance): a rigid rotation of the robot about the ankle needs K_e > k_g to be stable at all. Columns",
        "'fitted', 'no spring', 'half K_e', 'twice K_e': largest |hip pitch| over the run (dynamic scenarios:",
        "2 steps at 0.1 rad/s, 4 at 5 rad/s; 'fell' = passed 60 deg) or over the static equilibrium path",
        "(quasi-static). Sweep: K_e = 0.8..4 x fit, beta0 = fit -6..+6 deg; static (equilibrium path) for",
        "omega <= 0.1 rad/s, dynamic (walks) for omega = 5 rad/s.",
        "",
        *study_table(studies),
        "",
        *run_table(studies),
        "",
        "A negative lowest swing sole means the swing foot passed below the ground (swing contact is not",
        "modelled): such runs describe a robot that would have stumbled.",
        "",
        f"Swing-foot model check ({name}, fitted spring, {settings.check_steps} steps): with the swing foot "
        f"integrated on its spring (dt {1000 * settings.check_dt:g} ms) instead of held at its rest angle "
        f"(dt {1000 * base.settings.dt:g} ms), the hip-pitch history differs by at most "
        f"{math.degrees(check.gap):.2f} deg; final pitch {math.degrees(base.hip_pitch[-1]):.2f} vs "
        f"{math.degrees(full.hip_pitch[-1]):.2f} deg.",
        "",
        "Animations:",
        "",
        anim_note or "",
        "",
        *shown,
    ]
    return "\n".join(lines)


def section(out_dir: Path) -> str:
    """``pasibot analyze`` section "simulation": does the fitted spring hold the hip, per seed scenario.

    Runs :mod:`~pasibot_pin.studies.simulation_study` with its default settings, in pieces on a
    pool of :data:`POOL_WORKERS` processes (:class:`SimulationPlan`), writes the figures and the
    animation of the check scenario's fitted walk into ``out_dir``.

    Returns:
        The Markdown section.

    """
    plan = SimulationPlan(Path(out_dir))
    start = time.perf_counter()
    run_jobs(plan.jobs(), plan.done, POOL_WORKERS)
    print(f"    simulation studies of {len(plan.studies)} scenarios: {time.perf_counter() - start:.1f} s", flush=True)
    return plan.markdown()
