"""Statics: back-to-back torque split, load sharing, pin errors (seed 003 ch. 5, notes §4.5)."""

from __future__ import annotations

import numpy as np
import pytest

from geardyn.models.planetary.dynamics import load_sharing, spring_forces, static_solve

R_S, R_R = 0.03069, 0.12469  # base radii of Table 3.1 (m)


def test_back_to_back_torque_split(bench36):
    """100 N·m on the free reaction ring, motor (reaction sun) held: the sun shaft carries
    T z_s/z_r = 24.615 N·m and the carrier shaft T (z_s + z_r)/z_r = 124.615 N·m (notes §4.5;
    with the Table 3.1 base radii r_bs/r_br = 0.24613); the motor supplies nothing; each mesh
    carries T/(3 r_br) = 267.3 N."""
    q = static_solve(bench36, {"reaction.ring.u": 100.0 / R_R}, fixed=["reaction.sun.u"])
    f = spring_forces(bench36, q)
    assert abs(f["sun_shaft.torsion"]) == pytest.approx(100 * 16 / 65, rel=2e-4)
    assert abs(f["carrier_shaft.torsion"]) == pytest.approx(100 * 81 / 65, rel=2e-4)
    reaction = (bench36.stiffness_matrix() @ q)[bench36.dof("reaction.sun.u")] * R_S
    assert abs(reaction) < 1e-9 * 24.6
    for st in ("reaction", "test"):
        for p in (1, 2, 3):
            for m in ("sun", "ring"):
                assert abs(f[f"{st}.planet{p}.mesh_{m}"]) == pytest.approx(267.3, abs=0.05)
    # the two sets are loaded on opposite flanks (circulating power)
    assert np.sign(f["reaction.planet1.mesh_sun"]) == -np.sign(f["test.planet1.mesh_sun"])


def test_load_sharing_equal_spacing(bench36, lin_parker):
    """LSR = 1/N for ideal, equally spaced planets (seed 003 eq 5.1)."""
    q = static_solve(bench36, {"reaction.ring.u": 300.0 / R_R}, fixed=["reaction.sun.u"])
    f = spring_forces(bench36, q)
    for st in ("reaction", "test"):
        np.testing.assert_allclose(load_sharing(bench36, st, f), 1 / 3, rtol=1e-9)
    q = static_solve(lin_parker, {"sun.u": 20.0 / 0.02273}, fixed=["carrier.u"])
    f = spring_forces(lin_parker, q)
    np.testing.assert_allclose(load_sharing(lin_parker, "stage", f), 0.25, rtol=1e-9)
    # sun mesh force = T_s / (N r_bs)
    assert f["planet1.mesh_sun"] == pytest.approx(20.0 / 0.02273 / 4, rel=1e-9)


def test_pin_errors_change_lsr_with_seed003_sign(bench36):
    """Seed 003 ch. 5: tangential pin errors e = (60, 10, −60) µm; the planet with the positive
    error is preloaded first and carries more, the negative one less; Σ LSR = 1. A positive
    error here lags the carrier's positive rotation (pin at u_c − e), the flank loaded by a
    positive sun torque in the test set."""
    e = {"test.planet1.bearing.eta": -60e-6, "test.planet2.bearing.eta": -10e-6,
         "test.planet3.bearing.eta": 60e-6}
    # drive the test set's sun positively with its ring held: apply torque to the test sun
    loads = {"test.sun.u": 100.0 * 16 / 65 / R_S}
    q0 = static_solve(bench36, loads, fixed=["test.carrier.u", "reaction.carrier.u"])
    f0 = spring_forces(bench36, q0)
    assert f0["test.planet1.mesh_sun"] > 0
    q = static_solve(bench36, loads, fixed=["test.carrier.u", "reaction.carrier.u"], errors=e)
    lsr = load_sharing(bench36, "test", spring_forces(bench36, q, e))
    assert lsr.sum() == pytest.approx(1.0)
    assert lsr[0] > 1 / 3 > lsr[2]
    assert lsr[0] > lsr[1] > lsr[2]
    # effective stiffness of seed 003 eq 5.5 bounds the error force: |ΔF| ≤ K_eff |e|
    k_eff = 1 / (1 / 3.5e6 + 1 / (4.46e8 + 6.28e8))
    assert k_eff == pytest.approx(3.4886e6, rel=1e-4)  # notes §4.5
    f_nom = 267.3 * 2  # sun + ring mesh force per planet at 100 N·m
    dF = (lsr[0] - 1 / 3) * 3 * f_nom
    assert 0 < dF < k_eff * 60e-6 * 2


def test_singular_static_problem_is_explained(bench36):
    from geardyn.errors import InputError

    with pytest.raises(InputError, match="singular"):
        static_solve(bench36, {"reaction.ring.u": 1.0})
