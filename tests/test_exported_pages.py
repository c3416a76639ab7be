"""Every exported meshcat page is well formed: its scripts intact, its title bar's data valid JSON.

The pages are written by the commands (``export-html`` and ``simulate --html``, whose title is
long), parsed by the standard library's HTML parser, and checked tag by tag: every ``<script>``
opened is closed, meshcat's ``embedded-json`` script and our title-bar and ``#t=`` scripts are
whole and inside ``<body>``, and the title bar's data parses as JSON and matches ``<title>``.
"""

from __future__ import annotations

import html
import json
import re
from html.parser import HTMLParser

import pytest

from pasibot_pin.__main__ import main

pytestmark = [pytest.mark.integration]


class Page(HTMLParser):
    """The tags of a page in order, and each script's attributes and text."""

    def __init__(self, text: str):
        super().__init__(convert_charrefs=True)
        self.events: list[tuple[str, str]] = []
        self.scripts: list[dict] = []
        self.open_script: dict | None = None
        self.title = ""
        self._in_title = False
        self.feed(text)
        self.close()

    def handle_starttag(self, tag, attrs):
        self.events.append(("start", tag))
        if tag == "script":
            assert self.open_script is None, "a <script> opened inside another"
            self.open_script = {"attrs": dict(attrs), "text": ""}
        self._in_title = tag == "title"

    def handle_endtag(self, tag):
        self.events.append(("end", tag))
        if tag == "script":
            assert self.open_script is not None, "a </script> with no <script>"
            self.scripts.append(self.open_script)
            self.open_script = None
        self._in_title = False

    def handle_data(self, data):
        if self.open_script is not None:
            self.open_script["text"] += data
        elif self._in_title:
            self.title += data


def _check_page(text: str, expected_title: str) -> None:
    page = Page(text)
    assert page.open_script is None, "a <script> is never closed"
    starts = [t for kind, t in page.events if kind == "start"]
    ends = [t for kind, t in page.events if kind == "end"]
    assert starts.count("script") == ends.count("script") == len(page.scripts) == text.count("<script")
    # raw text: every '<script' opens a tag whose name is exactly 'script' (none split by an insertion)
    assert len(re.findall(r"<script[\s>]", text)) == text.count("<script")
    embedded = [s for s in page.scripts if s["attrs"].get("id") == "embedded-json"]
    assert len(embedded) == 1
    assert page.title == expected_title
    hud = [s for s in page.scripts if "pasibot_pin: the title" in s["text"]]
    seek = [s for s in page.scripts if "pasibot_pin: '#t=SECONDS'" in s["text"]]
    assert len(hud) == 1 and len(seek) == 1
    match = re.search(r"var info = (\{.*?\});\n", hud[0]["text"], re.S)
    assert match, "the title bar's data is missing"
    info = json.loads(match.group(1))
    assert info["title"] == expected_title
    assert len(info["t"]) == len(info["theta"]) > 1
    assert all(len(m) == len(info["t"]) for m in info["modes"].values())
    # our scripts sit at the end of <body>, after meshcat's, and the page ends whole
    body_end = text.rindex("</body>")
    assert text.index("pasibot_pin: the title") < body_end and text.index("pasibot_pin: '#t=") < body_end
    assert text.index('<script id="embedded-json">') < text.index('<div id="pasibot-hud"')
    assert text.rstrip().endswith("</html>")


def test_export_html_page_is_well_formed(tmp_path, capsys):
    out = tmp_path / "gait.html"
    assert main(["export-html", "--steps", "1", "--samples-per-step", "6", "--out", str(out)]) == 0
    text = out.read_text(encoding="utf-8")
    title = html.unescape(re.search(r"<title>(.*?)</title>", text).group(1))
    assert title != "MeshCat" and len(title) > len("MeshCat")
    _check_page(text, title)


def test_simulation_page_with_a_long_title_is_well_formed(tmp_path, capsys):
    """The simulated walk's title (50 characters) once split meshcat's ``<script id="embedded-json">``."""
    assert main(["simulate", "--ground", "weld", "--scenario", "run4", "--no-cases", "--html", "--steps", "1",
                 "--out", str(tmp_path)]) == 0  # fmt: skip
    (page,) = tmp_path.glob("*.html")
    text = page.read_text(encoding="utf-8")
    title = html.unescape(re.search(r"<title>(.*?)</title>", text).group(1))
    assert len(title) > 40
    _check_page(text, title)


@pytest.mark.parametrize("title", ["short", "a </script> & <b>tags</b> in a title, long enough to shift things"])
def test_any_title_keeps_the_page_whole(title, tmp_path):
    from pasibot_pin.model.robot import load
    from pasibot_pin.viz.viewer import WalkViewer, build_walk_scene, gait_trajectory

    robot = load("spring", legs=2)
    walk = gait_trajectory(robot, steps=1, samples_per_step=4)
    viewer = WalkViewer(robot, offline=True)
    try:
        build_walk_scene(viewer, walk.q, 30.0, title=title)
        text = viewer.static_html()
    finally:
        viewer.close()
    _check_page(text, title)
