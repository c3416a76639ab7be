"""Figures of the kinematic analyses: foot paths, foot pitch, K sweep, ankle motion, biped gait.

Each function takes ``ax=None`` (a new figure when omitted) and returns the figure; none
calls ``show()``. Stance is drawn solid, swing dashed; angles are shown in degrees.
"""

from __future__ import annotations

import math

import numpy as np

from pasibot_pin.errors import ParameterError
from pasibot_pin.kinematics.leg import STANCE, LegCycle
from pasibot_pin.kinematics.path_metrics import KSweep
from pasibot_pin.viz.plots import GROUND_LINE_COLOUR, GROUP_COLOURS, figure_axes, plot_robot

POINT_COLOURS = {"ankle": "#2673d9", "toe": "#d62728", "heel": "#7f7f7f", "hip": "#000000"}


def _axes(ax, figsize=(6, 5)):
    return figure_axes(ax, figsize)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Index ranges [start, end] (inclusive) of consecutive True values."""
    runs, start = [], None
    for k, m in enumerate(mask):
        if m and start is None:
            start = k
        if not m and start is not None:
            runs.append((start, k - 1))
            start = None
    if start is not None:
        runs.append((start, len(mask) - 1))
    return runs


def _phase_lines(ax, xy: np.ndarray, stance: np.ndarray, colour: str, label: str, lw: float = 2.0) -> None:
    """Plot a path solid where ``stance`` and dashed elsewhere (runs overlap by one sample)."""
    first = True
    for flag, style, width in ((True, "-", lw), (False, "--", lw * 0.6)):
        for a, b in _runs(stance == flag):
            lo, hi = max(a - 1, 0), min(b + 1, len(xy) - 1)
            ax.plot(
                xy[lo : hi + 1, 0],
                xy[lo : hi + 1, 1],
                style,
                color=colour,
                lw=width,
                label=(f"{label} (stance solid, swing dashed)" if first else None),
            )
            first = False


def _shade_stance(ax, theta_deg: np.ndarray) -> None:
    """Shade the stance windows (90..270 deg mod 360) over the crank-angle axis."""
    lo, hi = float(np.min(theta_deg)), float(np.max(theta_deg))
    first = True
    for turn in range(math.floor(lo / 360) - 1, math.ceil(hi / 360) + 1):
        a, b = 360 * turn + math.degrees(STANCE[0]), 360 * turn + math.degrees(STANCE[1])
        if b >= lo and a <= hi:
            ax.axvspan(max(a, lo), min(b, hi), color="#e8e8e8", zorder=0, label="stance" if first else None)
            first = False


def plot_leg_paths(cycle: LegCycle, ax=None, points: tuple[str, ...] = ("ankle", "toe", "heel")):
    """Ankle, toe and heel paths of one leg in the leg frame (seed Figs 4.2.5, 4.2.6, 4.3.5).

    Args:
        cycle: a :class:`~pasibot_pin.kinematics.leg.LegCycle`.
        ax: axes to draw on (default: a new figure).
        points: which paths to draw.

    Returns:
        The matplotlib figure.

    """
    fig, ax = _axes(ax)
    stance = cycle.in_stance()
    for name in points:
        _phase_lines(ax, getattr(cycle, name), stance, POINT_COLOURS[name], name)
    wrapped = np.mod(cycle.theta, 2 * math.pi)
    for deg in (90, 180, 270):
        k = np.flatnonzero(np.abs(wrapped - math.radians(deg)) < 1e-9)
        if k.size:
            ax.plot(*cycle.ankle[k[0]], "o", color=POINT_COLOURS["ankle"], ms=4)
            ax.annotate(f"{deg}°", cycle.ankle[k[0]], textcoords="offset points", xytext=(0, -12), fontsize=8)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (leg frame, forward) [m]")
    ax.set_ylabel("z (leg frame, up) [m]")
    ax.set_title(f"{cycle.robot.variant}: foot paths over a crank turn")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="upper right")
    return fig


def plot_foot_pitch(cycles: dict[str, LegCycle], ax=None):
    """Foot pitch against crank angle for several variants (stance shaded) [deg]."""
    fig, ax = _axes(ax, (7, 4))
    theta_deg = None
    for label, cycle in cycles.items():
        theta_deg = np.degrees(cycle.theta)
        ax.plot(theta_deg, np.degrees(cycle.foot_pitch), label=label)
    if theta_deg is not None:
        _shade_stance(ax, theta_deg)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("crank angle θ [deg]")
    ax.set_ylabel("foot pitch (heel → toe, CCW) [deg]")
    ax.set_title("Foot pitch in the leg frame")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return fig


def plot_k_sweep(sweep: KSweep, ax=None):
    """Ankle paths for several frame ratios K = L0 / L (seed Fig 4.2.4)."""
    fig, ax = _axes(ax)
    colours = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b"]
    for k, (K, cycle) in enumerate(zip(sweep.K, sweep.cycles)):
        stance = cycle.in_stance()
        _phase_lines(ax, cycle.ankle, stance, colours[k % len(colours)], f"K = {K:g}")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (leg frame) [m]")
    ax.set_ylabel("z (leg frame) [m]")
    ax.set_title(f"{sweep.variant}: ankle path for several K")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    return fig


def plot_ankle_velocity(cycle: LegCycle, ax=None):
    """Ankle velocity components against crank angle (seed Fig 5.1, top) [m/s]."""
    return _plot_motion(cycle, "ankle_velocity", "ankle velocity [m/s]", ("v_x", "v_z"), ax)


def plot_ankle_acceleration(cycle: LegCycle, ax=None):
    """Ankle acceleration components against crank angle (seed Fig 5.1, bottom) [m/s^2]."""
    return _plot_motion(cycle, "ankle_acceleration", "ankle acceleration [m/s²]", ("a_x", "a_z"), ax)


def _plot_motion(cycle: LegCycle, attr: str, ylabel: str, names: tuple[str, str], ax):
    values = getattr(cycle, attr)
    if values is None:
        raise ParameterError("parameter 'cycle' has no velocities: build it with leg_cycle(..., omega=...)")
    fig, ax = _axes(ax, (7, 4))
    theta_deg = np.degrees(cycle.theta)
    _shade_stance(ax, theta_deg)
    ax.plot(theta_deg, values[:, 0], label=names[0])
    ax.plot(theta_deg, values[:, 1], label=names[1])
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("crank angle θ [deg]")
    ax.set_ylabel(ylabel)
    ax.set_title(f"{cycle.robot.variant}: {ylabel.split(' [')[0]} at ω = {cycle.omega:g} rad/s (leg frame)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return fig


def plot_leg_summary(cycle: LegCycle):
    """Four panels: foot paths, foot pitch, ankle velocity and acceleration (needs ``omega``)."""
    from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

    fig, axes = subplots(2, 2, figsize=(12, 9))
    plot_leg_paths(cycle, ax=axes[0, 0])
    plot_foot_pitch({cycle.robot.variant: cycle}, ax=axes[0, 1])
    if cycle.ankle_velocity is not None:
        plot_ankle_velocity(cycle, ax=axes[1, 0])
        plot_ankle_acceleration(cycle, ax=axes[1, 1])
    else:
        axes[1, 0].axis("off")
        axes[1, 1].axis("off")
    return fig


GAIT_LEGEND_GAP = 6.0
"""Gap between the gait plot's x axis and its legend below, in legend font sizes (7 pt): room for
the tick labels and the axis label."""


def plot_gait(gait, ax=None, snapshots: int = 5, points: tuple[str, ...] = ("ankle", "toe", "heel")):
    """The biped walking in the world frame: hip path, both feet's paths, stick figures.

    Each foot's path is solid while that leg is in stance and dashed in swing.

    Args:
        gait: a :class:`~pasibot_pin.kinematics.gait.Gait`.
        ax: axes to draw on (default: a new figure).
        snapshots: number of stick figures drawn along the gait (0 for none).
        points: which foot points to trace (``ankle``, ``toe``, ``heel``).

    Returns:
        The matplotlib figure.

    """
    fig, ax = _axes(ax, (11, 6))
    robot = gait.robot
    if snapshots > 0:
        for k in np.linspace(0, gait.n - 1, snapshots).round().astype(int):
            plot_robot(robot, gait.q[k], ax=ax, ground=False, alpha=0.35)
    names = {"ankle": "foot", "toe": "toe", "heel": "heel"}
    frames = [f"{side}_{names[p]}" for side in ("right", "left") for p in points] + ["hip"]
    xz = gait.frames_xz(frames)
    stance = np.array(gait.stance)
    for side in ("right", "left"):
        for p in points:
            colour = POINT_COLOURS[p] if side == "right" else _lighter(POINT_COLOURS[p])
            _phase_lines(ax, xz[f"{side}_{names[p]}"], stance == side, colour, f"{side} {p}", lw=1.6)
    ax.plot(xz["hip"][:, 0], xz["hip"][:, 1], color=POINT_COLOURS["hip"], lw=1.5, label="hip (crank axis)")
    ax.axhline(0.0, color=GROUND_LINE_COLOUR, lw=1, label="ground")
    ax.set_aspect("equal")
    ax.set_xlabel("x (world, walking direction) [m]")
    ax.set_ylabel("z (world, up) [m]")
    steps = int(gait.step.max()) + 1
    ax.set_title(f"PASIBOT {robot.variant}: {steps} step(s), foot = {gait.foot}")
    ax.grid(True, alpha=0.3)
    # below the x axis' tick labels and label whatever the axes' height (borderaxespad in legend font sizes)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, 0.0), borderaxespad=GAIT_LEGEND_GAP, ncol=4)
    return fig


def _lighter(colour: str) -> str:
    rgb = np.array([int(colour[i : i + 2], 16) for i in (1, 3, 5)], dtype=float)
    rgb = rgb + (255 - rgb) * 0.5
    return "#" + "".join(f"{int(c):02x}" for c in rgb)


def plot_gait_hip(gait, ax=None):
    """Hip height (relative to its mean) and hip pitch against the right-crank angle."""
    fig, ax = _axes(ax, (8, 4))
    hip = gait.hip_path()
    theta_deg = np.degrees(gait.theta)
    L = gait.robot.geometry.L
    height = hip[:, 1] - hip[:, 1].mean()
    ax.plot(theta_deg, height, color=POINT_COLOURS["hip"], label="hip height − mean")
    for boundary in np.flatnonzero(np.diff(gait.step)) + 1:
        ax.axvline(theta_deg[boundary], color="#999999", lw=0.8, ls=":")
    ax.set_xlabel("right crank angle θ [deg]")
    ax.set_ylabel("hip height − mean [m]")
    twin = ax.twinx()
    pitch_deg = np.degrees(gait.pitch("hip"))
    twin.plot(theta_deg, pitch_deg, color=GROUP_COLOURS["hoeken"], label="hip pitch")
    if np.ptp(pitch_deg) < 1e-6:  # level hip: do not magnify round-off
        twin.set_ylim(-1.0, 1.0)
    twin.set_ylabel("hip pitch (atan2) [deg]")
    ax.set_title(f"{gait.robot.variant}: hip height (peak-to-peak {np.ptp(hip[:, 1]) / L:.4f} L) and pitch")
    ax.grid(True, alpha=0.3)
    lines = ax.get_legend_handles_labels()
    lines2 = twin.get_legend_handles_labels()
    ax.legend(lines[0] + lines2[0], lines[1] + lines2[1], fontsize=8, loc="upper right")
    return fig
