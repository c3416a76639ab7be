"""benchmarks/compare_outputs.py (issue 33): two analyze folders are the same report when every CSV and
Markdown file is byte-identical, every picture pixel-identical and every meshcat page equal but its uuids;
anything else is a difference."""

from __future__ import annotations

import base64
import importlib.util
import uuid
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "compare_outputs.py"


@pytest.fixture(scope="module")
def tool():
    spec = importlib.util.spec_from_file_location("compare_outputs", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _page() -> str:
    """A page as meshcat writes one: a fresh uuid in its text and inside a base64 payload."""
    payload = base64.b64encode(b"\x83\xa4uuid\xd9$" + str(uuid.uuid1()).encode() + b"\xa4type").decode()
    return f'<script>var id = "{uuid.uuid1()}"; fetch("data:application/octet-binary;base64,{payload}")</script>'


def _folder(root: Path, name: str, pixels: np.ndarray, level: int, table: str = "a,b\n1,2\n") -> Path:
    folder = root / name
    folder.mkdir()
    (folder / "table.csv").write_text(table)
    (folder / "report.md").write_text("# report\n")
    Image.fromarray(pixels).save(folder / "figure.png", compress_level=level)
    frames = [Image.fromarray(pixels), Image.fromarray(255 - pixels)]
    frames[0].save(folder / "walk.gif", save_all=True, append_images=frames[1:], duration=100, loop=0)
    (folder / "gait.html").write_text(_page())
    (folder / ".pasibot").write_text(name)  # the marker differs between any two folders
    return folder


def test_same_report_with_other_png_bytes_and_uuids(tool, tmp_path):
    pixels = np.random.default_rng(0).integers(0, 255, (20, 30, 3), dtype=np.uint8)
    a = _folder(tmp_path, "a", pixels, level=1)
    b = _folder(tmp_path, "b", pixels, level=9)
    assert (a / "figure.png").read_bytes() != (b / "figure.png").read_bytes()
    assert (a / "gait.html").read_text() != (b / "gait.html").read_text()
    bad, how = tool.compare(a, b)
    assert bad == []
    assert how == {"bytes": 3, "pixels": 1, "uuids": 1}


def test_a_pixel_a_number_or_a_missing_file_differs(tool, tmp_path):
    pixels = np.random.default_rng(1).integers(0, 255, (20, 30, 3), dtype=np.uint8)
    other = pixels.copy()
    other[5, 7, 1] ^= 1
    a = _folder(tmp_path, "a", pixels, level=1)
    b = _folder(tmp_path, "b", other, level=1, table="a,b\n1,2.0000000000000004\n")
    (b / "extra.csv").write_text("x\n")
    (b / "gait.html").write_text((b / "gait.html").read_text().replace("fetch", "fetch "))
    bad, _ = tool.compare(a, b)
    assert bad == [
        "extra.csv (only in AFTER)",
        "figure.png (its pixels differ)",
        "gait.html (it differs beyond its uuids)",
        "table.csv (its bytes differ)",
        "walk.gif (its pixels differ)",
    ]
