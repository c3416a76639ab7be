"""Checks on ``report.md`` text shared by the report tests: figure links, table units."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from PIL import Image

from pasibot_pin.report.files import FIGURE_DPI

_NUMERIC = re.compile(r"[\d\s.,/+\-−e%]*\d[\d\s.,/+\-−e%]*")


def images(folder: Path) -> set[str]:
    """Every PNG and GIF under ``folder``, as paths relative to it (``/`` separators)."""
    folder = Path(folder)
    return {p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.suffix.lower() in (".png", ".gif")}


def links(text: str) -> set[str]:
    """Targets of every Markdown link and image in ``text``."""
    return set(re.findall(r"\]\(([^)\s]+)\)", text))


def captioned_images(text: str) -> list[tuple[str, str]]:
    """(target, caption) of every embedded image: the italic line right after it, or '' when missing."""
    out = []
    for match in re.finditer(r"!\[[^\[\]]*\]\(([^)\s]+)\)\n\n(\*[^\n]+\*)?", text):
        out.append((match.group(1), (match.group(2) or "").strip("*")))
    return out


def tables(text: str) -> list[tuple[list[str], list[list[str]]]]:
    """Every Markdown table: (header cells, data rows' cells)."""
    out = []
    lines = text.splitlines()
    for k in range(len(lines) - 1):
        if lines[k].startswith("|") and re.fullmatch(r"\|(-+\|)+", lines[k + 1].strip()):
            header = [c.strip() for c in lines[k].strip().strip("|").split("|")]
            rows = []
            for line in lines[k + 2 :]:
                if not line.startswith("|"):
                    break
                rows.append([c.strip() for c in line.strip().strip("|").split("|")])
            out.append((header, rows))
    return out


def is_numeric(cell: str) -> bool:
    """A cell that states numbers: digits, separators and signs only, once remarks in parentheses are dropped."""
    return bool(_NUMERIC.fullmatch(re.sub(r"\([^)]*\)", "", cell).strip()))


def columns_without_units(text: str) -> list[str]:
    """Headers of table columns of numbers (most cells numeric) with no ``[unit]`` (``[-]`` for a pure number)."""
    missing = []
    for header, rows in tables(text):
        for col, name in enumerate(header):
            cells = [row[col] for row in rows if col < len(row) and row[col] not in ("-", "")]
            numeric = sum(is_numeric(c) for c in cells)
            if cells and numeric > len(cells) / 2 and "[" not in name:
                missing.append(name)
    return missing


def assert_reads_like_a_report(out: Path, text: str, least_figures: int, shared: bool = False) -> None:
    """Every figure in ``out`` linked, each embedded one captioned, every numeric column with a unit.

    ``shared``: ``text`` is one section of a report whose folder ``out`` holds the other sections' figures too;
    its own figures are those it links (each must be there).
    """
    written = images(out)
    linked = {t for t in links(text) if t.endswith((".png", ".gif"))}
    if shared:
        written &= linked
    assert len(written) >= least_figures, sorted(written)
    assert written - links(text) == set(), "figures written but not linked"
    assert linked <= images(out), "links to figures not written"
    embedded = captioned_images(text)
    assert embedded, "no figure shown"
    for target, caption in embedded:
        assert len(caption) > 20, f"{target} has no caption"
    for line in text.splitlines():  # figure lists: "- [name](path): caption"
        if line.startswith("- [") and line.split("(", 1)[1].split(")", 1)[0].endswith((".png", ".gif")):
            assert len(line.split("): ", 1)[-1]) > 15, line
    assert columns_without_units(text) == []
    for name in written:  # one resolution for every figure (torques_vs_beta was 70 dpi once)
        if name.endswith(".png"):
            assert Image.open(out / name).info["dpi"][0] == pytest.approx(FIGURE_DPI, abs=0.01), name
