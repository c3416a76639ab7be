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
# `pytest` runs on pytest-xdist workers (pyproject: addopts = "-n auto --dist loadscope").
# The unit of work is one test, so that long tests spread over the workers, except in the modules
# below: their module-scoped fixtures (the browser screenshots, the walks, the meshcat server, a
# reference sweep) are costly, and one module is one unit, built once, on one worker.
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
    }
)
# Longest units first (a longest-processing-time-first schedule: no long test starts last and
# keeps one worker busy alone), from the durations of a run on two workers (`--durations`).
# A nodeid prefix each; the other units follow in collection order.
LONGEST_FIRST = (
    "tests/test_wheel_install.py",  # ~60 s: a wheel in a clean venv, every command, analyze behind them
    "tests/test_browser.py",  # ~13 s of Chromium, two browsers at once
    "tests/test_gait_stability.py",  # the shot gait: a warm-up walk and seven step-map runs
    "tests/test_walking.py",  # the walker with one motor and with two, every variant on the floor
    "tests/test_mujoco_walk.py",  # the twin: three steps in each engine
    "tests/test_designs_twin.py",  # every committed design in both engines
    "tests/test_floor_static.py",  # its module fixtures: the quasi-static study of runs 1-4
    "tests/test_energy.py::test_analyze_step_contact_energy",
    "tests/test_floor.py::test_analyze_floor_section",
    "tests/test_floor.py::test_readme_and_docs_floor_numbers",
    "tests/test_report.py::test_model_and_simulation",
    "tests/test_cli_signals.py::test_sweep_stops",
    "tests/test_mjcf.py::test_mujoco_on_the_floor_run1",
    "tests/test_report.py::test_kinematics_section",
    "tests/test_notebooks.py::test_notebook_runs[08_floor",
    "tests/test_notebooks.py::test_notebook_runs[05_simulation",
    "tests/test_notebooks.py::test_notebook_runs[07_design",
    "tests/test_floor.py::test_simulate_command_on_the_floor",
    "tests/test_simulate.py::test_energy_is_conserved_without_motor_damping_or_impact[cranks-free",
    "tests/test_sweep.py",
    "tests/test_mjcf.py::test_loops_stay_closed",
    "tests/test_floor.py::test_simulate_study_command",
    "tests/test_notebooks.py::test_notebook_runs[04_viewer",
    "tests/test_readme_numbers.py::test_spring_study_bullets",
    "tests/test_docs_figures.py::test_docs_picture_is_the_library_drawing[simulation",
    "tests/test_notebooks.py::test_notebook_runs[02_kinematics",
    "tests/test_viewer.py",
    "tests/test_report.py::test_torques_section",
    "tests/test_questions.py",
    "tests/test_cli_signals.py",
    "tests/test_notebooks.py",
    "tests/test_readme_snippets.py::test_snippet_runs[2]",
    "tests/test_design_metrics.py",
    "tests/test_kinematics.py",
    "tests/test_gait.py",
    "tests/test_cli_design.py",
    "tests/test_floor.py",
    "tests/test_mjcf.py",
    "tests/test_simulate.py",
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
            return module if module.rsplit("/", 1)[-1] in WHOLE_MODULES else nodeid

        def _assign_work_unit(self, node) -> None:
            if not getattr(self, "_ranked", False):  # the queue is complete at the first assignment
                order = sorted(self.workqueue, key=_rank)  # stable: the rest keeps its order
                self.workqueue = OrderedDict((scope, self.workqueue[scope]) for scope in order)
                self._ranked = True
            super()._assign_work_unit(node)

    return ModuleOrTestScheduling(config, log)
