"""Continuous wavelet transform with the Morlet wavelet (PyWavelets ``cwt``, ``'morl'``).

Seed 003 eqs 1.33-1.34: ``d(a, b) = a^{-1/2} ∫ q(t) ψ((t − b)/a) dt``. Seed 004 §2.10 settings:
scales 1:50:2001 for cracks, 1:10:501 for spalls (:data:`SEED004_CRACK_SCALES`,
:data:`SEED004_SPALL_SCALES`), on averaged signals of 2¹⁶ points.
"""

from __future__ import annotations

import numpy as np
import pywt
import xarray as xr

from geardyn.errors import InputError
from geardyn.signal._checks import array1d, positive

SEED004_CRACK_SCALES = np.arange(1, 2002, 50)
SEED004_SPALL_SCALES = np.arange(1, 502, 10)


def cwt_morlet(x: np.ndarray, fs: float = 1.0, scales: np.ndarray | None = None) -> xr.DataArray:
    """|CWT| with the real Morlet wavelet; dims ``(scale, position)`` with a ``frequency``
    coordinate (pseudo-frequency ``pywt.scale2frequency('morl', a)·fs``, Hz or orders)
    and ``position`` in s (or rev). Default scales: seed 004 crack setting 1:50:2001."""
    a = array1d("x", x, 4)
    f = positive("fs", fs, "sample rate")
    sc = SEED004_CRACK_SCALES if scales is None else np.asarray(scales, dtype=float)
    if sc.ndim != 1 or sc.size == 0 or np.any(sc <= 0):
        raise InputError("scales: must be a non-empty 1-D array of positive scales")
    coef, freqs = pywt.cwt(a, sc, "morl", sampling_period=1.0 / f)
    return xr.DataArray(
        np.abs(coef),
        coords={"scale": sc, "frequency": ("scale", freqs), "position": np.arange(a.size) / f},
        dims=("scale", "position"),
        name="cwt_magnitude",
    )
