"""``make walking-map``: the walking map's files (CSV, picture), ``designs/`` and the quoted answer.

(``--compute``: the map walked again on the process pool, saved as CSV.) Then the map's picture,
``designs/`` (``tools/designs_catalog.py``) and the generated blocks of ``docs/walking.md`` and
``README.md`` (:func:`pasibot_pin.report.answers.walking.docs_texts`). The package computes and
returns; this tool reads and writes the repository's files.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from pathlib import Path

from pasibot_pin.files import write_text_atomic
from pasibot_pin.report.answers.walking import docs_texts
from pasibot_pin.studies.walking_map import (
    MAP_CSV,
    MAP_PNG,
    WalkingMap,
    add_twin,
    compute_walking_map,
    load_map,
    save_map,
    with_twin_of,
)
from pasibot_pin.viz.plots_walking import save_walking_map_figure

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
from designs_catalog import write_catalog  # noqa: E402  (a sibling tool)


def update_docs(wmap: WalkingMap) -> list[Path]:
    """Write the generated blocks of docs/walking.md (paragraph, tables, sweep) and README.md (paragraph)."""
    doc, readme = ROOT / "docs" / "walking.md", ROOT / "README.md"
    doc_text, readme_text = docs_texts(wmap, doc.read_text(encoding="utf-8"), readme.read_text(encoding="utf-8"))
    return [write_text_atomic(doc, doc_text), write_text_atomic(readme, readme_text)]


def main(argv: Sequence[str] | None = None) -> None:
    """(``--compute``: the map on 2 workers, saved as CSV) the picture, designs/, the quotes."""
    parser = argparse.ArgumentParser(description="the walking map's files: CSV, picture, designs/, quoted answer")
    parser.add_argument("--compute", action="store_true", help="walk every cell again first (about 30 min CPU)")
    parser.add_argument("--workers", type=int, default=2, help="worker processes of --compute (default 2)")
    parser.add_argument("--twin", action="store_true", help="walk the MuJoCo twin in the cells that have none yet")
    parser.add_argument(
        "--keep-twin",
        action="store_true",
        help="with --compute: walk our engine only and keep the committed twin's outcomes (our engine changed)",
    )
    args = parser.parse_args(argv)
    if args.twin and not args.compute:
        start = time.monotonic()
        save_map(add_twin(load_map(), 0.0, workers=args.workers))
        print(f"{MAP_CSV}: the twin's missing cells walked in {time.monotonic() - start:.0f} s wall")
    if args.compute:
        start = time.monotonic()
        partial = MAP_CSV.with_name("walking_map.partial.csv")  # an interrupted map resumes from it
        wmap = compute_walking_map(workers=args.workers, partial=partial, twin=not args.keep_twin)
        if args.keep_twin:
            wmap = with_twin_of(wmap, load_map())
        save_map(wmap)
        partial.unlink()
        cpu = sum(c.cpu_s for c in wmap.cells)
        print(f"{MAP_CSV}: {len(wmap.cells)} cells, {time.monotonic() - start:.0f} s wall, {cpu:.0f} s CPU of walks")
    wmap = load_map()
    print(save_walking_map_figure(wmap, MAP_PNG, dpi=100))  # the README's resolution (report/docs_figures)
    for written in [*write_catalog(wmap), *update_docs(wmap)]:
        print(written)


if __name__ == "__main__":
    main()
