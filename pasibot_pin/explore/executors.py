"""Where the designs run: this process, a local process pool, or a Dask cluster.

:func:`run_tasks` calls ``fn(*args)`` for every task and hands each result to ``on_result`` in
this process, as tasks finish (in any order). Every executor runs the same function on the same
arguments, so the results are equal bit for bit; ``tests/test_sweep.py`` compares a Dask
LocalCluster run with the local pool.

* ``workers = 1``: in this process, in order.
* the default: :func:`pasibot_pin.jobs.run_jobs`, one process per core (fork), the workers
  stopped cleanly on Ctrl-C or SIGTERM.
* ``dask = "local"``: a :class:`distributed.LocalCluster` of ``workers`` processes (one thread
  each), started and closed here. ``dask = "tcp://HOST:8786"``: an existing cluster's scheduler
  (start one with ``dask scheduler`` and ``dask worker tcp://HOST:8786`` on each machine, every
  machine with ``pasibot_pin[sweep]`` installed). At most :data:`IN_FLIGHT` tasks per worker
  are submitted at a time, so memory stays flat however many designs there are.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Callable, Sequence
from typing import TypeVar, cast

from pasibot_pin.errors import ParameterError
from pasibot_pin.extras import require

R = TypeVar("R")

IN_FLIGHT: int = 4
"""Tasks per Dask worker submitted ahead of the results."""

MAX_WORKERS: int = 64
"""The most worker processes a run starts (more only share the same cores and memory)."""

CONNECT_TIMEOUT: str = "3s"
"""How long to wait for a Dask scheduler before giving up."""


def default_workers() -> int:
    """One worker per core this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def check_workers(workers: int | None) -> int:
    """``workers`` (default: :func:`default_workers`) if it is a positive integer, else ValueError naming it."""
    if workers is None:
        return default_workers()
    if isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= MAX_WORKERS:
        raise ParameterError(f"--workers must be an integer in [1, {MAX_WORKERS}], got {workers!r}")
    return workers


def check_scheduler(address: str | None) -> None:
    """Before any work: ``address`` is ``None``, ``local``, or a Dask scheduler that answers (ValueError if not)."""
    if address is None:
        return
    require("sweep", ["distributed"], f"--dask {address}")
    if address == "local":
        return
    from distributed import Client  # deferred: optional extra (distributed)

    from pasibot_pin.net import tcp_refused  # deferred: keeps the CLI's start fast

    refused = tcp_refused(address)
    if refused:
        raise ParameterError(f"--dask {address}: cannot reach a Dask scheduler there ({refused})")
    try:
        Client(address, timeout=CONNECT_TIMEOUT).close()
    except (OSError, TimeoutError, ValueError) as err:
        raise ParameterError(f"--dask {address}: cannot reach a Dask scheduler there ({err})") from None


def run_tasks(
    fn: Callable[..., R],
    tasks: Sequence[tuple],
    on_result: Callable[[R], None],
    workers: int | None = None,
    dask: str | None = None,
    costs: Sequence[float] | None = None,
) -> None:
    """Run ``fn(*task)`` for every task; ``on_result(result)`` in this process as each one finishes.

    Args:
        fn: a module-level function (pickled by reference).
        tasks: the argument tuples.
        on_result: called with each result, in the order they finish.
        workers: processes (default one per core, at most :data:`MAX_WORKERS`, never more than the
            tasks); 1 runs in this process (without ``dask``).
        dask: ``None`` (local processes), ``"local"`` (a Dask LocalCluster) or a scheduler address.
        costs: each task's expected cost (local processes start the costly ones first, so the
            workers finish together); default all equal, in order.

    Raises:
        ValueError: a Dask scheduler that cannot be reached (before any task runs).

    """
    workers = min(check_workers(workers), max(1, len(tasks)))  # no more workers than tasks
    if dask is not None:
        _run_dask(fn, tasks, on_result, workers, dask)
    elif workers == 1:
        for task in tasks:
            on_result(fn(*task))
    else:
        from pasibot_pin.jobs import Job, run_jobs  # deferred: keeps the CLI's start fast

        jobs = [Job(1.0 if costs is None else float(costs[k]), k, fn, tuple(task)) for k, task in enumerate(tasks)]
        run_jobs(jobs, lambda _key, result: on_result(cast(R, result)), workers=workers)  # result: fn's, untyped


def _run_dask(
    fn: Callable[..., R], tasks: Sequence[tuple], on_result: Callable[[R], None], workers: int, address: str
) -> None:
    from distributed import Client, LocalCluster, as_completed  # deferred: optional extra (distributed)

    cluster = None
    if address == "local":
        cluster = LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=logging.ERROR
        )
        client = Client(cluster)
    else:
        try:
            client = Client(address, timeout=CONNECT_TIMEOUT)
        except (OSError, TimeoutError, ValueError) as err:
            raise ParameterError(f"--dask {address}: cannot reach a Dask scheduler there ({err})") from None
    try:
        capacity = max(1, len(client.scheduler_info().get("workers", {})) or workers) * IN_FLIGHT
        pending = iter(tasks)
        running = as_completed()
        for task in pending:
            running.add(client.submit(fn, *task, pure=False))
            if running.count() >= capacity:
                break
        for future in running:
            on_result(future.result())
            future.release()
            nxt = next(pending, None)
            if nxt is not None:
                running.add(client.submit(fn, *nxt, pure=False))
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
