"""Statics and time simulation of a :class:`PlanetaryModel` (SI units).

Mesh stiffness varies with the mesh position X (mesh cycles) computed from the integrated
body angles: sun mesh X = z_s(θ_s − θ_c)/2π, ring mesh X = z_r(θ_c − θ_r)/2π (rigid-body
rotation included in u). Planet n's meshes are offset by its phases from
:func:`geardyn.gears.planet_mesh_phases` (seed 004 Table 4-1): X_sn = X + rs_n ≡ X − z_sψ_n/2π
and X_rn = X + rr_n ≡ X + z_rψ_n/2π (a sun tooth meets planet n ψ_n after planet 1; planet n
meets a ring tooth 2π − ψ_n after planet 1), and the ring meshes by −γ_rs (seed 004 Table 4-2).
Transmission errors enter as displacement excitation δ = aᵀq + e (seed 004 eq 3.1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from geardyn.errors import InputError
from geardyn.gears import planet_mesh_phases
from geardyn.models.core.system import linear_system
from geardyn.models.planetary.model import PlanetaryModel
from geardyn.results import finish, shaft_variables
from geardyn.solve.control import RunControl
from geardyn.solve.integrate import IntegrationResult, LinearSystem, MassSchedule, newmark


@dataclass
class MeshLaw:
    """Stiffness k(X) (N/m) and error e(X) (m) of one mesh type over ``period`` mesh cycles.

    ``per_planet`` optionally overrides (k, e, period) for individual planets (1-based), e.g.
    a cracked sun tooth table spanning z_s cycles; X = 0 is the pitch-point entry of planet 1.
    """

    k: np.ndarray
    period: float = 1.0
    e: np.ndarray = field(default_factory=lambda: np.zeros(1))
    e_period: float = 1.0
    per_planet: dict[int, tuple[np.ndarray, float, np.ndarray, float]] = field(
        default_factory=dict)
    integer_offsets: bool = False  # use −w exactly (tables spanning whole gear revolutions)

    @staticmethod
    def constant(k: float) -> MeshLaw:
        return MeshLaw(np.array([float(k)]))


def mesh_coordinate(model: PlanetaryModel, stage: str, mesh: str) -> np.ndarray:
    """Row vector b with X = b q (mesh cycles) for the stage's sun or ring mesh."""
    info = model.stages[stage]
    if mesh == "sun":
        z = info.z_sun
        v = model.rotation_vector(info.bodies["sun"])
        v = v - model.rotation_vector(info.bodies["carrier"])
    else:
        z = info.z_ring
        v = model.rotation_vector(info.bodies["carrier"])
        v = v - model.rotation_vector(info.bodies["ring"])
    if z <= 0:
        raise InputError(f"stage '{stage}': tooth numbers are needed for time-varying meshes")
    return z * v / (2 * math.pi)


def spring_rows(
    model: PlanetaryModel,
    laws: dict[tuple[str, str], MeshLaw],
    mesh_damping: float = 0.0,
    contact_loss: bool = False,
    ring_phase: dict[str, float] | None = None,
) -> tuple[list[dict], list[int]]:
    """Variable-spring rows for the integrator and the indices of those springs in the model."""
    rows, idx = [], []
    a_all = model.spring_vectors()
    for i, s in enumerate(model.springs):
        if s.kind not in ("mesh_sun", "mesh_ring"):
            continue
        which = "sun" if s.kind == "mesh_sun" else "ring"
        law = laws.get((s.stage, which))
        if law is None:
            continue
        info = model.stages[s.stage]
        rs, rr = planet_mesh_phases(info.z_sun, info.z_ring, info.psi)
        n = s.planet - 1
        if law.integer_offsets:
            w = (info.z_sun if which == "sun" else info.z_ring) * (info.psi[n] - info.psi[0]) / (
                2 * math.pi)
            x0 = -w if which == "sun" else w
        else:
            x0 = rs[n] if which == "sun" else rr[n]
        if which == "ring" and ring_phase:
            x0 -= ring_phase.get(s.stage, 0.0)
        k, per, e, eper = law.k, law.period, law.e, law.e_period
        if s.planet in law.per_planet:
            k, per, e, eper = law.per_planet[s.planet]
        rows.append(dict(a=a_all[i], b=mesh_coordinate(model, s.stage, which), x0=x0,
                         k=np.asarray(k, float), k_period=per, e=np.asarray(e, float),
                         e_period=eper, c=mesh_damping, contact_loss=contact_loss))
        idx.append(i)
    return rows, idx


def build_system(
    model: PlanetaryModel,
    laws: dict[tuple[str, str], MeshLaw] | None = None,
    drives: list[dict] | None = None,
    force_t: np.ndarray | None = None,
    force: np.ndarray | None = None,
    rayleigh: tuple[float, float] = (0.0, 0.0),
    support_damping: dict[str, float] | None = None,
    mesh_damping: float = 0.0,
    contact_loss: bool = False,
    ring_phase: dict[str, float] | None = None,
    mass_schedule: MassSchedule | None = None,
    modal_damping: float = 0.0,
    gyroscopic: bool = False,
) -> tuple[LinearSystem, list[int]]:
    """Integrator system: constant springs in K₀, meshes with a law as variable springs.

    Damping: Rayleigh C = α M + β K_mean (seed 003 eq 1.16), plus viscous dampers on DOFs
    (``support_damping``: DOF name → N·s/m) and along each mesh line (``mesh_damping``), and
    modal damping ratio ζ on every elastic mode of the mean-stiffness model:
    C += M Φ diag(2ζω_i) Φᵀ M with mass-normalised Φ (seed 003 eq 1.16, c_i = 2 m_i ω_i ζ_i).
    ``gyroscopic``: add Ω_c G q̇ − Ω_c² K_Ω q per stage with Ω_c its current carrier speed
    (seed 003 eq 3.1). Built by :func:`geardyn.models.core.system.linear_system` on the
    model's assembly.
    """
    rows, idx = spring_rows(model, laws or {}, mesh_damping, contact_loss, ring_phase)
    sys = linear_system(model.assembly, rows, idx, transform=model.T, names=model.names,
                        rayleigh=rayleigh, modal_damping=modal_damping,
                        support_damping=support_damping, drives=drives, force_t=force_t,
                        force=force, mass_schedule=mass_schedule, gyroscopic=gyroscopic)
    return sys, idx


def static_solve(model: PlanetaryModel, loads: dict[str, float], fixed: list[str] | None = None,
                 errors: dict[str, float] | None = None) -> np.ndarray:
    """Static deflection K q = F with mean stiffness; ``loads``: DOF name → force (N; a torque
    T on a ``u`` DOF is T/r). ``fixed`` DOFs are held at 0 (e.g. the driving shaft), which
    removes rigid-body modes. ``errors``: spring name → displacement offset e (m) in
    δ = aᵀq + e (planet pin position errors, seed 003 eqs 5.4-5.5)."""
    n = len(model.names)
    f = np.zeros(n)
    for name, val in loads.items():
        f[model.dof(name)] += val
    a = model.spring_vectors()
    for name, e in (errors or {}).items():
        hit = [i for i, s in enumerate(model.springs) if s.name == name]
        if not hit:
            raise InputError(f"unknown spring '{name}' for an error")
        s = model.springs[hit[0]]
        f -= s.k * e * a[hit[0]]
    kk = model.stiffness_matrix()
    free = [i for i in range(n) if model.names[i] not in set(fixed or [])]
    q = np.zeros(n)
    sub = kk[np.ix_(free, free)]
    if np.linalg.matrix_rank(sub) < len(free):
        raise InputError("the static problem is singular: fix a DOF (e.g. the input shaft) "
                         "or add supports so that no rigid-body motion is left")
    q[free] = np.linalg.solve(sub, f[free])
    return q


def spring_forces(model: PlanetaryModel, q: np.ndarray, errors: dict[str, float] | None = None
                  ) -> dict[str, float]:
    """Force k(aᵀq + e) in every spring (N; positive in compression)."""
    a = model.spring_vectors()
    out = {}
    for i, s in enumerate(model.springs):
        e = (errors or {}).get(s.name, 0.0)
        out[s.name] = s.k * (a[i] @ q + e)
    return out


def load_sharing(model: PlanetaryModel, stage: str, forces: dict[str, float]) -> np.ndarray:
    """LSR_i = F_i / Σ F with F_i the sun + ring mesh force of planet i (seed 003 eq 5.1)."""
    info = model.stages[stage]
    n = len(info.psi)
    f = np.array([forces[f"{info.bodies[f'planet{i + 1}']}.mesh_sun"]
                  + forces[f"{info.bodies[f'planet{i + 1}']}.mesh_ring"] for i in range(n)])
    return f / f.sum()


def to_dataset(model: PlanetaryModel, res: IntegrationResult, idx: list[int],
               attrs: dict | None = None, shaft_names: dict[str, str] | None = None
               ) -> xr.Dataset:
    """xarray output in the geardyn result layout (docs/results.md): angle, speed and rpm of
    every body (``shaft``; ``shaft_names`` maps body → name, e.g. the mechanism link), q, v
    (time × dof), mesh stiffness, deflection (DTE), force per mesh, load-sharing ratio per
    planet of every stage (seed 003 eq 5.1), bearing forces."""
    names = model.names
    mesh_names = [model.springs[i].name for i in idx]
    k = res.k
    d = res.delta
    ds = xr.Dataset(
        {
            "q": (("time", "dof"), res.q, {"units": "m (u = r·θ; theta DOFs in rad)"}),
            "v": (("time", "dof"), res.v, {"units": "m/s (rad/s for theta DOFs)"}),
            "mesh_stiffness": (("time", "mesh"), k, {"units": "N/m"}),
            "mesh_deflection": (("time", "mesh"), d,
                                {"units": "m", "long_name": "dynamic transmission error "
                                 "along the line of action (incl. excitation error)"}),
            "mesh_force": (("time", "mesh"), k * d, {"units": "N"}),
        },
        coords={"time": ("time", res.t, {"units": "s"}), "dof": names, "mesh": mesh_names},
        attrs={"status": res.status, "diagnosis": res.diagnosis, "wall_time_s": res.wall_s,
               **(attrs or {})},
    )
    bodies = list(model.bodies)
    rot = np.array([model.rotation_vector(b) for b in bodies])  # θ = R q (rad)
    names_s = [(shaft_names or {}).get(b, b) for b in bodies]
    ds = ds.assign(shaft_variables(res.t, names_s, res.q @ rot.T, res.v @ rot.T))
    ds = ds.assign_coords(shaft=names_s, body=("shaft", bodies))
    ref = next((n for b, n in zip(bodies, names_s, strict=True)
                if model.bodies[b].kind == "rotor"), names_s[0])
    finish(ds, "planetary", ref)
    # load sharing per stage
    for st, info in model.stages.items():
        per = []
        for p in range(len(info.psi)):
            pn = info.bodies[f"planet{p + 1}"]
            cols = [j for j, m in enumerate(mesh_names) if m in (f"{pn}.mesh_sun",
                                                                   f"{pn}.mesh_ring")]
            if len(cols) != 2:
                break
            per.append((k[:, cols] * d[:, cols]).sum(1))
        if len(per) == len(info.psi) and per:
            tot = np.sum(per, axis=0)
            with np.errstate(divide="ignore", invalid="ignore"):
                lsr = np.array(per).T / tot[:, None]
            ds[f"lsr_{st}"] = (("time", f"planet_{st}"), lsr, {"units": "1",
                                                               "long_name": "load sharing ratio"})
    # bearing forces (constant springs)
    a = model.spring_vectors()
    bidx = [i for i, s in enumerate(model.springs) if s.kind in ("bearing", "planet_bearing")]
    if bidx:
        kb = np.array([model.springs[i].k for i in bidx])
        ds["bearing_force"] = (("time", "bearing"), (res.q @ a[bidx].T) * kb, {"units": "N"})
        ds = ds.assign_coords(bearing=[model.springs[i].name for i in bidx])
    return ds


def simulate(model: PlanetaryModel, sys: LinearSystem, idx: list[int], q0: np.ndarray,
             v0: np.ndarray, t_end: float, dt: float, save_every: int = 1, alpha: float = 0.0,
             progress=None, q_limit: float = 1e10,  # noqa: ANN001
             control: RunControl | None = None) -> xr.Dataset:
    """Newmark/HHT run of ``sys`` returned as an xarray Dataset (see :func:`to_dataset`);
    ``control``: progress, stop requests, checkpoints, resume (:mod:`geardyn.solve.control`).
    The energy terms of the run are in ``attrs`` (``energy_*``, J)."""
    res = newmark(sys, q0, v0, t_end, dt, save_every=save_every, alpha=alpha,
                  progress=progress, q_limit=q_limit, control=control)
    return to_dataset(model, res, idx, {"dt_s": dt, "hht_alpha": alpha,
                                        **{f"energy_{k}": v for k, v in res.energy.items()}})
