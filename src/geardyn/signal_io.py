"""Reading measured or simulated signals with their sample rate (or pulse times).

Formats (by extension): ``.wav`` (rate from the file; integer PCM scaled to ±1), ``.csv``
(columns; a ``time`` column [s] gives the rate, else pass ``fs``), ``.npy`` (array; pass
``fs``), ``.npz`` (keys ``x`` or ``signal``, ``fs``, optional ``pulse_times``), ``.nc``
(NetCDF3 via scipy, NetCDF4 via h5netcdf + h5py: a data variable along a ``time``
coordinate [s] or with an ``fs`` / ``sample_rate`` attribute). Pulse times (tacho or encoder
edges, [s]) are read by
:func:`read_pulse_times` from ``.csv``/``.txt``/``.npy`` (one column) or the ``pulse_times``
entry of ``.npz``/``.nc``. Every failure is an :class:`~geardyn.errors.InputError` naming the
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


def _pick(names: list[str], channel: str | int | None, src: str) -> int:
    if channel is None:
        return 0
    if isinstance(channel, int) or (isinstance(channel, str) and channel.isdigit()):
        i = int(channel)
        if not 0 <= i < len(names):
            raise InputError(f"channel: index {i} out of range; {src} has channels {names}")
        return i
    if channel not in names:
        raise InputError(f"channel: {channel!r} not found; {src} has channels {names}")
    return names.index(channel)


def read_signal(
    path: str | Path, fs: float | None = None, channel: str | int | None = None
) -> SignalRecord:
    """Read one channel of a signal file (see module doc for the formats)."""
    p = Path(path)
    src = str(p)
    if not p.is_file():
        raise InputError(f"signal: file {src} does not exist")
    ext = p.suffix.lower()
    pulses = None
    units = ""
    try:
        if ext == ".wav":
            from scipy.io import wavfile

            try:  # memory-mapped: only the chosen channel is converted (float32)
                rate, data = wavfile.read(p, mmap=True)
            except ValueError:  # formats that cannot be mapped (e.g. 24-bit PCM)
                rate, data = wavfile.read(p)
            data = data.reshape(data.shape[0], -1)
            names = [str(i) for i in range(data.shape[1])]
            i = _pick(names, channel, src)
            x, rate_hz = data[:, i], float(rate)
            if np.issubdtype(x.dtype, np.integer):
                x = x.astype(np.float32) / np.float32(np.iinfo(x.dtype).max + 1)
            else:
                x = np.asarray(x, dtype=float)
            _agree_fs(fs, rate_hz, src, "WAV header")
        elif ext in (".csv", ".txt"):
            import pandas as pd

            df = pd.read_csv(p)
            cols = [str(c) for c in df.columns]
            tcol = next((c for c in cols if c.strip().lower() in ("time", "t", "time_s")), None)
            data_cols = [c for c in cols if c != tcol]
            if not data_cols:
                raise InputError(f"{src}: no data column besides the time column")
            i = _pick(data_cols, channel, src)
            x = df[data_cols[i]].to_numpy(dtype=float)
            rate_hz = (_agree_fs(fs, _fs_from_time(df[tcol].to_numpy(), src), src,
                                 f"from its '{tcol}' column") if tcol else _check_fs(fs, src))
            names = data_cols
        elif ext == ".npy":
            # memory-mapped: a long record is not read whole; float32/float64 data is used as
            # stored (float32 is exact enough for vibration records: 24-bit mantissa)
            data = np.load(p, allow_pickle=False, mmap_mode="r")
            data = data.reshape(data.shape[0], -1)
            names = [str(i) for i in range(data.shape[1])]
            x = data[:, _pick(names, channel, src)]
            if x.dtype not in (np.float32, np.float64) or data.shape[1] > 1:
                x = np.asarray(x, dtype=float)
            rate_hz = _check_fs(fs, src)
        elif ext == ".npz":
            with np.load(p, allow_pickle=False) as z:
                key = next((k for k in ("x", "signal") if k in z), None)
                if key is None:
                    raise InputError(f"{src}: needs an 'x' or 'signal' array; has {list(z)}")
                x = np.asarray(z[key], dtype=float).ravel()
                fk = next((k for k in _FS_KEYS if k in z), None)
                rate_hz = (_agree_fs(fs, float(z[fk]), src, f"its '{fk}' entry") if fk
                           else _check_fs(fs, src))
                pulses = np.asarray(z["pulse_times"], float) if "pulse_times" in z else None
                names = [key]
        elif ext in (".nc", ".netcdf", ".h5"):
            with _open_nc(p) as ds:
                dv = [v for v in ds.data_vars if v != "pulse_times"]
                if not dv:
                    raise InputError(f"{src}: no data variable")
                one_d = [str(v) for v in dv if ds[v].ndim == 1]
                if channel is None and len(one_d) > 1:
                    raise InputError(f"channel: {src} holds {len(one_d)} 1-D channels; choose "
                                     f"one of: {', '.join(one_d)}")
                i = _pick([str(v) for v in dv], channel, src)
                da = ds[dv[i]]
                if da.ndim != 1:
                    raise InputError(
                        f"channel: variable '{dv[i]}' of {src} has dims {tuple(da.dims)}, not one "
                        f"channel; choose a 1-D channel: {', '.join(one_d) or '(none)'}")
                x = np.asarray(da.values, dtype=float)
                fk = next((k for k in _FS_KEYS if k in da.attrs or k in ds.attrs), None)
                if fk:
                    rate_hz = _agree_fs(fs, float(da.attrs.get(fk, ds.attrs.get(fk))), src,
                                        f"its '{fk}' attribute")
                elif "time" in da.coords:
                    rate_hz = _agree_fs(fs, _fs_from_time(da["time"].values, src), src,
                                        "from its time coordinate")
                else:
                    rate_hz = _check_fs(fs, src)
                units = str(da.attrs.get("units", ""))
                if "pulse_times" in ds:
                    pulses = np.asarray(ds["pulse_times"].values, dtype=float)
                names = [str(v) for v in dv]
        else:
            raise InputError(
                f"signal: unsupported file type {ext!r} ({src}); use .wav, .csv, .npy, .npz, .nc"
            )
    except InputError:
        raise
    except Exception as exc:  # malformed file → one clear message
        raise InputError(f"signal: cannot read {src}: {exc}") from None
    if x.size < 16:
        raise InputError(f"{src}: signal has {x.size} samples; at least 16 are needed")
    if not _all_finite(x):
        raise InputError(f"{src}: signal contains NaN or infinite values")
    return SignalRecord(x, float(rate_hz), names[_pick(names, channel, src)] if names else "x",
                        units, pulses, names)


def _all_finite(x: np.ndarray, chunk: int = 1 << 22) -> bool:
    """All samples finite, checked chunk by chunk (no record-sized temporary)."""
    return all(bool(np.isfinite(x[a:a + chunk]).all()) for a in range(0, x.shape[0], chunk))


def read_pulse_times(path: str | Path) -> np.ndarray:
    """Pulse times [s] (tacho/encoder edges), strictly increasing."""
    p = Path(path)
    src = str(p)
    if not p.is_file():
        raise InputError(f"pulse_times: file {src} does not exist")
    ext = p.suffix.lower()
    try:
        if ext in (".csv", ".txt"):
            import pandas as pd

            df = pd.read_csv(p)
            tp = df.iloc[:, 0].to_numpy(dtype=float)
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
