"""Spectra: amplitude/order spectrum, PSD, time STFT (scipy ``ShortTimeFFT``), angular
spectrogram (short-angle Fourier transform), order–speed map / waterfall.

Amplitude spectra are scaled so that a sine of amplitude ``A`` at a bin centre reads ``A``
(window coherent gain removed). Order spectra use events per revolution of the reference shaft
(seed 002 §3.2). Outputs are ``xarray.DataArray`` with named, unit-annotated coordinates.
"""

from __future__ import annotations

import numpy as np
import xarray as xr
from scipy import signal as sps

from geardyn.errors import InputError
from geardyn.signal._checks import array1d, positive, positive_int


def _window(name: str, n: int) -> np.ndarray:
    try:
        return sps.get_window(name, n, fftbins=True)
    except ValueError as exc:
        raise InputError(f"window: unknown window {name!r} ({exc})") from None


def _amplitude(x: np.ndarray, window: str) -> np.ndarray:
    w = _window(window, x.size)
    spec = np.abs(np.fft.rfft((x - 0.0) * w)) * 2.0 / w.sum()
    spec[0] /= 2.0
    if x.size % 2 == 0:
        spec[-1] /= 2.0
    return spec


def _single_sided(
    x: np.ndarray, rate: float, rate_name: str, rate_what: str, dim: str, units: str, window: str
) -> xr.DataArray:
    """Window-corrected single-sided amplitude spectrum on coordinate ``dim``."""
    a = array1d("x", x, 4)
    r = positive(rate_name, rate, rate_what)
    spec = _amplitude(a, window)
    axis = np.fft.rfftfreq(a.size, 1.0 / r)
    return xr.DataArray(
        spec,
        coords={dim: (dim, axis, {"units": units})},
        dims=dim,
        name="amplitude",
        attrs={"window": window},
    )


def amplitude_spectrum(x: np.ndarray, fs: float, window: str = "hann") -> xr.DataArray:
    """Single-sided amplitude spectrum of ``x`` sampled at ``fs`` [Hz]; coordinate ``frequency``
    [Hz] (seed 003 eq 1.26, discrete, window-corrected)."""
    return _single_sided(x, fs, "fs", "sample rate [Hz]", "frequency", "Hz", window)


def order_spectrum(x: np.ndarray, samples_per_rev: float, window: str = "hann") -> xr.DataArray:
    """Order spectrum of an angle-domain signal (``samples_per_rev`` samples per revolution):
    coordinate ``order`` [events/rev] with resolution ``1/revolutions`` (seed 002 §3.2)."""
    return _single_sided(
        x,
        samples_per_rev,
        "samples_per_rev",
        "samples per revolution",
        "order",
        "events/rev",
        window,
    )


def psd(x: np.ndarray, fs: float, nperseg: int = 4096, window: str = "hann") -> xr.DataArray:
    """Welch power spectral density [unit²/Hz], coordinate ``frequency`` [Hz]."""
    a = array1d("x", x, 4)
    f = positive("fs", fs, "sample rate [Hz]")
    n = min(positive_int("nperseg", nperseg, "segment length", minimum=4), a.size)
    freq, p = sps.welch(a, fs=f, window=window, nperseg=n)
    return xr.DataArray(
        p,
        coords={"frequency": ("frequency", freq, {"units": "Hz"})},
        dims="frequency",
        name="psd",
    )


def _stft(a, rate, nperseg, overlap, window):
    n = positive_int("nperseg", nperseg, "segment length", minimum=4)
    if n > a.size:
        raise InputError(f"nperseg: segment length {n} exceeds the signal length {a.size}")
    if not 0.0 <= overlap < 1.0:
        raise InputError(f"overlap: must be in [0, 1), got {overlap!r}")
    hop = max(1, int(round(n * (1.0 - overlap))))
    w = _window(window, n)
    sft = sps.ShortTimeFFT(w, hop=hop, fs=rate, scale_to="magnitude", mfft=n)
    # Only segments fully inside the signal (no zero-padded ends).
    p0 = sft.lower_border_end[1]
    p1 = sft.upper_border_begin(a.size)[1]
    s = sft.stft(a, p0=p0, p1=p1)
    mag = 2.0 * np.abs(s)
    mag[0] /= 2.0
    centres = sft.t(a.size, p0=p0, p1=p1)
    return sft.f, centres, mag


def stft(
    x: np.ndarray, fs: float, nperseg: int = 1024, overlap: float = 0.75, window: str = "hann"
) -> xr.DataArray:
    """Time STFT magnitude (seed 003 eqs 1.29-1.30) with scipy ``ShortTimeFFT``, amplitude
    scaled; dims ``(frequency [Hz], time [s])``; only segments fully inside the record."""
    a = array1d("x", x, 4)
    f = positive("fs", fs, "sample rate [Hz]")
    freq, centres, mag = _stft(a, f, nperseg, overlap, window)
    return xr.DataArray(
        mag,
        coords={
            "frequency": ("frequency", freq, {"units": "Hz"}),
            "time": ("time", centres, {"units": "s"}),
        },
        dims=("frequency", "time"),
        name="amplitude",
    )


def angular_spectrogram(
    x: np.ndarray,
    samples_per_rev: int,
    revs_per_segment: float = 8.0,
    overlap: float = 0.75,
    window: str = "hann",
    speed: np.ndarray | None = None,
) -> xr.DataArray:
    """Short-angle Fourier transform of an angle-domain signal: dims ``(order, angle)``; angle in
    revolutions at segment centres. If ``speed`` (one value per sample, e.g. rpm from
    :class:`AngleSignal.time`) is given, a ``speed`` coordinate (segment mean) is attached so
    that the result is an order–speed map / waterfall (plot against ``speed``)."""
    a = array1d("x", x, 4)
    spr = positive_int("samples_per_rev", samples_per_rev, "samples per revolution")
    n = int(round(positive("revs_per_segment", revs_per_segment) * spr))
    order, centres, mag = _stft(a, float(spr), n, overlap, window)
    coords = {
        "order": ("order", order, {"units": "events/rev"}),
        "angle": ("angle", centres, {"units": "rev"}),
    }
    if speed is not None:
        sp = array1d("speed", speed, a.size)
        if sp.size != a.size:
            raise InputError("speed: needs one value per angle sample")
        idx = np.clip(np.round(centres * spr).astype(int), 0, a.size - 1)
        half = n // 2
        cs = np.concatenate([[0.0], np.cumsum(sp)])
        lo = np.clip(idx - half, 0, a.size)
        hi = np.clip(idx + half, 1, a.size)
        coords["speed"] = ("angle", (cs[hi] - cs[lo]) / (hi - lo))
    return xr.DataArray(mag, coords=coords, dims=("order", "angle"), name="amplitude")


def order_speed_map(
    x: np.ndarray,
    fs: float,
    angle: np.ndarray,
    samples_per_rev: int = 256,
    revs_per_segment: float = 8.0,
    overlap: float = 0.75,
) -> xr.DataArray:
    """Order–speed map (waterfall) of a time signal with reference ``angle`` [rad] per sample:
    resample to angle, short-angle FT, and attach the segment mean speed [rpm]."""
    from geardyn.signal.resample import resample_to_angle

    sig = resample_to_angle(x, fs, angle, samples_per_rev=samples_per_rev)
    rpm = 60.0 / (samples_per_rev * np.gradient(sig.time))
    out = angular_spectrogram(sig.x, samples_per_rev, revs_per_segment, overlap, speed=rpm)
    out.coords["speed"].attrs["units"] = "rpm"
    return out


def hann_stft(x: np.ndarray, fs: float, nperseg: int, overlap: float):  # noqa: ANN201
    """Complex STFT ``(f, t, Z)`` of the mean-removed ``x``: Hann window, ``overlap`` fraction,
    no boundary padding or detrending (the common core of the kurtogram and order tracking)."""
    from scipy import signal as sps

    return sps.stft(x - x.mean(), fs=fs, window="hann", nperseg=nperseg,
                    noverlap=int(round(nperseg * overlap)), boundary=None, padded=False,
                    detrend=False)
