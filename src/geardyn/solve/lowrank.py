"""Newmark/HHT-α with the constant part factored once and the mesh changes as a Woodbury update.

Same scheme as :func:`geardyn.solve.integrate.newmark` (stiffness, damping and nonlinear
forces evaluated at the Newmark predictor, one linear solve per step), but the step matrix

    A(t) = M + (1 − α)(γ Δt C(t) + β Δt² K(t))

is split into a constant sparse part A₀ (mass, linear elements, speed controls and every mesh
at its *mean* stiffness and damping), factored once with a sparse LU, and a low-rank change
U D(t) Uᵀ: U holds the mesh deflection vectors a_e (and the two DOFs of each fluid coupling,
whose linearised damping block changes with the speeds), D(t) the deviations
(1 − α)(β Δt² (k_e(t) − k̄_e) + γ Δt (c_e(t) − c̄_e)) (contact loss: k = c = 0). Each step
solves (Sherman–Morrison–Woodbury, Golub & Van Loan §2.1.4)

    x = y − Z (I + D UᵀZ)⁻¹ D Uᵀ y,   y = A₀⁻¹ b,   Z = A₀⁻¹ U (precomputed),

i.e. one sparse triangular solve (O(nnz)) plus an r×r solve (r = meshes + 2 × couplings)
instead of a dense O(n³) factorisation. Mass schedules and gyroscopic terms are not supported
(they change M or C everywhere): use :func:`~geardyn.solve.integrate.newmark` for those.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from geardyn.errors import InputError
from geardyn.solve.integrate import (
    FLUID_COUPLING,
    SPEED_CONTROL,
    IntegrationResult,
    LinearSystem,
    _drive_forces,
    _force_table,
    _mesh_state,
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

    def coupling_blocks(self, v: np.ndarray, d) -> list[np.ndarray]:  # noqa: ANN001
        """Linearised damping block of each fluid coupling at speeds v (as in the kernels)."""
        out = []
        for i in self.couplings:
            a, b = d.a[i], d.b[i]
            wa = v[a] * d.ha[i]
            wb = v[b] * d.hb[i] * d.p1[i]
            ga = d.p0[i] * (2.0 * wa - wb)
            gb = -d.p0[i] * wa
            hb = d.p1[i] * d.hb[i]
            out.append(np.array([[ga * d.ha[i] ** 2, gb * hb * d.ha[i]],
                                 [-hb * ga * d.ha[i], -hb * gb * hb]]))
        return out

    def products(self, x: np.ndarray, dk: np.ndarray, dc: np.ndarray,
                 blocks: list[np.ndarray], vel: np.ndarray) -> np.ndarray:
        """C(t) vel + K(t) x with the deviations dk, dc and the coupling blocks."""
        out = self.K @ x + self.C @ vel
        out += self.w @ (dk * (self.w.T @ x) + dc * (self.w.T @ vel))
        for j, blk in enumerate(blocks):
            cols = self.u[:, self.r + 2 * j: self.r + 2 * j + 2]
            out += cols @ (blk @ (cols.T @ vel))
        return out

    def solve(self, b: np.ndarray, dk: np.ndarray, dc: np.ndarray,
              blocks: list[np.ndarray]) -> np.ndarray:
        """A(t)⁻¹ b by Woodbury (module docstring)."""
        y = self.lu.solve(b)
        m = self.u.shape[1]
        if m == 0:
            return y
        f = 1.0 - self.alpha
        dmat = np.zeros((m, m))
        dmat[np.arange(self.r), np.arange(self.r)] = f * (self.beta * self.dt**2 * dk
                                                          + self.gamma * self.dt * dc)
        for j, blk in enumerate(blocks):
            sl = slice(self.r + 2 * j, self.r + 2 * j + 2)
            dmat[sl, sl] = f * self.gamma * self.dt * blk
        cap = np.eye(m) + dmat @ self.uz
        return y - self.z @ np.linalg.solve(cap, dmat @ (self.u.T @ y))


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
) -> IntegrationResult:
    """Fixed-step Newmark/HHT-α of ``sys`` with the Woodbury step solve (module docstring).

    Same arguments and result as :func:`geardyn.solve.integrate.newmark`; a step producing
    non-finite values or |q| > ``q_limit`` stops the run with status ``diverged``.
    """
    _check(sys, alpha, dt, t_end, t0)
    w0 = time.perf_counter()
    st = _Step(sys, dt, alpha)
    s, d = sys.springs, sys.drives
    n, ns = sys.n, s.a.shape[0]
    beta, gamma = st.beta, st.gamma
    ft, fv = np.asarray(sys.force_t, float), np.ascontiguousarray(sys.force, float)
    kout, eout, dout = np.empty(ns), np.empty(ns), np.empty(ns)
    f = np.empty(n)

    def state(q: np.ndarray, v: np.ndarray, t: float) -> tuple:
        _mesh_state(q, s.a, s.b, s.x0, s.ktab, s.klen, s.kper, s.etab, s.elen, s.eper,
                    s.contact_loss, kout, eout, dout)
        _force_table(t, ft, fv, f)
        _drive_forces(t, q, v, d.kind, d.a, d.b, d.ha, d.hb, d.p0, d.p1, d.tx, d.ty, d.tlen, f)
        lost = (s.contact_loss == 1) & (dout < 0.0)
        k = np.where(lost, 0.0, kout)
        c = np.where(lost, 0.0, st.cbar)
        force = f - st.w @ (k * eout)
        return force, k - st.kbar, c - st.cbar, st.coupling_blocks(v, d)

    nsteps = int(round((t_end - t0) / dt))
    save_every = max(1, int(save_every))
    nsave = nsteps // save_every + 1
    Q, V = np.zeros((nsave, n)), np.zeros((nsave, n))
    KS, DS, TS = np.zeros((nsave, ns)), np.zeros((nsave, ns)), np.zeros(nsave)
    q, v = np.asarray(q0, float).copy(), np.asarray(v0, float).copy()
    force, dk, dc, blocks = state(q, v, t0)
    r0 = force - st.products(q, dk, dc, blocks, v)
    acc = spla.spsolve(st.M.tocsc(), r0) if n > 1 else r0 / st.M.toarray()[0, 0]
    Q[0], V[0], KS[0], DS[0], TS[0] = q, v, dk + st.kbar, dout, t0
    isave, status, diag = 1, "ok", ""
    report = max(1, nsteps // 100)
    for step in range(1, nsteps + 1):
        t = t0 + step * dt
        qp = q + dt * v + dt * dt * (0.5 - beta) * acc
        vp = v + dt * (1.0 - gamma) * acc
        force, dk, dc, blocks = state(qp, vp, t)
        rhs = (1.0 - alpha) * (force - st.products(qp, dk, dc, blocks, vp)) + alpha * r0
        acc = st.solve(rhs, dk, dc, blocks)
        q = qp + beta * dt * dt * acc
        v = vp + gamma * dt * acc
        r0 = force - st.products(q, dk, dc, blocks, v)
        bad = np.flatnonzero(~np.isfinite(q) | (np.abs(q) > q_limit))
        if bad.size:
            name = sys.dof_names[bad[0]] if sys.dof_names else f"#{bad[0]}"
            status = "diverged"
            diag = (f"diverged at t = {t:.6g} s: DOF '{name}' became non-finite or exceeded "
                    f"{q_limit:g}; results kept up to t = {t - dt:.6g} s")
            break
        if step % save_every == 0:
            Q[isave], V[isave], TS[isave] = q, v, t
            KS[isave], DS[isave] = dk + st.kbar, dout
            isave += 1
        if progress is not None and step % report == 0:
            progress(step / nsteps)
    if math.isfinite(TS[isave - 1]) and progress is not None and status == "ok":
        progress(1.0)
    sl = slice(0, isave)
    return IntegrationResult(TS[sl], Q[sl], V[sl], KS[sl], DS[sl], status, diag,
                             time.perf_counter() - w0)
