"""Fault isolation evidence: whose signature explains the change from the healthy baseline.

Detection indicators (:mod:`geardyn.diagnosis.features`) rise on many components when any
fault changes the machine: a crack's impulses, averaged over a few revolutions of another
member, still raise its TSA statistics, and a bearing's impacts raise every envelope line that
happens to sit near one of their harmonics. Isolation asks a sharper question per component:
is the change **periodic with this component's own fault period**? The answer is a statistic
per signal domain, judged against its own null sample from the healthy baseline members
(:func:`evidence_from_null`); :mod:`geardyn.diagnosis.localise` weighs them into a location.

* Rotating members (shafts, sun, ring, planets, wheels): the record is cut into its whole own
  revolutions (difference signal: every mesh harmonic of the member removed, Zakrajsek et al.
  1993). The **coherent synchronous deviation ratio** (:func:`coherent_sdr`) is, per order,
  the one-way analysis-of-variance F statistic of the record's mean revolution against the
  baselines' (Braun 1975; McFadden 1987), averaged over the orders: content that repeats with
  the member keeps its power in the mean, content at other periods behaves like noise across
  revolutions, and each order is judged against its own spread. For a wheel on a shaft
  shared with other wheels, the transmission error of its own mesh (``cSDR_TE``) tells them
  apart; planets are told apart by their planet-separated rows (``cSDR_planet``,
  :mod:`geardyn.diagnosis.planets`). The whole-band ratio :func:`synchronous_deviation_ratio`
  is kept for reference.
* Bearings: the **fault-band energy share** of each defect line in the squared-envelope
  spectrum (:func:`band_energy_share`, MathWorks ``faultBandMetrics``' band power); the
  increase shares of :func:`line_family_shares` (Randall & Antoni 2011 read the same comb by
  eye) are kept as a diagnostic.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from geardyn.errors import InputError
from geardyn.signal._checks import positive_int
from geardyn.signal.tsa import difference_signal

#: SDR at or below this is never isolation evidence: without a synchronous change SDR ≈ 1
#: (an F statistic); a component's change must be at least twice the non-synchronous spread.
#: Measured leak of a fault into another member's domain over a few revolutions: ≤ 1.13
#: (seed 004, sun crack seen in the carrier domain, 2 carrier revolutions).
SDR_FLOOR = 2.0


def revolution_blocks(x: np.ndarray, samples_per_rev: int) -> np.ndarray:
    """Whole revolutions of an own-angle signal as rows (n_rev × samples_per_rev)."""
    spr = positive_int("samples_per_rev", samples_per_rev, "samples per revolution", minimum=4)
    a = np.asarray(x, float)
    n = a.size // spr
    if n < 2:
        raise InputError(f"x: needs at least 2 whole revolutions ({2 * spr} samples) for a "
                         f"synchronous deviation ratio, got {a.size}")
    return a[: n * spr].reshape(n, spr)


def difference_blocks(blocks: np.ndarray, teeth: Sequence[int] | int,
                      regular: Iterable[int] = ()) -> np.ndarray:
    """Difference signal (Zakrajsek et al. 1993: mean, shaft order 1, every mesh harmonic of
    ``teeth`` and their first sidebands removed; ``regular`` orders removed too) of each
    revolution."""
    out = np.array([difference_signal(b, teeth) for b in blocks])
    extra = sorted({int(o) for o in regular if 0 < int(o) < blocks.shape[1] // 2 + 1})
    if extra:
        spec = np.fft.rfft(out, axis=1)
        spec[:, extra] = 0.0
        out = np.fft.irfft(spec, blocks.shape[1], axis=1)
    return out


def keep_orders_blocks(blocks: np.ndarray, orders: Iterable[int]) -> np.ndarray:
    """Rows reduced to the given orders (per revolution)."""
    spec = np.fft.rfft(blocks, axis=1)
    mask = np.zeros(spec.shape[1], bool)
    for o in orders:
        if 0 <= int(o) < mask.size:
            mask[int(o)] = True
    return np.fft.irfft(spec * mask, blocks.shape[1], axis=1)


def synchronous_deviation_ratio(record: np.ndarray, reference: np.ndarray) -> float:
    """SDR of the revolutions ``record`` (n_rev × spr) against the healthy mean revolution
    ``reference`` (spr,): F statistic of the revolutions' deviations (module docstring).
    Returns 0 for a record identical to the reference."""
    r = np.asarray(record, float)
    if r.ndim != 2 or r.shape[0] < 2:
        raise InputError("record: needs at least 2 revolutions (rows)")
    ref = np.asarray(reference, float)
    if ref.shape != r.shape[1:]:
        raise InputError(f"reference: {ref.shape} samples, the record's revolutions have "
                         f"{r.shape[1]}")
    d = r - ref
    n = d.shape[0]
    dm = d.mean(axis=0)
    num = float(np.mean(dm * dm))
    den = float(np.sum((d - dm) ** 2) / (n * (n - 1)) / d.shape[1])
    if den <= 0.0:
        return 0.0 if num <= 0.0 else float("inf")
    return num / den


@dataclass(frozen=True)
class LineShare:
    """Share of the envelope-spectrum increase explained by one bearing line family."""

    bearing: str
    line: str
    order: float
    share: float
    harmonics: int
    concentration: float = 0.0
    """share / fraction of the spectrum's bins the comb covers: 1 for an increase spread evenly
    (a dense comb such as the cage line's matches much by chance), ≫ 1 for the line's own comb."""


def line_family_shares(orders: np.ndarray, record: np.ndarray, baselines: Sequence[np.ndarray],
                       lines: dict[tuple[str, str], float], order_max: float | None = None,
                       ) -> list[LineShare]:
    """Shares of ``Σ Δ²`` at every harmonic of each line (``lines``: (bearing, line) → order
    of the reference) with ``Δ = max(0, record − mean(baselines))`` on the common ``orders``
    grid (module docstring). Each harmonic's comb tooth spans ±1 bin."""
    o = np.asarray(orders, float)
    s = np.asarray(record, float)
    base = np.mean([np.asarray(b, float) for b in baselines], axis=0)
    if base.shape != s.shape or o.shape != s.shape:
        raise InputError("envelope spectra: the record and the baselines need one order grid")
    top = float(o[-1]) if order_max is None else min(float(order_max), float(o[-1]))
    delta = np.clip(s - base, 0.0, None)
    delta[o > top] = 0.0
    total = float(np.sum(delta**2))
    step = float(o[1] - o[0])
    out = []
    for (bearing, line), f in lines.items():
        if not np.isfinite(f) or f <= 2 * step:
            out.append(LineShare(bearing, line, float(f), 0.0, 0))
            continue
        comb = comb_mask(o, f, top)  # ±1 bin around every harmonic (leakage, slip)
        n = int(top / f)
        share = float(np.sum(delta[comb] ** 2)) / total if total > 0 else 0.0
        coverage = float(comb.sum()) / max(int(np.sum(o <= top)), 1)
        out.append(LineShare(bearing, line, float(f), share, n,
                             share / coverage if coverage > 0 else 0.0))
    return out


# ---- evidence from a result -------------------------------------------------------------

#: Kinds judged by the synchronous deviation ratio (their own angle is a rotation).
ROTATING = ("shaft", "wheel", "sun", "ring", "planet")


@dataclass
class _RawStats:
    """Per-revolution spectrum statistics of a domain before its band is known."""

    acc: object  # geardyn.signal.stream.RevolutionStats
    spr: int
    removed: list[int]

    @property
    def n(self) -> int:
        return int(self.acc.n)

    def order_stats(self, top: int | None) -> OrderStats:
        """:func:`order_stats` of the difference rows (the removed orders empty)."""
        mean = self.acc.mean / self.spr
        var = self.acc.var / self.spr**2
        idx = [o for o in self.removed if 0 <= o < mean.size]
        mean[idx] = 0.0
        var[idx] = 0.0
        if top is not None:
            k = max(int(top), 1) + 1
            mean, var = mean[:k], var[:k]
        return OrderStats(mean, var, self.n)


@dataclass
class IsolationBlocks:
    """Difference signal of every whole own revolution, per own-angle domain of one record.

    ``domains``: key → (n_rev × samples_per_rev) array; ``of``: component → domain key
    (components with the same own angle and mesh orders share a domain: the planets of a
    stage, the wheels of a shaft with the shaft itself); ``of_te``: wheel → domain key of the
    transmission error of its own mesh (``transmission_error`` channels), which tells apart the
    wheels of one shaft."""

    domains: dict[str, np.ndarray]
    of: dict[str, str]
    of_te: dict[str, str] = field(default_factory=dict)
    of_planet: dict[str, str] = field(default_factory=dict)
    """planet → domain key of its planet-separated rows (McFadden 1994 windows at a ring
    sensor, :mod:`geardyn.diagnosis.planets`)."""
    top: dict[str, int] = field(default_factory=dict)
    """domain key → highest own order compared (the orders inside the channel band that every
    own-angle domain of the channel covers, :func:`isolation_blocks`); all orders when absent."""
    ambiguous: dict[str, np.ndarray] = field(default_factory=dict)
    """domain key → orders 0…top left out of the comparison because a harmonic of another
    turning member falls inside their resolution (:func:`ambiguous_orders`)."""
    run: object = None
    """The dynamic run this record was measured on (baseline ensemble members measured on one
    run share it: a leave-one-out null leaves the whole run out)."""
    stats: dict[str, OrderStats] = field(default_factory=dict)
    """Per-order statistics of domains whose rows were dropped (:meth:`compact`)."""

    def compact(self) -> IsolationBlocks:
        """A copy holding the per-order statistics of every own-angle and TE domain instead
        of their revolutions (all the evidence needs; a few per cent of the size), the
        planet-separated rows kept (their statistics depend on the rows shared by every
        record)."""
        keep = set(self.of_planet.values())
        stats = {**self.stats, **{k: order_stats(v, self.top.get(k))
                                  for k, v in self.domains.items()
                                  if k not in keep and v.shape[0] >= 2}}
        return replace(self, domains={k: v for k, v in self.domains.items() if k in keep},
                       stats=stats)


#: Samples per stretch of the record-long checks and interpolations.
_STRETCH = 1 << 20


def _uniform(x: np.ndarray, time: np.ndarray) -> tuple[np.ndarray, float, float]:
    """Samples on a uniform time grid (angle-sampled channels are interpolated)."""
    fs = (time.size - 1) / (time[-1] - time[0])
    uniform = True
    for a in range(0, time.size - 1, _STRETCH):
        dt = np.diff(time[a:a + _STRETCH + 1])
        if np.max(np.abs(dt * fs - 1.0)) >= 1e-6:
            uniform = False
            break
    if uniform:
        return x, fs, float(time[0])
    tu = time[0] + np.arange(int(np.floor((time[-1] - time[0]) * fs)) + 1) / fs
    return np.interp(tu, time, np.asarray(x, dtype=float)), fs, float(time[0])


def _on_uniform_grid(t0: float, fs: float, n: int, time: np.ndarray, values: np.ndarray
                     ) -> np.ndarray:
    """``np.interp(t0 + arange(n)/fs, time, values)`` stretch by stretch; ``values`` itself
    when the grid is ``time`` to 1e-9 of a sample interval (a uniformly sampled channel: the
    interpolation would move the values by less than their change over 1e-9 of a sample)."""
    if time.size == n:
        same = True
        for a in range(0, n, _STRETCH):
            tu = t0 + np.arange(a, min(n, a + _STRETCH)) / fs
            if np.max(np.abs(tu - time[a:a + _STRETCH])) > 1e-9 / fs:
                same = False
                break
        if same:
            return values
    out = np.empty(n)
    for a in range(0, n, _STRETCH):
        b = min(n, a + _STRETCH)
        out[a:b] = np.interp(t0 + np.arange(a, b) / fs, time, values)
    return out


def _gradient_extremes(a: np.ndarray) -> tuple[float, float]:
    """(min, max) of ``np.gradient(a)`` stretch by stretch."""
    if a.size < 2:
        raise InputError("angle: needs at least 2 samples")
    lo = min(float(a[1] - a[0]), float(a[-1] - a[-2]))
    hi = max(float(a[1] - a[0]), float(a[-1] - a[-2]))
    for s in range(1, a.size - 1, _STRETCH):
        e = min(a.size - 1, s + _STRETCH)
        g = (a[s + 1:e + 1] - a[s - 1:e - 1]) / 2.0
        lo, hi = min(lo, float(g.min())), max(hi, float(g.max()))
    return lo, hi


class _Domains:
    """Own-angle revolution blocks of one channel (uniform in time, reference angle known)."""

    def __init__(self, ds, comps, ref: str, channel: str, skip_s: float,  # noqa: ANN001
                 max_spr: int) -> None:
        from geardyn import results
        from geardyn.diagnosis.features import _reference_angle

        ch = results.channel(ds, channel)
        if ch.sampling == "events":
            raise InputError(f"channel: '{ch.name}' holds pulse times, not a signal")
        time = np.asarray(ch.time, float)
        x = np.asarray(ch.values)  # float32 stays float32 (converted stretch by stretch)
        if x.dtype not in (np.float32, np.float64):
            x = x.astype(float)
        keep = int(np.searchsorted(time, time[0] + float(skip_s), side="left"))
        time, x = time[keep:], x[keep:]
        mask, ang, _ = _reference_angle(ds, comps, ref, time)
        x, time = x[mask], time[mask]
        if ang[-1] < ang[0]:  # the sign of the mean increment
            np.negative(ang, out=ang)
        self.x, self.fs, self.t0 = _uniform(x, time)
        self.angle = _on_uniform_grid(self.t0, self.fs, self.x.size, time, ang)
        del ang
        g_min, g_max = _gradient_extremes(self.angle)
        self.rate = float(g_max * self.fs / (2 * np.pi))
        self.rate_min = float(max(g_min * self.fs / (2 * np.pi), 1e-300))
        self.max_spr = max_spr

    @property
    def band_hz(self) -> float:
        """Usable band of the channel [Hz]: ``fs/2.56`` (the anti-aliasing rule of
        :func:`geardyn.signal.resample.resample_to_angle`)."""
        return self.fs / 2.56

    def blocks(self, abs_ratio: float, teeth: Sequence[int], rows: bool = True
               ) -> tuple[np.ndarray | _RawStats, float] | None:
        """Difference signal of each whole revolution of the own angle ``abs_ratio·θ_ref``
        and the band [Hz] its orders cover unattenuated at every speed of the record (None
        with fewer than 2 revolutions). Samples per revolution: the power of two at or above
        ``fs`` per slowest own revolution (no band is lost to the angle grid), at most
        ``max_spr``. ``rows=False``: instead of the rows, the statistics of their spectra
        (:class:`_RawStats`), accumulated revolution batch by batch
        (:class:`geardyn.signal.stream.AngleGrid`: no record-long array)."""
        from geardyn.signal.stream import AngleGrid, RevolutionStats, revolution_spectra
        from geardyn.signal.tsa import _mesh_orders

        spr = int(2 ** np.ceil(np.log2(max(self.fs / (self.rate_min * abs_ratio), 16.0))))
        spr = min(spr, self.max_spr)
        grid = AngleGrid(self.x, self.fs, self.angle, spr, t0=self.t0, ratio=abs_ratio)
        start = (-grid.k0) % spr
        n = (grid.size - start) // spr
        if n < 2:
            return None
        ok = [z for z in teeth if 0 < z < spr // 2 - 1]
        band = min(float(grid.max_valid_order) * self.rate * abs_ratio, self.band_hz,
                   0.5 * spr * self.rate_min * abs_ratio)
        if rows:
            b = revolution_blocks(grid.samples(start, start + n * spr), spr)
            return (difference_blocks(b, ok) if ok else b), band
        acc = RevolutionStats()
        per = max(1, _STRETCH // spr)
        for r in range(0, n, per):
            x = grid.samples(start + r * spr, start + min(n, r + per) * spr)
            acc.add_spectra(revolution_spectra(x, spr))
        removed: list[int] = []
        if ok:  # difference_signal: mean, shaft order 1, mesh harmonics and ±1 sidebands
            mesh = _mesh_orders(spr, ok, None)
            removed = sorted({0, 1, *mesh, *(m - 1 for m in mesh), *(m + 1 for m in mesh)})
        return _RawStats(acc, spr, removed), band


def isolation_blocks(ds, cfg, channel: str, reference: str | None = None,  # noqa: ANN001
                     skip_s: float = 0.0, max_samples_per_rev: int = 65536,
                     rows: bool = True) -> IsolationBlocks:
    """Per-revolution difference signals of ``channel`` of result ``ds`` in the own angle of
    every rotating component (kinematics of ``cfg``; reference angle as in
    :func:`geardyn.diagnosis.features.features_from_result`: a tacho, else the result's shaft
    angle), and of every ``transmission_error`` channel in the own angles of its pair's two
    wheels. Own angles start at the reference angle's origin, so revolution r of two runs of
    the same operating profile covers the same angles (the alignment :func:`sdr_evidence`
    uses). Components with fewer than 2 whole revolutions are left out.

    Every own-angle domain of the channel is compared over one band [Hz] (``top``: the
    orders below the narrowest domain band): a domain that reached higher would see there,
    partly coherent over a short record, the lines of another component that its own domain
    cannot see — evidence for the wrong component.

    ``rows=False``: the own-angle and TE domains are returned as their per-order statistics
    (``stats``, as :meth:`IsolationBlocks.compact` gives: all the evidence needs), accumulated
    revolution batch by batch without the record's rows in memory (a long record)."""
    from geardyn import results
    from geardyn.diagnosis.components import machine_components

    ch = results.channel(ds, channel)
    ref = reference or ch.shaft or str(ds.attrs.get("reference_shaft", ""))
    comps = machine_components(cfg, ref)
    main = _Domains(ds, comps, ref, channel, skip_s, max_samples_per_rev)
    out = IsolationBlocks({}, {})
    bands: dict[str, tuple[float, float]] = {}
    own: dict[str, float] = {}
    raw: dict[str, _RawStats] = {}
    for c in comps.items:
        if c.kind not in ROTATING or c.abs_ratio == 0.0:
            continue
        teeth = tuple(sorted({*c.mesh_orders, *c.other_orders}))
        key = f"{c.abs_ratio:.12g}|{teeth}"
        if key not in out.domains and key not in raw:
            b = main.blocks(c.abs_ratio, teeth, rows)
            if b is None:
                continue
            if rows:
                out.domains[key] = b[0]
            else:
                raw[key] = b[0]
            bands[key] = (b[1], main.rate * c.abs_ratio)
            own[key] = c.abs_ratio
        out.of[c.name] = key
    del main
    _common_band(out, bands)
    rates = member_rates(comps)
    cancelled = planet_array_masks(comps, out.of)
    for key, a in own.items():
        n_rev = out.domains[key].shape[0] if rows else raw[key].n
        out.ambiguous[key] = ambiguous_orders(a, rates, n_rev, out.top[key])
        if key in cancelled:
            out.ambiguous[key] |= ~cancelled[key](out.top[key])
        if not rows:
            out.stats[key] = raw.pop(key).order_stats(out.top.get(key))
    names = {c.name for c in comps.items}
    graph = comps.analysis.graph if comps.analysis is not None else None
    for te in results.channels(ds):
        tch = results.channel(ds, te)
        if tch.kind != "transmission_error" or graph is None:
            continue
        mesh = next((m for m in graph.meshes if m.name == tch.attrs.get("pair")), None)
        if mesh is None:
            continue
        dom = None
        for link, wheel, z in ((mesh.link_a, mesh.wheel_a, mesh.teeth_a),
                               (mesh.link_b, mesh.wheel_b, mesh.teeth_b)):
            w = wheel or f"{link}/z{z}"
            if w not in names:
                continue
            dom = dom or _Domains(ds, comps, ref, te, skip_s, max_samples_per_rev)
            c = comps[w]
            key = f"TE {mesh.name}|{c.abs_ratio:.12g}"
            # every mesh of the wheel's shaft: the TE also carries the shaft's other meshes
            b = dom.blocks(c.abs_ratio, tuple(sorted({z, *c.mesh_orders, *c.other_orders})),
                           rows)
            if b is not None:
                out.top[key] = int(np.floor(b[1] / (dom.rate * c.abs_ratio)))
                if rows:
                    out.domains[key] = b[0]
                else:
                    out.stats[key] = b[0].order_stats(out.top[key])
                out.ambiguous[key] = ambiguous_orders(
                    c.abs_ratio, member_rates(comps),
                    b[0].shape[0] if rows else b[0].n, out.top[key])
                out.of_te[w] = key
    for name, rows in _planet_rows(ds, cfg, channel, ref, skip_s).items():
        if rows.shape[0] >= 2:
            out.domains[f"planet {name}"] = rows
            out.of_planet[name] = f"planet {name}"
    return out


#: Bearing lines whose harmonics can fall on a gear's orders: the impact rates of a race or
#: rolling-element defect (BSF's harmonics include 2·BSF, a ball striking both races). The cage
#: line FTF is left out: it modulates the others rather than striking, and its dense harmonics
#: (FTF ≈ 0.4 of the shaft) would reach most orders of a short record.
AMBIGUOUS_BEARING_LINES = ("BPFO", "BPFI", "BSF")


def member_rates(comps) -> list[float]:  # noqa: ANN001 - a Components
    """Rates (events per reference revolution) of every member whose harmonics can reach
    another member's orders: the own rates of the turning members and the impact lines of the
    bearings (:data:`AMBIGUOUS_BEARING_LINES`)."""
    rates = {c.abs_ratio for c in comps.items if c.kind in ROTATING and c.abs_ratio > 0.0}
    for c in comps.bearings:
        rates |= {abs(float(f)) for line, f in c.fault_orders.items()
                  if line in AMBIGUOUS_BEARING_LINES and np.isfinite(f) and f != 0.0}
    return sorted(rates)


def ambiguous_orders(own_ratio: float, ratios: Iterable[float], revolutions: int, top: int
                     ) -> np.ndarray:
    """Orders 0…``top`` of the own-angle domain turning ``own_ratio`` times per reference
    revolution that a harmonic of another member (``ratios``, own revolutions per reference
    revolution) can reach through the synchronous average of ``revolutions`` revolutions:
    harmonic k of a member at ratio r sits at own order k·r/own_ratio, and the average passes it
    at order o with the gain of the Dirichlet kernel, whose main lobe spans |k·r/own_ratio − o|
    < 1/revolutions (McFadden 1987, the comb filter of the TSA). Such an order is evidence for
    either member, so it is left out of both members' comparison; the sidelobes pass such a
    line with a power gain below 1/(π·revolutions·δ)², far below the within-revolution
    variance it adds."""
    mask = np.zeros(int(top) + 1, bool)
    if revolutions < 1 or own_ratio <= 0:
        return mask
    width = 1.0 / revolutions
    for r in ratios:
        if r <= 0 or abs(r / own_ratio - 1.0) < 1e-9:
            continue
        rho = r / own_ratio
        pos = np.arange(1, int((top + 1) / rho) + 2) * rho
        near = np.rint(pos)
        hit = (np.abs(pos - near) < width) & (near >= 1) & (near <= top)
        mask[near[hit].astype(int)] = True
    return mask


def planet_array_gain(angles: Sequence[float], top: int) -> np.ndarray:
    """|Σ_n exp(−i·o·ψ_n)| / N for own orders o = 0…``top`` of a sun or ring (relative to
    its carrier) whose N planets sit at carrier angles ψ_n. A tooth of that member meets
    planet n at relative angle ψ_n (+ the tooth's own angle), so the part of its fault
    signature that repeats with the member — the average over the carrier's positions, what
    its synchronous average keeps — is Σ_n s(θ − ψ_n): the planets' copies of one pattern
    s, whose spectrum is S(o)·Σ_n exp(−i·o·ψ_n) (the sun's signature repeated at each planet,
    McFadden 1991). Equally spaced planets: 1 at multiples of N, 0 elsewhere."""
    psi = np.asarray(angles, float)
    if psi.size == 0:
        return np.ones(int(top) + 1)
    o = np.arange(int(top) + 1)
    return np.abs(np.exp(-1j * np.outer(o, psi)).sum(axis=1)) / psi.size


#: Planet-array gain below which an order is taken as cancelled (round-off of the sum of N
#: unit phasors in double precision is ~1e-15; no physical gain is that small but zero).
ARRAY_CANCELLED = 1e-9


def planet_array_masks(comps, of: Mapping[str, str]  # noqa: ANN001 - a Components
                       ) -> dict[str, Any]:
    """Domain key → function ``top`` → bool mask of the orders 0…top at which a tooth fault
    of the domain's member can appear (:func:`planet_array_gain` above
    :data:`ARRAY_CANCELLED`), for every own-angle domain that belongs only to the sun or
    the ring of one planetary stage (a domain shared with another component keeps every
    order: that component's faults are not bound to the planets). Orders where the planets'
    copies cancel carry only what leaks in from other members' faults and noise; they are
    left out of the member's comparison like the ambiguous orders."""
    byname = {c.name: c for c in comps.items}
    members: dict[str, list[str]] = {}
    for c, key in of.items():
        members.setdefault(key, []).append(c)
    out: dict[str, Any] = {}
    for st in getattr(comps, "planetary", None) or []:
        if st.n_planets < 2:
            continue
        angles = tuple(float(a) for a in st.planet_angles)
        for key, names in members.items():
            if all(n in byname and byname[n].kind in ("sun", "ring")
                   and byname[n].stage == st.name for n in names):
                out[key] = (lambda top, a=angles: planet_array_gain(a, top) > ARRAY_CANCELLED)
    return out


def _common_band(out: IsolationBlocks, bands: Mapping[str, tuple[float, float]]) -> None:
    """``out.top`` of every domain in ``bands`` (key → (band [Hz], fastest own rate [rev/s])):
    the orders below the narrowest band, so that every domain sees the same frequencies."""
    if not bands:
        return
    common = min(b for b, _ in bands.values())
    for key, (_, rate) in bands.items():
        out.top[key] = int(np.floor(common / rate))


def _planet_rows(ds, cfg, channel: str, reference: str, skip_s: float  # noqa: ANN001
                 ) -> dict[str, np.ndarray]:
    """Planet-separated rows of every planet seen by the channel (empty when the module or
    the geometry does not apply: not a ring sensor, ring turning, too few passes)."""
    try:
        from geardyn.diagnosis.planets import planet_domains
    except ImportError:
        return {}
    try:
        return planet_domains(ds, cfg, channel, reference=reference, skip_s=skip_s)
    except InputError:
        return {}


@dataclass(frozen=True)
class Evidence:
    """Isolation evidence of one component: a statistic of the record, the same statistic of
    every healthy baseline member (its null sample) and the bound a healthy record exceeds
    with probability ``alpha`` (:func:`evidence_from_null`).

    ``mean`` is the geometric mean of the null sample and ``std`` the standard deviation of
    its logarithm; ``z`` the record's standardised score ``(log value − μ)/(s·√(1 + 1/n))``
    and ``p`` its one-sided Student p-value; ``group``: components whose evidence comes from
    one signal domain (they cannot be told apart by it)."""

    component: str
    measure: str
    value: float
    mean: float
    std: float
    threshold: float
    z: float = float("nan")
    p: float = float("nan")
    n: int = 0
    group: str = ""
    null: tuple[float, ...] = ()
    power: float = math.nan
    """Planet-separated evidence: the deviation power over its healthy expectation
    (:func:`deviation_power`), compared between the planets of one set."""
    dof: float = math.nan
    """Degrees of freedom of ``power``."""
    scale: float = math.nan
    """Standard deviation of the prediction of a healthy record's log statistic (with the
    runs of the null sample: :func:`geardyn.diagnosis.baseline.prediction_spread`)."""
    df: float = math.nan
    """Degrees of freedom of ``scale``."""
    deviation: np.ndarray | None = field(default=None, repr=False, compare=False)
    """Planet-separated evidence: the record's deviation power per order against the
    baselines (:func:`deviation_orders`; NaN where an order carries no variance)."""
    null_deviation: tuple[np.ndarray, ...] = field(default=(), repr=False, compare=False)
    """The same for each baseline member against the others (leaving its run out)."""
    null_runs: tuple[object, ...] = field(default=(), repr=False, compare=False)
    """The dynamic run of each ``null_deviation`` member."""

    @property
    def passed(self) -> bool:
        return bool(np.isfinite(self.value) and np.isfinite(self.threshold)
                    and self.value > self.threshold)

    def bound(self, alpha: float) -> float:
        """The threshold of this evidence at another per-test level ``alpha`` (the same
        Student prediction bound as :func:`evidence_from_null`; NaN without a null)."""
        from scipy.stats import t as student

        if self.n < 2 or not np.isfinite(self.mean) or self.mean <= 0:
            return math.nan
        if np.isfinite(self.scale) and np.isfinite(self.df):
            scale, df = self.scale, self.df
        else:
            scale, df = max(self.std, LOG_SPREAD_FLOOR) * math.sqrt(1.0 + 1.0 / self.n), self.n - 1
        return _exp_bound(math.log(self.mean) + float(student.isf(alpha, df)) * scale)

    def passes_at(self, alpha: float) -> bool:
        """The record's value exceeds :meth:`bound` at ``alpha``."""
        b = self.bound(alpha)
        return bool(np.isfinite(self.value) and np.isfinite(b) and self.value > b)

    @property
    def margin(self) -> float:
        """``value / threshold`` (> 1 ⇔ the evidence passes at its false-alarm probability)."""
        return float(self.value / self.threshold) if self.threshold > 0 else float("nan")


#: Floor of the standard deviation of log(statistic) over the baseline members: a numerical
#: floor, not a tuning — below 1 % the members agree to within round-off of the statistics'
#: own estimators, and a smaller spread would make any change of a few per cent "evidence".
LOG_SPREAD_FLOOR = 0.01


def _exp_bound(log_bound: float) -> float:
    """exp of a log-scale bound; a bound beyond exp's range (a null of 2 values has 1 degree
    of freedom, and t_1 at a small α is huge) is no usable threshold: infinite."""
    return math.exp(log_bound) if log_bound < 700.0 else math.inf


def evidence_from_null(component: str, measure: str, value: float, null: Sequence[float],
                       alpha: float, group: str = "",
                       runs: Sequence[object] | None = None) -> Evidence:
    """Evidence of ``value`` against the null sample ``null`` (the statistic of each healthy
    baseline member), on the log scale (the statistics are positive ratios with right-skewed
    spread): with μ, s the mean and sample std (ddof = 1, floored at
    :data:`LOG_SPREAD_FLOOR`) of the n log values, the threshold is the one-sided Student
    prediction bound ``exp(μ + t_(n−1)(1 − α)·s·√(1 + 1/n))`` that a new healthy record
    exceeds with probability α (Hahn & Meeker 1991, ch. 4); ``z = (log value − μ)/(s·√(1 +
    1/n))`` is the record's standardised score and ``p = P(T_(n−1) > z)`` its one-sided
    p-value. The Student law sets the threshold (the false-alarm probability with an
    estimated spread); the localisation posterior compares the hypotheses of one record by
    their scores z on one footing (a Gaussian likelihood ratio: with few members the Student
    tails would make every large score look alike). Fewer than 2 null values: no threshold
    (NaN). ``runs``: the dynamic run of each null value — members measured on one run share
    its dynamics, and μ, the prediction spread and its degrees of freedom come from the
    random-effects model of :func:`geardyn.diagnosis.baseline.prediction_spread` (one value
    per run: the formulas above)."""
    from scipy.stats import t as student

    from geardyn.diagnosis.baseline import prediction_spread

    finite = [i for i, v in enumerate(null) if np.isfinite(v)]
    vals = np.asarray([null[i] for i in finite], float)
    tags = (None if runs is None or None in list(runs)
            else np.asarray([str(runs[i]) for i in finite]))
    tiny = np.finfo(float).tiny
    n = vals.size
    if n < 2 or not np.isfinite(value):
        return Evidence(component, measure, float(value), math.nan, math.nan, math.nan,
                        group=group, n=n, null=tuple(float(v) for v in vals))
    logs = np.log(np.maximum(vals, tiny))
    mu, sd, df = prediction_spread(logs, tags)
    s = max(float(np.std(logs, ddof=1)), LOG_SPREAD_FLOOR)
    scale = max(sd, LOG_SPREAD_FLOOR * math.sqrt(1.0 + 1.0 / n))
    threshold = _exp_bound(mu + float(student.isf(alpha, df)) * scale)
    z = (math.log(max(float(value), tiny)) - mu) / scale
    p = float(student.sf(z, df))
    return Evidence(component, measure, float(value), math.exp(mu), s, threshold, z=z, p=p,
                    n=n, group=group, null=tuple(float(v) for v in vals), scale=scale, df=df)


def family_floor(evidence: Sequence[Evidence], alpha: float) -> list[Evidence]:
    """``evidence`` (the tests of one statistic over several components or lines: a
    *family*) with every prediction ``scale`` raised to the family's median scale, the
    threshold, ``z`` and ``p`` following (:func:`evidence_from_null` with that scale). The
    isolation counterpart of :func:`geardyn.diagnosis.baseline.family_floor`: a null of a
    few runs that happen to cluster gets at least its family's typical spread; a scale is
    never lowered. Fewer than 3 tests with a scale: unchanged."""
    from scipy.stats import t as student

    scales = [e.scale for e in evidence if np.isfinite(e.scale) and e.scale > 0]
    if len(scales) < 3:
        return list(evidence)
    floor = float(np.median(scales))
    out = []
    for e in evidence:
        if not (np.isfinite(e.scale) and e.scale < floor and np.isfinite(e.df)
                and e.mean > 0 and np.isfinite(e.value)):
            out.append(e)
            continue
        mu = math.log(e.mean)
        z = (math.log(max(float(e.value), np.finfo(float).tiny)) - mu) / floor
        out.append(replace(e, scale=floor, z=z, p=float(student.sf(z, e.df)),
                           threshold=_exp_bound(mu + float(student.isf(alpha, e.df)) * floor)))
    return out


# ---- coherent (per-order) synchronous deviation -----------------------------------------

@dataclass(frozen=True)
class OrderStats:
    """Per-order synchronous statistics of one run's revolutions in one own-angle domain:
    ``mean`` the mean revolution's spectrum (complex, orders 0…spr/2, amplitude scaled by
    1/spr so that runs resampled with other samples per revolution compare), ``var`` the
    within-run variance of the revolutions' spectra (ddof = 1), ``n`` the revolutions. Small
    enough to store per sweep case, and all :func:`coherent_sdr` needs."""

    mean: np.ndarray
    var: np.ndarray
    n: int


def order_stats(rows: np.ndarray, top: int | None = None) -> OrderStats:
    """:class:`OrderStats` of revolutions ``rows`` (n_rev × samples_per_rev, n_rev ≥ 2), orders
    0…``top`` (all when None)."""
    r = np.asarray(rows, float)
    if r.ndim != 2 or r.shape[0] < 2:
        raise InputError("rows: needs at least 2 revolutions (rows) for per-order statistics")
    spec = np.fft.rfft(r, axis=1) / r.shape[1]
    if top is not None:
        spec = spec[:, :max(int(top), 1) + 1]
    m = spec.mean(axis=0)
    v = np.sum(np.abs(spec - m) ** 2, axis=0) / (r.shape[0] - 1)
    return OrderStats(m, v, int(r.shape[0]))


def coherent_sdr(record: OrderStats, baselines: Sequence[OrderStats]) -> float:
    """Coherent synchronous deviation ratio of ``record`` against ``baselines`` (one
    :class:`OrderStats` per healthy record of the same domain): per order o ≥ 1,

        F_o = |m_rec(o) − B(o)|² / ( σ_b²(o)·(1 + 1/M) + V_rec(o)/n_rec + V(o)·⟨1/n_j⟩/M ),

    with B the mean of the M baselines' mean spectra, V the pooled within-record variance of
    the baselines' revolutions, V_rec the record's own, ⟨1/n_j⟩ the baselines' mean inverse
    revolution count and σ_b² the between-record variance of the baselines' mean spectra
    beyond what their within-record variance explains, ``max(Σ_j |m_j − B|²/(M − 1) −
    V·⟨1/n_j⟩, 0)``: the one-way random-effects analysis of variance of the revolutions per
    order (Searle, Casella & McCulloch 1992, ch. 3; for TSA orders: Braun 1975, McFadden
    1987), with the record's mean judged by its own revolution-to-revolution spread (Welch
    1947: the two samples need not share a variance). The denominator is the variance of the
    difference between a new healthy record's mean spectrum and B, so an order that differs
    between healthy machines (mesh sidebands that move with speed and load, a transfer path)
    weighs no more than an order that repeats exactly. cSDR is the mean of F_o over the
    orders that carry variance (orders removed by the difference signal carry none). Without
    a synchronous change, E[F_o] ≈ 1 whatever the power of the order, so a strong line counts
    as one order among many, while a local fault, which repeats every revolution and spreads
    over many orders, raises them all.

    Why the record's own variance: a fault of *another* member adds to this domain content
    that does not repeat with it (lines between its orders). Averaged over n revolutions such
    a line keeps the fraction |D_n(δ)|² of its power in the mean (D_n the Dirichlet kernel,
    δ its distance to the nearest order) and puts the rest in the revolutions' spread. Judged
    against the healthy baselines' spread it would score ∝ its power — a strong fault
    elsewhere would look synchronous here; judged against the record's own spread its score
    is bounded by n·|D_n(δ)|²/(1 − |D_n(δ)|²) whatever its power. One baseline: σ_b² cannot
    be estimated and is 0 (the fixed-effects test). Orders beyond the shortest record's grid
    are left out."""
    terms = _coherent_terms(record, baselines)
    if terms is None:
        return math.nan
    num, den = terms
    return float(np.mean(num / den))


def deviation_power(record: OrderStats, baselines: Sequence[OrderStats]
                    ) -> tuple[float, float]:
    """Synchronous deviation power of ``record`` against ``baselines`` over its expectation
    for a healthy record, ``Σ_o |m_rec(o) − B(o)|² / Σ_o D(o)`` (the terms of
    :func:`coherent_sdr`, summed before dividing: the strong orders weigh by their power), and
    its degrees of freedom ``ν = 2(Σ D)²/Σ D²`` (Satterthwaite 1946: under no change the
    numerator is a D-weighted sum of χ²₂/2 terms, ≈ χ²_ν/ν times its mean). Two such ratios of
    one sensor's records compare as F(ν₁, ν₂) when neither holds a change — the test that
    names one planet of a set (:func:`geardyn.diagnosis.localise.localise`). NaN without
    usable orders."""
    terms = _coherent_terms(record, baselines)
    if terms is None:
        return math.nan, math.nan
    num, den = terms
    return float(np.sum(num) / np.sum(den)), float(2.0 * np.sum(den) ** 2 / np.sum(den**2))


def deviation_orders(record: OrderStats, baselines: Sequence[OrderStats]) -> np.ndarray:
    """The record's synchronous deviation power per order, ``|m_rec(o) − B(o)|²`` (the
    numerators of :func:`coherent_sdr`), on the common order grid, NaN where an order carries
    no variance (all NaN when none does)."""
    terms = _coherent_terms(record, baselines, masked=False)
    k = min([record.mean.size, *(b.mean.size for b in baselines)])
    if terms is None:
        return np.full(k, np.nan)
    num, den = terms
    return np.where(np.isfinite(den) & (den > 0), num, np.nan)


def _coherent_terms(record: OrderStats, baselines: Sequence[OrderStats], masked: bool = True
                    ) -> tuple[np.ndarray, np.ndarray] | None:
    """Numerators |m_rec − B|² and random-effects denominators of :func:`coherent_sdr` over
    the orders that carry variance (None when none does); ``masked=False``: every order, the
    denominator NaN where no variance."""
    if not baselines:
        raise InputError("baselines: the coherent SDR needs at least 1 healthy run")
    k = min([record.mean.size, *(b.mean.size for b in baselines)])
    nb = np.array([b.n for b in baselines], float)
    big_m = len(baselines)
    means = np.array([b.mean[:k] for b in baselines])
    b_mean = means.mean(axis=0)
    pooled = np.sum([(b.n - 1) * b.var[:k] for b in baselines], axis=0) / float(np.sum(nb - 1))
    own = record.var[:k]
    both = pooled + own
    top = float(np.max(both[1:])) if k > 1 else 0.0
    ok = np.zeros(k, bool)
    ok[1:] = both[1:] > 1e-12 * top
    if top <= 0.0 or not ok.any():
        return None
    inv_n = float(np.mean(1.0 / nb))
    between = np.zeros(k)
    if big_m > 1:
        spread = np.sum(np.abs(means - b_mean) ** 2, axis=0) / (big_m - 1)
        # round-off: members that differ only in sensor noise give equal means to ~1e-13
        spread[spread <= ROUND_OFF * np.abs(b_mean) ** 2] = 0.0
        between = np.maximum(spread - pooled * inv_n, 0.0)
    num = np.abs(record.mean[:k] - b_mean) ** 2
    # round-off: a deterministic simulation repeated with other sensor seeds gives mean
    # spectra equal to ~1e-13 of their amplitude; a difference below 1e-10 of it is none
    num[num <= ROUND_OFF * (np.abs(record.mean[:k]) ** 2 + np.abs(b_mean) ** 2)] = 0.0
    den = between * (1.0 + 1.0 / big_m) + own / record.n + pooled * inv_n / big_m
    if not masked:
        return num, np.where(ok, den, np.nan)
    return num[ok], den[ok]


#: Relative power below which two mean spectra are taken as equal (amplitude 1e-10: far
#: above the ~1e-13 round-off of resampling and FFTs in double precision, far below any
#: physical change).
ROUND_OFF = 1e-20


def coherent_evidence(component: str, measure: str, record: OrderStats,
                      baselines: Sequence[OrderStats], alpha: float, group: str = "",
                      runs: Sequence[object] | None = None) -> Evidence:
    """cSDR of the record and its null sample: each baseline member's cSDR against the
    others (leave-one-out — the member itself is never in its own reference, and the record
    is in none; with ``runs``, the members measured on the member's own dynamic run are left
    out too: a re-measured twin would make the null too small), then
    :func:`evidence_from_null`."""
    if len(baselines) < 2:
        raise InputError("baselines: the coherent SDR needs at least 2 healthy records "
                         "(leave-one-out null)")
    tag = list(runs) if runs is not None and None not in runs else list(range(len(baselines)))
    if len(set(tag)) < 2:
        tag = list(range(len(baselines)))
    null = [coherent_sdr(b, [o for j, o in enumerate(baselines) if tag[j] != tag[i]])
            for i, b in enumerate(baselines)]
    return evidence_from_null(component, measure, coherent_sdr(record, baselines), null,
                              alpha, group, runs=tag)


def domain_stats(blocks: IsolationBlocks) -> dict[str, OrderStats]:
    """:class:`OrderStats` of every domain of ``blocks`` with at least 2 revolutions."""
    out = dict(getattr(blocks, "stats", None) or {})
    out.update({k: order_stats(v, blocks.top.get(k)) for k, v in blocks.domains.items()
                if v.shape[0] >= 2})
    return out


def sdr_evidence(baselines: Sequence[IsolationBlocks], record: IsolationBlocks,
                 alpha: float, pool_family: bool = True) -> dict[str, Evidence]:
    """Coherent SDR evidence per rotating component (:func:`coherent_evidence`): ``cSDR`` in
    its own-angle domain; ``cSDR_TE`` on the transmission error of its own mesh, which
    replaces it for a wheel (the shaft's signal is shared by its wheels); ``cSDR_planet`` on
    the planet-separated rows of a planet (``record.of_planet``, every planet from the same
    number of rows), which also carries the planet's :func:`deviation_power` for naming one
    planet of the set. ``alpha``: false-alarm probability of each test; ``pool_family``:
    each statistic's scales floored at their median over the domains
    (:func:`family_floor`)."""
    base = [domain_stats(b) for b in baselines]
    runs = [getattr(b, "run", None) for b in baselines]
    rec = domain_stats(record)
    _equal_planet_rows(baselines, record, base, rec)
    for key, mask in record.ambiguous.items():  # the record's orders for every record
        for stats in (rec, *base):
            if key in stats:
                stats[key] = _without(stats[key], mask)
    cache: dict[str, Evidence] = {}
    out: dict[str, Evidence] = {}
    items = [(c, key, "cSDR") for c, key in record.of.items()]
    items += [(c, key, "cSDR_TE") for c, key in record.of_te.items()]
    items += [(c, key, "cSDR_planet") for c, key in record.of_planet.items()]
    for _comp, key, measure in items:
        if key not in rec or any(key not in b for b in base):
            continue
        if key not in cache:
            ref = [b[key] for b in base]
            cache[key] = coherent_evidence("", measure, rec[key], ref, alpha, group=key,
                                           runs=runs)
            if measure == "cSDR_planet":
                power, dof = deviation_power(rec[key], ref)
                cache[key] = replace(cache[key], power=power, dof=dof,
                                     **planet_deviation(rec[key], ref, runs))
    for measure in ("cSDR", "cSDR_TE", "cSDR_planet") if pool_family else ():
        keys = [k for _c, k, m_ in items if m_ == measure and k in cache]
        keys = list(dict.fromkeys(keys))
        for k, e in zip(keys, family_floor([cache[k] for k in keys], alpha), strict=True):
            cache[k] = e
    for comp, key, measure in items:
        if key not in cache:
            continue
        ev = cache[key]
        if measure == "cSDR_planet":
            out.setdefault(f"{comp}#planet", replace(ev, component=comp))
            continue
        out[comp] = replace(ev, component=comp)
    return out


def planet_deviation(record: OrderStats, baselines: Sequence[OrderStats],
                      runs: Sequence[object]) -> dict[str, Any]:
    """Per-order deviation of a planet's rows (:func:`deviation_orders`) for the record and,
    leaving each baseline member's run out, for each member: what
    :func:`geardyn.diagnosis.localise.name_planet` compares between planets."""
    tag = list(runs) if None not in runs and len(set(runs)) >= 2 else \
        list(range(len(baselines)))
    null = []
    for i, b in enumerate(baselines):
        others = [o for j, o in enumerate(baselines) if tag[j] != tag[i]]
        null.append(deviation_orders(b, others) if others else np.full(1, np.nan))
    return {"deviation": deviation_orders(record, baselines), "null_deviation": tuple(null),
            "null_runs": tuple(tag)}


def _without(st: OrderStats, mask: np.ndarray) -> OrderStats:
    """``st`` with the orders of ``mask`` emptied (no variance: :func:`coherent_sdr` skips
    them)."""
    k = min(st.mean.size, mask.size)
    mean, var = st.mean.copy(), st.var.copy()
    mean[:k][mask[:k]] = 0.0
    var[:k][mask[:k]] = 0.0
    return OrderStats(mean, var, st.n)


def _equal_planet_rows(baselines: Sequence[IsolationBlocks], record: IsolationBlocks,
                       base: list[dict[str, OrderStats]], rec: dict[str, OrderStats]) -> None:
    """Planet-separated statistics of every planet from the same number of rows (the first
    rows every record has for every planet): the noise part of the deviation power falls as
    1/rows, so planets compare only on equal rows."""
    keys = set(record.of_planet.values())
    if not keys:
        return
    blocks = [record, *baselines]
    n0 = min(b.domains[k].shape[0] for b in blocks for k in keys if k in b.domains)
    if n0 < 2:
        return
    for stats, b in zip([rec, *base], blocks, strict=True):
        for k in keys:
            if k in b.domains:
                stats[k] = order_stats(b.domains[k][:n0], b.top.get(k))


# ---- bearings: fault-band energy of the squared-envelope spectrum -----------------------

def comb_mask(orders: np.ndarray, line: float, top: float) -> np.ndarray:
    """Bins within ±1 bin of every harmonic ``k·line ≤ top`` of an order grid (leakage and
    slip of a bearing line)."""
    o = np.asarray(orders, float)
    step = float(o[1] - o[0])
    comb = np.zeros(o.size, bool)
    if not np.isfinite(line) or line <= 2 * step:
        return comb
    for k in range(1, int(top / line) + 1):
        i = int(round((k * line - o[0]) / step))
        comb[max(i - 1, 0):min(i + 2, o.size)] = True
    return comb


def band_energy_share(orders: np.ndarray, spectrum: np.ndarray, line: float,
                      order_max: float | None = None,
                      exclude: np.ndarray | None = None) -> float:
    """Fault-band energy share of a squared-envelope spectrum: ``Σ S²`` over the line's
    comb (:func:`comb_mask`) divided by ``Σ S²`` over the whole band up to ``order_max``
    (MathWorks ``faultBandMetrics``' total band power, as a fraction, so that a sensitivity
    or transfer-path gain cancels). ``exclude``: bins left out of the comb (another
    bearing's lines, :func:`bearing_line_shares`); NaN when no bin is left."""
    o = np.asarray(orders, float)
    s = np.asarray(spectrum, float)
    top = float(o[-1]) if order_max is None else min(float(order_max), float(o[-1]))
    inside = o <= top
    total = float(np.sum(s[inside] ** 2))
    comb = comb_mask(o, line, top) & inside
    if exclude is not None:
        comb &= ~np.asarray(exclude, bool)
    return float(np.sum(s[comb] ** 2)) / total if total > 0 and comb.any() else math.nan


def bearing_line_shares(orders: np.ndarray, spectrum: np.ndarray, bearings: Sequence,
                        order_max: float | None = None) -> dict[tuple[str, str], float]:
    """(bearing, line) → fault-band energy share (:func:`band_energy_share`) of every line of
    every bearing (``Component`` s with ``fault_orders``) in one squared-envelope spectrum,
    each comb without the bins of the other bearings' impact lines
    (:data:`AMBIGUOUS_BEARING_LINES`): a harmonic of another bearing's line within ±1 bin of
    this one's is evidence for either, and a spalled bearing's strong comb would otherwise
    raise every other bearing's share wherever their harmonics meet (the bearings' analogue
    of :func:`ambiguous_orders`). A line equal to this one (an identical bearing on the same
    shaft) is the same hypothesis and is not left out."""
    o = np.asarray(orders, float)
    s = np.asarray(spectrum, float)
    top = float(o[-1]) if order_max is None else min(float(order_max), float(o[-1]))
    lines = [(c.name, line, float(f)) for c in bearings for line, f in c.fault_orders.items()]
    combs = {(n, line): comb_mask(o, f, top) for n, line, f in lines
             if line in AMBIGUOUS_BEARING_LINES and np.isfinite(f)}
    out: dict[tuple[str, str], float] = {}
    for name, line, f in lines:
        other = np.zeros(o.size, bool)
        for n2, l2, f2 in lines:
            if (n2, l2) in combs and n2 != name and not (
                    np.isfinite(f) and abs(f2 - f) <= 1e-9 * abs(f)):
                other |= combs[(n2, l2)]
        out[(name, line)] = band_energy_share(o, s, f, order_max, exclude=other)
    return out


def bearing_evidence(baselines: Sequence, record, alpha: float,  # noqa: ANN001
                     order_max: float | None = None,
                     runs: Sequence[object] | None = None) -> dict[str, Evidence]:
    """Per bearing, the fault-band energy share (:func:`bearing_line_shares`: without the
    other bearings' lines) in the squared-envelope spectrum of the whole band
    (``bearing_spectrum`` of every run; ``envelope_spectrum`` when a run lacks it): each run's
    kurtogram picks its own band, on healthy runs almost at random, and shares taken in
    different bands spread over orders of magnitude across the baselines — of each of its
    lines (BPFO, BPFI, BSF, FTF) in the record's squared-envelope spectrum against the same
    share in every baseline member (:func:`evidence_from_null`, ``runs``: the dynamic run of
    each member); the bearing's evidence is its line with the largest score. Each line is one
    test at ``alpha``. No family floor here (:func:`family_floor`): a line's spread depends
    on which deterministic lines its comb meets, which is the bearing's own geometry, so the
    bearings' spreads are not exchangeable (with the floor, a load-zone outer-race spall's
    BPFO share of 0.33 met a threshold of 16, a share being at most 1)."""
    comps = getattr(record, "components", None)
    runs_all = [record, *baselines]
    attr = ("bearing_spectrum" if all(getattr(f, "bearing_spectrum", None) is not None
                                      for f in runs_all) else "envelope_spectrum")
    spec = getattr(record, attr, None)
    if spec is None or comps is None:
        return {}
    base = []
    for b in baselines:
        s = getattr(b, attr, None)
        if s is None:
            return {}
        base.append(bearing_line_shares(np.asarray(s["order"].values, float),
                                        np.asarray(s.values, float), comps.bearings, order_max))
    rec = bearing_line_shares(np.asarray(spec["order"].values, float),
                              np.asarray(spec.values, float), comps.bearings, order_max)
    out: dict[str, Evidence] = {}
    for c in comps.bearings:
        for line in c.fault_orders:
            null = [b.get((c.name, line), math.nan) for b in base]
            ev = evidence_from_null(c.name, f"{line} band energy", rec[(c.name, line)], null,
                                    alpha, group=c.name, runs=runs)
            best = out.get(c.name)
            if best is None or (np.isfinite(ev.z) and not ev.z <= best.z):
                out[c.name] = ev
    return out


def evidence_tests(baselines: Sequence, record, blocks: IsolationBlocks | None  # noqa: ANN001
                   ) -> int:
    """Number of evidence tests the record will get (for the many-tests correction): one per
    own-angle, TE and planet domain, and one per bearing line."""
    n = 0
    if blocks is not None:
        n += len(set(blocks.of.values()) | set(blocks.of_te.values())
                 | set(blocks.of_planet.values()))
    comps = getattr(record, "components", None)
    if comps is not None and getattr(record, "envelope_spectrum", None) is not None:
        n += sum(len(c.fault_orders) for c in comps.bearings)
    return n
