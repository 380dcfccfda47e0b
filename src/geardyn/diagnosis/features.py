"""Condition indicators per machine component, driven by the kinematics.

:func:`extract_features` takes one channel ``x`` with the reference-shaft angle at each sample
and the components of :func:`geardyn.diagnosis.components.machine_components`, and computes,
per block of whole revolutions:

* **shafts** (own angle ``|r|·θ_ref``, sign handled): TSA (seed 003 eq 1.25), FM0, FM4, NA4
  (earlier blocks as history), NB4, energy ratio ER, RMS and kurtosis of the difference signal
  (Zakrajsek, Townsend & Decker 1993) — the residual/difference signals remove the mesh
  harmonics of **every** fixed-axis wheel on the shaft; the TSA's orders are shrunk by their
  synchronous fraction ``max(0, 1 − V/(N|X̄|²))`` (Wiener weighting with the
  revolution-to-revolution variance V, Braun 1975) and ER and the difference RMS use unbiased
  synchronous powers, so that the non-synchronous content a short average keeps (another
  component's fault, noise) raises neither — measured on seed 004 simulations (ring
  accelerometer, 3 carrier revolutions): a sun crack reads z = 76 on the sun and 6 on the
  planets with the shrinkage, 5.7 and 10.3 (ring) without;
  a shaft with several wheels also counts the combination tones ``a·Z_i + b·Z_j``
  (``|a| + |b| ≤`` :data:`COMBINATION_ORDER`) as regular meshing;
* **wheels** sharing a shaft: indicators on the wheel's own unambiguous mesh sidebands
  (:func:`geardyn.signal.indicators.wheel_indicators`: SER after Hanna et al. 2011, sideband
  kurtosis, NB4 restricted to the wheel; combination tones are not left out of the sidebands,
  which would cost most of the sensitivity — the healthy baseline carries them);
* **sun, planets, ring**: TSA in the component's own angle relative to the carrier (seed 004
  §8.2 averages per component revolution; the planets of a stage share it, so they are told
  apart only with ``planet_windows``: planet-separated TSA by McFadden's window technique,
  :func:`geardyn.signal.planetary_tsa`, one per planet, for a ring accelerometer on a fixed
  ring); same indicators as a shaft with the component's tooth count; for the ring the
  regular meshing also holds the planet-pass orders (multiples of N next to ``h·Z_r``,
  seed 003 §4.1);
* **bearings**: squared-envelope spectrum in orders of the reference (band of maximum
  spectral kurtosis, Antoni 2007, from the fast kurtogram :mod:`geardyn.signal.kurtogram`
  of the central :data:`KURTOGRAM_MAX_SAMPLES` samples, unless ``envelope_band`` is given,
  below the resampling's anti-aliasing limit):
  for each line BPFO/BPFI/BSF/FTF, the mean over harmonics 1–3 of the peak within
  ``±max(2/R, 0.02·order)`` (R revolutions per block; 2 % allows for rolling-element slip) over
  the median level in ``±max(20/R, 0.2·order)`` (Randall & Antoni 2011, "Rolling element
  bearing diagnostics — a tutorial", MSSP 25).

Resampling: the channel is resampled to a uniform angle of the reference and, per own-angle
ratio, to an integer number of samples per own revolution (a fast FFT length): a uniformly
time-sampled channel directly from its time samples, stretch by stretch
(:class:`geardyn.signal.stream.AngleGrid`: the values of
:func:`geardyn.signal.resample_to_angle`), an angle-sampled one (encoder IAS) by linear
interpolation in angle and then from the reference grid; TSAs are rolled so that their index 0
is own angle 0 (the reference angle's origin times the ratio). The reference grid has
:data:`GRID_FACTOR` (1.344) times the channel's samples per revolution at the slowest speed,
rounded up to a power of two: the whole band the interpolation keeps (0.42·fs), no
anti-aliasing filter needed. The TSAs and synchronous powers come from the mean and variance
of the revolutions' spectra accumulated revolution batch by batch
(:class:`geardyn.signal.stream.RevolutionStats`); a reference grid longer than
:data:`SEGMENT_MAX` samples (a long record) is never held whole: its envelope spectra are
averaged over segments (:func:`_long_reference_pass`) and its order spectrum and kurtogram
taken on the central revolutions (:func:`_kurtogram_span`).
Blocks hold at least :data:`MIN_REVS_PER_BLOCK` own revolutions: a component with fewer than
``4·n_blocks`` whole revolutions gets fewer blocks (one block of all its revolutions if it has
fewer than 8); one with less than one revolution is left out (listed in ``Features.notes``).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
import xarray as xr

from geardyn.diagnosis.components import BEARING_LINES, Component, Components, machine_components

if TYPE_CHECKING:
    from geardyn.config import Mechanism
from geardyn.errors import InputError
from geardyn.signal._checks import array1d, positive_int
from geardyn.signal.envelope import band_squared_envelope_spectrum, envelope_spectrum
from geardyn.signal.indicators import (
    energy_ratio,
    energy_ratio_from_power,
    fm0,
    fm4,
    kurtosis,
    na4,
    nb4,
    rms,
    synchronous_stats_from_moments,
    wheel_indicators,
)
from geardyn.signal.kurtogram import fast_kurtogram
from geardyn.signal.resample import AngleSignal, resample_to_angle
from geardyn.signal.spectra import order_spectrum
from geardyn.signal.stream import CHUNK, AngleGrid, ArrayGrid, RevolutionStats, revolution_spectra
from geardyn.signal.tsa import difference_signal, keep_orders, planetary_tsa, residual_signal

COLUMNS = ["component", "kind", "indicator", "value", "block", "channel"]
#: Sidebands per side used to localise a wheel on a shared shaft.
WHEEL_SIDEBANDS = 3
#: Fewest own revolutions averaged per block (TSA rejection of non-synchronous content ∝ 1/√N).
MIN_REVS_PER_BLOCK = 4
#: Largest |a| + |b| of the combination tones a·Z_i + b·Z_j counted as regular meshing.
COMBINATION_ORDER = 12
#: Most samples of the reference-angle signal the kurtogram is estimated on
#: (:func:`_kurtogram_span`).
KURTOGRAM_MAX_SAMPLES = 2**22
#: Reference-grid samples per revolution per channel sample per revolution at the slowest
#: speed: the anti-aliasing cut-off of the angular resampling, ``f_rot,min·spr/2.56``, then
#: keeps 0.8 of it above the band the interpolation keeps (0.42·fs), so the grid loses none of
#: the channel's band and needs no filter (2.56·0.42/0.8).
GRID_FACTOR = 2.56 * 0.42 / 0.8
#: Reference-grid samples above which the order spectrum, the squared-envelope spectra and the
#: synchronous statistics are computed segment by segment (:func:`_long_reference_pass`).
SEGMENT_MAX = 1 << 23
#: Bearing line harmonics.
BEARING_HARMONICS = (1, 2, 3)
TWO_PI = 2.0 * np.pi


@dataclass
class Features:
    """Indicators of one channel and the artefacts a report shows.

    ``table``: long format, columns :data:`COLUMNS` (``kind`` in shaft/wheel/bearing/sun/
    planet/ring; ``block`` 0-based in time order; dimensionless values);
    ``tsa``: component → one-revolution TSA (``angle`` coordinate [deg] of its own angle,
    ``units`` of the channel); ``order_spectrum`` and ``envelope_spectrum``: coordinate
    ``order`` [events/rev of the reference]; ``band``: envelope band (orders); ``kurtogram``:
    (window, frequency [orders]) or None; ``markers``: :func:`geardyn.signal.spectral_markers`
    at the mean speed, or None; ``block_tsa``: component → the TSA of each block (same angle
    grid as ``tsa``; input of :func:`reference_residuals`); ``components``: what was judged.
    """

    table: pd.DataFrame
    tsa: dict[str, xr.DataArray]
    order_spectrum: xr.DataArray | None
    envelope_spectrum: xr.DataArray | None
    band: tuple[float, float] | None
    kurtogram: xr.DataArray | None
    markers: pd.DataFrame | None
    channel: str = ""
    units: str = ""
    reference: str = ""
    samples_per_rev: int = 0
    revolutions: float = 0.0
    mean_rpm: float = math.nan
    notes: list[str] = field(default_factory=list)
    block_tsa: dict[str, list[np.ndarray]] = field(default_factory=dict)
    components: Components | None = None
    bearing_spectrum: xr.DataArray | None = None
    """Squared-envelope spectrum of the whole usable band (no band selection: the same
    definition for every run), which the bearings' isolation evidence compares between the
    record and its baselines (:func:`geardyn.diagnosis.isolation.bearing_evidence`); None
    when ``envelope_spectrum`` is already of the whole band, or for a record streamed in
    segments."""

    def values(self, component: str, indicator: str) -> np.ndarray:
        """Block values of one indicator of one component (time order)."""
        t = self.table
        sel = t[(t["component"] == component) & (t["indicator"] == indicator)]
        return sel.sort_values("block")["value"].to_numpy(dtype=float)

    def summary(self) -> pd.DataFrame:
        """Median over blocks: one row per (component, kind, indicator)."""
        g = self.table.groupby(["component", "kind", "indicator"], sort=False)["value"]
        return g.median().reset_index()


# ---------------------------------------------------------------------------- resampling
def _uniform_time(time: np.ndarray) -> float | None:
    """Sample rate [Hz] if ``time`` is uniform (relative jitter < 1e-6), else None (checked
    stretch by stretch: no record-long difference array)."""
    if time.size < 2:
        return None
    mean = float(time[-1] - time[0]) / (time.size - 1)
    if not mean > 0:
        return None
    for a in range(0, time.size - 1, CHUNK):
        dt = np.diff(time[a : a + CHUNK + 1])
        if float(np.max(np.abs(dt - mean))) > 1e-6 * mean:
            return None
    return 1.0 / mean


def _diff_extremes(a: np.ndarray) -> tuple[float, float]:
    """(min, max) of ``np.diff(a)``, stretch by stretch."""
    lo, hi = math.inf, -math.inf
    for i in range(0, a.size - 1, CHUNK):
        d = np.diff(a[i : i + CHUNK + 1])
        lo, hi = min(lo, float(d.min())), max(hi, float(d.max()))
    return lo, hi


def _auto_samples_per_rev(density: float) -> int:
    """Power of two at or above ``density`` (grid samples per reference revolution: the
    channel's samples per revolution for an angle-sampled channel, :data:`GRID_FACTOR` times
    its samples per revolution at the slowest speed for a time-sampled one), within
    [64, 16384]."""
    return int(min(16384, max(64, 2 ** math.ceil(math.log2(max(0.999 * density, 1.0))))))


def _signal(name: str, value: Any, min_len: int) -> np.ndarray:
    """A 1-D finite float signal; float32 is kept as it is (converted stretch by stretch where
    it is used), other types become float64."""
    a = np.asarray(value)
    if a.dtype not in (np.float32, np.float64):
        return array1d(name, value, min_len)
    if a.ndim != 1:
        raise InputError(f"{name}: signal must be 1-D, got shape {a.shape}")
    if a.size < min_len:
        raise InputError(f"{name}: signal needs at least {min_len} samples, got {a.size}")
    for i in range(0, a.size, CHUNK):
        if not np.all(np.isfinite(a[i : i + CHUNK])):
            raise InputError(f"{name}: signal contains NaN or infinite values")
    return a


def _reference_signal(x: np.ndarray, time: np.ndarray, angle: np.ndarray, spr: int) -> AngleSignal:
    """An angle-sampled channel interpolated linearly onto the reference grid."""
    dth = TWO_PI / spr
    k0, k1 = int(np.ceil(angle[0] / dth)), int(np.floor(angle[-1] / dth))
    if k1 - k0 < 4:
        raise InputError("ref_angle: the record spans fewer than 4 angular samples")
    grid = dth * np.arange(k0, k1 + 1)
    return AngleSignal(np.interp(grid, angle, x), spr, float(grid[0]), np.interp(grid, angle, time))


# ---------------------------------------------------------------------------- indicators
def _safe(fn: Callable[[], float]) -> float:
    try:
        v = float(fn())
    except (InputError, ZeroDivisionError, FloatingPointError):
        return math.nan
    return v if np.isfinite(v) else math.nan


def _gear_indicators(
    t: np.ndarray,
    teeth: tuple[int, ...],
    hist_res: list[np.ndarray],
    hist_tsa: list[np.ndarray],
    regular: frozenset[int] = frozenset(),
    regular_sidebands: bool = True,
) -> tuple[dict[str, float], np.ndarray]:
    """Shaft/gear TSA indicators of one block (Zakrajsek, Townsend & Decker 1993); returns the
    indicators and the residual (history for NA4 of later blocks). ``regular``: orders counted
    as regular meshing besides the mesh harmonics (the planet-pass orders of a ring, the
    combination tones of a shaft with several meshes), with their ±1 sidebands removed from
    the difference signal if ``regular_sidebands``."""
    if regular:
        return _gear_indicators_orders(t, teeth, hist_res, hist_tsa, regular, regular_sidebands)
    if teeth:
        d = difference_signal(t, teeth)
        r = residual_signal(t, teeth)
        out = {
            "FM0": _safe(lambda: fm0(t, teeth)),
            "FM4": _safe(lambda: fm4(d)),
            "NA4": _safe(lambda: na4(r, hist_res)),
            "NB4": _safe(lambda: nb4(t, teeth, hist_tsa)),
            "ER": _safe(lambda: energy_ratio(t, teeth)),
        }
    else:  # no mesh periodic in this angle: remove the mean and the shaft order only
        d = t - keep_orders(t, [0, 1])
        r = d
        out = {"NA4": _safe(lambda: na4(r, hist_res))}
    out["diff_rms"] = _safe(lambda: rms(d))
    out["diff_kurtosis"] = _safe(lambda: kurtosis(d))
    return out, r


def _gear_indicators_orders(
    t: np.ndarray,
    teeth: tuple[int, ...],
    hist_res: list[np.ndarray],
    hist_tsa: list[np.ndarray],
    regular: frozenset[int],
    regular_sidebands: bool = True,
) -> tuple[dict[str, float], np.ndarray]:
    """As :func:`_gear_indicators` with extra regular orders (same definitions, Zakrajsek et
    al. 1993: residual = TSA − regular − shaft order 1; difference = residual − first-order
    sidebands of the mesh harmonics, and of the extra orders if ``regular_sidebands``)."""
    n = t.size
    mesh = set(_mesh_order_set(n, teeth))
    reg = sorted(o for o in {*regular, *mesh} if 0 < o < n // 2)
    centres = reg if regular_sidebands else sorted(mesh)
    side = {o + j for o in centres for j in (-1, 1)}
    reg_sig = keep_orders(t, reg)
    r = t - keep_orders(t, [0, 1, *reg])
    d = t - keep_orders(t, sorted({0, 1, *reg, *side}))
    amp = np.abs(np.fft.rfft(t))[reg] * 2.0 / n
    out = {
        "FM0": _safe(lambda: (t.max() - t.min()) / float(amp.sum())),
        "FM4": _safe(lambda: fm4(d)),
        "NA4": _safe(lambda: na4(r, hist_res)),
        "NB4": _safe(lambda: nb4(t, teeth, hist_tsa)),
        "ER": _safe(lambda: rms(d) / rms(reg_sig)),
        "diff_rms": _safe(lambda: rms(d)),
        "diff_kurtosis": _safe(lambda: kurtosis(d)),
    }
    return out, r


def _mesh_order_set(n: int, teeth: tuple[int, ...]) -> list[int]:
    """Mesh harmonics ``k·Z`` of every tooth count below the Nyquist order of ``n`` samples."""
    return sorted({k * z for z in teeth for k in range(1, (n // 2) // z + 1) if k * z < n // 2})


def _combination_orders(teeth: tuple[int, ...], n: int) -> frozenset[int]:
    """Combination tones ``a·Z_i + b·Z_j`` (a, b ≠ 0, ``|a| + |b| ≤``
    :data:`COMBINATION_ORDER`) of every pair of meshes on one shaft, below the Nyquist order of
    ``n`` samples: the two meshes interact through the shaft and the non-linear contacts, so
    these orders are part of the healthy synchronous signal of a shaft carrying two wheels
    (e.g. 137 = 53 + 2·42, 409 = 11·42 − 53 on the seed 002 intermediate shaft)."""
    zs = sorted(set(teeth))
    if len(zs) < 2:
        return frozenset()
    m = COMBINATION_ORDER
    out: set[int] = set()
    for i, zi in enumerate(zs):
        for zj in zs[i + 1 :]:
            for a in range(-m, m + 1):
                for b in range(-m, m + 1):
                    if a and b and abs(a) + abs(b) <= m:
                        o = a * zi + b * zj
                        if 1 < o < n // 2:
                            out.add(o)
    return frozenset(out)


def _planet_pass_orders(comp: Component, comps: Components, n: int) -> frozenset[int]:
    """Regular orders of a ring seen from a fixed point: the mesh harmonics ``h·Z_r`` and the
    multiples of N within ±2N of them — the planet-pass modulation of N sequentially phased
    planets moves the ring mesh to multiples of N (seed 003 §4.1 dominant-sideband rule, e.g.
    81 and 84 for Z_r = 83, N = 3); a local ring fault spreads further."""
    st = next((s for s in comps.planetary if s.name == comp.stage), None)
    if comp.kind != "ring" or st is None or st.n_planets < 2:
        return frozenset()
    z, npl = st.ring_teeth, st.n_planets
    out: set[int] = set()
    for h in range(1, n // (2 * z) + 1):
        out.add(h * z)
        c = npl * round(h * z / npl)
        out.update(c + m * npl for m in range(-2, 3) if abs(c + m * npl - h * z) <= 2 * npl)
    return frozenset(out)


def _blocks(n_rev: int, n_blocks: int) -> tuple[int, int]:
    """(blocks, revolutions per block): ``n_blocks`` blocks if each gets at least
    :data:`MIN_REVS_PER_BLOCK` revolutions, else fewer (at least one block of every whole
    revolution): a TSA of one revolution rejects nothing that is not synchronous."""
    nb = max(1, min(n_blocks, n_rev // MIN_REVS_PER_BLOCK))
    return nb, n_rev // nb


def _tsa_array(t: np.ndarray, comp: Component, units: str, revs: int, how: str) -> xr.DataArray:
    n = t.size
    return xr.DataArray(
        t,
        coords={"angle": ("angle", np.arange(n) * 360.0 / n, {"units": "deg"})},
        dims="angle",
        name=comp.name,
        attrs={
            "units": units,
            "long_name": f"TSA of {comp.name}",
            "kind": comp.kind,
            "ratio": comp.ratio,
            "revolutions": revs,
            "method": how,
        },
    )


def _fast_multiple(n: int, multiple: int) -> int:
    """The smallest multiple of ``multiple`` at or above ``n`` (itself a multiple) whose FFT is
    fast (no prime factor above 11: a per-revolution FFT of a large prime length runs several
    times slower); ``n`` when ``multiple`` has such a factor itself (a ring of 83 teeth)."""
    from scipy.fft import next_fast_len

    rest = multiple
    for p in (2, 3, 5, 7, 11):
        while rest % p == 0:
            rest //= p
    if rest > 1:
        return n
    m = n
    while next_fast_len(m, real=True) != m:
        m += multiple
    return m


def _segment_revolutions(rpb: int, spr: int) -> int:
    """Revolutions per segment of a block of ``rpb`` (:func:`_long_reference_pass`): the
    fewest equal segments of at most :data:`SEGMENT_MAX` samples, shortened to a length whose
    FFT is fast."""
    from scipy.fft import next_fast_len

    nseg = max(1, math.ceil(rpb * spr / SEGMENT_MAX))
    r = max(1, rpb // nseg)
    while r > 1 and next_fast_len(r * spr, real=True) != r * spr:
        r -= 1
    return r


@dataclass
class _DomainStats:
    """Per-revolution spectrum statistics of one own-angle grid: revolutions from the grid's
    first sample (own-angle step ``k0``), ``nb`` blocks of ``rpb`` revolutions and all ``n_rev``
    whole revolutions."""

    spr: int
    k0: int
    n_rev: int
    nb: int
    rpb: int
    blocks: list[RevolutionStats]
    whole: RevolutionStats


def _revolution_stats(
    grid: AngleGrid | ArrayGrid,
    n_blocks: int,
    segment: tuple[int, Callable[[int, np.ndarray], None]] | None = None,
) -> _DomainStats:
    """:class:`_DomainStats` of ``grid``, computed in revolution batches of at most
    :data:`~geardyn.signal.stream.CHUNK` samples. ``segment = (revolutions, fn)``: each block's
    first ``rpb // revolutions`` segments of that many revolutions are also passed to
    ``fn(block, samples)``."""
    spr = grid.samples_per_rev
    n_rev = grid.size // spr
    if n_rev < 1:
        return _DomainStats(spr, grid.k0, 0, 0, 0, [], RevolutionStats())
    nb, rpb = _blocks(n_rev, n_blocks)
    per = max(1, CHUNK // spr)
    blocks = [RevolutionStats() for _ in range(nb)]
    whole = RevolutionStats()

    def feed(acc: RevolutionStats, r0: int, r1: int, x: np.ndarray | None = None) -> None:
        for a in range(r0, r1, per):
            b = min(r1, a + per)
            part = (grid.samples(a * spr, b * spr) if x is None
                    else x[(a - r0) * spr : (b - r0) * spr])
            acc.add_spectra(revolution_spectra(part, spr))

    for b in range(nb):
        start = b * rpb
        if segment is not None:
            seg_revs, fn = segment
            nseg = rpb // seg_revs
            for k in range(nseg):
                r0 = start + k * seg_revs
                x = grid.samples(r0 * spr, (r0 + seg_revs) * spr)
                fn(b, x)
                feed(blocks[b], r0, r0 + seg_revs, x)
            start += nseg * seg_revs
        feed(blocks[b], start, (b + 1) * rpb)
        whole.merge(blocks[b])
    rest = RevolutionStats()
    feed(rest, nb * rpb, n_rev)
    whole.merge(rest)
    return _DomainStats(spr, grid.k0, n_rev, nb, rpb, blocks, whole)


@dataclass
class _Ctx:
    ref: AngleGrid | ArrayGrid
    n_blocks: int
    channel: str
    units: str
    rows: list[dict[str, Any]]
    tsas: dict[str, xr.DataArray]
    notes: list[str]
    source: tuple[np.ndarray, float, float, np.ndarray] | None = None
    """(x, fs [Hz], t0 [s], reference angle [rad]) of a uniformly time-sampled channel: own
    angles are resampled from it directly (else from the reference grid)."""
    grids: dict[tuple[float, int], AngleGrid | ArrayGrid] = field(default_factory=dict)
    stats_cache: dict[float, _DomainStats] = field(default_factory=dict)
    blocks: dict[str, list[np.ndarray]] = field(default_factory=dict)

    def grid(self, abs_ratio: float, multiple: int = 2) -> AngleGrid | ArrayGrid:
        """Grid of the own angle ``abs_ratio·θ_ref`` with an integer number of samples per own
        revolution (a multiple of ``multiple``, same angular density as the reference)."""
        spr_ref = self.ref.samples_per_rev
        spr = max(multiple, int(math.ceil(spr_ref / abs_ratio / multiple)) * multiple)
        spr = _fast_multiple(max(spr, 8 * multiple if multiple < 8 else multiple), multiple)
        if abs(abs_ratio - 1.0) < 1e-12 and spr == spr_ref:
            return self.ref
        key = (round(abs_ratio, 12), spr)
        if key not in self.grids:
            if self.source is not None:
                x, fs, t0, th = self.source
                self.grids[key] = AngleGrid(x, fs, th, spr, t0=t0, ratio=abs_ratio)
            else:
                sig = self.ref.sig
                self.grids[key] = ArrayGrid(
                    resample_to_angle(sig.x, float(spr_ref), abs_ratio * sig.angle,
                                      samples_per_rev=spr)
                )
        return self.grids[key]

    def own(self, abs_ratio: float, multiple: int = 2) -> tuple[np.ndarray, int, int]:
        """(whole own revolutions from the first grid sample, samples per revolution,
        own-angle step of the first sample)."""
        g = self.grid(abs_ratio, multiple)
        spr = g.samples_per_rev
        n = (g.size // spr) * spr
        return (g.samples(0, n) if n else np.empty(0)), spr, g.k0

    def stats(self, abs_ratio: float) -> _DomainStats:
        key = round(abs_ratio, 12)
        if key not in self.stats_cache:
            self.stats_cache[key] = _revolution_stats(self.grid(abs_ratio), self.n_blocks)
        return self.stats_cache[key]

    def add(self, comp: Component, values: dict[str, float], block: int) -> None:
        for name, v in values.items():
            self.rows.append(
                {
                    "component": comp.name,
                    "kind": comp.kind,
                    "indicator": name,
                    "value": float(v),
                    "block": block,
                    "channel": self.channel,
                }
            )


def _own_angle_component(
    ctx: _Ctx, comp: Component, wheel_mode: bool, comps: Components | None = None
) -> None:
    """TSA in the component's own angle, per block: gear indicators (shafts, sun/planet/ring
    without a ring sensor) or per-wheel sideband indicators (wheels)."""
    st = ctx.stats(comp.abs_ratio)
    spr, k0, n_rev = st.spr, st.k0, st.n_rev
    if n_rev < 1:
        ctx.notes.append(
            f"{comp.name}: less than one revolution of its own angle (|ratio| "
            f"{comp.abs_ratio:.4g}) in the record; left out"
        )
        return
    hist_res: list[np.ndarray] = []
    hist_tsa: list[np.ndarray] = []
    for b in range(st.nb):
        seg = st.blocks[b]
        # wheels: plain TSA (their sideband ratios would be unstable near 0 after shrinkage)
        t = np.roll(seg.tsa(spr) if wheel_mode else _synchronous_tsa(seg, spr), k0)
        if wheel_mode:
            teeth = int(comp.teeth or comp.mesh_orders[0])
            vals = _safe_dict(
                lambda t=t, z=teeth: wheel_indicators(
                    t, z, comp.other_orders, WHEEL_SIDEBANDS, list(hist_tsa)
                ),
                ("SER", "sideband_kurtosis", "NB4"),
            )
        else:
            ring = _planet_pass_orders(comp, comps, spr) if comps is not None else frozenset()
            extra = ring or _combination_orders(comp.mesh_orders, spr)
            side = bool(ring)
            vals, r = _gear_indicators(t, comp.mesh_orders, hist_res, hist_tsa, extra, side)
            vals.update(_synchronous_energies(seg, spr, comp.mesh_orders, extra, side))
            hist_res.append(r)
        hist_tsa.append(t)
        ctx.blocks.setdefault(comp.name, []).append(t)
        ctx.add(comp, vals, b)
    if comp.name not in ctx.tsas:
        whole = np.roll(st.whole.tsa(spr), k0)
        ctx.tsas[comp.name] = _tsa_array(whole, comp, ctx.units, n_rev, "own-angle TSA")


def _synchronous_tsa(seg: RevolutionStats, spr: int) -> np.ndarray:
    """TSA of whole revolutions (their spectra's statistics ``seg``) with each order shrunk by
    its synchronous fraction ``max(0, 1 − V/(N|X̄|²))`` (Wiener weighting with the
    revolution-to-revolution variance ``V`` of Braun 1975): orders whose level in the average
    is mostly non-synchronous leakage (another component's fault or meshing over a few
    revolutions) are attenuated, synchronous ones kept."""
    n = seg.n
    if n < 2:
        return seg.tsa(spr)
    mean, var = seg.mean, seg.var
    p = np.abs(mean) ** 2
    gain = np.where(p > 0, np.clip(1.0 - var / (n * np.where(p > 0, p, 1.0)), 0.0, 1.0), 0.0)
    return np.fft.irfft(mean * gain, spr)


def _synchronous_energies(
    seg: RevolutionStats,
    spr: int,
    teeth: tuple[int, ...],
    regular: frozenset[int],
    regular_sidebands: bool = True,
) -> dict[str, float]:
    """ER and RMS of the difference signal from unbiased synchronous powers (Braun 1975;
    :func:`geardyn.signal.indicators.synchronous_energy_ratio`): with few revolutions per
    block the TSA keeps ``1/N`` of the non-synchronous power (other components' faults,
    noise), which would otherwise raise ER and the difference RMS of every component."""
    if seg.n < 2:
        return {}
    p, se = synchronous_stats_from_moments(seg.mean, seg.var, seg.n, spr)
    if not teeth and not regular:
        return {"diff_rms": float(np.sqrt(0.5 * max(float(p[2:].sum()), 0.0)))}
    try:
        er, drms = energy_ratio_from_power(
            p, se, spr, teeth, sorted(regular), regular_sidebands=regular_sidebands
        )
    except InputError:
        return {}
    return {"ER": er, "diff_rms": drms}


def _nanmean(values: list[float]) -> float:
    """Mean of the finite values, NaN if there is none (no warning)."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    return float(v.mean()) if v.size else math.nan


def _safe_dict(fn: Callable[[], dict[str, float]], keys: tuple[str, ...]) -> dict[str, float]:
    try:
        return {k: (float(v) if np.isfinite(v) else math.nan) for k, v in fn().items()}
    except InputError:
        return dict.fromkeys(keys, math.nan)


def _planetary_components(
    ctx: _Ctx, comps: Components, stage_name: str, sensor_angle: float
) -> set[str]:
    """Planet-separated TSA (McFadden window technique) of each planet of a fixed-ring stage
    seen by a ring accelerometer. Returns the components handled."""
    st = next((s for s in comps.planetary if s.name == stage_name), None)
    if st is None or not st.ring_fixed:
        ctx.notes.append(
            f"ring sensor: stage {stage_name!r} not found or its ring turns; own-angle TSA used"
        )
        return set()
    zr, n = st.ring_teeth, st.n_planets
    xs, spc, k0 = ctx.own(abs(st.ring_ratio), zr)
    n_rev = xs.size // spc
    if n_rev < 1:
        ctx.notes.append(f"stage {st.name}: less than one carrier revolution; left out")
        return set()
    # Planet n sits at θ_c + ψ_n (the model's planet positions) and faces a ring sensor at
    # frame angle φ when θ_c − θ_r = φ − ψ_n (geardyn.sensors.channels.ring_sensor_windows).
    # In u = |r|·θ_ref the passage is at u = φ − ψ_n, or at −φ + ψ_n if θ_c − θ_r decreases
    # as θ_ref grows; planetary_tsa centres planet n's windows at s0 + psi[n].
    psi_model = np.asarray(st.planet_angles, dtype=float)
    if st.ring_ratio < 0:  # u = θ_c − θ_r
        s0, psi = sensor_angle, np.mod(-psi_model, TWO_PI)
    else:  # u = −(θ_c − θ_r)
        s0, psi = -sensor_angle, np.mod(psi_model, TWO_PI)
    handled: set[str] = set()
    # Planets only: the sun meets every planet, so its fault needs no planet separation, and
    # its own angle relative to the carrier turns Z_r/Z_s times per carrier revolution — its
    # own-angle TSA averages that many more revolutions than the planet windows collect
    # (measured on a seed 004 sun crack, 10 carrier revolutions: z = 142 on ER own-angle,
    # 2.3–7.7 planet-window).
    members = [c for c in comps.items if c.stage == st.name and c.kind == "planet"]
    nb, rpb = _blocks(n_rev, ctx.n_blocks)

    used: dict[str, int] = {}

    def windowed(seg: np.ndarray, teeth: int, planet: int, start: int) -> np.ndarray | None:
        """Planet-window TSA of ``seg`` (whose first sample is ``start`` samples after the
        first of ``xs``): the sensor angle is shifted to the segment's own-angle origin and
        the result rolled so that index 0 is mesh count 0 (carrier angle 0). Window widths
        Z_r/(2N), Z_r/(4N) and 2 ring-mesh periods are tried in turn (the widest averages the
        most pieces per tooth; narrower ones when it leaves a tooth uncovered); none spans
        more than half a planet-pass lobe, so the windows stay away from the lobe edges where
        the neighbouring planets take over."""
        offset = k0 + start  # own-angle step of the segment's first sample
        sensor = s0 - TWO_PI * (offset % spc) / spc
        for wt in dict.fromkeys((max(2, zr // (2 * n)), max(2, zr // (4 * n)), 2)):
            try:
                t = planetary_tsa(seg, spc, zr, teeth, n, planet, psi, sensor, wt, detrend=2)
            except InputError:
                continue
            used["window_teeth"] = wt
            return np.roll(t, offset % t.size)
        return None

    for comp in members:
        teeth = int(comp.teeth or comp.mesh_orders[0])
        if teeth != st.planet_ring_teeth:
            continue  # sun-side wheel of a stepped planet: not in the ring-mesh count frame
        planets = [int(comp.planet or 0)]
        hist_res: dict[int, list[np.ndarray]] = {p: [] for p in planets}
        hist_tsa: dict[int, list[np.ndarray]] = {p: [] for p in planets}
        ok = True
        for b in range(nb):
            seg = xs[b * rpb * spc : (b + 1) * rpb * spc]
            per_planet = []
            for p in planets:
                t = windowed(seg, teeth, p, b * rpb * spc)
                if t is None:
                    ok = False
                    break
                vals, r = _gear_indicators(t, (teeth,), hist_res[p], hist_tsa[p])
                hist_res[p].append(r)
                hist_tsa[p].append(t)
                if p == planets[0]:
                    ctx.blocks.setdefault(comp.name, []).append(t)
                per_planet.append(vals)
            if not ok:
                break
            keys = per_planet[0].keys()
            ctx.add(comp, {k: _nanmean([v[k] for v in per_planet]) for k in keys}, b)
        if not ok:
            ctx.rows[:] = [r for r in ctx.rows if r["component"] != comp.name]
            ctx.blocks.pop(comp.name, None)
            ctx.notes.append(
                f"{comp.name}: too few carrier revolutions per block for the planet windows to "
                "cover every tooth; own-angle TSA used"
            )
            continue
        whole = windowed(xs[: n_rev * spc], teeth, planets[0], 0)
        if whole is not None:
            ctx.tsas[comp.name] = _tsa_array(
                whole,
                comp,
                ctx.units,
                n_rev,
                f"planet-window TSA (planet {planets[0]}, windows of "
                f"{used.get('window_teeth', 0)} ring-mesh periods)",
            )
        handled.add(comp.name)
    return handled


# ---------------------------------------------------------------------------- bearings
def _line_ratio(ses: np.ndarray, res: float, order: float) -> float:
    """Peak of a squared-envelope spectrum within ±max(2 bins, 2 %) of ``order`` over the
    median in ±max(20 bins, 20 %) (orders; ``res`` = bin width)."""
    tol = max(2.0 * res, 0.02 * order)
    wide = max(20.0 * res, 0.2 * order)
    i0, i1 = int(np.floor((order - tol) / res)), int(np.ceil((order + tol) / res))
    j0, j1 = int(np.floor((order - wide) / res)), int(np.ceil((order + wide) / res))
    if i0 < 1 or j1 >= ses.size:
        return math.nan
    peak = float(np.max(ses[i0 : i1 + 1]))
    level = float(np.median(ses[max(1, j0) : j1 + 1]))
    return peak / level if level > 0 else math.nan


def _ses_function(band: tuple[float, float] | None) -> Callable[..., xr.DataArray]:
    """Squared-envelope spectrum of a band from the band's own Fourier bins
    (:func:`geardyn.signal.envelope.band_squared_envelope_spectrum`: the same values without
    the record-long complex FFTs), of the full band by the analytic signal otherwise."""
    return envelope_spectrum if band is None else band_squared_envelope_spectrum


def _whole(ref: AngleGrid | ArrayGrid) -> np.ndarray:
    """The whole revolutions of a grid held whole (:class:`ArrayGrid`) from its first sample
    (for spectra that need no phase reference: order and envelope spectra)."""
    spr = ref.samples_per_rev
    return ref.samples(0, (ref.size // spr) * spr) if ref.size >= spr else ref.samples(0, 0)


def _line_ratios(ctx: _Ctx, comps: Components, values: np.ndarray, res: float, b: int) -> None:
    for comp in comps.bearings:
        vals = {}
        for line in BEARING_LINES:
            o = float(comp.fault_orders.get(line, math.nan))
            if not np.isfinite(o) or o <= 0:
                continue
            ratios = [_line_ratio(values, res, h * o) for h in BEARING_HARMONICS]
            ratios = [r for r in ratios if np.isfinite(r)]
            vals[line] = float(np.mean(ratios)) if ratios else math.nan
        ctx.add(comp, vals, b)


def _envelope_attrs(whole: xr.DataArray, units: str) -> xr.DataArray:
    whole = whole.rename(frequency="order")
    whole["order"].attrs["units"] = "events/rev"
    whole.attrs["units"] = f"({units})^2" if units else ""
    return whole


def _bearing_features(
    ctx: _Ctx, comps: Components, band: tuple[float, float] | None
) -> xr.DataArray | None:
    x = _whole(ctx.ref)
    spr = ctx.ref.samples_per_rev
    n_rev = x.size // spr
    if n_rev < 1:
        return None
    ses = _ses_function(band)
    whole = _envelope_attrs(ses(x, float(spr), band), ctx.units)
    if not comps.bearings:
        return whole
    nb, rpb = _blocks(n_rev, ctx.n_blocks)
    for b in range(nb):
        seg = x[b * rpb * spr : (b + 1) * rpb * spr]
        try:
            values = ses(seg, float(spr), band).values
        except InputError:
            continue
        _line_ratios(ctx, comps, values, 1.0 / rpb, b)
    return whole


def _long_reference_pass(
    ctx: _Ctx, comps: Components, band: tuple[float, float] | None
) -> xr.DataArray | None:
    """Squared-envelope spectra and the reference angle's synchronous statistics of a
    reference grid longer than :data:`SEGMENT_MAX` samples, in one pass over it. Each block is
    cut into segments of equal whole revolutions (the fewest with at most :data:`SEGMENT_MAX`
    samples each, shortened to a fast FFT length); a block's squared-envelope spectrum is the
    RMS over its segments' (Welch 1967 averaging: resolution ``1/segment revolutions``
    instead of ``1/block revolutions``; the peak-over-median line ratios then rest on averaged
    bins), the record's the RMS over all segments'. Fills ``ctx.stats_cache`` for the
    reference angle (ratio 1)."""
    ref = ctx.ref
    spr = ref.samples_per_rev
    n_rev = ref.size // spr
    nb, rpb = _blocks(n_rev, ctx.n_blocks)
    seg_revs = _segment_revolutions(rpb, spr)
    ses = _ses_function(band)
    acc: dict[str, Any] = {"ses": None, "n": 0, "blocks": [[None, 0] for _ in range(nb)]}

    def segment(b: int, x: np.ndarray) -> None:
        try:
            e = ses(x, float(spr), band)
        except InputError:
            return
        v = e.values**2
        acc["ses"] = (e, v) if acc["ses"] is None else (acc["ses"][0], acc["ses"][1] + v)
        acc["n"] += 1
        blk = acc["blocks"][b]
        blk[0] = v if blk[0] is None else blk[0] + v
        blk[1] += 1

    st = _revolution_stats(ref, ctx.n_blocks, (seg_revs, segment))
    if ctx.grid(1.0) is ref:
        ctx.stats_cache[round(1.0, 12)] = st
    env = None
    if acc["ses"] is not None:
        e, v = acc["ses"]
        env = _envelope_attrs(e.copy(data=np.sqrt(v / acc["n"])), ctx.units)
        env.attrs.update({"segments": acc["n"], "segment_revolutions": seg_revs})
    for b, (v, n) in enumerate(acc["blocks"]):
        if v is not None and comps.bearings:
            _line_ratios(ctx, comps, np.sqrt(v / n), 1.0 / seg_revs, b)
    return env


def _kurtogram_span(ref: AngleGrid | ArrayGrid, spr: int) -> np.ndarray:
    """The whole revolutions at the centre of the record on which the kurtogram is estimated:
    all of them up to :data:`KURTOGRAM_MAX_SAMPLES` samples, else the central
    ``KURTOGRAM_MAX_SAMPLES // spr`` revolutions. The kurtogram only chooses the envelope band
    of a record at a steady operating point; its estimate in a band of level ``k`` rests on
    ``N·2^−k`` samples (standard deviation ≈ ``2/√(N·2^−k)`` for Gaussian noise, Antoni
    2007), so 2²² samples keep it below 0.09 on every band at least one order wide at 16384
    samples/rev (level ≤ 13) and give Antoni's 128 samples per band at level 15."""
    n_rev = ref.size // spr
    keep = max(1, KURTOGRAM_MAX_SAMPLES // spr)
    if n_rev <= keep:
        return _whole(ref)
    start = (n_rev - keep) // 2
    return ref.samples(start * spr, (start + keep) * spr)


def _spectrum_and_band(
    ref: AngleGrid | ArrayGrid,
    units: str,
    envelope_band: tuple[float, float] | None,
    notes: list[str],
) -> tuple[xr.DataArray | None, xr.DataArray | None, tuple[float, float] | None]:
    """Order spectrum of the reference-angle signal (of the central revolutions of
    :func:`_kurtogram_span` for a grid streamed segment by segment, :func:`_long_reference_pass`:
    a display of a steady record, resolution ``1/revolutions`` of that span), kurtogram and
    envelope band (orders):
    ``envelope_band`` if given, else the band of maximum spectral kurtosis below the
    anti-aliasing limit of the resampling (Antoni 2007), estimated on the central
    revolutions of the record (:func:`_kurtogram_span`)."""
    spr = ref.samples_per_rev
    spec = None
    span = _whole(ref) if isinstance(ref, ArrayGrid) else _kurtogram_span(ref, spr)
    if span.size >= spr:
        spec = order_spectrum(span, spr).rename("amplitude")
        spec.attrs["units"] = units
        if not isinstance(ref, ArrayGrid):
            spec.attrs["revolutions"] = span.size // spr
    if envelope_band is not None:
        lo, hi = (float(v) for v in envelope_band)
        if not 0 < lo < hi < spr / 2:
            raise InputError(
                f"envelope_band: need 0 < lo < hi < {spr / 2:g} orders (Nyquist of the "
                f"reference grid), got ({lo:g}, {hi:g})"
            )
        return spec, None, (lo, hi)
    try:
        top = min(float(ref.max_valid_order), 0.5 * spr)
        kg = fast_kurtogram(span if not isinstance(ref, ArrayGrid) else
                            _kurtogram_span(ref, spr), float(spr), unit="events/rev", fmax=top)
    except InputError as exc:
        notes.append(f"kurtogram: {exc}; envelope of the full band")
        return spec, None, None
    lo, hi = kg.attrs.pop("band")
    kg.attrs["band_lo"], kg.attrs["band_hi"] = float(lo), float(hi)
    return spec, kg, (float(lo), float(hi))


# ---------------------------------------------------------------------------- public API
def extract_features(
    x: np.ndarray,
    time: np.ndarray,
    ref_angle: np.ndarray,
    components: Components,
    *,
    channel: str = "",
    units: str = "",
    n_blocks: int = 4,
    samples_per_rev: int | None = None,
    envelope_band: tuple[float, float] | None = None,
    ring_stage: str | None = None,
    sensor_angle: float = 0.0,
    planet_windows: bool = False,
) -> Features:
    """Indicators per component of one channel (see the module docstring).

    ``x``: channel samples (1-D, units ``units``); ``time`` [s] of each sample (need not be
    uniform: angle-sampled channels such as encoder IAS are interpolated in angle);
    ``ref_angle`` [rad]: the reference shaft's angle at each sample (monotonic; a decreasing
    angle, a shaft turning backwards, is negated). ``components``: from
    :func:`~geardyn.diagnosis.components.machine_components` (reference = the shaft of
    ``ref_angle``). ``n_blocks``: blocks of whole own revolutions per component.
    ``samples_per_rev``: of the reference grid (default: the power of two at or above
    :data:`GRID_FACTOR` times the channel's samples per revolution at the slowest speed for a
    time-sampled channel, at or above its samples per revolution for an angle-sampled one).
    ``envelope_band``: (lo, hi) in reference orders (default: kurtogram).
    ``ring_stage``: planetary stage whose fixed ring carries this accelerometer;
    ``sensor_angle`` [rad]: the sensor's angle in the frame — planet n, at ``θ_c + ψ_n``,
    faces it when ``θ_c − θ_r = sensor_angle − ψ_n``
    (:func:`geardyn.sensors.channels.ring_sensor_windows`). ``planet_windows``: give each
    planet of that stage its own planet-window TSA (McFadden) instead of the common
    own-angle TSA. Off by default: on the seed 004 simulations (ring accelerometer, 10
    carrier revolutions) the windows see a sun or ring crack on every planet (z-scores 7–71
    against a healthy baseline) and a planet-1 crack most on planet 2 (z 166 vs 14), through
    the coupled planet forces, while the own-angle TSA keeps sun and ring faults off the
    planets (|z| ≤ 2) and flags a planet crack on the planets (z 21, all alike).
    """
    if not isinstance(components, Components):
        raise InputError(
            f"components: expected the result of machine_components(), got "
            f"{type(components).__name__}"
        )
    xs = _signal("x", x, 16)
    t = array1d("time", time, xs.size, "sample times [s]")
    th = array1d("ref_angle", ref_angle, xs.size, "reference angle [rad]")
    if t.size != xs.size or th.size != xs.size:
        raise InputError(
            f"time/ref_angle: need one value per sample of x ({xs.size}), got "
            f"{t.size} and {th.size}"
        )
    nb = positive_int("n_blocks", n_blocks, "number of blocks")
    if not _diff_extremes(t)[0] > 0:
        raise InputError("time: sample times must increase strictly")
    d_min, d_max = _diff_extremes(th)
    if d_max < 0:
        th = -th
        d_min = -d_max
    elif not d_min > 0:
        raise InputError(
            "ref_angle: the reference angle must be strictly monotonic (the shaft stops or "
            "reverses in the record; crop it)"
        )
    revs = (th[-1] - th[0]) / TWO_PI
    if revs < 1.0:
        raise InputError(f"ref_angle: the record spans {revs:.3g} reference revolutions; needs ≥ 1")
    fs = _uniform_time(t)
    if samples_per_rev is not None:
        spr = positive_int("samples_per_rev", samples_per_rev, "samples per revolution", 8)
    elif fs is not None:  # channel samples per revolution at the slowest speed
        spr = _auto_samples_per_rev(GRID_FACTOR * TWO_PI / d_min)
    else:
        spr = _auto_samples_per_rev(xs.size / max(revs, 1e-12))
    duration = float(t[-1] - t[0])
    mean_rpm = 60.0 * revs / duration if duration > 0 else math.nan
    source = None
    if fs is not None:
        source = (xs, fs, float(t[0]), th)
        grid = AngleGrid(xs, fs, th, spr, t0=float(t[0]))
        ref: AngleGrid | ArrayGrid = (
            grid if grid.size > SEGMENT_MAX + spr else ArrayGrid(grid.signal())
        )
    else:
        ref = ArrayGrid(_reference_signal(np.asarray(xs, dtype=float), t, th, spr))
    ctx = _Ctx(ref, nb, channel, units, [], {}, [], source=source)

    spec, kg, band = _spectrum_and_band(ref, units, envelope_band, ctx.notes)
    full = None
    if isinstance(ref, ArrayGrid):
        env = _bearing_features(ctx, components, band)
        if components.bearings and band is not None and env is not None:
            full = _envelope_attrs(
                envelope_spectrum(_whole(ref), float(ref.samples_per_rev), None), units)
    else:
        env = _long_reference_pass(ctx, components, band)

    handled: set[str] = set()
    if ring_stage is not None and planet_windows:
        stage = ring_stage or (components.planetary[0].name if components.planetary else "")
        handled = _planetary_components(ctx, components, stage, sensor_angle)
    for comp in components.items:
        if comp.kind == "bearing" or comp.name in handled:
            continue
        _own_angle_component(ctx, comp, comp.kind == "wheel", components)

    markers = _markers(components, mean_rpm)
    table = pd.DataFrame(ctx.rows, columns=COLUMNS)
    return Features(
        table=table,
        tsa=ctx.tsas,
        block_tsa=ctx.blocks,
        order_spectrum=spec,
        envelope_spectrum=env,
        bearing_spectrum=full,
        band=None if band is None else (float(band[0]), float(band[1])),
        kurtogram=kg,
        markers=markers,
        channel=channel,
        units=units,
        reference=components.reference,
        samples_per_rev=spr,
        revolutions=float(revs),
        mean_rpm=float(mean_rpm),
        notes=ctx.notes,
        components=components,
    )


def _markers(components: Components, mean_rpm: float) -> pd.DataFrame | None:
    """Spectral markers at the mean reference speed (orders do not depend on it)."""
    if components.analysis is None or not np.isfinite(mean_rpm) or mean_rpm <= 0:
        return None
    from geardyn.kinematics.frequencies import characteristic_frequencies
    from geardyn.signal.annotate import spectral_markers

    ref = components.reference
    inputs = (
        {
            k: float(v) * mean_rpm / float(components.input_speeds[ref])
            for k, v in components.input_speeds.items()
        }
        if components.input_speeds
        else {ref: mean_rpm}
    )
    try:
        freqs = characteristic_frequencies(components.analysis, inputs, order_reference=ref)
        return spectral_markers(freqs)
    except (InputError, KeyError, ZeroDivisionError):
        return None


_RING = re.compile(r"ring of stage '([^']*)'")


def _reference_angle(
    ds: xr.Dataset, comps: Components, reference: str, time: np.ndarray
) -> tuple[np.ndarray, np.ndarray, str]:
    """Reference angle at ``time``: from a tacho channel on a shaft of the mechanism (pulse
    angles ``k·2π/R`` through :func:`geardyn.signal.angle_from_pulses`, divided by the shaft's
    ratio), else from the result's ``angle`` of the reference shaft. Returns (mask of ``time``
    inside the source span — a slice of the increasing ``time`` —, angle [rad] on those
    samples, source description)."""
    from geardyn import results
    from geardyn.signal.resample import angle_from_pulses

    tachos = []
    for name in results.channels(ds):
        ch = results.channel(ds, name)
        r = comps.ratios.get(ch.shaft, 0.0)
        if ch.kind == "tacho" and r != 0.0 and ch.values.size >= 3:
            tachos.append((ch.shaft != reference, ch, r))
    if tachos:
        _, ch, r = sorted(tachos, key=lambda z: z[0])[0]
        tp = np.asarray(ch.values, float)
        mask = _inside(time, tp[0], tp[-1])
        ang = angle_from_pulses(tp, time[mask], ch.pulses_per_rev or 1)
        ang /= abs(r)
        return mask, ang, f"tacho '{ch.name}' on '{ch.shaft}'"
    shaft_names = results.shafts(ds)
    src = reference if reference in shaft_names else None
    if src is None:
        src = next((s for s in shaft_names if comps.ratios.get(s, 0.0) != 0.0), None)
    if src is None:
        raise InputError(
            f"reference: no shaft of the result ({', '.join(shaft_names)}) turns with "
            f"'{reference}'; give reference= one of the mechanism's links"
        )
    ts, th = results.shaft_angle(ds, src)
    mask = _inside(time, ts[0], ts[-1])
    ang = np.interp(time[mask], ts, th)
    ang /= comps.ratios[src]
    return mask, ang, f"result angle of '{src}'"


def _inside(time: np.ndarray, lo: float, hi: float) -> slice:
    """The samples of increasing ``time`` within [lo, hi] (a slice: views, not copies)."""
    return slice(int(np.searchsorted(time, lo, side="left")),
                 int(np.searchsorted(time, hi, side="right")))


def features_from_result(
    ds: xr.Dataset,
    cfg: Mechanism,
    channel: str,
    reference: str | None = None,
    skip_s: float = 0.0,
    n_blocks: int = 4,
    planet_windows: bool = False,
) -> Features:
    """:func:`extract_features` of a sensor channel of a simulation result (docs/results.md).

    ``reference``: reference link (default: the channel's shaft, else the result's
    ``reference_shaft``). The reference angle comes from a tacho channel if the result has one
    on a turning link, else from the result's ``angle`` of the reference shaft interpolated at
    the channel's sample times. ``skip_s`` [s] of start transient are dropped. A ring
    accelerometer (``location`` "ring of stage 'X'") gets planet-window TSA for that stage if
    ``planet_windows`` (``sensor_angle_deg`` attr, default 0).
    """
    from geardyn import results

    ch = results.channel(ds, channel)
    if ch.sampling == "events":
        raise InputError(
            f"channel: '{ch.name}' holds pulse times ({ch.kind}), not a signal to diagnose; "
            f"choose one of {', '.join(results.channels(ds))} that is an accelerometer or encoder"
        )
    ref = reference or ch.shaft or str(ds.attrs.get("reference_shaft", ""))
    if not ref:
        raise InputError("reference: not given and the channel names no shaft")
    comps = machine_components(cfg, ref)
    skip = float(skip_s)
    if not np.isfinite(skip) or skip < 0:
        raise InputError(f"skip_s: must be a finite number ≥ 0 [s], got {skip_s!r}")
    time = np.asarray(ch.time, float)
    x = np.asarray(ch.values)  # float32 stays float32 (converted stretch by stretch)
    if x.dtype not in (np.float32, np.float64):
        x = x.astype(float)
    if not _diff_extremes(time)[0] > 0:
        raise InputError(f"time: the sample times of '{ch.name}' must increase strictly")
    keep = int(np.searchsorted(time, time[0] + skip, side="left"))
    if time.size - keep < 16:
        raise InputError(
            f"skip_s: dropping {skip:g} s leaves {time.size - keep} samples of '{ch.name}' "
            f"(record {time[0]:g}–{time[-1]:g} s)"
        )
    time, x = time[keep:], x[keep:]
    mask, ang, _src = _reference_angle(ds, comps, ref, time)
    loc = str(ch.attrs.get("location", ""))
    m = _RING.search(loc)
    ring_stage = m.group(1) if (m and ch.kind == "accelerometer") else None
    sensor = math.radians(float(ch.attrs.get("sensor_angle_deg", 0.0)))
    return extract_features(
        x[mask],
        time[mask],
        ang,
        comps,
        channel=ch.name,
        units=ch.units,
        n_blocks=n_blocks,
        ring_stage=ring_stage,
        sensor_angle=sensor,
        planet_windows=planet_windows,
    )


# ---------------------------------------------------------------------------- baseline reference
def _on_grid(ref: np.ndarray, n: int) -> np.ndarray:
    """A one-revolution signal on ``n`` samples (periodic Fourier resampling if sizes differ)."""
    r = np.asarray(ref, dtype=float)
    if r.size == n:
        return r
    from scipy.signal import resample

    return resample(r, n)


def reference_tsa(features: list[Features]) -> dict[str, np.ndarray]:
    """Mean whole-record TSA per component over healthy records (on the grid of the first
    record that has the component)."""
    out: dict[str, list[np.ndarray]] = {}
    for f in features:
        for name, da in f.tsa.items():
            grid = out.setdefault(name, [])
            n = grid[0].size if grid else da.size
            grid.append(_on_grid(da.values, n))
    return {k: np.mean(v, axis=0) for k, v in out.items()}


def reference_block_tsa(features: list[Features]) -> dict[str, list[np.ndarray]]:
    """Mean TSA per component and block index over healthy records (blocks present in every
    record that has the component)."""
    out: dict[str, list[list[np.ndarray]]] = {}
    for f in features:
        for name, blocks in f.block_tsa.items():
            acc = out.setdefault(name, [])
            for b, t in enumerate(blocks):
                if b == len(acc):
                    acc.append([])
                n = acc[b][0].size if acc[b] else t.size
                acc[b].append(_on_grid(t, n))
    return {k: [np.mean(v, axis=0) for v in blocks] for k, blocks in out.items()}


def reference_residuals(
    features: Features,
    reference: dict[str, np.ndarray | xr.DataArray],
    block_reference: dict[str, list[np.ndarray]] | None = None,
) -> pd.DataFrame:
    """Indicators of the difference between each block's TSA and a healthy reference TSA of
    the same component (rows in :data:`COLUMNS` layout).

    A synchronous average subtracted from a healthy reference average leaves the fault's own
    signature and the averaging noise — the healthy meshing, combination tones and structural
    responses cancel however strong they are (the reference-residual idea of Wang & Wong 2002,
    "Autoregressive model-based gear fault diagnosis", J. Vib. Acoust. 124, with the
    reference taken as a healthy average; NA4's use of baseline statistics, Decker 2002,
    NASA TM-2002-211491). Both TSAs share the own-angle origin (reference angle origin × ratio),
    so records must use the same angle origin (a tacho, or simulated angles from 0).

    ``block_reference`` (:func:`reference_block_tsa`): per-block references, used where they
    exist. When the records start from the same state and speed law (simulations), block
    ``b`` of every record covers the same angles of **every** shaft, so the deterministic
    non-synchronous content that a short average keeps (other shafts' meshes at non-integer
    orders) cancels as well, and the residual is the fault plus measurement noise.

    Detection, not localisation: any change of the machine's dynamics leaves a residual in
    every component's average. Measured on simulations: a seed 004 sun crack (ring
    accelerometer) raises RR_kurtosis from 3.0–3.4 to 15–400 on every shaft, planet and the
    sun; a seed 002 crack on the 42-tooth wheel raises it to 19.9 on its shaft but also to
    6.4 on the 53-tooth wheel sharing it and 4.4 on the output shaft. Use it to say *that*
    the machine changed; the per-component indicators of :func:`extract_features` say where.

    Indicators: ``RR_kurtosis`` (normalised kurtosis of the residual: 3 for Gaussian noise)
    and ``RR_rms`` (RMS of the residual over the RMS of the reference with its mean removed).
    Wheels: the residual restricted to the wheel's mesh harmonics and unambiguous sidebands
    (:func:`geardyn.signal.indicators.wheel_sideband_orders`, all harmonics)."""
    from geardyn.signal.indicators import wheel_sideband_orders

    comps = {c.name: c for c in features.components.items} if features.components else {}
    rows = []
    for name, blocks in features.block_tsa.items():
        if name not in reference or name not in comps:
            continue
        comp = comps[name]
        ref_v = reference[name]
        ref_v = ref_v.values if isinstance(ref_v, xr.DataArray) else ref_v
        per_block = (block_reference or {}).get(name, [])
        for b, t in enumerate(blocks):
            r = _on_grid(per_block[b] if b < len(per_block) else ref_v, t.size)
            d = t - r
            d = d - d.mean()
            rr = r - r.mean()
            if comp.kind == "wheel" and comp.teeth:
                mesh, side = wheel_sideband_orders(
                    t.size, int(comp.teeth), comp.other_orders, WHEEL_SIDEBANDS
                )
                d, rr = keep_orders(d, [*mesh, *side]), keep_orders(rr, [*mesh, *side])
            vals = {
                "RR_kurtosis": _safe(lambda d=d: kurtosis(d)),
                "RR_rms": _safe(lambda d=d, rr=rr: rms(d) / rms(rr)),
            }
            for ind, v in vals.items():
                rows.append(
                    {
                        "component": name,
                        "kind": comp.kind,
                        "indicator": ind,
                        "value": v,
                        "block": b,
                        "channel": features.channel,
                    }
                )
    return pd.DataFrame(rows, columns=COLUMNS)


def with_reference_residuals(
    baselines: list[Features], record: Features | None = None
) -> tuple[list[Features], Features | None]:
    """Append the reference-residual indicators (:func:`reference_residuals`) to the tables of
    healthy ``baselines`` — each against the mean TSAs (whole record and per block) of the
    **other** baselines
    (leave-one-out, so that its own noise is not in its reference) — and of ``record`` against
    the mean of all baselines. Needs at least 2 baselines; returns new objects."""
    from dataclasses import replace

    if len(baselines) < 2:
        raise InputError(
            f"baselines: reference residuals need at least 2 healthy records (leave-one-out), "
            f"got {len(baselines)}"
        )
    out = []
    for i, f in enumerate(baselines):
        others = [g for j, g in enumerate(baselines) if j != i]
        rr = reference_residuals(f, reference_tsa(others), reference_block_tsa(others))
        out.append(replace(f, table=pd.concat([f.table, rr], ignore_index=True)))
    rec = None
    if record is not None:
        rr = reference_residuals(record, reference_tsa(baselines), reference_block_tsa(baselines))
        rec = replace(record, table=pd.concat([record.table, rr], ignore_index=True))
    return out, rec


__all__ = [
    "COLUMNS",
    "Features",
    "extract_features",
    "features_from_result",
    "reference_block_tsa",
    "reference_residuals",
    "reference_tsa",
    "with_reference_residuals",
]
