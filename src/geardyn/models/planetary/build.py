"""Build the planetary model, mesh laws and simulation system from a :class:`GeardynConfig`."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from geardyn.config.planetary import PlanetaryDynamics, StageDynamics
from geardyn.errors import ConfigError, InputError
from geardyn.gears import seed004_params, square_wave, torsional_stiffness_curve
from geardyn.gears.torsional import (
    TorsionalMeshParams,
    pairs_in_contact,
    torsional_mesh_stiffness,
    wang_crack_curve,
    wang_spall_reduction,
)
from geardyn.models.planetary.dynamics import (
    MeshLaw,
    build_system,
    spring_forces,
    static_solve,
)
from geardyn.models.planetary.loads import gravity_forces, integrated_angle, loaded_square_mesh
from geardyn.models.planetary.model import (
    PlanetaryModel,
    RotorSpec,
    ShaftSpec,
    StageSpec,
    assemble,
)
from geardyn.operating import (
    RPM,
    BucketWheelSchedule,
    KlossMotor,
    PiecewiseMotor,
    held_profile,
    reference_angle_table,
)
from geardyn.sensors.planet_pass import planet_pass_signal
from geardyn.solve.integrate import (
    FLUID_COUPLING,
    SPEED_CONTROL,
    SPEED_SQUARED_LOAD,
    SPEED_TORQUE,
    LinearSystem,
    MassSchedule,
)

SAMPLES_PER_CYCLE = 64


def model_from_config(cfg: object, reduction: str | None = None) -> PlanetaryModel:
    """Assemble the model of ``cfg.planetary_dynamics`` (reduction overrides the config)."""
    pd: PlanetaryDynamics | None = getattr(cfg, "planetary_dynamics", None)
    if pd is None:
        raise ConfigError("the config has no [planetary_dynamics] section")
    mech = {s.name: s for s in cfg.planetary}  # type: ignore[attr-defined]
    multi = len(pd.stages) > 1
    specs = []
    for sd in pd.stages:
        st = mech[sd.stage]

        def member(p, radius):  # noqa: ANN001, ANN202
            return dict(mass=p.mass_kg, inertia=p.inertia_kgm2, radius=radius,
                        bearing=p.bearing_n_per_m, torsional=p.torsional_support_nm_per_rad)

        specs.append(StageSpec(
            sd.stage, st.n_planets, st.angles(),
            sun=member(sd.sun, sd.sun.base_radius_m),
            ring=member(sd.ring, sd.ring.base_radius_m),
            carrier=member(sd.carrier, sd.carrier_radius_m),
            planet=member(sd.planet, sd.planet.base_radius_m),
            alpha_s=math.radians(sd.pressure_angle_sun_deg),
            alpha_r=math.radians(sd.pressure_angle_ring_deg),
            k_sun_mesh=_mean_k(sd, "sun"), k_ring_mesh=_mean_k(sd, "ring"),
            planet_bearing=sd.planet_bearing_n_per_m,
            z_sun=st.sun_teeth, z_ring=st.ring_teeth, z_planet=st.planet_sun_teeth,
            prefix=multi,
        ))
    shafts = [ShaftSpec(s.name, s.a, s.b, s.torsional_nm_per_rad, s.flexural_n_per_m)
              for s in pd.shafts]
    rotors = [RotorSpec(r.name, r.inertia_kgm2, r.support_nm_per_rad) for r in pd.rotors]
    return assemble(specs, shafts, rotors, reduction or pd.reduction)


def _seed004_k(which: str, x: np.ndarray) -> tuple[np.ndarray, float, float]:
    p = seed004_params(which)
    # X = 0 at the pitch point of planet 1's first pair (seed 004 §4.2: offset PBP − PBD)
    eps = p.contact_ratio
    offset = _pitch_offset(which, eps)
    k = torsional_stiffness_curve(p, x, 0.0, offset) / p.r_pb**2
    return k, offset, p.r_pb


def _pitch_offset(which: str, eps: float) -> float:
    # PBP − PBD from notes §4.1: PBPs = 0.83382, PBPr = 1.43287, PBD = 1
    return (0.83382 if which == "sun" else 1.43287) - 1.0


def _mean_k(sd: StageDynamics, which: str) -> float:
    m = sd.sun_mesh if which == "sun" else sd.ring_mesh
    if m.model in ("constant", "sine"):
        return float(m.stiffness_n_per_m)  # type: ignore[arg-type]
    if m.model == "square":
        c = float(m.contact_ratio)  # type: ignore[arg-type]
        return m.k_max_n_per_m * (c - 1) + m.k_min_n_per_m * (2 - c)  # type: ignore[operator]
    x = np.linspace(0, 1, SAMPLES_PER_CYCLE, endpoint=False)
    return float(_seed004_k(which, x)[0].mean())


def _seed004_errors(which: str, x: np.ndarray, z_gear: int, z_planet: int, eps: float
                    ) -> np.ndarray:
    """Seed 004 §4.1-4.3 combined error (m): pitch (gear + planet, per revolution) + max profile
    of the pairs in contact (coefficients of notes §2.7, mm → m)."""
    if which == "sun":
        gear = (-0.002, 0.0015, -0.001)
        prof = (0.001, 0.0015, 0.002)
    else:
        gear = (-0.0015, 0.002, -0.0015)
        prof = (-0.001, 0.0015, -0.002)
    planet = (-0.0015, 0.001, 0.002)

    def pitch(coef: tuple[float, ...], frac: np.ndarray) -> np.ndarray:
        return sum(c * np.sin(2 * math.pi * (i + 1) * frac) for i, c in enumerate(coef))

    e = pitch(gear, np.mod(x / z_gear, 1.0)) + pitch(planet, np.mod(x / z_planet, 1.0))
    off = _pitch_offset(which, eps)
    y, tt = pairs_in_contact(x, eps, 0.0, off)
    best = np.full(x.shape, -np.inf)
    for j in range(int(math.ceil(eps)) + 1):
        tau = (tt + j) / eps
        val = sum(c * np.sin(2 * math.pi * (i + 1) * tau) for i, c in enumerate(prof))
        best = np.where(j < y, np.maximum(best, val), best)
    return (e + best) * 1e-3


def random_impulses(
    n: int, max_m: float, probability: float, seed: int | tuple[int, ...]
) -> np.ndarray:
    """Seed 004 §4.1.3 random impulse excitation (m), one draw per error-table sample.

    The thesis code draws an integer uniformly in [−400, 100], sets negatives to 0 and scales by
    1e−5 mm: an impulse with probability 100/501, uniform in (0, 1 µm]. Here the impulse height
    is uniform in (0, ``max_m``] with probability ``probability``. Unlike the thesis (which drew
    per right-hand-side call and therefore disabled it, notes §6), the sequence is drawn once per
    table with ``seed``, so runs are reproducible; the table repeats after its period.
    """
    rng = np.random.default_rng(seed)
    hit = rng.random(n) < probability
    return np.where(hit, rng.uniform(0.0, 1.0, n) * max_m, 0.0)


def mesh_laws(
    cfg: object,
    model: PlanetaryModel,
    mesh_force_n: dict[tuple[str, str], float] | None = None,
) -> dict[tuple[str, str], MeshLaw]:
    """Time-varying mesh laws of every stage from its mesh settings and faults.

    ``mesh_force_n``: static force per mesh type, (stage, "sun"|"ring") → N, used by square
    meshes with a ``load_law`` that gives no ``force_n`` (see :func:`static_mesh_forces`)."""
    pd: PlanetaryDynamics = cfg.planetary_dynamics  # type: ignore[attr-defined]
    laws: dict[tuple[str, str], MeshLaw] = {}
    for i, sd in enumerate(pd.stages):
        info = model.stages[sd.stage]
        for which, m in (("sun", sd.sun_mesh), ("ring", sd.ring_mesh)):
            if m.model == "seed004":
                laws[(sd.stage, which)] = _seed004_law(sd, which, info.z_sun, info.z_ring,
                                                       info.z_planet, info.psi)
                continue
            contact = m.contact_ratio
            if m.model == "constant":
                kc = float(m.stiffness_n_per_m)  # type: ignore[arg-type]

                def shape(x: np.ndarray, kc: float = kc) -> np.ndarray:
                    return np.full(x.shape, kc)
            elif m.model == "sine":
                ks, amp = float(m.stiffness_n_per_m), m.amplitude  # type: ignore[arg-type]

                def shape(x: np.ndarray, ks: float = ks, amp: float = amp) -> np.ndarray:
                    return ks * (1 + amp * np.sin(2 * math.pi * x))
            else:
                kx, kn, contact = m.k_max_n_per_m, m.k_min_n_per_m, m.contact_ratio
                if m.load_law is not None:
                    kx, kn, contact = _loaded(m, (mesh_force_n or {}).get((sd.stage, which)),
                                              f"stages '{sd.stage}' {which}_mesh")

                def shape(x: np.ndarray, kx: float = kx, kn: float = kn,  # type: ignore[misc]
                          c: float = contact) -> np.ndarray:
                    return square_wave(x, kx, kn, c)
            faults = [f for f in sd.faults if f.gear in (which, "planet")]
            if faults:
                if contact is None:
                    contact = standard_contact_ratio(
                        sd, which, info.z_sun, info.z_ring, info.z_planet,
                        f"planetary_dynamics.stages[{i}].{which}_mesh.contact_ratio")
                laws[(sd.stage, which)] = _faulty_model_law(
                    sd, which, shape, float(contact), info.z_sun, info.z_ring, info.z_planet,
                    info.psi)
            elif m.model == "constant":
                laws[(sd.stage, which)] = MeshLaw.constant(m.stiffness_n_per_m)  # type: ignore[arg-type]
            else:
                laws[(sd.stage, which)] = MeshLaw(shape(np.arange(SAMPLES_PER_CYCLE)
                                                        / SAMPLES_PER_CYCLE))
    return laws


def standard_contact_ratio(sd: StageDynamics, which: str, zs: int, zr: int, zp: int,
                           field: str = "contact_ratio") -> float:
    """Transverse contact ratio of the stage's sun–planet or ring–planet mesh with standard
    full-depth teeth (h_a* = 1, no profile shift) at the stage's pressure angle: ε = (path of
    contact)/(base pitch) from the tip circles (:func:`geardyn.gears.geometry.mesh_geometry`,
    module 1; ε does not depend on the module). Used by the tooth faults of the ``constant``
    and ``sine`` meshes, whose laws carry no contact ratio."""
    from geardyn.gears.geometry import GearBlank, mesh_geometry

    if which == "sun":
        a, b, alpha = GearBlank(zs), GearBlank(zp), sd.pressure_angle_sun_deg
    else:
        a, b, alpha = GearBlank(zp), GearBlank(zr, internal=True), sd.pressure_angle_ring_deg
    try:
        eps = mesh_geometry(a, b, 1.0, math.radians(alpha), 1.0, check=False).contact_ratio
    except (ConfigError, InputError) as e:
        raise ConfigError(f"{field}: a tooth fault on this mesh needs its contact ratio, and "
                          f"the standard-tooth value is undefined ({e}); give contact_ratio"
                          ) from None
    if not 1.0 <= eps < 3.0:
        raise ConfigError(f"{field}: a tooth fault on this mesh needs a contact ratio in [1, 3) "
                          f"(Wang 2010, ch. 5 covers 1 to 3 pairs); the standard-tooth value is "
                          f"{eps:.4g}: give contact_ratio")
    return float(eps)


def _loaded(m: object, force: float | None, where: str) -> tuple[float, float, float]:
    law = m.load_law  # type: ignore[attr-defined]
    f = law.force_n if law.force_n is not None else force
    if f is None:
        raise ConfigError(f"planetary_dynamics.{where}.load_law: no mesh force; give force_n "
                          "(N) or loads that fix a static solution")
    return loaded_square_mesh(m.k_max_n_per_m, m.k_min_n_per_m, m.contact_ratio,  # type: ignore[attr-defined]
                              abs(f), law.tip_relief_m, law.relief_roll_ratio,
                              law.reference_force_n, law.stiffness_exponent)


def static_mesh_forces(cfg: object, model: PlanetaryModel) -> dict[tuple[str, str], float]:
    """Mean static force (N) of each stage's sun and ring meshes under the run's torques
    (constant values; profiles by their time mean), with the speed-controlled bodies and motor
    rotors held (seed 003 notes §4.5: the motor supplies only losses)."""
    pd: PlanetaryDynamics = cfg.planetary_dynamics  # type: ignore[attr-defined]
    sim = pd.simulation
    if sim is None:
        return {}
    loads: dict[str, float] = {}
    for t in sim.torques:
        b = model.body(t.body)
        tq = t.torque_nm
        if t.profile:
            pts = np.asarray(t.profile, float)
            tq = float(np.trapezoid(pts[:, 1], pts[:, 0]) / (pts[-1, 0] - pts[0, 0])) \
                if len(pts) > 1 else float(pts[0, 1])
        name = _udof(model, t.body)
        loads[name] = loads.get(name, 0.0) + tq / b.radius
    fixed = [_udof(model, sc.body) for sc in sim.speed_controls]
    if sim.motor:
        fixed.append(_udof(model, sim.motor.rotor))
    try:
        q = static_solve(model, loads, fixed)
    except InputError as e:
        raise ConfigError(f"planetary_dynamics: the static mesh forces for the load law or "
                          f"the planet-pass force are undefined ({e}); give the force "
                          "explicitly (load_law.force_n, planet_pass.amplitude_n)") from None
    forces = spring_forces(model, q)
    out: dict[tuple[str, str], float] = {}
    for st in model.stages:
        for which in ("sun", "ring"):
            f = [abs(forces[s.name]) for s in model.springs
                 if s.stage == st and s.kind == f"mesh_{which}"]
            out[(st, which)] = float(np.mean(f)) if f else 0.0
    return out


def nominal_carrier_angle(model: PlanetaryModel, sim: object, stage: str, t: np.ndarray
                          ) -> np.ndarray:
    """Carrier angle θ_c(t) (rad) of the rigid-body motion the run imposes: the first speed
    control's profile, else the initial speeds held constant (used for the time-tabulated
    gravity and planet-pass forces; the simulated angle differs by the vibration)."""
    carrier = model.rotation_vector(model.stages[stage].bodies["carrier"])
    scs = sim.speed_controls  # type: ignore[attr-defined]
    if scs:
        ts, rpm = _held(scs[0].profile_rpm, float(t[-1]), "speed_controls[0].profile_rpm", "rpm")
        rate = float(carrier @ rigid_velocity(model, {scs[0].body: 1.0}))  # rad/s per rpm
        return rate * integrated_angle(t, ts, rpm)
    w_c = float(carrier @ rigid_velocity(model, sim.initial_speed_rpm))  # type: ignore[attr-defined]
    return w_c * np.asarray(t, float)


def mesh_harmonics(law: MeshLaw, n: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """Relative amplitudes 2|K_h|/K_0 and phases arg K_h (rad) of mesh harmonics h = 1…n of a
    law's stiffness table, k(X) = k̄(1 + Σ a_h cos(2π h X + φ_h)); the quasi-static mesh force
    k(X)·δ̄ has the same relative harmonics."""
    k = np.asarray(law.k, float)
    if k.size < 2:
        return np.zeros(n), np.zeros(n)
    spec = np.fft.rfft(k) / k.size
    per = int(round(law.period))
    idx = [h * per for h in range(1, n + 1)]
    amp = np.array([2 * abs(spec[i]) / spec[0].real if i < spec.size else 0.0 for i in idx])
    ph = np.array([np.angle(spec[i]) if i < spec.size else 0.0 for i in idx])
    return amp, ph


def _extra_forces(cfg: object, model: PlanetaryModel, t_grid: np.ndarray,
                  mesh_force_n: dict[tuple[str, str], float],
                  laws: dict[tuple[str, str], MeshLaw]) -> np.ndarray:
    """Opt-in gravity and planet-pass ring forces on the force grid (solved coordinates).

    Planet-pass (seed 003 eq 4.13): planet n sits at absolute angle θ_c + ψ_n here, so it is
    passed to :func:`~geardyn.sensors.planet_pass.planet_pass_signal` (planets at θ − ψ') as
    ψ' = −ψ_n; its mesh term cos(h z_r(θ_c + ψ_n) + φ_h) is then the model's ring-mesh phase
    2πh X_rn. Without ``harmonics``, F_n is the quasi-static ring-mesh force k_rn(X)·δ̄: the
    amplitudes and phases of the ring mesh law's harmonics (:func:`mesh_harmonics`) times the
    static force; a constant mesh gives the thesis's single cosine of amplitude F_n."""
    pd: PlanetaryDynamics = cfg.planetary_dynamics  # type: ignore[attr-defined]
    out = np.zeros((len(t_grid), len(model.names)))
    for sd in pd.stages:
        if not (sd.gravity_m_per_s2 > 0 or sd.planet_pass is not None):
            continue
        theta = nominal_carrier_angle(model, pd.simulation, sd.stage, t_grid)
        if sd.gravity_m_per_s2 > 0:
            out += gravity_forces(model, sd.stage, theta, sd.gravity_m_per_s2,
                                  math.radians(sd.gravity_angle_deg))
        if sd.planet_pass is not None:
            pp = sd.planet_pass
            info = model.stages[sd.stage]
            amp = pp.amplitude_n if pp.amplitude_n is not None else mesh_force_n[
                (sd.stage, "ring")]
            if pp.harmonics is not None:
                rel, ph = np.asarray(pp.harmonics, float), np.zeros(len(pp.harmonics))
            else:
                rel, ph = mesh_harmonics(laws[(sd.stage, "ring")]) if (
                    sd.stage, "ring") in laws else (np.zeros(3), np.zeros(3))
                if not rel.any():
                    rel, ph = np.ones(1), np.zeros(1)
                ph = ph - 2 * np.pi * np.arange(1, len(ph) + 1) * sd.sun_ring_phase
            ring = info.bodies["ring"]
            # ring angle relative to the carrier: the planets pass a ring-fixed sensor
            th_rel = theta - _nominal_ring_angle(model, pd.simulation, sd.stage, t_grid)
            f = planet_pass_signal(th_rel, len(info.psi), info.z_ring,
                                   amplitudes=amp * rel, phases=ph,
                                   planet_angles=list(np.mod(-info.psi, 2 * np.pi)),
                                   sensor_angle=math.radians(pp.sensor_angle_deg))
            out[:, model.dof(_udof(model, ring))] += f  # seed 003 eq 4.14: on u_r
    return out


def _nominal_ring_angle(model: PlanetaryModel, sim: object, stage: str, t: np.ndarray
                        ) -> np.ndarray:
    ring = model.rotation_vector(model.stages[stage].bodies["ring"])
    carrier = model.rotation_vector(model.stages[stage].bodies["carrier"])
    scs = sim.speed_controls  # type: ignore[attr-defined]
    if scs:
        v1 = rigid_velocity(model, {scs[0].body: 1.0})
        wc = float(carrier @ v1)
        return 0.0 if wc == 0 else float(ring @ v1) / wc * nominal_carrier_angle(
            model, sim, stage, t)
    return float(ring @ rigid_velocity(model, sim.initial_speed_rpm)) * np.asarray(t, float)  # type: ignore[attr-defined]


def _ring_entry_shift(zs: int, zr: int, psi: np.ndarray, planet: int) -> int:
    """Whole mesh cycles M_n = (z_s + z_r)(ψ_n − ψ_1)/2π between planet n's ring and sun mesh
    counts (rounded; an integer when the planets can be assembled, seed 004 Table 4-1).

    With the mesh phasing of :func:`geardyn.models.planetary.dynamics.spring_rows` (integer
    offsets: X_sn = z_s(θ_s − θ_c)/2π − z_s ψ'_n/2π, X_rn = z_r(θ_c − θ_r)/2π + z_r ψ'_n/2π − γ_rs,
    ψ'_n = ψ_n − ψ_1, and z_s(θ_s − θ_c) = z_r(θ_c − θ_r) in rigid motion), X_rn − X_sn =
    M_n − γ_rs: a planet tooth that enters the sun mesh at count 0 meets the ring half a planet
    revolution later, at ring count ⌊z_p/2⌋ + M_n of that planet's table."""
    d = (zs + zr) * (float(psi[planet - 1]) - float(psi[0])) / (2 * math.pi)
    return int(round(d))


def _entry_count(f: object, which: str, zs: int, zr: int, zp: int, psi: np.ndarray) -> int:
    """Mesh count at which the faulty tooth of fault ``f`` enters contact in the tables of
    the planet it meets: 0 for a sun or ring tooth (it meets each planet at that planet's
    count 0: the integer offsets of the tables time it); for a planet tooth, 0 in the sun mesh
    (seed 004 ch. 9: planet tooth 1 is the first in mesh with the sun) and ⌊z_p/2⌋ + M_n in the
    ring mesh (:func:`_ring_entry_shift`)."""
    if f.gear != "planet" or which == "sun":  # type: ignore[attr-defined]
        return 0
    n = f.planet_number  # type: ignore[attr-defined]
    return (zp // 2 + _ring_entry_shift(zs, zr, psi, n)) % zp


def _tooth_fault_curve(
    p: TorsionalMeshParams, x: np.ndarray, off: float, faults: list, planet: int, which: str,
    zs: int, zr: int, zp: int, psi: np.ndarray, thickness: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Seed 004 ch. 5 torsional stiffness K(X) (N·m/rad) of planet ``planet``'s sun or ring mesh
    with the tooth faults that reach it, and the spall profile error (m, to add to e).

    Crack (§5.3, :func:`~geardyn.gears.torsional.wang_crack_curve`): eq 5.14 with s → s(1 − V)
    for the cracked pair while the tooth is in contact. Spall (§5.4): the reduction of eq 5.14
    with s → s(1 − D/s) ramped by :func:`~geardyn.gears.torsional.wang_spall_reduction`, and
    the profile error D·cos((posit − P)/W·π/2)^(1/5) (§7.8). ``thickness``: the tooth thickness
    s (m) that the spall depth D is compared with. A planet fault reaches planet
    ``f.planet_number`` only."""
    eps = p.contact_ratio
    z_gear = zs if which == "sun" else zr
    k = torsional_stiffness_curve(p, x, 0.0, off)
    err = np.zeros(len(x))
    for f in faults:
        if f.gear == "planet" and f.planet_number != planet:
            continue
        teeth = zp if f.gear == "planet" else z_gear
        c0 = _entry_count(f, which, zs, zr, zp, psi)
        if f.kind == "crack":
            k = np.minimum(k, wang_crack_curve(p, x, f.crack_fraction, c0, teeth, 0.0, off))
            continue
        xs = x + off
        rel = np.mod(xs - c0, teeth)
        posit = np.where(rel <= eps, rel / eps, -1.0)
        frac_eq = min(f.spall_depth_m / thickness, 0.99)
        y, _ = pairs_in_contact(x, eps, 0.0, off)
        dk = np.zeros(len(x))
        for ny in (1, 2, 3):
            sel = y == ny
            if sel.any():
                v = [0.0] * ny
                v[0] = frac_eq
                dk[sel] = torsional_mesh_stiffness(p, ny) - torsional_mesh_stiffness(
                    p, ny, tuple(v))
        red = np.where(posit >= 0, wang_spall_reduction(
            np.maximum(posit, 0), f.spall_centre, f.spall_half_width, 1.0), 0.0) * dk
        k = k - red
        inside = (posit >= 0) & (np.abs(posit - f.spall_centre) < f.spall_half_width)
        prof = np.zeros(len(x))
        prof[inside] = f.spall_depth_m * np.cos(
            (posit[inside] - f.spall_centre) / f.spall_half_width * math.pi / 2) ** 0.2
        err = err - prof
    return k, err


def _fault_period(faults: list, z_gear: int, zp: int, base: int = 1) -> int:
    """Mesh cycles after which the faulty tables repeat: z_gear for a sun/ring tooth, z_p for a
    planet tooth (lcm with ``base``)."""
    period = base
    if any(f.gear != "planet" for f in faults):
        period = math.lcm(period, z_gear)
    if any(f.gear == "planet" for f in faults):
        period = math.lcm(period, zp)
    return period


def _faulty_model_law(sd: StageDynamics, which: str,
                      shape: Callable[[np.ndarray], np.ndarray], contact_ratio: float,
                      zs: int, zr: int, zp: int, psi: np.ndarray) -> MeshLaw:
    """A ``constant``, ``square`` or ``sine`` mesh law with tooth faults (issue 18).

    The healthy law k(X) of the model is multiplied, wherever a faulty tooth is in contact, by
    the relative reduction of the seed 004 ch. 5 model, K_fault(X)/K(X) (eq 5.14 with the crack
    or spall of :func:`_tooth_fault_curve`), with the mesh's own contact ratio (pairs in
    contact and the faulty tooth's contact span X ∈ [c₀, c₀ + ε] of its entry count c₀; X = 0 is
    a tooth entry, as in the square wave's double-contact phase [0, ε − 1)). The stage gives
    no tooth geometry (module, face width, root and shaft radii) for the potential-energy
    stiffness of :mod:`geardyn.gears`, so the split of tooth and body compliance is that of the
    seed 004 sun or ring mesh (:func:`~geardyn.gears.seed004_params`); the spall depth is
    compared with the stage's own tooth thickness πm/2, m = 2 r_b/(z cos α) of the faulty gear.
    """
    p = replace(seed004_params(which), contact_ratio=contact_ratio)
    faults = [f for f in sd.faults if f.gear in (which, "planet")]
    z_gear = zs if which == "sun" else zr
    period = _fault_period(faults, z_gear, zp)
    x = np.arange(period * SAMPLES_PER_CYCLE) / SAMPLES_PER_CYCLE
    healthy = torsional_stiffness_curve(p, x, 0.0, 0.0)
    # one cycle tiled: outside the faulty tooth's contact the law equals the healthy one
    k_model = np.tile(shape(x[:SAMPLES_PER_CYCLE]), period)
    per_planet = {}
    for pl in range(1, len(psi) + 1):
        kf, err = _tooth_fault_curve(p, x, 0.0, faults, pl, which, zs, zr, zp, psi,
                                     _stage_tooth_thickness(sd, zs))
        per_planet[pl] = (k_model * (kf / healthy), float(period), err, float(period))
    first = per_planet[1]
    return MeshLaw(first[0], first[1], first[2], first[3], per_planet, integer_offsets=True)


def _stage_tooth_thickness(sd: StageDynamics, zs: int) -> float:
    """Pitch-circle tooth thickness πm/2 (m) of the stage, m = 2 r_b/(z cos α) from the sun's
    base radius (all three gears share the module)."""
    alpha = math.radians(sd.pressure_angle_sun_deg)
    module = 2 * sd.sun.base_radius_m / (zs * math.cos(alpha))  # type: ignore[operator]
    return math.pi * module / 2


def _seed004_law(sd: StageDynamics, which: str, zs: int, zr: int, zp: int, psi: np.ndarray
                 ) -> MeshLaw:
    p = seed004_params(which)
    eps = p.contact_ratio
    off = _pitch_offset(which, eps)
    z_gear = zs if which == "sun" else zr
    faults = [f for f in sd.faults if f.gear in (which, "planet")]
    randomised = sd.random_error_max_m > 0
    if not faults and not sd.transmission_error and not randomised:
        x = np.arange(SAMPLES_PER_CYCLE) / SAMPLES_PER_CYCLE
        return MeshLaw(torsional_stiffness_curve(p, x, 0.0, off) / p.r_pb**2)
    errors_on = sd.transmission_error or randomised
    period = z_gear if not errors_on else math.lcm(z_gear, zp)
    if any(f.gear == "planet" for f in faults):
        period = math.lcm(period, zp)
    x = np.arange(period * SAMPLES_PER_CYCLE) / SAMPLES_PER_CYCLE
    e = _seed004_errors(which, x, z_gear, zp, eps) if sd.transmission_error else np.zeros(1)
    per_planet = {}
    for pl in range(1, len(psi) + 1):
        err = e.copy() if sd.transmission_error else np.zeros(len(x))
        if randomised:
            err = err + random_impulses(
                len(x),
                sd.random_error_max_m,
                sd.random_error_probability,
                (sd.random_error_seed, 0 if which == "sun" else 1, pl),
            )
        k, prof = _tooth_fault_curve(p, x, off, faults, pl, which, zs, zr, zp, psi,
                                     p.tooth_thickness)
        per_planet[pl] = (k / p.r_pb**2, float(period), err + prof, float(period))
    first = per_planet[1]
    return MeshLaw(first[0], first[1], first[2], first[3], per_planet, integer_offsets=True)


@dataclass
class Prepared:
    """Model, integrator system, mesh spring indices and initial state of a simulation;
    ``t_end_s`` is the run end (s) that the speed and torque tables cover."""

    model: PlanetaryModel
    system: LinearSystem
    mesh_index: list[int]
    q0: np.ndarray
    v0: np.ndarray
    t_end_s: float | None = None


def prepare(cfg: object, t_end_s: float | None = None) -> Prepared:
    """Model, integrator system and initial state of the config's simulation.

    ``t_end_s`` is the run end (s; default the config's ``simulation.t_end_s``, e.g. a CLI
    ``--t-end`` override). Speed and torque profiles that end before it hold their last value
    to ``t_end_s`` with a :class:`~geardyn.operating.ProfileWarning` naming the profile.
    """
    pd: PlanetaryDynamics | None = getattr(cfg, "planetary_dynamics", None)
    if pd is None:
        raise ConfigError("the config has no [planetary_dynamics] section")
    sim = pd.simulation
    if sim is None:
        raise ConfigError("planetary_dynamics.simulation is missing (t_end_s, dt_s, ...)")
    t_end = sim.t_end_s if t_end_s is None else float(t_end_s)
    if not t_end > 0:
        raise ConfigError(f"t_end_s: the run end must be > 0 s (got {t_end_s!r})")
    model = model_from_config(cfg)
    extras = any(sd.gravity_m_per_s2 > 0 or sd.planet_pass is not None for sd in pd.stages)
    need_f = any(
        (sd.planet_pass is not None and sd.planet_pass.amplitude_n is None)
        or any(m.load_law is not None and m.load_law.force_n is None
               for m in (sd.sun_mesh, sd.ring_mesh))
        for sd in pd.stages)
    mesh_force = static_mesh_forces(cfg, model) if need_f else {}
    laws = mesh_laws(cfg, model, mesh_force)
    names = model.names
    n = len(names)
    drives: list[dict] = []
    where = "planetary_dynamics.simulation"
    profiles = {}
    for i, t in enumerate(sim.torques):
        if t.profile:
            profiles[i] = _held(t.profile, t_end, f"{where}.torques[{i}].profile", "N·m")
    t_grid = np.array([0.0, t_end])
    if profiles:
        t_grid = np.unique(np.concatenate([t_grid] + [ts for ts, _ in profiles.values()]))
        # uniform grid for the kernel's table lookup (held at its ends)
        t_grid = np.linspace(0.0, t_grid[-1], max(len(t_grid), 2001))
    if extras:  # planet-pass / gravity: tabulate at the time step (at most 400001 rows)
        t_grid = np.linspace(0.0, t_grid[-1], max(len(t_grid), min(
            int(math.ceil(t_grid[-1] / sim.dt_s)) + 1, 400001)))
    force = np.zeros((len(t_grid), n))
    for i, t in enumerate(sim.torques):
        b = model.body(t.body)
        j = model.dof(_udof(model, t.body))
        tq = np.interp(t_grid, *profiles[i]) if i in profiles else t.torque_nm
        force[:, j] += tq / b.radius
    if extras:
        force += _extra_forces(cfg, model, t_grid, mesh_force, laws)
    for i, sc in enumerate(sim.speed_controls):
        b = model.body(sc.body)
        ts, rpm = _held(sc.profile_rpm, t_end, f"{where}.speed_controls[{i}].profile_rpm", "rpm")
        t_pad = 1.01 * t_end + 1e-3  # the kernel takes dθ_ref/dt over ±1e-6·span at t_end too
        if ts[-1] < t_pad:
            ts, rpm = np.append(ts, t_pad), np.append(rpm, rpm[-1])
        if ts[0] > -1e-3:  # ... and at t = 0: without a point before 0 the clamped table
            # halves ω_ref for t < 1e-6·span (a speed kick at the start of long tables)
            ts, rpm = np.insert(ts, 0, ts[0] - 1e-3 - 0.01 * t_end), np.insert(rpm, 0, rpm[0])
        tt, th = reference_angle_table(ts, rpm * RPM)
        drives.append(dict(kind=SPEED_CONTROL, a=model.dof(_udof(model, sc.body)),
                           ha=1.0 / b.radius, p0=sc.stiffness_nm_per_rad,
                           p1=sc.damping_nms_per_rad, x=tt, y=th))
    if sim.motor:
        mo = sim.motor
        rb = model.body(mo.rotor)
        if mo.kind == "piecewise":
            motor = PiecewiseMotor(mo.rated_power_w, mo.rated_speed_rpm, mo.frequency_hz,
                                   mo.poles)
        else:
            motor = KlossMotor(mo.breakdown_torque_nm, mo.breakdown_slip, mo.kloss_a,
                               mo.kloss_b, 120 * mo.frequency_hz / mo.poles)
        wx, ty = motor.table()
        drives.append(dict(kind=SPEED_TORQUE, a=model.dof(_udof(model, mo.rotor)),
                           ha=1.0 / rb.radius, x=wx, y=ty))
        if mo.coupling_to:
            ob = model.body(mo.coupling_to)
            drives.append(dict(kind=FLUID_COUPLING, a=model.dof(_udof(model, mo.rotor)),
                               b=model.dof(_udof(model, mo.coupling_to)), ha=1.0 / rb.radius,
                               hb=1.0 / ob.radius, p0=mo.coupling_q, p1=mo.coupling_ratio))
    mass_sched = None
    if sim.wheel_load:
        wl = sim.wheel_load
        b = model.body(wl.body)
        sch = BucketWheelSchedule()
        th = np.linspace(0, sch.points()["P47"] + 1.0, 4001)
        fac = sch.load_factor(th, wl.control_ratio) if wl.schedule else np.ones(len(th))
        # T = T_fl G (n_c / (k n_op / G))² → coefficient on ω_c² (rad/s)
        w_ref = wl.control_ratio * wl.rated_speed_rpm / wl.gear_ratio * RPM
        coef = wl.full_load_torque_nm * wl.gear_ratio / w_ref**2
        dof_c = model.dof(_udof(model, wl.body))
        drives.append(dict(kind=SPEED_SQUARED_LOAD, a=dof_c, ha=1.0 / b.radius, p0=coef,
                           x=th, y=fac))
        if wl.inertia_schedule:
            jj = wl.empty_inertia_kgm2 + wl.ore_inertia_kgm2 * sch.ore(th)
            m0 = model.mass_matrix()[dof_c, dof_c]
            extra = m0 - b.inertia / b.radius**2
            mass_sched = MassSchedule(np.array([dof_c]), np.array([dof_c]),
                                      np.array([1.0 / b.radius]),
                                      (th)[None, :], (extra + jj / b.radius**2)[None, :],
                                      np.array([len(th)]))
    ring_phase = {sd.stage: sd.sun_ring_phase for sd in pd.stages}
    cdamp = max([sd.sun_mesh.damping_ns_per_m for sd in pd.stages] + [0.0])
    sys, idx = build_system(model, laws, drives, t_grid, force,
                            (sim.rayleigh_alpha, sim.rayleigh_beta), sim.support_damping,
                            cdamp, sim.contact_loss, ring_phase, mass_sched,
                            sim.modal_damping_ratio, sim.gyroscopic)
    sys.springs.backlash = mesh_backlash(pd, model, idx)
    _planet_bearing_dampers(pd, model, sys)
    q0 = np.zeros(n)
    v0 = rigid_velocity(model, sim.initial_speed_rpm)
    # planet pin errors: offsets on the tangential planet-bearing springs, as a force
    for sd in pd.stages:
        if sd.pin_errors_m:
            info = model.stages[sd.stage]
            a = model.spring_vectors()
            for i, e in enumerate(sd.pin_errors_m):
                planet = info.bodies[f"planet{i + 1}"]
                name = f"{planet}.bearing.eta"
                j = [k for k, s in enumerate(model.springs) if s.name == name][0]
                if model.reduction != "torsional":
                    sys.force[:, :] -= model.springs[j].k * (-e) * a[j]
                    continue
                # rigid planet bearings (η = u_c): the bearing spring never deflects, so the
                # error reaches the meshes as an offset δ₀ = s·a·(−e ê_η) (planet centre at
                # η = u_c − e, the bearing spring's unstressed state above), scaled by the
                # static condensation of the bearing in series with the planet's meshes,
                # s = k_b / (k_b + k_s cos²α_s + k_r cos²α_r), so that the pin force is
                # F_e = K_eff e of seed 003 eqs 5.4-5.5 (s → 1 for rigid bearings)
                mesh = [(m_i, sp) for m_i, sp in enumerate(model.springs)
                        if sp.kind in ("mesh_sun", "mesh_ring") and sp.body == planet]
                off = np.zeros(model.n_full)
                off[model.dof_names.index(f"{planet}.eta")] = -e
                k_t = sum(sp.k * (sp.a @ off / e) ** 2 for _, sp in mesh) if e else 0.0
                k_b = model.springs[j].k
                scale = k_b / (k_b + k_t) if k_b > 0 else 1.0
                for m_i, sp in mesh:
                    d0 = scale * float(sp.a @ off)
                    if m_i in idx:
                        sys.springs.etab[idx.index(m_i)] += d0
                    else:  # constant mesh spring in K₀
                        sys.force[:, :] -= sp.k * d0 * a[m_i]
    return Prepared(model, sys, idx, q0, v0, t_end)


def _planet_bearing_dampers(pd: PlanetaryDynamics, model: PlanetaryModel,
                            sys: LinearSystem) -> None:
    """Add c a aᵀ to the damping matrix for every planet-bearing spring (radial and
    tangential) of a stage with ``planet_bearing_damping_ns_per_m`` = c > 0: a viscous damper
    on the planet–carrier relative motion (Wang 2010 eqs 3.35-3.40, c_px and c_py)."""
    a = model.spring_vectors()
    for sd in pd.stages:
        c = sd.planet_bearing_damping_ns_per_m
        if c <= 0:
            continue
        for i, s in enumerate(model.springs):
            if s.kind == "planet_bearing" and s.stage == sd.stage:
                sys.C += c * np.outer(a[i], a[i])


def mesh_backlash(pd: PlanetaryDynamics, model: PlanetaryModel, idx: list[int]) -> np.ndarray:
    """Backlash (m) of each variable spring ``idx`` (model spring indices): the
    ``backlash_m`` of its stage's ``sun_mesh`` or ``ring_mesh`` (the contact law of
    :func:`geardyn.solve.integrate._contact`)."""
    stages = {sd.stage: sd for sd in pd.stages}
    out = []
    for i in idx:
        s = model.springs[i]
        sd = stages[s.stage]
        out.append((sd.sun_mesh if s.kind == "mesh_sun" else sd.ring_mesh).backlash_m)
    return np.array(out, float)


def _held(points: object, t_end: float, field: str, unit: str) -> tuple[np.ndarray, np.ndarray]:
    """:func:`~geardyn.operating.held_profile` with input errors reported as config errors."""
    try:
        return held_profile(points, t_end, field, unit, stacklevel=4)
    except InputError as e:
        raise ConfigError(str(e)) from None


def _udof(model: PlanetaryModel, body: str) -> str:
    b = model.body(body)
    return f"{b.name}.theta" if b.kind == "rotor" else f"{b.name}.u"


def rigid_velocity(model: PlanetaryModel, speeds_rpm: dict[str, float]) -> np.ndarray:
    """Velocity vector of a rigid-body motion with the given body speeds (rpm).

    Least squares: zero deflection rate in every spring with stiffness (so supported DOFs stay
    at rest) and the given speeds (weighted ×1000); free bodies without a speed stay at rest.
    """
    n = len(model.names)
    if not speeds_rpm:
        return np.zeros(n)
    a = model.spring_vectors()
    # every spring with stiffness (meshes, bearings, supports, shafts) stays undeformed
    rows = [a[i] for i, s in enumerate(model.springs) if s.k > 0]
    rhs = [0.0] * len(rows)
    for body, rpm in speeds_rpm.items():
        b = model.body(body)
        rows.append(model.rotation_vector(b.name) * 1e3)
        rhs.append(rpm * RPM * 1e3)
    sol, *_ = np.linalg.lstsq(np.array(rows), np.array(rhs), rcond=None)
    return sol
