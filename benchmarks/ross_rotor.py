"""ROSS side of the issue-24 rotor (run with a Python that has ``ross-rotordynamics``, never
with geardyn's: ROSS is not a geardyn dependency). Prints JSON on stdout.

    python benchmarks/ross_rotor.py modal 12          # frequencies, unbalance response
    python benchmarks/ross_rotor.py time 12 lsim 1e-5 # CPU s per simulated second, 1× amp.

The rotor (issue 24): steel shaft (ROSS ``steel``: E 211 GPa, G 81.2 GPa, ρ 7810 kg/m³) 1 m,
Ø50 mm, ``n`` Timoshenko elements; discs 9.19 kg at L/3 and 3.68 kg at 3L/4 (annular steel
discs, bore 50 mm, width 50 mm, outer diameter for the mass: I_p, I_d below); bearings
1e7 N/m, 5e3 N·s/m at both ends; unbalance 1e-4 kg·m at disc 1; 3000 rpm.
"""

from __future__ import annotations

import json
import sys
import time
import warnings

import numpy as np

warnings.filterwarnings("ignore")

DISCS = ((1 / 3, 9.19, 0.040165275708741156, 0.021997221187703912),
         (3 / 4, 3.68, 0.007819436367036322, 0.0046763848501848275))
SPEED = 3000 * np.pi / 30
UNBALANCE = 1e-4


def rotor(n: int):  # noqa: ANN201
    import ross as rs

    shaft = [rs.ShaftElement(L=1.0 / n, idl=0.0, odl=0.05, material=rs.steel, n=i)
             for i in range(n)]
    discs = [rs.DiskElement(n=round(z * n), m=m, Ip=ip, Id=idd) for z, m, ip, idd in DISCS]
    brg = [rs.BearingElement(n=i, kxx=1e7, cxx=5e3) for i in (0, n)]
    return rs.Rotor(shaft, discs, brg)


def modal(n: int) -> dict:
    r = rotor(n)
    out = {}
    for rpm in (0.0, 3000.0):
        m = r.run_modal(rpm * np.pi / 30, num_modes=40, sparse=False)
        out[f"wn_{rpm:g}"] = [float(x) for x in m.wn]
        out[f"wd_{rpm:g}"] = [float(x) for x in m.wd]
    node = round(n / 3)
    resp = r.run_unbalance_response(node, UNBALANCE, 0.0, frequency=[SPEED])
    fr = np.asarray(resp.forced_resp)[:, 0]
    out["ndof_per_node"] = int(r.number_dof)
    out["unbalance_x"] = [float(fr[r.number_dof * node].real), float(fr[r.number_dof * node].imag)]
    out["unbalance_y"] = [float(fr[r.number_dof * node + 1].real),
                          float(fr[r.number_dof * node + 1].imag)]
    import ross

    out["ross_version"] = ross.__version__
    return out


def one_x(t: np.ndarray, x: np.ndarray, t_end: float) -> complex:
    """1× complex amplitude of ``x`` over the last 0.5 s (least squares on cos, sin, mean)."""
    sel = (t >= t_end - 0.5) & (t < t_end)
    A = np.c_[np.cos(SPEED * t[sel]), np.sin(SPEED * t[sel]), np.ones(sel.sum())]
    c = np.linalg.lstsq(A, x[sel], rcond=None)[0]
    return complex(c[0], -c[1])


def timed(n: int, method: str, dt: float, t_end: float = 2.0) -> dict:
    """Time response from rest at 3000 rpm: CPU seconds per simulated second, and the 1×
    amplitude of disc 1's x over the last 0.5 s against ROSS's own harmonic solution."""
    r = rotor(n)
    node = round(n / 3)
    t = np.arange(0.0, t_end + 0.5 * dt, dt)
    F = np.zeros((t.size, r.ndof))
    F[:, r.number_dof * node] = UNBALANCE * SPEED**2 * np.cos(SPEED * t)
    F[:, r.number_dof * node + 1] = UNBALANCE * SPEED**2 * np.sin(SPEED * t)
    c0 = time.process_time()
    if method == "lsim":
        res = r.run_time_response(SPEED, F, t)
    else:
        res = r.run_time_response(SPEED, F, t, method="newmark")
    cpu = time.process_time() - c0
    x = np.asarray(res.yout)[:, r.number_dof * node]
    amp = abs(one_x(t, x, t_end))
    resp = r.run_unbalance_response(node, UNBALANCE, 0.0, frequency=[SPEED])
    ref = abs(np.asarray(resp.forced_resp)[r.number_dof * node, 0])
    return {"cpu_s": cpu, "cpu_per_sim_s": cpu / t_end, "amp": float(amp), "ref": float(ref),
            "rel_error": float(abs(amp - ref) / ref), "steps": int(t.size - 1)}


if __name__ == "__main__":
    what, n = sys.argv[1], int(sys.argv[2])
    if what == "modal":
        print(json.dumps(modal(n)))
    else:
        print(json.dumps(timed(n, sys.argv[3], float(sys.argv[4]),
                               float(sys.argv[5]) if len(sys.argv) > 5 else 2.0)))
