"""The exported HTML in a real browser: headless Chromium (Debian), WebGL through SwiftShader.

The page is loaded from the filesystem, with the network-quieting flags, and screenshotted:

- at two animation times (``#t=`` pauses the walk there): the robot is drawn (its pixels
  differ from an export without the robot) and it has walked forward between the two;
- once with no ``#t=``: the page plays by itself (the robot has left its pose at ``#t=0``,
  where a page that does not play would keep it).

Every kind of exported page (``export_html``'s prescribed gait, the report's simulated walk
``simulation_<run>.html``, ``pasibot walk``'s floor walk) is also loaded, and its title bar
(``#pasibot-hud``) reads the page's title, then the time it was paused at, the crank angle and
each foot's mode.

Each Chromium start costs about 2 s of CPU and each page's load (its script, SwiftShader's
WebGL) about 3 s more, spread over both cores: the paused pages load side by side in frames of
one window for their screenshots, and the exported pages likewise for their title bars; the
playing page has a Chromium of its own (in a grid its frames would make the whole window redraw).

Chromium must be installed (``make browser-deps``, run by ``make test``). A missing browser is
a failure, never a skip. Screenshots are kept in tests/artifacts/browser/.
"""

from __future__ import annotations

import math
import os
import shutil
import subprocess
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from pasibot_pin.viz import viewer

pytestmark = [pytest.mark.browser, pytest.mark.slow]

ARTIFACTS = Path(__file__).resolve().parent / "artifacts" / "browser"
WIDTH, HEIGHT = 800, 600
FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--enable-unsafe-swiftshader",
    "--use-angle=swiftshader",
    "--hide-scrollbars",
]
T_EARLY, T_MID, T_LATE = 0.2, 0.9, 1.6  # [s], within one play of the 2 s walk
HUD_ROWS = 60
"""Rows at the top of the page that hold the title bar (scenario, time, crank angle, foot modes)."""
CHANGED = 40  # a pixel "differs" when a channel moves by more than this (of 255)
SEEK_BUDGET_MS = 1000
"""Virtual time [ms] given to a page paused by ``#t=`` before its screenshot or its title bar is read."""


def chromium() -> str:
    path = shutil.which("chromium") or ("/usr/bin/chromium" if os.path.exists("/usr/bin/chromium") else None)
    if path is None:
        pytest.fail("chromium is not installed: run `make browser-deps` (Debian package 'chromium')")
    return path


def run_chromium(address: str, size: tuple[int, int], budget_ms: int, *extra: str) -> subprocess.CompletedProcess:
    """Headless Chromium (:data:`FLAGS`, a fresh profile) on ``address`` in a window of ``size`` [px], after
    ``budget_ms`` of virtual time, with ``extra`` flags (what to output); fails the test if Chromium does."""
    with tempfile.TemporaryDirectory(prefix="chromium-profile-") as profile:
        cmd = [
            chromium(),
            *FLAGS,
            *extra,
            f"--window-size={size[0]},{size[1]}",
            f"--user-data-dir={profile}",
            f"--virtual-time-budget={budget_ms}",
            address,
        ]
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=90)
    assert proc.returncode == 0, f"chromium failed ({proc.returncode}):\n{proc.stderr[-2000:]}"
    return proc


def screenshot(html: Path, png: Path, fragment: str = "", budget_ms: int = 3000, size=(WIDTH, HEIGHT)) -> np.ndarray:
    """Load ``html`` from the filesystem in headless Chromium and save a screenshot; returns RGB (rows, cols, 3)."""
    proc = run_chromium(html.resolve().as_uri() + fragment, size, budget_ms, f"--screenshot={png}")
    assert png.exists(), f"chromium wrote no screenshot:\n{proc.stderr[-2000:]}"
    return np.asarray(Image.open(png).convert("RGB")).astype(int)


def page_shot(html: Path, png: Path, fragment: str = "", budget_ms: int = 3000) -> np.ndarray:
    """One page in a WIDTH x HEIGHT window: its rows below the title bar (whose text changes with the time)."""
    return screenshot(html, png, fragment, budget_ms)[HUD_ROWS:]


def grid_shots(pages: dict[str, str], folder: Path, budget_ms: int) -> dict[str, np.ndarray]:
    """Several pages in one browser: a grid of WIDTH x HEIGHT iframes, one screenshot, cut into tiles.

    Each page is the exported file itself (``address`` relative to ``folder``, with its fragment) in
    a frame of the window's size, so it draws what it draws alone in such a window; one Chromium
    start (about a second of CPU) instead of one per page.
    """
    cols = 3
    rows = -(-len(pages) // cols)
    frames = "\n".join(
        f'<iframe src="{address}" style="position:absolute;left:{(k % cols) * WIDTH}px;top:{(k // cols) * HEIGHT}px;'
        f'width:{WIDTH}px;height:{HEIGHT}px;border:0"></iframe>'
        for k, address in enumerate(pages.values())
    )
    grid = folder / "grid.html"
    grid.write_text(f'<html><body style="margin:0;overflow:hidden">{frames}</body></html>')
    image = screenshot(grid, folder / "grid.png", "", budget_ms, (cols * WIDTH, rows * HEIGHT))
    tiles = {}
    for k, name in enumerate(pages):
        top, left = (k // cols) * HEIGHT, (k % cols) * WIDTH
        tiles[name] = image[top + HUD_ROWS : top + HEIGHT, left : left + WIDTH]
        Image.fromarray(image[top : top + HEIGHT, left : left + WIDTH].astype(np.uint8)).save(folder / f"{name}.png")
    return tiles


def changed(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs(a - b).max(axis=2) > CHANGED


@pytest.fixture(scope="module")
def shots(tmp_path_factory):
    import pasibot_pin as pp

    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    robot = pp.load("spring", legs=2)
    folder = tmp_path_factory.mktemp("browser")
    with_robot = viewer.export_html(folder / "walk.html", robot, steps=2, samples_per_step=30, fps=30.0)
    viewer.export_html(folder / "empty.html", robot, steps=2, samples_per_step=30, fps=30.0, show_robot=False)
    shutil.copy(with_robot.path, ARTIFACTS / "walk.html")
    # Two browsers at once: the playing page (every frame drawn; the longest) and one grid of
    # the paused pages. A paused page (#t=) is drawn once it has loaded: virtual time waits for the
    # loading, so SEEK_BUDGET_MS is enough (its screenshots equal those after 3000 ms, pixel for pixel).
    # The playing page has a browser of its own: in the grid its frames would redraw the whole window
    # (measured: 10 core-s more for the module).
    paused = {
        "robot_start": "walk.html#t=0",
        "robot_early": f"walk.html#t={T_EARLY}",
        "robot_mid": f"walk.html#t={T_MID}",
        "robot_late": f"walk.html#t={T_LATE}",
        "empty_early": f"empty.html#t={T_EARLY}",
        "empty_late": f"empty.html#t={T_LATE}",
    }
    with ThreadPoolExecutor(max_workers=2) as pool:
        playing = pool.submit(page_shot, with_robot.path, folder / "autoplay.png", "", 1500)
        grid = pool.submit(grid_shots, paused, folder, SEEK_BUDGET_MS)
        images = {"autoplay": playing.result(), **grid.result()}
    for name in ["autoplay", *paused]:  # kept for a look; written from this run's own folder, never read back
        shutil.copy(folder / f"{name}.png", ARTIFACTS / f"{name}.png")
    return images, with_robot


def test_screenshots_have_the_page_size(shots):
    images, _ = shots
    for name, img in images.items():
        assert img.shape == (HEIGHT - HUD_ROWS, WIDTH, 3), name
        assert img.std() > 10, f"{name} is blank"


def test_the_static_scene_does_not_move(shots):
    """Control: without the robot, the two times give the same picture (ground, paths, sky)."""
    images, _ = shots
    assert changed(images["empty_early"], images["empty_late"]).sum() < 50


def test_the_robot_is_drawn(shots):
    images, _ = shots
    for when in ("early", "late"):
        mask = changed(images[f"robot_{when}"], images[f"empty_{when}"])
        assert mask.sum() > 1500, f"robot at {when}: only {mask.sum()} pixels differ from the empty scene"
        rows = np.flatnonzero(mask.any(axis=1))
        assert rows[-1] - rows[0] > HEIGHT / 4, "the robot should stand a good part of the view high"
        rgb = images[f"robot_{when}"][mask]
        orange = (rgb[:, 0] > 150) & (rgb[:, 0] - rgb[:, 2] > 90)  # the Hoeken links (#f28c1a)
        blue = (rgb[:, 2] > 120) & (rgb[:, 2] - rgb[:, 0] > 60)  # the pantograph (#2673d9)
        joints = np.abs(rgb - 0x22).max(axis=1) < 30  # the joint markers (#222222)
        contacts = (rgb[:, 1] > 120) & (rgb[:, 1] - rgb[:, 0] > 60) & (rgb[:, 1] - rgb[:, 2] > 40)  # #1a9e3a
        counts = (orange.sum(), blue.sum(), joints.sum(), contacts.sum())
        assert orange.sum() > 20 and blue.sum() > 200 and joints.sum() > 100 and contacts.sum() > 20, counts


def test_the_robot_walks_forward_between_the_two_times(shots):
    images, export = shots
    assert changed(images["robot_early"], images["robot_late"]).sum() > 1500
    cols = {}
    for when in ("early", "late"):
        mask = changed(images[f"robot_{when}"], images[f"empty_{when}"])
        cols[when] = np.flatnonzero(mask).astype(float) % WIDTH
    shift_px = np.median(cols["late"]) - np.median(cols["early"])
    # seen from the robot's right side, x (forward) points right on the screen
    hip_advance = np.interp([T_EARLY, T_LATE], np.arange(len(export.q)) / export.fps, export.q[:, 0])
    assert hip_advance[1] - hip_advance[0] > 0.3
    assert shift_px > 40, f"the robot moved {shift_px:.0f} px, expected it to the right"


def test_the_seek_lands_at_the_requested_time(shots):
    """The robot's place on screen follows the hip's x at the three requested times.

    The robot's pixels move with its hip (the legs hang from it), and the camera looks square at the walking
    plane, so the median column of the robot's pixels moves in proportion to the hip's x.
    """
    images, export = shots
    times = (T_EARLY, T_MID, T_LATE)
    hip_x = np.interp(times, np.arange(len(export.q)) / export.fps, export.q[:, 0])
    column = []
    for name in ("robot_early", "robot_mid", "robot_late"):
        mask = changed(images[name], images["empty_early"])
        column.append(np.median(np.flatnonzero(mask) % WIDTH))
    expected = (hip_x[1] - hip_x[0]) / (hip_x[2] - hip_x[0])
    seen = (column[1] - column[0]) / (column[2] - column[0])
    assert seen == pytest.approx(expected, abs=0.08), (column, hip_x)


def test_the_page_plays_by_itself(shots):
    """No #t=: after 1.5 s of virtual time the robot has left its pose at t = 0 (the animation runs).

    A page that loaded the walk but did not play it would show the pose at t = 0, as ``#t=0`` does.
    """
    images, _ = shots
    assert changed(images["autoplay"], images["empty_early"]).sum() > 1500, "autoplay: no robot"
    assert changed(images["robot_start"], images["empty_early"]).sum() > 1500, "#t=0: no robot"
    assert changed(images["autoplay"], images["robot_start"]).sum() > 500


# --------------------------------------------------------------------------- every exported page's title bar
def title_bars(pages: dict[str, Path], budget_ms: int = SEEK_BUDGET_MS) -> dict[str, tuple[list[str], str]]:
    """Each page's title bar (``#pasibot-hud``) lines and document title, paused at t = 0.5 s, in one Chromium.

    The pages (all in one folder) load side by side in frames of a page written beside them, which copies each
    frame's title bar text and title into its own DOM as the frames run (``--allow-file-access-from-files``: a
    file's frames are readable by a file beside them); Chromium's ``--dump-dom`` then prints that page.
    """
    (folder,) = {path.parent for path in pages.values()}
    names = list(pages)
    frames = "\n".join(
        f'<iframe id="frame{k}" src="{pages[name].name}#t=0.5" style="position:absolute;left:{k * WIDTH}px;top:0;'
        f'width:{WIDTH}px;height:{HEIGHT}px;border:0"></iframe><pre id="hud{k}"></pre><pre id="title{k}"></pre>'
        for k, name in enumerate(names)
    )
    script = f"""<script>
setInterval(function () {{
  for (var k = 0; k < {len(names)}; k++) {{
    var page = document.getElementById("frame" + k).contentDocument;
    var hud = page && page.getElementById("pasibot-hud");
    if (hud) {{
      document.getElementById("hud" + k).textContent = hud.textContent;
      document.getElementById("title" + k).textContent = page.title;
    }}
  }}
}}, 20);
</script>"""
    reader = folder / "title_bars.html"
    reader.write_text(f'<html><body style="margin:0;overflow:hidden">{frames}\n{script}</body></html>')
    size = (len(names) * WIDTH, HEIGHT)
    proc = run_chromium(reader.resolve().as_uri(), size, budget_ms, "--allow-file-access-from-files", "--dump-dom")
    assert "<html" in proc.stdout, f"chromium dumped no page:\n{proc.stderr[-2000:]}"
    return {
        name: (_text_of(proc.stdout, f"hud{k}").splitlines(), _text_of(proc.stdout, f"title{k}"))
        for k, name in enumerate(names)
    }


def _text_of(dom: str, element_id: str) -> str:
    """The text inside the element ``element_id`` of a dumped DOM, read by the HTML parser (entities decoded)."""
    from html.parser import HTMLParser

    class Element(HTMLParser):
        def __init__(self):
            super().__init__()
            self.depth, self.text = 0, []

        def handle_starttag(self, tag, attrs):
            if self.depth or dict(attrs).get("id") == element_id:
                self.depth += 1

        def handle_endtag(self, tag):
            self.depth = max(0, self.depth - 1)

        def handle_data(self, data):
            if self.depth:
                self.text.append(data)

    parser = Element()
    parser.feed(dom)
    return "".join(parser.text)


@pytest.fixture(scope="module")
def exported_pages(tmp_path_factory):
    """One page of each kind the package exports: (file, the title its bar must show)."""
    import pasibot_pin as pp
    from pasibot_pin.dynamics.simulator import SimulationSettings, simulate
    from pasibot_pin.model.design import Design, design_robot
    from pasibot_pin.report.animation import SIMULATION_TITLE, export_animation
    from pasibot_pin.report.walking import write_walk_animation
    from pasibot_pin.studies.spring_study import scenario_inputs, standing_pitch
    from pasibot_pin.studies.walking import WalkSettings, walk_design

    folder = tmp_path_factory.mktemp("pages")
    robot = pp.load("spring", legs=2)
    pages = {}
    viewer.export_html(folder / "gait.html", robot, steps=1, samples_per_step=20, fps=30.0)
    pages["gait"] = (folder / "gait.html", "PASIBOT spring biped, 1 step (prescribed gait, stance sole welded flat)")
    run4 = scenario_inputs("run4")  # the report's simulation page: pasibot analyze's simulation_run4.html
    pitch = standing_pitch(run4.robot, run4.fit, math.pi / 2)  # started where it stands, as the report starts it
    settings = SimulationSettings(omega=run4.omega, spring=run4.fit, swing_ankle="rest", dt=0.01, initial_pitch=pitch)
    result = simulate(run4.robot, settings, duration=1.0)
    assert not result.fell
    export_animation(run4.robot, result, html=folder / "simulation_run4.html", fps=20.0)
    pages["simulation"] = (folder / "simulation_run4.html", SIMULATION_TITLE)
    design = Design(variant="parallel", parallel_toe=4.5, parallel_heel=4.5, omega=2.0)
    walker = design_robot(design, 2)  # with its visuals: the page draws them
    walk = walk_design(design, WalkSettings(steps=1), walker)  # pasibot walk's page
    write_walk_animation(walk, walker, html=folder / "walk.html", fps=20.0)
    pages["walk"] = (folder / "walk.html", f"parallel on the floor, 2 rad/s: {walk.verdict.short()}")
    return pages


def test_every_exported_page_shows_its_title_bar(exported_pages):
    """Each page type, loaded in Chromium: the title bar (#pasibot-hud) holds the page's title, then the time,
    the crank angle and each foot's contact mode; the document's title is the same title."""
    import re

    bars = title_bars({kind: path for kind, (path, _) in exported_pages.items()})
    for kind, (_, title) in exported_pages.items():
        lines, document_title = bars[kind]
        assert lines and lines[0] == title, (kind, lines)
        clock = re.fullmatch(
            r"t = (\d+\.\d\d) s   crank angle = -?\d+\.\d deg   right: [\w ]+   left: [\w ]+", lines[1]
        )
        assert clock and abs(float(clock.group(1)) - 0.5) <= 0.05, (kind, lines)  # the frame #t=0.5 paused at
        assert document_title in (title, "pasibot t=0.5"), kind
