"""Speed and angle: tacho/encoder → angle and speed; angular resampling (computed order
tracking) with anti-aliasing; IAS of a distant shaft via a kinematic ratio.

Angular resampling turns a time signal ``x(t)`` sampled at ``fs`` [Hz] into ``x(θ_k)`` sampled
at ``samples_per_rev`` equal angle steps of the reference shaft, so that a spectrum of it is an
order spectrum (events per revolution, seed 002 §3.2). Steps:

1. anti-aliasing: zero-phase low-pass at ``f_rot,min × samples_per_rev/2.56`` [Hz] (the
   slowest shaft rotation frequency in the record), so that nothing aliases at any speed;
2. angle → time: the instants ``t_k`` where ``θ(t_k) = θ_k`` (linear inversion of the finely
   sampled angle history, or cubic Hermite inversion of tacho/encoder pulses);
3. band-limited interpolation of the filtered signal at ``t_k``: a Kaiser-windowed sinc over
   ±:data:`SINC_HALF_WIDTH` samples (Smith & Gossett 1984, "A flexible sampling-rate
   conversion method"; numba, O(n)). A short polynomial (4-point Lagrange) interpolator leaves
   errors of several per cent for content above a tenth of the sample rate, and they fold into
   images at ``fs − f``: at speeds where the images fall on whole orders they survive the
   synchronous average as spurious lines (a speed-dependent false alarm), elsewhere they
   raise the noise floor. The kernel keeps content up to ``fs/2.56`` (passband ripple below
   1e-4) and rejects images by 80 dB.

The orders a record supports are limited by both the anti-aliasing cut-off and the band the
interpolation keeps, :data:`SINC_PASSBAND` ``= 0.42·fs`` (gain within 5 % of 1, no images;
above ``fs/2`` a resampled signal holds only images):
``max_valid_order = min(0.8·cutoff, 0.42·fs)/f_rot,max``.

Units: time [s], angle [rad], speed [rad/s], orders [events/rev].
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np
from scipy import signal as sps
from scipy.interpolate import CubicSpline, PchipInterpolator

from geardyn.errors import InputError
from geardyn.signal._checks import array1d, increasing, positive, positive_int


@dataclass(frozen=True)
class AngleSignal:
    """A signal sampled in angle: ``x[k]`` at ``angle[k] = angle0 + k·2π/samples_per_rev`` [rad],
    with ``time[k]`` [s] the instant of each sample (for speed/order maps). ``max_valid_order``:
    highest order kept unattenuated by the anti-aliasing filter at every speed of the record."""

    x: np.ndarray
    samples_per_rev: int
    angle0: float
    time: np.ndarray
    max_valid_order: float = np.inf

    @property
    def angle(self) -> np.ndarray:
        return self.angle0 + 2.0 * np.pi * np.arange(self.x.size) / self.samples_per_rev

    @property
    def revolutions(self) -> float:
        return self.x.size / self.samples_per_rev


def angle_from_pulses(
    pulse_times: np.ndarray,
    time: np.ndarray,
    pulses_per_rev: int = 1,
    angle0: float = 0.0,
) -> np.ndarray:
    """Shaft angle [rad] at ``time`` [s] from tacho/encoder pulse times: cubic spline through the
    pulse angles ``angle0 + k·2π/R`` (exact for constant acceleration); where the spline would
    run backwards (abrupt speed changes) monotone PCHIP interpolation is used instead.
    ``time`` must lie within the pulse span (extrapolation is refused)."""
    tp = array1d("pulse_times", pulse_times, 3, "pulse times")
    increasing("pulse_times", tp)
    t = array1d("time", time, 1, "time vector")
    r = positive_int("pulses_per_rev", pulses_per_rev, "pulses per revolution")
    if t.min() < tp[0] or t.max() > tp[-1]:
        raise InputError(
            f"time: [{t.min():g}, {t.max():g}] s extends beyond the pulses "
            f"[{tp[0]:g}, {tp[-1]:g}] s; crop the signal to the pulse span"
        )
    ang = angle0 + 2.0 * np.pi * np.arange(tp.size) / r
    out = CubicSpline(tp, ang)(t)
    if t.size > 1 and _runs_backwards(out, t):
        out = PchipInterpolator(tp, ang)(t)
    return out


def _runs_backwards(angle: np.ndarray, t: np.ndarray, chunk: int = 1 << 20) -> bool:
    """Whether ``angle`` fails to increase between two increasing instants of ``t`` (checked
    stretch by stretch: no record-long difference arrays)."""
    for a in range(0, t.size - 1, chunk):
        d = np.diff(angle[a : a + chunk + 1])
        if np.any(d[np.diff(t[a : a + chunk + 1]) > 0] <= 0):
            return True
    return False


def speed_from_pulses(
    pulse_times: np.ndarray, pulses_per_rev: int = 1
) -> tuple[np.ndarray, np.ndarray]:
    """Mean speed [rad/s] over each pulse interval, at the interval mid-times [s]
    (seed 002 eq 1 with an ideal clock)."""
    tp = array1d("pulse_times", pulse_times, 2, "pulse times")
    increasing("pulse_times", tp)
    r = positive_int("pulses_per_rev", pulses_per_rev, "pulses per revolution")
    return 0.5 * (tp[1:] + tp[:-1]), (2.0 * np.pi / r) / np.diff(tp)


def angle_from_speed(time: np.ndarray, speed: np.ndarray, angle0: float = 0.0) -> np.ndarray:
    """Shaft angle [rad] by trapezoidal integration of a speed history [rad/s] (exact for a
    piecewise-linear speed law). Use it to feed :func:`geardyn.sensors.simulate_ias` or
    :func:`resample_to_angle` when a model outputs speed only."""
    t = array1d("time", time, 2, "time vector")
    w = array1d("speed", speed, 2, "speed history")
    if t.size != w.size:
        raise InputError(f"speed: length {w.size} differs from time length {t.size}")
    increasing("time", t)
    out = np.empty_like(t)
    out[0] = angle0
    np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t), out=out[1:])
    out[1:] += angle0
    return out


def speed_from_angle(time: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Angular speed [rad/s] ``dθ/dt`` (second-order finite differences)."""
    t = array1d("time", time, 3, "time vector")
    th = array1d("angle", angle, 3, "angle history")
    if t.size != th.size:
        raise InputError(f"angle: length {th.size} differs from time length {t.size}")
    increasing("time", t)
    return np.gradient(th, t, edge_order=2)


def distant_shaft(reference: np.ndarray, ratio: float | complex, offset: float = 0.0) -> np.ndarray:
    """Speed or angle of another shaft through a kinematic ratio (``ω_other = ratio·ω_ref``).

    Use ``KinematicAnalysis.velocity_ratios([ref])`` for the ratio (real part; imaginary parts
    only appear for bevel axes). Works on IAS samples and angle histories alike; ``offset`` is
    added (an initial angle).
    """
    ref = array1d("reference", reference, 1, "reference speed/angle")
    r = complex(ratio)
    if abs(r.imag) > 1e-12 * max(1.0, abs(r)):
        raise InputError("ratio: must be real (same-axis shafts); got a complex ratio")
    if r.real == 0:
        raise InputError("ratio: must be non-zero (the other shaft does not turn)")
    return r.real * ref + offset


def link_ratio(analysis, reference: str, target: str) -> float:
    """Speed ratio ``ω_target/ω_reference`` of a 1-DOF mechanism from its kinematics
    (seed 000 eq 5 via ``KinematicAnalysis.velocity_ratios``); feed it to
    :func:`distant_shaft` to get the IAS or angle of a distant shaft from a measured one."""
    try:
        idx = analysis.graph.index(target)
    except (KeyError, ValueError):
        raise InputError(f"target: unknown link {target!r}") from None
    col = analysis.velocity_ratios([reference])[:, 0]  # per unit speed about ref's own axis
    r = complex(col[idx] / col[analysis.graph.index(reference)])
    if abs(r.imag) > 1e-12 * max(1.0, abs(r)):
        raise InputError(f"target: {target!r} does not turn about the axis of {reference!r}")
    return float(r.real)


def _time_of_angle(time: np.ndarray, angle: np.ndarray, targets: np.ndarray) -> np.ndarray:
    return np.interp(targets, angle, time)


#: Half-width of the band-limited interpolation kernel [input samples] (48 taps).
SINC_HALF_WIDTH = 24
#: Cut-off of the kernel [fraction of the input sample rate]: its transition band (Kaiser:
#: Δf ≈ (A − 7.95)/(2.285·2π·(2·SINC_HALF_WIDTH − 1)) ≈ 0.107 for A = 80 dB) spans
#: 0.397–0.503, so content up to fs/2.56 passes and images of it (above 0.6·fs) are rejected.
SINC_CUTOFF = 0.45
#: Highest frequency the resampled signal keeps [fraction of the input sample rate]: the
#: kernel's gain is within 5 % of 1 below it (0.952 measured at 0.42·fs) and images of content
#: below it fall above 0.58·fs, where the kernel rejects them by more than 50 dB.
SINC_PASSBAND = 0.42
#: Kaiser β for an 80 dB stopband (Kaiser 1974: β = 0.1102·(A − 8.7)).
SINC_BETA = 0.1102 * (80.0 - 8.7)
#: Kernel table resolution [points per input sample] (linear interpolation between points:
#: relative kernel error ~ (π·0.45/512)² / 8 ≈ 1e-6).
SINC_TABLE_DENSITY = 512


def _sinc_table() -> np.ndarray:
    """The interpolation kernel h(d) = 2f_c·sinc(2f_c·d)·w_Kaiser(d/H) at d = 0, 1/density, …,
    H (and one point beyond, 0), normalised so that the kernel sums to 1 over whole-sample
    shifts (unit gain at DC)."""
    h = SINC_HALF_WIDTH
    d = np.arange(h * SINC_TABLE_DENSITY + 2) / SINC_TABLE_DENSITY
    w = np.where(d < h, np.i0(SINC_BETA * np.sqrt(np.clip(1.0 - (d / h) ** 2, 0.0, 1.0)))
                 / np.i0(SINC_BETA), 0.0)
    k = 2.0 * SINC_CUTOFF * np.sinc(2.0 * SINC_CUTOFF * d) * w
    dc = k[0] + 2.0 * k[SINC_TABLE_DENSITY:h * SINC_TABLE_DENSITY:SINC_TABLE_DENSITY].sum()
    return k / dc


_SINC = _sinc_table()


def _polyphase(table: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The kernel of :func:`_sinc_table` rearranged by phase: row ``m`` holds the 2H tap
    weights h(j − m/density), j = 1 − H … H, of a position ``m/density`` past a sample, and the
    second array their increments to row ``m + 1`` (linear interpolation between phases, the
    same values as interpolating the table itself; contiguous rows let the tap loop
    vectorise)."""
    d, h = SINC_TABLE_DENSITY, SINC_HALF_WIDTH
    taps = np.arange(1 - h, h + 1)
    rows = table[np.abs(taps[None, :] * d - np.arange(d + 1)[:, None])]
    return np.ascontiguousarray(rows[:-1]), np.ascontiguousarray(np.diff(rows, axis=0))


_SINC_PHASES, _SINC_SLOPES = _polyphase(_SINC)


@numba.njit(cache=True, fastmath={"reassoc", "contract"})
def _sinc_interp(x: np.ndarray, pos: np.ndarray, phases: np.ndarray,
                 slopes: np.ndarray, density: int) -> np.ndarray:  # pragma: no cover - numba
    """Band-limited interpolation of ``x`` at fractional sample positions ``pos`` with the
    polyphase kernel of :func:`_polyphase` (edges: the first/last sample repeated)."""
    n = x.size
    taps = phases.shape[1]
    half = taps // 2
    out = np.empty(pos.size)
    for k in range(pos.size):
        p = pos[k]
        i = int(np.floor(p))
        q = (p - i) * density
        m = int(q)
        r = q - m
        if m >= density:  # p - i rounded up to 1
            m, r = density - 1, 1.0
        base = i + 1 - half
        acc = 0.0
        if base >= 0 and base + taps <= n:
            for j in range(taps):
                acc += x[base + j] * (phases[m, j] + r * slopes[m, j])
        else:
            for j in range(taps):
                idx = min(max(base + j, 0), n - 1)
                acc += x[idx] * (phases[m, j] + r * slopes[m, j])
        out[k] = acc
    return out


def interpolate_bandlimited(x: np.ndarray, pos: np.ndarray) -> np.ndarray:
    """``x`` (uniformly sampled) at fractional sample positions ``pos`` by band-limited
    (windowed-sinc) interpolation (module docstring, step 3)."""
    return _sinc_interp(np.ascontiguousarray(x, dtype=float),
                        np.ascontiguousarray(pos, dtype=float), _SINC_PHASES, _SINC_SLOPES,
                        SINC_TABLE_DENSITY)


def lowpass(x: np.ndarray, fs: float, cutoff: float, order: int = 8) -> np.ndarray:
    """Zero-phase Butterworth low-pass (``sosfiltfilt``) at ``cutoff`` [Hz]."""
    a = array1d("x", x, 16)
    f = positive("fs", fs, "sample rate [Hz]")
    c = positive("cutoff", cutoff, "cut-off frequency [Hz]")
    if c >= 0.5 * f:
        return a.copy()
    sos = sps.butter(order, c, btype="low", fs=f, output="sos")
    pad = 3 * (2 * len(sos) + 1)
    if a.size <= pad:
        raise InputError(f"x: the zero-phase filter needs more than {pad} samples, got {a.size}")
    return sps.sosfiltfilt(sos, a)


def resample_to_angle(
    x: np.ndarray,
    fs: float,
    angle: np.ndarray | None = None,
    *,
    pulse_times: np.ndarray | None = None,
    pulses_per_rev: int = 1,
    samples_per_rev: int = 256,
    max_order: float | None = None,
    anti_alias: bool = True,
    t0: float = 0.0,
) -> AngleSignal:
    """Computed order tracking: resample ``x`` (time samples at ``fs`` [Hz], first at ``t0``) to
    ``samples_per_rev`` samples per revolution of the reference shaft.

    The reference angle comes from either ``angle`` (rad, one value per sample of ``x``; from a
    simulation or an encoder; a strictly decreasing angle — a counter-rotating shaft, e.g.
    :func:`distant_shaft` with a negative :func:`link_ratio` — is negated) or ``pulse_times``
    of a tacho/encoder with ``pulses_per_rev``.
    Anti-aliasing: zero-phase low-pass at ``f_rot,min × samples_per_rev/2.56`` [Hz] (cannot
    alias at the slowest speed); band-limited interpolation (module docstring). Orders up to
    ``max_valid_order = min(0.8·cutoff, 0.42·fs)/f_rot,max`` pass at every speed;
    if ``max_order`` is given and exceeds that, an error tells the
    ``samples_per_rev`` needed (≈ 3.2 × max_order × speed ratio).
    Returns an :class:`AngleSignal` covering whole angle steps inside the record.
    """
    xs = array1d("x", x, 16)
    f = positive("fs", fs, "sample rate [Hz]")
    spr = positive_int("samples_per_rev", samples_per_rev, "samples per revolution", minimum=4)
    t = t0 + np.arange(xs.size) / f
    if (angle is None) == (pulse_times is None):
        raise InputError("resample_to_angle: give exactly one of angle= or pulse_times=")
    if angle is not None:
        th = array1d("angle", angle, xs.size, "angle history")
        if th.size != xs.size:
            raise InputError(f"angle: length {th.size} differs from signal length {xs.size}")
    else:
        tp = array1d("pulse_times", pulse_times, 3, "pulse times")
        inside = (t >= tp[0]) & (t <= tp[-1])
        if inside.sum() < 16:
            raise InputError("pulse_times: the pulses cover fewer than 16 signal samples")
        xs, t = xs[inside], t[inside]
        th = angle_from_pulses(tp, t, pulses_per_rev)
    d = np.diff(th)
    if np.all(d < 0):  # a counter-rotating shaft (negative kinematic ratio): its own forward
        th, d = -th, -d  # angle is the negated one; orders are the same
    if not np.all(d > 0):
        raise InputError("angle: the reference angle must be strictly monotonic (the shaft "
                         "must not stop or reverse during the record)")
    f_rot = d * f / (2.0 * np.pi)  # rotation frequency per sample interval [Hz]
    f_min, f_max = float(f_rot.min()), float(f_rot.max())
    # Anti-aliasing: the largest cut-off that cannot alias at the slowest speed (2.56 rule).
    cutoff = f_min * spr / 2.56
    # orders kept at every speed, within the band the interpolation keeps
    valid = min(0.8 * cutoff, SINC_PASSBAND * f) / f_max
    if max_order is not None:
        mo = positive("max_order", max_order, "maximum order")
        if mo > valid:
            if mo * f_max > SINC_PASSBAND * f:
                raise InputError(
                    f"max_order: order {mo:g} at up to {f_max:.4g} rev/s is "
                    f"{mo * f_max:.4g} Hz, beyond the band angular resampling keeps, 0.42·fs "
                    f"= {SINC_PASSBAND * f:.4g} Hz (sample rate {f:.4g} Hz); use a smaller "
                    "max_order"
                )
            need = int(np.ceil(mo * 2.56 / 0.8 * f_max / f_min))
            raise InputError(
                f"max_order: order {mo:g} cannot be kept alias-free over a speed range of "
                f"{f_min:.4g}-{f_max:.4g} rev/s with samples_per_rev={spr}; use "
                f"samples_per_rev >= {need} or a smaller max_order"
            )
    if anti_alias and cutoff < 0.5 * f:
        xs = lowpass(xs, f, cutoff)
    dth = 2.0 * np.pi / spr
    k0 = int(np.ceil(th[0] / dth))
    k1 = int(np.floor(th[-1] / dth))
    if k1 - k0 < 4:
        raise InputError("angle: the record spans fewer than 4 angular samples")
    targets = dth * np.arange(k0, k1 + 1)
    tk = _time_of_angle(t, th, targets)
    pos = (tk - t[0]) * f
    xr = interpolate_bandlimited(xs, pos)
    return AngleSignal(xr, spr, float(targets[0]), tk, valid)


def resample_ias_to_angle(angle: np.ndarray, ias: np.ndarray, samples_per_rev: int) -> np.ndarray:
    """Re-grid IAS samples [rad/s] given at increasing angles [rad] onto a uniform angle grid of
    ``samples_per_rev`` per revolution starting at ``angle[0]`` (linear interpolation; the
    elapsed-time samples are already nearly uniform in angle)."""
    th = array1d("angle", angle, 3)
    w = array1d("ias", ias, th.size)
    if w.size != th.size:
        raise InputError("ias: must have one value per angle")
    increasing("angle", th)
    spr = positive_int("samples_per_rev", samples_per_rev, "samples per revolution")
    grid = th[0] + 2 * np.pi / spr * np.arange(int((th[-1] - th[0]) * spr / (2 * np.pi)) + 1)
    return np.interp(grid, th, w)


__all__ = [
    "AngleSignal",
    "angle_from_pulses",
    "angle_from_speed",
    "distant_shaft",
    "link_ratio",
    "lowpass",
    "resample_ias_to_angle",
    "resample_to_angle",
    "speed_from_angle",
    "speed_from_pulses",
]
