"""Experiment: the thesis code's carrier-torsion tie (cunfangMCKF.m, carrier row u_c:
F += Kpx·((u_pk − u_r*)·r_c/r_r − u_c) + Cpx·(rates), k = 1..3, Kpx = 1e8 N/m, Cpx = 1e10 N·s/m,
one-way: no reaction on the planet or ring rows; not in eq 3.40). In our coordinates the tie
deflection is (r_c/r_rb)(u_r − u_pk − cos α_r u_c) (zero in the rigid-body motion)."""
from __future__ import annotations

import copy
import sys

import numpy as np

sys.path.append("tests")
from seed004_ranking import T_END, scores_angle, scores_time, show  # noqa: E402

from geardyn.config.loader import parse_config  # noqa: E402
from geardyn.models.planetary.build import prepare, rigid_velocity  # noqa: E402
from geardyn.models.planetary.dynamics import simulate  # noqa: E402
from validation.seed004._reclaimer import DT, SAVE, raw  # noqa: E402


def tie_vector(model):
    info = model.stages["planetary"]
    rc, rrb = info.r_carrier, info.r_ring
    out = []
    for k in (1, 2, 3):
        g = np.zeros(len(model.names))
        g[model.dof("ring.u")] += rc / rrb
        g[model.dof(f"planet{k}.u")] -= rc / rrb
        g[model.dof("carrier.u")] -= rc / rrb * np.cos(info.alpha_r)  # r_c cos α = r_rb − r_pb
        out.append(g)
    return out


def run(faults, t_end, kpx=0.0, cpx=0.0, symmetric=False, carrier_j=None, cpb=0.0, edit=None):
    d = copy.deepcopy(raw())
    st = d["planetary_dynamics"]["stages"][0]
    st["faults"] = faults
    st["transmission_error"] = False
    if carrier_j is not None:
        st["carrier"]["inertia_kgm2"], st["carrier"]["mass_kg"] = carrier_j
    if edit is not None:
        edit(d)
    p = prepare(parse_config(d), t_end_s=t_end)
    m, s = p.model, p.system
    uc = m.dof("carrier.u")
    if kpx or cpx:
        v = rigid_velocity(m, {"sun": 32.4263})
        for g in tie_vector(m):
            assert abs(g @ v) < 1e-9 * np.abs(v).max()
            if symmetric:
                s.K += kpx * np.outer(g, g)
                s.C += cpx * np.outer(g, g)
            else:  # row u_c only: F_uc += k·tie → K[uc] −= k·g
                s.K[uc] -= kpx * g
                s.C[uc] -= cpx * g
    if cpb:  # planet-bearing dampers (Table 7-1 c_px = c_py), relative planet–carrier
        a = m.spring_vectors()
        for i, sp in enumerate(m.springs):
            if sp.kind == "planet_bearing":
                s.C += cpb * np.outer(a[i], a[i])
    ds = simulate(m, s, p.mesh_index, p.q0, p.v0, t_end, DT, save_every=SAVE)
    assert ds.attrs["status"] == "ok", ds.attrs["diagnosis"]
    return ds


if __name__ == "__main__":
    faults = {"sun_crack": [{"kind": "crack", "gear": "sun", "crack_fraction": 0.4}],
              "planet_crack": [{"kind": "crack", "gear": "planet", "crack_fraction": 0.4}],
              "ring_crack": [{"kind": "crack", "gear": "ring", "crack_fraction": 0.4}]}
    case2 = (92926.0, 26431.0)
    variants = {
        "arm": {},
        "wheel": dict(carrier_j=case2),
        "arm+cpb1e10": dict(cpb=1e10),
        "wheel+cpb1e4": dict(carrier_j=case2, cpb=1e4),
        "wheel+cpb1e10": dict(carrier_j=case2, cpb=1e10),
        "wheel+tie": dict(carrier_j=case2, kpx=1e8, cpx=1e10),
        "wheel+tie+cpb1e10": dict(carrier_j=case2, kpx=1e8, cpx=1e10, cpb=1e10),
        "wheel+symtie": dict(carrier_j=case2, kpx=1e8, cpx=1e10, symmetric=True),
    }
    only = sys.argv[1:] or list(variants)
    for name in only:
        kw = variants[name]
        h = run([], T_END, **kw)
        for fname, f in faults.items():
            c = run(f, T_END, **kw)
            show(f"{name} {fname} time", scores_time(h, c))
            show(f"{name} {fname} angle", scores_angle(h, c))
