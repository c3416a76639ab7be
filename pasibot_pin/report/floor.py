"""Files of the floor study: the fitted case's CSV and the figure (hip pitch of every case, contact modes).

``floor_<scenario>.csv`` holds :func:`~pasibot_pin.studies.floor_study.floor_columns` of the fitted
case (strings for the contact modes, full precision for numbers); ``floor_<scenario>.png`` is
:func:`~pasibot_pin.viz.plots_floor.plot_floor_study`. Both are written under temporary names
and renamed together.
"""

from __future__ import annotations

import csv
from pathlib import Path

import matplotlib.pyplot as plt

from pasibot_pin.files import atomic_paths
from pasibot_pin.report.files import save_figure_file
from pasibot_pin.studies.floor_study import FloorStudy, floor_columns
from pasibot_pin.viz.plots_floor import plot_floor_study

CSV_NAME = "floor_{scenario}.csv"
PLOT_NAME = "floor_{scenario}.png"


def floor_files(out: Path, scenario: str, force: bool = False) -> tuple[Path, Path]:
    """(csv, png) of ``scenario`` in ``out``; FileExistsError if one exists and ``force`` is false."""
    files = (Path(out) / CSV_NAME.format(scenario=scenario), Path(out) / PLOT_NAME.format(scenario=scenario))
    existing = [str(p) for p in files if p.exists()]
    if existing and not force:
        raise FileExistsError(f"{', '.join(existing)} exists; pass --force to overwrite")
    return files


def write_floor(study: FloorStudy, csv_path: Path, png_path: Path) -> list[Path]:
    """Write the fitted case's CSV and the study's figure; returns the paths."""
    cols = floor_columns(study.cases[0].result)
    with atomic_paths(csv_path, png_path) as (csv_tmp, png_tmp):
        with csv_tmp.open("w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(list(cols))
            for row in zip(*cols.values()):
                writer.writerow([x if isinstance(x, str) else repr(float(x)) for x in row])
        fig = plot_floor_study(study)
        try:
            save_figure_file(fig, png_tmp, 100)
        finally:
            plt.close(fig)
    return [csv_path, png_path]
