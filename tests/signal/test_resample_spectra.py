"""Run-up with known order content: exact order peaks after angular resampling, smeared time
spectrum; resampling from tacho pulses; STFT/angular spectrogram ridges; distant shaft."""

from __future__ import annotations

import numpy as np
import pytest

from geardyn.errors import InputError
from geardyn.signal import (
    amplitude_spectrum,
    angle_from_pulses,
    angular_spectrogram,
    distant_shaft,
    order_spectrum,
    order_speed_map,
    psd,
    resample_to_angle,
    stft,
)

FS = 20_000.0
F0, F1, T = 10.0, 50.0, 4.0  # linear run-up 10 → 50 rev/s in 4 s: 120 revolutions
ORDERS = {3.0: 1.0, 7.5: 0.5, 22.0: 0.25}


def runup():
    t = np.arange(int(T * FS)) / FS
    a = (F1 - F0) / T
    theta = 2 * np.pi * (F0 * t + 0.5 * a * t**2)
    x = sum(amp * np.cos(o * theta + 0.3) for o, amp in ORDERS.items())
    return t, theta, x


def peak_near(spec, coord, target, half_width):
    sel = spec.sel({coord: slice(target - half_width, target + half_width)})
    i = int(np.argmax(sel.values))
    return float(sel[coord][i]), float(sel[i])


def test_order_spectrum_of_runup_has_exact_peaks_time_spectrum_smears():
    t, theta, x = runup()
    sig = resample_to_angle(x, FS, theta, samples_per_rev=512)
    assert sig.max_valid_order >= 22
    spec = order_spectrum(sig.x, sig.samples_per_rev)
    res = 1.0 / sig.revolutions
    for o, amp in ORDERS.items():
        where, level = peak_near(spec, "order", o, 1.0)
        assert abs(where - o) <= res / 2 + 1e-12  # exact order, within half a bin
        assert level == pytest.approx(amp, rel=0.03)  # ≤ 3 % (scalloping ≤ bin offset)
    # away from the three orders and their Hann main lobes: nothing above 0.5 % of the largest
    o = spec["order"].values
    far = np.all([np.abs(o - k) > 3 * res for k in ORDERS], axis=0) & (o < 100)
    assert float(spec.values[far].max()) < 5e-3
    # the time spectrum of the same record smears each order over its swept band
    tspec = amplitude_spectrum(x, FS)
    assert float(tspec.max()) < 0.15 * max(ORDERS.values())


def test_resampling_from_tacho_pulses():
    t, theta, x = runup()
    a = (F1 - F0) / T
    k = np.arange(1, 120)  # 118 whole revolutions: every order falls on a bin
    tp = (-F0 + np.sqrt(F0**2 + 2 * a * k)) / a  # exact once-per-rev instants
    ang = angle_from_pulses(tp, t[(t >= tp[0]) & (t <= tp[-1])], 1, angle0=2 * np.pi)
    np.testing.assert_allclose(ang, theta[(t >= tp[0]) & (t <= tp[-1])], atol=1e-6)
    sig = resample_to_angle(x, FS, pulse_times=tp, pulses_per_rev=1, samples_per_rev=512)
    spec = order_spectrum(sig.x, sig.samples_per_rev)
    for o, amp in ORDERS.items():
        where, level = peak_near(spec, "order", o, 1.0)
        assert abs(where - o) <= 1.0 / sig.revolutions
        assert level == pytest.approx(amp, rel=0.05)


def test_resampling_from_encoder_edges():
    t, theta, x = runup()
    a = (F1 - F0) / T
    ppr = 64
    k = np.arange(ppr, 119 * ppr + 1) / ppr  # revolutions at each encoder edge
    tp = (-F0 + np.sqrt(F0**2 + 2 * a * k)) / a
    sig = resample_to_angle(x, FS, pulse_times=tp, pulses_per_rev=ppr, samples_per_rev=512)
    spec = order_spectrum(sig.x, sig.samples_per_rev)
    for o, amp in ORDERS.items():
        where, level = peak_near(spec, "order", o, 1.0)
        assert abs(where - o) <= 1.0 / sig.revolutions
        assert level == pytest.approx(amp, rel=0.05)


def test_insufficient_samples_per_rev_for_speed_range_is_refused():
    t, theta, x = runup()
    with pytest.raises(InputError, match="samples_per_rev >= "):
        resample_to_angle(x, FS, theta, samples_per_rev=64, max_order=22)


def test_stft_and_angular_spectrogram_ridges():
    t, theta, x = runup()
    s = stft(x, FS, nperseg=4096, overlap=0.5)
    # ridge of order 3 at the segment-centre speed: f = 3 (F0 + a t)
    a = (F1 - F0) / T
    band = s.sel(frequency=slice(20, 160))
    ridge = band["frequency"].values[band.argmax("frequency").values]
    np.testing.assert_allclose(ridge, 3 * (F0 + a * s["time"].values), atol=2 * FS / 4096)
    sig = resample_to_angle(x, FS, theta, samples_per_rev=512)
    m = angular_spectrogram(sig.x, 512, revs_per_segment=8)
    ridge_o = m["order"].values[m.sel(order=slice(1, 5)).argmax("order").values + 8]
    np.testing.assert_allclose(ridge_o, 3.0, atol=1 / 8)
    osm = order_speed_map(x, FS, theta, samples_per_rev=512, revs_per_segment=8)
    assert osm["speed"].min() > 60 * F0 * 0.99 and osm["speed"].max() < 60 * F1 * 1.01
    assert np.all(np.diff(osm["speed"].values) > 0)


def test_psd_of_white_noise_integrates_to_variance():
    x = np.random.default_rng(0).normal(0, 2.0, 200_000)
    p = psd(x, 1000.0, nperseg=1024)
    var = float(p.integrate("frequency"))
    assert var == pytest.approx(4.0, rel=0.03)


def test_distant_shaft_via_kinematic_ratio():
    from geardyn import analyze_kinematics, load_config

    kin = analyze_kinematics(load_config("examples/hammami_back_to_back.toml"))
    ratios = kin.velocity_ratios(["motor"])
    idx = kin.graph.index("carrier")
    r = ratios[idx, 0]  # seed 003 §4.1: sun → carrier ratio 16/81
    w_motor = np.array([150.0, 160.0])
    np.testing.assert_allclose(distant_shaft(w_motor, r), w_motor * 16 / 81, rtol=1e-12)
    with pytest.raises(InputError, match="ratio"):
        distant_shaft(w_motor, 0.0)
    from geardyn.signal import link_ratio

    assert link_ratio(kin, "motor", "carrier") == pytest.approx(16 / 81, rel=1e-12)
    with pytest.raises(InputError, match="target"):
        link_ratio(kin, "motor", "nolink")


def test_bad_sample_rate_is_named():
    with pytest.raises(InputError, match="fs: sample rate"):
        amplitude_spectrum(np.ones(16), 0.0)
    with pytest.raises(InputError, match="x: signal contains NaN"):
        order_spectrum(np.array([1.0, np.nan, 0.0, 1.0]), 4)


def test_counter_rotating_shaft_angle_is_accepted():
    """Issue 9: a negative link ratio (counter-rotating shaft) gave a decreasing angle that
    resample_to_angle refused; the order content does not depend on the sense of rotation."""
    from geardyn.signal import distant_shaft, order_spectrum, resample_to_angle

    fs, f_ref = 5000.0, 10.0
    t = np.arange(int(4 * fs)) / fs
    th_ref = 2 * np.pi * f_ref * t
    th = distant_shaft(th_ref, -55 / 42)  # counter-rotating output shaft
    x = np.cos(7 * np.abs(th))  # order 7 of the output shaft
    sig = resample_to_angle(x, fs, th, samples_per_rev=64)
    spec = order_spectrum(sig.x, 64)
    assert float(spec["order"][int(np.argmax(spec.values))]) == pytest.approx(7.0, abs=0.3)
    with pytest.raises(InputError, match="monotonic"):
        resample_to_angle(x, fs, np.sin(t), samples_per_rev=64)
