"""The found designs, committed in ``designs/`` (one TOML design file per design, a picture, a table).

:func:`pick_designs` chooses them from the walking map (:mod:`pasibot_pin.studies.walking_map`):
the walker with the smallest sole, the fastest walker, the walker of the least motor energy per
metre, and instructive non-walkers (the spring variant on the smallest walker's sole and speed; the
fastest walker's sole turned faster still, when that fails). :func:`write_catalog` writes each as
``designs/NAME.toml`` (``pasibot walk --design designs/NAME.toml`` walks it again), its picture
``designs/NAME.png`` (stick snapshots of the first steps, the hip's path) and ``designs/README.md``,
a table generated from the map's 20-step verdicts (:func:`catalog_markdown`).

``python -m pasibot_pin.report.designs_catalog`` writes them; ``--check`` re-simulates every design
for the map's full step count and compares the outcome, steps and largest hip pitch with the table
(the test suite re-simulates fewer steps: ``tests/test_walking_map.py``).

Units: SI; soles over L; crank speed [rad/s].
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from pasibot_pin.files import atomic_path, write_text_atomic
from pasibot_pin.model.design import design_robot, load_design
from pasibot_pin.studies.walking import WalkSettings, walk_design
from pasibot_pin.studies.walking_map import MapCell, WalkingMap, load_map, map_design
from pasibot_pin.viz.figure_files import save_figure_file
from pasibot_pin.viz.plots import plot_robot, robot_segments

DESIGNS_DIR = Path(__file__).resolve().parents[2] / "designs"
"""Where the found designs of a source checkout are kept."""

PICTURE_STEPS = 4
"""Steps simulated for a design's picture (a non-walker stops at its failure) [-]."""


@dataclass(frozen=True)
class Entry:
    """One committed design: its file name (no suffix), why it is here, and its map cell."""

    name: str
    why: str
    cell: MapCell

    @property
    def design(self):
        """Its :class:`~pasibot_pin.model.design.Design`."""
        return map_design(self.cell.variant, self.cell.sole, self.cell.omega)


def _name(role: str, c: MapCell) -> str:
    return f"{role}_{c.variant}_sole{c.sole:g}L_omega{c.omega:g}"


def pick_designs(wmap: WalkingMap) -> list[Entry]:
    """The walkers worth keeping and instructive non-walkers (each cell once), see the module's notes."""
    walkers = wmap.walkers()
    picks: list[Entry] = []
    if walkers:
        small = min(walkers, key=lambda c: (c.sole, c.omega))
        fast = max(walkers, key=lambda c: (c.omega, -c.sole))
        cheap = min(walkers, key=lambda c: c.energy_per_m_J if math.isfinite(c.energy_per_m_J) else math.inf)
        picks += [
            Entry(_name("smallest_sole", small), "the walker with the smallest sole", small),
            Entry(_name("fastest", fast), "the walker of the highest crank speed", fast),
            Entry(_name("least_energy", cheap), "the walker of the least motor energy per metre", cheap),
        ]
        spring = wmap.cell("spring", small.sole, small.omega) if "spring" in wmap.variants else None
        if spring is not None and not spring.walks:
            why = f"not a walker: the spring variant on the smallest walker's sole and speed ({spring.outcome})"
            picks.append(Entry(_name("spring", spring), why, spring))
        faster = [c for c in wmap.cells if c.variant == fast.variant and c.sole == fast.sole and c.omega > fast.omega]
        if faster:
            c = min(faster, key=lambda c: c.omega)
            why = f"not a walker: the fastest walker's feet, cranks at {c.omega:g} rad/s ({c.outcome})"
            picks.append(Entry(_name("too_fast", c), why, c))
    seen, out = set(), []
    for e in picks:
        key = (e.cell.variant, e.cell.sole, e.cell.omega)
        if key not in seen:
            seen.add(key)
            out.append(e)
    return out


HEADER = (
    "| design | variant | sole toe / heel [L] | omega [rad/s] | outcome | steps | advance per step [% of 8 L] | "
    "max hip pitch [deg] | cost of transport [-] |"
)


def catalog_row(e: Entry) -> str:
    """One README row: the map's verdict of the design."""
    c = e.cell
    advance = "-" if math.isnan(c.advance_per_step) else f"{100 * c.advance_per_step:.1f}"
    cot = "-" if math.isnan(c.cost_of_transport) else f"{c.cost_of_transport:.2f}"
    outcome = c.outcome if c.walks else f"{c.outcome} at {c.decided_at_s:.2f} s"
    return (
        f"| [{e.name}]({e.name}.toml) | {c.variant} | {c.sole:g} / {c.sole:g} | {c.omega:g} | {outcome} | "
        f"{c.steps} | {advance} | {c.max_hip_pitch_deg:.2f} | {cot} |"
    )


def catalog_markdown(entries: Sequence[Entry], steps: int) -> str:
    """``designs/README.md``: what the folder is, the table, the pictures."""
    lines = [
        "# Found designs",
        "",
        "Designs found by the walking map (`docs/walking.md`, `make walking-map`), one TOML design file each, as "
        "`pasibot --design FILE` reads it: `pasibot walk --design designs/NAME.toml` walks it again. The table is "
        f"the map's verdict ({steps} steps on the floor), written by `python -m pasibot_pin.report.designs_catalog`; "
        "`tests/test_walking_map.py` re-simulates every design.",
        "",
        "<!-- generated by pasibot_pin.report.designs_catalog.catalog_markdown() -->",
        HEADER,
        "|" + "---|" * HEADER.count(" | ") + "---|",
        *[catalog_row(e) for e in entries],
        "",
        *[f"* **{e.name}**: {e.why}." for e in entries],
        "",
    ]
    for e in entries:
        lines += [f"![{e.name}]({e.name}.png)", ""]
    return "\n".join(lines)


def draw_design(e: Entry, path: Path, steps: int = PICTURE_STEPS) -> Path:
    """Stick snapshots of the design's first ``steps`` steps (or up to its failure) and the hip's path, as PNG."""
    import matplotlib  # deferred: heavy (matplotlib), keeps the CLI's start fast

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast

    from pasibot_pin.viz.plots_layout import subplots  # deferred: heavy (matplotlib), keeps the CLI's start fast

    robot = design_robot(e.design, 2, visuals=False)
    walk = walk_design(e.design, WalkSettings(steps=steps), robot)
    res = walk.result

    fig, ax = subplots(figsize=(7.5, 5.0))
    snapshots = [res.q[min(np.searchsorted(res.t, t), len(res.t) - 1)] for t in np.linspace(0.0, res.t[-1], 7)]
    points = [p for q in snapshots for _g, a, b in robot_segments(robot, q) for p in (a, b)]
    for k, q in enumerate(snapshots):
        plot_robot(robot, q, ax=ax, alpha=0.25 + 0.75 * k / 6)
    hip = robot.model.getFrameId("hip")
    path_xz = []
    for q in res.q[:: max(1, len(res.q) // 400)]:
        pin.framesForwardKinematics(robot.model, robot.data, q)
        path_xz.append(robot.data.oMf[hip].translation[[0, 2]])
    ax.plot(*np.array(path_xz).T, color="black", lw=0.8, label="hip path")
    xz = np.array(points + path_xz)
    ax.set_xlim(xz[:, 0].min() - 0.05, xz[:, 0].max() + 0.05)  # every snapshot in view [m]
    ax.set_ylim(min(-0.05, xz[:, 1].min() - 0.05), xz[:, 1].max() + 0.1)
    ax.legend(loc="upper left", fontsize=8, frameon=False)
    ax.set_title(f"{e.name}: {walk.verdict.short()} ({walk.verdict.steps} of {steps} steps simulated here)")
    with atomic_path(Path(path)) as tmp:
        save_figure_file(fig, tmp, 90)
    plt.close(fig)
    return Path(path)


def write_catalog(wmap: WalkingMap, folder: Path = DESIGNS_DIR, pictures: bool = True) -> list[Path]:
    """Write every picked design's TOML (and picture) and ``README.md`` into ``folder``."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    entries = pick_designs(wmap)
    written = []
    for e in entries:
        written.append(e.design.save(folder / f"{e.name}.toml", force=True))
        if pictures:
            written.append(draw_design(e, folder / f"{e.name}.png"))
    written.append(write_text_atomic(folder / "README.md", catalog_markdown(entries, wmap.steps)))
    return written


def check_catalog(wmap: WalkingMap, folder: Path = DESIGNS_DIR) -> list[str]:
    """Re-simulate every committed design for the map's steps; the differences from the table (empty: none)."""
    problems = []
    for e in pick_designs(wmap):
        v = walk_design(load_design(folder / f"{e.name}.toml"), WalkSettings(steps=wmap.steps)).verdict
        got = (v.outcome, v.steps, round(math.degrees(v.max_hip_pitch), 2))
        want = (e.cell.outcome, e.cell.steps, round(e.cell.max_hip_pitch_deg, 2))
        print(f"{e.name}: {v.summary()}", flush=True)
        if got != want:
            problems.append(f"{e.name}: simulated {got}, table {want}")
    return problems


def main(argv: Sequence[str] | None = None) -> None:
    """Write ``designs/`` from the committed walking map, or ``--check`` it."""
    parser = argparse.ArgumentParser(description="write designs/ from docs/results/walking_map.csv")
    parser.add_argument("--check", action="store_true", help="re-simulate every design (full steps) and compare")
    args = parser.parse_args(argv)
    wmap = load_map()
    if args.check:
        problems = check_catalog(wmap)
        print("\n".join(problems) or "every design re-simulates to its table row")
        raise SystemExit(1 if problems else 0)
    for path in write_catalog(wmap):
        print(path)


if __name__ == "__main__":
    main()
