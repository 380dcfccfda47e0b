"""Implicit Newmark integration of the FE transmission: a time step set by accuracy.

Average-acceleration Newmark (β = ¼, γ = ½: unconditionally stable, no numerical damping,
second order; Newmark 1959; Géradin & Rixen, *Mechanical Vibrations*, 3rd ed., 2015, §7.3)
of M q̈ + C q̇ + K q = F(t, q, q̇) with the nonlinear bearing and mesh forces, gyroscopic
terms, applied loads and the speed controller of :mod:`geardyn.solve.explicit` (same kernels,
same records, same energy channels). Each step solves R(q₁) = M a₁ + C v₁ + K q₁ − F = 0
for the end-of-step displacement with a₁ = (q₁ − q̃)/(β dt²), v₁ = ṽ + γ dt a₁ by a
modified Newton iteration on the constant matrix

    S₀ = M/(β dt²) + γ/(β dt) (C_s + Σ_s Ω_s⁰ G_s) + K_lin,

K_lin the stiffness linearised at the static preload (bearing and mesh tangents included),
C_s the sparse part of the damping (supports, dashpots, the stiffness-proportional modal part)
and Ω_s⁰ the initial shaft speeds; the residual itself is always the exact one (dense or
low-rank modal damping, current speeds, current contact states), so the converged step is the
Newmark step of the nonlinear system; S₀ only sets the convergence rate (contraction ≈ the
relative change of the tangent stiffness against S₀). S₀ is factored once: reverse
Cuthill-McKee ordering (scipy.sparse.csgraph), banded LU without pivoting (S₀ = symmetric
positive definite + skew gyroscopic part: every leading minor is regular), so that a solve costs
O(n b) with b the bandwidth — linear in the number of elements of a shaft line.

Newton stops when every increment is below ``rtol`` × the step's change of its DOF class
(translations, rotations) plus a floor (:data:`ATOL_M`, :data:`ATOL_RAD`); a step still
unconverged after :data:`MAX_ITER` iterations is counted (``newton_unconverged_steps``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from geardyn.errors import InputError
from geardyn.models.transmission.kernels import bearing_forces, mesh_forces
from geardyn.solve.control import RunControl, drive_chunks
from geardyn.solve.explicit import (
    REC_BLOCK,
    _dot,
    _interp,
    _linear_forces,
    applied_loads,
    book_energy,
    csr,
    gyroscopic_forces,
    linear_args,
    no_gyroscopic,
    no_loads,
    no_support_tables,
    record,
    record_buffer,
    ref_sign_speed,
    step_powers,
)

BETA, GAMMA = 0.25, 0.5
#: Newton floors: increments below these never block convergence [m], [rad].
ATOL_M = 1e-14
ATOL_RAD = 1e-13
#: Relative Newton tolerance on the step's change of each DOF class.
RTOL = 1e-8
MAX_ITER = 30


def banded_factor(S: np.ndarray) -> tuple[np.ndarray, np.ndarray, int, int]:
    """(LU in place of S[perm][:, perm], perm, lower and upper bandwidth): reverse
    Cuthill-McKee ordering of the pattern of S, then :func:`_band_lu`."""
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import reverse_cuthill_mckee

    pat = csr_matrix((S != 0.0) | (S.T != 0.0))
    perm = np.asarray(reverse_cuthill_mckee(pat, symmetric_mode=True), np.int64)
    A = np.ascontiguousarray(S[np.ix_(perm, perm)])
    r, c = np.nonzero(A)
    bl = int(max(0, (r - c).max())) if r.size else 0
    bu = int(max(0, (c - r).max())) if r.size else 0
    ok = _band_lu(A, bl, bu)
    if not ok:
        raise InputError("newmark: the step matrix M/(β dt²) + γ C/(β dt) + K_lin has a zero "
                         "pivot (a free DOF without mass?)")
    return A, perm, bl, bu


@njit(cache=True)
def _band_lu(A, bl, bu):  # pragma: no cover - compiled
    """Doolittle LU without pivoting of a banded matrix stored dense (in place)."""
    n = A.shape[0]
    for k in range(n):
        piv = A[k, k]
        if piv == 0.0 or not math.isfinite(piv):
            return False
        for i in range(k + 1, min(n, k + bl + 1)):
            lik = A[i, k] / piv
            A[i, k] = lik
            if lik != 0.0:
                for j in range(k + 1, min(n, k + bu + 1)):
                    A[i, j] -= lik * A[k, j]
    return True


@njit(cache=True)
def _band_solve(LU, perm, bl, bu, b, x, y):  # pragma: no cover - compiled
    """x = S⁻¹ b with the factors of :func:`banded_factor` (``y`` work array)."""
    n = b.size
    for i in range(n):
        acc = b[perm[i]]
        for j in range(max(0, i - bl), i):
            acc -= LU[i, j] * y[j]
        y[i] = acc
    for i in range(n - 1, -1, -1):
        acc = y[i]
        for j in range(i + 1, min(n, i + bu + 1)):
            acc -= LU[i, j] * y[j]
        y[i] = acc / LU[i, i]
    for i in range(n):
        x[perm[i]] = y[i]


@njit(cache=True)
def _csr_matvec(data, idx, ptr, x, out):  # pragma: no cover - compiled
    """out = A x (CSR)."""
    for i in range(ptr.size - 1):
        acc = 0.0
        for p in range(ptr[i], ptr[i + 1]):
            acc += data[p] * x[idx[p]]
        out[i] = acc


@njit(cache=True)
def _forces(q, v, a, t, K, C, fext, f, diss, bargs, margs, bl, mf, gargs, xargs, fx
            ):  # pragma: no cover - compiled
    """f = F_ext + F_loads + F_connecting − K q − C v − Σ Ω G v (everything but inertia);
    diss: dissipation powers (reset here)."""
    diss[:] = 0.0
    f[:] = fext
    if fx.size > 0:
        applied_loads(q, v, a, t, fx, *xargs)
        f += fx
    bearing_forces(q, v, f, diss, *bargs, bl)
    mesh_forces(q, v, f, diss, *margs, mf)
    cw = C[5]
    _linear_forces(q, v, f, cw, *K, *C[:5], C[6])
    diss[4] += _dot(v, cw)
    if gargs[0].size > 0:
        gyroscopic_forces(v, f, *gargs)


@njit(cache=True)
def run_chunk(
    q, v, a, fext, diss, bl, mf, energy, sc, stats, step0, step1, dt, rec_every, rec,
    Mcsr, LU, perm, lbw, ubw, K, C, bargs, margs, drive_dof, load_dof, ref_dof, drive_sign,
    ref_sign, t_ref, w_ref, kp, ki, t0_drive, max_disp, rec_dofs, gargs, xargs, fx, rtol,
):  # pragma: no cover - compiled
    """Advance global steps ``step0`` → ``step1`` (Newmark, modified Newton on S₀); state and
    records as in :func:`geardyn.solve.explicit.run_chunk`. ``stats`` = [Newton iterations,
    unconverged steps]. Returns (last step reached, status 0 ok / 1 diverged)."""
    n = q.size
    nb = bl.shape[0]
    nm = mf.size
    nd = rec_dofs.size
    f = np.zeros(n)
    r = np.zeros(n)
    dq = np.zeros(n)
    y = np.zeros(n)
    qt = np.zeros(n)
    vt = np.zeros(n)
    ma = np.zeros(n)
    q1 = np.zeros(n)
    v1 = np.zeros(n)
    a1 = np.zeros(n)
    pw0 = np.zeros(energy.size)
    pw1 = np.zeros(energy.size)
    buf = np.empty((REC_BLOCK, rec.shape[1]))
    r0 = 0
    nbuf = 0
    t = sc[0]
    integ = sc[1]
    td = sc[2]
    c_a = 1.0 / (BETA * dt * dt)
    c_v = GAMMA / (BETA * dt)
    for step in range(step0, step1):
        if step % rec_every == 0:
            if nbuf == 0:
                r0 = step // rec_every
            record(buf, nbuf, t, td, q, v, bl, mf, rec_dofs, nd, nb, nm)
            nbuf += 1
            if nbuf == REC_BLOCK:
                rec[r0 : r0 + nbuf, :] = buf
                nbuf = 0
        step_powers(fext, v, diss, fx, drive_dof, load_dof, pw0)
        t1 = t + dt
        wr = _interp(t1, t_ref, w_ref)
        for j in range(n):
            qt[j] = q[j] + dt * v[j] + dt * dt * (0.5 - BETA) * a[j]
            vt[j] = v[j] + dt * (1.0 - GAMMA) * a[j]
            a1[j] = a[j]
            q1[j] = qt[j] + BETA * dt * dt * a1[j]
            v1[j] = vt[j] + GAMMA * dt * a1[j]
        err = 0.0
        converged = False
        for _it in range(MAX_ITER):
            err = wr - ref_sign_speed(v1, ref_dof, ref_sign)
            td = t0_drive + kp * err + ki * (integ + err * dt)
            fext[drive_dof] = drive_sign * td
            _forces(q1, v1, a1, t1, K, C, fext, f, diss, bargs, margs, bl, mf, gargs, xargs,
                    fx)
            _csr_matvec(Mcsr[0], Mcsr[1], Mcsr[2], a1, ma)
            for j in range(n):
                r[j] = f[j] - ma[j]
            _band_solve(LU, perm, lbw, ubw, r, dq, y)
            stats[0] += 1
            # tolerance per DOF class from the step's change
            ct = 0.0
            cr = 0.0
            dt_ = 0.0
            dr = 0.0
            for j in range(n):
                q1[j] += dq[j]
                a1[j] += c_a * dq[j]
                v1[j] += c_v * dq[j]
                ch = abs(q1[j] - q[j])
                if j % 6 < 3:
                    ct = max(ct, ch)
                    dt_ = max(dt_, abs(dq[j]))
                else:
                    cr = max(cr, ch)
                    dr = max(dr, abs(dq[j]))
            if dt_ <= rtol * ct + ATOL_M and dr <= rtol * cr + ATOL_RAD:
                converged = True
                break
        if not converged:
            stats[1] += 1
        integ += err * dt
        ok = True
        for j in range(n):
            q[j] = q1[j]
            v[j] = v1[j]
            a[j] = a1[j]
            if not (abs(a[j]) < 1e30) or (j % 6 < 3 and abs(q[j]) > max_disp):
                ok = False
        t = t1
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


def step_matrix(M: np.ndarray, K_lin: np.ndarray, C_sparse: np.ndarray | None, dt: float,
                gyro: np.ndarray | None = None) -> np.ndarray:
    """S₀ = M/(β dt²) + γ/(β dt)(C_s + Σ Ω⁰ G) + K_lin (dense, for :func:`banded_factor`)."""
    S = M / (BETA * dt * dt) + K_lin
    cv = GAMMA / (BETA * dt)
    if C_sparse is not None:
        S = S + cv * C_sparse
    if gyro is not None:
        S = S + cv * gyro
    return S


#: Loop state carried between chunks and written to checkpoints.
STATE = ("q", "v", "a", "fext", "diss", "bl", "mf", "energy", "sc", "fx", "stats")


def run_loop(
    q, v, dt, n_steps, rec_every, M, K, K_lin, C, C_sparse, bargs, margs,  # noqa: ANN001
    drive_dof, load_dof, ref_dof, drive_sign, load_sign, ref_sign, load_torque,  # noqa: ANN001
    t_ref, w_ref, kp, ki, t0_drive, integ0, max_disp, rec_dofs,  # noqa: ANN001
    control: RunControl | None = None, gargs: tuple | None = None,
    xargs: tuple | None = None, gyro0: np.ndarray | None = None, rtol: float = RTOL,
) -> tuple:
    """Newmark counterpart of :func:`geardyn.solve.explicit.run_loop` (same arguments but M,
    not M⁻¹; ``K_lin`` and ``C_sparse`` (or None) for the step matrix, ``gyro0`` = Σ Ω⁰ G).
    Returns (records, energy, steps done, status, q, v, ∫e, stats)."""
    gargs = gargs if gargs is not None else no_gyroscopic()
    xargs = xargs if xargs is not None else no_loads()
    if len(xargs) == 10:  # unbalances and external loads only (no speed-dependent supports)
        xargs = tuple(xargs) + no_support_tables()
    S = step_matrix(M, K_lin, C_sparse, dt, gyro0)
    LU, perm, lbw, ubw = banded_factor(S)
    Mcsr = csr(M)
    Kc, Cc = linear_args(K, C)
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
          "energy": np.zeros(8), "sc": np.zeros(3), "fx": np.zeros(n if nx else 0),
          "stats": np.zeros(2)}
    run_id = {"scheme": "newmark-fe", "nsteps": int(n_steps), "dt": float(dt),
              "rec_every": int(rec_every), "n": int(n), "ncols": int(rec.shape[1]),
              "gyroscopic": int(gargs[0].size), "loads": int(nx)}
    if ctl.resume is not None:
        from geardyn.solve.control import check_same_run

        check_same_run(ctl.resume, run_id)
        for k in STATE:
            st[k][...] = ctl.resume[k]
        done = int(ctl.resume["step"])
        rec[: _recorded(done, rec_every)] = ctl.resume["rec"]
    else:
        _start(st, M, Kc, Cc, bargs, margs, drive_dof, load_dof, ref_dof, drive_sign,
               load_sign, ref_sign, load_torque, t_ref, w_ref, kp, ki, t0_drive, integ0, gargs,
               xargs)
        done = 0

    def state(steps: int) -> dict:
        return {**run_id, "step": steps, **st, "rec": rec[: _recorded(steps, rec_every)]}

    def advance(start: int, stop: int) -> tuple[int, int]:
        return run_chunk(
            st["q"], st["v"], st["a"], st["fext"], st["diss"], st["bl"], st["mf"],
            st["energy"], st["sc"], st["stats"], start, stop, dt, rec_every, rec, Mcsr, LU,
            perm, lbw, ubw, Kc, Cc, bargs, margs, drive_dof, load_dof, ref_dof, drive_sign,
            ref_sign, t_ref, w_ref, kp, ki, t0_drive, max_disp, rec_dofs, gargs, xargs,
            st["fx"], rtol)

    done, status = drive_chunks(ctl, done, n_steps, advance, state)
    if status == 0 and n_steps % rec_every == 0:
        sc = st["sc"]
        record(rec, n_steps // rec_every, sc[0], sc[2], st["q"], st["v"], st["bl"], st["mf"],
               rec_dofs, nd, nb, nm)
    if status == 0:
        rows = n_steps // rec_every + 1
    elif status == 1:
        rows = _recorded(done + 1, rec_every)
    else:
        rows = _recorded(done, rec_every)
    return (rec[:rows], st["energy"], done, status, st["q"], st["v"], float(st["sc"][1]),
            st["stats"])


def _start(st: dict, M: np.ndarray, K, C, bargs, margs, drive_dof, load_dof,  # noqa: ANN001
           ref_dof, drive_sign, load_sign, ref_sign, load_torque, t_ref, w_ref, kp, ki,  # noqa: ANN001
           t0_drive, integ0, gargs, xargs) -> None:  # noqa: ANN001
    """Initial drive torque, loads and the consistent acceleration M a₀ = F(q₀, v₀)."""
    q, v = st["q"], st["v"]
    err = float(np.interp(0.0, t_ref, w_ref)) - ref_sign * v[ref_dof]
    td = t0_drive + kp * err + ki * integ0
    fext = st["fext"]
    fext[:] = 0.0
    fext[drive_dof] = drive_sign * td
    fext[load_dof] = -load_sign * load_torque
    f = np.zeros(q.size)
    _forces(q, v, st["a"], 0.0, K, C, fext, f, st["diss"], bargs, margs, st["bl"], st["mf"],
            gargs, xargs, st["fx"])
    st["a"][:] = np.linalg.solve(M, f)
    st["sc"][:] = (0.0, integ0, td)


def _recorded(steps: int, rec_every: int) -> int:
    return (steps + rec_every - 1) // rec_every
