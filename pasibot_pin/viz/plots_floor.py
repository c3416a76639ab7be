"""Figures of the floor simulation: hip pitch of each spring case, and each foot's contact mode.

Each function takes ``ax=None`` (or ``axes=None``) and returns the figure; none calls show().
Angles in degrees, time in s.
"""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np

from pasibot_pin.dynamics.floor.run import MODES
from pasibot_pin.dynamics.verdict import TIP_LIMIT
from pasibot_pin.model.coordinates import SIDES
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


def plot_floor3d_study(study, axes=None):
    """Hip roll and hip pitch [deg] against time [s] of every case of a 3-D floor study; returns the figure.

    The roll panel marks the tip limit (|roll| past it: ``tipped``); an x marks where a run stopped
    at a failure (it tipped, fell, slipped, ...).
    """
    if axes is None:
        from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

        fig, axes = subplots(2, 1, figsize=(7, 5.5), sharex=True)
    else:
        fig = axes[0].figure
    for case in study.cases:
        res = case.result
        for ax, angle in zip(axes, (res.roll, res.pitch), strict=True):
            line = ax.plot(res.t, np.degrees(angle), lw=1.2, label=case.label)[0]
            if res.verdict.outcome not in ("walks", "undecided") and len(res.t):
                ax.plot(res.t[-1], np.degrees(angle[-1]), "x", color=line.get_color(), ms=8)
    limit = math.degrees(TIP_LIMIT)
    for sign in (1.0, -1.0):
        axes[0].axhline(sign * limit, color="k", ls="--", lw=0.8, label="tip limit" if sign > 0 else None)
    axes[0].set_ylabel("hip roll [deg]")
    axes[0].set_title(f"{study.scenario} on the 3-D floor (x: the run failed)")
    axes[0].legend(fontsize=8)
    axes[1].set_ylabel("hip pitch [deg]")
    axes[1].set_xlabel("time [s]")
    for ax in axes:
        ax.axhline(0.0, color="k", lw=0.6)
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
        from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

        fig, axes = subplots(2, 1, figsize=(7, 5.5), height_ratios=(3, 1.4))
    else:
        fig = axes[0].figure
    plot_floor_pitch(study, ax=axes[0])
    fitted = study.cases[0]
    plot_contact_modes(fitted.result, ax=axes[1], title=f"contact modes, {fitted.label} spring")
    return fig


WELD_COLOUR, FLOOR_COLOUR = "#457b9d", "#e76f51"
"""The weld's and the floor's bars in :func:`plot_weld_vs_floor`."""


def plot_weld_vs_floor(study, ax=None):
    """Largest |hip pitch| [deg] of every scenario and spring case, weld beside floor (``FloorSpringStudy``).

    Every bar carries its value above it (a zero is a ``0.0`` and a dot on the axis, not a missing bar);
    hatched bars: the run fell or failed (the bar is where it stopped, labelled ``fell``/``failed``).
    The legend names the colours and the hatch; the ticks name the spring case (and the run when
    there are several).
    """
    from matplotlib.patches import Patch  # deferred: heavy (matplotlib), keeps the CLI's start fast

    rows = study.rows
    fig, ax = figure_axes(ax, (max(9.0, 2.5 + 1.0 * len(rows)), 3.8))  # about an inch per spring case
    x = np.arange(len(rows))
    several = len({r.scenario for r in rows}) > 1
    for k, r in enumerate(rows):
        weld_fell, floor_failed = not np.isnan(r.weld_fell_at), bool(r.floor_failed)
        bars = (
            (x[k] - 0.2, np.degrees(r.weld_max_pitch), WELD_COLOUR, weld_fell, "fell"),
            (x[k] + 0.2, np.degrees(r.floor_max_pitch), FLOOR_COLOUR, floor_failed, "failed"),
        )
        for xk, value, colour, stopped, word in bars:
            ax.bar(xk, value, 0.4, color=colour, hatch="//" if stopped else None, ec="k" if stopped else colour)
            ax.plot(xk, 0.0, "o", color=colour, ms=4, clip_on=False, zorder=3)  # a zero bar stays visible
            ax.annotate(
                word if stopped else f"{value:.1f}",
                (xk, value),
                xytext=(0, 2),
                textcoords="offset points",
                ha="center",
                va="bottom",
                fontsize=8,
            )
    labels = [f"{r.scenario}\n{r.case}" if several else r.case for r in rows]
    ax.set_xticks(x, labels, fontsize=9)
    ax.set_xlim(-0.6, len(rows) - 0.4)
    ax.set_ylim(0.0, 1.15 * max([1.0] + [np.degrees(max(r.weld_max_pitch, r.floor_max_pitch)) for r in rows]))
    ax.set_xlabel("spring case" if not several else "run and spring case")
    ax.set_ylabel("largest |hip pitch| [deg]")
    scenarios = ", ".join(dict.fromkeys(r.scenario for r in rows))
    ax.set_title(f"{scenarios}: largest |hip pitch| over {study.settings.duration:g} s, weld against floor")
    handles = [
        Patch(color=WELD_COLOUR, label="welded stance foot"),
        Patch(color=FLOOR_COLOUR, label="on the floor (heel and toe)"),
        Patch(facecolor="white", edgecolor="k", hatch="//", label="fell or failed (bar: where it stopped)"),
    ]
    ax.legend(handles=handles, fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # beside: never on a bar
    ax.grid(alpha=0.3, axis="y")
    return fig


def plot_floor_static_map(sweep, what: str = "floor", ax=None):
    """One run's K_e x beta0 map of the quasi-static answer (``FloorStaticSweep``), ``weld`` or ``floor``.

    One cell per grid point (K_e [N.m/rad] across, beta0 [deg] up). Colour: the largest |hip pitch|
    along the stance [deg]; grey cells have none, their text says why (weld: ``none``; floor: the
    first failure, its crank angle, and the crank angles held flat). Star: the fitted spring.
    """
    fig, ax = figure_axes(ax, (6, 4.5))
    grid = np.degrees(sweep.grid(what))
    k, b = np.asarray(sweep.stiffness), np.degrees(np.asarray(sweep.rest))
    ax.imshow(np.ones(grid.shape), cmap="Greys", vmin=0, vmax=5, origin="lower", aspect="auto")
    image = ax.imshow(
        np.where(np.isfinite(grid), grid, np.nan), cmap="viridis_r", vmin=0, vmax=30, origin="lower", aspect="auto"
    )
    for i in range(len(b)):
        for j in range(len(k)):
            cell = sweep.cells[i][j]
            if np.isfinite(grid[i, j]):
                text = f"{grid[i, j]:.1f}"
            elif what == "weld" or cell.failure is None:
                text = "none"
            else:
                theta, status = cell.failure
                flat = sum(s == "flat" for s in cell.status)
                text = f"{status} {math.degrees(theta):.0f}°\n{flat}/{len(cell.status)} flat"
            ax.text(j, i, text, ha="center", va="center", fontsize=6)
    fit_k = int(np.argmin(np.abs(k - sweep.fitted.stiffness)))
    fit_b = int(np.argmin(np.abs(np.asarray(sweep.rest) - sweep.fitted.rest_angle)))
    ax.plot(fit_k, fit_b - 0.3, "*", color="#e6007e", ms=10)
    ax.set_xticks(range(len(k)), [f"{x:.0f}" for x in k], fontsize=7)
    ax.set_yticks(range(len(b)), [f"{x:.1f}" for x in b], fontsize=7)
    ax.set_xlabel("K_e [N.m/rad]")
    ax.set_ylabel("beta0 [deg]")
    ax.set_title(f"{sweep.scenario}, {what}", fontsize=9)
    fig.colorbar(image, ax=ax, label="max |hip pitch| [deg]")
    return fig


def plot_floor_static_maps(sweeps, axes=None):
    """The K_e x beta0 maps of every run (rows), weld (left) beside floor (right); returns the figure."""
    sweeps = [s for s in sweeps if s.stiffness is not None]
    if axes is None:
        from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

        fig, axes = subplots(len(sweeps), 2, figsize=(10, 3.2 * len(sweeps)), squeeze=False)
    else:
        axes = np.atleast_2d(axes)
        fig = axes[0, 0].figure
    for row, sweep in enumerate(sweeps):
        for col, what in enumerate(("weld", "floor")):
            plot_floor_static_map(sweep, what, ax=axes[row, col])
    return fig
