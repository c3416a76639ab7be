"""Figures of the torque analysis.

Torques against beta with the fitted spring (seed Fig 7.3.2, 7.4.x), torques against time,
and K_e per scenario. Each function takes ``ax=None`` and returns the figure; none calls
``show()``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from pasibot_pin.viz.plots import figure_axes

TORQUE_STYLE = {
    "Ta": ("T_a (stance crank)", "tab:blue", "-"),
    "Te": ("T_e (stance ankle)", "tab:red", "-"),
    "Ta_swing": ("T_a' (swing crank)", "tab:blue", "--"),
    "Te_swing": ("T_e' (swing ankle)", "tab:red", "--"),
}


def _axes(ax):
    """(figure, axes, created): a new figure when ``ax`` is None."""
    created = ax is None
    fig, ax = figure_axes(ax, (7, 4.5))
    return fig, ax, created


def plot_torques_vs_beta(result, fit=None, ax=None, title: str | None = None):
    """T_a, T_e, T_a', T_e' against the stance ankle angle beta [deg], with the fitted spring line.

    Args:
        result: a :class:`~pasibot_pin.dynamics.inverse.TorqueResult`.
        fit: a :class:`~pasibot_pin.studies.methods.spring_fit.SpringFit` to draw (optional).
        ax: matplotlib axes (default: a new figure).
        title: figure title.

    Returns:
        The figure.

    """
    fig, ax, created = _axes(ax)
    beta_deg = np.degrees(result.beta)
    order = np.argsort(beta_deg)
    for key, (label, colour, style) in TORQUE_STYLE.items():
        ax.plot(beta_deg[order], getattr(result, key)[order], style, color=colour, marker=".", ms=3, label=label)
    if fit is not None:
        line = np.linspace(result.beta.min(), result.beta.max(), 50)
        ax.plot(
            np.degrees(line),
            fit.torque(line),
            ":",
            color="k",
            lw=2,
            label=f"fit: K_e = {fit.K_e:.1f} N.m/rad, beta0 = {math.degrees(fit.beta0):.1f} deg, R^2 = {fit.r2:.3f}",
        )
    ax.set_xlabel("stance ankle angle beta [deg]")
    ax.set_ylabel("torque [N.m]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    if title:
        ax.set_title(title)
    return fig


def plot_torques_vs_time(result, ax=None, title: str | None = None):
    """The four torques against time [s] (against the right crank angle [deg] when quasi-static)."""
    fig, ax, created = _axes(ax)
    if result.omega > 0:
        x, xlabel = result.t, "time t [s]"
    else:
        x, xlabel = np.degrees(result.theta_right), "right crank angle theta_R [deg] (quasi-static)"
    for key, (label, colour, style) in TORQUE_STYLE.items():
        ax.plot(x, getattr(result, key), style, color=colour, label=label)
    swaps = [k for k in range(1, len(result.stance)) if result.stance[k] != result.stance[k - 1]]
    for k in swaps:
        ax.axvline(x[k], color="grey", lw=0.8, alpha=0.6)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("torque [N.m]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    if title:
        ax.set_title(title + (" (grey: stance swaps)" if swaps else ""))
    return fig


def plot_stiffness_table(
    names: Sequence[str], values: Mapping[str, Sequence[float]], ax=None, title: str | None = None
):
    """Grouped bars of K_e [N.m/rad] per scenario, one bar per model (``values``: label -> K_e list)."""
    fig, ax, created = _axes(ax)
    width = 0.8 / max(len(values), 1)
    x = np.arange(len(names))
    for k, (label, ks) in enumerate(values.items()):
        ax.bar(x + k * width, [np.nan if v is None else v for v in ks], width, label=label)
    ax.set_xticks(x + width * (len(values) - 1) / 2)
    ax.set_xticklabels(names)
    ax.set_ylabel("ankle stiffness K_e [N.m/rad]")
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend(fontsize=8)
    if title:
        ax.set_title(title)
    return fig
