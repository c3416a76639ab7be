"""One range per parameter (issue 35, point 5): the design record's specs are the only source of a parameter's range.

Every flag that sets a design parameter and every library check of the crank speed omega accept exactly the
values the design record accepts, probed on both sides of each end: the command line's bound
(``cli/bounds.BOUNDS``), the record itself (``Design``, what ``Design.with_`` builds), the inverse dynamics'
``check_omega``, the gait settings and a walk's floor settings (the record's range from ``MIN_WALK_OMEGA``).
Each is asked on its own, by its own entry point: a range copied by hand into one of them fails here.
"""

from __future__ import annotations

import math

import pytest

from pasibot_pin.cli.bounds import BOUNDS
from pasibot_pin.dynamics.inverse import check_omega
from pasibot_pin.errors import ParameterError
from pasibot_pin.model.design import MIN_WALK_OMEGA, SPECS, Design, design_robot
from pasibot_pin.studies.kinematics_study import GaitSettings
from pasibot_pin.studies.walking import WalkSettings, floor_settings

FLAGS: dict[tuple[str, str], tuple[str, float]] = {
    ("build-urdf", "--L"): ("L", 1.0),
    ("build-urdf", "--K"): ("K", 1.0),
    ("simulate", "--stiffness"): ("spring_stiffness", 1.0),
    ("simulate", "--rest-angle"): ("spring_rest_angle", 180.0 / math.pi),
    ("simulate", "--damping"): ("spring_damping", 1.0),
    ("energy", "--body-mass"): ("body_mass", 1.0),
    ("energy", "--com-dx"): ("body_com_dx", 1.0),
    ("torques", "--omega"): ("omega", 1.0),
    ("view", "--reactions"): ("omega", 1.0),
    ("export-html", "--reactions"): ("omega", 1.0),
    ("gait", "--omega"): ("omega", 1.0),
    ("energy", "--omegas"): ("omega", 1.0),
    ("walk", "--omega"): ("omega", 1.0),
    ("find-walker", "--omega"): ("omega", 1.0),
}
"""(command, flag) -> (the design parameter it sets, the flag's unit over the record's)."""

TURNING = {("gait", "--omega"), ("energy", "--omegas")}
"""Flags whose cranks must turn: the record's range without its 0."""

WALKING = {("walk", "--omega"), ("find-walker", "--omega")}
"""Flags of a walk: the record's range from MIN_WALK_OMEGA."""


def probes(low: float, high: float) -> list[float]:
    """Values on both sides of each end, inside, and the non-finite ones."""
    eps = 1e-9 * max(1.0, abs(high))
    return [low - eps, low, low + eps, 0.5 * (low + high), high - eps, high, high + eps, math.nan, math.inf, -math.inf]


def accepts(call, value) -> bool:
    try:
        call(value)
    except ParameterError:
        return False
    return True


def in_record(name: str, value: float) -> bool:
    """Whether the design record takes ``value`` for ``name`` (``Design.with_`` builds the record again)."""
    return accepts(lambda x: Design().with_(**{name: x}), value)


@pytest.mark.parametrize("key", list(FLAGS), ids=[" ".join(k) for k in FLAGS])
def test_a_design_parameter_s_flag_takes_exactly_the_record_s_range(key):
    name, scale = FLAGS[key]
    spec, bound = SPECS[name], BOUNDS[key[0]][key[1]]
    low = max(spec.low, MIN_WALK_OMEGA) if key in WALKING else spec.low
    for value in probes(low, spec.high) + probes(spec.low, spec.high):
        expected = in_record(name, value)
        if key in TURNING:
            expected = expected and value > 0
        if key in WALKING:
            expected = expected and value >= MIN_WALK_OMEGA
        assert bound.holds(value * scale) == expected, (key, value)


def test_the_libraries_checks_of_omega_take_the_record_s_range():
    spec = SPECS["omega"]
    for value in probes(spec.low, spec.high):
        record = in_record("omega", value)
        assert accepts(check_omega, value) == record, value  # the inverse dynamics (0: quasi-static)
        assert accepts(lambda x: GaitSettings(omega=x), value) == (record and value > 0), value


def test_a_walk_takes_the_record_s_omega_from_its_walking_minimum():
    robot = design_robot(Design(variant="parallel"), 2, visuals=False)
    spec = SPECS["omega"]
    for value in probes(MIN_WALK_OMEGA, spec.high):
        expected = in_record("omega", value) and value >= MIN_WALK_OMEGA
        walkable = accepts(lambda x: floor_settings(Design(variant="parallel", omega=x), WalkSettings(), robot), value)
        assert walkable == expected, value
    assert 0.0 < MIN_WALK_OMEGA < spec.high and spec.low <= MIN_WALK_OMEGA
