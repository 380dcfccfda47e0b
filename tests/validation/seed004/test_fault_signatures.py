"""Seed 004 ch. 9 tooth-fault signatures not covered by tests/planetary/test_seed004.py:
indication codes C, E, G of Table 9-17 (eqs 9.1, 9.2; §9.1.3), ring and planet spalls, the
per-planet ordering of the fault passages (planet numbering), and the signal ranking of
Tables 9-1…9-16. Disturbances are located on the difference faulty − healthy of a velocity,
in mesh cycles X = z_r θ_c/2π (events repeat exactly: no noise, no transmission error)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import detrend, find_peaks
from scipy.stats import kendalltau

from ._reclaimer import R_C, ZP, ZR, ZS, mesh_cycles, run

T_END = 8.0  # s ≈ 67 mesh cycles, 2 planet revolutions relative to the carrier

pytestmark = pytest.mark.slow  # twelve 8 s runs of the 19-DOF model (≈ 12 s on one core)


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

# Wang 2010 Tables 9-1 (sun crack), 9-4 (ring crack), 9-7 (planet-1 crack): grades of the 12
# averaged signals, 1 = most detectable.
SEED_GRADES = {
    "sun_crack": dict(us=1, uc=1, xr=2, yr=2, ur=2, xs=3, ys=3, up=3, xc=4, yc=4, xp=4, yp=4),
    "ring_crack": dict(us=1, uc=1, xr=2, yr=2, ur=2, xs=3, ys=3, xc=4, yc=4, xp=4, yp=4, up=4),
    "planet_crack": dict(us=1, ur=1, uc=1, up=1, xr=2, yr=2, xp=3, yp=3, xs=3, ys=3, xc=4,
                         yc=4),
}


def _seed_signals(ds) -> dict[str, np.ndarray]:
    """The thesis's 12 signals (§3.4, §8.2): velocities of the sun, ring and carrier x, y in the
    fixed frame, planet 1's x*, y* about the sun centre (orbit r_c included, Fig 8-20), and the
    torsional rates (m/s)."""
    t = ds.time.values
    th = ds.q.sel(dof="carrier.u").values / R_C
    c, s = np.cos(th), np.sin(th)
    out = {}
    for body, k in (("sun", "s"), ("ring", "r"), ("carrier", "c")):
        x, y = ds.q.sel(dof=f"{body}.x").values, ds.q.sel(dof=f"{body}.y").values
        out["x" + k] = np.gradient(x * c - y * s, t)
        out["y" + k] = np.gradient(x * s + y * c, t)
    rad = R_C + ds.q.sel(dof="planet1.zeta").values
    eta = ds.q.sel(dof="planet1.eta").values
    out["xp"] = np.gradient(rad * c - eta * s, t)
    out["yp"] = np.gradient(rad * s + eta * c, t)
    for k in ("us", "ur", "uc", "up"):
        out[k] = ds.v.sel(dof=SIGNALS[k]).values
    return out


def _ranking(runs, case: str, t0: float = 2.0) -> tuple[list[str], dict[str, float]]:
    """Signals ordered by fault visibility: peak to peak of the fault-induced change over the
    peak to peak of the healthy signal, both against the carrier angle (mesh cycles: the
    thesis's "shaft position", so that the two runs are compared at the same gear position)
    and linearly detrended, from t0 on."""
    _, h = runs["healthy"]
    _, c = runs[case]
    xh, xc = mesh_cycles(h), mesh_cycles(c)
    lo = max(np.interp(t0, h.time.values, xh), np.interp(t0, c.time.values, xc))
    grid = np.linspace(lo, min(xh[-1], xc[-1]), 20000)
    sh, sc = _seed_signals(h), _seed_signals(c)
    score = {}
    for k in SIGNALS:
        a = np.interp(grid, xh, sh[k])
        b = np.interp(grid, xc, sc[k])
        score[k] = float(np.ptp(detrend(b - a)) / np.ptp(detrend(a)))
    return sorted(score, key=lambda k: -score[k]), score


def _seed_model(d: dict) -> None:
    """The thesis's crack runs (ch. 9 case 2): carrier arm + bucket wheel + 12 buckets as one
    body (Table 6-4 / eqs 6.8-6.13: 26 431 kg, 92 926 kg·m², checked in
    test_seed004_gear_side.py), before loading; planet-bearing dampers c_px = c_py = 1e10 N·s/m
    (Table 7-1 and the thesis code; AN31 prints 1e4, which changes nothing here)."""
    st = d["planetary_dynamics"]["stages"][0]
    st["carrier"]["mass_kg"], st["carrier"]["inertia_kgm2"] = 26431.0, 92926.0
    st["planet_bearing_damping_ns_per_m"] = 1e10


@pytest.fixture(scope="module")
def seed_runs():
    out = {"healthy": run([], T_END, edit=_seed_model)}
    for size in (0.05, 0.4):  # the thesis's smallest crack (Table 9-16 "5 %") and a middle one
        for gear in ("sun", "ring", "planet"):
            out[f"{gear}_crack", size] = run(
                [{"kind": "crack", "gear": gear, "crack_fraction": size}], T_END,
                edit=_seed_model)
    return out


@pytest.mark.parametrize("size", [0.05, 0.4])
@pytest.mark.parametrize("case", ["sun_crack", "ring_crack", "planet_crack"])
def test_table_9_16_carrier_torsional_signal_first(seed_runs, case, size):
    """Tables 9-1/9-4/9-7 and 9-16: the carrier torsional signal uc is in the first grade for
    every crack (tied with us for sun and ring cracks, so the grades do not separate the two:
    uc must be in our top 2), and the twelve signals' order agrees with the thesis's grades
    beyond chance: Kendall τ-b of our scores against the grades, one-sided p < 0.01 under a
    random order (the threshold is the test's significance level, not a fitted number).
    Measured: uc 1st for all at 5 %; at 40 % 2nd (sun, after ur by 5 %), 1st, 1st; τ 0.61-0.74."""
    runs = {"healthy": seed_runs["healthy"], case: seed_runs[case, size]}
    rank, score = _ranking(runs, case)
    assert rank.index("uc") < 2, rank
    keys = list(SIGNALS)
    tau, p = kendalltau([-score[k] for k in keys], [SEED_GRADES[case][k] for k in keys],
                        alternative="greater")
    assert p < 0.01, (tau, p, rank)
    # planet x*, y* carry the orbit (0.26 m/s): the last two, as in Fig 8-23 / Table 9-2 "chaos"
    assert set(rank[-2:]) == {"xp", "yp"}


def test_default_model_ranks_carrier_signal_low_regression_guard(runs):
    # regression guard (no source value): with the example's defaults (carrier arm only, no
    # planet-bearing damper) the carrier rotation is isolated from the mesh forces by the
    # planet bearings (a 26 Hz carrier-on-bearings mode), so uc is not among the most
    # sensitive signals (measured: 10th of 12 for the sun crack, 7th for the planet crack);
    # the thesis's ranking needs its Table 7-1 c_px = 1e10 (test above, docs/validation.md).
    for case in ("sun_crack", "planet_crack"):
        rank, _ = _ranking(runs, case)
        assert rank.index("uc") >= 5, rank
