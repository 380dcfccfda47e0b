"""Cost per Newmark step of the general mechanism model from 20 to 200 DOF, one core.

Model family: a two-stage parallel gearbox (square-wave meshes 23/67 and 19/71, module 4 mm)
whose input and output lines are flexible: each a chain of m torsional stations (rotors of
0.05 kg·m² joined by 2e5 N·m/rad shafts), n = 3 + 2m DOF; a stiff speed control on the first
input station and a torque on the last output station. The number of meshes stays 2 while n
grows — the case the Woodbury update is made for (an FE or multi-station shaft model).

Rows, for n = 20, 50, 100, 200: marginal wall time per step (runs of 400 and 2000 steps: the
set-up cancels) of

* ``lowrank`` — :func:`geardyn.solve.lowrank.newmark_lowrank` (A₀ factored once, Woodbury);
* ``dense refactor`` — the loop a user would write: the same scheme, assembling the dense step
  matrix and calling ``numpy.linalg.solve`` every step (same Python loop, same run);
* ``numba kernel`` — :func:`geardyn.solve.integrate.newmark` (compiled, dense solve per step).

Then the growth exponent p of each (cost ∝ nᵖ, fitted between 20 and 200 DOF; target for the
low-rank solver p ≤ 1.3) and the largest difference between the low-rank and dense results.
"""

from __future__ import annotations

import math
import time

import numpy as np

from geardyn.config.loader import parse_config
from geardyn.models.core.simulate import prepare
from geardyn.solve.integrate import SPEED_CONTROL, LinearSystem, newmark
from geardyn.solve.lowrank import newmark_lowrank

SIZES = (20, 50, 100, 200)
DT = 2e-5
STEPS = 400
LONG = 2000  # cost per step = (time of LONG steps − time of STEPS steps) / (LONG − STEPS)


def gearbox(n_dof: int) -> dict:
    """Config of the family member with about ``n_dof`` DOF (n = 3 + 2m)."""
    m = max(1, (n_dof - 3) // 2)
    rotors = [{"name": f"in{i}", "inertia_kgm2": 0.05} for i in range(m)]
    rotors += [{"name": f"out{i}", "inertia_kgm2": 0.05} for i in range(m)]
    shafts = [{"name": f"si{i}", "a": f"in{i}", "b": f"in{i + 1}" if i + 1 < m else "input",
               "torsional_nm_per_rad": 2e5} for i in range(m)]
    shafts += [{"name": f"so{i}", "a": f"out{i}", "b": f"out{i + 1}" if i + 1 < m else "output",
                "torsional_nm_per_rad": 2e5} for i in range(m)]
    return {
        "frame": "housing",
        "links": ["housing", "input", "middle", "output"],
        "parallel": [
            {"name": "g1", "a": {"link": "input", "teeth": 23}, "b": {"link": "middle",
                                                                    "teeth": 67}},
            {"name": "g2", "a": {"link": "middle", "teeth": 19}, "b": {"link": "output",
                                                                     "teeth": 71}},
        ],
        "input_speeds_rpm": {"input": 3000.0},
        "dynamics": {
            "module_m": 0.004,
            "meshes": [{"pair": "g1", "model": "square"}, {"pair": "g2", "model": "square"}],
            "rotors": rotors, "shafts": shafts,
            "simulation": {
                "t_end_s": STEPS * DT, "dt_s": DT, "initial_speed_rpm": {"in0": 3000.0},
                "speed_controls": [{"body": "in0", "profile_rpm": [[0.0, 3000.0],
                                                                   [10.0, 3000.0]],
                                    "stiffness_nm_per_rad": 1e5, "damping_nms_per_rad": 50.0}],
                "torques": [{"body": f"out{m - 1}", "torque_nm": 100.0}],
            },
        },
    }


def dense_refactor(sys: LinearSystem, q0: np.ndarray, v0: np.ndarray, steps: int, dt: float
                   ) -> np.ndarray:
    """The straightforward loop: average-acceleration Newmark, stiffness at the predictor,
    dense step matrix assembled and solved every step (speed controls and the tabulated force
    only, which is what this family uses)."""
    from geardyn.solve.integrate import _drive_forces, _force_table, _mesh_state

    s, d = sys.springs, sys.drives
    n, ns = sys.n, s.a.shape[0]
    k0, c0 = np.array(sys.K), np.array(sys.C)
    for i in range(d.kind.shape[0]):
        if d.kind[i] == SPEED_CONTROL:
            k0[d.a[i], d.a[i]] += d.p0[i] * d.ha[i] ** 2
            c0[d.a[i], d.a[i]] += d.p1[i] * d.ha[i] ** 2
    kout, eout, dout, f = np.empty(ns), np.empty(ns), np.empty(ns), np.empty(n)
    ft, fv = np.asarray(sys.force_t, float), np.ascontiguousarray(sys.force, float)

    def assemble(q: np.ndarray, v: np.ndarray, t: float) -> tuple:
        _mesh_state(q, s.a, s.b, s.x0, s.ktab, s.klen, s.kper, s.etab, s.elen, s.eper,
                    s.gap(), kout, eout, dout)
        _force_table(t, ft, fv, f)
        _drive_forces(t, q, v, d.kind, d.a, d.b, d.ha, d.hb, d.p0, d.p1, d.tx, d.ty, d.tlen, f)
        kk = k0 + (s.a.T * kout) @ s.a
        cc = c0 + (s.a.T * s.c) @ s.a
        return kk, cc, f - s.a.T @ (kout * eout)

    q, v = q0.copy(), v0.copy()
    kk, cc, ff = assemble(q, v, 0.0)
    acc = np.linalg.solve(sys.M, ff - cc @ v - kk @ q)
    out = np.zeros((steps + 1, n))
    out[0] = q
    for step in range(1, steps + 1):
        qp = q + dt * v + dt * dt * 0.25 * acc
        vp = v + dt * 0.5 * acc
        kk, cc, ff = assemble(qp, vp, step * dt)
        acc = np.linalg.solve(sys.M + 0.5 * dt * cc + 0.25 * dt * dt * kk,
                              ff - cc @ vp - kk @ qp)
        q = qp + 0.25 * dt * dt * acc
        v = vp + 0.5 * dt * acc
        out[step] = q
    return out


def _wall(fn, steps: int, repeat: int = 3) -> tuple[float, object]:  # noqa: ANN001
    best, out = math.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn(steps)
        best = min(best, time.perf_counter() - t0)
    return best, out


def _per_step(fn) -> tuple[float, object]:  # noqa: ANN001
    """Marginal cost of one step (the set-up — factorisation, tables — cancels out)."""
    short, out = _wall(fn, STEPS)
    long, _ = _wall(fn, LONG)
    return max(long - short, 1e-12) / (LONG - STEPS), out


def run() -> list[dict]:
    costs: dict[str, list[float]] = {"lowrank": [], "dense refactor": [], "numba kernel": []}
    ns: list[int] = []
    rows: list[dict] = []
    for size in SIZES:
        p = prepare(parse_config(gearbox(size)))
        sys, n = p.system, p.model.n
        ns.append(n)
        newmark(sys, p.q0, p.v0, 5 * DT, DT)  # compile / load cache
        q0, v0 = p.q0, p.v0
        c_low, low = _per_step(lambda k, s=sys, q=q0, v=v0: newmark_lowrank(s, q, v, k * DT,
                                                                            DT))
        c_dense, dense = _per_step(lambda k, s=sys, q=q0, v=v0: dense_refactor(s, q, v, k, DT))
        c_nb, _ = _per_step(lambda k, s=sys, q=q0, v=v0: newmark(s, q, v, k * DT, DT))
        for key, c in (("lowrank", c_low), ("dense refactor", c_dense), ("numba kernel", c_nb)):
            costs[key].append(c)
        diff = float(np.abs(low.q - dense).max() / np.abs(dense).max())  # type: ignore[union-attr]
        rows.append({
            "case": f"n = {n} DOF, 2 meshes, steps {STEPS} → {LONG}",
            "measured": f"lowrank {c_low * 1e6:.0f} µs/step, dense refactor "
                        f"{c_dense * 1e6:.0f} µs/step, numba kernel {c_nb * 1e6:.0f} µs/step; "
                        f"lowrank vs dense {diff:.1e}",
            "target": "same result (< 1e-9)",
            "met": diff < 1e-9,
        })
    rows += _whole_drive_rows()
    for key, c in costs.items():
        p_fit = math.log(c[-1] / c[0]) / math.log(ns[-1] / ns[0])
        rows.append({
            "case": f"growth of the {key} cost per step, {ns[0]} → {ns[-1]} DOF",
            "measured": f"n^{p_fit:.2f}",
            "target": "≤ n^1.3" if key == "lowrank" else "(reference)",
            "met": p_fit <= 1.3 if key == "lowrank" else None,
        })
    return rows


def _whole_drive_rows() -> list[dict]:
    """Seed 004 whole reclaimer drive (examples/reclaimer_whole_drive.toml, 9 DOF, 9 square-wave
    meshes + a fluid coupling), 2 simulated seconds at dt = 1e-4 s: simulated seconds per CPU
    second of both solvers (with 9 meshes for 9 DOF the Woodbury update is no smaller than
    the matrix; it pays off when the meshes are few against the DOF)."""
    import tomllib
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "examples" / "reclaimer_whole_drive.toml"
    p = prepare(parse_config(tomllib.loads(path.read_text())), 2.0)
    rows = []
    for name, fn in (("numba kernel", newmark), ("lowrank", newmark_lowrank)):
        fn(p.system, p.q0, p.v0, 10 * 1e-4, 1e-4)
        t0 = time.process_time()
        res = fn(p.system, p.q0, p.v0, 2.0, 1e-4, save_every=10)
        cpu = time.process_time() - t0
        rows.append({"case": f"seed 004 whole drive, {p.model.n} DOF, 2 s, {name}",
                     "measured": f"{2.0 / cpu:.1f} sim-s / CPU-s ({res.status})",
                     "target": "(reference)", "met": None})
    return rows


if __name__ == "__main__":
    for r in run():
        print(r)
