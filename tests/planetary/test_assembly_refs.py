"""Lin & Parker assembly against the printed block matrices (issue 12, mutation-testing gaps).

The coupled model of one stage with unequally spaced planets and distinct pressure angles is
compared entry by entry with seed 003 eqs 3.3-3.22 written out as explicit 3×3 blocks (with
the errata of the seed 003 notes §2.3: K_s2 off the diagonal, (3.22) entries −cos α_s), the
gyroscopic and centripetal matrices (3.4-3.8), the torsional reduction (4.2, 4.4) and the
gravity loads of ``geardyn.models.planetary.loads`` in closed form.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from geardyn.errors import ConfigError, InputError
from geardyn.models.planetary.loads import gravity_forces, integrated_angle, loaded_square_mesh
from geardyn.models.planetary.model import RotorSpec, ShaftSpec, StageSpec, assemble

PSI = [0.3, 2.2, 4.4]  # unequal planet angles (rad)
AS, AR = 0.38, 0.31  # sun and ring pressure angles (rad)
KS, KR, KP = 3.1e8, 4.3e8, 1.7e8
SUN = dict(mass=1.2, inertia=0.011, radius=0.05, bearing=2.1e8, torsional=3.0e5)
RING = dict(mass=5.5, inertia=0.52, radius=0.15, bearing=1.3e8, torsional=1.1e6)
CARRIER = dict(mass=2.3, inertia=0.057, radius=0.1, bearing=0.9e8, torsional=2.0e5)
PLANET = dict(mass=0.45, inertia=0.0023, radius=0.045)


def _stage(prefix: bool = False) -> StageSpec:
    return StageSpec("s", 3, list(PSI), sun=dict(SUN), ring=dict(RING), carrier=dict(CARRIER),
                     planet=dict(PLANET), alpha_s=AS, alpha_r=AR, k_sun_mesh=KS,
                     k_ring_mesh=KR, planet_bearing=KP, prefix=prefix)


def _blocks_reference() -> np.ndarray:
    """K_b + K_m of seed 003 eqs 3.9-3.22, block order (c, r, s, p1, p2, p3)."""
    k = np.zeros((18, 18))

    def blk(i: int, j: int, b: np.ndarray) -> None:
        k[3 * i:3 * i + 3, 3 * j:3 * j + 3] += b

    for i, p in enumerate((CARRIER, RING, SUN)):  # (3.9)-(3.10): diag(k_x, k_y, k_u/r²)
        blk(i, i, np.diag([p["bearing"], p["bearing"], p["torsional"] / p["radius"] ** 2]))
    sa, ca = math.sin(AS), math.cos(AS)
    sr, cr = math.sin(AR), math.cos(AR)
    for n, psi in enumerate(PSI):
        s, c = math.sin(psi), math.cos(psi)
        # carrier-planet bearing (3.14)-(3.16)
        blk(0, 0, KP * np.array([[1, 0, -s], [0, 1, c], [-s, c, 1]]))
        kc2 = KP * np.array([[-c, s, 0], [-s, -c, 0], [0, -1, 0]])
        blk(0, 3 + n, kc2)
        blk(3 + n, 0, kc2.T)
        blk(3 + n, 3 + n, KP * np.diag([1.0, 1.0, 0.0]))
        # ring-planet mesh (3.17)-(3.19), ψ_rn = ψ_n + α_r (3.24)
        s1, c1 = math.sin(psi + AR), math.cos(psi + AR)
        blk(1, 1, KR * np.array([[s1 * s1, -s1 * c1, -s1], [-s1 * c1, c1 * c1, c1],
                                 [-s1, c1, 1]]))
        kr2 = KR * np.array([[-s1 * sr, s1 * cr, s1], [c1 * sr, -c1 * cr, -c1],
                             [sr, -cr, -1]])
        blk(1, 3 + n, kr2)
        blk(3 + n, 1, kr2.T)
        blk(3 + n, 3 + n, KR * np.array([[sr * sr, -sr * cr, -sr], [-sr * cr, cr * cr, cr],
                                         [-sr, cr, 1]]))
        # sun-planet mesh (3.20)-(3.22), ψ_sn = ψ_n − α_s (3.23); (3.22) with the erratum
        s2, c2 = math.sin(psi - AS), math.cos(psi - AS)
        blk(2, 2, KS * np.array([[s2 * s2, -s2 * c2, -s2], [-s2 * c2, c2 * c2, c2],
                                 [-s2, c2, 1]]))
        ks2 = KS * np.array([[s2 * sa, s2 * ca, -s2], [-c2 * sa, -c2 * ca, c2],
                             [-sa, -ca, 1]])
        blk(2, 3 + n, ks2)
        blk(3 + n, 2, ks2.T)
        blk(3 + n, 3 + n, KS * np.array([[sa * sa, sa * ca, -sa], [sa * ca, ca * ca, -ca],
                                         [-sa, -ca, 1]]))
    return k


def test_coupled_stiffness_equals_the_printed_blocks():
    m = assemble([_stage()])
    assert m.names[:3] == ["carrier.x", "carrier.y", "carrier.u"]
    assert m.names[9:12] == ["planet1.zeta", "planet1.eta", "planet1.u"]
    k_ref = _blocks_reference()
    np.testing.assert_allclose(m.stiffness_matrix(), k_ref, rtol=0, atol=1e-6 * KR)


def test_mass_gyroscopic_and_centripetal_matrices():
    """(3.3) diag(m, m, I/r²); (3.4)-(3.5) G_i = [[0, −2m, 0], [2m, 0, 0], [0, 0, 0]];
    (3.6)-(3.8 corrected) K_Ω,i = diag(m, m, 0), every body of the stage."""
    m = assemble([_stage()])
    mass, g, kw = [], [], []
    for p in (CARRIER, RING, SUN, PLANET, PLANET, PLANET):
        mass += [p["mass"], p["mass"], p["inertia"] / p["radius"] ** 2]
        g.append(np.array([[0, -2 * p["mass"], 0], [2 * p["mass"], 0, 0], [0, 0, 0]]))
        kw.append(np.diag([p["mass"], p["mass"], 0.0]))
    np.testing.assert_allclose(m.mass_matrix(), np.diag(mass), rtol=1e-14)
    from scipy.linalg import block_diag

    np.testing.assert_allclose(m.gyroscopic_matrix(), block_diag(*g), rtol=1e-14, atol=0)
    np.testing.assert_allclose(m.centripetal_matrix(), block_diag(*kw), rtol=1e-14, atol=0)


def test_rotation_vector_and_dof_lookup():
    m = assemble([_stage(prefix=True)])
    c = m.rotation_vector("s.sun")
    assert c[m.dof("s.sun.u")] == pytest.approx(1 / SUN["radius"])
    assert np.count_nonzero(c) == 1
    with pytest.raises(ConfigError, match="unknown DOF 's.sun.w'"):
        m.dof("s.sun.w")
    with pytest.raises(ConfigError, match="unknown body 'moon'"):
        m.body("moon")


def test_torsional_reduction_eq_4_2_and_4_4_with_pressure_angles():
    """Model B keeps u (central x, y and planet ζ fixed, planet η = u_c): the mesh rows
    (3.20)/(3.17) reduce by hand to δ_sn = u_s + u_n − cos α_s u_c and
    δ_rn = u_r − u_n − cos α_r u_c (eq 4.4 when α = 0); the carrier mass gets N m_p (4.2)."""
    m = assemble([_stage()], reduction="torsional")
    assert m.names == ["carrier.u", "ring.u", "sun.u", "planet1.u", "planet2.u", "planet3.u"]
    hand = np.zeros((6, 6))
    for n in range(3):
        a = np.zeros(6)
        a[[2, 3 + n, 0]] = [1, 1, -math.cos(AS)]
        hand += KS * np.outer(a, a)
        b = np.zeros(6)
        b[[1, 3 + n, 0]] = [1, -1, -math.cos(AR)]
        hand += KR * np.outer(b, b)
    for i, p in enumerate((CARRIER, RING, SUN)):
        hand[i, i] += p["torsional"] / p["radius"] ** 2
    np.testing.assert_allclose(m.stiffness_matrix(), hand, rtol=1e-12, atol=1e-6)
    mm = np.diag(m.mass_matrix())
    assert mm[0] == pytest.approx(CARRIER["inertia"] / 0.1**2 + 3 * PLANET["mass"], rel=1e-14)
    assert mm[3] == pytest.approx(PLANET["inertia"] / PLANET["radius"] ** 2, rel=1e-14)


def test_transverse_reduction_keeps_the_translations():
    m = assemble([_stage()], reduction="transverse")
    assert m.names == ["carrier.x", "carrier.y", "ring.x", "ring.y", "sun.x", "sun.y",
                       "planet1.zeta", "planet1.eta", "planet2.zeta", "planet2.eta",
                       "planet3.zeta", "planet3.eta"]
    keep = [0, 1, 3, 4, 6, 7, 9, 10, 12, 13, 15, 16]
    np.testing.assert_allclose(m.stiffness_matrix(), _blocks_reference()[np.ix_(keep, keep)],
                               rtol=0, atol=1e-6 * KR)
    with pytest.raises(ConfigError, match="reduction 'radial' is not one of"):
        assemble([_stage()], reduction="radial")


def test_shafts_and_rotors():
    """Torsional shaft k (θ_a − θ_b)² with θ = u/r; flexural springs between x and y; a rotor
    is one θ DOF with its support."""
    st = _stage(prefix=True)
    m = assemble([st], [ShaftSpec("in", "motor", "s.sun", torsional=2.0e4, flexural=0.0),
                        ShaftSpec("c", "s.carrier", "s.ring", torsional=0.0, flexural=5.0e6)],
                 [RotorSpec("motor", 0.3, support=70.0)])
    k = m.stiffness_matrix()
    base = assemble([st]).stiffness_matrix()
    i_m, i_s = m.dof("motor.theta"), m.dof("s.sun.u")
    rs = SUN["radius"]
    assert k[i_m, i_m] == pytest.approx(2.0e4 + 70.0, rel=1e-14)
    assert k[i_m, i_s] == pytest.approx(-2.0e4 / rs, rel=1e-14)
    assert k[i_s, i_s] - base[i_s - 0, i_s - 0] == pytest.approx(2.0e4 / rs**2, rel=1e-9)
    for d in ("x", "y"):
        ic, ir = m.dof(f"s.carrier.{d}"), m.dof(f"s.ring.{d}")
        assert k[ic, ir] - base[ic, ir] == pytest.approx(-5.0e6, rel=1e-12)
        assert k[ic, ic] - base[ic, ic] == pytest.approx(5.0e6, rel=1e-12)
    assert m.mass_matrix()[i_m, i_m] == pytest.approx(0.3)
    with pytest.raises(ConfigError, match="shaft 'bad': flexural stiffness needs two central"):
        assemble([st], [ShaftSpec("bad", "motor", "s.sun", flexural=1.0)],
                 [RotorSpec("motor", 0.3)])
    with pytest.raises(ConfigError, match="body name 's.carrier' is used twice"):
        assemble([st, _stage(prefix=True)])


# ---- gravity and load law (loads.py) ------------------------------------------------------


def test_gravity_closed_form_in_the_carrier_frame():
    """Central member: F_x = −m g sin φ, F_y = −m g cos φ; planet n: F_ζ = −m g sin(φ + ψ_n),
    F_η = −m g cos(φ + ψ_n); φ = θ_c + angle0; default g = 9.81 m/s²."""
    m = assemble([_stage()])
    th = np.array([0.0, 0.7, 2.9])
    f = gravity_forces(m, "s", th, angle0=0.25)
    phi = th + 0.25
    sun = m.dof("sun.x")
    np.testing.assert_allclose(f[:, sun], -SUN["mass"] * 9.81 * np.sin(phi), rtol=1e-14)
    np.testing.assert_allclose(f[:, sun + 1], -SUN["mass"] * 9.81 * np.cos(phi), rtol=1e-14)
    z2 = m.dof("planet2.zeta")
    np.testing.assert_allclose(f[:, z2], -PLANET["mass"] * 9.81 * np.sin(phi + PSI[1]),
                               rtol=1e-14)
    np.testing.assert_allclose(f[:, z2 + 1], -PLANET["mass"] * 9.81 * np.cos(phi + PSI[1]),
                               rtol=1e-14)
    assert np.all(f[:, [m.dof("sun.u"), m.dof("planet2.u")]] == 0)
    # zero gravity is allowed and gives no force
    assert np.all(gravity_forces(m, "s", th, g=0.0) == 0)


@pytest.mark.parametrize("g", [-1.0, math.inf, math.nan])
def test_gravity_bad_g_is_named(g):
    with pytest.raises(InputError, match="gravity: g must be a finite number ≥ 0"):
        gravity_forces(assemble([_stage()]), "s", np.zeros(2), g=g)


def test_gravity_unknown_stage_lists_the_stages():
    with pytest.raises(InputError, match=r"gravity: unknown stage 'x' \(stages: s\)"):
        gravity_forces(assemble([_stage()]), "x", np.zeros(2))


def test_loaded_square_mesh_by_hand():
    """k̄₀ = k_max(c₀ − 1) + k_min(2 − c₀) (seed 003 eq 1.12); δ = F/k̄₀;
    c = min(2, c₀ + 2ρ min(δ/C_a, 1)); k (F/F_ref)^n."""
    kmax, kmin, c0, ca = 6e8, 4e8, 1.6, 10e-6
    kbar = kmax * 0.6 + kmin * 0.4  # 5.2e8
    f = 1040.0  # δ = 2 µm = C_a/5
    assert loaded_square_mesh(kmax, kmin, c0, f, ca) == pytest.approx(
        (kmax, kmin, c0 + 2 * 0.25 * 0.2), rel=1e-12)
    assert loaded_square_mesh(kmax, kmin, c0, f, ca, relief_roll_ratio=0.1)[2] == pytest.approx(
        c0 + 2 * 0.1 * 0.2, rel=1e-12)
    # δ beyond the relief: the whole relief roll closes, c capped at 2
    assert loaded_square_mesh(kmax, kmin, c0, 20 * kbar * ca, ca)[2] == pytest.approx(2.0)
    assert loaded_square_mesh(kmax, kmin, 1.2, 2 * kbar * ca, ca, 0.2)[2] == pytest.approx(1.6)
    k1, k2, _ = loaded_square_mesh(kmax, kmin, c0, 4000.0, ca, reference_force_n=1000.0,
                                   stiffness_exponent=0.5)
    assert (k1, k2) == pytest.approx((2 * kmax, 2 * kmin), rel=1e-12)


@pytest.mark.parametrize("kwargs, message", [
    (dict(k_max=0.0), r"load law: k_max must be a finite number > 0"),
    (dict(k_min=math.nan), r"load law: k_min must be a finite number > 0"),
    (dict(tip_relief_m=-1.0), r"load law: tip_relief_m must be a finite number > 0"),
    (dict(contact_ratio=2.1), r"load law: contact_ratio must be in \[1, 2\]"),
    (dict(contact_ratio=0.9), r"load law: contact_ratio must be in \[1, 2\]"),
    (dict(force_n=-1.0), r"load law: the mesh force must be finite and ≥ 0 N"),
    (dict(relief_roll_ratio=0.0), r"load law: relief_roll_ratio must be in \(0, 0.5\]"),
    (dict(relief_roll_ratio=0.6), r"load law: relief_roll_ratio must be in \(0, 0.5\]"),
    (dict(stiffness_exponent=1.0), r"load law: stiffness_exponent needs reference_force_n > 0"),
])
def test_load_law_bad_input_is_named(kwargs, message):
    args = dict(k_max=6e8, k_min=4e8, contact_ratio=1.6, force_n=100.0, tip_relief_m=1e-5)
    args.update(kwargs)
    with pytest.raises(InputError, match=message):
        loaded_square_mesh(**args)


def test_load_law_accepts_the_interval_ends():
    for c0 in (1.0, 2.0):
        assert loaded_square_mesh(6e8, 4e8, c0, 0.0, 1e-5, relief_roll_ratio=0.5)[2] == c0


def test_integrated_angle_of_a_ramp():
    """Rate 0 → 10 rad/s over 2 s then held: θ = 2.5 t² for t ≤ 2, 10 + 10 (t − 2) after."""
    t = np.array([0.0, 0.5, 1.3, 2.0, 3.7])
    want = np.where(t <= 2, 2.5 * t**2, 10 + 10 * (t - 2))
    np.testing.assert_allclose(integrated_angle(t, np.array([0.0, 2.0]), np.array([0.0, 10.0])),
                               want, rtol=1e-12)


def test_spring_kinds_split_the_stiffness_and_carry_their_labels():
    """The kinds of the Spring docstring partition K: the supports are diag(k_t/r²) (3.9), the
    meshes and planet bearings the blocks of (3.14)-(3.22), the shafts k (θ_a − θ_b)²; every
    mesh/planet-bearing spring names its planet (1-based) and body; stage info keeps the
    geometry used for mesh phasing."""
    st = _stage(prefix=True)
    m = assemble([st], [ShaftSpec("in", "motor", "s.sun", torsional=2.0e4),
                        ShaftSpec("c", "s.carrier", "s.ring", flexural=5.0e6)],
                 [RotorSpec("motor", 0.3, support=70.0)])
    kinds = ("bearing", "support_u", "planet_bearing", "mesh_sun", "mesh_ring", "shaft")
    assert {s.kind for s in m.springs} == set(kinds)
    np.testing.assert_allclose(sum(m.stiffness_matrix((k,)) for k in kinds),
                               m.stiffness_matrix(), rtol=1e-14, atol=1e-6)
    sup = np.zeros(m.n_full)
    for role, p in (("carrier", CARRIER), ("ring", RING), ("sun", SUN)):
        sup[m.dof(f"s.{role}.u")] = p["torsional"] / p["radius"] ** 2
    sup[m.dof("motor.theta")] = 70.0
    np.testing.assert_allclose(m.stiffness_matrix(("support_u",)), np.diag(sup), rtol=1e-14)
    ks = m.stiffness_matrix(("shaft",))
    i_m, i_s = m.dof("motor.theta"), m.dof("s.sun.u")
    assert ks[i_m, i_s] == pytest.approx(-2.0e4 / SUN["radius"], rel=1e-14)
    ix_c, ix_r = m.dof("s.carrier.x"), m.dof("s.ring.y")
    assert ks[ix_c, ix_c] == pytest.approx(5.0e6) and ks[ix_r, ix_r] == pytest.approx(5.0e6)
    for s in m.springs:
        if s.kind in ("mesh_sun", "mesh_ring", "planet_bearing"):
            assert s.body == f"s.planet{s.planet}" and 1 <= s.planet <= 3
            assert s.bin and s.stage == "s"
    assert {s.body for s in m.springs if s.kind == "shaft"} == {"in", "c"}
    assert all(isinstance(s.bin, str) and s.bin.startswith(("bearing", "mesh", "shaft",
                                                            "support"))
               for s in m.springs)
    names = {s.name for s in m.springs}
    assert {"c.flex.x", "c.flex.y", "in.torsion", "motor.support"} <= names
    info = m.stages["s"]
    assert (info.alpha_s, info.alpha_r) == (AS, AR)
    assert (info.r_sun, info.r_ring, info.r_planet, info.r_carrier) == (0.05, 0.15, 0.045, 0.1)
    assert m.bodies["s.planet2"].inertia == PLANET["inertia"]
    assert m.bodies["s.planet2"].radius == PLANET["radius"]


def test_missing_bearing_and_support_are_zero():
    """A central member given without ``bearing`` / ``torsional`` has no bearing spring
    stiffness (seed 003 eqs 3.9-3.10 with k = 0): the sun's diagonal loses exactly its
    bearing and support terms."""
    st = _stage()
    st.sun = {k: v for k, v in SUN.items() if k not in ("bearing", "torsional")}
    k_ref = _blocks_reference()
    i = 6  # sun block (c, r, s)
    k_ref[i:i + 3, i:i + 3] -= np.diag([SUN["bearing"], SUN["bearing"],
                                        SUN["torsional"] / SUN["radius"] ** 2])
    np.testing.assert_allclose(assemble([st]).stiffness_matrix(), k_ref, rtol=0,
                               atol=1e-6 * KR)
