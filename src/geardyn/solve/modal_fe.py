"""Exponential (exact modal) integration of the linear FE structure with the bearing, mesh and
drive forces as port forces: a time step set by accuracy, not by the stiff shaft modes.

The FE transmission M q̈ + C q̇ + K q = F_conn(q, q̇) + F_ext(t, q̇) is split at the tangent
stiffness of the static preload, K_lin = K + J (J = −∂F_conn/∂q, symmetric):

    M q̈ + C q̇ + K_lin q = g(t, q, q̇),    g = F_conn(q, q̇) + J q + F_ext(t, q̇),

an identity (no approximation). When C is diagonal in the modes Φ of (M, K_lin) (modal
damping, seed 002 §2.1; the truncated ModalDamping too), every mass-normalised modal
coordinate obeys η̈_j + 2ζ_jω_j η̇_j + ω_j² η_j = φ_jᵀ g, and g acts on the port DOFs only
(bearing and mesh nodes, drive and load, recorded DOFs). Over a step h each mode is advanced
exactly for a force quadratic in time through its values at the previous, current and next
step (a second-order hold; the exact piecewise-polynomial recurrence of Chopra, *Dynamics of
Structures*, 4th ed. 2012, §5.2, one degree higher), its coefficients from the exponential of
the augmented matrix (Van Loan, IEEE TAC 23, 1978): no stability limit from the linear
structure, however stiff its highest (axial, torsional) modes. The rigid-body modes keep the
ω² the eigen-solver gives (tiny, of either sign), so that Σ M φ ω² φᵀ M is K_lin itself.

The end-of-step force comes from one evaluation per step (a predictor-corrector in PEC mode,
as the exponential time differencing of Cox & Matthews, J. Comput. Phys. 176, 2002): predict
with the hold's end value extrapolated linearly from the last two steps, evaluate g at the
predicted state, then correct the modal state with the evaluated value (no second
evaluation). Exact on the linear structure; the error is that of the hold's representation of
the port forces, so the step follows the highest frequency they must resolve
(:func:`geardyn.models.transmission.simulate.modal_step`: by default one step per point of
the mesh-stiffness table at the top mesh frequency — the stiffness is interpolated linearly
between table points, so the mesh force has a kink at each). Records keep the record rate
exactly: a record inside a step is the exact modal state at that time under the step's hold
(bearing and mesh records interpolated linearly between the step's evaluations).

Cost per step: one evaluation of the bearing and mesh kernels (same kernels as
:mod:`geardyn.solve.explicit`), the port projections Φ_P η, Φ_P η̇ and Φ_Pᵀ g_P (3 n p for p
port DOFs: linear in the number of elements at a fixed number of bearings and meshes), and O(n)
modal updates; no n² damping product.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from geardyn.errors import InputError
from geardyn.models.transmission.kernels import bearing_forces, mesh_forces_lanes
from geardyn.solve.control import RunControl, drive_chunks
from geardyn.solve.explicit import (
    E_MODAL,
    REC_BLOCK,
    _interp,
    book_energy,
    record,
    record_buffer,
    ref_sign_speed,
    step_powers,
)

#: Records per segment of the run over which the step is constant (its speed from the
#: schedule over the segment).
SEGMENT_RECORDS = 1000
#: Largest relative off-diagonal term of Φᵀ C Φ for C to count as modal (diagonal) damping.
MODAL_TOL = 1e-9


def modal_coefficients(w2: np.ndarray, c: np.ndarray, h: float, tau: float | None = None
                       ) -> np.ndarray:
    """(2, 5, n) exact coefficients of one step h (or of the state at ``tau`` ≤ h into it)
    of η̈ + c η̇ + w2 η = p(t), p the quadratic through p₋₁, p₀, p₁ at t = −h, 0, h
    (second-order hold):
    [η₁, η̇₁] = cf[:, 0] η₀ + cf[:, 1] η̇₀ + cf[:, 2] p₋₁ + cf[:, 3] p₀ + cf[:, 4] p₁.
    With s = t/h, p = a + b s + c₂ s², a = p₀, b = (p₁ − p₋₁)/2, 2c₂ = p₁ − 2p₀ + p₋₁; the
    exponential of the augmented system (η, η̇, p, h ṗ, h² p̈) gives the response to a, b, 2c₂
    (Van Loan, IEEE TAC 23, 1978)."""
    from scipy.linalg import expm

    n = w2.size
    A = np.zeros((n, 5, 5))
    A[:, 0, 1] = 1.0
    A[:, 1, 0] = -w2
    A[:, 1, 1] = -c
    A[:, 1, 2] = 1.0
    A[:, 2, 3] = 1.0 / h
    A[:, 3, 4] = 1.0 / h
    E = expm(A * (h if tau is None else tau))  # one 5 × 5 exponential per mode (batched)
    g0, g1, g2 = E[:, :2, 2], E[:, :2, 3], E[:, :2, 4]
    out = np.zeros((n, 2, 5))
    out[:, :, 0] = E[:, :2, 0]
    out[:, :, 1] = E[:, :2, 1]
    out[:, :, 2] = -0.5 * g1 + g2
    out[:, :, 3] = g0 - 2.0 * g2
    out[:, :, 4] = 0.5 * g1 + g2
    return np.ascontiguousarray(out.transpose(1, 2, 0))


def modal_basis(M: np.ndarray, K_lin: np.ndarray, C: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """(ω², mass-normalised Φ, modal damping c_j = φ_jᵀ C φ_j, largest relative
    off-diagonal term of Φᵀ C Φ) of the symmetric pencil (M, K_lin)."""
    from scipy.linalg import eigh

    # ω² kept as computed, rigid-body modes included (tiny, of either sign): the modal
    # stiffness Σ M φ ω² φᵀ M must be K_lin itself, since g adds J q back exactly (a rigid
    # mode set to ω² = 0 leaves a force ∝ its growing rotation angle)
    w2, phi = eigh(0.5 * (K_lin + K_lin.T), M)
    D = phi.T @ C @ phi
    c = np.diag(D).copy()
    off = D - np.diag(c)
    scale = max(float(np.max(np.abs(c))), 1e-300)
    return w2, phi, c, float(np.max(np.abs(off))) / scale if off.size else 0.0


@njit(cache=True, _nrt=False, fastmath={"reassoc", "contract"})
def _ports_state(Phi, nv, eta, deta, ports, q, v):  # pragma: no cover - compiled
    """q[ports] = Φ_P η; v[ports[:nv]] = Φ_P η̇ on the first ``nv`` ports (those whose
    velocity the kernels read): dot products of the rows of ``Phi`` = Φ_P (p × n, contiguous
    rows) with the modal state, four ports per pass (one load of η, η̇ for four rows; the
    reassociated sums vectorise)."""
    p = ports.size
    n = eta.size
    i = 0
    while i + 4 <= nv:  # position and speed from the same rows
        a0 = a1 = a2 = a3 = 0.0
        b0 = b1 = b2 = b3 = 0.0
        for j in range(n):
            e = eta[j]
            d = deta[j]
            a0 += Phi[i, j] * e
            b0 += Phi[i, j] * d
            a1 += Phi[i + 1, j] * e
            b1 += Phi[i + 1, j] * d
            a2 += Phi[i + 2, j] * e
            b2 += Phi[i + 2, j] * d
            a3 += Phi[i + 3, j] * e
            b3 += Phi[i + 3, j] * d
        q[ports[i]] = a0
        q[ports[i + 1]] = a1
        q[ports[i + 2]] = a2
        q[ports[i + 3]] = a3
        v[ports[i]] = b0
        v[ports[i + 1]] = b1
        v[ports[i + 2]] = b2
        v[ports[i + 3]] = b3
        i += 4
    while i < nv:
        a0 = 0.0
        b0 = 0.0
        for j in range(n):
            a0 += Phi[i, j] * eta[j]
            b0 += Phi[i, j] * deta[j]
        q[ports[i]] = a0
        v[ports[i]] = b0
        i += 1
    while i + 4 <= p:
        a0 = a1 = a2 = a3 = 0.0
        for j in range(n):
            e = eta[j]
            a0 += Phi[i, j] * e
            a1 += Phi[i + 1, j] * e
            a2 += Phi[i + 2, j] * e
            a3 += Phi[i + 3, j] * e
        q[ports[i]] = a0
        q[ports[i + 1]] = a1
        q[ports[i + 2]] = a2
        q[ports[i + 3]] = a3
        i += 4
    while i < p:
        a0 = 0.0
        for j in range(n):
            a0 += Phi[i, j] * eta[j]
        q[ports[i]] = a0
        i += 1


@njit(cache=True, _nrt=False)
def _port_forces(q, v, f, diss, bargs, margs, bl, mf, fext, ports, jdat, jidx, jptr, Phi, pm,
                 qp):  # pragma: no cover - compiled
    """f = F_ext + F_conn(q, v) + J q on the ports (J in CSR over the port positions);
    ``pm`` = Φ_Pᵀ f_P (modal forces); diss: dissipation powers of the kernels (reset);
    ``qp``: work array (ports)."""
    for i in range(ports.size):
        f[ports[i]] = fext[ports[i]]
    diss[:] = 0.0
    bearing_forces(q, v, f, diss, *bargs, bl)
    mesh_forces_lanes(q, v, f, diss, *margs, mf)
    _project(q, f, ports, jdat, jidx, jptr, Phi, pm, qp)


@njit(cache=True, _nrt=False, fastmath={"contract"})
def _project(q, f, ports, jdat, jidx, jptr, Phi, pm, qp):  # pragma: no cover - compiled
    """f_P += J_PP q_P (J in CSR: row k lists its columns, unsigned: no negative-index
    wrap-around), then pm = Φ_Pᵀ f_P; ``qp`` receives q_P (one gather, then single
    indirections)."""
    p = ports.size
    for k in range(p):
        qp[k] = q[ports[k]]
    for k in range(p):  # a gather per row: no chain of scattered updates
        s = 0.0
        for e in range(jptr[k], jptr[k + 1]):
            s += jdat[e] * qp[jidx[e]]
        f[ports[k]] += s
    pm[:] = 0.0
    i = 0
    while i + 8 <= p:  # eight ports per pass: an eighth of the loads and stores of pm
        f0, f1, f2, f3 = f[ports[i]], f[ports[i + 1]], f[ports[i + 2]], f[ports[i + 3]]
        f4, f5, f6, f7 = f[ports[i + 4]], f[ports[i + 5]], f[ports[i + 6]], f[ports[i + 7]]
        for j in range(pm.size):
            pm[j] += (((Phi[i, j] * f0 + Phi[i + 1, j] * f1)
                       + (Phi[i + 2, j] * f2 + Phi[i + 3, j] * f3))
                      + ((Phi[i + 4, j] * f4 + Phi[i + 5, j] * f5)
                         + (Phi[i + 6, j] * f6 + Phi[i + 7, j] * f7)))
        i += 8
    while i < p:
        fi = f[ports[i]]
        for j in range(pm.size):
            pm[j] += Phi[i, j] * fi
        i += 1


@njit(cache=True, _nrt=False, fastmath={"reassoc", "contract"})
def _record_dense(rec, ir, t, td, j, cd, eta, deta, pm, p0, p1, Phr, bl0, bl1, mf0, mf1, w,
                  nd, nb, nm, ea, eb):  # pragma: no cover - compiled
    """Row ``ir`` at time t inside a step: the exact modal state at that time under the step's
    hold (coefficients ``cd[j]``) from the start state η, η̇ and the hold's values p₋₁, p₀, p₁,
    on the recorded DOFs (``Phr`` = their rows of Φ); bearing and mesh records interpolated
    linearly (weight ``w`` of the end values) between the step's evaluations. ``ea``, ``eb``:
    work arrays (n) for the modal state."""
    rec[ir, 0] = t
    rec[ir, 1] = td
    c = cd[j]
    for k in range(eta.size):  # the modal state, then its projections (no chain in memory)
        ea[k] = (c[0, 0, k] * eta[k] + c[0, 1, k] * deta[k] + c[0, 2, k] * pm[k]
                 + c[0, 3, k] * p0[k] + c[0, 4, k] * p1[k])
        eb[k] = (c[1, 0, k] * eta[k] + c[1, 1, k] * deta[k] + c[1, 2, k] * pm[k]
                 + c[1, 3, k] * p0[k] + c[1, 4, k] * p1[k])
    for r in range(nd):
        sa = 0.0
        sb = 0.0
        for k in range(eta.size):
            sa += Phr[r, k] * ea[k]
            sb += Phr[r, k] * eb[k]
        rec[ir, 2 + r] = sa
        rec[ir, 2 + nd + r] = sb
    for i in range(nb):
        for c3 in range(3):
            rec[ir, 2 + 2 * nd + c3 * nb + i] = (1.0 - w) * bl0[i, c3] + w * bl1[i, c3]
    for i in range(nm):
        rec[ir, 2 + 2 * nd + 3 * nb + i] = (1.0 - w) * mf0[i] + w * mf1[i]


@njit(cache=True, _nrt=False)
def _damping_power(cdamp, deta):  # pragma: no cover - compiled
    """Σ c_j η̇_j² (four partial sums: no serial chain)."""
    a0 = a1 = a2 = a3 = 0.0
    n = deta.size
    j = 0
    while j + 4 <= n:
        a0 += cdamp[j] * deta[j] * deta[j]
        a1 += cdamp[j + 1] * deta[j + 1] * deta[j + 1]
        a2 += cdamp[j + 2] * deta[j + 2] * deta[j + 2]
        a3 += cdamp[j + 3] * deta[j + 3] * deta[j + 3]
        j += 4
    while j < n:
        a0 += cdamp[j] * deta[j] * deta[j]
        j += 1
    return (a0 + a1) + (a2 + a3)


@njit(cache=True)
def run_chunk(
    eta, deta, p0, pprev, q, v, fext, diss, bl, mf, energy, sc, tick0, nsteps, u, m, K,
    rec, cf, cd, cdamp, nv, Phi, Phr, rec_dofs, ports, jdat, jidx, jptr, bargs, margs,
    drive_dof, load_dof, ref_dof, drive_sign, ref_sign, t_ref, w_ref, kp, ki, t0_drive,
    max_disp,
):  # pragma: no cover - compiled
    """Advance ``nsteps`` steps of ``m`` ticks from tick ``tick0``: exact modal step for the
    port forces on a quadratic hold, the end value predicted by linear extrapolation, evaluated
    once at the predicted state, then corrected (PEC). Time in ticks of ``u`` seconds (t =
    tick · u): a step is ``m`` ticks (h = m u; ``cf``, ``cd`` its coefficients), a record
    every ``K`` ticks (at a step start from the ports; inside a step by the exact
    modal state under the hold, coefficients ``cd[j]`` for tick j of the step). State: modal
    η, η̇, modal port forces ``p0`` (current) and ``pprev`` (previous step), q and v on the
    ports (at the state where the forces were evaluated), fext, diss, bl, mf, energy,
    sc = [t, ∫e, T_d, modal damping power]. Record columns as
    :func:`geardyn.solve.explicit.run_chunk`. Returns (tick reached, status 0 ok / 1 diverged
    while advancing from that tick).

    The work arrays are allocated here; the steps run in :func:`_steps` (no reference
    counting), the modal state in two buffers (start and end of a step) and the modal forces
    in three (previous, current, next), used in rotation instead of copied."""
    n = eta.size
    E = _aligned_rows(2, Phi.shape[1])
    DE = _aligned_rows(2, Phi.shape[1])
    P = _aligned_rows(3, Phi.shape[1])
    E[0, :n] = eta
    DE[0, :n] = deta
    P[0, :n] = pprev
    P[1, :n] = p0
    buf = np.empty((REC_BLOCK, rec.shape[1]))
    # per port the bound of |q| (:func:`_steps`' divergence check): 1e12, and for the
    # translations |q| ≤ max_disp as |q| < the next float above it
    lim = np.empty(ports.size)
    lt = min(np.nextafter(max_disp, np.inf), 1e12)
    for i in range(ports.size):
        lim[i] = lt if ports[i] % 6 < 3 else 1e12
    tick, code, last = _steps(
        E, DE, P, q, v, fext, diss, bl, mf, energy, sc, tick0, nsteps, u, m, K, rec, cf, cd,
        cdamp, nv, Phi, Phr, rec_dofs, ports, jdat, jidx, jptr, bargs, margs, drive_dof,
        load_dof, ref_dof, drive_sign, ref_sign, t_ref, w_ref, kp, ki, t0_drive, max_disp,
        np.zeros(q.size), np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(bl.shape),
        np.zeros(mf.size), np.zeros(energy.size), np.zeros(energy.size), np.zeros(0), buf,
        np.zeros(ports.size), lim)
    eta[:] = E[last % 2, :n]
    deta[:] = DE[last % 2, :n]
    pprev[:] = P[last % 3, :n]
    p0[:] = P[(last + 1) % 3, :n]
    return tick, code


@njit(cache=True)
def _aligned_rows(r, npad):  # pragma: no cover - compiled
    """Zeroed (r, npad) array whose rows start on 64-byte boundaries (``npad`` a multiple
    of 8): whole-cache-line vector loads."""
    raw = np.zeros(r * npad + 8)
    off = ((64 - raw.ctypes.data % 64) % 64) // 8
    return raw[off : off + r * npad].reshape((r, npad))


@njit(cache=True, _nrt=False)
def _flush(rec, r0, buf, nbuf):  # pragma: no cover - compiled
    """rec[r0 : r0 + nbuf] = buf[:nbuf] (element by element: no temporary)."""
    for r in range(nbuf):
        for c in range(buf.shape[1]):
            rec[r0 + r, c] = buf[r, c]


@njit(cache=True, _nrt=False)
def _steps(
    E, DE, P, q, v, fext, diss, bl, mf, energy, sc, tick0, nsteps, u, m, K, rec, cf, cd,
    cdamp, nv, Phi, Phr, rec_dofs, ports, jdat, jidx, jptr, bargs, margs, drive_dof, load_dof,
    ref_dof, drive_sign, ref_sign, t_ref, w_ref, kp, ki, t0_drive, max_disp,
    f, ph, ea, eb, bl0, mf0, pw0, pw1, empty, buf, qp, lim,
):  # pragma: no cover - compiled
    """The steps of :func:`run_chunk`: step s reads the modal state from ``E[s % 2]``,
    ``DE[s % 2]`` and writes the end state to the other row; the modal forces of the previous
    and current step are ``P[s % 3]``, ``P[(s + 1) % 3]``, the evaluated ones go to
    ``P[(s + 2) % 3]``. ``lim``: per port the bound of |q| (a port at or beyond it: diverged).
    The record ticks are counted (``nxt``: the next one at or after the step's start), not
    found by divisions. Returns (tick reached, status, steps taken)."""
    n = cdamp.size
    dt = m * u
    nb = bl.shape[0]
    nm = mf.size
    nd = rec_dofs.size
    r0 = 0
    nbuf = 0
    t = sc[0]
    integ = sc[1]
    td = sc[2]
    pd0 = sc[3]
    dense = False
    nxt = -(-tick0 // K) * K  # the first record tick at or after tick0
    for s in range(nsteps):
        tick = tick0 + s * m
        ia = s % 2  # start state
        ib = 1 - ia  # end state
        ip = s % 3  # modal forces: previous step
        i0 = (s + 1) % 3  # current step
        i1 = (s + 2) % 3  # evaluated at the end of this step
        eta = E[ib, :n]
        deta = DE[ib, :n]
        p1 = P[i1, :n]
        if tick == nxt:
            nxt += K
            if nbuf == 0:
                r0 = tick // K
            record(buf, nbuf, t, td, q, v, bl, mf, rec_dofs, nd, nb, nm)
            nbuf += 1
            if nbuf == REC_BLOCK:
                _flush(rec, r0, buf, nbuf)
                nbuf = 0
        # a record falls inside this step: keep the start loads for the dense output (the
        # modal start state stays in its buffer)
        dense = m > 1 and nxt <= tick + m - 1
        if dense:
            for i in range(nb):
                for c in range(3):
                    bl0[i, c] = bl[i, c]
            for i in range(nm):
                mf0[i] = mf[i]
        td0 = td
        if s == 0:
            step_powers(fext, v, diss, empty, drive_dof, load_dof, pw0)
            pw0[E_MODAL] = pd0  # the modal damping's power (its dissipation is not a kernel's)
        else:  # the previous step's end powers (same state, same arrays)
            for c in range(pw0.size):
                pw0[c] = pw1[c]
        # predictor: exact modal step, the hold's end value extrapolated linearly
        for j in range(n):
            pm = P[ip, j]
            pj = P[i0, j]
            pe = 2.0 * pj - pm
            ph[j] = pe
            e = E[ia, j]
            d = DE[ia, j]
            eta[j] = (cf[0, 0, j] * e + cf[0, 1, j] * d + cf[0, 2, j] * pm + cf[0, 3, j] * pj
                      + cf[0, 4, j] * pe)
            deta[j] = (cf[1, 0, j] * e + cf[1, 1, j] * d + cf[1, 2, j] * pm + cf[1, 3, j] * pj
                       + cf[1, 4, j] * pe)
        # the port state and the modal forces over the padded rows (zeros past the n modes):
        # loops of whole vectors, no remainder
        _ports_state(Phi, nv, E[ib], DE[ib], ports, q, v)
        t = (tick + m) * u
        wr = _interp(t, t_ref, w_ref)
        err = wr - ref_sign_speed(v, ref_dof, ref_sign)
        integ += err * dt
        td = t0_drive + kp * err + ki * integ
        fext[drive_dof] = drive_sign * td
        _port_forces(q, v, f, diss, bargs, margs, bl, mf, fext, ports, jdat, jidx, jptr, Phi,
                     P[i1], qp)
        # corrector: the hold's end value is the evaluated force
        for j in range(n):
            dp = p1[j] - ph[j]
            eta[j] += cf[0, 4, j] * dp
            deta[j] += cf[1, 4, j] * dp
        if dense:
            for jt in range(1, m):
                if tick + jt == nxt:
                    nxt += K
                    if nbuf == 0:
                        r0 = (tick + jt) // K
                    w = jt / m
                    _record_dense(buf, nbuf, (tick + jt) * u, (1.0 - w) * td0 + w * td, jt - 1,
                                  cd, E[ia, :n], DE[ia, :n], P[ip, :n], P[i0, :n], p1, Phr,
                                  bl0, bl, mf0, mf, w, nd, nb, nm, ea, eb)
                    nbuf += 1
                    if nbuf == REC_BLOCK:
                        _flush(rec, r0, buf, nbuf)
                        nbuf = 0
        pd1 = _damping_power(cdamp, deta)
        ok = math.isfinite(pd1)
        for i in range(ports.size):
            if not (abs(q[ports[i]]) < lim[i]):
                ok = False
        step_powers(fext, v, diss, empty, drive_dof, load_dof, pw1)
        pw1[E_MODAL] = pd1
        book_energy(energy, dt, pw0, pw1)
        pd0 = pd1
        sc[0] = t
        sc[1] = integ
        sc[2] = td
        sc[3] = pd1
        sc[5] += 1.0
        if not ok:
            _flush(rec, r0, buf, nbuf)
            return tick, 1, s + 1
    _flush(rec, r0, buf, nbuf)
    return tick0 + nsteps * m, 0, nsteps


class ModalSetup:
    """Modal basis, port DOFs and step coefficients of a transmission for :func:`run_loop`."""

    def __init__(self, M: np.ndarray, K: np.ndarray, K_lin: np.ndarray, C: np.ndarray,
                 ports: tuple[np.ndarray, np.ndarray], rec_dofs: np.ndarray,
                 tick_s: float) -> None:
        """``tick_s``: the time unit; steps are whole numbers of ticks, records fall on ticks
        (the state at a tick inside a step is the exact modal solution under the step's
        hold)."""
        w2, phi, c, off = modal_basis(M, K_lin, C)
        if off > MODAL_TOL:
            raise InputError(f"modal integrator: the damping is not diagonal in the modes of "
                             f"(M, K_lin) (off-diagonal {off:.2g} of the diagonal > "
                             f"{MODAL_TOL:g}): use integrator = 'newmark' or 'explicit'")
        self.off_diagonal = off
        self.w2 = w2
        self.cdamp = c
        self.phi = phi
        vel, rest = (np.asarray(x, np.int64) for x in ports)
        # the recorded DOFs are read from the ports (position and speed)
        rd = np.asarray(rec_dofs, np.int64)
        vel = np.union1d(vel, rd)
        rest = np.setdiff1d(rest, vel)
        self.ports = np.concatenate([vel, rest])
        self.nv = int(vel.size)
        n = M.shape[0]
        J = 0.5 * (K_lin + K_lin.T) - K
        Jpp = J[np.ix_(self.ports, self.ports)]
        outside = np.setdiff1d(np.arange(n), self.ports)
        self.leak = float(np.max(np.abs(J[outside, :]), initial=0.0))
        r, cc = np.nonzero(Jpp)  # CSR of Jpp: row k lists its columns
        ptr = np.zeros(self.ports.size + 1, np.int64)
        np.add.at(ptr, r + 1, 1)
        self.J = (Jpp[r, cc].copy(), cc.astype(np.uint64), np.cumsum(ptr).astype(np.int64))
        # rows of Φ_P and Φ_R padded to a multiple of 8 modes and 64-byte aligned: the
        # projections' vector loads never straddle cache lines (the loops run over the n modes)
        self.Phi = aligned_rows(phi[self.ports, :])
        self.rec_dofs = rd
        self.Phr = aligned_rows(phi[rd, :])
        self.tick = float(tick_s)
        self.M = M
        self._coefficients: dict[int, tuple[np.ndarray, np.ndarray]] = {}

    def coefficients(self, m: int) -> tuple[np.ndarray, np.ndarray]:
        """(step coefficients, coefficients at ticks 1 … m − 1 inside it) of a step of ``m``
        ticks (:func:`modal_coefficients`; cached)."""
        if m not in self._coefficients:
            h = m * self.tick
            cf = modal_coefficients(self.w2, self.cdamp, h)
            cd = np.array([modal_coefficients(self.w2, self.cdamp, h, j * self.tick)
                           for j in range(1, max(2, m))])
            self._coefficients[m] = (cf, cd)
        return self._coefficients[m]


def aligned_rows(a: np.ndarray) -> np.ndarray:
    """``a`` (r × n) in a zero-padded (r × 8⌈n/8⌉) array whose rows start on 64-byte
    boundaries."""
    r, n = a.shape
    npad = -(-n // 8) * 8
    raw = np.zeros(r * npad + 8)
    off = (-raw.ctypes.data % 64) // 8
    out = raw[off : off + r * npad].reshape(r, npad)
    out[:, :n] = a
    return out


def port_dofs(model, extra: list[int]) -> tuple[np.ndarray, np.ndarray]:  # noqa: ANN001
    """(ports whose velocity the kernels read, the other ports): the global DOFs read or
    loaded by the bearing kernel (bearing nodes: x, y, z; θz with its speed) and the mesh
    kernel (mesh nodes: all six, with speeds), and ``extra`` (drive, load, reference θz, with
    speeds)."""
    vel: set[int] = set(int(x) for x in extra)
    pos: set[int] = set()
    for nd in model.bearings.node:
        pos.update(6 * int(nd) + k for k in (0, 1, 2))
        vel.add(6 * int(nd) + 5)
    for a, b in zip(model.meshes.na, model.meshes.nb, strict=True):
        vel.update(6 * int(a) + k for k in range(6))
        vel.update(6 * int(b) + k for k in range(6))
    return np.array(sorted(vel), np.int64), np.array(sorted(pos - vel), np.int64)


def _schedule_key(schedule, n_ticks: int, seg: int, u: float) -> int:  # noqa: ANN001
    """Σ (i + 1) m_i over the segments i of the run (m_i: the schedule's step in ticks)."""
    return int(sum((i + 1) * max(1, int(schedule(s0 * u, min(s0 + seg, n_ticks) * u)))
                   for i, s0 in enumerate(range(0, n_ticks, seg))))


STATE = ("eta", "deta", "p0", "pprev", "q", "v", "fext", "diss", "bl", "mf", "energy", "sc")


def run_loop(
    setup: ModalSetup, q, v, n_ticks, rec_ticks, schedule, bargs, margs,  # noqa: ANN001
    drive_dof, load_dof, ref_dof, drive_sign, load_sign, ref_sign, load_torque,  # noqa: ANN001
    t_ref, w_ref, kp, ki, t0_drive, integ0, max_disp, rec_dofs,  # noqa: ANN001
    control: RunControl | None = None,
) -> tuple:
    """Modal counterpart of :func:`geardyn.solve.explicit.run_loop` (no gyroscopic terms or
    applied loads) over ``n_ticks`` ticks of ``setup.tick`` s, a record every ``rec_ticks``
    ticks; ``schedule(t0, t1)`` gives the step (in ticks) for the part of the run between t0
    and t1 [s] (whole steps per chunk; the last step ends on ``n_ticks``). Returns (records,
    energy, steps done, status, q, v, ∫e, time reached [s])."""
    u, K = setup.tick, int(rec_ticks)
    phi, M = setup.phi, setup.M
    ctl = control or RunControl()
    n = q.size
    nb = bargs[0].size
    nm = margs[0].size
    nd = rec_dofs.size
    nrec = n_ticks // K + 1
    rec = record_buffer(nrec, nd, nb, nm)
    st = {"eta": phi.T @ (M @ np.asarray(q, float)), "deta": phi.T @ (M @ np.asarray(v, float)),
          "p0": np.zeros(n), "pprev": np.zeros(n), "q": np.array(q, float),
          "v": np.array(v, float), "fext": np.zeros(n), "diss": np.zeros(5),
          "bl": np.zeros((nb, 3)), "mf": np.zeros(nm), "energy": np.zeros(8),
          "sc": np.zeros(6)}  # t, ∫e, T_d, damping power, last step (ticks), steps
    run_id = {"scheme": "modal-fe", "nsteps": int(n_ticks), "dt": float(u),
              "rec_every": int(K), "n": int(n), "ncols": int(rec.shape[1]),
              # the model: its modal damping and frequencies (another mass or damping is
              # another run)
              "modal_damping": float(np.sum(setup.cdamp)), "modal_stiffness": float(
                  np.sum(setup.w2)),
              # the step schedule (a speed-following step with another bound is another run)
              "schedule": _schedule_key(schedule, n_ticks, SEGMENT_RECORDS * K, u)}

    def recorded(ticks: int) -> int:  # rows once the ticks before ``ticks`` are done
        return (ticks + K - 1) // K

    if ctl.resume is not None:
        from geardyn.solve.control import check_same_run

        check_same_run(ctl.resume, run_id)
        for k in STATE:
            st[k][...] = ctl.resume[k]
        done = int(ctl.resume["step"])
        rec[: recorded(done)] = ctl.resume["rec"]
    else:
        err = float(np.interp(0.0, t_ref, w_ref)) - ref_sign * v[ref_dof]
        td = t0_drive + kp * err + ki * integ0
        fext = st["fext"]
        fext[drive_dof] = drive_sign * td
        fext[load_dof] = -load_sign * load_torque
        f = np.zeros(n)
        _port_forces(st["q"], st["v"], f, st["diss"], bargs, margs, st["bl"], st["mf"], fext,
                     setup.ports, *setup.J, setup.Phi, st["p0"], np.zeros(setup.ports.size))
        st["pprev"][:] = st["p0"]
        st["sc"][:] = (0.0, integ0, td, _damping_power(setup.cdamp, st["deta"]), 0.0, 0.0)
        done = 0

    def state(ticks: int) -> dict:
        return {**run_id, "step": ticks, **st, "rec": rec[: recorded(ticks)]}

    seg = SEGMENT_RECORDS * K

    def advance(start: int, stop: int) -> tuple[int, int]:
        # the step is a function of the tick alone (the schedule over its segment of
        # SEGMENT_RECORDS records), so the steps do not depend on where chunks end;
        # consecutive segments with the same step run as one compiled call (the same steps)
        tick = start
        while tick < stop and tick < n_ticks:
            m, steps, t = 0, 0, tick
            while t < stop and t < n_ticks:
                s0 = (t // seg) * seg
                ms = max(1, int(schedule(s0 * u, min(s0 + seg, n_ticks) * u)))
                ms = min(ms, n_ticks - t)
                if steps and ms != m:
                    break
                k = max(1, -(-(min(s0 + seg, stop, n_ticks) - t) // ms))
                k = min(k, (n_ticks - t) // ms)
                m, steps, t = ms, steps + k, t + k * ms
            if m != int(st["sc"][4]) and st["sc"][4] > 0:
                # the hold's previous value at −h of the new step: on the previous step's line
                p0, pprev = st["p0"], st["pprev"]
                pprev[:] = p0 + (pprev - p0) * (m / st["sc"][4])
            st["sc"][4] = m
            cf, cd = setup.coefficients(m)
            tick, code = run_chunk(
                st["eta"], st["deta"], st["p0"], st["pprev"], st["q"], st["v"], st["fext"],
                st["diss"], st["bl"], st["mf"], st["energy"], st["sc"], tick, steps, u, m, K,
                rec, cf, cd, setup.cdamp, setup.nv, setup.Phi, setup.Phr,
                setup.rec_dofs, setup.ports, *setup.J, bargs, margs, drive_dof, load_dof,
                ref_dof, drive_sign, ref_sign, t_ref, w_ref, kp, ki, t0_drive, max_disp)
            if code != 0:
                return tick, code
        return tick, 0

    done, status = drive_chunks(ctl, done, n_ticks, advance, state)
    if status == 0 and n_ticks % K == 0:
        sc = st["sc"]
        record(rec, n_ticks // K, sc[0], sc[2], st["q"], st["v"], st["bl"], st["mf"],
               setup.rec_dofs, nd, nb, nm)
    if status == 0:
        rows = n_ticks // K + 1
    elif status == 1:  # the failed step's records were written
        rows = min(nrec, recorded(done + int(st["sc"][4])))
    else:
        rows = recorded(done)
    return (rec[:rows], st["energy"], int(st["sc"][5]), status, phi @ st["eta"],
            phi @ st["deta"], float(st["sc"][1]), float(st["sc"][0]))
