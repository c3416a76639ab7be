"""One command-line grammar: a flag several commands share has one default, and multi-file commands take --out DIR.

The parsers are read from ``pasibot``'s own argument parser (every subcommand registered), so a
command added later is checked too.
"""

from __future__ import annotations

import argparse
from collections import defaultdict

import pytest

from pasibot_pin.__main__ import build_parser, main
from pasibot_pin.cli.common import DEFAULTS
from pasibot_pin.model.params import SOLE_FLOOR_MU

# Flags shared by name whose meaning differs between commands: the reason is the exception's text.
DIFFERENT_MEANING = {
    "--out": "a FILE for one-file commands (export-html, export-mjcf, build-urdf), a DIR otherwise",
    "--csv": "a FILE for one-table commands; a switch (results.csv in --out) for sweep and optimize",
    "--omega": "gait: the crank rate of a prescribed gait; torques, walk: overrides the scenario's (design's) rate",
    "--samples": "torques: one stance's grid with both ends (61); contact: the stance without its last sample (60)",
    "--steps": "torques: stances of the K_e fit (1); walk: the verdict's steps on the floor (20)",
    "--objective": "optimize: METRIC:min|max, repeatable; find-walker: what makes the best walker (sole)",
}


def _subparsers() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


def _defaults() -> dict[str, dict[str, object]]:
    """flag -> {command: default} for every long option of every subcommand."""
    table: dict[str, dict[str, object]] = defaultdict(dict)
    for command, sub in _subparsers().items():
        for action in sub._actions:
            for flag in action.option_strings:
                if flag.startswith("--") and flag != "--help":
                    table[flag][command] = action.default
    return table


def test_every_shared_flag_has_one_default():
    shared = {flag: by_command for flag, by_command in _defaults().items() if len(by_command) > 1}
    assert {"--legs", "--fps", "--scenario", "--mu", "--variant", "--force"} <= set(shared)
    for flag, by_command in shared.items():
        values = {repr(v) for v in by_command.values()}
        if flag in DIFFERENT_MEANING:
            continue
        assert len(values) == 1, f"{flag} has different defaults: {by_command}"
        if flag in DEFAULTS:
            assert set(by_command.values()) == {DEFAULTS[flag]}, (flag, by_command)


def test_the_exceptions_are_few_and_still_needed():
    table = _defaults()
    for flag in DIFFERENT_MEANING:
        values = {repr(v) for v in table[flag].values()}
        assert len(table[flag]) > 1 and len(values) > 1, f"{flag} is no longer an exception: drop it from the list"
    # --steps differs only in torques, walk and find-walker: every other command walks the same 2 steps
    steps = {c: v for c, v in table["--steps"].items() if c not in ("torques", "walk", "find-walker")}
    assert set(steps.values()) == {DEFAULTS["--steps"]}, steps


def test_the_friction_default_is_the_floor_and_mjcf_default():
    from pasibot_pin.dynamics.floor.settings import FloorSettings
    from pasibot_pin.model.mjcf import MjcfOptions
    from pasibot_pin.studies.contact import CONTACT_MU
    from pasibot_pin.studies.floor_cases import FloorStudySettings

    assert DEFAULTS["--mu"] == SOLE_FLOOR_MU == CONTACT_MU
    assert FloorSettings().mu == MjcfOptions().mu == FloorStudySettings("run1").mu == SOLE_FLOOR_MU


def test_every_command_writing_several_files_takes_out_dir():
    for command, sub in _subparsers().items():
        flags = {flag: action for action in sub._actions for flag in action.option_strings}
        several = {"--csv", "--plot"} <= set(flags) or command in ("analyze", "simulate", "sweep", "optimize")
        if several:
            assert "--out" in flags and flags["--out"].metavar == "DIR", command


@pytest.mark.parametrize(
    ("argv", "names"),
    [
        (["gait", "--legs", "1", "--step-deg", "30"], ["gait_spring_1leg.csv", "gait_spring_1leg.png"]),
        (["torques", "--scenario", "4", "--samples", "5"], ["torques_run4.csv", "torques_run4.png"]),
    ],
)
def test_out_dir_writes_the_csv_and_the_figure_under_default_names(tmp_path, capsys, argv, names):
    out = tmp_path / "new" / "folder"
    assert main([*argv, "--out", str(out)]) == 0
    for name in names:
        assert (out / name).stat().st_size > 100, name
    assert main([*argv, "--out", str(out)]) == 2, "existing files are kept without --force"
    assert "--force" in capsys.readouterr().err


def test_gait_refuses_steps_with_one_leg_even_when_equal_to_the_default(capsys):
    assert main(["gait", "--legs", "1", "--steps", "2"]) == 2
    assert "'--steps' applies to --legs 2" in capsys.readouterr().err


def test_simulate_weld_refuses_mu(tmp_path, capsys):
    assert main(["simulate", "--ground", "weld", "--mu", "0.5", "--out", str(tmp_path)]) == 2
    assert "--mu applies to --ground floor" in capsys.readouterr().err
