"""The README's generated pictures are what the library draws (``make docs-figures``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

from pasibot_pin.report.docs_figures import DOCS_DPI, write_torques_figure

DOCS = Path(__file__).resolve().parents[1] / "docs"


def test_torques_picture_is_the_library_drawing(tmp_path):
    fresh = Image.open(write_torques_figure(tmp_path / "torques.png"))
    committed = Image.open(DOCS / "torques.png")
    assert fresh.size == committed.size
    assert round(committed.info["dpi"][0]) == DOCS_DPI
    a = np.asarray(fresh.convert("L"), dtype=float)
    b = np.asarray(committed.convert("L"), dtype=float)
    assert np.mean(np.abs(a - b)) < 3.0, "docs/torques.png is stale: run `make docs-figures`"
