"""Figures of the forward simulation: hip pitch, ankle angles, motor torque, the spring sweep.

Each function takes ``ax=None`` (or ``axes=None``) and returns the figure; none calls show().
Angles are plotted in degrees, torques in N.m, time in s.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from pasibot_pin.viz.plots import figure_axes

if TYPE_CHECKING:
    from pasibot_pin.dynamics.simulator import SimulationResult
    from pasibot_pin.studies.methods.statics import StaticEquilibrium


def _axes(ax, figsize=(7, 3.5)):
    return figure_axes(ax, figsize)


def _impact_lines(ax, result) -> None:
    for imp in result.impacts:
        ax.axvline(imp.t, color="#bbbbbb", lw=0.8, ls=":")


FALL_WINDOW = 0.2
"""A run that fell before this share of the longest run gets its own panel of the first seconds [-]."""


def fall_window(results: Mapping[str, SimulationResult]) -> float | None:
    """The time span [s] of the falls' panel: 1.5 x the last fall, or None when no run fell that early."""
    falls = [float(res.t[-1]) for res in results.values() if res.fell and len(res.t)]
    longest = max((float(res.t[-1]) for res in results.values() if len(res.t)), default=0.0)
    if not falls or max(falls) >= FALL_WINDOW * longest:
        return None
    return 1.5 * max(falls)


def plot_hip_pitch(results: Mapping[str, SimulationResult], ax=None, t_max: float | None = None, falls: bool = True):
    """Hip pitch [deg] against time [s] for several runs (label -> SimulationResult).

    Args:
        results: label -> SimulationResult.
        ax: matplotlib axes or ``None``.
        t_max: draw up to this time [s] and set the axis there (``None``: every sample).
        falls: draw the runs that fell (an x and "fell at ... s" where each stopped); ``False``
            leaves them out (they are shown in a panel of their own).

    Returns:
        The figure.

    """
    fig, ax = _axes(ax)
    for k, (label, res) in enumerate(results.items()):  # one colour per run, whichever panel draws it
        if res.fell and not falls:
            continue
        keep = slice(None) if t_max is None else np.asarray(res.t) <= t_max
        line = ax.plot(res.t[keep], np.degrees(res.hip_pitch[keep]), lw=1.2, label=label, color=f"C{k % 10}")[0]
        if res.fell:
            t, pitch = res.t[-1], np.degrees(res.hip_pitch[-1])
            ax.plot(t, pitch, "x", color=line.get_color(), ms=8)
            ax.annotate(f"fell at {t:.2f} s", (t, pitch), xytext=(4, -10), textcoords="offset points", fontsize=7)
    first = next(iter(results.values()), None)
    if first is not None and t_max is None:
        _impact_lines(ax, first)
    if t_max is not None:
        ax.set_xlim(0.0, t_max)
    ax.axhline(0.0, color="k", lw=0.6)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("hip pitch [deg]")
    ax.set_title("hip pitch (x: fell; dotted: touchdowns)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return fig


def plot_ankle_angles(result, ax=None, rest_angle: float | None = None):
    """Ankle angles beta (right, left) against time; optionally the spring's rest angle [rad]."""
    fig, ax = _axes(ax)
    for col, (side, colour) in enumerate((("right", "#d62728"), ("left", "#8e44ad"))):
        ax.plot(result.t, np.degrees(result.beta[:, col]), color=colour, lw=1.2, label=f"beta {side}")
    if rest_angle is not None:
        ax.axhline(np.degrees(rest_angle), color="k", lw=0.8, ls="--", label="beta0")
    _impact_lines(ax, result)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("ankle angle beta [deg]")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return fig


def plot_motor_torque(result, ax=None):
    """Crank (motor) torques against time [N.m]."""
    fig, ax = _axes(ax)
    for col, (side, colour) in enumerate((("right", "#d62728"), ("left", "#8e44ad"))):
        ax.plot(result.t, result.motor_torque[:, col], color=colour, lw=1.0, label=f"T_a {side} crank")
    _impact_lines(ax, result)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("motor torque [N.m]")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return fig


def plot_simulation(
    results: Mapping[str, SimulationResult], main: str | None = None, rest_angle: float | None = None, axes=None
):
    """Hip pitch of every run, ankle angles and motor torque of the ``main`` run, against time [s].

    When some runs fell early (:func:`fall_window`), a first panel shows the first seconds with
    every run, each fall marked with an x and its time; the hip-pitch panel below then spans the
    whole run of the springs that held. Otherwise there are three panels, every run in the first.

    Args:
        results: label -> SimulationResult.
        main: the label whose ankle angles and motor torque are drawn (default: the first).
        rest_angle: the spring's rest angle beta0 [rad], drawn on the ankle panel.
        axes: three (or, when runs fell early, four) matplotlib axes, or ``None`` for a new figure.

    Returns:
        The figure.

    """
    window = fall_window(results)
    if axes is None:
        from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

        rows = 3 if window is None else 4
        ratios = (3, 3, 3) if window is None else (2.4, 3, 3, 3)
        fig, axes = subplots(rows, 1, figsize=(8, 3 * rows), height_ratios=ratios)
        for ax in axes[rows - 2 :]:
            ax.sharex(axes[rows - 3])
    else:
        fig = axes[0].figure
    main = main or next(iter(results))
    full = axes if window is None else axes[1:]
    if window is not None:
        plot_hip_pitch(results, ax=axes[0], t_max=window)
        axes[0].set_title(f"the first {window:.2f} s: where the runs fell (x)")
    plot_hip_pitch(results, ax=full[0], falls=window is None)
    if window is not None:
        full[0].set_title("the whole run of the springs that held (dotted: touchdowns)")
    plot_ankle_angles(results[main], ax=full[1], rest_angle=rest_angle)
    plot_motor_torque(results[main], ax=full[2])
    for ax in full[:-1]:
        ax.set_xlabel("")
    full[1].set_title(f"run: {main}")
    return fig


def plot_spring_sweep(
    stiffness: ArrayLike,
    rest_angles: ArrayLike,
    excursion: np.ndarray,
    fitted: tuple[float, float] | None = None,
    best: tuple[float, float] | None = None,
    ax=None,
):
    """Map of the largest hip-pitch excursion over (K_e, beta0).

    Args:
        stiffness: K_e values [N.m/rad] (columns).
        rest_angles: beta0 values [rad] (rows).
        excursion: (len(rest_angles), len(stiffness)) largest |hip pitch| [rad]; inf or NaN
            where the robot fell.
        fitted: the inverse-dynamics fit (K_e [N.m/rad], beta0 [rad]), marked with a star.
        best: the most level pair, marked with a circle.
        ax: matplotlib axes or ``None``.

    Returns:
        The figure.

    """
    fig, ax = _axes(ax, figsize=(6, 4.5))
    data = np.degrees(np.where(np.isfinite(excursion), excursion, np.nan))
    k = np.asarray(stiffness, dtype=float)
    b = np.degrees(np.asarray(rest_angles, dtype=float))
    mesh = ax.pcolormesh(k, b, data, shading="nearest", cmap="viridis_r")
    fig.colorbar(mesh, ax=ax, label="max |hip pitch| [deg] (blank: fell or no stable equilibrium)")
    if fitted is not None:
        ax.plot(fitted[0], np.degrees(fitted[1]), "*", color="#e6007e", ms=14, label="inverse-dynamics fit")
    if best is not None:
        ax.plot(best[0], np.degrees(best[1]), "o", mfc="none", mec="w", ms=12, mew=2, label="most level")
    ax.set_xlabel("stiffness K_e [N.m/rad]")
    ax.set_ylabel("rest angle beta0 [deg]")
    ax.legend(fontsize=8, loc="best")
    return fig


def plot_static_equilibrium(equilibria: Mapping[str, StaticEquilibrium], ax=None):
    """Static-equilibrium hip pitch against the crank angle (label -> StaticEquilibrium)."""
    fig, ax = _axes(ax)
    missing = []
    for label, eq in equilibria.items():
        stable = eq.found & (eq.stiffness > 0)
        if not np.any(stable):  # nothing to draw: named in the title, not in the legend
            missing.append(label)
            continue
        ax.plot(np.degrees(eq.theta[stable]), np.degrees(eq.hip_pitch[stable]), ".-", lw=1.2, label=label)
    ax.axhline(0.0, color="k", lw=0.6)
    ax.set_xlabel("stance crank angle theta [deg]")
    ax.set_ylabel("equilibrium hip pitch [deg]")
    title = "quasi-static limit (omega -> 0); gaps: no stable equilibrium"
    if missing:
        title += f"\nnone stable at any crank angle: {', '.join(missing)}"
    ax.set_title(title, fontsize=10)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return fig
