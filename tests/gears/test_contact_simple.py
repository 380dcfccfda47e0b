"""Johnson contact law (seed 002 eqs 8-9), square wave (seed 003 eqs 1.11-1.14), ISO 6336-1."""

from __future__ import annotations

import math

import numpy as np
import pytest

from geardyn.errors import InputError
from geardyn.gears.contact import (
    force_from_deflection,
    johnson_deflection,
    johnson_modulus,
    total_deflection,
)
from geardyn.gears.simple import (
    henriot_mean_stiffness,
    iso_mesh_stiffness,
    iso_q_prime,
    iso_single_pair_stiffness,
    square_wave,
    square_wave_fourier,
    square_wave_mean,
)


def test_johnson_values_by_hand():
    # seed 002 Table 2 material: E = 202 GPa, ν = 0.255 → E* = E/(2(1−ν²)) = 202e9/1.869950
    e_star = johnson_modulus(202e9, 0.255)
    assert e_star == pytest.approx(202e9 / 1.86995, rel=1e-6)
    # F = 1000 N, L = 25 mm, ΔR = 20 mm: E* = 1.080243e11 Pa, c = π L E* = 8.48421e9 N/m;
    # δ = F/c (ln(4 c ΔR / F) − 1) = 1.178661e-7 × (ln(678736.6) − 1) = 1.178661e-7 × 12.42799
    #   = 1.464839e-6 m
    c = math.pi * 0.025 * e_star
    assert c == pytest.approx(8.48421e9, rel=1e-5)
    d = johnson_deflection(1000.0, 0.025, e_star, 0.02)
    assert float(d) == pytest.approx(1.464839e-6, rel=1e-5)
    # δ(F)/F decreases with load (softening log term): nonlinear law
    f = np.array([100.0, 1000.0, 10000.0])
    dd = johnson_deflection(f, 0.025, e_star, 0.02)
    assert np.all(np.diff(dd) > 0) and np.all(np.diff(dd / f) < 0)


def test_eq9_inversion_round_trip():
    e_star = johnson_modulus(206e9, 0.3)
    f = np.array([10.0, 500.0, 5000.0, 20000.0])
    d = total_deflection(f, 4e8, 0.02, e_star, 0.03)
    back = force_from_deflection(d, np.full(4, 4e8), 0.02, e_star, np.full(4, 0.03))
    assert np.allclose(back, f, rtol=1e-9)
    assert force_from_deflection(
        np.array([-1e-6, 0.0]), np.full(2, 4e8), 0.02, e_star, np.full(2, 0.03)
    ).tolist() == [0.0, 0.0]


def test_johnson_rejects_negative_force():
    with pytest.raises(InputError):
        johnson_deflection(-1.0, 0.01, 1e11, 0.01)


def test_square_wave_eq_1_11_to_1_13():
    kmax, kmin, c = 5e8, 3e8, 1.6
    t = np.linspace(0, 4, 40001)[:-1]
    k = square_wave(t, kmax, kmin, c)
    assert k.mean() == pytest.approx(square_wave_mean(kmax, kmin, c), rel=1e-4)
    # eq 1.12 by hand: 5e8·0.6 + 0.4·3e8 = 4.2e8
    assert square_wave_mean(kmax, kmin, c) == pytest.approx(4.2e8)
    # Fourier series (eq 1.11) converges to the square wave away from the jumps
    kf = square_wave_fourier(t, kmax, kmin, c, n_harmonics=400)
    ph = np.mod(t, 1.0)
    away = (np.abs(ph - 0.6) > 0.02) & (ph > 0.02) & (ph < 0.98)
    assert np.max(np.abs(kf[away] - k[away])) < 0.02 * (kmax - kmin)
    with pytest.raises(InputError):
        square_wave(t, kmax, kmin, 2.5)


def test_iso_6336_worked_case_by_hand():
    # z1 = 20, z2 = 40, x = 0, α_n = 20°, β = 0, h_fP = 1.25 m_n, solid steel blanks:
    # q' = 0.04723 + 0.15551/20 + 0.25791/40 = 0.06145325 mm·µm/N → c'_th = 16.27253 N/(mm·µm)
    # C_B = 1 + 0.5(1.2 − 1.25) = 0.975, C_M = 0.8 → c' = 12.69257 N/(mm·µm)
    assert iso_q_prime(20, 40) == pytest.approx(0.06145325, rel=1e-9)
    c = iso_single_pair_stiffness(20, 40)
    assert c == pytest.approx(12.69257e9, rel=1e-6)
    # c_γα = c'(0.75 ε_α + 0.25) with ε_α = 1.6: 12.69257 × 1.45 = 18.40423
    assert iso_mesh_stiffness(c, 1.6) == pytest.approx(18.40423e9, rel=1e-6)
    # helical β = 15°: z_n = z/cos³β and c' ∝ cos β
    ch = iso_single_pair_stiffness(20, 40, helix_angle=math.radians(15))
    cb3 = math.cos(math.radians(15)) ** 3
    q = 0.04723 + 0.15551 * cb3 / 20 + 0.25791 * cb3 / 40
    assert ch == pytest.approx(0.8 * 0.975 * math.cos(math.radians(15)) / q * 1e9, rel=1e-9)
    # light load: (F/b / 100 N/mm)^0.25
    cl = iso_single_pair_stiffness(20, 40, load_per_width=50e3)
    assert cl == pytest.approx(c * 0.5**0.25, rel=1e-12)


def test_henriot_matches_iso_theoretical():
    # seed 003 eq 1.14: k̄ = b/(A1 + A2/z1 + A3/z2), A = ISO C1..C3; b = 20 mm, z = 20/40
    assert henriot_mean_stiffness(0.02, 20, 40) == pytest.approx(20 / 0.06145325 * 1e6, rel=1e-9)
