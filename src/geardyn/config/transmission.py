"""Config schema of the finite-element transmission (issue 6, seed 002 §3.1).

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
    """Outer-race spall (seed 002 §3.5.2)."""

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
    viscous_torque_nms_per_rad: float = Field(0.0, ge=0, description="α_bea of seed 002 §3.1")
    rolling_resistance: float = Field(
        0.0, ge=0, description="torque per (Σ contact load × d_m/2), dimensionless"
    )
    outer_spall: SpallConfig | None = None

    @model_validator(mode="after")
    def _geom(self) -> BearingConfig:
        if self.element_diameter_m >= self.pitch_diameter_m:
            raise ValueError("element_diameter_m must be < pitch_diameter_m")
        if self.kind == "roller":
            if self.roller_length_m is None:
                raise ValueError("roller bearings need roller_length_m")
            if 2 * self.roller_fillet_m >= self.roller_length_m:
                raise ValueError("roller_fillet_m: two fillets must be shorter than the roller")
        return self


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
        True, description="extended contact outside the path (seed 002 §2.5.1; spur pairs)"
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
    ``revolutions`` of the reference shaft (seed 002 Table 1)."""

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
    drive: TorqueConfig
    load: TorqueConfig
    speed_law: SpeedLaw | None = None
    simulation: SimulationConfig = Field(default_factory=SimulationConfig)
    unbalance: list[UnbalanceConfig] = Field(default_factory=list)
    external_loads: list[ExternalLoadConfig] = Field(default_factory=list)

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
    from geardyn.config.gears import pair_model  # noqa: PLC0415

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
