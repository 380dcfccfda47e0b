"""Sensor channels of a simulation result (``[[sensors]]``, docs/results.md).

:func:`apply_sensors` turns a result in the geardyn layout into measured channels
``sensors.<name>``:

* encoder: encoder edges of the shaft angle, counter clock and elapsed-time IAS (seed 002 eq 1,
  :func:`geardyn.sensors.simulate_ias`), one sample per encoder interval (angle sampling);
* tacho: pulse times of the shaft (events);
* accelerometer: a force at its location — the planet–ring mesh forces weighted by the
  planet-pass windows for a ring sensor (seed 003 eqs 4.10-4.14, the force version of eq 4.13
  with the simulated mesh forces in place of the harmonic model), or a bearing's force on the
  housing — through the transfer path (:mod:`geardyn.sensors.transfer`), then white noise and
  the ADC (:func:`geardyn.sensors.accelerometer`).

Random draws use ``numpy.random.SeedSequence([run seed, sensor seed, sensor index])``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import xarray as xr
from scipy import signal as sps

from geardyn.errors import InputError
from geardyn.results import PREFIX, check_rotation, shafts

#: Index of the force column per location: (variable, selection dict).
ForceRef = tuple[str, dict]


@dataclass
class RingSet:
    """What a ring-mounted sensor of one planetary stage needs from the model."""

    carrier_shaft: str
    ring_shaft: str
    planet_angles: np.ndarray
    ring_meshes: list[str]


@dataclass
class SensorContext:
    """Model facts for the sensors: ring sets per stage, bearing force columns per location."""

    reference_shaft: str
    rings: dict[str, RingSet] = field(default_factory=dict)
    bearings: dict[tuple[str, str], ForceRef] = field(default_factory=dict)
    #: gear pair → (link a, teeth a, link b, teeth b) for transmission-error sensors
    meshes: dict[str, tuple[str, int, str, int]] = field(default_factory=dict)


def apply_sensors(ds: xr.Dataset, specs: list, seed: int, ctx: SensorContext) -> xr.Dataset:
    """Add one ``sensors.<name>`` channel per spec to ``ds`` (in place; also returned).

    A shaft seen by a sensor that stops or turns backwards sets the run status (``stopped`` /
    ``reversed``); encoder and tacho channels then cover only the forward-turning part."""
    t = np.asarray(ds["time"].values, float)
    seen = [s.shaft or ctx.reference_shaft for s in specs if s.kind != "transmission_error"]
    for s in specs:
        if s.kind == "transmission_error" and s.pair in ctx.meshes:
            la, _, lb, _ = ctx.meshes[s.pair]
            seen += [shaft_of_link(ds, la), shaft_of_link(ds, lb)]
    check_rotation(ds, [s for s in seen if s in shafts(ds)])
    for i, spec in enumerate(specs):
        rng = np.random.default_rng(np.random.SeedSequence([int(seed) & 0xFFFFFFFF,
                                                            spec.seed, i]))
        where = f"sensors[{i}] '{spec.name}'"
        if spec.kind in ("encoder", "tacho"):
            _pulse_channel(ds, spec, t, rng, where)
        elif spec.kind == "transmission_error":
            _te_channel(ds, spec, ctx, where)
        else:
            _accelerometer_channel(ds, spec, t, rng, ctx, where)
    return ds


def _forward(ds: xr.Dataset, shaft: str, where: str) -> tuple[np.ndarray, np.ndarray]:
    names = shafts(ds)
    if shaft not in names:
        raise InputError(f"{where}.shaft: '{shaft}' is not a shaft of the model (shafts: "
                         f"{', '.join(names)})")
    t = np.asarray(ds["time"].values, float)
    th = np.asarray(ds["angle"].sel(shaft=shaft).values, float)
    w = np.asarray(ds["speed"].sel(shaft=shaft).values, float)
    sgn = np.sign(np.median(w)) or 1.0
    th, w = sgn * th, sgn * w
    stop = np.flatnonzero(w <= 1e-9 * max(float(np.max(np.abs(w))), 1e-12))
    n = int(stop[0]) if stop.size else t.size
    if n < 3:
        raise InputError(f"{where}.shaft: '{shaft}' does not turn during the run; an "
                         f"encoder or tacho on it measures nothing")
    return t[:n], th[:n] - th[0]


def _pulse_channel(ds: xr.Dataset, spec, t, rng, where: str) -> None:  # noqa: ANN001
    from geardyn.sensors.encoder import pulse_times_from_angle, simulate_ias

    tt, th = _forward(ds, spec.shaft, where)
    key = PREFIX + spec.name
    base = {"sensor_kind": spec.kind, "shaft": spec.shaft, "pulses_per_rev": spec.ppr,
            "location": spec.shaft}
    if spec.kind == "tacho":
        tp = pulse_times_from_angle(tt, th, spec.ppr)
        ds[key] = xr.DataArray(
            tp, dims=(f"{key}.pulse",),
            attrs={**base, "units": "s", "long_name": f"tacho pulse times of '{spec.shaft}'",
                   "sampling": "events"})
        return
    grad = spec.graduation_error_rad if spec.graduation_error_rad > 0 else None
    m = simulate_ias(tt, th, spec.ppr, f_clock=spec.clock_hz or None, graduation_error=grad,
                     seed=rng) if spec.clock_hz else _ideal_ias(tt, th, spec.ppr, grad, rng)
    dim = f"{key}.angle"
    ds[key] = xr.DataArray(
        m.ias, dims=(dim,),
        coords={dim: (dim, m.angle, {"units": "rad", "long_name": "encoder angle"}),
                f"{key}.time": (dim, m.time, {"units": "s", "long_name": "edge time"})},
        attrs={**base, "units": "rad/s", "sampling": "angle",
               "long_name": f"IAS of '{spec.shaft}' (elapsed time, Thibault et al. 2024, eq 1)",
               "clock_hz": float(spec.clock_hz or 0.0)})


def shaft_of_link(ds: xr.Dataset, link: str) -> str:
    """The result's shaft that carries mechanism link ``link`` (FE shafts name their link in
    the ``link`` coordinate; lumped models name shafts after their links)."""
    if "link" in ds.coords:
        for s, ln in zip(ds["shaft"].values, ds["link"].values, strict=True):
            if str(ln) == link:
                return str(s)
    return link


def _edge_angle(ds: xr.Dataset, shaft: str, ppr: int, clock_hz: float | None, where: str
                ) -> tuple[np.ndarray, np.ndarray]:
    """Encoder edge times [s] (latched by the clock) and their angles k·2π/R [rad]."""
    from geardyn.sensors.encoder import pulse_times_from_angle, quantise_clock

    tt, th = _forward(ds, shaft, where)
    tp = pulse_times_from_angle(tt, th, ppr)
    if clock_hz:
        tp = quantise_clock(tp, clock_hz) / clock_hz
    k = np.round((np.interp(tp, tt, th)) / (2 * np.pi / ppr))
    return tp, k * 2 * np.pi / ppr


def _te_channel(ds: xr.Dataset, spec, ctx: SensorContext, where: str) -> None:  # noqa: ANN001
    """Angular transmission error of wheel a of ``spec.pair`` from an encoder on each shaft:
    ``TE = θ_a − (z_b/z_a)·θ_b`` [rad], both angles forward from the latched edges, on a
    uniform time grid at the slower encoder's mean edge rate (seed 002 §3.1 setup: encoders
    and a counter clock)."""
    if spec.pair not in ctx.meshes:
        raise InputError(f"{where}.pair: '{spec.pair}' is not a fixed-axis gear pair of the "
                         f"model (pairs: {', '.join(ctx.meshes) or 'none'})")
    la, za, lb, zb = ctx.meshes[spec.pair]
    sa, sb = shaft_of_link(ds, la), shaft_of_link(ds, lb)
    ta, aa = _edge_angle(ds, sa, spec.ppr, spec.clock_hz, where)
    tb, ab = _edge_angle(ds, sb, spec.ppr, spec.clock_hz, where)
    t0, t1 = max(ta[0], tb[0]), min(ta[-1], tb[-1])
    fs = min(ta.size / (ta[-1] - ta[0]), tb.size / (tb[-1] - tb[0]))
    ts = t0 + np.arange(int(np.floor((t1 - t0) * fs)) + 1) / fs
    te = np.interp(ts, ta, aa) - (zb / za) * np.interp(ts, tb, ab)
    key = PREFIX + spec.name
    dim = f"{key}.time"
    ds[key] = xr.DataArray(
        te - te.mean(), dims=(dim,),
        coords={dim: (dim, ts, {"units": "s", "long_name": "time"})},
        attrs={"sensor_kind": "transmission_error", "units": "rad", "sampling": "time",
               "sample_rate_hz": float(fs), "shaft": sa, "pair": spec.pair,
               "location": f"pair '{spec.pair}'", "pulses_per_rev": spec.ppr,
               "clock_hz": float(spec.clock_hz or 0.0),
               "long_name": f"transmission error of pair '{spec.pair}' (angle of its wheel a, "
                            "mean removed)"})


def _ideal_ias(tt, th, ppr, grad, rng):  # noqa: ANN001, ANN202
    from geardyn.sensors.encoder import elapsed_time_ias, pulse_times_from_angle

    return elapsed_time_ias(pulse_times_from_angle(tt, th, ppr, grad, rng), ppr, None)


def _force(ds: xr.Dataset, spec, ctx: SensorContext, where: str) -> tuple[np.ndarray, str]:  # noqa: ANN001
    if spec.location == "ring":
        stage = spec.stage or next(iter(ctx.rings), None)
        ring = ctx.rings.get(stage) if stage else None
        if ring is None:
            raise InputError(f"{where}.location: 'ring' needs a planetary stage in the model")
        tc = np.asarray(ds["angle"].sel(shaft=ring.carrier_shaft).values, float)
        tr = np.asarray(ds["angle"].sel(shaft=ring.ring_shaft).values, float)
        w = ring_sensor_windows(tc - tr, ring.planet_angles, np.radians(spec.sensor_angle_deg))
        fr = np.asarray(ds["mesh_force"].sel(mesh=ring.ring_meshes).values, float)
        return np.sum(w.T * fr, axis=1), f"ring of stage '{stage}'"
    ref = ctx.bearings.get((spec.location, spec.direction))
    if ref is None:
        have = sorted({k[0] for k in ctx.bearings} | ({"ring"} if ctx.rings else set()))
        raise InputError(f"{where}.location: unknown location '{spec.location}' (locations: "
                         f"{', '.join(have)})")
    var, sel = ref
    return np.asarray(ds[var].sel(**sel).values, float), (
        f"bearing '{spec.location}', {spec.direction}")


def ring_sensor_windows(carrier_angle: np.ndarray, planet_angles: np.ndarray,
                        sensor_angle: float) -> np.ndarray:
    """Planet-pass weights (n_planets × samples) of a sensor on the ring at angle
    ``sensor_angle`` [rad] of the frame: planet n sits at ``θ_c + ψ_n`` (the model's planet
    positions, carrier angle relative to the ring) and is in view within ±π/N of the sensor,
    weighted by the Hann lobe ``½(1 + cos(N·Δ))`` (seed 003 eqs 4.10-4.12, centred gate:
    :func:`geardyn.sensors.planet_pass.planet_pass_windows` with ψ → −ψ and the sensor moved
    back by π/N so the lobe peaks where the planet faces the sensor)."""
    from geardyn.sensors.planet_pass import planet_pass_windows

    psi = np.mod(-np.asarray(planet_angles, float), 2 * np.pi)
    return planet_pass_windows(carrier_angle, psi.size, psi, sensor_angle - np.pi / psi.size)


def sample_at(t: np.ndarray, x: np.ndarray, ts: np.ndarray) -> np.ndarray:
    """``x`` (on the result's time grid ``t``) at the sensor's sample times ``ts`` by
    band-limited interpolation (:func:`geardyn.signal.resample.interpolate_bandlimited`,
    Smith & Gossett 1984) on a uniform grid, linear otherwise. Linear interpolation leaves
    images of every line f at f_rec − f (f_rec the result's rate) that alias into the sensor's
    band; when the sensor rate is a whole multiple of a shaft's rate they fall on whole orders
    of that shaft and survive synchronous averaging — a healthy record at such a speed then
    alarms against baselines at other speeds (measured on the parallel template at 1500 rpm,
    20 kHz: cSDR margin 1.61 with linear interpolation, 0.49 band-limited)."""
    from geardyn.signal.resample import interpolate_bandlimited

    step = np.diff(t)
    if t.size < 2 or not np.allclose(step, step.mean(), rtol=1e-6, atol=0.0):
        return np.interp(ts, t, x)
    pos = (ts - t[0]) / step.mean()
    whole = np.round(pos)
    if np.all(np.abs(pos - whole) < 1e-9):  # the sensor samples the result's own grid
        return np.asarray(x, float)[np.clip(whole.astype(int), 0, x.size - 1)]
    return interpolate_bandlimited(x, pos)


def _accelerometer_channel(ds: xr.Dataset, spec, t, rng, ctx: SensorContext,  # noqa: ANN001
                           where: str) -> None:
    from geardyn.sensors.accelerometer import accelerometer
    from geardyn.sensors.transfer import apply_transfer_path

    force, label = _force(ds, spec, ctx, where)
    fs_rec = (t.size - 1) / (t[-1] - t[0])
    fs = spec.sample_rate_hz or fs_rec
    ts = t[0] + np.arange(int(np.floor((t[-1] - t[0]) * fs)) + 1) / fs
    if fs < fs_rec:  # anti-aliasing before decimation
        sos = sps.butter(8, 0.4 * fs, fs=fs_rec, output="sos")
        force = sps.sosfiltfilt(sos, force)
    x = sample_at(t, force, ts)
    if spec.transfer_path:
        x = apply_transfer_path(x, fs, spec.transfer_path)
        units, what = "m/s^2", "acceleration"
    else:
        units, what = "N", "force"
    bits = spec.adc_bits
    x = accelerometer(x, spec.noise_rms, bits, spec.adc_full_scale, seed=rng)
    key = PREFIX + spec.name
    dim = f"{key}.time"
    ds[key] = xr.DataArray(
        x, dims=(dim,), coords={dim: (dim, ts, {"units": "s", "long_name": "time"})},
        attrs={"sensor_kind": "accelerometer", "units": units, "sampling": "time",
               "sample_rate_hz": float(fs), "shaft": spec.shaft or ctx.reference_shaft,
               "location": label, "long_name": f"{what} at the {label}",
               "sensor_angle_deg": float(spec.sensor_angle_deg),
               "transfer_modes_hz": [float(m.frequency_hz) for m in spec.transfer_path]
               or [0.0], "noise_rms": float(spec.noise_rms), "adc_bits": int(bits or 0)})
