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


@pytest.mark.parametrize(
    ("walkers", "words"),
    [
        ({"parallel": 9, "rigid": 0, "spring": 0}, "9 of them walk, all parallel; no rigid or spring design walks"),
        ({"parallel": 2, "rigid": 1, "spring": 0}, "3 of them walk (2 parallel, 1 rigid); no spring design walks"),
        ({"parallel": 0, "rigid": 0}, "none of them walks"),
    ],
)
def test_the_answers_count_walkers_in_words(walkers, words):
    """Issue 34's phrase "walkers by variant parallel (9)": the box says how many walk, and of which variant."""
    from pasibot_pin.report.answers import _walkers

    assert _walkers(walkers) == words


def test_no_page_carries_the_phrases_issue_34_lists():
    bad = ("1 steps", "walkers by variant parallel", "design(s)", "walked 108 of the cells", "> <!--")
    for page in [*PAGES, ROOT / "designs" / "README.md"]:
        text = page.read_text(encoding="utf-8")
        assert not [p for p in bad if p in text], page.name


def test_the_reports_summary_counts_spring_walkers_in_words():
    from pasibot_pin.report.markdown import _walk_count

    assert _walk_count(0, 120) == "none of the 120 spring designs walk"
    assert _walk_count(1, 120) == "1 of the 120 spring designs walks"
    assert _walk_count(7, 120) == "7 of the 120 spring designs walk"


UNITS = ("(m)", "(deg)", "(L)", "(N.m", "(rad/s)", "lengths in m", "(s)")


@pytest.mark.parametrize("page", [*PAGES, ROOT / "designs" / "README.md"], ids=lambda p: p.name)
def test_every_pictures_alt_text_names_its_units(page):
    """Issue 34: image alt texts without their units. Every still picture's alt text names a unit (an animation's
    frames carry their own axes)."""
    import re

    alts = re.findall(r"!\[([^\]]*)\]\(([^)]*\.png)\)", page.read_text(encoding="utf-8"))
    assert not [alt for alt, _ in alts if not any(u in alt for u in UNITS)]
