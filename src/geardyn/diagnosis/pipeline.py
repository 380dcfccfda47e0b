"""From a config to a verdict: healthy baseline, record, thresholds, verdict.json, report.html.

:func:`diagnose` simulates the healthy variant of a config (every fault removed) for each
baseline seed and the configured machine (its faults included) with the record seed, measures
them with the config's ``[[sensors]]``, extracts the indicators per component
(:func:`geardyn.diagnosis.features.features_from_result`), sets thresholds from the pooled
baseline (:mod:`geardyn.diagnosis.baseline`), judges the record
(:mod:`geardyn.diagnosis.verdict`) and writes ``verdict.json`` and ``report.html``.
:func:`diagnose_files` does the same from result files (measured or simulated NetCDF in the
result layout of docs/results.md).

Options come from the config's ``[diagnosis]`` section (:class:`~geardyn.config.diagnosis.
DiagnosisSpec`); keyword arguments that are not None override them.
"""

from __future__ import annotations

import math
import tempfile
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypedDict, Unpack

import xarray as xr
from pydantic import ValidationError

from geardyn.config.diagnosis import DiagnosisSpec
from geardyn.diagnosis.baseline import ThresholdRule, thresholds
from geardyn.diagnosis.faults import ConfiguredFault, fault_list, healthy_variant
from geardyn.diagnosis.report import write_report
from geardyn.diagnosis.verdict import Verdict, judge
from geardyn.errors import ConfigError, InputError

if TYPE_CHECKING:
    from geardyn.config.loader import GeardynConfig
    from geardyn.diagnosis.ensemble import Member
    from geardyn.diagnosis.features import Features
    from geardyn.diagnosis.isolation import IsolationBlocks
    from geardyn.kinematics import CharacteristicFrequencies

#: ``progress(message, fraction)``: what is being done and the overall fraction done (0–1).
Progress = Callable[[str, float], None]


class Overrides(TypedDict, total=False):
    """Keyword overrides of ``[diagnosis]`` taken by :func:`diagnose`, :func:`diagnose_files`
    and :func:`geardyn.diagnosis.measured.diagnose_record` (None: the config's value). The
    names are the DiagnosisSpec fields but for ``k`` (``threshold_k``) and ``n_blocks``
    (``blocks``); :data:`SIMULATION_ONLY` ones apply where healthy runs are simulated."""

    channel: str | None
    reference: str | None
    k: float | None
    false_alarm_probability: float | None
    sigma_floor: float | None
    n_blocks: int | None
    skip_s: float | None
    reference_residuals: bool | None
    baseline_seeds: Sequence[int] | None
    record_seed: int | None
    t_end_s: float | None
    revolutions: float | None


#: Override keywords whose DiagnosisSpec field has another name.
_FIELD = {"k": "threshold_k", "n_blocks": "blocks"}
#: Overrides that set the simulated runs (seeds, run length).
SIMULATION_ONLY = ("baseline_seeds", "record_seed", "t_end_s", "revolutions")


def options_from(cfg: GeardynConfig, overrides: Mapping[str, Any], caller: str,
                 refused: Sequence[str] = ()) -> DiagnosisSpec:
    """:func:`options` from the :class:`Overrides` keywords of ``caller``; a keyword that is
    not an override, or one of ``refused``, is a TypeError naming it (as Python's own for
    an unexpected keyword)."""
    bad = sorted(k for k in overrides if k not in Overrides.__annotations__ or k in refused)
    if bad:
        raise TypeError(f"{caller}() got unexpected keyword argument(s) {', '.join(bad)}")
    return options(cfg, **{_FIELD.get(k, k): v for k, v in overrides.items()})


def options(cfg: GeardynConfig, **overrides: Any) -> DiagnosisSpec:
    """``[diagnosis]`` of ``cfg`` (defaults if absent) with the non-None ``overrides``
    (DiagnosisSpec field names) applied and validated; a bad value raises ConfigError naming
    the field, e.g. ``diagnosis.threshold_k``."""
    base = getattr(cfg, "diagnosis", None) or DiagnosisSpec()
    data = base.model_dump()
    data.update({k: (list(v) if isinstance(v, tuple) else v)
                 for k, v in overrides.items() if v is not None})
    try:
        return DiagnosisSpec.model_validate(data)
    except ValidationError as exc:
        from geardyn.config.loader import format_validation_error

        raise ConfigError(
            [f"diagnosis.{m}" for m in format_validation_error(exc, data)]
        ) from None


def check_output_dir(out_dir: str | Path) -> Path:
    """Create ``out_dir`` if needed and check that a file can be written there (before any
    simulation runs); InputError otherwise."""
    out = Path(out_dir)
    try:
        out.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=out, prefix=".geardyn-write-test"):
            pass
    except OSError as exc:
        raise InputError(f"out: cannot write to '{out}': {exc.strerror or exc}") from None
    return out


def _say(progress: Progress | None, message: str, fraction: float) -> None:
    if progress is not None:
        progress(message, min(1.0, max(0.0, fraction)))


def _check_status(ds: xr.Dataset, what: str) -> None:
    status = str(ds.attrs.get("status", "ok"))
    if status != "ok":
        raise InputError(
            f"{what}: simulation status '{status}' ({ds.attrs.get('diagnosis', '')}); a "
            "diagnosis needs a run at a steady operating point (check the speed profile, "
            "t_end_s and skip_s)"
        )


def _channel(ds: xr.Dataset, wanted: str | None, what: str) -> str:
    from geardyn.results import channel, channels

    if wanted is not None:
        return channel(ds, wanted).name
    names = channels(ds)
    if not names:
        raise InputError(
            f"{what}: the result has no sensor channel; add [[sensors]] to the config "
            "(e.g. an accelerometer on the ring or a bearing)"
        )
    return names[0]


def check_ready(cfg: GeardynConfig, opts: DiagnosisSpec) -> None:
    """What a simulated diagnosis needs, checked before any run (so that a missing piece costs
    no simulation): a dynamic model to simulate (:func:`geardyn.run.simulated_model`),
    ``[[sensors]]`` with at least one signal sensor (a tacho alone gives no vibration
    signal), ``diagnosis.channel`` (``--channel``) among them and ``diagnosis.reference``
    (``--reference``) a turning shaft of the model. Raises ConfigError naming
    the section or field. The run length options are checked first (:func:`_run_length`)."""
    from geardyn.run import simulated_model

    _run_length(cfg, opts)
    simulated_model(cfg)
    signal = [s.name for s in getattr(cfg, "sensors", None) or [] if s.kind != "tacho"]
    if not signal:
        raise ConfigError(
            "sensors: diagnose needs at least one signal sensor in [[sensors]] (accelerometer, "
            "encoder or transmission_error; a tacho gives no vibration signal), e.g. "
            "[[sensors]] name = \"acc\", kind = \"accelerometer\", location = a bearing or "
            "\"ring\" (docs/config.md, `sensors`; the `geardyn init` templates have one)")
    if opts.channel is not None and opts.channel not in signal:
        raise ConfigError(f"diagnosis.channel (--channel): '{opts.channel}' is not a signal "
                          f"sensor of the config (signal sensors: {', '.join(signal)})")
    if opts.reference is not None:
        from geardyn.config.sensors import model_names

        shafts = model_names(cfg)[0] or set()
        frame = getattr(cfg, "frame", None)
        if opts.reference not in shafts or opts.reference == frame:
            raise ConfigError(f"diagnosis.reference (--reference): '{opts.reference}' is not a "
                              f"turning shaft of the model (shafts: "
                              f"{', '.join(sorted(shafts - {frame}))})")


def _run_length(cfg: GeardynConfig, opts: DiagnosisSpec) -> dict[str, float | None]:
    """``run_simulation`` keywords of the run length, checked against the simulated model."""
    # t_end_s sets the length of a lumped run: planetary model or [dynamics] mechanism model
    planetary = getattr(cfg, "planetary_dynamics", None) is not None or (
        getattr(cfg, "dynamics", None) is not None
        and getattr(cfg, "transmission", None) is None)
    if opts.t_end_s is not None and not planetary:
        raise ConfigError("diagnosis.t_end_s (--t-end): applies to the planetary model; the FE "
                          "transmission's run length is set by diagnosis.revolutions "
                          "(--revolutions)")
    if opts.revolutions is not None and planetary:
        raise ConfigError("diagnosis.revolutions (--revolutions): applies to the FE "
                          "transmission; the planetary run length is diagnosis.t_end_s (--t-end)")
    return {"t_end_s": opts.t_end_s, "revolutions": opts.revolutions}


def operating_frequencies(
    cfg: GeardynConfig, ds: xr.Dataset, reference: str | None = None, skip_s: float = 0.0
) -> CharacteristicFrequencies:
    """Characteristic frequencies at the record's mean input speeds (after ``skip_s``), orders
    of ``reference`` (default: the first input); the config's input speeds where the result
    lacks a shaft."""
    from geardyn.kinematics import analyze_kinematics, characteristic_frequencies

    inputs = dict(cfg.input_speeds_rpm)
    shafts = [str(s) for s in ds["shaft"].values] if "shaft" in ds.coords else []
    if "speed_rpm" in ds and "time" in ds.coords:
        steady = ds["speed_rpm"].where(ds["time"] >= skip_s, drop=True)
        for link in inputs:
            if link in shafts and steady.sizes.get("time", 0):
                rpm = float(steady.sel(shaft=link).mean())
                if math.isfinite(rpm) and rpm != 0.0:
                    inputs[link] = rpm
    kin = analyze_kinematics(cfg)
    ref = reference if reference in kin.graph.links else None
    return characteristic_frequencies(kin, inputs, order_reference=ref)


def _features(ds: xr.Dataset, cfg: GeardynConfig, channel: str, opts: DiagnosisSpec
              ) -> Features:
    from geardyn.diagnosis.features import features_from_result

    return features_from_result(ds, cfg, channel, reference=opts.reference,
                                skip_s=opts.skip_s, n_blocks=opts.blocks)


def _blocks(ds: xr.Dataset, cfg: GeardynConfig, channel: str, opts: DiagnosisSpec
            ) -> IsolationBlocks:
    from geardyn.diagnosis.isolation import isolation_blocks

    # per-order statistics only (what the evidence needs): no record-long rows in memory
    return isolation_blocks(ds, cfg, channel, reference=opts.reference, skip_s=opts.skip_s,
                            rows=False)


def _judged_run(group: Sequence[Member], cfg: GeardynConfig, opts: DiagnosisSpec,
                run_length: dict[str, float | None], progress: Progress | None, runs: int
                ) -> list[tuple[Member, Features, IsolationBlocks]]:
    """One dynamic run of the baseline ensemble simulated, measured by each of its members
    and reduced to its features and isolation blocks (a task of :func:`diagnose`)."""
    from geardyn.diagnosis.ensemble import simulate_run

    judged = []
    for member, ds in simulate_run(group, run_length, progress, runs):
        what = f"healthy baseline {member.label}"
        _check_status(ds, what)
        ch = _channel(ds, opts.channel, what)
        blocks = _blocks(ds, cfg, ch, opts)
        blocks.run = member.run
        judged.append((member, _features(ds, cfg, ch, opts), blocks))
        del ds
    return judged


def _run_signature(ds: xr.Dataset) -> tuple | None:
    """Model, time grid and initial shaft speeds of a simulated run (None for other files):
    runs with one signature follow one operating profile revolution by revolution."""
    from geardyn.results import is_result

    if not is_result(ds) or ds.attrs.get("model") not in ("planetary", "transmission"):
        return None
    t = ds["time"].values
    w0 = tuple(round(float(v), 6) for v in ds["speed"].isel(time=0).values)
    return (str(ds.attrs["model"]), t.size, round(float(t[0]), 9), round(float(t[-1]), 9), w0)


def judge_features(
    cfg: GeardynConfig,
    opts: DiagnosisSpec,
    baseline: list[Features],
    record: Features,
    *,
    baseline_blocks: Sequence[IsolationBlocks] | None = None,
    record_blocks: IsolationBlocks | None = None,
    aligned: bool = True,
    info: tuple[dict[str, Any], dict[str, Any]] | None = None,
    expected: list[ConfiguredFault] | None = None,
) -> Verdict:
    """Verdict of ``record`` against the healthy ``baseline`` features: reference residuals
    (if asked), the per-test level from the false-alarm probability (Šidák over every
    detection indicator and isolation statistic, :mod:`geardyn.diagnosis.localise`),
    thresholds, detection per component, isolation evidence (:mod:`geardyn.diagnosis.
    isolation`: coherent SDR per own-angle, transmission-error and planet-separated domain
    from the per-revolution blocks, fault-band energy per bearing line) and localisation.
    ``aligned`` is accepted for compatibility and ignored: the evidence compares each record
    with the baselines' mean revolution, which holds for baselines at other speeds and loads
    too."""

    from geardyn.diagnosis.features import with_reference_residuals
    from geardyn.diagnosis.isolation import bearing_evidence, evidence_tests, sdr_evidence
    from geardyn.diagnosis.localise import localise, per_test_level
    from geardyn.diagnosis.verdict import record_values

    del aligned
    if opts.reference_residuals:
        baseline, record = with_reference_residuals(baseline, record)
    p_fa = float(getattr(opts, "false_alarm_probability", 0.01))
    confidence = float(getattr(opts, "localisation_confidence", 0.95))
    tables = [f.table for f in baseline]
    blocks_ok = (record_blocks is not None and baseline_blocks is not None
                 and len(baseline_blocks) >= 2)
    # the dynamic run of each baseline member: measurements of one run share its dynamics
    runs = ([getattr(b, "run", None) for b in baseline_blocks]
            if baseline_blocks is not None and len(baseline_blocks) == len(baseline) else None)
    if runs is not None and None in runs:
        runs = None
    # m tests: every usable (component, indicator, channel) threshold the record has a value
    # for, and every isolation statistic
    th0 = thresholds(tables, ThresholdRule(sigma_floor=opts.sigma_floor), runs)
    keys = set(map(tuple, record_values(record.table)[["component", "kind", "indicator",
                                                        "channel"]].to_numpy().tolist()))
    m_det = sum(1 for r in th0[th0["usable"]][["component", "kind", "indicator", "channel"]]
                .to_numpy().tolist() if tuple(r) in keys)
    m = max(m_det + evidence_tests(baseline, record, record_blocks if blocks_ok else None), 1)
    # an explicit factor overrides the stated probability
    alpha, k, p_fa = per_test_level(p_fa, opts.threshold_k, m)
    pool = bool(getattr(opts, "family_floor", True))
    rule = ThresholdRule(k=k, sigma_floor=opts.sigma_floor, family_floor=pool)
    th = thresholds(tables, rule, runs)
    items = record.components.items if record.components is not None else []
    verdict = judge(record.table, th, rule, machine=cfg.name,
                    baseline=(info or ({}, {}))[0], record_info=(info or ({}, {}))[1],
                    expected_faults=expected, components=[(c.name, c.kind) for c in items],
                    notes=record.notes)
    verdict.stages = {c.name: c.stage for c in items if c.stage}
    evidence = bearing_evidence(baseline, record, alpha, runs=runs)
    if blocks_ok:
        evidence.update(sdr_evidence(baseline_blocks, record_blocks, alpha, pool_family=pool))
    localise(verdict, evidence, record.components, alpha=alpha, false_alarm_probability=p_fa,
             tests=m, confidence=confidence)
    return verdict


def _finish(
    cfg: GeardynConfig,
    out: Path,
    opts: DiagnosisSpec,
    baseline: list[Features],
    record: Features,
    record_ds: xr.Dataset,
    channel: str,
    info: tuple[dict[str, Any], dict[str, Any]],
    expected: list[ConfiguredFault] | None,
    blocks: tuple[list[IsolationBlocks], IsolationBlocks] | None = None,
    aligned: bool = True,
) -> Verdict:
    """Verdict (:func:`judge_features`), verdict.json and report.html from the features."""
    verdict = judge_features(cfg, opts, baseline, record,
                             baseline_blocks=blocks[0] if blocks else None,
                             record_blocks=blocks[1] if blocks else None, aligned=aligned,
                             info=info, expected=expected)
    from geardyn.diagnosis.verdict import provenance

    verdict.provenance = {**provenance(cfg), **verdict.provenance}
    verdict.write(out)
    shaft = str(record_ds[f"sensors.{channel}"].attrs.get("shaft", "")) or None
    freqs = operating_frequencies(cfg, record_ds, opts.reference or shaft, opts.skip_s)
    write_report(out, verdict, record, healthy=baseline[0], freqs=freqs, record_ds=record_ds,
                 channel=channel)
    return verdict


def diagnose(
    cfg: GeardynConfig,
    out_dir: str | Path,
    *,
    progress: Progress | None = None,
    workers: int | None = 1,
    **overrides: Unpack[Overrides],
) -> Verdict:
    """Simulate the healthy baseline and the faulty record of ``cfg``, judge the record and
    write ``out_dir/verdict.json`` and ``out_dir/report.html``.

    ``workers``: processes simulating the baseline runs (:mod:`geardyn.diagnosis.parallel`;
    None: one per core; the record runs in this process meanwhile); the verdict is the same
    for any number.

    Defaults from ``[diagnosis]`` (baseline seeds 0, 1, 2; record seed 100; k = 3; σ floor
    5 % of |mean|; 4 blocks; the first sensor channel). ``t_end_s`` [s] (planetary model) or
    ``revolutions`` (FE transmission) override the run length, ``skip_s`` [s] is the start
    transient discarded; ``reference_residuals`` adds the
    RR indicators of :func:`geardyn.diagnosis.features.with_reference_residuals`. Raises
    InputError when the output directory is not writable (before any simulation), a run does
    not end with status ``ok`` or the result has no sensor channel.
    """
    from geardyn.diagnosis.ensemble import baseline_runs
    from geardyn.diagnosis.parallel import check_workers, result, submit, worker_pool
    from geardyn.run import run_simulation

    n_workers = check_workers(workers)
    opts = options_from(cfg, overrides, "diagnose")
    check_ready(cfg, opts)
    out = check_output_dir(out_dir)
    if opts.record_seed in opts.baseline_seeds:
        raise ConfigError(f"diagnosis.record_seed: {opts.record_seed} is also a baseline seed "
                          f"{opts.baseline_seeds}; the record must be an independent run")
    run_length = _run_length(cfg, opts)
    groups = baseline_runs(healthy_variant(cfg), opts)
    runs = len(groups)
    n = runs + 1

    def tick(message: str, f: float) -> None:
        _say(progress, message, f * runs / n)

    what = f"record (configured faults), seed {opts.record_seed}"
    with worker_pool(n_workers, runs) as pool:
        # the baseline runs on the workers (none: here, in order) while the record runs here
        tasks = [submit(pool, _judged_run, (g, cfg, opts, run_length,
                                           tick if pool is None else None, runs))
                 for g in groups]
        judged = [result(t) for t in tasks] if pool is None else []
        rec_ds = run_simulation(cfg, seed=opts.record_seed, **run_length,
                                progress=lambda f: _say(progress, f"simulating {what}",
                                                        (len(judged) + 0.9 * f) / n))
        _check_status(rec_ds, what)
        ch = _channel(rec_ds, opts.channel, what)
        _say(progress, f"indicators of the {what}", (len(judged) + 0.95) / n)
        record = _features(rec_ds, cfg, ch, opts)
        rec_blocks = _blocks(rec_ds, cfg, ch, opts)
        if pool is not None:
            for t in tasks:
                _say(progress, f"healthy baseline run {len(judged) + 1}/{runs} on "
                     f"{min(n_workers, runs)} workers", (len(judged) + 1) / n)
                judged.append(result(t))
    members = [m for run in judged for m, _, _ in run]
    feats = [f for run in judged for _, f, _ in run]
    blocks = [b for run in judged for _, _, b in run]
    drawn = [{"label": m.label, "seed": m.seed, **m.values} for m in members]
    _say(progress, "verdict and report", 0.99)
    info = ({"seeds": list(opts.baseline_seeds), "blocks": opts.blocks, **run_length,
             "skip_s": opts.skip_s, "members": drawn},
            {"seed": opts.record_seed, **run_length})
    verdict = _finish(cfg, out, opts, feats, record, rec_ds, ch, info, fault_list(cfg),
                      blocks=(blocks, rec_blocks), aligned=True)
    _say(progress, "done", 1.0)
    return verdict


def _open(path: str | Path, what: str) -> xr.Dataset:
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{what}: file '{p}' does not exist")
    try:
        return xr.load_dataset(p)
    except (OSError, ValueError) as exc:
        raise InputError(f"{what}: cannot read '{p}' as NetCDF: {exc}") from None


def diagnose_files(
    baseline_paths: Sequence[str | Path],
    record_path: str | Path,
    cfg: GeardynConfig,
    out_dir: str | Path,
    *,
    progress: Progress | None = None,
    **overrides: Unpack[Overrides],
) -> Verdict:
    """Judge the result file ``record_path`` against the healthy result files
    ``baseline_paths`` (NetCDF in the result layout, e.g. from ``geardyn simulate`` or a
    measurement converted to it); ``cfg`` describes the machine (kinematics). Writes
    ``out_dir/verdict.json`` and ``out_dir/report.html``; the configured faults of ``cfg``
    are not assumed to be those of the record (expected faults unknown)."""
    if not baseline_paths:
        raise InputError("baseline: give at least one healthy result file (--baseline)")
    opts = options_from(cfg, overrides, "diagnose_files", refused=SIMULATION_ONLY)
    out = check_output_dir(out_dir)
    n = len(baseline_paths) + 1
    feats = []
    blocks: list[IsolationBlocks] = []
    starts: list[tuple | None] = []
    for i, path in enumerate(baseline_paths):
        what = f"baseline file '{path}'"
        _say(progress, f"indicators of {what}", i / n)
        ds = _open(path, "baseline")
        ch = _channel(ds, opts.channel, what)
        feats.append(_features(ds, cfg, ch, opts))
        blocks.append(_blocks(ds, cfg, ch, opts))
        starts.append(_run_signature(ds))
    _say(progress, f"indicators of record '{record_path}'", (n - 1) / n)
    rec_ds = _open(record_path, "record")
    ch = _channel(rec_ds, opts.channel, f"record '{record_path}'")
    record = _features(rec_ds, cfg, ch, opts)
    rec_blocks = _blocks(rec_ds, cfg, ch, opts)
    info = ({"files": [str(p) for p in baseline_paths], "blocks": opts.blocks,
             "skip_s": opts.skip_s}, {"file": str(record_path)})
    # revolution-by-revolution comparison only for simulated runs of one operating profile
    aligned = None not in starts and len(set(starts + [_run_signature(rec_ds)])) == 1
    verdict = _finish(cfg, out, opts, feats, record, rec_ds, ch, info, None,
                      blocks=(blocks, rec_blocks), aligned=aligned)
    _say(progress, "done", 1.0)
    return verdict
