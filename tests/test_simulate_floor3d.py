"""``pasibot simulate --ground floor --3d``: the spring cases (or a design) on the 3-D floor.

The written feet's forces hold the whole robot's vertical momentum balance (Newton on its centre of
mass, from Pinocchio), and the seed's spring robot on centred plates tips over sideways like every
planar walker (issue 32).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from pasibot_pin.__main__ import main
from pasibot_pin.model.design import design_robot, load_design
from pasibot_pin.model.spatial import free_flyer_model
from pasibot_pin.studies.floor_cases import FloorStudySettings, floor_study

ROOT = Path(__file__).resolve().parents[1]
SLOW_COMB = ROOT / "designs" / "3d" / "upright_smallest_reach_comb0.2L_omega0.5.toml"


def _columns(path: Path) -> dict[str, np.ndarray]:
    with path.open() as handle:
        rows = list(csv.DictReader(handle))
    return {name: np.array([float(r[name]) for r in rows]) for name in rows[0]}


@pytest.mark.slow
def test_a_design_on_the_3d_floor_balances_its_weight(tmp_path, capsys):
    """The written feet's normal forces against Newton for the whole robot: their impulse less the
    weight's is the change of the centre of mass's vertical momentum (Pinocchio's CoM of the run)."""
    out = tmp_path / "s"
    assert main(["simulate", "--3d", "--design", str(SLOW_COMB), "--duration", "1.5", "--out", str(out)]) == 0
    assert "3-D floor, design" in capsys.readouterr().out
    cols = _columns(out / "floor3d_design.csv")
    assert (out / "floor3d_design.png").stat().st_size > 10_000
    design = load_design(SLOW_COMB)
    settings = FloorStudySettings("run1", 1.5, dt=1e-3, design=design, spatial=True)
    run = floor_study(settings).cases[0].result
    np.testing.assert_allclose(
        cols["hip_y_m"], run.hip[:, 1], rtol=0, atol=1e-9
    )  # the file is the run (BLAS round-off)
    np.testing.assert_allclose(cols["hip_roll_deg"], np.degrees(run.roll), rtol=0, atol=1e-6)
    model = free_flyer_model(design_robot(design, 2, visuals=False).model)
    data = model.createData()
    mass = sum(model.inertias[j].mass for j in range(model.njoints))
    com = np.array([pin.centerOfMass(model, data, q)[2] for q in run.q])
    h, n = float(run.t[1] - run.t[0]), len(run.t) - 1  # the run's own step: it divides the crank period
    assert h <= 1e-3 and 1.5 <= n * h < 1.5 + h
    momentum = mass * ((com[-1] - com[-2]) - (com[1] - com[0])) / h
    impulse = h * (cols["right_Fn_N"][1:] + cols["left_Fn_N"][1:]).sum() - mass * 9.81 * h * n  # steps 1..n
    assert abs(impulse - momentum) < 0.005 * mass * 9.81 * h * n, (impulse, momentum)  # 0.12 % found


@pytest.mark.slow
def test_the_seed_spring_robot_on_centred_plates_tips(tmp_path, capsys):
    out = tmp_path / "s"
    assert main(["simulate", "--3d", "--scenario", "1", "--no-cases", "--duration", "4", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    cols = _columns(out / "floor3d_run1.csv")
    roll = np.abs(cols["hip_roll_deg"])
    if "tipped" in text:  # the verdict and the trace agree: the roll passed the limit where the run stopped
        assert roll.max() > math.degrees(0.1745) * 0.99
    else:  # else it failed otherwise (fell, slipped) but did not walk upright
        assert "walks" not in text.split(":", 1)[1].split(";")[0]


def test_3d_is_refused_with_study_and_with_the_weld(tmp_path, capsys):
    assert main(["simulate", "--3d", "--study", "--out", str(tmp_path / "a")]) == 2
    assert "--3d" in capsys.readouterr().err
    assert main(["simulate", "--ground", "weld", "--3d", "--out", str(tmp_path / "b")]) == 2
    assert "--3d applies to --ground floor only" in capsys.readouterr().err
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()
