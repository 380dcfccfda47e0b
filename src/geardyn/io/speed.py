"""Shaft speed of a measured record: pulse times from an analog tacho or encoder channel, and the
shaft angle from pulses, a speed profile or a constant speed.

:func:`pulse_times_from_signal` follows MATLAB's ``tachorpm``: the two state levels of the pulse
train are the modes of the lower and upper halves of a 100-bin histogram (``statelevels``,
IEEE 181-2011 §5.2 histogram method), the threshold lies midway between them, and a pulse is a
rising crossing of the threshold, its time interpolated linearly between the two samples around
it. A hysteresis band (default 10 % of the level difference, a judgement: well above the noise
of a clean TTL tacho, well below its swing) makes a crossing count only after the signal has
been below ``threshold − hysteresis/2`` and reaches ``threshold + hysteresis/2``, so noise on a
slow edge gives one pulse, not several.
"""

from __future__ import annotations

import numpy as np

from geardyn.errors import InputError


def state_levels(x: np.ndarray, bins: int = 100) -> tuple[float, float]:
    """Low and high state levels of a two-level signal (histogram modes of its lower and upper
    halves, IEEE 181-2011 §5.2; MATLAB ``statelevels``)."""
    x = np.asarray(x, float)
    lo, hi = float(np.min(x)), float(np.max(x))
    if not hi > lo:
        return lo, hi
    counts, edges = np.histogram(x, bins=bins, range=(lo, hi))
    centres = 0.5 * (edges[1:] + edges[:-1])
    half = bins // 2
    return (float(centres[np.argmax(counts[:half])]),
            float(centres[half + np.argmax(counts[half:])]))


def pulse_times_from_signal(x: np.ndarray, fs: float, t0: float = 0.0,
                            threshold: float | None = None, hysteresis: float | None = None,
                            where: str = "tacho") -> np.ndarray:
    """Rising-edge times [s] of an analog pulse train sampled at ``fs`` [Hz] (module
    docstring); ``threshold``/``hysteresis`` in the signal's units."""
    x = np.asarray(x, float)
    low, high = state_levels(x)
    if not high > low:
        raise InputError(f"{where}: the signal is constant ({low:g}); no pulses")
    thr = 0.5 * (low + high) if threshold is None else float(threshold)
    h = 0.1 * (high - low) if hysteresis is None else float(hysteresis)
    if not low < thr < high:
        raise InputError(f"{where}: threshold {thr:g} lies outside the signal's state levels "
                         f"{low:g}…{high:g}")
    # entries into the upper band, into the lower band, and upward crossings of the threshold
    # (one byte per sample transient; the event lists are as long as the pulse count)
    up = _entries(x >= thr + 0.5 * h)
    low_band = x < thr - 0.5 * h
    down = _entries(low_band)
    if low_band[0]:  # a record starting low: its first rising edge is whole
        down = np.concatenate([[0], down])
    cross = _entries(x >= thr)
    # a rise: an entry into the upper band after the last band entered was the lower one
    last_down = np.searchsorted(down, up, side="right") - 1  # last down entry before each up
    prev_up = np.concatenate([[-1], up[:-1]])
    ok = last_down >= 0
    ok &= np.where(ok, down[np.maximum(last_down, 0)] > prev_up, False)
    rise = up[ok]
    k = cross[np.searchsorted(cross, rise, side="right") - 1]  # first sample ≥ thr of the edge
    i = k - 1
    frac = (thr - x[i]) / (x[i + 1] - x[i])
    return t0 + (i + frac) / fs


def _entries(mask: np.ndarray) -> np.ndarray:
    """Indices where ``mask`` becomes True (not index 0: the state before is unknown)."""
    m = mask.view(np.int8) if mask.dtype == bool else mask.astype(np.int8)
    return np.flatnonzero(np.diff(m) == 1) + 1


def trim_pulses(tp: np.ndarray, t_start: float, t_end: float) -> np.ndarray:
    """Pulses of a tacho longer than the record, trimmed to the record span keeping one pulse
    beyond each end (so that the angle of every sample is interpolated, not extrapolated)."""
    tp = np.asarray(tp, float)
    i0 = max(0, int(np.searchsorted(tp, t_start, side="right")) - 1)
    i1 = min(tp.size, int(np.searchsorted(tp, t_end, side="left")) + 1)
    return tp[i0:i1]


def angle_from_profile(t: np.ndarray, profile_rpm: list[tuple[float, float]]) -> np.ndarray:
    """Angle [rad] at ``t`` of a piecewise-linear speed profile ``[(t_s, rpm), …]`` (exact
    integral: trapezoids between the profile points, a partial trapezoid inside)."""
    pt = np.array([p[0] for p in profile_rpm], float)
    w = np.array([p[1] for p in profile_rpm], float) * 2 * np.pi / 60.0
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(pt))])
    k = np.clip(np.searchsorted(pt, t, side="right") - 1, 0, pt.size - 2)
    dt = t - pt[k]
    slope = (w[k + 1] - w[k]) / (pt[k + 1] - pt[k])
    return cum[k] + w[k] * dt + 0.5 * slope * dt**2


def repair_missing_pulses(tp: np.ndarray, window: int = 9) -> tuple[np.ndarray, list[float]]:
    """Pulse times with missed pulses restored: an interval ``d`` of ``r = d/m`` local median
    intervals (running median over ``window`` intervals) holds ``round(r) − 1`` missed pulses
    when ``r > 1.5`` (halfway between one interval and two), inserted evenly. Returns the
    repaired times and the times [s] of the intervals repaired."""
    from scipy.ndimage import median_filter

    tp = np.asarray(tp, float)
    if tp.size < 4:
        return tp, []
    d = np.diff(tp)
    m = median_filter(d, size=min(window, d.size), mode="nearest")
    r = d / m
    bad = np.flatnonzero(r > 1.5)
    if bad.size == 0:
        return tp, []
    pieces, start = [], 0
    for i in bad:
        k = int(round(r[i]))
        pieces.append(tp[start:i + 1])
        pieces.append(tp[i] + d[i] * np.arange(1, k) / k)
        start = i + 1
    pieces.append(tp[start:])
    return np.concatenate(pieces), [float(tp[i]) for i in bad]
