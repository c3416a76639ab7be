"""``pasibot gait``: foot paths of one leg, or the biped's multi-step walk, as CSV and a plot.

``--legs 1``: one crank turn in the leg frame (x forward, z up, origin at the crank pivot),
one CSV row per sample with the columns of :data:`LEG_COLUMNS`. ``--legs 2``: the biped
walking ``--steps`` steps in the world frame, columns :func:`walk_columns`. All SI units,
angles in rad.
"""

from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path

import numpy as np

from .common import add_robot_options

LEG_COLUMNS: tuple[str, ...] = (
    "theta",
    "ankle_x",
    "ankle_z",
    "toe_x",
    "toe_z",
    "heel_x",
    "heel_z",
    "foot_pitch",
    "ankle_vx",
    "ankle_vz",
    "ankle_ax",
    "ankle_az",
    "stance",
)
"""CSV columns for one leg: [rad], [m], [rad], [m/s], [m/s^2]; ``stance`` is 1 in 90..270 deg."""

WALK_POINTS: tuple[tuple[str, str], ...] = (("ankle", "foot"), ("toe", "toe"), ("heel", "heel"))


def walk_columns() -> list[str]:
    """CSV columns for the biped walk (world frame, [rad], [s], [m])."""
    cols = ["theta", "theta_left", "t", "step", "stance", "hip_x", "hip_z", "hip_pitch"]
    for side in ("right", "left"):
        cols += [f"{side}_{p}_{axis}" for p, _ in WALK_POINTS for axis in ("x", "z")]
        cols.append(f"{side}_foot_pitch")
    return cols


def register(sub: argparse._SubParsersAction) -> None:
    """Add the subcommand."""
    p = sub.add_parser(
        "gait",
        help="foot paths of one leg (--legs 1) or a multi-step biped walk (--legs 2) as CSV and plot",
        description=__doc__,
    )
    add_robot_options(p, legs_default=1)
    p.add_argument("--steps", type=int, default=None, help="steps (half crank turns) to walk, --legs 2 (default 2)")
    p.add_argument("--step-deg", type=float, default=5.0, help="crank increment between samples [deg] (default 5)")
    p.add_argument("--omega", type=float, default=0.1, help="crank rate [rad/s] (default 0.1, seed Fig 5.1)")
    p.add_argument(
        "--foot",
        default="flat",
        help="--legs 2 stance contact: flat (sole welded level), point (ankle pinned, hip level), "
        "toe (toe pinned, hip level) (default flat)",
    )
    p.add_argument("--csv", type=Path, default=None, help="write the samples to this CSV file")
    p.add_argument("--plot", type=Path, default=None, help="write a figure to this file (.png, .pdf, .svg)")
    p.add_argument("--force", action="store_true", help="overwrite existing output files")
    p.set_defaults(func=run)


def _check_output(path: Path | None, force: bool, option: str) -> None:
    if path is not None and path.exists() and not force:
        raise FileExistsError(f"{option} {path} exists; pass --force to overwrite it")


def _samples(span_deg: float, step_deg: float) -> int:
    if not math.isfinite(step_deg) or step_deg <= 0.0:
        raise ValueError(f"parameter '--step-deg' must be a positive crank increment [deg], got {step_deg!r}")
    count = span_deg / step_deg
    n = round(count)
    if n < 2 or abs(count - n) > 1e-9 * count:
        raise ValueError(f"parameter '--step-deg' = {step_deg:g} deg must divide {span_deg:g} deg into >= 2 samples")
    return n


def write_csv(path: Path, columns: list[str] | tuple[str, ...], rows: np.ndarray | list) -> None:
    """Write rows under a header, full float precision."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(columns)
        for row in rows:
            writer.writerow([repr(float(x)) if isinstance(x, (float, np.floating)) else x for x in row])


def leg_rows(cycle) -> list[list]:
    """CSV rows (:data:`LEG_COLUMNS`) of a leg cycle computed with ``omega``."""
    stance = cycle.in_stance()
    rows = []
    for k in range(len(cycle.theta)):
        rows.append(
            [
                float(cycle.theta[k]),
                *map(float, cycle.ankle[k]),
                *map(float, cycle.toe[k]),
                *map(float, cycle.heel[k]),
                float(cycle.foot_pitch[k]),
                *map(float, cycle.ankle_velocity[k]),
                *map(float, cycle.ankle_acceleration[k]),
                int(stance[k]),
            ]
        )
    return rows


def walk_rows(walk) -> list[list]:
    """CSV rows (:func:`walk_columns`) of a :class:`~pasibot_pin.gait.Walk`."""
    frames = ["hip"] + [f"{side}_{frame}" for side in ("right", "left") for _, frame in WALK_POINTS]
    xz = walk.frames_xz(frames)
    hip_pitch = walk.pitch("hip")
    pitch = {side: walk.pitch(f"{side}_foot") for side in ("right", "left")}
    t = walk.t if walk.t is not None else np.full(walk.n, np.nan)
    rows = []
    for k in range(walk.n):
        row = [
            float(walk.theta[k]),
            float(walk.theta[k] + math.pi),
            float(t[k]),
            int(walk.step[k]),
            walk.stance[k],
            *map(float, xz["hip"][k]),
            float(hip_pitch[k]),
        ]
        for side in ("right", "left"):
            for _, frame in WALK_POINTS:
                row += list(map(float, xz[f"{side}_{frame}"][k]))
            row.append(float(pitch[side][k]))
        rows.append(row)
    return rows


def run(args: argparse.Namespace) -> int:
    """Compute, print a summary, write the CSV and the plot."""
    import matplotlib

    matplotlib.use("Agg")
    from ..robot import load

    if args.legs not in (1, 2):
        raise ValueError(f"parameter '--legs' must be 1 or 2, got {args.legs!r}")
    if not math.isfinite(args.omega) or args.omega <= 0:
        raise ValueError(f"parameter '--omega' must be a positive crank rate [rad/s], got {args.omega!r}")
    _check_output(args.csv, args.force, "--csv")
    _check_output(args.plot, args.force, "--plot")
    robot = load(args.variant, args.legs)
    if args.legs == 1:
        if args.steps is not None:
            raise ValueError("parameter '--steps' applies to --legs 2; --legs 1 samples one crank turn")
        return _run_leg(robot, args)
    return _run_walk(robot, args)


def _run_leg(robot, args: argparse.Namespace) -> int:
    from .. import kinematics as kin
    from ..plots_gait import plot_leg_summary

    n = _samples(360.0, args.step_deg)
    cycle = kin.leg_cycle(robot, kin.crank_grid(2 * math.pi / n), omega=args.omega)
    metrics = kin.straight_line_metrics(robot)
    print(f"PASIBOT {robot.variant}, one leg, {len(cycle.theta)} samples, omega = {args.omega:g} rad/s")
    for key, value in metrics.in_L().items():
        print(f"  {key:22s} {value:.6g}")
    speeds = kin.leg_cycle(robot, np.radians([90.0, 180.0, 270.0]), omega=args.omega).ankle_velocity[:, 0]
    L = robot.geometry.L
    print("  ankle v_x / (L omega) at 90, 180, 270 deg: " + ", ".join(f"{v / (L * args.omega):.6f}" for v in speeds))
    if args.csv is not None:
        write_csv(args.csv, LEG_COLUMNS, leg_rows(cycle))
        print(f"wrote {args.csv}")
    if args.plot is not None:
        _save(plot_leg_summary(cycle), args.plot)
    return 0


def _run_walk(robot, args: argparse.Namespace) -> int:
    from ..gait import walk
    from ..plots_gait import plot_walk, plot_walk_hip

    steps = 2 if args.steps is None else args.steps
    sps = _samples(180.0, args.step_deg)
    w = walk(robot, steps, sps, omega=args.omega, foot=args.foot)
    L = robot.geometry.L
    hip = w.hip_path()
    starts = [hip[k * sps, 0] for k in range(steps)] + [hip[-1, 0]]
    print(f"PASIBOT {robot.variant}, two legs, foot = {w.foot}, {steps} step(s), {w.n} samples")
    print(f"  hip advance per step / L: {', '.join(f'{d / L:.6f}' for d in np.diff(starts))}")
    print(f"  hip height peak-to-peak / L: {np.ptp(hip[:, 1]) / L:.6f}")
    print(f"  hip pitch range [deg]: {np.degrees(w.pitch().min()):.4f} .. {np.degrees(w.pitch().max()):.4f}")
    print(f"  largest closure residual: {w.residual.max():.2e}")
    if w.exchange_jump and max(w.exchange_jump) > 1e-9:
        print(f"  pose jump at the exchanges (the new stance foot lands tilted): {max(w.exchange_jump):.4f}")
    if args.csv is not None:
        write_csv(args.csv, walk_columns(), walk_rows(w))
        print(f"wrote {args.csv}")
    if args.plot is not None:
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(2, 1, figsize=(11, 10), gridspec_kw={"height_ratios": [3, 1]})
        plot_walk(w, ax=axes[0])
        plot_walk_hip(w, ax=axes[1])
        fig.tight_layout()
        _save(fig, args.plot)
    return 0


def _save(fig, path: Path) -> None:
    import matplotlib.pyplot as plt

    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    print(f"wrote {path}")
