"""Time simulation of the ``[dynamics]`` model: drives, initial state, integration, result layout.

Drives reuse the integrator's torque elements (:mod:`geardyn.solve.integrate`): speed controls,
motor speed–torque curves (seed 004 TorM, Kloss), the fluid coupling T = q ω_m (ω_m − ω_p)
(seed 004 eq 6.6, here on the body it drives directly: ``coupling_ratio`` 1 unless given), the
bucket-wheel load T = T_fl G (ω/ω_ref)² s(θ) (seed 004 ch. 6) and tabulated torques. They act
on bodies with a coordinate of their own: links turning in the frame and rotors.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import xarray as xr

from geardyn.config.dynamics import Dynamics, DynamicsSimulation
from geardyn.errors import ConfigError, InputError
from geardyn.models.core.graph import model_from_config
from geardyn.models.core.model import CoreModel
from geardyn.operating import (
    RPM,
    BucketWheelSchedule,
    KlossMotor,
    PiecewiseMotor,
    held_profile,
    reference_angle_table,
)
from geardyn.results import finish, shaft_variables
from geardyn.solve.control import RunControl
from geardyn.solve.integrate import (
    FLUID_COUPLING,
    SPEED_CONTROL,
    SPEED_SQUARED_LOAD,
    SPEED_TORQUE,
    IntegrationResult,
    LinearSystem,
    MassSchedule,
)

WHERE = "dynamics.simulation"


@dataclass
class Prepared:
    """Model, integrator system and rigid-body initial state of a ``[dynamics]`` run."""

    model: CoreModel
    system: LinearSystem
    q0: np.ndarray
    v0: np.ndarray
    t_end_s: float
    sim: DynamicsSimulation


def _dof(model: CoreModel, body: str, where: str) -> int:
    b = model.body(body)
    if b.dof is None:
        raise ConfigError(f"{where}: '{body}' turns in another moving link, so it has no "
                          "coordinate of its own; drives and loads act on links turning in the "
                          "frame or on rotors")
    return b.dof


def _held(points: object, t_end: float, field: str, unit: str) -> tuple[np.ndarray, np.ndarray]:
    try:
        return held_profile(points, t_end, field, unit, stacklevel=4)
    except InputError as e:
        raise ConfigError(str(e)) from None


def drive_rows(model: CoreModel, sim: DynamicsSimulation, t_end: float
               ) -> tuple[list[dict], np.ndarray, np.ndarray, MassSchedule | None]:
    """Torque elements, force-table times (s), forces (N·m per coordinate) and the bucket
    wheel's inertia schedule (or None)."""
    drives: list[dict] = []
    profiles = {i: _held(t.profile, t_end, f"{WHERE}.torques[{i}].profile", "N·m")
                for i, t in enumerate(sim.torques) if t.profile}
    t_grid = np.array([0.0, t_end])
    if profiles:
        t_grid = np.linspace(0.0, max(t_end, *(ts[-1] for ts, _ in profiles.values())), 2001)
    force = np.zeros((len(t_grid), model.n))
    for i, t in enumerate(sim.torques):
        j = _dof(model, t.body, f"{WHERE}.torques[{i}]")
        force[:, j] += np.interp(t_grid, *profiles[i]) if i in profiles else t.torque_nm
    for i, sc in enumerate(sim.speed_controls):
        j = _dof(model, sc.body, f"{WHERE}.speed_controls[{i}]")
        ts, rpm = _held(sc.profile_rpm, t_end, f"{WHERE}.speed_controls[{i}].profile_rpm", "rpm")
        t_pad = 1.01 * t_end + 1e-3
        if ts[-1] < t_pad:
            ts, rpm = np.append(ts, t_pad), np.append(rpm, rpm[-1])
        # held 1 s before t = 0 too, with θ_ref(0) = 0: the kernel's reference speed is a
        # central difference over ±h that a table starting at 0 would halve for t < h
        ts, rpm = np.insert(ts, 0, ts[0] - 1.0), np.insert(rpm, 0, rpm[0])
        tt, th = reference_angle_table(ts, rpm * RPM)
        th = th - np.interp(0.0, tt, th)
        drives.append(dict(kind=SPEED_CONTROL, a=j, p0=sc.stiffness_nm_per_rad,
                           p1=sc.damping_nms_per_rad, x=tt, y=th))
    if sim.motor:
        mo = sim.motor
        j = _dof(model, mo.rotor, f"{WHERE}.motor.rotor")
        if mo.kind == "piecewise":
            motor = PiecewiseMotor(mo.rated_power_w, mo.rated_speed_rpm, mo.frequency_hz,
                                   mo.poles)
        else:
            motor = KlossMotor(mo.breakdown_torque_nm, mo.breakdown_slip, mo.kloss_a,
                               mo.kloss_b, 120 * mo.frequency_hz / mo.poles)
        wx, ty = motor.table()
        drives.append(dict(kind=SPEED_TORQUE, a=j, x=wx, y=ty))
        if mo.coupling_to:
            jb = _dof(model, mo.coupling_to, f"{WHERE}.motor.coupling_to")
            drives.append(dict(kind=FLUID_COUPLING, a=j, b=jb, p0=mo.coupling_q,
                               p1=mo.coupling_ratio))
    schedule = None
    if sim.wheel_load:
        wl = sim.wheel_load
        j = _dof(model, wl.body, f"{WHERE}.wheel_load.body")
        sch = BucketWheelSchedule()
        th = np.linspace(0, sch.points()["P47"] + 1.0, 4001)
        fac = sch.load_factor(th, wl.control_ratio) if wl.schedule else np.ones(len(th))
        w_ref = wl.control_ratio * wl.rated_speed_rpm / wl.gear_ratio * RPM
        drives.append(dict(kind=SPEED_SQUARED_LOAD, a=j,
                           p0=wl.full_load_torque_nm * wl.gear_ratio / w_ref**2, x=th, y=fac))
        if wl.inertia_schedule:
            # seed 004 inertiaC: empty wheel + ore bucket-loads vs carrier angle, replacing the
            # link's own inertia on its diagonal (planets' orbit terms kept)
            jj = wl.empty_inertia_kgm2 + wl.ore_inertia_kgm2 * sch.ore(th)
            extra = model.M[j, j] - model.body(wl.body).inertia
            schedule = MassSchedule(np.array([j]), np.array([j]), np.array([1.0]), th[None, :],
                                    (extra + jj)[None, :], np.array([len(th)]))
    return drives, t_grid, force, schedule


def rigid_velocity(model: CoreModel, speeds_rpm: dict[str, float]) -> np.ndarray:
    """q̇ of the rigid-body motion with the given body speeds (rpm): every mesh and shaft
    undeformed (least squares, the given speeds weighted ×1000)."""
    if not speeds_rpm:
        return np.zeros(model.n)
    rows = [m.a / max(np.abs(m.a).max(), 1e-300) for m in model.meshes]
    rows += [s.a for s in model.springs]
    rhs = [0.0] * len(rows)
    for body, rpm in speeds_rpm.items():
        rows.append(model.body(body).rotation * 1e3)
        rhs.append(rpm * RPM * 1e3)
    sol, *_ = np.linalg.lstsq(np.array(rows), np.array(rhs), rcond=None)
    return sol


def prepare(cfg: object, t_end_s: float | None = None) -> Prepared:
    """Model, system and initial state of the config's ``[dynamics.simulation]``."""
    spec: Dynamics | None = getattr(cfg, "dynamics", None)
    if spec is None or spec.simulation is None:
        raise ConfigError("dynamics.simulation is missing (t_end_s, dt_s, drives)")
    sim = spec.simulation
    t_end = sim.t_end_s if t_end_s is None else float(t_end_s)
    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"t_end_s: the run end must be a finite time > 0 s (got {t_end_s!r})")
    model = model_from_config(cfg)
    drives, t_grid, force, schedule = drive_rows(model, sim, t_end)
    v0 = rigid_velocity(model, dict(sim.initial_speed_rpm))

    backlash = mesh_backlash(cfg, model)

    def build() -> LinearSystem:
        system = model.system((sim.rayleigh_alpha, sim.rayleigh_beta), drives, t_grid, force,
                              sim.contact_loss, schedule, sim.gyroscopic)
        system.springs.backlash = backlash.copy()
        return system

    q_static = orient_meshes(model, build(), v0)
    system = build()
    from geardyn.solve.sanity import check_time_step, mesh_period, shortest_period

    check_time_step(sim.dt_s, f"{WHERE}.dt_s", shortest_period(system),
                    mesh_period(system, [v0]))
    q0 = q_static if sim.initial_state == "static" else np.zeros(model.n)
    return Prepared(model, system, q0, v0, t_end, sim)


def mesh_backlash(cfg: object, model: CoreModel) -> np.ndarray:
    """Backlash (m) of every mesh of ``model``: ``backlash_m`` of its ``[[dynamics.meshes]]``
    entry (pair name, then ``<stage>.sun|ring``, then the stage name), 0 without one. The
    contact law is :func:`geardyn.solve.integrate._contact` on the oriented deflection
    (:func:`orient_meshes`: δ > 0 on the flank loaded by the initial drives)."""
    from geardyn.models.core.graph import _pair_size

    spec: Dynamics = cfg.dynamics  # type: ignore[attr-defined]
    graph = {m.name: m for m in cfg.graph().meshes}  # type: ignore[attr-defined]
    return np.array([_pair_size(graph[m.name], spec).settings.backlash_m
                     if m.name in graph else 0.0 for m in model.meshes], float)


def orient_meshes(model: CoreModel, system: LinearSystem, v0: np.ndarray) -> np.ndarray:
    """Orient every mesh so that its deflection is positive on the flank loaded by the
    initial drive torques (contact loss, seed 004 eq 3.2, is δ < 0; mesh forces come out
    positive under load).

    Quasi-static deflection under the initial loads f = F − C v₀ (drives, torques): the rigid
    part of f accelerates the rigid-body modes (Φ mass-normalised null space of K + speed-control
    stiffness), the rest deflects the springs, K q = f − M Φ Φᵀ f. A mesh with aᵀq < 0 has
    its row (and error table) negated; unloaded meshes keep their sign. Returns q (the
    ``initial_state = "static"`` start).
    """
    from geardyn.solve.integrate import reference_rhs

    n = model.n
    d = system.drives
    acc = reference_rhs(system)(0.0, np.concatenate([np.zeros(n), v0]))[n:]
    f = system.M @ acc
    k = model.stiffness_matrix()
    for i in range(d.kind.shape[0]):
        if d.kind[i] == SPEED_CONTROL:
            k[d.a[i], d.a[i]] += d.p0[i] * d.ha[i] ** 2
    import scipy.linalg as sla

    null = sla.null_space(k, rcond=1e-10)
    if null.shape[1]:
        mn = null.T @ system.M @ null
        f = f - system.M @ null @ np.linalg.solve(mn, null.T @ f)
    q, *_ = np.linalg.lstsq(k, f, rcond=1e-12)
    for m in model.meshes:
        delta = float(m.a @ q)
        if delta < -1e-12 * max(float(np.abs(m.a).max()) * float(np.abs(q).max()), 1e-300):
            m.a = -m.a
            m.e = -m.e
    return q


def integrate(p: Prepared, progress: Callable[[float], None] | None = None,
              control: RunControl | None = None) -> IntegrationResult:
    """Run the prepared system with the configured solver. ``control``
    (:class:`~geardyn.solve.control.RunControl`: progress, stop requests, checkpoints) drives the
    compiled Newmark loop; the low-rank solver takes its progress callback only."""
    sim = p.sim
    if sim.solver == "lowrank":
        from geardyn.solve.lowrank import newmark_lowrank

        if progress is None and control is not None:
            progress = control.progress
        return newmark_lowrank(p.system, p.q0, p.v0, p.t_end_s, sim.dt_s,
                               save_every=sim.save_every, alpha=sim.hht_alpha, progress=progress)
    from geardyn.solve.integrate import newmark

    return newmark(p.system, p.q0, p.v0, p.t_end_s, sim.dt_s, save_every=sim.save_every,
                   alpha=sim.hht_alpha, progress=progress, control=control)


def to_dataset(model: CoreModel, res: IntegrationResult, reference: str,
               attrs: dict | None = None) -> xr.Dataset:
    """Result layout of docs/results.md: angle/speed/speed_rpm per shaft (every moving link and
    rotor, about its own axis), mesh stiffness, deflection and force, q and v."""
    mesh_names = [m.name for m in model.meshes]
    ds = xr.Dataset(
        {
            "q": (("time", "dof"), res.q, {"units": "rad"}),
            "v": (("time", "dof"), res.v, {"units": "rad/s"}),
            "mesh_stiffness": (("time", "mesh"), res.k, {"units": "N/m"}),
            "mesh_deflection": (("time", "mesh"), res.delta,
                                {"units": "m", "long_name": "dynamic transmission error along "
                                 "the line of action (incl. excitation error)"}),
            "mesh_force": (("time", "mesh"), res.k * res.delta, {"units": "N"}),
        },
        coords={"time": ("time", res.t, {"units": "s"}), "dof": model.dof_names,
                "mesh": mesh_names},
        attrs={"status": res.status, "diagnosis": res.diagnosis, "wall_time_s": res.wall_s,
               **(attrs or {})},
    )
    names = list(model.bodies)
    rot = model.rotation_matrix()
    ds = ds.assign(shaft_variables(res.t, names, res.q @ rot.T, res.v @ rot.T))
    ds = ds.assign_coords(shaft=names)
    bearings = [s for s in model.springs if s.kind == "bearing"]
    if bearings:  # lateral model: force k aᵀq of every bearing spring (one per direction)
        a = np.array([s.a for s in bearings])
        k = np.array([s.k for s in bearings])
        ds["bearing_force"] = (("time", "bearing"), (res.q @ a.T) * k, {"units": "N"})
        ds = ds.assign_coords(bearing=[s.name for s in bearings])
    return finish(ds, "mechanism", reference if reference in names else names[0])


def simulate(cfg: object, t_end_s: float | None = None,
             progress: Callable[[float], None] | None = None,
             control: RunControl | None = None) -> xr.Dataset:
    """Simulate the config's ``[dynamics]`` model; result in the layout of docs/results.md.

    The time step is checked before the run (shortest natural period, mesh period at the initial
    speeds: refused or warned naming ``dynamics.simulation.dt_s``) and the energy balance after it
    (status ``suspect`` when it does not close; not booked with an inertia schedule or the
    low-rank solver)."""
    from geardyn.solve.sanity import check_energy, check_time_step, mesh_period, shortest_period

    p = prepare(cfg, t_end_s)
    check_time_step(p.sim.dt_s, "dynamics.simulation.dt_s", shortest_period(p.system),
                    mesh_period(p.system, [p.v0]))
    res = integrate(p, progress, control)
    ref = next(iter(getattr(cfg, "input_speeds_rpm", {}) or {}), "")
    if p.sim.motor is not None:
        ref = p.sim.motor.rotor
    ds = to_dataset(p.model, res, ref, {"dt_s": p.sim.dt_s, "hht_alpha": p.sim.hht_alpha,
                                        "solver": p.sim.solver})
    ds.attrs.update({f"energy_{k}": v for k, v in res.energy.items()})
    if ds.attrs["status"] == "ok" and len(p.system.mass_schedule.dof) == 0:
        problem = check_energy(res.energy)
        if problem:
            ds.attrs["status"] = "suspect"
            ds.attrs["diagnosis"] = problem
    return ds
