"""Spectral kurtosis and the STFT kurtogram against closed forms (Antoni 2006): SK = 0 for
stationary Gaussian noise, −1 for a pure tone, large in the band of repetitive impulses."""

from __future__ import annotations

import numpy as np
import pytest

from geardyn.errors import InputError
from geardyn.signal import best_band, kurtogram, spectral_kurtosis

FS = 20_000.0


def impulses_in_noise(seed: int = 0, n: int = 2**16) -> np.ndarray:
    """Impulses every 12.3 ms exciting a 3 kHz resonance (decay 600 s⁻¹), impulse-response
    RMS 1, in white noise of σ = 0.5."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / FS
    tt = np.arange(0, 0.02, 1 / FS)
    h = np.exp(-600 * tt) * np.sin(2 * np.pi * 3000 * tt)
    imp = np.zeros(n)
    imp[(np.arange(0.005, t[-1], 0.0123) * FS).astype(int)] = 1.0
    y = np.convolve(imp, h)[:n]
    return y / np.std(y) + rng.normal(0, 0.5, n)


def test_white_noise_has_zero_spectral_kurtosis():
    """SK estimator variance ≈ 4/K for K segments (Antoni 2006); K ≥ 1000 here, so |mean| <
    0.05 and every bin within ±0.35 (≈ 5 standard deviations) for windows 16…256."""
    x = np.random.default_rng(1).normal(size=2**16)
    for n in (16, 64, 256):
        sk = spectral_kurtosis(x, FS, n).values[1:-1]
        assert abs(sk.mean()) < 0.05
        assert np.max(np.abs(sk)) < 0.35


def test_pure_tone_has_spectral_kurtosis_minus_one():
    """|X| constant at the tone's bin: ⟨|X|⁴⟩/⟨|X|²⟩² = 1, SK = −1 (to 1e-6)."""
    n = 2**14
    x = np.cos(2 * np.pi * 64 * np.arange(n) / 1024)  # exactly on bin 4 of a 64-point window
    sk = spectral_kurtosis(x, 1024.0, 64)
    assert float(sk.sel(frequency=64.0)) == pytest.approx(-1.0, abs=1e-6)


def test_impulses_give_large_sk_in_their_band_and_the_kurtogram_finds_it():
    """Measured with a 32-sample window: SK 3.3 at the 3 kHz resonance, 5.8 at its maximum
    (1.6–1.9 kHz, the flank where the filtered impulse response is shortest), ≈ 0 at 8 kHz
    (noise only). Asserted: SK > 2 at 3 kHz and < 0.5 at 8 kHz; the kurtogram maximum > 4; the
    squared envelope in the chosen band shows the impulse rate 1/12.3 ms = 81.3 Hz at > 10×
    the median level (what the band is chosen for)."""
    from geardyn.signal import envelope_spectrum

    y = impulses_in_noise()
    sk = spectral_kurtosis(y, FS, 32)
    assert float(sk.sel(frequency=3000, method="nearest")) > 2.0
    assert float(sk.sel(frequency=8000, method="nearest")) < 0.5
    kg = kurtogram(y, FS)
    assert float(kg.max()) > 4.0
    band = kg.attrs["band"]
    assert band == best_band(kg)
    assert kg.dims == ("window", "frequency")
    ses = envelope_spectrum(y, FS, band)
    line = float(ses.sel(frequency=slice(79, 84)).max())
    assert line > 10 * float(ses.sel(frequency=slice(20, 400)).median())
    # fmax keeps the band below a limit (e.g. an anti-aliasing cut-off)
    _, hi2 = kurtogram(y, FS, fmax=1000.0).attrs["band"]
    assert hi2 <= 1000.0


def test_bad_input():
    with pytest.raises(InputError, match="x: 100 samples give .* segments"):
        spectral_kurtosis(np.ones(100), FS, 64)
    with pytest.raises(InputError, match="overlap"):
        spectral_kurtosis(np.ones(10_000), FS, 64, overlap=1.0)
    with pytest.raises(InputError, match="x: .*NaN"):
        kurtogram(np.full(1000, np.nan), FS)
