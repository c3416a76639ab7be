"""Run independent pieces of work on a process pool, longest first.

``pasibot analyze`` hands every piece (a report section, a spring case, a sweep row, a figure
task) to one pool of :data:`WORKERS` processes. :func:`run_jobs` keeps exactly one job per
worker in flight and always starts the longest ready job next (by its CPU estimate), so the
long ones do not end up alone at the end. A finished job may release new ones (e.g. a
scenario's figures once its cases and sweep are in).

Ctrl-C or SIGTERM: the workers ignore SIGINT (the main process handles it) and die with their
parent (Linux ``PR_SET_PDEATHSIG``). The command line's handler (``pasibot_pin.__main__``) stops
every descendant, grandchildren included, and raises in the main process; :func:`run_jobs` then
cancels the queued jobs and terminates any worker still running before it re-raises, so no
worker is left behind.

Profiling: with the environment variable :data:`PROFILE_ENV` (``PASIBOT_PROFILE_DIR``) naming a
folder, each job runs under :mod:`cProfile` where it runs (in its worker, or here with one worker),
and its statistics go to ``<folder>/<job key>.prof`` (:func:`profile_path`), its CPU time beside
them (:func:`profiled`); ``benchmarks/profile_analyze.py`` reads them. Unset, nothing changes: the
jobs run as they are.
"""

from __future__ import annotations

import ctypes
import gc
import heapq
import importlib
import itertools
import multiprocessing
import os
import re
import signal
import sys
import time
from collections.abc import Callable, Iterable
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from dataclasses import dataclass, field

from pasibot_pin.files import remove_temporaries

WORKERS = 2
"""Processes of the pool (the machine the goal was set on has 2 cores)."""


@dataclass(order=True)
class Job:
    """One piece of work: ``fn(*args)`` in a worker.

    Attributes:
        estimate: expected CPU time [s] (only orders the jobs: longest first).
        key: the job's name, handed back with its result.
        fn: a module-level function (it is pickled by reference).
        args: its arguments (pickled).

    """

    estimate: float
    key: object = field(compare=False)
    fn: Callable = field(compare=False)
    args: tuple = field(default=(), compare=False)


PROFILE_ENV = "PASIBOT_PROFILE_DIR"
"""Environment variable: a folder where every job's profile is written (unset or empty: no profiling)."""


def profile_path(folder: str | os.PathLike, key: object) -> str:
    """The profile file of the job ``key`` in ``folder``: the key's text made a file name, ``.prof``.

    ``("simulation", ("case", "run1", "half K_e"))`` -> ``simulation-case-run1-half-K_e.prof``.
    """
    name = re.sub(r"[^A-Za-z0-9._]+", "-", str(key)).strip("-.")
    return os.path.join(folder, f"{name or 'job'}.prof")


def profiled(folder: str, key: object, fn: Callable, *args):
    """``fn(*args)`` under :mod:`cProfile`; its statistics dumped to :func:`profile_path`.

    The profile's clock is cProfile's own (wall time [s]: a CPU clock costs a system call per
    event, 4x the run time); the job's CPU time [s] goes beside it, one line of JSON in the
    same name with ``.json`` (``{"key": ..., "cpu_s": ..., "wall_s": ...}``).
    """
    import cProfile  # deferred: keeps the CLI's start fast
    import json  # deferred: keeps the CLI's start fast

    profile = cProfile.Profile()
    cpu, wall = time.process_time(), time.perf_counter()
    try:
        return profile.runcall(fn, *args)
    finally:
        cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
        os.makedirs(folder, exist_ok=True)
        path = profile_path(folder, key)
        profile.dump_stats(path)
        with open(os.path.splitext(path)[0] + ".json", "w", encoding="utf-8") as handle:
            json.dump({"key": str(key), "cpu_s": cpu, "wall_s": wall}, handle)


def _call(job: Job, folder: str | None) -> tuple[Callable, tuple]:
    """What to run for ``job``: its function and arguments, wrapped in :func:`profiled` when ``folder`` is set."""
    if folder:
        return profiled, (folder, job.key, job.fn, *job.args)
    return job.fn, job.args


OnDone = Callable[[object, object], Iterable[Job] | None]
"""``on_done(key, result)``, called in the main process; returns the jobs it releases (or None)."""


def _die_clean(signum, frame) -> None:
    """A worker's SIGTERM: remove the files it is writing (never left under a .part name), then die of it."""
    remove_temporaries()
    signal.signal(signum, signal.SIG_DFL)
    os.kill(os.getpid(), signum)


def _worker_init() -> None:
    if os.environ.get(PROFILE_ENV):  # a profiled parent's profiler is not the jobs' (they have their own)
        sys.setprofile(None)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, _die_clean)
    try:  # die with the parent, even if it is killed outright (Linux only)
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass


def run_jobs(jobs: Iterable[Job], on_done: OnDone, workers: int = WORKERS, preload: Iterable[str] = ()) -> None:
    """Run ``jobs`` (and those ``on_done`` releases) longest first on ``workers`` processes.

    ``workers <= 1`` runs them one by one in this process (same order, same results).
    With :data:`PROFILE_ENV` set, each job is profiled (:func:`profiled`).
    Any job's exception is re-raised here after the pool is shut down. ``preload`` names modules
    that most workers import (e.g. ``matplotlib.pyplot``): imported once here, before the workers
    fork, they cost their import time once instead of once per worker.
    """
    for module in preload if workers > 1 else ():
        importlib.import_module(module)
    order = itertools.count()
    ready: list[tuple[float, int, Job]] = []

    def push(new: Iterable[Job] | None) -> None:
        for job in new or ():
            heapq.heappush(ready, (-job.estimate, next(order), job))

    push(jobs)
    folder = os.environ.get(PROFILE_ENV) or None  # profile every job (see the module's docstring)
    if workers <= 1:
        while ready:
            job = heapq.heappop(ready)[2]
            fn, args = _call(job, folder)
            push(on_done(job.key, fn(*args)))
        return

    # The objects alive now (the preloaded modules) are frozen before the workers fork: a worker's full
    # collections then skip them (each traversed them all, about 0.1 s of CPU a collection) and leave their
    # pages shared. The parent gets them back once the pool is done (see the ``finally`` below).
    gc.freeze()
    pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("fork"), initializer=_worker_init)
    running: dict[Future, Job] = {}
    try:
        while ready or running:
            while ready and len(running) < workers:
                job = heapq.heappop(ready)[2]
                fn, args = _call(job, folder)
                running[pool.submit(fn, *args)] = job
            finished, _ = wait(running, return_when=FIRST_COMPLETED)
            for future in finished:
                job = running.pop(future)
                push(on_done(job.key, future.result()))
    except BaseException:
        processes = list((getattr(pool, "_processes", None) or {}).values())
        pool.shutdown(wait=False, cancel_futures=True)
        for process in processes:
            process.terminate()
        for process in processes:
            process.join(timeout=5)
        raise
    else:
        pool.shutdown(wait=True)
    finally:
        gc.unfreeze()
