"""Long records in ``geardyn analyze``: the same analysis in bounded memory (issue 13 item 2).

A record longer than :data:`LONG_SAMPLES` is never copied whole: it stays as read (a float32
``.npy`` is memory-mapped, not converted), the order tracking runs on overlapping chunks
(:func:`resample_chunked`), the time spectrogram averages the STFT frames of blocks
(:func:`block_spectrogram`), the raw-signal indicators accumulate moments chunk by chunk
(:func:`chunked_indicators`), and the per-component indicators use a central excerpt of whole
revolutions (:func:`central_excerpt`). Memory then grows with the angle-domain signal
(samples/rev × revolutions), not with the time samples.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from geardyn.errors import InputError

#: Records longer than this (samples) take the bounded-memory path.
LONG_SAMPLES = 1 << 22
#: Samples of the central excerpt used for the per-component indicators of a long record.
FEATURE_SAMPLES = 1 << 20
#: Core length of one order-tracking chunk and its overlap on each side (samples).
CHUNK = 1 << 21
MARGIN = 1 << 15


def resample_chunked(x: np.ndarray, fs: float, angle_of_time: Callable[[np.ndarray], np.ndarray],
                     samples_per_rev: int, i0: int = 0, i1: int | None = None):  # noqa: ANN201
    """:func:`geardyn.signal.resample_to_angle` of ``x[i0:i1]`` chunk by chunk.

    Each chunk of :data:`CHUNK` samples is resampled with :data:`MARGIN` samples of overlap on
    both sides (the zero-phase anti-aliasing filter settles within the margin) and keeps the
    angle samples whose instants fall in its core; the angle grid is absolute (multiples of
    2π/samples_per_rev), so the chunks join without a seam. ``angle_of_time`` gives the
    reference angle [rad] at times [s]. The valid order range is the smallest of the chunks'.
    """
    from geardyn.signal import resample_to_angle
    from geardyn.signal.resample import AngleSignal

    n = x.shape[0]
    i1 = n if i1 is None else i1
    parts: list[np.ndarray] = []
    times: list[np.ndarray] = []
    angle0 = None
    valid = math.inf
    for a in range(i0, i1, CHUNK):
        b = min(i1, a + CHUNK)
        lo, hi = max(i0, a - MARGIN), min(i1, b + MARGIN)
        if hi - lo < 16:
            continue
        t = np.arange(lo, hi) / fs
        sig = resample_to_angle(np.asarray(x[lo:hi], dtype=float), fs, angle_of_time(t),
                                samples_per_rev=samples_per_rev, t0=lo / fs)
        keep = (sig.time >= a / fs) & (sig.time < b / fs) if b < i1 else sig.time >= a / fs
        if not np.any(keep):
            continue
        first = int(np.argmax(keep))
        if angle0 is None:
            angle0 = sig.angle0 + 2 * np.pi * first / samples_per_rev
        parts.append(sig.x[keep])
        times.append(sig.time[keep])
        valid = min(valid, sig.max_valid_order)
    if angle0 is None:
        raise InputError("angle: the record spans fewer than 4 angular samples")
    return AngleSignal(np.concatenate(parts), samples_per_rev, float(angle0),
                       np.concatenate(times), valid)


def block_spectrogram(x: np.ndarray, fs: float, nperseg: int, max_columns: int = 512):  # noqa: ANN201
    """Time spectrogram of a long record with at most ``max_columns`` time columns: each
    column is the mean STFT magnitude (:func:`geardyn.signal.stft`, Hann, 50 % overlap) of one
    block of the record (block centre as its time); dims ``(frequency [Hz], time [s])``."""
    import xarray as xr

    from geardyn.signal import stft

    n = x.shape[0]
    block = max(2 * nperseg, math.ceil(n / max_columns))
    columns, centres, freq = [], [], None
    for a in range(0, n - nperseg + 1, block):
        b = min(n, a + block)
        if b - a < nperseg:
            break
        s = stft(np.asarray(x[a:b], dtype=float), fs, nperseg=nperseg, overlap=0.5)
        freq = s["frequency"].values
        columns.append(s.values.mean(axis=1))
        centres.append((a + b) / 2 / fs)
    return xr.DataArray(
        np.stack(columns, axis=1),
        coords={"frequency": ("frequency", freq, {"units": "Hz"}),
                "time": ("time", np.asarray(centres), {"units": "s"})},
        dims=("frequency", "time"), name="amplitude",
        attrs={"note": f"mean STFT magnitude over blocks of {block} samples"},
    )


def chunked_indicators(x: np.ndarray, chunk: int = CHUNK) -> dict[str, float]:
    """:func:`geardyn.signal.signal_indicators` (RMS, peak, crest factor, kurtosis, skewness;
    Hammami 2015, eqs 1.21-1.24) from moments accumulated chunk by chunk: central moments about the
    mean of a first pass, so the sums stay well conditioned."""
    n = x.shape[0]
    if n < 2:
        raise InputError("x: needs at least 2 samples")
    total = 0.0
    for a in range(0, n, chunk):
        total += float(np.sum(x[a:a + chunk], dtype=float))
    mean = total / n
    s2 = s3 = s4 = sq = 0.0
    pk = 0.0
    for a in range(0, n, chunk):
        v = np.asarray(x[a:a + chunk], dtype=float)
        sq += float(np.dot(v, v))
        pk = max(pk, float(np.max(np.abs(v))))
        c = v - mean
        c2 = c * c
        s2 += float(np.sum(c2))
        s3 += float(np.dot(c2, c))
        s4 += float(np.dot(c2, c2))
    rms = math.sqrt(sq / n)
    var = s2 / n
    if var == 0:
        raise InputError("x: signal is constant; normalised moments are undefined")
    return {"rms": rms, "peak": pk, "crest_factor": pk / rms if rms > 0 else math.nan,
            "kurtosis": (s4 / n) / var**2, "skewness": (s3 / n) / var**1.5}


def central_excerpt(i0: int, i1: int, max_samples: int | None = None) -> tuple[int, int]:
    """The central ``max_samples`` (default :data:`FEATURE_SAMPLES`) of the sample range
    ``[i0, i1)`` (all of it if shorter)."""
    max_samples = FEATURE_SAMPLES if max_samples is None else max_samples
    if i1 - i0 <= max_samples:
        return i0, i1
    mid = (i0 + i1) // 2
    return mid - max_samples // 2, mid + max_samples // 2
