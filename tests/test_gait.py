"""The biped's prescribed gait in the world frame, and the ``pasibot gait`` CLI.

Expected world positions come from closed-form leg geometry written here (units of L,
complex x + i z), independent of pasibot_pin.model.assembly: with the hip level, every point is
the hip position plus its leg-frame position.
"""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

import pasibot_pin as pp
from pasibot_pin.__main__ import main
from pasibot_pin.kinematics import gait

DEG = math.pi / 180
SPS = 12  # samples per step (15 deg)


def ankle_leg_frame(theta):
    """Closed-form ankle (joint 13) in the leg frame, units of L: 13 = 3*8 - 2*4 (K = 2)."""
    theta = np.asarray(theta, dtype=float)
    p1 = np.exp(1j * theta)
    p3 = 2.0 + 0j
    d = np.abs(p3 - p1)
    p2 = (p1 + p3) / 2 - 1j * (p3 - p1) / d * np.sqrt(2.5**2 - (d / 2) ** 2)
    p4 = p1 + 2 * (p2 - p1)
    return 3 * (2.0 - 12j) - 2 * p4


@pytest.fixture(scope="module")
def gaits(robots):
    """Three-step gaits: every variant with a flat foot, plus the seed's point and toe feet."""
    cases = [(v, "flat") for v in pp.VARIANTS] + [(v, "point") for v in pp.VARIANTS] + [("rigid", "toe")]
    return {(v, foot): gait.prescribed_gait(robots[(v, 2)], 3, SPS, omega=0.1, foot=foot) for v, foot in cases}


def test_gait_structure(gaits, robots):
    """Shapes, step/stance bookkeeping, time stamps and closure at every sample (< 1e-10)."""
    w = gaits[("spring", "flat")]
    n = 3 * SPS + 1
    assert w.q.shape == (n, robots[("spring", 2)].model.nq)
    assert w.theta == pytest.approx(math.pi / 2 + np.arange(n) * math.pi / SPS)
    assert w.t == pytest.approx((w.theta - w.theta[0]) / 0.1)
    assert list(w.step) == [0] * SPS + [1] * SPS + [2] * (SPS + 1)
    assert w.stance == ["right"] * SPS + ["left"] * SPS + ["right"] * (SPS + 1)
    for one in gaits.values():
        assert one.residual.max() < 1e-10
        assert np.all(np.isfinite(one.q))
    # the viewer's call: positional steps and samples_per_step, default foot
    default = gait.prescribed_gait(robots[("spring", 2)], 1, 4)
    assert default.omega > 0 and default.t is not None  # always time-stamped (the README tour prints .t)
    assert default.t == pytest.approx((default.theta - default.theta[0]) / default.omega)
    assert default.t[0] == 0 and np.all(np.diff(default.t) > 0)


@pytest.mark.parametrize("case", [("rigid", "flat"), ("parallel", "flat"), ("spring", "flat"), ("rigid", "point")])
def test_stance_contact_stays_fixed(gaits, case):
    """During its stance, the stance ankle does not move (1e-9 m); flat feet stay level."""
    w = gaits[case]
    xz = w.frames_xz(["right_foot", "left_foot"])
    pitch = {s: w.pitch(f"{s}_foot") for s in ("right", "left")}
    for k in range(3):
        idx = np.flatnonzero(w.step == k)
        side = w.stance[idx[0]]
        assert all(w.stance[i] == side for i in idx)
        ankle = xz[f"{side}_foot"][idx]
        assert np.max(np.abs(ankle - ankle[0])) < 1e-9
        assert abs(ankle[0, 1]) < 1e-9  # on the ground
        if w.foot == "flat":
            assert np.max(np.abs(pitch[side][idx])) < 1e-9


def test_toe_pinned_gait(gaits, L):
    """The seed's fixed-length foot: the stance toe stays on the ground, the hip level."""
    w = gaits[("rigid", "toe")]
    toes = w.frames_xz(["right_toe", "left_toe"])
    for k in range(3):
        idx = np.flatnonzero(w.step == k)
        toe = toes[f"{w.stance[idx[0]]}_toe"][idx]
        assert np.max(np.abs(toe - toe[0])) < 1e-9 and abs(toe[0, 1]) < 1e-9
    assert np.max(np.abs(w.pitch())) < 1e-9
    assert max(w.exchange_jump) > 1e-3  # the new toe lands above the ground: the pose drops


@pytest.mark.parametrize("case", [("spring", "flat"), ("rigid", "point"), ("parallel", "point"), ("spring", "point")])
def test_level_hip_world_posture(gaits, L, case):
    """Hip level: hip height varies < 0.0195 L, 8 L per step, both ankles at hip + closed form."""
    w = gaits[case]
    hip = w.hip_path()
    assert np.max(np.abs(w.pitch("hip"))) < 1e-9
    assert np.ptp(hip[:, 1]) < 0.0195 * L
    starts = hip[::SPS, 0]
    assert np.diff(starts) == pytest.approx(8 * L, abs=1e-9)
    xz = w.frames_xz(["right_foot", "left_foot"])
    right = L * ankle_leg_frame(w.theta)
    left = L * ankle_leg_frame(w.theta + math.pi)
    for pts, expected in ((xz["right_foot"], right), (xz["left_foot"], left)):
        assert np.max(np.abs(pts[:, 0] - hip[:, 0] - expected.real)) < 1e-9
        assert np.max(np.abs(pts[:, 1] - hip[:, 1] - expected.imag)) < 1e-9
    # the hip sits 28 L above the stance ankle at touch-down (docs/reference.md §4)
    assert hip[0, 1] == pytest.approx(28 * L, abs=1e-9)


def test_parallel_flat_gait_is_nearly_level(gaits, L):
    """With the extension, a flat-welded foot tilts the hip by at most the foot's stance pitch."""
    w = gaits[("parallel", "flat")]
    bound = math.asin(2 * 0.00975 / 2 / 4.2) + 1e-4  # the stabiliser's tilt, joint 4 off its line
    assert np.max(np.abs(w.pitch("hip"))) < bound
    starts = w.hip_path()[::SPS, 0]
    assert np.diff(starts) == pytest.approx(8 * L, abs=1e-9)  # 90 and 270 deg: foot exactly level


def test_rigid_flat_gait_body_pitch(gaits, L):
    """Rigid foot welded flat: the hip pitches (atan2, signed) by minus the sole's leg-frame angle."""
    w = gaits[("rigid", "flat")]
    pitch = w.pitch("hip")
    # sole direction in the leg frame: the shank 6 -> 13 turned by +90 deg; 6 from the closed form
    theta = w.theta[0]
    p1 = np.exp(1j * theta)
    p3 = 2.0 + 0j
    d = np.abs(p3 - p1)
    p4 = p1 + 2 * ((p1 + p3) / 2 - 1j * (p3 - p1) / d * np.sqrt(2.5**2 - (d / 2) ** 2) - p1)
    p8 = 2.0 - 12j
    dd = np.abs(p8 - p4)
    p5 = p4 + 3.0 * (p8 - p4) / dd * np.exp(1j * np.arccos((9 + dd**2 - 36) / (6 * dd)))
    p6 = p4 + 3 * (p5 - p4)
    sole = np.angle(1j * (3 * p8 - 2 * p4 - p6))
    assert pitch[0] == pytest.approx(-sole, abs=1e-9)
    assert pitch.max() > math.radians(25)  # signed, not folded by arccos
    assert max(w.exchange_jump) > 0.1


def test_atan2_keeps_the_sign():
    """body_pitch is signed; the seed's arccos of the trace folds -a onto +a."""
    for angle in (-0.4, 0.3):
        c, s = math.cos(angle), math.sin(angle)
        rot = np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])  # x axis turned CCW in x-z by angle
        assert gait.body_pitch(rot) == pytest.approx(angle)
        assert gait.seed_trace_angle(rot) == pytest.approx(abs(angle))


def test_gait_bad_input(robots):
    with pytest.raises(ValueError, match="two-legged"):
        gait.prescribed_gait(robots[("spring", 1)])
    with pytest.raises(ValueError, match="steps"):
        gait.prescribed_gait(robots[("spring", 2)], 0)
    with pytest.raises(ValueError, match="samples_per_step"):
        gait.prescribed_gait(robots[("spring", 2)], 1, 1)
    with pytest.raises(ValueError, match="foot"):
        gait.prescribed_gait(robots[("spring", 2)], 1, 4, foot="heel")
    with pytest.raises(ValueError, match="omega"):
        gait.prescribed_gait(robots[("spring", 2)], 1, 4, omega=0.0)


# --------------------------------------------------------------------------- CLI
def _read(path):
    with path.open() as handle:
        rows = list(csv.reader(handle))
    return rows[0], rows[1:]


def test_cli_one_leg(tmp_path, monkeypatch, L):
    monkeypatch.chdir(tmp_path)
    assert (
        main(["gait", "--variant", "rigid", "--legs", "1", "--step-deg", "10", "--csv", "leg.csv", "--plot", "leg.png"])
        == 0
    )
    header, rows = _read(tmp_path / "leg.csv")
    expected = [
        "theta_rad",
        "ankle_x_m",
        "ankle_z_m",
        "toe_x_m",
        "toe_z_m",
        "heel_x_m",
        "heel_z_m",
        "foot_pitch_rad",
        "ankle_vx_m_s",
        "ankle_vz_m_s",
        "ankle_ax_m_s2",
        "ankle_az_m_s2",
    ]
    assert header[: len(expected)] == expected
    assert len(rows) == 37
    data = np.array([[float(x) for x in r[: len(expected)]] for r in rows])
    k90 = 9
    assert data[k90, 0] == pytest.approx(math.pi / 2)
    assert data[k90, 1:3] == pytest.approx([6 * L, -28 * L], abs=1e-9)
    assert data[k90, 8] == pytest.approx(-2 * L * 0.1, abs=1e-12)  # default omega 0.1 rad/s
    assert (tmp_path / "leg.png").stat().st_size > 10_000
    # no silent overwrite; --force allows it
    assert main(["gait", "--legs", "1", "--csv", "leg.csv"]) == 2
    assert main(["gait", "--legs", "1", "--step-deg", "30", "--csv", "leg.csv", "--force"]) == 0
    assert len(_read(tmp_path / "leg.csv")[1]) == 13


def test_cli_two_legs(tmp_path, monkeypatch, L):
    monkeypatch.chdir(tmp_path)
    assert (
        main(
            [
                "gait",
                "--variant",
                "spring",
                "--legs",
                "2",
                "--steps",
                "2",
                "--step-deg",
                "15",
                "--omega",
                "0.5",
                "--csv",
                "walk.csv",
                "--plot",
                "walk.png",
            ]
        )
        == 0
    )
    header, rows = _read(tmp_path / "walk.csv")
    for col in (
        "theta_rad",
        "t_s",
        "step",
        "stance",
        "hip_x_m",
        "hip_z_m",
        "hip_pitch_rad",
        "right_ankle_x_m",
        "right_ankle_z_m",
        "left_ankle_x_m",
        "left_ankle_z_m",
        "right_toe_x_m",
        "left_heel_z_m",
    ):
        assert col in header
    assert len(rows) == 2 * 12 + 1
    col = {name: i for i, name in enumerate(header)}
    hip_x = np.array([float(r[col["hip_x_m"]]) for r in rows])
    assert hip_x[-1] - hip_x[0] == pytest.approx(16 * L, abs=1e-9)
    assert float(rows[-1][col["t_s"]]) == pytest.approx(2 * math.pi / 0.5)
    assert {r[col["stance"]] for r in rows} == {"right", "left"}
    assert (tmp_path / "walk.png").stat().st_size > 10_000


def test_cli_bad_input(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["gait", "--legs", "1", "--step-deg", "7"]) == 2
    assert "--step-deg" in capsys.readouterr().err
    assert main(["gait", "--legs", "1", "--steps", "3"]) == 2
    assert main(["gait", "--legs", "2", "--foot", "heel"]) == 2
    assert main(["gait", "--variant", "nope"]) == 2
    assert not list(tmp_path.iterdir())
