"""Figures of the floor simulation: hip pitch of each spring case, and each foot's contact mode.

Each function takes ``ax=None`` (or ``axes=None``) and returns the figure; none calls show().
Angles in degrees, time in s.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from pasibot_pin.dynamics.floor import MODES, SIDES
from pasibot_pin.viz.plots import figure_axes

MODE_COLORS = {"flat": "#2a9d8f", "heel": "#e9c46a", "toe": "#f4a261", "sliding": "#e76f51", "air": "#ffffff"}
"""One colour per contact mode (air is blank)."""


def plot_floor_pitch(study, ax=None):
    """Hip pitch [deg] against time [s] of every spring case of a floor study (``FloorStudy``)."""
    fig, ax = figure_axes(ax, (7, 3.5))
    for case in study.cases:
        res = case.result
        line = ax.plot(res.t, np.degrees(res.hip_pitch), lw=1.2, label=case.label)[0]
        if res.failed and len(res.t):
            ax.plot(res.t[-1], np.degrees(res.hip_pitch[-1]), "x", color=line.get_color(), ms=8)
    ax.axhline(0.0, color="k", lw=0.6)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("hip pitch [deg]")
    ax.set_title(f"{study.scenario} on the floor (x: the run failed)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return fig


def plot_contact_modes(result, ax=None, title: str = "contact mode of each foot"):
    """Each foot's contact mode against time [s] of one :class:`~pasibot_pin.dynamics.floor.FloorResult`."""
    fig, ax = figure_axes(ax, (7, 1.8))
    for row, side in enumerate(SIDES):
        modes = result.modes[side]
        start = 0
        for k in range(1, len(modes) + 1):
            if k == len(modes) or modes[k] != modes[start]:
                t0 = result.t[start - 1] if start > 0 else 0.0
                ax.broken_barh([(t0, result.t[k - 1] - t0)], (row - 0.4, 0.8), color=MODE_COLORS[modes[start]])
                start = k
    ax.set_yticks(range(len(SIDES)), SIDES)
    ax.set_xlabel("time [s]")
    ax.set_title(title)
    handles = [plt.Rectangle((0, 0), 1, 1, color=MODE_COLORS[m], ec="k", lw=0.3) for m in MODES]
    ax.legend(handles, MODES, fontsize=7, ncol=len(MODES), loc="upper right")
    return fig


def plot_floor_study(study, axes=None):
    """Hip pitch of every case above the fitted case's contact modes; returns the figure."""
    if axes is None:
        fig, axes = plt.subplots(2, 1, figsize=(7, 5.5), height_ratios=(3, 1.4), constrained_layout=True)
    else:
        fig = axes[0].figure
    plot_floor_pitch(study, ax=axes[0])
    fitted = study.cases[0]
    plot_contact_modes(fitted.result, ax=axes[1], title=f"contact modes, {fitted.label} spring")
    return fig


def plot_weld_vs_floor(study, ax=None):
    """Largest |hip pitch| [deg] of every scenario and spring case, weld beside floor (``FloorSpringStudy``).

    Hatched bars: the run fell or failed (the bar is where it stopped).
    """
    fig, ax = figure_axes(ax, (9, 3.8))
    rows = study.rows
    x = np.arange(len(rows))
    weld = [np.degrees(r.weld_max_pitch) for r in rows]
    floor = [np.degrees(r.floor_max_pitch) for r in rows]
    for k, r in enumerate(rows):
        ax.bar(x[k] - 0.2, weld[k], 0.4, color="#457b9d", hatch="//" if not np.isnan(r.weld_fell_at) else None)
        ax.bar(x[k] + 0.2, floor[k], 0.4, color="#e76f51", hatch="//" if r.floor_failed else None)
    ax.set_xticks(x, [f"{r.scenario}\n{r.case}" for r in rows], fontsize=6, rotation=90)
    ax.set_ylabel("largest |hip pitch| [deg]")
    ax.set_title(f"weld (blue) against floor (orange) over {study.settings.duration:g} s; hatched: fell or failed")
    ax.grid(alpha=0.3, axis="y")
    return fig
