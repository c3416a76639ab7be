"""A design's walk on the floor as files: its animation (meshcat HTML page, stick GIF) and its JSON.

The frames are the floor run's configurations resampled at ``fps`` frames per second of
simulated time; each foot's floor force (heel plus toe, at their centre of pressure) is an arrow,
each foot's contact mode the one the simulation found.

Units: SI, angles [rad] (degrees in the printed and JSON figures, named ``_deg``).
"""

from __future__ import annotations

import math
from dataclasses import asdict
from pathlib import Path

import numpy as np

from pasibot_pin.constraints import frame_rows
from pasibot_pin.files import atomic_path
from pasibot_pin.model.coordinates import SIDES
from pasibot_pin.model.spatial import free_flyer_model
from pasibot_pin.studies.motor_load import motor_load
from pasibot_pin.viz.animation import save_gif
from pasibot_pin.viz.viewer import ForceArrows, WalkViewer, build_walk_scene

FORCE_SCALE = 5e-4
"""Arrow length per newton of floor force [m/N]."""


def walk_frames(result, fps: float) -> np.ndarray:
    """Indices of the run's samples nearest each frame at ``fps`` frames per second [1/s]."""
    times = np.arange(0.0, result.t[-1] + 1e-12, 1.0 / fps) if len(result.t) else np.zeros(1)
    return np.clip(np.searchsorted(result.t, times), 0, max(len(result.t) - 1, 0))


def floor_force_tracks(robot, result, index: np.ndarray) -> dict:
    """One :class:`~pasibot_pin.viz.viewer.ForceArrows` per foot: its floor force at its centre of pressure.

    The heel and toe points of every frame are evaluated in one batch (:func:`~pasibot_pin.constraints.frame_rows`).
    """
    frames = [robot.frame_id(f"{side}_{point}") for side in SIDES for point in result.points]
    xz = frame_rows(robot.model, frames, range(len(frames))).positions(result.q[index])  # (N, points) x + i z [m]
    tracks, n = {}, len(result.points)
    for i, side in enumerate(SIDES):
        feet = slice(n * i, n * i + n)
        fn, ft = result.normal[index, feet], result.tangential[index, feet]
        total = fn.sum(axis=1)
        weights = np.where(total[:, None] > 0, fn / np.where(total > 0, total, 1.0)[:, None], 1.0 / n)
        cop = np.sum(weights * xz[:, feet], axis=1)
        points = np.column_stack((cop.real, np.zeros(len(index)), cop.imag))
        forces = np.column_stack((ft.sum(axis=1), np.zeros(len(index)), total))
        tracks[f"{side} foot"] = ForceArrows(points, forces, FORCE_SCALE)
    return tracks


def write_walk_animation(
    walk,
    robot,
    html: Path | None = None,
    gif: Path | None = None,
    fps: float = 20.0,
    dpi: int = 100,
    progress: bool = False,
):
    """Write the walk as a one-file meshcat page and/or a stick GIF (each to a temporary name, then renamed).

    Args:
        walk: a :class:`~pasibot_pin.studies.walking.DesignWalk`.
        robot: its robot.
        html: the HTML file (``None``: none).
        gif: the GIF file (``None``: none).
        fps: frames per second of simulated time [1/s].
        dpi: the GIF's resolution [dots per inch] (6.4 x 5 in: 640 x 500 px at the default). The GIF's
            camera follows the robot (:func:`~pasibot_pin.viz.animation.save_gif`'s ``follow``).
        progress: a progress bar over the GIF's frames on stderr.

    Returns:
        The files written (none when none was asked for, or the run has no sample to draw: a walk
        that diverged before its first step).

    """
    result = walk.result
    if (html is None and gif is None) or len(result.t) == 0:
        return []
    index = walk_frames(result, fps)
    qs, times = result.q[index], result.t[index]
    forces = floor_force_tracks(robot, result, index)
    modes = {side: [result.modes[side][k] for k in index] for side in SIDES}
    title = f"{robot.variant} on the floor, {walk.omega:.3g} rad/s: {walk.verdict.short()}"
    # what both pictures show: the camera follows the robot over the walk's own ground
    shown = {"title": title, "forces": forces, "modes": modes, "times": times, "follow": True}
    shown["ground"] = walk.settings.ground
    written = []
    if gif is not None:
        with atomic_path(gif) as temp:
            save_gif(robot, qs, temp, fps=fps, dpi=dpi, force=True, progress=progress, **shown)
        written.append(gif)
    if html is not None:
        viewer = WalkViewer(robot, offline=True)
        try:
            build_walk_scene(viewer, qs, fps, **shown)
            text = viewer.static_html()
        finally:
            viewer.close()
        with atomic_path(html) as temp:
            temp.write_text(text, encoding="utf-8")
        written.append(html)
    return written


def verdict_json(walk, multipliers=None) -> dict:
    """The walk as a JSON-ready dict: the verdict's figures, the motor's, and the multipliers if given."""
    v, result = walk.verdict, walk.result
    load = motor_load(result, walk.omega, walk.settings.crank_ramp)
    out = {
        "outcome": v.outcome,
        "detail": v.detail,
        "decided_at_s": v.decided_at,
        "steps": v.steps,
        "advance_m": v.advance_m,
        "advance_per_step": _finite(v.advance_per_step),
        "max_hip_pitch_deg": math.degrees(v.max_hip_pitch),
        "max_slip_m": v.max_slip_m,
        "motor_torque_peak_Nm": _finite(load.torque_peak_Nm),
        "motor_torque_rms_Nm": _finite(load.torque_rms_Nm),
        "motor_torque_max_Nm": _finite(load.torque_max_Nm),
        "motor_power_peak_W": _finite(load.power_peak_W),
        "motor_power_mean_W": _finite(load.power_mean_W),
        "exchange_impulse_Nms": _finite(load.exchange_impulse_Nms),
        "exchange_impulse_floor_Nms": _finite(load.impulse_floor_Nms),
        "crank_speed_dip_rad_s": _finite(load.speed_dip_rad_s),
        "reflected_inertia_kg_m2": load.reflected_inertia,
        "mean_motor_power_W": _finite(v.mean_motor_power_w),
        "motor_energy_per_metre_J_per_m": _finite(v.power_per_metre),
        "cost_of_transport": _finite(v.cost_of_transport),
        "omega_rad_s": walk.omega,
        "dt_s": walk.dt,
        "simulated_s": v.simulated_s,
        "margins": [_margin_json(m) for m in v.margins],
    }
    if multipliers is not None:
        out["multipliers"] = [[float(z.real), float(z.imag)] for z in multipliers.multipliers]
        out["stable"] = bool(multipliers.stable)
        out["stability_method"] = "Newton shooting of the step map, forward differences"
        point = multipliers.fixed_point
        if getattr(multipliers, "fitted", False):
            out["stability_method"] = f"least-squares fit of the step map to {point.evaluations} simulated steps"
            out["stability_newton_note"] = multipliers.newton_note
            out["dominant_multiplier_spread"] = [float(point.spread[0]), float(point.spread[1])]
            out["step_jitter_rms"] = dict(zip(multipliers.labels, map(float, point.jitter)))
        out["stability_cpu_s"] = float(multipliers.cpu_s)
        out["stability_steps_simulated"] = int(multipliers.evaluations)
    return out


def _margin_json(m) -> dict:
    """One rule's margin as JSON: NaN (no figure) as null, strict JSON."""
    figures = {name: _finite(getattr(m, name)) for name in ("value", "margin", "scale")}
    return {**asdict(m), **figures, "near": m.near}


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def walk_lines(walk) -> list[str]:
    """The printed answer: outcome, steps, advance, hip pitch, slip, the motor's torque and power, CoT."""
    d = verdict_json(walk)
    lines = [f"outcome: {d['outcome']}" + (f" at t = {d['decided_at_s']:.3f} s ({d['detail']})" if d["detail"] else "")]
    lines.append(f"steps: {d['steps']} in {d['simulated_s']:.2f} s at {walk.omega:g} rad/s (time step {walk.dt:g} s)")
    ratio = d["advance_per_step"]
    per_step = f" ({100 * ratio:.1f} % of the linkage's 8 L per step)" if ratio is not None else ""
    lines.append(f"advance: {d['advance_m']:.3f} m{per_step}")
    slide = f"largest slide in one stance: {1e3 * d['max_slip_m']:.2f} mm"
    lines.append(f"max |hip pitch|: {d['max_hip_pitch_deg']:.2f} deg; {slide}")
    lines.extend(motor_load(walk.result, walk.omega, walk.settings.crank_ramp).summary().splitlines())
    lines.append(f"margins: {walk.verdict.margins_text()}")
    cot, per_m = d["cost_of_transport"], d["motor_energy_per_metre_J_per_m"]
    if cot is not None:
        lines.append(f"cost of transport: {cot:.4f} ({per_m:.2f} J/m over whole strides)")
    return lines


def _frames_3d(walk, robot, fps: float) -> tuple[slice, str]:
    """The samples a 3-D walk's pictures show (``fps`` frames a simulated second) and their title."""
    every = max(1, round(1.0 / (fps * max(walk.dt, 1e-9))))
    roll = f"max roll {walk.result.max_hip_roll_deg:.1f} deg"
    return slice(None, None, every), f"{robot.variant} in 3-D, {walk.omega:g} rad/s: {walk.verdict.short()}, {roll}"


def write_walk3d_gif(walk, robot, footprint, gif: Path, fps: float = 20.0, progress: bool = False) -> Path:
    """Write a 3-D walk (:class:`~pasibot_pin.studies.walking.DesignWalk3D`) as a GIF of its two views, atomically.

    Args:
        walk: the 3-D walk.
        robot: its robot.
        footprint: its soles' shape.
        gif: the file.
        fps: frames per second of simulated time [1/s].
        progress: a progress bar over the frames on stderr.

    """
    from pasibot_pin.viz.walk3d_gif import save_walk3d_gif  # deferred: heavy (matplotlib), keeps the CLI's start fast

    frames, title = _frames_3d(walk, robot, fps)
    model, result = free_flyer_model(robot.model), walk.result
    times = result.t[frames]
    return save_walk3d_gif(model, result.q[frames], footprint, gif, fps, times, title, walk.ground, progress=progress)


def write_walk3d_page(walk, robot, footprint, html: Path, fps: float = 20.0) -> Path:
    """Write a 3-D walk (:class:`~pasibot_pin.studies.walking.DesignWalk3D`) as a one-file meshcat page, atomically.

    Args:
        walk: the 3-D walk.
        robot: its robot, loaded with visuals.
        footprint: its soles' shape.
        html: the file.
        fps: frames per second of simulated time [1/s].

    """
    from pasibot_pin.viz.walk3d import walk3d_html  # deferred: heavy (meshcat), keeps the CLI's start fast

    frames, title = _frames_3d(walk, robot, fps)
    text = walk3d_html(robot, free_flyer_model(robot.model), walk.result.q[frames], footprint, fps, title, walk.ground)
    with atomic_path(html) as temp:
        temp.write_text(text, encoding="utf-8")
    return html
