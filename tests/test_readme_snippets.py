"""Every Python snippet of the README and docs/*.md runs as written (in a temporary folder; viewers are closed)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

pytestmark = [pytest.mark.integration]

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
SNIPPETS = [
    (page.relative_to(ROOT).as_posix(), block)
    for page in PAGES
    for block in re.findall(r"```python\n(.*?)```", page.read_text(encoding="utf-8"), re.S)
]


def test_the_readme_has_snippets():
    assert len(SNIPPETS) >= 3
    assert any(page == "README.md" for page, _ in SNIPPETS)


@pytest.mark.parametrize("index", range(len(SNIPPETS)))
def test_snippet_runs(index, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    try:
        page, block = SNIPPETS[index]
        exec(compile(block, f"{page} python block {index}", "exec"), namespace)
    finally:
        for value in namespace.values():  # a WalkViewer owns a meshcat server process: stop it
            if type(value).__name__ == "WalkViewer":
                value.close()
