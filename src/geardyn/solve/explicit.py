"""Explicit time integration of the FE transmission (seed 002 eq 3) with a speed-tracking drive.

The implicit Newmark/HHT-α integrators of the lumped-parameter models are in
:mod:`geardyn.solve.integrate`; this module is the explicit one (issue 12: one ``solve``
package; :mod:`geardyn.models.transmission.integrate` re-exports it).

Explicit velocity-Verlet (central-difference) scheme compiled with numba: the contact forces
are strongly nonlinear but cheap, the model is small (≈100 DOF), so an explicit step below
the stability limit 2/ω_max is the fastest robust choice (no Jacobians of the contact laws).
Velocity-dependent forces (damping, friction, squeeze film, controller) use a predicted
end-of-step velocity. The loop runs in compiled code, in chunks that return to Python
(progress, Ctrl-C, checkpoints: :class:`geardyn.solve.control.RunControl`); the whole loop
state is carried between chunks, so the result does not depend on the chunking. Outputs are
decimated.

Cost per step (issue 12): K q in CSC over its non-zeros, M⁻¹ f as a CSC or (lumped mass)
diagonal product, C v either the dense modal damping matrix (BLAS) or, with a cutoff,
:class:`ModalDamping` (sparse stiffness-proportional part + rank-r modal part, no n² term);
records go through a small block buffer into an array on 4 kB pages (:func:`record_array`).

Drive: T_d = T_0 + K_p e + K_i ∫e, e = ω_ref(t) − ω_ref_node, on the drive node; the load
torque is constant and resists the rotation (seed 002 §3.2: operating point reached by the
torque laws). Energy bookkeeping integrates input, output, the work of the applied loads and
each dissipation channel.

Gyroscopic terms (optional): M q̈ + (C + Σ_s Ω_s(t) G_s) q̇ + K q = F, G_s the gyroscopic
matrix of shaft s per rad/s (Timoshenko elements + wheels, :mod:`geardyn.elements`), Ω_s(t)
the current mean spin θ̇z of the shaft's nodes (Lalanne & Ferraris, *Rotordynamics
Prediction in Engineering*, 1998, ch. 1-2, assembled). G_s is skew-symmetric: the terms do
no work.

Applied loads (optional): unbalances m e at a node, F = m e (θ̇² cos θ + θ̈ sin θ,
θ̇² sin θ − θ̈ cos θ) with θ = θz + φ the node's rotation (the force of the rotating point
mass on the rotor, its own inertia neglected; Lalanne & Ferraris 1998 ch. 1), and external
forces/torques F = F₀ + A cos(2π f t + n θz,ref + φ) on any DOF (time law f, angle law n).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from geardyn.errors import InputError
from geardyn.models.transmission.kernels import bearing_forces, mesh_forces
from geardyn.solve.control import RunControl, check_record_size, drive_chunks

# channels of the energy accumulator
E_IN, E_OUT, E_VISC, E_ROLL, E_FRIC, E_SQZ, E_MODAL, E_EXT = range(8)


def no_gyroscopic() -> tuple:
    """Gyroscopic arguments of the loops without gyroscopic terms."""
    return (np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0), np.zeros(0, np.int64),
            np.zeros(1, np.int64), np.zeros(0, np.int64), np.zeros(0))


def gyroscopic_args(G: dict[str, np.ndarray], spin_dofs: dict[str, list[int]]) -> tuple:
    """Sparse (COO) gyroscopic matrices of the shafts for :func:`gyroscopic_forces`:
    (rows, cols, values per rad/s, shaft index per entry, CSR offsets of each shaft's θz DOFs,
    the θz DOFs, work array of the shaft speeds)."""
    rows, cols, vals, sh, ptr, dofs = [], [], [], [], [0], []
    for i, (name, g) in enumerate(G.items()):
        r, c = np.nonzero(g)
        rows.append(r)
        cols.append(c)
        vals.append(g[r, c])
        sh.append(np.full(r.size, i, np.int64))
        dofs.extend(spin_dofs[name])
        ptr.append(len(dofs))
    if not rows:
        return no_gyroscopic()
    return (np.concatenate(rows).astype(np.int64), np.concatenate(cols).astype(np.int64),
            np.concatenate(vals).astype(float), np.concatenate(sh), np.array(ptr, np.int64),
            np.array(dofs, np.int64), np.zeros(len(G)))


def no_loads() -> tuple:
    """Applied-load arguments of the loops without unbalances, external loads or
    speed-dependent supports."""
    z, zi = np.zeros(0), np.zeros(0, np.int64)
    return (zi, z, z, zi, z, z, z, z, zi, z) + no_support_tables()


def no_support_tables() -> tuple:
    """Empty speed-dependent support arguments of :func:`applied_loads`."""
    return (np.zeros((0, 4), np.int64), np.zeros(0, np.int64), np.zeros((0, 2)),
            np.zeros((0, 2, 4, 4)), np.zeros((0, 2, 4, 4)))


@njit(cache=True)
def gyroscopic_forces(v, f, g_row, g_col, g_val, g_sh, sh_ptr, sh_dofs, om
                      ):  # pragma: no cover - compiled
    """f −= Σ_s Ω_s G_s v with Ω_s the mean θ̇z of shaft s's nodes (``om`` receives Ω_s)."""
    for s in range(sh_ptr.size - 1):
        w = 0.0
        for j in range(sh_ptr[s], sh_ptr[s + 1]):
            w += v[sh_dofs[j]]
        om[s] = w / (sh_ptr[s + 1] - sh_ptr[s])
    for e in range(g_row.size):
        f[g_row[e]] -= om[g_sh[e]] * g_val[e] * v[g_col[e]]


@njit(cache=True)
def applied_loads(q, v, a, t, fx, u_dof, u_me, u_ph, x_dof, x_f0, x_amp, x_freq, x_ord,
                  x_angdof, x_ph, s_dofs, s_wdof, s_rpm, s_dK, s_dC
                  ):  # pragma: no cover - compiled
    """Unbalance forces (``u_dof``: x DOF of the node; θz is ``u_dof`` + 5) and external loads
    at time ``t`` into ``fx`` (overwritten); speed-dependent supports: −ΔK(n) u − ΔC(n) u̇ on
    their DOFs ``s_dofs`` (x, y, θx, θy), ΔK, ΔC the change of the tabulated 4×4 coefficients
    from the values in K and C, interpolated linearly in the shaft speed n = |θ̇z| (rpm) of
    ``s_wdof`` over ``s_rpm`` (held outside the table)."""
    fx[:] = 0.0
    for i in range(s_wdof.size):
        rpm = abs(v[s_wdof[i]]) * 30.0 / math.pi
        nt = s_rpm.shape[1]
        k = 0
        while k < nt - 2 and rpm > s_rpm[i, k + 1]:
            k += 1
        w = (rpm - s_rpm[i, k]) / (s_rpm[i, k + 1] - s_rpm[i, k])
        w = min(1.0, max(0.0, w))
        for r in range(4):
            acc = 0.0
            for c in range(4):
                d = s_dofs[i, c]
                acc += ((1.0 - w) * s_dK[i, k, r, c] + w * s_dK[i, k + 1, r, c]) * q[d]
                acc += ((1.0 - w) * s_dC[i, k, r, c] + w * s_dC[i, k + 1, r, c]) * v[d]
            fx[s_dofs[i, r]] -= acc
    for i in range(u_dof.size):
        d = u_dof[i]
        th = q[d + 5] + u_ph[i]
        w = v[d + 5]
        al = a[d + 5]
        c = math.cos(th)
        s = math.sin(th)
        fx[d] += u_me[i] * (w * w * c + al * s)
        fx[d + 1] += u_me[i] * (w * w * s - al * c)
    for i in range(x_dof.size):
        ph = 2.0 * math.pi * x_freq[i] * t + x_ph[i]
        if x_ord[i] != 0.0:
            ph += x_ord[i] * q[x_angdof[i]]
        fx[x_dof[i]] += x_f0[i] + x_amp[i] * math.cos(ph)


def csr(A: np.ndarray) -> tuple:
    """(data, column indices, row pointers) of the non-zeros of dense ``A`` (row-major): K and
    M⁻¹ of the transmission are block-diagonal per shaft (shafts couple only through bearings
    and meshes), so the loop's products cost O(nnz) instead of O(n²)."""
    A = np.asarray(A, dtype=float)
    rows, cols = np.nonzero(A)
    ptr = np.zeros(A.shape[0] + 1, np.int64)
    np.add.at(ptr, rows + 1, 1)
    return (A[rows, cols].copy(), cols.astype(np.int64), np.cumsum(ptr).astype(np.int64))


class ModalDamping(NamedTuple):
    """Modal damping without the dense n² product (:func:`modal_damping`):
    C = β K_lin + B diag(w) Bᵀ, B = M Φ_r over the modes Φ_r below the cutoff."""

    stiffness: np.ndarray
    """β K_lin (n × n, sparse like K_lin), β = 2ζ/ω_c."""
    basis: np.ndarray
    """B = M Φ_r (n × r), mass-normalised modes below the cutoff."""
    weights: np.ndarray
    """w_i = 2ζω_i − βω_i² of the retained modes (r)."""
    ratios: np.ndarray
    """Damping ratio of every mode of (M, K_lin), ascending frequency (n)."""
    frequencies_hz: np.ndarray
    """Undamped frequencies of (M, K_lin) [Hz] (n)."""


def modal_damping(M: np.ndarray, K_lin: np.ndarray, zeta: float, cutoff_hz: float
                  ) -> ModalDamping:
    """Modal damping ratio ``zeta`` on every elastic mode of (M, K_lin) below ``cutoff_hz``
    (exactly, as C = M Φ diag(2ζω) Φᵀ M of seed 002 §2.1 does), and the stiffness-proportional
    ratio ζ ω/ω_c (≥ ζ) above it, rigid modes (< 0.5 Hz) undamped.

    C = β K_lin + M Φ_r diag(2ζω_r − βω_r²) Φ_rᵀ M with β = 2ζ/ω_c: Φ diagonalises both
    terms, so mode i gets 2ζ_iω_i = βω_i² (+ 2ζω_i − βω_i² if retained). The product C v costs
    nnz(K_lin) + 2 n r instead of n² (r = modes below the cutoff)."""
    from scipy.linalg import eigh

    if not (math.isfinite(cutoff_hz) and cutoff_hz > 0):
        raise InputError(f"modal damping cutoff must be a finite frequency > 0 Hz (got "
                         f"{cutoff_hz})")
    w2, phi = eigh(K_lin, M)
    w = np.sqrt(np.clip(w2, 0.0, None))
    f = w / (2 * math.pi)
    wc = 2 * math.pi * cutoff_hz
    beta = 2.0 * zeta / wc
    keep = (f >= 0.5) & (f < cutoff_hz)
    basis = np.ascontiguousarray(M @ phi[:, keep])
    weights = 2.0 * zeta * w[keep] - beta * w[keep] ** 2
    ratios = np.where(f < 0.5, 0.0, np.where(keep, zeta, 0.5 * beta * w))
    S = beta * 0.5 * (K_lin + K_lin.T)
    return ModalDamping(S, basis, weights, ratios, f)


def linear_args(K: np.ndarray, C: np.ndarray | ModalDamping) -> tuple[tuple, tuple]:
    """Loop arguments of the linear forces K q + C v (:func:`_linear_forces`): the union of
    the sparsity patterns in CSC (row indices, column pointers, K values, values of C's sparse
    part, empty without one; K and that part are symmetric, so CSC = CSR), and (Bᵀ, B, w,
    work, dense C, C v, work). ``C`` a dense matrix: the plain product (empty low-rank part);
    a :class:`ModalDamping`: sparse + low rank, no dense C."""
    K = np.asarray(K, dtype=float)
    n = K.shape[0]
    # non-symmetric K or C (cross-coupled supports): the row passes below read columns, so
    # they get the transposes (symmetric matrices are passed as they are: the same bits)
    if isinstance(C, ModalDamping):
        S = np.asarray(C.stiffness, dtype=float)
        if not (np.array_equal(K, K.T) and np.array_equal(S, S.T)):
            K, S = K.T.copy(), S.T.copy()
        rows, cols = np.nonzero((K != 0.0) | (S != 0.0) | (K.T != 0.0) | (S.T != 0.0))
        bdat = S[rows, cols].copy()
        B = np.ascontiguousarray(C.basis, dtype=float)
        BT, w, Cd = np.ascontiguousarray(B.T), np.asarray(C.weights, float), np.zeros((0, 0))
    else:
        rows, cols = np.nonzero(K)
        bdat = np.zeros(0)
        B, BT, w = np.zeros((n, 0)), np.zeros((0, n)), np.zeros(0)
        C = np.asarray(C, dtype=float)
        Cd = np.ascontiguousarray(C if np.array_equal(C, C.T) else C.T)
    # CSC: column j lists the rows i of its entries (np.nonzero is row-major: sort by column)
    o = np.lexsort((rows, cols))
    rows, cols = rows[o], cols[o]
    bdat = bdat[o] if bdat.size else bdat
    ptr = np.zeros(n + 1, np.int64)
    np.add.at(ptr, cols + 1, 1)
    return ((rows.astype(np.int64), np.cumsum(ptr).astype(np.int64), K[rows, cols].copy(),
             bdat), (BT, B, w, np.zeros(w.size), Cd, np.zeros(n), np.zeros(n)))


def csc(A: np.ndarray) -> tuple:
    """(data, row indices, column pointers) of the non-zeros of dense ``A``, for
    :func:`_csc_matvec`; a diagonal ``A`` (lumped mass) as (diagonal, empty, empty)."""
    A = np.asarray(A, dtype=float)
    if np.count_nonzero(A - np.diag(np.diag(A))) == 0:
        return np.diag(A).copy(), np.zeros(0, np.int64), np.zeros(0, np.int64)
    return csr(A.T)


@njit(cache=True)
def _csc_matvec(data, idx, ptr, x, out):  # pragma: no cover - compiled
    """out += A x (A in CSC: column form, no serial reduction chain; empty pointers: A is
    the diagonal ``data``)."""
    if ptr.size == 0:
        for j in range(data.size):
            out[j] += data[j] * x[j]
        return
    for j in range(ptr.size - 1):
        xj = x[j]
        for p in range(ptr[j], ptr[j + 1]):
            out[idx[p]] += data[p] * xj


@njit(cache=True)
def _dot(x, y):  # pragma: no cover - compiled
    """Σ x_i y_i in index order (0 for empty x; no BLAS: see :func:`_linear_forces`)."""
    acc = 0.0
    for i in range(x.size):
        acc += x[i] * y[i]
    return acc


@njit(cache=True)
def _linear_forces(q, v, f, cw, idx, ptr, kdat, bdat, BT, B, w, y, Cd, tmp
                   ):  # pragma: no cover - compiled
    """f −= K q + C v and ``cw`` = C v (see :func:`linear_args`): one pass over K (CSC), or
    over the common sparsity pattern of K and the sparse part of C (both symmetric), then the
    low-rank modal part B diag(w) Bᵀ v, or the dense C of the plain modal damping."""
    n = q.size
    if bdat.size == 0:  # K only, column form (axpy): no serial reduction chain
        for j in range(n):
            qj = q[j]
            for p in range(ptr[j], ptr[j + 1]):
                f[idx[p]] -= kdat[p] * qj
    else:
        for i in range(n):  # K and C's sparse part on their common pattern (symmetric)
            ak = 0.0
            ac = 0.0
            for p in range(ptr[i], ptr[i + 1]):
                c = idx[p]
                ak += kdat[p] * q[c]
                ac += bdat[p] * v[c]
            f[i] -= ak
            cw[i] = ac
    # matrix-vector products as plain loops, not BLAS: a threaded BLAS splits them by its
    # thread count, and a run must give the same bits whatever the BLAS threads (resume,
    # interrupts, a sweep worker against the driver). Written as axpy passes over contiguous
    # rows (no reduction chain: vectorised without reordering any sum); C is symmetric.
    r = w.size
    if r > 0:  # low-rank modal part B diag(w) Bᵀ v; B is n × r, BT its transpose
        for k in range(r):
            y[k] = 0.0
        for j in range(n):
            vj = v[j]
            for k in range(r):
                y[k] += B[j, k] * vj
        for k in range(r):
            yk = y[k] * w[k]
            for i in range(n):
                cw[i] += BT[k, i] * yk
    if Cd.shape[0] > 0:  # four rows per pass: a quarter of the loads and stores of cw
        for i in range(n):
            cw[i] = 0.0
        j = 0
        while j + 4 <= n:
            v0, v1, v2, v3 = v[j], v[j + 1], v[j + 2], v[j + 3]
            for i in range(n):
                cw[i] += (Cd[j, i] * v0 + Cd[j + 1, i] * v1) + (Cd[j + 2, i] * v2
                                                                  + Cd[j + 3, i] * v3)
            j += 4
        while j < n:
            vj = v[j]
            for i in range(n):
                cw[i] += Cd[j, i] * vj
            j += 1
    for i in range(n):
        f[i] -= cw[i]


@njit(cache=True)
def _accel(q, v, t, Minv, K, C, fext, f, diss, bargs, margs, bl, mf, gargs, fx, a, hdt
           ):  # pragma: no cover
    """``a`` = M⁻¹ (F_ext + F_connecting − K q − C v − Σ Ω G v_g); ``Minv`` in CSC, ``K`` and
    ``C`` as built by :func:`linear_args`; on entry ``a`` holds the previous acceleration.

    Gyroscopic terms: v_g is the end-of-step velocity v + hdt (a_new − a_old) (``v`` the
    predicted one, ``hdt`` = dt/2), solved by fixed-point iteration (contraction ≈ Ω dt ≪ 1),
    i.e. the skew term treated implicitly. With the predicted velocity alone the explicit step
    is unstable for the undamped high modes near the stability limit (growth ≈ Ω dt (ω dt)²/4
    per step); the implicit treatment keeps the scheme's amplification at 1."""
    f[:] = fext
    if fx.size > 0:
        f += fx
    bearing_forces(q, v, f, diss, *bargs, bl)
    mesh_forces(q, v, f, diss, *margs, mf)
    cw = C[5]
    _linear_forces(q, v, f, cw, *K, *C[:5], C[6])
    diss[4] += _dot(v, cw)
    if gargs[0].size == 0:
        a[:] = 0.0
        _csc_matvec(Minv[0], Minv[1], Minv[2], f, a)
        return
    n = f.size
    a_old = a.copy()
    vg = v.copy()
    fg = np.empty(n)
    for _ in range(20):
        fg[:] = f
        gyroscopic_forces(vg, fg, *gargs)
        a[:] = 0.0
        _csc_matvec(Minv[0], Minv[1], Minv[2], fg, a)
        dmax = 0.0
        vmax = 0.0
        for j in range(n):
            vn = v[j] + hdt * (a[j] - a_old[j])
            dmax = max(dmax, abs(vn - vg[j]))
            vmax = max(vmax, abs(vn))
            vg[j] = vn
        if dmax <= 1e-13 * vmax:
            break


@njit(cache=True, _nrt=False)
def step_powers(fext, v, diss, fx, drive_dof, load_dof, pw):  # pragma: no cover - compiled
    """The powers of the energy channels at one instant into ``pw`` (channels ``E_IN`` …
    ``E_EXT``): input and output at the drive and load, the dissipation powers ``diss``, the
    applied loads' power F·v (0 without loads). One piece of code for every FE loop."""
    pw[E_IN] = fext[drive_dof] * v[drive_dof]
    pw[E_OUT] = -fext[load_dof] * v[load_dof]
    for c in range(5):
        pw[2 + c] = diss[c]
    pw[E_EXT] = _dot(fx, v)


@njit(cache=True, _nrt=False)
def book_energy(energy, dt, pw0, pw1):  # pragma: no cover - compiled
    """energy += trapezoid of each channel's power over a step dt (start ``pw0``, end
    ``pw1``, :func:`step_powers`)."""
    for k in range(energy.size):
        energy[k] += 0.5 * dt * (pw0[k] + pw1[k])


@njit(cache=True)
def start_loop(
    q, v, Minv, K, C, bargs, margs, drive_dof, load_dof, ref_dof, drive_sign, load_sign,
    ref_sign, load_torque, t_ref, w_ref, kp, ki, t0_drive, integ0,
    a, fext, diss, bl, mf, sc, gargs, xargs, fx,
):  # pragma: no cover - compiled
    """Initial state of the loop at t = 0: drive torque, acceleration ``a``, dissipation
    powers ``diss``, bearing loads ``bl``, mesh forces ``mf``, applied loads ``fx`` (empty
    without loads; θ̈ taken 0 at the start); ``sc`` = [t, ∫e, T_d]."""
    n = q.size
    f = np.zeros(n)
    t = 0.0
    wr = _interp(t, t_ref, w_ref)
    err = wr - ref_sign_speed(v, ref_dof, ref_sign)
    td = t0_drive + kp * err + ki * integ0
    fext[:] = 0.0
    fext[drive_dof] = drive_sign * td
    fext[load_dof] = -load_sign * load_torque
    diss[:] = 0.0
    if fx.size > 0:
        applied_loads(q, v, a, t, fx, *xargs)
    _accel(q, v, t, Minv, K, C, fext, f, diss, bargs, margs, bl, mf, gargs, fx, a, 0.0)
    sc[0] = t
    sc[1] = integ0
    sc[2] = td


#: rows of the record buffer of :func:`run_chunk` (64 kB for 32 columns)
REC_BLOCK = 256


@njit(cache=True)
def run_chunk(
    q, v, a, fext, diss, bl, mf, energy, sc, step0, step1, dt, rec_every, rec,
    Minv, K, C, bargs, margs, drive_dof, load_dof, ref_dof, drive_sign, ref_sign,
    t_ref, w_ref, kp, ki, t0_drive, max_disp, rec_dofs, gargs, xargs, fx,
):  # pragma: no cover - compiled
    """Advance global steps ``step0`` → ``step1`` (velocity Verlet); the loop state (q, v, a,
    fext, diss, bl, mf, energy, sc = [t, ∫e, T_d], fx) is updated in place so that chunks
    continue exactly. Global step s is recorded (before advancing it) in row s // rec_every of
    ``rec`` when s is a multiple of ``rec_every``. Returns (last step reached, status): status 0 ok,
    1 diverged while advancing from that step.

    Record columns: t, drive torque, angles and speeds of ``rec_dofs``, per bearing Σ Q_j,
    then housing force x, then y (n_bearings each), mesh forces."""
    n = q.size
    nb = bl.shape[0]
    nm = mf.size
    nd = rec_dofs.size
    f = np.zeros(n)
    vh = np.zeros(n)
    vp = np.zeros(n)
    pw0 = np.zeros(energy.size)
    pw1 = np.zeros(energy.size)
    # records go through a small buffer copied in blocks: rows written one by one straight
    # into the large record array cost ≈ 1 µs per step in cache misses
    buf = np.empty((REC_BLOCK, rec.shape[1]))
    r0 = 0
    nbuf = 0
    t = sc[0]
    integ = sc[1]
    td = sc[2]
    for step in range(step0, step1):
        if step % rec_every == 0:
            if nbuf == 0:
                r0 = step // rec_every
            record(buf, nbuf, t, td, q, v, bl, mf, rec_dofs, nd, nb, nm)
            nbuf += 1
            if nbuf == REC_BLOCK:
                rec[r0 : r0 + nbuf, :] = buf
                nbuf = 0
        step_powers(fext, v, diss, fx, drive_dof, load_dof, pw0)  # before the step
        for j in range(n):
            vh[j] = v[j] + 0.5 * dt * a[j]
            q[j] += dt * vh[j]
            vp[j] = vh[j] + 0.5 * dt * a[j]
        t += dt
        wr = _interp(t, t_ref, w_ref)
        err = wr - ref_sign_speed(vp, ref_dof, ref_sign)
        integ += err * dt
        td = t0_drive + kp * err + ki * integ
        fext[drive_dof] = drive_sign * td
        diss[:] = 0.0
        if fx.size > 0:
            applied_loads(q, vp, a, t, fx, *xargs)
        _accel(q, vp, t, Minv, K, C, fext, f, diss, bargs, margs, bl, mf, gargs, fx, a,
               0.5 * dt)
        ok = True
        j6 = 0
        for j in range(n):
            v[j] = vh[j] + 0.5 * dt * a[j]
            if abs(a[j]) > 1e30 or (j6 < 5 and abs(q[j]) > max_disp):
                ok = False
            j6 = 0 if j6 == 5 else j6 + 1
        step_powers(fext, v, diss, fx, drive_dof, load_dof, pw1)
        book_energy(energy, dt, pw0, pw1)
        sc[0] = t
        sc[1] = integ
        sc[2] = td
        if not (abs(q[ref_dof]) < 1e12) or not ok:
            rec[r0 : r0 + nbuf, :] = buf[:nbuf]
            return step, 1
    rec[r0 : r0 + nbuf, :] = buf[:nbuf]
    return step1, 0


@njit(cache=True, _nrt=False)
def record(rec, ir, t, td, q, v, bl, mf, rec_dofs, nd, nb, nm):  # pragma: no cover
    """Row ``ir`` of the records (columns: see :func:`run_chunk`)."""
    rec[ir, 0] = t
    rec[ir, 1] = td
    for j in range(nd):
        rec[ir, 2 + j] = q[rec_dofs[j]]
        rec[ir, 2 + nd + j] = v[rec_dofs[j]]
    for j in range(nb):
        for c in range(3):
            rec[ir, 2 + 2 * nd + c * nb + j] = bl[j, c]
    for j in range(nm):
        rec[ir, 2 + 2 * nd + 3 * nb + j] = mf[j]


@njit(cache=True, _nrt=False)
def _interp(x, xp, fp):  # pragma: no cover - compiled
    """np.interp of a scalar (same formula, no array temporaries): ``xp`` ascending."""
    n = xp.size
    if x <= xp[0]:
        return fp[0]
    if x >= xp[n - 1]:
        return fp[n - 1]
    j = 0
    while xp[j + 1] <= x:
        j += 1
    if x == xp[j]:
        return fp[j]
    slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j])
    return slope * (x - xp[j]) + fp[j]


@njit(cache=True, _nrt=False)
def ref_sign_speed(v, ref_dof, sign):  # pragma: no cover - compiled
    return sign * v[ref_dof]


def damped_step_limit(xi: float) -> float:
    """Largest ω dt for which this loop's step is stable on a mode with damping ratio ``xi``:
    2(√(1+4ξ²) − 2ξ). The damping force uses the predicted velocity v + dt a, so the limit is
    the central-difference one 2(√(1+ξ²) − ξ) (Belytschko, Liu & Moran, *Nonlinear Finite
    Elements for Continua and Structures*, 2000, §6.3) with the ratio doubled (derived from
    the spectral radius of the one-mode amplification matrix of (q, v, a); checked in
    tests/transmission/test_modal_damping.py): 1.64 at ξ = 0.1, 0.83 at ξ = 0.5, 2 undamped."""
    if not (math.isfinite(xi) and xi >= 0):
        raise InputError(f"damping ratio must be a finite number ≥ 0 (got {xi})")
    return 2.0 * (math.sqrt(1.0 + 4.0 * xi * xi) - 2.0 * xi)


def stable_time_step(M: np.ndarray, K_lin: np.ndarray) -> float:
    """2/ω_max of the linearised undamped system."""
    from scipy.linalg import eigh

    w2 = eigh(K_lin, M, eigvals_only=True, subset_by_index=[M.shape[0] - 1, M.shape[0] - 1])
    return 2.0 / math.sqrt(w2[0])


def record_buffer(nrec: int, nd: int, nb: int, nm: int) -> np.ndarray:
    """The record array of an FE run (columns of :func:`run_chunk`: time, reference turn, nd
    displacements and velocities, 3 loads per bearing, one force per mesh) for ``nrec`` rows,
    after the size check that names the option to lower."""
    cols = 2 + 2 * nd + 3 * nb + nm
    check_record_size(nrec, cols, "lower transmission.simulation.record_rate_hz or the "
                      "revolutions")
    return record_array((nrec, cols))


def record_array(shape: tuple[int, int]) -> np.ndarray:
    """Zeroed record array on ordinary 4 kB pages. numpy asks for transparent huge pages on
    large arrays (madvise); with the kernel's defrag = madvise setting the first touch of
    each huge page then compacts memory synchronously: 1.6 s of system time for the 467 MB
    of records of the 300-revolution seed 002 run (lumped mass), against 0.3 s of ordinary
    page faults. The records are written once, sequentially, so huge pages buy nothing."""
    mod = getattr(getattr(np, "_core", None), "multiarray", None)
    toggle = getattr(mod, "_set_madvise_hugepage", None)
    if toggle is None:  # pragma: no cover - numpy without the switch
        return np.zeros(shape)
    previous = toggle(False)
    try:
        return np.zeros(shape)
    finally:
        toggle(previous)


#: Loop state carried between chunks and written to checkpoints.
STATE = ("q", "v", "a", "fext", "diss", "bl", "mf", "energy", "sc", "fx")


def run_loop(
    q, v, dt, n_steps, rec_every, Minv, K, C, bargs, margs,  # noqa: ANN001
    drive_dof, load_dof, ref_dof, drive_sign, load_sign, ref_sign, load_torque,  # noqa: ANN001
    t_ref, w_ref, kp, ki, t0_drive, integ0, max_disp, rec_dofs,  # noqa: ANN001
    control: RunControl | None = None, gargs: tuple | None = None,
    xargs: tuple | None = None,
) -> tuple:
    """Integrate ``n_steps`` steps in chunks; returns (records, energy, steps done, status, q,
    v, ∫e). status 0 ok, 1 diverged, 2 stopped by ``control`` (the records cover the steps
    done). ``C``: dense damping matrix or :class:`ModalDamping`. ``control.resume`` continues
    a checkpointed run of the same setup. ``gargs``:
    :func:`gyroscopic_args` (default none); ``xargs``: applied loads (see
    :func:`applied_loads`; default none). Energy channels: see ``E_IN`` … ``E_EXT``."""
    gargs = gargs if gargs is not None else no_gyroscopic()
    Minv = csc(Minv)
    K, C = linear_args(K, C)
    xargs = xargs if xargs is not None else no_loads()
    if len(xargs) == 10:  # unbalances and external loads only (no speed-dependent supports)
        xargs = tuple(xargs) + no_support_tables()
    nx = xargs[0].size + xargs[3].size + xargs[11].size
    ctl = control or RunControl()
    n = q.size
    nb = bargs[0].size
    nm = margs[0].size
    nd = rec_dofs.size
    nrec = n_steps // rec_every + 1
    rec = record_buffer(nrec, nd, nb, nm)
    st = {"q": np.array(q, float), "v": np.array(v, float), "a": np.zeros(n),
          "fext": np.zeros(n), "diss": np.zeros(5), "bl": np.zeros((nb, 3)), "mf": np.zeros(nm),
          "energy": np.zeros(8), "sc": np.zeros(3), "fx": np.zeros(n if nx else 0)}
    run_id = {"scheme": "verlet", "nsteps": int(n_steps), "dt": float(dt),
              "rec_every": int(rec_every), "n": int(n), "ncols": int(rec.shape[1]),
              "gyroscopic": int(gargs[0].size), "loads": int(nx)}
    if C[2].size:
        run_id["damping_modes"] = int(C[2].size)
    if ctl.resume is not None:
        done = _resume(ctl.resume, run_id, st, rec)
    else:
        start_loop(st["q"], st["v"], Minv, K, C, bargs, margs, drive_dof, load_dof, ref_dof,
                   drive_sign, load_sign, ref_sign, load_torque, t_ref, w_ref, kp, ki,
                   t0_drive, integ0, st["a"], st["fext"], st["diss"], st["bl"], st["mf"],
                   st["sc"], gargs, xargs, st["fx"])
        done = 0

    def state(steps: int) -> dict:
        return {**run_id, "step": steps, **st, "rec": rec[: _recorded(steps, rec_every)]}

    def advance(start: int, stop: int) -> tuple[int, int]:
        return run_chunk(
            st["q"], st["v"], st["a"], st["fext"], st["diss"], st["bl"], st["mf"],
            st["energy"], st["sc"], start, stop, dt, rec_every, rec, Minv, K, C, bargs,
            margs, drive_dof, load_dof, ref_dof, drive_sign, ref_sign, t_ref, w_ref, kp, ki,
            t0_drive, max_disp, rec_dofs, gargs, xargs, st["fx"])

    done, status = drive_chunks(ctl, done, n_steps, advance, state)
    if status == 0 and n_steps % rec_every == 0:
        sc = st["sc"]
        record(rec, n_steps // rec_every, sc[0], sc[2], st["q"], st["v"], st["bl"], st["mf"],
               rec_dofs, nd, nb, nm)
    if status == 0:
        rows = n_steps // rec_every + 1
    elif status == 1:  # advancing from step `done` failed: that step was recorded if due
        rows = _recorded(done + 1, rec_every)
    else:
        rows = _recorded(done, rec_every)
    return (rec[:rows], st["energy"], done, status, st["q"], st["v"], float(st["sc"][1]))


def _resume(saved: dict, run_id: dict, st: dict, rec: np.ndarray) -> int:
    """Fill the loop state and the records from checkpoint ``saved`` (same run only)."""
    from geardyn.solve.control import check_same_run

    check_same_run(saved, run_id)
    for k in STATE:
        st[k][...] = saved[k]
    done = int(saved["step"])
    rec[: _recorded(done, run_id["rec_every"])] = saved["rec"]
    return done


def _recorded(steps: int, rec_every: int) -> int:
    """Rows recorded once global steps 0 … steps − 1 have been advanced."""
    return (steps + rec_every - 1) // rec_every
