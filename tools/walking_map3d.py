"""``make walking-map-3d``: the 3-D walking map (comb reach and leg spacing x crank speed, with the twin).

``--compute`` walks every cell again (about 20 minutes on 2 cores, MuJoCo's twin included), resuming
from ``docs/results/walking_map3d.partial.csv`` when a run was interrupted; ``--ours`` walks only our
3-D floor again and keeps the committed twin's columns (after a change to our engine alone). Without
either, the committed ``docs/results/walking_map3d.csv`` is only drawn again as ``docs/walking_map3d.png``.
"""

from __future__ import annotations

import argparse
from dataclasses import asdict, replace
from pathlib import Path

from pasibot_pin.studies.walking_map3d import compute_walking_map_3d, load_map3d, save_map3d
from pasibot_pin.viz.plots_walking3d import save_walking_map3d_figure

ROOT = Path(__file__).resolve().parents[1]
CSV = ROOT / "docs" / "results" / "walking_map3d.csv"
PARTIAL = CSV.with_suffix(".partial.csv")
PNG = ROOT / "docs" / "walking_map3d.png"


def main(argv: list[str] | None = None) -> int:
    """Compute (``--compute``) and draw the 3-D walking map."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--compute", action="store_true", help="walk every cell again")
    parser.add_argument("--ours", action="store_true", help="walk our 3-D floor again, keep the twin's columns")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)
    if args.ours and not args.compute:
        committed = load_map3d(CSV)
        ours = compute_walking_map_3d(workers=args.workers, twin=False, partial=PARTIAL)
        twin = {(c.feet, c.value, c.omega): c for c in committed.cells}
        fields = [f for f in asdict(committed.cells[0]) if f.startswith("twin_")]
        cells = [replace(c, **{f: getattr(twin[(c.feet, c.value, c.omega)], f) for f in fields}) for c in ours.cells]
        save_map3d(replace(ours, cells=cells), CSV)
        PARTIAL.unlink(missing_ok=True)
    if args.compute:
        save_map3d(compute_walking_map_3d(workers=args.workers, partial=PARTIAL), CSV)
        PARTIAL.unlink(missing_ok=True)
    wmap = load_map3d(CSV)
    save_walking_map3d_figure(wmap, PNG)
    print(f"wrote {PNG.relative_to(ROOT)}; smallest comb reach that walks [L]: {wmap.smallest_reach()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
