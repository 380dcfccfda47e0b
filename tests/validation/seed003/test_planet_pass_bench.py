"""Planet-pass ring force coupled into the simulated 12-DOF bench (seed 003 eqs 4.10-4.14) and
the ring/carrier spectra of Figs 4.7-4.13 (stationary 1498.5 rpm, 100 N·m on the free ring).

- Coupling checked against an independent method: with constant mesh stiffness the bench is
  linear time-invariant, so the test-ring response at every carrier order must equal the
  receptance H(ω) = (K − ω²M + iωC)⁻¹ (``geardyn.signal.tpa.frf_from_mck``) times the applied
  force, in magnitude and phase.
- Spectra (notes §4.1, thesis ch. 4 §3): dominant components 325.6 Hz (66 f_c), 636.4 Hz
  (129 f_c), 962.0 Hz (195 f_c = 3 f_m), sidebands at multiples of N f_c = 14.8 Hz.
"""

from __future__ import annotations

import numpy as np
import pytest

from geardyn.signal.tpa import frf_from_mck

from ._bench import (
    ZR,
    N,
    f_carrier,
    f_mesh,
    raw,
    run,
    square_meshes,
    stationary,
)

RPM, DT = 1498.5, 2e-5
FC, FM = f_carrier(RPM), f_mesh(RPM)
TC = 1 / FC


def _exact_orders(x: np.ndarray, orders: np.ndarray) -> np.ndarray:
    """Complex amplitude at carrier orders over a whole number of carrier periods (no window:
    the orders are DFT bins of the record)."""
    t = np.arange(x.size) * DT
    return np.array([2 * np.mean(x * np.exp(-2j * np.pi * k * FC * t)) for k in orders])


@pytest.fixture(scope="module")
def linear_run():
    d = stationary(raw("planetary_bench_12dof.toml"), RPM, 100.0)
    for st in d["planetary_dynamics"]["stages"]:
        st["sun_mesh"] = {"model": "constant", "stiffness_n_per_m": 4.46e8}
        st["ring_mesh"] = {"model": "constant", "stiffness_n_per_m": 6.28e8}
        if st["stage"] == "test":
            st["planet_pass"] = {"harmonics": [1.0, 0.5]}
    sim = d["planetary_dynamics"]["simulation"]
    sim["rayleigh_beta"] = 0.0
    sim["modal_damping_ratio"] = 0.05  # transients gone after 0.2 s (lowest mode 96 Hz)
    t_end = 0.2 + 3 * TC
    return run(d, t_end, DT)


def test_planet_pass_amplitude_is_static_ring_mesh_force(linear_run):
    """F_nj of eq 4.13 defaults to the static ring-planet mesh force: 100 N·m on the ring →
    T/(N r_br) = 267.3 N per planet (notes §4.5)."""
    _, p, ds = linear_run
    i = p.model.dof("test.ring.u")
    f = p.system.force[:, i] - p.system.force[:, i].mean()
    r_br = p.model.body("test.ring").radius
    assert 100.0 / (3 * r_br) == pytest.approx(267.3, abs=0.1)
    # one planet in its window at the passage peak (w = 1), harmonics 1 + 0.5
    assert np.abs(f).max() == pytest.approx(1.5 * 100.0 / (3 * r_br), rel=0.02)


def test_ring_response_equals_receptance_times_force(linear_run):
    _, p, ds = linear_run
    sys = p.system
    model = p.model
    i = model.dof("test.ring.u")
    k_tot = sys.K.copy()
    for e in range(sys.springs.a.shape[0]):
        k_tot += sys.springs.ktab[e, 0] * np.outer(sys.springs.a[e], sys.springs.a[e])
    c_tot = sys.C.copy()
    a = int(sys.drives.a[0])  # speed control on the reaction sun: stiffness and damping
    k_tot[a, a] += sys.drives.p0[0] * sys.drives.ha[0] ** 2
    c_tot[a, a] += sys.drives.p1[0] * sys.drives.ha[0] ** 2
    sel = ds.sel(time=slice(0.2, None))
    n = int(round(3 * TC / DT))
    x = sel.q.sel(dof="test.ring.u").values[:n]
    t = sel.time.values[:n]
    f = np.interp(t, sys.force_t, sys.force[:, i])
    orders = np.array([60, 63, 66, 69, 72, 126, 129, 132])
    xk, fk = _exact_orders(x - x.mean(), orders), _exact_orders(f - f.mean(), orders)
    h = frf_from_mck(sys.M, c_tot, k_tot, 2 * np.pi * orders * FC)[:, i, i]
    big = np.abs(fk) > 0.05 * np.abs(fk).max()
    assert big.sum() >= 4
    ratio = xk[big] / (h[big] * fk[big])
    np.testing.assert_allclose(np.abs(ratio), 1.0, atol=0.02)  # magnitude within 2 %
    np.testing.assert_allclose(np.angle(ratio), 0.0, atol=0.02)  # phase within 0.02 rad


@pytest.fixture(scope="module")
def bench_100():
    d = square_meshes(stationary(raw("planetary_bench_12dof.toml"), RPM, 100.0), 1.5,
                      {"tip_relief_m": 5e-6})
    d["planetary_dynamics"]["stages"][1]["planet_pass"] = {}
    t_end = 0.1 + 3 * TC
    return run(d, t_end, DT)


def _orders(ds, dof: str, orders: np.ndarray) -> np.ndarray:
    sel = ds.sel(time=slice(0.1, None))
    n = int(round(3 * TC / DT))
    acc = np.gradient(sel.v.sel(dof=dof).values, DT)[:n]
    return np.abs(_exact_orders(acc - acc.mean(), orders))


@pytest.mark.parametrize(("h", "dominant"), [(1, 66), (2, 129), (3, 195)])
def test_ring_dominant_carrier_order_per_mesh_harmonic(bench_100, h, dominant):
    """Figs 4.7-4.10 / notes §4.1: the largest component near h·f_m is the multiple of N nearest
    to h·Z_r (325.6, 636.4, 962.0 Hz); searched over h·Z_r ± 7 carrier orders."""
    _, _, ds = bench_100
    orders = np.arange(h * ZR - 7, h * ZR + 8)
    amp = _orders(ds, "test.ring.u", orders)
    assert orders[np.argmax(amp)] == dominant
    assert dominant * FC == pytest.approx({1: 325.6, 2: 636.4, 3: 962.0}[h], abs=0.05)


def test_ring_sidebands_at_multiples_of_n_carrier_orders(bench_100):
    """Fig 4.8: sidebands spaced N·f_c = 14.8 Hz; the thesis lists 296.2, 310.9, 325.6, 340.2,
    369.6, 384.3 Hz (orders 60, 63, 66, 69, 75, 78) as the largest around f_m. Every one of
    the six largest orders in 56…80 is a multiple of N, and they hold ≥ 90 % of the band's
    energy; asymmetric: order 66 (f_m + f_c) above 63 (f_m − 2f_c)."""
    _, _, ds = bench_100
    orders = np.arange(56, 81)
    amp = _orders(ds, "test.ring.u", orders)
    top6 = set(orders[np.argsort(amp)[::-1][:6]])
    assert all(k % N == 0 for k in top6), top6
    assert np.sum(amp[orders % N == 0] ** 2) >= 0.9 * np.sum(amp**2)
    assert amp[orders == 66][0] > amp[orders == 63][0]
    # regression guard (no source value): five of the thesis's six orders are reproduced; the
    # sixth is 72 here and 78 in the thesis (its levels are read off a figure, no numbers).
    assert top6 == {60, 63, 66, 69, 72, 75}


def test_carrier_spectrum_mesh_line(bench_100):
    """Figs 4.11-4.13 (test carrier): oscillation at the mesh period with carrier sidebands.
    Our carrier carries no planet-pass force, so its f_m band is the meshes' net torque: with
    sequential phasing (Table 4.2) the three planets' first and second harmonics cancel and
    3 f_m (195 f_c) dominates the 0-1100 Hz mesh lines."""
    _, _, ds = bench_100
    orders = np.array([65, 130, 195])
    amp = _orders(ds, "test.carrier.u", orders)
    assert amp[2] > 10 * max(amp[0], amp[1])
    # regression guard (no source value): the thesis says the largest carrier response near
    # f_m is right on f_m (65 f_c). A symmetric, sequentially phased model cancels f_m on the
    # carrier exactly; with the thesis's pin errors it becomes the largest line
    # (test_carrier_fm.py). Pinned: ratio of our (leakage-level) f_m line to the 3 f_m line.
    assert amp[0] / amp[2] == pytest.approx(0.0117, rel=0.25)
