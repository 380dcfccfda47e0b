"""Planet-separated revolutions of ring accelerometers, for naming the faulty planet.

Every planet of a stage turns alike relative to the carrier, so the own-angle revolutions of
:func:`geardyn.diagnosis.isolation.isolation_blocks` put all planets of a stage in one domain:
a planet fault raises them all. A sensor on a fixed ring, however, sees mostly the planet that
is passing it (the planet-pass lobe, seed 003 eqs 4.10-4.12). **Vibration separation**
(McFadden & Smith 1985, "An explanation for the asymmetry of the modulation sidebands about
the tooth meshing frequency in epicyclic gear vibration", Proc. IMechE C 199; McFadden 1991,
"A technique for calculating the time domain averages of the vibration of the individual
planet gears and the sun gear in an epicyclic gearbox", JSV 144; McFadden 1994, "Window
functions for the calculation of the time domain averages of the vibration of the individual
planet gears and sun gear in an epicyclic gearbox", J. Vib. Acoust. 116) cuts the signal into
windows centred on the passes of planet n and places each window at the teeth of planet n that
are meshing with the ring at that moment.

Geometry (the conventions of the model and of
:func:`geardyn.sensors.channels.ring_sensor_windows`): with ``u = θ_c − θ_r`` the carrier
angle relative to the ring, planet n sits at ``u + ψ_n`` and faces a sensor at frame angle φ
when ``u = φ − ψ_n + 2πk`` (pass k). Its ring-mesh count is ``X_n = Z_r (u + ψ_n − ψ_1)/2π``
(seed 004 Table 4-1 planet phases, integer offsets: the ring teeth between planet 1's position
and planet n's), and the tooth of planet n in contact is ``X_n mod Z_p``: **tooth 0 of planet
n** is where ``X_n ≡ 0 (mod Z_p)``. At the sensor, ``X_n = Z_r(φ − ψ_1)/2π + k·Z_r``, the same
for every planet: on each carrier revolution the tooth at the sensor advances by
``Z_r mod Z_p`` teeth, so ``M`` consecutive passes whose windows of ``W`` teeth leave no gap
cover every tooth once (:func:`passes_per_row`).

Rows (McFadden 1991 averaging, kept per revolution of the planet's teeth so that the rows can
be compared): row r of planet n holds passes ``k = rM … rM + M − 1`` (k counted from the
reference angle's origin, so row r of two runs of one operating profile holds the same passes
and the same window pattern). Each pass contributes a Hann window of ``W`` ring-mesh periods
(McFadden 1994) centred on the pass, with a window-weighted quadratic removed (the slow
planet-pass lobe times the mean mesh force, seed 003 eq 4.10, which would otherwise leave
steps where windows meet); the row is the window-weighted mean of its passes on the tooth grid
(``Z_p × samples per tooth``; every tooth covered, some by two windows). The mesh harmonics of
planet n (orders ``k·Z_p`` of its tooth frame: ring and sun meshes alike) and their first
sidebands are removed as in :func:`geardyn.diagnosis.isolation.difference_blocks` (difference
signal, Zakrajsek, Townsend & Decker 1993), so a local tooth fault remains. The mean of the rows
is the planet-separated TSA of planet n; the rows feed the synchronous deviation ratio
(:func:`geardyn.diagnosis.isolation.synchronous_deviation_ratio`) per planet.

Several ring accelerometers of one stage (different sensor angles): their windows of the passes
of row r are averaged together, each weighted by its analysis window — the same tooth of
planet n seen through another path. Averaging (rather than concatenating the sensors' rows)
keeps one deterministic pattern per row (a different sensor angle gives another window pattern
and another transfer path; concatenated rows would count that difference as between-row
scatter and raise the denominator of the F statistic), keeps R equal to the number of
independent repetitions, and lowers independent sensor noise by the number of sensors.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from geardyn.errors import InputError
from geardyn.signal._checks import positive_int

TWO_PI = 2.0 * math.pi
_RING = re.compile(r"ring of stage '([^']*)'")
#: Degree of the window-weighted polynomial removed from each window (as
#: :func:`geardyn.signal.planetary_tsa` ``detrend=2``): mean, slope and curvature of the
#: planet-pass lobe (seed 003 eq 4.10: a Hann lobe, quadratic near its peak).
DETREND_DEGREE = 2


@dataclass(frozen=True)
class PlanetWindowing:
    """How the planets of one stage were separated.

    ``window_teeth`` W: Hann window length in ring-mesh periods; ``passes_per_row`` M: planet
    passes (carrier revolutions relative to the ring) per row; ``samples_per_tooth``: samples
    per ring-mesh period (row length ``Z_p × samples_per_tooth``); ``first_row``: index of the
    first row kept, counted from the reference angle's origin (rows of runs with one operating
    profile and one ``skip_s`` start at the same index); ``channels``: ring accelerometers
    combined."""

    stage: str
    planet_teeth: int
    ring_teeth: int
    n_planets: int
    window_teeth: int
    passes_per_row: int
    samples_per_tooth: int
    first_row: int
    channels: tuple[str, ...]


class PlanetDomains(dict):
    """component name → rows (n_rows × spr) of planet-separated difference signals, with
    ``windowing``: stage → :class:`PlanetWindowing` and ``stage_of``: component → stage."""

    def __init__(self) -> None:
        super().__init__()
        self.windowing: dict[str, PlanetWindowing] = {}
        self.stage_of: dict[str, str] = {}


def ring_accelerometers(ds, stage: str | None = None) -> list[str]:  # noqa: ANN001
    """Accelerometer channels of result ``ds`` mounted on the ring of a planetary stage
    (``location`` attribute ``ring of stage '<stage>'``), of ``stage`` only if given."""
    from geardyn import results

    out = []
    for name in results.channels(ds):
        a = ds[results.PREFIX + name].attrs
        m = _RING.fullmatch(str(a.get("location", "")))
        if a.get("sensor_kind") == "accelerometer" and m and stage in (None, m.group(1)):
            out.append(name)
    return out


def passes_per_row(ring_teeth: int, planet_teeth: int, window_teeth: int) -> int:
    """Fewest consecutive planet passes M whose windows of ``window_teeth`` teeth cover every
    tooth of the planet, whatever the first pass. The tooth at the sensor advances by
    ``Z_r mod Z_p`` per pass, so M passes cover every tooth when the largest circular gap
    between their tooth positions is at most W (a Hann window of ``W·spt + 1`` samples spans W
    teeth). InputError when no M ≤ Z_p does (e.g. Z_r a multiple of Z_p: the same teeth at
    every pass)."""
    zr = positive_int("ring_teeth", ring_teeth, "ring tooth count")
    zp = positive_int("planet_teeth", planet_teeth, "planet tooth count")
    w = positive_int("window_teeth", window_teeth, "window length in ring-mesh periods")
    step = zr % zp
    for m in range(1, zp + 1):
        worst = 0
        for s in range(zp):
            pos = np.sort([(s + step * k) % zp for k in range(m)])
            gaps = np.diff(np.append(pos, pos[0] + zp))
            worst = max(worst, int(gaps.max()))
        if worst <= w:
            return m
    raise InputError(f"window_teeth: windows of {w} teeth never cover all {zp} planet teeth "
                     f"(ring {zr} teeth advances the tooth at the sensor by {step} per pass)")


class _RingChannel:
    """One ring accelerometer resampled to the carrier angle relative to the ring."""

    def __init__(self, ds, comps, st, name: str, ref: str, skip_s: float,  # noqa: ANN001
                 spt: int | None) -> None:
        from geardyn import results
        from geardyn.diagnosis.features import _reference_angle
        from geardyn.diagnosis.isolation import _uniform
        from geardyn.signal.resample import resample_to_angle

        ch = results.channel(ds, name)
        if ch.sampling != "time":
            raise InputError(f"channels: '{name}' is not a time-sampled accelerometer")
        self.name = name
        self.phi = math.radians(float(ch.attrs.get("sensor_angle_deg", 0.0)))
        if not math.isfinite(self.phi):
            raise InputError(f"channels: '{name}' has a non-finite sensor_angle_deg")
        time = np.asarray(ch.time, float)
        x = np.asarray(ch.values, float)
        if not np.all(np.isfinite(x)):
            raise InputError(f"channels: '{name}' contains NaN or infinite samples")
        keep = time >= time[0] + float(skip_s)
        time, x = time[keep], x[keep]
        if time.size < 16:
            raise InputError(f"skip_s: {skip_s} s leaves fewer than 16 samples of '{name}'")
        mask, ang, _ = _reference_angle(ds, comps, ref, time)
        x, time = x[mask], time[mask]
        u = -st.ring_ratio * ang  # θ_c − θ_r (ring ratio: θ_r − θ_c per reference angle)
        self.sign = 1 if u[-1] > u[0] else -1
        x, fs, t0 = _uniform(x, time)
        v = np.interp(t0 + np.arange(x.size) / fs, time, self.sign * u)
        rate = float(np.max(np.gradient(v)) * fs / TWO_PI)  # carrier rev/s, fastest
        if spt is None:
            spt = int(2 ** np.floor(np.log2(max(fs / (rate * st.ring_teeth), 8.0))))
        self.spt = spt
        self.spc = st.ring_teeth * spt  # samples per carrier revolution
        sig = resample_to_angle(x, fs, v, samples_per_rev=self.spc, t0=t0)
        self.x = sig.x
        self.i0 = int(round(sig.angle0 / TWO_PI * self.spc))  # grid index of sample 0 (of v)


def _rows_of_planet(rc: _RingChannel, psi_rel: float, psi_n: float, zp: int, zr: int,
                    w_teeth: int, m_pass: int, pass_average: bool = True,
                    ) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """Row index → (Σ window·piece, Σ window) on the tooth grid of planet n for one channel
    (only rows whose passes all lie inside the record)."""
    spt, spc, sgn = rc.spt, rc.spc, rc.sign
    m = zp * spt
    half = w_teeth * spt // 2
    win = np.hanning(2 * half + 3)[1:-1]  # W·spt + 1 samples, no zero end points
    u_pos = np.linspace(-1.0, 1.0, win.size)
    basis = np.vander(u_pos, DETREND_DEGREE + 1)
    sw = np.sqrt(win)
    fit = np.linalg.pinv(basis * sw[:, None]) * sw[None, :]  # window-weighted least squares
    # tooth coordinate (samples) of grid index g: sgn·g + offset, offset = spt·Z_r(ψ_n − ψ_1)/2π
    offset = int(round(spt * zr * psi_rel / TWO_PI))
    # passes: v = sgn·u at u = φ − ψ_n + 2πk → grid index sgn·(φ − ψ_n)·spc/2π + k·spc
    g0 = sgn * (rc.phi - psi_n) * spc / TWO_PI
    k_lo = math.ceil((rc.i0 + half + 1 - g0) / spc)  # + 1: rounding of the centre
    k_hi = math.floor((rc.i0 + rc.x.size - 2 - half - g0) / spc)
    ks = np.arange(k_lo, k_hi + 1)
    if ks.size == 0:
        return {}
    centres = np.round(g0 + ks * spc).astype(int)
    pieces = np.array([rc.x[c - half - rc.i0:c + half + 1 - rc.i0] for c in centres])
    pieces = pieces - (pieces @ fit.T) @ basis.T
    if pass_average and ks.size > 1:
        pieces = pieces - pieces.mean(axis=0)
    rows: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    for r in range(math.ceil(k_lo / m_pass), math.floor((k_hi + 1) / m_pass)):
        acc, wsum = np.zeros(m), np.zeros(m)
        for k in range(r * m_pass, (r + 1) * m_pass):
            c = centres[k - k_lo]
            idx = np.mod(sgn * np.arange(c - half, c + half + 1) + offset, m)
            np.add.at(acc, idx, pieces[k - k_lo] * win)
            np.add.at(wsum, idx, win)
        rows[r] = (acc, wsum)
    return rows


def planet_domains(ds, cfg, channel: str, reference: str | None = None,  # noqa: ANN001
                   skip_s: float = 0.0, channels: Sequence[str] | None = None,
                   window_teeth: int | None = None,
                   samples_per_tooth: int | None = None) -> PlanetDomains:
    """Planet-separated rows (module docstring) of every planet of every fixed-ring planetary
    stage seen by the ring accelerometer ``channel`` of result ``ds`` (kinematics of ``cfg``;
    reference angle as in :func:`geardyn.diagnosis.isolation.isolation_blocks`: a tacho, else
    the result's shaft angle; the first ``skip_s`` seconds dropped).

    Returns component (``machine_components`` names, e.g. ``planetary.planet2/z32``) → array
    (n_rows × ``Z_p·samples_per_tooth``): row r is one cycle of planet n's teeth from tooth 0,
    difference signal; components with fewer than 2 rows are left out; a ``channel`` that is
    not a ring accelerometer gives an empty result. ``channels``: further ring accelerometers
    of the same stages whose windows are averaged in (module docstring). ``window_teeth`` W:
    Hann window length in ring-mesh periods, default ``max(2, Z_r // (2N))`` (half a
    planet-pass lobe, so a window stays where its planet dominates, as in
    :func:`geardyn.diagnosis.features.features_from_result`); ``samples_per_tooth``: default the
    power of two at or below the channel's samples per ring-mesh period (at the fastest
    carrier speed). The windowing used is in ``result.windowing[stage]``."""
    from geardyn import results
    from geardyn.diagnosis.components import machine_components
    from geardyn.diagnosis.isolation import difference_blocks

    out = PlanetDomains()
    if float(skip_s) < 0 or not math.isfinite(float(skip_s)):
        raise InputError(f"skip_s: must be a finite number >= 0, got {skip_s!r}")
    names = list(dict.fromkeys([channel, *(channels or ())]))
    rings = set(ring_accelerometers(ds))
    for name in names[1:]:
        if name not in rings:
            raise InputError(f"channels: '{name}' is not an accelerometer on a ring (ring "
                             f"accelerometers: {', '.join(sorted(rings)) or 'none'})")
    if channel not in rings:
        results.channel(ds, channel)  # an unknown name is an error, another sensor is not
        return out
    ch = results.channel(ds, channel)
    ref = reference or ch.shaft or str(ds.attrs.get("reference_shaft", ""))
    comps = machine_components(cfg, ref)
    by_stage: dict[str, list[str]] = {}
    for name in names:
        stage = _RING.fullmatch(str(ds[results.PREFIX + name].attrs["location"])).group(1)
        by_stage.setdefault(stage, []).append(name)
    for stage, chans in by_stage.items():
        st = next((s for s in comps.planetary if s.name == stage), None)
        if st is None or not st.ring_fixed:
            continue
        zr, zp, n = st.ring_teeth, st.planet_ring_teeth, st.n_planets
        w = max(2, zr // (2 * n)) if window_teeth is None else positive_int(
            "window_teeth", window_teeth, "window length in ring-mesh periods", minimum=1)
        m_pass = passes_per_row(zr, zp, w)
        spt = None if samples_per_tooth is None else positive_int(
            "samples_per_tooth", samples_per_tooth, "samples per ring-mesh period", minimum=4)
        sensors = []
        for name in chans:
            rc = _RingChannel(ds, comps, st, name, ref, skip_s, spt)
            spt = rc.spt  # every channel of the stage on one tooth grid
            sensors.append(rc)
        psi = np.asarray(st.planet_angles, float)
        first = None
        for comp in comps.items:
            if comp.kind != "planet" or comp.stage != stage or comp.teeth != zp:
                continue  # the sun-side wheel of a stepped planet is not in the ring count
            p = int(comp.planet or 0)
            parts = [_rows_of_planet(rc, psi[p] - psi[0], psi[p], zp, zr, w, m_pass)
                     for rc in sensors]
            common = sorted(set.intersection(*(set(d) for d in parts)))
            if len(common) < 2:
                continue
            acc = np.array([sum(d[r][0] for d in parts) for r in common])
            wsum = np.array([sum(d[r][1] for d in parts) for r in common])
            rows = acc / wsum
            teeth = [zp] if 0 < zp < rows.shape[1] // 2 - 1 else []
            out[comp.name] = difference_blocks(rows, teeth) if teeth else rows
            out.stage_of[comp.name] = stage
            first = common[0] if first is None else min(first, common[0])
        if first is not None:
            out.windowing[stage] = PlanetWindowing(stage, zp, zr, n, w, m_pass, int(spt),
                                                   int(first), tuple(chans))
    return out


__all__ = ["PlanetDomains", "PlanetWindowing", "passes_per_row", "planet_domains",
           "ring_accelerometers"]
