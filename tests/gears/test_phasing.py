"""Planetary mesh phasing: seed 004 Tables 4-1/4-2 and the seed 003 bench."""

from __future__ import annotations

import math

import numpy as np
import pytest

from geardyn.gears.geometry import GearBlank, mesh_geometry
from geardyn.gears.pe_stiffness import mesh_stiffness
from geardyn.gears.phasing import planet_mesh_phases, sun_ring_phase


def test_seed004_table_4_1():
    psi = [0.0, 2 * math.pi / 3, 4 * math.pi / 3]
    rs, rr = planet_mesh_phases(19, 83, psi)
    # rsn: 0, −1/3, −2/3 → fractional 0, 2/3, 1/3; rrn: 0, 2/3, 1/3
    assert rs == pytest.approx([0, 2 / 3, 1 / 3])
    assert rr == pytest.approx([0, 2 / 3, 1 / 3])


def test_seed003_reaction_set():
    # seed 003 bench (z_s 16, z_r 65): Z_r ψ/2π fractional 0, 2/3, 1/3; Z_s ψ/2π 0, 1/3, 2/3
    rs, rr = planet_mesh_phases(16, 65, [0.0, 2 * math.pi / 3, 4 * math.pi / 3])
    assert rr == pytest.approx([0, 2 / 3, 1 / 3])
    assert np.mod(-rs, 1.0) == pytest.approx([0, 1 / 3, 2 / 3])


def test_seed004_sun_ring_phase():
    a20 = math.radians(20)
    ring = mesh_geometry(
        GearBlank(32, form_radius=0.0),
        GearBlank(83, internal=True, addendum_coef=1.25),
        0.016,
        a20,
        0.245,
    )
    args = (0.016, a20, ring.base_radius[0], -ring.u_start, ring.base_pitch)
    # Table 4-2: rrs = 0.5859 mesh cycle (notes §4.1 recompute 0.58585), with the inv() quirk
    assert sun_ring_phase(*args) == pytest.approx(0.58585, abs=2e-5)
    # the involute form (t_b = 25.6097 mm instead of 26.7327 mm) shifts it by Δt_b/p_b
    d = sun_ring_phase(*args, thesis_quirk=False) - sun_ring_phase(*args)
    assert abs(d) == pytest.approx((26.7327 - 25.6097) / 47.2341, abs=1e-4)


def test_table_periodic_interpolation():
    g = mesh_geometry(GearBlank(20), GearBlank(30), 0.002, math.radians(20), 0.02)
    t = mesh_stiffness(g, n_per_cycle=64)
    x = np.array([0.25, 1.25, 7.25, -0.75])
    assert np.allclose(t.at(x), t.total[16])
