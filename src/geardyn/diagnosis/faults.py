"""The faults a config puts in a machine: the healthy variant of a config and the list of its
configured faults with the component each one sits on (the expected alarm of a diagnosis).

Faults live in three places of a config:

* ``planetary_dynamics.stages[].faults`` — seed 004 ch. 9 tooth crack / spall on the sun, the
  ring or planet ``planet`` (default 1) of a stage: a planet fault sits on that planet's
  component (``'planetary.planet2/z32'``);
* ``gear_geometry[].cracks`` / ``.spalls`` — root crack / spall on side ``a`` or ``b`` of a named
  gear pair (every planet of a stage for an unindexed ``'<stage>.sun-planet'`` entry);
* ``transmission.bearings[].outer_spall`` — outer-race spall of an FE-transmission bearing.

Components are named as in the kinematics tables (:func:`geardyn.kinematics.
characteristic_frequencies`): wheels by their ``wheels.wheel`` name (``'planetary.sun'``,
``'intermediate/z42'``), bearings by their name.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from geardyn.config.loader import parse_config

if TYPE_CHECKING:
    from geardyn.config.loader import GeardynConfig
    from geardyn.kinematics.graph import GearMesh


@dataclass(frozen=True)
class ConfiguredFault:
    """One fault of a config: the component it sits on (kinematics name), its kind (``wheel`` or
    ``bearing``), a description with sizes in SI units, the config field that holds it and the
    link (shaft) carrying the component (a shaft TSA contains its wheels, so an alarm on that
    shaft is consistent with the fault)."""

    component: str
    kind: str
    description: str
    field: str
    shaft: str = ""

    def __str__(self) -> str:
        return f"{self.component}: {self.description} ({self.field})"


def healthy_variant(cfg: GeardynConfig) -> GeardynConfig:
    """The same machine with every configured fault removed (validated again)."""
    data: dict[str, Any] = cfg.model_dump(exclude_unset=False)
    pd = data.get("planetary_dynamics")
    if pd:
        for stage in pd.get("stages", []):
            stage["faults"] = []
    for entry in data.get("gear_geometry", []):
        entry["cracks"] = []
        entry["spalls"] = []
    tr = data.get("transmission")
    if tr:
        for bearing in tr.get("bearings", []):
            bearing["outer_spall"] = None
    return parse_config(data, source="healthy variant")


def _wheel(mesh: GearMesh, side: str) -> tuple[str, str]:
    """Kinematics name of the wheel on side ``a``/``b`` of a mesh (as in ``freqs.wheels``)
    and its link."""
    link, wheel, teeth = (
        (mesh.link_a, mesh.wheel_a, mesh.teeth_a)
        if side == "a"
        else (mesh.link_b, mesh.wheel_b, mesh.teeth_b)
    )
    return wheel or f"{link}/z{teeth}", link


def _meshes_of(entry: str, meshes: list[GearMesh]) -> list[GearMesh]:
    """Meshes a ``gear_geometry`` entry names: the mesh itself, or every planet's mesh for an
    unindexed planetary entry ``'<stage>.sun-planet'``."""
    out = []
    for m in meshes:
        rest = m.name[len(entry):] if m.name.startswith(entry) else None
        if m.name == entry or (rest is not None and rest.isdigit() and m.stage is not None):
            out.append(m)
    return out


def _planetary_faults(cfg: GeardynConfig, meshes: dict[str, GearMesh]) -> list[ConfiguredFault]:
    out: list[ConfiguredFault] = []
    pd = cfg.planetary_dynamics
    if pd is None:
        return out
    for i, sd in enumerate(pd.stages):
        for j, f in enumerate(sd.faults):
            planet = f.planet_number or 1
            mesh_name = f"{sd.stage}.{'ring' if f.gear == 'ring' else 'sun'}-planet{planet}"
            mesh = meshes.get(mesh_name)
            side = "b" if f.gear == "planet" else "a"
            fallback = f"{sd.stage}.{f.gear}" + (str(planet) if f.gear == "planet" else "")
            component, link = _wheel(mesh, side) if mesh is not None else (fallback, "")
            if f.kind == "crack":
                what = f"tooth crack, {f.crack_fraction:.0%} of the tooth thickness"
            else:
                what = (f"tooth spall, depth {f.spall_depth_m * 1e3:.3g} mm at "
                        f"{f.spall_centre:.2f} of the path of contact")
            if f.gear == "planet":
                what += f", on planet {planet}"
            out.append(ConfiguredFault(component, "wheel", what,
                                       f"planetary_dynamics.stages[{i}].faults[{j}]", link))
    return out


def _geometry_faults(cfg: GeardynConfig, meshes: list[GearMesh]) -> list[ConfiguredFault]:
    out: list[ConfiguredFault] = []
    for i, entry in enumerate(cfg.gear_geometry):
        found = _meshes_of(entry.pair, meshes)
        items = [("cracks", j, c) for j, c in enumerate(entry.cracks)]
        items += [("spalls", j, s) for j, s in enumerate(entry.spalls)]
        for kind, j, fault in items:
            if kind == "cracks":
                what = f"root crack {fault.depth_m * 1e3:.3g} mm deep on tooth {fault.tooth}"
            else:
                what = (f"spall {fault.radial_width_m * 1e3:.3g} mm wide, "
                        f"{fault.depth_m * 1e3:.3g} mm deep on tooth {fault.tooth}")
            wheels = dict(_wheel(m, fault.gear) for m in found) or {
                f"{entry.pair}.{fault.gear}": ""
            }
            for name, link in wheels.items():
                out.append(ConfiguredFault(name, "wheel", what,
                                           f"gear_geometry[{i}] '{entry.pair}'.{kind}[{j}]", link))
    return out


def _bearing_faults(cfg: GeardynConfig, frame: str) -> list[ConfiguredFault]:
    tr = cfg.transmission
    if tr is None:
        return []
    links = {s.name: s.link or "" for s in tr.shafts}
    out = []
    for i, b in enumerate(tr.bearings):
        s = b.outer_spall
        if s is not None:
            what = (f"outer-race spall {s.angular_length_deg:.3g}° long, "
                    f"{s.depth_m * 1e3:.3g} mm deep at {s.angle_deg:.3g}°")
            link = links.get(b.at.shaft, "")
            out.append(ConfiguredFault(b.name, "bearing", what,
                                       f"transmission.bearings[{i}] '{b.name}'.outer_spall",
                                       link if link != frame else ""))
    return out


def fault_list(cfg: GeardynConfig) -> list[ConfiguredFault]:
    """Every fault configured in ``cfg`` with the component it sits on (empty if healthy)."""
    from geardyn.kinematics import analyze_kinematics

    graph = analyze_kinematics(cfg).graph
    meshes = list(graph.meshes)
    return (
        _planetary_faults(cfg, {m.name: m for m in meshes})
        + _geometry_faults(cfg, meshes)
        + _bearing_faults(cfg, graph.frame)
    )
