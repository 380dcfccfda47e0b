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
envelope. :func:`kurtogram` is this STFT kurtogram; :func:`fast_kurtogram` is the 1/3-binary filter
tree of the fast kurtogram (Antoni 2007, MSSP 21, 108-124), the one the diagnosis uses. Both
pick the band of maximum SK (:func:`best_band`).

Units: ``fs`` in Hz (frequency in Hz), or samples per revolution for an angle-domain signal
(frequency then in orders, events/rev: set ``unit="events/rev"``).
"""

from __future__ import annotations

import numba
import numpy as np
import xarray as xr
from scipy import signal as sps

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


# ------------------------------------------------------------------ fast kurtogram
#: Low-pass prototype h0 of the binary split (Antoni 2007): cut-off 1/8 + ε so that
#: neighbouring bands overlap and no frequency falls between them; order 16, Hamming window,
#: −6 dB at 0.2 cycles/sample (ε = 0.075), the values of Antoni's program Fast_Kurtogram.m.
_H0 = sps.firwin(17, 0.4)
#: Prototype of the 1/3 split (same program): order 24, −6 dB at 2/15 cycles/sample
#: = 1/12 + 0.05.
_H1 = sps.firwin(25, 0.4 * 2 / 3)
_N_H0 = np.arange(_H0.size)
_N_H1 = np.arange(_H1.size)
#: Quasi-analytic low part h(n) = h0(n) e^{jπn/4} ([0, 1/4]) and high part
#: g(n) = h0(n) e^{j3πn/4} ([1/4, 1/2]) (Antoni 2007). Antoni's program builds g from h
#: reversed in time and modulated by (−1)^n: the same magnitude response.
_H_LOW = _H0 * np.exp(2j * np.pi * _N_H0 / 8)
_H_HIGH = _H0 * np.exp(2j * np.pi * 3 * _N_H0 / 8)
#: The three 1/3 parts h_i(n) = h1(n) e^{j2π(2i+1)n/12}, i = 0, 1, 2 ([i/6, (i+1)/6]).
_H_THIRDS = tuple(_H1 * np.exp(2j * np.pi * (2 * i + 1) * _N_H1 / 12) for i in range(3))
#: Fewest samples per band at the finest level: the paper's rule nlevel ≤ log2(N) − 7.
_SAMPLES_FINEST = 2**7


@numba.njit(cache=True, nogil=True)
def _fir_decimate_rows(  # pragma: no cover - numba
    x: np.ndarray, taps: np.ndarray, q: int, sign: bool
) -> np.ndarray:
    """Rows of ``x`` filtered by ``taps`` (fully overlapping part only: no start-up
    transient) and kept one sample in ``q``: ``y[k] = Σ_m taps[m] x[qk + L − 1 − m]``, times
    ``(−1)^k`` if ``sign``."""
    rows, n = x.shape
    n_taps = taps.size
    n_out = max((n - n_taps) // q + 1, 0)
    out = np.empty((rows, n_out), dtype=np.complex128)
    for r in range(rows):
        for k in range(n_out):
            acc = 0.0j
            base = q * k + n_taps - 1
            for m in range(n_taps):
                acc += taps[m] * x[r, base - m]
            out[r, k] = -acc if (sign and k % 2 == 1) else acc
    return out


@numba.njit(cache=True, nogil=True)
def _fir_decimate_kurtosis(  # pragma: no cover - numba
    x: np.ndarray, taps: np.ndarray, q: int, floor: float
) -> np.ndarray:
    """:func:`_complex_kurtosis` of :func:`_fir_decimate_rows` ``(x, taps, q)``, without
    storing the filtered rows (NaN for a row too short to give one output sample)."""
    rows, n = x.shape
    n_taps = taps.size
    n_out = (n - n_taps) // q + 1
    out = np.empty(rows)
    for r in range(rows):
        if n_out <= 0:
            out[r] = np.nan
            continue
        m2 = 0.0
        m4 = 0.0
        for k in range(n_out):
            acc = 0.0j
            base = q * k + n_taps - 1
            for m in range(n_taps):
                acc += taps[m] * x[r, base - m]
            p = acc.real * acc.real + acc.imag * acc.imag
            m2 += p
            m4 += p * p
        m2 /= n_out
        m4 /= n_out
        out[r] = m4 / (m2 * m2) - 2.0 if m2 > floor else 0.0
    return out


def _complex_kurtosis(c: np.ndarray, floor: float) -> np.ndarray:
    """Kurtosis of complex envelopes (one per row): E|c|⁴ / (E|c|²)² − 2, zero for a
    circular complex Gaussian, −1 for a constant modulus (Antoni 2007). Rows whose
    power is at or below ``floor`` (rounding noise only) get 0, the Gaussian value."""
    p = c.real**2 + c.imag**2
    m2 = p.mean(axis=1)
    m4 = (p * p).mean(axis=1)
    ok = m2 > floor
    return np.where(ok, m4 / np.where(ok, m2, 1.0) ** 2 - 2.0, 0.0)


def _kept(n_rows: int, width: float, fmax: float) -> int:
    """Bands (in frequency order, ``width`` wide from 0) whose lower edge is below ``fmax``:
    the others, and every band split from them, lie wholly above it."""
    if not np.isfinite(fmax):
        return n_rows
    return min(n_rows, int(np.ceil(fmax / width - 1e-12)))


def _fast_kurtogram_rows(
    a: np.ndarray, nlevel: int, fmax: float = np.inf
) -> list[tuple[float, np.ndarray]]:
    """(level, kurtosis of each band in frequency order) for levels 0, 1, 1.6, 2, …, nlevel
    of the 1/3-binary tree (Antoni 2007) fed with the analytic signal ``a + jH{a}``: the 1/2
    splits of level k−1 give level k, its 1/3 splits level k + log₂3 − 1 (bandwidth
    ``2^−(level+1)`` of the sample rate). ``fmax`` (fraction of the sample rate): bands whose
    lower edge is at or above it are not computed (NaN), nor split further — the filter bank
    of the bands below it is the same."""
    floor = (16 * np.finfo(float).eps) ** 2 * float(np.mean(a * a))
    nodes = sps.hilbert(a)[None, :]
    rows = [(0.0, _complex_kurtosis(nodes, floor))]
    for k in range(1, nlevel + 1):
        keep = _kept(2 * nodes.shape[0], 2.0 ** -(k + 1), fmax)
        src = nodes[: (keep + 1) // 2]
        low = _fir_decimate_rows(src, _H_LOW, 2, False)
        # the decimated high part lies in [−1/2, 0]: (−1)^n brings it back to [0, 1/2]
        high = _fir_decimate_rows(src, _H_HIGH, 2, True)
        halves = np.empty((2 * low.shape[0], low.shape[1]), dtype=complex)
        halves[0::2], halves[1::2] = low, high
        halves = halves[:keep]
        kh = np.full(2**k, np.nan)
        kh[:keep] = _complex_kurtosis(halves, floor)
        rows.append((float(k), kh))
        if k < nlevel:  # 1/3 bands of level k − 1: level k + log2(3) − 1
            keep3 = _kept(3 * nodes.shape[0], 2.0 ** -(k + 1) * 2 / 3, fmax)
            src3 = nodes[: (keep3 + 2) // 3]
            kq = np.full(3 * 2 ** (k - 1), np.nan)
            kq[: 3 * src3.shape[0]] = np.stack(
                [_fir_decimate_kurtosis(src3, h, 3, floor) for h in _H_THIRDS], axis=1
            ).ravel()
            kq[keep3:] = np.nan
            rows.append((k + np.log2(3.0) - 1.0, kq))
        nodes = halves
    return rows


def fast_kurtogram(
    x: np.ndarray,
    fs: float,
    nlevel: int | None = None,
    unit: str = "Hz",
    fmax: float | None = None,
) -> xr.DataArray:
    """Fast kurtogram (Antoni 2007, "Fast computation of the kurtogram for the detection of
    transient faults", MSSP 21, 108-124): kurtosis of the complex envelope of every band of
    the 1/3-binary tree filter bank.

    Each level splits every band of the level above in two with the quasi-analytic pair
    h(n) = h0(n) e^{jπn/4}, g(n) = h0(n) e^{j3πn/4} followed by decimation by 2 (h0:
    16th-order Hamming FIR, cut-off 1/8 + ε), and in three with h1(n) e^{j2π(2i+1)n/12}
    and decimation by 3. Level ``k`` (k = 0 … ``nlevel``) has ``2^k`` bands of width
    ``fs/2^(k+1)``; level ``k + log2(3) − 1`` (k = 1 … ``nlevel``−1) has ``3·2^(k−1)`` bands
    of width ``fs/(3·2^k)``; bandwidth = ``fs·2^−(level+1)`` on every row. The kurtosis of
    each band's output ``c`` (only samples where the filters lie wholly inside the record) is
    ``K = E|c|⁴ / (E|c|²)² − 2``: 0 for circular Gaussian noise (standard deviation
    ≈ 2/√N_band for N_band output samples), −1 for a pure tone, large where repeated
    impulses excite a resonance. The tree is fed with the analytic signal ``x + jH{x}`` of
    the mean-removed record (level 0 = the whole band [0, fs/2]); Antoni's program feeds the
    real ``x``, whose mirror spectrum near 0 and fs/2 leaks through the quasi-analytic filters
    into the edge bands and makes their output non-circular (Gaussian noise then gives
    K = |E c²|²/(E|c|²)² ≈ +0.18 at level 1 instead of 0), and uses the real kurtosis
    E x⁴/(E x²)² − 3 at level 0. Negative values are kept (the program clips them to 0).

    ``nlevel``: number of binary levels; default and maximum ``floor(log2 N) − 7`` (Antoni's
    rule, program Fast_Kurtogram: at least 2⁷ = 128 samples per band at the finest level),
    so ``x`` needs ≥ 256 samples. ``fs``: sample rate [Hz], or samples per revolution for an
    angle-domain signal (frequencies then in orders: ``unit="events/rev"``). ``fmax``: highest
    frequency allowed for the selected band (e.g. the anti-aliasing limit of an order-tracked
    signal): bands whose upper edge exceeds it are NaN.

    Returns dims ``(level, frequency)``: coordinate ``level`` [-] (0, 1, 1.6, 2, 2.6, …,
    ``nlevel``), non-dimension coordinate ``bandwidth`` [``unit``] on ``level``, coordinate
    ``frequency`` [``unit``] = centres of the finest grid, ``fs/(3·2^(nlevel+1))`` wide, on
    which each band's value is held over the columns it covers (Antoni's display). attrs:
    ``band`` = (lo, hi) of the cell of maximum kurtosis (:func:`best_band`), ``fs``,
    ``nlevel``, ``units``.
    """
    a = array1d("x", x, 2 * _SAMPLES_FINEST)
    f = positive("fs", fs, "sample rate")
    top = int(np.floor(np.log2(a.size))) - 7
    if nlevel is None:
        n_lev = top
    else:
        n_lev = positive_int("nlevel", nlevel, "number of levels")
        if n_lev > top:
            raise InputError(
                f"nlevel: at most log2(N) − 7 = {top} for N = {a.size} samples (≥ "
                f"{_SAMPLES_FINEST} samples per band at the finest level), got {nlevel!r}"
            )
    a = a - a.mean()
    if not np.any(a):
        raise InputError("x: the signal is constant; its kurtogram is undefined")
    fm_frac = np.inf if fmax is None else positive("fmax", fmax, "highest band frequency") / f
    rows = _fast_kurtogram_rows(a, n_lev, fm_frac)
    n_col = 3 * 2**n_lev
    unit_w = f / (2 * n_col)
    grid = (np.arange(n_col) + 0.5) * unit_w
    levels = np.array([lev for lev, _ in rows])
    width = f * 2.0 ** -(levels + 1)
    vals = np.array([k[np.repeat(np.arange(k.size), n_col // k.size)] for _, k in rows])
    if fmax is not None:
        fm = positive("fmax", fmax, "highest band frequency")
        hi = (np.floor(grid[None, :] / width[:, None]) + 1) * width[:, None]
        vals[hi > fm * (1 + 1e-12)] = np.nan
        if np.all(np.isnan(vals)):
            raise InputError(
                f"fmax: {fm:g} leaves no band below it (narrowest band {width[-1]:g} {unit})"
            )
    out = xr.DataArray(
        vals,
        coords={
            "level": ("level", levels, {"units": "-", "long_name": "level k = −log2(B/fs) − 1"}),
            "bandwidth": ("level", width, {"units": unit, "long_name": "bandwidth B"}),
            "frequency": ("frequency", grid, {"units": unit}),
        },
        dims=("level", "frequency"),
        name="spectral_kurtosis",
        attrs={
            "units": "-",
            "long_name": "kurtosis of the complex envelope (fast kurtogram, Antoni 2007)",
            "fs": f,
            "nlevel": n_lev,
        },
    )
    out.attrs["band"] = best_band(out)
    return out


def _best_band_fast(kg: xr.DataArray) -> tuple[float, float]:
    """(lo, hi) of the fast-kurtogram cell of maximum kurtosis; a band touching 0 or fs/2 is
    narrowed by half a column of the finest grid so that a band-pass filter exists."""
    fs = float(kg.attrs["fs"])
    vals = np.asarray(kg.values)
    i, j = np.unravel_index(int(np.nanargmax(vals)), vals.shape)
    width = float(kg["bandwidth"].values[i])
    freq = kg["frequency"].values
    lo = np.floor(freq[j] / width) * width
    margin = 0.5 * float(freq[1] - freq[0]) if freq.size > 1 else 0.25 * width
    return float(max(lo, margin)), float(min(lo + width, 0.5 * fs - margin))


def best_band(kg: xr.DataArray) -> tuple[float, float]:
    """Envelope band at the maximum of a kurtogram (frequency units of the kurtogram). Fast
    kurtogram (dim ``level``): the band of the maximum cell. STFT kurtogram (dim
    ``window``): ``(f_c − f_s/N_w, f_c + f_s/N_w)``, clipped to ``(0, f_s/2)``."""
    if "level" in kg.dims:
        return _best_band_fast(kg)
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


__all__ = ["MIN_SEGMENTS", "best_band", "fast_kurtogram", "kurtogram", "spectral_kurtosis"]
