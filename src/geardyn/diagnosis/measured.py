"""Diagnosis of measured records: ``geardyn diagnose CONFIG --record FILE [--baseline FILE …]``.

The record (any format :func:`geardyn.io.read_record` reads, mapped by the config's
``[measurement]`` section, or a geardyn result file) is judged against healthy baselines that
are measured files, simulated runs of the healthy machine (the ensemble of
:func:`geardyn.diagnosis.ensemble.simulate_baseline`, as ``geardyn diagnose`` without files),
or both. Every record goes through the same feature extraction
(:func:`geardyn.diagnosis.features.features_from_result`, :func:`geardyn.diagnosis.isolation.
isolation_blocks`) and the same judgement (:func:`geardyn.diagnosis.pipeline.judge_features`),
so a measured record gives the verdict.json and report.html of a simulated one.

When both kinds of baseline are given, each simulated baseline channel is scaled to the
measured healthy level: by the ratio of the median RMS of the measured baselines' channel to
the median RMS of the simulated ones (a transfer path or sensitivity the model does not know
scales the whole channel; the shape of its content is what the simulation contributes).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Unpack

import numpy as np
import xarray as xr

from geardyn.errors import InputError

if TYPE_CHECKING:
    from geardyn.config.loader import GeardynConfig
    from geardyn.diagnosis.pipeline import Overrides, Progress
    from geardyn.diagnosis.verdict import Verdict


def load_record(path: str | Path, cfg: GeardynConfig, what: str) -> xr.Dataset:
    """A record file in the result layout: a geardyn result as it is, any other file through
    the config's ``[measurement]`` mapping (an error saying so when the config has none)."""
    from geardyn.io import read_record
    from geardyn.io.record import _geardyn_result

    p = Path(path)
    if not p.is_file():
        raise InputError(f"{what}: file '{p}' does not exist")
    if p.suffix.lower() in (".nc", ".netcdf"):  # a result or a NetCDF record: readable?
        import xarray as xr

        try:
            xr.open_dataset(p).close()
        except Exception as exc:  # noqa: BLE001 - corrupt or not NetCDF at all
            raise InputError(f"{what}: cannot read '{p}' as NetCDF: {exc}") from None
    ds = _geardyn_result(p)
    if ds is not None:
        return ds
    if getattr(cfg, "measurement", None) is None:
        raise InputError(f"{what}: '{p}' is a measured file; map its channels onto the model in "
                         "the config's [measurement] section ([[measurement.channels]]: source, "
                         "name, kind, location, sensitivity; docs/measured.md)")
    return read_record(p, cfg=cfg)


def record_channel(ds: xr.Dataset, wanted: str | None, what: str) -> str:
    """The channel to diagnose: ``wanted``, else the first signal channel (not a tacho)."""
    from geardyn.results import channel, channels

    measured = ds.attrs.get("model") == "measured"
    if wanted is not None:
        names = channels(ds)
        if wanted not in names:
            hint = ("map it in [[measurement.channels]]" if measured else
                    "add it to [[sensors]]")
            raise InputError(f"{what}: channel '{wanted}' not found; the record has "
                             f"{', '.join(names) or 'no channel'} ({hint})")
        return channel(ds, wanted).name
    usable = [n for n in channels(ds) if channel(ds, n).kind != "tacho"]
    if not usable:
        raise InputError(f"{what}: the record has no signal channel; "
                         + ("map an accelerometer (or other sensor) channel of the file in "
                            "[[measurement.channels]]" if measured else
                            "add [[sensors]] to the config"))
    return usable[0]


def _check_speed(ds: xr.Dataset, what: str) -> None:
    from geardyn.results import channel, channels

    has_tacho = any(channel(ds, n).kind == "tacho" for n in channels(ds))
    if "angle" not in ds and not has_tacho:
        raise InputError(f"{what}: the record has no speed reference; give a tacho or encoder "
                         "channel, profile_rpm or speed_rpm in [measurement]")


def _duration(ds: xr.Dataset, ch: str) -> float:
    from geardyn.results import channel

    t = channel(ds, ch).time
    return float(t[-1] - t[0]) if t.size > 1 else 0.0


def _rms(ds: xr.Dataset, ch: str) -> float:
    x = np.asarray(ds["sensors." + ch].values, float)
    return float(np.sqrt(np.mean((x - x.mean()) ** 2)))


def diagnose_record(
    cfg: GeardynConfig,
    record_path: str | Path,
    out_dir: str | Path,
    *,
    baseline_paths: Sequence[str | Path] = (),
    simulate: bool | None = None,
    progress: Progress | None = None,
    **overrides: Unpack[Overrides],
) -> Verdict:
    """Judge the record file against measured baseline files, simulated healthy runs, or both
    (``simulate``: default True when no baseline file is given); write ``out_dir/verdict.json``
    and ``out_dir/report.html``. The record is read (and its mapping checked) before any
    simulation. Planetary runs last as long as the record unless ``t_end_s`` or
    ``[diagnosis] t_end_s`` says otherwise. ``overrides``: the ``[diagnosis]`` keywords of
    :func:`geardyn.diagnosis.pipeline.diagnose` (:class:`~geardyn.diagnosis.pipeline.
    Overrides`) but ``record_seed``."""
    from geardyn.diagnosis.pipeline import (
        _blocks,
        _check_status,
        _features,
        _finish,
        _run_length,
        _say,
        check_output_dir,
        options_from,
    )

    simulate = (not baseline_paths) if simulate is None else simulate
    if not baseline_paths and not simulate:
        raise InputError("baseline: give healthy baseline file(s) (--baseline) or simulate "
                         "the healthy machine (--simulate-baseline)")
    opts = options_from(cfg, overrides, "diagnose_record", refused=("record_seed",))
    out = check_output_dir(out_dir)
    for path in baseline_paths:  # every file named exists, before any reading
        if not Path(path).is_file():
            raise InputError(f"baseline: file '{path}' does not exist")
    what = f"record '{record_path}'"
    _say(progress, f"reading {what}", 0.0)
    baseline_ds = [(path, load_record(path, cfg, "baseline")) for path in baseline_paths]
    rec_ds = load_record(record_path, cfg, "record")
    ch = record_channel(rec_ds, opts.channel, what)
    _check_speed(rec_ds, what)
    measured_files = []
    for path, ds in baseline_ds:
        record_channel(ds, ch, f"baseline file '{path}'")
        _check_speed(ds, f"baseline file '{path}'")
        measured_files.append((path, ds))
    del baseline_ds
    planetary = getattr(cfg, "planetary_dynamics", None) is not None
    run_length: dict[str, float | None] = {}
    if simulate:
        names = {s.name for s in getattr(cfg, "sensors", [])}
        if ch not in names:
            raise InputError(f"{what}: channel '{ch}' has no simulated counterpart; name the "
                             "measured channel like the [[sensors]] entry that models it "
                             f"(sensors: {', '.join(sorted(names)) or 'none: add [[sensors]]'})")
        if planetary and opts.t_end_s is None:
            opts = opts.model_copy(update={"t_end_s": _duration(rec_ds, ch)})
        run_length = _run_length(cfg, opts)
    n_sim = len(opts.baseline_seeds) if simulate else 0
    n = len(measured_files) + n_sim + 1
    feats, blocks, levels, done = [], [], [], 0
    for i, (path, ds) in enumerate(measured_files):
        _say(progress, f"indicators of baseline file '{path}'", done / n)
        f = _features(ds, cfg, ch, opts)
        # only the first baseline's order spectrum is drawn (behind the record's); the others
        # would hold a record-long spectrum each until the end
        feats.append(f if not feats else replace(f, order_spectrum=None))
        blocks.append(_blocks(ds, cfg, ch, opts))
        levels.append(_rms(ds, ch))
        measured_files[i] = (path, None)  # the file's samples are no longer needed
        del ds
        done += 1
    info_base: dict[str, Any] = {"blocks": opts.blocks, "skip_s": opts.skip_s}
    if measured_files:
        info_base["files"] = [str(p) for p, _ in measured_files]
    if simulate:
        from geardyn.diagnosis.ensemble import simulate_baseline
        from geardyn.diagnosis.faults import healthy_variant

        level = float(np.median(levels)) if levels else None
        sims, drawn = [], []
        for member, ds in simulate_baseline(
                healthy_variant(cfg), opts, run_length,
                progress=lambda m, f: _say(progress, m, (done + f * n_sim) / n)):
            _check_status(ds, f"healthy baseline {member.label}")
            sims.append(ds)
            drawn.append({"label": member.label, "seed": member.seed, **member.values})
        scale = 1.0
        if level is not None:
            sim_level = float(np.median([_rms(ds, ch) for ds in sims]))
            scale = level / sim_level if sim_level > 0 else 1.0
            info_base["simulated_scale"] = scale
        for member_ds in sims:
            if scale != 1.0:
                key = "sensors." + ch
                member_ds[key] = member_ds[key] * scale
            feats.append(_features(member_ds, cfg, ch, opts))
            blocks.append(_blocks(member_ds, cfg, ch, opts))
        info_base.update({"seeds": list(opts.baseline_seeds), **run_length, "members": drawn})
    _say(progress, f"indicators of {what}", (n - 1) / n)
    record = _features(rec_ds, cfg, ch, opts)
    rec_blocks = _blocks(rec_ds, cfg, ch, opts)
    rec_info: dict[str, Any] = {"file": str(record_path)}
    if rec_ds.attrs.get("model") == "measured":
        rec_info.update({k: rec_ds.attrs[k] for k in ("timestamp", "speed_rpm", "load_nm",
                                                     "speed_source", "warnings")
                         if k in rec_ds.attrs and rec_ds.attrs[k] != ""})
    verdict = _finish(cfg, out, opts, feats, record, rec_ds, ch, (info_base, rec_info), None,
                      blocks=(blocks, rec_blocks))
    _say(progress, "done", 1.0)
    return verdict


def simulated_reference(cfg: GeardynConfig, opts: Any, channel: str,
                        progress: Progress | None = None) -> list[Any]:
    """Features of ``channel`` in simulated healthy runs of ``cfg`` (the baseline ensemble of
    :func:`geardyn.diagnosis.ensemble.simulate_baseline`, run length from ``opts``/the
    config): the healthy reference of a trend."""
    from geardyn.diagnosis.ensemble import simulate_baseline
    from geardyn.diagnosis.faults import healthy_variant
    from geardyn.diagnosis.pipeline import _check_status, _features, _run_length

    names = {s.name for s in getattr(cfg, "sensors", [])}
    if channel not in names:
        raise InputError(f"simulated baseline: channel '{channel}' has no simulated "
                         "counterpart; name the measured channel like the [[sensors]] entry "
                         f"that models it (sensors: {', '.join(sorted(names)) or 'none'})")
    feats = []
    for member, ds in simulate_baseline(healthy_variant(cfg), opts, _run_length(cfg, opts),
                                        progress=progress):
        _check_status(ds, f"healthy baseline {member.label}")
        feats.append(_features(ds, cfg, channel, opts))
    return feats
