"""A measured file → the result layout of docs/results.md, through the channel mapping.

:func:`read_record` reads any supported file (:func:`geardyn.io.raw.read_raw`), applies the
``[measurement]`` mapping of the config (:class:`geardyn.config.measurement.MeasurementSpec`:
which file channel is which sensor, where it sits on the model, units and sensitivity, the
speed source) and returns an :class:`xarray.Dataset` that the diagnosis and ``analyze`` read
exactly like a simulated run: ``sensors.<name>`` channels with their time (or pulse, or encoder
angle) dimension and attributes, and ``angle``/``speed``/``speed_rpm`` of the speed shaft on a
``time``/``shaft`` grid. Attributes: ``model = "measured"``, ``source_file``, ``timestamp``,
``speed_rpm`` (mean, speed shaft) and ``load_nm`` of the operating point, ``warnings``.

Checks (errors name the file and the channel; warnings too): a channel that does not exist,
non-finite samples, no sample rate or one contradicting the file's, a record shorter than
``min_revolutions`` of the speed shaft, a tacho whose mean speed contradicts ``speed_rpm``
(2 %) or that covers only part of the record (warning; a tacho longer than the record is
trimmed), clipped stretches (≥ 3 consecutive samples at the channel's extreme value: warning).
"""

from __future__ import annotations

import datetime as dt
import math
import re
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr

from geardyn.errors import InputError
from geardyn.io.raw import RawChannel, RawRecord, read_raw
from geardyn.io.speed import (
    angle_from_profile,
    pulse_times_from_signal,
    repair_missing_pulses,
    trim_pulses,
)
from geardyn.results import LAYOUT, PREFIX, RAD_S_TO_RPM, is_result

if TYPE_CHECKING:
    from geardyn.config.measurement import MeasuredChannel, MeasurementSpec

#: Samples of the ``time`` grid of the shaft variables at most (the angle is smooth; linear
#: interpolation between grid points errs by α·Δt²/8: 1e-6 rad for α = 1 rad/s² over 600 s).
SHAFT_GRID = 200_000
#: Relative agreement needed between a mapped sample rate and the file's own.
RATE_TOLERANCE = 1e-4
#: A stated operating speed and a tacho's mean speed must agree to this fraction.
SPEED_TOLERANCE = 0.02


class RecordWarning(UserWarning):
    """A measured record is usable but suspicious (clipping, partial tacho…)."""


def read_record(path: str | Path, measurement: MeasurementSpec | None = None,
                cfg: Any = None, *, fs: float | None = None) -> xr.Dataset:
    """Read a measured (or geardyn result) file into the result layout (module docstring).

    ``measurement``: the channel mapping (default: ``cfg.measurement``; without one every file
    channel becomes a channel of unknown kind, named as in the file); ``cfg``: the machine
    (input links, planetary stages) the mapping refers to; ``fs`` [Hz]: the sample rate when
    neither the file nor the mapping states one."""
    p = Path(path)
    if measurement is None and cfg is not None:
        measurement = getattr(cfg, "measurement", None)
    result = _geardyn_result(p)
    if result is not None:
        return result
    spec = measurement
    raw = read_raw(p, delimiter=getattr(spec, "delimiter", None),
                   decimal=getattr(spec, "decimal", None), header=getattr(spec, "header", None),
                   time_channel=getattr(spec, "time_channel", None),
                   sources=[str(c.file_channel) for c in spec.channels] if spec else None)
    if spec is None:
        return _unmapped(raw, fs)
    return _mapped(raw, spec, cfg, fs)


def _geardyn_result(p: Path) -> xr.Dataset | None:
    if p.suffix.lower() not in (".nc", ".netcdf", ".h5") or not p.is_file():
        return None
    try:
        ds = xr.open_dataset(p)
    except Exception:  # noqa: BLE001 - not NetCDF: the raw readers report it
        return None
    if not is_result(ds):
        ds.close()
        return None
    return ds.load()


# ----------------------------------------------------------------------------- the layout
def _base_attrs(raw: RawRecord, model_ref: str, stamp: str | None) -> dict[str, Any]:
    import geardyn

    return {"geardyn_layout": LAYOUT, "model": "measured", "status": "ok", "diagnosis": "",
            "seed": -1, "reference_shaft": model_ref, "source_file": str(raw.path),
            "source_format": raw.format, "timestamp": stamp or "",
            "geardyn_version": geardyn.__version__, "reader_notes": "; ".join(raw.notes)}


def _time_channel(ds: xr.Dataset, name: str, x: np.ndarray, fs: float, t0: float,
                  attrs: dict[str, Any]) -> None:
    key = PREFIX + name
    dim = f"{key}.time"
    t = np.arange(x.size, dtype=float)  # t0 + i/fs, without record-long temporaries
    t /= fs
    t += t0
    ds[key] = xr.DataArray(x, dims=(dim,),
                           coords={dim: (dim, t, {"units": "s", "long_name": "time"})},
                           attrs={"sampling": "time", "sample_rate_hz": float(fs), **attrs})


def _rate(rc: RawChannel, mapped: float | None, src: str) -> float:
    if rc.fs is not None:
        if not (math.isfinite(rc.fs) and rc.fs > 0):
            raise InputError(f"{src}: the file states a sample rate of {rc.fs!r} Hz")
        if mapped is not None and abs(mapped - rc.fs) > RATE_TOLERANCE * rc.fs:
            raise InputError(f"{src}: sample_rate_hz {mapped:g} Hz of the mapping contradicts "
                             f"the file's own rate {rc.fs:g} Hz; drop sample_rate_hz or fix it")
        return float(rc.fs)
    if mapped is None:
        raise InputError(f"{src}: the file states no sample rate; give sample_rate_hz in "
                         "[measurement] (or in the channel's [[measurement.channels]] entry)")
    return float(mapped)


def _finite(x: np.ndarray, fs: float, t0: float, src: str) -> None:
    bad = ~np.isfinite(x)
    if bad.any():
        i = int(np.argmax(bad))
        raise InputError(f"{src}: {int(bad.sum())} non-finite sample(s) (NaN/inf), the first "
                         f"at sample {i} (t = {t0 + i / fs:.6g} s); a dropout or an empty "
                         "field: cut the record or fill the gap")


def clipped(x: np.ndarray, run: int = 3) -> tuple[int, int]:
    """``(samples in runs of ≥ run equal samples at the channel's max or min, first index)``:
    a signal through an amplifier or ADC at its limit stays there; a continuous signal
    reaches its extreme at isolated samples."""
    n, first = 0, -1
    for level in (np.max(x), np.min(x)):
        at = np.concatenate([[False], x == level, [False]])
        d = np.diff(at.astype(np.int8))
        starts, ends = np.flatnonzero(d == 1), np.flatnonzero(d == -1)
        long = (ends - starts) >= run
        n += int(np.sum((ends - starts)[long]))
        if long.any():
            s = int(starts[long][0])
            first = s if first < 0 else min(first, s)
    return n, first


def _unmapped(raw: RawRecord, fs: float | None) -> xr.Dataset:
    ds = xr.Dataset(attrs=_base_attrs(raw, "", raw.timestamp))
    for name, rc in raw.channels.items():
        safe = re.sub(r"[^A-Za-z0-9_\-]", "_", name)
        src = f"{raw.path}: channel '{name}'"
        if rc.attrs.get("events"):
            ds[PREFIX + safe] = xr.DataArray(rc.values, dims=(f"{PREFIX}{safe}.pulse",),
                                             attrs={"sensor_kind": "tacho", "units": "s",
                                                    "sampling": "events", "shaft": ""})
            continue
        rate = _rate(rc, fs, src)
        _finite(rc.values, rate, rc.t0, src)
        _time_channel(ds, safe, rc.values, rate, rc.t0,
                      {"sensor_kind": "", "units": rc.units, "shaft": "", "location": "",
                       "long_name": f"channel '{name}' of {raw.path.name}",
                       "source_channel": name})
    return ds


def _scale(c: MeasuredChannel, rc: RawChannel, src: str) -> tuple[float, str]:
    """Factor from file values to the channel's units, and those units (pint)."""
    from geardyn.config.measurement import DEFAULT_UNITS
    from geardyn.io.units import scale_factor

    if rc.attrs.get("full_scale_fraction") and c.sensitivity is not None and \
            c.full_scale is None:
        raise InputError(f"{src}: audio samples are fractions of digital full scale; give "
                         "full_scale (the quantity at full scale, e.g. \"10 V\") with the "
                         "sensitivity")
    file_units = c.file_units or rc.units or ("V" if c.sensitivity is not None else "")
    target = c.units or (None if c.kind in ("tacho", "encoder") else DEFAULT_UNITS[c.kind])
    if target is not None and not (file_units or c.full_scale):
        return 1.0, target  # the file states no unit: its values are in the channel's units
    return scale_factor(file_units, c.sensitivity, c.full_scale, target, src)


def _label(c: MeasuredChannel, cfg: Any) -> str:
    if c.location == "ring":
        stages = [s.name for s in getattr(cfg, "planetary", [])] if cfg is not None else []
        stage = c.stage or (stages[0] if len(stages) == 1 else None)
        return f"ring of stage '{stage}'" if stage else "ring"
    if c.location:
        return f"bearing '{c.location}', {c.direction}"
    return ""


def _stamp(spec: MeasurementSpec, raw: RawRecord) -> str:
    if spec.timestamp is not None:
        s = spec.timestamp
        return s.isoformat() if isinstance(s, dt.datetime) else str(s)
    if raw.timestamp:
        return raw.timestamp
    return stamp_from_name(raw.path) or dt.datetime.fromtimestamp(
        raw.path.stat().st_mtime).isoformat(timespec="seconds")


_STAMP = re.compile(r"(\d{4})-?(\d{2})-?(\d{2})[T_ -]?(\d{2})[:_-]?(\d{2})[:_-]?(\d{2})")


def stamp_from_name(p: Path) -> str | None:
    """``pump_2026-03-01_12-30-00.csv`` / ``20260301T123000.wav`` → ISO 8601, else None."""
    m = _STAMP.search(p.stem)
    if not m:
        return None
    try:
        return dt.datetime(*map(int, m.groups())).isoformat()
    except ValueError:
        return None


def _mapped(raw: RawRecord, spec: MeasurementSpec, cfg: Any, fs: float | None) -> xr.Dataset:
    inputs = list(getattr(cfg, "input_speeds_rpm", {}) or {}) if cfg is not None else []
    pulse_ch = [c for c in spec.channels if c.kind in ("tacho", "encoder")]
    speed_shaft = (spec.speed_shaft or (pulse_ch[0].shaft if pulse_ch else None)
                   or (inputs[0] if inputs else None))
    ds = xr.Dataset(attrs=_base_attrs(raw, speed_shaft or "", _stamp(spec, raw)))
    notes: list[str] = []
    spans: list[tuple[float, float, float]] = []  # (t0, t_end, fs) of the signal channels
    pulses: dict[str, tuple[np.ndarray, MeasuredChannel, str]] = {}
    for c in spec.channels:
        rc = raw.get(c.file_channel)
        src = f"{raw.path}: channel '{c.name}' (file channel '{rc.name}')"
        if c.kind in ("tacho", "encoder"):
            pulses[c.name] = (_pulses(c, rc, spec, fs, src, notes), c, src)
            continue
        if rc.attrs.get("events"):
            raise InputError(f"{src}: holds pulse times, not a {c.kind} signal; map it as kind "
                             "= \"tacho\" with signal = \"pulse_times\"")
        rate = _rate(rc, c.sample_rate_hz or spec.sample_rate_hz or fs, src)
        _finite(rc.values, rate, rc.t0, src)
        factor, units = _scale(c, rc, src)
        if rc.attrs.get("full_scale_fraction") and c.full_scale is None:
            notes.append(f"{src}: audio samples are fractions of digital full scale and no "
                         f"full_scale is given: the channel is in relative units, not {units}")
        x = np.multiply(rc.values, factor, dtype=float)  # one float64 copy, scaled
        n_clip, first = clipped(x)
        if n_clip:
            notes.append(f"{src}: {n_clip} clipped sample(s) ({n_clip / x.size:.2%}; runs of "
                         f"≥ 3 samples at the extreme value, first at t = "
                         f"{rc.t0 + first / rate:.6g} s): the sensor or ADC saturated there")
        spans.append((rc.t0, rc.t0 + (x.size - 1) / rate, rate))
        _time_channel(ds, c.name, x, rate, rc.t0, {
            "sensor_kind": c.kind, "units": units, "shaft": c.shaft or speed_shaft or "",
            "location": _label(c, cfg), "direction": c.direction,
            "sensor_angle_deg": float(c.sensor_angle_deg),
            "long_name": f"{c.kind} '{c.name}' ({_label(c, cfg) or 'measured'})",
            "source_channel": rc.name, "sensitivity": c.sensitivity or "",
            "scale_factor": factor})
    if not spans:
        raise InputError(f"{raw.path}: the mapping names no signal channel (only tacho/encoder "
                         "channels); add an accelerometer (or other) channel")
    t_start, t_end = min(s[0] for s in spans), max(s[1] for s in spans)
    for name, (tp, c, src) in pulses.items():
        tp = _checked_pulses(tp, c, src, t_start, t_end, notes)
        key = PREFIX + name
        if c.kind == "tacho":
            ds[key] = xr.DataArray(tp, dims=(f"{key}.pulse",), attrs={
                "sensor_kind": "tacho", "shaft": c.shaft, "pulses_per_rev": c.ppr,
                "location": c.shaft, "units": "s", "sampling": "events",
                "long_name": f"tacho pulse times of '{c.shaft}'", "source_channel":
                str(c.file_channel)})
        else:
            from geardyn.sensors import elapsed_time_ias

            m = elapsed_time_ias(tp, c.ppr)
            dim = f"{key}.angle"
            ds[key] = xr.DataArray(m.ias, dims=(dim,), coords={
                dim: (dim, m.angle, {"units": "rad", "long_name": "encoder angle"}),
                f"{key}.time": (dim, m.time, {"units": "s", "long_name": "edge time"})},
                attrs={"sensor_kind": "encoder", "shaft": c.shaft, "pulses_per_rev": c.ppr,
                       "location": c.shaft, "units": "rad/s", "sampling": "angle",
                       "long_name": f"IAS of '{c.shaft}' (elapsed time, seed 002 eq 1)",
                       "clock_hz": 0.0, "source_channel": str(c.file_channel)})
        pulses[name] = (tp, c, src)
    _shaft_variables(ds, spec, raw, pulses, speed_shaft, t_start, t_end,
                     max(s[2] for s in spans), cfg)
    for n in notes:
        warnings.warn(n, RecordWarning, stacklevel=3)
    ds.attrs["warnings"] = "\n".join(notes)
    if spec.load_nm is not None:
        ds.attrs["load_nm"] = float(spec.load_nm)
    return ds


def _pulses(c: MeasuredChannel, rc: RawChannel, spec: MeasurementSpec, fs: float | None,
            src: str, notes: list[str]) -> np.ndarray:
    if c.signal == "pulse_times" or rc.attrs.get("events"):
        tp = np.asarray(rc.values, float)
        if not np.all(np.isfinite(tp)):
            raise InputError(f"{src}: non-finite pulse times")
    else:
        rate = _rate(rc, c.sample_rate_hz or spec.sample_rate_hz or fs, src)
        _finite(rc.values, rate, rc.t0, src)
        tp = pulse_times_from_signal(rc.values, rate, rc.t0, c.threshold, c.hysteresis, src)
    if tp.size < 3:
        raise InputError(f"{src}: {tp.size} pulse(s) found; at least 3 are needed (check "
                         "threshold/hysteresis, or that this is the tacho channel)")
    if np.any(np.diff(tp) <= 0):
        raise InputError(f"{src}: pulse times must increase strictly")
    tp, fixed = repair_missing_pulses(tp)
    if fixed:
        notes.append(f"{src}: {len(fixed)} interval(s) of about twice the local pulse "
                     f"interval (missed pulses), the first after t = {fixed[0]:.6g} s: "
                     "pulses inserted")
    return tp


def _checked_pulses(tp: np.ndarray, c: MeasuredChannel, src: str, t_start: float,
                    t_end: float, notes: list[str]) -> np.ndarray:
    """Trim a tacho longer than the record; warn when it covers only part of it (the analysis
    then uses the covered part; tolerance: two pulse intervals or 2 % of the record)."""
    tp = trim_pulses(tp, t_start, t_end)
    if tp.size < 3:
        raise InputError(f"{src}: fewer than 3 pulses fall within the record "
                         f"({t_start:.6g}–{t_end:.6g} s)")
    duration = t_end - t_start
    tol = max(2.0 * float(np.max(np.diff(tp))), 0.02 * duration)
    gap0, gap1 = tp[0] - t_start, t_end - tp[-1]
    if gap0 > tol or gap1 > tol:
        lo, hi = max(t_start, tp[0]), min(t_end, tp[-1])
        notes.append(f"{src}: the pulses span {tp[0]:.6g}–{tp[-1]:.6g} s but the record "
                     f"{t_start:.6g}–{t_end:.6g} s: the {c.kind} covers "
                     f"{(hi - lo) / duration:.0%} of it; only that part is order-tracked")
    return tp


def _shaft_variables(ds: xr.Dataset, spec: MeasurementSpec, raw: RawRecord,
                     pulses: dict[str, tuple[np.ndarray, MeasuredChannel, str]],
                     shaft: str | None, t_start: float, t_end: float, fs: float,
                     cfg: Any = None) -> None:
    """``angle``/``speed``/``speed_rpm`` of the speed shaft on a ``time`` grid (from the
    tacho/encoder on it, else the profile, else the constant speed), and of every link of
    ``cfg`` turning with it (its kinematic ratio, seed 000 eq 5); checks the record length and
    the stated speed."""
    from geardyn.results import shaft_variables
    from geardyn.signal.resample import angle_from_pulses

    src_pulse = next(((tp, c, s) for tp, c, s in pulses.values() if c.shaft == shaft),
                     next(iter(pulses.values()), None))
    n = int(min(SHAFT_GRID, max(2, round((t_end - t_start) * fs) + 1)))
    if src_pulse is not None:
        tp, c, where = src_pulse
        shaft = c.shaft
        lo, hi = max(t_start, tp[0]), min(t_end, tp[-1])
        t = np.linspace(lo, hi, n)
        angle = angle_from_pulses(tp, t, c.ppr)
        mean_rpm = 60.0 * (tp.size - 1) / c.ppr / (tp[-1] - tp[0])
        if spec.speed_rpm is not None and abs(mean_rpm - spec.speed_rpm) > \
                SPEED_TOLERANCE * spec.speed_rpm:
            raise InputError(f"{where}: the pulses give {mean_rpm:.6g} rpm of '{shaft}' "
                             f"({c.ppr} pulse(s)/rev), but [measurement] speed_rpm is "
                             f"{spec.speed_rpm:g} rpm (tolerance 2 %): check pulses_per_rev, "
                             "the shaft or speed_rpm")
        how = f"{c.kind} '{c.name}'"
    elif spec.profile_rpm is not None:
        pt = spec.profile_rpm
        if pt[0][0] > t_start + 1e-9 or pt[-1][0] < t_end - 1e-9:
            raise InputError(f"{raw.path}: [measurement] profile_rpm covers {pt[0][0]:g}–"
                             f"{pt[-1][0]:g} s but the record spans {t_start:.6g}–{t_end:.6g} "
                             "s; the profile must cover the record")
        t = np.linspace(t_start, t_end, n)
        angle = angle_from_profile(t, pt)
        how = "profile_rpm"
    elif spec.speed_rpm is not None:
        t = np.linspace(t_start, t_end, n)
        angle = spec.speed_rpm * 2 * np.pi / 60.0 * (t - t_start)
        how = "speed_rpm"
    else:
        ds.attrs["speed_source"] = ""
        return  # no speed: analyze may still get one (--speed); diagnose refuses
    if shaft is None:
        raise InputError(f"{raw.path}: [measurement] speed_shaft: name the shaft the speed "
                         "refers to (the config has no input link)")
    speed = np.gradient(angle, t)
    revs = (angle[-1] - angle[0]) / (2 * np.pi)
    if revs < spec.min_revolutions:
        raise InputError(f"{raw.path}: the record covers {revs:.3g} revolutions of '{shaft}' "
                         f"(speed from {how}); at least {spec.min_revolutions:g} are needed "
                         "(measurement.min_revolutions): record longer, or check the speed "
                         "and the sample rate")
    ratios = _ratios(cfg, shaft)
    names = list(ratios)
    r = np.array([ratios[k] for k in names])
    ds.coords["time"] = ("time", t, {"units": "s", "long_name": "time"})
    ds.coords["shaft"] = ("shaft", names)
    for k, v in shaft_variables(t, names, angle[:, None] * r, speed[:, None] * r).items():
        ds[k] = v
    ds.attrs.update({"reference_shaft": shaft, "speed_source": how,
                     "speed_rpm": float(np.mean(speed) * RAD_S_TO_RPM)})


def _ratios(cfg: Any, shaft: str) -> dict[str, float]:
    """``{link: ω_link/ω_shaft}`` of the links of ``cfg`` turning with ``shaft`` (the shaft
    first; only the shaft itself when the kinematics do not fix the ratios)."""
    out = {shaft: 1.0}
    if cfg is None or not getattr(cfg, "links", None):
        return out
    from geardyn.diagnosis.components import link_ratios
    from geardyn.kinematics import analyze_kinematics

    try:
        an = analyze_kinematics(cfg)
        inputs = dict(getattr(cfg, "input_speeds_rpm", {}) or {}) if an.dof > 1 else None
        ratios = link_ratios(an, shaft, inputs)
    except Exception:  # noqa: BLE001 - a multi-DOF machine without input speeds, etc.
        return out
    frame = getattr(cfg, "frame", None)
    out.update({k: float(v) for k, v in ratios.items()
                if k != frame and k != shaft and v != 0.0 and np.isfinite(v)})
    return out
