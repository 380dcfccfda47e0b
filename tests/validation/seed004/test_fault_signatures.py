"""Seed 004 ch. 9 tooth-fault signatures not covered by tests/planetary/test_seed004.py:
indication codes C, E, G of Table 9-17 (eqs 9.1, 9.2; §9.1.3), ring and planet spalls, the
per-planet ordering of the fault passages (planet numbering), and the signal ranking of
Tables 9-1…9-16. Disturbances are located on the difference faulty − healthy of a velocity,
in mesh cycles X = z_r θ_c/2π (events repeat exactly: no noise, no transmission error)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import detrend, find_peaks

from ._reclaimer import ZP, ZR, ZS, mesh_cycles, run

T_END = 8.0  # s ≈ 67 mesh cycles, 2 planet revolutions relative to the carrier

pytestmark = pytest.mark.slow  # five 8 s runs of the 19-DOF model (≈ 8 s on one core)


@pytest.fixture(scope="module")
def runs():
    cases = {
        "healthy": [],
        "sun_crack": [{"kind": "crack", "gear": "sun", "crack_fraction": 0.4}],
        "planet_crack": [{"kind": "crack", "gear": "planet", "crack_fraction": 0.4}],
        "ring_spall": [{"kind": "spall", "gear": "ring", "spall_depth_m": 2e-4}],
        "planet_spall": [{"kind": "spall", "gear": "planet", "spall_depth_m": 2e-4}],
    }
    return {k: run(f, T_END) for k, f in cases.items()}


def _events(runs, case: str, dof: str, rel: float) -> tuple[np.ndarray, np.ndarray]:
    """Mesh-cycle positions and relative heights of the disturbances of |v_fault − v_healthy|
    above ``rel`` of its maximum (clusters closer than 2 mesh cycles merged)."""
    _, h = runs["healthy"]
    _, c = runs[case]
    x = mesh_cycles(c)
    diff = np.abs(c.v.sel(dof=dof).values - h.v.sel(dof=dof).values)
    diff[x < 8.0] = 0.0  # start-up transient (first 8 mesh cycles)
    pk, _ = find_peaks(diff, height=rel * diff.max())
    keep = np.r_[True, np.diff(x[pk]) > 2.0]
    return x[pk][keep], diff[pk][keep] / diff.max()


def test_code_c_sun_crack_in_planet_signal(runs):
    """Table 9-17 C / eq 9.1: a sun crack disturbs planet 1's torsional velocity
    N z_p/z_s = 5.05 times per planet revolution (z_p mesh cycles): every z_s/N = 6.33 cycles."""
    x, _ = _events(runs, "sun_crack", "planet1.u", 0.3)
    spacing = np.median(np.diff(x))
    assert ZP / spacing == pytest.approx(3 * ZP / ZS, rel=0.01)


def test_code_e_and_g_planet_crack(runs):
    """Eq 9.2 (code E): the cracked planet tooth meets the sun and then the ring half a planet
    revolution later, so the sun signal has z_s/(z_p/2) = 1.1875 humps per z_s mesh cycles:
    events every z_p/2 = 16 cycles. Code G: two humps per planet revolution in the planet
    signal; the bigger one is the sun-planet mesh, as the §9.1.3 text says (Table 9-17's G says
    the ring mesh; the two statements contradict each other, notes §6 item 12)."""
    x, height = _events(runs, "planet_crack", "sun.u", 0.01)
    assert ZS / np.median(np.diff(x)) == pytest.approx(ZS / (ZP / 2), rel=0.04)
    xp, hp = _events(runs, "planet_crack", "planet1.u", 0.05)
    sun_pass = xp[np.argmax(hp)]  # the biggest hump: the sun-planet mesh passage
    phase = np.mod(xp - sun_pass + ZP / 4, ZP / 2) - ZP / 4  # ≈ 0 at both passages
    np.testing.assert_allclose(phase, 0.0, atol=1.0)  # humps every z_p/2 cycles
    at_sun = np.abs(np.mod(xp - sun_pass + ZP / 2, ZP) - ZP / 2) < 2
    assert at_sun.sum() >= 2 and (~at_sun).sum() >= 2  # two humps per planet revolution
    assert hp[at_sun].min() > 3 * hp[~at_sun].max()  # the sun-mesh hump is the bigger one


def test_ring_spall_once_per_planet_pass(runs):
    """Ring spall (§9.2.2, code A of Table 9-16 for ring faults): each planet passes the spalled
    ring tooth once per carrier revolution, every z_r/N = 27.67 mesh cycles."""
    x, _ = _events(runs, "ring_spall", "carrier.u", 0.3)
    assert np.median(np.diff(x)) == pytest.approx(ZR / 3, rel=0.01)


def test_planet_spall_two_meshes(runs):
    """Planet spall (§9.2.3): the spalled planet tooth meets the sun and the ring once each per
    planet revolution (z_p cycles), half a revolution apart (eq 9.3 counting)."""
    x, _ = _events(runs, "planet_spall", "sun.u", 0.05)
    gaps = np.diff(x)
    np.testing.assert_allclose(np.sort(gaps)[:2], ZP / 2, atol=1.0)
    assert np.all(np.abs(gaps - np.round(gaps / (ZP / 2)) * ZP / 2) < 1.0)


def test_fault_passes_follow_the_planet_numbering(runs):
    """Planet numbering (checked against the thesis code Kms1, §13.1.18: the sun tooth in mesh
    with planet n at mesh count X is X − z_s ψ_n/2π): the cracked sun tooth meets planet 2
    z_s/3 = 6.33 cycles after planet 1 and planet 3 after 12.67 (planets numbered in the
    direction of rotation, ψ_n = 0°, 120°, 240°), so the dips of the per-planet sun-mesh
    stiffness follow 1 → 2 → 3 (offsets mod z_s). A fixed ring tooth is met 1 → 3 → 2 (ψ
    decreasing), every z_r/3 = 27.67 cycles (offsets mod z_r). The thesis's equations place
    planet n at π − ψ_n (notes §2.5), which would mirror planets 2 and 3; its tooth bookkeeping
    (Kms1/Kmr1) does not, and we follow the bookkeeping."""
    for case, mesh, period, offsets in (("sun_crack", "mesh_sun", ZS, {2: ZS / 3, 3: 2 * ZS / 3}),
                                        ("ring_spall", "mesh_ring", ZR,
                                         {3: ZR / 3, 2: 2 * ZR / 3})):
        _, ds = runs[case]
        _, h = runs["healthy"]
        x = mesh_cycles(ds)
        first = {}
        for n in (1, 2, 3):
            dk = (h.mesh_stiffness - ds.mesh_stiffness).sel(mesh=f"planet{n}.{mesh}").values
            first[n] = x[np.flatnonzero(dk > 0.5 * dk.max())[0]]
        for n, off in offsets.items():
            assert np.mod(first[n] - first[1], period) == pytest.approx(off, abs=0.5)


SIGNALS = {"xs": "sun.x", "ys": "sun.y", "us": "sun.u", "xr": "ring.x", "yr": "ring.y",
           "ur": "ring.u", "xc": "carrier.x", "yc": "carrier.y", "uc": "carrier.u",
           "xp": "planet1.zeta", "yp": "planet1.eta", "up": "planet1.u"}


def _ranking(runs, case: str) -> list[str]:
    """Signals ordered by fault visibility: peak-to-peak of the fault-induced change over the
    peak-to-peak of the healthy signal (both linearly detrended, t > 2 s)."""
    _, h = runs["healthy"]
    _, c = runs[case]
    sel = h.time.values > 2.0
    score = {}
    for key, dof in SIGNALS.items():
        vh = h.v.sel(dof=dof).values[sel]
        vc = c.v.sel(dof=dof).values[sel]
        score[key] = np.ptp(detrend(vc - vh)) / np.ptp(detrend(vh))
    return sorted(score, key=lambda k: -score[k])


@pytest.mark.parametrize("case", ["sun_crack", "planet_crack"])
def test_torsional_signals_rank_first(runs, case):
    """Table 9-16 conclusion: torsional signals are superior to transverse ones. The three most
    sensitive signals are torsional (us, ur, up in some order) for sun and planet cracks."""
    assert set(_ranking(runs, case)[:3]) == {"us", "ur", "up"}


def test_ranking_pinned(runs):
    # regression guard (no source value): Tables 9-1…9-16 grade averaged signals, spectra and
    # CWT maps by eye ("good order", "chaos") on fixed-frame planet coordinates with the
    # thesis's noise; the carrier torsional signal uc ranks first there. With our metric on
    # noise-free runs it does not; pinned: the five most sensitive signals of our model and the
    # place of uc (1-based).
    for case, top5, uc_place in (("sun_crack", ["us", "up", "ur", "yp", "xp"], 12),
                                 ("planet_crack", ["ur", "us", "up", "yp", "xp"], 7)):
        rank = _ranking(runs, case)
        assert rank[:5] == top5
        assert rank.index("uc") + 1 == uc_place
