"""Bad input raises ValueError naming the parameter (and the loop, for assembly failures)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pasibot_pin as pp
from pasibot_pin.model.closure import assemble, solve_configuration


def test_unknown_variant_lists_the_valid_ones():
    with pytest.raises(ValueError, match="rigid, parallel, spring"):
        pp.load("hoeken")


@pytest.mark.parametrize("legs", [0, 3, 1.5])
def test_bad_leg_count(legs):
    with pytest.raises(ValueError, match="legs"):
        pp.load("rigid", legs)


@pytest.mark.parametrize(
    "name, value", [("L", -0.05), ("L", 0.0), ("K", float("nan")), ("r4", -9.0), ("r2", float("inf"))]
)
def test_non_positive_or_non_finite_length(name, value):
    with pytest.raises(ValueError, match=name):
        pp.load("rigid", 1, **{name: value})


def test_unknown_geometry_parameter():
    with pytest.raises(ValueError, match="r99"):
        pp.load("rigid", 1, r99=1.0)


@pytest.mark.parametrize("mass", [-1.0, 0.0, float("nan")])
def test_bad_mass(mass):
    with pytest.raises(ValueError, match="hip mass"):
        pp.load("spring", 2, masses=pp.percentage_mass_model().with_(hip=mass))


def test_bad_link_mass():
    masses = pp.percentage_mass_model()
    links = dict(masses.links)
    links["l4"] = -2.0
    with pytest.raises(ValueError, match="l4"):
        masses.with_(links=links)


def test_unknown_mass_rule_and_inertia():
    with pytest.raises(ValueError, match="mass_rule"):
        pp.load(mass_rule="elephant")
    with pytest.raises(ValueError, match="inertia"):
        pp.load(inertia="heavy")


def test_k_too_large_names_the_loop_and_the_crank_angle():
    # K = 7: |3 - 1| >= 6 > 2.5 + 2.5, the Hoeken loop (joint 2) cannot close at any angle
    with pytest.raises(ValueError, match=r"loop j2 cannot assemble at crank angle 180\.000 deg"):
        pp.load("rigid", 1, K=7.0)


def test_loop_that_fails_only_at_some_crank_angles():
    # K = 4.2: joint 2 closes at theta = 0 (|1-3| = 3.2 < 5) but not at 180 deg (5.2 > 5)
    from pasibot_pin.model.assembly import leg_points

    geometry = pp.Geometry(K=4.2)
    assert np.isfinite(leg_points(0.0, geometry)["p13"]).all()
    with pytest.raises(ValueError, match="loop j2 .*180"):
        leg_points(math.pi, geometry)
    with pytest.raises(ValueError, match="loop j2 .*180"):
        pp.load("rigid", 1, K=4.2)  # q0 is at 180 deg
    ok = pp.load("rigid", 1)
    with pytest.raises(ValueError, match="theta"):
        assemble(ok, float("nan"))


def test_newton_failure_names_a_constraint_row():
    robot = pp.load("rigid", 1)
    prescribed = [robot_crank(robot)]
    # ask the crank pin to be where the coupler cannot follow: a huge K is not needed, just a
    # configuration solve with an impossible extra prescription (rocker angle fixed far away)
    from pasibot_pin.model.closure import joint_coordinate

    prescribed.append(joint_coordinate(robot, "right_j3"))
    with pytest.raises(ValueError, match="loop closure failed: constraint right_j"):
        solve_configuration(robot, robot.q0, prescribed, [math.pi, -1.0], max_iter=20)


def robot_crank(robot):
    from pasibot_pin.model.closure import joint_coordinate

    return joint_coordinate(robot, "right_j0_crank")


def test_bad_q_guess():
    robot = pp.load("rigid", 1)
    with pytest.raises(ValueError, match="q_guess"):
        solve_configuration(robot, np.full(robot.model.nq, np.nan))


def test_a_linkage_that_cannot_turn_is_a_design_error_and_still_a_value_error():
    """K = 7 cannot close the Hoeken loop (|3 - 1| = 6 > 2.5 + 2.5): a DesignError, which code written against
    ValueError still catches."""
    from pasibot_pin.errors import DesignError, PasibotError

    with pytest.raises(DesignError) as caught:
        pp.load("rigid", 1, K=7.0)
    assert isinstance(caught.value, PasibotError) and isinstance(caught.value, ValueError)


def test_bad_input_is_a_parameter_error():
    from pasibot_pin.errors import ParameterError

    with pytest.raises(ParameterError, match="variant"):
        pp.load("hoeken")
    with pytest.raises(ParameterError, match="legs"):
        pp.load("rigid", 3)


def test_at_most_60_bare_value_errors_in_the_package(package_trees):
    """Errors that cross the public API are typed (issue 35): a bare ``raise ValueError`` is the exception."""
    import ast

    bare = []
    for rel, tree in package_trees.items():
        for node in ast.walk(tree):
            if isinstance(node, ast.Raise) and node.exc is not None:
                exc = node.exc.func if isinstance(node.exc, ast.Call) else node.exc
                if isinstance(exc, ast.Name) and exc.id == "ValueError":
                    bare.append(f"{rel}:{node.lineno}")
    assert len(bare) <= 60, bare


def test_walk_design_raises_the_design_error_it_documents():
    """A record-valid K past the full-turn range (1.491 < K < 3 for the seed's links) cannot be built: walk_design
    raises DesignError before any simulation, as its docstring says."""
    from pasibot_pin.errors import DesignError
    from pasibot_pin.model.design import Design
    from pasibot_pin.studies.walking import walk_design

    design = Design(K=3.5, omega=1.0)  # inside the record's range for K, [1, 4]
    with pytest.raises(DesignError, match="cannot assemble"):
        walk_design(design)
