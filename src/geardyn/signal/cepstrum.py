"""Cepstra (seed 003 eqs 1.27-1.28; seed 002 §3.4 suggests the cepstrum of the angular spectrum
to separate once-per-rev families).

* real cepstrum ``c(τ) = F⁻¹{ log|X(f)| }``;
* power cepstrum ``C(τ) = |F⁻¹{ log |X(f)|² }|²`` (seed 003 eq 1.27 with the auto-spectrum).

An echo ``x(t) = s(t) + a·s(t − τ0)`` (|a| < 1) gives rahmonics at ``τ0, 2τ0, …``. The quefrency
axis is in seconds for time signals (``fs`` [Hz]) or revolutions for angle signals (pass the
samples per revolution as ``fs``).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from geardyn.signal._checks import array1d, positive

_TINY = 1e-300


def real_cepstrum(x: np.ndarray, fs: float = 1.0) -> xr.DataArray:
    """Real cepstrum ``F⁻¹{log|X|}``; coordinate ``quefrency`` [s] (or [rev])."""
    a = array1d("x", x, 4)
    f = positive("fs", fs, "sample rate")
    c = np.fft.irfft(np.log(np.abs(np.fft.rfft(a)) + _TINY), a.size)
    q = np.arange(a.size) / f
    return xr.DataArray(c, coords={"quefrency": q}, dims="quefrency", name="real_cepstrum")


def power_cepstrum(x: np.ndarray, fs: float = 1.0) -> xr.DataArray:
    """Power cepstrum ``|F⁻¹{log|X|²}|²`` (seed 003 eq 1.27); coordinate ``quefrency``."""
    a = array1d("x", x, 4)
    f = positive("fs", fs, "sample rate")
    c = np.abs(np.fft.irfft(np.log(np.abs(np.fft.rfft(a)) ** 2 + _TINY), a.size)) ** 2
    q = np.arange(a.size) / f
    return xr.DataArray(c, coords={"quefrency": q}, dims="quefrency", name="power_cepstrum")
