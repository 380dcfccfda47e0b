"""The generic modal solver (geardyn.solve.eigen) against closed forms and invariants.

* 2-DOF spring-mass chain: ω² roots of m1 m2 λ² − (m1 k2 + m2 (k1 + k2)) λ + k1 k2 = 0;
  free-free pair ω² = k (1/m1 + 1/m2) with one rigid-body mode (seed 003 eq 3.27).
* Rigid disc on isotropic tilt springs k_r spinning at Ω (gyroscopic I_p Ω):
  ω_f,b = ½ (± Ω I_p/I_d + √((Ω I_p/I_d)² + 4 k_r/I_d)), forward and backward whirl.
* Point mass on an isotropic spring seen from a frame turning at Ω (Coriolis G = 2m J,
  centripetal K_Ω = m I, seed 003 eq 3.1): ω = |ω_n ± Ω|.
* Modal energies (seed 003 eqs 3.28-3.29): Σ kinetic = Σ strain = ½ ω² for mass-normalised
  shapes, per element ½ k δ².
* Lin & Parker (1999): a stage with N = 4 equally spaced planets has its translational modes in
  degenerate pairs (6 pairs), all others simple; unequal planets split the pairs.
"""

from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np
import pytest

from geardyn.config.loader import load_config
from geardyn.elements.disc import disc_gyroscopic, rigid_disc
from geardyn.errors import InputError
from geardyn.models.core.assembly import Assembly, RankOne
from geardyn.solve.eigen import (
    assembly_strain,
    campbell,
    degenerate_groups,
    eigenmodes,
    frame_terms,
    kinetic_energy,
    strain_rank_one,
)

EX = Path(__file__).resolve().parents[2] / "examples"
TWO_PI = 2 * math.pi


def test_two_dof_chain_closed_form() -> None:
    """ground –k1– m1 –k2– m2: frequencies 1e-12, φᵀMφ = I, strain per spring ½ k δ²."""
    m1, m2, k1, k2 = 2.0, 1.0, 3.0e4, 1.0e4
    M = np.diag([m1, m2])
    K = np.array([[k1 + k2, -k2], [-k2, k2]])
    b = m1 * k2 + m2 * (k1 + k2)
    disc = math.sqrt(b * b - 4 * m1 * m2 * k1 * k2)
    w2 = np.array([(b - disc), (b + disc)]) / (2 * m1 * m2)
    em = eigenmodes(M, K)
    np.testing.assert_allclose(em.freq_hz, np.sqrt(w2) / TWO_PI, rtol=1e-12)
    np.testing.assert_allclose(em.shapes.T @ M @ em.shapes, np.eye(2), atol=1e-12)
    assert list(em.multiplicity) == [1, 1] and not em.rigid.any()
    rows = np.array([[1.0, 0.0], [-1.0, 1.0]])  # deflections of k1 and k2
    ep = strain_rank_one(em.shapes, rows, np.array([k1, k2]))
    phi = em.shapes
    np.testing.assert_allclose(ep[:, 0], 0.5 * k1 * phi[0] ** 2, rtol=1e-12)
    np.testing.assert_allclose(ep[:, 1], 0.5 * k2 * (phi[1] - phi[0]) ** 2, rtol=1e-12)
    np.testing.assert_allclose(ep.sum(1), 0.5 * w2, rtol=1e-12)
    np.testing.assert_allclose(kinetic_energy(M, em.freq_hz, phi).sum(1), 0.5 * w2, rtol=1e-12)


def test_fixed_dof_and_rigid_mode() -> None:
    """Clamping the ground DOF of a 3-mass chain gives the 2-DOF chain (zeros on the fixed
    DOF); the free-free pair has ω² = k (1/m1 + 1/m2) and one rigid mode at exactly 0 Hz."""
    m1, m2, k1, k2 = 2.0, 1.0, 3.0e4, 1.0e4
    M3 = np.diag([5.0, m1, m2])
    K3 = np.array([[k1, -k1, 0.0], [-k1, k1 + k2, -k2], [0.0, -k2, k2]])
    ref = eigenmodes(np.diag([m1, m2]), K3[1:, 1:])
    em = eigenmodes(M3, K3, fixed=[0])
    np.testing.assert_allclose(em.freq_hz, ref.freq_hz, rtol=1e-12)
    assert em.shapes.shape == (3, 2) and np.all(em.shapes[0] == 0.0)
    np.testing.assert_allclose(np.abs(em.shapes[1:]), np.abs(ref.shapes), rtol=1e-10)
    free = eigenmodes(np.diag([m1, m2]), np.array([[k2, -k2], [-k2, k2]]))
    assert free.freq_hz[0] == 0.0 and list(free.rigid) == [True, False]
    assert free.freq_hz[1] == pytest.approx(math.sqrt(k2 * (1 / m1 + 1 / m2)) / TWO_PI,
                                            rel=1e-12)
    # zero_hz=0 keeps the round-off frequency of the rigid mode unsnapped but ≥ 0
    raw = eigenmodes(np.diag([m1, m2]), np.array([[k2, -k2], [-k2, k2]]), zero_hz=0.0)
    assert 0.0 <= raw.freq_hz[0] < 1e-3 and not raw.rigid.any()


def test_degenerate_groups_rule() -> None:
    """|f_j − f_first| ≤ max(atol, rtol |f_j|), measured from the group's first mode."""
    f = np.array([0.0, 4e-4, 10.0, 10.0 + 5e-6, 10.1, 100.0, 100.0008, 100.0016])
    assert degenerate_groups(f, rtol=1e-6, atol_hz=1e-3) == [[0, 1], [2, 3], [4], [5, 6], [7]]
    # without atol only the relative rule: 5e-6 ≤ 1e-6 · 10 still joins, 8e-4 > 1e-4 not
    assert degenerate_groups(f, rtol=1e-6, atol_hz=0.0) == [[0], [1], [2, 3], [4], [5], [6],
                                                            [7]]
    assert degenerate_groups(f, rtol=2e-2, atol_hz=0.0) == [[0], [1], [2, 3, 4], [5, 6, 7]]
    with pytest.raises(InputError, match="rtol"):
        degenerate_groups(f, rtol=-1.0)


def _disc_rotor(m: float, i_p: float, i_d: float, k_t: float, k_z: float, k_r: float
                ) -> Assembly:
    """Rigid disc (x, y, z, θx, θy, θz) on isotropic supports, free to spin about z."""
    asm = Assembly()
    idx = asm.add_dofs("disc", ["x", "y", "z", "rx", "ry", "rz"])
    asm.add_frame("spin", asm.row({"disc.rz": 1.0}))  # Ω = θ̇z
    asm.add_block("disc", "disc", idx, frame="spin", M=rigid_disc(m, i_p, i_d),
                  G=disc_gyroscopic(i_p))
    for lab, k in (("x", k_t), ("y", k_t), ("z", k_z), ("rx", k_r), ("ry", k_r)):
        asm.add_rank_one(RankOne(f"support.{lab}", "support", k, asm.row({f"disc.{lab}": 1.0})))
    return asm


def _whirl(speed: np.ndarray, i_p: float, i_d: float, k_r: float) -> tuple[np.ndarray, ...]:
    a = speed * i_p / i_d
    root = np.sqrt(a * a + 4 * k_r / i_d)
    return 0.5 * (root - a) / TWO_PI, 0.5 * (root + a) / TWO_PI  # backward, forward [Hz]


def test_disc_rotor_campbell_forward_backward_whirl() -> None:
    """Sorted Campbell of a spinning disc: axial, lateral (×2) constant, tilt modes split into
    backward/forward whirl (closed form, 1e-9); the free spin (0 Hz) dropped by min_hz."""
    m, i_p, i_d, k_t, k_z, k_r = 10.0, 0.2, 0.1, 4.0e6, 9.0e6, 2.0e4
    asm = _disc_rotor(m, i_p, i_d, k_t, k_z, k_r)
    speeds = np.array([0.0, 150.0, 700.0, 2500.0])
    spin = asm.row({"disc.rz": 1.0})  # the free spin: rigid-body motion at unit speed
    terms = frame_terms(asm, spin)
    assert len(terms) == 1 and terms[0][0] == 1.0
    out = campbell(asm.matrix("M"), asm.matrix("K"), terms, speeds, n_modes=6, min_hz=1e-3)
    bw, fw = _whirl(speeds, i_p, i_d, k_r)
    lat = math.sqrt(k_t / m) / TWO_PI
    ax = math.sqrt(k_z / m) / TWO_PI
    for i in range(speeds.size):
        ref = np.sort([bw[i], fw[i], lat, lat, ax])
        np.testing.assert_allclose(out[i, :5], ref, rtol=1e-9)
        assert np.isnan(out[i, 5])  # only five elastic modes
    # without min_hz the free spin shows as a 0 Hz mode, first column
    out0 = campbell(asm.matrix("M"), asm.matrix("K"), [(1.0, asm.matrix("G"), None)], speeds)
    assert np.all(np.abs(out0[:, 0]) < 1e-6) and out0.shape == (4, 6)


def test_disc_rotor_tracked_whirl_crosses_the_lateral_mode() -> None:
    """Tracked Campbell: the forward whirl crosses the lateral frequency and keeps its column
    (sorted columns would swap), each column one closed-form curve (1e-9)."""
    m, i_p, i_d, k_t, k_z, k_r = 10.0, 0.2, 0.1, 4.0e6, 9.0e6, 2.0e4
    asm = _disc_rotor(m, i_p, i_d, k_t, k_z, k_r)
    speeds = np.linspace(0.0, 1500.0, 16) + 3.0  # the crossing (≈ 1165 rad/s) not on the grid
    args = (asm.matrix("M"), asm.matrix("K"), [(1.0, asm.matrix("G"), None)], speeds)
    tracked = campbell(*args, n_modes=5, min_hz=1e-3, track=True)
    bw, fw = _whirl(speeds, i_p, i_d, k_r)
    lat = np.full(speeds.size, math.sqrt(k_t / m) / TWO_PI)
    ax = np.full(speeds.size, math.sqrt(k_z / m) / TWO_PI)
    assert fw[0] < lat[0] < fw[-1]  # the crossing is inside the speed range
    for curve in (bw, fw, lat, ax):
        hit = [j for j in range(5) if np.allclose(tracked[:, j], curve, rtol=1e-9)]
        assert hit, curve
    sorted_ = campbell(*args, n_modes=5, min_hz=1e-3)
    np.testing.assert_allclose(np.sort(tracked, axis=1), sorted_, rtol=1e-12)
    fw_sorted = [j for j in range(5) if np.allclose(sorted_[:, j], fw, rtol=1e-9)]
    assert not fw_sorted  # sorted columns do not follow the forward whirl across the crossing


def test_rotating_frame_point_mass_centripetal_and_coriolis() -> None:
    """m q̈ + Ω·2mJ q̇ + (k − Ω² m) q = 0 in a frame at Ω = rate × speed: ω = |ω_n ± Ω|."""
    m, k, rate = 3.0, 1.2e5, 2.0
    wn = math.sqrt(k / m)
    G = 2 * m * np.array([[0.0, -1.0], [1.0, 0.0]])
    speeds = np.array([0.0, 17.0, 0.3 * wn, 0.9 * wn])
    out = campbell(m * np.eye(2), k * np.eye(2), [(rate, G, m * np.eye(2))], speeds)
    om = rate * speeds
    ref = np.sort(np.stack([np.abs(wn - om), wn + om], 1), axis=1) / TWO_PI
    np.testing.assert_allclose(out, ref, rtol=1e-9)


def test_energy_sum_rule_rank_one_and_blocks() -> None:
    """Torsional chain with a rank-one ground spring, a 2×2 block element and a rank-one
    coupling: per element ½ k δ², Σ strain = Σ kinetic = ½ ω² (1e-10)."""
    asm = Assembly()
    asm.add_dofs("", ["a", "b", "c"], [0.3, 0.1, 0.2])
    k0, k1, k2 = 5.0e4, 2.0e4, 3.0e4
    asm.add_rank_one(RankOne("ground", "support", k0, asm.row({"a": 1.0})))
    asm.add_block("shaft", "shaft", ["a", "b"], K=k1 * np.array([[1.0, -1.0], [-1.0, 1.0]]))
    asm.add_rank_one(RankOne("coupling", "shaft", k2, asm.row({"b": 1.0, "c": -2.0})))
    M, K = asm.matrix("M"), asm.matrix("K")
    em = eigenmodes(M, K)
    names, kinds, ep = assembly_strain(asm, em.shapes)
    assert names == ["ground", "coupling", "shaft"] and kinds == ["support", "shaft", "shaft"]
    p = em.shapes
    np.testing.assert_allclose(ep[:, 0], 0.5 * k0 * p[0] ** 2, rtol=1e-12)
    np.testing.assert_allclose(ep[:, 1], 0.5 * k2 * (p[1] - 2 * p[2]) ** 2, rtol=1e-12)
    np.testing.assert_allclose(ep[:, 2], 0.5 * k1 * (p[0] - p[1]) ** 2, rtol=1e-12)
    half_w2 = 0.5 * (TWO_PI * em.freq_hz) ** 2
    np.testing.assert_allclose(ep.sum(1), half_w2, rtol=1e-10)
    np.testing.assert_allclose(kinetic_energy(M, em.freq_hz, p).sum(1), half_w2, rtol=1e-10)
    _, _, only = assembly_strain(asm, em.shapes, kinds=["support"])
    assert only.shape == (3, 1)


@pytest.fixture(scope="module")
def lin_parker():  # noqa: ANN201
    from geardyn.models.planetary.build import model_from_config

    return model_from_config(load_config(EX / "planetary_lin_parker.toml"))


def test_planetary_degenerate_pairs_and_sum_rule(lin_parker) -> None:  # noqa: ANN001
    """Lin & Parker, N = 4 equal planets: translational modes in 6 degenerate pairs, every other
    mode simple; energies on the planetary assembly's own elements sum to ½ ω² (1e-9). A 1 %
    heavier planet splits the pairs (the grouping can tell)."""
    from geardyn.models.planetary.modal import modes

    model = lin_parker
    em = eigenmodes(model.mass_matrix(), model.stiffness_matrix())
    pairs = [g for g in em.groups if len(g) == 2]
    assert len(pairs) == 6 and all(len(g) in (1, 2) for g in em.groups)
    types = modes(model).mode_type
    assert all(types[i] == "translational" for g in pairs for i in g)
    assert sum(m == 2 for m in em.multiplicity) == 12
    el = ~em.rigid
    half_w2 = 0.5 * (TWO_PI * em.freq_hz[el]) ** 2
    _, _, ep = assembly_strain(model.assembly, model.transform @ em.shapes)
    np.testing.assert_allclose(ep[el].sum(1), half_w2, rtol=1e-9)
    ek = kinetic_energy(model.mass_matrix(), em.freq_hz, em.shapes)
    np.testing.assert_allclose(ek[el].sum(1), half_w2, rtol=1e-9)
    heavy = copy.deepcopy(model)
    for j, name in enumerate(heavy.assembly.names):
        if name.startswith("planet1."):
            heavy.assembly.point_mass[j] *= 1.01
    split = eigenmodes(heavy.mass_matrix(), heavy.stiffness_matrix())
    assert max(len(g) for g in split.groups) == 1


def test_bad_input_is_named() -> None:
    """Non-finite or mis-shaped matrices, fixed DOFs out of range, bad speeds: InputError."""
    M, K = np.eye(2), np.eye(2)
    with pytest.raises(InputError, match="K: non-finite"):
        eigenmodes(M, np.array([[1.0, np.nan], [np.nan, 1.0]]))
    with pytest.raises(InputError, match="K: must be a 2 × 2"):
        eigenmodes(M, np.eye(3))
    with pytest.raises(InputError, match="fixed"):
        eigenmodes(M, K, fixed=[2])
    with pytest.raises(InputError, match="zero_hz"):
        eigenmodes(M, K, zero_hz=float("nan"))
    with pytest.raises(InputError, match="speeds"):
        campbell(M, K, [], np.array([0.0, np.inf]))
    with pytest.raises(InputError, match="G: must be a 2 × 2"):
        campbell(M, K, [(1.0, np.eye(3), None)], np.array([0.0]))
    with pytest.raises(InputError, match="motion"):
        frame_terms(Assembly(), np.array([np.nan]))
    with pytest.raises(InputError, match="n_modes"):
        campbell(M, K, [], np.array([0.0]), n_modes=-1)


def test_model_campbells_track_the_same_frequencies(lin_parker) -> None:  # noqa: ANN001
    """Planetary, mechanism and FE Campbell wrappers with ``track``: at every speed the tracked
    columns hold the same frequencies as the sorted ones (all modes kept, 1e-9); at the first
    speed they are sorted."""
    from geardyn.models.core import model_from_config as core_model
    from geardyn.models.core.modal import core_campbell
    from geardyn.models.planetary.modal import campbell as planetary_campbell
    from geardyn.models.transmission import build_model, prepare
    from geardyn.models.transmission.modal import fe_campbell

    speeds = np.array([0.0, 200.0, 600.0, 1500.0])
    cases = [(planetary_campbell, (lin_parker, speeds))]
    mech = core_model(load_config(EX / "three_stage_gearbox.toml"))
    cases.append((core_campbell, (mech, next(iter(mech.bodies.keys() - {mech.frame})), speeds)))
    cfg = load_config(EX / "seed002_transmission.toml")
    fe = build_model(cfg)
    prep = prepare(fe, cfg.transmission.speed_law.reference.shaft)
    cases.append((fe_campbell, (fe, prep, speeds * 30.0 / math.pi)))
    for fn, args in cases:
        n = len(args[0].dof_names) if hasattr(args[0], "dof_names") else len(args[0].names)
        sorted_ = fn(*args, n_modes=n).values
        tracked = fn(*args, n_modes=n, track=True).values
        np.testing.assert_allclose(np.sort(tracked, axis=1), np.sort(sorted_, axis=1),
                                   rtol=1e-9, atol=1e-6)
        np.testing.assert_allclose(tracked[0], sorted_[0], rtol=1e-12, atol=1e-6)
