"""Config schema of the general torsional model of any geared mechanism: section ``[dynamics]``.

The mechanism description (links, gear pairs, turning pairs, stages) gives the graph; this
section adds what the dynamics needs and the kinematics does not (SI units, stated in the
field names):

* gear sizes: one ``module_m`` (and pressure angle, face width) for every gear pair, overridden
  per pair in ``[[dynamics.meshes]]`` (a pair name, a stage name, or ``<stage>.sun`` /
  ``<stage>.ring`` for the sun or ring meshes of a planetary stage);
* link inertias (``[[dynamics.links]]``); by default each link is the sum of its wheel blanks
  (steel discs of pitch diameter and face width, rings as annuli) — see docs/dynamics.md;
* extra rotors (motor, bucket wheel) and torsional shafts between bodies;
* ``[dynamics.simulation]``: run length, time step, damping and the drives, which reuse the
  planetary section's drive blocks (speed controls, torques, motor curve + fluid coupling,
  bucket-wheel load; :mod:`geardyn.config.planetary`).
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from geardyn.config.planetary import MotorDrive, SpeedControl, TorqueLoad, WheelLoad


class _M(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)


class LinkDynamics(_M):
    """Mass properties of one mechanism link (defaults from its gear blanks)."""

    link: str = Field(description="mechanism link")
    inertia_kgm2: float | None = Field(None, gt=0, description="polar moment of inertia about "
                                       "the link's own axis (kg·m²)")
    diametral_inertia_kgm2: float | None = Field(
        None, ge=0, description="moment of inertia about a diameter (kg·m²); matters only for "
        "links whose axis turns (bevel planet pinions); default half the polar one (thin disc)")
    mass_kg: float | None = Field(None, ge=0, description="mass (kg), for the orbit of a link "
                                  "carried off its carrier's axis (planets)")
    orbit_radius_m: float | None = Field(
        None, ge=0, description="distance of the link's centre from its carrier's axis (m); "
        "default from the pitch radii of its first mesh with a gear coaxial to the carrier")
    bearing_n_per_m: float = Field(
        0.0, ge=0, description="lateral model: bearing stiffness (N/m) in x and y to the frame "
        "(a link turning in the frame), or radial and tangential on its pin (a planet)")


class MeshDynamics(_M):
    """Gear size and stiffness law of a gear pair (or of every mesh of a stage)."""

    pair: str = Field(min_length=1, description="gear pair name, stage name, or '<stage>.sun' / "
                      "'<stage>.ring' for a planetary stage's sun or ring meshes")
    module_m: float | None = Field(None, gt=0, le=0.1, description="module (m); mean module for "
                                   "a bevel pair")
    pressure_angle_deg: float | None = Field(None, gt=0, lt=45)
    face_width_m: float | None = Field(None, gt=0, description="face width (m)")
    model: Literal["constant", "sine", "square", "gear_geometry"] = Field(
        "constant", description="constant k; sine k̄(1 + amplitude sin 2πX); square wave with the "
        "contact ratio (k_double = 2 k_single, Hammami 2015, eq 1.11); gear_geometry: the PE "
        "table of "
        "the pair's [[gear_geometry]] entry")
    stiffness_n_per_m: float | None = Field(
        None, gt=0, description="mean mesh stiffness along the line of action (N/m); default "
        "c_γ·b with c_γ = 2e10 N/m² (ISO 6336-1 mean mesh stiffness, 20 N/(mm·µm))")
    amplitude: float = Field(0.0, ge=0, lt=1, description="sine: relative amplitude")
    contact_ratio: float | None = Field(None, ge=1, le=2, description="square: contact ratio "
                                        "(default from the standard-addendum geometry)")
    damping_ratio: float | None = Field(None, ge=0, lt=1, description="mesh damping ratio ζ "
                                        "(c = 2ζ√(k m_eq))")
    transmission_error_m: float = Field(0.0, ge=0, description="amplitude of a sinusoidal "
                                        "transmission error at the mesh frequency (m)")
    backlash_m: float = Field(
        0.0, ge=0, description="normal backlash along the line of action (m): no force while "
        "−b < δ < 0 (δ > 0 on the flank loaded by the initial drives), back-flank contact "
        "F = k (δ + b) for δ ≤ −b; 0: no backlash (simulation.contact_loss then gives the "
        "one-sided law)")
    position_angle_deg: float | None = Field(
        None, description="lateral model: direction (deg) from gear a's centre to gear b's "
        "(from the internal gear's centre for an internal pair); planetary meshes take the "
        "planet angle; default 0")


class RotorDynamics(_M):
    """A body outside the mechanism (motor rotor, bucket wheel): DOF ``<name>.theta`` (rad)."""

    name: str = Field(min_length=1)
    inertia_kgm2: float = Field(gt=0)


#: Fields that describe a shaft by its geometry and material (an FE shaft).
SHAFT_GEOMETRY_FIELDS = ("outer_diameter_m", "inner_diameter_m", "length_m", "shear_modulus_pa",
                         "youngs_modulus_pa", "poisson_ratio", "density_kg_m3", "elements")


class ShaftDynamics(_M):
    """Shaft between two bodies (links or rotors); ``b`` may be the frame (a torsional
    support). Either a torsional spring (``torsional_nm_per_rad``) or, given by its geometry
    and material, a torsional FE shaft line of ``elements`` two-node elements whose inner nodes
    are DOFs of the model (:mod:`geardyn.models.core.fe_shafts`, docs/dynamics.md "FE
    shafts")."""

    name: str = Field(min_length=1)
    a: str
    b: str
    torsional_nm_per_rad: float | None = Field(
        None, gt=0, description="torsional stiffness of a massless shaft (N·m/rad); or give "
        "the geometry (outer_diameter_m, length_m, material) for an FE shaft")
    damping_nms_per_rad: float = Field(
        0.0, ge=0, description="damping between the two ends (N·m·s/rad); on an FE shaft "
        "stiffness-proportional, C = (c/k) K with k = G I_p / L, the same end-to-end damper "
        "for a massless shaft")
    outer_diameter_m: float | None = Field(None, gt=0, description="FE shaft: outer "
                                           "diameter (m)")
    inner_diameter_m: float = Field(0.0, ge=0, description="FE shaft: bore diameter (m)")
    length_m: float | None = Field(None, gt=0, description="FE shaft: length between the "
                                   "two bodies (m)")
    shear_modulus_pa: float | None = Field(None, gt=0, description="FE shaft: shear modulus "
                                           "G (Pa); or youngs_modulus_pa and poisson_ratio")
    youngs_modulus_pa: float | None = Field(None, gt=0, description="FE shaft: Young's "
                                            "modulus E (Pa), G = E / (2 (1 + ν))")
    poisson_ratio: float | None = Field(None, gt=-1, lt=0.5, description="FE shaft: "
                                        "Poisson's ratio ν")
    density_kg_m3: float = Field(7850.0, gt=0, description="FE shaft: density (kg/m³)")
    elements: int = Field(4, ge=1, le=200, description="FE shaft: number of two-node "
                          "torsional elements (elements − 1 inner nodes; 1: the two ends "
                          "only, consistent mass)")

    @model_validator(mode="after")
    def _one_description(self) -> ShaftDynamics:
        geometry = sorted(f for f in SHAFT_GEOMETRY_FIELDS if f in self.model_fields_set)
        if self.torsional_nm_per_rad is not None:
            if geometry:
                raise ValueError(
                    f"give either torsional_nm_per_rad (a massless torsional spring) or the "
                    f"shaft geometry (an FE shaft), not both: remove {', '.join(geometry)} or "
                    "torsional_nm_per_rad")
            return self
        missing = [f for f in ("outer_diameter_m", "length_m") if getattr(self, f) is None]
        if missing:
            raise ValueError(
                "a shaft needs torsional_nm_per_rad (a massless torsional spring) or its "
                "geometry and material (an FE shaft: outer_diameter_m, length_m, "
                "shear_modulus_pa or youngs_modulus_pa + poisson_ratio); missing "
                f"{', '.join(missing)}")
        e_nu = (self.youngs_modulus_pa is not None, self.poisson_ratio is not None)
        if (self.shear_modulus_pa is not None) == all(e_nu) or any(e_nu) != all(e_nu):
            raise ValueError(
                "shear_modulus_pa: give the shear modulus G, or youngs_modulus_pa and "
                "poisson_ratio (G = E / (2 (1 + ν))), exactly one of the two")
        if self.inner_diameter_m >= self.outer_diameter_m:  # type: ignore[operator]
            raise ValueError(f"inner_diameter_m: the bore {self.inner_diameter_m:g} m must be "
                             f"smaller than outer_diameter_m {self.outer_diameter_m:g} m")
        return self

    @property
    def is_fe(self) -> bool:
        """True for a shaft given by its geometry (an FE shaft line)."""
        return self.torsional_nm_per_rad is None

    @property
    def shear_modulus(self) -> float:
        """G (Pa): given, or E / (2 (1 + ν))."""
        if self.shear_modulus_pa is not None:
            return self.shear_modulus_pa
        return self.youngs_modulus_pa / (2 * (1 + self.poisson_ratio))  # type: ignore[operator]

    @property
    def polar_moment_m4(self) -> float:
        """Polar second moment of area of the tube, I_p = π (D⁴ − d⁴) / 32 (m⁴)."""
        d_o, d_i = float(self.outer_diameter_m or 0.0), self.inner_diameter_m
        return math.pi * (d_o**4 - d_i**4) / 32

    @property
    def stiffness_nm_per_rad(self) -> float:
        """End-to-end torsional stiffness (N·m/rad): given, or G I_p / L."""
        if self.torsional_nm_per_rad is not None:
            return self.torsional_nm_per_rad
        return self.shear_modulus * self.polar_moment_m4 / self.length_m  # type: ignore[operator]


class DynamicsSimulation(_M):
    """Time integration (Newmark average acceleration or HHT-α) and the drives."""

    t_end_s: float = Field(gt=0)
    dt_s: float = Field(gt=0)
    save_every: int = Field(1, ge=1)
    hht_alpha: float = Field(0.0, ge=0, le=1 / 3)
    solver: Literal["newmark", "lowrank"] = Field(
        "newmark", description="newmark: solve/integrate.py (dense solve per step); lowrank: "
        "constant part factored once, mesh changes as a Woodbury update (solve/lowrank.py)")
    contact_loss: bool = Field(False, description="mesh force 0 when the deflection is < 0 "
                               "(meshes without backlash_m; a backlash implies it)")
    gyroscopic: bool = Field(False, description="lateral model: gyroscopic and centripetal "
                             "terms of each carrier frame at its current speed (Hammami 2015, eq "
                             "3.1)")
    rayleigh_alpha: float = Field(0.0, ge=0, description="C += α M (1/s)")
    rayleigh_beta: float = Field(0.0, ge=0, description="C += β K_mean (s)")
    initial_state: Literal["rest", "static"] = Field(
        "rest", description="rest: undeformed, rigid-body speeds; static: deflected by the "
        "initial loads (quasi-static, the rigid-body acceleration removed): starts close to "
        "the steady state, without the start transient")
    initial_speed_rpm: dict[str, float] = Field(
        default_factory=dict, description="rigid-body initial speeds (body → rpm); the "
        "kinematics gives the other links")
    torques: list[TorqueLoad] = Field(default_factory=list)
    speed_controls: list[SpeedControl] = Field(default_factory=list)
    motor: MotorDrive | None = None
    wheel_load: WheelLoad | None = None

    @model_validator(mode="after")
    def _steps(self) -> DynamicsSimulation:
        if self.dt_s >= self.t_end_s:
            raise ValueError(f"dt_s: the time step {self.dt_s:g} s must be shorter than t_end_s "
                             f"{self.t_end_s:g} s")
        return self


class Dynamics(_M):
    """The general torsional model of the mechanism (docs/dynamics.md)."""

    module_m: float = Field(gt=0, le=0.1, description="module of every gear pair (m) unless a "
                            "[[dynamics.meshes]] entry says otherwise")
    pressure_angle_deg: float = Field(20.0, gt=0, lt=45)
    face_width_m: float | None = Field(None, gt=0, description="face width (m); default 10 "
                                       "modules")
    density_kg_m3: float = Field(7850.0, gt=0, description="density of the gear blanks")
    mesh_damping_ratio: float = Field(0.05, ge=0, lt=1, description="default mesh damping ratio "
                                      "(0.03-0.17 in the literature; Kahraman & Singh 1991)")
    lateral: bool = Field(
        False, description="add the lateral DOFs of Lin & Parker (1999): x, y of every link "
        "turning in the frame, radial/tangential ζ, η of every planet on its carrier")
    links: list[LinkDynamics] = Field(default_factory=list)
    meshes: list[MeshDynamics] = Field(default_factory=list)
    rotors: list[RotorDynamics] = Field(default_factory=list)
    shafts: list[ShaftDynamics] = Field(default_factory=list)
    simulation: DynamicsSimulation | None = None


def check_dynamics(cfg: object) -> list[str]:
    """Cross-checks of ``[dynamics]`` against the mechanism: names of links, pairs and bodies."""
    dy: Dynamics | None = getattr(cfg, "dynamics", None)
    if dy is None:
        return []
    problems: list[str] = []
    graph = cfg.graph()  # type: ignore[attr-defined]
    links = set(graph.links)
    frame = graph.frame
    rotors = [r.name for r in dy.rotors]
    bodies = (links - {frame}) | set(rotors)
    for i, lk in enumerate(dy.links):
        if lk.link not in links or lk.link == frame:
            problems.append(f"dynamics.links[{i}].link: '{lk.link}' is not a moving link "
                            f"(moving links: {', '.join(sorted(links - {frame}))})")
    pairs = {m.name for m in graph.meshes}
    stages = {m.stage for m in graph.meshes if m.stage}
    planetary = {s.name for s in graph.planetary_sets}
    known = pairs | stages | {f"{s}.{w}" for s in planetary for w in ("sun", "ring")}
    for i, me in enumerate(dy.meshes):
        if me.pair not in known:
            problems.append(f"dynamics.meshes[{i}].pair: unknown gear pair or stage "
                            f"'{me.pair}' (known: {', '.join(sorted(known))})")
    for i, r in enumerate(dy.rotors):
        if r.name in links or rotors.count(r.name) > 1:
            problems.append(f"dynamics.rotors[{i}].name: '{r.name}' is already a link or rotor")
    shaft_names = [sh.name for sh in dy.shafts]
    for i, sh in enumerate(dy.shafts):
        if sh.a == sh.b:
            problems.append(f"dynamics.shafts[{i}] '{sh.name}'.b: the shaft joins '{sh.a}' to "
                            "itself (a and b must be two different bodies)")
        if sh.is_fe and shaft_names.count(sh.name) > 1:
            problems.append(f"dynamics.shafts[{i}].name: '{sh.name}' is used by another shaft "
                            "(an FE shaft names its nodes '<name>.n<i>': names must be unique)")
        for side in ("a", "b"):
            name = getattr(sh, side)
            if name not in bodies and not (side == "b" and name == frame):
                problems.append(f"dynamics.shafts[{i}] '{sh.name}'.{side}: unknown body '{name}' "
                                f"(bodies: {', '.join(sorted(bodies))}; b may be the frame)")
    sim = dy.simulation
    if sim is not None:
        refs = [("torques", t.body) for t in sim.torques]
        refs += [("speed_controls", s.body) for s in sim.speed_controls]
        refs += [("initial_speed_rpm", b) for b in sim.initial_speed_rpm]
        if sim.motor:
            refs.append(("motor.rotor", sim.motor.rotor))
            if sim.motor.coupling_to:
                refs.append(("motor.coupling_to", sim.motor.coupling_to))
        if sim.wheel_load:
            refs.append(("wheel_load.body", sim.wheel_load.body))
        for where, name in refs:
            if name not in bodies:
                problems.append(f"dynamics.simulation.{where}: unknown body '{name}' "
                                f"(bodies: {', '.join(sorted(bodies))})")
    return problems
