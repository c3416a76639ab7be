"""benchmarks/profile_tests.py: the workers' records add up to its report (sums, modules, xdist's group suffix)."""

import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

import os  # noqa: E402

from profile_tests import machine_busy, report  # noqa: E402


def test_the_report_adds_the_workers_records(tmp_path):
    records = {
        "gw0": {
            "span": 10.0,
            "cpu": 9.0,
            "tests": [["tests/test_a.py::one@test_a.py", 4.0, 3.5], ["tests/test_b.py::two", 2.0, 1.0]],
        },
        "gw1": {"span": 8.0, "cpu": 7.5, "tests": [["tests/test_a.py::three@plain_install", 6.0, 6.5]]},
    }
    for name, record in records.items():
        (tmp_path / f"{name}.json").write_text(json.dumps(record))
    text = report(tmp_path, 12.0, top=2, modules=5)
    assert text.splitlines()[0] == "pytest: 12.0 s wall, 3 tests, 11.0 s CPU in the tests"
    assert "gw0: 9.0 s CPU over 10.0 s, in tests 60 % of it" in text  # 6 s of 10 in tests
    assert "gw1: 7.5 s CPU over 8.0 s, in tests 75 % of it" in text
    modules = text.split("modules by CPU [s] (top 5):\n")[1].split("\n\n")[0].splitlines()
    assert [line.split() for line in modules] == [["10.0", "tests/test_a.py"], ["1.0", "tests/test_b.py"]]
    tests = text.split("wall [s] beside):\n")[1].splitlines()
    assert [line.split() for line in tests] == [
        ["6.5", "6.0", "tests/test_a.py::three"],
        ["3.5", "4.0", "tests/test_a.py::one"],
    ]


def test_no_record_says_so(tmp_path):
    assert report(tmp_path, 1.0, top=3, modules=3) == "no test ran"


def test_the_machine_line_is_the_busy_time_beyond_the_tests(tmp_path):
    (tmp_path / "gw0.json").write_text(
        json.dumps({"span": 10.0, "cpu": 9.0, "tests": [["tests/test_a.py::one", 4.0, 3.0]]})
    )
    text = report(tmp_path, 10.0, top=1, modules=1, machine=12.0)
    cores = os.cpu_count() or 1
    assert (
        f"machine: 12.0 core-s busy over the run ({100 * 12 / (10 * cores):.0f} % of {cores} cores), 9.0 core-s more"
        in text
    )
    assert "machine:" not in report(tmp_path, 10.0, top=1, modules=1)


def test_busy_time_is_every_cpu_field_but_idle_and_iowait():
    ticks = os.sysconf("SC_CLK_TCK")
    # user nice system idle iowait irq softirq steal guest guest_nice: busy = 1+2+3+6+7+8 ticks (guest is in user)
    stat = "cpu  1 2 3 4 5 6 7 8 9 10\ncpu0 1 2 3 4 5 6 7 8 9 10\n"
    assert machine_busy(stat) == (1 + 2 + 3 + 6 + 7 + 8) / ticks
    assert machine_busy() is None or machine_busy() > 0
