"""The `pasibot` command line: info, build-urdf, analyze (model step)."""

from __future__ import annotations

import subprocess
import sys

import pytest

import pasibot_pin as pp
from pasibot_pin.__main__ import main


def test_info_prints_sizes_loops_and_mobility(capsys):
    assert main(["info", "--variant", "parallel", "--legs", "1"]) == 0
    out = capsys.readouterr().out
    assert "nq = 13, nv = 13" in out
    assert "right_j13 [right_l5_shank | right_foot_bar]" in out
    assert "Gruebler DOF = 1" in out and "nv - rank(J_c) = 13 - 12 = 1" in out
    assert "actuated joints: right_j0_crank" in out


def test_info_rejects_unknown_variant(capsys):
    assert main(["info", "--variant", "wheel"]) == 2
    err = capsys.readouterr().err  # as `walk --variant wheel` says it: info builds the same design's robot
    assert "parameter 'variant'" in err and "'wheel'" in err and "spring" in err


def test_python_dash_m_works():
    out = subprocess.run(
        [sys.executable, "-m", "pasibot_pin", "info", "--variant", "spring", "--legs", "2"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    assert "numerical mobility nv - rank(J_c) = 19 - 15 = 4" in out


HEAVY = ("matplotlib", "mujoco", "optuna", "dask", "distributed", "pyarrow", "scipy", "meshcat", "yourdfpy", "trimesh")
"""Optional or slow-to-import libraries: only the commands that use them import them."""


@pytest.mark.slow
def test_the_command_line_starts_without_the_heavy_libraries():
    """Every ``pasibot`` process builds the whole parser: it imports none of HEAVY (each would add
    0.1-1.7 s to every command, ``--help`` and a refused flag included)."""
    code = (
        "import sys\n"
        "import pasibot_pin.cli\n"
        "from pasibot_pin.__main__ import build_parser\n"
        "build_parser()\n"
        f"print(sorted({{name.split('.')[0] for name in sys.modules}} & set({HEAVY!r})))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True).stdout
    assert out.strip() == "[]"
    # the check can fail: the same probe sees them once a command that plots has been imported
    probe = code.replace("build_parser()", "import pasibot_pin.report.floor")
    out = subprocess.run([sys.executable, "-c", probe], check=True, capture_output=True, text=True).stdout
    assert "matplotlib" in out


def test_build_urdf_renders_and_refuses_to_overwrite(tmp_path, capsys):
    target = tmp_path / "leg.urdf"
    assert main(["build-urdf", "--variant", "rigid", "--legs", "1", "--L", "0.1", "--out", str(target)]) == 0
    text = target.read_text()
    assert 'xyz="0.2 0 0"' in text  # joint 3 at K L = 0.2 m
    assert main(["build-urdf", "--variant", "rigid", "--legs", "1", "--out", str(target)]) == 2
    assert "exists" in capsys.readouterr().err
    assert target.read_text() == text, "the user's file must be left alone"
    assert main(["build-urdf", "--variant", "rigid", "--legs", "1", "--out", str(target), "--force"]) == 0
    assert target.read_text() == pp.urdf_path("rigid", 1).read_text()


def test_build_urdf_rejects_bad_ratio(capsys):
    assert main(["build-urdf", "--ratio", "r4=-1"]) == 2
    assert "r4" in capsys.readouterr().err


@pytest.mark.slow  # about 2 s of CPU: the model step loads a dozen robots
@pytest.mark.parametrize("variant", ["spring"])
def test_analyze_model_step_writes_pictures(tmp_path, variant):
    from pasibot_pin.report import model as model_report

    section = model_report.section(tmp_path)
    assert (tmp_path / f"robot_{variant}.png").stat().st_size > 10_000
    assert "Gruebler DOF" in section and (tmp_path / "info.txt").is_file()


def test_version_names_the_package_and_pinocchio(capsys):
    from importlib.metadata import version

    with pytest.raises(SystemExit) as stop:
        main(["--version"])
    assert stop.value.code == 0
    out = capsys.readouterr().out.strip()
    assert out.startswith(f"pasibot {version('pasibot-pin')} ") and "pin 4." in out
    assert pp.__version__ == version("pasibot-pin")  # one version: the package's


def test_robot_repr_is_one_short_line():
    text = repr(pp.load("parallel", 2))
    assert "\n" not in text and len(text) < 160
    assert "variant='parallel'" in text and "nq=29" in text


@pytest.mark.parametrize("command", [["torques"], ["contact"]])
def test_scenario_1_is_run1_in_every_command(command, capsys):
    assert main([*command, "--scenario", "1"]) == 0
    short = capsys.readouterr().out
    assert main([*command, "--scenario", "run1"]) == 0
    assert capsys.readouterr().out == short
    assert main([*command, "--scenario", "9"]) == 2
    assert "unknown scenario '9'" in capsys.readouterr().err


def test_help_is_plain_text():
    from pasibot_pin.__main__ import build_parser

    sub = next(a for a in build_parser()._actions if a.dest == "command")
    for name, parser in sub.choices.items():
        text = parser.format_help()
        assert "``" not in text and ":func:" not in text and ":mod:" not in text and ":class:" not in text, name
