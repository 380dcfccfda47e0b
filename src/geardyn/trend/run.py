"""Records → indicator tables → the trend store, on the project's Dask machinery.

:func:`update_store` reads each record not yet in the store (:func:`record_table`: the
record through the ``[measurement]`` mapping, the diagnosis' features of its channel), on a
``dask.distributed`` cluster (:func:`geardyn.sweep.runner._client`: a scheduler address, or a
LocalCluster of single-threaded worker processes) when there are several records and more
than one worker, else in this process. Each record is written into the store by the process
that read it (in its own group, written aside and renamed: the client stays idle, so two
workers keep two cores busy): Ctrl-C keeps every record already written and a re-run
resumes.
"""

from __future__ import annotations

import glob
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import pandas as pd

from geardyn.errors import GeardynError, InputError
from geardyn.trend.store import TrendStore, record_key

#: File extensions taken from a folder of records.
RECORD_EXTENSIONS = (".csv", ".tsv", ".txt", ".wav", ".flac", ".npy", ".npz", ".mat", ".tdms",
                     ".uff", ".unv", ".mf4", ".mdf", ".h5", ".hdf5", ".nc")


def expand_records(items: Sequence[str | Path]) -> list[Path]:
    """Files, folders (their record files, sorted) and glob patterns → record files, each
    once, in the order given."""
    out: list[Path] = []
    for item in items:
        p = Path(item)
        if p.is_dir():
            found = sorted(f for f in p.iterdir() if f.is_file()
                           and f.suffix.lower() in RECORD_EXTENSIONS)
        elif p.is_file():
            found = [p]
        else:
            found = [Path(f) for f in sorted(glob.glob(str(item))) if Path(f).is_file()]
            if not found:
                raise InputError(f"records: '{item}' is no file, folder or matching pattern")
        out += [f for f in found if f not in out]
    if not out:
        raise InputError("records: no record file found")
    return out


def record_table(path: str, cfg: Any, opts: Any) -> tuple[pd.DataFrame, dict[str, Any]]:
    """The indicator table (per block) and the record's attributes (worker task)."""
    import warnings

    from geardyn.diagnosis.features import features_from_result
    from geardyn.diagnosis.measured import _check_speed, load_record, record_channel

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = load_record(path, cfg, "record")
    what = f"record '{path}'"
    ch = record_channel(ds, opts.channel, what)
    _check_speed(ds, what)
    f = features_from_result(ds, cfg, ch, reference=opts.reference, skip_s=opts.skip_s,
                             n_blocks=opts.blocks)
    a = ds.attrs
    notes = [str(w.message) for w in caught] or [str(a.get("warnings", ""))]
    info = {"file": str(path), "timestamp": str(a.get("timestamp", "")),
            "speed_rpm": float(a.get("speed_rpm", float("nan")) or float("nan")),
            "load_nm": float(a.get("load_nm", float("nan"))),
            "warnings": "\n".join(n for n in notes if n), "channel": ch}
    return f.table, info


def _task(args: tuple[str, str, Any, Any]) -> tuple[str, str, Any, Any]:
    path, key, cfg, opts = args
    try:
        table, info = record_table(path, cfg, opts)
        return key, path, table, info
    except GeardynError as exc:
        return key, path, None, str(exc)


#: Most records per cluster task: a task of several records costs the scheduler (which runs
#: in the client process of a LocalCluster, on the cores the workers use) one round trip
#: instead of one per record; with at least 32 tasks the workers stay evenly loaded.
BATCH = 16


def _remote(items: list[tuple[str, str]], cfg: Any, opts: Any, store: str
            ) -> list[tuple[str, str, Any, Any]]:
    """Worker task: each record's indicators written into the store by the worker itself (its
    own group, written aside and renamed: workers never share a group), so that the client
    only collects names; per record (key, path, True/False added, info) or (…, None,
    reason)."""
    out = []
    for path, key in items:
        key, path, table, info = _task((path, key, cfg, opts))
        if table is not None:
            table = TrendStore(store, create=False, tidy=False).add(key, table, info)
        out.append((key, path, table, info))
    return out


def update_store(store: TrendStore, paths: Sequence[Path], cfg: Any, opts: Any, *,
                 workers: int | None = None, scheduler: str | None = None,
                 progress: Callable[[str, float], None] | None = None
                 ) -> dict[str, list[str]]:
    """Add the records not yet in ``store``; returns the files ``added``, ``present`` and
    ``failed`` (with the reason) — a failed record is reported, not stored, and tried again
    on the next run. On a cluster each worker writes the records it reads (the store must be
    on a file system the workers share, as for a LocalCluster)."""
    have = store.keys()
    todo, present = [], []
    for p in paths:
        key = record_key(p)
        (present if key in have else todo).append((str(p), key))
    have |= {k for _, k in todo}
    done: dict[str, list[str]] = {"added": [], "present": [p for p, _ in present], "failed": []}
    tasks = [(p, k, cfg, opts) for p, k in dict((k, (p, k)) for p, k in todo).values()]

    def keep(result: tuple[str, str, Any, Any], written: bool = False) -> None:
        key, path, table, info = result
        if table is None:
            done["failed"].append(info if str(info).startswith(path) else f"{path}: {info}")
        elif (table is True) if written else store.add(key, table, info):
            done["added"].append(path)
        if progress is not None:
            progress(f"indicators of {Path(path).name}",
                     (len(done["added"]) + len(done["failed"])) / max(len(tasks), 1))

    if scheduler is None and (len(tasks) < 2 or (workers or 1) <= 1):
        for t in tasks:
            keep(_task(t))
        return done
    from distributed import as_completed

    from geardyn.sweep.runner import _client

    with _client(scheduler, workers) as client:
        # the config and options go to every worker once, not with every task
        cfg_f, opts_f = client.scatter([cfg, opts], broadcast=True)
        size = max(1, min(BATCH, len(tasks) // 32))
        batches = [[(p, k) for p, k, _, _ in tasks[i:i + size]]
                   for i in range(0, len(tasks), size)]
        futures = client.map(_remote, batches, cfg=cfg_f, opts=opts_f,
                             store=str(store.path.resolve()), pure=False)
        for fut in as_completed(futures):
            for result in fut.result():
                keep(result, written=True)
    return done
