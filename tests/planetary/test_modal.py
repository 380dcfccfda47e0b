"""Modal analysis against seed 003 ch. 3 (notes §4.2) and Lin & Parker (1999) invariants."""

from __future__ import annotations

import math

import numpy as np
import pytest

from geardyn.models.planetary import ShaftSpec, StageSpec, assemble
from geardyn.models.planetary.modal import campbell, modes, strain_energy_table


def test_bench_high_band_carrier_pairs(bench36):
    """Seed 003 Table 3.3 / notes §4.2: carrier-translation pairs 1847.1 and 1888.0 Hz (×2)."""
    r = modes(bench36)
    f = r.freq_hz
    for target in (1847.1, 1888.0):
        hit = np.flatnonzero(np.abs(f - target) < 0.1)
        assert len(hit) == 2, (target, f[(f > 1800) & (f < 1950)])
        assert all(r.mode_type[i] == "translational" for i in hit)
        assert all(r.multiplicity[i] == 2 for i in hit)
        # dominant motion: carrier translation, dominant strain: carrier bearing (Table 3.7)
        for i in hit:
            row = r.table()[i]
            assert ".carrier." in row["dominant_motion"]
            assert "carrier.bearing" in row["dominant_strain"]
    # approximate closed form of the notes (carrier on its bearing + 3 planet bearings)
    assert math.sqrt((4.8e8 + 3 * 3.5e6) / 3.643) / (2 * math.pi) == pytest.approx(1847.1, abs=1.0)


def test_bench_without_flexural_coupling_collapses(bench36):
    """Notes §4.2: without the carrier flexural coupling the pair collapses to 1847.1 ×4."""
    import copy

    m = copy.deepcopy(bench36)
    for s in m.springs:
        if s.name.startswith("carrier_shaft.flex"):
            s.k = 0.0
    f = modes(m).freq_hz
    assert np.sum(np.abs(f - 1847.1) < 0.1) == 4


def test_bench_multiplicity_structure(bench36):
    """R = 1, T = 2, no planet modes for 3 planets; one rigid-body mode at 0 Hz."""
    r = modes(bench36)
    assert r.freq_hz[0] == pytest.approx(0.0, abs=1e-3)
    assert r.mode_type.count("rigid") == 1
    assert "planet" not in r.mode_type
    assert "mixed" not in r.mode_type
    for t, m in zip(r.mode_type[1:], r.multiplicity[1:], strict=True):
        if t == "rotational":
            assert m == 1
        else:
            assert t == "translational" and m in (2, 4)  # 4 = two identical stages degenerate


def test_rotational_modes_planets_move_alike(bench36):
    """Seed 003: in rotational modes all planets of a set have the same modal deflection."""
    r = modes(bench36)
    names = bench36.names
    for i, t in enumerate(r.mode_type):
        if t != "rotational":
            continue
        phi = r.shapes[:, i]
        for st in ("reaction", "test"):
            us = [phi[names.index(f"{st}.planet{p}.u")] for p in (1, 2, 3)]
            assert np.ptp(us) <= 1e-6 * max(np.abs(phi).max(), 1e-30)


def test_energy_bins_sum_to_total(bench36):
    """Tables 3.4/3.5 layout: 36 kinetic bins, spring bins; both sum to the modal energy."""
    r = modes(bench36)
    assert r.kinetic.shape == (36, 36)
    labels, table = strain_energy_table(bench36, r)
    assert len(labels) == 48 + 6  # Table 3.5: 48 bins; + 2 shafts × (torsion, x, y)
    assert labels[0] == "bearing of reaction.carrier (x)"
    assert labels[36] == "mesh reaction.ring-reaction.planet1"  # Table 3.5 index 37
    assert labels[47] == "mesh test.sun-test.planet3"  # index 48
    np.testing.assert_allclose(table[1:].sum(1), 1.0, rtol=1e-12)
    assert np.all(table[:, [11, 14, 17]] == 0.0)  # planet rotation bins: no support
    for i in range(1, 36):
        w2 = (2 * math.pi * r.freq_hz[i]) ** 2
        total = 0.5 * w2  # mass-normalised: ½ ω² φᵀMφ = ½ ω²
        assert r.kinetic[i].sum() == pytest.approx(total, rel=1e-8)
        assert r.strain[i].sum() == pytest.approx(total, rel=1e-6)
    ds = r.to_dataset()
    np.testing.assert_allclose(ds.kinetic_fraction.sum("dof").values[1:], 1.0, rtol=1e-9)
    np.testing.assert_allclose(ds.strain_fraction.sum("spring").values[1:], 1.0, rtol=1e-9)


def test_lin_parker_four_planets_has_planet_modes(lin_parker):
    """Lin & Parker (1999), N = 4 planets: 3 planet-mode frequencies (one per planet DOF),
    each of multiplicity N − 3 = 1, with the central members at rest."""
    r = modes(lin_parker)
    n = len(r.freq_hz)
    assert n == 21
    counts = {t: r.mode_type.count(t) for t in set(r.mode_type)}
    # 3 + 3 rotational (incl. rigid), 6 translational pairs, 3 planet modes (×(N−3)=1 each)
    assert counts["rigid"] == 1
    assert counts["rotational"] == 5
    assert counts["translational"] == 12
    assert counts["planet"] == 3
    for i, t in enumerate(r.mode_type):
        if t == "planet":
            assert r.multiplicity[i] == 1


def test_torsional_reduction_matches_direct_torsional_model(bench12):
    """Model B (12 DOF): with α = 0 the reduced mesh deflections are the thesis eq 4.4 form
    δ_sn = u_s + u_n − u_c, δ_rn = u_r − u_n − u_c; check against a hand-built matrix."""
    st = StageSpec(
        "s", 3, [0.0, 2 * math.pi / 3, 4 * math.pi / 3],
        sun=dict(mass=1.0, inertia=0.01, radius=0.05, bearing=1e8),
        ring=dict(mass=5.0, inertia=0.5, radius=0.15, bearing=1e8, torsional=1e6),
        carrier=dict(mass=2.0, inertia=0.05, radius=0.10, bearing=1e8),
        planet=dict(mass=0.5, inertia=0.002, radius=0.05),
        alpha_s=0.0, alpha_r=0.0, k_sun_mesh=3e8, k_ring_mesh=4e8, planet_bearing=1e8,
        prefix=False,
    )
    m = assemble([st], reduction="torsional")
    k = m.stiffness_matrix()
    names = m.names
    assert names == ["carrier.u", "ring.u", "sun.u", "planet1.u", "planet2.u", "planet3.u"]
    ks, kr = 3e8, 4e8
    hand = np.zeros((6, 6))
    for p in range(3):
        a = np.zeros(6)
        a[[2, 3 + p, 0]] = [1, 1, -1]
        hand += ks * np.outer(a, a)
        b = np.zeros(6)
        b[[1, 3 + p, 0]] = [1, -1, -1]
        hand += kr * np.outer(b, b)
    hand[1, 1] += 1e6 / 0.15**2
    np.testing.assert_allclose(k, hand, rtol=1e-12, atol=1e-3)
    # eq 4.2: carrier mass term I_c/r_c² + N m_p
    assert m.mass_matrix()[0, 0] == pytest.approx(0.05 / 0.1**2 + 3 * 0.5)
    # the bench 12-DOF model is 12 DOF with one rigid-body mode
    r = modes(bench12)
    assert len(r.freq_hz) == 12 and r.mode_type.count("rigid") == 1


def test_transverse_reduction_dofs(lin_parker):
    from geardyn.models.planetary.model import reduction_matrix

    t = reduction_matrix(lin_parker, "transverse")
    assert t.shape == (21, 14)


def test_campbell_zero_speed_matches_modes_and_splits(lin_parker):
    r = modes(lin_parker)
    c = campbell(lin_parker, np.array([0.0, 300.0]), n_modes=21)
    np.testing.assert_allclose(np.sort(c.values[0]), np.sort(r.freq_hz), rtol=1e-6, atol=1e-3)
    # gyroscopic coupling splits translational pairs at speed
    f1 = c.values[1]
    assert not np.allclose(np.sort(f1)[1:5], np.sort(r.freq_hz)[1:5], rtol=1e-6)


def test_shaft_unknown_body_rejected():
    from geardyn.errors import ConfigError

    st = StageSpec("s", 3, [0, 2, 4], sun=dict(mass=1, inertia=1, radius=1),
                   ring=dict(mass=1, inertia=1, radius=1),
                   carrier=dict(mass=1, inertia=1, radius=1),
                   planet=dict(mass=1, inertia=1, radius=1), alpha_s=0.3, alpha_r=0.3,
                   k_sun_mesh=1.0, k_ring_mesh=1.0, planet_bearing=1.0)
    with pytest.raises(ConfigError, match="unknown body 'nope'"):
        assemble([st], [ShaftSpec("x", "s.sun", "nope", 1.0)])
