"""Spectral kurtosis (SK) and an STFT-based kurtogram to choose the envelope band.

SK after Antoni (2006, "The spectral kurtosis: a useful tool for characterising non-stationary
signals", MSSP 20) with the STFT estimator of Antoni & Randall (2006, "The spectral kurtosis:
application to the vibratory surveillance and diagnostics of rotating machines", MSSP 20):

    SK(f) = ⟨|X(t, f)|⁴⟩_t / ⟨|X(t, f)|²⟩_t² − 2,

with ``X`` the STFT. SK is 0 for stationary Gaussian noise, −1 for a pure tone, and large and
positive in the band where repetitive impulses (bearing or tooth faults) excite a resonance.
The kurtogram evaluates SK for window lengths ``N_w = 2^k``: short windows resolve impulses
but blur frequency, long windows the opposite; the maximum over (window, frequency) gives the
band ``f_c ± f_s/N_w`` (the −6 dB bandwidth of a Hann window is ≈ 2 bins) in which to take the
envelope. This is the STFT kurtogram, not the 1/3-binary filter tree of the fast kurtogram
(Antoni 2007, MSSP 21); both pick the band of maximum SK.

Units: ``fs`` in Hz (frequency in Hz), or samples per revolution for an angle-domain signal
(frequency then in orders, events/rev: set ``unit="events/rev"``).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from geardyn.errors import InputError
from geardyn.signal._checks import array1d, positive, positive_int
from geardyn.signal.spectra import hann_stft

#: Fewest STFT segments for an SK estimate (its standard deviation is ≈ 2/√K for noise).
MIN_SEGMENTS = 16


def _sk(a: np.ndarray, fs: float, nperseg: int, overlap: float) -> tuple[np.ndarray, np.ndarray]:
    f, _, z = hann_stft(a, fs, nperseg, overlap)
    p2 = np.mean(np.abs(z) ** 2, axis=1)
    p4 = np.mean(np.abs(z) ** 4, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        sk = np.where(p2 > 0, p4 / np.where(p2 > 0, p2, 1.0) ** 2 - 2.0, 0.0)
    # DC and Nyquist bins are real: their SK is not the complex-Gaussian one; left out.
    sk[0] = 0.0
    if nperseg % 2 == 0:
        sk[-1] = 0.0
    return f, sk


def spectral_kurtosis(
    x: np.ndarray, fs: float, nperseg: int = 256, overlap: float = 0.75, unit: str = "Hz"
) -> xr.DataArray:
    """STFT estimate of the spectral kurtosis (Antoni & Randall 2006) with Hann windows of
    ``nperseg`` samples; coordinate ``frequency`` [``unit``]. Needs at least
    :data:`MIN_SEGMENTS` segments."""
    a = array1d("x", x, 8)
    f = positive("fs", fs, "sample rate")
    n = positive_int("nperseg", nperseg, "window length", minimum=8)
    if not 0.0 <= overlap < 1.0:
        raise InputError(f"overlap: must be in [0, 1), got {overlap!r}")
    hop = max(1, int(round(n * (1 - overlap))))
    k = 1 + (a.size - n) // hop if a.size >= n else 0
    if k < MIN_SEGMENTS:
        raise InputError(
            f"x: {a.size} samples give {k} segments of nperseg={n}; spectral kurtosis needs at "
            f"least {MIN_SEGMENTS} (record longer or use a shorter window)"
        )
    freq, sk = _sk(a, f, n, overlap)
    return xr.DataArray(
        sk,
        coords={"frequency": ("frequency", freq, {"units": unit})},
        dims="frequency",
        name="spectral_kurtosis",
        attrs={"units": "-", "long_name": "spectral kurtosis", "nperseg": n},
    )


def kurtogram(
    x: np.ndarray,
    fs: float,
    windows: tuple[int, ...] | None = None,
    overlap: float = 0.75,
    unit: str = "Hz",
    fmax: float | None = None,
) -> xr.DataArray:
    """STFT kurtogram: SK for each window length (default ``2^3 … 2^k`` with at least
    :data:`MIN_SEGMENTS` segments, up to 2⁸ = 256: longer windows span several impulses and
    lose them), on the frequency grid of the longest window
    (each level's value held over its own bins). Dims ``(window, frequency)``; attrs
    ``band`` (the chosen envelope band, :func:`best_band`) and ``units``. ``fmax``: highest
    frequency allowed for the band (e.g. the anti-aliasing limit of an order-tracked signal);
    SK above it is set to NaN."""
    a = array1d("x", x, 8)
    f = positive("fs", fs, "sample rate")
    if windows is None:
        hop_frac = 1 - overlap
        windows = tuple(
            2**k
            for k in range(3, 9)
            if 1 + (a.size - 2**k) / max(1, 2**k * hop_frac) >= MIN_SEGMENTS
        )
    if not windows:
        raise InputError(
            f"x: {a.size} samples are too few for a kurtogram (needs {MIN_SEGMENTS} segments "
            "of at least 8 samples)"
        )
    ws = sorted(positive_int("windows", w, "window length", minimum=8) for w in windows)
    grid = np.fft.rfftfreq(ws[-1], 1.0 / f)
    rows = []
    for n in ws:
        sk = spectral_kurtosis(a, f, n, overlap, unit)
        idx = np.clip(np.round(grid / (f / n)).astype(int), 0, sk.size - 1)
        rows.append(sk.values[idx])
    vals = np.array(rows)
    if fmax is not None:
        fm = positive("fmax", fmax, "highest band frequency")
        for i, n in enumerate(ws):
            vals[i, grid + f / n > fm] = np.nan
        if np.all(np.isnan(vals)):
            raise InputError(f"fmax: {fm:g} leaves no band below it (fs = {f:g})")
    out = xr.DataArray(
        vals,
        coords={
            "window": ("window", np.array(ws), {"units": "samples"}),
            "frequency": ("frequency", grid, {"units": unit}),
        },
        dims=("window", "frequency"),
        name="spectral_kurtosis",
        attrs={"units": "-", "long_name": "spectral kurtosis", "fs": f},
    )
    out.attrs["band"] = best_band(out)
    return out


def best_band(kg: xr.DataArray) -> tuple[float, float]:
    """Band ``(f_c − f_s/N_w, f_c + f_s/N_w)`` around the maximum of a kurtogram, clipped to
    ``(0, f_s/2)`` (frequency units of the kurtogram)."""
    fs = float(kg.attrs["fs"])
    vals = np.asarray(kg.values)
    i, j = np.unravel_index(int(np.nanargmax(vals)), vals.shape)
    nw = int(kg["window"].values[i])
    fc = float(kg["frequency"].values[j])
    half = fs / nw
    lo = max(fc - half, 0.5 * fs / nw)
    hi = min(fc + half, 0.5 * fs * (1 - 1 / nw))
    if hi <= lo:
        lo, hi = 0.25 * fs / nw, 0.5 * fs * (1 - 1 / nw)
    return float(lo), float(hi)


__all__ = ["MIN_SEGMENTS", "best_band", "kurtogram", "spectral_kurtosis"]
