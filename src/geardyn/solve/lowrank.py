"""Newmark/HHT-α with the constant part factored once and the mesh changes as a Woodbury update.

Same scheme as :func:`geardyn.solve.integrate.newmark` (stiffness, damping and nonlinear
forces evaluated at the Newmark predictor, one linear solve per step), but the step matrix

    A(t) = M + (1 − α)(γ Δt C(t) + β Δt² K(t))

is split into a constant sparse part A₀ (mass, linear elements, speed controls and every mesh
at its *mean* stiffness and damping), factored once with a sparse LU, and a low-rank change
U D(t) Uᵀ: U holds the mesh deflection vectors a_e (and the two DOFs of each fluid coupling,
whose linearised damping block changes with the speeds), D(t) the deviations
(1 − α)(β Δt² (k_e(t) − k̄_e) + γ Δt (c_e(t) − c̄_e)) (teeth separated, by contact loss or
within the backlash: k = c = 0; back flank: tangent k, force k (δ + b)). Each step
solves (Sherman–Morrison–Woodbury, Golub & Van Loan §2.1.4)

    x = y − Z (I + D UᵀZ)⁻¹ D Uᵀ y,   y = A₀⁻¹ b,   Z = A₀⁻¹ U (precomputed),

i.e. two sparse triangular solves with the SuperLU factors of A₀ (O(nnz)) plus an r×r solve
(r = meshes + 2 × couplings) instead of a dense O(n³) factorisation; sparse matrix–vector
products for M, K̄, C̄. The step loop is compiled (numba, the mesh, force and drive functions of
:mod:`geardyn.solve.integrate`). Mass schedules and gyroscopic terms are not supported (they
change M or C everywhere): use :func:`~geardyn.solve.integrate.newmark` for those.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import numba as nb
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from geardyn.errors import InputError
from geardyn.solve.integrate import (
    FLUID_COUPLING,
    SPEED_CONTROL,
    IntegrationResult,
    LinearSystem,
    _contact,
    _coupling_blocks,
    _drive_forces,
    _force_table,
    _mesh_state,
    _secant,
    compiled_rhs,
)


def _check(sys: LinearSystem, alpha: float, dt: float, t_end: float, t0: float) -> None:
    if sys.mass_schedule.dof.size:
        raise InputError("solver 'lowrank': a mass schedule changes M every step; use "
                         "solver 'newmark'")
    if sys.gyro_g.shape[0]:
        raise InputError("solver 'lowrank': gyroscopic terms change C every step; use "
                         "solver 'newmark'")
    if not 0.0 <= alpha <= 1.0 / 3.0:
        raise InputError(f"hht_alpha {alpha} must be in [0, 1/3]")
    if not (dt > 0 and t_end > t0):
        raise InputError(f"dt_s must be > 0 and t_end_s > t0 (got dt {dt}, t_end {t_end})")


class _Step:
    """The constant factorisation and the low-rank basis of one system and time step."""

    def __init__(self, sys: LinearSystem, dt: float, alpha: float) -> None:
        s, d = sys.springs, sys.drives
        n = sys.n
        self.beta = (1.0 + alpha) ** 2 / 4.0
        self.gamma = 0.5 + alpha
        self.alpha = alpha
        self.dt = dt
        kc = np.array(sys.K, float)
        cc = np.array(sys.C, float)
        for i in range(d.kind.shape[0]):
            if d.kind[i] == SPEED_CONTROL:
                a = d.a[i]
                kc[a, a] += d.p0[i] * d.ha[i] ** 2
                cc[a, a] += d.p1[i] * d.ha[i] ** 2
        self.kbar = np.array([s.ktab[e, : s.klen[e]].mean() for e in range(s.a.shape[0])])
        self.cbar = np.array(s.c, float)
        w = np.asarray(s.a, float).T  # n × r
        self.w = w
        self.couplings = [i for i in range(d.kind.shape[0]) if d.kind[i] == FLUID_COUPLING]
        cols = [w]
        for i in self.couplings:
            e = np.zeros((n, 2))
            e[d.a[i], 0] = 1.0
            e[d.b[i], 1] = 1.0
            cols.append(e)
        self.u = np.hstack(cols) if cols else np.zeros((n, 0))
        self.K = sp.csr_matrix(kc + (w * self.kbar) @ w.T)
        self.C = sp.csr_matrix(cc + (w * self.cbar) @ w.T)
        self.M = sp.csr_matrix(np.asarray(sys.M, float))
        a0 = self.M + (1 - alpha) * (self.gamma * dt * self.C + self.beta * dt * dt * self.K)
        self.lu = spla.splu(sp.csc_matrix(a0))
        self.z = self.lu.solve(self.u) if self.u.shape[1] else np.zeros((n, 0))
        self.uz = self.u.T @ self.z
        self.r = w.shape[1]


@nb.njit(cache=True)
def _csc_triangular(indptr, indices, data, x, lower):
    """In-place solve of a sparse triangular system stored by columns (SuperLU's L or U)."""
    n = x.shape[0]
    for jj in range(n):
        j = jj if lower else n - 1 - jj
        d = 1.0
        for p in range(indptr[j], indptr[j + 1]):
            if indices[p] == j:
                d = data[p]
        x[j] /= d
        xj = x[j]
        for p in range(indptr[j], indptr[j + 1]):
            i = indices[p]
            if (lower and i > j) or (not lower and i < j):
                x[i] -= data[p] * xj


@nb.njit(cache=True)
def _lu_solve(b, perm_r, perm_c, lp, li, lx, up, ui, ux, out):
    """A₀ x = b with Pr A₀ Pc = L U (scipy SuperLU conventions)."""
    n = b.shape[0]
    y = np.empty(n)
    for j in range(n):
        y[perm_r[j]] = b[j]
    _csc_triangular(lp, li, lx, y, True)
    _csc_triangular(up, ui, ux, y, False)
    for i in range(n):
        out[i] = y[perm_c[i]]


@nb.njit(cache=True)
def _csr_matvec(indptr, indices, data, x, out):
    for i in range(out.shape[0]):
        acc = 0.0
        for p in range(indptr[i], indptr[i + 1]):
            acc += data[p] * x[indices[p]]
        out[i] += acc


@nb.njit(cache=True)
def _products(kp, ki, kx, cp, ci, cx, w, dk, dc, ca, cb, blocks, x, vel, out):
    """out = C(t) vel + K(t) x (constant sparse part + mesh deviations + coupling blocks)."""
    out[:] = 0.0
    _csr_matvec(kp, ki, kx, x, out)
    _csr_matvec(cp, ci, cx, vel, out)
    n, r = w.shape
    for e in range(r):
        sx = 0.0
        sv = 0.0
        for i in range(n):
            sx += w[i, e] * x[i]
            sv += w[i, e] * vel[i]
        g = dk[e] * sx + dc[e] * sv
        if g != 0.0:
            for i in range(n):
                out[i] += w[i, e] * g
    for j in range(ca.shape[0]):
        va, vb = vel[ca[j]], vel[cb[j]]
        out[ca[j]] += blocks[j, 0, 0] * va + blocks[j, 0, 1] * vb
        out[cb[j]] += blocks[j, 1, 0] * va + blocks[j, 1, 1] * vb


@nb.njit(cache=True)
def _state(q, v, t, sa, sb, sx0, ktab, klen, kper, etab, elen, eper, gap, kbar, cbar,
           dkind, da, db, dha, dhb, dp0, dp1, dtx, dty, dtl, ft, fv, ca, cidx,
           kout, eout, dout, f, dk, dc, blocks, ks):
    """Mesh state, force vector and the deviations from the constant part at (q, v, t);
    ``ks`` the recorded stiffness F/δ (:func:`~geardyn.solve.integrate._secant`)."""
    _mesh_state(q, sa, sb, sx0, ktab, klen, kper, etab, elen, eper, gap, kout, eout, dout)
    _force_table(t, ft, fv, f)
    _drive_forces(t, q, v, dkind, da, db, dha, dhb, dp0, dp1, dtx, dty, dtl, f)
    n = q.shape[0]
    for e in range(sa.shape[0]):
        state, shift = _contact(dout[e], gap[e])
        lost = state == 0
        k = kout[e]
        ks[e] = _secant(k, dout[e], shift)
        dk[e] = k - kbar[e]
        dc[e] = (0.0 if lost else cbar[e]) - cbar[e]
        if k != 0.0 and eout[e] != 0.0:
            for i in range(n):
                f[i] -= k * eout[e] * sa[e, i]
    _coupling_blocks(v, cidx, da, db, dha, dhb, dp0, dp1, blocks)


@nb.njit(cache=True)
def _lowrank_kernel(kp, ki, kx, cp, ci, cx, w, kbar, cbar, z, uz, ca, cb, cidx,
                    perm_r, perm_c, lp, li, lx, up, ui, ux,
                    sa, sb, sx0, ktab, klen, kper, etab, elen, eper, gap,
                    dkind, da, db, dha, dhb, dp0, dp1, dtx, dty, dtl, ft, fv,
                    q0, v0, acc0, t0, dt, nsteps, save_every, alpha, qlim,
                    Q, V, KS, DS, TS):
    """Fixed-step HHT-α/Newmark with the Woodbury solve; returns (steps, status, bad DOF)."""
    n = q0.shape[0]
    ns = sa.shape[0]
    r = w.shape[1]
    m = z.shape[1]
    nc = ca.shape[0]
    beta = (1.0 + alpha) ** 2 / 4.0
    gamma = 0.5 + alpha
    fa = 1.0 - alpha
    kout, eout, dout = np.empty(ns), np.empty(ns), np.empty(ns)
    dk, dc, ks = np.empty(ns), np.empty(ns), np.empty(ns)
    f, prod, rhs, y = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    blocks = np.zeros((nc, 2, 2))
    dmat = np.zeros((m, m))
    uy = np.empty(m)
    q = q0.copy()
    v = v0.copy()
    acc = acc0.copy()
    _state(q, v, t0, sa, sb, sx0, ktab, klen, kper, etab, elen, eper, gap, kbar, cbar,
           dkind, da, db, dha, dhb, dp0, dp1, dtx, dty, dtl, ft, fv, ca, cidx,
           kout, eout, dout, f, dk, dc, blocks, ks)
    _products(kp, ki, kx, cp, ci, cx, w, dk, dc, ca, cb, blocks, q, v, prod)
    r0 = f - prod
    Q[0] = q
    V[0] = v
    KS[0] = ks
    DS[0] = dout
    TS[0] = t0
    isave = 1
    for step in range(1, nsteps + 1):
        t = t0 + step * dt
        qp = q + dt * v + dt * dt * (0.5 - beta) * acc
        vp = v + dt * (1.0 - gamma) * acc
        _state(qp, vp, t, sa, sb, sx0, ktab, klen, kper, etab, elen, eper, gap, kbar, cbar,
               dkind, da, db, dha, dhb, dp0, dp1, dtx, dty, dtl, ft, fv, ca, cidx,
               kout, eout, dout, f, dk, dc, blocks, ks)
        _products(kp, ki, kx, cp, ci, cx, w, dk, dc, ca, cb, blocks, qp, vp, prod)
        for i in range(n):
            rhs[i] = fa * (f[i] - prod[i]) + alpha * r0[i]
        _lu_solve(rhs, perm_r, perm_c, lp, li, lx, up, ui, ux, y)
        if m > 0:
            dmat[:, :] = 0.0
            for e in range(r):
                dmat[e, e] = fa * (beta * dt * dt * dk[e] + gamma * dt * dc[e])
            for j in range(nc):
                for a in range(2):
                    for b in range(2):
                        dmat[r + 2 * j + a, r + 2 * j + b] = fa * gamma * dt * blocks[j, a, b]
            for e in range(r):
                s_ = 0.0
                for i in range(n):
                    s_ += w[i, e] * y[i]
                uy[e] = s_
            for j in range(nc):
                uy[r + 2 * j] = y[ca[j]]
                uy[r + 2 * j + 1] = y[cb[j]]
            cap = np.eye(m) + dmat @ uz
            corr = np.linalg.solve(cap, dmat @ uy)
            y -= z @ corr
        q = qp + beta * dt * dt * y
        v = vp + gamma * dt * y
        acc = y.copy()
        _products(kp, ki, kx, cp, ci, cx, w, dk, dc, ca, cb, blocks, q, v, prod)
        r0 = f - prod
        bad = -1
        for j in range(n):
            if not math.isfinite(q[j]) or abs(q[j]) > qlim:
                bad = j
                break
        if bad >= 0:
            return step - 1, 1, bad
        if step % save_every == 0:
            Q[isave] = q
            V[isave] = v
            KS[isave] = ks
            DS[isave] = dout
            TS[isave] = t
            isave += 1
    return nsteps, 0, -1


def _csr(a: sp.spmatrix) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    a = sp.csr_matrix(a)
    return a.indptr.astype(np.int64), a.indices.astype(np.int64), a.data.astype(float)


def _csc(a: sp.spmatrix) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    a = sp.csc_matrix(a)
    return a.indptr.astype(np.int64), a.indices.astype(np.int64), a.data.astype(float)


def newmark_lowrank(
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
    chunk_steps: int = 20000,
) -> IntegrationResult:
    """Fixed-step Newmark/HHT-α of ``sys`` with the Woodbury step solve (module docstring).

    Same arguments and result as :func:`geardyn.solve.integrate.newmark`; the run is cut into
    chunks of ``chunk_steps`` for ``progress(fraction)``; a step producing non-finite values or
    |q| > ``q_limit`` stops the run with status ``diverged`` (the computed part is kept).
    """
    _check(sys, alpha, dt, t_end, t0)
    w0 = time.perf_counter()
    st = _Step(sys, dt, alpha)
    s, d = sys.springs, sys.drives
    n, ns = sys.n, s.a.shape[0]
    lu = st.lu
    fixed = (*_csr(st.K), *_csr(st.C), np.ascontiguousarray(st.w), st.kbar, st.cbar,
             np.ascontiguousarray(st.z), np.ascontiguousarray(st.uz),
             np.array([d.a[i] for i in st.couplings], np.int64),
             np.array([d.b[i] for i in st.couplings], np.int64),
             np.array(st.couplings, np.int64),
             lu.perm_r.astype(np.int64), lu.perm_c.astype(np.int64), *_csc(lu.L), *_csc(lu.U),
             s.a, s.b, s.x0, s.ktab, s.klen, s.kper, s.etab, s.elen, s.eper, s.gap(),
             d.kind, d.a, d.b, d.ha, d.hb, d.p0, d.p1, d.tx, d.ty, d.tlen,
             np.asarray(sys.force_t, float), np.ascontiguousarray(sys.force, float))
    q, v, t = np.asarray(q0, float).copy(), np.asarray(v0, float).copy(), float(t0)
    acc = compiled_rhs(sys)(t, np.concatenate([q, v]))[n:]
    nsteps = int(round((t_end - t0) / dt))
    save_every = max(1, int(save_every))
    chunk = max(save_every, (chunk_steps // save_every) * save_every)
    parts: list[tuple[np.ndarray, ...]] = []
    done, status, diag, first = 0, "ok", "", True
    while done < nsteps:
        k = min(chunk, nsteps - done)
        nsave = k // save_every + 1
        Q, V = np.zeros((nsave, n)), np.zeros((nsave, n))
        KS, DS, TS = np.zeros((nsave, ns)), np.zeros((nsave, ns)), np.zeros(nsave)
        steps, code, bad = _lowrank_kernel(*fixed, q, v, acc, t, dt, k, save_every, alpha,
                                           q_limit, Q, V, KS, DS, TS)
        kept = steps // save_every + 1
        sl = slice(0 if first else 1, kept)
        parts.append((TS[sl], Q[sl], V[sl], KS[sl], DS[sl]))
        first = False
        if code != 0:
            name = sys.dof_names[bad] if sys.dof_names else f"#{bad}"
            status = "diverged"
            diag = (f"diverged at t = {t + (steps + 1) * dt:.6g} s: DOF '{name}' became "
                    f"non-finite or exceeded {q_limit:g}; results kept up to "
                    f"t = {t + steps * dt:.6g} s")
            break
        # the next chunk restarts from the saved end state (steps multiple of save_every)
        q, v, t = Q[kept - 1].copy(), V[kept - 1].copy(), float(TS[kept - 1])
        acc = compiled_rhs(sys)(t, np.concatenate([q, v]))[n:]
        done += k
        if progress is not None:
            progress(done / nsteps)
    ts, qs, vs, ks, ds = (np.concatenate(x) for x in zip(*parts, strict=True))
    return IntegrationResult(ts, qs, vs, ks, ds, status, diag, time.perf_counter() - w0)
