"""The test tiers and their scheduling (issue 35): the markers are registered and enforced, `make test-fast`
leaves the marked tiers out, and the tests sharing a module fixture (or the plain install) run on one xdist worker.

pytest 9.2 changed how node ids are stored, and pytest-xdist 3.8's ``--dist loadgroup`` then silently stops
grouping (pytest-dev/pytest-xdist#1386): every worker builds every module fixture again. ``pyproject.toml``
pins pytest below 9.2; :func:`test_a_module_fixture_s_tests_share_one_worker` fails if grouping is lost.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
TIERS = {"slow", "integration", "browser", "mujoco", "network"}


def test_the_tiers_are_registered_and_enforced_and_make_test_fast_leaves_them_out():
    options = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["pytest"]["ini_options"]
    assert {line.split(":", 1)[0] for line in options["markers"]} == TIERS
    assert "--strict-markers" in options["addopts"].split() and "loadgroup" in options["addopts"].split()
    fast = re.search(r'^test-fast:.*\n\t.*pytest -q -m "([^"]+)"', (ROOT / "Makefile").read_text(), re.M)
    assert fast is not None
    assert set(re.findall(r"not (\w+)", fast.group(1))) == TIERS
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert "make test " in readme and "make test-fast" in readme


@pytest.fixture(scope="module")
def shared() -> list[str]:
    return []


def test_a_module_fixture_s_tests_share_one_worker(request, shared):
    """This test uses a module fixture: it carries its module's xdist group, and under ``--dist loadgroup``
    xdist has put the group in its node id (what its scheduler reads)."""
    mark = request.node.get_closest_marker("xdist_group")
    assert mark is not None and mark.kwargs["name"] == "test_tiers.py"
    if request.config.getoption("dist", "no") == "loadgroup" and hasattr(request.config, "workerinput"):
        assert request.node.nodeid.endswith("@test_tiers.py"), request.node.nodeid
    shared.append(request.node.nodeid)


def test_a_test_without_module_fixture_is_its_own_unit(request):
    assert request.node.get_closest_marker("xdist_group") is None
    assert "@" not in request.node.nodeid


def test_the_plain_install_s_tests_are_one_group_whatever_their_module():
    """A test that uses the plain install (plain_install.py's session fixtures) is scheduled in its one group, from
    any module: the venv is built and ``analyze`` run once, on one worker."""
    from types import SimpleNamespace

    from conftest import unit_of_work
    from plain_install import GROUP

    for module in ("test_report.py", "test_energy.py", "test_wheel_install.py"):
        item = SimpleNamespace(nodeid=f"tests/{module}::test_a", fixturenames=["analyzed", "installed", "analyze"])
        assert unit_of_work(item) == GROUP == "plain_install"
    alone = SimpleNamespace(nodeid="tests/test_report.py::test_b", fixturenames=["tmp_path"])
    assert unit_of_work(alone) == alone.nodeid


def test_a_test_s_time_is_kept_under_the_id_collection_gives():
    """The durations that order the next run are kept by the collected node id: xdist's group suffix, the plain
    install's included, is not part of it (else the group's time is never read back)."""
    from conftest import collected_id

    assert collected_id("tests/test_a.py::t@test_a.py") == "tests/test_a.py::t"
    assert collected_id("tests/test_energy.py::test_x@plain_install") == "tests/test_energy.py::test_x"
    assert collected_id("tests/test_a.py::t[a@b]") == "tests/test_a.py::t[a@b]"
    assert collected_id("tests/test_a.py::t[a@b]@test_a.py") == "tests/test_a.py::t[a@b]"
    assert collected_id("tests/test_a.py::t") == "tests/test_a.py::t"
