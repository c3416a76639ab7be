"""The design record: defaults are the seed's design, files round-trip, bad values are named."""

from __future__ import annotations

import math

import pytest

import pasibot_pin as pp
from pasibot_pin.model.design import CHOICES, SPECS, Design, load_design
from pasibot_pin.model.params import Geometry


def test_defaults_are_the_seed_design():
    design = Design()
    assert design.geometry() == Geometry()
    masses = design.masses()
    # seed Tab 7.1.2 (the percentage rule on 65 kg, rounded to 0.1 kg), written here from the seed
    for link, kg in {"l1": 0.3, "l2": 1.4, "l3": 0.7, "l4": 2.5, "l5": 2.4, "l6": 1.7, "l7": 0.8}.items():
        assert round(masses.links[link], 1) == kg, link
    assert masses.foot == pytest.approx(0.02 * 65.0)
    assert masses.hip == 16.0 and masses.hip_com == (0.0, 0.0)  # the seed's body: 16 kg at joint 8
    assert design.spring_stiffness is None and design.omega == 0.1


def test_every_spec_default_lies_inside_its_bounds_and_is_the_records_default():
    design = Design().values()
    shares = Design().fractions()
    for name, spec in SPECS.items():
        assert spec.low < spec.high, name
        if math.isnan(spec.default):
            assert design[name] is None, name  # unset: fitted by the study
        elif name.endswith("_fraction"):
            assert design[name] is None and shares[name.removesuffix("_fraction")] == spec.default, name
        else:
            assert spec.low <= spec.default <= spec.high, name
            assert design[name] == pytest.approx(spec.default), name
    for name, valid in CHOICES.items():
        assert design[name] in valid


@pytest.mark.parametrize("suffix", [".toml", ".json"])
def test_file_round_trip(tmp_path, suffix):
    design = Design(variant="parallel", motors="one", K=2.2, ratios={"r4": 9.5}, body_mass=30.0, spring_stiffness=400.0)
    path = design.save(tmp_path / f"d{suffix}")
    assert load_design(path) == design
    with pytest.raises(FileExistsError, match="--force"):
        design.save(path)
    design.with_(K=2.3).save(path, force=True)
    assert load_design(path).K == 2.3
    assert [p.name for p in tmp_path.iterdir()] == [f"d{suffix}"]  # no temporary file left


def test_with_changes_flat_names_and_the_model_uses_them():
    design = Design().with_(K=2.2, r4=9.5, body_mass=30.0, body_com_dx=0.3, variant="rigid")
    assert design.ratios["r4"] == 9.5 and design.geometry().length(4) == pytest.approx(9.5 * 0.05)
    robot = pp.load(design.variant, 2, geometry=design.geometry(), masses=design.masses())
    base = pp.load(design.variant, 2, geometry=design.geometry(), masses=design.with_(body_com_dx=0.0).masses())
    hip = robot.model.inertias[robot.model.getJointId("hip_planar")]
    lever0 = base.model.inertias[base.model.getJointId("hip_planar")].lever
    assert hip.mass == pytest.approx(30.0) and hip.lever[0] - lever0[0] == pytest.approx(0.3)


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"Kx": 2.0}, "unknown design parameter 'Kx'"),
        ({"K": float("nan")}, "'K' = nan"),
        ({"K": 50.0}, r"'K' = 50.0 \[-\] is outside \[1, 4\]"),
        ({"L": -0.05}, "'L'"),
        ({"r4": 0.0}, "'r4'"),
        ({"variant": "wheel"}, "'variant' must be one of rigid, parallel, spring"),
        ({"body_mass": "heavy"}, "'body_mass' must be a number"),
        ({"omega": True}, "'omega' must be a number"),
    ],
)
def test_bad_values_are_named(changes, message):
    with pytest.raises(ValueError, match=message):
        Design().with_(**changes)


def test_bad_files_are_named(tmp_path):
    with pytest.raises(ValueError, match="no design file"):
        load_design(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("K = = 2\n")
    with pytest.raises(ValueError, match="not valid TOML"):
        load_design(bad)
    unknown = tmp_path / "unknown.json"
    unknown.write_text('{"legs_count": 3}')
    with pytest.raises(ValueError, match="unknown design parameter 'legs_count'"):
        load_design(unknown)
    with pytest.raises(ValueError, match=r"\.toml or \.json"):
        Design().save(tmp_path / "d.yaml")


@pytest.mark.parametrize("suffix", [".toml", ".json"])
def test_saved_file_has_the_mode_open_gives(tmp_path, suffix):
    """A design file is readable by others as any file the user writes (0644 under umask 022), not mkstemp's 0600."""
    import os
    import stat

    old = os.umask(0o022)
    try:
        path = Design().save(tmp_path / f"d{suffix}")
        plain = tmp_path / "plain.txt"
        plain.write_text("x")
    finally:
        os.umask(old)
    assert stat.S_IMODE(path.stat().st_mode) == stat.S_IMODE(plain.stat().st_mode) == 0o644
    assert not list(tmp_path.glob(".*.tmp"))
