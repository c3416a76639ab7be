"""``make lateral-mass``: a mass the crank moves sideways, on the centred-sole walker in 3-D.

The planar map's walker (parallel extension, 6 L soles, centred on each leg's plane: it tips in 3-D)
with a share of its 16 kg body on a slider through the hip, at ``amplitude sin(theta + phase)`` of
the right crank (:class:`~pasibot_pin.model.spatial.LateralMass`), walked on the 3-D floor
(:func:`~pasibot_pin.studies.walking.walk_design_3d`) over mass x amplitude x phase x crank speed.
Prints one row per walk: the outcome, the steps, the largest |roll| and when the run ended. About
8 s of CPU a walk; the default grid (48 walks) takes about 4 minutes on 2 cores.
"""

from __future__ import annotations

import argparse
import math

from pasibot_pin.jobs import Job, run_jobs
from pasibot_pin.progress import progress_bar
from pasibot_pin.studies.walking import WalkSettings, walk_design_3d
from pasibot_pin.studies.walking_map3d import walker_base

PHASES = tuple(k * math.pi / 4 for k in range(-3, 5))
"""Eight phases ahead of the right crank [rad]."""


def walk_cell(mass: float, amplitude: float, phase: float, omega: float, steps: int) -> tuple:
    """One walk: (outcome, steps, max |roll| [deg], end time [s])."""
    design = walker_base().with_(
        omega=omega, lateral_mass=mass, lateral_amplitude=amplitude, lateral_phase=phase
    )  # fmt: skip
    walk = walk_design_3d(design, WalkSettings(steps=steps))
    return walk.verdict.outcome, walk.verdict.steps, walk.result.max_hip_roll_deg, float(walk.result.t[-1])


def main(argv: list[str] | None = None) -> int:
    """Walk the grid and print it."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--mass", type=float, nargs="+", default=[15.0], help="moved mass [kg] (< the 16 kg body)")
    parser.add_argument("--amplitude", type=float, nargs="+", default=[3.0, 5.0, 7.0], help="reach [L]")
    parser.add_argument("--omega", type=float, nargs="+", default=[0.5, 2.0], help="crank speeds [rad/s]")
    parser.add_argument("--steps", type=int, default=6)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)
    cells = [(m, a, p, w) for w in args.omega for m in args.mass for a in args.amplitude for p in PHASES]
    rows: dict[tuple, tuple] = {}
    bar = progress_bar(len(cells), 0, True, unit="walk")

    def done(key, result):
        rows[key] = result
        bar.update(1)

    run_jobs((Job(1.0, cell, walk_cell, (*cell, args.steps)) for cell in cells), done, workers=args.workers)
    bar.close()
    print("| mass [kg] | amplitude [L] | phase [rad] | omega [rad/s] | outcome | steps | max roll [deg] | ended [s] |")
    print("|---|---|---|---|---|---|---|---|")
    for cell in cells:
        outcome, steps, roll, end = rows[cell]
        mass, amplitude, phase, omega = cell
        print(f"| {mass:g} | {amplitude:g} | {phase:+.3f} | {omega:g} | {outcome} | {steps} | {roll:.2f} | {end:.2f} |")
    walkers = sum(rows[c][0] == "walks" for c in cells)
    print(f"{walkers} of {len(cells)} walk {args.steps} steps upright")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
