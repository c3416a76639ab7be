"""CSV headers name their units: every numeric column written by the commands ends in its SI unit."""

from __future__ import annotations

import csv

import pytest

from pasibot_pin.__main__ import main
from pasibot_pin.units import unit_of, with_unit

UNITS = ("s", "rad", "deg", "m", "N", "Nm", "J", "kg", "m_s", "m_s2", "rad_s", "Nm_rad")
UNITLESS = {"stance", "stance_right", "step", "feasible", "mu_needed", "variant", "right_mode", "left_mode"}


def test_names_get_their_unit_once():
    assert with_unit("theta") == "theta_rad"
    assert with_unit("Ta") == "Ta_Nm"
    assert with_unit("swing_j0_crank_M") == "swing_j0_crank_M_Nm"
    assert with_unit("ground_Fx") == "ground_Fx_N"
    assert with_unit("ankle_vx") == "ankle_vx_m_s"
    assert with_unit("W_crank_pos") == "W_crank_pos_J"
    assert with_unit("hip_pitch_deg") == "hip_pitch_deg"  # already carries one
    assert with_unit(with_unit("hip_x")) == "hip_x_m"
    assert with_unit("stance") == "stance" and unit_of("mu_needed") is None


def _header(path) -> list[str]:
    with open(path, newline="") as handle:
        return next(csv.reader(handle))


def _numeric_columns(path) -> list[str]:
    with open(path, newline="") as handle:
        rows = list(csv.DictReader(handle))
    out = []
    for name in rows[0]:
        try:
            [float(r[name]) for r in rows if r[name] != ""]
        except ValueError:
            continue
        out.append(name)
    return out


@pytest.mark.parametrize(
    "argv",
    [
        ["gait", "--legs", "1", "--step-deg", "30"],
        ["gait", "--steps", "1", "--step-deg", "30"],
        ["torques", "--samples", "5"],
        ["contact", "--samples", "5"],
        ["energy", "--omegas", "1", "--nodes", "8"],
        ["simulate", "--ground", "weld", "--steps", "1", "--no-cases", "--dt", "0.02"],
        ["simulate", "--duration", "0.05", "--no-cases"],
    ],
    ids=lambda a: "-".join(a[:3]),
)
@pytest.mark.slow
def test_every_numeric_csv_column_names_its_unit(argv, tmp_path, capsys):
    assert main([*argv, "--out", str(tmp_path)]) == 0
    (path,) = tmp_path.glob("*.csv")
    header = _header(path)
    assert len(set(header)) == len(header)
    for name in _numeric_columns(path):
        if name in UNITLESS or name.startswith("cot_") or name.endswith("friction_use"):
            continue
        assert any(name.endswith("_" + unit) for unit in UNITS), f"{path.name}: {name} has no unit"
