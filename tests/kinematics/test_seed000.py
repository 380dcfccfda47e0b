"""Validation of the kinematic method against seed 000 (Penaud, Alazard, Amiez 2012).

Every expected number below is printed in the paper; tolerances follow the number of digits
the paper gives (e.g. 0.86 → ±0.005).
"""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest

from geardyn import analyze_kinematics, load_config
from geardyn.kinematics import characteristic_frequencies


@pytest.fixture(scope="module")
def diff(examples_dir):
    return analyze_kinematics(load_config(examples_dir / "car_differential.toml"))


@pytest.fixture(scope="module")
def mgb(examples_dir):
    return analyze_kinematics(load_config(examples_dir / "alouette3_mgb.toml"))


def test_car_differential_rank_and_dof(diff):
    # seed 000 §2.5: "the rank of the kinematic constraint matrix M (equation (3)) is 5, that is
    # a 2 d.o.f. mechanism"
    assert diff.rank == 5
    assert diff.dof == 2
    # the rank decision is clear-cut: a gap of many decades in the singular values
    sv = diff.singular_values
    assert sv[4] / sv[0] > 1e-3 and sv[5] / sv[0] < 1e-14


def test_car_differential_reference_links(diff):
    # seed 000 Table 2: 2-7 → 1, 3-5/3-6/4-5/4-6 → 7 (link 1 = housing, 7 = cage)
    assert diff.reference_links() == {
        "2-7": "housing",
        "3-5": "cage",
        "3-6": "cage",
        "4-5": "cage",
        "4-6": "cage",
    }


def test_car_differential_constraint_matrix_eq3(diff):
    e = cmath.exp(1j * math.pi / 4)
    ec = e.conjugate()
    expected = np.array(
        [
            [1, 0, 0, 0, 0, 0, 0],
            [-78, 13, 0, 0, 0, 0, 65],
            [0, 0, 14 * ec, 0, 10 * e, 0, -14 * ec - 10 * e],
            [0, 0, 14 * e, 0, 0, 10 * ec, -14 * e - 10 * ec],
            [0, 0, 0, 14 * e, 10 * ec, 0, -14 * e - 10 * ec],
            [0, 0, 0, 14 * ec, 0, 10 * e, -14 * ec - 10 * e],
        ],
        dtype=complex,
    )
    np.testing.assert_allclose(diff.M, expected, atol=1e-12)


def test_car_differential_velocity_ratio_matrix_eq6(diff):
    om = diff.velocity_ratios(["left_wheel", "right_wheel"])
    # rows: housing, drive pinion, left, right, pinion a, pinion b, cage
    np.testing.assert_allclose(
        om[[0, 2, 3, 6]].real, [[0, 0], [1, 0], [0, 1], [0.5, 0.5]], atol=1e-12
    )
    np.testing.assert_allclose(om[1], [-2.5, -2.5], atol=1e-12)
    # 0.86 e^{±0.95 i} = 0.5 ± 0.7 i (two decimals in the paper)
    np.testing.assert_allclose(np.abs(om[4:6]), 0.86, atol=0.005)
    np.testing.assert_allclose(np.angle(om[4]), [0.95, -0.95], atol=0.005)
    np.testing.assert_allclose(np.angle(om[5]), [-0.95, 0.95], atol=0.005)
    np.testing.assert_allclose(om[4, 0], 0.5 + 0.7j, atol=1e-12)  # 0.7 = 0.5·14/10 exactly
    # relative velocity of pinion 5 w.r.t. the cage is along the pin axis: 0.7 i (seed 000 §2.5)
    assert om[4, 0] - om[6, 0] == pytest.approx(0.7j, abs=1e-12)


def test_car_differential_operating_modes_eq7_eq8(diff):
    straight = diff.speeds({"left_wheel": 1.0, "right_wheel": 1.0})
    np.testing.assert_allclose(straight, [0, -5, 1, 1, 1, 1, 1], atol=1e-12)
    jacked = diff.speeds({"left_wheel": 1.0, "right_wheel": -1.0})  # eq 7
    np.testing.assert_allclose(jacked, [0, 0, 1, -1, 1.4j, -1.4j, 0], atol=1e-12)
    turning = diff.speeds({"left_wheel": 26.0, "right_wheel": 30.0})  # eq 8, rad/s
    np.testing.assert_allclose(turning[[0, 1, 2, 3, 6]], [0, -140, 26, 30, 28], atol=1e-10)
    assert abs(turning[4]) == pytest.approx(28.14, abs=0.005)
    assert np.angle(turning[4]) == pytest.approx(-0.10, abs=0.005)
    assert abs(turning[5]) == pytest.approx(28.14, abs=0.005)
    assert np.angle(turning[5]) == pytest.approx(0.10, abs=0.005)


def test_alouette_reference_links_table4(mgb):
    assert mgb.reference_links() == {
        "1-6": "carrier1",  # 5
        "1-8": "main_rotor",  # 7
        "2-3": "housing",  # 1
        "3-4": "housing",  # 1
        "3-6": "carrier1",  # 5
        "5-8": "main_rotor",  # 7
    }
    assert mgb.dof == 1


def test_alouette_velocity_ratios_eq9(mgb):
    om = mgb.velocity_ratios(["input"])[:, 0]
    j = 1j  # e^{iπ/2}
    expected = [0, 1, 0.488 * j, 0.415, 0.173 * j, -0.592 * j, 0.0612 * j, -0.210 * j]
    # half a unit of the last digit printed in eq 9
    tol = [1e-12, 1e-12, 5e-4, 5e-4, 5e-4, 5e-4, 5e-5, 5e-4]
    for got, exp, t in zip(om, expected, tol, strict=True):
        assert abs(got - exp) <= t, (got, exp)
    # "reduction ratio between input shaft and tail rotor shaft is 1/0.415, main rotor 1/0.0612"
    assert 1 / abs(om[3]) == pytest.approx(1 / 0.415, rel=2e-3)
    assert 1 / abs(om[6]) == pytest.approx(1 / 0.0612, rel=2e-3)
    # main rotor "along the axis normal to the input axis"
    assert np.angle(om[6]) == pytest.approx(math.pi / 2, abs=1e-12)


def test_alouette_exact_ratios(mgb):
    # exact fractions from the tooth counts: bevel 20/41; epicyclic stages 51/(51+93) each
    om = mgb.velocity_ratios(["input"])[:, 0]
    assert om[2] == pytest.approx(20 / 41 * 1j, rel=1e-12)
    assert om[6] == pytest.approx(20 / 41 * (51 / 144) ** 2 * 1j, rel=1e-12)


def test_speed_profiles_broadcast(diff):
    t = np.linspace(0, 1, 5)
    w = diff.speeds({"left_wheel": 10 * t, "right_wheel": 12 * t})
    assert w.shape == (7, 5)
    np.testing.assert_allclose(w[6], 11 * t, atol=1e-12)


def test_frequencies_car_differential_mesh_consistency(diff):
    # Willis (eq 2): both sides of a pair see the same mesh frequency
    f = characteristic_frequencies(diff, {"left_wheel": 248.2817, "right_wheel": 286.4789})
    m = f.meshes.set_index("pair")
    np.testing.assert_allclose(m["teeth_a"] * m["rel_a_hz"], m["mesh_hz"], rtol=1e-12)
    np.testing.assert_allclose(m["teeth_b"] * m["rel_b_hz"], m["mesh_hz"], rtol=1e-12)
    # crown mesh: 13 teeth × drive-shaft speed (140 rad/s in eq 8)
    assert m.loc["2-7", "mesh_hz"] == pytest.approx(13 * 140.0 / (2 * math.pi), rel=1e-6)


def test_alouette_adjacency_table_3(mgb):
    t = mgb.adjacency_frame()
    assert t.loc["housing", "planet1"] == "93∠180°"  # −N7
    assert t.loc["planet1", "housing"] == "21∠0°"  # N6
    assert t.loc["input", "bevel_wheel"] == "20∠-45°"  # N3 e^{−iπ/4}
    assert t.loc["bevel_wheel", "input"] == "41∠45°"  # N4 e^{iπ/4}
    assert t.loc["carrier1", "planet1"] == "level=4"
    assert t.loc["main_rotor", "planet2"] == "level=5"
    assert t.loc["housing", "tail_rotor"] == "level=3"
    assert t.loc["input", "tail_rotor"] == ""
    # internal gear weights are exactly −N (no rounding residue in M)
    assert mgb.constraint_frame().loc["1-6", "housing"] == -93
