"""Run the config's dynamic model and its sensors: one entry point for every simulator.

:func:`run_simulation` picks the model from the config (``[planetary_dynamics]`` lumped model
or ``[transmission]`` FE model), integrates it and applies ``[[sensors]]``; the result is in the
layout of docs/results.md whatever the model.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable

import numpy as np
import xarray as xr

from geardyn.errors import ConfigError, GeardynError, InputError
from geardyn.sensors.channels import RingSet, SensorContext, apply_sensors
from geardyn.solve.control import RunControl
from geardyn.solve.sanity import (
    MIN_STEPS_PER_MESH_REFUSE,
    check_energy,
    check_time_step,
    mesh_period,
    shortest_period,
)


def run_simulation(cfg, seed: int = 0, t_end_s: float | None = None,  # noqa: ANN001
                   revolutions: float | None = None,
                   progress: Callable[[float], None] | None = None,
                   control: RunControl | None = None, model: str | None = None,
                   prepared=None) -> xr.Dataset:  # noqa: ANN001
    """Simulate ``cfg`` and measure it with its sensors.

    ``seed`` drives every random draw of the run (sensor noise, graduation errors, the seed 004
    random impulse errors when enabled): the same config and seed give the same result.
    ``t_end_s`` overrides the planetary run length, ``revolutions`` the FE speed law's.
    ``control`` (:class:`~geardyn.solve.control.RunControl`): progress, cost estimate, stop
    requests, checkpoints and resume of the chunked integration. ``model`` picks the model
    (:func:`simulated_model`: ``planetary``, ``mechanism`` or ``transmission``) when the config
    describes a lumped model and an FE transmission; ``prepared``: the FE model's
    :func:`geardyn.models.transmission.prepare` already computed (``geardyn transmission``
    prints its modes first), reused.

    The time step is checked before the run (:func:`geardyn.solve.sanity.check_time_step`:
    refused with an InputError naming it, or a :class:`~geardyn.solve.sanity.TimeStepWarning`).
    A diverged run returns its partial result with ``status = 'diverged'``, a stopped one with
    ``interrupted``, one failing the output checks (mesh deflection vs module, energy balance)
    with ``suspect`` (no exception; ``diagnosis`` says why). BLAS runs one thread during the
    run (:func:`geardyn.solve.determinism.single_thread_blas`): the same bits in any process.
    """
    from geardyn.solve.determinism import single_thread_blas

    with single_thread_blas():
        return _run_simulation(cfg, seed, t_end_s, revolutions, progress, control, model,
                               prepared)


def _run_simulation(cfg, seed: int = 0, t_end_s: float | None = None,  # noqa: ANN001
                    revolutions: float | None = None,
                    progress: Callable[[float], None] | None = None,
                    control: RunControl | None = None, model: str | None = None,
                    prepared=None) -> xr.Dataset:  # noqa: ANN001
    """:func:`run_simulation` without the BLAS thread limit."""
    if not isinstance(seed, int | np.integer) or seed < 0:
        raise InputError(f"seed: must be an integer >= 0, got {seed!r}")
    if t_end_s is not None and not (math.isfinite(t_end_s) and t_end_s > 0):
        raise InputError(f"t_end_s: must be a finite time > 0 s, got {t_end_s!r}")
    from geardyn.config.sensors import sensor_name_problems

    problems = sensor_name_problems(cfg)  # before the run, not after it
    if problems:
        raise InputError("\n".join(problems))
    ctl = control or RunControl(progress=progress)
    if progress is not None and ctl.progress is None:
        ctl.progress = progress
    kind = simulated_model(cfg, model)
    from geardyn.resources import check_run

    check_run(cfg, kind, t_end_s, revolutions)  # before any allocation
    if kind == "planetary":
        ds = _planetary(cfg, int(seed), t_end_s, ctl)
    elif kind == "mechanism":
        from geardyn.models.core.simulate import simulate as simulate_mechanism

        ds = simulate_mechanism(cfg, t_end_s, control=ctl)
    else:
        ds = _transmission(cfg, revolutions, t_end_s, ctl, prepared)
    return add_sensors(cfg, ds, int(seed))


#: Names of the simulated models (``--model`` of ``geardyn simulate`` and ``geardyn modes``).
MODELS = ("planetary", "mechanism", "transmission")


def simulated_model(cfg, model: str | None = None) -> str:  # noqa: ANN001
    """The model ``run_simulation`` runs: ``planetary`` (``[planetary_dynamics]`` with its
    ``simulation``), ``mechanism`` (``[dynamics]`` with its ``simulation``) or ``transmission``
    (the FE shaft lines of ``[transmission]``). Without ``model``: the one the config describes
    (planetary before mechanism, as before); a lumped model and a ``[transmission]`` together
    are ambiguous (ConfigError asking for ``model``)."""
    have = []
    pdyn = getattr(cfg, "planetary_dynamics", None)
    if pdyn is not None and pdyn.simulation is not None:
        have.append("planetary")
    dyn = getattr(cfg, "dynamics", None)
    if dyn is not None and dyn.simulation is not None:
        have.append("mechanism")
    if getattr(cfg, "transmission", None) is not None:
        have.append("transmission")
    if model is not None:
        if model not in MODELS:
            raise InputError(f"model: must be one of {', '.join(MODELS)}, got {model!r}")
        if model not in have:
            section = {"planetary": "[planetary_dynamics] with [planetary_dynamics.simulation]",
                       "mechanism": "[dynamics] with [dynamics.simulation]",
                       "transmission": "[transmission]"}[model]
            raise ConfigError(f"model '{model}': the config has no {section}")
        return model
    if not have:
        raise ConfigError("nothing to simulate: the config has no [planetary_dynamics] section "
                          "with [planetary_dynamics.simulation], no [dynamics] section with "
                          "[dynamics.simulation] and no [transmission]")
    if "transmission" in have and len(have) > 1:
        raise ConfigError(f"the config describes {len(have)} models ({', '.join(have)}): choose "
                          f"one with --model {' | '.join(have)}")
    return have[0]


def _reference(cfg, names: list[str]) -> str:  # noqa: ANN001
    for link in (getattr(cfg, "input_speeds_rpm", None) or {}):
        if link in names:
            return link
    return names[0]


def _seeded(cfg, seed: int):  # noqa: ANN001, ANN202
    """The config with the seed 004 random impulse errors re-seeded for run ``seed``."""
    pd = cfg.planetary_dynamics
    if seed == 0 or not any(sd.random_error_max_m > 0 for sd in pd.stages):
        return cfg
    stages = [sd.model_copy(update={"random_error_seed": sd.random_error_seed + 1_000_003 * seed})
              for sd in pd.stages]
    return cfg.model_copy(update={"planetary_dynamics": pd.model_copy(update={"stages": stages})})


def _planetary(cfg, seed: int, t_end_s: float | None,  # noqa: ANN001
               control: RunControl) -> xr.Dataset:
    from geardyn.models.planetary.build import prepare
    from geardyn.models.planetary.dynamics import to_dataset
    from geardyn.solve.integrate import newmark

    cfg = _seeded(cfg, seed)
    sim = cfg.planetary_dynamics.simulation
    t1 = sim.t_end_s if t_end_s is None else t_end_s
    p = prepare(cfg, t_end_s=t1)
    model = p.model
    names = body_links(cfg, model)
    check_time_step(sim.dt_s, "planetary_dynamics.simulation.dt_s",
                    shortest_period(p.system), mesh_period(p.system, _planetary_speeds(cfg, p)))
    res = newmark(p.system, p.q0, p.v0, t1, sim.dt_s, save_every=sim.save_every,
                  alpha=sim.hht_alpha, control=control)
    ds = to_dataset(model, res, p.mesh_index, {"dt_s": sim.dt_s, "hht_alpha": sim.hht_alpha},
                    shaft_names=names)
    ds.attrs["reference_shaft"] = _reference(cfg, [str(s) for s in ds["shaft"].values])
    ds.attrs.update({f"energy_{k}": v for k, v in res.energy.items()})
    _check_mesh_deflection(ds, cfg)
    if len(p.system.mass_schedule.dof) == 0:  # a mass schedule adds ½vᵀṀv: not booked
        _suspect(ds, check_energy(res.energy))
    if ds.attrs["status"] == "ok" and p.system.springs.a.shape[0]:
        # the mesh speeds reached (motor run-ups may exceed the estimate made before the run)
        tm = mesh_period(p.system, res.v)
        if tm is not None and tm / sim.dt_s < MIN_STEPS_PER_MESH_REFUSE:
            _suspect(ds, f"the mesh period fell to {tm:.4g} s during the run: "
                         f"{tm / sim.dt_s:.3g} steps per mesh cycle with "
                         f"planetary_dynamics.simulation.dt_s = {sim.dt_s:g} s (aliased)")
    return ds


def _suspect(ds: xr.Dataset, problem: str) -> None:
    """Status ``suspect`` with ``problem`` appended to the diagnosis (only an ``ok`` run)."""
    if not problem or ds.attrs.get("status") not in ("ok", "suspect"):
        return
    ds.attrs["status"] = "suspect"
    kept = "; the computed part is kept"
    ds.attrs["diagnosis"] = "; ".join(x for x in (str(ds.attrs.get("diagnosis", ""))
                                                  .removesuffix(kept), problem + kept) if x)


def _planetary_speeds(cfg, p) -> list[np.ndarray]:  # noqa: ANN001
    """Velocity states bounding the run's speeds before it starts: the initial state, each
    speed control at its largest profile speed, a motor's coupling at synchronous speed."""
    from geardyn.models.planetary.build import rigid_velocity

    sim = cfg.planetary_dynamics.simulation
    speeds = [np.asarray(p.v0, float)]
    targets = [{sc.body: max(abs(r) for _, r in sc.profile_rpm)} for sc in sim.speed_controls]
    mo = sim.motor
    if mo is not None and mo.coupling_to:
        targets.append({mo.coupling_to: 120.0 * mo.frequency_hz / mo.poles / mo.coupling_ratio})
    for tg in targets:
        try:
            speeds.append(rigid_velocity(p.model, tg))
        except (GeardynError, KeyError, ValueError):  # a body the model does not know
            continue
    return speeds


#: A mesh deflection beyond this fraction of the module is not a gear mesh any more.
MAX_DEFLECTION_PER_MODULE = 0.1


def _check_mesh_deflection(ds: xr.Dataset, cfg) -> None:  # noqa: ANN001
    """Status ``suspect`` when a mesh deflects more than :data:`MAX_DEFLECTION_PER_MODULE` of
    its module (module = 2 r_b,sun / (z_sun cos α_s), seed 003 Table 3.1 radii): typically a
    time step far too large for the mesh stiffness, whose run still ends without overflow."""
    if ds.attrs.get("status") != "ok" or "mesh_deflection" not in ds:
        return
    stages = {s.name: s for s in cfg.planetary}
    worst = []
    for sd in cfg.planetary_dynamics.stages:
        z = stages[sd.stage].sun_teeth
        module = 2 * sd.sun.base_radius_m / (z * math.cos(math.radians(sd.pressure_angle_sun_deg)))
        names = [str(m) for m in ds["mesh"].values]
        if len(cfg.planetary_dynamics.stages) > 1:
            names = [m for m in names if m.startswith(f"{sd.stage}.")]
        if not names:
            continue
        d = float(np.nanmax(np.abs(_compression(ds["mesh_deflection"].sel(mesh=names).values,
                                                 _stage_backlash(sd, names)))))
        if not math.isfinite(d) or d > MAX_DEFLECTION_PER_MODULE * module:
            worst.append(f"stage '{sd.stage}': mesh deflection up to {d * 1e3:.3g} mm for a "
                         f"module of {module * 1e3:.3g} mm")
    if worst:
        ds.attrs["status"] = "suspect"
        ds.attrs["diagnosis"] = ("; ".join(worst) + f" (more than {MAX_DEFLECTION_PER_MODULE:g}"
                                 " × module): reduce simulation.dt_s or check the stiffnesses "
                                 "and loads; the computed part is kept")


def _stage_backlash(sd, names: list[str]) -> np.ndarray:  # noqa: ANN001 - StageDynamics
    """Backlash (m) of each named mesh of a stage: its sun or ring mesh law."""
    return np.array([(sd.sun_mesh if n.endswith("mesh_sun") else sd.ring_mesh).backlash_m
                     for n in names])


def _compression(delta: np.ndarray, backlash: np.ndarray) -> np.ndarray:
    """Tooth compression of meshes with backlash b: δ on the drive flank (δ ≥ 0), δ + b on
    the back flank (δ ≤ −b), 0 while the teeth are apart; the gap itself is no deflection."""
    return np.where(delta >= 0, delta, np.minimum(delta + backlash, 0.0))


def body_links(cfg, model) -> dict[str, str]:  # noqa: ANN001
    """Shaft name of each planetary-model body: its mechanism link for sun, carrier and a
    turning ring, the body name otherwise (planets, rotors, a ring fixed in the frame)."""
    frame = getattr(cfg, "frame", None)
    stages = {s.name: s for s in getattr(cfg, "planetary", [])}
    out = {b: b for b in model.bodies}
    for st, info in model.stages.items():
        mech = stages.get(st)
        if mech is None:
            continue
        for role in ("sun", "carrier", "ring"):
            link = getattr(mech, role, None)
            if isinstance(link, str) and link != frame:
                out[info.bodies[role]] = link
    if len(set(out.values())) != len(out):  # two bodies on one link: keep body names
        return {b: b for b in model.bodies}
    return out


def _transmission(cfg, revolutions: float | None, t_end_s: float | None,  # noqa: ANN001
                  control: RunControl, prepared=None) -> xr.Dataset:  # noqa: ANN001
    from geardyn.models.transmission import simulate
    from geardyn.models.transmission.simulate import SimulationDivergedError

    if t_end_s is not None:
        warnings.warn("t_end_s does not apply to the FE transmission (its speed law sets the "
                      "run length); use revolutions", stacklevel=3)
    try:
        ds = simulate(cfg, revolutions=revolutions, prepared=prepared, control=control,
                      check_step=True)
    except SimulationDivergedError as exc:
        ds = exc.result
    return ds


def sensor_context(cfg, ds: xr.Dataset) -> SensorContext:  # noqa: ANN001
    """What the sensors need to know of the model behind result ``ds``: ring sets of the
    planetary stages (carrier and ring shafts, planet angles, ring meshes) and the force column
    of every bearing location."""
    ctx = SensorContext(str(ds.attrs.get("reference_shaft", ds["shaft"].values[0])))
    if ds.attrs.get("model") == "planetary":
        from geardyn.models.planetary.build import model_from_config

        model = model_from_config(cfg)
        names = dict(zip([str(b) for b in ds["body"].values],
                         [str(s) for s in ds["shaft"].values], strict=True))
        for st, info in model.stages.items():
            planets = [info.bodies[f"planet{i + 1}"] for i in range(len(info.psi))]
            ctx.rings[st] = RingSet(names[info.bodies["carrier"]], names[info.bodies["ring"]],
                                    np.asarray(info.psi, float),
                                    [f"{pl}.mesh_ring" for pl in planets])
    if any(s.kind == "transmission_error" for s in getattr(cfg, "sensors", [])):
        from geardyn.kinematics import analyze_kinematics

        g = analyze_kinematics(cfg).graph
        ctx.meshes = {m.name: (m.link_a, m.teeth_a, m.link_b, m.teeth_b) for m in g.meshes}
    if "bearing" in ds.coords:
        for b in ds["bearing"].values:
            b = str(b)
            if "axis" in ds["bearing_force"].dims:  # FE: force (x, y) on the housing
                for d in ("x", "y"):
                    ctx.bearings[(b, d)] = ("bearing_force", {"bearing": b, "axis": d})
                continue
            body, _, axis = b.rpartition(".bearing.")  # lumped: one spring per direction
            d = {"x": "x", "y": "y", "zeta": "x", "eta": "y"}.get(axis)
            if d:
                ctx.bearings[(body, d)] = ("bearing_force", {"bearing": b})
    return ctx


def add_sensors(cfg, ds: xr.Dataset, seed: int = 0) -> xr.Dataset:  # noqa: ANN001
    """Measure result ``ds`` of ``cfg``'s model with the config's ``[[sensors]]``."""
    ds.attrs["seed"] = int(seed)
    if getattr(cfg, "sensors", None):
        apply_sensors(ds, list(cfg.sensors), int(seed), sensor_context(cfg, ds))
    return ds
