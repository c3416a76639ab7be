"""The README's pictures are what the library draws (``make docs-figures``): each is redrawn and compared."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image, ImageSequence

from pasibot_pin.report.docs_figures import DOCS_DPI, DOCS_PICTURES, GIF_DPI

DOCS = Path(__file__).resolve().parents[1] / "docs"
README = Path(__file__).resolve().parents[1] / "README.md"


def _grey_frames(path: Path) -> list[np.ndarray]:
    with Image.open(path) as image:
        return [np.asarray(frame.convert("L"), dtype=float) for frame in ImageSequence.Iterator(image)]


@pytest.mark.slow
@pytest.mark.parametrize(("write", "name"), DOCS_PICTURES, ids=[name for _, name in DOCS_PICTURES])
def test_docs_picture_is_the_library_drawing(write, name, tmp_path):
    fresh_path = write(tmp_path / name)
    committed_path = DOCS / name
    with Image.open(fresh_path) as fresh, Image.open(committed_path) as committed:
        assert fresh.size == committed.size, f"docs/{name} has another size: run `make docs-figures`"
        if name.endswith(".png"):
            assert round(committed.info["dpi"][0]) == DOCS_DPI
        else:
            assert committed.size == (round(6.4 * GIF_DPI), round(5.0 * GIF_DPI))  # save_gif's 6.4 x 5 in
    new, old = _grey_frames(fresh_path), _grey_frames(committed_path)
    assert len(new) == len(old), f"docs/{name} has another number of frames: run `make docs-figures`"
    for a, b in zip(new, old):
        assert np.mean(np.abs(a - b)) < 3.0, f"docs/{name} is stale: run `make docs-figures`"


def test_every_readme_picture_is_drawn_by_the_library():
    """Each picture the README shows from docs/ has its writer in DOCS_PICTURES."""
    import re

    shown = set(re.findall(r"\]\(docs/([\w.]+\.(?:png|gif))\)", README.read_text(encoding="utf-8")))
    assert shown, "the README shows no picture from docs/"
    drawn = {name for _, name in DOCS_PICTURES}
    # make floor-springs; make walking-map-3d (tools/walking_map3d.py draws it from the committed map)
    generated_elsewhere = {"floor_springs.png", "floor_quasi_static.png", "walking_map3d.png"}
    assert shown - generated_elsewhere <= drawn, sorted(shown - drawn - generated_elsewhere)
