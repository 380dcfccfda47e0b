"""Slice coupling along the face: the seed 002 §2.2 unloaded-slice correction as a
two-parameter (Pasternak) elastic foundation.

Seed 002 §2.2 computes the mesh deflection slice by slice and adds "a corrective term ... if the
adjacent slices are unloaded ... dedicated to the introduction of convective effects on flexion",
fitted to an unpublished FE model. Here the same physics comes from a published method instead:
each tooth, seen along the face coordinate z, is a two-parameter (Pasternak) foundation

    k(z)·w − d/dz(G(z)·dw/dz) = q(z)                                              (P1)

(Pasternak 1954; Kerr 1964, "Elastic and viscoelastic foundation models", J. Appl. Mech. 31,
eq 12) — k (N/m per m of face) the slice's own PE stiffness (seed 002 eq 6-7) and G (N) the
shear layer that makes an unloaded slice deflect with its loaded neighbour.

Coupling parameter (derived here, not fitted). Vlasov's variational method (Vlasov & Leontiev
1966, *Beams, plates and shells on elastic foundations*, ch. 1): take the tooth as a Kirchhoff
cantilever plate of height h (root circle to the load point), w(y, z) = W(z)·φ(y) with φ the
cantilever's tip-load shape φ = (3s² − s³)/2, s = y/h, φ(h) = 1. The plate energy
D/2·[w_yy² + w_zz² + 2ν w_yy w_zz + 2(1 − ν) w_yz²] integrated over y gives (P1) with

    k = ∫ D φ''² dy = 3D/h³,    G = ∫ D [2(1 − ν) φ'² − 2ν φ φ''] dy = (2.4 − 3ν)·D/h,

so the decay length λ = √(G/k) = h·√(0.8 − ν) (λ = h/√2 at ν = 0.3). G is the tooth plate's
twisting resistance: the other deflection modes of a slice (shear, fillet-foundation rotation,
both w ∝ y) need nearly the same twist (G = 2(1 − ν)D/h for φ = y/h), so G is taken as
λ²·k_bending with k_bending the PE bending stiffness of the slice (the tapered tooth instead of
the uniform plate; :func:`vlasov_length_ratio`, the ratio λ/h is settable) while the foundation
stiffness k is the slice's whole PE tooth stiffness (bending + shear + compression + fillet).
As the fillet-foundation term dominates k, the effective decay length √(G/k) is 2-7 times λ.
Left out: the plate's own bending along the face (the D φ² W''² term, a third parameter),
transverse shear of the thick plate (Mindlin) and the spreading of the fillet deformation in
the gear body.

Discrete form (per tooth, K slices of width Δz): a tridiagonal stiffness matrix with k_i·Δz on
the diagonal and coupling springs G/Δz between neighbours. The two teeth deflect in series with
the local (uncoupled) Hertzian compliance of the loaded slices; with all loaded slices at the
same mesh approach δ, the pair stiffness is the condensed stiffness

    k_pair = 1ᵀ (C_a,LL + C_b,LL + C_h,LL)⁻¹ 1,    C = K⁻¹ restricted to the loaded set L.   (P2)

Closed form used to validate (P2) (derived from (P1) with uniform k, G): an unloaded end of
length L₂ beyond a uniformly deflected loaded zone, free at the face end (w' = 0), deflects as
w = δ·cosh((L₂ − x)/λ)/cosh(L₂/λ) and adds the end spring √(kG)·tanh(L₂/λ) to k·L₁
(:func:`closed_form_stiffness`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from geardyn.errors import InputError

if TYPE_CHECKING:
    from geardyn.gears.geometry import MeshGeometry


def vlasov_length_ratio(poisson_ratio: float) -> float:
    """λ/h = √(0.8 − ν): Vlasov decay length of a cantilever tooth plate over its load height
    (module docstring; k = 3D/h³, G = (2.4 − 3ν)D/h)."""
    if not 0.0 < poisson_ratio < 0.5:
        raise InputError(f"poisson_ratio must be in (0, 0.5) (got {poisson_ratio})")
    return math.sqrt(0.8 - poisson_ratio)


def closed_form_stiffness(
    k: float, shear: float, loaded_length: float, unloaded_lengths: tuple[float, ...]
) -> float:
    """Stiffness (N/m) of a uniform Pasternak foundation (k in N/m², shear G in N) deflected
    uniformly over ``loaded_length`` with free unloaded ends of the given lengths (m):
    k·L₁ + Σ √(kG)·tanh(L₂/λ), λ = √(G/k) (continuous solution of eq P1)."""
    if shear == 0.0:
        return k * loaded_length
    lam = math.sqrt(shear / k)
    return k * loaded_length + sum(math.sqrt(k * shear) * math.tanh(x / lam)
                                   for x in unloaded_lengths)


def _compliance(k_diag: np.ndarray, k_cpl: np.ndarray) -> np.ndarray:
    """Inverse of the batched tridiagonal foundation matrices: diag k_diag (N, K), coupling
    springs k_cpl (N, K−1) between neighbours."""
    n, nk = k_diag.shape
    a = np.zeros((n, nk, nk))
    i = np.arange(nk)
    a[:, i, i] = k_diag
    if nk > 1:
        a[:, i[:-1], i[:-1]] += k_cpl
        a[:, i[1:], i[1:]] += k_cpl
        a[:, i[:-1], i[1:]] = -k_cpl
        a[:, i[1:], i[:-1]] = -k_cpl
    return np.linalg.inv(a)


def condensed_stiffness(
    foundations: list[tuple[np.ndarray, np.ndarray]],
    local_compliance: np.ndarray,
    loaded: np.ndarray,
) -> np.ndarray:
    """Pair stiffness (N/m) of eq P2, batched over N rows of K slices.

    ``foundations``: per tooth (k_diag (N, K) slice stiffnesses in N/m, k_cpl (N, K−1) coupling
    springs in N/m); ``local_compliance`` (N, K) the series compliance (m/N) of each loaded
    slice (Hertz); ``loaded`` (N, K) bool. Rows with nothing loaded give 0.
    """
    loaded = np.asarray(loaded, dtype=bool)
    m = sum(_compliance(kd, kc) for kd, kc in foundations)
    m = m + np.where(loaded, local_compliance, 0.0)[:, :, None] * np.eye(loaded.shape[1])
    both = loaded[:, :, None] & loaded[:, None, :]
    eye = np.eye(loaded.shape[1], dtype=bool)[None]
    m = np.where(both, m, np.where(eye, 1.0, 0.0))
    rhs = loaded.astype(float)
    x = np.linalg.solve(m, rhs[:, :, None])[:, :, 0]
    return (x * rhs).sum(axis=1)


def coupling_springs(shear: np.ndarray, dz: float) -> np.ndarray:
    """Springs G/Δz (N/m) between neighbouring slices from the shear parameter G (N) of each
    slice (N, K): the interface takes the mean of its two slices."""
    return 0.5 * (shear[:, 1:] + shear[:, :-1]) / dz


def with_slice_coupling(
    g: MeshGeometry, on: bool = True, length_ratio: float | None = None
) -> MeshGeometry:
    """A copy of ``g`` whose mesh stiffness tables use slice coupling (``on``) with decay
    length λ = ``length_ratio``·h (None: √(0.8 − ν) of each gear, :func:`vlasov_length_ratio`).
    """
    if length_ratio is not None and not (math.isfinite(length_ratio) and length_ratio > 0):
        raise InputError(f"slice coupling length_ratio must be finite and > 0 (got {length_ratio})")
    return dataclasses.replace(g, slice_coupling=bool(on), slice_coupling_ratio=length_ratio)


@dataclass(frozen=True)
class CouplingGrids:
    """Per-unit-width compliances and load heights of both teeth on a grid of LOA positions,
    ready to build coupled slice stiffnesses (:meth:`pair_stiffness`)."""

    u: np.ndarray
    total: tuple[np.ndarray, np.ndarray]
    """Tooth compliance per unit width (m·m/N): bending + shear + axial + fillet."""
    bending: tuple[np.ndarray, np.ndarray]
    height: tuple[np.ndarray, np.ndarray]
    """Load height h (m): radial distance from the root circle to the contact point."""
    ratio: tuple[float, float]
    """λ/h of each tooth."""
    hertz: float
    """Hertzian compliance per unit width (m·m/N)."""

    @classmethod
    def build(cls, g: MeshGeometry, u: np.ndarray, length_ratio: float | None) -> CouplingGrids:
        from geardyn.gears.contact import hertz_compliance
        from geardyn.gears.pe_stiffness import tooth_compliance

        radii = g.contact_radii(u)
        tot, bend, height, ratio = [], [], [], []
        for i, blank in enumerate((g.a, g.b)):
            c = tooth_compliance(g, i, radii[i])
            tot.append(c.total)
            bend.append(c.bending)
            h = g.root_radius[i] - radii[i] if blank.internal else radii[i] - g.root_radius[i]
            height.append(np.maximum(h, 1e-3 * g.normal_module))
            nu = blank.material.poisson_ratio
            ratio.append(vlasov_length_ratio(nu) if length_ratio is None else length_ratio)
        ma, mb = g.a.material, g.b.material
        ch = hertz_compliance(ma.youngs_modulus, ma.poisson_ratio, mb.youngs_modulus,
                              mb.poisson_ratio)
        return cls(u, (tot[0], tot[1]), (bend[0], bend[1]), (height[0], height[1]),
                   (ratio[0], ratio[1]), ch)

    def tooth(self, i: int, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(total compliance, shear parameter G (N)) per unit width of tooth i at positions u
        (clipped to the path: an unloaded slice is taken at the nearest contact height)."""
        uc = np.clip(u, self.u[0], self.u[-1])
        c = np.interp(uc, self.u, self.total[i])
        lam = self.ratio[i] * np.interp(uc, self.u, self.height[i])
        return c, lam**2 / np.interp(uc, self.u, self.bending[i])

    def pair_stiffness(
        self,
        u: np.ndarray,
        w: np.ndarray,
        dz: float,
        loaded: np.ndarray | None = None,
        compliance: tuple[np.ndarray | None, np.ndarray | None] = (None, None),
    ) -> np.ndarray:
        """Coupled pair stiffness (N/m) of N tooth pairs, each K slices of width dz (eq P2).

        ``u`` (N, K) LOA positions, ``w`` (N, K) in-contact fractions (the Hertzian compliance
        of a partly engaged slice is 1/(w·Δz) per unit compliance), ``loaded`` (default w > 0)
        the slices in contact (a spall removes some); ``compliance`` optional per-slice tooth
        compliances replacing the healthy ones (a cracked tooth).
        """
        u = np.atleast_2d(u)
        w = np.atleast_2d(w)
        loaded = (w > 0) if loaded is None else (np.asarray(loaded, dtype=bool) & (w > 0))
        out = np.zeros(u.shape[0])
        rows = np.flatnonzero(loaded.any(axis=1))
        if rows.size == 0:
            return out
        found = []
        for i in (0, 1):
            c, shear = self.tooth(i, u[rows])
            ci = compliance[i]
            if ci is not None:
                c = np.asarray(ci)[rows]
            found.append((dz / c, coupling_springs(shear, dz)))
        ww = np.where(loaded[rows], w[rows], 1.0)
        out[rows] = condensed_stiffness(found, self.hertz / (ww * dz), loaded[rows])
        return out

    def compliance_matrix(self, u: np.ndarray, dz: float) -> np.ndarray:
        """Structural compliance matrices C_a + C_b (m/N) of N tooth pairs (u: (N, K) LOA
        positions of their slices): the inverse tridiagonal foundations of both teeth."""
        u = np.atleast_2d(u)
        out = np.zeros(u.shape + (u.shape[1],))
        for i in (0, 1):
            c, shear = self.tooth(i, u)
            out += _compliance(dz / c, coupling_springs(shear, dz))
        return out


def coupled_contact_forces(
    approach: np.ndarray,
    compliance: np.ndarray,
    width: float,
    e_star: float,
    radius_sum: np.ndarray,
    iterations: int = 40,
) -> np.ndarray:
    """Slice forces F ≥ 0 (N) of N coupled tooth pairs under the approaches ``approach``
    (N, K) (m; δ − gap per slice, −inf where the slice cannot touch), seed 002 eq 9 with the
    structural term coupled: approach_k = (C F)_k + δ_c(F_k) where F_k > 0, F_k = 0 where
    approach_k ≤ (C F)_k; ``compliance`` C (N, K, K) from :meth:`CouplingGrids.compliance_matrix`,
    δ_c the Johnson contact deflection of a slice of width ``width`` (seed 002 eq 8).

    Solved as the minimum of the convex complementary energy ½FᵀCF + ΣΦ_c(F) − Σ F·approach by
    secant iterations on the Johnson compliance, δ_c = c_s(F)·F with
    c_s = (ln(4πLE*ΔR/F) − 1)/(πLE*), each a linear complementarity problem solved by an active
    set (drop slices pulled into tension, add slices that would overlap).
    """
    d = np.asarray(approach, dtype=float)
    n, nk = d.shape
    c_j = math.pi * width * e_star
    rs = np.broadcast_to(np.asarray(radius_sum, dtype=float), d.shape)
    can = np.isfinite(d)
    act = can & (d > 0)
    diag = np.einsum("nkk->nk", compliance)
    f = np.where(act, np.maximum(d, 0.0) / np.maximum(diag, 1e-30) * 0.5, 0.0)
    eye = np.eye(nk)
    for _ in range(iterations):
        fs = np.maximum(f, 1e-6 * np.maximum(f.max(axis=1, keepdims=True), 1e-3))
        cs = (np.log(4.0 * c_j * rs / fs) - 1.0) / c_j
        m_full = compliance + cs[:, :, None] * eye
        for _ in range(2 * nk + 2):
            both = act[:, :, None] & act[:, None, :]
            m = np.where(both, m_full, eye[None])
            rhs = np.where(act, d, 0.0)
            f_new = np.linalg.solve(m, rhs[:, :, None])[:, :, 0]
            neg = act & (f_new < 0)
            gap = np.where(can & ~act, d - np.einsum("nkl,nl->nk", compliance, f_new), -1.0)
            add = can & ~act & (gap > 1e-15)
            if not (neg.any() or add.any()):
                break
            # drop the most negative slice of each row, add overlapping ones
            worst = np.where(neg, f_new, np.inf).argmin(axis=1)
            drop = np.zeros_like(act)
            rows = np.flatnonzero(neg.any(axis=1))
            drop[rows, worst[rows]] = True
            act = (act & ~drop) | np.where(neg.any(axis=1, keepdims=True), False, add)
        f_new = np.where(act, np.maximum(f_new, 0.0), 0.0)
        done = np.all(np.abs(f_new - f) <= 1e-11 * np.maximum(np.abs(f_new).max(), 1.0))
        f = f_new
        if done:
            break
    return f
