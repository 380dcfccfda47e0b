"""Sensor models: IAS order spectrum of a known angle-periodic speed fluctuation, accelerometer
noise and ADC quantisation."""

from __future__ import annotations

import numpy as np
import pytest

from geardyn.errors import InputError
from geardyn.sensors import accelerometer, adc_quantise, elapsed_time_ias
from geardyn.signal import order_spectrum


def test_ias_order_spectrum_of_angle_periodic_speed_fluctuation():
    """ω(θ) = ω0 (1 + ε cos(kθ)): the elapsed-time IAS (80 MHz, 1000 pulses/rev) sampled in angle
    shows order k with amplitude ε·ω0·sinc(kΔθ/2) (interval mean); quantisation noise stays
    far below it."""
    r, fc = 1000, 80e6
    w0, eps, k = 2 * np.pi * 10.0, 0.01, 20
    revs, sub = 32, 16
    th = np.linspace(0.0, 2 * np.pi * revs, r * revs * sub + 1)
    inv_w = 1.0 / (w0 * (1 + eps * np.cos(k * th)))
    # t(θ) = ∫ dθ/ω by Simpson's rule on each encoder interval (16 sub-steps)
    h = th[1] - th[0]
    seg = inv_w[:-1].reshape(-1, sub)
    nxt = np.append(seg[1:, 0], inv_w[-1])
    ends = np.column_stack([seg, nxt])
    wts = np.ones(sub + 1)
    wts[1:-1:2], wts[2:-1:2] = 4, 2
    tp = np.concatenate([[0.0], np.cumsum(ends @ wts * h / 3)])
    m = elapsed_time_ias(tp, r, fc, clock_phase=0.5)
    spec = order_spectrum(m.ias, r)
    expected = eps * w0 * np.sinc(k / r)  # np.sinc(x) = sin(πx)/(πx); kΔθ/2 = πk/R
    assert float(spec.sel(order=k)) == pytest.approx(expected, rel=0.01)
    floor = float(spec.sel(order=slice(40, 400)).max())
    assert floor < 0.01 * expected


def test_accelerometer_noise_and_adc():
    x = np.sin(np.linspace(0, 200, 100_000))
    y = accelerometer(x, noise_rms=0.05, bits=None, seed=4)
    assert np.std(y - x) == pytest.approx(0.05, rel=0.02)
    np.testing.assert_array_equal(y, accelerometer(x, noise_rms=0.05, bits=None, seed=4))
    with pytest.raises(InputError, match="seed"):
        accelerometer(x, noise_rms=0.05)
    q = 2 * 2.0 / 2**12
    z = adc_quantise(x, 12, 2.0)
    assert np.max(np.abs(z - x)) <= q / 2 + 1e-15
    assert np.std(z - x) == pytest.approx(q / np.sqrt(12), rel=0.05)
    clipped = adc_quantise(3 * x, 12, 2.0)
    assert clipped.max() <= 2.0 and clipped.min() >= -2.0
    with pytest.raises(InputError, match="full scale"):
        adc_quantise(3 * x, 12, 2.0, clip=False)
    with pytest.raises(InputError, match="bits"):
        adc_quantise(x, 0, 1.0)
