"""Run a sweep on ``dask.distributed``: a LocalCluster (one single-threaded worker process per
core, each under a nanny) or an existing cluster, results written by the driver as cases end.

One driver per store (:mod:`geardyn.sweep.lock`). Resume: cases whose ``status`` is set in the
store and whose data match their checksum are skipped (damaged ones run again; ``failed`` ones
only with ``retry_failed``), so re-running the command after an interruption (Ctrl-C, a killed
driver) finishes the sweep; a worker killed mid-case is
restarted by its nanny and the scheduler runs the case again (up to
``distributed.scheduler.allowed-failures`` times, then the case is recorded ``failed``).
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
import time
import uuid
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import xarray as xr

from geardyn.errors import InputError
from geardyn.sweep import store
from geardyn.sweep.case import STATUS_FAILED, run_case
from geardyn.sweep.lock import store_lock
from geardyn.sweep.spec import Sweep, load_spec

#: Environment of LocalCluster workers: one thread for BLAS, OpenMP and numba per process.
WORKER_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
              "NUMBA_NUM_THREADS": "1"}


@dataclass
class SweepProgress:
    """Counts passed to the progress callback after each case."""

    total: int
    skipped: int
    done: int = 0
    failed: int = 0
    started: float = 0.0

    @property
    def left(self) -> int:
        return self.total - self.skipped - self.done

    @property
    def rate_per_min(self) -> float:
        dt = time.perf_counter() - self.started
        return 60.0 * self.done / dt if dt > 0 and self.done else float("nan")

    @property
    def eta_s(self) -> float:
        r = self.rate_per_min
        return 60.0 * self.left / r if r == r and r > 0 else float("nan")


@dataclass
class SweepSummary:
    """What a run did: store path, cases run now, skipped (already done), failed now; the
    cases found damaged (and run again), and the failed and pending cases of the store."""

    out: Path
    total: int
    run: int
    skipped: int
    failed: int
    wall_s: float
    damaged: dict[int, str] = field(default_factory=dict)
    failed_total: int = 0
    pending: int = 0


@contextlib.contextmanager
def _deferred_sigint() -> Iterator[None]:
    """Hold Ctrl-C while a case is written (raised right after): a case is stored whole or
    not at all, whatever the moment of the interrupt."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []
    old = signal.signal(signal.SIGINT, lambda s, f: caught.append(s))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)
    if caught:
        raise KeyboardInterrupt


@contextlib.contextmanager
def _quiet_on_interrupt() -> Iterator[None]:
    """Restore distributed's log level after a run: on Ctrl-C :func:`_run_cases` silences it
    while the cluster closes (connections cut mid-task log tracebacks that say nothing to the
    user)."""
    log = logging.getLogger("distributed")
    level = log.level
    try:
        yield
    finally:
        log.setLevel(level)


def _task(sweep: Sweep, i: int, state_samples: int | None, out: Path | None = None
          ) -> dict[str, Any]:
    case = sweep.cases[i]
    return {"index": i, "seed": case.seed, "config": sweep.case_config(case),
            "run": sweep.spec.run.model_dump(), "outputs": sweep.spec.outputs.model_dump(),
            "state_samples": state_samples,
            "store": str(out.resolve()) if out is not None else None}


@contextlib.contextmanager
def _client(scheduler: str | None, n_workers: int | None) -> Iterator[Any]:
    """A dask client: to ``scheduler`` if given, else to a new LocalCluster of ``n_workers``
    single-threaded processes (default: one per core) with nannies."""
    import dask
    from distributed import Client, LocalCluster

    if scheduler is not None:
        try:
            client = Client(scheduler, timeout=30)
        except (OSError, TimeoutError) as exc:
            raise InputError(f"--scheduler: cannot reach '{scheduler}': {exc}") from None
        try:
            yield client
        finally:
            client.close()
        return
    n = n_workers or os.cpu_count() or 1
    if n < 1:
        raise InputError(f"workers: must be ≥ 1, got {n}")
    env = dict(dask.config.get("distributed.nanny.pre-spawn-environ", {}) or {})
    # dask's default MALLOC_TRIM_THRESHOLD_=65536 makes glibc hand every freed numpy buffer back
    # to the OS; with the statistical profiler (10 ms samples) it made a seed 004 case 35-40 %
    # slower in a worker than in-process (2.6 vs 1.9 s); without both: within 4 %
    env.pop("MALLOC_TRIM_THRESHOLD_", None)
    env.update(WORKER_ENV)
    preload = [*dask.config.get("distributed.worker.preload", []), "geardyn.sweep._worker"]
    with dask.config.set({"distributed.nanny.pre-spawn-environ": env,
                          "distributed.worker.profile.enabled": False,
                          "distributed.worker.preload": preload}):
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address=":0", silence_logs=logging.CRITICAL)
        client = Client(cluster)
        try:
            yield client
        finally:
            with contextlib.suppress(Exception):
                client.close(timeout=10)
            with contextlib.suppress(Exception):
                cluster.close(timeout=10)


def _failed(index: int, exc: BaseException) -> dict[str, Any]:
    return {"index": index, "status": STATUS_FAILED, "arrays": {}, "kinds": {},
            "message": f"{type(exc).__name__}: {exc}", "wall_time_s": float("nan")}


def run(
    spec: str | Path | Sweep,
    out: str | Path,
    *,
    scheduler: str | None = None,
    n_workers: int | None = None,
    client: Any = None,
    retry_failed: bool = False,
    overrides: dict[str, Any] | None = None,
    cases: list[int] | None = None,
    progress: Callable[[SweepProgress], None] | None = None,
) -> SweepSummary:
    """Run the sweep ``spec`` (a spec file or a :class:`Sweep`) into the Zarr store ``out``.

    The store is locked for the run (a second driver: InputError naming the first). A new
    store gets its whole layout from the spec and the cases' configs after the run-time checks
    (:func:`geardyn.sweep.layout.plan`; ConfigError naming the case). In an existing one,
    cases already stored whose data match their checksums are skipped, damaged ones run again
    (``SweepSummary.damaged``), ``failed`` ones only with ``retry_failed``; the spec must be
    the one that made the store. Verdicts (when the spec asks) are computed again at the end.
    ``client``: an existing ``distributed.Client``;
    else ``scheduler`` (address of a running scheduler) or a LocalCluster of ``n_workers``
    processes. ``overrides`` are merged into the spec file's tables (see
    :func:`geardyn.sweep.spec.load_spec`). ``cases``: run only these case indices (the
    others stay pending). ``progress`` is called after each case.
    Ctrl-C cancels the remaining cases and raises KeyboardInterrupt; the store keeps every
    case finished so far.
    """
    t0 = time.perf_counter()
    sweep = spec if isinstance(spec, Sweep) else load_spec(spec, overrides)
    out = Path(out)
    if cases is not None:
        bad = [i for i in cases if not 0 <= i < len(sweep.cases)]
        if bad:
            raise InputError(f"cases: {bad} out of range (the sweep has cases 0 to "
                             f"{len(sweep.cases) - 1})")
    if not out.parent.exists():
        raise InputError(f"--out: directory '{out.parent}' does not exist")
    with store_lock(out):
        damaged: dict[int, str] = {}
        if out.exists():
            store.check_same_sweep(out, sweep)
            damaged = store.verify(out)
        else:
            from geardyn.solve.sanity import TimeStepWarning
            from geardyn.sweep.layout import plan

            layout = plan(sweep)
            for note in layout.notes:
                warnings.warn(note, TimeStepWarning, stacklevel=2)
            if not store.create(out, sweep, layout):
                store.check_same_sweep(out, sweep)
        status = store.statuses(out)
        wanted = set(range(len(sweep.cases)) if cases is None else cases)
        todo = [i for i, s in enumerate(status) if i in wanted
                and (s == store.PENDING or i in damaged
                     or (retry_failed and s == STATUS_FAILED))]
        store.mark_pending(out, [i for i in todo if status[i] != store.PENDING])
        prog = SweepProgress(total=len(sweep.cases), skipped=len(sweep.cases) - len(todo),
                             started=time.perf_counter())
        if progress is not None:
            progress(prog)
        if todo:
            with _quiet_on_interrupt(), contextlib.ExitStack() as stack:
                cl = client if client is not None else stack.enter_context(
                    _client(scheduler, n_workers))
                _run_cases(cl, sweep, out, todo, prog, progress)
        if sweep.spec.outputs.verdicts is not None:
            from geardyn.sweep.verdicts import write_verdicts

            write_verdicts(out, sweep)
        final = store.statuses(out)
    return SweepSummary(out, len(sweep.cases), prog.done, prog.skipped, prog.failed,
                        time.perf_counter() - t0, damaged=damaged,
                        failed_total=int((final == STATUS_FAILED).sum()),
                        pending=int((final == store.PENDING).sum()))


def _run_cases(client: Any, sweep: Sweep, out: Path, todo: list[int], prog: SweepProgress,
               progress: Callable[[SweepProgress], None] | None) -> None:
    from distributed import as_completed

    writer = store.Writer(out)
    n_state = writer.sizes.get("state_time")
    token = uuid.uuid4().hex[:8]
    futures = [client.submit(run_case, _task(sweep, i, n_state, out),
                             key=f"geardyn-case-{i}-{token}", pure=False) for i in todo]
    index = {f.key: i for f, i in zip(futures, todo, strict=True)}
    try:
        for fut in as_completed(futures):
            i = index[fut.key]
            try:
                res = fut.result()
            except Exception as exc:  # noqa: BLE001 - e.g. KilledWorker after retries
                res = _failed(i, exc)
            with _deferred_sigint():
                writer.write_case(i, res)
            fut.release()
            prog.done += 1
            prog.failed += res["status"] == STATUS_FAILED
            if progress is not None:
                progress(prog)
    except BaseException as exc:
        if isinstance(exc, KeyboardInterrupt):
            logging.getLogger("distributed").setLevel(logging.CRITICAL)
        for f in futures:
            if not f.done():
                f.cancel()
        raise


def open_dataset(path: str | Path) -> xr.Dataset:
    """The data set of a sweep store (see :func:`geardyn.sweep.store.open_dataset`)."""
    return store.open_dataset(path)
