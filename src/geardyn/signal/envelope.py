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


#: Bandwidths kept on each side of the band by :func:`band_squared_envelope_spectrum`.
SKIRT = 4


def band_squared_envelope_spectrum(
    x: np.ndarray, fs: float, band: tuple[float, float], order: int = 4
) -> xr.DataArray:
    """:func:`envelope_spectrum` (squared, Hann, mean removed) of the band ``(lo, hi)``
    computed from the band's own Fourier bins: with ``Z`` the analytic signal's spectrum
    (``2·X_b`` for ``0 < f < fs/2``, ``X_b`` at 0 and fs/2; ``X_b`` that of the zero-phase
    band-passed ``x``), the DFT of ``|z|²`` is the autocorrelation ``E[m] = Σ_k Z[k+m]
    Z*[k] / N``, taken over the bins within :data:`SKIRT` bandwidths of the band (outside
    them the zero-phase 4th-order Butterworth band-pass, amplitude ``1/(1 + Ω⁸)`` with
    ``Ω ≈ 2·|f − f_c|/B``, passes less than 2.4·10⁻⁸ of the amplitude, so the cross terms
    with the band that are dropped are below that fraction) by a zero-padded FFT of twice
    their number; the periodic Hann window is the 3-term convolution
    ``0.5·E[m] − 0.25·(E[m−1] + E[m+1])``. Same values as :func:`envelope_spectrum` to that
    truncation, without the record-long complex FFTs of the analytic signal; the spectrum
    stops where ``|z|²`` has no content (lags beyond the bins kept: ``2·SKIRT + 1``
    bandwidths)."""
    from scipy import fft as sfft

    a = array1d("x", x, 16)
    f = positive("fs", fs, "sample rate [Hz]")
    lo, hi = (float(b) for b in band)
    if not 0 < lo < hi < f / 2:
        raise InputError(f"band: need 0 < f_lo < f_hi < fs/2 = {f / 2:g} Hz, got ({lo:g}, {hi:g})")
    sos = sps.butter(order, (lo, hi), btype="bandpass", fs=f, output="sos")
    pad = 3 * (2 * len(sos) + 1)
    if a.size <= pad:
        raise InputError(f"x: the band-pass filter needs more than {pad} samples, got {a.size}")
    n = a.size
    xb = sfft.rfft(sps.sosfiltfilt(sos, a))
    width = hi - lo
    k0 = max(0, int(np.floor((lo - SKIRT * width) * n / f)))
    k1 = min(xb.size - 1, int(np.ceil((hi + SKIRT * width) * n / f)))
    z = xb[k0 : k1 + 1] * 2.0
    if k0 == 0:
        z[0] /= 2.0
    if n % 2 == 0 and k1 == xb.size - 1:
        z[-1] /= 2.0
    del xb
    m = z.size
    size = sfft.next_fast_len(2 * m)
    v = sfft.ifft(z, size)
    e = sfft.fft(v.real**2 + v.imag**2)[: m + 1] * (size / n)  # E[0 … m], E[m] = 0
    e[0] = 0.0  # mean removed
    ext = np.concatenate([np.conj(e[1:2]), e, [0.0]])  # E[−1] = conj(E[1]); E[m+1] = 0
    win = 0.5 * ext[1:-1] - 0.25 * (ext[:-2] + ext[2:])
    nbin = min(n // 2 + 1, m + 2)
    spec = np.zeros(nbin)
    k = min(nbin, win.size)
    spec[:k] = np.abs(win[:k]) * 4.0 / n
    spec[0] /= 2.0
    if n % 2 == 0 and nbin == n // 2 + 1:
        spec[-1] /= 2.0
    out = xr.DataArray(
        spec,
        coords={"frequency": ("frequency", np.arange(nbin) * f / n, {"units": "Hz"})},
        dims="frequency",
        name="squared_envelope_spectrum",
        attrs={"window": "hann", "band": (lo, hi)},
    )
    return out
