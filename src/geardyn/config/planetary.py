"""Config schema of the lumped-parameter planetary model and its simulation (issue 4).

TOML section ``[planetary_dynamics]`` (the mechanism's ``[[planetary]]`` stages give the tooth
numbers, planet count and planet angles). SI units, stated in the field names.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    ValidationInfo,
    field_validator,
    model_validator,
)


class _M(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)


class MemberParams(_M):
    """A central member or planet: mass, inertia, radius, supports."""

    mass_kg: float = Field(gt=0, description="mass (kg)")
    inertia_kgm2: float = Field(gt=0, description="polar moment of inertia (kg·m²)")
    base_radius_m: float | None = Field(
        None, gt=0, description="base radius (m), sun/ring/planet; u = r_b θ")
    bearing_n_per_m: float = Field(0.0, ge=0, description="bearing stiffness in x and y (N/m)")
    torsional_support_nm_per_rad: float = Field(
        0.0, ge=0, description="torsional support to the frame (N·m/rad)")
    tip_radius_m: float | None = Field(
        None, gt=0, description="planet tip radius (m), used to check that planets fit")


class MeshLoadLaw(_M):
    """Load-dependent square-wave mesh (Hammami 2015, §1.2 item 5): c(F) = min(2, c₀ + 2ρ·min(δ/C_a,
    1)) with δ = F/k̄₀, and k ∝ (F/F_ref)^n. F is the static mesh force of the run's loads."""

    tip_relief_m: float = Field(gt=0, description="tip relief depth C_a (m)")
    relief_roll_ratio: float = Field(0.25, gt=0, le=0.5, description="relief roll length / "
                                     "base pitch at each end (ρ)")
    reference_force_n: float | None = Field(None, gt=0, description="force at which k_max and "
                                            "k_min are given (N), with stiffness_exponent")
    stiffness_exponent: float = Field(0.0, ge=0, le=1, description="k ∝ (F/F_ref)^n")
    force_n: float | None = Field(None, gt=0, description="mesh force (N) instead of the static "
                                  "solution of the run's loads")


class MeshParams(_M):
    """Mesh stiffness along the line of action (N/m).

    ``constant``: k = stiffness_n_per_m. ``square``: k_max for the double-contact part of the
    mesh cycle, k_min otherwise (Hammami 2015, eq 1.11). ``sine``: k = k_mean(1 + amplitude·sin
    2πX).
    ``seed004``: the piecewise-constant torsional stiffness of Wang 2010, ch. 5 (sun or ring mesh
    of the Wang 2010 gearbox, via :func:`geardyn.gears.seed004_params`) divided by the pinion base
    radius squared.
    """

    model: Literal["constant", "square", "sine", "seed004"] = "constant"
    stiffness_n_per_m: float | None = Field(None, gt=0, description="mean mesh stiffness (N/m)")
    k_max_n_per_m: float | None = Field(None, gt=0, description="square wave: double contact")
    k_min_n_per_m: float | None = Field(None, gt=0, description="square wave: single contact")
    contact_ratio: float | None = Field(None, ge=1, le=2)
    amplitude: float = Field(0.0, ge=0, lt=1, description="sine: relative amplitude")
    damping_ns_per_m: float = Field(0.0, ge=0, description="viscous mesh damping (N·s/m)")
    backlash_m: float = Field(
        0.0, ge=0, description="normal backlash along the line of action (m) of every mesh of "
        "this kind in the stage: no force while −b < δ < 0, back-flank contact F = k (δ + b) "
        "for δ ≤ −b; 0: no backlash (simulation.contact_loss then gives the one-sided law)")
    load_law: MeshLoadLaw | None = Field(
        None, description="square only, opt-in: contact ratio (and stiffness) rising with the "
        "static mesh force (geardyn.models.planetary.loads.loaded_square_mesh)")

    @model_validator(mode="after")
    def _check(self) -> MeshParams:
        if self.load_law is not None and self.model != "square":
            raise ValueError(f"load_law needs model 'square' (got '{self.model}')")
        if self.model in ("constant", "sine") and self.stiffness_n_per_m is None:
            raise ValueError(f"model '{self.model}' needs stiffness_n_per_m (N/m)")
        if self.model == "square":
            if None in (self.k_max_n_per_m, self.k_min_n_per_m, self.contact_ratio):
                raise ValueError("model 'square' needs k_max_n_per_m, k_min_n_per_m and "
                                 "contact_ratio")
            if self.k_min_n_per_m > self.k_max_n_per_m:  # type: ignore[operator]
                raise ValueError("k_min_n_per_m must not exceed k_max_n_per_m")
        return self


class FaultParams(_M):
    """Wang 2010, ch. 9 tooth fault: crack (fraction of tooth thickness) or spall, on one tooth of
    the sun, the ring or planet ``planet`` (1-based, default 1) of the stage.

    It acts on every mesh model (Wang 2010, ch. 5 stiffness reduction; see
    :func:`geardyn.models.planetary.build.mesh_laws`): a sun or ring tooth meets every planet in
    turn, a planet tooth meets that planet's sun and ring meshes only.
    """

    kind: Literal["crack", "spall"]
    gear: Literal["sun", "ring", "planet"]
    planet: int | None = Field(
        None, description="planet number (1-based) of a gear = 'planet' fault; default 1; "
        "not allowed for sun and ring faults")
    crack_fraction: float = Field(0.0, ge=0, lt=1, description="crack: s → s(1 − V)")
    spall_depth_m: float = Field(0.0, ge=0, description="spall depth D (m)")
    spall_centre: float = Field(0.6, gt=0, lt=1, description="fraction of the path of contact")
    spall_half_width: float = Field(0.05, gt=0, lt=1, description="fraction of the path")

    @field_validator("planet")
    @classmethod
    def _planet(cls, v: int | None, info: ValidationInfo) -> int | None:
        if v is None:
            return v
        gear = info.data.get("gear")
        if gear in ("sun", "ring"):
            raise ValueError(f"a {gear} fault sits on a {gear} tooth, which meets every planet: "
                             f"planet = {v} is only for gear = 'planet' (remove it)")
        if v < 1:
            raise ValueError(f"planets are numbered from 1 (got {v})")
        return v

    @property
    def planet_number(self) -> int | None:
        """The faulty planet (1-based) of a planet fault, None for a sun or ring fault."""
        if self.gear != "planet":
            return None
        return 1 if self.planet is None else self.planet


class PlanetPassForce(_M):
    """Hammami 2015, eq 4.13-4.14: Σ_n w_n U_n F_n Σ_h a_h cos(h z_r(θ_c − ψ_n)) on the ring."""

    amplitude_n: float | None = Field(None, gt=0, description="F_n (N); default: the static "
                                      "ring-planet mesh force of the run's loads")
    harmonics: list[float] | None = Field(
        None, min_length=1, description="relative amplitude of mesh harmonics 1, 2, …; default: "
        "those of the quasi-static ring-mesh force k_rn(X)·δ̄ (the ring mesh law)")
    sensor_angle_deg: float = Field(0.0, description="sensor position on the ring (deg)")


class StageDynamics(_M):
    """Lumped parameters of one mechanism planetary stage (Hammami 2015, Table 3.1 layout)."""

    stage: str = Field(description="name of a [[planetary]] stage of the mechanism")
    pressure_angle_sun_deg: float = Field(20.0, gt=0, lt=45)
    pressure_angle_ring_deg: float = Field(20.0, gt=0, lt=45)
    carrier_radius_m: float = Field(gt=0, description="planet-circle radius r_c (m)")
    sun: MemberParams
    ring: MemberParams
    carrier: MemberParams
    planet: MemberParams
    planet_bearing_n_per_m: float = Field(gt=0, description="planet bearing, radial and "
                                          "tangential (N/m)")
    planet_bearing_damping_ns_per_m: float = Field(
        0.0, ge=0, description="viscous damper across each planet bearing, radial and "
        "tangential (N·s/m; Wang 2010 Table 7-1 c_px = c_py = 1e10, which pins the planets to "
        "the carrier)")
    sun_mesh: MeshParams
    ring_mesh: MeshParams
    transmission_error: bool = Field(False, description="Wang 2010 pitch + profile errors")
    random_error_max_m: float = Field(
        0.0,
        ge=0,
        description="Wang 2010, §4.1.3 random impulse excitation: largest impulse (m; the thesis "
        "uses 1e-6); 0 disables it",
    )
    random_error_probability: float = Field(
        100 / 501,
        gt=0,
        le=1,
        description="probability that a sample of the error table carries an impulse (Wang 2010 "
        "code: 100/501)",
    )
    random_error_seed: int = Field(0, ge=0, description="seed of the random impulses")
    faults: list[FaultParams] = Field(default_factory=list)
    sun_ring_phase: float = Field(0.0, description="γ_rs (mesh cycles), Wang 2010, Table 4-2")
    pin_errors_m: list[float] | None = Field(
        None, description="tangential planet pin position errors e_i (m), Hammami 2015, eq 5.4")
    gravity_m_per_s2: float = Field(0.0, ge=0, description="opt-in weight of the stage's "
                                    "bodies (m/s²; 9.81 on earth), Hammami 2015, ch. 5 §2.1.2")
    gravity_angle_deg: float = Field(0.0, description="carrier x axis above the horizontal at "
                                     "t = 0 (deg)")
    planet_pass: PlanetPassForce | None = Field(
        None, description="opt-in planet-pass ring force F_j(t) on the ring rotation DOF "
        "(Hammami 2015, eqs 4.10-4.14)")

    @model_validator(mode="after")
    def _check(self) -> StageDynamics:
        for role in ("sun", "ring", "planet"):
            if getattr(self, role).base_radius_m is None:
                raise ValueError(f"{role}.base_radius_m is required")
        return self


class ShaftDynamics(_M):
    """Shaft between two bodies (``stage.sun``, ``stage.carrier``, ``stage.ring``, rotors)."""

    name: str
    a: str
    b: str
    torsional_nm_per_rad: float = Field(0.0, ge=0)
    flexural_n_per_m: float = Field(0.0, ge=0)


class RotorDynamics(_M):
    """Torsional body outside the stages (motor rotor, wheel); DOF ``<name>.theta`` (rad)."""

    name: str
    inertia_kgm2: float = Field(gt=0)
    support_nm_per_rad: float = Field(0.0, ge=0)


def check_profile(points: list[tuple[float, float]] | None, unit: str) -> None:
    """A piecewise-linear profile ``[[t_s, value], …]``: at least one point, times ≥ 0 and
    strictly increasing (``np.interp`` needs sorted abscissae)."""
    if points is None:
        return
    if not points:
        raise ValueError(f"needs at least one [t_s, {unit}] point")
    times = [t for t, _ in points]
    if times[0] < 0:
        raise ValueError(f"profile times must be ≥ 0 s (got {times[0]:g} s)")
    for i in range(1, len(times)):
        if times[i] <= times[i - 1]:
            raise ValueError(f"profile times must increase strictly: point {i} at "
                             f"{times[i]:g} s follows {times[i - 1]:g} s (sort the points)")


class TorqueLoad(_M):
    """Constant or piecewise-linear torque on a body: ``profile`` = [[t_s, N·m], …]."""

    body: str
    torque_nm: float = 0.0
    profile: list[tuple[float, float]] | None = Field(
        None, description="[[t_s, N·m], …], times increasing; overrides torque_nm")

    @field_validator("profile")
    @classmethod
    def _sorted(cls, v: list[tuple[float, float]] | None) -> list[tuple[float, float]] | None:
        check_profile(v, "N·m")
        return v


class SpeedControl(_M):
    """Imposed speed of a body through a stiff speed control (inverter-like)."""

    body: str
    profile_rpm: list[tuple[float, float]] = Field(description="[[t_s, rpm], …], times "
                                                   "increasing")
    stiffness_nm_per_rad: float = Field(gt=0)
    damping_nms_per_rad: float = Field(0.0, ge=0)

    @field_validator("profile_rpm")
    @classmethod
    def _sorted(cls, v: list[tuple[float, float]]) -> list[tuple[float, float]]:
        check_profile(v, "rpm")
        return v


class MotorDrive(_M):
    """Induction motor on a rotor, optionally through a fluid coupling to a body.

    ``piecewise``: Wang 2010 TorM; ``kloss``: Hammami 2015, eq 1.18.
    """

    rotor: str
    kind: Literal["piecewise", "kloss"] = "piecewise"
    rated_power_w: float = Field(450e3, gt=0)
    rated_speed_rpm: float = Field(950.0, gt=0)
    frequency_hz: float = Field(50.0, gt=0)
    poles: int = Field(6, gt=0)
    breakdown_torque_nm: float = Field(0.0, ge=0)
    breakdown_slip: float = Field(0.2, gt=0, lt=1)
    kloss_a: float = 1.0
    kloss_b: float = 0.0
    coupling_to: str | None = Field(None, description="body driven through the coupling")
    coupling_q: float = Field(15.0, gt=0, description="q_cc (N·m·s²/rad²), Wang 2010, eq 6.6")
    coupling_ratio: float = Field(1.0, gt=0, description="ideal reduction between coupling "
                                  "and body (29.2971 in Wang 2010)")


class WheelLoad(_M):
    """Wang 2010 bucket-wheel load on the carrier: T = T_fl G (n_c/(k n_op/G))² × schedule."""

    body: str
    full_load_torque_nm: float = Field(4342.4, gt=0)
    gear_ratio: float = Field(157.2789, gt=0)
    rated_speed_rpm: float = Field(950.0, gt=0)
    control_ratio: float = Field(5.0, gt=0)
    schedule: bool = True
    inertia_schedule: bool = Field(False, description="carrier + wheel inertia vs angle")
    empty_inertia_kgm2: float = Field(92926.0, gt=0)
    ore_inertia_kgm2: float = Field(16312.0, ge=0, description="per bucket-load")


class Simulation(_M):
    t_end_s: float = Field(gt=0)
    dt_s: float = Field(gt=0)

    @model_validator(mode="after")
    def _steps(self) -> Simulation:
        if self.dt_s >= self.t_end_s:
            raise ValueError(f"dt_s: the time step {self.dt_s:g} s must be shorter than t_end_s "
                             f"{self.t_end_s:g} s")
        return self

    save_every: int = Field(1, ge=1)
    hht_alpha: float = Field(0.0, ge=0, le=1 / 3)
    contact_loss: bool = Field(False, description="mesh force 0 when the deflection is < 0 "
                               "(meshes without backlash_m; a backlash implies it)")
    rayleigh_alpha: float = Field(0.0, ge=0, description="C = α M + β K (1/s)")
    rayleigh_beta: float = Field(0.0, ge=0, description="(s)")
    modal_damping_ratio: float = Field(0.0, ge=0, lt=1, description="ζ on every elastic mode")
    gyroscopic: bool = Field(False, description="gyroscopic + centripetal terms at the current "
                             "carrier speed (Hammami 2015, eq 3.1)")
    support_damping: dict[str, float] = Field(default_factory=dict,
                                              description="DOF name → N·s/m")
    initial_speed_rpm: dict[str, float] = Field(
        default_factory=dict, description="rigid-body initial speeds (body → rpm); one body "
        "fixes the motion through the kinematics of each stage")
    torques: list[TorqueLoad] = Field(default_factory=list)

    @field_validator("support_damping")
    @classmethod
    def _damping(cls, v: dict[str, float]) -> dict[str, float]:
        bad = {k: x for k, x in v.items() if x < 0}
        if bad:
            raise ValueError(f"damping must be ≥ 0 N·s/m (got {bad})")
        return v
    speed_controls: list[SpeedControl] = Field(default_factory=list)
    motor: MotorDrive | None = None
    wheel_load: WheelLoad | None = None


class PlanetaryDynamics(_M):
    """Lumped-parameter planetary model (Lin & Parker form) and its simulation settings."""

    reduction: Literal["none", "torsional", "transverse"] = "none"
    stages: list[StageDynamics] = Field(min_length=1)
    shafts: list[ShaftDynamics] = Field(default_factory=list)
    rotors: list[RotorDynamics] = Field(default_factory=list)
    simulation: Simulation | None = None


def _check_faults(sd: StageDynamics, st: object, where: str) -> list[str]:
    """Faults against the mechanism stage: the planet number exists (1 … n_planets); a planet
    fault needs a simple planet (a stepped planet's tooth meets either the sun or the ring,
    and the config does not say which step is faulty)."""
    problems = []
    n = st.n_planets  # type: ignore[attr-defined]
    for j, f in enumerate(sd.faults):
        k = f.planet_number
        if k is None:
            continue
        if not 1 <= k <= n:
            problems.append(f"{where}.faults[{j}].planet: planet {k} does not exist: stage "
                            f"'{sd.stage}' has {n} planet{'s' if n > 1 else ''} (1 … {n})")
        if st.stepped:  # type: ignore[attr-defined]
            problems.append(
                f"{where}.faults[{j}].gear: a planet tooth fault on stepped planets cannot be "
                "represented (the model has one planet tooth count and the config does not say "
                "whether the faulty tooth is on the sun-side or the ring-side step)")
    return problems


def check_planetary_dynamics(cfg: object) -> list[str]:
    """Cross-checks against the mechanism: stage names, planets fitting, body names."""
    pd: PlanetaryDynamics | None = getattr(cfg, "planetary_dynamics", None)
    if pd is None:
        return []
    problems: list[str] = []
    stages = {s.name: s for s in getattr(cfg, "planetary", [])}
    bodies: set[str] = {r.name for r in pd.rotors}
    multi = len(pd.stages) > 1
    for i, sd in enumerate(pd.stages):
        where = f"planetary_dynamics.stages[{i}]"
        st = stages.get(sd.stage)
        if st is None:
            problems.append(f"{where}.stage: unknown planetary stage '{sd.stage}' "
                            f"(mechanism stages: {', '.join(stages) or 'none'})")
            continue
        pre = f"{sd.stage}." if multi else ""
        bodies |= {pre + b for b in ("sun", "ring", "carrier")}
        bodies |= {f"{pre}planet{j + 1}" for j in range(st.n_planets)}
        ang = sorted(a % (2 * math.pi) for a in st.angles())
        nxt = ang[1:] + [ang[0] + 2 * math.pi]
        gaps = [b - a for a, b in zip(ang, nxt, strict=True)] if len(ang) > 1 else [2 * math.pi]
        rt = sd.planet.tip_radius_m or (
            sd.planet.base_radius_m  # type: ignore[operator]
            / math.cos(math.radians(sd.pressure_angle_sun_deg))
            * (1 + 2 / st.planet_ring_teeth))
        min_dist = 2 * sd.carrier_radius_m * math.sin(min(gaps) / 2)
        if min_dist <= 2 * rt:
            problems.append(
                f"{where}: planets do not fit: the closest planet centres are "
                f"{min_dist * 1e3:.1f} mm apart (2 r_c sin(Δψ/2)) but the planet tip diameter is "
                f"{2 * rt * 1e3:.1f} mm")
        rs, rp, rr = sd.sun.base_radius_m, sd.planet.base_radius_m, sd.ring.base_radius_m
        rc = sd.carrier_radius_m
        # rigid rotation must not strain the meshes: r_c cos α_s = r_bs + r_bp and
        # r_c cos α_r = r_br − r_bp (Lin & Parker deflections, seed 003 notes §2.3)
        for label, alpha, target in (
            ("pressure_angle_sun_deg", sd.pressure_angle_sun_deg, rs + rp),  # type: ignore[operator]
            ("pressure_angle_ring_deg", sd.pressure_angle_ring_deg, rr - rp),  # type: ignore[operator]
        ):
            got = rc * math.cos(math.radians(alpha))
            if abs(got - target) > 5e-3 * rc:
                hint = (f"use {math.degrees(math.acos(target / rc)):.3f} deg"
                        if 0 < target < rc else "check the radii")
                problems.append(
                    f"{where}.{label}: inconsistent with the radii: r_c cos α = {got * 1e3:.3f} mm "
                    f"but the base radii require {target * 1e3:.3f} mm (rule r_c cos α_s = r_bs + "
                    f"r_bp, r_c cos α_r = r_br − r_bp, to 0.5 %); {hint}")
        problems += _check_faults(sd, st, where)
        if sd.pin_errors_m is not None and len(sd.pin_errors_m) != st.n_planets:
            problems.append(f"{where}.pin_errors_m: {len(sd.pin_errors_m)} values for "
                            f"{st.n_planets} planets")
    for j, sh in enumerate(pd.shafts):
        for side in ("a", "b"):
            name = getattr(sh, side)
            if name not in bodies:
                problems.append(f"planetary_dynamics.shafts[{j}] '{sh.name}'.{side}: unknown body "
                                f"'{name}' (bodies: {', '.join(sorted(bodies))})")
    sim = pd.simulation
    if sim is not None:
        refs = [("torques", t.body) for t in sim.torques] + [
            ("speed_controls", s.body) for s in sim.speed_controls] + [
            ("initial_speed_rpm", b) for b in sim.initial_speed_rpm]
        if sim.motor:
            refs.append(("motor.rotor", sim.motor.rotor))
            if sim.motor.coupling_to:
                refs.append(("motor.coupling_to", sim.motor.coupling_to))
        if sim.wheel_load:
            refs.append(("wheel_load.body", sim.wheel_load.body))
        for where, name in refs:
            if name not in bodies:
                problems.append(f"planetary_dynamics.simulation.{where}: unknown body '{name}' "
                                f"(bodies: {', '.join(sorted(bodies))})")
    return problems
