"""The healthy baseline as an ensemble over what is uncertain in a real fleet (issue 18).

Simulated baselines that differ only by their sensor noise give thresholds no real machine
respects: a fleet's healthy records differ by their operating point, their manufacturing errors
and their sensor mountings. :func:`member_configs` draws, per dynamic run (``[diagnosis]``
``baseline_seeds``, default 0 … ``ensemble.members`` − 1):

* a **speed factor** f ∈ 1 ± ``speed_tolerance``, applied everywhere the config states the input
  speed: ``input_speeds_rpm``; planetary and mechanism simulations: ``initial_speed_rpm``,
  speed-control profiles, the motor's rated speed, supply frequency and rated power (an inverter
  in its constant-torque V/f range: the rated torque is kept); FE transmission: the speed law's
  start and end speeds, ``simulation.initial_rpm`` (the run keeps its number of revolutions);
* a **load factor** g ∈ 1 ± ``load_tolerance`` on every load torque: ``torques`` (constant and
  profile), the bucket-wheel load's full-load torque; FE: drive and load torques;
* **manufacturing errors**: one amplitude factor e ∈ 1 ± ``error_scale_tolerance`` on the
  configured error amplitudes (seed 004 random impulse errors ``random_error_max_m``, configured
  ``pin_errors_m``, FE unbalances), tangential planet pin errors ± ``pin_error_m`` per planet
  (Lin & Parker's pin position error, seed 003 eq 5.4), FE bearing clearances
  × (1 ± ``bearing_clearance_tolerance``); the run seed re-draws the seed 004 random impulses
  (:func:`geardyn.run.run_simulation`);

and, per measurement (``measurements_per_run`` per run), for each accelerometer a frequency and
a damping factor per transfer-path mode (1 ± ``transfer_path_tolerance``), a gain factor
(1 ± ``sensitivity_tolerance``, on 1/modal mass) and a noise factor (1 ± ``noise_tolerance``),
and new sensor noise (each sensor's ``seed`` + measurement index).

All draws are uniform on their range and come from
``numpy.random.default_rng([ensemble.seed, run seed, 0])`` (dynamics) and
``default_rng([ensemble.seed, run seed, 1, measurement])`` (sensors): the same config and seeds
give the same members whatever their number, a zero tolerance leaves its quantity nominal
without shifting the other draws.

:func:`simulate_baseline` simulates each run once without sensors and measures it once per
measurement variant (:func:`geardyn.run.add_sensors`): the sensors act after the dynamics, so a
measurement equals a full :func:`~geardyn.run.run_simulation` of the member's config with its
seed, bit for bit, at the cost of the sensor model only.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from geardyn.errors import ConfigError

if TYPE_CHECKING:
    import xarray as xr

    from geardyn.config.diagnosis import DiagnosisSpec, EnsembleSpec
    from geardyn.config.loader import GeardynConfig

#: ``progress(message, fraction)``, as :data:`geardyn.diagnosis.pipeline.Progress`.
Progress = Callable[[str, float], None]


@dataclass(frozen=True)
class Member:
    """One measured baseline member: run ``run`` (dynamic seed ``seed``), measurement
    ``measurement`` of it; ``config`` is the perturbed config (dynamics and sensors) whose
    :func:`~geardyn.run.run_simulation` with ``seed`` gives the member's result; ``values``
    the drawn factors and the resulting values (JSON-ready, for verdict.json)."""

    label: str
    config: GeardynConfig = field(repr=False)
    seed: int
    run: int
    measurement: int
    values: dict[str, Any]


def _factor(rng: np.random.Generator, tolerance: float) -> float:
    """1 + U(−1, 1)·tolerance; one draw whatever the tolerance (draws stay aligned)."""
    return 1.0 + float(rng.uniform(-1.0, 1.0)) * tolerance


def _scaled_profile(points: list | None, factor: float) -> list | None:
    return None if points is None else [(t, v * factor) for t, v in points]


def _drive_sim(sim: Any, f: float, g: float) -> Any:  # noqa: ANN401 - a simulation section
    """Planetary or mechanism simulation section at speed factor ``f`` and load factor ``g``."""
    upd: dict[str, Any] = {
        "initial_speed_rpm": {k: v * f for k, v in sim.initial_speed_rpm.items()},
        "torques": [t.model_copy(update={"torque_nm": t.torque_nm * g,
                                         "profile": _scaled_profile(t.profile, g)})
                    for t in sim.torques],
        "speed_controls": [s.model_copy(update={"profile_rpm": _scaled_profile(s.profile_rpm, f)})
                           for s in sim.speed_controls],
    }
    if sim.motor is not None:
        mo = sim.motor
        upd["motor"] = mo.model_copy(update={"rated_speed_rpm": mo.rated_speed_rpm * f,
                                             "frequency_hz": mo.frequency_hz * f,
                                             "rated_power_w": mo.rated_power_w * f})
    if sim.wheel_load is not None:
        wl = sim.wheel_load
        upd["wheel_load"] = wl.model_copy(
            update={"full_load_torque_nm": wl.full_load_torque_nm * g})
    return sim.model_copy(update=upd)


def _planetary(cfg: Any, ens: EnsembleSpec, f: float, g: float, e: float,  # noqa: ANN401
               rng: np.random.Generator, values: dict[str, Any]) -> dict[str, Any]:
    """``planetary_dynamics`` update: drives, error amplitudes, planet pin errors."""
    pd = cfg.planetary_dynamics
    n_planets = {s.name: s.n_planets for s in getattr(cfg, "planetary", [])}
    stages, pins = [], {}
    for sd in pd.stages:
        n = n_planets.get(sd.stage, len(sd.pin_errors_m or []))
        drawn = rng.uniform(-1.0, 1.0, n) * ens.pin_error_m
        base = np.asarray(sd.pin_errors_m or [0.0] * n, float) * e
        pin = [float(x) for x in base + drawn]
        pins[sd.stage] = pin
        upd: dict[str, Any] = {"random_error_max_m": sd.random_error_max_m * e}
        if n and any(pin):
            upd["pin_errors_m"] = pin
        stages.append(sd.model_copy(update=upd))
    values["pin_errors_m"] = pins
    upd_pd: dict[str, Any] = {"stages": stages}
    if pd.simulation is not None:
        upd_pd["simulation"] = _drive_sim(pd.simulation, f, g)
    return {"planetary_dynamics": pd.model_copy(update=upd_pd)}


def _transmission(cfg: Any, ens: EnsembleSpec, f: float, g: float, e: float,  # noqa: ANN401
                  rng: np.random.Generator, values: dict[str, Any]) -> dict[str, Any]:
    """``transmission`` update: speed law, torques, unbalances, bearing clearances."""
    t = cfg.transmission
    upd: dict[str, Any] = {
        "drive": t.drive.model_copy(update={"torque_nm": t.drive.torque_nm * g}),
        "load": t.load.model_copy(update={"torque_nm": t.load.torque_nm * g}),
        "unbalance": [u.model_copy(update={"mass_eccentricity_kg_m":
                                           u.mass_eccentricity_kg_m * e}) for u in t.unbalance],
    }
    if t.speed_law is not None:
        upd["speed_law"] = t.speed_law.model_copy(
            update={"start_rpm": t.speed_law.start_rpm * f, "end_rpm": t.speed_law.end_rpm * f})
    if t.simulation.initial_rpm is not None:
        upd["simulation"] = t.simulation.model_copy(
            update={"initial_rpm": t.simulation.initial_rpm * f})
    bearings, clear = [], {}
    for b in t.bearings:
        c = b.diametral_clearance_m * _factor(rng, ens.bearing_clearance_tolerance)
        clear[b.name] = c
        bearings.append(b.model_copy(update={"diametral_clearance_m": c}))
    upd["bearings"] = bearings
    values["bearing_clearance_m"] = clear
    return {"transmission": t.model_copy(update=upd)}


def _dynamics_update(cfg: GeardynConfig, ens: EnsembleSpec, rng: np.random.Generator
                     ) -> tuple[dict[str, Any], dict[str, Any]]:
    """Config update and drawn values of one dynamic run (draw order fixed: speed, load, error
    scale, then the planetary pins and the FE bearings)."""
    f = _factor(rng, ens.speed_tolerance)
    g = _factor(rng, ens.load_tolerance)
    e = _factor(rng, ens.error_scale_tolerance)
    values: dict[str, Any] = {"speed_factor": f, "load_factor": g, "error_scale": e}
    upd: dict[str, Any] = {
        "input_speeds_rpm": {k: v * f for k, v in cfg.input_speeds_rpm.items()}}
    if getattr(cfg, "planetary_dynamics", None) is not None:
        upd.update(_planetary(cfg, ens, f, g, e, rng, values))
    dy = getattr(cfg, "dynamics", None)
    if dy is not None and dy.simulation is not None:
        upd["dynamics"] = dy.model_copy(update={"simulation": _drive_sim(dy.simulation, f, g)})
    if getattr(cfg, "transmission", None) is not None:
        upd.update(_transmission(cfg, ens, f, g, e, rng, values))
    values["input_speeds_rpm"] = dict(upd["input_speeds_rpm"])
    return upd, values


def _sensors(cfg: GeardynConfig, ens: EnsembleSpec, rng: np.random.Generator,
             measurement: int) -> tuple[list, dict[str, Any]]:
    """Sensors of one measurement: transfer path, gain and noise of every accelerometer drawn
    (in sensor order; every sensor draws, so adding one keeps the others), new noise seeds."""
    out, values = [], {}
    for s in cfg.sensors:
        fr = [_factor(rng, ens.transfer_path_tolerance) for _ in s.transfer_path]
        dr = [_factor(rng, ens.transfer_path_tolerance) for _ in s.transfer_path]
        gain = _factor(rng, ens.sensitivity_tolerance)
        noise = _factor(rng, ens.noise_tolerance)
        upd: dict[str, Any] = {"seed": s.seed + measurement}
        if s.kind == "accelerometer":
            path = [m.model_copy(update={"frequency_hz": m.frequency_hz * a,
                                         "damping_ratio": m.damping_ratio * b,
                                         "modal_mass_kg": m.modal_mass_kg / gain})
                    for m, a, b in zip(s.transfer_path, fr, dr, strict=True)]
            upd.update(transfer_path=path, noise_rms=s.noise_rms * noise)
            values[s.name] = {
                "frequency_factor": fr, "damping_factor": dr,
                "gain_factor": gain if s.transfer_path else 1.0, "noise_factor": noise,
                "transfer_path": [m.model_dump() for m in path],
                "noise_rms": s.noise_rms * noise, "seed": s.seed + measurement}
        else:
            values[s.name] = {"seed": s.seed + measurement}
        out.append(s.model_copy(update=upd))
    return out, values


def _validated(cfg: GeardynConfig, update: dict[str, Any], label: str) -> GeardynConfig:
    """``cfg`` with ``update`` applied, validated again as a whole (cross-checks included)."""
    from geardyn.config.loader import parse_config

    variant = cfg.model_copy(update=update)
    try:
        return parse_config(variant.model_dump(), source=f"baseline ensemble member {label}")
    except ConfigError as exc:
        raise ConfigError([*exc.problems, "the value was drawn by [diagnosis.ensemble]: narrow "
                           "its tolerances or change the nominal value"],
                          source=exc.source) from None


def _check(cfg: GeardynConfig, ens: EnsembleSpec) -> None:
    supported = any(getattr(cfg, sec, None) is not None
                    for sec in ("planetary_dynamics", "transmission", "dynamics"))
    if not supported and (ens.speed_tolerance or ens.load_tolerance):
        raise ConfigError("diagnosis.ensemble.speed_tolerance: the config has no simulated "
                          "model ([planetary_dynamics], [dynamics] or [transmission]) whose "
                          "speed and load could vary")


def operating_point(cfg: GeardynConfig, speed_factor: float, load_factor: float
                    ) -> GeardynConfig:
    """``cfg`` at another operating point: every stated input speed × ``speed_factor`` and
    every load torque × ``load_factor``, as the ensemble's speed and load factors (module
    docstring); errors, pins and clearances nominal. Validated again as a whole."""
    from geardyn.config.diagnosis import EnsembleSpec

    for name, v in (("speed_factor", speed_factor), ("load_factor", load_factor)):
        if not (np.isfinite(v) and v > 0):
            raise ConfigError(f"{name}: must be a finite number > 0, got {v!r}")
    ens = EnsembleSpec(pin_error_m=0.0, bearing_clearance_tolerance=0.0)
    rng = np.random.default_rng(0)
    f, g, values = float(speed_factor), float(load_factor), {}
    upd: dict[str, Any] = {
        "input_speeds_rpm": {k: v * f for k, v in cfg.input_speeds_rpm.items()}}
    if getattr(cfg, "planetary_dynamics", None) is not None:
        upd.update(_planetary(cfg, ens, f, g, 1.0, rng, values))
    dy = getattr(cfg, "dynamics", None)
    if dy is not None and dy.simulation is not None:
        upd["dynamics"] = dy.model_copy(update={"simulation": _drive_sim(dy.simulation, f, g)})
    if getattr(cfg, "transmission", None) is not None:
        upd.update(_transmission(cfg, ens, f, g, 1.0, rng, values))
    return _validated(cfg, upd, f"operating point (speed × {f:g}, load × {g:g})")


def member_configs(cfg: GeardynConfig, spec: DiagnosisSpec, seed: int | None = None
                   ) -> list[Member]:
    """The baseline members of ``cfg`` (normally its healthy variant,
    :func:`geardyn.diagnosis.faults.healthy_variant`) under ``spec`` (``[diagnosis]``): one
    dynamic run per ``spec.baseline_seeds``, each measured ``ensemble.measurements_per_run``
    times, in run-major order. ``seed`` is the seed of the perturbation draws (default
    ``spec.ensemble.seed``). Each member's config is validated again (a perturbed value that
    breaks a rule raises ConfigError naming the field and the member)."""
    ens = spec.ensemble
    seed = ens.seed if seed is None else int(seed)
    if seed < 0:
        raise ConfigError(f"diagnosis.ensemble.seed: must be >= 0, got {seed}")
    _check(cfg, ens)
    members: list[Member] = []
    for i, s in enumerate(spec.baseline_seeds):
        dyn_update, dyn_values = _dynamics_update(cfg, ens, np.random.default_rng([seed, s, 0]))
        for j in range(ens.measurements_per_run):
            label = f"run {i} (seed {s}), measurement {j}"
            sensors, sens_values = _sensors(cfg, ens, np.random.default_rng([seed, s, 1, j]), j)
            variant = _validated(cfg, {**dyn_update, "sensors": sensors}, label)
            values = {"run": i, "measurement": j, "seed": int(s), "ensemble_seed": seed,
                      **dyn_values, "sensors": sens_values}
            members.append(Member(label, variant, int(s), i, j, values))
    return members


def baseline_runs(healthy_cfg: GeardynConfig, spec: DiagnosisSpec) -> list[list[Member]]:
    """The members of :func:`member_configs` grouped by dynamic run (run order): each group is
    one simulation measured by its members' sensors (:func:`simulate_run`)."""
    by_run: dict[int, list[Member]] = {}
    for m in member_configs(healthy_cfg, spec):
        by_run.setdefault(m.run, []).append(m)
    return list(by_run.values())


def simulate_run(group: Sequence[Member], run_length: dict[str, float | None],
                 progress: Progress | None = None, runs: int = 1
                 ) -> Iterator[tuple[Member, xr.Dataset]]:
    """Simulate one dynamic run of the baseline ensemble (``group``: its members, one run of
    :func:`baseline_runs`) once without sensors (:func:`geardyn.run.run_simulation` with
    ``run_length``: ``t_end_s`` or ``revolutions``) and yield ``(member, measured result)``
    for each member (:func:`geardyn.run.add_sensors` on a shallow copy: the dynamic arrays are
    shared, not copied). The result's ``attrs`` carry ``ensemble_member`` (the label); its
    ``status`` is the caller's to check. ``progress(message, fraction)`` reports the fraction
    of ``runs`` runs done (this run being run ``group[0].run``)."""
    from geardyn.run import add_sensors, run_simulation

    first = group[0]
    i = first.run
    what = f"healthy baseline run {i + 1}/{runs} (seed {first.seed})"

    def tick(frac: float) -> None:
        if progress is not None:
            progress(f"simulating {what}", min(1.0, (i + 0.95 * frac) / runs))

    bare = first.config.model_copy(update={"sensors": []})
    ds = run_simulation(bare, seed=first.seed, progress=tick, **run_length)
    for m in group:
        if progress is not None:
            progress(f"measuring {m.label}", min(1.0, (i + 0.95 + 0.05 * m.measurement
                                                       / len(group)) / runs))
        meas = add_sensors(m.config, ds.copy(deep=False), m.seed)
        meas.attrs["ensemble_member"] = m.label
        yield m, meas


def simulate_baseline(healthy_cfg: GeardynConfig, spec: DiagnosisSpec,
                      run_length: dict[str, float | None],
                      progress: Progress | None = None) -> Iterator[tuple[Member, xr.Dataset]]:
    """Simulate and measure the baseline ensemble of ``healthy_cfg``: yields ``(member,
    measured result)`` in :func:`member_configs` order, one dynamic run at a time
    (:func:`simulate_run` over :func:`baseline_runs`). ``progress(message, fraction)``
    reports the fraction of the runs done."""
    groups = baseline_runs(healthy_cfg, spec)
    for group in groups:
        yield from simulate_run(group, run_length, progress, runs=len(groups))
