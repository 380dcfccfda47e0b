"""Gear-pair builder: a validated ``[[gear_geometry]]`` entry and its mesh of the mechanism →
the physics objects of the pair (:class:`PairModel`: involute geometry, tooth faults, profile
corrections), which the stiffness tables, the FE transmission and the mechanism model use.

The config layer (:mod:`geardyn.config.gears`) only describes and names the entries; it calls
:func:`build_pair` to check them while loading (a bad rim radius, a spall outside the contact
zone or a crack through the tooth is a ConfigError naming the entry). Geometry: standard
involute relations (:func:`geardyn.gears.geometry.mesh_geometry`; Wang 2010, Table 4-2
formulas); faults: Thibault et al. 2024, eqs 13-14 (:mod:`geardyn.gears.faults`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numpy as np

from geardyn.errors import ConfigError

if TYPE_CHECKING:
    from geardyn.config.gears import GearGeometryConfig, WheelGeometry
    from geardyn.gears.faults import Crack, Spall
    from geardyn.gears.geometry import GearBlank, MeshGeometry
    from geardyn.gears.loaded import Corrections


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


def _blank(w: WheelGeometry, teeth: int, internal: bool) -> GearBlank:
    """The gear blank of one wheel (teeth, tool, radii, material)."""
    from geardyn.gears.geometry import GearBlank, Material

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


def _involute_pair(entry: GearGeometryConfig, ba: GearBlank, bb: GearBlank,
                   wa: WheelGeometry, wb: WheelGeometry, label: str) -> MeshGeometry:
    """Mesh geometry of the pinion ``ba`` (module and pressure angle of the entry) with the
    wheel ``bb`` (its own tool when given)."""
    from geardyn.gears.geometry import mesh_geometry

    if wa.normal_module_m is not None and abs(wa.normal_module_m - entry.normal_module_m) > 0:
        raise ConfigError(
            f"gear pair '{label}': the pinion module must equal normal_module_m (set the other "
            "wheel's normal_module_m to model a different tool)"
        )
    return mesh_geometry(
        ba,
        bb,
        entry.normal_module_m,
        math.radians(entry.normal_pressure_angle_deg),
        entry.face_width_m,
        math.radians(entry.helix_angle_deg),
        label=label,
        module_b=wb.normal_module_m,
        pressure_angle_b=(
            math.radians(wb.normal_pressure_angle_deg)
            if wb.normal_pressure_angle_deg is not None
            else None
        ),
    )


def _check_rims(geom: MeshGeometry, sides: tuple, swapped: bool, label: str) -> None:
    """A bore below the root circle of an external wheel, an outer rim above the root circle
    of an internal one (``sides``: (wheel config, blank, side name) of the model's a and b)."""
    for k, (w, b, name) in enumerate(sides):
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


def _slice_coupled(entry: GearGeometryConfig, geom: MeshGeometry, label: str) -> MeshGeometry:
    """The geometry with the face slices coupled when asked (Thibault et al. 2024, §2.2)."""
    if entry.slice_coupling_length_ratio is not None and not entry.slice_coupling:
        raise ConfigError(
            f"gear pair '{label}': slice_coupling_length_ratio is set but slice_coupling is "
            "false (set slice_coupling = true or remove the ratio)"
        )
    if not entry.slice_coupling:
        return geom
    from geardyn.gears.slice_coupling import with_slice_coupling

    return with_slice_coupling(geom, True, entry.slice_coupling_length_ratio)


def _tooth_faults(entry: GearGeometryConfig, teeth: dict[str, int],
                  side: Callable[[str], Literal["a", "b"]], label: str) -> list[Crack | Spall]:
    """The entry's root cracks and spalls on the model's sides (``side`` maps a/b of the
    mechanism to the model's), each tooth index checked against its wheel."""
    from geardyn.gears.faults import Crack, Spall

    faults: list[Crack | Spall] = []
    for i, c in enumerate(entry.cracks):
        if c.tooth >= teeth[c.gear]:
            raise ConfigError(
                f"gear pair '{label}': cracks[{i}].tooth {c.tooth} must be < {teeth[c.gear]} "
                f"(teeth of side {c.gear})"
            )
        if c.width_m is not None and c.width_m > entry.face_width_m:
            raise ConfigError(f"gear pair '{label}': cracks[{i}].width_m exceeds the face width")
        faults.append(Crack(side(c.gear), c.tooth, c.depth_m, math.radians(c.angle_deg),
                            c.radius_m, c.width_m, c.law))
    for i, s in enumerate(entry.spalls):
        if s.tooth >= teeth[s.gear]:
            raise ConfigError(
                f"gear pair '{label}': spalls[{i}].tooth {s.tooth} must be < {teeth[s.gear]}"
            )
        faults.append(Spall(side(s.gear), s.tooth, s.radius_m, s.radial_width_m, s.depth_m,
                            s.axial_position_m, s.axial_length_m))
    return faults


def _check_faults_act(geom: MeshGeometry, faults: list, n_cracks: int, label: str) -> None:
    """Faults must be able to act: a spall band within the contact zone of its wheel, a crack
    between root and tip and inside the tooth (its compliance computable)."""
    from geardyn.gears.faults import Crack, Spall

    r_contact = geom.contact_radii(np.array([geom.u_start, geom.u_end]))
    for i, f in enumerate(faults):
        k = 0 if f.gear == "a" else 1
        lo, hi = sorted(float(x) for x in r_contact[k])
        idx = i if isinstance(f, Crack) else i - n_cracks
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
            continue
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


def build_pair(entry: GearGeometryConfig, mesh, label: str) -> PairModel:  # noqa: ANN001
    """The :class:`PairModel` of one ``[[gear_geometry]]`` entry on ``mesh`` (a mesh of the
    mechanism graph): the external wheel is the model's pinion (side a), so an internal side a
    swaps the sides; ConfigError naming the pair for an entry that cannot be built."""
    from geardyn.gears.loaded import Corrections, TipRelief

    internal_a = abs(mesh.theta_a) > math.pi / 2
    internal_b = abs(mesh.theta_b) > math.pi / 2
    wa, wb = entry.a, entry.b
    ba = _blank(wa, mesh.teeth_a, internal_a)
    bb = _blank(wb, mesh.teeth_b, internal_b)
    swapped = internal_a
    if swapped:
        ba, bb, wa, wb = bb, ba, wb, wa
    geom = _involute_pair(entry, ba, bb, wa, wb, label)
    _check_rims(geom, ((wa, ba, "a"), (wb, bb, "b")), swapped, label)
    geom = _slice_coupled(entry, geom, label)

    def side(s: str) -> Literal["a", "b"]:
        if not swapped:
            return s  # type: ignore[return-value]
        return "b" if s == "a" else "a"

    faults = _tooth_faults(entry, {"a": mesh.teeth_a, "b": mesh.teeth_b}, side, label)
    _check_faults_act(geom, faults, len(entry.cracks), label)
    corr = Corrections(
        tuple(TipRelief(side(t.gear), t.amount_m, t.start_radius_m, t.shape)
              for t in entry.tip_reliefs),
        entry.lead_crowning_m,
        entry.profile_crowning_m,
    )
    return PairModel(label, geom, tuple(faults), corr, entry.torque_nm, swapped)


def pair_names(cfg) -> list[str]:  # noqa: ANN001
    """Names of the gear pairs that have geometry in the config."""
    from geardyn.config.gears import matches, mechanism_meshes

    meshes, _ = mechanism_meshes(cfg)
    return [m.name for m in meshes
            if any(matches(e.pair, m.name, m.stage) for e in cfg.gear_geometry)]


def pair_model(cfg, name: str) -> PairModel:  # noqa: ANN001
    """Resolve gear pair ``name`` of a loaded config into a :class:`PairModel`."""
    from geardyn.config.gears import matches, mechanism_meshes

    meshes, _ = mechanism_meshes(cfg)
    by_name = {m.name: m for m in meshes}
    if name not in by_name:
        raise ConfigError(
            f"--pair '{name}': no gear pair of that name (known: {', '.join(by_name)})"
        )
    mesh = by_name[name]
    for entry in cfg.gear_geometry:
        if matches(entry.pair, mesh.name, mesh.stage):
            return build_pair(entry, mesh, name)
    have = ", ".join(pair_names(cfg)) or "none"
    raise ConfigError(
        f"gear pair '{name}' has no [[gear_geometry]] entry (pairs with geometry: {have})"
    )
