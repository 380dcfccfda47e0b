"""The few independent runs of one diagnosis (the baseline ensemble's dynamic runs) on local
worker processes.

A diagnosis simulates a handful of runs (six by default) and judges one record: too few tasks
for a Dask cluster to pay its start-up (≈ 10 s for two local workers, measured 2026-11-26,
against ≈ 3 s per run), so they go to a :class:`multiprocessing.pool.Pool` of forked processes
(started in well under a second; they inherit the imported modules and the compiled kernels)
where the platform has ``fork``, spawned ones elsewhere. ``geardyn sweep`` and ``geardyn
trend`` keep Dask for their many cases.

Each task's result is the same as in the calling process (every run carries its own seed), so
the verdict does not depend on the number of workers. Workers ignore SIGINT: Ctrl-C stops the
caller, which terminates the pool; nothing is written before every task has returned.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import signal
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from multiprocessing.pool import AsyncResult, Pool
from typing import Any

from geardyn.errors import InputError


def available_cores() -> int:
    """Cores this process may run on (its CPU affinity where the platform tells it)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - macOS, Windows
        return max(1, os.cpu_count() or 1)


def check_workers(workers: int | None, name: str = "workers") -> int:
    """``workers`` as a process count: None → one per available core; else an integer ≥ 1."""
    if workers is None:
        return available_cores()
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise InputError(f"{name}: must be a whole number ≥ 1, got {workers!r}")
    return workers


def _ignore_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)


@contextmanager
def worker_pool(workers: int, tasks: int) -> Iterator[Pool | None]:
    """A pool of ``min(workers, tasks)`` worker processes, or None when that is one (the
    caller then runs the tasks itself). On leaving — normally or by an error or Ctrl-C — the
    pool is terminated: no worker outlives the call."""
    n = min(int(workers), int(tasks))
    if n <= 1:
        yield None
        return
    method = "fork" if "fork" in mp.get_all_start_methods() else "spawn"
    pool = mp.get_context(method).Pool(n, initializer=_ignore_sigint)
    try:
        yield pool
    finally:
        pool.terminate()
        pool.join()


def submit(pool: Pool | None, fn: Callable[..., Any], args: Sequence[Any]
           ) -> AsyncResult | Callable[[], Any]:
    """``fn(*args)`` started on ``pool`` (an :class:`AsyncResult`), or deferred (a callable
    running it here) without a pool; :func:`result` takes either."""
    if pool is None:
        return lambda: fn(*args)
    return pool.apply_async(fn, tuple(args))


def result(task: AsyncResult | Callable[[], Any]) -> Any:
    """The value of a task of :func:`submit` (a worker's exception is raised here)."""
    return task() if callable(task) else task.get()
