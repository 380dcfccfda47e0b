"""``[outputs.diagnosis]``: every case judged as ``geardyn diagnose`` judges its config.

A case of a sweep with this output *is* the record of :func:`geardyn.diagnosis.pipeline.
diagnose` for the case's config: it runs with the config's ``diagnosis.record_seed`` (the
case's ``seed``), over the run length of ``[diagnosis]`` (``t_end_s`` / ``revolutions``;
the sweep's ``[run]`` overrides both the record and its baseline), and is judged by
:func:`~geardyn.diagnosis.pipeline.judge_features` against the **healthy baseline ensemble of
its own config**: ``[diagnosis.ensemble]`` of the config with its faults removed
(:func:`geardyn.diagnosis.faults.healthy_variant`, simulated by
:func:`geardyn.diagnosis.ensemble.simulate_baseline`). The verdict is the one ``geardyn
diagnose`` writes for that config and seed; no other case of the sweep enters it (compare
``[outputs.verdicts]``, which judges the cases against the sweep's own healthy cases).

**Baseline cache.** The baseline depends only on the healthy config and the diagnosis
options, so the cases that share them (a fault and its healthy records at one operating
point) share one simulated ensemble: what the verdict reads of its features (:func:`_slim`)
and its per-order statistics are kept in
``STORE/diagnosis_cache/baseline-<key>.pkl``, ``key`` a SHA-256 of the healthy config, the
``[diagnosis]`` options, the run length and the geardyn version. The first worker that needs
it holds ``<file>.lock`` (:func:`geardyn.sweep.lock.wait_lock`: created exclusively; another
worker waits; a lock whose process is gone is taken over) while it simulates, and writes the
file under a temporary name renamed into place — an interrupted worker leaves no partial
file. A resumed sweep finds the ensembles of its finished cases there. The workers must see
the store's folder to share the cache (a LocalCluster does; a cluster needs a shared file
system, else each host caches in its own copy of the path, or each case simulates its
baseline and says so in its ``message`` where the path cannot be created). A lock left on a
shared file system by a worker of *another* host cannot be checked and is waited for: delete
it by hand once that worker is known to be gone (as the store's own lock).

**Record machine.** ``record_machine = "nominal"`` (default) runs the config as written, as
``geardyn diagnose`` does, with run seed ``diagnosis.record_seed``. ``"fleet"`` runs another
machine of the baseline's fleet: the config perturbed as one ensemble member
(:func:`geardyn.diagnosis.ensemble.member_configs`: speed, load, errors, pins, clearances,
sensors within ``[diagnosis.ensemble]``'s tolerances) with perturbation seed
``SeedSequence([fleet_seed, h])``'s first word, h the first 32 bits of the healthy config's
hash, and run seed ``SeedSequence([record_seed, h])``'s first word (:func:`fleet_run_seed`):
the run seed draws what a run draws (the seed 004 random manufacturing errors, the sensor
noise), so the machines of two healthy configs never share those draws through an equal
``record_seed``; the records of one healthy config and one seed are one machine, healthy or
faulty.

**SNR** of a fault record: ``mean((x_fault − x_healthy)²) / noise_rms²``, x the judged
channel of the faulty machine and of its healthy variant run with the same seed (same sensor
noise and manufacturing errors: they cancel), the power of the fault's signature over the
sensor noise power; 0 for a healthy record. The healthy signal is cached as the baseline is
(``paired-<key>.npy``): a healthy case writes its own channel there, a fault case reads it
or simulates it.

Stored per case (:data:`VARIABLES`, prefix ``diagnosis.``): ``verdict`` (healthy / alarm /
uncertain), ``detected``, ``location``, ``localisation_state``, ``localisation_level``,
``confidence``, ``candidates``, ``expected`` (configured faults' components), ``localised``
and ``planet_named`` (1/0, NaN where undefined: :meth:`geardyn.diagnosis.verdict.Verdict.
summary`), ``first_alarm`` and ``first_margin`` (the strongest detection), ``tests``,
``alpha_per_test``, ``snr``, ``cpu_s`` (the case's CPU time without the baseline),
``baseline_cpu_s`` (the baseline's CPU time when it was simulated) and ``baseline``
(the cache key: cases with one key share one baseline).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import pickle
import time
import uuid
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from geardyn.errors import GeardynError, InputError

#: Folder of the cache inside the store.
CACHE = "diagnosis_cache"

#: Per-case variables (name after ``diagnosis.`` → (is text, attributes)).
VARIABLES: dict[str, tuple[bool, dict[str, str]]] = {
    "verdict": (
        True,
        {
            "long_name": "machine verdict of geardyn diagnose: healthy / alarm "
            "(detected and localised) / uncertain (detected, location uncertain)"
        },
    ),
    "detected": (
        False,
        {
            "units": "1",
            "long_name": "1: a detection indicator above its "
            "threshold (the machine is not healthy); 0 nothing detected",
        },
    ),
    "location": (True, {"long_name": "components the fault is localised to (', '-separated)"}),
    "localisation_state": (True, {"long_name": "none (nothing detected) / localised / uncertain"}),
    "localisation_level": (
        True,
        {
            "long_name": "what the location names: component / planet "
            "set / planet ('' not localised)"
        },
    ),
    "confidence": (False, {"units": "1", "long_name": "posterior probability of the location"}),
    "candidates": (True, {"long_name": "candidates of an uncertain location, most probable first"}),
    "expected": (
        True,
        {"long_name": "components of the config's faults (geardyn.diagnosis.faults.fault_list)"},
    ),
    "localised": (
        False,
        {
            "units": "1",
            "long_name": "1: the verdict's location matches the "
            "configured faults (Verdict.summary 'localised'); 0 not; NaN none",
        },
    ),
    "planet_named": (
        False,
        {"units": "1", "long_name": "1: the faulty planet named alone; 0 not; NaN no planet fault"},
    ),
    "first_alarm": (True, {"long_name": "strongest detection: component and indicator"}),
    "first_margin": (False, {"units": "1", "long_name": "its margin (value / threshold)"}),
    "tests": (False, {"units": "1", "long_name": "tests m of the many-tests correction"}),
    "alpha_per_test": (
        False,
        {"units": "1", "long_name": "per-test false-alarm level α (Šidák 1967)"},
    ),
    "snr": (
        False,
        {
            "units": "1",
            "long_name": "fault signature power over sensor noise "
            "power: mean((x_fault − x_healthy)²)/noise_rms², same seed; 0 healthy",
        },
    ),
    "cpu_s": (
        False,
        {
            "units": "s",
            "long_name": "CPU time of the case (record, paired "
            "healthy run, verdict; not the baseline)",
        },
    ),
    "baseline_cpu_s": (
        False,
        {
            "units": "s",
            "long_name": "CPU time of the case's baseline "
            "ensemble when it was simulated (shared by its key)",
        },
    ),
    "baseline": (True, {"long_name": "key of the baseline ensemble (cases with one key share it)"}),
}


#: ``[diagnosis]`` options that do not change the baseline ensemble's simulation or features
#: (the record's seed; how thresholds pool spreads), left out of its cache key.
NOT_IN_BASELINE = ("record_seed", "family_floor")


def _hash(obj: Any) -> str:  # noqa: ANN401
    text = json.dumps(obj, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()


@dataclass
class Record:
    """What a case of a diagnosis sweep runs: the record's config (the case config or a
    machine of its fleet), the healthy config of its baseline, the options, the run length
    and the keys of the caches."""

    config: Any
    case_config: Any
    healthy: Any
    opts: Any
    run_length: dict[str, float | None]
    healthy_key: str
    baseline_key: str
    run_seed: int
    """Seed of the record's run (:func:`fleet_run_seed` for fleet machines, else the case's
    seed)."""


def fleet_run_seed(record_seed: int, healthy_key: str) -> int:
    """Run seed of the fleet machine ``record_seed`` of the healthy config with hash
    ``healthy_key`` (module docstring, "Record machine")."""
    h = int(healthy_key[:8], 16)
    return int(np.random.SeedSequence([int(record_seed), h]).generate_state(1)[0])


def record(
    cfg: Any,
    seed: int,
    run: dict[str, Any],
    options: dict[str, Any],  # noqa: ANN401
) -> Record:
    """The :class:`Record` of a case: ``cfg`` the case's validated config, ``seed`` its run
    seed (the config's ``diagnosis.record_seed``), ``run`` the sweep's ``[run]`` overrides,
    ``options`` the ``[outputs.diagnosis]`` table."""
    from geardyn import __version__
    from geardyn.diagnosis import pipeline as pipe
    from geardyn.diagnosis.faults import healthy_variant

    opts = pipe.options(cfg)
    pipe.check_ready(cfg, opts)
    given = {k: v for k, v in run.items() if v is not None}
    run_length = (
        {"t_end_s": given.get("t_end_s"), "revolutions": given.get("revolutions")}
        if given
        else pipe._run_length(cfg, opts)
    )
    healthy = healthy_variant(cfg)
    # the record's seed is no part of the baseline: records of any seed share it
    data = healthy.model_dump(mode="json")
    if data.get("diagnosis"):
        for name in NOT_IN_BASELINE:
            data["diagnosis"].pop(name, None)
    h_key = _hash(data)
    o = opts.model_dump(mode="json")
    for name in NOT_IN_BASELINE:
        o.pop(name, None)
    b_key = _hash({"healthy": h_key, "options": o, "run": run_length, "version": __version__})[:24]
    rec_cfg, run_seed = cfg, int(seed)
    if options.get("record_machine") == "fleet":
        rec_cfg = fleet_machine(cfg, opts, seed, fleet_seed(options, h_key))
        run_seed = fleet_run_seed(seed, h_key)
    return Record(rec_cfg, cfg, healthy, opts, run_length, h_key, b_key, run_seed)


def fleet_seed(options: dict[str, Any], healthy_key: str) -> int:
    """Perturbation seed of the record machines of one healthy config (module docstring)."""
    h = int(healthy_key[:8], 16)
    ss = np.random.SeedSequence([int(options.get("fleet_seed", 0)), h])
    return int(ss.generate_state(1)[0])


def fleet_machine(cfg: Any, opts: Any, seed: int, perturbation_seed: int) -> Any:  # noqa: ANN401
    """``cfg`` drawn as one machine of the baseline's fleet: the perturbations of
    :func:`geardyn.diagnosis.ensemble.member_configs` with run seed ``seed`` and perturbation
    seed ``perturbation_seed`` (one measurement)."""
    from geardyn.diagnosis.ensemble import member_configs

    ens = opts.ensemble.model_copy(update={"measurements_per_run": 1})
    spec = opts.model_copy(update={"baseline_seeds": [int(seed)], "ensemble": ens})
    return member_configs(cfg, spec, seed=perturbation_seed)[0].config


def _cache_dir(store: str | None) -> Path | None:
    if not store:
        return None
    d = Path(store) / CACHE
    try:
        d.mkdir(exist_ok=True)
    except OSError:
        return None
    return d


def _write_atomic(path: Path, write: Any) -> None:  # noqa: ANN401 - a callable(file)
    """``write(file)`` into a temporary name beside ``path``, renamed into place."""
    tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex[:8]}.tmp")
    try:
        with tmp.open("wb") as fh:
            write(fh)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


def _slim(feats: Any, opts: Any) -> Any:  # noqa: ANN401 - Features, DiagnosisSpec
    """What the verdict reads of a baseline member's features (:func:`geardyn.diagnosis.
    pipeline.judge_features`: the indicator table, the envelope spectrum of the bearing
    evidence, the components; the TSAs only for ``reference_residuals``): the cache keeps a
    tenth of the size (12 MB → 1 MB for a 12 s Wang 2010 member)."""
    from dataclasses import replace

    if opts.reference_residuals:
        return feats
    return replace(feats, tsa={}, block_tsa={}, order_spectrum=None, kurtogram=None, markers=None)


def _simulate_baseline(rec: Record) -> dict[str, Any]:
    """Features and compact per-order statistics of every member of the baseline ensemble of
    ``rec.healthy`` (as :func:`geardyn.studies.runner.run_configuration` and
    :func:`geardyn.diagnosis.pipeline._judged_run` reduce them), with the CPU time."""
    from geardyn.diagnosis import pipeline as pipe
    from geardyn.diagnosis.ensemble import simulate_baseline

    t0 = time.process_time()
    feats, blocks = [], []
    for member, ds in simulate_baseline(rec.healthy, rec.opts, rec.run_length):
        what = f"healthy baseline {member.label}"
        pipe._check_status(ds, what)
        ch = pipe._channel(ds, rec.opts.channel, what)
        feats.append(_slim(pipe._features(ds, rec.healthy, ch, rec.opts), rec.opts))
        b = pipe._blocks(ds, rec.healthy, ch, rec.opts).compact()
        b.run = member.run
        blocks.append(b)
        del ds
    return {"features": feats, "blocks": blocks, "cpu_s": time.process_time() - t0}


def baseline(rec: Record, store: str | None) -> tuple[dict[str, Any], bool, str]:
    """The baseline ensemble of ``rec`` from the store's cache, or simulated (and cached);
    returns it, whether it was simulated here, and a note ('' or why the cache was not
    used)."""
    from geardyn.sweep.lock import wait_lock

    d = _cache_dir(store)
    if d is None:
        return _simulate_baseline(rec), True, "baseline not cached (store folder not writable)"
    path = d / f"baseline-{rec.baseline_key}.pkl"
    with wait_lock(path):
        if path.exists():
            with path.open("rb") as fh:
                base = pickle.load(fh)  # noqa: S301 - the sweep's own cache
            if "error" in base:  # a baseline that cannot be simulated fails every case fast
                raise InputError(f"{base['error']} (cached: delete '{path}' to simulate it again)")
            return base, False, ""
        try:
            base = _simulate_baseline(rec)
        except (GeardynError, ValueError, FloatingPointError) as exc:
            msg = f"healthy baseline ensemble: {type(exc).__name__}: {exc}"
            _write_atomic(path, lambda fh: pickle.dump({"error": msg}, fh))
            raise InputError(msg) from None
        _write_atomic(path, lambda fh: pickle.dump(base, fh, protocol=pickle.HIGHEST_PROTOCOL))
        return base, True, ""


def _paired_path(
    rec: Record, store: str | None, seed: int, options: dict[str, Any], channel: str
) -> Path | None:
    d = _cache_dir(store)
    if d is None:
        return None
    key = _hash(
        {
            "healthy": rec.healthy_key,
            "seed": int(seed),
            "run": rec.run_length,
            "record_machine": options.get("record_machine"),
            "fleet_seed": options.get("fleet_seed"),
            "channel": channel,
        }
    )[:24]
    return d / f"paired-{key}.npy"


def _save(path: Path, x: np.ndarray) -> None:
    _write_atomic(path, lambda fh: np.save(fh, x))


def paired_healthy(
    rec: Record,
    store: str | None,
    seed: int,
    options: dict[str, Any],
    channel: str,
    own: np.ndarray | None = None,
) -> np.ndarray:
    """The judged channel of the healthy variant of the record's machine run with ``seed``
    (cached; ``own``: the case is that healthy run itself — its channel is stored)."""
    from geardyn.run import run_simulation
    from geardyn.sweep.lock import wait_lock

    path = _paired_path(rec, store, seed, options, channel)
    if own is not None:
        if path is not None and not path.exists():
            with wait_lock(path):
                if not path.exists():
                    _save(path, own)
        return own
    if path is not None and path.exists():
        return np.load(path)

    def simulate() -> np.ndarray:
        cfg = rec.healthy
        if options.get("record_machine") == "fleet":
            cfg = fleet_machine(cfg, rec.opts, seed, fleet_seed(options, rec.healthy_key))
        ds = run_simulation(cfg, seed=rec.run_seed, **rec.run_length)
        return np.asarray(ds[f"sensors.{channel}"].values, float)

    if path is None:
        return simulate()
    with wait_lock(path):
        if path.exists():
            return np.load(path)
        x = simulate()
        _save(path, x)
        return x


def _noise_rms(cfg: Any, channel: str) -> float:  # noqa: ANN401
    for s in getattr(cfg, "sensors", []):
        if s.name == channel:
            return float(s.noise_rms)
    return math.nan


def _flag(v: Any) -> float:  # noqa: ANN401
    return float(bool(v)) if isinstance(v, bool | np.bool_) else math.nan


def judge(
    ds: Any,
    rec: Record,
    seed: int,
    options: dict[str, Any],  # noqa: ANN401
    store: str | None,
    cpu0: float,
) -> tuple[dict[str, Any], str]:
    """The ``diagnosis.*`` arrays of a case (module docstring) from its record ``ds``, and a
    note for the case's message ('' when none). ``cpu0``: the case's CPU clock at its
    start."""
    from geardyn.diagnosis import pipeline as pipe
    from geardyn.diagnosis.faults import fault_list

    base, simulated, note = baseline(rec, store)
    cpu_base = float(base["cpu_s"]) if simulated else 0.0
    opts, cfg = rec.opts, rec.config
    ch = pipe._channel(ds, opts.channel, "record")
    x = np.asarray(ds[f"sensors.{ch}"].values, float)
    expected = fault_list(cfg)
    if not expected:
        paired_healthy(rec, store, seed, options, ch, own=x)
        snr = 0.0
    else:
        h = paired_healthy(rec, store, seed, options, ch)
        noise = _noise_rms(cfg, ch)
        snr = (
            float(np.mean((x - h) ** 2)) / noise**2
            if h.shape == x.shape and noise > 0
            else math.nan
        )
    feat = pipe._features(ds, cfg, ch, opts)
    rb = pipe._blocks(ds, cfg, ch, opts).compact()
    verdict = pipe.judge_features(
        cfg,
        opts,
        base["features"],
        feat,
        baseline_blocks=base["blocks"],
        record_blocks=rb,
        expected=expected,
    )
    s = verdict.summary()
    loc = verdict.localisation or {}
    det = verdict.detection or {}
    alarms = det.get("alarms") or []
    values: dict[str, Any] = {
        "verdict": str(s.get("verdict") or ""),
        "detected": float(bool(det.get("detected", False))),
        "location": ", ".join(loc.get("components") or []),
        "localisation_state": str(loc.get("state") or ""),
        "localisation_level": str(loc.get("level") or ""),
        "confidence": (float(loc["confidence"]) if loc.get("confidence") is not None else math.nan),
        "candidates": ", ".join(s.get("candidates") or []),
        "expected": ", ".join(s.get("expected") or []),
        "localised": _flag(s.get("localised")),
        "planet_named": _flag(s.get("planet_named")),
        "first_alarm": (f"{alarms[0]['component']} {alarms[0]['indicator']}" if alarms else ""),
        "first_margin": float(alarms[0]["margin"]) if alarms else math.nan,
        "tests": float(det.get("tests", 0)),
        "alpha_per_test": float(det.get("alpha_per_test", math.nan)),
        "snr": snr,
        "cpu_s": max(time.process_time() - cpu0 - cpu_base, 0.0),
        "baseline_cpu_s": float(base["cpu_s"]),
        "baseline": rec.baseline_key,
    }
    arrays = {
        f"diagnosis.{k}": (np.asarray(v, dtype=object if VARIABLES[k][0] else float), {}, [], {})
        for k, v in values.items()
    }
    return arrays, note
