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
        "contact ratio (k_double = 2 k_single, seed 003 eq 1.11); gear_geometry: the PE table of "
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


class ShaftDynamics(_M):
    """Torsional shaft between two bodies (links or rotors); ``b`` may be the frame (a
    torsional support)."""

    name: str = Field(min_length=1)
    a: str
    b: str
    torsional_nm_per_rad: float = Field(gt=0)
    damping_nms_per_rad: float = Field(0.0, ge=0)


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
                             "terms of each carrier frame at its current speed (seed 003 eq "
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
    for i, sh in enumerate(dy.shafts):
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
