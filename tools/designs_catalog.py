"""``make designs``: ``designs/``, the found designs (TOML, picture, README table), and ``--check``.

The picks and the texts are :mod:`pasibot_pin.report.designs_catalog`'s; this tool writes them
into the repository's ``designs/`` folder (the package computes and returns, it never writes into
the repository). ``--check`` re-simulates every committed design for the full step count and
compares its outcome, steps and largest hip pitch with the table.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Sequence
from pathlib import Path

from pasibot_pin.files import write_text_atomic
from pasibot_pin.model.design import load_design
from pasibot_pin.report.designs_catalog import (
    SWEEP_NAME,
    Entry,
    catalog_markdown,
    draw_design,
    pick_designs,
    sweep_rows,
)
from pasibot_pin.studies.walking import WalkSettings, walk_design
from pasibot_pin.studies.walking_map import WalkingMap, load_map

ROOT = Path(__file__).resolve().parents[1]
DESIGNS_DIR = ROOT / "designs"
SWEEP_CSV = ROOT / "docs" / "results" / SWEEP_NAME
"""The repository's committed walking sweep (the tool names its own files; the package finds its copy)."""


def entries(wmap: WalkingMap) -> list[Entry]:
    """The committed picks: the walking map's and the committed sweep's fastest walker."""
    return pick_designs(wmap, sweep_rows(SWEEP_CSV))


def write_catalog(wmap: WalkingMap, folder: Path = DESIGNS_DIR, pictures: bool = True) -> list[Path]:
    """Write every picked design's TOML (and picture) and ``README.md`` into ``folder``; stale picks removed."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    picks = entries(wmap)
    written = []
    for e in picks:
        written.append(e.design.save(folder / f"{e.name}.toml", force=True))
        if pictures:
            written.append(draw_design(e, folder / f"{e.name}.png"))
    names = {e.name for e in picks}
    for old in [*folder.glob("*.toml"), *folder.glob("*.png")]:
        if old.stem not in names:  # a design the picks no longer hold (renamed or dropped)
            old.unlink()
    written.append(write_text_atomic(folder / "README.md", catalog_markdown(picks, wmap.steps)))
    return written


def check_catalog(wmap: WalkingMap, folder: Path = DESIGNS_DIR) -> list[str]:
    """Re-simulate every committed design for the map's steps; the differences from the table (empty: none)."""
    problems = []
    for e in entries(wmap):
        v = walk_design(load_design(folder / f"{e.name}.toml"), WalkSettings(steps=wmap.steps)).verdict
        got = (v.outcome, v.steps, round(math.degrees(v.max_hip_pitch), 2))
        if e.cell is not None:
            want = (e.cell.outcome, e.cell.steps, round(e.cell.max_hip_pitch_deg, 2))
        else:
            r = e.sweep or {}
            want = (r["floor_outcome"], int(float(r["floor_steps"])), round(float(r["floor_max_hip_pitch_deg"]), 2))
        print(f"{e.name}: {v.summary()}", flush=True)
        if got != want:
            problems.append(f"{e.name}: simulated {got}, table {want}")
    return problems


def main(argv: Sequence[str] | None = None) -> None:
    """Write ``designs/`` from the committed walking map and sweep, or ``--check`` it."""
    parser = argparse.ArgumentParser(description="write designs/ from docs/results/walking_map.csv and the sweep")
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
