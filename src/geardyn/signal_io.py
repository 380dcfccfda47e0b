"""Reading one signal channel with its sample rate (or pulse times) for ``geardyn analyze``.

Every format of :func:`geardyn.io.read_raw` (docs/measured.md): CSV/TSV (delimiter, decimal
comma and header detected; a time column gives the rate and is never the signal), WAV/FLAC
(integer PCM as a fraction of full scale; ``full_scale`` and ``sensitivity`` give a physical
quantity), ``.npy`` (pass ``fs``), ``.npz`` (arrays, ``fs``, optional ``pulse_times``), MAT,
TDMS, UFF 58, MDF4, HDF5 and NetCDF. Pulse times (tacho or encoder edges, [s]) are read by
:func:`read_pulse_times`. Every failure is an :class:`~geardyn.errors.InputError` naming the
file and the rule.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from geardyn.errors import InputError

_FS_KEYS = ("fs", "sample_rate", "sampling_rate", "sample_rate_hz")


@dataclass
class SignalRecord:
    """One channel ``x`` sampled at ``fs`` [Hz]; optional ``pulse_times`` [s] stored with it."""

    x: np.ndarray
    fs: float
    name: str = "signal"
    units: str = ""
    pulse_times: np.ndarray | None = None
    channels: list[str] = field(default_factory=list)

    @property
    def duration(self) -> float:
        return self.x.size / self.fs


def _fs_from_time(t: np.ndarray, src: str) -> float:
    dt = np.diff(np.asarray(t, dtype=float))
    if dt.size == 0 or np.any(dt <= 0):
        raise InputError(f"{src}: the time column must increase strictly")
    if np.max(np.abs(dt - dt.mean())) > 1e-6 * dt.mean() + 1e-12:
        raise InputError(f"{src}: time samples are not uniformly spaced; resample first")
    return 1.0 / float(dt.mean())


def _agree_fs(fs: float | None, rate_hz: float, src: str, origin: str) -> float:
    """The file's own sample rate; ``fs`` given as well must agree with it (1e-6)."""
    if fs is not None and abs(float(fs) - rate_hz) > 1e-6 * rate_hz:
        raise InputError(f"--fs: {float(fs):g} Hz contradicts the sample rate of {src} "
                         f"({rate_hz:g} Hz, {origin}); drop --fs or fix the file")
    return rate_hz


def _check_fs(fs: float | None, src: str) -> float:
    if fs is None:
        raise InputError(f"{src}: the file holds no sample rate; pass fs (Hz)")
    v = float(fs)
    if not np.isfinite(v) or v <= 0:
        raise InputError(f"fs: sample rate must be > 0, got {fs!r}")
    return v


def read_signal(
    path: str | Path, fs: float | None = None, channel: str | int | None = None, *,
    sensitivity: str | None = None, full_scale: str | None = None, units: str | None = None,
) -> SignalRecord:
    """Read one channel of a signal file: any format of :func:`geardyn.io.read_raw` (CSV/TSV
    with delimiter, decimal comma and header detected, WAV/FLAC, NPY/NPZ, MAT, TDMS, UFF, MDF4,
    HDF5, NetCDF). A file with several signal channels needs ``channel`` (name or 0-based
    index); a time column is never a signal. ``sensitivity`` (e.g. ``"100 mV/g"``) and
    ``full_scale`` (audio: the quantity at digital full scale, e.g. ``"10 V"``) turn the file's
    values into a physical quantity (``units``, default SI base units)."""
    from geardyn.io import read_raw
    from geardyn.io.units import scale_factor

    p = Path(path)
    src = str(p)
    if not p.is_file():
        raise InputError(f"signal: file {src} does not exist")
    raw = read_raw(p)
    signals = [n for n, c in raw.channels.items() if not c.attrs.get("events")]
    events = [c for c in raw.channels.values() if c.attrs.get("events")]
    if not signals:
        raise InputError(f"{src}: no signal channel (only pulse times)")
    if channel is None:
        if len(signals) > 1:
            raise InputError(f"channel: {src} holds {len(signals)} signal channels; choose one "
                             f"with --channel (name or 0-based index): {', '.join(signals)}"
                             + (f" (time column '{raw.time_channel}')" if raw.time_channel
                                else ""))
        rc = raw.channels[signals[0]]
    elif isinstance(channel, int) or (isinstance(channel, str) and channel.isdigit()
                                      and channel not in raw.channels):
        i = int(channel)
        if not 0 <= i < len(signals):
            raise InputError(f"channel: index {i} out of range; {src} has signal channels "
                             f"{', '.join(signals)}")
        rc = raw.channels[signals[i]]
    else:
        rc = raw.get(str(channel))
        if rc.attrs.get("events"):
            raise InputError(f"channel: '{rc.name}' of {src} holds pulse times, not a signal")
    if rc.fs is not None:
        rate_hz = _agree_fs(fs, float(rc.fs), src, "stated in the file")
    else:
        rate_hz = _check_fs(fs, src)
    x = rc.values
    if x.size < 16:
        raise InputError(f"{src}: signal has {x.size} samples; at least 16 are needed")
    if not _all_finite(x):
        raise InputError(f"{src}: channel '{rc.name}' contains NaN or infinite values")
    unit = rc.units
    if sensitivity or full_scale or units:
        factor, unit = scale_factor(rc.units or ("V" if sensitivity else ""), sensitivity,
                                    full_scale, units, f"{src}: channel '{rc.name}'")
        x = np.asarray(x, dtype=float) * factor
    elif rc.attrs.get("full_scale_fraction"):
        unit = "FS"
    pulses = np.asarray(events[0].values, float) if events else None
    return SignalRecord(x, float(rate_hz), rc.name, unit, pulses, signals)


def _all_finite(x: np.ndarray, chunk: int = 1 << 22) -> bool:
    """All samples finite, checked chunk by chunk (no record-sized temporary)."""
    return all(bool(np.isfinite(x[a:a + chunk]).all()) for a in range(0, x.shape[0], chunk))


def read_pulse_times(path: str | Path) -> np.ndarray:
    """Pulse times [s] (tacho/encoder edges), strictly increasing: the first column of a
    ``.csv``/``.txt`` table (header detected: a header-less file keeps its first pulse), a
    ``.npy`` vector, or the ``pulse_times`` entry of ``.npz``/``.nc``."""
    p = Path(path)
    src = str(p)
    if not p.is_file():
        raise InputError(f"pulse_times: file {src} does not exist")
    ext = p.suffix.lower()
    try:
        if ext in (".csv", ".txt", ".tsv"):
            from geardyn.io.table import first_column

            tp = first_column(p)
        elif ext == ".npy":
            tp = np.load(p, allow_pickle=False).astype(float).ravel()
        elif ext == ".npz":
            with np.load(p, allow_pickle=False) as z:
                if "pulse_times" not in z:
                    raise InputError(f"pulse_times: {src} has no 'pulse_times' array")
                tp = np.asarray(z["pulse_times"], dtype=float).ravel()
        elif ext == ".nc":
            with _open_nc(p) as ds:
                if "pulse_times" not in ds:
                    raise InputError(f"pulse_times: {src} has no 'pulse_times' variable")
                tp = np.asarray(ds["pulse_times"].values, dtype=float).ravel()
        else:
            raise InputError(f"pulse_times: unsupported file type {ext!r} ({src})")
    except InputError:
        raise
    except Exception as exc:
        raise InputError(f"pulse_times: cannot read {src}: {exc}") from None
    if tp.size < 3 or not np.all(np.diff(tp) > 0):
        raise InputError(f"pulse_times: {src} needs >= 3 strictly increasing times")
    return tp


def write_signal_netcdf(
    path: str | Path,
    x: np.ndarray,
    fs: float,
    name: str = "signal",
    units: str = "",
    pulse_times: np.ndarray | None = None,
) -> Path:
    """Write a signal (and optional pulse times) as NetCDF readable by :func:`read_signal`."""
    import xarray as xr

    f = _check_fs(fs, "fs")
    a = np.asarray(x, dtype=float)
    ds = xr.Dataset({name: (("time",), a, {"units": units, "fs": f})},
                    coords={"time": np.arange(a.size) / f})
    if pulse_times is not None:
        ds["pulse_times"] = (("pulse",), np.asarray(pulse_times, dtype=float), {"units": "s"})
    p = Path(path)
    from geardyn.checkpoint import write_atomic

    # NetCDF3 via scipy (no HDF5 library needed), written aside and renamed
    write_atomic(p, lambda tmp: ds.to_netcdf(tmp, engine="scipy"))
    return p


def _open_nc(p: Path):
    import xarray as xr

    with p.open("rb") as fh:
        magic = fh.read(8)
    if not (magic.startswith(b"CDF") or magic.startswith(b"\x89HDF")):
        raise InputError(f"signal: {p} is not a NetCDF file (neither NetCDF3 nor NetCDF4/HDF5 "
                         "header)")
    try:
        return xr.open_dataset(p)
    except (ImportError, ValueError) as exc:
        if "h5py" in str(exc) or "engine" in str(exc):
            raise InputError(
                f"signal: {p} is NetCDF4/HDF5, which needs the h5py package (pip install h5py); "
                "NetCDF3 files are read without it"
            ) from None
        raise
