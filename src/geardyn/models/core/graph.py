"""Graph → model: the torsional dynamic model of any mechanism of the seed 000 form.

Coordinates. The turning pairs form a tree rooted at the frame (breadth first); every moving
link ``l`` gets one coordinate ``q_l`` (rad): its rotation relative to its parent ``p(l)``
about the axis of their turning pair. In the complex notation of seed 000 (§2.5: an angular
velocity is ``|ω| e^{iφ}`` in the plane of the sketch) the link's angular velocity is

    Ω_l = Ω_{p(l)} + e^{iφ_l} q̇_l,         i.e.   Ω = P q̇   (P complex, links × n),

where ``φ_l`` (mod π) is the direction of the turning-pair axis, read from the kinematic
nullspace (the relative velocity of two links joined by a turning pair lies along its axis).

Meshes. Row ``w`` of the constraint matrix (seed 000 eq 2: the Willis relation of the pair
relative to its carrier k, eq 1) gives ``w P q̇ = 0`` for every rigid-body motion. For a valid
geometry ``w P`` is a complex number times a real row (both gears' contact velocities lie
along the common tooth axis ψ), so the mesh deflection along the line of action is

    δ = (m cos α / 2) · Re(e^{−iψ} w P) q   (m: module, α: pressure angle),

the Willis row scaled by the base radii (r_b = m z cos α / 2): the rigid-body modes of the
model are exactly the kinematic nullspace (seed 000 eq 5). For a planetary stage this is the
torsional Lin & Parker deflection, δ_sp = r_bs(θ_s − θ_c) + r_bp(θ_p − θ_c) (seed 003 notes
§2.3 with r_c cos α_s = r_bs + r_bp).

Kinetic energy. Each link is axisymmetric about its own axis: ½ J (Re e^{−iφ_l} Ω_l)² +
½ J_d (Im e^{−iφ_l} Ω_l)², plus ½ m r_o² ω_p² for a link whose centre sits at distance r_o from
the axis of its carrier p (planets; bevel planet pinions).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from geardyn.config.dynamics import Dynamics, MeshDynamics
from geardyn.errors import ConfigError, KinematicsError
from geardyn.gears import planet_mesh_phases, square_wave
from geardyn.kinematics.graph import GearMesh, MechanismGraph
from geardyn.kinematics.willis import (
    KinematicAnalysis,
    _half_turn,
    analyze_graph,
    turning_tree,
)
from geardyn.models.core.assembly import Assembly, RankOne
from geardyn.models.core.blanks import Blank, contact_ratio, disc_blank, wheel_blank
from geardyn.models.core.fe_shafts import add_shaft_nodes, inner_node_count, stamp_fe_shaft
from geardyn.models.core.lateral import (
    LateralBody,
    add_lateral_mass,
    add_rotating_frames,
    bearing_springs,
    bevel_translation,
    lateral_layout,
    lateral_map_3d,
    mesh_translation,
)
from geardyn.models.core.model import MESH, Body, CoreModel, MeshElement, Spring

#: ISO 6336-1 mean mesh stiffness per unit face width, c_γα ≈ 20 N/(mm·µm) = 2e10 N/m².
C_GAMMA = 2.0e10
#: Samples per mesh cycle of the sine/square stiffness and error tables.
SAMPLES_PER_CYCLE = 64
_TOL = 1e-9


@dataclass(frozen=True)
class PairSize:
    """Module (m), pressure angle (rad), face width (m) and law of one gear pair."""

    module: float
    alpha: float
    face_width: float
    settings: MeshDynamics


def physical_basis(kin: KinematicAnalysis, inputs: Sequence[str] | None = None) -> np.ndarray:
    """A basis (links × dof, complex) of the physical motions (seed 000 eq 5).

    The physical motions are the real rotations about the turning-pair axes allowed by every
    Willis row (:attr:`KinematicAnalysis.physical`); they do not depend on which links are
    inputs. ``inputs`` (when they fix the motion) only normalises the basis: column c is the
    motion with input c at unit speed about its own axis; the model built on either basis is
    the same.
    """
    if kin.dof == 0:
        return np.zeros((len(kin.links), 0), complex)
    if inputs is not None and len(inputs) == kin.dof:
        return kin.velocity_ratios(list(inputs))
    return kin.physical


def axis_directions(tree: list[tuple[str, str]], kin: KinematicAnalysis) -> dict[str, float]:
    """Direction φ (rad, sketch plane) of each link's turning-pair axis, from the pitch angles
    (:func:`geardyn.kinematics.willis.axis_directions`), checked against the motions: the
    relative angular velocity of a link in its parent must lie along that axis."""
    idx = {x: i for i, x in enumerate(kin.links)}
    omega0 = kin.physical
    scale = max(float(np.abs(omega0).max()) if omega0.size else 1.0, 1.0)
    for link, parent in tree:
        rel = omega0[idx[link]] - omega0[idx[parent]]
        if rel.size == 0 or np.abs(rel).max() <= _TOL * scale:
            continue
        off = np.abs((rel * np.exp(-1j * kin.axes[link])).imag).max()
        if off > 1e-7 * np.abs(rel).max():
            raise KinematicsError(
                f"link '{link}' turning in '{parent}': its relative angular velocity is not "
                f"along one axis in every motion (off-axis part {off:.3g}); check the pitch "
                "angles of its gears (Penaud et al. 2012, §2.2)")
    return dict(kin.axes)


def velocity_map(tree: list[tuple[str, str]], phi: Mapping[str, float], graph: MechanismGraph,
                 n: int) -> np.ndarray:
    """P (links × n, complex): Ω = P q̇ with q_i the i-th tree link's relative rotation."""
    p = np.zeros((len(graph.links), n), complex)
    idx = {x: i for i, x in enumerate(graph.links)}
    for i, (link, parent) in enumerate(tree):
        p[idx[link]] = p[idx[parent]]
        p[idx[link], i] += np.exp(1j * phi[link])
    return p


def _pair_size(mesh: GearMesh, spec: Dynamics,
               geometry: Mapping[str, tuple[float, float, float]] | None = None) -> PairSize:
    """Settings of a mesh: exact pair name, then '<stage>.sun|ring', then the stage name; the
    module, pressure angle and face width of a [[gear_geometry]] entry (``geometry``: mesh name
    → (m, α deg, b)) come before the section defaults."""
    keys = [mesh.name]
    if mesh.stage and mesh.name.startswith(f"{mesh.stage}."):
        role = mesh.name[len(mesh.stage) + 1:].split("-")[0]
        keys.append(f"{mesh.stage}.{role}")
    if mesh.stage:
        keys.append(mesh.stage)
    by = {m.pair: m for m in spec.meshes}
    s = next((by[k] for k in keys if k in by), MeshDynamics(pair=mesh.name))
    g_mod, g_alpha, g_width = (geometry or {}).get(mesh.name, (None, None, None))
    module = s.module_m or g_mod or spec.module_m
    alpha = math.radians(s.pressure_angle_deg or g_alpha or spec.pressure_angle_deg)
    width = s.face_width_m or g_width or spec.face_width_m or 10 * module
    return PairSize(module, alpha, width, s)


def _internal(theta: float) -> bool:
    return abs(theta) > math.pi / 2


def _real_row(row: np.ndarray, where: str) -> tuple[np.ndarray, float]:
    """(Re(e^{−iψ} row), ψ) with ψ the phase of the largest entry; checks Im ≈ 0."""
    j = int(np.argmax(np.abs(row)))
    psi = _half_turn(float(np.angle(row[j])))
    r = row * np.exp(-1j * psi)
    if np.abs(r.imag).max() > 1e-7 * np.abs(row).max():
        raise KinematicsError(
            f"{where}: the contact velocities of the two gears are not along one tooth axis "
            f"(imaginary residue {np.abs(r.imag).max():.3g}); check the pitch angles "
            "(Penaud et al. 2012, §2.2)")
    return r.real, psi


def _stiffness_table(size: PairSize, mesh: GearMesh, k_mean: float,
                     pe: Mapping[str, np.ndarray]) -> np.ndarray:
    s = size.settings
    x = np.arange(SAMPLES_PER_CYCLE) / SAMPLES_PER_CYCLE
    if s.model == "constant":
        return np.array([k_mean])
    if s.model == "sine":
        return k_mean * (1 + s.amplitude * np.sin(2 * math.pi * x))
    if s.model == "square":
        eps = s.contact_ratio or contact_ratio(
            size.module, mesh.teeth_b if _internal(mesh.theta_a) else mesh.teeth_a,
            mesh.teeth_a if _internal(mesh.theta_a) else mesh.teeth_b, size.alpha,
            internal_b=_internal(mesh.theta_a) or _internal(mesh.theta_b))
        eps = min(max(eps, 1.0), 2.0)
        k_single = k_mean / eps  # k_double = 2 k_single; mean k_d(ε−1) + k_s(2−ε) = k_s ε
        return square_wave(x, 2 * k_single, k_single, eps)
    if mesh.name not in pe:
        raise ConfigError(f"dynamics.meshes '{s.pair}': model 'gear_geometry' needs a "
                          f"[[gear_geometry]] entry for pair '{mesh.name}'")
    return np.asarray(pe[mesh.name], float)


def _inertias(graph: MechanismGraph, spec: Dynamics, sizes: dict[str, PairSize],
              tree: list[tuple[str, str]]) -> tuple[dict[str, Blank], dict[str, float]]:
    """Blank of every moving link (sum of its wheels, or a carrier disc) and orbit radii."""
    wheels: dict[str, dict[str, Blank]] = {x: {} for x in graph.links}
    radius: dict[tuple[str, str], float] = {}  # (mesh, link) → pitch radius
    for m in graph.meshes:
        sz = sizes[m.name]
        for link, z, th, wheel in ((m.link_a, m.teeth_a, m.theta_a, m.wheel_a),
                                   (m.link_b, m.teeth_b, m.theta_b, m.wheel_b)):
            radius[(m.name, link)] = sz.module * z / 2
            wheels[link].setdefault(wheel or f"{link}/z{z}", wheel_blank(
                sz.module, z, sz.face_width, spec.density_kg_m3, _internal(th)))
    orbit: dict[str, float] = {}
    coaxial = _coaxial_groups(graph)
    for link, p in tree:
        if p == graph.frame:
            continue
        for m in graph.meshes:
            if link not in (m.link_a, m.link_b):
                continue
            other = m.link_b if m.link_a == link else m.link_a
            th_o = m.theta_b if m.link_a == link else m.theta_a
            th_l = m.theta_a if m.link_a == link else m.theta_b
            if other not in coaxial.get(p, {p}):
                continue
            r_l, r_o = radius[(m.name, link)], radius[(m.name, other)]
            if abs(math.sin(th_l)) > 1e-9 or abs(math.sin(th_o)) > 1e-9:
                orbit[link] = r_o  # bevel planet pinion: centre near the side gear's radius
            else:
                orbit[link] = r_o - r_l if _internal(th_o) else r_o + r_l
            break
    out: dict[str, Blank] = {}
    given = {lk.link: lk for lk in spec.links}
    children: dict[str, list[str]] = {}
    for link, p in tree:
        children.setdefault(p, []).append(link)
    for link, _p in tree:
        bl = list(wheels[link].values())
        if bl:
            blank = Blank(sum(b.mass for b in bl), sum(b.inertia for b in bl),
                          sum(b.diametral for b in bl))
        elif any(c in orbit for c in children.get(link, [])):
            carried = [c for c in children[link] if c in orbit]
            r = max(orbit[c] + max(radius[k] for k in radius if k[1] == c) for c in carried)
            w = max(sizes[m.name].face_width for m in graph.meshes
                    if m.link_a in carried or m.link_b in carried)
            blank = disc_blank(r, w, spec.density_kg_m3)
        else:
            blank = None  # type: ignore[assignment]
        g = given.get(link)
        if g is not None:
            if g.orbit_radius_m is not None:
                orbit[link] = g.orbit_radius_m
            if g.inertia_kgm2 is not None:
                j = g.inertia_kgm2
                mass = g.mass_kg if g.mass_kg is not None else (blank.mass if blank else 0.0)
                jd = g.diametral_inertia_kgm2 if g.diametral_inertia_kgm2 is not None else j / 2
                blank = Blank(mass, j, jd)
            elif blank is not None:
                blank = Blank(g.mass_kg if g.mass_kg is not None else blank.mass, blank.inertia,
                              g.diametral_inertia_kgm2 if g.diametral_inertia_kgm2 is not None
                              else blank.diametral)
        if blank is None:
            raise ConfigError(f"dynamics.links: link '{link}' carries no gear and no planet, so "
                              "its inertia has no default; give inertia_kgm2 in "
                              "[[dynamics.links]]")
        out[link] = blank
    return out, orbit


def _coaxial_groups(graph: MechanismGraph) -> dict[str, set[str]]:
    """Links turning about the same axis as each link (joined on one axis level)."""
    from geardyn.kinematics.willis import multi_turning_pairs

    out: dict[str, set[str]] = {}
    for _level, comp in multi_turning_pairs(graph):
        for x in comp:
            out.setdefault(x, {x}).update(comp)
    return out


def build_model(graph: MechanismGraph, spec: Dynamics, inputs: Sequence[str] | None = None,
                pe_tables: Mapping[str, np.ndarray] | None = None,
                geometry: Mapping[str, tuple[float, float, float]] | None = None) -> CoreModel:
    """The torsional model of ``graph`` with the sizes and laws of ``spec`` (module docstring).

    ``inputs``: links whose unit speeds define the physical motions (default: see
    :func:`physical_basis`); ``pe_tables``: mesh name → stiffness over one mesh cycle (N/m) for
    meshes with ``model = "gear_geometry"``; ``geometry``: mesh name → (module m, pressure
    angle deg, face width m) of its [[gear_geometry]] entry.
    """
    kin = analyze_graph(graph)
    omega0 = physical_basis(kin, inputs)
    tree = turning_tree(graph)
    phi = axis_directions(tree, kin)
    n_links = len(tree)
    rotors = list(spec.rotors)
    layout = (lateral_layout(tree, phi, graph, n_links + len(rotors)) if spec.lateral
              else {})
    n = n_links + len(rotors) + 2 * len(layout) + inner_node_count(spec.shafts)
    pmap = velocity_map(tree, phi, graph, n)
    idx = {x: i for i, x in enumerate(graph.links)}
    qdot = np.array([[(np.exp(-1j * phi[x]) * (omega0[idx[x], c] - omega0[idx[p], c])).real
                      for c in range(kin.dof)] for x, p in tree]).reshape(n_links, kin.dof)
    if kin.dof and np.abs(pmap[:, :n_links] @ qdot - omega0).max() > 1e-7 * max(
            1.0, float(np.abs(omega0).max())):
        raise KinematicsError(f"mechanism '{graph.name}': the kinematic motions are not "
                              "rotations about the turning-pair axes (check pitch angles)")
    sizes = {m.name: _pair_size(m, spec, geometry) for m in graph.meshes}
    blanks, orbit = _inertias(graph, spec, sizes, tree)

    # named DOFs: the links' relative rotations, the rotors, the lateral translations
    asm = Assembly()
    for x, _p in tree:
        asm.add_dofs(x, ["theta"])
    for r in rotors:
        asm.add_dofs(r.name, ["theta"], [r.inertia_kgm2])
    for lb in layout.values():
        asm.add_dofs(lb.link, ["x", "y"] if lb.kind == "fixed" else ["zeta", "eta"])
    add_shaft_nodes(asm, spec.shafts)  # FE shaft inner nodes <shaft>.n<i>.theta (fe_shafts.py)
    # mass: one inertia block per link (module docstring)
    bodies: dict[str, Body] = {}
    for i, (link, p) in enumerate(tree):
        rel = np.exp(-1j * phi[link]) * pmap[idx[link]]
        b = blanks[link]
        asm.add_mapped(f"{link}.inertia", "inertia", np.array([rel.real, rel.imag]),
                       M=np.diag([b.inertia, b.diametral]))
        if p != graph.frame and orbit.get(link, 0.0) > 0 and link not in layout:
            hp = (np.exp(-1j * phi[p]) * pmap[idx[p]]).real
            asm.add_mapped(f"{link}.orbit", "inertia", hp, M=[[b.mass * orbit[link] ** 2]])
        bodies[link] = Body(link, "link", rel.real.copy(), b.inertia,
                            i if p == graph.frame else None)
    for j, r in enumerate(rotors):
        k = n_links + j
        bodies[r.name] = Body(r.name, "rotor", asm.row({k: 1.0}), r.inertia_kgm2, k)

    if layout:
        rot = {x: b.rotation for x, b in bodies.items()}
        masses = {x: blanks[x].mass for x in layout}
        add_lateral_mass(asm, layout, masses, orbit, rot)
        add_rotating_frames(asm, layout, masses, orbit, rot, _coaxial_groups(graph))
        given = {lk.link: lk.bearing_n_per_m for lk in spec.links}
        for e in bearing_springs(layout, given, n):
            asm.add_rank_one(e)
    for sh in spec.shafts:
        ha = bodies[sh.a].rotation
        hb = np.zeros(n) if sh.b == graph.frame else bodies[sh.b].rotation
        if sh.is_fe:
            stamp_fe_shaft(asm, sh, ha, hb, lateral=bool(layout))
            continue
        asm.add_rank_one(Spring(sh.name, "support" if sh.b == graph.frame else "shaft",
                                sh.torsional_nm_per_rad, ha - hb, sh.damping_nms_per_rad))
    meshes = _meshes(graph, kin, pmap, phi, sizes, blanks, spec.mesh_damping_ratio,
                     pe_tables or {}, layout, tree)
    for m in meshes:
        asm.add_rank_one(RankOne(m.name, MESH, m.k_mean, m.a.copy(), m.c))
    return CoreModel(asm, meshes, bodies, list(graph.links), pmap, graph.frame)


def _meshes(graph: MechanismGraph, kin: KinematicAnalysis, pmap: np.ndarray,
            phi: Mapping[str, float], sizes: Mapping[str, PairSize],
            blanks: Mapping[str, Blank], zeta_default: float,
            pe: Mapping[str, np.ndarray], layout: Mapping[str, LateralBody],
            tree: list[tuple[str, str]]) -> list[MeshElement]:
    idx = {x: i for i, x in enumerate(graph.links)}
    phases = _planet_phases(graph)
    parent = dict(tree)
    own = {x: i for i, (x, _p) in enumerate(tree)}
    out = []
    for row, (m, k) in enumerate(zip(graph.meshes, kin.carriers, strict=True), start=1):
        sz = sizes[m.name]
        where = f"gear pair '{m.name}'"
        real, psi = _real_row(kin.M[row] @ pmap, where)
        # orient δ so that gear a's own rotation relative to the carrier counts positive
        # (Lin & Parker: +u_s for the sun mesh, +u_r for the ring mesh)
        if (np.exp(1j * (m.theta_a + phi[m.link_a] - psi))).real < 0:
            real = -real
        a = sz.module * math.cos(sz.alpha) / 2 * real
        a = a + mesh_translation(m, layout, sz.alpha, sz.settings.position_angle_deg, len(a))
        if layout and (abs(math.sin(m.theta_a)) > 1e-9 or abs(math.sin(m.theta_b)) > 1e-9):
            centre = tuple(lateral_map_3d(x, layout, phi, parent, len(a))
                           for x in (m.link_a, m.link_b))
            a = a + bevel_translation(m, a, psi, sz.alpha, phi, own, centre)  # type: ignore[arg-type]
        rel_a = np.exp(-1j * phi[m.link_a]) * (pmap[idx[m.link_a]] - pmap[idx[k]])
        b = m.teeth_a / (2 * math.pi) * rel_a.real
        s = sz.settings
        k_mean = s.stiffness_n_per_m or C_GAMMA * sz.face_width
        ktab = _stiffness_table(sz, m, k_mean, pe)
        k_mean = float(np.mean(ktab))
        rb_a = sz.module * m.teeth_a * math.cos(sz.alpha) / 2
        rb_b = sz.module * m.teeth_b * math.cos(sz.alpha) / 2
        compliance = sum(rb**2 / blanks[x].inertia for x, rb in ((m.link_a, rb_a),
                                                                  (m.link_b, rb_b))
                         if x != graph.frame)
        zeta = s.damping_ratio if s.damping_ratio is not None else zeta_default
        c = 2 * zeta * math.sqrt(k_mean / compliance) if compliance > 0 else 0.0
        x = np.arange(SAMPLES_PER_CYCLE) / SAMPLES_PER_CYCLE
        e = (s.transmission_error_m * np.sin(2 * math.pi * x) if s.transmission_error_m > 0
             else np.zeros(1))
        out.append(MeshElement(
            m.name, m.link_a, m.link_b, k, m.teeth_a, m.teeth_b, a, b, ktab, 1.0, e, 1.0, c,
            False, phases.get(m.name, 0.0), rb_a, rb_b, psi, m.stage))
    return out


def _planet_phases(graph: MechanismGraph) -> dict[str, float]:
    """Mesh phase x0 (cycles) of planet n's sun and ring meshes (seed 004 Table 4-1,
    :func:`geardyn.gears.planet_mesh_phases`); the ring's X here counts ring teeth relative to
    the carrier, the opposite sense of the planetary model's, hence −rr."""
    out: dict[str, float] = {}
    by_name = {m.name: m for m in graph.meshes}
    for ps in graph.planetary_sets:
        sun = next((m for m in graph.meshes if m.name == f"{ps.name}.sun-planet1"), None)
        ring = next((m for m in graph.meshes if m.name == f"{ps.name}.ring-planet1"), None)
        if sun is None or ring is None:
            continue
        rs, rr = planet_mesh_phases(sun.teeth_a, ring.teeth_a, np.asarray(ps.planet_angles))
        for i in range(len(ps.planets)):
            if f"{ps.name}.sun-planet{i + 1}" in by_name:
                out[f"{ps.name}.sun-planet{i + 1}"] = float(rs[i])
                out[f"{ps.name}.ring-planet{i + 1}"] = -float(rr[i])
    return out


def model_from_config(cfg: object, inputs: Sequence[str] | None = None) -> CoreModel:
    """The ``[dynamics]`` model of a loaded config (PE tables from ``[[gear_geometry]]``)."""
    spec: Dynamics | None = getattr(cfg, "dynamics", None)
    if spec is None:
        raise ConfigError("the config has no [dynamics] section (see docs/dynamics.md)")
    graph = cfg.graph()  # type: ignore[attr-defined]
    pe: dict[str, np.ndarray] = {}
    geometry: dict[str, tuple[float, float, float]] = {}
    entries = getattr(cfg, "gear_geometry", None) or []
    if entries:
        from geardyn.config.gears import matches as _matches

        for m in graph.meshes:
            e = next((e for e in entries if _matches(e.pair, m.name, m.stage)), None)
            if e is not None:  # transverse module and pressure angle: the PE table and the
                # base radii are in the transverse plane (helical pairs, m_t = m_n / cos β)
                beta = math.radians(e.helix_angle_deg)
                alpha_t = math.atan(math.tan(math.radians(e.normal_pressure_angle_deg))
                                    / math.cos(beta))
                geometry[m.name] = (e.normal_module_m / math.cos(beta), math.degrees(alpha_t),
                                    e.face_width_m)
    wanted = {m.name for m in graph.meshes
              if _pair_size(m, spec).settings.model == "gear_geometry"}
    if wanted:
        from geardyn.gears.pe_stiffness import mesh_stiffness
        from geardyn.models.gear_pairs import pair_model

        for name in wanted:
            pe[name] = mesh_stiffness(pair_model(cfg, name).geometry,
                                      n_per_cycle=SAMPLES_PER_CYCLE).total
    if inputs is None:
        inputs = list(getattr(cfg, "input_speeds_rpm", {}) or {})
    return build_model(graph, spec, inputs, pe, geometry)
