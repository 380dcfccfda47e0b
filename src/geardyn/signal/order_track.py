"""Order tracks (amplitude of one order against speed) and tacho-less speed estimation.

* :func:`order_track`: computed order tracking (angular resampling, seed 002 §3.2) followed by
  a DFT at the chosen order over blocks of whole reference revolutions (Hann window, 50 %
  overlap): the amplitude of order ``o`` in each block against the block's mean speed [rpm].
  A block of ``R`` revolutions resolves orders ``1/R`` apart; the window's coherent gain is
  removed so that ``A·cos(o·θ)`` reads ``A``. (Vold–Kalman filtering is not needed for
  amplitudes of well separated orders.)
* :func:`speed_from_order`: the reference speed without a tacho, from a dominant order of known
  value (a mesh order): the STFT peak inside the band swept by that order over the stated speed
  range, refined by parabolic interpolation of the log-magnitude (Gasior & Gonzalez 2004) and
  followed frame to frame, gives ``f_peak(t)``; ``ω = 2π f_peak/o`` and its time integral is
  the angle (trapezoidal rule, exact for a piecewise-linear speed; Bonnardot, El Badaoui,
  Randall, Danière & Guillet 2005 do the same by demodulating a mesh harmonic).

Units: time [s], frequency [Hz], speed [rad/s] or [rpm] as stated, angle [rad].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from geardyn.errors import InputError
from geardyn.signal._checks import array1d, positive, positive_int
from geardyn.signal.resample import AngleSignal, angle_from_speed, resample_to_angle
from geardyn.signal.spectra import hann_stft


def order_amplitudes(
    sig: AngleSignal, order: float, revs_per_block: float = 8.0, overlap: float = 0.5
) -> xr.DataArray:
    """Amplitude of ``order`` in blocks of ``revs_per_block`` revolutions of an angle-domain
    signal (Hann window, ``overlap`` of blocks); coordinates ``speed`` [rpm] (block mean),
    ``time`` [s] and ``revolution`` (block centre)."""
    o = positive("order", order, "order [events/rev]")
    spr = sig.samples_per_rev
    n = int(round(positive("revs_per_block", revs_per_block, "revolutions per block") * spr))
    if o >= 0.5 * spr:
        raise InputError(f"order: {o:g} is above the Nyquist order {spr / 2:g} of the signal")
    if not 0.0 <= overlap < 1.0:
        raise InputError(f"overlap: must be in [0, 1), got {overlap!r}")
    if sig.x.size < n:
        raise InputError(
            f"x: {sig.revolutions:.3g} revolutions, fewer than revs_per_block={revs_per_block:g}"
        )
    if o < 2.0 * spr / n:
        raise InputError(
            f"revs_per_block: order {o:g} needs blocks of at least {2.0 / o:g} revolutions "
            "(two periods of the order under the Hann window)"
        )
    hop = max(1, int(round(n * (1 - overlap))))
    starts = np.arange(0, sig.x.size - n + 1, hop)
    w = np.hanning(n)
    ph = np.exp(-1j * o * 2 * np.pi * np.arange(n) / spr)
    amps, rpm, tmid, rev = [], [], [], []
    for s in starts:
        seg = sig.x[s : s + n]
        amps.append(2.0 * abs(np.sum((seg - seg.mean()) * w * ph)) / w.sum())
        dt = sig.time[s + n - 1] - sig.time[s]
        rpm.append(60.0 * (n - 1) / spr / dt)
        tmid.append(0.5 * (sig.time[s] + sig.time[s + n - 1]))
        rev.append((s + 0.5 * n) / spr)
    return xr.DataArray(
        np.array(amps),
        coords={
            "speed": ("block", np.array(rpm), {"units": "rpm"}),
            "time": ("block", np.array(tmid), {"units": "s"}),
            "revolution": ("block", np.array(rev), {"units": "rev"}),
        },
        dims="block",
        name="order_amplitude",
        attrs={"order": o, "revs_per_block": float(revs_per_block)},
    )


def order_track(
    x: np.ndarray,
    fs: float,
    order: float,
    angle: np.ndarray | None = None,
    *,
    pulse_times: np.ndarray | None = None,
    pulses_per_rev: int = 1,
    samples_per_rev: int | None = None,
    revs_per_block: float = 8.0,
    overlap: float = 0.5,
    t0: float = 0.0,
) -> xr.DataArray:
    """Amplitude of ``order`` of the reference against its speed [rpm] (order track): resample
    ``x`` (``fs`` [Hz]) to the reference angle (``angle`` [rad] per sample, or tacho/encoder
    ``pulse_times`` [s]) with :func:`geardyn.signal.resample_to_angle`, then
    :func:`order_amplitudes`. ``samples_per_rev`` defaults to the power of two ≥ 8·order."""
    spr = (
        int(2 ** np.ceil(np.log2(max(64.0, 8.0 * positive("order", order, "order")))))
        if samples_per_rev is None
        else positive_int("samples_per_rev", samples_per_rev, minimum=8)
    )
    sig = resample_to_angle(
        x,
        fs,
        angle,
        pulse_times=pulse_times,
        pulses_per_rev=pulses_per_rev,
        samples_per_rev=spr,
        t0=t0,
    )
    return order_amplitudes(sig, order, revs_per_block, overlap)


@dataclass(frozen=True)
class SpeedEstimate:
    """Tacho-less reference speed: ``time`` [s] (STFT frame centres), ``speed`` [rad/s],
    ``angle`` [rad] (0 at the first frame), ``peak_hz`` (tracked frequency [Hz]) and
    ``order`` (the tracked order)."""

    time: np.ndarray
    speed: np.ndarray
    angle: np.ndarray
    peak_hz: np.ndarray
    order: float

    @property
    def rpm(self) -> np.ndarray:
        return self.speed * 60.0 / (2.0 * np.pi)

    def angle_at(self, time: np.ndarray) -> np.ndarray:
        """Angle [rad] at ``time`` [s] (linear between frames; inside the frame span only)."""
        t = array1d("time", time, 1, "time vector")
        if t.min() < self.time[0] or t.max() > self.time[-1]:
            raise InputError(
                f"time: [{t.min():g}, {t.max():g}] s outside the tracked span "
                f"[{self.time[0]:g}, {self.time[-1]:g}] s"
            )
        # integrate the linear speed between frames exactly: quadratic angle
        i = np.clip(np.searchsorted(self.time, t, side="right") - 1, 0, self.time.size - 2)
        h = t - self.time[i]
        dt = self.time[i + 1] - self.time[i]
        acc = (self.speed[i + 1] - self.speed[i]) / dt
        return self.angle[i] + self.speed[i] * h + 0.5 * acc * h * h


def speed_from_order(
    x: np.ndarray,
    fs: float,
    order: float,
    rpm_range: tuple[float, float],
    nperseg: int = 2048,
    overlap: float = 0.75,
    max_step: float = 0.05,
) -> SpeedEstimate:
    """Reference speed from a dominant order (a mesh order) without a tacho.

    ``rpm_range``: (min, max) reference speed [rpm] bounding the search band
    ``order·rpm/60`` [Hz] in the first frame; later frames search within ``±max_step`` (relative)
    of the previous peak. STFT with a Hann window of ``nperseg`` samples. Raises when the band
    is outside ``(0, fs/2)``."""
    a = array1d("x", x, 16)
    f = positive("fs", fs, "sample rate [Hz]")
    o = positive("order", order, "order [events/rev]")
    lo_rpm, hi_rpm = (positive("rpm_range", v, "speed [rpm]") for v in rpm_range)
    if hi_rpm <= lo_rpm:
        raise InputError(f"rpm_range: need min < max, got ({lo_rpm:g}, {hi_rpm:g})")
    if o * hi_rpm / 60.0 >= 0.5 * f:
        raise InputError(
            f"order: {o:g} × {hi_rpm:g} rpm = {o * hi_rpm / 60:g} Hz is above fs/2 = {f / 2:g} Hz"
        )
    n = positive_int("nperseg", nperseg, "segment length", minimum=16)
    if n > a.size:
        raise InputError(f"nperseg: {n} exceeds the signal length {a.size}")
    freq, tt, z = hann_stft(a, f, n, overlap)
    mag = np.log(np.abs(z) + 1e-300)
    df = freq[1] - freq[0]
    lo, hi = o * lo_rpm / 60.0, o * hi_rpm / 60.0
    peaks = np.empty(tt.size)
    for k in range(tt.size):
        if k > 0:
            lo, hi = peaks[k - 1] * (1 - max_step), peaks[k - 1] * (1 + max_step)
        i0 = max(1, int(np.floor(lo / df)))
        i1 = min(freq.size - 2, int(np.ceil(hi / df)))
        if i1 <= i0:
            i1 = i0 + 1
        j = i0 + int(np.argmax(mag[i0 : i1 + 1, k]))
        j = min(max(j, 1), freq.size - 2)
        y0, y1, y2 = mag[j - 1, k], mag[j, k], mag[j + 1, k]
        den = y0 - 2 * y1 + y2
        delta = 0.5 * (y0 - y2) / den if den != 0 else 0.0
        peaks[k] = (j + float(np.clip(delta, -0.5, 0.5))) * df
    if tt.size < 2:
        raise InputError(f"x: {a.size} samples give fewer than 2 STFT frames of {n}")
    speed = 2.0 * np.pi * peaks / o
    angle = angle_from_speed(tt, speed)
    return SpeedEstimate(tt, speed, angle, peaks, o)


__all__ = ["SpeedEstimate", "order_amplitudes", "order_track", "speed_from_order"]
