"""Band-limited angular resampling (Smith & Gossett 1984): no interpolation images.

A 4-point polynomial interpolator leaves errors of several per cent for content above a tenth
of the sample rate; they fold to ``fs − f`` and, when the samples per revolution are whole,
survive the synchronous average as spurious orders (the speed-dependent false alarm of issue
18). Reference: a pure tone has exactly one order."""

from __future__ import annotations

import numpy as np
import pytest

from geardyn.signal.resample import interpolate_bandlimited, resample_to_angle


@pytest.mark.parametrize("ratio", [0.05, 0.2, 0.35, 0.39])  # flat band: fs/2.56
def test_kernel_passes_the_band_and_leaves_no_images(ratio: float) -> None:
    rng = np.random.default_rng(1)
    i = np.arange(4000)
    pos = np.sort(rng.uniform(100, 3900, 20000))
    y = interpolate_bandlimited(np.cos(2 * np.pi * ratio * i + 0.3), pos)
    ref = np.cos(2 * np.pi * ratio * pos + 0.3)
    gain = float(np.dot(y, ref) / np.dot(ref, ref))
    # design: passband ripple ≤ 1e-4 up to fs/2.56, images ≥ 80 dB down (module docstring)
    assert gain == pytest.approx(1.0, abs=2e-4)
    assert np.std(y - gain * ref) < 1e-4 * np.std(ref)


def test_synchronous_average_holds_only_the_tone() -> None:
    fs, samples_per_shaft_rev, order = 5000.0, 1000, 350  # the tone at 0.35·fs
    f_rot = fs / samples_per_shaft_rev  # whole samples per revolution: images are synchronous
    t = np.arange(40 * samples_per_shaft_rev) / fs
    x = np.cos(2 * np.pi * order * f_rot * t)
    sig = resample_to_angle(x, fs, 2 * np.pi * f_rot * t, samples_per_rev=2048)
    revs = sig.x[: (sig.x.size // 2048) * 2048].reshape(-1, 2048)[2:-2]
    spec = np.abs(np.fft.rfft(revs.mean(axis=0))) / 1024
    assert spec[order] == pytest.approx(1.0, abs=1e-3)
    others = np.delete(spec, order)
    # the former 4-point Lagrange interpolation gave 0.78 at the tone and 0.137 at order 650
    # (= fs − f in orders)
    assert others.max() < 1e-4
    assert sig.max_valid_order == pytest.approx(0.42 * fs / f_rot, rel=1e-9)


def test_kernel_gain_at_the_kept_band_edge() -> None:
    # SINC_PASSBAND: within 5 % of 1 at 0.42·fs (the orders a resampled record keeps)
    i = np.arange(4000)
    pos = np.linspace(100.25, 3899.25, 15000)
    y = interpolate_bandlimited(np.cos(2 * np.pi * 0.42 * i), pos)
    ref = np.cos(2 * np.pi * 0.42 * pos)
    assert 0.95 < float(np.dot(y, ref) / np.dot(ref, ref)) < 1.0
