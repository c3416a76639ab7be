"""Shared fixtures: robots are loaded once per session (loading is cheap but not free)."""

from __future__ import annotations

import os

import matplotlib
import pytest

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")

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
# `pytest` runs on pytest-xdist workers (pyproject: addopts = "-n auto --dist loadscope").
# The unit of work is one module, so module-scoped fixtures (the browser screenshots, the walks,
# the meshcat server) are built once, on one worker. The modules below have no costly module
# fixture and hold long tests of their own: their tests are scheduled one by one.
SPLIT_MODULES = frozenset(
    {"test_notebooks.py", "test_simulate.py", "test_energy.py", "test_regression.py", "test_report.py"}
)
# Longest units first (a longest-processing-time-first schedule: no long test starts last and
# keeps one worker busy alone). A nodeid prefix each; the other units follow in collection order.
LONGEST_FIRST = (
    "tests/test_browser.py",
    "tests/test_energy.py::test_analyze_step_contact_energy",
    "tests/test_cli_signals.py",
    "tests/test_floor.py",
    "tests/test_mjcf.py",
    "tests/test_sweep.py",
    "tests/test_design_metrics.py",
    "tests/test_cli_design.py",
    "tests/test_questions.py",
    "tests/test_optimize.py",
    "tests/test_cli_errors.py",
    "tests/test_notebooks.py::test_notebook_runs[05_simulation",
    "tests/test_simulate.py::test_energy_is_conserved_without_motor_damping_or_impact[cranks-free",
    "tests/test_viewer.py",
    "tests/test_report.py::test_model_and_simulation",
    "tests/test_report.py::test_kinematics_section",
    "tests/test_notebooks.py::test_notebook_runs[04_viewer",
    "tests/test_simulate.py::test_simulate_command",
    "tests/test_notebooks.py",
    "tests/test_kinematics.py",
    "tests/test_simulate.py::test_without_spring",
    "tests/test_simulate.py::test_forward_of_inverse",
)


def _rank(scope: str) -> int:
    return next((k for k, prefix in enumerate(LONGEST_FIRST) if scope.startswith(prefix)), len(LONGEST_FIRST))


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """``--dist loadscope`` with the units and the order above (other ``--dist`` modes: xdist's own)."""
    if config.getvalue("dist") != "loadscope":
        return None
    from collections import OrderedDict

    from xdist.scheduler import LoadScopeScheduling

    class ModuleOrTestScheduling(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            module = nodeid.split("::", 1)[0]
            return nodeid if module.rsplit("/", 1)[-1] in SPLIT_MODULES else module

        def _assign_work_unit(self, node) -> None:
            if not getattr(self, "_ranked", False):  # the queue is complete at the first assignment
                order = sorted(self.workqueue, key=_rank)  # stable: the rest keeps its order
                self.workqueue = OrderedDict((scope, self.workqueue[scope]) for scope in order)
                self._ranked = True
            super()._assign_work_unit(node)

    return ModuleOrTestScheduling(config, log)
