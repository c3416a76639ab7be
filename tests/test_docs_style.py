"""Readable docs (issue 34): the README fits in 250 lines, and no line of README.md or docs/*.md outside
a table or a code block runs past 400 characters; the walking answer leads with at most 40 words."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def _prose_lines(text: str):
    fenced = False
    for number, line in enumerate(text.splitlines(), 1):
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        if not fenced and not line.lstrip().startswith("|"):
            yield number, line


def test_the_readme_fits_in_250_lines():
    assert len((ROOT / "README.md").read_text(encoding="utf-8").splitlines()) <= 250


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_no_prose_line_runs_past_400_characters(page):
    long = [(n, len(line)) for n, line in _prose_lines(page.read_text(encoding="utf-8")) if len(line) > 400]
    assert not long, f"{page.name}: lines (number, length) {long}"


def test_the_walking_answer_leads_with_at_most_40_words():
    from pasibot_pin.report.answers.walking import walking_answer, walking_paragraph
    from pasibot_pin.studies.walking_map import load_map

    lead = walking_paragraph(walking_answer(load_map())).split("\n\n")[0]
    assert len(lead.split()) <= 40 and "\n" not in lead
