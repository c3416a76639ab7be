"""``make walking-map``, its first half: walk the planar walking map again and save it (docs/results/walking_map.csv).

``--compute`` walks every cell (108 designs x 20 steps, about 30 minutes of CPU on 2 workers), resuming from
``docs/results/walking_map.partial.csv`` when a run was interrupted; ``--keep-twin`` walks our engine only and
keeps the committed MuJoCo twin's outcomes (for a change of our engine alone); ``--twin`` walks the twin in every
cell that has no twin outcome yet. The second half, ``python -m pasibot_pin.report.walking_answer``, draws
``docs/walking_map.png`` and writes ``designs/`` and the quoted answer from the saved map.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from pasibot_pin.studies.walking_map import add_twin, compute_walking_map, load_map, save_map, with_twin_of

ROOT = Path(__file__).resolve().parents[1]
CSV = ROOT / "docs" / "results" / "walking_map.csv"
PARTIAL = CSV.with_name("walking_map.partial.csv")


def main(argv: list[str] | None = None) -> int:
    """Compute (``--compute``) or complete (``--twin``) the walking map and save it."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--compute", action="store_true", help="walk every cell again (about 30 min of CPU)")
    parser.add_argument("--workers", type=int, default=2, help="worker processes (default 2)")
    parser.add_argument("--twin", action="store_true", help="walk the MuJoCo twin where the map has no twin outcome")
    parser.add_argument("--keep-twin", action="store_true", help="with --compute: our engine only, keep the twin's")
    args = parser.parse_args(argv)
    start = time.monotonic()
    if args.compute:
        wmap = compute_walking_map(workers=args.workers, partial=PARTIAL, twin=not args.keep_twin)
        if args.keep_twin:
            wmap = with_twin_of(wmap, load_map(CSV))
        save_map(wmap, CSV)
        PARTIAL.unlink(missing_ok=True)
        cpu = sum(c.cpu_s for c in wmap.cells)
        print(
            f"{CSV.relative_to(ROOT)}: {len(wmap.cells)} cells, {time.monotonic() - start:.0f} s wall, {cpu:.0f} s CPU"
        )
    elif args.twin:
        save_map(add_twin(load_map(CSV), 0.0, workers=args.workers), CSV)
        print(f"{CSV.relative_to(ROOT)}: the twin's missing cells walked in {time.monotonic() - start:.0f} s wall")
    else:
        parser.error("give --compute or --twin")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
