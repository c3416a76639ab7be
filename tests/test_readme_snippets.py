"""Every Python snippet of the README runs as written (in a temporary folder; a viewer it starts is closed)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

README = (Path(__file__).resolve().parents[1] / "README.md").read_text(encoding="utf-8")
SNIPPETS = re.findall(r"```python\n(.*?)```", README, re.S)


def test_the_readme_has_snippets():
    assert len(SNIPPETS) >= 3


@pytest.mark.parametrize("index", range(len(SNIPPETS)))
def test_snippet_runs(index, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    try:
        exec(compile(SNIPPETS[index], f"README.md python block {index}", "exec"), namespace)
    finally:
        for value in namespace.values():  # a WalkViewer owns a meshcat server process: stop it
            if type(value).__name__ == "WalkViewer":
                value.close()
