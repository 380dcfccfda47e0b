"""Characteristic frequencies of the planetary examples against seeds 003 and 004.

Expected values: seed 003 notes §4.1 (derived from Z_s = 16, Z_p = 24, Z_r = 65 at 1498.5 rpm,
matching the thesis's 320.66 Hz, T_c = 0.2027 s, sideband spacing 3·f_c), seed 004 Table 6-3
and §6.5-6.6 (ratios 5.3684, −1.5938, 29.2971, 157.279, 6.04 rpm at 950 rpm).
"""

from __future__ import annotations

import math

import pytest

from geardyn import analyze_kinematics, load_config
from geardyn.kinematics import characteristic_frequencies


@pytest.fixture(scope="module")
def bench(examples_dir):
    cfg = load_config(examples_dir / "hammami_back_to_back.toml")
    a = analyze_kinematics(cfg)
    return a, characteristic_frequencies(a, {"motor": 1498.5})


@pytest.fixture(scope="module")
def reclaimer(examples_dir):
    cfg = load_config(examples_dir / "reclaimer_drive.toml")
    a = analyze_kinematics(cfg)
    return a, characteristic_frequencies(a, {"motor": 950.0})


def test_bench_is_one_dof_and_reaction_ring_stands_still(bench):
    a, f = bench
    assert a.dof == 1
    links = f.links.set_index("link")
    assert links.loc["reaction_ring", "rpm"] == pytest.approx(0.0, abs=1e-9)


def test_bench_mesh_and_carrier_frequency(bench):
    _, f = bench
    links = f.links.set_index("link")
    f_c = links.loc["carrier", "hz"]
    assert f_c == pytest.approx(4.93333, abs=5e-6)  # seed 003 notes §4.1
    assert 1 / f_c == pytest.approx(0.20270, abs=5e-6)  # T_c
    # sun/carrier ratio 1 + 65/16 = 81/16 (exact)
    assert links.loc["motor", "hz"] / f_c == pytest.approx(81 / 16, rel=1e-12)
    fm = f.meshes["mesh_hz"].to_numpy()
    assert len(fm) == 12
    assert fm == pytest.approx([320.667] * 12, abs=5e-4)  # thesis: 320.66 Hz
    # f_m = Z_r·f_c = Z_s·(f_s − f_c) (seed 003 notes §2.1)
    assert fm[0] == pytest.approx(65 * f_c, rel=1e-12)
    # planet relative to carrier f_m/Z_p = 13.361 Hz
    wheels = f.wheels.set_index("wheel")
    assert wheels.loc["test.planet1/z24", "fault_hz"] == pytest.approx(2 * 13.361, abs=2e-3)
    # sun tooth fault: N·(f_s − f_c) = 3 × 20.042 Hz
    assert wheels.loc["test.sun", "fault_hz"] == pytest.approx(3 * 20.042, abs=2e-3)


def test_bench_planet_pass_is_sideband_spacing(bench):
    _, f = bench
    pp = f.planet_pass.set_index("set")
    # sideband spacing n·N·f_c with N = 3: 14.8 Hz (seed 003 notes §4.1, "not 14.7")
    assert pp.loc["test.ring@carrier", "planet_pass_hz"] == pytest.approx(14.8, abs=5e-5)
    assert pp.loc["test.ring@carrier", "n_planets"] == 3


def test_reclaimer_planetary_ratios(reclaimer):
    a, f = reclaimer
    links = f.links.set_index("link")
    carrier = links.loc["bucket_wheel", "hz"]
    sun = links.loc["sun_shaft", "hz"]
    assert sun / carrier == pytest.approx(5.3684, abs=5e-5)  # Table 6-3
    ratio = a.velocity_ratios(["motor"])[:, 0]
    g = a.graph
    planet = ratio[g.index("planetary.planet1")] / ratio[g.index("bucket_wheel")]
    assert planet.real == pytest.approx(-1.5938, abs=6e-5)  # Table 6-3, same axis → real
    assert planet.real == pytest.approx(1 - 83 / 32, rel=1e-12)  # tabular method, exact
    assert abs(planet.imag) < 1e-12


def test_reclaimer_total_ratio_and_bucket_wheel_speed(reclaimer):
    _, f = reclaimer
    links = f.links.set_index("link")
    motor, sun, wheel = (links.loc[k, "rpm"] for k in ("motor", "sun_shaft", "bucket_wheel"))
    assert motor / sun == pytest.approx(29.2971, abs=5e-5)  # eq 6.7
    assert motor / wheel == pytest.approx(157.279, abs=5e-4)  # §6.6: 157.2792
    assert wheel == pytest.approx(6.04, abs=5e-3)  # 950/157.2792 = 6.04 rpm
    # the bevel first stage turns the shaft axes by 90° in the sketch plane
    assert abs(links.loc["shaft2", "direction_deg"]) == pytest.approx(90.0, abs=1e-9)


def test_reclaimer_sun_fault_count_per_carrier_rev(reclaimer):
    # seed 004 notes §2.10: sun-crack humps per carrier revolution = (5.3684 − 1)·3 = 13.1052
    a, _ = reclaimer
    f = characteristic_frequencies(a, {"motor": 950.0}, order_reference="bucket_wheel")
    wheels = f.wheels.set_index("wheel")
    assert wheels.loc["planetary.sun", "fault_order"] == pytest.approx(13.1052, abs=5e-4)
    # ring: 3 planets pass a ring tooth per carrier revolution
    assert wheels.loc["planetary.ring", "fault_order"] == pytest.approx(3.0, rel=1e-12)
    # mesh order per carrier revolution = Z_r = 83 (seed 004 notes §2.10)
    meshes = f.meshes.set_index("pair")
    assert meshes.loc["planetary.ring-planet1", "mesh_order"] == pytest.approx(83.0, rel=1e-12)


def test_hunting_tooth(reclaimer):
    _, f = reclaimer
    m = f.meshes.set_index("pair").loc["G3-G4"]
    # 21 and 68 are coprime: the same tooth pair meets every 21·68 mesh periods
    assert m["hunting_hz"] == pytest.approx(m["mesh_hz"] / (21 * 68), rel=1e-12)
    assert m["hunting_period_s"] == pytest.approx(21 * 68 / m["mesh_hz"], rel=1e-12)
    assert math.lcm(21, 68) == 21 * 68
