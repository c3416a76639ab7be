"""Figures of the contact, single-motor and energy analyses (matplotlib; never calls show()).

Each function takes ``ax=None`` (a new figure) and returns the figure. The abscissa is the
stance crank angle in degrees; infeasible contact samples are shaded.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from pasibot_pin.viz.plots import figure_axes


def _axes(ax, figsize=(7.0, 4.0)):
    return figure_axes(ax, figsize)


def _shade_infeasible(ax, deg: np.ndarray, feasible: np.ndarray) -> None:
    bad = ~np.asarray(feasible, dtype=bool)
    if not bad.any():
        return
    half = 0.5 * (np.median(np.diff(deg)) if deg.size > 1 else 1.0)
    start = None
    for k in range(deg.size + 1):
        if k < deg.size and bad[k]:
            start = k if start is None else start
        elif start is not None:
            ax.axvspan(deg[start] - half, deg[k - 1] + half, color="tab:red", alpha=0.12, lw=0)
            start = None
    ax.plot([], [], color="tab:red", alpha=0.3, lw=6, label="infeasible (tip/slip)")


def plot_contact_forces(res, ax=None):
    """Heel and toe forces, normal and tangential [N], against the stance crank angle."""
    fig, ax = _axes(ax)
    deg = np.degrees(res.theta)
    ax.plot(deg, res.heel_force[:, 1], color="tab:blue", label="heel Fz")
    ax.plot(deg, res.toe_force[:, 1], color="tab:orange", label="toe Fz")
    ax.plot(deg, res.heel_force[:, 0], "--", color="tab:blue", label="heel Fx")
    ax.plot(deg, res.toe_force[:, 0], "--", color="tab:orange", label="toe Fx")
    ax.plot(deg, res.wrench[:, 1], ":", color="k", label="demanded Fz")
    _shade_infeasible(ax, deg, res.feasible)
    ax.set_xlabel("stance crank angle theta [deg]")
    ax.set_ylabel("ground force on the foot [N]")
    ax.set_title(f"heel/toe contact forces (mu = {res.mu:g}; best effort where infeasible)")
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)
    return fig


def plot_cop(res, ax=None):
    """Centre of pressure along the sole [mm] against the stance crank angle, with the sole's edges."""
    fig, ax = _axes(ax)
    deg = np.degrees(res.theta)
    cop = np.where(np.isfinite(res.s_cop), res.s_cop, np.nan) * 1e3
    ax.axhspan(np.min(res.s_heel) * 1e3, np.max(res.s_toe) * 1e3, color="tab:green", alpha=0.12, label="sole")
    ax.plot(deg, res.s_heel * 1e3, color="tab:green", lw=1)
    ax.plot(deg, res.s_toe * 1e3, color="tab:green", lw=1)
    ax.plot(deg, cop, color="k", label="CoP demanded (My / Fz)")
    _shade_infeasible(ax, deg, res.feasible)
    for ev in res.tip_events():
        ax.plot(math.degrees(ev["theta"]), (ev["x"] - np.interp(ev["t"], res.t, res.ankle_x)) * 1e3, "o", color="r")
    ax.set_xlabel("stance crank angle theta [deg]")
    ax.set_ylabel("CoP ahead of the stance ankle [mm]")
    ax.set_title("centre of pressure (red dots: the CoP crosses a sole edge)")
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)
    return fig


def plot_friction(res, ax=None):
    """Friction coefficient needed |Fx| / Fz [-] against the stance crank angle, and the available mu."""
    fig, ax = _axes(ax)
    deg = np.degrees(res.theta)
    need = np.where(np.isfinite(res.mu_needed), res.mu_needed, np.nan)
    ax.plot(deg, need, color="k", label="needed |Ft| / Fn")
    ax.axhline(res.mu, color="tab:red", ls="--", label=f"available mu = {res.mu:g}")
    ax.set_xlabel("stance crank angle theta [deg]")
    ax.set_ylabel("friction coefficient [-]")
    ax.set_title("friction needed by the stance foot")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    return fig


def contact_figure(res, title: str = ""):
    """Three stacked panels: forces, CoP, friction. Returns the figure."""
    from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

    fig, axes = subplots(3, 1, figsize=(7.5, 10.0), sharex=True)
    plot_contact_forces(res, axes[0])
    plot_cop(res, axes[1])
    plot_friction(res, axes[2])
    for ax in axes[:2]:
        ax.set_xlabel("")
    if title:
        fig.suptitle(title)
    return fig


def plot_single_motor(torques, single, ax=None):
    """Both crank torques of the two-motor solution and the single motor's torque [N.m]."""
    fig, ax = _axes(ax)
    deg = np.degrees(np.asarray(torques.theta_right))
    ax.plot(deg, torques.Ta, label="T_a (stance crank, two motors)")
    ax.plot(deg, torques.Ta_swing, label="T_a' (swing crank, two motors)")
    ax.plot(deg, single.motor, "k", lw=2, label="one motor (cranks coupled pi apart)")
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.set_xlabel("right crank angle theta_R [deg]")
    ax.set_ylabel("crank torque [N.m]")
    ax.set_title(f"one motor: peak {single.peak():.2f} N.m, RMS {single.rms():.2f} N.m")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    return fig


def plot_powers(powers: dict[str, np.ndarray], theta: np.ndarray, ax=None):
    """Actuator powers [W] against the stance crank angle (from :func:`pasibot_pin.studies.energy.actuator_powers`)."""
    fig, ax = _axes(ax)
    deg = np.degrees(np.asarray(theta))
    for name, p in powers.items():
        ax.plot(deg, p, label=name.replace("_", " "))
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.set_xlabel("stance crank angle theta [deg]")
    ax.set_ylabel("power given by the actuator [W]")
    ax.set_title("actuator power over a step")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    return fig


def plot_cost_of_transport(rows: Sequence, ax=None, key: str = "motors"):
    """Cost of transport [-] against the crank speed [rad/s], one line per variant."""
    fig, ax = _axes(ax)
    groups: dict[str, list] = {}
    for r in rows:
        groups.setdefault(r.variant, []).append(r)
    for variant, group in sorted(groups.items()):
        sel = sorted(group, key=lambda r: r.omega)
        ax.plot([r.omega for r in sel], [r.cot[key] for r in sel], "o-", label=f"{variant}: CoT {key}")
        if key == "motors" and any(r.ankle[1] for r in sel):  # the variant has ankle actuators (a spring)
            ax.plot(
                [r.omega for r in sel], [r.cot["actuators"] for r in sel], "s--", label=f"{variant}: CoT with ankles"
            )
        ax.plot([r.omega for r in sel], [r.cot["single"] for r in sel], "^:", label=f"{variant}: CoT one motor")
    ax.set_xscale("log")
    ax.set_xlabel("crank speed omega [rad/s]")
    ax.set_ylabel("cost of transport W+ / (m g d) [-]")
    ax.set_title("cost of transport (positive work, no regeneration)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, which="both")
    return fig
