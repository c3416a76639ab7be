"""The per-job profiler of the process pool (issue 33): off by default; with PASIBOT_PROFILE_DIR set each
job's cProfile statistics and CPU time are written beside each other, and the results are the same."""

from __future__ import annotations

import json
import math
import pstats

from pasibot_pin.jobs import PROFILE_ENV, Job, profile_path, run_jobs


def _run(workers: int) -> dict:
    found: dict = {}
    jobs = [Job(1.0, ("root", k), math.sqrt, (float(k * k),)) for k in range(1, 4)]
    run_jobs(jobs, lambda key, result: found.__setitem__(key, result), workers=workers)
    return found


def test_profiles_are_written_per_job_and_change_no_result(tmp_path, monkeypatch):
    plain = _run(1)
    assert not list(tmp_path.iterdir())
    monkeypatch.setenv(PROFILE_ENV, str(tmp_path))
    for workers in (1, 2):
        assert _run(workers) == plain == {("root", k): float(k) for k in range(1, 4)}
        for k in range(1, 4):
            path = profile_path(tmp_path, ("root", k))
            assert pstats.Stats(path).total_calls >= 1
            record = json.loads(open(path[: -len(".prof")] + ".json", encoding="utf-8").read())
            assert record["key"] == str(("root", k)) and record["cpu_s"] >= 0.0
