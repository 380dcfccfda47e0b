"""GTDT transfer path analysis (seed 003 ch. 5 §3, eqs 5.6-5.21, ``geardyn.signal.tpa``) applied
to the simulated 12-DOF bench: FRFs H(ω) = (K − ω²M + iωC)⁻¹ of the bench model (the thesis's
impact-hammer FRFs, notes §2.7), operational responses from a stationary 1498.5 rpm / 100 N·m
run with the planet-pass ring force.

Thesis (notes §4.6): T^D between the two rings "should be zero" (not directly connected; the
measured one is not); the largest path contributions to test planet 2 come from the directly
connected DOFs (test carrier, test sun); the phase PPC at 100 Hz and 321 Hz shows u_sr, u_cr,
u_1r, u_2r negligible and u_rt, u_st, u_ct significant.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import detrend

from geardyn.signal.tpa import frf_from_mck, gtdt, path_contributions, reconstruct

from ._bench import f_carrier, raw, run, stationary

RPM, DT = 1498.5, 2e-5
FC = f_carrier(RPM)
TC = 1 / FC


@pytest.fixture(scope="module")
def bench():
    d = stationary(raw("planetary_bench_12dof.toml"), RPM, 100.0)
    d["planetary_dynamics"]["stages"][1]["planet_pass"] = {}
    cfg, p, ds = run(d, 0.1 + 3 * TC, DT)
    model = p.model
    mm, kk = model.mass_matrix(), model.stiffness_matrix()
    cc = 2e-6 * kk  # the example's Rayleigh β
    sel = ds.sel(time=slice(0.1, None))
    n = int(round(3 * TC / DT))
    t = np.arange(n) * DT
    orders = np.array([20, 65, 66])  # ≈ 100 Hz, f_m = 320.7 Hz, 325.6 Hz
    q = detrend(sel.q.values[:n], axis=0)  # vibration: the rigid-body rotation removed
    x = np.array([[2 * np.mean(q[:, j] * np.exp(-2j * np.pi * k * FC * t))
                   for j in range(mm.shape[0])] for k in orders])
    h = frf_from_mck(mm, cc, kk, 2 * np.pi * orders * FC)
    return model, gtdt(h), x, orders


def test_direct_transmissibility_zero_between_unconnected_dofs(bench):
    model, g, _, _ = bench
    names = model.names
    rr, rt = names.index("reaction.ring.u"), names.index("test.ring.u")
    p1, p2 = names.index("test.planet1.u"), names.index("test.planet2.u")
    for i, j in ((rr, rt), (rt, rr), (p1, p2), (p2, p1)):
        np.testing.assert_allclose(np.abs(g.direct[:, i, j]), 0.0, atol=1e-9)
    # the global transmissibility between the rings is not zero (it carries the indirect paths)
    assert np.all(np.abs(g.global_[:, rr, rt]) > 1e-6)


def test_reconstruction_of_simulated_responses(bench):
    """Eq 5.21 returns the operational responses (machine precision)."""
    _, g, x, _ = bench
    np.testing.assert_allclose(reconstruct(g, x), x, rtol=1e-8, atol=1e-12 * np.abs(x).max())


def test_contributions_to_test_planet_2(bench):
    """Only the directly connected DOFs (test ring, sun, carrier) contribute to test planet 2;
    u_sr, u_cr, u_1r, u_2r (and every other DOF of the model) contribute nothing, at 100 Hz and
    at f_m. The thesis also lists u_1t, u_3t and u_rr as significant in its measured PPC; in the
    torsional model they have no direct path (not reproducible: measured T^D between unconnected
    DOFs is polluted, as the thesis notes for the two rings)."""
    model, g, x, orders = bench
    names = model.names
    i = names.index("test.planet2.u")
    ppc = np.abs(path_contributions(g, x))[:, i, :]
    direct = {names.index(f"test.{b}.u") for b in ("ring", "sun", "carrier")}
    for j in range(len(names)):
        if j != i and j not in direct:
            np.testing.assert_allclose(ppc[:, j], 0.0, atol=1e-12 * ppc.max())
    for f_idx in range(len(orders)):
        assert all(ppc[f_idx, j] > 1e-6 * ppc[f_idx].max() for j in direct)
    # thesis (Figs 5.16-5.17): the largest contributions come from the test carrier and the
    # test sun (at f_m); ranked here, not measured against levels (figure-only)
    at_fm = {names[j]: ppc[1, j] for j in direct}
    top2 = sorted(at_fm, key=at_fm.get)[::-1][:2]
    assert set(top2) == {"test.carrier.u", "test.sun.u"}
