"""Files of the floor studies: a scenario's fitted case (CSV, figure) and the weld-against-floor spring study.

``floor_<scenario>.csv`` holds :func:`~pasibot_pin.studies.floor_cases.floor_columns` of the fitted
case (strings for the contact modes, full precision for numbers); ``floor_<scenario>.png`` is
:func:`~pasibot_pin.viz.plots_floor.plot_floor_study`. Both are written under temporary names
and renamed together.
"""

from __future__ import annotations

import csv
import math
import os
from pathlib import Path

import matplotlib.pyplot as plt

from pasibot_pin.dynamics.floor.result3d import Floor3DResult
from pasibot_pin.files import atomic_paths, check_replaceable
from pasibot_pin.jobs import Job
from pasibot_pin.model.scenarios import get_scenario
from pasibot_pin.report.files import save_figure_file, write_dict_rows
from pasibot_pin.report.floor_static import cases_markdown, floor_text, static_files, sweep_markdown, write_static_into
from pasibot_pin.report.markdown import Section
from pasibot_pin.studies.floor_cases import FloorStudy, floor3d_columns, floor_columns
from pasibot_pin.studies.floor_static import floor_static_study
from pasibot_pin.studies.simulation_study import cached_inputs
from pasibot_pin.studies.spring_study import SPRING_CASES
from pasibot_pin.studies.weld_vs_floor import (
    CaseComparison,
    FloorSpringSettings,
    FloorSpringStudy,
    compare_case,
    floor_spring_study,
    quasi_static_of,
)
from pasibot_pin.units import with_unit
from pasibot_pin.viz.plots_floor import plot_floor3d_study, plot_floor_study, plot_weld_vs_floor

CSV_NAME = "floor_{scenario}.csv"
PLOT_NAME = "floor_{scenario}.png"
SPATIAL_PREFIX = "floor3d"
"""The 3-D floor's files replace ``floor`` with this in :data:`CSV_NAME` and :data:`PLOT_NAME`."""


def floor_files(out: Path, scenario: str, force: bool = False, spatial: bool = False) -> tuple[Path, Path]:
    """(csv, png) of ``scenario`` in ``out`` (``floor3d_*`` if ``spatial``); FileExistsError if there, not ``force``."""
    names = (CSV_NAME, PLOT_NAME)
    if spatial:
        names = tuple(name.replace("floor", SPATIAL_PREFIX, 1) for name in names)  # type: ignore[assignment]
    files = (Path(out) / names[0].format(scenario=scenario), Path(out) / names[1].format(scenario=scenario))
    existing = [str(p) for p in files if os.path.lexists(p)]
    if existing and not force:
        raise FileExistsError(f"{', '.join(existing)} exists; pass --force to overwrite")
    for path in files:
        check_replaceable(path, "--out")  # --force replaces regular files only
    return files


def write_floor(study: FloorStudy, csv_path: Path, png_path: Path) -> list[Path]:
    """Write the fitted case's CSV and the study's figure (3-D: the hip's roll too); returns the paths."""
    spatial = study.settings is not None and study.settings.spatial
    result = study.cases[0].result
    cols = floor3d_columns(result) if isinstance(result, Floor3DResult) else floor_columns(result)
    with atomic_paths(csv_path, png_path) as (csv_tmp, png_tmp):
        with csv_tmp.open("w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow([with_unit(name) for name in cols])  # t_s, right_heel_Fn_N, ...
            for row in zip(*cols.values()):
                writer.writerow([x if isinstance(x, str) else repr(float(x)) for x in row])
        fig = plot_floor3d_study(study) if spatial else plot_floor_study(study)
        try:
            save_figure_file(fig, png_tmp, 100)
        finally:
            plt.close(fig)
    return [csv_path, png_path]


SPRINGS_NAME = "floor_springs"
"""Stem of the weld-against-floor table (``.md``, ``.csv``) and figure (``.png``)."""


def _deg(angle: float) -> str:
    return "no stable eq." if math.isinf(angle) else f"{math.degrees(angle):.1f}"


def outcome_text(row: CaseComparison) -> str:
    """The floor run's outcome in words; an ``undecided`` run says why (shorter than two step periods)."""
    if not row.floor_outcome.startswith("undecided"):
        return row.floor_outcome
    omega = get_scenario(row.scenario).omega
    return (
        f"undecided: the {row.floor_end:g} s run is shorter than two steps ({math.pi / omega:.1f} s each at "
        f"{omega:g} rad/s); it did not fall"
    )


WELD_DT_MS = 10.0
"""The welded runs' time step in this table [ms] (``floor_spring_study.compare_case``)."""


def floor_spring_table(study: FloorSpringStudy) -> list[dict[str, str]]:
    """The table's rows, one per scenario and spring case, columns with their units.

    A welded run that fell has no largest pitch (its last sample is where the fall was caught):
    the column says ``fell`` and the next one when.
    """
    out, span = [], f"{study.settings.duration:g} s"
    for r in study.rows:
        fell = "" if math.isnan(r.weld_fell_at) else f"{r.weld_fell_at:.2f}"
        weld_pitch = "fell" if fell else f"{math.degrees(r.weld_max_pitch):.1f}"
        start = r.floor_start if r.floor_start == "none" else f"{r.floor_start} {r.floor_start_modes}"
        out.append(
            {
                "run": r.scenario,
                "spring": r.case,
                "K_e [N.m/rad]": f"{r.stiffness:.1f}",
                "weld: quasi-static max pitch [deg]": _deg(r.weld_static),
                "floor: quasi-static max pitch [deg]": floor_text(r.floor_static),
                f"weld: max pitch in {span} [deg]": weld_pitch,
                f"weld: fell at, dt {WELD_DT_MS:g} ms [s]": fell,
                "floor: start": "cannot stand" if r.floor_start == "none" else start,
                "floor: start pitch [deg]": ""
                if r.floor_start == "none"
                else f"{math.degrees(r.floor_start_pitch):.2f}",
                f"floor: max pitch in {span} [deg]": f"{math.degrees(r.floor_max_pitch):.1f}",
                "floor: landings [-]": str(r.floor_landings),
                "floor: outcome": outcome_text(r),
            }
        )
    return out


def floor_spring_markdown(study: FloorSpringStudy, figure: str = SPRINGS_NAME + ".png", statics=None) -> str:
    """The report section: what the floor changes, the table and the figure (linked, with a caption).

    ``statics``: :class:`~pasibot_pin.studies.floor_static.FloorStaticSweep` of each run; their
    K_e x beta0 maps follow (:func:`~pasibot_pin.report.floor_static.sweep_markdown`).
    """
    rows = floor_spring_table(study)
    head = list(rows[0]) if rows else []
    lines = [
        "## The spring study on the floor: weld against floor",
        "",
        f"Each case runs {study.settings.duration:g} s, welded (stance foot welded flat, swing foot at the",
        f"spring's rest angle) and on a floor (heel and toe unilateral, mu = {study.settings.mu:g}).",
        "The floor starts from a consistent state: the flat double support where the floor holds it at rest,",
        "else the springs engaged",
        "with the cranks held until the robot rests (`settled`); `cannot stand`: it finds no rest at theta0",
        "and the run starts from the flat double support. The weld's quasi-static column is the largest",
        "equilibrium hip pitch along the stance (cranks held); the floor's, the same where the sole holds",
        "it flat at every crank angle, else the first crank angle where the foot rolls onto its heel or toe,",
        "no equilibrium is stable, or the swing foot dips into the floor (`pasibot_pin.studies.floor_static`).",
        "",
        "| " + " | ".join(head) + " |",
        "|" + "---|" * len(head),
    ]
    lines += ["| " + " | ".join(row.values()) + " |" for row in rows]
    lines += [
        "",
        f"![Largest hip pitch (deg) of every run and spring case, weld beside floor]({figure})",
        "",
        f"*Largest |hip pitch| [deg] over {study.settings.duration:g} s of each spring case, welded stance foot (blue) "
        "beside the floor (orange), each bar labelled with its value (a dot on the axis marks zero); hatched: the run "
        "fell or failed, the bar where it stopped.*",
        "",
    ]
    if statics and any(s.stiffness is not None for s in statics):
        lines.append(sweep_markdown(statics))
    return "\n".join(lines)


def floor_spring_files(out: Path, force: bool = False, sweep: bool = False) -> list[Path]:
    """``floor_springs.md``, ``.csv`` and ``.png`` in ``out``; FileExistsError if one exists and ``force`` is false.

    ``sweep``: also ``floor_quasi_static.csv`` and ``.png``.
    """
    paths = [Path(out) / f"{SPRINGS_NAME}{ext}" for ext in (".md", ".csv", ".png")]
    if sweep:
        paths += static_files(out, force=True)
    existing = [str(p) for p in paths if os.path.lexists(p)]
    if existing and not force:
        raise FileExistsError(f"{', '.join(existing)} exists; pass --force to overwrite")
    for path in paths:
        check_replaceable(path, "--out")  # --force replaces regular files only
    return paths


def floor_spring_line(row: CaseComparison) -> str:
    """One printed line of a study row: weld and floor side by side."""
    fell = "" if math.isnan(row.weld_fell_at) else f", fell at {row.weld_fell_at:.2f} s"
    return (
        f"  {row.scenario} {row.case:10s}: weld max |pitch| {math.degrees(row.weld_max_pitch):.1f} deg{fell}; "
        f"floor ({row.floor_start}) max |pitch| {math.degrees(row.floor_max_pitch):.1f} deg, {row.floor_outcome}"
    )


def write_floor_spring(study: FloorSpringStudy, out: Path, force: bool = False, statics=None) -> list[Path]:
    """Write ``floor_springs.md``, ``.csv`` and ``.png`` in ``out`` (FileExistsError without ``force``).

    ``statics``: the quasi-static sweeps (:func:`~pasibot_pin.studies.floor_static.floor_static_study`):
    their maps go into the markdown, ``floor_quasi_static.csv`` and ``.png``.
    """
    sweep = bool(statics) and any(s.stiffness is not None for s in statics)
    paths = floor_spring_files(out, force, sweep)
    rows = floor_spring_table(study)
    with atomic_paths(*paths) as (md_tmp, csv_tmp, png_tmp, *static_tmp):
        if sweep:
            write_static_into(statics, *static_tmp)
        md_tmp.write_text(floor_spring_markdown(study, statics=statics), encoding="utf-8")
        write_dict_rows(csv_tmp, rows)
        fig = plot_weld_vs_floor(study)
        try:
            save_figure_file(fig, png_tmp, 100)
        finally:
            plt.close(fig)
    return paths


REPORT_SCENARIOS: tuple[str, ...] = ("run1",)
"""The runs ``pasibot analyze`` simulates on the floor (run 1's four spring cases; ``make floor-springs``
runs all four runs into ``docs/``, about four times the work). Its quasi-static answers cover
:data:`STATIC_SCENARIOS` (exact statics, no simulation: cheap)."""
STATIC_SCENARIOS: tuple[str, ...] = ("run1", "run2", "run3", "run4")


def _section_files(out_dir: Path, study: FloorSpringStudy) -> None:
    """Write the section's CSV and figure (``floor_springs.md`` is not kept: report.md holds the text)."""
    folder = Path(out_dir)
    write_floor_spring(study, folder, force=True)
    (folder / f"{SPRINGS_NAME}.md").unlink()


def static_others(scenarios: tuple[str, ...]) -> list:
    """The quasi-static floor answers of :data:`STATIC_SCENARIOS` not in ``scenarios`` (exact statics, no grid)."""
    others = tuple(s for s in STATIC_SCENARIOS if s not in scenarios)
    return floor_static_study(others, sweep=False) if others else []


def _section(study: FloorSpringStudy, others: list):
    """The section's text and the facts the report's summary quotes (:class:`~pasibot_pin.report.markdown.Section`).

    ``others``: :func:`static_others` of the study's scenarios.
    """
    statics = quasi_static_of(study) + others
    runs = ", ".join(study.settings.scenarios)
    note = (
        f"\nThis report simulates {runs} and answers runs 1-4 quasi-statically (below: exact statics, no "
        "simulation); `make floor-springs` simulates every walking scenario and sweeps K_e x beta0 "
        "(docs/floor.md, docs/floor_springs.md).\n\n"
    )
    fitted = study.row(study.settings.scenarios[0], "fitted")
    facts = {
        "duration": study.settings.duration,
        "weld_max_pitch": fitted.weld_max_pitch,
        "floor_max_pitch": fitted.floor_max_pitch,
        "floor_start": fitted.floor_start,
        "floor_outcome": outcome_text(fitted),
        "quasi_static_weld_holds": sum(math.isfinite(p.weld_excursion) for s in statics for p in s.cases.values()),
        "quasi_static_floor_holds": sum(p.holds for s in statics for p in s.cases.values()),
    }
    return Section(floor_spring_markdown(study) + note + cases_markdown(statics), facts)


def build(out_dir: Path):
    """``pasibot analyze``'s floor section: weld against floor for :data:`REPORT_SCENARIOS`.

    Writes the CSV and the figure; returns the text and the facts the report's summary quotes
    (:class:`~pasibot_pin.report.markdown.Section`). :class:`FloorPlan` does the same in pool jobs.
    """
    study = floor_spring_study(FloorSpringSettings(scenarios=REPORT_SCENARIOS))
    _section_files(out_dir, study)
    return _section(study, static_others(REPORT_SCENARIOS))


_STATIC_CACHES: dict[str, dict] = {}
"""Per scenario, the quasi-static solves' cache its spring cases share in this process (as
:func:`~pasibot_pin.studies.weld_vs_floor.floor_spring_study` shares it between them)."""


def floor_case_task(scenario: str, label: str, settings) -> CaseComparison:
    """One spring case of ``scenario``, weld against floor (a pool job; inputs computed once per process).

    The cases of a scenario that run in the same process share its quasi-static cache (the
    assembly at each crank angle and the projections: the same numbers, solved once).
    """
    cache = _STATIC_CACHES.setdefault(scenario, {})
    return compare_case(cached_inputs(scenario), label, dict(SPRING_CASES)[label], settings, cache)


_CASE_ESTIMATE = {"fitted": 3.0, "no spring": 2.5, "half K_e": 2.5, "twice K_e": 3.0}
"""CPU time [s] of one floor case (measured on the default analysis; it only orders the work)."""


class FloorPlan:
    """:func:`build` as pool jobs (:mod:`pasibot_pin.jobs`): one job per scenario and spring case.

    :meth:`jobs` gives the cases; :meth:`done` takes each one and, once all are in, releases the
    job writing the CSV and the figure; :meth:`section` gives the text and facts. The rows keep
    :func:`~pasibot_pin.studies.weld_vs_floor.floor_spring_study`'s order, so the files and
    the text are the same as :func:`build`'s.
    """

    def __init__(self, out_dir: Path, settings=None):
        self.out_dir = Path(out_dir)
        self.settings = settings or FloorSpringSettings(scenarios=REPORT_SCENARIOS)
        self.rows: dict = {}
        self.others: list | None = None
        self.study: FloorSpringStudy | None = None

    def _keys(self) -> list[tuple[str, str]]:
        return [(scenario, label) for scenario in self.settings.scenarios for label, _ in SPRING_CASES]

    def jobs(self) -> list:
        """One job per (scenario, spring case), and one for the other runs' quasi-static answers."""
        cases = [
            Job(_CASE_ESTIMATE[label], ("case", scenario, label), floor_case_task, (scenario, label, self.settings))
            for scenario, label in self._keys()
        ]
        return [*cases, Job(1.5, ("static",), static_others, (tuple(self.settings.scenarios),))]

    def done(self, key, result) -> list:
        """Take a job's result; return the file-writing job once every case is in."""
        if key[0] == "static":
            self.others = result
            return []
        if key[0] != "case":
            return []
        self.rows[key[1:]] = result
        if len(self.rows) < len(self._keys()):
            return []
        self.study = FloorSpringStudy(self.settings, [self.rows[k] for k in self._keys()])
        return [Job(0.3, ("files",), _section_files, (self.out_dir, self.study))]

    def section(self):
        """The section's :class:`~pasibot_pin.report.markdown.Section`, once every job is done."""
        if self.study is None or self.others is None:
            raise RuntimeError("FloorPlan.section() before every job is done")
        return _section(self.study, self.others)
