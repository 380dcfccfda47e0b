"""Timoshenko shaft element vs analytical beam theory (issue 6 acceptance: within 1 %)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from geardyn.elements import ShaftSection
from geardyn.errors import InputError
from geardyn.models.transmission.assembly import assemble_shaft, modal_analysis

# seed 002 Table 1 shaft
SEED = ShaftSection(0.060, 0.045, 210e9, 0.3, 7800.0)
L = 0.5


def _plane_block(K, M):
    """x–z bending DOFs (x, θy) of every node."""
    n = K.shape[0] // 6
    idx = np.array([[6 * i, 6 * i + 4] for i in range(n)]).ravel()
    return K[np.ix_(idx, idx)], M[np.ix_(idx, idx)], n


def timoshenko_ss(n: int, length: float, s: ShaftSection) -> float:
    """Exact natural frequency (Hz) of mode n of a simply supported Timoshenko beam:
    E I k⁴ − ω² (ρA + ρI k² (1 + E/(κG))) + ω⁴ ρ² I/(κG) = 0, k = nπ/L (lower root)."""
    E, G, k_s = s.youngs_modulus, s.shear_modulus, s.kappa
    rho, A, I = s.density, s.area, s.second_moment
    k = n * math.pi / length
    a = rho * rho * I / (k_s * G)
    b = -(rho * A + rho * I * k * k * (1 + E / (k_s * G)))
    c = E * I * k**4
    w2 = (-b - math.sqrt(b * b - 4 * a * c)) / (2 * a)
    return math.sqrt(w2) / (2 * math.pi)


@pytest.mark.parametrize("elements", [5, 20])
def test_simply_supported_timoshenko_within_1_percent(elements: int) -> None:
    K, M = assemble_shaft(SEED, L, elements)
    kb, mb, n = _plane_block(K, M)
    fixed = [0, 2 * (n - 1)]  # x at both ends
    f, _ = modal_analysis(mb, kb, fixed)
    modes = 1 if elements == 5 else 3
    for m in range(1, modes + 1):
        ref = timoshenko_ss(m, L, SEED)
        assert abs(f[m - 1] / ref - 1) < 0.01, (m, f[m - 1], ref)
    # shear matters for this stubby shaft: Euler-Bernoulli would be > 3 % higher for mode 2
    eb2 = (2 * math.pi / L) ** 2 * math.sqrt(
        SEED.youngs_modulus * SEED.second_moment / (SEED.density * SEED.area)
    ) / (2 * math.pi)
    if elements == 20:
        assert eb2 / f[1] > 1.03


def test_slender_beam_tends_to_euler_bernoulli() -> None:
    s = ShaftSection(0.02, 0.0, 210e9, 0.3, 7800.0)
    length = 2.0
    K, M = assemble_shaft(s, length, 20)
    kb, mb, n = _plane_block(K, M)
    f, _ = modal_analysis(mb, kb, [0, 2 * (n - 1)])
    c = math.sqrt(s.youngs_modulus * s.second_moment / (s.density * s.area))
    for m in (1, 2, 3):
        ref = (m * math.pi / length) ** 2 * c / (2 * math.pi)
        assert abs(f[m - 1] / ref - 1) < 0.01


def test_free_free_torsion_and_axial() -> None:
    K, M = assemble_shaft(SEED, L, 20)
    n = K.shape[0] // 6
    it = np.arange(n) * 6 + 5
    iz = np.arange(n) * 6 + 2
    ft, _ = modal_analysis(M[np.ix_(it, it)], K[np.ix_(it, it)])
    fa, _ = modal_analysis(M[np.ix_(iz, iz)], K[np.ix_(iz, iz)])
    assert ft[0] < 1e-3 and fa[0] < 1e-3  # rigid rotation / translation
    ct = math.sqrt(SEED.shear_modulus / SEED.density)
    ca = math.sqrt(SEED.youngs_modulus / SEED.density)
    for m in (1, 2):
        assert abs(ft[m] / (m * ct / (2 * L)) - 1) < 0.01
        assert abs(fa[m] / (m * ca / (2 * L)) - 1) < 0.01


def test_mass_matrix_total_mass_and_inertia() -> None:
    K, M = assemble_shaft(SEED, L, 5)
    n = K.shape[0] // 6
    ones = np.zeros(6 * n)
    ones[0::6] = 1.0
    assert ones @ M @ ones == pytest.approx(SEED.density * SEED.area * L, rel=1e-12)
    rot = np.zeros(6 * n)
    rot[5::6] = 1.0
    assert rot @ M @ rot == pytest.approx(SEED.density * SEED.polar_moment * L, rel=1e-12)
    # rigid rotation about z and rigid translation produce no elastic force
    assert np.abs(K @ (1e3 * rot)).max() < 1e-6
    assert np.abs(K @ ones).max() < 1e-6


def test_bad_section_is_named() -> None:
    with pytest.raises(InputError, match="inner_diameter"):
        ShaftSection(0.05, 0.06)


def _whirl(M, K, G, omega, fixed):
    """Damped natural frequencies (Hz) of M q̈ + Ω G q̇ + K q = 0 (state space)."""
    n = M.shape[0]
    free = np.setdiff1d(np.arange(n), fixed)
    m, k, g = (a[np.ix_(free, free)] for a in (M, K, G))
    nf = free.size
    minv = np.linalg.inv(m)
    A = np.block([[np.zeros((nf, nf)), np.eye(nf)], [-minv @ k, -omega * minv @ g]])
    lam = np.linalg.eigvals(A)
    f = np.abs(lam.imag[lam.imag > 0]) / (2 * math.pi)
    return np.sort(f[f > 1.0])


def test_gyroscopic_whirl_of_rayleigh_beam() -> None:
    """Simply supported spinning Rayleigh beam (shear suppressed: κ → ∞): mode 1 forward
    and backward whirl solve (ρA + ρI k²) ω² ∓ ρJ k² Ω ω − E I k⁴ = 0 (e.g. Genta, Dynamics
    of Rotating Systems, 2005, §4); FE with 20 elements within 1 %."""
    from geardyn.elements import timoshenko_gyroscopic

    class Rayleigh(ShaftSection):
        @property
        def kappa(self) -> float:  # no shear deformation (Φ → 0)
            return 1e9

    s = Rayleigh(0.10, 0.0, 210e9, 0.3, 7800.0)
    length, ne = 0.25, 20
    K, M = assemble_shaft(s, length, ne)
    G = np.zeros_like(K)
    ge = timoshenko_gyroscopic(length / ne, s)
    for e in range(ne):
        G[6 * e : 6 * e + 12, 6 * e : 6 * e + 12] += ge
    n = ne + 1
    fixed = [0, 1, 6 * (n - 1), 6 * (n - 1) + 1, 2, 5]  # x, y at both ends; z, θz at one
    k = math.pi / length
    rho, A, I = s.density, s.area, s.second_moment
    a = rho * A + rho * I * k * k
    f0 = _whirl(M, K, G, 0.0, fixed)
    w0 = math.sqrt(s.youngs_modulus * I * k**4 / a) / (2 * math.pi)
    assert abs(f0[0] / w0 - 1) < 0.01
    omega = 4.0 * 2 * math.pi * w0  # spin 4× the first critical frequency
    f = _whirl(M, K, G, omega, fixed)
    b = 2 * rho * I * k * k * omega
    c = s.youngs_modulus * I * k**4
    wf = (b + math.sqrt(b * b + 4 * a * c)) / (2 * a) / (2 * math.pi)
    wb = (-b + math.sqrt(b * b + 4 * a * c)) / (2 * a) / (2 * math.pi)
    assert wb < w0 < wf and wf / wb > 1.2  # a strong, measurable split
    assert min(abs(f / wb - 1)) < 0.01
    assert min(abs(f / wf - 1)) < 0.01
