"""Gear-geometry section of a config: ``[[gear_geometry]]`` entries attached to named gear pairs.

Each entry names a gear pair of the mechanism in ``pair``:

* a general pair (``gear_pairs[].name``, default ``'<link a>-<link b>'``) or a parallel stage
  (its ``name``);
* a planetary mesh ``'<stage>.sun-planet<i>'`` / ``'<stage>.ring-planet<i>'``, or
  ``'<stage>.sun-planet'`` / ``'<stage>.ring-planet'`` (no index) for every planet of the stage.

Tooth counts and which side is internal come from the mechanism; the entry's ``a``/``b`` blocks
describe the wheels on the pair's sides ``a``/``b`` (for planetary meshes: a = sun or ring,
b = planet). The stiffness model always takes the external wheel as its pinion: when side a
is internal (ring meshes), the sides are swapped internally and the stiffness table's angle is
the rotation of the planet. Units: metres (``*_m``), degrees (``*_deg``), pascals (``*_pa``),
newton-metres (``*_nm``). Bevel stages are not supported (cylindrical gears only).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, StrictInt

from geardyn.errors import ConfigError

if TYPE_CHECKING:
    from geardyn.gears.faults import Crack, Spall
    from geardyn.gears.geometry import MeshGeometry
    from geardyn.gears.loaded import Corrections


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


class WheelGeometry(_Model):
    """One wheel of a pair (sizes in m)."""

    profile_shift: float = Field(0.0, ge=-1.5, le=1.5, description="profile shift coefficient x")
    addendum_coef: float = Field(1.0, gt=0, le=2.0, description="h_a* (× normal module)")
    dedendum_coef: float = Field(1.25, gt=0, le=2.5, description="h_f* (× normal module)")
    tip_radius_m: float | None = Field(None, gt=0, description="tip radius override (m)")
    root_radius_m: float | None = Field(None, gt=0, description="root radius override (m)")
    rim_radius_m: float | None = Field(
        None, gt=0, description="bore radius (external) or outer rim radius (internal) (m)"
    )
    form_radius_m: float | None = Field(
        None, ge=0, description="radius where the usable involute starts (m); 0 = base circle"
    )
    tip_round_m: float = Field(0.0, ge=0, description="tip edge round radius (m)")
    root_fillet: Literal["involute", "trochoid"] = Field(
        "involute", description="flank below the involute in the PE stiffness: 'involute' "
        "(extended to the root, as the Thibault et al. 2024 / Wang 2010 tables) or 'trochoid' "
        "(the fillet cut by "
        "the rack tip, Sainsot root angle θ_f = b1/r)")
    rack_tip_radius_m: float | None = Field(
        None, gt=0, description="generating rack tip radius ρ_fP (m; trochoid fillet; default "
        "the full round of the basic rack)")
    normal_module_m: float | None = Field(
        None,
        gt=0,
        description="module of this wheel's tool if different (m); must give the same base pitch",
    )
    normal_pressure_angle_deg: float | None = Field(None, gt=0, lt=45)
    youngs_modulus_pa: float = Field(2.06e11, gt=0, description="Young's modulus (Pa)")
    poisson_ratio: float = Field(0.3, gt=0, lt=0.5, description="Poisson ratio")
    density_kg_m3: float = Field(7850.0, gt=0, description="density (kg/m³)")


class CrackConfig(_Model):
    """Root crack (Thibault et al. 2024, eq 14): on ``gear`` side a/b of the pair, tooth index
    from 0."""

    gear: Literal["a", "b"] = "b"
    tooth: StrictInt = Field(0, ge=0)
    depth_m: float = Field(gt=0, description="crack depth q0 (m)")
    angle_deg: float = Field(
        45.0, gt=0, lt=90, description="crack angle to the tooth perpendicular"
    )
    radius_m: float | None = Field(None, gt=0, description="start radius (m); default root circle")
    width_m: float | None = Field(None, gt=0, description="axial crack extent (m); default face")
    law: Literal["uniform", "linear", "parabolic"] = "uniform"


class SpallConfig(_Model):
    """Rectangular spall (Thibault et al. 2024, eq 13)."""

    gear: Literal["a", "b"] = "b"
    tooth: StrictInt = Field(0, ge=0)
    radius_m: float = Field(gt=0, description="radial centre of the spall (m)")
    radial_width_m: float = Field(gt=0, description="radial width d_r (m)")
    depth_m: float = Field(1e-4, gt=0, description="depth δ_spall (m)")
    axial_position_m: float | None = Field(
        None, ge=0, description="axial centre (m from face start)"
    )
    axial_length_m: float | None = Field(None, gt=0, description="axial length d_z (m)")


class TipReliefConfig(_Model):
    gear: Literal["a", "b"] = "a"
    amount_m: float = Field(gt=0, description="relief at the tip (m)")
    start_radius_m: float = Field(gt=0, description="radius where the relief starts (m)")
    shape: Literal["linear", "parabolic"] = "linear"


class GearGeometryConfig(_Model):
    """Geometry of a named gear pair (or of all planets' sun or ring meshes of a stage)."""

    pair: str = Field(min_length=1, description="gear pair / stage / planetary mesh name")
    normal_module_m: float = Field(
        gt=0, le=0.1, description="normal module m_n (m; a module over 0.1 m is refused: a value "
        "in mm typed into this m field)")
    normal_pressure_angle_deg: float = Field(20.0, gt=0, lt=45, description="α_n (deg)")
    helix_angle_deg: float = Field(0.0, gt=-60, lt=60, description="β (deg)")
    face_width_m: float = Field(gt=0, description="face width b (m)")
    a: WheelGeometry = Field(default_factory=WheelGeometry)
    b: WheelGeometry = Field(default_factory=WheelGeometry)
    cracks: list[CrackConfig] = Field(default_factory=list)
    spalls: list[SpallConfig] = Field(default_factory=list)
    tip_reliefs: list[TipReliefConfig] = Field(default_factory=list)
    lead_crowning_m: float = Field(0.0, ge=0, description="lead crowning at the face ends (m)")
    profile_crowning_m: float = Field(
        0.0, ge=0, description="profile crowning at the ends of the path of contact (m)"
    )
    torque_nm: float | None = Field(
        None, gt=0, description="torque on the pinion (N·m) for loaded-contact analysis"
    )
    slice_coupling: bool = Field(
        False, description="couple the face slices of each tooth in the mesh stiffness tables "
        "(Thibault et al. 2024, §2.2 unloaded-slice correction: two-parameter foundation, a "
        "partly loaded "
        "face is stiffer than its loaded slices alone); false = independent slices")
    slice_coupling_length_ratio: float | None = Field(
        None, gt=0, le=5, description="decay length of the slice coupling over the load height "
        "λ/h (dimensionless; default √(0.8 − ν) from the cantilever-plate derivation); needs "
        "slice_coupling = true")


@dataclass(frozen=True)
class PairModel:
    """A resolved pair: geometry plus faults and corrections, ready for the physics modules."""

    name: str
    geometry: MeshGeometry
    faults: tuple[Crack | Spall, ...]
    corrections: Corrections
    torque: float | None
    swapped: bool
    """True when the mechanism's side a (internal) became the model's side b."""


def _matches(entry: str, mesh_name: str, stage: str | None) -> bool:
    if entry == mesh_name:
        return True
    if stage is not None and mesh_name.startswith(entry):
        rest = mesh_name[len(entry) :]
        return entry in (f"{stage}.sun-planet", f"{stage}.ring-planet") and rest.isdigit()
    return False


def _build(cfg_entry: GearGeometryConfig, mesh, label: str) -> PairModel:  # noqa: ANN001
    from geardyn.gears.faults import Crack, Spall
    from geardyn.gears.geometry import GearBlank, Material, mesh_geometry
    from geardyn.gears.loaded import Corrections, TipRelief

    internal_a = abs(mesh.theta_a) > math.pi / 2
    internal_b = abs(mesh.theta_b) > math.pi / 2

    def blank(w: WheelGeometry, teeth: int, internal: bool) -> GearBlank:
        return GearBlank(
            teeth=teeth,
            internal=internal,
            profile_shift=w.profile_shift,
            addendum_coef=w.addendum_coef,
            dedendum_coef=w.dedendum_coef,
            tip_radius=w.tip_radius_m,
            root_radius=w.root_radius_m,
            rim_radius=w.rim_radius_m,
            tip_round=w.tip_round_m,
            form_radius=w.form_radius_m,
            root_fillet=w.root_fillet,
            rack_tip_radius=w.rack_tip_radius_m,
            material=Material(w.youngs_modulus_pa, w.poisson_ratio, w.density_kg_m3),
        )

    wa, wb = cfg_entry.a, cfg_entry.b
    ba = blank(wa, mesh.teeth_a, internal_a)
    bb = blank(wb, mesh.teeth_b, internal_b)
    swapped = internal_a
    if swapped:
        ba, bb, wa, wb = bb, ba, wb, wa
    if wa.normal_module_m is not None and abs(wa.normal_module_m - cfg_entry.normal_module_m) > 0:
        raise ConfigError(
            f"gear pair '{label}': the pinion module must equal normal_module_m (set the other "
            "wheel's normal_module_m to model a different tool)"
        )
    geom = mesh_geometry(
        ba,
        bb,
        cfg_entry.normal_module_m,
        math.radians(cfg_entry.normal_pressure_angle_deg),
        cfg_entry.face_width_m,
        math.radians(cfg_entry.helix_angle_deg),
        label=label,
        module_b=wb.normal_module_m,
        pressure_angle_b=(
            math.radians(wb.normal_pressure_angle_deg)
            if wb.normal_pressure_angle_deg is not None
            else None
        ),
    )

    for k, (w, b, name) in enumerate(((wa, ba, "a"), (wb, bb, "b"))):
        rim, root = w.rim_radius_m, geom.root_radius[k]
        if rim is None:
            continue
        side_name = ("b" if name == "a" else "a") if swapped else name
        if not b.internal and rim >= root:
            raise ConfigError(
                f"gear pair '{label}': {side_name}.rim_radius_m {rim:g} m (the bore of an "
                f"external gear) must be below its root radius {root:.6g} m")
        if b.internal and rim <= root:
            raise ConfigError(
                f"gear pair '{label}': {side_name}.rim_radius_m {rim:g} m (the outer rim of an "
                f"internal gear) must be above its root radius {root:.6g} m")
    if cfg_entry.slice_coupling_length_ratio is not None and not cfg_entry.slice_coupling:
        raise ConfigError(
            f"gear pair '{label}': slice_coupling_length_ratio is set but slice_coupling is "
            "false (set slice_coupling = true or remove the ratio)"
        )
    if cfg_entry.slice_coupling:
        from geardyn.gears.slice_coupling import with_slice_coupling

        geom = with_slice_coupling(geom, True, cfg_entry.slice_coupling_length_ratio)

    def side(s: str) -> Literal["a", "b"]:
        if not swapped:
            return s  # type: ignore[return-value]
        return "b" if s == "a" else "a"

    faults: list[Crack | Spall] = []
    teeth = {"a": mesh.teeth_a, "b": mesh.teeth_b}
    for i, c in enumerate(cfg_entry.cracks):
        if c.tooth >= teeth[c.gear]:
            raise ConfigError(
                f"gear pair '{label}': cracks[{i}].tooth {c.tooth} must be < {teeth[c.gear]} "
                f"(teeth of side {c.gear})"
            )
        if c.width_m is not None and c.width_m > cfg_entry.face_width_m:
            raise ConfigError(f"gear pair '{label}': cracks[{i}].width_m exceeds the face width")
        faults.append(
            Crack(
                side(c.gear),
                c.tooth,
                c.depth_m,
                math.radians(c.angle_deg),
                c.radius_m,
                c.width_m,
                c.law,
            )
        )
    for i, s in enumerate(cfg_entry.spalls):
        if s.tooth >= teeth[s.gear]:
            raise ConfigError(
                f"gear pair '{label}': spalls[{i}].tooth {s.tooth} must be < {teeth[s.gear]}"
            )
        faults.append(
            Spall(
                side(s.gear),
                s.tooth,
                s.radius_m,
                s.radial_width_m,
                s.depth_m,
                s.axial_position_m,
                s.axial_length_m,
            )
        )
    # faults must be able to act: spall band within the contact zone, crack inside the tooth
    u_ends = np.array([geom.u_start, geom.u_end])
    r_contact = geom.contact_radii(u_ends)
    for i, f in enumerate(faults):
        k = 0 if f.gear == "a" else 1
        lo, hi = sorted(float(x) for x in r_contact[k])
        kind = "cracks" if isinstance(f, Crack) else "spalls"
        idx = i if kind == "cracks" else i - len(cfg_entry.cracks)
        if isinstance(f, Spall):
            if f.radius + f.radial_width / 2 < lo or f.radius - f.radial_width / 2 > hi:
                raise ConfigError(
                    f"gear pair '{label}': spalls[{idx}].radius_m {f.radius * 1e3:.3f} mm "
                    f"(± {f.radial_width * 5e2:.3f} mm) is outside the contact zone of that "
                    f"wheel ({lo * 1e3:.3f} to {hi * 1e3:.3f} mm): it would never be in contact"
                )
            if f.axial_position is not None and not 0 <= f.axial_position <= geom.face_width:
                raise ConfigError(
                    f"gear pair '{label}': spalls[{idx}].axial_position_m must lie on the face "
                    f"(0 to {geom.face_width} m)"
                )
        else:
            rr = (geom.root_radius[k], geom.tip_radius[k])
            if f.radius is not None and not min(rr) <= f.radius <= max(rr):
                raise ConfigError(
                    f"gear pair '{label}': cracks[{idx}].radius_m must lie between the root and "
                    f"tip radii ({min(rr) * 1e3:.3f} to {max(rr) * 1e3:.3f} mm)"
                )
            from geardyn.errors import InputError
            from geardyn.gears.pe_stiffness import tooth_compliance

            try:
                tooth_compliance(geom, k, np.array([0.5 * (lo + hi)]), f.depth, f)
            except InputError as exc:
                raise ConfigError(f"gear pair '{label}': cracks[{idx}]: {exc}") from None
    corr = Corrections(
        tuple(
            TipRelief(side(t.gear), t.amount_m, t.start_radius_m, t.shape)
            for t in cfg_entry.tip_reliefs
        ),
        cfg_entry.lead_crowning_m,
        cfg_entry.profile_crowning_m,
    )
    return PairModel(label, geom, tuple(faults), corr, cfg_entry.torque_nm, swapped)


def _meshes(cfg):  # noqa: ANN001, ANN202
    from geardyn.config.mechanism import BevelStage

    bevel = {st.name for st in cfg.bevel if isinstance(st, BevelStage)}
    return [m for m in cfg.graph().meshes], bevel


def check_gear_geometry(cfg) -> list[str]:  # noqa: ANN001
    """Problems of the ``gear_geometry`` section (one message per problem, naming the entry)."""
    problems: list[str] = []
    if not cfg.gear_geometry:
        return problems
    meshes, bevel = _meshes(cfg)
    seen: dict[str, int] = {}
    for i, entry in enumerate(cfg.gear_geometry):
        where = f"gear_geometry[{i}] (pair '{entry.pair}')"
        if entry.pair in bevel:
            problems.append(f"{where}: bevel stages are not supported (cylindrical gears only)")
            continue
        matched = [m for m in meshes if _matches(entry.pair, m.name, m.stage)]
        if not matched:
            names = ", ".join(m.name for m in meshes)
            problems.append(f"{where}: no gear pair of that name (known: {names})")
            continue
        for m in matched:
            if m.name in seen:
                problems.append(
                    f"{where}: pair '{m.name}' already has geometry (gear_geometry[{seen[m.name]}])"
                )
            seen[m.name] = i
        try:
            _build(entry, matched[0], matched[0].name)
        except ConfigError as exc:
            problems.extend(f"gear_geometry[{i}]: {p}" for p in exc.problems)
    return problems


def pair_names(cfg) -> list[str]:  # noqa: ANN001
    """Names of the gear pairs that have geometry in the config."""
    meshes, _ = _meshes(cfg)
    out = []
    for m in meshes:
        if any(_matches(e.pair, m.name, m.stage) for e in cfg.gear_geometry):
            out.append(m.name)
    return out


def pair_model(cfg, name: str) -> PairModel:  # noqa: ANN001
    """Resolve gear pair ``name`` of a loaded config into a :class:`PairModel`."""
    meshes, _ = _meshes(cfg)
    by_name = {m.name: m for m in meshes}
    if name not in by_name:
        raise ConfigError(
            f"--pair '{name}': no gear pair of that name (known: {', '.join(by_name)})"
        )
    mesh = by_name[name]
    for entry in cfg.gear_geometry:
        if _matches(entry.pair, mesh.name, mesh.stage):
            return _build(entry, mesh, name)
    have = ", ".join(pair_names(cfg)) or "none"
    raise ConfigError(
        f"gear pair '{name}' has no [[gear_geometry]] entry (pairs with geometry: {have})"
    )
