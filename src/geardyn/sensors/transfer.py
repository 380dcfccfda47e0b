"""Transfer path from a force to an accelerometer: a sum of single-DOF modes.

Each mode is the accelerance of a mass–spring–damper excited by the force,
``H_i(s) = s² / (m_i (s² + 2ζ_i ω_i s + ω_i²))`` [m/s² per N] (modal superposition of the
structure between the force and the sensor, e.g. a bearing housing; seed 003 §5 treats the
same path as a measured transmissibility). The path is ``H(s) = Σ_i H_i(s)``. It is applied in
discrete time by the bilinear transform with the frequency pre-warped at each ω_i, so every
resonance sits exactly at its frequency (``scipy.signal.bilinear``).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from scipy import signal as sps

from geardyn.errors import InputError
from geardyn.signal._checks import array1d, positive


def mode_filter(frequency_hz: float, damping_ratio: float, modal_mass_kg: float, fs: float
                ) -> tuple[np.ndarray, np.ndarray]:
    """Digital (b, a) of one mode's accelerance at sample rate ``fs`` [Hz] (pre-warped)."""
    f = positive("frequency_hz", frequency_hz, "mode frequency [Hz]")
    z = positive("damping_ratio", damping_ratio, "modal damping ratio")
    m = positive("modal_mass_kg", modal_mass_kg, "modal mass [kg]")
    rate = positive("fs", fs, "sample rate [Hz]")
    if f >= 0.45 * rate:
        raise InputError(
            f"transfer_path.frequency_hz: mode at {f:g} Hz is above 0.45 × the sample rate "
            f"({rate:g} Hz); raise sample_rate_hz (or the simulation's record rate)")
    if z >= 1:
        raise InputError(f"transfer_path.damping_ratio: must be < 1, got {z:g}")
    w = 2.0 * rate * np.tan(np.pi * f / rate)  # pre-warped analog frequency [rad/s]
    b, a = sps.bilinear([1.0 / m, 0.0, 0.0], [1.0, 2.0 * z * w, w * w], fs=rate)
    return b, a


def apply_transfer_path(force: np.ndarray, fs: float, modes: Sequence) -> np.ndarray:
    """Acceleration [m/s²] at the sensor for a force history [N] sampled at ``fs`` [Hz];
    ``modes``: objects or dicts with ``frequency_hz``, ``damping_ratio``, ``modal_mass_kg``.
    The force's mean (static load) passes no acceleration (s² numerator), so the filter starts
    from the static state."""
    x = array1d("force", force, 2, "force history")
    if not np.all(np.isfinite(x)):
        raise InputError("force: the force history contains NaN or infinite values")
    out = np.zeros_like(x)
    for md in modes:
        g = md if isinstance(md, dict) else md.__dict__
        b, a = mode_filter(g["frequency_hz"], g.get("damping_ratio", 0.05),
                           g.get("modal_mass_kg", 1.0), fs)
        out += sps.lfilter(b, a, x - x[0])
    return out


def accelerance(frequency: np.ndarray, modes: Sequence) -> np.ndarray:
    """Continuous accelerance ``H(j2πf)`` [m/s² per N] of the path at ``frequency`` [Hz]."""
    s = 2j * np.pi * np.asarray(frequency, float)
    h = np.zeros(s.shape, complex)
    for md in modes:
        g = md if isinstance(md, dict) else md.__dict__
        w = 2 * np.pi * g["frequency_hz"]
        h += s * s / (g.get("modal_mass_kg", 1.0) * (s * s + 2 * g.get("damping_ratio", 0.05)
                                                      * w * s + w * w))
    return h
