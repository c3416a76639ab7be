"""Compare two ``pasibot analyze`` output folders: the same report, file for file.

Usage: ``python benchmarks/compare_outputs.py BEFORE AFTER`` (e.g. two ``--out`` folders of one
analysis, before and after a speed change). Every file of either folder (but the folder's marker)
is compared with its namesake, and each one counts as the same when:

- a picture (PNG, GIF): its bytes are equal, or else its pixels are (every frame decoded to RGBA,
  the same size, count and duration): an encoder's settings may change the bytes, not the picture;
- a meshcat page (HTML): equal once every uuid is masked, in the text and inside its base64 data
  (meshcat names its objects by time-based uuids, so no two builds are byte-identical);
- any other file (CSV, Markdown, text): its bytes are equal.

Prints the files that differ or exist in only one folder and a count per kind; exits non-zero
when any file differs.
"""

from __future__ import annotations

import base64
import re
import sys
from pathlib import Path

MARKER = ".pasibot"
"""The output folder's marker file (:data:`pasibot_pin.files.MARKER`): not part of the report."""

PICTURES = (".png", ".gif")
PAGES = (".html",)

UUID = re.compile(rb"[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}")
BASE64 = re.compile(rb"(base64,)([A-Za-z0-9+/=]+)")

DIFFERS = {"bytes": "its bytes differ", "pixels": "its pixels differ", "uuids": "it differs beyond its uuids"}
"""How a file that is not the same differs, by the rule it was compared by."""


def files(folder: Path) -> dict[str, Path]:
    """Relative path -> file of every file of ``folder`` (the marker and temporaries left out)."""
    return {
        str(p.relative_to(folder)): p
        for p in sorted(folder.rglob("*"))
        if p.is_file() and p.name != MARKER and ".part-" not in p.name
    }


def frames(path: Path) -> tuple[tuple, list[bytes]]:
    """A picture's (size, frame count, durations) and every frame's RGBA bytes."""
    from PIL import Image, ImageSequence  # deferred: heavy (PIL), a benchmark tool's import

    with Image.open(path) as image:
        pixels, durations = [], []
        for frame in ImageSequence.Iterator(image):
            pixels.append(frame.convert("RGBA").tobytes())
            durations.append(frame.info.get("duration"))
        return (image.size, len(pixels), tuple(durations)), pixels


def page_text(data: bytes) -> bytes:
    """A meshcat page with every uuid masked, in its text and in its base64 payloads (decoded)."""

    def masked(match: re.Match) -> bytes:
        try:
            payload = base64.b64decode(match.group(2), validate=True)
        except ValueError:
            return match.group(0)
        return match.group(1) + UUID.sub(b"<uuid>", payload)

    return UUID.sub(b"<uuid>", BASE64.sub(masked, data))


def same(a: Path, b: Path) -> tuple[bool, str]:
    """Whether ``a`` and ``b`` hold the same content, and how that was decided (``bytes``, ``pixels``, ``uuids``)."""
    data_a, data_b = a.read_bytes(), b.read_bytes()
    if data_a == data_b:
        return True, "bytes"
    suffix = a.suffix.lower()
    if suffix in PICTURES:
        return frames(a) == frames(b), "pixels"
    if suffix in PAGES:
        return page_text(data_a) == page_text(data_b), "uuids"
    return False, "bytes"


def compare(before: Path, after: Path) -> tuple[list[str], dict[str, int]]:
    """The names that differ (or exist on one side), and how many files matched by each rule."""
    a, b = files(before), files(after)
    bad, how = [], {"bytes": 0, "pixels": 0, "uuids": 0}
    for name in sorted(set(a) | set(b)):
        if name not in a or name not in b:
            bad.append(f"{name} (only in {'AFTER' if name in b else 'BEFORE'})")
            continue
        equal, rule = same(a[name], b[name])
        if equal:
            how[rule] += 1
        else:
            bad.append(f"{name} ({DIFFERS[rule]})")
    return bad, how


def main() -> int:
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    bad, how = compare(Path(sys.argv[1]), Path(sys.argv[2]))
    for name in bad:
        print(f"differs: {name}")
    print(
        f"{sum(how.values())} files the same ({how['bytes']} byte for byte, {how['pixels']} pictures pixel for pixel, "
        f"{how['uuids']} meshcat pages but their uuids); {len(bad)} differ"
    )
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
