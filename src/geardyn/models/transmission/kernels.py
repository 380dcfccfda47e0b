"""Compiled (numba) connecting forces of the FE transmission: bearings and gear meshes.

Structure-of-arrays parameters built by :mod:`.assembly`. All SI. The state is the global DOF
vector (6 per node: x, y, z, θx, θy, θz, θz = full rotation).

Bearings (seed 002 §2.1, Table 3-4; Thibault et al. [19]): inner ring at a node, outer ring
fixed. Rolling element j sits at ψ_j = φ_cage + 2πj/Z with φ_cage = θz·(1 − D cos α/d_m)/2
(outer ring fixed), so ball passage modulates the stiffness (BPFO). Ball: groove-centre
distance A_j = √((A₀ − P_d/2 + u_r)² + u_z²), δ_j = A_j − A₀ (Harris & Kotzalas §7),
Q_j = K δ_j^1.5. Roller: δ_j = u_r − P_d/2, Q_j = K δ_j^(10/9) (Palmgren), axial load on the
flanges through a linear penalty beyond the axial play. Load-dependent rolling resistance
torque T = c_rr (d_m/2) Σ Q_j (sign opposing rotation) and viscous torque α_bea ω (seed 002
§3.1). Outer-race spall: over its angular length the contact deflection loses the spall depth.

Gear meshes (seed 002 §2.2-2.4): K slices across the face; slice deflection
δ_k = V_k · (q_a, q_b), the linearised form of eqs 4-5 (θz enters as r_b θz, exact for
the full rotation since r_b,a/r_b,b = z_a/z_b). For every tooth pair p in contact at the mesh
phase ξ = z_a s θz,a /(2π) + ξ₀ (table of :func:`geardyn.gears.mesh_stiffness`, structural
stiffness K_tot,p = the table's pair stiffness without its constant Hertz term), the slice
force solves seed 002 eq 9, δ_k = F/(K_tot,p/K) + Johnson δ_c(F; L_p/K, E*, ΔR_p) (Newton,
monotone from below since δ(F) is concave); squeeze-film damping (α_eng/K) δ̇_k on
slices in contact; Coulomb
friction μ F_p per tooth pair p (eq 10) along the profile tangent, regularised by
tanh(v_s/v_reg), with pair load shares and contact positions from the same table.

Backlash (optional, per mesh ``m_bl`` ≥ 0, normal backlash j_bn along the line of action;
< 0: drive flank only): the back flanks act along the mirrored line of action (the other
common tangent of the base circles, slice vectors ``m_Vb``), closing when V_b·q > j_bn; their
force uses the same pair stiffness table at the same mesh phase (symmetric teeth, the phase
offset between the two flanks' mesh cycles neglected), squeeze film likewise, no friction.
Between the flanks (−j_bn < δ < 0) the teeth separate and carry no load (vibro-impacts).
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.extending import intrinsic

V_REG = 1e-3  # m/s, friction regularisation speed

# The kernels allocate nothing: compiled without the runtime's reference counting (_nrt=False),
# so a call passes its ~20 array arguments without an atomic increment and decrement each
# (≈ 11 % of the modal FE step in a profile).


@intrinsic
def _sqrt(typingctx, x):  # noqa: ARG001 - numba intrinsic signature
    """IEEE square root of a float64 as the processor's instruction (llvm.sqrt): math.sqrt
    compiles to a C library call (for its error handling), whose spills around the call
    cost more than the root; the value is the same (both correctly rounded)."""
    sig = types.float64(types.float64)

    def codegen(context, builder, signature, args):  # noqa: ARG001
        fn = builder.module.declare_intrinsic("llvm.sqrt", [ir.DoubleType()])
        return builder.call(fn, args)

    return sig, codegen


@intrinsic
def _f2i(typingctx, x):  # noqa: ARG001 - numba intrinsic signature
    """The bits of a float64 as an int64 (no conversion)."""
    sig = types.int64(types.float64)

    def codegen(context, builder, signature, args):  # noqa: ARG001
        return builder.bitcast(args[0], ir.IntType(64))

    return sig, codegen


@intrinsic
def _i2f(typingctx, i):  # noqa: ARG001 - numba intrinsic signature
    """The float64 with the bits of an int64 (no conversion)."""
    sig = types.float64(types.int64)

    def codegen(context, builder, signature, args):  # noqa: ARG001
        return builder.bitcast(args[0], ir.DoubleType())

    return sig, codegen


_LN2_HI = 6.93147180369123816490e-01
_LN2_LO = 1.90821492927058770002e-10
_LG1 = 6.666666666666735130e-01
_LG2 = 3.999999999940941908e-01
_LG3 = 2.857142874366239149e-01
_LG4 = 2.222219843214978396e-01
_LG5 = 1.818357216161805012e-01
_LG6 = 1.531383769920937332e-01
_LG7 = 1.479819860511658591e-01


@njit(inline="always")
def _log(x):  # pragma: no cover - compiled
    """ln x of a positive normal float64 within 1 ulp, inline and branch-free (so that a loop
    of eq 9 Newton iterations vectorises): the argument reduction and minimax polynomial of
    fdlibm's e_log.c (Sun Microsystems 1993) in the form of musl libc's log.c: x = 2^k (1 + f)
    with 1 + f in [√2/2, √2), s = f/(2 + f), ln(1 + f) = f − f²/2 + s(f²/2 + R(s²)) with
    R = Lg1 s² + … + Lg7 s¹⁴, ln 2 in two parts."""
    u = _f2i(x)
    hx = (u >> 32) + (0x3FF00000 - 0x3FE6A09E)
    k = (hx >> 20) - 0x3FF
    hx = (hx & 0x000FFFFF) + 0x3FE6A09E
    f = _i2f((hx << 32) | (u & 0xFFFFFFFF)) - 1.0
    hfsq = 0.5 * f * f
    s = f / (2.0 + f)
    z = s * s
    w = z * z
    t1 = w * (_LG2 + w * (_LG4 + w * _LG6))
    t2 = z * (_LG1 + w * (_LG3 + w * (_LG5 + w * _LG7)))
    dk = float(k)
    return s * (hfsq + (t2 + t1)) + dk * _LN2_LO - hfsq + f + dk * _LN2_HI


@njit(cache=True, _nrt=False)
def log_inline(x):  # pragma: no cover - compiled
    """:func:`_log` as a callable (tests)."""
    return _log(x)


@njit(cache=True, _nrt=False)
def _tanh(x):  # pragma: no cover - compiled
    """math.tanh, without the call where it is ±1 in double precision (|x| ≥ 20): the
    regularised friction and rolling-resistance signs are saturated almost always."""
    if x >= 20.0:
        return 1.0
    if x <= -20.0:
        return -1.0
    return math.tanh(x)


@njit(cache=True, _nrt=False)
def bearing_forces(
    q, v, f, diss,
    b_node, b_type, b_z, b_k, b_a0, b_pd, b_cage, b_dm, b_crr, b_visc, b_kax, b_cax,
    b_sp_ang, b_sp_len, b_sp_depth, b_dc, b_ds, b_load,
):  # pragma: no cover - compiled
    """Add bearing forces to ``f``; diss[0] += viscous power, diss[1] += rolling-resistance
    power; ``b_load[i]`` receives Σ Q_j of bearing i and the force (x, y) the bearing
    transmits to the housing [N] (``b_load`` of shape (n_bearings, 3)). ``b_dc``, ``b_ds``:
    cos and sin of the angular pitch 2π/Z (:func:`.assembly.pitch_rotation`)."""
    for i in range(b_node.size):
        n0 = 6 * b_node[i]
        ux = q[n0]
        uy = q[n0 + 1]
        uz = q[n0 + 2]
        th = q[n0 + 5]
        om = v[n0 + 5]
        cage = th * b_cage[i]
        z = b_z[i]
        fx = 0.0
        fy = 0.0
        fz = 0.0
        qsum = 0.0
        # rolling-element angles by rotation: (c, s) of ψ_j+1 = rotation of (c, s) of ψ_j by
        # 2π/Z (the cage's cos and sin per bearing instead of two calls per element)
        dc = b_dc[i]
        ds = b_ds[i]
        cn = math.cos(cage)
        sn = math.sin(cage)
        for j in range(z):
            c = cn
            s = sn
            cn = c * dc - s * ds
            sn = s * dc + c * ds
            ur = ux * c + uy * s
            red = 0.0
            if b_sp_depth[i] > 0.0:
                psi = cage + 2.0 * math.pi * j / z
                d = (psi - b_sp_ang[i]) % (2.0 * math.pi)
                if d > math.pi:
                    d -= 2.0 * math.pi
                if abs(d) < 0.5 * b_sp_len[i]:
                    red = b_sp_depth[i]
            if b_type[i] == 0:
                ar = b_a0[i] - 0.5 * b_pd[i] + ur
                a = _sqrt(ar * ar + uz * uz)
                dl = a - b_a0[i] - red
                if dl > 0.0:
                    qj = b_k[i] * dl * _sqrt(dl)
                    qsum += qj
                    qa = qj / a
                    fx -= qa * ar * c
                    fy -= qa * ar * s
                    fz -= qa * uz
            else:
                dl = ur - 0.5 * b_pd[i] - red
                if dl > 0.0:
                    qj = b_k[i] * dl * math.exp(math.log(dl) * (1.0 / 9.0))  # dl^(10/9)
                    qsum += qj
                    fx -= qj * c
                    fy -= qj * s
        if b_type[i] == 1:
            gap = abs(uz) - 0.5 * b_cax[i]
            if gap > 0.0:
                fz -= b_kax[i] * gap * (1.0 if uz > 0 else -1.0)
        f[n0] += fx
        f[n0 + 1] += fy
        f[n0 + 2] += fz
        trr = b_crr[i] * 0.5 * b_dm[i] * qsum * _tanh(om / 1e-2)
        f[n0 + 5] -= b_visc[i] * om + trr
        diss[0] += b_visc[i] * om * om
        diss[1] += trr * om
        b_load[i, 0] = qsum
        b_load[i, 1] = -fx
        b_load[i, 2] = -fy


@njit(cache=True, _nrt=False)
def johnson_force(delta, ks, width, estar, rsum):  # pragma: no cover - compiled
    """F ≥ 0 with δ = F/ks + F/(π L E*)(ln(4π L E* ΔR/F) − 1) (seed 002 eq 9)
    (:func:`johnson_solve` from its default start)."""
    return johnson_solve(delta, ks, width, estar, rsum, 0.0)[0]


@njit(cache=True, _nrt=False)
def johnson_solve(delta, ks, width, estar, rsum, start):  # pragma: no cover - compiled
    """(F ≥ 0 with δ = F/ks + F/(π L E*)(ln(4π L E* ΔR/F) − 1) (seed 002 eq 9), dδ/dF at
    the last iterate).

    Newton on the concave increasing δ(F): after the first step the iterates approach the
    root monotonically from below, from any positive start (``start``, e.g. the solution of
    a neighbouring slice extrapolated with its dδ/dF; ≤ 0: ln(4π L E* ΔR/F) ≈ 13, tooth
    loads). Stops when a step moves F by < 1e-4 F: Newton's error after that step is
    |g''|/(2g') e² ≤ e²/(2F(ln(4π L E* ΔR/F) − 2)) < 5e-10 F (quadratic convergence; two
    iterations for tooth loads from the default start, one from a start within 1e-4)."""
    if delta <= 0.0:
        return 0.0, 0.0
    c = math.pi * width * estar
    a = 4.0 * c * rsum
    iks = 1.0 / ks  # reciprocals once: divisions dominate the iteration's cost
    ic = 1.0 / c
    f = start if start > 0.0 else delta / (iks + 12.0 * ic)
    dg = iks + 11.0 * ic
    for _ in range(40):
        lg = math.log(a / f)
        g = f * (iks + ic * (lg - 1.0)) - delta
        dg = iks + (lg - 2.0) * ic
        fn = f - g / dg
        if fn <= 0.0:
            fn = 0.1 * f
        if abs(fn - f) < 1e-4 * f:
            return fn, dg
        f = fn
    return f, dg


def mesh_work_size(pmax: int, nsl: int) -> int:
    """Scratch values the mesh kernels need for ``pmax`` pair columns and ``nsl`` slices: 6
    per pair column, 3 per slice of either flank, 5 per (pair, slice) lane (lanes rounded up
    to a multiple of 8)."""
    return 6 * pmax + 6 * nsl + 5 * (((pmax * 2 * nsl + 7) // 8) * 8)


@njit(inline="always")
def _mesh_body(
    q, v, f, diss,
    m_na, m_nb, m_V, m_nsl, m_tlen, m_npc, m_za, m_s, m_xi0,
    m_ks, m_len, m_rsum, m_rhoa, m_rhob, m_np, m_that, m_mu, m_csf, m_estar, m_gap, m_Vb, m_bl,
    m_work, m_force,
    lanes,
):  # pragma: no cover - compiled
    """The body of :func:`mesh_forces` (``lanes`` False) and :func:`mesh_forces_lanes`
    (True), inlined into both (the flag folds away)."""
    # rows of pmax per pair in contact: stiffness and length per slice, gap, ΔR, ρ_a, ρ_b;
    # then per slice (drive flank, back flank): force, deflection, rate, Newton iterate (−F
    # once converged), δ of the pair being solved
    pmax = m_ks.shape[2]
    smax = 2 * m_V.shape[1]
    o = 6 * pmax
    fsl = m_work[o : o + smax]
    dsl = m_work[o + smax : o + 2 * smax]
    ddsl = m_work[o + 2 * smax : o + 3 * smax]
    fw = m_work[o + 3 * smax : o + 4 * smax]
    dpw = m_work[o + 4 * smax : o + 5 * smax]
    # lanes: per (pair, slice) lane, after the slice rows: iterate, δ − gap, 4π L E* ΔR, 1/k_s,
    # 1/(π L E*)
    ol = o + 3 * smax
    nlw = ((pmax * smax + 7) // 8) * 8 if lanes else 0
    if lanes:
        fw = m_work[ol : ol + nlw]
        dpw = m_work[ol + nlw : ol + 2 * nlw]
    la = m_work[ol + 2 * nlw : ol + 3 * nlw]
    liks = m_work[ol + 3 * nlw : ol + 4 * nlw]
    lic = m_work[ol + 4 * nlw : ol + 5 * nlw]
    for i in range(m_na.size):
        a0 = 6 * m_na[i]
        b0 = 6 * m_nb[i]
        xi = m_za[i] * m_s[i] * q[a0 + 5] / (2.0 * math.pi) + m_xi0[i]
        pos = xi * m_npc[i]
        n = m_tlen[i]
        fl = math.floor(pos)
        fr = pos - fl
        i0 = int(fl % n)
        i1 = (i0 + 1) % n
        shift = 1 if i1 % int(m_npc[i]) == 0 else 0
        nsl = m_nsl[i]
        cs = m_csf[i] / nsl
        npr = 0
        for p in range(m_np[i]):
            # column p is the pair that entered floor(ξ) − p mesh cycles ago; at a cycle
            # boundary the next sample's columns are shifted by one. Interpolating the
            # same pair (zero outside contact) keeps the force continuous in θ.
            p1 = p + shift
            k0 = m_ks[i, i0, p]
            k1 = m_ks[i, i1, p1] if p1 < m_np[i] else 0.0
            ks = (1.0 - fr) * k0 + fr * k1
            if ks <= 0.0:
                continue
            if k0 > 0.0:
                ii, pp = i0, p
            else:
                ii, pp = i1, p1
            # no-load gap (separation distance off the path, profile corrections), seed
            # 002 eqs 11-12; a pair missing from one sample keeps the other's gap
            g0 = m_gap[i, i0, p] if k0 > 0.0 else m_gap[i, ii, pp]
            g1 = m_gap[i, i1, p1] if k1 > 0.0 else m_gap[i, ii, pp]
            m_work[npr] = ks / nsl
            m_work[1 * pmax + npr] = (1.0 - fr) * g0 + fr * g1
            m_work[2 * pmax + npr] = m_len[i, ii, pp] / nsl
            m_work[3 * pmax + npr] = m_rsum[i, ii, pp]
            m_work[4 * pmax + npr] = m_rhoa[i, ii, pp]
            m_work[5 * pmax + npr] = m_rhob[i, ii, pp]
            npr += 1
        ftot = 0.0
        tx = m_that[i, 0]
        ty = m_that[i, 1]
        dut = (v[a0] - v[b0]) * tx + (v[a0 + 1] - v[b0 + 1]) * ty
        wa = v[a0 + 5]
        wb = v[b0 + 5]
        nfl = 2 if m_bl[i] >= 0.0 else 1
        ffs = 0.0  # friction: Σ ff, Σ ff ρ_a, Σ ff ρ_b, power
        ffa = 0.0
        ffb = 0.0
        pfr = 0.0
        psq = 0.0
        back_any = False
        nk = nfl * nsl
        for ksl in range(nk):  # slice deflections and their rates
            k = ksl % nsl
            d = 0.0
            dd = 0.0
            if ksl >= nsl:
                for m in range(6):
                    d += m_Vb[i, k, m] * q[a0 + m] + m_Vb[i, k, 6 + m] * q[b0 + m]
                    dd += m_Vb[i, k, m] * v[a0 + m] + m_Vb[i, k, 6 + m] * v[b0 + m]
                d -= m_bl[i]
            else:
                for m in range(6):
                    d += m_V[i, k, m] * q[a0 + m] + m_V[i, k, 6 + m] * q[b0 + m]
                    dd += m_V[i, k, m] * v[a0 + m] + m_V[i, k, 6 + m] * v[b0 + m]
            fsl[ksl] = 0.0
            dsl[ksl] = d
            ddsl[ksl] = dd
        if lanes:
            # eq 9 for every (pair, slice) lane of the mesh at once: the two Newton iterations of
            # johnson_solve from its default start, vectorised over the lanes (branch-free, inline
            # logarithm: the same iterates as johnson_solve one slice at a time); the rare lanes
            # not converged in two continue in johnson_solve
            nl = npr * nk
            nl8 = ((nl + 7) // 8) * 8
            for r in range(npr):
                gap = m_work[pmax + r]
                c = math.pi * m_work[2 * pmax + r] * m_estar[i]
                a = 4.0 * c * m_work[3 * pmax + r]
                iks = 1.0 / m_work[r]
                ic = 1.0 / c
                for ksl in range(nk):
                    ln = r * nk + ksl
                    dp = dsl[ksl] - gap
                    la[ln] = a
                    liks[ln] = iks
                    lic[ln] = ic
                    if dsl[ksl] <= 0.0 or dp <= 0.0:
                        fw[ln] = 0.0  # no contact
                        dpw[ln] = 0.0
                    else:
                        fw[ln] = dp / (iks + 12.0 * ic)
                        dpw[ln] = dp
            for ln in range(nl, nl8):  # padding lanes: no contact, finite values
                fw[ln] = 0.0
                dpw[ln] = 0.0
                la[ln] = 1.0
                liks[ln] = 1.0
                lic[ln] = 1.0
            for _ in range(2):
                for ln in range(nl8):
                    fo = fw[ln]  # > 0: iterate; 0: no contact; < 0: −F once converged
                    x = fo if fo > 0.0 else 1.0
                    lg = _log(la[ln] / x)
                    g = x * (liks[ln] + lic[ln] * (lg - 1.0)) - dpw[ln]
                    dg = liks[ln] + (lg - 2.0) * lic[ln]
                    fn = x - g / dg
                    fn = fn if fn > 0.0 else 0.1 * x
                    fn = -fn if abs(fn - x) < 1e-4 * x else fn
                    fw[ln] = fn if fo > 0.0 else fo
            for ln in range(nl):
                if fw[ln] > 0.0:  # not converged in two: the remaining iterations
                    r = ln // nk
                    fw[ln] = -johnson_solve(dpw[ln], m_work[r], m_work[2 * pmax + r], m_estar[i],
                                            m_work[3 * pmax + r], fw[ln])[0]
            for r in range(npr):
                ra = m_work[4 * pmax + r]
                rb = m_work[5 * pmax + r]
                for ksl in range(nk):
                    fp = -fw[r * nk + ksl]
                    if fp <= 0.0:
                        continue
                    fsl[ksl] += fp
                    if m_mu[i] > 0.0 and ksl < nsl:
                        vs = dut + wa * ra + wb * rb
                        ff = m_mu[i] * fp * _tanh(vs / V_REG)
                        ffs += ff
                        ffa += ff * ra
                        ffb += ff * rb
                        pfr += ff * vs
        else:
            for r in range(npr):
                # each pair across the slices, eq 9 by johnson_solve's Newton iterations taken
                # for all slices in lockstep (independent chains of divisions and logarithms
                # overlap; the same iterates, hence the same forces, as one slice at a time)
                gap = m_work[pmax + r]
                ra = m_work[4 * pmax + r]
                rb = m_work[5 * pmax + r]
                c = math.pi * m_work[2 * pmax + r] * m_estar[i]
                a = 4.0 * c * m_work[3 * pmax + r]
                iks = 1.0 / m_work[r]
                ic = 1.0 / c
                for ksl in range(nk):
                    dp = dsl[ksl] - gap
                    if dsl[ksl] <= 0.0 or dp <= 0.0:
                        fw[ksl] = 0.0  # no contact
                        continue
                    fw[ksl] = dp / (iks + 12.0 * ic)
                    dpw[ksl] = dp
                for it in range(2):
                    for ksl in range(nk):
                        fo = fw[ksl]
                        if fo <= 0.0:  # no contact, or converged (−F)
                            continue
                        dp = dpw[ksl]
                        lg = math.log(a / fo)
                        g = fo * (iks + ic * (lg - 1.0)) - dp
                        dg = iks + (lg - 2.0) * ic
                        fn = fo - g / dg
                        if fn <= 0.0:
                            fn = 0.1 * fo
                        if abs(fn - fo) < 1e-4 * fo:
                            fw[ksl] = -fn
                        elif it == 1:  # not converged in two: the remaining iterations
                            fw[ksl] = -johnson_solve(dp, m_work[r], m_work[2 * pmax + r],
                                                     m_estar[i], m_work[3 * pmax + r], fn)[0]
                        else:
                            fw[ksl] = fn
                for ksl in range(nk):
                    fp = -fw[ksl]
                    if fp <= 0.0:
                        continue
                    fsl[ksl] += fp
                    if m_mu[i] > 0.0 and ksl < nsl:
                        vs = dut + wa * ra + wb * rb
                        ff = m_mu[i] * fp * _tanh(vs / V_REG)
                        ffs += ff
                        ffa += ff * ra
                        ffb += ff * rb
                        pfr += ff * vs
        for ksl in range(nk):
            fk = fsl[ksl]
            if fk > 0.0:
                dd = ddsl[ksl]
                fv = cs * dd
                psq += fv * dd
                if ksl >= nsl:
                    ftot -= fk
                    back_any = True
                else:
                    ftot += fk
                fsl[ksl] = fk + fv
        diss[2] += pfr
        diss[3] += psq
        f[a0] -= ffs * tx
        f[a0 + 1] -= ffs * ty
        f[b0] += ffs * tx
        f[b0 + 1] += ffs * ty
        f[a0 + 5] -= ffa
        f[b0 + 5] -= ffb
        for m in range(6):  # Σ_k F_k V_k, one update per DOF
            sa = 0.0
            sb = 0.0
            for k in range(nsl):
                sa += fsl[k] * m_V[i, k, m]
                sb += fsl[k] * m_V[i, k, 6 + m]
            if back_any:
                for k in range(nsl):
                    sa += fsl[nsl + k] * m_Vb[i, k, m]
                    sb += fsl[nsl + k] * m_Vb[i, k, 6 + m]
            f[a0 + m] -= sa
            f[b0 + m] -= sb
        m_force[i] = ftot


# error_model="numpy": no division-by-zero test (no divisor is 0; none inside the lanes)
@njit(cache=True, _nrt=False, error_model="numpy")
def mesh_forces(
    q, v, f, diss,
    m_na, m_nb, m_V, m_nsl, m_tlen, m_npc, m_za, m_s, m_xi0,
    m_ks, m_len, m_rsum, m_rhoa, m_rhob, m_np, m_that, m_mu, m_csf, m_estar, m_gap, m_Vb, m_bl,
    m_work, m_force,
):  # pragma: no cover - compiled
    """Add gear-mesh forces to ``f``; diss[2] += friction power, diss[3] += squeeze-film
    power; ``m_force[i]`` receives the total normal (transverse LOA) contact force of mesh i
    (drive flank positive, back flank negative). ``m_work``: scratch of at least
    :func:`mesh_work_size` values (:meth:`.assembly.Meshes.args`).

    The tooth pairs in contact and their table values at the mesh phase do not depend on the
    slice: they are read once per mesh, then every slice solves eq 9 for each of them; the
    slice forces and the friction forces are summed before they are added to ``f`` (one
    update per DOF and mesh)."""
    _mesh_body(q, v, f, diss, m_na, m_nb, m_V, m_nsl, m_tlen, m_npc, m_za, m_s, m_xi0, m_ks,
        m_len, m_rsum, m_rhoa, m_rhob, m_np, m_that, m_mu, m_csf, m_estar, m_gap, m_Vb, m_bl,
        m_work, m_force, False)


@njit(cache=True, _nrt=False, error_model="numpy")
def mesh_forces_lanes(
    q, v, f, diss,
    m_na, m_nb, m_V, m_nsl, m_tlen, m_npc, m_za, m_s, m_xi0,
    m_ks, m_len, m_rsum, m_rhoa, m_rhob, m_np, m_that, m_mu, m_csf, m_estar, m_gap, m_Vb, m_bl,
    m_work, m_force,
):  # pragma: no cover - compiled
    """:func:`mesh_forces` with eq 9 solved for every (pair, slice) lane of a mesh at once:
    the two Newton iterations of :func:`johnson_solve` from its default start as one
    branch-free loop over the lanes with an inline logarithm (:func:`_log`, within 1 ulp of the
    C library), which vectorises; lanes not converged in two continue in
    :func:`johnson_solve`. The forces differ from :func:`mesh_forces` by rounding only. Used
    by the modal integrator (:mod:`geardyn.solve.modal_fe`), where the eq 9 solves were a
    quarter of the step; the other callers keep :func:`mesh_forces`."""
    _mesh_body(q, v, f, diss, m_na, m_nb, m_V, m_nsl, m_tlen, m_npc, m_za, m_s, m_xi0, m_ks,
        m_len, m_rsum, m_rhoa, m_rhob, m_np, m_that, m_mu, m_csf, m_estar, m_gap, m_Vb, m_bl,
        m_work, m_force, True)


@njit(cache=True)
def perturbed_connecting_forces(q, v, cols, h, bargs, margs, nb, nm, out
                                ):  # pragma: no cover - compiled
    """out[:, k] = bearing + mesh forces (:func:`bearing_forces`, :func:`mesh_forces`) at
    q + h e_cols[k]: the evaluations of a finite-difference Jacobian in one call, each as
    :func:`.assembly.connecting_forces` computes it (fresh force, dissipation and load
    arrays)."""
    n = q.size
    qp = q.copy()
    f = np.zeros(n)
    diss = np.zeros(5)
    bl = np.zeros((nb, 3))
    mf = np.zeros(nm)
    for k in range(cols.size):
        j = cols[k]
        qp[j] = q[j] + h
        f[:] = 0.0
        diss[:] = 0.0
        bl[:, :] = 0.0
        mf[:] = 0.0
        bearing_forces(qp, v, f, diss, *bargs, bl)
        mesh_forces(qp, v, f, diss, *margs, mf)
        for i in range(n):
            out[i, k] = f[i]
        qp[j] = q[j]
