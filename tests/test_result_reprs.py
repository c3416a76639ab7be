"""Result records print as one short line: shapes and key figures, no array dumps or object addresses."""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

import pasibot_pin as pp
from pasibot_pin.kinematics import gait
from pasibot_pin.reprs import short

LONGEST = 600
"""Characters a result's repr may take (a dataclass repr of a walk takes hundreds of thousands)."""


def _check(result) -> str:
    text = repr(result)
    assert text.startswith(type(result).__name__ + "(")
    assert "\n" not in text and len(text) <= LONGEST, text[:300]
    assert not re.search(r"0x[0-9a-f]{6,}", text)  # no object addresses
    assert "array([" not in text  # no array dumps
    for f in dataclasses.fields(result):
        if f.repr:
            assert f"{f.name}=" in text  # every field named
    return text


@pytest.fixture(scope="module")
def robot():
    return pp.load("spring", 2)


def test_walk_repr_shows_shapes_and_figures(robot):
    walk = gait.prescribed_gait(robot, steps=1, samples_per_step=6)
    text = _check(walk)
    assert f"q=array({walk.q.shape[0]}x{walk.q.shape[1]}," in text
    assert "robot=<robot spring, 2 leg(s)>" in text
    assert f"omega={walk.omega:.4g}" in text
    t = walk.t
    assert f"t=array({len(t)}, {t.min():.4g}..{t.max():.4g})" in text


def test_leg_run_and_walk_run_repr(robots):
    from pasibot_pin.studies.kinematics_study import biped_run, leg_run

    run = leg_run(robots[("parallel", 1)], step_deg=30.0)
    _check(run)
    _check(run.cycle)
    _check(biped_run(robots[("spring", 2)], steps=1, step_deg=30.0))


def test_spring_fit_repr():
    from pasibot_pin.studies.methods.spring_fit import fit_spring

    beta = np.linspace(0.5, 1.5, 200)
    fit = fit_spring(beta, 300.0 * (beta - 1.2))
    text = _check(fit)
    assert len(text) < 300


def test_short_text_of_each_kind():
    assert short(np.zeros((300, 17))) == "array(300x17, 0..0)"
    assert short(np.array([1.0, 2.5])) == "[1, 2.5]"
    assert short(np.array([np.nan] * 10)) == "array(10, float64)"
    assert short(3.14159265) == "3.142"
    assert short("x" * 100).endswith("...'") and len(short("x" * 100)) < 50
    assert short(list(range(100))) == "list[100 int]"
    assert short({f"k{i}": np.zeros(3) for i in range(10)}).startswith("dict[10: k0, k1, k2, k3, ...")
    assert short(object()) == "<object>"
