"""TSA, indicators, cepstrum, envelope and CWT on signals with known analytic answers."""

from __future__ import annotations

import numpy as np
import pytest

from geardyn.errors import InputError
from geardyn.signal import (
    crest_factor,
    cwt_morlet,
    difference_signal,
    energy_ratio,
    envelope_spectrum,
    fm0,
    fm4,
    kurtosis,
    m6a,
    m8a,
    na4,
    planetary_tsa,
    power_cepstrum,
    real_cepstrum,
    regular_signal,
    residual_signal,
    rms,
    sideband_level_factor,
    skewness,
    tsa,
    tsa_from_tacho,
)

SPR = 1024


def periodic(spr=SPR, z=20):
    th = 2 * np.pi * np.arange(spr) / spr
    return np.cos(z * th) + 0.3 * np.cos(2 * z * th + 1.0) + 0.1 * np.cos(th)


def test_tsa_noise_reduction_scales_as_one_over_sqrt_n():
    rng = np.random.default_rng(1)
    p = periodic()
    sigma = 1.0
    ns = np.array([16, 64, 256])
    resid = []
    for n in ns:
        x = np.tile(p, n) + rng.normal(0, sigma, SPR * n)
        resid.append(rms(tsa(x, SPR) - p))
    resid = np.array(resid)
    np.testing.assert_allclose(resid, sigma / np.sqrt(ns), rtol=0.08)
    slope = np.polyfit(np.log(ns), np.log(resid), 1)[0]
    assert slope == pytest.approx(-0.5, abs=0.03)


def test_tsa_from_tacho_recovers_the_periodic_waveform():
    fs, f_rot = 25_600.0, 12.5  # 2048 samples per revolution
    n = 40
    t = np.arange(int(n * fs / f_rot)) / fs
    theta = 2 * np.pi * f_rot * t
    x = np.cos(7 * theta) + 0.5 * np.sin(3 * theta)
    tacho = (np.arange(1, n)) / f_rot
    avg = tsa_from_tacho(x, fs, tacho, samples_per_rev=256)
    th = 2 * np.pi * np.arange(256) / 256
    np.testing.assert_allclose(avg, np.cos(7 * th) + 0.5 * np.sin(3 * th), atol=2e-3)


def test_gaussian_noise_kurtosis_fm4_m6a_m8a():
    rng = np.random.default_rng(2)
    g = rng.normal(0, 1, 2**18)
    assert kurtosis(g) == pytest.approx(3.0, abs=0.05)
    assert skewness(g) == pytest.approx(0.0, abs=0.02)
    # FM4 family on the difference signal of a Gaussian "TSA" carrying mesh harmonics
    z = 32
    th = 2 * np.pi * np.arange(2**16) / 2**16
    t_sig = 5 * np.cos(z * th) + 2 * np.cos(2 * z * th) + rng.normal(0, 1, th.size)
    d = difference_signal(t_sig, z)
    assert fm4(d) == pytest.approx(3.0, abs=0.1)
    assert m6a(d) == pytest.approx(15.0, rel=0.1)  # E[g⁶]/σ⁶ = 15
    assert m8a(d) == pytest.approx(105.0, rel=0.2)  # E[g⁸]/σ⁸ = 105
    # the mesh harmonics are gone from the difference signal
    assert kurtosis(t_sig) < 2.0


def test_rms_crest_factor_kurtosis_of_a_sine():
    t = np.arange(10_000) / 10_000
    x = 3.0 * np.sin(2 * np.pi * 50 * t)
    assert rms(x) == pytest.approx(3 / np.sqrt(2), rel=1e-9)
    assert crest_factor(x) == pytest.approx(np.sqrt(2), rel=1e-6)
    assert kurtosis(x) == pytest.approx(1.5, rel=1e-9)


def test_fm0_energy_ratio_sideband_level_factor_analytic():
    n, z = 4096, 25
    th = 2 * np.pi * np.arange(n) / n
    assert fm0(2.0 * np.cos(z * th), z) == pytest.approx(2.0, rel=1e-9)  # 2A / A
    x = 2.0 * np.cos(z * th) + 0.5 * np.cos(37 * th)
    assert energy_ratio(x, z) == pytest.approx(0.25, rel=1e-9)
    np.testing.assert_allclose(regular_signal(x, z), 2.0 * np.cos(z * th), atol=1e-12)
    s = 0.2
    y = np.cos(z * th) + s * (np.cos((z - 1) * th) + np.cos((z + 1) * th))
    assert sideband_level_factor(y, z) == pytest.approx(2 * s / np.sqrt((1 + 2 * s**2) / 2))
    # residual keeps the sidebands, the difference signal removes them
    np.testing.assert_allclose(residual_signal(y, z), s * (y - np.cos(z * th)) / s, atol=1e-12)
    np.testing.assert_allclose(difference_signal(y, z), 0.0, atol=1e-12)


def test_na4_normalises_by_the_history_variance():
    rng = np.random.default_rng(3)
    cur = rng.normal(0, 1, 2**17)
    assert na4(cur) == pytest.approx(3.0, abs=0.06)
    hist = [rng.normal(0, np.sqrt(3), 2**17)]  # mean variance (3 + 1)/2 = 2
    assert na4(cur, hist) == pytest.approx(3.0 / 4.0, rel=0.03)


def test_cepstrum_of_an_echo_peaks_at_its_delay():
    fs, delay, a = 10_000.0, 123, 0.5
    s = np.random.default_rng(4).normal(0, 1, 2**16)
    x = s + a * np.roll(s, delay)
    for cep in (real_cepstrum(x, fs), power_cepstrum(x, fs)):
        q = cep.sel(quefrency=slice(0.002, 0.05))
        assert float(q["quefrency"][int(np.argmax(q.values))]) == pytest.approx(delay / fs)
    # real cepstrum of 1 + a·e^{-iωτ}: first rahmonic a/2
    assert float(real_cepstrum(x, fs)[delay]) == pytest.approx(a / 2, rel=0.1)


def test_envelope_spectrum_of_am_carrier_peaks_at_modulation_frequency():
    fs, fc, fm, m = 20_000.0, 3000.0, 37.0, 0.4
    t = np.arange(int(2 * fs)) / fs
    x = (1 + m * np.cos(2 * np.pi * fm * t)) * np.cos(2 * np.pi * fc * t)
    env = envelope_spectrum(x, fs, band=(2500, 3500), squared=False)
    sel = env.sel(frequency=slice(1, 500))
    i = int(np.argmax(sel.values))
    assert float(sel["frequency"][i]) == pytest.approx(fm)
    assert float(sel[i]) == pytest.approx(m, rel=0.02)
    sq = envelope_spectrum(x, fs, band=(2500, 3500), squared=True)
    assert float(sq.sel(frequency=fm)) == pytest.approx(2 * m, rel=0.02)
    assert float(sq.sel(frequency=2 * fm)) == pytest.approx(m**2 / 2, rel=0.05)
    with pytest.raises(InputError, match="band"):
        envelope_spectrum(x, fs, band=(3500, 2500))


def test_cwt_morlet_ridge_at_the_tone_frequency():
    fs, f0 = 1000.0, 50.0
    x = np.sin(2 * np.pi * f0 * np.arange(2048) / fs)
    c = cwt_morlet(x, fs, scales=np.arange(2, 64))
    mid = c.isel(position=slice(512, 1536)).mean("position")
    f_best = float(c["frequency"][int(np.argmax(mid.values))])
    assert f_best == pytest.approx(f0, rel=0.05)


def test_planetary_tsa_separates_the_faulty_planet():
    zr, zp, n_pl, spt = 65, 24, 3, 32
    spc = zr * spt
    revs = 48
    m = np.arange(spc * revs) / spt  # ring-mesh count
    theta = 2 * np.pi * m / zr  # carrier angle
    # transfer window of planet 0 (at the sensor when θ = 2πk), Hann lobe of width 2π/3
    rel = (theta + np.pi / n_pl) % (2 * np.pi)
    win0 = np.where(rel < 2 * np.pi / n_pl, 0.5 * (1 - np.cos(n_pl * rel)), 0.0)
    # tooth 5 of planet 0 meshes with the ring when m ≡ 5 (mod 24): a short pulse
    dm = (m - 5.0 + zp / 2) % zp - zp / 2
    x = win0 * np.exp(-0.5 * (dm * spt / 2.0) ** 2)
    x += np.random.default_rng(5).normal(0, 0.02, x.size)
    p0 = planetary_tsa(x, spc, zr, zp, n_pl, planet=0)
    p1 = planetary_tsa(x, spc, zr, zp, n_pl, planet=1)
    assert p0.size == zp * spt
    assert int(np.argmax(p0)) == pytest.approx(5 * spt, abs=1)
    assert p0.max() == pytest.approx(1.0, rel=0.1)
    assert np.max(np.abs(p1)) < 0.15 * p0.max()


def test_tsa_bad_input():
    with pytest.raises(InputError, match="samples_per_rev"):
        tsa(np.ones(100), 0)
    with pytest.raises(InputError, match="x: needs at least one revolution"):
        tsa(np.ones(10), 64)


def test_short_or_malformed_inputs_raise_named_errors():
    from geardyn.signal import envelope, resample_to_angle, stft

    with pytest.raises(InputError, match="x: the band-pass filter needs more than"):
        envelope(np.ones(20), 100.0, band=(10, 20))
    with pytest.raises(InputError, match="x: signal must be 1-D"):
        tsa(np.ones((3, 4)), 4)
    with pytest.raises(InputError, match="nperseg"):
        stft(np.ones(100), 10.0, nperseg=200)
    with pytest.raises(InputError, match="angle: the reference angle must be strictly monotonic"):
        resample_to_angle(np.ones(100), 100.0, np.concatenate([np.linspace(0, 5, 50),
                                                               np.linspace(5, 0, 50)]))
    with pytest.raises(InputError, match="samples_per_carrier_rev"):
        planetary_tsa(np.ones(1000), 100, 65, 24, 3)
