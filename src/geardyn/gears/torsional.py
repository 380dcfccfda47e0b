"""Seed 004 (Wang 2010, ch. 5) combined torsional mesh stiffness, with its crack and spall models.

A second, simpler model than :mod:`geardyn.gears.pe_stiffness`: each tooth is a uniform
cantilever of height h and thickness s loaded at mid-height, each body a hollow cylinder, and
FE-fitted factors a_n, b_n scale tooth and body terms for n pairs in contact (seed 004 eqs
5.10-5.19, notes §2.8)::

    K_n = r_pb / { a_n/(n r_p)·[(h_p/2)³/(3 E I_p) + (h_g/2)³/(3 E I_g)]
                   + b_n/r_pf·[(r_pf − r_ps)/(E b r_ps) + (r_gf − r_gs)/(E b r_gs)] }

with I = b s³/12 (eq 5.11) and K in N·m/rad (torque on the "pinion" per radian of its
rotation). The stiffness is piecewise constant in the number of pairs in contact Y(X), which
follows from the contact ratio and the mesh phase (seed 004 §4.2, notes §2.6).

Reproduces the thesis values 1.7448e8 N·m/rad (sun–planet, 2 pairs) and 7.6873e8 N·m/rad
(ring–planet, 2 pairs). The ring value needs the thesis's ring "root" radius 0.680 m and ring
host radius 0.880 m, which make the ring body term negative (notes §2.8): reproduced as
published, flagged in the docs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from geardyn.errors import InputError

#: FE-fitted factors of Jia (seed 004 eqs 5.17-5.19); a_3, b_3 as used by the thesis code.
A_FACTORS = (2.7462, 1.9479, 1.7754)
B_FACTORS = (2.2932, 2.2853, 2.2771)


def equal_effect_factors(a1: float = 2.7462, a2: float = 1.9479) -> float:
    """a_3 from the equal-effect assumption (seed 004 eqs 5.15-5.16).

    a_1/(1+E) = a_2/2 gives E; a_3 = 3·a_1/(1+2E). The thesis text gives 1.7755
    (exact solution 1.77583); its code uses 1.7754.
    """
    e = 2.0 * a1 / a2 - 1.0
    return 3.0 * a1 / (1.0 + 2.0 * e)


@dataclass(frozen=True)
class TorsionalMeshParams:
    """Inputs of seed 004 eq 5.14 (SI units).

    ``pinion``: the member whose rotation defines K (sun for sun–planet, planet for
    ring–planet). r_pb base radius, r_p pitch radius, r_pf root radius, r_ps shaft radius;
    gear: r_gf root (or the thesis's equivalent) radius, r_gs shaft/host radius.
    """

    r_pb: float
    r_p: float
    r_pf: float
    r_ps: float
    r_gf: float
    r_gs: float
    tooth_height: float
    tooth_thickness: float
    face_width: float
    youngs_modulus: float
    contact_ratio: float

    def tooth_compliance(self, thickness_fraction: float = 1.0) -> float:
        """(h/2)³/(3 E I) for one tooth with thickness s·fraction (seed 004 eq 5.11)."""
        s = self.tooth_thickness * thickness_fraction
        inertia = self.face_width * s**3 / 12.0
        return (self.tooth_height / 2.0) ** 3 / (3.0 * self.youngs_modulus * inertia)

    def body_term(self) -> float:
        """(r_pf − r_ps)/(E b r_ps) + (r_gf − r_gs)/(E b r_gs) (seed 004 eq 5.12)."""
        eb = self.youngs_modulus * self.face_width
        return (self.r_pf - self.r_ps) / (eb * self.r_ps) + (self.r_gf - self.r_gs) / (
            eb * self.r_gs
        )


def torsional_mesh_stiffness(
    p: TorsionalMeshParams,
    n_pairs: int,
    crack_fraction: tuple[float, ...] | None = None,
    a: tuple[float, ...] = A_FACTORS,
    b: tuple[float, ...] = B_FACTORS,
) -> float:
    """Combined torsional stiffness K_n (N·m/rad) with n pairs in contact (seed 004 eq 5.14).

    ``crack_fraction`` gives, per pair in contact, the crack depth V as a fraction of the tooth
    thickness of the pinion-side tooth pair (s → s(1 − V), seed 004 §5.3); each pair contributes
    a_n/n² × (its own tooth terms), as in the thesis code (notes §2.8).
    """
    if n_pairs not in (1, 2, 3):
        raise InputError(f"n_pairs must be 1, 2 or 3 (got {n_pairs})")
    v = crack_fraction or (0.0,) * n_pairs
    if len(v) != n_pairs:
        raise InputError(f"crack_fraction needs {n_pairs} entries (got {len(v)})")
    if any(not 0.0 <= x < 1.0 for x in v):
        raise InputError(f"crack fractions must be in [0, 1) (got {v})")
    an = a[n_pairs - 1]
    tooth = sum(
        an / n_pairs**2 * (p.tooth_compliance(1.0 - vi) + p.tooth_compliance(1.0)) for vi in v
    )
    # a cracked tooth belongs to the pinion side; the mating tooth is healthy
    denom = tooth / p.r_p + b[n_pairs - 1] / p.r_pf * p.body_term()
    return p.r_pb / denom


def pairs_in_contact(
    x: np.ndarray, contact_ratio: float, phase: float = 0.0, pitch_offset: float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """Number of pairs in contact Y and fractional position (seed 004 §4.2, Yms/Ymr).

    ``x`` in mesh cycles; X' = x + pitch_offset − phase with pitch_offset = PBP − PBD (the
    pitch-point offset in base pitches); Y = #{k ≥ 0: frac(X') + k ≤ ε}. Returns (Y, frac).
    """
    xs = np.asarray(x, dtype=float) + pitch_offset - phase
    tt = xs - np.floor(xs)
    kmax = int(math.ceil(contact_ratio)) + 1
    y = np.zeros(tt.shape, dtype=int)
    for k in range(kmax + 1):
        y += (tt + k <= contact_ratio).astype(int)
    return y, tt


def torsional_stiffness_curve(
    p: TorsionalMeshParams,
    x: np.ndarray,
    phase: float = 0.0,
    pitch_offset: float = 0.0,
) -> np.ndarray:
    """Healthy piecewise-constant stiffness K_{Y(X)} (N·m/rad) over mesh positions x (cycles)."""
    y, _ = pairs_in_contact(x, p.contact_ratio, phase, pitch_offset)
    levels = {n: torsional_mesh_stiffness(p, n) for n in np.unique(y) if n in (1, 2, 3)}
    out = np.empty(y.shape)
    for n, k in levels.items():
        out[y == n] = k
    if np.any(~np.isin(y, list(levels))):
        raise InputError("contact ratio outside 1-3: the Wang 2010 model covers 1 to 3 pairs")
    return out


def wang_crack_curve(
    p: TorsionalMeshParams,
    x: np.ndarray,
    crack_fraction: float,
    cracked_pair: int = 0,
    teeth: int | None = None,
    phase: float = 0.0,
    pitch_offset: float = 0.0,
) -> np.ndarray:
    """Stiffness with a cracked tooth, seed 004 §5.3 (notes §2.8; mstiffs shape).

    The cracked tooth is the pair that entered contact at mesh count ``cracked_pair`` (modulo
    ``teeth`` if given). While it is in contact: with one pair, K = K_crack; with two pairs
    and the cracked tooth the newest pair, K = K_healthy − ΔK·fra³/2 (fra = fraction of the
    current single/double period, as printed in the thesis); otherwise K = K_crack, where
    K_crack is eq 5.14 with s → s(1 − V) for that tooth.
    """
    xs = np.asarray(x, dtype=float)
    y, tt = pairs_in_contact(xs, p.contact_ratio, phase, pitch_offset)
    out = torsional_stiffness_curve(p, xs, phase, pitch_offset)
    count = np.floor(xs + pitch_offset - phase).astype(int)
    pbc = p.contact_ratio - 1.0
    for n in (1, 2, 3):
        sel_n = y == n
        if not sel_n.any():
            continue
        healthy = torsional_mesh_stiffness(p, n)
        for i in range(n):
            v = [0.0] * n
            v[i] = crack_fraction
            cracked = torsional_mesh_stiffness(p, n, tuple(v))
            # pair i (0 = newest) entered at count − i
            entered = count - i
            hit = entered == cracked_pair
            if teeth:
                hit = np.mod(entered - cracked_pair, teeth) == 0
            sel = sel_n & hit
            if n == 2 and i == 0:
                fra = np.where(tt < pbc, tt / max(pbc, 1e-12), 0.0)
                out[sel] = healthy - (healthy - cracked) * fra[sel] ** 3 / 2.0
            else:
                out[sel] = cracked
    return out


def wang_spall_reduction(
    posit: np.ndarray, centre: float, half_width: float, delta_k: float
) -> np.ndarray:
    """Stiffness reduction of a spalled pair at path position ``posit`` (seed 004 §5.4).

    ``posit`` is the fraction of the path of contact (0 = entry); spall centred at ``centre``
    with half-width ``half_width`` (fractions) and maximum reduction ``delta_k`` (N·m/rad):
    ΔK·cos((posit − P)/W·π/2)^(1/5) for 0 ≤ posit − P < W, a linear ramp ΔK·posit/P before
    the centre, 0 after the spall (notes §2.8, as coded in the thesis).
    """
    d = np.asarray(posit, dtype=float) - centre
    inside = (d >= 0) & (d < half_width)
    out = np.zeros_like(d)
    out[inside] = delta_k * np.cos(d[inside] / half_width * math.pi / 2.0) ** 0.2
    before = (d < 0) & (np.asarray(posit) >= 0)
    out[before] = delta_k * np.asarray(posit, dtype=float)[before] / centre
    return out


def seed004_params(mesh: str = "sun") -> TorsionalMeshParams:
    """The seed 004 planetary meshes (Tables 4-2, 6-2, 7-1): ``"sun"`` or ``"ring"``.

    m = 16 mm, z = 19/32/83, α = 20°, b = 245 mm, E = 210 GPa, h = 2.25 m, s = πm/2; shafts:
    sun 82 mm, planet 136 mm, ring host 880 mm; the ring "root" radius is the thesis's 680 mm.
    Contact ratios 1.60569 (sun) and 2.26669 (ring, with R_ra = 644 mm).
    """
    m = 0.016
    al = math.radians(20.0)
    common = dict(
        tooth_height=2.25 * m,
        tooth_thickness=math.pi * m / 2.0,
        face_width=0.245,
        youngs_modulus=210e9,
    )
    from geardyn.gears.geometry import GearBlank, mesh_geometry

    if mesh == "sun":
        eps = mesh_geometry(GearBlank(19), GearBlank(32), m, al, 0.245).contact_ratio
        return TorsionalMeshParams(
            r_pb=0.152 * math.cos(al),
            r_p=0.152,
            r_pf=0.132,
            r_ps=0.082,
            r_gf=0.236,
            r_gs=0.136,
            contact_ratio=eps,
            **common,
        )
    if mesh == "ring":
        eps = mesh_geometry(
            GearBlank(32, form_radius=0.0),
            GearBlank(83, internal=True, addendum_coef=1.25),
            m,
            al,
            0.245,
        ).contact_ratio
        return TorsionalMeshParams(
            r_pb=0.256 * math.cos(al),
            r_p=0.256,
            r_pf=0.236,
            r_ps=0.136,
            r_gf=0.680,
            r_gs=0.880,
            contact_ratio=eps,
            **common,
        )
    raise InputError(f"mesh must be 'sun' or 'ring' (got {mesh!r})")
