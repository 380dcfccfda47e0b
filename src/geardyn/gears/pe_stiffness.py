"""Potential-energy (PE) tooth compliance and time-varying mesh stiffness.

Per tooth (seed 002 eq 6, Chen & Shao 2011): the tooth is a non-uniform cantilever from the
root circle to the contact point, loaded by the contact force F inclined by β (seed 002's
b_eff) to the tooth perpendicular; with x the distance from a section to the load point along
the centreline, h(x) the half-thickness, h_P the half-thickness at the load point::

    1/K_b = ∫ (x cos β − h_P sin β)² / (E I) dx,   I = (2h)³ L/12
    1/K_s = ∫ 1.2 cos²β / (G A) dx,               A = 2h L
    1/K_c = ∫ sin²β / (E A) dx

plus the Sainsot fillet-foundation term (seed 002 eq 7, :mod:`.fillet_foundation`) and the
constant Hertzian term (:func:`.contact.hertz_compliance`). A tooth pair's stiffness is
k = 1/(1/k_h + Σ_gears (1/K_b + 1/K_s + 1/K_c + 1/K_f)); simultaneous pairs add in parallel.

Geometry: above the base circle the section follows the involute; between the root circle and
the base circle (few teeth) the flank is taken as the radial line through the base-circle
point (Chen & Shao's straight-line simplification) — the default ``root_fillet="involute"`` of
:class:`~.geometry.GearBlank`. With ``root_fillet="trochoid"`` the section below the involute's
form (junction) radius is the rack-generated trochoid (:mod:`.trochoid`), integrated in its
normal angle γ, and the Sainsot root angle is the trochoid's θ_f = b1/r (the load height u_f is
measured from the root circle along the centreline in both cases). Internal-gear (ring) teeth
use the concave involute of the ring with their root at the ring root circle. All compliances
scale as 1/width, so curves are computed per unit face width and scaled per slice.

Helical gears (seed 002 §2.2, Fig 1): K thin slices along the face, each a spur slice whose
contact position on the transverse line of action lags by z·tan β_b (stiffness along the
transverse line of action); a slice only partly on the path counts with its in-contact
fraction, so that the table has no slice-sized steps.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from geardyn.errors import InputError
from geardyn.gears.contact import hertz_compliance
from geardyn.gears.faults import Crack, Spall
from geardyn.gears.fillet_foundation import fillet_foundation_compliance
from geardyn.gears.geometry import MeshGeometry, inv
from geardyn.gears.slice_coupling import CouplingGrids
from geardyn.gears.trochoid import trochoid_fillet

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

_GX, _GW = np.polynomial.legendre.leggauss(40)


@dataclass(frozen=True)
class ToothCompliance:
    """Per-unit-width compliances (m·m/N) of one tooth at contact radii (arrays)."""

    bending: np.ndarray
    shear: np.ndarray
    axial: np.ndarray
    fillet: np.ndarray

    @property
    def total(self) -> np.ndarray:
        return self.bending + self.shear + self.axial + self.fillet


def _rim_ratio(g: MeshGeometry, i: int) -> float:
    """h_fi = r_f / r_int of Sainsot (ring: equivalent rim thickness)."""
    blank = (g.a, g.b)[i]
    rf = g.root_radius[i]
    mn = g.normal_module
    if not blank.internal:
        rint = blank.rim_radius if blank.rim_radius is not None else max(rf - 3.5 * mn, 0.25 * rf)
        return rf / rint
    rout = blank.rim_radius if blank.rim_radius is not None else rf + 3.5 * mn
    t = rout - rf
    return rf / max(rf - t, 1e-9)


def tooth_compliance(
    g: MeshGeometry,
    gear: int,
    r_contact: np.ndarray,
    crack_depth: float = 0.0,
    crack: Crack | None = None,
) -> ToothCompliance:
    """PE compliances per unit width of gear ``gear`` (0 = a, 1 = b) loaded at radii r_contact.

    ``crack_depth`` (m) with the angle/radius of ``crack`` applies the Chen & Shao dead-zone
    section (seed 002 eq 14). Vectorised over ``r_contact``.
    """
    blank = (g.a, g.b)[gear]
    mat = blank.material
    e, gm = mat.youngs_modulus, mat.shear_modulus
    rb = g.base_radius[gear]
    rf = g.root_radius[gear]
    ra = g.tip_radius[gear]
    a2 = g.half_angle_base[gear]
    z = blank.teeth
    rc = np.atleast_1d(np.asarray(r_contact, dtype=float))
    ac = np.arccos(np.clip(rb / rc, -1.0, 1.0))
    tq = (_GX + 1.0) / 2.0  # [0, 1] nodes
    wq = _GW / 2.0

    fillet = None  # fixed (fillet) segment: (y, h, w) on Gauss nodes, trochoid only
    if not blank.internal:
        theta_c = a2 - inv(ac)
        beta = np.tan(ac) - a2
        y_c = rc * np.cos(theta_c)
        h_c = rc * np.sin(theta_c)
        theta_f = a2 if rf <= rb else a2 - float(inv(math.acos(rb / rf)))
        if blank.root_fillet == "trochoid":
            tro = trochoid_fillet(g, gear)
            theta_f = tro.root_angle
            r_j = tro.junction_radius
            gam = math.pi / 2 + (tro.pressure_angle - math.pi / 2) * tq
            yf, hf = tro.point(gam)
            wf = wq * (math.pi / 2 - tro.pressure_angle) * np.abs(tro.dy_dgamma(gam))
            fillet = (yf[None, :], hf[None, :], wf[None, :])
        y_root = rf * math.cos(theta_f)

        def section(r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            """(y, h, dy/dr) at radii r (involute above r_b, radial line below)."""
            a_r = np.arccos(np.clip(rb / np.maximum(r, rb), -1.0, 1.0))
            th = np.where(r >= rb, a2 - inv(a_r), a2)
            dy = np.where(r >= rb, np.cos(th) + np.sin(th) * np.tan(a_r), np.cos(a2))
            return r * np.cos(th), r * np.sin(th), dy

        if fillet is None:
            segs = [
                (np.full_like(rc, rf), np.minimum(rc, max(rb, rf))),
                (np.full_like(rc, max(rb, rf)), rc),
            ]
        else:
            segs = [(np.full_like(rc, r_j), np.maximum(rc, r_j))]
            involute_section = section

            def section(r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
                """Involute above the fillet junction, trochoid below (crack start only)."""
                if np.all(r >= r_j):
                    return involute_section(r)
                yq, hq = zip(*(tro.section_at_radius(float(x)) for x in np.ravel(r)), strict=True)
                return np.array(yq), np.array(hq), np.full(np.size(r), np.nan)
        c_of = lambda y: y - y_root  # noqa: E731
        u_f = y_c - h_c * np.tan(beta) - rf
        tip_c = ra * math.cos(a2 - float(inv(math.acos(rb / ra)))) - y_root
        tip_h = ra * math.sin(a2 - float(inv(math.acos(rb / ra))))
    else:
        theta_c = math.pi / z - a2 + inv(ac)
        beta = theta_c + ac
        y_c = rc * np.cos(theta_c)
        h_c = rc * np.sin(theta_c)
        theta_f = math.pi / z - a2 + float(inv(math.acos(rb / rf)))
        y_root = rf * math.cos(theta_f)

        def section(r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            a_r = np.arccos(np.clip(rb / r, -1.0, 1.0))
            th = math.pi / z - a2 + inv(a_r)
            dy = np.cos(th) - np.sin(th) * np.tan(a_r)
            return r * np.cos(th), r * np.sin(th), dy

        segs = [(rc, np.full_like(rc, rf))]
        c_of = lambda y: y_root - y  # noqa: E731
        u_f = rf - y_c - h_c * np.tan(beta)
        th_a = math.pi / z - a2 + float(inv(math.acos(rb / ra)))
        tip_c = y_root - ra * math.cos(th_a)
        tip_h = ra * math.sin(th_a)

    c_p = c_of(y_c)
    cb, sb = np.cos(beta), np.sin(beta)
    kb = np.zeros_like(rc)
    ks = np.zeros_like(rc)
    ka = np.zeros_like(rc)

    # crack geometry (dead zone): start on the loaded flank at r_start
    cracked = crack is not None and crack_depth > 0.0
    if cracked:
        assert crack is not None
        r_start = crack.radius if crack.radius is not None else rf
        yq, hq0, _ = section(np.array([r_start]))
        c_start = float(c_of(yq)[0])
        h_q = float(hq0[0]) - crack_depth * math.cos(crack.angle)
        c_q = max(c_start - crack_depth * math.sin(crack.angle), 0.0)
        if h_q <= -float(hq0[0]) * 0.98:
            raise InputError(
                f"crack depth {crack_depth * 1e3:.3f} mm cuts through the tooth "
                f"(root half-thickness {float(hq0[0]) * 1e3:.3f} mm)"
            )

    parts = []
    for lo, hi in segs:
        span = hi - lo
        if np.all(np.abs(span) <= 0):
            continue
        r = lo[:, None] + span[:, None] * tq[None, :]
        y, h, dy = section(r)
        parts.append((y, h, wq[None, :] * span[:, None] * np.abs(dy)))
    if fillet is not None:
        parts.append(fillet)
    for y, h, w in parts:
        c = c_of(y)
        if cracked:
            s = np.clip((c - c_q) / max(tip_c - c_q, 1e-12), 0.0, 1.0)
            h_dead = h_q + (tip_h - h_q) * s**2
            width2 = np.where(c < c_q, 2.0 * h, h + np.minimum(h_dead, h))
        else:
            width2 = 2.0 * h
        width2 = np.maximum(width2, 1e-9)
        arm = cb[:, None] * (c_p[:, None] - c) - sb[:, None] * h_c[:, None]
        kb += np.sum(w * 12.0 * arm**2 / (e * width2**3), axis=1)
        ks += np.sum(w * 1.2 * cb[:, None] ** 2 / (gm * width2), axis=1)
        ka += np.sum(w * sb[:, None] ** 2 / (e * width2), axis=1)
    s_f = 2.0 * rf * theta_f
    kf = fillet_foundation_compliance(
        beta, np.maximum(u_f, 0.0), s_f, theta_f, _rim_ratio(g, gear), e, 1.0
    )
    return ToothCompliance(bending=kb, shear=ks, axial=ka, fillet=np.asarray(kf))


@dataclass
class StiffnessTable:
    """Mesh stiffness over the pinion angle (SI): see :func:`mesh_stiffness`.

    ``pair_stiffness[i, p]`` is the stiffness (N/m, along the transverse line of action) of
    the p-th youngest tooth pair at angle i; ``tooth_a/tooth_b[i, p]`` its tooth indices;
    ``contact[i, p]`` its LOA position u (m) of the mid-face slice (NaN = out of contact).
    """

    geometry: MeshGeometry
    mesh_cycle: np.ndarray
    angle_a: np.ndarray
    pair_stiffness: np.ndarray
    tooth_a: np.ndarray
    tooth_b: np.ndarray
    contact: np.ndarray
    faults: tuple = field(default_factory=tuple)
    n_per_cycle: int = 0
    slice_coupling: bool = False
    """True when the slices of each tooth were coupled along the face (:mod:`.slice_coupling`)."""

    @property
    def total(self) -> np.ndarray:
        """Total mesh stiffness k(θ) (N/m) along the transverse line of action."""
        return self.pair_stiffness.sum(axis=1)

    @property
    def period_cycles(self) -> float:
        """Mesh cycles covered by the table (its period when it spans a full period)."""
        return self.mesh_cycle.size / self.n_per_cycle

    def at(self, mesh_cycle: np.ndarray | float) -> np.ndarray:
        """Total stiffness (N/m) at mesh phases ξ, linear interpolation, periodic over the table.

        Build the table over one mesh cycle (healthy) or the hunting period (faults) so that
        the wrap-around is physical; ξ = r_b,a·φ_a/p_bt = z_a·φ_a/(2π).
        """
        return np.interp(
            np.asarray(mesh_cycle, dtype=float),
            self.mesh_cycle,
            self.total,
            period=self.period_cycles,
        )

    @property
    def torsional(self) -> np.ndarray:
        """Torsional stiffness referred to gear a: k·r_b,a² (N·m/rad)."""
        return self.total * self.geometry.base_radius[0] ** 2

    def to_xarray(self):  # noqa: ANN201 - xarray imported lazily
        from geardyn.gears.results import table_to_dataset

        return table_to_dataset(self)

    def plot(self, ax: Axes | None = None, **kw: Any) -> Figure:
        """Total stiffness [N/m] against mesh position [mesh cycles] on ``ax`` (a new figure
        if None); returns the figure, never saves. ``kw``: ``pairs=True`` adds each tooth
        pair, ``label``, ``xmax`` and line options (:func:`.plot.plot_stiffness_table`).
        """
        from geardyn.gears.plot import plot_stiffness_table

        return plot_stiffness_table(self, ax, **kw)


def _grid(g: MeshGeometry, n: int = 601) -> np.ndarray:
    return np.linspace(g.u_start, g.u_end, n)


def pair_compliance_curve(
    g: MeshGeometry, u: np.ndarray, crack: Crack | None = None, crack_depth: float = 0.0
) -> np.ndarray:
    """Per-unit-width compliance (m·m/N) of one tooth pair vs LOA position u (seed 002 eq 9,
    linear form): Hertz + both teeth; an optional crack on ``crack.gear``."""
    ra, rb_ = g.contact_radii(u)
    ca = tooth_compliance(
        g, 0, ra, crack_depth if crack and crack.gear == "a" else 0.0, crack
    ).total
    cb = tooth_compliance(
        g, 1, rb_, crack_depth if crack and crack.gear == "b" else 0.0, crack
    ).total
    ma, mb = g.a.material, g.b.material
    ch = hertz_compliance(ma.youngs_modulus, ma.poisson_ratio, mb.youngs_modulus, mb.poisson_ratio)
    return ca + cb + ch


def mesh_stiffness(
    g: MeshGeometry,
    n_per_cycle: int = 64,
    n_cycles: float | None = 1.0,
    n_slices: int | None = None,
    faults: tuple[Crack | Spall, ...] | list[Crack | Spall] = (),
    grid_points: int = 401,
    slice_coupling: bool | None = None,
) -> StiffnessTable:
    """Time-varying mesh stiffness over ``n_cycles`` mesh cycles (None = full hunting period).

    Vectorised: pair compliance curves are built once on a grid of LOA positions (Gauss
    quadrature of the PE integrals) and interpolated for every slice of every pair in contact.
    ``n_slices`` defaults to 1 for a healthy spur pair, 24 otherwise (helical or faults).
    ``slice_coupling`` (None: ``g.slice_coupling``) couples the slices of each tooth along the
    face (seed 002 §2.2 unloaded-slice correction, :mod:`.slice_coupling`, decay length ratio
    ``g.slice_coupling_ratio``); off, the slices are independent.
    """
    if n_per_cycle < 4:
        raise InputError(f"n_per_cycle must be ≥ 4 (got {n_per_cycle})")
    faults = tuple(faults)
    for f in faults:
        side = 0 if f.gear == "a" else 1
        zt = (g.a, g.b)[side].teeth
        if not 0 <= f.tooth < zt:
            raise InputError(f"fault on gear {f.gear}: tooth {f.tooth} outside 0..{zt - 1}")
    cycles = float(g.hunting_cycles) if n_cycles is None else float(n_cycles)
    if cycles <= 0:
        raise InputError("n_cycles must be > 0")
    if n_slices is None:
        n_slices = 1 if (g.helix_angle == 0.0 and not faults) else 24
    if n_slices < 1 or grid_points < 16:
        raise InputError(
            f"n_slices must be ≥ 1 and grid_points ≥ 16 (got {n_slices}, {grid_points})"
        )
    n_total = int(round(cycles * n_per_cycle))
    # the healthy mesh is periodic over one mesh cycle: compute one cycle and tile it; faults
    # are then applied only to the (angle, pair) entries where the faulty tooth is in contact
    n = min(n_per_cycle, n_total)
    xi1 = np.arange(n) / n_per_cycle
    b = g.face_width
    dz = b / n_slices
    zk = (np.arange(n_slices) + 0.5) * dz
    lag = zk * math.tan(abs(g.base_helix_angle))
    pbt = g.base_pitch
    n_pairs = int(math.ceil((g.path_length + lag[-1]) / pbt)) + 1
    ugrid = _grid(g, grid_points)
    kgrid = 1.0 / pair_compliance_curve(g, ugrid)  # per unit width
    coupled = g.slice_coupling if slice_coupling is None else bool(slice_coupling)
    cgrid = CouplingGrids.build(g, ugrid, g.slice_coupling_ratio) if coupled else None
    age = np.arange(n_pairs)

    half = 0.5 * dz * math.tan(abs(g.base_helix_angle))  # contact-line spread within a slice

    def positions(x: np.ndarray, a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(u, w): LOA position and in-contact fraction of every slice.

        Slice k of the pair that entered at mesh count j = floor(ξ) − age sits at
        u = u_start + (ξ − j)·p_bt − lag_k; on a helical slice the contact spreads over
        u ± half, so w is the fraction of that spread on the path and u the centre of the
        part in contact (smooth entry/exit instead of whole-slice steps).
        """
        u = (g.u_start + (x - (np.floor(x) - a)) * pbt)[..., None] - lag
        if half == 0.0:
            w = ((u >= g.u_start - 1e-12) & (u <= g.u_end + 1e-12)).astype(float)
            return u, w
        lo = np.maximum(u - half, g.u_start)
        hi = np.minimum(u + half, g.u_end)
        w = np.clip((hi - lo) / (2.0 * half), 0.0, 1.0)
        return np.where(w > 0, 0.5 * (lo + hi), u), w

    u1, w1 = positions(xi1[:, None], age[None, :])  # (n, P, K)
    in1 = w1 > 0
    if cgrid is None:
        pair1 = (np.interp(u1, ugrid, kgrid) * dz * w1).sum(axis=2)
    else:
        shape = u1.shape
        pair1 = cgrid.pair_stiffness(
            u1.reshape(-1, n_slices), w1.reshape(-1, n_slices), dz
        ).reshape(shape[:2])
    mid = n_slices // 2
    cu1 = np.where(in1[:, :, mid], u1[:, :, mid], np.nan)
    reps = -(-n_total // n)
    pair_k = np.tile(pair1, (reps, 1))[:n_total]
    cu = np.tile(cu1, (reps, 1))[:n_total]
    xi = np.arange(n_total) / n_per_cycle
    j = np.floor(xi)[:, None] - age[None, :]
    ja = np.mod(j, g.a.teeth).astype(int)
    jb = np.mod(j, g.b.teeth).astype(int)

    if faults:
        hits = [(ja if f.gear == "a" else jb) == f.tooth for f in faults]
        rows, cols = np.nonzero(np.logical_or.reduce(hits))
        if rows.size:
            u, wt = positions(xi[rows], age[cols])  # (H, K)
            inside = wt > 0
            ks_ = np.interp(u, ugrid, kgrid) * dz * wt
            loaded = inside.copy()  # coupled model: slices in contact
            ctooth = [cgrid.tooth(i, u)[0] for i in (0, 1)] if cgrid is not None else []
            for f, hit in zip(faults, hits, strict=True):
                h = hit[rows, cols][:, None] & inside
                if not h.any():
                    continue
                if isinstance(f, Crack):
                    q = f.depth_at(zk, b)
                    for qv in np.unique(q):
                        if qv <= 0:
                            continue
                        sel = h & (q == qv)[None, :]
                        if cgrid is not None:  # the cracked tooth alone
                            side = 0 if f.gear == "a" else 1
                            hit_t = hit[rows, cols][:, None] & (q == qv)[None, :]
                            rc = g.contact_radii(ugrid)[side]
                            ct = tooth_compliance(g, side, rc, float(qv), f).total
                            uc = np.clip(u[hit_t], ugrid[0], ugrid[-1])
                            ctooth[side][hit_t] = np.interp(uc, ugrid, ct)
                            continue
                        kc = 1.0 / pair_compliance_curve(g, ugrid, f, float(qv))
                        ks_[sel] = np.interp(u[sel], ugrid, kc) * dz * wt[sel]
                elif isinstance(f, Spall):
                    ra, rbb = g.contact_radii(u)
                    rr = ra if f.gear == "a" else rbb
                    ks_[f.covers(rr, zk[None, :], b) & h] = 0.0
                    loaded[f.covers(rr, zk[None, :], b) & h] = False
            pair_k = pair_k.copy()
            if cgrid is None:
                pair_k[rows, cols] = ks_.sum(axis=1)
            else:
                pair_k[rows, cols] = cgrid.pair_stiffness(
                    u, wt, dz, loaded, (ctooth[0], ctooth[1])
                )
    return StiffnessTable(
        geometry=g,
        mesh_cycle=xi,
        angle_a=xi * 2.0 * math.pi / g.a.teeth,
        pair_stiffness=pair_k,
        tooth_a=ja,
        tooth_b=jb,
        contact=cu,
        faults=faults,
        n_per_cycle=n_per_cycle,
        slice_coupling=coupled,
    )


def mean_stiffness(g: MeshGeometry, n_per_cycle: int = 256) -> float:
    """Mean mesh stiffness (N/m) over one mesh cycle of the healthy pair."""
    return float(mesh_stiffness(g, n_per_cycle=n_per_cycle).total.mean())
