"""``--design FILE`` on the commands: the design's numbers reach the output.

The commands run in this process (``main``, the code ``pasibot`` runs after its imports); the
entry point's own process, exit codes and stderr are tested by ``test_cli.py`` and ``test_sweep.py``.
"""

from __future__ import annotations

import re
import subprocess

import numpy as np
import pytest

from pasibot_pin.__main__ import main
from pasibot_pin.errors import DesignError
from pasibot_pin.model.design import Design


@pytest.fixture()
def _cli(capsys, tmp_path, monkeypatch):
    """``pasibot ARGS`` in this process, run in an empty folder: a CompletedProcess (exit code, stdout, stderr)."""
    work = tmp_path / "cwd"
    work.mkdir()
    monkeypatch.chdir(work)

    def run(*args: str) -> subprocess.CompletedProcess:
        capsys.readouterr()
        try:
            code = main(list(args))
        except SystemExit as stop:  # argparse's own refusals
            code = stop.code
        out, err = capsys.readouterr()
        return subprocess.CompletedProcess(["pasibot", *args], code, out, err)

    return run


@pytest.fixture()
def design_file(tmp_path):
    return Design().with_(K=2.2, r4=9.4, body_mass=25.0).save(tmp_path / "d.toml")


@pytest.mark.slow  # renders the design's xacro: about 1.6 s of CPU
def test_info_and_build_urdf_use_the_design(_cli, design_file, tmp_path):
    import yourdfpy

    info = _cli("info", "--design", str(design_file))
    assert info.returncode == 0 and "K=2.2" in info.stdout
    out = tmp_path / "d.urdf"
    res = _cli("build-urdf", "--design", str(design_file), "--out", str(out))
    assert res.returncode == 0, res.stderr
    urdf = yourdfpy.URDF.load(str(out), load_meshes=False, build_scene_graph=False)
    assert urdf.link_map["hip"].inertial.mass == pytest.approx(25.0)
    j6 = urdf.joint_map["right_j6"]  # L4 carries the shank at its end: r4 L along its axis
    assert np.linalg.norm(j6.origin[:3, 3]) == pytest.approx(9.4 * 0.05)
    j3 = urdf.joint_map["right_j3"]  # the rocker pivot at K L
    assert j3.origin[0, 3] == pytest.approx(2.2 * 0.05)


def test_torques_of_a_design_equal_the_scenario_it_copies(_cli, tmp_path):
    """A design with run 1's speed and body gives run 1's K_e: two paths (design record, scenario)."""
    path = Design().with_(omega=0.1, body_mass=16.0).save(tmp_path / "run1.toml")
    by_design = _cli("torques", "--design", str(path))
    by_scenario = _cli("torques", "--scenario", "run1")
    assert by_design.returncode == 0, by_design.stderr

    def k_e(text):
        return float(re.search(r"K_e = ([0-9.]+) N.m/rad", text).group(1))

    assert k_e(by_design.stdout) == k_e(by_scenario.stdout)
    assert "scenario design" in by_design.stdout


@pytest.mark.parametrize("variant", ["rigid", "parallel"])
def test_torques_of_a_design_without_a_free_ankle_fit_no_spring(_cli, tmp_path, variant):
    """Without a free ankle the linkage holds the foot: no spring is fitted (a rigid foot's beta is constant, a
    parallel foot's T_e is zero, so a fit would print K_e = -0 and beta0 = inf); the crank torques are printed."""
    from pasibot_pin.dynamics.inverse import crank_grid, inverse_dynamics
    from pasibot_pin.model.design import design_robot
    from pasibot_pin.studies.torques_study import TorqueSettings, scenario_torques

    design = Design().with_(variant=variant, omega=0.5)
    res = _cli("torques", "--samples", "21", "--design", str(design.save(tmp_path / "d.toml")))
    assert res.returncode == 0, res.stderr
    assert "K_e" not in res.stdout and "inf" not in res.stdout and "nan" not in res.stdout.lower()
    assert f"variant {variant} has no free ankle" in res.stdout
    run = scenario_torques(TorqueSettings(samples=21, design=design))
    assert run.fit is None and np.all(run.result.Te == 0.0)
    with pytest.raises(DesignError, match="free ankle"):
        run.spring  # noqa: B018
    # the printed range is the crank torque over the stance, computed again on a grid of our own
    grid = crank_grid(run.result.theta[0], run.result.theta[-1], 21)
    ta = inverse_dynamics(design_robot(design, 2), grid, 0.5).Ta
    low, high = map(float, re.search(r"T_a from (-?[0-9.]+) to (-?[0-9.]+) N.m", res.stdout).groups())
    assert (low, high) == (round(float(ta.min()), 2), round(float(ta.max()), 2))


def test_simulate_walks_the_design_on_the_floor(_cli, tmp_path):
    path = (
        Design()
        .with_(omega=5.0, body_mass=20.0, spring_stiffness=450.0, spring_rest_angle=1.6)
        .save(tmp_path / "d.toml")
    )
    res = _cli("simulate", "--design", str(path), "--duration", "0.2", "--no-cases", "--out", str(tmp_path / "o"))
    assert res.returncode == 0, res.stderr
    assert (tmp_path / "o" / "floor_design.csv").is_file()
    weld = _cli("simulate", "--design", str(path), "--ground", "weld")
    assert weld.returncode == 2 and "--design applies to --ground floor" in weld.stderr


@pytest.mark.parametrize("command", ["info", "build-urdf", "torques", "simulate", "export-mjcf", "sweep"])
def test_a_bad_design_file_is_one_line(_cli, tmp_path, command):
    bad = tmp_path / "bad.toml"
    bad.write_text("K = 'two'\n")
    extra = ["--out", str(tmp_path / "o")] if command in ("export-mjcf", "sweep") else []
    res = _cli(command, "--design", str(bad), *extra)
    assert res.returncode == 2 and res.stderr.count("\n") == 1 and "'K'" in res.stderr, res.stderr


def test_gait_walks_the_design(_cli, design_file):
    """The stroke printed for the design's leg equals the analytic assembly's x(90 deg) - x(270 deg)."""
    import math

    from pasibot_pin.model.assembly import leg_points
    from pasibot_pin.model.design import load_design

    res = _cli("gait", "--design", str(design_file), "--legs", "1")
    assert res.returncode == 0, res.stderr
    stroke = float(re.search(r"stroke/L\s+([0-9.]+)", res.stdout).group(1))
    design = load_design(design_file)
    ankle = leg_points(np.array([math.pi / 2, 3 * math.pi / 2]), design.geometry(), design.variant)["p13"]
    assert stroke == pytest.approx((ankle[0, 0] - ankle[1, 0]) / design.L, rel=1e-5)


def test_export_html_draws_the_design(_cli, design_file, tmp_path):
    res = _cli("export-html", "--design", str(design_file), "--out", str(tmp_path / "d.html"), "--steps", "1")
    assert res.returncode == 0, res.stderr
    assert (tmp_path / "d.html").stat().st_size > 10_000


def test_contact_of_a_design_equals_the_scenario_it_copies(_cli, tmp_path):
    path = Design().with_(omega=0.1, body_mass=16.0).save(tmp_path / "run1.toml")
    by_design = _cli("contact", "--design", str(path))
    by_scenario = _cli("contact", "--scenario", "run1")
    assert by_design.returncode == 0, by_design.stderr
    assert by_design.stdout.splitlines()[1:] == by_scenario.stdout.splitlines()[1:]


def test_energy_of_a_design_equals_the_variant_table(_cli, tmp_path):
    path = Design().with_(body_mass=16.0).save(tmp_path / "d.toml")
    by_design = _cli("energy", "--design", str(path), "--omegas", "0.1,5")
    by_variant = _cli("energy", "--variants", "spring", "--omegas", "0.1,5")
    assert by_design.returncode == 0, by_design.stderr
    assert by_design.stdout == by_variant.stdout
