"""The process pool freezes the parent's objects for its workers (issue 33): a worker's full garbage
collections skip what it inherited; the parent's collector is as it was once the pool is done."""

from __future__ import annotations

import gc

from pasibot_pin.jobs import Job, run_jobs


def frozen_in_worker(_: int) -> int:
    """How many objects the running process's collector holds frozen."""
    return gc.get_freeze_count()


def test_workers_inherit_frozen_objects_and_the_parent_is_restored():
    assert gc.get_freeze_count() == 0
    found: dict = {}
    jobs = [Job(1.0, k, frozen_in_worker, (k,)) for k in range(4)]
    run_jobs(jobs, lambda key, result: found.__setitem__(key, result), workers=2)
    assert sorted(found) == [0, 1, 2, 3]
    assert all(count > 0 for count in found.values())
    assert gc.get_freeze_count() == 0


def test_one_worker_runs_here_and_freezes_nothing():
    found: dict = {}
    run_jobs([Job(1.0, "only", frozen_in_worker, (0,))], lambda key, result: found.__setitem__(key, result), workers=1)
    assert found == {"only": 0}
