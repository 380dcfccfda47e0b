"""Accelerometer channel: additive Gaussian noise and ADC quantisation/clipping.

Units: whatever the input signal carries (typically m/s²); ``full_scale`` is in the same unit.
"""

from __future__ import annotations

import numpy as np

from geardyn.errors import InputError
from geardyn.signal._checks import array1d, positive, positive_int, rng


def adc_quantise(x: np.ndarray, bits: int, full_scale: float, clip: bool = True) -> np.ndarray:
    """Mid-tread ADC of ``bits`` bits over ``[-full_scale, +full_scale)``.

    The step is ``q = 2·full_scale/2**bits``; the quantisation error of an unclipped sample is at
    most ``q/2`` (uniform error, RMS ``q/√12`` for a busy signal). Samples beyond the range are
    clipped to the extreme codes (``clip=False`` raises instead).
    """
    a = array1d("x", x, 1)
    b = positive_int("bits", bits, "ADC resolution", minimum=1)
    if b > 32:
        raise InputError(f"bits: ADC resolution must be <= 32, got {bits}")
    fs = positive("full_scale", full_scale, "ADC full scale")
    q = 2.0 * fs / 2**b
    codes = np.round(a / q)
    lo, hi = -(2 ** (b - 1)), 2 ** (b - 1) - 1
    if not clip and (codes.min() < lo or codes.max() > hi):
        raise InputError(f"x: signal exceeds the ADC full scale ±{fs:g}")
    return np.clip(codes, lo, hi) * q


def accelerometer(
    x: np.ndarray,
    noise_rms: float = 0.0,
    bits: int | None = 24,
    full_scale: float | None = None,
    seed: int | np.random.Generator | None = None,
) -> np.ndarray:
    """Measured accelerometer channel: ``x`` + white Gaussian noise (RMS ``noise_rms``, drawn with
    ``seed``) then an ADC of ``bits`` bits over ``±full_scale`` (``None`` → 1.2 × the peak of the
    noisy signal; ``bits=None`` → no quantisation)."""
    a = array1d("x", x, 1)
    if not np.isfinite(noise_rms) or noise_rms < 0:
        raise InputError(f"noise_rms: must be >= 0, got {noise_rms!r}")
    y = a + rng(seed).normal(0.0, noise_rms, a.size) if noise_rms > 0 else a.copy()
    if bits is None:
        return y
    if full_scale is None:
        full_scale = 1.2 * float(np.max(np.abs(y))) or 1.0
    return adc_quantise(y, bits, full_scale)
