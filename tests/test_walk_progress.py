"""``walk``'s progress bar: one tick per simulated second on a terminal, and nothing else changes.

The bar is a judge that passes every sample on (:class:`~pasibot_pin.studies.walking.ProgressJudge`):
the walk with it is the walk without it, bit for bit, planar and 3-D. ``pasibot walk`` shows it only
on a terminal's stderr and never with ``--json``.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from pasibot_pin.__main__ import main
from pasibot_pin.model.design import design_robot, load_design
from pasibot_pin.studies.walking import WalkSettings, walk_design, walk_design_3d

FAST = "designs/map_top_speed_parallel_sole6L_omega3.toml"


@pytest.mark.slow  # two planar walks of 3 steps at 3 rad/s and two short 3-D ones: about 5 s of CPU
@pytest.mark.parametrize("walker", [walk_design, walk_design_3d], ids=["planar", "3d"])
def test_the_bar_changes_nothing_and_counts_the_simulated_seconds(walker, capsys):
    design = load_design(FAST)
    robot = design_robot(design, 2, visuals=False)
    plain = walker(design, WalkSettings(steps=3), robot)
    capsys.readouterr()
    shown = walker(design, WalkSettings(steps=3), robot, progress=True)
    err = capsys.readouterr().err
    np.testing.assert_array_equal(shown.result.q, plain.result.q)
    np.testing.assert_array_equal(shown.result.t, plain.result.t)
    assert shown.verdict == plain.verdict
    seconds = int(plain.result.t[-1])
    counts = [int(n) for n in re.findall(r"(\d+)/\d+ (?:\[|simulated seconds)", err)]  # tqdm's or the plain bar's
    assert counts and counts[-1] == seconds


def test_the_command_asks_for_the_bar_on_a_terminal_only(monkeypatch):
    """On a terminal's stderr without --json the walk shows its bar; under a pipe, or for --json, it does not."""
    from pasibot_pin.__main__ import build_parser
    from pasibot_pin.cli.walk import _progress

    parser = build_parser()
    plain, scripted = parser.parse_args(["walk"]), parser.parse_args(["walk", "--json"])
    monkeypatch.setattr("sys.stderr.isatty", lambda: False)
    assert not _progress(plain) and not _progress(scripted)
    monkeypatch.setattr("sys.stderr.isatty", lambda: True)
    assert _progress(plain) and not _progress(scripted)


@pytest.mark.slow  # a planar walk of 3 steps at 3 rad/s: about 1.5 s of CPU
def test_the_command_under_a_pipe_writes_nothing_on_stderr(capsys):
    assert main(["walk", "--design", FAST, "--steps", "3"]) == 0
    out, err = capsys.readouterr()
    assert out.startswith("outcome: walks") and err == ""
