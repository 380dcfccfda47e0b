"""Sweep throughput on the seed 004 fault data set (examples/sweeps/seed004_fault_dataset.toml:
30 s runs of the reclaimer gearbox, ring-accelerometer channel, states, indicators, verdicts).

The first ``GEARDYN_BENCH_SWEEP_CASES`` cases (default 12: healthy and 10 % sun crack, both
speeds, three seeds) run three ways:

* **direct**: the same cases in one process, ``run_simulation`` + ``features_from_result``
  (what a hand-written loop does), warm numba cache;
* **sweep, 1 worker** and **sweep, 2 workers**: ``geardyn.sweep.run`` on a LocalCluster of single-
  threaded worker processes (BLAS/numba threads 1), into a Zarr store.

An interleaved run in one process separates the machinery from the load: each case simulated
directly, then through ``run_case`` (what a worker runs), alternately, and each result written
by the driver's ``store.Writer``.

Rates are cases per minute in steady state (from the completion of the first case per worker
to the last: worker start-up and imports, a fixed cost per sweep, are reported apart).
Targets (issue 10): parallel efficiency rate(2)/(2·rate(1)) ≥ 0.9 on 2 cores, per-case overhead
of the sweep machinery vs direct ≤ 5 %. ``load`` is ``os.getloadavg()`` (1 min) before/after:
others share the cores, so compare it with the number of workers.
"""

from __future__ import annotations

import os
import tempfile
import time
from pathlib import Path

EX = Path(__file__).resolve().parents[1] / "examples" / "sweeps" / "seed004_fault_dataset.toml"
N_CASES = int(os.environ.get("GEARDYN_BENCH_SWEEP_CASES", "12"))
TARGET_EFFICIENCY = 0.9
TARGET_OVERHEAD = 0.05


def _load() -> str:
    return f"{os.getloadavg()[0]:.2f}"


def _direct(sweep, cases: list[int]) -> tuple[float, list[float]]:  # noqa: ANN001
    """Wall time of the cases run in this process: simulation + indicators."""
    from geardyn.config.loader import parse_config
    from geardyn.diagnosis.features import features_from_result
    from geardyn.diagnosis.pipeline import options
    from geardyn.run import run_simulation

    ind = sweep.spec.outputs.indicators
    t_end = sweep.spec.run.t_end_s
    cfg0 = parse_config(sweep.case_config(sweep.cases[0]))
    run_simulation(cfg0, seed=0, t_end_s=0.5)  # load the numba cache
    times = []
    for i in cases:
        t0 = time.perf_counter()
        cfg = parse_config(sweep.case_config(sweep.cases[i]))
        ds = run_simulation(cfg, seed=sweep.cases[i].seed, t_end_s=t_end)
        opts = options(cfg, channel=ind.channel, skip_s=ind.skip_s, blocks=ind.blocks)
        features_from_result(ds, cfg, opts.channel, reference=opts.reference,
                             skip_s=opts.skip_s, n_blocks=opts.blocks)
        times.append(time.perf_counter() - t0)
    return sum(times), times


def _interleaved(sweep, cases: list[int]) -> dict:  # noqa: ANN001
    """Worker-side machinery (``run_case``: config validation, states, channel decimation,
    packing) against the direct simulation + indicators of the same case, alternated in this
    process so that a change of machine load hits both; then the driver's write of each
    result into a store (``store.Writer``)."""
    from geardyn.config.loader import parse_config
    from geardyn.diagnosis.features import features_from_result
    from geardyn.diagnosis.pipeline import options
    from geardyn.run import run_simulation
    from geardyn.sweep import store
    from geardyn.sweep.case import run_case
    from geardyn.sweep.layout import plan
    from geardyn.sweep.runner import _task

    ind = sweep.spec.outputs.indicators
    layout = plan(sweep)
    n_state = layout.sizes.get("state_time")
    t_direct = t_case = 0.0
    results = []
    for i in cases:
        t0 = time.perf_counter()
        cfg = parse_config(sweep.case_config(sweep.cases[i]))
        ds = run_simulation(cfg, seed=sweep.cases[i].seed, t_end_s=sweep.spec.run.t_end_s)
        opts = options(cfg, channel=ind.channel, skip_s=ind.skip_s, blocks=ind.blocks)
        features_from_result(ds, cfg, opts.channel, reference=opts.reference,
                             skip_s=opts.skip_s, n_blocks=opts.blocks)
        t1 = time.perf_counter()
        results.append(run_case(_task(sweep, i, n_state)))
        t_direct += t1 - t0
        t_case += time.perf_counter() - t1
    with tempfile.TemporaryDirectory() as tmp:
        store.create(Path(tmp) / "w.zarr", sweep, layout)
        writer = store.Writer(Path(tmp) / "w.zarr")
        t0 = time.perf_counter()
        for i, r in zip(cases, results, strict=True):
            writer.write_case(i, r)
        t_write = (time.perf_counter() - t0) / len(cases)
    return {"direct": t_direct / len(cases), "case": t_case / len(cases), "write": t_write}


def _swept(sweep, cases: list[int], workers: int) -> dict:  # noqa: ANN001
    from geardyn.sweep import run

    stamps: list[float] = []

    def progress(p) -> None:  # noqa: ANN001
        if p.done:
            stamps.append(time.perf_counter())

    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        c0 = time.process_time()
        summary = run(sweep, Path(tmp) / "bench.zarr", n_workers=workers, cases=cases,
                      progress=progress)
        wall = time.perf_counter() - t0
        cpu = time.process_time() - c0
    k = min(workers, len(stamps) - 1)
    steady = (stamps[-1] - stamps[k - 1]) / (len(stamps) - k)  # s per case
    return {"wall": wall, "per_case": steady, "startup": stamps[k - 1] - t0 - k * steady,
            "failed": summary.failed, "driver_cpu": cpu / len(stamps)}


def run() -> list[dict]:
    from geardyn.sweep import load_spec

    sweep = load_spec(EX)
    cases = list(range(min(N_CASES, len(sweep.cases))))
    n = len(cases)
    rows: list[dict] = []
    load0 = _load()
    direct, _ = _direct(sweep, cases)
    rows.append({"run": f"direct loop, {n} cases × {sweep.spec.run.t_end_s:g} s", "workers": 1,
                 "wall [s]": direct, "s/case": direct / n, "cases/min": 60 * n / direct,
                 "load (before/after)": f"{load0}/{_load()}"})
    res = {}
    for w in (1, 2):
        load0 = _load()
        r = _swept(sweep, cases, w)
        res[w] = r
        rows.append({"run": f"sweep, {w} worker{'s' if w > 1 else ''}", "workers": w,
                     "wall [s]": r["wall"], "s/case": r["per_case"],
                     "cases/min": 60 / r["per_case"], "start-up [s]": r["startup"],
                     "driver CPU [s/case]": r["driver_cpu"],
                     "failed": r["failed"], "load (before/after)": f"{load0}/{_load()}"})
    k = min(4, n)
    load0 = _load()
    il = _interleaved(sweep, cases[:k])
    worker_overhead = il["case"] / il["direct"] - 1
    rows.append({"run": f"interleaved, {k} cases: direct | run_case | driver write",
                 "s/case": f"{il['direct']:.3f} | {il['case']:.3f} | {il['write']:.3f}",
                 "load (before/after)": f"{load0}/{_load()}"})
    eff = res[1]["per_case"] / (2 * res[2]["per_case"])
    overhead = res[1]["per_case"] / (direct / n) - 1
    rows.append({"run": "parallel efficiency rate(2)/(2·rate(1))", "value": eff,
                 "target": f"≥ {TARGET_EFFICIENCY}",
                 "met": "yes" if eff >= TARGET_EFFICIENCY else "no (see load)"})
    rows.append({"run": "per-case overhead of the sweep (1 worker) vs direct", "value": overhead,
                 "target": f"≤ {TARGET_OVERHEAD:.0%}",
                 "met": "yes" if overhead <= TARGET_OVERHEAD else "no (see load)"})
    machinery = worker_overhead + il["write"] / il["direct"]
    rows.append({"run": "machinery overhead, interleaved: run_case/direct − 1 + write/direct",
                 "value": machinery, "target": f"≤ {TARGET_OVERHEAD:.0%}",
                 "met": "yes" if machinery <= TARGET_OVERHEAD else "no"})
    return rows
