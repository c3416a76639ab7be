"""Compare two ``pasibot analyze`` output folders: every CSV and Markdown file must be byte-identical.

Usage: ``python benchmarks/compare_outputs.py BEFORE AFTER`` (e.g. two ``--out`` folders of one
analysis, before and after a speed change). Prints the files that differ or exist in only one
folder, and how many PNG/GIF files differ (pictures may change when only their drawing changes).
Exits non-zero when a CSV or Markdown file differs.
"""

from __future__ import annotations

import sys
from pathlib import Path

TEXT = (".csv", ".md")
PICTURES = (".png", ".gif")


def files(folder: Path, suffixes: tuple[str, ...]) -> dict[str, bytes]:
    """Relative path -> bytes of every file of ``folder`` with one of ``suffixes``."""
    return {
        str(p.relative_to(folder)): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file() and p.suffix in suffixes and ".part-" not in p.name
    }


def differences(a: dict[str, bytes], b: dict[str, bytes]) -> list[str]:
    """Names that differ or are missing on one side."""
    return [name for name in sorted(set(a) | set(b)) if a.get(name) != b.get(name)]


def main() -> int:
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    before, after = Path(sys.argv[1]), Path(sys.argv[2])
    text_a, text_b = files(before, TEXT), files(after, TEXT)
    bad = differences(text_a, text_b)
    for name in bad:
        print(f"differs: {name}")
    pics = differences(files(before, PICTURES), files(after, PICTURES))
    print(f"{len(text_a)} CSV/Markdown files compared, {len(bad)} differ; {len(pics)} pictures differ")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
