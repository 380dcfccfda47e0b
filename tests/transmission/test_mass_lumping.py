"""Lumped (HRZ diagonal) mass of the Timoshenko shaft element (issue 12) against closed forms:
simply supported Timoshenko beam (frequency equation of tests/transmission/test_elements.py),
free-free Euler-Bernoulli beam (β₁L = 4.7300408, e.g. Blevins, *Formulas for Natural Frequency
and Mode Shape*, 1979, Table 8-1), free-free rod (ω_n = nπc/L, bracketed by the lumped (below)
and consistent (above) discretisations), the element's highest frequency (2c/L lumped,
√12 c/L consistent: Cook et al., *Concepts and Applications of FEA*, 2002, §11.3-11.4), and the
seed 002 transmission with either mass."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import eigh

from geardyn.config.loader import load_config, parse_config
from geardyn.elements import ShaftSection, timoshenko_element
from geardyn.errors import ConfigError, InputError
from tests.transmission.test_elements import timoshenko_ss

SEED = ShaftSection(0.060, 0.045, 210e9, 0.3, 7800.0)
L = 0.5
EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "seed002_transmission.toml"


def _shaft(s: ShaftSection, length: float, ne: int, mass: str) -> tuple[np.ndarray, np.ndarray]:
    """(K, M) of a uniform shaft of ``ne`` elements (assembled here, independent of
    :mod:`geardyn.models.transmission.assembly`)."""
    n = 6 * (ne + 1)
    K, M = np.zeros((n, n)), np.zeros((n, n))
    ke, me = timoshenko_element(length / ne, s, mass)
    for e in range(ne):
        sl = slice(6 * e, 6 * e + 12)
        K[sl, sl] += ke
        M[sl, sl] += me
    return K, M


def _freqs(K: np.ndarray, M: np.ndarray, dofs: np.ndarray, fixed: list[int] = ()) -> np.ndarray:
    keep = np.setdiff1d(np.arange(dofs.size), fixed)
    idx = dofs[keep]
    w2 = eigh(K[np.ix_(idx, idx)], M[np.ix_(idx, idx)], eigvals_only=True)
    return np.sqrt(np.clip(w2, 0.0, None)) / (2 * math.pi)


def _bending_dofs(ne: int) -> np.ndarray:
    return np.array([[6 * i, 6 * i + 4] for i in range(ne + 1)]).ravel()


def test_lumped_element_is_diagonal_and_keeps_mass_and_inertia() -> None:
    _, M = timoshenko_element(0.1, SEED, "lumped")
    assert np.count_nonzero(M - np.diag(np.diag(M))) == 0
    m, jp = SEED.density * SEED.area * 0.1, SEED.density * SEED.polar_moment * 0.1
    for d in (0, 1, 2):  # each direction carries the element mass, half per node
        assert M[d, d] + M[6 + d, 6 + d] == pytest.approx(m, rel=1e-12)
        assert M[d, d] == pytest.approx(M[6 + d, 6 + d], rel=1e-12)
    assert M[5, 5] + M[11, 11] == pytest.approx(jp, rel=1e-12)
    # Euler-Bernoulli limit (Φ → 0): HRZ rotation inertia ρAL³/78 + rotary inertia ρIL/2
    s = ShaftSection(0.001, 0.0, 210e9, 0.3, 7800.0)
    _, Ms = timoshenko_element(1.0, s, "lumped")
    ref = s.density * s.area / 78 + 0.5 * s.density * s.second_moment
    assert Ms[4, 4] == pytest.approx(ref, rel=1e-4)
    assert np.all(np.diag(M) > 0)


def test_unknown_mass_kind_is_named() -> None:
    with pytest.raises(InputError, match="mass"):
        timoshenko_element(0.1, SEED, "diagonal")


@pytest.mark.parametrize("mass", ["consistent", "lumped"])
def test_simply_supported_timoshenko_both_masses(mass: str) -> None:
    """Modes 1-3 within 1 % at 20 elements; the error shrinks from 5 to 20 elements."""
    err = {}
    for ne in (5, 20):
        K, M = _shaft(SEED, L, ne, mass)
        f = _freqs(K, M, _bending_dofs(ne), [0, 2 * ne])
        err[ne] = [abs(f[m - 1] / timoshenko_ss(m, L, SEED) - 1) for m in (1, 2, 3)]
    assert max(err[20]) < 0.01, err
    assert err[20][1] < err[5][1]


@pytest.mark.parametrize("mass", ["consistent", "lumped"])
def test_free_free_euler_bernoulli_first_bending(mass: str) -> None:
    """Slender free-free beam: f₁ = (β₁L)² √(EI/(ρAL⁴)) / 2π, β₁L = 4.7300408, within 1 %."""
    s = ShaftSection(0.02, 0.0, 210e9, 0.3, 7800.0)
    length, ne = 2.0, 20
    K, M = _shaft(s, length, ne, mass)
    f = _freqs(K, M, _bending_dofs(ne))
    assert f[1] < 1e-3 * f[2]  # two rigid modes (translation, rotation)
    f1 = f[2]
    ref = 4.7300408**2 * math.sqrt(s.youngs_modulus * s.second_moment
                                   / (s.density * s.area * length**4)) / (2 * math.pi)
    assert f1 == pytest.approx(ref, rel=0.01)


def test_free_free_rod_bracketed_by_lumped_and_consistent() -> None:
    """Axial and torsional modes 1-2: lumped < nπc/(2π L) < consistent, both within 1 % at
    20 elements (rod: ω_lumped = 2c/h sin(kh/2) < ck, ω_consistent > ck)."""
    ne = 20
    ca = math.sqrt(SEED.youngs_modulus / SEED.density)
    ct = math.sqrt(SEED.shear_modulus / SEED.density)
    for dof, c in ((2, ca), (5, ct)):
        idx = np.arange(ne + 1) * 6 + dof
        fl = _freqs(*_shaft(SEED, L, ne, "lumped"), idx)
        fc = _freqs(*_shaft(SEED, L, ne, "consistent"), idx)
        for m in (1, 2):
            ref = m * c / (2 * L)
            assert fl[m] < ref < fc[m]
            assert abs(fl[m] / ref - 1) < 0.01 and abs(fc[m] / ref - 1) < 0.01


def test_element_highest_frequency_and_step_gain() -> None:
    """Seed 002 shaft element (L = 0.1 m): the axial mode bounds the spectrum, 2c/L lumped and
    √12 c/L consistent, so the explicit stable step 2/ω_max grows by √3."""
    c = math.sqrt(SEED.youngs_modulus / SEED.density)
    h = 0.1
    wl = eigh(*timoshenko_element(h, SEED, "lumped"), eigvals_only=True)[-1] ** 0.5
    wc = eigh(*timoshenko_element(h, SEED), eigvals_only=True)[-1] ** 0.5
    assert wl == pytest.approx(2 * c / h, rel=1e-9)
    assert wc == pytest.approx(math.sqrt(12) * c / h, rel=1e-9)


def _cfg(mass: str | None):
    d = load_config(EXAMPLE).model_dump(exclude_none=True)
    if mass is not None:
        d["transmission"]["mass"] = mass
    return parse_config(d)


def test_mass_option_in_config_and_model() -> None:
    from geardyn.models.transmission import build_model, prepare
    from geardyn.models.transmission.simulate import with_mass

    with pytest.raises(ConfigError, match="transmission.mass"):
        _cfg("diagonal")
    cons = _cfg(None)
    assert cons.transmission.mass == "consistent"
    lum = _cfg("lumped")
    mc = with_mass(build_model(cons), cons.transmission)
    ml = with_mass(build_model(lum), lum.transmission)
    assert np.count_nonzero(ml.M - np.diag(np.diag(ml.M))) == 0
    assert with_mass(ml, lum.transmission) is ml
    # same rigid-body mass and inertia of every shaft (translation x, rotation z)
    for dof in (0, 5):
        e = np.zeros(ml.ndof)
        e[dof::6] = 1.0
        assert e @ ml.M @ e == pytest.approx(e @ mc.M @ e, rel=1e-12)
    pc, pl = prepare(mc, "output"), prepare(ml, "output")
    # the stable step grows by nearly √3 (the axial element mode bounds both)
    assert 1.5 < pl.dt_stable / pc.dt_stable < math.sqrt(3) + 1e-9
    # labelled regression guard (no source): at 5 elements per shaft the elastic modes below
    # 500 Hz move by < 1 % with lumping, those below 700 Hz by < 5 % (3.9 % for 561 Hz)
    f0 = pc.frequencies_hz
    for fmax, tol in ((500.0, 0.01), (700.0, 0.05)):
        sel = (f0 > 1.0) & (f0 < fmax)
        assert np.all(np.abs(pl.frequencies_hz[sel] / f0[sel] - 1) < tol)
