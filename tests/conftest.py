"""Shared fixtures: robots are loaded once per session (loading is cheap but not free)."""

from __future__ import annotations

import os

import pytest

# Headless plots, here and in the commands' subprocesses; set before matplotlib is first imported
# (not imported here: a worker that runs no plotting test never pays for it).
os.environ["MPLBACKEND"] = "Agg"

import pasibot_pin as pp  # noqa: E402

ALL_MODELS = [(variant, legs) for variant in pp.VARIANTS for legs in (1, 2)]


@pytest.fixture(scope="session")
def robots():
    """Dict (variant, legs) -> loaded robot with default parameters."""
    return {key: pp.load(*key) for key in ALL_MODELS}


@pytest.fixture(scope="session")
def L():
    """The default crank length [m]."""
    return pp.Geometry().L


# --------------------------------------------------------------------------- xdist scheduling
# `pytest` runs on pytest-xdist workers (pyproject: addopts = "-n auto --dist loadgroup"). The unit of
# work is one test, so that long tests spread over the workers, except in the modules below: their
# module-scoped fixtures (the browser screenshots, the walks, the meshcat server, a reference sweep)
# are costly, and one module is one ``xdist_group``, built once, on one worker.
WHOLE_MODULES = frozenset(
    {
        "test_browser.py",
        "test_viewer.py",
        "test_animation.py",
        "test_gait.py",
        "test_kinematics.py",
        "test_contact.py",
        "test_design_metrics.py",
        "test_floor_static.py",
        "test_newton_euler.py",
        "test_optimize.py",
        "test_questions.py",
        "test_single_motor.py",
        "test_sweep.py",
        "test_wheel_install.py",  # one venv per run; analyze runs in the background meanwhile
        "test_walking.py",
        "test_gait_stability.py",
        "test_gait_stability3d.py",
    }
)
# The tiers (pyproject's markers): `slow`, `integration`, `browser`, `mujoco`, `network`; `make test-fast`
# leaves them out. Slow tests go first, so that none starts last and keeps one worker busy alone.
FIRST = ("slow", "browser", "integration", "mujoco")


def pytest_collection_modifyitems(config, items) -> None:
    """Group the whole modules on one worker each; put the marked (long) tests first, stably."""
    for item in items:
        module = item.nodeid.split("::", 1)[0].rsplit("/", 1)[-1]
        if module in WHOLE_MODULES:
            item.add_marker(pytest.mark.xdist_group(name=module))
    items.sort(key=lambda item: not any(item.get_closest_marker(m) for m in FIRST))
