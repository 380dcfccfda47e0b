"""FE transmission of seed 002 (issue 6): wall time of the ASC [360-430 rpm / 20 rev] and NSC
[200-900 rpm / 300 rev] runs on one core, where the time goes, and the ratio against a
straightforward ``scipy.integrate.solve_ivp`` implementation of the same equations (same
compiled force kernels, numpy right-hand side) on a short run.

Issue 24 row: the NSC run in CPU seconds with the default consistent mass (the modal
integrator) against its target (≤ 8 CPU s), in the same run as the ``solve_ivp`` baseline.

Issue 12 rows: the NSC run in CPU seconds with the default consistent mass and with the fast
options (``mass = "lumped"``; and with ``modal_damping_cutoff_hz``), the highest linearised
frequency (it sets the explicit step) for both masses, and the cost per simulated revolution
against the element count for the default and the fast options. The machine's 1-minute load
average is printed with the CPU-second rows (other jobs share the cores).
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

EX = Path(__file__).resolve().parents[1] / "examples" / "seed002_transmission.toml"


#: issue 24: the NSC run with the default (consistent) mass, CPU seconds on one core
NSC_TARGET_CPU_S = 8.0
#: the fast options of issue 12 (lumped mass; and the truncated modal damping for many elements)
LUMPED = {"mass": "lumped"}
CUTOFF_HZ = 4000.0
LUMPED_CUTOFF = {"mass": "lumped", "modal_damping_cutoff_hz": CUTOFF_HZ}


def _cfg(start: float, end: float, revs: float, options: dict | None = None):
    from geardyn.config.loader import load_config, parse_config

    d = load_config(EX).model_dump(exclude_none=True)
    d["transmission"]["speed_law"].update(start_rpm=start, end_rpm=end, revolutions=revs)
    d["transmission"].update(options or {})
    return parse_config(d)


def _kernel_split(model, prep, n: int = 20000) -> dict[str, float]:
    """µs per call of each part of one right-hand-side evaluation."""
    from geardyn.models.transmission.kernels import bearing_forces, mesh_forces

    q = prep.q0.copy()
    v = np.zeros_like(q)
    f = np.zeros_like(q)
    diss = np.zeros(5)
    bl = np.zeros((model.bearings.node.size, 3))
    mf = np.zeros(model.meshes.na.size)
    ba, ma = model.bearings.args(), model.meshes.args()
    out = {}
    t0 = time.perf_counter()
    for _ in range(n):
        bearing_forces(q, v, f, diss, *ba, bl)
    out["bearings_us"] = (time.perf_counter() - t0) / n * 1e6
    t0 = time.perf_counter()
    for _ in range(n):
        mesh_forces(q, v, f, diss, *ma, mf)
    out["meshes_us"] = (time.perf_counter() - t0) / n * 1e6
    Minv = np.linalg.inv(model.M)
    t0 = time.perf_counter()
    for _ in range(n):
        Minv @ (model.K @ q + prep.C @ v)
    out["matvec_numpy_us"] = (time.perf_counter() - t0) / n * 1e6
    return out


def _scaled_cfg(elements: int, options: dict | None = None):
    """The stationary 400 rpm case with ``elements`` per shaft (node positions scaled)."""
    from geardyn.config.loader import parse_config

    k = elements // 5
    d = _cfg(400.0, 400.0, 1.0, options).model_dump(exclude_none=True)
    t = d["transmission"]
    for s in t["shafts"]:
        s["elements"] = elements
    for item in [*t["wheels"], *t["bearings"], t["drive"], t["load"], t["speed_law"]]:
        ref = item.get("at") or item.get("reference")
        ref["node"] *= k
    return parse_config(d)


def _scaling_rows(options: dict | None = None, label: str = "default") -> list[dict]:
    """CPU seconds per simulated revolution (integration only) against the element count;
    target (issue 12): growth no faster than elements²."""
    from geardyn.models.transmission import build_model, prepare, simulate

    rows, els, cost = [], [], []
    for el in (5, 10, 20):
        cfg = _scaled_cfg(el, options)
        prep = prepare(build_model(cfg), "output")
        simulate(cfg, revolutions=0.02, prepared=prep)  # compile / cache load
        c0 = time.process_time()
        ds = simulate(cfg, revolutions=0.5, prepared=prep)
        c = (time.process_time() - c0) / 0.5
        els.append(3 * el)
        cost.append(c)
        rows.append({"case": f"{label}: {3 * el} shaft elements, 400 rpm: CPU s per revolution",
                     "target": "-", "measured_s": c, "met": "", "steps": ds.attrs["steps"],
                     "us_per_step": c * 0.5 / ds.attrs["steps"] * 1e6})
    p = float(np.polyfit(np.log(els), np.log(cost), 1)[0])
    rows.append({"case": f"{label}: cost per revolution ∝ elements^p: p", "target": "<= 2",
                 "measured_s": p, "met": p <= 2.0, "load_1min": os.getloadavg()[0]})
    return rows


def _solve_ivp_run(model, prep, duration: float) -> tuple[float, int]:
    """Straightforward first-order form y = (q, v) with scipy's LSODA (stiff/non-stiff
    switching) and the same kernels (constant drive torque = the static reaction)."""
    from scipy.integrate import solve_ivp

    from geardyn.models.transmission.kernels import bearing_forces, mesh_forces
    from geardyn.models.transmission.simulate import speed_ratios

    n = model.ndof
    Minv = np.linalg.inv(model.M)
    r = speed_ratios(model, "output")
    w0 = 395 * np.pi / 30
    v0 = np.zeros(n)
    for s, ids in model.shaft_nodes.items():
        for nd in ids:
            v0[6 * nd + 5] = model.shaft_sign[s] * r[s] * w0
    fext = np.zeros(n)
    fext[6 * model.load_node + 5] = -model.node_sign(model.load_node) * model.load_torque
    fext[6 * model.drive_node + 5] = model.load_torque * r["input"] ** -1 / 0.9
    ba, ma = model.bearings.args(), model.meshes.args()
    diss = np.zeros(5)
    bl = np.zeros((model.bearings.node.size, 3))
    mf = np.zeros(model.meshes.na.size)
    calls = [0]

    def rhs(_t, y):
        calls[0] += 1
        q, v = y[:n], y[n:]
        f = fext.copy()
        bearing_forces(q, v, f, diss, *ba, bl)
        mesh_forces(q, v, f, diss, *ma, mf)
        return np.concatenate([v, Minv @ (f - model.K @ q - prep.C @ v)])

    t0 = time.perf_counter()
    solve_ivp(rhs, (0.0, duration), np.concatenate([prep.q0, v0]), method="LSODA",
              rtol=1e-6, atol=1e-10)
    return time.perf_counter() - t0, calls[0]


def run() -> list[dict]:
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    from scipy.linalg import eigh

    from geardyn.models.transmission import build_model, prepare, simulate

    rows: list[dict] = []
    asc = _cfg(360.0, 430.0, 20.0)
    model = build_model(asc)
    t0 = time.perf_counter()
    prep = prepare(model, "output")
    t_prep = time.perf_counter() - t0
    simulate(asc, revolutions=0.2, prepared=prep)  # numba warm-up / cache load
    t0 = time.perf_counter()
    ds = simulate(asc, prepared=prep)
    t_asc = time.perf_counter() - t0
    us_step = ds.attrs["wall_integrate_s"] / ds.attrs["steps"] * 1e6
    rows.append({"case": "ASC 360-430 rpm / 20 rev", "target": "-", "measured_s": t_asc,
                 "met": "", "steps": ds.attrs["steps"], "us_per_step": us_step,
                 "simulated_s": float(ds.time[-1])})
    nsc = _cfg(200.0, 900.0, 300.0)
    t0 = time.perf_counter()
    c0 = time.process_time()
    ds = simulate(nsc, prepared=prep)
    c_nsc = time.process_time() - c0
    t_nsc = time.perf_counter() - t0
    rows.append({"case": "NSC 200-900 rpm / 300 rev", "target": "<= 600 s",
                 "measured_s": t_nsc, "met": t_nsc <= 600.0, "steps": ds.attrs["steps"],
                 "us_per_step": ds.attrs["wall_integrate_s"] / ds.attrs["steps"] * 1e6,
                 "simulated_s": float(ds.time[-1])})
    rows.append({"case": f"NSC 200-900 rpm / 300 rev, CPU seconds, consistent mass (default; "
                 f"{ds.attrs['integrator']}, h = {ds.attrs['time_step_s'] * 1e6:.3g} us)",
                 "target": f"<= {NSC_TARGET_CPU_S:g} CPU s", "measured_s": c_nsc,
                 "met": c_nsc <= NSC_TARGET_CPU_S, "steps": ds.attrs["steps"],
                 "us_per_step": c_nsc / ds.attrs["steps"] * 1e6,
                 "load_1min": os.getloadavg()[0]})
    prep_lumped = prep
    for label, opts in (("lumped mass", LUMPED),
                        (f"lumped mass, modal damping cutoff {CUTOFF_HZ:.0f} Hz", LUMPED_CUTOFF)):
        cfg = _cfg(200.0, 900.0, 300.0, opts)
        prep_l = prepare(build_model(cfg), "output")
        simulate(cfg, revolutions=0.02, prepared=prep_l)  # compile / cache load
        c0 = time.process_time()
        ds = simulate(cfg, prepared=prep_l)
        c = time.process_time() - c0
        rows.append({"case": f"NSC 200-900 rpm / 300 rev, CPU seconds, {label} (issue 12)",
                     "target": "<= 12 CPU s", "measured_s": c, "met": c <= 12.0,
                     "steps": ds.attrs["steps"],
                     "us_per_step": ds.attrs["wall_integrate_s"] / ds.attrs["steps"] * 1e6,
                     "load_1min": os.getloadavg()[0]})
        if opts is LUMPED:
            prep_lumped = prep_l
    for label, p in (("consistent", prep), ("lumped", prep_lumped)):
        w2 = eigh(p.K_lin, p.model.M, eigvals_only=True)[-1]
        rows.append({"case": f"highest linearised frequency [Hz] (step limit in us), {label} "
                     "mass", "target": "-", "measured_s": float(np.sqrt(w2) / (2 * np.pi)),
                     "met": "", "us_per_step": p.dt_stable * 1e6})
    rows += _scaling_rows()
    rows += _scaling_rows(LUMPED, "lumped")
    rows += _scaling_rows(LUMPED_CUTOFF, f"lumped, cutoff {CUTOFF_HZ:.0f} Hz")
    rows.append({"case": "prepare (static Newton + FD Jacobian + eig)", "target": "-",
                 "measured_s": t_prep, "met": ""})
    split = _kernel_split(model, prep)
    for k, v in split.items():
        rows.append({"case": f"per call: {k}", "target": "-", "measured_s": v * 1e-6,
                     "met": "", "us_per_step": v})
    dur = 0.005
    t_ivp, calls = _solve_ivp_run(model, prep, dur)
    n_ours = int(np.ceil(dur / (0.8 * prep.dt_stable)))
    t0 = time.perf_counter()
    simulate(_cfg(395.0, 395.0, 395.0 / 60 * dur), prepared=prep)
    t_ours = time.perf_counter() - t0
    rows.append({"case": f"solve_ivp LSODA, {dur * 1e3:.0f} ms simulated", "target": "reference",
                 "measured_s": t_ivp, "met": "", "steps": calls})
    rows.append({"case": f"geardyn explicit numba, {dur * 1e3:.0f} ms simulated",
                 "target": "-", "measured_s": t_ours, "met": "", "steps": n_ours})
    rows.append({"case": "speed-up vs solve_ivp", "target": "> 1", "measured_s": t_ivp / t_ours,
                 "met": t_ivp > t_ours})
    t0 = time.perf_counter()
    simulate(_cfg(395.0, 395.0, 395.0 / 60 * dur, LUMPED), prepared=prep_lumped)
    t_l = time.perf_counter() - t0
    rows.append({"case": f"geardyn explicit numba, lumped mass, {dur * 1e3:.0f} ms simulated",
                 "target": "-", "measured_s": t_l, "met": "",
                 "steps": int(np.ceil(dur / (0.8 * prep_lumped.dt_stable)))})
    rows.append({"case": "speed-up vs solve_ivp, lumped mass", "target": "> 1",
                 "measured_s": t_ivp / t_l, "met": t_ivp > t_l})
    return rows
