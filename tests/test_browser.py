"""The exported HTML in a real browser: headless Chromium (Debian), WebGL through SwiftShader.

The page is loaded from the filesystem, with the network-quieting flags, and screenshotted:

- at two animation times (``#t=`` pauses the walk there): the robot is drawn (its pixels
  differ from an export without the robot) and it has walked forward between the two;
- twice with no ``#t=``, after different virtual-time budgets: the page plays by itself.

Chromium must be installed (``make browser-deps``, run by ``make test``). A missing browser is
a failure, never a skip. Screenshots are kept in tests/artifacts/browser/.
"""

from __future__ import annotations

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

# meshcat imports pyzmq's deprecated eventloop module; not ours to fix.
pytestmark = pytest.mark.filterwarnings("ignore:zmq.eventloop.ioloop is deprecated:DeprecationWarning")

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
    f"--window-size={WIDTH},{HEIGHT}",
]
T_EARLY, T_MID, T_LATE = 0.2, 0.9, 1.6  # [s], within one play of the 2 s walk
HUD_ROWS = 60
"""Rows at the top of the page that hold the title bar (scenario, time, crank angle, foot modes)."""
CHANGED = 40  # a pixel "differs" when a channel moves by more than this (of 255)
SEEK_BUDGET_MS = 1000
"""Virtual time [ms] given to a page paused by ``#t=`` before its screenshot."""


def chromium() -> str:
    path = shutil.which("chromium") or ("/usr/bin/chromium" if os.path.exists("/usr/bin/chromium") else None)
    if path is None:
        pytest.fail("chromium is not installed: run `make browser-deps` (Debian package 'chromium')")
    return path


def screenshot(html: Path, png: Path, fragment: str = "", budget_ms: int = 3000) -> np.ndarray:
    """Load ``html`` from the filesystem in headless Chromium and save a screenshot; returns RGB."""
    with tempfile.TemporaryDirectory(prefix="chromium-profile-") as profile:
        cmd = [
            chromium(),
            *FLAGS,
            f"--user-data-dir={profile}",
            f"--virtual-time-budget={budget_ms}",
            f"--screenshot={png}",
            html.resolve().as_uri() + fragment,
        ]
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=90)
    assert proc.returncode == 0 and png.exists(), f"chromium failed ({proc.returncode}):\n{proc.stderr[-2000:]}"
    # the rows below the title bar (its text changes with the time shown)
    return np.asarray(Image.open(png).convert("RGB")).astype(int)[HUD_ROWS:]


def changed(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs(a - b).max(axis=2) > CHANGED


@pytest.fixture(scope="module")
def shots(tmp_path_factory):
    import pasibot_pin as pp

    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    robot = pp.load("spring", legs=2)
    folder = tmp_path_factory.mktemp("browser")
    with_robot = viewer.export_html(folder / "walk.html", robot, steps=2, samples_per_step=30, fps=30.0)
    without = viewer.export_html(folder / "empty.html", robot, steps=2, samples_per_step=30, fps=30.0, show_robot=False)
    shutil.copy(with_robot.path, ARTIFACTS / "walk.html")
    # The playing pages take longest (every frame is drawn): they start first, so that the two
    # threads finish together rather than one running the last long job alone.
    # A paused page (#t=) is drawn once it has loaded: virtual time waits for the loading, so
    # SEEK_BUDGET_MS is enough (measured: its screenshots equal those after 3000 ms, pixel for pixel).
    jobs = {
        "autoplay_b": (with_robot.path, "", 1500),
        "autoplay_a": (with_robot.path, "", 600),
        "robot_early": (with_robot.path, f"#t={T_EARLY}", SEEK_BUDGET_MS),
        "robot_mid": (with_robot.path, f"#t={T_MID}", SEEK_BUDGET_MS),
        "robot_late": (with_robot.path, f"#t={T_LATE}", SEEK_BUDGET_MS),
        "empty_early": (without.path, f"#t={T_EARLY}", SEEK_BUDGET_MS),
        "empty_late": (without.path, f"#t={T_LATE}", SEEK_BUDGET_MS),
    }
    with ThreadPoolExecutor(max_workers=2) as pool:
        futures = {
            name: pool.submit(screenshot, html, folder / f"{name}.png", fragment, budget)
            for name, (html, fragment, budget) in jobs.items()
        }
        images = {name: f.result() for name, f in futures.items()}
    for name in jobs:  # kept for a look; written from this run's own folder, never read back
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
    """No #t=: after more virtual time the robot is elsewhere (the animation runs)."""
    images, _ = shots
    assert changed(images["autoplay_a"], images["autoplay_b"]).sum() > 500
    for name in ("autoplay_a", "autoplay_b"):
        assert changed(images[name], images["empty_early"]).sum() > 1500, f"{name}: no robot"
