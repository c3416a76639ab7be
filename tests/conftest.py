"""Shared fixtures: robots are loaded once per session (loading is cheap but not free)."""

from __future__ import annotations

import os
import sys

import pytest

# Byte code is written (to the ignored __pycache__ folders) even where the environment says not to: without
# it every xdist worker rewrites the test modules' asserts again, and every worker and every command a test
# starts compiles the package from source again (about 5 s of CPU per worker).
sys.dont_write_bytecode = False
os.environ.pop("PYTHONDONTWRITEBYTECODE", None)

# Headless plots, here and in the commands' subprocesses; set before matplotlib is first imported
# (not imported here: a worker that runs no plotting test never pays for it).
os.environ["MPLBACKEND"] = "Agg"

from plain_install import GROUP as PLAIN_INSTALL  # noqa: E402
from plain_install import analyze, analyzed, installed  # noqa: E402, F401  (session fixtures: the plain install)

import pasibot_pin as pp  # noqa: E402

ALL_MODELS = [(variant, legs) for variant in pp.VARIANTS for legs in (1, 2)]


@pytest.fixture(scope="session")
def robots():
    """Dict (variant, legs) -> loaded robot with default parameters."""
    return {key: pp.load(*key) for key in ALL_MODELS}


@pytest.fixture(scope="session")
def package_trees():
    """Dict path (relative to the package, posix) -> parsed module, of every module of pasibot_pin: parsed once
    per worker for the tests that scan the source (about 0.6 s a parse of the whole package)."""
    import ast  # deferred: only the source-scanning tests need it
    from pathlib import Path

    package = Path(pp.__file__).parent
    return {
        path.relative_to(package).as_posix(): ast.parse(path.read_text(encoding="utf-8"))
        for path in sorted(package.rglob("*.py"))
    }


@pytest.fixture(scope="session")
def L():
    """The default crank length [m]."""
    return pp.Geometry().L


# --------------------------------------------------------------------------- xdist scheduling
# `pytest` runs on pytest-xdist workers (pyproject: addopts = "-n auto --dist loadgroup"). The unit of
# work is one test, so that long tests spread over the workers, except that the tests of one module that
# share a module-scoped fixture (the browser screenshots, the walks, the meshcat server, a shooting, a
# reference sweep) form one ``xdist_group``: the fixture is built once, on one worker, not once per worker.
# The tests of any module that use the plain install (plain_install.py: the wheel in a clean venv and
# `pasibot analyze` run there) form one group too, PLAIN_INSTALL: its session fixtures are built once.
# The tiers (pyproject's markers): `slow`, `integration`, `browser`, `mujoco`, `network`; `make test-fast`
# leaves them out.
# The longest go first, so that none starts last and keeps one worker busy alone (pyproject's
# --no-loadscope-reorder keeps this order; xdist would put the largest groups first): each test's time as
# the last run measured it (setup, call and teardown, kept in pytest's cache folder by the controller: not
# a list in the repository), a group's the sum of its tests'. Tests never timed (a fresh clone, a new
# test) rank by their tier marks instead, after the timed ones that took longer than a second.
TIERS = ("slow", "browser", "integration", "mujoco", "network")
DURATIONS = "pasibot/durations"
"""pytest cache key: node id -> seconds of its last run."""
_RUN: dict[str, float] = {}


def _shared_module_fixture(item) -> bool:
    """Whether ``item`` uses (directly or through another fixture) a module-scoped fixture."""
    info = getattr(item, "_fixtureinfo", None)
    if info is None:
        return False
    return any(defs and defs[-1].scope == "module" for defs in info.name2fixturedefs.values())


def unit_of_work(item) -> str:
    """What xdist schedules ``item`` with: the plain install's group (PLAIN_INSTALL), its module's (it uses a module
    fixture: the module file's name), or the test alone (its node id)."""
    if "installed" in getattr(item, "fixturenames", ()):
        return PLAIN_INSTALL
    if _shared_module_fixture(item):
        return item.nodeid.split("::", 1)[0].rsplit("/", 1)[-1]
    return item.nodeid


def _marks(item) -> int:
    return sum(item.get_closest_marker(m) is not None for m in TIERS)


def _measured(config) -> dict[str, float]:
    cache = getattr(config, "cache", None)  # None under -p no:cacheprovider
    return {} if cache is None else dict(cache.get(DURATIONS, {}))


@pytest.hookimpl(tryfirst=True)  # before xdist's own hook, which turns the group marks into the node ids' "@group"
def pytest_collection_modifyitems(config, items) -> None:
    """Group the tests sharing a module fixture, or the plain install, on one worker; the longest tests and groups
    first."""
    measured = _measured(config)
    rank: dict[str, tuple[float, int]] = {}
    for item in items:
        key = unit_of_work(item)
        if key != item.nodeid:
            item.add_marker(pytest.mark.xdist_group(name=key))
        seconds, marks = rank.get(key, (0.0, 0))
        rank[key] = (seconds + measured.get(item.nodeid, 0.0), max(marks, _marks(item)))

    def first(item) -> tuple[bool, float, float]:
        group = item.get_closest_marker("xdist_group")
        seconds, marks = rank[group.kwargs["name"] if group else item.nodeid]
        return (False, -seconds, 0.0) if seconds >= 1.0 else (True, -marks, -seconds)

    items.sort(key=first)


def collected_id(nodeid: str) -> str:
    """``nodeid`` without xdist's ``@group`` suffix (a module's file name or PLAIN_INSTALL): the id collection gives.

    A group's name holds no ``]`` or ``::``; an ``@`` inside a parameter's id (``[a@b]``) is left alone.
    """
    base, at, group = nodeid.rpartition("@")
    return base if at and "]" not in group and "::" not in group else nodeid


def pytest_runtest_logreport(report) -> None:
    """Add up each test's setup, call and teardown time (in the controller: xdist sends it every report)."""
    nodeid = collected_id(report.nodeid)
    _RUN[nodeid] = _RUN.get(nodeid, 0.0) + report.duration


def pytest_sessionfinish(session) -> None:
    """Keep this run's times for the next run's order (the controller's, or a run without workers)."""
    config = session.config
    if hasattr(config, "workerinput") or getattr(config, "cache", None) is None or not _RUN:
        return
    config.cache.set(DURATIONS, {**_measured(config), **{k: round(v, 3) for k, v in _RUN.items()}})
