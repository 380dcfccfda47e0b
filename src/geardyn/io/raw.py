"""Channels as a file holds them (before the channel mapping), and the dispatch by format.

Each format family has its own small module (:mod:`geardyn.io.table`, :mod:`~geardyn.io.audio`,
:mod:`~geardyn.io.arrays`, :mod:`~geardyn.io.matlab`, :mod:`~geardyn.io.tdms`,
:mod:`~geardyn.io.uff`, :mod:`~geardyn.io.mdf`, :mod:`~geardyn.io.hdf`) returning a
:class:`RawRecord`: named 1-D channels, each with its sample rate when the file states one, its
units when the file states them, and the file's timestamp when it has one. Every failure is an
:class:`~geardyn.errors.InputError` naming the file (and the channel).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from geardyn.errors import InputError

#: Attribute names that state a sample rate [Hz] (HDF5/NetCDF/NPZ/MAT).
FS_KEYS = ("fs", "Fs", "FS", "sample_rate", "sample_rate_hz", "sampling_rate", "samplerate",
           "sampling_frequency")
#: Attribute names that state a sample interval [s].
DT_KEYS = ("dt", "wf_increment", "sample_interval", "time_increment")
#: Names of a time column/variable [s] (case-insensitive, units in brackets removed).
TIME_NAMES = ("time", "t", "time_s", "zeit", "temps", "timestamp_s", "x_axis")


@dataclass
class RawChannel:
    """One channel of a file: ``values``, sample rate ``fs`` [Hz] if the file states it (None
    otherwise), ``units`` as the file states them ('' if not), start time ``t0`` [s]."""

    name: str
    values: np.ndarray
    fs: float | None = None
    units: str = ""
    t0: float = 0.0
    attrs: dict[str, Any] = field(default_factory=dict)


@dataclass
class RawRecord:
    """The channels of one file (``channels`` in file order), the time channel's name if the
    file has one (never a signal), the file's timestamp (ISO 8601) and notes on what was
    detected (delimiter, header…)."""

    path: Path
    channels: dict[str, RawChannel]
    time_channel: str | None = None
    timestamp: str | None = None
    notes: list[str] = field(default_factory=list)
    format: str = ""

    def names(self) -> list[str]:
        return list(self.channels)

    def get(self, source: str | int) -> RawChannel:
        """The channel ``source`` (name, or 0-based index as int or digits); an error naming the
        file and listing its channels otherwise."""
        names = self.names()
        if isinstance(source, int) or (isinstance(source, str) and source.isdigit()
                                       and source not in self.channels):
            i = int(source)
            if not 0 <= i < len(names):
                raise InputError(f"{self.path}: channel index {i} out of range; the file has "
                                 f"channels {', '.join(names) or '(none)'}")
            return self.channels[names[i]]
        if source in self.channels:
            return self.channels[source]
        full = [c for c in self.channels.values() if c.attrs.get("header") == source]
        if len(full) == 1:  # a table column by its whole header, 'acc [V]'
            return full[0]
        # TDMS 'group/channel', HDF5 '/a/b': also accept the last part when it is unique
        tail = [n for n in names if n.rsplit("/", 1)[-1] == str(source).strip("/")]
        if len(tail) == 1:
            return self.channels[tail[0]]
        if self.time_channel is not None and str(source).split("[")[0].split("(")[0] \
                .strip() == self.time_channel:
            raise InputError(f"{self.path}: '{source}' is the time column; it is never "
                             f"analysed as a signal (channels: {', '.join(names)})")
        raise InputError(f"{self.path}: channel '{source}' does not exist; the file has "
                         f"channels {', '.join(names) or '(none)'}")


def uniform_rate(t: np.ndarray, src: str, rel: float = 1e-3) -> float:
    """Sample rate [Hz] of a uniformly spaced, strictly increasing time vector [s]
    (least-squares slope of t against the index); an error naming ``src`` if the steps are not
    uniform to ``rel`` of a step."""
    t = np.asarray(t, dtype=float)
    if t.size < 2:
        raise InputError(f"{src}: a time vector needs at least 2 samples")
    dt = np.diff(t)
    if np.any(~np.isfinite(dt)) or np.any(dt <= 0):
        raise InputError(f"{src}: the time values must increase strictly")
    step = (t[-1] - t[0]) / (t.size - 1)
    dev = np.max(np.abs(t - (t[0] + step * np.arange(t.size))))
    if dev > rel * step + 1e-12 * abs(t[-1]):
        raise InputError(f"{src}: time samples are not uniformly spaced (deviation "
                         f"{dev:.3g} s from a uniform {step:.6g} s step); resample first")
    return 1.0 / step


def is_uniform_time(t: np.ndarray, rel: float = 0.1) -> bool:
    """True if ``t`` increases strictly with steps uniform to ``rel`` of a step: a time column
    (printed with few digits) rather than a signal."""
    t = np.asarray(t, dtype=float)
    if t.size < 3 or not np.all(np.isfinite(t)):
        return False
    step = (t[-1] - t[0]) / (t.size - 1)
    if step <= 0 or np.any(np.diff(t) <= 0):
        return False
    return bool(np.max(np.abs(t - (t[0] + step * np.arange(t.size)))) <= rel * step)


def is_time_name(name: str) -> bool:
    """``time``, ``t``, ``Time [s]``, ``time (s)`` … (case-insensitive)."""
    base, _ = split_unit(name)
    return base.strip().lower().replace(" ", "_") in TIME_NAMES


def split_unit(name: str) -> tuple[str, str]:
    """``'acc [m/s^2]'`` → ``('acc', 'm/s^2')``; ``'time (s)'`` → ``('time', 's')``."""
    s = str(name).strip()
    for a, b in (("[", "]"), ("(", ")")):
        if s.endswith(b) and a in s:
            i = s.rindex(a)
            return s[:i].strip(), s[i + 1:-1].strip()
    return s, ""


def read_raw(path: str | Path, *, delimiter: str | None = None, decimal: str | None = None,
             header: bool | None = None, time_channel: str | None = None,
             sources: list[str] | None = None) -> RawRecord:
    """Read every channel of a file (the format from its extension and magic bytes).

    ``delimiter``/``decimal``/``header`` override the CSV detection; ``time_channel`` names
    the file's time channel; ``sources`` (HDF5 of any layout) the dataset paths to read."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"record: file {p} does not exist")
    ext = p.suffix.lower()
    try:
        if ext in (".csv", ".tsv", ".txt", ".dat", ".asc"):
            from geardyn.io.table import read_table

            return read_table(p, delimiter=delimiter, decimal=decimal, header=header,
                              time_channel=time_channel)
        if ext in (".wav", ".flac"):
            from geardyn.io.audio import read_audio

            return read_audio(p)
        if ext in (".npy", ".npz"):
            from geardyn.io.arrays import read_numpy

            return read_numpy(p, time_channel=time_channel)
        if ext == ".mat":
            from geardyn.io.matlab import read_mat

            return read_mat(p, time_channel=time_channel)
        if ext == ".tdms":
            from geardyn.io.tdms import read_tdms

            return read_tdms(p)
        if ext in (".uff", ".unv"):
            from geardyn.io.uff import read_uff

            return read_uff(p)
        if ext in (".mf4", ".mdf"):
            from geardyn.io.mdf import read_mdf

            return read_mdf(p)
        if ext in (".nc", ".netcdf", ".cdf"):
            from geardyn.io.hdf import read_netcdf

            return read_netcdf(p, time_channel=time_channel)
        if ext in (".h5", ".hdf5", ".hdf", ".he5"):
            from geardyn.io.hdf import read_hdf5

            return read_hdf5(p, time_channel=time_channel, sources=sources)
    except InputError:
        raise
    except ImportError as exc:
        raise InputError(f"record: reading {p} needs the package '{exc.name}' "
                         f"(pip install {exc.name})") from None
    except Exception as exc:  # noqa: BLE001 - a malformed file: one clear message
        raise InputError(f"record: cannot read {p} as {ext[1:].upper()}: "
                         f"{type(exc).__name__}: {exc}") from None
    raise InputError(f"record: unsupported file type '{ext}' ({p}); supported: .csv/.tsv/.txt, "
                     ".wav/.flac, .npy/.npz, .mat (v5, v7.3), .tdms, .uff/.unv (58/58b), .mf4, "
                     ".nc, .h5/.hdf5")
