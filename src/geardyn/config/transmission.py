"""Config schema of the finite-element transmission (issue 6, Thibault et al. 2024, §3.1).

``[transmission]`` section of a geardyn TOML file. SI units, stated in field names. Shafts are
meshed with Timoshenko elements (nodes 0..elements along +z from the shaft start); wheels,
bearings and torques sit on shaft nodes given as (shaft name, local node index). Gear meshes
refer to ``[[gear_geometry]]`` pairs by name (the gear geometry issue-3 schema).
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


class ShaftConfig(_Strict):
    name: str
    link: str | None = Field(None, description="mechanism link carried by the shaft")
    position_m: tuple[float, float] = Field(description="axis position (x, y) in m")
    length_m: float = Field(gt=0)
    elements: int = Field(5, ge=1, le=200)
    outer_diameter_m: float = Field(gt=0)
    inner_diameter_m: float = Field(0.0, ge=0)
    youngs_modulus_pa: float = Field(210e9, gt=0)
    poisson_ratio: float = Field(0.3, gt=-1, lt=0.5)
    density_kg_m3: float = Field(7800.0, gt=0)

    @model_validator(mode="after")
    def _bore(self) -> ShaftConfig:
        if self.inner_diameter_m >= self.outer_diameter_m:
            raise ValueError("inner_diameter_m must be < outer_diameter_m")
        return self


class NodeRef(_Strict):
    shaft: str
    node: int = Field(ge=0, description="local node index along the shaft (0 = shaft start)")


class SpallConfig(_Strict):
    """Outer-race spall (Thibault et al. 2024, §3.5.2)."""

    angle_deg: float = Field(description="angular centre on the outer race (0 = +x axis)")
    angular_length_deg: float = Field(gt=0, lt=360)
    depth_m: float = Field(gt=0)


class BearingConfig(_Strict):
    name: str
    at: NodeRef
    kind: Literal["ball", "roller"]
    elements: int = Field(ge=3, description="number of balls / rollers")
    pitch_diameter_m: float = Field(gt=0)
    element_diameter_m: float = Field(gt=0)
    diametral_clearance_m: float = Field(0.0, ge=0, description="total radial clearance")
    inner_conformity: float = Field(0.51, gt=0.5, description="ball: groove radius / D")
    outer_conformity: float = Field(0.52, gt=0.5, description="ball: groove radius / D")
    roller_length_m: float | None = Field(None, gt=0)
    roller_fillet_m: float = Field(0.0, ge=0)
    axial_clearance_m: float = Field(0.0, ge=0, description="roller: total axial play")
    flange_stiffness_n_per_m: float = Field(1e8, gt=0, description="roller: flange contact")
    youngs_modulus_pa: float = Field(206e9, gt=0)
    poisson_ratio: float = Field(0.3, gt=-1, lt=0.5)
    viscous_torque_nms_per_rad: float = Field(0.0, ge=0,
                                              description="α_bea of Thibault et al. 2024, §3.1")
    rolling_resistance: float = Field(
        0.0, ge=0, description="torque per (Σ contact load × d_m/2), dimensionless"
    )
    outer_spall: SpallConfig | None = None

    @model_validator(mode="after")
    def _geom(self) -> BearingConfig:
        if self.element_diameter_m >= self.pitch_diameter_m:
            raise ValueError("element_diameter_m must be < pitch_diameter_m")
        if self.kind == "ball":
            # the groove-centre distance A₀ = (f_i + f_o − 1) D must exceed half the clearance:
            # beyond it every ball is out of contact at any load and the contact law
            # (Harris & Kotzalas 2006, §7) gives spurious forces
            limit = 2.0 * (self.inner_conformity + self.outer_conformity - 1.0) \
                * self.element_diameter_m
            if self.diametral_clearance_m >= limit:
                raise ValueError(
                    f"diametral_clearance_m: {self.diametral_clearance_m:g} m must be < "
                    f"2 (f_i + f_o − 1) D = {limit:g} m (inner_conformity, outer_conformity, "
                    "element_diameter_m; Harris & Kotzalas 2006 §7: the groove-centre "
                    "distance A₀ = (f_i + f_o − 1) D)")
        if self.kind == "roller":
            if self.roller_length_m is None:
                raise ValueError("roller bearings need roller_length_m")
            if 2 * self.roller_fillet_m >= self.roller_length_m:
                raise ValueError("roller_fillet_m: two fillets must be shorter than the roller")
        return self


_COEF = ("xx", "xy", "yx", "yy")


class SupportConfig(_Strict):
    """Linear bearing / support between a shaft node and the housing (ROSS's
    ``BearingElement``; Friswell et al. 2010, §5.5): force on the shaft
    −K (x, y) − C (ẋ, ẏ) with the 2×2 stiffness K = [[kxx, kxy], [kyx, kyy]] and damping
    C = [[cxx, cxy], [cyx, cyy]] (cross terms of fluid-film bearings allowed, non-symmetric),
    or full 4×4 matrices on (x, y, θx, θy). Coefficients are numbers, or lists tabulated
    against ``speeds_rpm`` (interpolated linearly at the current shaft speed during a run,
    held constant outside the table, as ROSS interpolates its coefficients)."""

    name: str
    at: NodeRef
    speeds_rpm: list[float] | None = Field(
        None, min_length=2, description="shaft speeds of the tabulated coefficients (ascending)")
    kxx_n_per_m: float | list[float] = 0.0
    kxy_n_per_m: float | list[float] = 0.0
    kyx_n_per_m: float | list[float] = 0.0
    kyy_n_per_m: float | list[float] = 0.0
    cxx_ns_per_m: float | list[float] = 0.0
    cxy_ns_per_m: float | list[float] = 0.0
    cyx_ns_per_m: float | list[float] = 0.0
    cyy_ns_per_m: float | list[float] = 0.0
    kzz_n_per_m: float = Field(0.0, ge=0, description="axial stiffness")
    czz_ns_per_m: float = Field(0.0, ge=0, description="axial damping")
    stiffness_matrix: list[list[float]] | None = Field(
        None, description="4×4 stiffness on (x, y, θx, θy) in N/m, N, N·m/rad (replaces kxx…)")
    damping_matrix: list[list[float]] | None = Field(
        None, description="4×4 damping on (x, y, θx, θy) (replaces cxx…)")

    @model_validator(mode="after")
    def _table(self) -> SupportConfig:
        sp = self.speeds_rpm
        for kind in ("k", "c"):
            for c in _COEF:
                f = f"{kind}{c}_{'n_per_m' if kind == 'k' else 'ns_per_m'}"
                val = getattr(self, f)
                if isinstance(val, list):
                    if sp is None:
                        raise ValueError(f"{f}: a list of values needs speeds_rpm")
                    if len(val) != len(sp):
                        raise ValueError(f"{f}: {len(val)} values for {len(sp)} speeds_rpm")
        if sp is not None and any(b <= a for a, b in zip(sp, sp[1:], strict=False)):
            raise ValueError("speeds_rpm: must be strictly ascending")
        for f in ("stiffness_matrix", "damping_matrix"):
            m = getattr(self, f)
            if m is not None and (len(m) != 4 or any(len(r) != 4 for r in m)):
                raise ValueError(f"{f}: must be 4×4 on (x, y, θx, θy)")
        return self

    def matrices(self, speed_rpm: float) -> tuple[list[list[float]], list[list[float]]]:
        """(K, C) 4×4 on (x, y, θx, θy) at ``speed_rpm`` (linear interpolation of the table,
        constant outside it)."""
        import numpy as np

        def val(f: str) -> float:
            v = getattr(self, f)
            if isinstance(v, list):
                return float(np.interp(abs(speed_rpm), self.speeds_rpm, v))
            return float(v)

        out = []
        for kind, unit, full in (("k", "n_per_m", self.stiffness_matrix),
                                 ("c", "ns_per_m", self.damping_matrix)):
            if full is not None:
                out.append([list(map(float, r)) for r in full])
                continue
            m = [[0.0] * 4 for _ in range(4)]
            for c in _COEF:
                m["xy".index(c[0])]["xy".index(c[1])] = val(f"{kind}{c}_{unit}")
            out.append(m)
        return out[0], out[1]


class DiscConfig(_Strict):
    """Rigid disc (not a gear wheel) on a shaft node: mass, polar and diametral inertia given,
    or computed from an annular geometry (ρ π (R² − r²) w, I_p = m (R² + r²)/2,
    I_d = m (R² + r²)/4 + m w²/12; Friswell et al. 2010, §5.3); ``offset_m`` places its
    centre of mass along the shaft axis from the node (rigid link)."""

    name: str
    at: NodeRef
    mass_kg: float | None = Field(None, gt=0)
    polar_inertia_kg_m2: float | None = Field(None, ge=0)
    diametral_inertia_kg_m2: float | None = Field(None, ge=0)
    outer_diameter_m: float | None = Field(None, gt=0)
    inner_diameter_m: float = Field(0.0, ge=0)
    width_m: float | None = Field(None, gt=0)
    density_kg_m3: float = Field(7810.0, gt=0)
    offset_m: float = Field(0.0, description="axial offset of the centre of mass from the node")

    @model_validator(mode="after")
    def _given(self) -> DiscConfig:
        geo = self.outer_diameter_m is not None or self.width_m is not None
        if geo:
            if self.outer_diameter_m is None or self.width_m is None:
                raise ValueError("outer_diameter_m and width_m: give both for a disc geometry")
            if self.inner_diameter_m >= self.outer_diameter_m:
                raise ValueError("inner_diameter_m must be < outer_diameter_m")
            if self.mass_kg is not None or self.polar_inertia_kg_m2 is not None:
                raise ValueError("mass_kg / polar_inertia_kg_m2: give either the geometry "
                                 "(outer_diameter_m, width_m) or the mass and inertias")
        elif self.mass_kg is None or self.polar_inertia_kg_m2 is None:
            raise ValueError("mass_kg and polar_inertia_kg_m2 (or outer_diameter_m and "
                             "width_m) are required")
        return self

    def properties(self) -> tuple[float, float, float]:
        """(mass kg, I_p, I_d kg·m²)."""
        if self.outer_diameter_m is not None:
            from geardyn.elements.disc import solid_disc_properties

            return solid_disc_properties(0.5 * self.outer_diameter_m, 0.5 * self.inner_diameter_m,
                                         self.width_m, self.density_kg_m3)
        ip = float(self.polar_inertia_kg_m2)
        idia = ip / 2 if self.diametral_inertia_kg_m2 is None else self.diametral_inertia_kg_m2
        return float(self.mass_kg), ip, float(idia)


class DashpotConfig(_Strict):
    """Linear spring-dashpot on one DOF of a node, to the housing or to another node ``to``
    (same DOF): F = −k (u − u_to) − c (u̇ − u̇_to)."""

    name: str
    at: NodeRef
    to: NodeRef | None = Field(None, description="other node (default: the housing)")
    dof: Literal["x", "y", "z", "rx", "ry", "rz"]
    damping: float = Field(ge=0, description="N·s/m (x, y, z) or N·m·s/rad (rx, ry, rz)")
    stiffness: float = Field(0.0, ge=0, description="N/m or N·m/rad")


class WheelConfig(_Strict):
    pair: str = Field(description="name of the [[gear_geometry]] pair")
    gear: Literal["a", "b"]
    at: NodeRef


class MeshConfig(_Strict):
    pair: str
    slices: int = Field(5, ge=1, le=50)
    friction_coefficient: float = Field(0.03, ge=0, le=0.5)
    squeeze_film_ns_per_m: float = Field(100.0, ge=0)
    table_points_per_cycle: int = Field(64, ge=8, le=1024)
    off_line_of_action: bool = Field(
        True, description="extended contact outside the path (Thibault et al. 2024, §2.5.1; "
        "spur pairs)"
    )
    backlash_m: float | None = Field(
        None, ge=0, description="normal backlash along the line of action: tooth separation "
        "and back-flank contact (default: drive flank only)"
    )


class TorqueConfig(_Strict):
    at: NodeRef
    torque_nm: float = Field(0.0, description="constant part (drive: +, load: resisting)")


class SpeedLaw(_Strict):
    """Speed law of the reference shaft: linear ramp in time from start to end speed covering
    ``revolutions`` of the reference shaft (Thibault et al. 2024, Table 1)."""

    reference: NodeRef
    start_rpm: float = Field(gt=0)
    end_rpm: float = Field(gt=0)
    revolutions: float = Field(gt=0)
    bandwidth_hz: float = Field(2.0, gt=0, description="speed-controller bandwidth")


class SimulationConfig(_Strict):
    time_step_s: float | None = Field(None, gt=0, description="default: 0.8 × stability limit")
    record_rate_hz: float = Field(50_000.0, gt=0)
    revolutions: float | None = Field(
        None, gt=0, description="override of the speed-law revolutions (short runs)"
    )
    duration_s: float | None = Field(None, gt=0, description="plain torque laws: duration")
    initial_rpm: float | None = Field(
        None, gt=0, description="plain torque laws: initial speed of the drive shaft"
    )
    gyroscopic: bool = Field(
        False, description="gyroscopic terms Ω_s(t) G_s q̇ of shafts and wheels at each "
        "shaft's current speed in the time integration"
    )
    integrator: Literal["explicit", "newmark", "exponential", "modal", "auto"] = Field(
        "auto", description="explicit: velocity Verlet at 0.8 × the stability limit; newmark: "
        "implicit average acceleration with Newton iterations, 20 steps per period of "
        "resolved_frequency_hz; exponential: exact modal integration of a linear rotor at "
        "constant speed (no meshes, no Hertzian bearings; step = 1/record_rate_hz); modal: "
        "exact modal integration of the linear structure with the bearing, mesh and drive "
        "forces on a quadratic hold (modal damping only; no gyroscopic terms, unbalances, "
        "external loads, support damping), 4 steps per period of resolved_frequency_hz; "
        "auto: exponential where it applies, else modal, else newmark when its step is ≥ 4 × "
        "the explicit one, else explicit")
    resolved_frequency_hz: float | None = Field(
        None, gt=0, description="newmark and modal: highest frequency to resolve (newmark: "
        "step = 1/(20 f); modal: 1/(4 f)); default: the mesh harmonic of order a quarter of "
        "the stiffness table's points per cycle at the top mesh frequency (modal: one step "
        "per table point), or 10 orders of the top shaft speed without meshes")
    structural_frequency_hz: float | None = Field(
        None, gt=0, description="modal, default step only: the step follows the speed (one "
        "step per stiffness-table point at the current mesh frequency) but resolves this "
        "structural frequency at every speed (step ≤ 1/(4 f)), never shorter than the step at "
        "the top speed; default: the step at the top speed for the whole run")
    record: list[str] = Field(
        default_factory=list, description="extra outputs by name: a DOF "
        "('{shaft}.n{i}.{x,y,z,rx,ry,rz}'), a disc name (its node's x and y) or a support "
        "name (its force on the housing)")


class UnbalanceConfig(_Strict):
    """Rotating unbalance at a shaft node: force m e θ̇² along the node's rotating direction
    θz + phase (plus the tangential m e θ̈ term)."""

    at: NodeRef
    mass_eccentricity_kg_m: float = Field(gt=0, description="unbalance m·e in kg·m")
    phase_deg: float = Field(0.0, description="angle of the unbalance from +x at θz = 0")


class ExternalLoadConfig(_Strict):
    """Force or torque on one DOF of a node: F = value + amplitude·cos(2π f t + n θz + φ),
    θz the rotation of the node (time law: frequency_hz; angle law: order n per revolution)."""

    at: NodeRef
    dof: Literal["x", "y", "z", "rx", "ry", "rz"] = Field(
        description="x, y, z: force in N; rx, ry, rz: torque about that axis in N·m"
    )
    value: float = Field(0.0, description="constant part (N or N·m)")
    amplitude: float = Field(0.0, description="amplitude of the harmonic part (N or N·m)")
    frequency_hz: float = Field(0.0, ge=0, description="time law: frequency of the harmonic part")
    order: float = Field(0.0, description="angle law: cycles per revolution of the node")
    phase_deg: float = Field(0.0)


class TransmissionConfig(_Strict):
    modal_damping: float = Field(0.01, ge=0, lt=1)
    modal_damping_cutoff_hz: float | None = Field(
        None, gt=0, description="modal damping exactly on the modes below this frequency, "
        "stiffness-proportional (ratio ζ f/f_c) above it: no dense n² product in the time "
        "step (default: every mode, dense product)"
    )
    mass: Literal["consistent", "lumped"] = Field(
        "consistent", description="shaft-element mass matrix: consistent, or lumped (HRZ "
        "diagonal: diagonal M⁻¹ and a √3 longer stable explicit step)"
    )
    shafts: list[ShaftConfig] = Field(min_length=1)
    wheels: list[WheelConfig] = Field(default_factory=list)
    bearings: list[BearingConfig] = Field(default_factory=list)
    meshes: list[MeshConfig] = Field(default_factory=list)
    discs: list[DiscConfig] = Field(default_factory=list)
    supports: list[SupportConfig] = Field(default_factory=list)
    dashpots: list[DashpotConfig] = Field(default_factory=list)
    drive: TorqueConfig | None = Field(
        None, description="drive torque node (default: node 0 of the first shaft, 0 N·m)")
    load: TorqueConfig | None = Field(
        None, description="load torque node (default: last node of the first shaft, 0 N·m)")
    speed_law: SpeedLaw | None = None
    simulation: SimulationConfig = Field(default_factory=SimulationConfig)
    unbalance: list[UnbalanceConfig] = Field(default_factory=list)
    external_loads: list[ExternalLoadConfig] = Field(default_factory=list)

    @model_validator(mode="before")
    @classmethod
    def _default_torques(cls, data):  # noqa: ANN001, ANN206
        """A bare rotor needs no drive/load: 0 N·m at node 0 of the first shaft."""
        if isinstance(data, dict) and data.get("shafts"):
            first = data["shafts"][0]
            name = first.get("name") if isinstance(first, dict) else getattr(first, "name", None)
            if data.get("drive") is None and name is not None:
                data = {**data, "drive": {"at": {"shaft": name, "node": 0}, "torque_nm": 0.0}}
            last = first.get("elements", 5) if isinstance(first, dict) else first.elements
            if data.get("load") is None and name is not None:
                data = {**data, "load": {"at": {"shaft": name, "node": last}, "torque_nm": 0.0}}
        return data

    @model_validator(mode="after")
    def _refs(self) -> TransmissionConfig:
        shafts = {s.name: s for s in self.shafts}
        problems: list[str] = []
        if len(shafts) != len(self.shafts):
            problems.append("shafts: names must be unique")

        def check(ref: NodeRef, where: str) -> None:
            s = shafts.get(ref.shaft)
            if s is None:
                problems.append(f"{where}.shaft: unknown shaft '{ref.shaft}'")
            elif ref.node > s.elements:
                problems.append(
                    f"{where}.node: {ref.node} beyond the last node {s.elements} of '{s.name}'"
                )

        for i, w in enumerate(self.wheels):
            check(w.at, f"wheels[{i}].at")
        for i, b in enumerate(self.bearings):
            check(b.at, f"bearings[{i}] '{b.name}'.at")
        check(self.drive.at, "drive.at")
        check(self.load.at, "load.at")
        if self.speed_law is not None:
            check(self.speed_law.reference, "speed_law.reference")
        for i, u in enumerate(self.unbalance):
            check(u.at, f"unbalance[{i}].at")
        for i, x in enumerate(self.external_loads):
            check(x.at, f"external_loads[{i}].at")
        for i, d in enumerate(self.discs):
            check(d.at, f"discs[{i}] '{d.name}'.at")
        for i, b in enumerate(self.supports):
            check(b.at, f"supports[{i}] '{b.name}'.at")
        for i, d in enumerate(self.dashpots):
            check(d.at, f"dashpots[{i}] '{d.name}'.at")
            if d.to is not None:
                check(d.to, f"dashpots[{i}] '{d.name}'.to")
        names = [x.name for x in (*self.bearings, *self.supports, *self.discs, *self.dashpots)]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            problems.append(f"bearings/supports/discs/dashpots: names must be unique ({dup})")
        wheel_pairs = {(w.pair, w.gear) for w in self.wheels}
        mesh_pairs = {m.pair for m in self.meshes}
        for i, w in enumerate(self.wheels):
            if w.pair not in mesh_pairs:
                problems.append(f"wheels[{i}].pair: no [[transmission.meshes]] entry for pair "
                                f"'{w.pair}' (meshes: {', '.join(sorted(mesh_pairs)) or 'none'})")
        for i, m in enumerate(self.meshes):
            for g in ("a", "b"):
                if (m.pair, g) not in wheel_pairs:
                    problems.append(f"meshes[{i}].pair: no wheel for gear {g} of pair '{m.pair}'")
        if problems:
            raise ValueError("\n".join(problems))
        return self


def check_transmission(cfg) -> list[str]:  # noqa: ANN001 - GeardynConfig (avoid cycle)
    """Cross-checks against the gear geometry: pairs exist and shaft axes sit at the centre
    distance of each mesh."""
    t: TransmissionConfig | None = getattr(cfg, "transmission", None)
    if t is None:
        return []
    from geardyn.models.gear_pairs import pair_model  # noqa: PLC0415

    problems: list[str] = []
    shafts = {s.name: s for s in t.shafts}
    geometry_pairs = {g.pair for g in getattr(cfg, "gear_geometry", [])}
    for i, w in enumerate(t.wheels):
        if w.pair not in geometry_pairs:
            known = ", ".join(sorted(geometry_pairs)) or "none"
            problems.append(f"transmission.wheels[{i}].pair: unknown pair '{w.pair}' (pairs "
                            f"with [[gear_geometry]]: {known})")
    seen: dict[tuple[str, str], int] = {}
    for i, w in enumerate(t.wheels):
        if (w.pair, w.gear) in seen:
            problems.append(f"transmission.wheels[{i}]: gear {w.gear} of pair '{w.pair}' is "
                            f"already placed by wheels[{seen[(w.pair, w.gear)]}]")
        seen.setdefault((w.pair, w.gear), i)
    for i, m in enumerate(t.meshes):
        try:
            g = pair_model(cfg, m.pair).geometry
        except Exception as exc:  # noqa: BLE001 - reported with the field name
            problems.append(f"transmission.meshes[{i}].pair: {exc}")
            continue
        wa = next(w for w in t.wheels if w.pair == m.pair and w.gear == "a")
        wb = next(w for w in t.wheels if w.pair == m.pair and w.gear == "b")
        pa, pb = shafts[wa.at.shaft].position_m, shafts[wb.at.shaft].position_m
        dist = math.hypot(pb[0] - pa[0], pb[1] - pa[1])
        if abs(dist - g.centre_distance) > 1e-6:
            problems.append(
                f"transmission.shafts: axes of '{wa.at.shaft}' and '{wb.at.shaft}' are "
                f"{dist * 1e3:.4f} mm apart but pair '{m.pair}' needs the centre distance "
                f"{g.centre_distance * 1e3:.4f} mm"
            )
    return problems
