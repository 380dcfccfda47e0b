"""Seed 003 load sweep (Figs 4.14-4.17) and variable load (Figs 4.18-4.20), 12-DOF bench at
1498.5 rpm with the planet-pass ring force and the load-dependent square mesh.

Thesis (notes §4.3): the dominant test-ring component is f_m at 100 N·m and moves to 2f_m at
900 N·m ("larger contact ratio and stiffness at higher load"); under a variable load starting at
100 N·m the dominant line is 636.4 Hz (129 f_c, the carrier harmonic nearest 2f_m), like the
average (≈ 400 N·m) load. The FE stiffness curves of Figs 4.14-4.15 are figure-only, so the
load law is ours (``loaded_square_mesh``): unloaded contact ratio 1.5, tip relief C_a = 5 µm
over a quarter base pitch at each end (assumed; the thesis gives no gear geometry).
"""

from __future__ import annotations

import numpy as np
import pytest

from geardyn.models.planetary.loads import loaded_square_mesh

from ._bench import f_carrier, f_mesh, raw, run, square_meshes, stationary, table_units

RPM, DT = 1498.5, 2e-5
FC, FM = f_carrier(RPM), f_mesh(RPM)
TC = 1 / FC
LAW = {"tip_relief_m": 5e-6}


def _config(torque: float, profile: list | None = None, law: dict = LAW) -> dict:
    d = square_meshes(stationary(raw("planetary_bench_12dof.toml"), RPM, torque), 1.5, law)
    d["planetary_dynamics"]["stages"][1]["planet_pass"] = {}
    if profile:
        d["planetary_dynamics"]["simulation"]["torques"] = [
            {"body": "reaction.ring", "profile": profile}]
    return d


def _ring_lines(ds, t0: float = 0.1) -> tuple[float, float, float]:
    """(dominant frequency in 250-1100 Hz, amplitude at the f_m group, at the 2f_m group) of the
    test-ring acceleration (Hann spectrum, m/s² on u = r θ)."""
    sel = ds.sel(time=slice(t0, None))
    acc = np.gradient(sel.v.sel(dof="test.ring.u").values, DT)
    acc = acc - acc.mean()
    w = np.hanning(acc.size)
    f = np.fft.rfftfreq(acc.size, DT)
    a = np.abs(np.fft.rfft(acc * w)) * 2 / w.sum()
    band = (f > 250) & (f < 1100)
    a1 = a[(f > FM - 25) & (f < FM + 25)].max()
    a2 = a[(f > 2 * FM - 25) & (f < 2 * FM + 25)].max()
    return float(f[band][np.argmax(a[band])]), float(a1), float(a2)


@pytest.fixture(scope="module")
def sweep():
    out = {}
    for torque in (100.0, 300.0, 500.0, 700.0, 900.0):
        out[torque] = _ring_lines(run(_config(torque), 0.1 + 3 * TC, DT)[2])
    return out


def test_law_closed_form():
    """c(F) = min(2, c₀ + 2ρ min(δ/C_a, 1)), δ = F/k̄₀ (k̄₀ eq 1.12): ring mesh at 100 and 900
    N·m ring torque (F = T/(3 r_br) = 267.3 and 2406.0 N, notes §4.5), worked by hand."""
    km = 6.28e8
    for f_n, c_hand in ((267.3, 1.5 + 0.5 * 267.3 / km / 5e-6),
                        (2406.0, 1.5 + 0.5 * 2406.0 / km / 5e-6)):
        kx, kn, c = loaded_square_mesh(1.2 * km, 0.8 * km, 1.5, f_n, 5e-6)
        assert (kx, kn) == (1.2 * km, 0.8 * km)
        assert c == pytest.approx(c_hand, rel=1e-12)
    assert loaded_square_mesh(1.2 * km, 0.8 * km, 1.5, 1e9, 5e-6)[2] == 2.0  # capped
    kx, _, _ = loaded_square_mesh(1.2 * km, 0.8 * km, 1.5, 4 * 267.3, 5e-6, 0.25, 267.3, 0.5)
    assert kx == pytest.approx(2 * 1.2 * km, rel=1e-12)  # k ∝ (F/F_ref)^0.5


def test_dominant_line_moves_from_fm_to_2fm(sweep):
    """Figs 4.16-4.17: f_m group dominant at 100 N·m (66 f_c = 325.6 Hz), 2f_m group (129 f_c =
    636.4 Hz) at 900 N·m; tolerance: the exact carrier order (one spectral bin = f_c/3).
    Reproduced with the support read as N·m/rad only: the square-wave excitation itself never
    has 2f_m above f_m (test_square_wave_excitation_bound); the test ring's 532 Hz rotation
    mode, between f_m and 2f_m, does the lifting (with the printed N/m unit there is no mode
    there and the switch is gone, test_no_switch_with_the_printed_support_unit)."""
    assert sweep[100.0][0] == pytest.approx(66 * FC, abs=FC / 3)
    assert sweep[900.0][0] == pytest.approx(129 * FC, abs=FC / 3)
    ratio = [sweep[t][2] / sweep[t][1] for t in sorted(sweep)]
    assert ratio[0] < 1 < ratio[-1]
    assert np.all(np.diff(ratio) > 0)  # the 2f_m share grows with the load


@pytest.mark.parametrize("c", np.linspace(1.05, 1.95, 19))
def test_square_wave_excitation_bound(c):
    """Closed form: for a square-wave mesh stiffness with contact ratio c (eq 1.11) the static
    transmission error F/k(t) is a square wave of the same duty d = c − 1, whose harmonics go
    as |sin πhd|/h, so |2nd|/|1st| = |cos πd| ≤ 1 at every load: on its own the excitation
    cannot make 2f_m dominate. Checked on the sampled wave (2¹⁶ samples, to 1e-3)."""
    n = 1 << 16
    x = np.arange(n) / n
    k = np.where(x < c - 1, 1.2, 0.8)
    te = np.abs(np.fft.rfft(1.0 / k)) / n
    assert te[2] / te[1] == pytest.approx(abs(np.cos(np.pi * (c - 1))), abs=1e-3)
    assert te[2] <= te[1] * (1 + 1e-3)


def test_no_switch_with_the_printed_support_unit():
    """Figs 4.16-4.17 not reproduced with Table 3.1's printed unit of the ring support (7.9e6
    N/m on u, docs/validation.md): no mode between 146 Hz and 1.1 kHz, the ring responds like
    its mass, and the 2f_m/f_m ratio stays below 1 at 900 N·m as the excitation bound says."""
    d = table_units(_config(900.0))
    _, a1, a2 = _ring_lines(run(d, 0.1 + 3 * TC, DT)[2])
    assert a2 < a1


@pytest.mark.parametrize("tip_relief", [10e-6, 20e-6])
def test_switch_does_not_rest_on_the_chosen_tip_relief(tip_relief):
    """The switch (f_m at 100 N·m, 2f_m at 900 N·m) holds for C_a = 5, 10 and 20 µm; it needs
    the load law (at a fixed c = 1.5 the even harmonics vanish, |cos π/2| = 0) and fails at
    C_a = 2.5 µm, where c reaches 2 by 700 N·m and the mesh stops fluctuating
    (experiments/seed003_load_sweep.py)."""
    law = {"tip_relief_m": tip_relief}
    low = _ring_lines(run(_config(100.0, law=law), 0.1 + 3 * TC, DT)[2])
    high = _ring_lines(run(_config(900.0, law=law), 0.1 + 3 * TC, DT)[2])
    assert low[2] < low[1] and high[2] > high[1]


def test_amplitude_trend_pinned(sweep):
    # regression guard (no source value): the thesis's ring acceleration *decreases* with load
    # (Fig 4.16); ours grows in every variant tried (C_a 2.5-20 µm, no load law, no planet-pass
    # force, printed support unit; experiments/seed003_load_sweep.py): both excitations are
    # linear in the load (Δk·F/k̄ and the planet-pass force F_nj = static ring mesh force,
    # eq 4.13), e.g. without the load law RMS 1.29 → 12.2 m/s² for 100 → 900 N·m; the arm
    # masses' inertia (ΔI = T L/g, L = 0.5-2 m) does not reverse it. A fall needs the thesis's
    # FE stiffness (Figs 4.14-4.15, figure-only) or a displacement excitation: a long tip
    # relief's STE (design load above 900 N·m) reverses it below 1.1 kHz, the load law's short
    # relief does not (experiments/seed003_harris_map.py, test_harris_map.py).
    # Pinned: the 2f_m/f_m group ratio at 100, 300, 500, 700, 900 N·m (to 10 %).
    ratio = [sweep[t][2] / sweep[t][1] for t in sorted(sweep)]
    np.testing.assert_allclose(ratio, [0.82, 2.39, 3.54, 4.64, 5.26], rtol=0.1)


def test_variable_load_dominant_line():
    """Fig 4.20: torque on the free ring varied from 100 N·m (Fig 4.18 is figure-only; here
    100 → 700 → 400 N·m over three carrier periods, time mean ≈ 420 N·m): the dominant line is
    636.4 Hz (129 f_c). Limitation: the load law uses the time-mean static mesh force (the mesh
    tables are functions of the mesh position, not of time)."""
    t_end = 0.1 + 3 * TC
    prof = [[0.0, 100.0], [0.1 + 1.5 * TC, 700.0], [t_end, 400.0]]
    f_dom, _, _ = _ring_lines(run(_config(100.0, prof), t_end, DT)[2])
    assert f_dom == pytest.approx(129 * FC, abs=FC / 3)


@pytest.mark.parametrize("c", [1.5, 1.6, 1.77])
def test_mesh_harmonics_closed_form(c):
    """The planet-pass amplitudes come from the mesh table's harmonics (``mesh_harmonics``).
    For the square wave (eq 1.11), the relative amplitude of harmonic h is
    2Δk|sin(πh(c−1))|/(πh k̄) (continuous form; to 0.5 % when the double-contact share is
    whole samples, c = 1.5) and exactly the Dirichlet sum 2Δk|sin(πhn₁/L)|/(L|sin(πh/L)| k̄)
    of the L-sample table with n₁ double-contact samples."""
    from geardyn.gears import square_wave
    from geardyn.models.planetary.build import SAMPLES_PER_CYCLE, mesh_harmonics
    from geardyn.models.planetary.dynamics import MeshLaw

    n = SAMPLES_PER_CYCLE
    x = np.arange(n) / n
    k = square_wave(x, 1.2, 0.8, c)
    amp, _ = mesh_harmonics(MeshLaw(k), 3)
    n1 = int(np.sum(k == 1.2))
    k_bar = k.mean()
    h = np.arange(1, 4)
    exact = 2 * 0.4 * np.abs(np.sin(np.pi * h * n1 / n)) / (n * np.abs(np.sin(np.pi * h / n))
                                                          ) / k_bar
    np.testing.assert_allclose(amp, exact, rtol=1e-9, atol=1e-15)
    if c == 1.5:
        cont = 2 * 0.4 * np.abs(np.sin(np.pi * h * (c - 1))) / (np.pi * h) / 1.0
        np.testing.assert_allclose(amp, cont, rtol=5e-3, atol=1e-12)
