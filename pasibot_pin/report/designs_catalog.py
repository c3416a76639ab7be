"""The found designs, committed in ``designs/`` (one TOML design file per design, a picture, a table).

:func:`pick_designs` chooses them: the fastest walker found (the walking sweep's, its toe and heel
soles of their own: :func:`fastest_sweep_design`), and from the walking map
(:mod:`pasibot_pin.studies.walking_map`) the walker with the smallest sole, the walker of the highest
crank speed on the map's grid, the walker of the least motor energy per metre, and instructive
non-walkers (the spring variant on the smallest walker's sole and speed; the map's top-speed walker's
sole turned faster still, when that fails). :func:`catalog_markdown` is ``designs/README.md``, a table
of the committed 20-step verdicts; :func:`draw_design` a design's picture.

``tools/designs_catalog.py`` (``make designs``) writes them into ``designs/``; ``--check``
re-simulates every design for the full step count and compares it with the table (the test suite
re-simulates fewer steps: ``tests/test_walking_map.py``).

Units: SI; soles over L; crank speed [rad/s].
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from pasibot_pin.dynamics.verdict import LINKAGE_ADVANCE_PER_STEP
from pasibot_pin.files import atomic_path
from pasibot_pin.model.design import CHOICES, Design, design_robot
from pasibot_pin.model.paths import result_path
from pasibot_pin.studies.walking import WalkSettings, walk_design
from pasibot_pin.studies.walking_map import MapCell, WalkingMap, map_design
from pasibot_pin.viz.figure_files import save_figure_file
from pasibot_pin.viz.plots import plot_robot, robot_segments

SWEEP_NAME = "walking_sweep.csv"
"""The committed walking sweep (``pasibot sweep --floor 20 --n 200`` over the variants, omega and the soles),
read where :func:`~pasibot_pin.model.paths.result_path` finds it; ``tools/`` passes its own path."""

PICTURE_STEPS = 4
"""Steps simulated for a design's picture (a non-walker stops at its failure) [-]."""

TWIN_NOTES = {
    "fastest": "the MuJoCo twin disagrees on it: its left foot slides 5.1 mm in one stance at 0.92 s, past the "
    "verdict's 5 mm limit, so there it slipped; at half the twin's time step (0.05 ms) it slides less and walks, as "
    "ours does: the disagreement sits on the edge of the limit, not in the gait (`tests/test_designs_twin.py` holds "
    "the twin to both)",
}
"""Where the MuJoCo twin's 3-step outcome differs from ours, by the entry's role: what it says (Markdown; the
figures it quotes are the twin's, checked by ``tests/test_designs_twin.py``)."""

TWIN_OUTCOMES = {"fastest": "slipped"}
"""The MuJoCo twin's 3-step outcome of those entries, by role (``tests/test_designs_twin.py``)."""


def sweep_rows(path: Path | None = None) -> list[dict]:
    """The walking sweep's rows as dicts of strings (the csv module: no pyarrow); default: the committed sweep."""
    with open(result_path(SWEEP_NAME) if path is None else path, newline="") as handle:
        return list(csv.DictReader(handle))


def fastest_sweep_design(rows: list[dict]) -> tuple[Design, dict]:
    """The :class:`~pasibot_pin.model.design.Design` of the sweep's fastest walker, and its row."""
    walkers = [r for r in rows if r["floor_outcome"] == "walks"]
    row = max(walkers, key=lambda r: float(r["omega"]))
    names = [k for k in Design().values() if k in row]
    values = {k: (row[k] if k in CHOICES else float(row[k]) if row[k] not in ("", "nan") else None) for k in names}
    return Design.from_dict(values), row


@dataclass(frozen=True)
class Entry:
    """One committed design: its file name (no suffix), its role, why it is here, and its verdict's source.

    Attributes:
        name: the file name without its suffix.
        role: what it was picked as (``fastest``, ``smallest_sole``, ...).
        why: why it is here, in words.
        cell: its walking map cell (``None`` for the sweep's walker).
        sweep: its walking sweep row (``None`` for a map cell).

    """

    name: str
    role: str
    why: str
    cell: MapCell | None = None
    sweep: dict | None = None

    @property
    def design(self) -> Design:
        """Its :class:`~pasibot_pin.model.design.Design`."""
        if self.sweep is not None:
            return fastest_sweep_design([self.sweep])[0]
        assert self.cell is not None
        return map_design(self.cell.variant, self.cell.sole, self.cell.omega)

    @property
    def twin_outcome(self) -> str:
        """The MuJoCo twin's 3-step outcome where it is recorded as differing from ours (``""``: the same)."""
        return TWIN_OUTCOMES.get(self.role, "")


def _name(role: str, c: MapCell) -> str:
    return f"{role}_{c.variant}_sole{c.sole:g}L_omega{c.omega:g}"


def sweep_entry(rows: list[dict]) -> Entry:
    """The fastest walker found: the walking sweep's walker of the highest crank speed."""
    design, row = fastest_sweep_design(rows)
    d = design
    name = f"fastest_{d.variant}_toe{d.parallel_toe:.1f}L_heel{d.parallel_heel:.1f}L_omega{d.omega:.2f}"
    why = (
        "the fastest walker found: the walking sweep's walker of the highest crank speed (its soles reach "
        f"{design.parallel_toe:.1f} L ahead of and {design.parallel_heel:.1f} L behind the ankle; its advance is "
        f"the sweep's, over all its steps); {TWIN_NOTES['fastest']}"
    )
    return Entry(name, "fastest", why, sweep=row)


def pick_designs(wmap: WalkingMap, rows: list[dict] | None = None) -> list[Entry]:
    """The fastest walker of the sweep ``rows`` (when one walks), then the map's picks (see the module's notes)."""
    walkers = wmap.walkers()
    picks: list[Entry] = []
    if rows and any(r["floor_outcome"] == "walks" for r in rows):
        picks.append(sweep_entry(rows))
    if walkers:
        small = min(walkers, key=lambda c: (c.sole, c.omega))
        top = max(walkers, key=lambda c: (c.omega, -c.sole))
        cheap = min(walkers, key=lambda c: c.energy_per_m_J if math.isfinite(c.energy_per_m_J) else math.inf)
        picks += [
            Entry(_name("smallest_sole", small), "smallest_sole", "the walker with the smallest sole", small),
            Entry(_name("map_top_speed", top), "map_top_speed",
                  "the walker of the highest crank speed on the walking map's grid (symmetric soles)", top),
            Entry(_name("least_energy", cheap), "least_energy",
                  "the walker of the least motor energy per metre", cheap),
        ]  # fmt: skip
        spring = wmap.cell("spring", small.sole, small.omega) if "spring" in wmap.variants else None
        if spring is not None and not spring.walks:
            why = f"not a walker: the spring variant on the smallest walker's sole and speed ({spring.outcome})"
            picks.append(Entry(_name("spring", spring), "spring", why, spring))
        faster = [c for c in wmap.cells if c.variant == top.variant and c.sole == top.sole and c.omega > top.omega]
        if faster:
            c = min(faster, key=lambda c: c.omega)
            why = f"not a walker: the map's top-speed walker's feet, cranks at {c.omega:g} rad/s ({c.outcome})"
            picks.append(Entry(_name("too_fast", c), "too_fast", why, c))
    seen, out = set(), []
    for e in picks:
        key = e.name if e.cell is None else (e.cell.variant, e.cell.sole, e.cell.omega)
        if key not in seen:
            seen.add(key)
            out.append(e)
    return out


HEADER = (
    "| design | variant | sole toe / heel [L] | omega [rad/s] | outcome | steps | advance per step [% of 8 L] | "
    "max hip pitch [deg] | cost of transport [-] |"
)


def _sweep_row(e: Entry) -> str:
    """The sweep's walker's README row: the sweep's 20-step floor verdict."""
    d, r = e.design, e.sweep
    assert r is not None
    steps = int(float(r["floor_steps"]))
    advance = float(r["floor_advance_m"]) / (steps * LINKAGE_ADVANCE_PER_STEP * d.L)
    return (
        f"| [{e.name}]({e.name}.toml) | {d.variant} | {d.parallel_toe:.1f} / {d.parallel_heel:.1f} | "
        f"{d.omega:.2f} | {r['floor_outcome']} | {steps} | {100 * advance:.1f} | "
        f"{float(r['floor_max_hip_pitch_deg']):.2f} | {float(r['floor_cost_of_transport']):.2f} |"
    )


def catalog_row(e: Entry) -> str:
    """One README row: the map's (or the sweep's) verdict of the design."""
    if e.cell is None:
        return _sweep_row(e)
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
        "Designs found by the walking map and the walking sweep (`docs/walking.md`, `make walking-map`), one TOML "
        "design file each, as `pasibot --design FILE` reads it: `pasibot walk --design designs/NAME.toml` walks it "
        f"again. The table is their verdict ({steps} steps on the floor), written by `make designs` "
        "(`tools/designs_catalog.py`); `tests/test_walking_map.py` re-simulates every design.",
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
        lines += [f"![{e.name}: stick snapshots of its first steps and its hip's path, lengths in m]({e.name}.png)", ""]
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

    from matplotlib.lines import Line2D  # deferred: heavy (matplotlib), keeps the CLI's start fast

    from pasibot_pin.viz.plots import robot_legend  # deferred: heavy (matplotlib), keeps the CLI's start fast

    fig, ax = subplots(figsize=(7.5, 6.0))
    snapshots = [res.q[min(np.searchsorted(res.t, t), len(res.t) - 1)] for t in np.linspace(0.0, res.t[-1], 7)]
    segments = [s for q in snapshots for s in robot_segments(robot, q)]
    points = [p for _g, a, b in segments for p in (a, b)]
    for k, q in enumerate(snapshots):
        plot_robot(robot, q, ax=ax, alpha=0.25 + 0.75 * k / 6)
    hip = robot.model.getFrameId("hip")
    path_xz = []
    for q in res.q[:: max(1, len(res.q) // 400)]:
        pin.framesForwardKinematics(robot.model, robot.data, q)
        path_xz.append(robot.data.oMf[hip].translation[[0, 2]])
    (hip_line,) = ax.plot(*np.array(path_xz).T, color="black", lw=0.8, label="hip path (the hip frame's x, z) [m]")
    xz = np.array(points + path_xz)
    ax.set_xlim(xz[:, 0].min() - 0.05, xz[:, 0].max() + 0.05)  # every snapshot in view [m]
    ax.set_ylim(min(-0.05, xz[:, 1].min() - 0.05), xz[:, 1].max() + 0.1)
    fading = Line2D(
        [], [], color="#404040", lw=2.5, alpha=0.35, label=f"7 snapshots over {res.t[-1]:.2f} s: fainter = earlier"
    )
    robot_legend(ax, {g for g, _a, _b in segments}, True, True, extra=[hip_line, fading])
    ax.set_xlabel("x, forward [m]")
    ax.set_ylabel("z, up [m]")
    ax.set_title(f"{e.name}: {walk.verdict.short()} ({walk.verdict.steps} of {steps} steps simulated here)", fontsize=9)
    with atomic_path(Path(path)) as tmp:
        save_figure_file(fig, tmp, 90)
    plt.close(fig)
    return Path(path)
