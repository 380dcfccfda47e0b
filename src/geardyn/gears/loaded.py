"""Loaded tooth contact: static transmission error (STE) and load sharing (seed 002 §2.3-2.6).

For each angle the transmission error δ (m, along the transverse line of action) is found such
that the slice forces balance the torque: Σ_jk F_jk = T_a / r_b,a, with per-slice deflection
(seed 002 eqs 11-13)::

    δ_jk = δ − D_jk − δ_corr(r_jk) − δ_spall(r_jk, z_k),   F_jk = F(δ_jk)  (eq 9 inverted)

F(δ) inverts the nonlinear law δ = F/K_tot + Johnson(F) (seed 002 eqs 8-9), K_tot being the
PE structural stiffness of the slice (bending, shear, compression, fillet-foundation of both
teeth; :mod:`.pe_stiffness`). The separation distance D_jk (seed 002 §2.5.1) is zero on the
theoretical path; beyond it (external pairs) it is the normal gap between the tip corner of one
gear and the involute flank of the other after a further rigid rotation, computed exactly from
the involute's parallel-curve property (normal distance = r_b × difference of involute start
angles). Tip rounds are not modelled in D (sharp tip corners); internal pairs get no extension.

Profile corrections δ_corr (seed 002 §2.5.2) are deflection reductions by contact radius:
linear or parabolic tip relief on each gear, lead crowning along the face.

With slice coupling (seed 002 §2.2 unloaded-slice correction, :mod:`.slice_coupling`) the
structural term of eq 9 is the coupled compliance of each tooth pair's slices along the face.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from geardyn.errors import InputError
from geardyn.gears.contact import force_from_deflection, johnson_modulus
from geardyn.gears.faults import Spall
from geardyn.gears.geometry import MeshGeometry, inv
from geardyn.gears.pe_stiffness import tooth_compliance


@dataclass(frozen=True)
class TipRelief:
    """Tip relief of amount ``amount`` (m) at the tip, starting at radius ``start_radius`` (m)."""

    gear: Literal["a", "b"] = "a"
    amount: float = 0.0
    start_radius: float = 0.0
    shape: Literal["linear", "parabolic"] = "linear"


@dataclass(frozen=True)
class Corrections:
    """Profile/lead corrections (m): tip reliefs; lead crowning at the face ends,
    δ = C_β(2z/b − 1)²; profile crowning at the ends of the path of contact,
    δ = C_α(2(u − u_m)/g_α)² with u_m the middle of the path (sum of both flanks)."""

    tip_reliefs: tuple[TipRelief, ...] = ()
    lead_crowning: float = 0.0
    profile_crowning: float = 0.0


@dataclass
class LoadedResult:
    """Static loaded contact over the mesh cycle(s) (SI units)."""

    mesh_cycle: np.ndarray
    ste: np.ndarray
    """Static transmission error along the transverse line of action (m)."""
    pair_force: np.ndarray
    """Force carried by each tooth pair (N), [angle, pair age]."""
    load: float
    """Total line-of-action force T_a / r_b,a (N)."""
    extended: np.ndarray = field(default_factory=lambda: np.zeros(0))
    """True where a pair carries load outside the theoretical path of contact."""

    @property
    def load_sharing(self) -> np.ndarray:
        """Fraction of the load carried by each pair."""
        return self.pair_force / self.load

    @property
    def secant_stiffness(self) -> np.ndarray:
        """Loaded mesh stiffness W/δ (N/m)."""
        return self.load / self.ste


def _rot(p: np.ndarray, c: np.ndarray, ang: np.ndarray) -> np.ndarray:
    ca, sa = np.cos(ang), np.sin(ang)
    d = p - c
    return c + np.stack([ca * d[..., 0] - sa * d[..., 1], sa * d[..., 0] + ca * d[..., 1]], -1)


def _sigma(x: np.ndarray, centre: np.ndarray, rb: float, s: float) -> np.ndarray:
    d = x - centre
    rr = np.hypot(d[..., 0], d[..., 1])
    phi = np.arctan2(d[..., 1], d[..., 0])
    return phi - s * inv(np.arccos(np.clip(rb / rr, -1.0, 1.0)))


def separation_distance(g: MeshGeometry, u: np.ndarray) -> np.ndarray:
    """Separation distance D (m) for nominal LOA positions u (0 on the path of contact).

    External pairs only (internal pairs: +inf outside the path, i.e. no extended contact).
    """
    u = np.asarray(u, dtype=float)
    out = np.zeros_like(u)
    after = u > g.u_end
    before = u < g.u_start
    if g.internal:
        out[after | before] = np.inf
        return out
    rba, rbb = g.base_radius
    aw = g.working_pressure_angle
    oa = np.array([0.0, 0.0])
    ob = np.array([g.centre_distance, 0.0])
    ta = rba * np.array([math.cos(aw), math.sin(aw)])
    e = np.array([math.sin(aw), -math.cos(aw)])

    def x_of(uu: float) -> np.ndarray:
        return ta + (rba * math.tan(aw) + uu) * e

    # with this orientation both flanks in contact satisfy φ = σ + inv α (σ: involute start)
    if after.any():
        q0 = x_of(g.u_end)
        d = u[after] - g.u_end
        q = _rot(np.broadcast_to(q0, (d.size, 2)), oa, -d / rba)
        q_rel = _rot(q, ob, -(d / rbb))
        out[after] = np.abs(rbb * (_sigma(q_rel, ob, rbb, 1.0) - _sigma(q0, ob, rbb, 1.0)))
    if before.any():
        q0 = x_of(g.u_start)
        d = g.u_start - u[before]
        q = _rot(np.broadcast_to(q0, (d.size, 2)), ob, -d / rbb)
        q_rel = _rot(q, oa, -d / rba)
        out[before] = np.abs(rba * (_sigma(q_rel, oa, rba, 1.0) - _sigma(q0, oa, rba, 1.0)))
    return out


def correction(g: MeshGeometry, corr: Corrections, u: np.ndarray, z: np.ndarray) -> np.ndarray:
    """δ_corr (m) at LOA positions u and axial positions z (seed 002 eq 12)."""
    u = np.asarray(u, dtype=float)
    ra, rb_ = g.contact_radii(np.clip(u, g.u_start, g.u_end))
    out = np.zeros(np.broadcast(u, z).shape)
    for tr in corr.tip_reliefs:
        i = 0 if tr.gear == "a" else 1
        r = ra if i == 0 else rb_
        tip = g.tip_radius[i]
        if g.internal and i == 1:
            span = tr.start_radius - tip
            s = np.clip((tr.start_radius - r) / span, 0.0, 1.0) if span > 0 else 0.0 * r
        else:
            span = tip - tr.start_radius
            s = np.clip((r - tr.start_radius) / span, 0.0, 1.0) if span > 0 else 0.0 * r
        out = out + tr.amount * (s if tr.shape == "linear" else s**2)
    if corr.profile_crowning:
        um = 0.5 * (g.u_start + g.u_end)
        out = out + corr.profile_crowning * (2.0 * (u - um) / g.path_length) ** 2
    if corr.lead_crowning:
        zz = np.asarray(z, dtype=float)
        out = out + corr.lead_crowning * (2.0 * zz / g.face_width - 1.0) ** 2
    return out


def static_transmission_error(
    g: MeshGeometry,
    torque_a: float,
    n_per_cycle: int = 64,
    n_cycles: float = 1.0,
    n_slices: int | None = None,
    corrections: Corrections | None = None,
    spalls: tuple[Spall, ...] = (),
    extended: bool = True,
    grid_points: int = 201,
    slice_coupling: bool | None = None,
) -> LoadedResult:
    """Static TE and load sharing under torque ``torque_a`` (N·m on gear a), seed 002 eqs 9-13.

    ``slice_coupling`` (None: ``g.slice_coupling``): the structural deflections of the slices of
    each tooth are coupled along the face (:mod:`.slice_coupling`, seed 002 §2.2 unloaded-slice
    correction) and the slice forces solve eq 9 with that coupled compliance
    (:func:`.slice_coupling.coupled_contact_forces`); off, each slice inverts eq 9 alone.
    """
    if not (math.isfinite(torque_a) and torque_a > 0):
        raise InputError(f"torque must be > 0 N·m (got {torque_a})")
    if n_per_cycle < 1 or n_cycles <= 0 or (n_slices is not None and n_slices < 1):
        raise InputError("n_per_cycle and n_slices must be ≥ 1 and n_cycles > 0")
    corr = corrections or Corrections()
    if n_slices is None:
        n_slices = 1 if (g.helix_angle == 0.0 and not spalls and not corr.lead_crowning) else 20
    w_total = torque_a / g.base_radius[0]
    pbt = g.base_pitch
    ext = 0.4 * pbt if (extended and not g.internal) else 0.0
    lo, hi = g.u_start - ext, g.u_end + ext
    ugrid = np.linspace(g.u_start, g.u_end, grid_points)
    ra, rb_ = g.contact_radii(ugrid)
    cstruct = tooth_compliance(g, 0, ra).total + tooth_compliance(g, 1, rb_).total
    ma = g.a.material
    estar = johnson_modulus(ma.youngs_modulus, ma.poisson_ratio)
    rho_a, rho_b = g.roll_lengths(ugrid)
    rsum_grid = np.abs(rho_b - rho_a) if g.internal else rho_a + rho_b

    n = int(round(n_cycles * n_per_cycle))
    xi = np.arange(n) / n_per_cycle
    dz = g.face_width / n_slices
    zk = (np.arange(n_slices) + 0.5) * dz
    lag = zk * math.tan(abs(g.base_helix_angle))
    n_pairs = int(math.ceil((hi - lo + lag[-1]) / pbt)) + 2
    age = np.arange(-1, n_pairs - 1)
    j = np.floor(xi)[:, None] - age[None, :]
    u = (g.u_start + (xi[:, None] - j) * pbt)[:, :, None] - lag[None, None, :]
    active = (u >= lo) & (u <= hi)
    uc = np.clip(u, g.u_start, g.u_end)
    kt = dz / np.interp(uc, ugrid, cstruct)
    rsum = np.interp(uc, ugrid, rsum_grid)
    gap = np.where(active, separation_distance(g, u.ravel()).reshape(u.shape), np.inf)
    gap = gap + correction(g, corr, u, zk[None, None, :])
    ja = np.mod(j, g.a.teeth).astype(int)
    jb = np.mod(j, g.b.teeth).astype(int)
    for sp in spalls:
        tooth = ja if sp.gear == "a" else jb
        rr = g.contact_radii(uc)[0 if sp.gear == "a" else 1]
        cov = sp.covers(rr, zk[None, None, :], g.face_width) & (tooth == sp.tooth)[:, :, None]
        gap = gap + np.where(cov, sp.depth, 0.0)

    coupled = g.slice_coupling if slice_coupling is None else bool(slice_coupling)
    if coupled:
        from geardyn.gears.slice_coupling import CouplingGrids, coupled_contact_forces

        cgrid = CouplingGrids.build(g, ugrid, g.slice_coupling_ratio)
        comp = cgrid.compliance_matrix(u.reshape(-1, n_slices), dz)
        rs_flat = rsum.reshape(-1, n_slices)

    def forces(delta: np.ndarray) -> np.ndarray:
        d = delta[:, None, None] - gap
        if coupled:
            fc = coupled_contact_forces(
                np.where(np.isfinite(d), d, -np.inf).reshape(-1, n_slices), comp, dz, estar,
                rs_flat,
            )
            return fc.reshape(d.shape)
        return force_from_deflection(np.where(np.isfinite(d), d, -1.0), kt, dz, estar, rsum)

    # bracket and bisect δ (vectorised over angles); total force is monotone in δ
    lo_d = np.zeros(n)
    hi_d = np.full(n, w_total / (kt.sum(axis=(1, 2)) + 1e-30) * 4.0 + 1e-6)
    for _ in range(60):
        f = forces(hi_d).sum(axis=(1, 2))
        if np.all(f >= w_total):
            break
        hi_d = np.where(f < w_total, hi_d * 2.0, hi_d)
    for _ in range(50):
        mid = 0.5 * (lo_d + hi_d)
        f = forces(mid).sum(axis=(1, 2))
        lo_d = np.where(f < w_total, mid, lo_d)
        hi_d = np.where(f < w_total, hi_d, mid)
    ste = 0.5 * (lo_d + hi_d)
    fk = forces(ste)
    pf = fk.sum(axis=2)
    outside = (u < g.u_start) | (u > g.u_end)
    ext_loaded = np.any((fk > 0) & outside, axis=2)
    return LoadedResult(mesh_cycle=xi, ste=ste, pair_force=pf, load=w_total, extended=ext_loaded)
