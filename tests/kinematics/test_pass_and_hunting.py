"""Planet-pass and hunting-tooth frequencies against hand calculations (issue 20).

Cases the older tests could not tell apart from a wrong formula:

- a planet pass computed from the absolute carrier speed ``n·|ω_c|`` equals the right one
  ``n·|ω_c − ω_r|`` only when the ring is fixed: here the ring turns, and the pass relative to
  the sun ``n·|ω_c − ω_s|`` is checked too;
- a hunting-tooth frequency ``f_m / (Z_a·Z_b)`` equals ``f_m / lcm(Z_a, Z_b)`` only for coprime
  tooth counts: here 20/30 (lcm 60, product 600).

Hand values: Willis for a simple planetary, ``(ω_s − ω_c)/(ω_r − ω_c) = −Z_r/Z_s``, so
``ω_c = (Z_s ω_s + Z_r ω_r)/(Z_s + Z_r)``; the same tooth pair meets again after lcm(Z_a, Z_b)
mesh cycles, i.e. after lcm/Z_a revolutions of gear a.
"""

from __future__ import annotations

import math

import pytest

from geardyn import analyze_kinematics
from geardyn.config.loader import parse_config
from geardyn.gears.geometry import GearBlank, mesh_geometry
from geardyn.kinematics import characteristic_frequencies

ZS, ZP, ZR, N = 19, 32, 83, 3  # seed 004 reclaimer stage (Table 6-2)


def _stage(ring: str) -> dict:
    links = [{"name": x} for x in ("housing", "sun", "carrier", "ring_shaft")]
    return {
        "name": "planetary with a turning ring",
        "frame": "housing",
        "links": links if ring == "ring_shaft" else links[:3],
        "planetary": [{"name": "st", "sun": "sun", "ring": ring, "carrier": "carrier",
                       "sun_teeth": ZS, "planet_teeth": ZP, "ring_teeth": ZR,
                       "n_planets": N}],
    }


def test_planet_pass_with_a_turning_ring():
    kin = analyze_kinematics(parse_config(_stage("ring_shaft")))
    ws, wr = 1500.0, -300.0  # rpm, both about the common axis
    wc = (ZS * ws + ZR * wr) / (ZS + ZR)  # 35.294 rpm
    f = characteristic_frequencies(kin, {"sun": ws, "ring_shaft": wr})
    links = f.links.set_index("link")
    assert links.loc["carrier", "signed_rpm"] == pytest.approx(wc, rel=1e-12)
    pp = f.planet_pass.set_index("central")
    assert pp.loc["ring_shaft", "planet_pass_hz"] == pytest.approx(N * abs(wc - wr) / 60,
                                                                   rel=1e-12)  # 16.765 Hz
    assert pp.loc["sun", "planet_pass_hz"] == pytest.approx(N * abs(wc - ws) / 60,
                                                            rel=1e-12)  # 73.235 Hz
    # the wrong formula would give n·|ω_c| = 1.765 Hz for both
    assert pp.loc["ring_shaft", "planet_pass_hz"] > 5 * N * abs(wc) / 60


def test_planet_pass_relative_to_the_sun_with_a_fixed_ring():
    kin = analyze_kinematics(parse_config(_stage("housing")))
    ws = 950.0
    wc = ZS * ws / (ZS + ZR)
    f = characteristic_frequencies(kin, {"sun": ws})
    pp = f.planet_pass.set_index("central")
    assert pp.loc["sun", "planet_pass_hz"] == pytest.approx(N * (ws - wc) / 60, rel=1e-12)
    assert pp.loc["housing", "planet_pass_hz"] == pytest.approx(N * wc / 60, rel=1e-12)


def test_hunting_tooth_of_a_non_coprime_pair():
    za, zb, rpm = 20, 30, 1200.0
    cfg = parse_config({"name": "pair", "frame": "housing",
                        "links": [{"name": "housing"}, {"name": "a"}, {"name": "b"}],
                        "parallel": [{"name": "ab", "a": {"link": "a", "teeth": za},
                                      "b": {"link": "b", "teeth": zb}}]})
    f = characteristic_frequencies(analyze_kinematics(cfg), {"a": rpm})
    m = f.meshes.set_index("pair").loc["ab"]
    f_m = za * rpm / 60  # 400 Hz
    assert m["mesh_hz"] == pytest.approx(f_m, rel=1e-12)
    # the same tooth pair meets after lcm/z_a = 3 revolutions of gear a (hand: teeth 0 and 0
    # meet again when 20·k is a multiple of 30, first at k = 3)
    revs = next(k for k in range(1, za * zb + 1) if (za * k) % zb == 0)
    assert revs == 3
    assert m["hunting_hz"] == pytest.approx(rpm / 60 / revs, rel=1e-12)  # 6.667 Hz
    assert m["hunting_period_s"] == pytest.approx(revs * 60 / rpm, rel=1e-12)
    assert m["hunting_hz"] != pytest.approx(f_m / (za * zb))  # not the coprime formula


def test_gear_geometry_hunting_cycles_of_a_non_coprime_pair():
    g = mesh_geometry(GearBlank(teeth=20), GearBlank(teeth=30), 0.003, math.radians(20.0), 0.02)
    assert g.hunting_cycles == 60  # lcm(20, 30): 3 turns of the 20-tooth gear
    assert g.hunting_cycles == next(c for c in range(1, 601) if c % 20 == 0 and c % 30 == 0)
