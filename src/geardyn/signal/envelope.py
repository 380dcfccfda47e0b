"""Envelope and squared-envelope spectra: band-pass (zero-phase Butterworth) around a resonance
or mesh frequency, analytic signal by the Hilbert transform, spectrum of its modulus (seed 003
§1.4, Ch.1 envelope analysis). Units: ``fs`` and ``band`` in Hz (or orders with an angle-domain
signal and ``fs`` = samples per revolution)."""

from __future__ import annotations

import numpy as np
import xarray as xr
from scipy import signal as sps

from geardyn.errors import InputError
from geardyn.signal._checks import array1d, positive
from geardyn.signal.spectra import amplitude_spectrum


def envelope(
    x: np.ndarray, fs: float, band: tuple[float, float] | None = None, order: int = 4
) -> np.ndarray:
    """|analytic signal| of ``x`` after an optional band-pass ``band = (f_lo, f_hi)`` [Hz]."""
    a = array1d("x", x, 16)
    f = positive("fs", fs, "sample rate [Hz]")
    if band is not None:
        lo, hi = (float(b) for b in band)
        if not 0 < lo < hi < f / 2:
            raise InputError(
                f"band: need 0 < f_lo < f_hi < fs/2 = {f / 2:g} Hz, got ({lo:g}, {hi:g})"
            )
        sos = sps.butter(order, (lo, hi), btype="bandpass", fs=f, output="sos")
        pad = 3 * (2 * len(sos) + 1)
        if a.size <= pad:
            raise InputError(f"x: the band-pass filter needs more than {pad} samples, got {a.size}")
        a = sps.sosfiltfilt(sos, a)
    return np.abs(sps.hilbert(a))


def envelope_spectrum(
    x: np.ndarray,
    fs: float,
    band: tuple[float, float] | None = None,
    squared: bool = True,
    window: str = "hann",
) -> xr.DataArray:
    """Amplitude spectrum of the (squared) envelope, mean removed; coordinate ``frequency``."""
    e = envelope(x, fs, band)
    if squared:
        e = e * e
    out = amplitude_spectrum(e - e.mean(), fs, window)
    out.name = "squared_envelope_spectrum" if squared else "envelope_spectrum"
    return out


def squared_envelope_spectrum(
    x: np.ndarray, fs: float, band: tuple[float, float] | None = None, unit: str = "Hz"
) -> xr.DataArray:
    """Squared-envelope spectrum (SES) of the band ``band = (lo, hi)``: amplitude spectrum
    (Hann, mean removed) of ``|x_b + j H{x_b}|²``, ``x_b`` = ``x`` band-passed to ``band``
    (Antoni 2007: the band of the fast kurtogram, ``fast_kurtogram(...).attrs["band"]``;
    Randall & Antoni 2011, "Rolling element bearing diagnostics — a tutorial", MSSP 25).
    Repetitive impulses at rate ``1/T`` give lines at ``k/T``. This is
    :func:`envelope_spectrum` with ``squared=True``; ``unit``: frequency unit of ``fs`` and
    ``band`` (``"events/rev"`` for an angle-domain signal, ``fs`` then in samples per
    revolution). Coordinate ``frequency`` [``unit``]."""
    out = envelope_spectrum(x, fs, band, squared=True)
    out["frequency"].attrs["units"] = unit
    return out
