"""Diagnose the records of many machine configurations, each against its own baseline ensemble.

A :class:`Configuration` is one machine at one operating point with its sensors (a base config,
path overrides, speed and load factors); its :class:`RecordSpec` s are the records diagnosed
against it: healthy records and faults of several kinds and sizes. :func:`run_configuration`
simulates the configuration's healthy baseline ensemble once (as ``geardyn diagnose`` does,
:func:`geardyn.diagnosis.ensemble.simulate_baseline`), then simulates and judges every record
(:func:`geardyn.diagnosis.pipeline.judge_features`) and returns one row per record: the verdict
summary, the localisation and the record's signal-to-noise ratio.

SNR of a fault record: ``mean((x_fault − x_healthy)²) / noise_rms²``, x the judged channel of the
faulty and of the healthy machine simulated with the same seed (the same sensor-noise draws and
manufacturing errors cancel): the power of the fault's signature in the channel over the sensor
noise power.

:func:`run_study` runs configurations on Dask (a ``LocalCluster`` or a scheduler address), one
task per configuration, and writes each configuration's rows to ``OUT/rows/<id>.json`` as it
finishes (written to a temporary name and renamed: an interrupted study keeps every finished
configuration and resumes where it stopped).
"""

from __future__ import annotations

import json
import math
import os
import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from geardyn.errors import ConfigError, GeardynError


@dataclass(frozen=True)
class RecordSpec:
    """One record of a configuration: ``label`` (e.g. ``"sun crack 20 %"``), ``fault_type``
    (``"healthy"`` for none), ``severity`` (in the fault's own measure; 0 healthy),
    ``update``: config path → value setting the fault on the healthy configuration, ``seed``:
    the run seed."""

    label: str
    fault_type: str
    severity: float
    update: Mapping[str, Any] = field(default_factory=dict)
    seed: int = 100


@dataclass(frozen=True)
class Configuration:
    """One machine configuration of a study: ``base`` config file, ``update`` (path → value,
    applied to it before its faults are removed), operating point (``speed_factor``,
    ``load_factor`` on every stated speed and load), the ``records`` judged against its
    baseline ensemble, the study ``half`` it belongs to and the ``params`` reported with each
    row."""

    id: str
    machine: str
    half: str
    base: str
    update: Mapping[str, Any]
    speed_factor: float
    load_factor: float
    records: tuple[RecordSpec, ...]
    params: Mapping[str, float | str] = field(default_factory=dict)
    fleet_seed: int | None = 1
    """Each record's machine is drawn from the same fleet as the baseline ensemble (the
    ``[diagnosis.ensemble]`` tolerances, perturbation seed ``fleet_seed``, run seed the record's
    seed: the healthy and faulty records of one seed are one machine); None: the nominal
    machine."""


def _apply(data: dict[str, Any], update: Mapping[str, Any]) -> dict[str, Any]:
    from geardyn.sweep.spec import set_path

    for path, value in update.items():
        set_path(data, path, value)
    return data


def healthy_configuration(conf: Configuration) -> Any:  # noqa: ANN401 - a GeardynConfig
    """The healthy machine of ``conf`` at its operating point (validated)."""
    from geardyn.config.loader import load_config, parse_config
    from geardyn.diagnosis.ensemble import operating_point
    from geardyn.diagnosis.faults import healthy_variant

    data = _apply(load_config(conf.base).model_dump(), conf.update)
    cfg = healthy_variant(parse_config(data, source=f"study configuration {conf.id}"))
    return operating_point(cfg, conf.speed_factor, conf.load_factor)


def fleet_machine(cfg: Any, opts: Any, seed: int, fleet_seed: int) -> Any:  # noqa: ANN401
    """``cfg`` drawn as one machine of the baseline's fleet: the perturbations of
    :func:`geardyn.diagnosis.ensemble.member_configs` (speed, load, errors, pins,
    clearances, sensors) with run seed ``seed`` and perturbation seed ``fleet_seed``."""
    from geardyn.diagnosis.ensemble import member_configs

    ens = opts.ensemble.model_copy(update={"measurements_per_run": 1})
    spec = opts.model_copy(update={"baseline_seeds": [int(seed)], "ensemble": ens})
    return member_configs(cfg, spec, seed=fleet_seed)[0].config


def _noise_rms(cfg: Any, channel: str) -> float:  # noqa: ANN401
    for s in cfg.sensors:
        if s.name == channel:
            return float(s.noise_rms)
    return math.nan


def run_configuration(conf: Configuration, cases: str | Path | None = None,
                      baseline_cache: str | Path | None = None) -> list[dict[str, Any]]:
    """Rows (one per record of ``conf``) of the verdicts against the configuration's baseline
    ensemble; a record whose run or judgement fails gets ``status`` ``failed: …`` (never
    dropped). With ``cases`` (a file path) the inputs of every verdict — the baseline's and
    the records' features and per-order statistics — are pickled there, so that
    :func:`rejudge` can judge them again without simulating (a cache the study writes and
    reads itself). ``baseline_cache``: such a file of an earlier run of the same
    configuration — its baseline ensemble is reused instead of simulated (the baseline does
    not depend on the records)."""
    from geardyn.config.loader import parse_config
    from geardyn.diagnosis import pipeline as pipe
    from geardyn.diagnosis.ensemble import simulate_baseline
    from geardyn.diagnosis.faults import fault_list
    from geardyn.run import run_simulation

    t0 = time.process_time()
    healthy = healthy_configuration(conf)
    opts = pipe.options(healthy)
    run_length = pipe._run_length(healthy, opts)
    feats, blocks = [], []
    cached = _baseline_from(baseline_cache, conf) if baseline_cache is not None else None
    if cached is not None:
        feats, blocks, t_cached = cached
        t0 -= t_cached  # the baseline's CPU time as measured when it was simulated
    for member, ds in (() if cached is not None
                       else simulate_baseline(healthy, opts, run_length)):
        pipe._check_status(ds, f"healthy baseline {member.label}")
        ch = pipe._channel(ds, opts.channel, "healthy baseline")
        feats.append(pipe._features(ds, healthy, ch, opts))
        blocks.append(pipe._blocks(ds, healthy, ch, opts).compact())
        blocks[-1].run = member.run
        del ds
    t_base = time.process_time() - t0
    paired: dict[int, np.ndarray] = {}
    rows = []
    judged: list[tuple[dict[str, Any], Any, Any]] = []
    for rec in sorted(conf.records, key=lambda r: r.fault_type != "healthy"):
        row: dict[str, Any] = {"config": conf.id, "machine": conf.machine, "half": conf.half,
                               "record": rec.label, "fault_type": rec.fault_type,
                               "severity": float(rec.severity), "seed": int(rec.seed),
                               "speed_factor": conf.speed_factor,
                               "load_factor": conf.load_factor, **dict(conf.params),
                               "baseline_cpu_s": t_base}
        t1 = time.process_time()
        try:
            data = _apply(healthy.model_dump(), rec.update)
            cfg = parse_config(data, source=f"study record {conf.id} {rec.label}")
            if conf.fleet_seed is not None:
                cfg = fleet_machine(cfg, opts, rec.seed, conf.fleet_seed)
            ds = run_simulation(cfg, seed=rec.seed, **run_length)
            pipe._check_status(ds, f"record {rec.label}")
            ch = pipe._channel(ds, opts.channel, "record")
            x = np.asarray(ds[f"sensors.{ch}"].values, float)
            if rec.fault_type == "healthy":
                paired.setdefault(rec.seed, x)
                snr = 0.0
            else:
                h = paired.get(rec.seed)
                noise = _noise_rms(cfg, ch)
                snr = (float(np.mean((x - h) ** 2)) / noise**2
                       if h is not None and h.shape == x.shape and noise > 0 else math.nan)
            feat = pipe._features(ds, cfg, ch, opts)
            rb = pipe._blocks(ds, cfg, ch, opts).compact()
            del ds
            verdict = pipe.judge_features(cfg, opts, feats, feat, baseline_blocks=blocks,
                                          record_blocks=rb, expected=fault_list(cfg))
            row.update(_verdict_row(verdict), snr=snr, status="ok")
            judged.append((dict(row), feat, rb))
        except (GeardynError, ValueError, FloatingPointError) as exc:
            row.update(status=f"failed: {exc}")
        row["record_cpu_s"] = time.process_time() - t1
        rows.append(row)
    if cases is not None:
        _write_pickle(Path(cases), {"configuration": conf, "baseline": feats,
                                    "blocks": blocks, "records": judged,
                                    "baseline_cpu_s": t_base})
    return rows


def _baseline_from(path: str | Path, conf: Configuration) -> tuple[list, list, float] | None:
    """Baseline features, blocks and CPU time from a case cache of the same configuration
    (same id, base, update and operating point); None when absent or of another one."""
    import pickle

    p = Path(path)
    if not p.exists():
        return None
    with p.open("rb") as fh:
        case = pickle.load(fh)  # noqa: S301 - the study's own cache
    old = case["configuration"]
    same = (old.id, old.base, dict(old.update), old.speed_factor, old.load_factor) == \
        (conf.id, conf.base, dict(conf.update), conf.speed_factor, conf.load_factor)
    if not same:
        return None
    t = float(case.get("baseline_cpu_s", 0.0)) or float(
        next((r[0].get("baseline_cpu_s", 0.0) for r in case["records"]), 0.0))
    return case["baseline"], case["blocks"], t


def _write_pickle(path: Path, obj: Any) -> None:  # noqa: ANN401
    import pickle

    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    with tmp.open("wb") as fh:
        pickle.dump(obj, fh, protocol=pickle.HIGHEST_PROTOCOL)
    os.replace(tmp, path)


def rejudge(out: str | Path, workers: int = 1) -> int:
    """Judge again every stored record of the study in ``out`` with the current code (its
    cached features and per-order statistics, no simulation) and rewrite the rows, in
    ``workers`` processes; returns the configurations judged again. Rows of failed records are
    kept as they are."""
    from concurrent.futures import ProcessPoolExecutor

    paths = sorted((Path(out) / "cases").glob("*.pkl"))
    if workers <= 1:
        return sum(_rejudge_one(p, Path(out)) for p in paths)
    with ProcessPoolExecutor(max_workers=workers) as pool:
        return sum(pool.map(_rejudge_one, paths, [Path(out)] * len(paths)))


def _rejudge_one(path: Path, out: Path) -> int:
    import pickle

    from geardyn.config.loader import parse_config
    from geardyn.diagnosis import pipeline as pipe
    from geardyn.diagnosis.faults import fault_list

    with path.open("rb") as fh:
        case = pickle.load(fh)  # noqa: S301 - the study's own cache
    conf = case["configuration"]
    healthy = healthy_configuration(conf)
    opts = pipe.options(healthy)
    new = {}
    for row, feat, rb in case["records"]:
        rec = next(r for r in conf.records if r.label == row["record"] and r.seed == row["seed"])
        cfg = parse_config(_apply(healthy.model_dump(), rec.update))
        verdict = pipe.judge_features(cfg, opts, case["baseline"], feat,
                                      baseline_blocks=case["blocks"], record_blocks=rb,
                                      expected=fault_list(cfg))
        new[(row["record"], row["seed"])] = {**row, **_verdict_row(verdict)}
    rows_path = out / "rows" / f"{conf.id}.json"
    old = json.loads(rows_path.read_text()) if rows_path.exists() else []
    _write_rows(rows_path, [new.get((r["record"], r.get("seed")), r) for r in old])
    return 1


def _verdict_row(verdict: Any) -> dict[str, Any]:  # noqa: ANN401 - a Verdict
    """The columns of a study row from a verdict: machine verdict, detection, location."""
    s = verdict.summary()
    loc = verdict.localisation or {}
    det = verdict.detection or {}
    alarms = det.get("alarms") or []
    return {
        "verdict": s.get("verdict"),
        "detected": bool(det.get("detected", False)),
        "location": ", ".join(loc.get("components") or []),
        "level": loc.get("level") or "",
        "localisation": loc.get("state") or "",
        "confidence": (float(loc["confidence"]) if loc.get("confidence") is not None
                       else math.nan),
        "localised": s.get("localised"),
        "planet_named": s.get("planet_named"),
        "expected": ", ".join(s.get("expected") or []),
        "candidates": ", ".join(s.get("candidates") or []),
        "first_alarm": (f"{alarms[0]['component']} {alarms[0]['indicator']}" if alarms else ""),
        "first_margin": float(alarms[0]["margin"]) if alarms else math.nan,
        "tests": int(det.get("tests", 0)),
        "alpha_per_test": float(det.get("alpha_per_test", math.nan)),
    }


def _write_rows(path: Path, rows: list[dict[str, Any]]) -> None:
    tmp = path.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(rows, indent=1, default=_json_default))
    os.replace(tmp, path)


def _json_default(v: Any) -> Any:  # noqa: ANN401
    if isinstance(v, np.generic):
        return v.item()
    raise TypeError(f"not JSON-serialisable: {type(v).__name__}")


def done_ids(out: str | Path) -> set[str]:
    """Configurations whose rows are stored in ``out``."""
    d = Path(out) / "rows"
    return {p.stem for p in d.glob("*.json")} if d.is_dir() else set()


def read_rows(out: str | Path) -> list[dict[str, Any]]:
    """Every stored row of the study in ``out``."""
    rows: list[dict[str, Any]] = []
    for p in sorted((Path(out) / "rows").glob("*.json")):
        rows.extend(json.loads(p.read_text()))
    return rows


def run_study(configurations: Iterable[Configuration], out: str | Path, *,
              scheduler: str | None = None, workers: int = 2,
              progress: Callable[[str], None] | None = None,
              baselines_from: str | Path | None = None) -> int:
    """Run every configuration not yet stored in ``out`` on Dask (``scheduler`` address, else
    a ``LocalCluster`` of ``workers`` single-threaded processes); returns the number run.
    ``baselines_from``: an earlier study folder whose cached baseline ensembles are reused
    for the configurations they match (the records are simulated again).
    The design is written to ``OUT/design.json`` first; a store holding another design is
    refused."""
    from dask.distributed import Client, LocalCluster, as_completed

    confs = list(configurations)
    out = Path(out)
    (out / "rows").mkdir(parents=True, exist_ok=True)
    mine = {c.id: json.loads(json.dumps(asdict(c), default=_json_default)) for c in confs}
    dfile = out / "design.json"
    stored = {d["id"]: d for d in json.loads(dfile.read_text())} if dfile.exists() else {}
    clash = sorted(i for i, d in mine.items() if i in stored and stored[i] != d)
    if clash:
        raise ConfigError(f"--out: {out} holds other configurations under the ids "
                          f"{', '.join(clash[:5])}; choose a new folder (or delete it)")
    merged = {**stored, **mine}
    dfile.write_text(json.dumps([merged[i] for i in sorted(merged)], indent=1,
                                sort_keys=True))
    todo = [c for c in confs if c.id not in done_ids(out)]
    if not todo:
        return 0
    if scheduler:
        client = Client(scheduler)
        cluster = None
    else:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
    try:
        reuse = (lambda c: Path(baselines_from) / "cases" / f"{c.id}.pkl") \
            if baselines_from else (lambda c: None)
        futures = {client.submit(run_configuration, c, out / "cases" / f"{c.id}.pkl",
                                 reuse(c), pure=False, key=f"study-{c.id}"): c
                   for c in todo}
        for n, fut in enumerate(as_completed(futures), 1):
            c = futures[fut]
            try:
                rows = fut.result()
            except Exception as exc:  # noqa: BLE001 - the configuration itself failed
                rows = [{"config": c.id, "machine": c.machine, "half": c.half,
                         "record": r.label, "fault_type": r.fault_type,
                         "severity": r.severity, "status": f"failed: {exc}"}
                        for r in c.records]
            _write_rows(out / "rows" / f"{c.id}.json", rows)
            if progress is not None:
                progress(f"{n}/{len(todo)} configurations ({c.id}: "
                         f"{sum(r.get('status') == 'ok' for r in rows)}/{len(rows)} ok)")
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return len(todo)
