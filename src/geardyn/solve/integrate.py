"""Time integration of M q̈ + C q̇ + K(t, q) q = F(t, q, q̇) with numba-compiled kernels.

Generic interface (any lumped model, not only planetary): constant M₀, C₀, K₀ plus

- *variable springs* (:class:`VarSprings`): rank-one springs with deflection δ = aᵀq + e,
  stiffness k(X) and displacement error e(X) tabulated periodically over a coordinate
  X = bᵀq + X₀ (mesh cycles for gear meshes, so the mesh phase follows the integrated body
  angles), viscous damping c along a, optional contact loss (k = c = 0 when δ < 0) or
  backlash b (tooth separation for −b < δ < 0, back-flank contact F = k (δ + b) for δ ≤ −b:
  :func:`_contact`);
- *torque elements* (:class:`Drives`): speed–torque curves (motors), fluid couplings, speed-
  squared loads with an angle schedule, imposed speed (stiff speed control);
- a tabulated force history F(t), an optional mass schedule M_ii(θ) and optional gyroscopic
  terms Ω G q̇ − Ω² K_Ω q with Ω = rᵀq̇ (rotating-frame models).

Schemes: fixed-step Newmark (average acceleration γ = ½, β = ¼ by default) and HHT-α
(Hilber-Hughes-Taylor 1977: β = (1+α)²/4, γ = ½ + α, α ∈ [0, ⅓]); the stiffness and the
nonlinear forces are evaluated at the Newmark predictor (one linear solve per step).
``method="adaptive"`` integrates with scipy's LSODA calling the same compiled right-hand side,
and :func:`reference_rhs` is a plain-numpy right-hand side used to check the kernels.

Divergence: a step producing non-finite values or |q| > ``q_limit`` stops the run; the result
holds every step computed before it and a ``diagnosis`` naming the time and the DOF.

Long runs go in chunks that return to Python (:mod:`geardyn.solve.control`): progress, stop
requests (status ``interrupted``), checkpoints and resume; the chunks continue exactly (the whole
loop state is carried), so the result does not depend on the chunking.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numba as nb
import numpy as np

from geardyn.solve.control import RunControl, check_record_size

# ---------------------------------------------------------------------------------------------
# data containers (structure of arrays)


@dataclass
class VarSprings:
    """Variable rank-one springs (SI: N/m, m, N·s/m; X in cycles of the tables)."""

    a: np.ndarray  # (ns, n) deflection vectors
    b: np.ndarray  # (ns, n) coordinate vectors, X = b·q + x0
    x0: np.ndarray  # (ns,)
    ktab: np.ndarray  # (ns, Lk) stiffness samples over one period
    klen: np.ndarray  # (ns,) used samples
    kper: np.ndarray  # (ns,) period of the k table in X units
    etab: np.ndarray  # (ns, Le) error samples (m)
    elen: np.ndarray
    eper: np.ndarray
    c: np.ndarray  # (ns,) damping
    contact_loss: np.ndarray  # (ns,) int8
    backlash: np.ndarray | None = None  # (ns,) m along a, ≥ 0 (None: zeros)

    def __post_init__(self) -> None:
        if self.backlash is None:
            self.backlash = np.zeros(self.a.shape[0])

    def gap(self) -> np.ndarray:
        """The contact law of each spring as the kernels take it (m): 0 two-sided linear,
        b > 0 backlash (separation for −b < δ < 0, back flank for δ ≤ −b), ∞ one-sided
        (``contact_loss`` with b = 0: an infinite backlash). A backlash b > 0 implies contact
        loss, whatever ``contact_loss`` says. Raises InputError on a negative or non-finite
        backlash, naming the spring."""
        from geardyn.errors import InputError

        b = np.asarray(self.backlash, float)
        if b.shape != (self.a.shape[0],):
            raise InputError(f"backlash: {b.shape} values for {self.a.shape[0]} variable "
                             "springs")
        bad = np.flatnonzero(~np.isfinite(b) | (b < 0))
        if bad.size:
            raise InputError(f"backlash of variable spring #{bad[0]}: {b[bad[0]]!r} m must be "
                             "finite and ≥ 0")
        return np.where(b > 0, b, np.where(np.asarray(self.contact_loss) == 1, np.inf, 0.0))

    @staticmethod
    def empty(n: int) -> VarSprings:
        z = np.zeros((0, n))
        e = np.zeros(0)
        return VarSprings(z, z.copy(), e, np.zeros((0, 1)), np.zeros(0, np.int64), e.copy(),
                          np.zeros((0, 1)), np.zeros(0, np.int64), e.copy(), e.copy(),
                          np.zeros(0, np.int8))

    @staticmethod
    def build(rows: list[dict], n: int) -> VarSprings:
        """From dicts with keys a, b, x0, k (array over one period), k_period, e, e_period, c,
        contact_loss, backlash (m)."""
        if not rows:
            return VarSprings.empty(n)
        lk = max(len(r["k"]) for r in rows)
        le = max(len(r.get("e", [0.0])) for r in rows)
        ns = len(rows)
        out = VarSprings(
            np.array([r["a"] for r in rows], float),
            np.array([r["b"] for r in rows], float),
            np.array([r.get("x0", 0.0) for r in rows], float),
            np.zeros((ns, lk)),
            np.array([len(r["k"]) for r in rows], np.int64),
            np.array([r.get("k_period", 1.0) for r in rows], float),
            np.zeros((ns, le)),
            np.array([len(r.get("e", [0.0])) for r in rows], np.int64),
            np.array([r.get("e_period", 1.0) for r in rows], float),
            np.array([r.get("c", 0.0) for r in rows], float),
            np.array([1 if r.get("contact_loss", False) else 0 for r in rows], np.int8),
            np.array([r.get("backlash", 0.0) for r in rows], float),
        )
        out.gap()  # validates the backlash
        for i, r in enumerate(rows):
            out.ktab[i, : len(r["k"])] = r["k"]
            e = np.asarray(r.get("e", [0.0]), float)
            out.etab[i, : len(e)] = e
        return out


SPEED_TORQUE, FLUID_COUPLING, SPEED_SQUARED_LOAD, SPEED_CONTROL = 0, 1, 2, 3


@dataclass
class Drives:
    """Torque elements (SoA). ``ha``/``hb`` convert DOF velocity to rad/s and torque to force
    (1/r for u = rθ coordinates, 1 for angle coordinates).

    - type 0 speed–torque source on a: T = table(ω_a) (x: rad/s, y: N·m), +T on a;
    - type 1 fluid coupling a (motor) → b through ratio p1 (ω_b,in = p1 ω_b):
      T = p0 ω_a (ω_a − p1 ω_b) (seed 004 eq 6.6), −T on a, +p1 T on b;
    - type 2 load: T = p0 ω_a² s(θ_a) for ω_a > 0 (table x: θ rad, y: factor), −T on a;
    - type 3 speed control: T = p0 (θ_ref(t) − θ_a) + p1 (ω_ref(t) − ω_a) (table x: t, y: θ_ref).
    """

    kind: np.ndarray
    a: np.ndarray
    b: np.ndarray
    ha: np.ndarray
    hb: np.ndarray
    p0: np.ndarray
    p1: np.ndarray
    tx: np.ndarray
    ty: np.ndarray
    tlen: np.ndarray

    @staticmethod
    def build(rows: list[dict]) -> Drives:
        ln = max([len(r.get("x", [0.0])) for r in rows] + [1])
        ne = len(rows)
        d = Drives(
            np.array([r["kind"] for r in rows], np.int64),
            np.array([r["a"] for r in rows], np.int64),
            np.array([r.get("b", 0) for r in rows], np.int64),
            np.array([r.get("ha", 1.0) for r in rows], float),
            np.array([r.get("hb", 1.0) for r in rows], float),
            np.array([r.get("p0", 0.0) for r in rows], float),
            np.array([r.get("p1", 0.0) for r in rows], float),
            np.zeros((ne, ln)),
            np.zeros((ne, ln)),
            np.array([len(r.get("x", [0.0])) for r in rows], np.int64),
        )
        for i, r in enumerate(rows):
            x = np.asarray(r.get("x", [0.0]), float)
            d.tx[i, : len(x)] = x
            d.ty[i, : len(x)] = np.asarray(r.get("y", [0.0]), float)
        return d


@dataclass
class MassSchedule:
    """M_ii = table(θ_ctrl) with θ_ctrl = h·q_ctrl (e.g. carrier + bucket-wheel inertia)."""

    dof: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    ctrl: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    h: np.ndarray = field(default_factory=lambda: np.zeros(0))
    tx: np.ndarray = field(default_factory=lambda: np.zeros((0, 1)))
    ty: np.ndarray = field(default_factory=lambda: np.zeros((0, 1)))
    tlen: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))


@dataclass
class LinearSystem:
    """Everything the kernels need (SI units)."""

    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    springs: VarSprings
    drives: Drives
    force_t: np.ndarray  # (nt,) time grid of the force table (uniform)
    force: np.ndarray  # (nt, n)
    mass_schedule: MassSchedule = field(default_factory=MassSchedule)
    dof_names: list[str] | None = None
    gyro_g: np.ndarray = field(default_factory=lambda: np.zeros((0, 1, 1)))  # (ng, n, n)
    gyro_k: np.ndarray = field(default_factory=lambda: np.zeros((0, 1, 1)))  # K_Ω
    gyro_rate: np.ndarray = field(default_factory=lambda: np.zeros((0, 1)))  # Ω = rate·v

    @property
    def n(self) -> int:
        return self.M.shape[0]


# ---------------------------------------------------------------------------------------------
# compiled pieces


@nb.njit(cache=True)
def _interp(x: float, xs: np.ndarray, ys: np.ndarray, n: int) -> float:
    if n == 1:
        return ys[0]
    if x <= xs[0]:
        return ys[0]
    if x >= xs[n - 1]:
        return ys[n - 1]
    lo, hi = 0, n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if xs[mid] <= x:
            lo = mid
        else:
            hi = mid
    w = (x - xs[lo]) / (xs[hi] - xs[lo])
    return ys[lo] * (1 - w) + ys[hi] * w


@nb.njit(cache=True)
def _periodic(x: float, tab: np.ndarray, n: int, period: float) -> float:
    if n == 1:
        return tab[0]
    s = (x / period) % 1.0 * n
    i = int(math.floor(s))
    w = s - i
    i = i % n
    j = (i + 1) % n
    return tab[i] * (1 - w) + tab[j] * w


@nb.njit(cache=True)
def _contact(d, g):
    """Contact state of a mesh with deflection d (m, drive flank d > 0) and gap g
    (:meth:`VarSprings.gap`): (1, 0) drive flank or two-sided linear spring (g = 0); (0, s)
    teeth separated, −g < d < 0, no force (s = g past mid-gap, else 0, the flank the stored
    energy is booked against); (−1, g) back flank, d ≤ −g: F = k (d + g) ≤ 0. The backlash law
    of the piecewise-linear clearance oscillator (Kahraman & Singh 1990, seed 004 §2.2 ref. 9);
    g = ∞ gives the one-sided law of seed 004 eq 3.2."""
    if g == 0.0 or d >= 0.0:
        return 1, 0.0
    if d > -g:
        return 0, (g if d <= -0.5 * g else 0.0)
    return -1, g


@nb.njit(cache=True)
def _mesh_state(q, sa, sb, sx0, ktab, klen, kper, etab, elen, eper, gap, kout, eout, dout):
    """k (tangent: 0 while separated), effective error e + s (the force is k (aᵀq + e + s))
    and deflection δ = aᵀq + e of every variable spring at q (dense a, b rows)."""
    ns = sa.shape[0]
    n = q.shape[0]
    for e in range(ns):
        x = sx0[e]
        d = 0.0
        for j in range(n):
            x += sb[e, j] * q[j]
            d += sa[e, j] * q[j]
        k = _periodic(x, ktab[e], klen[e], kper[e])
        er = _periodic(x, etab[e], elen[e], eper[e])
        d += er
        state, shift = _contact(d, gap[e])
        if state == 0:
            k = 0.0  # teeth separated (seed 004 eq 3.2)
        kout[e] = k
        eout[e] = er + shift
        dout[e] = d


@nb.njit(cache=True)
def _drive_forces(t, q, v, dk, da, db, dha, dhb, dp0, dp1, dtx, dty, dtl, f):
    for i in range(dk.shape[0]):
        a = da[i]
        wa = v[a] * dha[i]
        k = dk[i]
        if k == 0:
            tq = _interp(wa, dtx[i], dty[i], dtl[i])
            f[a] += tq * dha[i]
        elif k == 1:
            # linearised about (v_a, v_b) in C (_coupling_blocks): here T* minus the C v* part
            b = db[i]
            wb = v[b] * dhb[i] * dp1[i]
            tq = dp0[i] * wa * (wa - wb)
            ga = dp0[i] * (2.0 * wa - wb)
            gb = -dp0[i] * wa
            lin = ga * wa + gb * wb
            f[a] -= (tq - lin) * dha[i]
            f[b] += (tq - lin) * dp1[i] * dhb[i]
        elif k == 2:
            if wa > 0.0:
                th = q[a] * dha[i]
                tq = dp0[i] * wa * wa * _interp(th, dtx[i], dty[i], dtl[i])
                f[a] -= tq * dha[i]
        elif k == 3:
            # linear in (q, v): the k θ and c ω parts go into K and C (see _step_args)
            n = dtl[i]
            th_ref = _interp(t, dtx[i], dty[i], n)
            h = 1e-6 * (dtx[i, n - 1] - dtx[i, 0] + 1.0)
            w_ref = _interp(t + h, dtx[i], dty[i], n) - _interp(t - h, dtx[i], dty[i], n)
            w_ref /= 2 * h
            f[a] += (dp0[i] * th_ref + dp1[i] * w_ref) * dha[i]


@nb.njit(cache=True)
def _force_table(t, ft, fv, f):
    nt = ft.shape[0]
    n = f.shape[0]
    if nt == 0:
        for j in range(n):
            f[j] = 0.0
        return
    if nt == 1 or t <= ft[0]:
        for j in range(n):
            f[j] = fv[0, j]
        return
    if t >= ft[nt - 1]:
        for j in range(n):
            f[j] = fv[nt - 1, j]
        return
    s = (t - ft[0]) / (ft[1] - ft[0])
    i = int(math.floor(s))
    if i >= nt - 1:
        i = nt - 2
    w = s - i
    for j in range(n):
        f[j] = fv[i, j] * (1 - w) + fv[i + 1, j] * w


@nb.njit(cache=True)
def _applied_power(t, q, v, dk, da, db, dha, dhb, dp0, dp1, dtx, dty, dtl, ft, fv, gg, gk, gr,
                   fbuf):
    """Power vᵀF of the applied forces at (q, v, t): force table, the full drive torques (motor
    curves, fluid couplings, loads, speed control) and the gyroscopic/centripetal forces
    −Ω G q̇ + Ω² K_Ω q (seed 003 eq 3.1); and Σ|F_j v_j|, the gross power exchanged (the
    scale of the energy balance). Energy bookkeeping only."""
    n = q.shape[0]
    _force_table(t, ft, fv, fbuf)
    for i in range(dk.shape[0]):
        a = da[i]
        wa = v[a] * dha[i]
        k = dk[i]
        if k == 0:
            fbuf[a] += _interp(wa, dtx[i], dty[i], dtl[i]) * dha[i]
        elif k == 1:
            b = db[i]
            tq = dp0[i] * wa * (wa - v[b] * dhb[i] * dp1[i])
            fbuf[a] -= tq * dha[i]
            fbuf[b] += tq * dp1[i] * dhb[i]
        elif k == 2:
            if wa > 0.0:
                fbuf[a] -= dp0[i] * wa * wa * _interp(q[a] * dha[i], dtx[i], dty[i],
                                                      dtl[i]) * dha[i]
        elif k == 3:
            m = dtl[i]
            h = 1e-6 * (dtx[i, m - 1] - dtx[i, 0] + 1.0)
            w_ref = (_interp(t + h, dtx[i], dty[i], m) - _interp(t - h, dtx[i], dty[i], m)) / (
                2 * h)
            th_ref = _interp(t, dtx[i], dty[i], m)
            fbuf[a] += (dp0[i] * (th_ref - q[a] * dha[i]) + dp1[i] * (w_ref - wa)) * dha[i]
    p = 0.0
    pabs = 0.0
    for j in range(n):
        p += fbuf[j] * v[j]
        pabs += abs(fbuf[j] * v[j])
    for g in range(gg.shape[0]):
        om = 0.0
        for j in range(n):
            om += gr[g, j] * v[j]
        for i in range(n):
            s = 0.0
            for j in range(n):
                s += -om * gg[g, i, j] * v[j] + om * om * gk[g, i, j] * q[j]
            p += v[i] * s
            pabs += abs(v[i] * s)
    return p, pabs


@nb.njit(cache=True)
def _dissipated_power(v, c0p, c0i, c0x, ai, ax, an, sc, gap, shift, deff):
    """vᵀC₀v (C₀ in CSR) plus Σ c (aᵀv)² of the mesh dampers in contact (W); contact from the
    deflection δ = ``deff`` − ``shift`` (effective deflection less the flank shift)."""
    p = 0.0
    for i in range(v.shape[0]):
        s = 0.0
        for k in range(c0p[i], c0p[i + 1]):
            s += c0x[k] * v[c0i[k]]
        p += v[i] * s
    for e in range(an.shape[0]):
        if sc[e] == 0.0:
            continue
        state, _s = _contact(deff[e] - shift[e], gap[e])
        if state == 0:
            continue
        w = 0.0
        for k in range(an[e]):
            w += ax[e, k] * v[ai[e, k]]
        p += sc[e] * w * w
    return p


@nb.njit(cache=True)
def _energy_step(t, q, v, dt, c0p, c0i, c0x, ai, ax, an, sc, gap, sout, kout, eout,
                 dk, da, db, dha, dhb, dp0, dp1, dtx, dty, dtl, ft, fv, gg, gk, gr,
                 en, ek, ee, ed, fbuf):
    """Energy accumulators over one step ending at state (q, v, t).

    ``en`` = [applied work, dissipated work, parametric work, applied power, dissipated power,
    gross applied work ∫Σ|F_j v_j|, gross applied power] (powers at the previous state);
    ``ek``, ``ee``, ``ed`` = k, e, δ of each variable spring at the previous state, updated to
    the new one: k and e are those the step used (``kout``, ``eout``, at the Newmark
    predictor), δ = aᵀq + e. With backlash e and δ are the effective ones, shifted by the
    flank offset ``sout`` (:func:`_contact`), so that ½kδ² is the contact's energy; a change
    of flank happens while separated (k = 0) and books no work. Trapezoidal rule for the
    powers; the parametric work of a spring (stiffness and error varying with the mesh
    position) over the step is
    ½Δk·(δ₀² + δ₁²)/2 + k̄ δ̄ Δe, so that with the spring work k̄ δ̄ aᵀΔq it adds up exactly to
    Δ(½kδ²) for any sequence of k and e."""
    pa, pg = _applied_power(t, q, v, dk, da, db, dha, dhb, dp0, dp1, dtx, dty, dtl, ft, fv,
                            gg, gk, gr, fbuf)
    wp = 0.0
    for e in range(an.shape[0]):
        er = eout[e]
        d = er
        for j in range(an[e]):
            d += ax[e, j] * q[ai[e, j]]
        k = kout[e]
        wp += 0.25 * (k - ek[e]) * (d * d + ed[e] * ed[e]) + 0.25 * (k + ek[e]) * (
            d + ed[e]) * (er - ee[e])
        ek[e] = k
        ee[e] = er
        ed[e] = d
    pd = _dissipated_power(v, c0p, c0i, c0x, ai, ax, an, sc, gap, sout, ed)
    en[0] += 0.5 * dt * (en[3] + pa)
    en[1] += 0.5 * dt * (en[4] + pd)
    en[2] += wp
    en[3] = pa
    en[4] = pd
    en[5] += 0.5 * dt * (en[6] + pg)
    en[6] = pg


@nb.njit(cache=True)
def _lu_solve(A, b):
    """Solve A x = b in place (x into ``b``, ``A`` overwritten by its LU factors; Gaussian
    elimination with partial pivoting, Golub & Van Loan alg. 3.4.1). A singular matrix gives
    non-finite values, which the divergence check reports."""
    n = b.shape[0]
    for k in range(n):
        p = k
        amax = abs(A[k, k])
        for i in range(k + 1, n):
            if abs(A[i, k]) > amax:
                amax = abs(A[i, k])
                p = i
        if p != k:
            for j in range(n):
                tmp = A[k, j]
                A[k, j] = A[p, j]
                A[p, j] = tmp
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
        d = A[k, k]
        for i in range(k + 1, n):
            m = A[i, k] / d
            if m != 0.0:
                for j in range(k + 1, n):
                    A[i, j] -= m * A[k, j]
                b[i] -= m * b[k]
    for i in range(n - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, n):
            s -= A[i, j] * b[j]
        b[i] = s / A[i, i]


@nb.njit(cache=True)
def _mesh_eval(q, ai, ax, an, bi, bx, bn, sx0, ktab, klen, kper, etab, elen, eper, sc, gap,
               kout, eout, dout, cout, sout):
    """Tangent k, effective error e + s, deflection δ = aᵀq + e, damping c and flank shift s
    of every variable spring at q (sparse a, b rows); the force is k (aᵀq + e + s) + c aᵀq̇.
    Contact law :func:`_contact`: separated (contact loss, seed 004 eq 3.2, or within the
    backlash) k = c = 0; back flank s = b."""
    for e in range(sx0.shape[0]):
        x = sx0[e]
        for p in range(bn[e]):
            x += bx[e, p] * q[bi[e, p]]
        d = 0.0
        for p in range(an[e]):
            d += ax[e, p] * q[ai[e, p]]
        k = _periodic(x, ktab[e], klen[e], kper[e])
        er = _periodic(x, etab[e], elen[e], eper[e])
        d += er
        c = sc[e]
        state, shift = _contact(d, gap[e])
        if state == 0:
            k = 0.0
            c = 0.0
        kout[e] = k
        eout[e] = er + shift
        dout[e] = d
        cout[e] = c
        sout[e] = shift


@nb.njit(cache=True)
def _secant(k, d, s):
    """Recorded stiffness F/δ of a spring at tangent k, deflection d, flank shift s: k on the
    drive flank, 0 separated, k (d + s)/d on the back flank (so that k·δ is the contact
    force)."""
    if s == 0.0 or k == 0.0:
        return k
    return k * (d + s) / d


@nb.njit(cache=True)
def _coupling_blocks(v, cidx, da, db, dha, dhb, dp0, dp1, blocks):
    """Damping blocks of the fluid couplings linearised about v (rows/cols: DOFs a, b)."""
    for j in range(cidx.shape[0]):
        i = cidx[j]
        a = da[i]
        b = db[i]
        wa = v[a] * dha[i]
        wb = v[b] * dhb[i] * dp1[i]
        ga = dp0[i] * (2.0 * wa - wb)
        gb = -dp0[i] * wa
        hb = dp1[i] * dhb[i]
        blocks[j, 0, 0] = ga * dha[i] * dha[i]
        blocks[j, 0, 1] = gb * hb * dha[i]
        blocks[j, 1, 0] = -hb * ga * dha[i]
        blocks[j, 1, 1] = -hb * gb * hb


@nb.njit(cache=True)
def _residual(q, v, f, kp, ki, kx, cp, ci, cx, ai, ax, an, kout, eout, cout, cidx, da, db,
              blocks, gg, gk, om, out):
    """out = f − C(t) v − K(t) q: constant part (CSR), Σ a (k (aᵀq + e) + c aᵀv) of the
    variable springs, the coupling blocks and the gyroscopic terms Ω G v − Ω² K_Ω q."""
    n = q.shape[0]
    for i in range(n):
        s = f[i]
        for p in range(kp[i], kp[i + 1]):
            s -= kx[p] * q[ki[p]]
        for p in range(cp[i], cp[i + 1]):
            s -= cx[p] * v[ci[p]]
        out[i] = s
    for e in range(an.shape[0]):
        k = kout[e]
        c = cout[e]
        if k == 0.0 and c == 0.0:
            continue
        aq = eout[e]
        av = 0.0
        for p in range(an[e]):
            aq += ax[e, p] * q[ai[e, p]]
            av += ax[e, p] * v[ai[e, p]]
        g = k * aq + c * av
        for p in range(an[e]):
            out[ai[e, p]] -= g * ax[e, p]
    for j in range(cidx.shape[0]):
        a = da[cidx[j]]
        b = db[cidx[j]]
        va = v[a]
        vb = v[b]
        out[a] -= blocks[j, 0, 0] * va + blocks[j, 0, 1] * vb
        out[b] -= blocks[j, 1, 0] * va + blocks[j, 1, 1] * vb
    for g in range(gg.shape[0]):
        for i in range(n):
            s = 0.0
            for j in range(n):
                s += om[g] * gg[g, i, j] * v[j] - om[g] * om[g] * gk[g, i, j] * q[j]
            out[i] -= s


@nb.njit(cache=True)
def _gyro_rates(v, gr, om):
    for g in range(gr.shape[0]):
        s = 0.0
        for j in range(v.shape[0]):
            s += gr[g, j] * v[j]
        om[g] = s


@nb.njit(cache=True)
def _mass_diag(q, M0, md, mc, mh, mtx, mty, mtl, dm):
    """Changes M_ii(θ) − M₀_ii of the scheduled masses at q."""
    for i in range(md.shape[0]):
        dm[i] = _interp(q[mc[i]] * mh[i], mtx[i], mty[i], mtl[i]) - M0[md[i], md[i]]


@nb.njit(cache=True)
def _newmark_kernel(M0, sc, gap, dk, da, db, dha, dhb, dp0, dp1, dtx, dty, dtl, ft, fv,
                    md, mc, mh, mtx, mty, mtl, gg, gk, gr, c0p, c0i, c0x, kp, ki, kx, cp, ci, cx,
                    ai, ax, an, bi, bx, bn, sx0, ktab, klen, kper, etab, elen, eper, cidx,
                    A0, A0inv, Z, UZ, kbar, cbar, lowrank,
                    qs, vs, accs, r0s, t0, dt, step0, nsteps, save_every, alpha, qlim,
                    Q, V, KS, DS, TS, en, ek, ee, ed, energy, start):
    """Fixed-step HHT-α/Newmark from global step ``step0`` over ``nsteps`` steps.

    Step matrix A = M + (1 − α)(γΔt C + βΔt² K) = A₀ + U D Uᵀ (+ gyroscopic terms): A₀ the
    constant part (mass, linear elements, speed controls, every variable spring at its mean
    stiffness and damping), U the spring vectors aₑ, unit vectors of the fluid-coupling DOFs
    (linearised damping block) and of the scheduled masses, D the deviations. ``lowrank``:
    Sherman–Morrison–Woodbury with the precomputed A₀⁻¹, Z = A₀⁻¹U, UᵀZ (Golub & Van Loan
    §2.1.4), x = y − Z (I + D UᵀZ)⁻¹ D Uᵀ y, y = A₀⁻¹ b; else A is formed and factored (LU).

    The state (q, v, a, r0: ``qs``, ``vs``, ``accs``, ``r0s``) and the energy accumulators are
    updated in place, so that chunks continue exactly; global step s is saved in row
    s // save_every when s is a multiple of ``save_every``. Returns (steps done, status,
    offending DOF); t = t0 + s·dt. ``energy``: book the energy terms (:func:`_energy_step`).

    ``start`` (with ``nsteps`` = 0): the initial acceleration M a = F − C v − K q at (q, v, t0)
    (into ``accs``; ``r0s`` the residual force), the springs' k and δ (row 0 of ``KS``,
    ``DS``) and the energy accumulators' start values. One kernel for both, written with loops
    only (no array expressions, no slice assignments), to keep the compile time short."""
    n = qs.shape[0]
    ns = sx0.shape[0]
    nc = cidx.shape[0]
    nm = md.shape[0]
    m = Z.shape[1]
    beta = (1.0 + alpha) ** 2 / 4.0
    gamma = 0.5 + alpha
    fa = 1.0 - alpha
    sk = fa * beta * dt * dt
    scd = fa * gamma * dt
    q = np.empty(n)
    v = np.empty(n)
    acc = np.empty(n)
    r0 = np.empty(n)
    for i in range(n):
        q[i] = qs[i]
        v[i] = vs[i]
        acc[i] = accs[i]
        r0[i] = r0s[i]
    qp = np.empty(n)
    vp = np.empty(n)
    f = np.empty(n)
    res = np.empty(n)
    y = np.empty(n)
    fbuf = np.empty(n)
    kout = np.empty(ns)
    eout = np.empty(ns)
    dout = np.empty(ns)
    cout = np.empty(ns)
    sout = np.empty(ns)
    blocks = np.zeros((nc, 2, 2))
    om = np.zeros(gg.shape[0])
    dm = np.zeros(nm)
    w = np.empty(m)
    cap = np.empty((m, m))
    A = np.empty((n, n))
    h1 = dt * dt * (0.5 - beta)
    h2 = dt * (1.0 - gamma)
    if start:
        t = t0 + step0 * dt
        _mesh_eval(q, ai, ax, an, bi, bx, bn, sx0, ktab, klen, kper, etab, elen, eper, sc,
                   gap, kout, eout, dout, cout, sout)
        _force_table(t, ft, fv, f)
        _drive_forces(t, q, v, dk, da, db, dha, dhb, dp0, dp1, dtx, dty, dtl, f)
        _coupling_blocks(v, cidx, da, db, dha, dhb, dp0, dp1, blocks)
        _gyro_rates(v, gr, om)
        _residual(q, v, f, kp, ki, kx, cp, ci, cx, ai, ax, an, kout, eout, cout, cidx, da,
                  db, blocks, gg, gk, om, r0s)
        _mass_diag(q, M0, md, mc, mh, mtx, mty, mtl, dm)
        for i in range(n):
            for j in range(n):
                A[i, j] = M0[i, j]
            accs[i] = r0s[i]
        for i in range(nm):
            A[md[i], md[i]] += dm[i]
        _lu_solve(A, accs)
        for i in range(en.shape[0]):
            en[i] = 0.0
        for e in range(ns):
            ek[e] = kout[e]
            ee[e] = eout[e]
            ed[e] = dout[e] + sout[e]
            KS[0, e] = _secant(kout[e], dout[e], sout[e])
            DS[0, e] = dout[e]
        en[3], en[6] = _applied_power(t, q, v, dk, da, db, dha, dhb, dp0, dp1, dtx, dty, dtl,
                                      ft, fv, gg, gk, gr, fbuf)
        en[4] = _dissipated_power(v, c0p, c0i, c0x, ai, ax, an, sc, gap, sout, ed)
    for local in range(1, nsteps + 1):
        step = step0 + local
        t = t0 + step * dt
        for i in range(n):
            qp[i] = q[i] + dt * v[i] + h1 * acc[i]
            vp[i] = v[i] + h2 * acc[i]
        _mesh_eval(qp, ai, ax, an, bi, bx, bn, sx0, ktab, klen, kper, etab, elen, eper, sc,
                   gap, kout, eout, dout, cout, sout)
        _force_table(t, ft, fv, f)
        _drive_forces(t, qp, vp, dk, da, db, dha, dhb, dp0, dp1, dtx, dty, dtl, f)
        _coupling_blocks(vp, cidx, da, db, dha, dhb, dp0, dp1, blocks)
        _gyro_rates(vp, gr, om)
        _mass_diag(qp, M0, md, mc, mh, mtx, mty, mtl, dm)
        _residual(qp, vp, f, kp, ki, kx, cp, ci, cx, ai, ax, an, kout, eout, cout, cidx, da,
                  db, blocks, gg, gk, om, res)
        for i in range(n):
            res[i] = fa * res[i] + alpha * r0[i]
        if lowrank:
            for i in range(n):
                s = 0.0
                for j in range(n):
                    s += A0inv[i, j] * res[j]
                y[i] = s
            # w = Uᵀy, then the rows of D (I + D UᵀZ)c = D w, block by block
            for e in range(ns):
                s = 0.0
                for p in range(an[e]):
                    s += ax[e, p] * y[ai[e, p]]
                w[e] = s
            for j in range(nc):
                w[ns + 2 * j] = y[da[cidx[j]]]
                w[ns + 2 * j + 1] = y[db[cidx[j]]]
            for i in range(nm):
                w[ns + 2 * nc + i] = y[md[i]]
            for e in range(ns):
                de = sk * (kout[e] - kbar[e]) + scd * (cout[e] - cbar[e])
                for c in range(m):
                    cap[e, c] = de * UZ[e, c]
                cap[e, e] += 1.0
                w[e] *= de
            for j in range(nc):
                r = ns + 2 * j
                b00 = scd * blocks[j, 0, 0]
                b01 = scd * blocks[j, 0, 1]
                b10 = scd * blocks[j, 1, 0]
                b11 = scd * blocks[j, 1, 1]
                for c in range(m):
                    cap[r, c] = b00 * UZ[r, c] + b01 * UZ[r + 1, c]
                    cap[r + 1, c] = b10 * UZ[r, c] + b11 * UZ[r + 1, c]
                cap[r, r] += 1.0
                cap[r + 1, r + 1] += 1.0
                w0 = w[r]
                w[r] = b00 * w0 + b01 * w[r + 1]
                w[r + 1] = b10 * w0 + b11 * w[r + 1]
            for i in range(nm):
                r = ns + 2 * nc + i
                for c in range(m):
                    cap[r, c] = dm[i] * UZ[r, c]
                cap[r, r] += 1.0
                w[r] *= dm[i]
            _lu_solve(cap, w)
            for i in range(n):
                s = y[i]
                for c in range(m):
                    s -= Z[i, c] * w[c]
                y[i] = s
        else:
            for i in range(n):
                for j in range(n):
                    A[i, j] = A0[i, j]
            for e in range(ns):
                de = sk * (kout[e] - kbar[e]) + scd * (cout[e] - cbar[e])
                if de != 0.0:
                    for p in range(an[e]):
                        g = de * ax[e, p]
                        for p2 in range(an[e]):
                            A[ai[e, p], ai[e, p2]] += g * ax[e, p2]
            for j in range(nc):
                a = da[cidx[j]]
                b = db[cidx[j]]
                A[a, a] += scd * blocks[j, 0, 0]
                A[a, b] += scd * blocks[j, 0, 1]
                A[b, a] += scd * blocks[j, 1, 0]
                A[b, b] += scd * blocks[j, 1, 1]
            for i in range(nm):
                A[md[i], md[i]] += dm[i]
            for g in range(gg.shape[0]):
                for i in range(n):
                    for j in range(n):
                        A[i, j] += scd * om[g] * gg[g, i, j] - sk * om[g] * om[g] * gk[g, i, j]
            for i in range(n):
                y[i] = res[i]
            _lu_solve(A, y)
        for i in range(n):
            q[i] = qp[i] + beta * dt * dt * y[i]
            v[i] = vp[i] + gamma * dt * y[i]
            acc[i] = y[i]
        if alpha != 0.0:
            # HHT: r0 for the next step is the residual force at n+1 (without inertia)
            _residual(q, v, f, kp, ki, kx, cp, ci, cx, ai, ax, an, kout, eout, cout, cidx, da,
                      db, blocks, gg, gk, om, r0)
        bad = -1
        for j in range(n):
            if not math.isfinite(q[j]) or abs(q[j]) > qlim:
                bad = j
                break
        if bad >= 0:
            return local - 1, 1, bad
        if energy:
            _energy_step(t, q, v, dt, c0p, c0i, c0x, ai, ax, an, sc, gap, sout, kout, eout, dk, da,
                         db, dha, dhb,
                         dp0, dp1, dtx, dty, dtl, ft, fv, gg, gk, gr, en, ek, ee, ed, fbuf)
        if step % save_every == 0:
            row = step // save_every
            for i in range(n):
                Q[row, i] = q[i]
                V[row, i] = v[i]
            for e in range(ns):
                KS[row, e] = _secant(kout[e], dout[e], sout[e])
                DS[row, e] = dout[e]
            TS[row] = t
    if nsteps > 0:
        for i in range(n):
            qs[i] = q[i]
            vs[i] = v[i]
            accs[i] = acc[i]
            r0s[i] = r0[i]
    return nsteps, 0, -1


@nb.njit(cache=True)
def _rhs_kernel(t, y, M0, sc, gap, dk, da, db, dha, dhb, dp0, dp1, dtx, dty, dtl, ft, fv,
                md, mc, mh, mtx, mty, mtl, gg, gk, gr, c0p, c0i, c0x, kp, ki, kx, cp, ci, cx,
                ai, ax, an, bi, bx, bn, sx0, ktab, klen, kper, etab, elen, eper, cidx):
    """y' = [v, M(q)⁻¹ (F − C v − K q)] at (t, y = [q, v]) (seed 004 eq 3.41), with the
    helpers of the step kernel (fluid couplings linearised about v: same value)."""
    n = M0.shape[0]
    ns = sx0.shape[0]
    q = np.empty(n)
    v = np.empty(n)
    for i in range(n):
        q[i] = y[i]
        v[i] = y[n + i]
    kout = np.empty(ns)
    eout = np.empty(ns)
    dout = np.empty(ns)
    cout = np.empty(ns)
    f = np.empty(n)
    blocks = np.zeros((cidx.shape[0], 2, 2))
    om = np.zeros(gg.shape[0])
    dm = np.zeros(md.shape[0])
    _mesh_eval(q, ai, ax, an, bi, bx, bn, sx0, ktab, klen, kper, etab, elen, eper, sc, gap,
               kout, eout, dout, cout, np.empty(ns))
    _force_table(t, ft, fv, f)
    _drive_forces(t, q, v, dk, da, db, dha, dhb, dp0, dp1, dtx, dty, dtl, f)
    _coupling_blocks(v, cidx, da, db, dha, dhb, dp0, dp1, blocks)
    _gyro_rates(v, gr, om)
    out = np.empty(2 * n)
    acc = np.empty(n)
    _residual(q, v, f, kp, ki, kx, cp, ci, cx, ai, ax, an, kout, eout, cout, cidx, da, db,
              blocks, gg, gk, om, acc)
    _mass_diag(q, M0, md, mc, mh, mtx, mty, mtl, dm)
    m = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            m[i, j] = M0[i, j]
    for i in range(md.shape[0]):
        m[md[i], md[i]] += dm[i]
    _lu_solve(m, acc)
    for i in range(n):
        out[i] = v[i]
        out[n + i] = acc[i]
    return out


def _sparse_rows(mat: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows of ``mat`` as padded (indices, values, counts) of their nonzero entries."""
    nz = [np.flatnonzero(r) for r in mat]
    width = max([len(i) for i in nz] + [1])
    idx = np.zeros((mat.shape[0], width), np.int64)
    val = np.zeros((mat.shape[0], width))
    for e, i in enumerate(nz):
        idx[e, : len(i)] = i
        val[e, : len(i)] = mat[e, i]
    return idx, val, np.array([len(i) for i in nz], np.int64)


def _csr(a: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    ptr, idx, val = [0], [], []
    for row in a:
        nz = np.flatnonzero(row)
        idx.extend(nz)
        val.extend(row[nz])
        ptr.append(len(idx))
    return np.array(ptr, np.int64), np.array(idx, np.int64), np.array(val, float)


#: Linear solve of a Newmark step: Woodbury update of the constant factored part, or dense LU.
SOLVES = ("auto", "lowrank", "dense")


def _dense_ops(a0: np.ndarray) -> float:
    """Multiply-adds of a step's in-place LU (:func:`_lu_solve`, rows with a zero multiplier
    skipped) for the sparsity of ``a0`` and its fill-in, plus copy and substitution."""
    import scipy.linalg as sla

    n = a0.shape[0]
    lu, _ = sla.lu_factor(a0, check_finite=False)
    below = np.count_nonzero(np.tril(lu, -1), axis=0)
    return float(below @ (n - np.arange(n)) + 2 * n * n)


def _lowrank_ops(n: int, m: int) -> float:
    """Multiply-adds of a Woodbury step solve: A₀⁻¹b, UᵀZ-based m × m system and its LU, Zc."""
    return float(2 * n * n + 2 * n * m + m**3 / 3 + 2 * m * m)


def _step_args(sys: LinearSystem, dt: float, alpha: float, solve: str) -> tuple[tuple, str]:
    """Kernel arguments of :func:`_newmark_kernel` (constant step matrix A₀ and its inverse,
    the low-rank basis) and the linear solve used (``lowrank`` or ``dense``)."""
    if solve not in SOLVES:
        raise ValueError(f"solve {solve!r} must be one of {SOLVES}")
    s, d, ms = sys.springs, sys.drives, sys.mass_schedule
    n = sys.n
    beta, gamma, fa = (1.0 + alpha) ** 2 / 4.0, 0.5 + alpha, 1.0 - alpha
    k0 = np.array(sys.K, float)
    c0 = np.array(sys.C, float)
    for i in np.flatnonzero(d.kind == SPEED_CONTROL):
        k0[d.a[i], d.a[i]] += d.p0[i] * d.ha[i] ** 2
        c0[d.a[i], d.a[i]] += d.p1[i] * d.ha[i] ** 2
    a = np.asarray(s.a, float)
    kbar = np.array([s.ktab[e, : s.klen[e]].mean() for e in range(a.shape[0])])
    cbar = np.array(s.c, float)
    a0 = np.array(sys.M, float) + fa * (gamma * dt * c0 + beta * dt * dt * k0)
    a0 += (a.T * fa * (beta * dt * dt * kbar + gamma * dt * cbar)) @ a
    cidx = np.flatnonzero(d.kind == FLUID_COUPLING).astype(np.int64)
    cols = [a.T]
    for i in cidx:
        cols.append(np.eye(n)[:, [d.a[i], d.b[i]]])
    cols.append(np.eye(n)[:, ms.dof])
    u = np.hstack(cols)
    m = u.shape[1]
    if solve == "auto":
        solve = "lowrank" if (sys.gyro_g.shape[0] == 0
                              and _lowrank_ops(n, m) < _dense_ops(a0)) else "dense"
    if solve == "lowrank" and sys.gyro_g.shape[0]:
        raise ValueError("solve 'lowrank': gyroscopic terms change the whole step matrix; use "
                         "'dense' or 'auto'")
    if solve == "lowrank":
        a0inv = np.linalg.inv(a0)
        z = a0inv @ u
        uz = u.T @ z
    else:
        a0inv, z, uz = np.zeros((0, 0)), np.zeros((n, 0)), np.zeros((0, 0))
    ai, ax, an = _sparse_rows(a)
    bi, bx, bn = _sparse_rows(np.asarray(s.b, float))
    args = (np.ascontiguousarray(sys.M, float), s.c, s.gap(),
            d.kind, d.a, d.b, d.ha, d.hb, d.p0, d.p1, d.tx, d.ty, d.tlen,
            np.asarray(sys.force_t, float), np.ascontiguousarray(sys.force, float),
            ms.dof, ms.ctrl, ms.h, ms.tx, ms.ty, ms.tlen,
            sys.gyro_g, sys.gyro_k, sys.gyro_rate, *_csr(np.asarray(sys.C, float)),
            *_csr(k0), *_csr(c0), ai, ax, an, bi, bx, bn,
            s.x0, s.ktab, s.klen, s.kper, s.etab, s.elen, s.eper, cidx)
    step = (np.ascontiguousarray(a0), np.ascontiguousarray(a0inv), np.ascontiguousarray(z),
            np.ascontiguousarray(uz), kbar, cbar, solve == "lowrank")
    return args + step, solve


# ---------------------------------------------------------------------------------------------
# drivers


@dataclass
class IntegrationResult:
    """Saved states; ``status`` is ``"ok"``, ``"diverged"`` or ``"interrupted"`` (a stop
    request between chunks) with a ``diagnosis``; ``energy`` the energy balance terms (J) of
    :func:`newmark` (empty when not available)."""

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    k: np.ndarray  # variable-spring stiffness F/δ at saved steps (0 while separated)
    delta: np.ndarray  # variable-spring deflection (incl. error) at saved steps; k·δ = force
    status: str
    diagnosis: str
    wall_s: float
    energy: dict[str, float] = field(default_factory=dict)


def stored_energy(sys: LinearSystem, q: np.ndarray, v: np.ndarray, k: np.ndarray,
                  delta: np.ndarray) -> tuple[float, float]:
    """Kinetic ½vᵀMv and potential ½qᵀK₀q + Σ ½kδ² energy (J) of state (q, v) with the
    variable springs at stiffness ``k`` and deflection ``delta``."""
    ke = 0.5 * float(v @ sys.M @ v)
    pe = 0.5 * float(q @ sys.K @ q) + 0.5 * float(np.sum(k * delta * delta))
    return ke, pe


#: Integrator state carried between chunks and written to checkpoints.
_STATE = ("q", "v", "acc", "r0", "en", "ek", "ee", "ed")
_SAVED = ("Q", "V", "KS", "DS", "TS")


def newmark(
    sys: LinearSystem,
    q0: np.ndarray,
    v0: np.ndarray,
    t_end: float,
    dt: float,
    save_every: int = 1,
    alpha: float = 0.0,
    t0: float = 0.0,
    q_limit: float = 1e10,
    progress: Callable[[float], None] | None = None,
    chunk_steps: int | None = None,
    control: RunControl | None = None,
    energy: bool = True,
    solve: str = "auto",
) -> IntegrationResult:
    """Fixed-step Newmark (α = 0, average acceleration) or HHT-α (0 < α ≤ ⅓) integration.

    The run is cut into chunks (at most ``chunk_steps`` steps each, else sized by ``control``)
    that continue exactly, so that ``progress(fraction)`` can be reported, a stop request of
    ``control`` ends the run with status ``interrupted`` and its computed part, and a
    checkpoint of ``control`` gets the full state (``control.resume`` continues from one,
    bit-identically). A divergence (non-finite or |q| > ``q_limit``) stops the run and keeps
    what was computed. ``energy``: book the work of the applied forces, dissipated and
    parametric work, stored energy at start and end (:func:`_energy_step`, in
    ``IntegrationResult.energy``; 0.3-0.7 µs per step, 5-12 %, on the reclaimer model).
    ``solve``: the step's linear solve, ``lowrank`` (Woodbury update of the constant part
    factored once, :func:`_newmark_kernel`), ``dense`` (LU of the whole step matrix every step)
    or ``auto`` (lowrank when it needs fewer operations, counted from the sparsity of the
    step matrix's LU, and there are no gyroscopic terms).
    """
    if not 0.0 <= alpha <= 1.0 / 3.0:
        raise ValueError(f"HHT alpha {alpha} must be in [0, 1/3]")
    if not (dt > 0 and t_end > t0):
        raise ValueError(f"dt must be > 0 and t_end > t0 (dt = {dt!r} s, t0 = {t0!r} s, "
                         f"t_end = {t_end!r} s)")
    ctl = control or RunControl(progress=progress)
    if progress is not None and ctl.progress is None:
        ctl.progress = progress
    args, solve = _step_args(sys, dt, alpha, solve)
    dt, t0, alpha, q_limit = float(dt), float(t0), float(alpha), float(q_limit)  # one signature
    nsteps = int(round((t_end - t0) / dt))
    save_every = max(1, int(save_every))
    n, ns = sys.n, sys.springs.a.shape[0]
    nsave = nsteps // save_every + 1
    check_record_size(nsave, 2 * n + 2 * ns + 1, f"raise save_every ({save_every}) or shorten "
                      "the run")
    out = {"Q": np.zeros((nsave, n)), "V": np.zeros((nsave, n)), "KS": np.zeros((nsave, ns)),
           "DS": np.zeros((nsave, ns)), "TS": np.zeros(nsave)}
    st = {"q": np.asarray(q0, float).copy(), "v": np.asarray(v0, float).copy(),
          "acc": np.zeros(n), "r0": np.zeros(n), "en": np.zeros(7), "ek": np.zeros(ns),
          "ee": np.zeros(ns), "ed": np.zeros(ns)}
    run_id = {"scheme": "newmark", "nsteps": nsteps, "dt": float(dt), "t0": float(t0),
              "save_every": save_every, "alpha": float(alpha), "n": n, "ns": ns,
              "energy": int(energy), "solve": solve}
    if ctl.resume is not None:
        done, stored0 = _resume_newmark(ctl.resume, run_id, st, out)
    else:
        _newmark_kernel(*args, st["q"], st["v"], st["acc"], st["r0"], t0, dt, 0, 0, save_every,
                        alpha, q_limit, out["Q"], out["V"], out["KS"], out["DS"], out["TS"],
                        st["en"], st["ek"], st["ee"], st["ed"], energy, True)
        out["Q"][0], out["V"][0], out["TS"][0] = st["q"], st["v"], t0
        done = 0
        stored0 = stored_energy(sys, st["q"], st["v"], st["ek"], st["ed"])
    status, diag = "ok", ""
    w0 = time.perf_counter()

    def state() -> dict:
        rows = done // save_every + 1
        return {**run_id, "step": done, "stored_start": np.array(stored0),
                **{k: st[k] for k in _STATE}, **{k: out[k][:rows] for k in _SAVED}}

    while done < nsteps:
        m = ctl.next_chunk(done, nsteps, chunk_steps)
        w = time.perf_counter()
        steps, code, bad = _newmark_kernel(
            *args, st["q"], st["v"], st["acc"], st["r0"], t0, dt, done, m, save_every, alpha,
            q_limit, out["Q"], out["V"], out["KS"], out["DS"], out["TS"], st["en"], st["ek"],
            st["ee"], st["ed"], energy, False)
        w = time.perf_counter() - w
        if code != 0:
            done += steps
            name = sys.dof_names[bad] if sys.dof_names else f"#{bad}"
            status = "diverged"
            diag = (
                f"diverged at t = {t0 + (done + 1) * dt:.6g} s: DOF '{name}' became non-finite "
                f"or exceeded {q_limit:g}; results kept up to t = {t0 + done * dt:.6g} s. "
                "Reduce dt, add damping, or check for negative/unsupported stiffness and "
                "unbounded loads."
            )
            break
        done += m
        ctl.chunk_done(m, w, done, nsteps, state)
        if ctl.stop_requested and done < nsteps:
            status = "interrupted"
            diag = (f"{ctl.stop_reason or 'interrupted'} at t = {t0 + done * dt:.6g} s (step "
                    f"{done} of {nsteps}): the computed part is kept")
            break
    rows = done // save_every + 1
    terms: dict[str, float] = {}
    if status != "diverged" and energy:
        ke1, pe1 = stored_energy(sys, st["q"], st["v"], st["ek"], st["ed"])
        en = st["en"]
        terms = {"applied_J": float(en[0]), "dissipated_J": float(en[1]),
                  "parametric_J": float(en[2]), "gross_applied_J": float(en[5]),
                  "kinetic_start_J": float(stored0[0]),
                  "potential_start_J": float(stored0[1]), "kinetic_end_J": ke1,
                  "potential_end_J": pe1}
    return IntegrationResult(
        out["TS"][:rows], out["Q"][:rows], out["V"][:rows], out["KS"][:rows],
        out["DS"][:rows], status, diag, time.perf_counter() - w0, terms,
    )


def _resume_newmark(saved: dict, run_id: dict, st: dict, out: dict) -> tuple[int, tuple]:
    """Fill the state and the saved rows from checkpoint ``saved`` (same run only)."""
    from geardyn.solve.control import check_same_run

    check_same_run(saved, run_id)
    done = int(saved["step"])
    for k in _STATE:
        st[k][...] = saved[k]
    rows = done // run_id["save_every"] + 1
    for k in _SAVED:
        out[k][:rows] = saved[k]
    s0 = np.asarray(saved["stored_start"], float)
    return done, (float(s0[0]), float(s0[1]))


def compiled_rhs(sys: LinearSystem) -> Callable[[float, np.ndarray], np.ndarray]:
    """First-order right-hand side y' = f(t, y) (y = [q, v]) using the compiled kernels."""
    args = _step_args(sys, 1.0, 0.0, "dense")[0][:-7]

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        return _rhs_kernel(t, y, *args)

    return rhs


def adaptive(sys: LinearSystem, q0: np.ndarray, v0: np.ndarray, t_eval: np.ndarray,
             rtol: float = 1e-6, atol: float = 1e-12, method: str = "LSODA") -> IntegrationResult:
    """Adaptive-step integration (scipy ``solve_ivp``) of the compiled right-hand side."""
    from scipy.integrate import solve_ivp

    w0 = time.perf_counter()
    sol = solve_ivp(compiled_rhs(sys), (t_eval[0], t_eval[-1]), np.concatenate([q0, v0]),
                    method=method, t_eval=t_eval, rtol=rtol, atol=atol)
    n = sys.n
    y = sol.y.T
    ns = sys.springs.a.shape[0]
    status = "ok" if sol.success else "diverged"
    return IntegrationResult(sol.t, y[:, :n], y[:, n:], np.full((len(sol.t), ns), np.nan),
                             np.full((len(sol.t), ns), np.nan), status,
                             "" if sol.success else str(sol.message), time.perf_counter() - w0)


def reference_rhs(sys: LinearSystem) -> Callable[[float, np.ndarray], np.ndarray]:
    """Plain Python/numpy right-hand side of the same model (the benchmark's baseline and an
    independent check of the kernels; written from the equations, not from the kernels)."""
    s, d, ms = sys.springs, sys.drives, sys.mass_schedule
    n = sys.n
    backlash = np.asarray(s.backlash, float)

    def periodic(x: float, tab: np.ndarray, ln: int, per: float) -> float:
        if ln == 1:
            return float(tab[0])
        pos = (x / per) % 1.0 * ln
        i = int(pos)
        w = pos - i
        return float(tab[i % ln] * (1 - w) + tab[(i + 1) % ln] * w)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        q, v = y[:n], y[n:]
        M = sys.M.copy()
        for i in range(len(ms.dof)):
            ln = ms.tlen[i]
            M[ms.dof[i], ms.dof[i]] = np.interp(q[ms.ctrl[i]] * ms.h[i], ms.tx[i, :ln],
                                                ms.ty[i, :ln])
        K = sys.K.copy()
        C = sys.C.copy()
        if len(sys.force_t):
            f = np.array([np.interp(t, sys.force_t, sys.force[:, j]) for j in range(n)])
        else:
            f = np.zeros(n)
        for g in range(sys.gyro_g.shape[0]):
            om = sys.gyro_rate[g] @ v
            C += om * sys.gyro_g[g]
            K -= om**2 * sys.gyro_k[g]
        for e in range(s.a.shape[0]):
            x = s.b[e] @ q + s.x0[e]
            k = periodic(x, s.ktab[e], s.klen[e], s.kper[e])
            er = periodic(x, s.etab[e], s.elen[e], s.eper[e])
            delta = s.a[e] @ q + er
            c = s.c[e]
            back = 0.0  # back flank: F = k (δ + b)
            if delta < 0 and (s.contact_loss[e] or backlash[e] > 0):
                if backlash[e] > 0 and delta <= -backlash[e]:
                    back = backlash[e]
                else:
                    k, c = 0.0, 0.0
            K += k * np.outer(s.a[e], s.a[e])
            C += c * np.outer(s.a[e], s.a[e])
            f -= k * (er + back) * s.a[e]
        for i in range(len(d.kind)):
            a = d.a[i]
            ln = d.tlen[i]
            wa = v[a] * d.ha[i]
            if d.kind[i] == SPEED_TORQUE:
                f[a] += np.interp(wa, d.tx[i, :ln], d.ty[i, :ln]) * d.ha[i]
            elif d.kind[i] == FLUID_COUPLING:
                b = d.b[i]
                tq = d.p0[i] * wa * (wa - v[b] * d.hb[i] * d.p1[i])
                f[a] -= tq * d.ha[i]
                f[b] += tq * d.p1[i] * d.hb[i]
            elif d.kind[i] == SPEED_SQUARED_LOAD:
                if wa > 0:
                    tq = d.p0[i] * wa**2 * np.interp(q[a] * d.ha[i], d.tx[i, :ln], d.ty[i, :ln])
                    f[a] -= tq * d.ha[i]
            elif d.kind[i] == SPEED_CONTROL:
                tx, ty = d.tx[i, :ln], d.ty[i, :ln]
                h = 1e-6 * (tx[-1] - tx[0] + 1.0)
                wr = (np.interp(t + h, tx, ty) - np.interp(t - h, tx, ty)) / (2 * h)
                tq = d.p0[i] * (np.interp(t, tx, ty) - q[a] * d.ha[i]) + d.p1[i] * (wr - wa)
                f[a] += tq * d.ha[i]
        return np.concatenate([v, np.linalg.solve(M, f - C @ v - K @ q)])

    return rhs
