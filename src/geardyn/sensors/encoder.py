"""Encoder / counter-clock measurement of instantaneous angular speed (IAS).

Elapsed-time method (seed 002 eq 1): a counter clock of frequency ``f_clock`` counts the ticks
``N_i`` between encoder edges ``i-1`` and ``i``; with ``R`` pulses per revolution the IAS sample
at the angle ``i·Δθ`` (``Δθ = 2π/R``) is ``IAS_i = Δθ/Δt_i = 2π f_clock/(R N_i)`` [rad/s].

Quantisation: ``N_i`` differs from the true ``f_clock·Δt_i`` by less than one tick, so the error
on each interval's mean speed ``ω̄_i = Δθ/Δt_i`` is bounded by ``ω̄_i/N_i`` (relative error
``< 1/N_i ≈ R ω̄_i/(2π f_clock)``). It grows with speed (seed 002 §3.1, "higher at high speed
because ... the number of clock pulses is smaller"): relative error ∝ ω, absolute error ∝ ω².

Units: time [s], angle [rad], speed [rad/s], clock frequency [Hz].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from geardyn.errors import InputError
from geardyn.signal._checks import array1d, increasing, positive, positive_int, rng


@dataclass(frozen=True)
class IASMeasurement:
    """IAS by the elapsed-time method (seed 002 eq 1), one sample per encoder interval.

    ``angle`` [rad]: encoder angle at the end of each interval (``i·Δθ``, nominal graduation);
    ``ias`` [rad/s]: ``Δθ/Δt_i`` with the quantised ``Δt_i = N_i/f_clock``; ``ticks``: ``N_i``;
    ``time`` [s]: quantised edge times (end of each interval); ``bound`` [rad/s]: quantisation
    bound ``ias_i/(N_i - 1)`` (the true interval-mean speed lies within ``ias ± bound``).
    """

    angle: np.ndarray
    ias: np.ndarray
    ticks: np.ndarray
    time: np.ndarray
    bound: np.ndarray
    pulses_per_rev: int
    f_clock: float


def pulse_times_from_angle(
    time: np.ndarray,
    angle: np.ndarray,
    pulses_per_rev: int,
    graduation_error: np.ndarray | float | None = None,
    seed: int | np.random.Generator | None = None,
    angle_offset: float = 0.0,
) -> np.ndarray:
    """Times [s] at which encoder edges pass, given a shaft angle history ``angle(time)`` [rad].

    Edge ``k`` sits at the angle ``angle_offset + k·2π/R + ε_{k mod R}``; ``graduation_error``
    is either an array of ``R`` angular errors [rad] (the graduation pattern, repeated every
    revolution) or a standard deviation [rad] for a Gaussian pattern drawn with ``seed``. The
    angle history must be strictly increasing (a forward-turning shaft). Edge times are found by
    cubic Hermite interpolation of ``time(angle)`` using the local speed; sample the angle
    history finely enough (≥ 4 samples per encoder interval is plenty for smooth speed laws).
    """
    t = array1d("time", time, 3, "time vector")
    th = array1d("angle", angle, 2, "angle history")
    if th.size != t.size:
        raise InputError(f"angle: length {th.size} differs from time length {t.size}")
    increasing("time", t)
    increasing("angle", th, "angle history (shaft must turn forward; negate it otherwise)")
    r = positive_int("pulses_per_rev", pulses_per_rev, "encoder resolution")
    eps = _graduation(graduation_error, r, seed)
    dth = 2.0 * np.pi / r
    k0 = int(np.ceil((th[0] - angle_offset - eps.max()) / dth))
    k1 = int(np.floor((th[-1] - angle_offset - eps.min()) / dth))
    k = np.arange(k0, k1 + 1)
    targets = angle_offset + k * dth + eps[np.mod(k, r)]
    keep = (targets >= th[0]) & (targets <= th[-1])
    targets = targets[keep]
    # Cubic Hermite inversion: time as a function of angle, with dt/dθ = 1/ω.
    w = np.gradient(th, t, edge_order=2)
    if np.any(w <= 0):
        raise InputError("angle: the shaft speed must stay > 0 to generate encoder pulses")
    from scipy.interpolate import CubicHermiteSpline

    return CubicHermiteSpline(th, t, 1.0 / w)(targets)


def _graduation(err: np.ndarray | float | None, r: int, seed) -> np.ndarray:
    if err is None:
        return np.zeros(r)
    if np.ndim(err) == 0:
        s = float(err)
        if not np.isfinite(s) or s < 0:
            raise InputError(f"graduation_error: standard deviation must be >= 0, got {err!r}")
        e = rng(seed).normal(0.0, s, r) if s > 0 else np.zeros(r)
    else:
        e = array1d("graduation_error", err, r, "graduation error pattern")
        if e.size != r:
            raise InputError(f"graduation_error: needs one value per pulse ({r}), got {e.size}")
    if np.max(np.abs(e)) >= np.pi / r:
        raise InputError("graduation_error: errors must stay below half a graduation (π/R)")
    return e


def quantise_clock(pulse_times: np.ndarray, f_clock: float, clock_phase: float = 0.0) -> np.ndarray:
    """Counter values (integer ticks) latched at each edge: ``floor(t·f_clock + phase)``.

    ``clock_phase`` in [0, 1) is the clock's fractional tick at ``t = 0``.
    """
    tp = array1d("pulse_times", pulse_times, 2, "pulse times")
    increasing("pulse_times", tp)
    fc = positive("f_clock", f_clock, "clock frequency [Hz]")
    if not 0.0 <= clock_phase < 1.0:
        raise InputError(f"clock_phase: must be in [0, 1), got {clock_phase!r}")
    return np.floor(tp * fc + clock_phase).astype(np.int64)


def elapsed_time_ias(
    pulse_times: np.ndarray,
    pulses_per_rev: int,
    f_clock: float | None = None,
    clock_phase: float = 0.0,
) -> IASMeasurement:
    """IAS by the elapsed-time method, seed 002 eq 1: ``IAS_i = 2π f_clock/(R N_i)`` [rad/s].

    ``pulse_times`` [s] are the true edge times; they are latched by a counter clock of
    ``f_clock`` [Hz] (``None`` means an ideal clock, no quantisation). The returned samples are
    equally spaced in angle (``Δθ = 2π/R``), the natural angular sampling of the method.
    """
    r = positive_int("pulses_per_rev", pulses_per_rev, "encoder resolution")
    tp = array1d("pulse_times", pulse_times, 2, "pulse times")
    increasing("pulse_times", tp)
    dth = 2.0 * np.pi / r
    if f_clock is None:
        dt = np.diff(tp)
        ticks = np.full(dt.size, -1, dtype=np.int64)
        ias = dth / dt
        bound = np.zeros_like(ias)
        tq = tp[1:]
        fc = np.inf
    else:
        fc = positive("f_clock", f_clock, "clock frequency [Hz]")
        counts = quantise_clock(tp, fc, clock_phase)
        ticks = np.diff(counts)
        if np.any(ticks < 2):
            raise InputError(
                "f_clock: fewer than 2 clock ticks between encoder edges; the clock is too slow "
                "for this speed and resolution"
            )
        ias = 2.0 * np.pi * fc / (r * ticks)
        bound = ias / (ticks - 1)
        tq = counts[1:] / fc
    angle = dth * np.arange(1, tp.size)
    return IASMeasurement(angle, ias, ticks, tq, bound, r, fc)


def quantisation_bound(speed: np.ndarray | float, pulses_per_rev: int, f_clock: float):
    """Quantisation error bound [rad/s] at speed ``speed`` [rad/s]: ``ω/N`` with
    ``N = 2π f_clock/(R ω)`` ticks per interval, i.e. ``R ω²/(2π f_clock)`` (seed 002 §3.1:
    the error grows with speed)."""
    r = positive_int("pulses_per_rev", pulses_per_rev, "encoder resolution")
    fc = positive("f_clock", f_clock, "clock frequency [Hz]")
    w = np.asarray(speed, dtype=float)
    return r * w**2 / (2.0 * np.pi * fc)


def tacho_pulse_times(
    time: np.ndarray, angle: np.ndarray, pulses_per_rev: int = 1, angle_offset: float = 0.0
) -> np.ndarray:
    """Once-per-rev (or ``pulses_per_rev``) tachometer pulse times [s] from an angle history."""
    return pulse_times_from_angle(time, angle, pulses_per_rev, angle_offset=angle_offset)


def simulate_ias(
    time: np.ndarray,
    angle: np.ndarray,
    pulses_per_rev: int = 1000,
    f_clock: float = 80e6,
    graduation_error: np.ndarray | float | None = None,
    seed: int | np.random.Generator | None = None,
    clock_phase: float = 0.0,
) -> IASMeasurement:
    """Simulated IAS measurement of a shaft with angle history ``angle(time)`` [rad]:
    encoder (``pulses_per_rev``, graduation errors) + counter clock ``f_clock`` [Hz] +
    elapsed-time method (seed 002 eq 1). Defaults are the seed 002 setup (1000 pulses/rev,
    80 MHz). This is the entry point for simulated shafts (dynamic models)."""
    tp = pulse_times_from_angle(time, angle, pulses_per_rev, graduation_error, seed)
    return elapsed_time_ias(tp, pulses_per_rev, f_clock, clock_phase)
