"""Condition indicators (dimensionless unless stated).

Statistical: RMS (seed 003 eqs 1.20-1.21), peak, crest factor (1.22), kurtosis (1.23-1.24,
normalised: Gaussian → 3), skewness. Gear metrics after Stewart (1977) and Zakrajsek, Townsend &
Decker (1993, NASA TM-106032) / Decker (2002, NASA TM-2002-211491):

* FM0 = peak-to-peak(TSA) / Σ amplitudes of the mesh harmonics;
* FM4 = N Σ d⁴ / (Σ d²)² of the difference signal ``d`` (normalised kurtosis, ≈3 for Gaussian);
* M6A = N² Σ d⁶ / (Σ d²)³ (≈15 for Gaussian); M8A = N³ Σ d⁸ / (Σ d²)⁴ (≈105 for Gaussian);
* NA4 = N Σ (r − r̄)⁴ / [ (1/M) Σ_m Σ_n (r_mn − r̄_m)² ]² on the residual ``r`` of the current
  record normalised by the mean variance of the M records so far (trend indicator; M=1 → FM4
  of the residual);
* NB4: as NA4 on the envelope of the band-passed (around the mesh frequency) TSA;
* energy ratio ER = RMS(d) / RMS(regular);
* sideband level factor SLF = (amplitudes of the first-order sidebands of the mesh fundamental,
  orders Z ± 1) / RMS(TSA).

Several wheels on one shaft (``teeth`` a sequence): FM0, ER, the residual and difference signals
remove/count the mesh harmonics of **every** wheel. One wheel among several shares the shaft's
TSA, so it is told apart by its own mesh sidebands (:func:`wheel_sideband_orders`): the orders
``k·Z_w ± j`` (j = 1…J) that are not within ±J of another wheel's mesh harmonic. On those orders:

* sideband energy ratio SER = Σ sideband amplitudes / Σ mesh-harmonic amplitudes of the wheel
  (Hanna, Hatch, Kalb, Weiss & Luo 2011, "Detection of wind turbine gear tooth defects using
  sideband energy ratio", GE Bently Nevada: SER with the first 6 sidebands of the mesh);
* sideband kurtosis: FM4-like normalised kurtosis of the signal rebuilt from those sidebands
  only (≈2.25 for a sinusoidal once-per-rev modulation, large for a local tooth fault).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from scipy.signal import hilbert

from geardyn.errors import InputError
from geardyn.signal._checks import array1d, positive_int
from geardyn.signal.tsa import (
    _mesh_orders,
    difference_signal,
    keep_orders,
    regular_signal,
    residual_signal,
    tooth_counts,
)


def rms(x: np.ndarray) -> float:
    """Root mean square (seed 003 eq 1.21)."""
    a = array1d("x", x, 1)
    return float(np.sqrt(np.mean(a * a)))


def peak(x: np.ndarray) -> float:
    """Largest absolute value."""
    return float(np.max(np.abs(array1d("x", x, 1))))


def crest_factor(x: np.ndarray) -> float:
    """Peak / RMS (seed 003 eq 1.22); √2 for a sine."""
    r = rms(x)
    if r == 0:
        raise InputError("x: crest factor undefined for an all-zero signal")
    return peak(x) / r


def _moment_ratio(a: np.ndarray, p: int) -> float:
    c = a - a.mean()
    v = np.mean(c * c)
    if v == 0:
        raise InputError("x: signal is constant; normalised moments are undefined")
    return float(np.mean(c**p) / v ** (p / 2))


def kurtosis(x: np.ndarray) -> float:
    """Normalised 4th moment (seed 003 eq 1.24); 3 for Gaussian, 1.5 for a sine."""
    return _moment_ratio(array1d("x", x, 2), 4)


def skewness(x: np.ndarray) -> float:
    """Normalised 3rd moment; 0 for a symmetric distribution."""
    return _moment_ratio(array1d("x", x, 2), 3)


def _norm_moment_zero_mean(d: np.ndarray, p: int) -> float:
    s2 = np.sum(d * d)
    if s2 == 0:
        raise InputError("signal: all zero; the metric is undefined")
    n = d.size
    return float(n ** (p // 2 - 1) * np.sum(d**p) / s2 ** (p // 2))


def _amplitudes(a: np.ndarray) -> np.ndarray:
    """Single-sided amplitudes of the orders of a one-revolution signal (sine A reads A)."""
    return np.abs(np.fft.rfft(a)) * 2.0 / a.size


def fm0(
    tsa_signal: np.ndarray, teeth: int | Sequence[int], mesh_harmonics: int | None = None
) -> float:
    """FM0 = peak-to-peak of the TSA / sum of the mesh-harmonic amplitudes of every wheel in
    ``teeth`` (Stewart 1977; Zakrajsek, Townsend & Decker 1993)."""
    a = array1d("tsa_signal", tsa_signal, 4)
    spec = _amplitudes(a)
    den = float(sum(spec[o] for o in _mesh_orders(a.size, teeth, mesh_harmonics)))
    if den == 0:
        raise InputError("tsa_signal: no mesh-harmonic content; FM0 undefined")
    return float((a.max() - a.min()) / den)


def fm4(difference: np.ndarray) -> float:
    """FM4 of a difference signal (≈3 for Gaussian)."""
    d = array1d("difference", difference, 2)
    return _norm_moment_zero_mean(d - d.mean(), 4)


def m6a(difference: np.ndarray) -> float:
    """M6A of a difference signal (≈15 for Gaussian)."""
    d = array1d("difference", difference, 2)
    return _norm_moment_zero_mean(d - d.mean(), 6)


def m8a(difference: np.ndarray) -> float:
    """M8A of a difference signal (≈105 for Gaussian)."""
    d = array1d("difference", difference, 2)
    return _norm_moment_zero_mean(d - d.mean(), 8)


def na4(residual: np.ndarray, history: Sequence[np.ndarray] = ()) -> float:
    """NA4 of the current residual signal normalised by the mean variance of ``history``
    residuals plus the current one (records in chronological order)."""
    r = array1d("residual", residual, 2)
    recs = [array1d("history", h, 2) for h in history] + [r]
    var = np.mean([np.mean((h - h.mean()) ** 2) for h in recs])
    if var == 0:
        raise InputError("residual: zero variance; NA4 undefined")
    c = r - r.mean()
    return float(np.mean(c**4) / var**2)


def nb4(
    tsa_signal: np.ndarray,
    teeth: int | Sequence[int],
    history: Sequence[np.ndarray] = (),
    half_band: int | None = None,
) -> float:
    """NB4: NA4 applied to the envelope of the TSA band-passed around the mesh fundamental
    (orders ``Z ± half_band``, default ``Z/2``; Zakrajsek, Townsend & Decker 1993); ``history``
    holds earlier TSAs. With several wheels (``teeth`` a sequence) the band is centred on the
    first one and the mesh harmonics of the others are removed from it."""
    counts = tooth_counts(teeth)
    z = counts[0]
    hb = z // 2 if half_band is None else positive_int("half_band", half_band)

    def env(t: np.ndarray) -> np.ndarray:
        a = array1d("tsa_signal", t, 4)
        spec = np.fft.rfft(a)
        o = np.arange(spec.size)
        spec[(o < z - hb) | (o > z + hb)] = 0.0
        if len(counts) > 1:
            spec[_mesh_orders(a.size, counts[1:], None)] = 0.0
        return np.abs(hilbert(np.fft.irfft(spec, a.size)))

    cur = env(tsa_signal)
    return na4(cur, [env(h) for h in history])


def energy_ratio(
    tsa_signal: np.ndarray, teeth: int | Sequence[int], mesh_harmonics: int | None = None
) -> float:
    """ER = RMS(difference) / RMS(regular), every wheel in ``teeth`` removed / kept
    (Zakrajsek, Townsend & Decker 1993)."""
    reg = regular_signal(tsa_signal, teeth, mesh_harmonics)
    d = difference_signal(tsa_signal, teeth, mesh_harmonics)
    den = rms(reg)
    if den == 0:
        raise InputError("tsa_signal: no mesh-harmonic content; energy ratio undefined")
    return rms(d) / den


def _synchronous_stats(x: np.ndarray, samples_per_rev: int) -> tuple[np.ndarray, np.ndarray]:
    """Unclipped unbiased synchronous power per order and its standard error ``V/N``."""
    a = array1d("x", x, 4)
    spr = positive_int("samples_per_rev", samples_per_rev, "samples per revolution", minimum=4)
    n = a.size // spr
    if n < 2:
        raise InputError(f"x: needs at least 2 whole revolutions of {spr} samples, got {n}")
    spec = np.fft.rfft(a[: n * spr].reshape(n, spr), axis=1) * (2.0 / spr)
    mean = spec.mean(axis=0)
    var = np.sum(np.abs(spec - mean) ** 2, axis=0) / (n - 1)
    return np.abs(mean) ** 2 - var / n, var / n


def synchronous_stats_from_moments(
    mean: np.ndarray, var: np.ndarray, n: int, samples_per_rev: int
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_synchronous_stats` from the mean and variance (ddof = 1) of the per-revolution
    rfft spectra of ``n ≥ 2`` revolutions (unscaled, e.g. accumulated revolution batch by
    batch, :class:`geardyn.signal.stream.RevolutionStats`)."""
    if n < 2:
        raise InputError(f"x: needs at least 2 whole revolutions, got {n}")
    c = 2.0 / int(samples_per_rev)
    m = np.asarray(mean) * c
    v = np.asarray(var) * (c * c)
    return np.abs(m) ** 2 - v / n, v / n


def synchronous_power(x: np.ndarray, samples_per_rev: int, clip: bool = True) -> np.ndarray:
    """Unbiased synchronous power per order of an angle-domain record of N ≥ 2 whole
    revolutions: ``|X̄(o)|² − V(o)/N``, with ``X̄`` the spectrum of the TSA and
    ``V(o) = Σ_n |X_n(o) − X̄(o)|²/(N − 1)`` the variance of the per-revolution spectra (the
    non-synchronous part, which the TSA only attenuates to ``V/N``; Braun 1975, "The
    extraction of periodic waveforms by time domain averaging", Acustica 32). Clipped at 0
    unless ``clip`` is False (sums over many orders stay unbiased only unclipped);
    single-sided amplitude² scale (a sine of amplitude A reads A²)."""
    p, _ = _synchronous_stats(x, samples_per_rev)
    return np.maximum(p, 0.0) if clip else p


def synchronous_energy_ratio(
    x: np.ndarray,
    samples_per_rev: int,
    teeth: int | Sequence[int] = (),
    regular: Sequence[int] = (),
    shaft_harmonics: int = 1,
    sidebands: int = 1,
    regular_sidebands: bool = True,
) -> tuple[float, float]:
    """Energy ratio ER = RMS(difference)/RMS(regular) (Zakrajsek et al. 1993) from unbiased
    synchronous powers (:func:`synchronous_power`), so that non-synchronous content left in a
    short average does not inflate it. Regular orders: mesh harmonics of ``teeth`` plus
    ``regular``; the difference band leaves out orders 0…``shaft_harmonics``, the regular
    orders and the ±1…``sidebands`` sidebands of the mesh harmonics (and of the ``regular``
    orders unless ``regular_sidebands`` is False). Each sum is unbiased (unclipped orders) and
    floored at its standard error ``√Σ(V/N)²`` (the spread of the estimate when there is no
    synchronous content), so that it never reads 0. Returns ``(ER, rms of the difference)``."""
    p, se = _synchronous_stats(x, samples_per_rev)
    return energy_ratio_from_power(
        p, se, samples_per_rev, teeth, regular, shaft_harmonics, sidebands, regular_sidebands
    )


def energy_ratio_from_power(
    p: np.ndarray,
    se: np.ndarray,
    samples_per_rev: int,
    teeth: int | Sequence[int] = (),
    regular: Sequence[int] = (),
    shaft_harmonics: int = 1,
    sidebands: int = 1,
    regular_sidebands: bool = True,
) -> tuple[float, float]:
    """:func:`synchronous_energy_ratio` from the unbiased synchronous power per order ``p`` and
    its standard error ``se`` (:func:`synchronous_stats_from_moments`)."""
    spr = int(samples_per_rev)
    has_teeth = (isinstance(teeth, (int, np.integer)) and teeth) or (
        not isinstance(teeth, (int, np.integer)) and len(teeth)
    )
    mesh = set(_mesh_orders(spr, teeth, None)) if has_teeth else set()
    reg = {o for o in {*mesh, *(int(o) for o in regular)} if 0 < o < p.size}
    if not reg:
        raise InputError("teeth/regular: no regular order below Nyquist; ER undefined")
    centres = reg if regular_sidebands else mesh
    out = {0, *range(1, shaft_harmonics + 1), *reg}
    out |= {o + j for o in centres for j in range(-sidebands, sidebands + 1)}
    keep = np.ones(p.size, dtype=bool)
    keep[[o for o in out if 0 <= o < p.size]] = False
    idx = sorted(reg)

    def total(sel) -> float:  # noqa: ANN001
        return max(float(p[sel].sum()), float(np.sqrt(np.sum(se[sel] ** 2))))

    e_reg, e_diff = total(idx), total(keep)
    if e_reg == 0:
        raise InputError("x: no synchronous power at the regular orders; ER undefined")
    return float(np.sqrt(e_diff / e_reg)), float(np.sqrt(0.5 * e_diff))


def wheel_sideband_orders(
    n: int,
    teeth: int,
    other_teeth: Sequence[int] = (),
    sidebands: int = 3,
    mesh_harmonics: int | None = None,
    exclude: Sequence[int] = (),
) -> tuple[list[int], list[int]]:
    """Mesh orders ``k·Z`` and unambiguous sideband orders ``k·Z ± j`` (j = 1…``sidebands``) of
    one wheel in a one-revolution signal of ``n`` samples (orders up to ``n/2 − 1``).

    A sideband is ambiguous, and left out, when it lies within ±``sidebands`` of a mesh harmonic
    of another wheel of the same shaft (``other_teeth``); a mesh harmonic is left out when
    another wheel has one at the same order; orders in ``exclude`` (e.g. combination tones of
    the shaft's meshes) are never sidebands. Returns ``(mesh_orders, sideband_orders)``.
    """
    nn = positive_int("n", n, "samples per revolution", minimum=4)
    z = positive_int("teeth", teeth, "tooth count")
    j_max = positive_int("sidebands", sidebands, "number of sidebands per side")
    others = tooth_counts(other_teeth) if len(other_teeth) else ()
    top = nn // 2 - 1
    other_mesh = np.array(
        sorted({k * zo for zo in others for k in range(1, (top + j_max) // zo + 1)}), dtype=int
    )
    mesh = _mesh_orders(nn, z, mesh_harmonics)
    mesh = [m for m in mesh if m <= top and m not in set(other_mesh.tolist())]

    def ambiguous(o: int) -> bool:
        return bool(other_mesh.size) and bool(np.min(np.abs(other_mesh - o)) <= j_max)

    own = set(_mesh_orders(nn, z, None))
    side: set[int] = set()
    for m in mesh:
        for j in range(1, j_max + 1):
            for o in (m - j, m + j):
                if 1 <= o <= top and o not in own and not ambiguous(o):
                    side.add(o)
    return mesh, sorted(side - {int(o) for o in exclude})


def sideband_energy_ratio(
    tsa_signal: np.ndarray,
    teeth: int,
    other_teeth: Sequence[int] = (),
    sidebands: int = 3,
    mesh_harmonics: int | None = None,
    exclude: Sequence[int] = (),
) -> float:
    """SER of one wheel: Σ amplitudes of its unambiguous sidebands / Σ amplitudes of its mesh
    harmonics (Hanna et al. 2011), orders from :func:`wheel_sideband_orders`."""
    a = array1d("tsa_signal", tsa_signal, 4)
    mesh, side = wheel_sideband_orders(
        a.size, teeth, other_teeth, sidebands, mesh_harmonics, exclude
    )
    spec = _amplitudes(a)
    den = float(spec[mesh].sum()) if mesh else 0.0
    if den == 0:
        raise InputError(f"tsa_signal: no mesh-harmonic content at orders k·{teeth}; SER undefined")
    return float(spec[side].sum()) / den


def sideband_kurtosis(
    tsa_signal: np.ndarray,
    teeth: int,
    other_teeth: Sequence[int] = (),
    sidebands: int = 3,
    mesh_harmonics: int | None = None,
    exclude: Sequence[int] = (),
) -> float:
    """Normalised kurtosis (FM4 form, Zakrajsek et al. 1993) of the signal rebuilt from the
    wheel's unambiguous sideband orders only (:func:`wheel_sideband_orders`)."""
    a = array1d("tsa_signal", tsa_signal, 4)
    _, side = wheel_sideband_orders(
        a.size, teeth, other_teeth, sidebands, mesh_harmonics, exclude
    )
    if not side:
        raise InputError(
            f"teeth: wheel {teeth} has no unambiguous sideband orders below Nyquist "
            f"(other wheels {list(other_teeth)}, sidebands={sidebands})"
        )
    return _norm_moment_zero_mean(keep_orders(a, side), 4)


def wheel_nb4(
    tsa_signal: np.ndarray,
    teeth: int,
    other_teeth: Sequence[int] = (),
    sidebands: int = 3,
    history: Sequence[np.ndarray] = (),
    mesh_harmonics: int | None = None,
    exclude: Sequence[int] = (),
) -> float:
    """NB4 (Zakrajsek et al. 1993) restricted to one wheel: NA4 of the envelope of the signal
    rebuilt from the wheel's mesh harmonics and unambiguous sidebands
    (:func:`wheel_sideband_orders`); ``history``: earlier TSAs of the same shaft."""

    def env(t: np.ndarray) -> np.ndarray:
        a = array1d("tsa_signal", t, 4)
        mesh, side = wheel_sideband_orders(
            a.size, teeth, other_teeth, sidebands, mesh_harmonics, exclude
        )
        return np.abs(hilbert(keep_orders(a, [*mesh, *side])))

    return na4(env(tsa_signal), [env(h) for h in history])


def wheel_indicators(
    tsa_signal: np.ndarray,
    teeth: int,
    other_teeth: Sequence[int] = (),
    sidebands: int = 3,
    history: Sequence[np.ndarray] = (),
    mesh_harmonics: int | None = 3,
    exclude: Sequence[int] = (),
) -> dict[str, float]:
    """Indicators localising one wheel among the wheels of its shaft from the shaft's TSA, all
    on the wheel's own mesh harmonics 1…``mesh_harmonics`` (default 3, as SER practice; None:
    up to Nyquist, where empty harmonics add only noise) and their unambiguous sidebands:
    ``SER``, ``sideband_kurtosis`` and ``NB4`` (:func:`wheel_nb4`; ``history``: earlier
    TSAs). ``exclude``: orders that are never sidebands (combination tones)."""
    h, ex = mesh_harmonics, exclude
    return {
        "SER": sideband_energy_ratio(tsa_signal, teeth, other_teeth, sidebands, h, ex),
        "sideband_kurtosis": sideband_kurtosis(tsa_signal, teeth, other_teeth, sidebands, h, ex),
        "NB4": wheel_nb4(tsa_signal, teeth, other_teeth, sidebands, history, h, ex),
    }


def sideband_level_factor(tsa_signal: np.ndarray, teeth: int) -> float:
    """SLF = (|X(Z−1)| + |X(Z+1)|) / RMS(TSA), amplitudes from the one-revolution TSA."""
    a = array1d("tsa_signal", tsa_signal, 4)
    z = positive_int("teeth", teeth, "tooth count")
    spec = np.abs(np.fft.rfft(a)) * 2.0 / a.size
    if z + 1 >= spec.size:
        raise InputError("teeth: mesh order + 1 exceeds the TSA's Nyquist order")
    return float((spec[z - 1] + spec[z + 1]) / rms(a))


def gear_indicators(
    tsa_signal: np.ndarray, teeth: int | Sequence[int], mesh_harmonics: int | None = None
) -> dict[str, float]:
    """All single-record indicators of a one-revolution TSA of a shaft whose wheels have
    ``teeth`` teeth (SLF: first wheel)."""
    d = difference_signal(tsa_signal, teeth, mesh_harmonics)
    r = residual_signal(tsa_signal, teeth, mesh_harmonics)
    return {
        "rms": rms(tsa_signal),
        "peak": peak(tsa_signal),
        "crest_factor": crest_factor(tsa_signal),
        "kurtosis": kurtosis(tsa_signal),
        "skewness": skewness(tsa_signal),
        "FM0": fm0(tsa_signal, teeth, mesh_harmonics),
        "FM4": fm4(d),
        "M6A": m6a(d),
        "M8A": m8a(d),
        "NA4": na4(r),
        "NB4": nb4(tsa_signal, teeth),
        "energy_ratio": energy_ratio(tsa_signal, teeth, mesh_harmonics),
        "SLF": sideband_level_factor(tsa_signal, tooth_counts(teeth)[0]),
    }


def signal_indicators(x: np.ndarray) -> dict[str, float]:
    """RMS, peak, crest factor, kurtosis and skewness of any signal."""
    return {
        "rms": rms(x),
        "peak": peak(x),
        "crest_factor": crest_factor(x),
        "kurtosis": kurtosis(x),
        "skewness": skewness(x),
    }
