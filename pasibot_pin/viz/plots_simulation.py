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
    from pasibot_pin.studies.statics import StaticEquilibrium


def _axes(ax, figsize=(7, 3.5)):
    return figure_axes(ax, figsize)


def _impact_lines(ax, result) -> None:
    for imp in result.impacts:
        ax.axvline(imp.t, color="#bbbbbb", lw=0.8, ls=":")


def plot_hip_pitch(results: Mapping[str, SimulationResult], ax=None):
    """Hip pitch against time for several runs (label -> SimulationResult)."""
    fig, ax = _axes(ax)
    for label, res in results.items():
        line = ax.plot(res.t, np.degrees(res.hip_pitch), lw=1.2, label=label)[0]
        if res.fell:
            ax.plot(res.t[-1], np.degrees(res.hip_pitch[-1]), "x", color=line.get_color(), ms=8)
    first = next(iter(results.values()), None)
    if first is not None:
        _impact_lines(ax, first)
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
    """Three panels: hip pitch of every run, ankle angles and motor torque of the ``main`` run.

    Args:
        results: label -> SimulationResult.
        main: the label whose ankle angles and motor torque are drawn (default: the first).
        rest_angle: the spring's rest angle beta0 [rad], drawn on the ankle panel.
        axes: three matplotlib axes, or ``None`` for a new figure.

    Returns:
        The figure.

    """
    if axes is None:
        from pasibot_pin.viz.plots_layout import subplots

        fig, axes = subplots(3, 1, figsize=(8, 9), sharex=True)
    else:
        fig = axes[0].figure
    main = main or next(iter(results))
    plot_hip_pitch(results, ax=axes[0])
    plot_ankle_angles(results[main], ax=axes[1], rest_angle=rest_angle)
    plot_motor_torque(results[main], ax=axes[2])
    for ax in axes[:-1]:
        ax.set_xlabel("")
    axes[1].set_title(f"run: {main}")
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
