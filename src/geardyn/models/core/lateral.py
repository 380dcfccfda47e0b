"""Lateral DOFs of the general model: the in-plane translations of Lin & Parker (1999).

With ``[dynamics] lateral = true``:

* a link turning in the frame gets ``x``, ``y`` (m, fixed frame), held by a bearing of
  ``bearing_n_per_m`` in x and y;
* a planet — a link turning, on a parallel axis, in a carrier that turns in the frame — gets
  ``zeta`` (radial) and ``eta`` (tangential) (m) *relative to its pin* at the planet angle ψ,
  held by the planet bearing (seed 003 eqs 3.14-3.16: δ_ζ = −ζ, δ_η = −η in these
  coordinates). Its centre moves by (x_c, y_c) + R(ψ)(ζ, η), plus the orbit r_c θ_c of the
  carrier rotation, so ½ m |R(ψ)ᵀ d + (0, r_c θ̇_c)|² replaces the orbit term;
* a mesh of two parallel-axis gears adds the relative centre displacement projected on its line
  of action, n·(d_a − d_b) with n = (−sin(ψ − α), cos(ψ − α)) for an external pair (ψ: from
  a's centre to b's) and n·(d_int − d_ext) with n = (−sin(ψ + α), cos(ψ + α)) for an internal
  one (ψ: from the internal gear's centre to the external gear's) — the Lin & Parker sun–planet
  and ring–planet deflections (seed 003 notes §2.3), the torsional part being the Willis row.

The members of a planetary stage are described in its carrier frame (ψ fixed), as Lin &
Parker do: :func:`add_rotating_frames` registers that frame's gyroscopic and centripetal matrices
(Ω G q̇ − Ω² K_Ω q at the carrier speed Ω, seed 003 eq 3.1); a link turning in the frame that
is not coaxial with a carrier is described in the fixed frame.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from geardyn.kinematics.graph import GearMesh, MechanismGraph
from geardyn.models.core.assembly import Assembly
from geardyn.models.core.model import Spring


@dataclass(frozen=True)
class LateralBody:
    """Lateral coordinates of one link: ``kind`` "fixed" (x, y) or "planet" (ζ, η)."""

    link: str
    kind: str
    dofs: tuple[int, int]
    angle: float = 0.0  # planet angle ψ (rad)
    carrier: str | None = None


def lateral_layout(tree: list[tuple[str, str]], phi: Mapping[str, float],
                   graph: MechanismGraph, first: int) -> dict[str, LateralBody]:
    """Which links get lateral DOFs, numbered from ``first`` (module docstring)."""
    angles = {p: a for ps in graph.planetary_sets
              for p, a in zip(ps.planets, ps.planet_angles, strict=True)}
    parent = dict(tree)
    out: dict[str, LateralBody] = {}
    k = first
    for link, p in tree:
        if p == graph.frame:
            out[link] = LateralBody(link, "fixed", (k, k + 1))
        elif parent.get(p) == graph.frame and abs(math.sin(phi[link] - phi[p])) < 1e-9:
            out[link] = LateralBody(link, "planet", (k, k + 1), angles.get(link, 0.0), p)
        else:
            continue
        k += 2
    return out


def centre_map(link: str, layout: Mapping[str, LateralBody], n: int) -> np.ndarray:
    """D (2 × n): displacement (x, y) of the link's centre = D q (the carrier's rotation
    excluded: it is in the Willis row)."""
    d = np.zeros((2, n))
    b = layout.get(link)
    if b is None:
        return d
    if b.kind == "fixed":
        d[0, b.dofs[0]] = 1.0
        d[1, b.dofs[1]] = 1.0
        return d
    c, s = math.cos(b.angle), math.sin(b.angle)
    d[:, b.dofs[0]] = (c, s)
    d[:, b.dofs[1]] = (-s, c)
    return d + centre_map(b.carrier or "", layout, n)


def body_map(b: LateralBody, layout: Mapping[str, LateralBody], orbit: Mapping[str, float],
             rotation: Mapping[str, np.ndarray], n: int) -> np.ndarray:
    """D (2 × n): the body's translation in Lin & Parker's coordinates — (x, y) of a link
    turning in the frame; for a planet (ζ, η) at ψ including its carrier's translation and
    orbit r_c θ_c (η of Lin & Parker carries u_c)."""
    d = centre_map(b.link, layout, n)
    if b.kind == "planet":
        c, s = math.cos(b.angle), math.sin(b.angle)
        d = np.array([[c, s], [-s, c]]) @ d  # (ζ, η) components at ψ
        d[1] += orbit.get(b.link, 0.0) * rotation[b.carrier or ""]
    return d


def add_lateral_mass(asm: Assembly, layout: Mapping[str, LateralBody],
                     mass: Mapping[str, float], orbit: Mapping[str, float],
                     rotation: Mapping[str, np.ndarray]) -> None:
    """Translational kinetic energy ½ m |D q̇|² of every link with lateral DOFs, stamped as
    mass blocks Dᵀ (m I) D (D: :func:`body_map`)."""
    for b in layout.values():
        d = body_map(b, layout, orbit, rotation, asm.n)
        asm.add_mapped(f"{b.link}.translation", "inertia", d, M=mass[b.link] * np.eye(2))


def add_rotating_frames(asm: Assembly, layout: Mapping[str, LateralBody],
                        mass: Mapping[str, float], orbit: Mapping[str, float],
                        rotation: Mapping[str, np.ndarray], coaxial: Mapping[str, set[str]]
                        ) -> None:
    """One rotating frame per carrier with planets, turning at Ω = r·q̇ (r: the carrier's
    rotation row), holding the carrier, its coaxial central members and its planets (the stage,
    in the carrier frame): G = Σ m Dᵀ [[0, −2], [2, 0]] D and K_Ω = Σ m Dᵀ D (seed 003 eqs
    3.4-3.8; Lin & Parker 1999), D the body's translation map (:func:`body_map`)."""
    skew = np.array([[0.0, -2.0], [2.0, 0.0]])
    carriers = sorted({b.carrier or "" for b in layout.values() if b.kind == "planet"})
    for c in carriers:
        members = [b for b in layout.values()
                   if (b.kind == "planet" and b.carrier == c)
                   or (b.kind == "fixed" and b.link in coaxial.get(c, set()))]
        asm.add_frame(c, rotation[c].copy())
        for b in members:
            d = body_map(b, layout, orbit, rotation, asm.n)
            m = mass[b.link]
            asm.add_mapped(f"{b.link}.frame", "rotating_frame", d, frame=c, G=m * skew,
                           K_omega=m * np.eye(2))


def bearing_springs(layout: Mapping[str, LateralBody], stiffness: Mapping[str, float], n: int
                    ) -> list[Spring]:
    """Bearings: x, y to the frame, or radial/tangential on the pin (N/m)."""
    out = []
    for b in layout.values():
        labels = ("x", "y") if b.kind == "fixed" else ("zeta", "eta")
        for j, lab in zip(b.dofs, labels, strict=True):
            a = np.zeros(n)
            a[j] = 1.0
            out.append(Spring(f"{b.link}.bearing.{lab}", "bearing", stiffness.get(b.link, 0.0),
                              a))
    return out


def mesh_translation(m: GearMesh, layout: Mapping[str, LateralBody], alpha: float,
                     position_deg: float | None, n: int) -> np.ndarray:
    """Lateral part of the mesh deflection row (module docstring); zero without lateral DOFs
    or for a pair on intersecting axes."""
    if (abs(math.sin(m.theta_a)) > 1e-9 or abs(math.sin(m.theta_b)) > 1e-9
            or not ({m.link_a, m.link_b} & set(layout))):
        return np.zeros(n)
    int_a = abs(m.theta_a) > math.pi / 2
    int_b = abs(m.theta_b) > math.pi / 2
    planet = next((x for x in (m.link_b, m.link_a)
                   if x in layout and layout[x].kind == "planet"), None)
    if planet is not None:
        psi = layout[planet].angle
        if planet == m.link_a and not (int_a or int_b):
            psi += math.pi  # from a (the planet) to b
    else:
        psi = math.radians(position_deg or 0.0)
    da, db = centre_map(m.link_a, layout, n), centre_map(m.link_b, layout, n)
    # internal pair: σ n·(d_int − d_ext) with σ = +1 when the internal gear is side a, −1
    # otherwise (the torsional row is oriented by side a) — n·(d_a − d_b) either way
    tilt = alpha if (int_a or int_b) else -alpha
    nvec = np.array([-math.sin(psi + tilt), math.cos(psi + tilt)])
    return nvec @ (da - db)


def lateral_map_3d(link: str, layout: Mapping[str, LateralBody], phi: Mapping[str, float],
                   parent: Mapping[str, str], n: int) -> np.ndarray:
    """D (3 × n): translation of the link's centre in the sketch frame (Re, Im, out of the
    sketch). The lateral plane of a link with axis φ is spanned by x̂ = (−sin φ, cos φ, 0) (in
    the sketch) and ŷ = (0, 0, 1); a link without lateral DOFs (a differential pinion) moves
    with the nearest ancestor that has them (its carrier), the frame not at all."""
    d = np.zeros((3, n))
    while link not in layout:
        if link not in parent:
            return d
        link = parent[link]
    p = layout[link].carrier if layout[link].kind == "planet" else link
    f = phi[p or link]
    dd = centre_map(link, layout, n)
    d[0], d[1], d[2] = -math.sin(f) * dd[0], math.cos(f) * dd[0], dd[1]
    return d


def bevel_translation(m: GearMesh, torsional: np.ndarray, psi: float, alpha: float,
                      phi: Mapping[str, float], own: Mapping[str, int],
                      centre: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """Lateral part of a bevel pair's mesh row through its pitch-cone geometry.

    Tredgold's equivalent spur pair at the mean point of the pitch-cone generator (the tooth
    axis ψ of seed 000, in the plane of both axes; Niemann & Winter, Maschinenelemente III
    §24; ISO 10300-1 §6: the tangential, radial and axial mesh forces F_t, F_t tan α cos δ,
    F_t tan α sin δ): the line of action has the component cos α out of the sketch plane
    (tangential at the mean point) and sin α in the plane, normal to the generator, pushing
    the gears apart. A gear's centre displaced by d along its own radial direction ρ̂ (in the
    sketch, from its axis towards the generator) approaches its mate by sin α cos δ ρ̂·d (δ the
    pitch-cone angle, cos δ = |ĝ·ê| with ĝ = e^{iψ}, ê the gear axis); along ŷ (out of the
    sketch) by cos α ŷ·d. Hence, up to the sign of the torsional row,

        δ_lat = σ [sin α ŝ·(d_a − d_b) + cos α ŷ·(d_a − d_b)],

ŝ in the sketch, normal to the generator, from gear a towards gear b (ŝ·ρ̂_a = cos δ_a,
ŝ·ρ̂_b = −cos δ_b: for centres moving normal to their axes this is
cos δ_a ρ̂_a·d_a + cos δ_b ρ̂_b·d_b; a pinion carried by a cage also moves along its own
axis, which ŝ counts),

    σ = ±1 such that the tangential direction matches the torsional row: a rotation of gear a
    about its axis ê_a moves its mean point along (ê_a × ρ̂_a)·ŷ. The axial components of the
    gear forces (sin δ) act on no DOF of the lateral model. Gear bodies lie on the side of the
    apex towards ĝ (a convention of the sketch; the other side mirrors x̂). ``own``: index of
    each link's own coordinate; ``centre``: the 3 × n translation maps of gears a and b
    (:func:`lateral_map_3d`)."""
    n = len(torsional)
    g = np.array([math.cos(psi), math.sin(psi)])
    rho = []
    for link in (m.link_a, m.link_b):
        e = np.array([math.cos(phi[link]), math.sin(phi[link])])
        r = g - (g @ e) * e
        rho.append(r / np.linalg.norm(r))
    if m.link_a in own:
        e_a = np.array([math.cos(phi[m.link_a]), math.sin(phi[m.link_a])])
        tang, coef = e_a[0] * rho[0][1] - e_a[1] * rho[0][0], torsional[own[m.link_a]]
    else:  # gear a on the frame: gear b's rotation moves its point along −(ê_b × ρ̂_b)·ŷ
        e_b = np.array([math.cos(phi[m.link_b]), math.sin(phi[m.link_b])])
        tang, coef = -(e_b[0] * rho[1][1] - e_b[1] * rho[1][0]), torsional[own[m.link_b]]
    if abs(coef) == 0.0 or abs(tang) < 1e-12:
        return np.zeros(n)
    sigma = math.copysign(1.0, coef * tang)
    da, db = centre
    # ŝ: in the sketch, normal to the generator, from gear a towards gear b (ŝ·ρ̂_a = cos δ_a,
    # ŝ·ρ̂_b = −cos δ_b). For a centre moving normal to its own axis ŝ·d = cos δ ρ̂·d; a centre
    # that moves with its carrier (a differential pinion) also moves along its own axis, whose
    # part sin δ ê·d counts as well
    s_hat = np.array([-g[1], g[0]])
    s_hat *= math.copysign(1.0, s_hat @ rho[0])
    sep = s_hat @ (da[:2] - db[:2])
    return sigma * (math.sin(alpha) * sep + math.cos(alpha) * (da[2] - db[2]))
