"""Bearing connecting forces vs Hertz / Stribeck hand calculations."""

from __future__ import annotations

import math

import numpy as np
import pytest

from geardyn.bearings.frequencies import bearing_frequencies
from geardyn.bearings.hertz import (
    ball_race_stiffness,
    ellipticity,
    point_contact_stiffness,
    reduced_modulus,
    roller_race_stiffness,
)
from geardyn.models.transmission.assembly import pitch_rotation
from geardyn.models.transmission.kernels import bearing_forces

E, NU = 179e9, 0.3  # seed 002 Table 3
EP = reduced_modulus(E, NU, E, NU)
D, DM, FI, FO, Z = 0.0127, 0.080, 0.51, 0.5175, 11


def test_sphere_on_flat_is_classical_hertz() -> None:
    """κ = 1 limit: δ = (9 Q² / (16 R E*²))^(1/3) for a sphere of radius R on a flat."""
    r = 0.01
    k = point_contact_stiffness(r, r, EP)  # both principal relative radii = r
    q = 1000.0
    estar = EP / 2
    delta = (9 * q * q / (16 * r * estar**2)) ** (1 / 3)
    assert q / delta**1.5 == pytest.approx(k, rel=1e-9)


def test_ellipticity_vs_hamrock_brewe_approximations() -> None:
    """Exact κ, ℱ, ℰ vs Hamrock & Brewe (1983) fits (stated accuracy ≈ 3 %)."""
    for rx, ry in [(0.005, 0.05), (0.0054, 0.166), (0.0073, 0.129)]:
        k, ff, ee = ellipticity(rx, ry)
        a = ry / rx
        assert k == pytest.approx(1.0339 * a**0.6360, rel=0.03)
        assert ee == pytest.approx(1.0003 + 0.5968 / a, rel=0.03)
        assert ff == pytest.approx(1.5277 + 0.6023 * math.log(a), rel=0.03)


def test_ball_stiffness_seed_table3_order_of_magnitude() -> None:
    """Harris (steel, E = 207.7 GPa): δ = 2.79e-4 δ* Q^(2/3) Σρ^(1/3) mm; for the inner
    contact of the Table 3 bearing, evaluate with δ* from the exact ellipticity and compare."""
    ki, ko, kt = ball_race_stiffness(D, DM, FI, FO, reduced_modulus(207.7e9, 0.3, 207.7e9, 0.3))
    g = D / DM
    rho = 4 / (D * 1e3) + 2 / (D * 1e3) * g / (1 - g) - 1 / (FI * D * 1e3)  # 1/mm
    rx = 1 / (2 / D + 2 / D * g / (1 - g))
    ry = 1 / (2 / D - 1 / (FI * D))
    k, ff, ee = ellipticity(rx, ry)
    dstar = 2 * ff / math.pi * (math.pi / (2 * k * k * ee)) ** (1 / 3)
    q = 500.0
    delta_mm = 2.79e-4 * dstar * q ** (2 / 3) * rho ** (1 / 3)
    assert q / (delta_mm * 1e-3) ** 1.5 == pytest.approx(ki, rel=0.01)
    assert kt < min(ki, ko)


def _call(kind, k, a0, pd, x, y=0.0, z=0.0, theta=0.0, spall=(0.0, 0.0, 0.0), z_el=Z):
    q = np.zeros(6)
    q[0], q[1], q[2], q[5] = x, y, z, theta
    v = np.zeros(6)
    f = np.zeros(6)
    diss = np.zeros(5)
    bl = np.zeros((1, 3))
    bearing_forces(
        q, v, f, diss, np.array([0]), np.array([kind]), np.array([z_el]), np.array([k]),
        np.array([a0]), np.array([pd]), np.array([0.5 * (1 - D / DM)]), np.array([DM]),
        np.array([0.0]), np.array([0.0]), np.array([1e8]), np.array([0.0]),
        np.array([spall[0]]), np.array([spall[1]]), np.array([spall[2]]),
        *pitch_rotation(np.array([z_el])), bl,
    )
    # action-reaction: the force on the housing is minus the force on the shaft
    assert bl[0, 1:] == pytest.approx(-f[:2], abs=1e-9 * (1 + np.abs(f[:2]).max()))
    return f, bl[0, 0]


@pytest.mark.parametrize("kind", [0, 1])
def test_radial_load_matches_stribeck_integral(kind: int) -> None:
    """Zero clearance: F_r = Z Q_max J_r(0.5), J_r = 0.2288 (point) / 0.2453 (line)
    (Harris & Kotzalas, Table 7.1), averaged over the cage position."""
    if kind == 0:
        k = ball_race_stiffness(D, DM, FI, FO, EP)[2]
        a0, n_exp, jr, z_el = (FI + FO - 1) * D, 1.5, 0.2288, Z
    else:
        k = roller_race_stiffness(0.0078)
        a0, n_exp, jr, z_el = 0.0, 10 / 9, 0.2453, 18
    dr = 10e-6
    qmax = k * dr**n_exp
    pitch = 2 * math.pi / z_el / (0.5 * (1 - D / DM))
    fr = np.mean([-_call(kind, k, a0, 0.0, dr, theta=t, z_el=z_el)[0][0]
                  for t in np.linspace(0, pitch, 64, endpoint=False)])
    assert fr == pytest.approx(z_el * qmax * jr, rel=0.01)


def test_clearance_and_axial_geometry() -> None:
    k = ball_race_stiffness(D, DM, FI, FO, EP)[2]
    a0 = (FI + FO - 1) * D
    pd = 45e-6
    f, _ = _call(0, k, a0, pd, 20e-6)  # inside the 22.5 µm radial play
    assert np.abs(f).max() == 0.0
    # pure axial displacement, zero clearance: δ = √(A0² + u²) − A0 on every ball
    u = 50e-6
    f, qs = _call(0, k, a0, 0.0, 0.0, z=u)
    delta = math.hypot(a0, u) - a0
    assert -f[2] == pytest.approx(Z * k * delta**1.5 * u / math.hypot(a0, u), rel=1e-9)
    assert qs == pytest.approx(Z * k * delta**1.5, rel=1e-9)


def test_ball_passage_at_bpfo_and_spall() -> None:
    """Force on a radially displaced ring over one shaft revolution: its fundamental order
    is the BPFO order of geardyn.bearings.frequencies; an outer-race spall in the loaded zone
    adds a dip once per ball pass."""
    k = ball_race_stiffness(D, DM, FI, FO, EP)[2]
    a0 = (FI + FO - 1) * D
    n = 4096
    revs = 16
    th = np.arange(n) / n * 2 * math.pi * revs
    fx = -np.array([_call(0, k, a0, 45e-6, 40e-6, theta=t)[0][0] for t in th])
    spec = np.abs(np.fft.rfft(fx - fx.mean()))
    orders = np.fft.rfftfreq(n, 1 / (n / revs))
    bpfo = bearing_frequencies(1.0, 0.0, Z, D, DM).bpfo
    peak = orders[np.argmax(spec)]
    assert peak == pytest.approx(bpfo, abs=1 / revs)
    fs = -np.array([_call(0, k, a0, 45e-6, 40e-6, theta=t, spall=(0.0, 0.19, 100e-6))[0][0]
                   for t in th])
    assert (fs <= fx + 1e-9).all()  # the spall only removes load
    assert (fx - fs).max() > 0.2 * fx.max()  # a ball over the spall loses its load
    # dips once per ball pass: BPFO is also the fundamental of the loss
    dspec = np.abs(np.fft.rfft(fx - fs - (fx - fs).mean()))
    assert orders[np.argmax(dspec)] == pytest.approx(bpfo, abs=1 / revs)
