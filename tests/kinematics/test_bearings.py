"""Bearing characteristic frequencies against a hand calculation from geometry.

Reference case: SKF 6205-2RS deep-groove ball bearing as documented by the Case Western Reserve
University bearing data centre: n = 9, d = 0.3126 in, D = 1.537 in, α = 0. Published defect
frequencies as multiples of shaft speed: BPFI 5.4152, BPFO 3.5848, FTF 0.39828, and 4.7135 for
the ball (= D/d·(1 − (d/D)²), i.e. twice the ball spin frequency). Hand calculation:
d/D = 0.203383; BPFO = 4.5·(1 − 0.203383) = 3.58478; BPFI = 4.5·1.203383 = 5.41522;
FTF = 0.5·0.796617 = 0.398309; BSF = 1.537/(2·0.3126)·(1 − 0.041365) = 2.35676.
"""

from __future__ import annotations

import math

import pytest

from geardyn import analyze_kinematics
from geardyn.bearings import bearing_frequencies
from geardyn.config import parse_config
from geardyn.kinematics import characteristic_frequencies

IN = 0.0254
D6205 = dict(n_elements=9, element_diameter=0.3126 * IN, pitch_diameter=1.537 * IN)


def test_6205_against_published_multipliers():
    f = bearing_frequencies(1.0, 0.0, **D6205)
    assert f.bpfi == pytest.approx(5.4152, abs=5e-5)
    assert f.bpfo == pytest.approx(3.5848, abs=5e-5)
    assert f.ftf == pytest.approx(0.39828, abs=5e-5)
    assert 2 * f.bsf == pytest.approx(4.7135, abs=1e-4)  # published value rounded from inches
    assert f.bsf == pytest.approx(2.35676, abs=5e-5)


def test_invariants_rotating_outer_ring():
    # only the relative speed matters for BPFO/BPFI/BSF; BPFO + BPFI = n·|f_i − f_o|
    a = bearing_frequencies(30.0, 0.0, **D6205, contact_angle=math.radians(15))
    b = bearing_frequencies(10.0, -20.0, **D6205, contact_angle=math.radians(15))
    for k in ("bpfo", "bpfi", "bsf", "ftf"):
        assert getattr(a, k) == pytest.approx(getattr(b, k), rel=1e-12)
    assert a.bpfo + a.bpfi == pytest.approx(9 * 30.0, rel=1e-12)
    # cage in the fixed frame: f_o + FTF (signed)
    assert b.cage_abs == pytest.approx(
        abs(-20.0 + 0.5 * 30.0 * (1 - 0.3126 / 1.537 * math.cos(math.radians(15))))
    )
    z = bearing_frequencies(12.0, 12.0, **D6205)
    assert z.bpfo == z.bpfi == z.bsf == 0.0


def test_bad_geometry_is_rejected():
    with pytest.raises(ValueError, match="element_diameter_m"):
        bearing_frequencies(1.0, 0.0, n_elements=9, element_diameter=0.05, pitch_diameter=0.04)
    with pytest.raises(ValueError, match="contact_angle_deg"):
        bearing_frequencies(1.0, 0.0, **D6205, contact_angle=math.radians(95))


CFG = {
    "name": "shaft on two bearings + planet bearing",
    "frame": "housing",
    "links": ["housing", "shaft", "out", "carrier"],
    "parallel": [
        {"name": "stage", "a": {"link": "shaft", "teeth": 20}, "b": {"link": "out", "teeth": 60}}
    ],
    "planetary": [
        {
            "name": "ps",
            "sun": "out",
            "ring": "housing",
            "carrier": "carrier",
            "sun_teeth": 20,
            "planet_teeth": 30,
            "ring_teeth": 80,
            "n_planets": 4,
            "planet_bearing": {
                "kind": "roller",
                "n_elements": 14,
                "element_diameter_m": 0.008,
                "pitch_diameter_m": 0.05,
            },
        }
    ],
    "bearings": [
        {
            "name": "shaft_DE",
            "inner": "shaft",
            "outer": "housing",
            "n_elements": 9,
            "element_diameter_m": 0.3126 * IN,
            "pitch_diameter_m": 1.537 * IN,
        }
    ],
}


def test_bearings_in_a_mechanism():
    cfg = parse_config(CFG)
    a = analyze_kinematics(cfg)
    f = characteristic_frequencies(a, {"shaft": 1797.0})
    b = f.bearings.set_index("bearing")
    # 1797 rpm = 29.95 Hz: BPFO = 3.5848 × 29.95 = 107.36 Hz (hand calculation)
    assert b.loc["shaft_DE", "bpfo_hz"] == pytest.approx(3.5848 * 29.95, abs=0.01)
    assert b.loc["shaft_DE", "bpfo_order"] == pytest.approx(3.5848, abs=5e-5)
    # planet bearing: inner ring on the carrier pin, outer in the planet; relative speed is
    # the planet speed relative to the carrier: f_out·(1 − ... ) → f_rel = Z_s/Z_p·(f_sun − f_c)
    f_sun = 29.95 * 20 / 60
    f_c = f_sun * 20 / (20 + 80)
    f_rel = 20 / 30 * (f_sun - f_c)
    pb = b.loc["ps.planet1.bearing"]
    assert pb["rel_hz"] == pytest.approx(f_rel, rel=1e-9)
    gamma = 0.008 / 0.05
    assert pb["bpfo_hz"] == pytest.approx(14 * f_rel / 2 * (1 - gamma), rel=1e-9)
    assert pb["bpfi_hz"] == pytest.approx(14 * f_rel / 2 * (1 + gamma), rel=1e-9)
    assert len(b) == 5  # 1 shaft bearing + 4 planet bearings
