"""GTDT identities on FRFs of a known M, C, K model (seed 003 §5.3, notes §2.7) and the
planet-pass sideband pattern of seed 003 §4.1."""

from __future__ import annotations

import numpy as np
import pytest

from geardyn import analyze_kinematics, load_config
from geardyn.errors import InputError
from geardyn.kinematics import characteristic_frequencies
from geardyn.sensors import dominant_carrier_orders, planet_pass_signal
from geardyn.signal import (
    amplitude_spectrum,
    external_responses,
    frf_from_mck,
    gtdt,
    path_contributions,
    reconstruct,
    spectral_markers,
)


def chain_model(n=6):
    """Spring-mass chain (grounded at both ends) plus one extra spring 0–3: DOF pairs with no
    spring between them have Z_ij = 0 at every frequency."""
    m = np.diag(np.linspace(1.0, 2.0, n))
    k = np.zeros((n, n))
    springs = [(i, i + 1, 1e4 * (1 + 0.1 * i)) for i in range(n - 1)] + [(0, 3, 3e3)]
    for i, j, kk in springs:
        k[[i, j], [i, j]] += kk
        k[i, j] -= kk
        k[j, i] -= kk
    k[0, 0] += 2e4
    k[-1, -1] += 2e4
    c = 1e-3 * k + 0.5 * m
    connected = {(i, j) for i, j, _ in springs} | {(j, i) for i, j, _ in springs}
    return m, c, k, connected


def test_gtdt_identities_on_known_model():
    m, c, k, connected = chain_model()
    n = m.shape[0]
    omega = np.linspace(5.0, 300.0, 40)
    H = frf_from_mck(m, c, k, omega)
    g = gtdt(H)
    Z = k[None] - omega[:, None, None] ** 2 * m[None] + 1j * omega[:, None, None] * c[None]
    scale = np.abs(g.direct).max()
    for i in range(n):
        for j in range(n):
            if i == j:
                # T^D_ii = 1/(Z_ii H_ii)  (5.14)
                np.testing.assert_allclose(g.direct[:, i, i], 1 / (Z[:, i, i] * H[:, i, i]),
                                           rtol=1e-9)
                continue
            # T^D_ij = −Z_ij/Z_ii (5.13), from the model matrices (not from H)
            np.testing.assert_allclose(g.direct[:, i, j], -Z[:, i, j] / Z[:, i, i],
                                       rtol=1e-8, atol=1e-10 * scale)
            if (i, j) not in connected:
                assert np.max(np.abs(g.direct[:, i, j])) < 1e-10 * scale
            else:
                assert np.min(np.abs(g.direct[:, i, j])) > 1e-3
    # T^G_ij = H_ij/H_jj (5.8)
    np.testing.assert_allclose(g.global_[:, 1, 4], H[:, 1, 4] / H[:, 4, 4], rtol=1e-12)


def test_gtdt_exact_reconstruction_and_external_responses():
    m, c, k, _ = chain_model()
    omega = np.linspace(5.0, 300.0, 25)
    H = frf_from_mck(m, c, k, omega)
    rng = np.random.default_rng(7)
    f = np.zeros((omega.size, m.shape[0]), dtype=complex)
    f[:, [1, 4]] = rng.normal(size=(omega.size, 2)) + 1j * rng.normal(size=(omega.size, 2))
    x = np.einsum("fij,fj->fi", H, f)
    g = gtdt(H)
    # x^ext_j = H_jj f_j (5.19): zero where no external force acts
    xe = external_responses(g, x)
    np.testing.assert_allclose(xe, np.diagonal(H, axis1=1, axis2=2) * f, atol=1e-12 * abs(x).max())
    # (5.21): sum of path contributions returns x
    np.testing.assert_allclose(reconstruct(g, x), x, rtol=1e-9, atol=1e-14)
    ppc = path_contributions(g, x)
    assert ppc.shape == (omega.size, 6, 6)


def test_gtdt_bad_input():
    with pytest.raises(InputError, match="H:"):
        gtdt(np.ones((3, 2, 4)))
    g = gtdt(np.eye(3) + 0.1)
    with pytest.raises(InputError, match="x: operational responses"):
        reconstruct(g, np.ones(4))


# --- planet-pass model, seed 003 §4.1 -------------------------------------------------------

def bench_carrier_hz():
    kin = analyze_kinematics(load_config("examples/hammami_back_to_back.toml"))
    f = characteristic_frequencies(kin, {"motor": 1498.5})
    links = f.links.set_index("link")
    return float(links.loc["carrier", "hz"]), f


def test_planet_pass_sideband_pattern_of_seed003():
    f_c, _ = bench_carrier_hz()
    assert f_c == pytest.approx(4.93333, abs=1e-5)  # notes §4.1
    fs, revs = 8192.0, 16
    t = np.arange(int(round(revs / f_c * fs))) / fs
    x = planet_pass_signal(2 * np.pi * f_c * t, 3, 65, amplitudes=[1.0, 0.6, 0.4])
    spec = amplitude_spectrum(x, fs)
    found = []
    for lo, hi in ((250, 400), (580, 700), (900, 1000)):
        sel = spec.sel(frequency=slice(lo, hi))
        found.append(float(sel["frequency"][int(np.argmax(sel.values))]))
    res = fs / t.size
    # seed 003 §4.1: largest components at 325.6, 636.4 and 962.0 Hz
    np.testing.assert_allclose(found, [325.6, 636.4, 962.0], atol=max(0.06, res / 2))
    assert dominant_carrier_orders(65, 3) == [66, 129, 195]
    np.testing.assert_allclose(found, np.array([66, 129, 195]) * f_c, atol=res / 2)
    # the printed sign of eq 4.13 (+Z_r ψ) would put them at 64 and 131 carrier orders
    y = planet_pass_signal(2 * np.pi * f_c * t, 3, 65, [1.0, 0.6, 0.4], mesh_phase_sign=1)
    sy = amplitude_spectrum(y, fs).sel(frequency=slice(580, 700))
    assert float(sy["frequency"][int(np.argmax(sy.values))]) == pytest.approx(131 * f_c, abs=res)


def test_centred_gating_keeps_lobes_whole_for_offset_planets():
    th = np.linspace(0, 4 * np.pi, 20_001)
    psi = 2 * np.pi * np.arange(3) / 3
    d = np.pi / 3  # test-set planets offset by π/3 (seed 003)
    a = planet_pass_signal(th, 3, 65, planet_angles=psi + d)
    b = planet_pass_signal(th - d, 3, 65, planet_angles=psi)
    np.testing.assert_allclose(a, b, atol=1e-9)  # a pure rotation of the pattern
    c = planet_pass_signal(th, 3, 65, planet_angles=psi + d, gating="thesis")
    assert np.max(np.abs(c - b)) > 0.5  # printed (4.12) gate cuts the lobes mid-way
    # counter-phasing of the two rings: window sum (amplitude envelope) of one set is zero
    # where the other, offset by π/3, is at its maximum
    env = planet_pass_signal(np.array([np.pi / 3]), 3, 1, planet_angles=psi)  # lobe peak
    env_off = planet_pass_signal(np.array([np.pi / 3]), 3, 1, planet_angles=psi + d)
    assert abs(env[0]) > 0.4 and abs(env_off[0]) < 1e-12


def test_annotation_markers_for_the_bench():
    _, f = bench_carrier_hz()
    mk = spectral_markers(f)
    mesh = mk[mk.kind == "mesh"]["hz"].values
    assert np.any(np.isclose(mesh, 1498.5 / 60 * 1040 / 81))  # f_m, notes §4.1
    dom = np.sort(mk[mk.kind == "planet_dominant"]["hz"].values)
    for target in (325.6, 636.4, 962.0):
        assert np.min(np.abs(dom - target)) < 0.05
    shaft = mk[mk.kind == "shaft"]["order"].values
    assert np.any(np.isclose(shaft, 1.0)) and np.any(np.isclose(shaft, 16 / 81))


def test_annotation_bearing_and_planetary_markers():
    from geardyn.config import parse_config

    inch = 0.0254
    cfg = parse_config({
        "name": "shaft + planetary", "frame": "housing",
        "links": ["housing", "shaft", "out", "carrier"],
        "parallel": [{"name": "stage", "a": {"link": "shaft", "teeth": 20},
                      "b": {"link": "out", "teeth": 60}}],
        "planetary": [{"name": "ps", "sun": "out", "ring": "housing", "carrier": "carrier",
                       "sun_teeth": 20, "planet_teeth": 30, "ring_teeth": 80, "n_planets": 4}],
        "bearings": [{"name": "shaft_DE", "inner": "shaft", "outer": "housing", "n_elements": 9,
                      "element_diameter_m": 0.3126 * inch, "pitch_diameter_m": 1.537 * inch}],
    })
    f = characteristic_frequencies(analyze_kinematics(cfg), {"shaft": 1797.0})
    mk = spectral_markers(f)
    bpfo = mk[mk.label.str.startswith("1BPFO shaft_DE")]
    assert float(bpfo.hz.iloc[0]) == pytest.approx(3.5848 * 29.95, abs=0.01)  # hand value
    f_c = 29.95 * 20 / 60 * 20 / 100
    dom = mk[mk.kind == "planet_dominant"].hz.values
    # Z_r = 80, N = 4: h·Z_r is a multiple of N → dominant exactly at the mesh harmonics
    np.testing.assert_allclose(np.sort(dom), [80 * f_c, 160 * f_c, 240 * f_c], rtol=1e-9)
