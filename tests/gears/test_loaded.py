"""Loaded contact: static TE and load sharing (seed 002 eqs 9-13, §2.5)."""

from __future__ import annotations

import numpy as np
import pytest

from geardyn.errors import InputError
from geardyn.gears.faults import Spall
from geardyn.gears.geometry import GearBlank, mesh_geometry
from geardyn.gears.loaded import (
    Corrections,
    TipRelief,
    separation_distance,
    static_transmission_error,
)
from geardyn.gears.pe_stiffness import mesh_stiffness

from .seed002 import A20, seed002_low


@pytest.fixture(scope="module")
def low():
    return seed002_low()


def test_separation_zero_on_path_symmetric_and_quadratic():
    g = mesh_geometry(GearBlank(20), GearBlank(20), 0.003, A20, 0.02)
    inside = np.linspace(g.u_start, g.u_end, 11)
    assert np.all(separation_distance(g, inside) == 0)
    d1, d2 = 1e-4, 2e-4
    s = separation_distance(g, np.array([g.u_start - d1, g.u_end + d1, g.u_end + d2]))
    assert s[0] == pytest.approx(s[1], rel=1e-9, abs=0)  # 20/20: both ends alike
    assert s[2] / s[1] == pytest.approx(4.0, rel=0.05)  # tip corner leaves the flank tangentially


def test_load_sharing_sums_to_one(low):
    r = static_transmission_error(low, 200.0, n_per_cycle=16)
    assert np.allclose(r.load_sharing.sum(axis=1), 1.0, atol=1e-6)
    assert np.all(r.ste > 0)


def test_ste_grows_with_torque_and_is_softening_to_linear(low):
    r1 = static_transmission_error(low, 50.0, n_per_cycle=8)
    r2 = static_transmission_error(low, 500.0, n_per_cycle=8)
    assert np.all(r2.ste > r1.ste)
    # mean linear PE stiffness vs loaded secant stiffness: same order (Johnson term < Hertz const)
    k_lin = mesh_stiffness(low, n_per_cycle=8).total
    ratio = r2.secant_stiffness / k_lin
    assert np.all((ratio > 0.5) & (ratio < 2.0))


def test_extended_contact_grows_with_load(low):
    lo = static_transmission_error(low, 20.0, n_per_cycle=32)
    hi = static_transmission_error(low, 2000.0, n_per_cycle=32)
    assert hi.extended.sum() > lo.extended.sum()
    # without extension no pair carries load outside the path
    off = static_transmission_error(low, 2000.0, n_per_cycle=32, extended=False)
    assert not off.extended.any()
    # extension smooths the STE: lower peak-to-peak
    assert np.ptp(hi.ste) < np.ptp(off.ste)


def test_tip_relief_unloads_tip(low):
    base = static_transmission_error(low, 200.0, n_per_cycle=32, extended=False)
    rel = static_transmission_error(
        low,
        200.0,
        n_per_cycle=32,
        extended=False,
        corrections=Corrections((TipRelief("a", 20e-6, 0.064), TipRelief("b", 20e-6, 0.0835))),
    )
    # column 1 = the newest pair; at ξ = 0 it enters at the tip of gear b, where gear b's
    # relief (20 µm, more than the ~10 µm deflection) removes its load
    assert base.load_sharing[0, 1] > 0.3
    assert rel.load_sharing[0, 1] < 0.5 * base.load_sharing[0, 1]
    # in the single-contact zone (mid-mesh, contact near the pitch point) relief does not act
    single = np.isclose(base.load_sharing.max(axis=1), 1.0)
    mid = single & np.isclose(rel.load_sharing.max(axis=1), 1.0)
    assert mid.any()
    assert np.allclose(rel.ste[mid], base.ste[mid], rtol=1e-9)


def test_spall_eq13_acts_only_on_spalled_tooth(low):
    sp = Spall("b", 0, radius=0.0825, radial_width=0.0029, depth=1e-4)
    kw = dict(n_per_cycle=16, n_cycles=3, n_slices=4, extended=False)
    h = static_transmission_error(low, 200.0, **kw)
    f = static_transmission_error(low, 200.0, spalls=(sp,), **kw)
    d = f.ste - h.ste
    assert d.max() > 0
    assert np.all(d >= -1e-12)
    # tooth 0 of gear b is in contact only during the first two mesh cycles of this window
    assert np.all(np.abs(d[f.mesh_cycle >= 2.0]) < 1e-12)


def test_bad_torque(low):
    with pytest.raises(InputError, match="torque"):
        static_transmission_error(low, -5.0)


def test_profile_crowning_unloads_path_ends(low):
    base = static_transmission_error(low, 200.0, n_per_cycle=32, extended=False)
    cr = static_transmission_error(
        low, 200.0, n_per_cycle=32, extended=False, corrections=Corrections(profile_crowning=10e-6)
    )
    # at ξ = 0 the entering pair sits at the path start, where the crowning is largest
    assert cr.load_sharing[0, 1] < base.load_sharing[0, 1]
    assert cr.ste.mean() > base.ste.mean()
