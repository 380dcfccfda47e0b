"""Exact integration of a linear FE rotor at constant speed (no gear meshes, no Hertzian
bearings): the driver of :mod:`geardyn.solve.exponential_fe` for
:func:`geardyn.models.transmission.simulate.simulate` (``integrator = "exponential"``, or
``auto`` when it applies)."""

from __future__ import annotations

import math

import numpy as np

from geardyn.solve import exponential_fe as ef


def exponential_reason(model, t, w0: float, w1: float, C: np.ndarray,  # noqa: ANN001
                       gyro: np.ndarray | None) -> str:
    """Why the exponential integrator does not apply ('' when it does): ``t`` the
    TransmissionConfig, ``C`` the dense damping, ``gyro`` Σ Ω_s G_s or None."""
    if model.meshes.na.size or model.bearings.node.size:
        return "gear meshes and Hertzian bearings are nonlinear"
    if w0 != w1 or model.drive_torque != 0.0 or model.load_torque != 0.0:
        return "the speed is not constant (speed ramp or drive/load torques)"
    lat, rest = ef.lateral_split(model.ndof)
    for i, x in enumerate(t.external_loads):
        if x.dof not in ("x", "y", "rx", "ry"):
            return f"external_loads[{i}] acts on the axial/torsional DOF '{x.dof}'"
    mats = [model.M, model.K, C] + ([gyro] if gyro is not None else [])
    if not ef.uncoupled(mats, lat, rest):
        return "the lateral DOFs are coupled with the axial/torsional ones"
    from scipy.linalg import eigvalsh

    ix = np.ix_(lat, lat)
    w2 = eigvalsh(0.5 * (model.K[ix] + model.K[ix].T), model.M[ix], subset_by_index=[0, 0])
    if not w2[0] > (2 * math.pi * 0.5) ** 2:  # below 0.5 Hz: a rigid (defective) lateral mode
        return "the lateral motion has a rigid-body mode (unsupported rotor)"
    return ""


def _loads(model, t, q0: np.ndarray, v0: np.ndarray, lat_pos: dict[int, int]  # noqa: ANN001
           ) -> tuple[np.ndarray, np.ndarray]:
    """(F̂ (components, lateral DOFs) complex, ω (components) rad/s) of the unbalances and
    external loads at constant speed (:func:`geardyn.solve.explicit.applied_loads`)."""
    from geardyn.models.transmission.simulate import _DOF

    nl = len(lat_pos)
    amps, ws = [], []
    for u in t.unbalance:
        nd = model.node_of(u.at.shaft, u.at.node)
        om = v0[6 * nd + 5]
        a = u.mass_eccentricity_kg_m * om * om * np.exp(1j * (q0[6 * nd + 5]
                                                             + math.radians(u.phase_deg)))
        f = np.zeros(nl, complex)
        f[lat_pos[6 * nd]] = a
        f[lat_pos[6 * nd + 1]] = -1j * a
        amps.append(f)
        ws.append(om)
    for x in t.external_loads:
        nd = model.node_of(x.at.shaft, x.at.node)
        j = lat_pos[6 * nd + _DOF[x.dof]]
        if x.value != 0.0:
            f = np.zeros(nl, complex)
            f[j] = x.value
            amps.append(f)
            ws.append(0.0)
        if x.amplitude != 0.0:
            f = np.zeros(nl, complex)
            f[j] = x.amplitude * np.exp(1j * (x.order * q0[6 * nd + 5] + math.radians(x.phase_deg)))
            amps.append(f)
            ws.append(2 * math.pi * x.frequency_hz + x.order * v0[6 * nd + 5])
    if not amps:
        return np.zeros((0, nl), complex), np.zeros(0)
    return np.array(amps), np.array(ws, float)


def run_exponential(model, t, C: np.ndarray, gyro: np.ndarray | None,  # noqa: ANN001
                    q0: np.ndarray, v0: np.ndarray, dt: float, n_steps: int,
                    rec_dofs: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                                   np.ndarray]:
    """Records (layout of :func:`geardyn.solve.explicit.run_chunk`, every step recorded),
    energy channels, end state (q, v). Raises InputError if the modal basis is defective."""
    from geardyn.errors import InputError
    from geardyn.solve.explicit import E_EXT, E_MODAL

    lat, rest = ef.lateral_split(model.ndof)
    ix = np.ix_(lat, lat)
    M, K = model.M[ix], model.K[ix]
    Ct = C[ix] + (gyro[ix] if gyro is not None else 0.0)
    lam, V, Vi, cond = ef.modal_basis(M, K, Ct)
    if not cond < ef.MAX_COND:
        raise InputError(
            "transmission.simulation.integrator: 'exponential' needs a complete modal basis of "
            f"the lateral motion (condition number {cond:.3g} ≥ {ef.MAX_COND:g}: free-free or "
            "repeated undamped modes); use 'newmark'")
    nl = lat.size
    lat_pos = {int(j): i for i, j in enumerate(lat)}
    F, w = _loads(model, t, q0, v0, lat_pos)
    W = Vi[:, nl:] @ np.linalg.inv(M)  # modal force per unit DOF force
    Gp = np.array([0.5 * (W @ f) * ef.phi(lam, 1j * om, dt) for f, om in zip(F, w, strict=True)]
                  ).reshape(len(w), 2 * nl)
    Gm = np.array([0.5 * (W @ f.conj()) * ef.phi(lam, -1j * om, dt)
                   for f, om in zip(F, w, strict=True)]).reshape(len(w), 2 * nl)
    E = np.exp(lam * dt)
    x0 = np.concatenate([q0[lat], v0[lat]])
    xi = Vi @ x0
    rec_lat = [k for k, j in enumerate(rec_dofs) if int(j) in lat_pos]
    rows = [lat_pos[int(rec_dofs[k])] for k in rec_lat]
    Vrec = np.ascontiguousarray(np.concatenate([V[rows], V[[nl + r for r in rows]]]))
    loaded = np.flatnonzero(np.abs(F).sum(axis=0)) if F.size else np.zeros(0, int)
    Vpow = np.ascontiguousarray(V[nl + loaded]) if loaded.size else np.zeros((0, 2 * nl), complex)
    fpow = np.ascontiguousarray(F[:, loaded].T) if loaded.size else np.zeros((0, len(w)), complex)
    out = np.zeros((n_steps + 1, Vrec.shape[0]))
    pw = np.zeros(1)
    ef.run(xi, E, Gp, Gm, w, dt, n_steps, Vrec, out, Vpow, fpow, pw)
    nr = rec_dofs.size
    time = np.arange(n_steps + 1) * dt
    rec = np.zeros((n_steps + 1, 2 + 2 * nr))
    rec[:, 0] = time
    nrl = len(rec_lat)
    for i, k in enumerate(rec_lat):
        rec[:, 2 + k] = out[:, i]
        rec[:, 2 + nr + k] = out[:, nrl + i]
    for k, j in enumerate(rec_dofs):
        if int(j) not in lat_pos:  # rigid axial/torsional motion
            rec[:, 2 + k] = q0[j] + v0[j] * time
            rec[:, 2 + nr + k] = v0[j]
    xe = (V @ xi).real
    q1, v1 = q0.copy(), v0.copy()
    q1[rest] = q0[rest] + v0[rest] * time[-1]
    q1[lat], v1[lat] = xe[:nl], xe[nl:]
    energy = np.zeros(8)
    energy[E_EXT] = pw[0]

    def stored(q: np.ndarray, v: np.ndarray) -> float:
        return 0.5 * float(v @ model.M @ v) + 0.5 * float(q @ model.K @ q)

    # dissipation (damping) from the balance: the integration is exact for this linear system
    energy[E_MODAL] = pw[0] - (stored(q1, v1) - stored(q0, v0))
    return rec, energy, q1, v1
