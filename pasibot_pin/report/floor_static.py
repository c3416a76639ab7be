"""Tables, CSV and figure of the quasi-static spring study on the floor (:mod:`pasibot_pin.studies.floor_static`).

``floor_quasi_static.csv`` has one row per spring case and per (K_e, beta0) cell of every run;
``floor_quasi_static.png`` is :func:`~pasibot_pin.viz.plots_floor.plot_floor_static_maps`. The
markdown goes into ``floor_springs.md`` (:mod:`pasibot_pin.report.floor`) and the report.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import matplotlib.pyplot as plt

from pasibot_pin.errors import ParameterError
from pasibot_pin.report.files import save_figure_file, write_dict_rows
from pasibot_pin.studies.floor_static import CAUSES, FloorStatic, FloorStaticSweep

STATIC_NAME = "floor_quasi_static"
"""Stem of the sweep's CSV and figure."""


def weld_text(path: FloorStatic) -> str:
    """The weld's quasi-static answer: ``14.0`` [deg] or ``none`` (no stable equilibrium somewhere)."""
    value = path.weld_excursion
    return f"{math.degrees(value):.1f}" if math.isfinite(value) else "none"


def floor_text(path: FloorStatic, short: bool = False) -> str:
    """The floor's quasi-static answer: ``14.0`` [deg] or ``rolls onto toe at 90°``.

    ``short``: ``toe 90° (3/19)``, with the crank angles held flat.
    """
    fail = path.failure
    if fail is None:
        return f"{math.degrees(path.excursion):.1f}"
    theta, status = fail
    if short:
        return f"{status} {math.degrees(theta):.0f}° ({flat_count(path)})"
    return f"{CAUSES[status]} at {math.degrees(theta):.0f}°"


def flat_count(path: FloorStatic) -> str:
    """``k/n``: crank angles where the sole holds the weld's equilibrium flat."""
    return f"{sum(s == 'flat' for s in path.status)}/{len(path.status)}"


def case_rows(sweeps: Sequence[FloorStaticSweep]) -> list[dict[str, str]]:
    """One row per run and spring case, with units."""
    rows = []
    for sweep in sweeps:
        for label, path in sweep.cases.items():
            rows.append(
                {
                    "run": sweep.scenario,
                    "spring": label,
                    "K_e [N.m/rad]": f"{path.spring.stiffness if path.spring else 0.0:.1f}",
                    "weld: quasi-static max pitch [deg]": weld_text(path),
                    "floor: quasi-static max pitch [deg]": floor_text(path),
                    "floor: crank angles held flat [-]": flat_count(path),
                }
            )
    return rows


def cell_rows(sweeps: Sequence[FloorStaticSweep]) -> list[dict[str, str]]:
    """The CSV: one row per run and (K_e, beta0) cell, weld beside floor, full precision."""
    rows = []
    for sweep in sweeps:
        if sweep.stiffness is None or sweep.rest is None:
            continue
        for i, beta0 in enumerate(sweep.rest):
            for j, k in enumerate(sweep.stiffness):
                path = sweep.cells[i][j]
                fail = path.failure
                rows.append(
                    {
                        "run": sweep.scenario,
                        "K_e [N.m/rad]": repr(float(k)),
                        "beta0 [deg]": repr(math.degrees(float(beta0))),
                        "weld: quasi-static max pitch [deg]": repr(math.degrees(path.weld_excursion)),
                        "floor: quasi-static max pitch [deg]": repr(math.degrees(path.excursion)),
                        "floor: first failure": "" if fail is None else fail[1],
                        "floor: first failure theta [deg]": "" if fail is None else repr(math.degrees(fail[0])),
                        "floor: crank angles held flat [-]": flat_count(path),
                    }
                )
    return rows


def _table(rows: list[dict[str, str]]) -> list[str]:
    head = list(rows[0]) if rows else []
    body = ["| " + " | ".join(r.values()) + " |" for r in rows]
    return ["| " + " | ".join(head) + " |", "|" + "---|" * len(head), *body]


def map_table(sweep: FloorStaticSweep) -> list[str]:
    """A run's K_e x beta0 map as a markdown table: ``weld / floor`` in each cell."""
    if sweep.stiffness is None or sweep.rest is None:
        raise ParameterError(f"the {sweep.scenario} sweep has no K_e x beta0 grid")
    head = ["beta0 [deg] \\ K_e [N.m/rad]", *(f"{k:.0f}" for k in sweep.stiffness)]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for i, beta0 in enumerate(sweep.rest):
        cells = [f"{weld_text(c)} / {floor_text(c, short=True)}" for c in sweep.cells[i]]
        lines.append("| " + " | ".join([f"{math.degrees(beta0):.1f}", *cells]) + " |")
    return lines


def cases_markdown(sweeps: Sequence[FloorStaticSweep]) -> str:
    """The spring cases' quasi-static answers, weld beside floor, with how they are read."""
    samples = len(next(iter(sweeps[0].cases.values())).theta) if sweeps and sweeps[0].cases else 0
    lines = [
        "### Quasi-static (omega -> 0), weld against floor",
        "",
        f"Cranks held at {samples} crank angles along the stance, the swing foot in the air at its rest angle",
        "(`pasibot_pin.studies.floor_static`). The weld: the largest equilibrium hip pitch, `none` where some",
        "crank angle has no stable one. The floor: the same, where the sole holds the weld's equilibrium flat at",
        "every crank angle (heel and toe loaded: the centre of mass over the sole); else the first crank angle",
        "where it does not: the foot rolls onto its heel or toe (standing on one point is never stable), no stable",
        "equilibrium, or the swing foot at its rest angle dips into the floor (double support, not resolved here).",
        "",
        *_table(case_rows(sweeps)),
        "",
    ]
    return "\n".join(lines)


def sweep_markdown(sweeps: Sequence[FloorStaticSweep], figure: str = STATIC_NAME + ".png") -> str:
    """The (K_e, beta0) maps of every run, weld / floor in each cell, and the figure."""
    lines = [
        "### The quasi-static K_e x beta0 sweep on the floor",
        "",
        "The weld sweep's grid (K_e: 0.8 to 4 times the fit; beta0: the fit +-6 deg). Each cell:",
        "`weld / floor`, the largest |hip pitch| [deg] along the stance, or `none` (weld: no stable",
        "equilibrium somewhere) and the floor's first failure: `heel`/`toe` (rolls onto it), `none`,",
        "`swing` (the swing foot dips into the floor), at the crank angle given, and how many of the",
        "crank angles the sole holds flat.",
        "",
    ]
    for sweep in sweeps:
        if sweep.stiffness is None:
            continue
        holds = sum(c.holds for row in sweep.cells for c in row)
        total = sum(len(row) for row in sweep.cells)
        lines += [f"**{sweep.scenario}** (the floor holds {holds} of {total} cells)", "", *map_table(sweep), ""]
    lines += [
        f"![K_e (N.m/rad) x beta0 (deg) maps of runs 1-4, weld beside floor]({figure})",
        "",
        "*Largest |hip pitch| along the stance [deg], weld (left) beside floor (right); grey: no answer "
        "(the floor's first failure, its crank angle and the crank angles held flat written in the cell); "
        "star: the inverse-dynamics fit.*",
        "",
    ]
    return "\n".join(lines)


def static_files(out: Path, force: bool = False) -> tuple[Path, Path]:
    """(csv, png) of the sweep in ``out``; FileExistsError if one exists and ``force`` is false."""
    paths = (Path(out) / f"{STATIC_NAME}.csv", Path(out) / f"{STATIC_NAME}.png")
    existing = [str(p) for p in paths if p.exists()]
    if existing and not force:
        raise FileExistsError(f"{', '.join(existing)} exists; pass --force to overwrite")
    return paths


def write_static_into(sweeps: Sequence[FloorStaticSweep], csv_path: Path, png_path: Path) -> None:
    """Write the sweep's CSV and figure straight to these paths (the caller renames them)."""
    from pasibot_pin.viz.plots_floor import (  # deferred: heavy (matplotlib), keeps the CLI's start fast
        plot_floor_static_maps,
    )

    write_dict_rows(csv_path, cell_rows(sweeps))
    fig = plot_floor_static_maps(sweeps)
    try:
        save_figure_file(fig, png_path, 100)
    finally:
        plt.close(fig)
