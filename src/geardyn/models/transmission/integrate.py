"""Time integration of the FE transmission (seed 002 eq 3) with a speed-tracking drive.

Explicit velocity-Verlet (central-difference) scheme compiled with numba: the contact forces
are strongly nonlinear but cheap, the model is small (≈100 DOF), so an explicit step below
the stability limit 2/ω_max is the fastest robust choice (no Jacobians of the contact laws).
Velocity-dependent forces (damping, friction, squeeze film, controller) use a predicted
end-of-step velocity. The whole loop runs in compiled code; outputs are decimated.

Drive: T_d = T_0 + K_p e + K_i ∫e, e = ω_ref(t) − ω_ref_node, on the drive node; the load
torque is constant and resists the rotation (seed 002 §3.2: operating point reached by the
torque laws). Energy bookkeeping integrates input, output and each dissipation channel.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from geardyn.models.transmission.kernels import bearing_forces, mesh_forces

# channels of the energy accumulator
E_IN, E_OUT, E_VISC, E_ROLL, E_FRIC, E_SQZ, E_MODAL = range(7)


@njit(cache=True)
def _accel(q, v, t, Minv, K, C, fext, f, diss, bargs, margs, bl, mf):  # pragma: no cover
    f[:] = fext
    bearing_forces(q, v, f, diss, *bargs, bl)
    mesh_forces(q, v, f, diss, *margs, mf)
    f -= K @ q
    cv = C @ v
    f -= cv
    diss[4] += v @ cv
    return Minv @ f


@njit(cache=True)
def run_loop(
    q, v, dt, n_steps, rec_every, Minv, K, C, bargs, margs,
    drive_dof, load_dof, ref_dof, drive_sign, load_sign, ref_sign, load_torque,
    t_ref, w_ref, kp, ki, t0_drive, integ0, max_disp, rec_dofs,
):  # pragma: no cover - compiled
    """Integrate; returns (records, energy, n_done, status). status 0 ok, 1 diverged.

    Record columns: t, drive torque, angles and speeds of ``rec_dofs``, per bearing Σ Q_j,
    then housing force x, then y (n_bearings each), mesh forces."""
    n = q.size
    nrec = n_steps // rec_every + 1
    nb = bargs[0].size
    nm = margs[0].size
    nd = rec_dofs.size
    rec = np.zeros((nrec, 2 + 2 * nd + 3 * nb + nm))
    energy = np.zeros(7)
    f = np.zeros(n)
    fext = np.zeros(n)
    diss = np.zeros(5)
    bl = np.zeros((nb, 3))
    mf = np.zeros(nm)
    integ = integ0
    t = 0.0
    wr = np.interp(t, t_ref, w_ref)
    err = wr - ref_sign_speed(v, ref_dof, ref_sign)
    td = t0_drive + kp * err + ki * integ
    fext[drive_dof] = drive_sign * td
    fext[load_dof] = -load_sign * load_torque
    a = _accel(q, v, t, Minv, K, C, fext, f, diss, bargs, margs, bl, mf)
    ir = 0
    status = 0
    step = 0
    for step in range(n_steps + 1):
        if step % rec_every == 0:
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
            ir += 1
        if step == n_steps:
            break
        # power before the step (trapezoid)
        p_in0 = fext[drive_dof] * v[drive_dof]
        p_out0 = -fext[load_dof] * v[load_dof]
        d0 = diss.copy()
        vh = v + 0.5 * dt * a
        q += dt * vh
        t += dt
        vp = vh + 0.5 * dt * a
        wr = np.interp(t, t_ref, w_ref)
        err = wr - ref_sign_speed(vp, ref_dof, ref_sign)
        integ += err * dt
        td = t0_drive + kp * err + ki * integ
        fext[drive_dof] = drive_sign * td
        diss[:] = 0.0
        a = _accel(q, vp, t, Minv, K, C, fext, f, diss, bargs, margs, bl, mf)
        v = vh + 0.5 * dt * a
        p_in1 = fext[drive_dof] * v[drive_dof]
        p_out1 = -fext[load_dof] * v[load_dof]
        energy[E_IN] += 0.5 * dt * (p_in0 + p_in1)
        energy[E_OUT] += 0.5 * dt * (p_out0 + p_out1)
        for c in range(5):
            energy[2 + c] += 0.5 * dt * (d0[c] + diss[c])
        if not (np.abs(q[ref_dof]) < 1e12) or np.abs(a).max() > 1e30:
            status = 1
            break
        ok = True
        for j in range(n):
            if j % 6 < 5 and abs(q[j]) > max_disp:
                ok = False
        if not ok:
            status = 1
            break
    return rec[:ir], energy, step, status, q, v, integ


@njit(cache=True)
def ref_sign_speed(v, ref_dof, sign):  # pragma: no cover - compiled
    return sign * v[ref_dof]


def stable_time_step(M: np.ndarray, K_lin: np.ndarray) -> float:
    """2/ω_max of the linearised undamped system."""
    from scipy.linalg import eigh

    w2 = eigh(K_lin, M, eigvals_only=True, subset_by_index=[M.shape[0] - 1, M.shape[0] - 1])
    return 2.0 / math.sqrt(w2[0])
