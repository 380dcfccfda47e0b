"""Independent references for the lateral option of the general model (lateral.py).

* Invariance: the sketch frame of the general model is fixed by the input link (its axis is
  φ = 0). Choosing another input link of the same mechanism turns the whole sketch (every axis
  and the frame of every planet angle) by the angle between the two axes; the lateral axes of a
  link are attached to its own axis (x̂ = (−sin φ, cos φ), ŷ out of the sketch), so M, K, G and
  K_Ω must be the same up to the sign of each coordinate (θ and x̂ follow φ mod π), and the
  natural and Campbell frequencies must be equal (1e-9).
* Bevel pairs whose axes are not 90° apart (pitch-cone angles tan δ_a = sin Σ/(z_b/z_a +
  cos Σ), δ_b = Σ − δ_a: ISO 10300-1, Niemann-Winter III §24) and a bevel gear fixed to the
  frame meshing with a pinion carried by a cage: the mesh row against the 3-D hand projection
  of the contact normal N = cos α ẑ + sin α ŝ on the rigid-body displacements
  u = θ ê × P + d at the mean point P (tests/mechanism/test_bevel_lateral.py generalised).
* Planets at ψ ≠ 0 and tree orders with links without lateral DOFs first: the planet centre
  from the carrier-frame kinematics of Lin & Parker (1999) (seed 003 notes §2.3),
  d = d_c + R(ψ)(ζ, η), the sun–planet row n·(d_s − d_p) with n = (−sin(ψ − α), cos(ψ − α)) and
  the ring–planet row with n = (−sin(ψ + α), cos(ψ + α)), written by hand.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np
import pytest
import scipy.linalg as sla

from geardyn.config.loader import parse_config
from geardyn.models.core.graph import model_from_config

ZS, ZP, ZR, NP = 25, 35, 95, 4
MOD, ALPHA = 0.002, math.radians(20.0)
Z_IN, Z_OUT = 30, 40


def _stage_behind_bevel(sigma: float, angles: list[float] | None = None) -> dict:
    """An input shaft driving, through a bevel pair at shaft angle Σ, the sun of a fixed-ring
    planetary stage: the stage's parallel axes lie at Σ in the sketch of input 'in'."""
    links = ([{"link": "in", "inertia_kgm2": 0.01, "mass_kg": 2.0, "bearing_n_per_m": 3e8},
              {"link": "sun", "inertia_kgm2": 2e-4, "mass_kg": 0.4, "bearing_n_per_m": 1e8},
              {"link": "carrier", "inertia_kgm2": 2.2e-2, "mass_kg": 5.4,
               "bearing_n_per_m": 1.5e8}]
             + [{"link": f"st.planet{i + 1}", "inertia_kgm2": 6e-4 * (1 + 0.1 * i),
                 "mass_kg": 0.66 * (1 + 0.05 * i), "bearing_n_per_m": 2e8 * (1 + 0.2 * i)}
                for i in range(NP)])
    stage = {"name": "st", "sun": "sun", "ring": "housing", "carrier": "carrier",
             "sun_teeth": ZS, "planet_teeth": ZP, "ring_teeth": ZR, "n_planets": NP}
    if angles is not None:
        stage["planet_angles_deg"] = angles
    return {
        "frame": "housing", "links": ["housing", "in", "sun", "carrier"],
        "bevel": [{"name": "bv", "a": {"link": "in", "teeth": Z_IN},
                   "b": {"link": "sun", "teeth": Z_OUT}, "shaft_angle_deg": sigma}],
        "planetary": [stage],
        "dynamics": {"module_m": MOD, "pressure_angle_deg": math.degrees(ALPHA),
                     "lateral": True,
                     "meshes": [{"pair": "bv", "stiffness_n_per_m": 2e8},
                                {"pair": "st.sun", "stiffness_n_per_m": 5e8},
                                {"pair": "st.ring", "stiffness_n_per_m": 4e8}],
                     "links": links},
    }


def _axes(model) -> dict[str, float]:  # noqa: ANN001
    """Axis direction φ of each moving link: the phase of its Ω per unit of its own relative
    rotation (seed 000 Ω = Σ e^{iφ} q̇ along the turning tree)."""
    col = {nm: i for i, nm in enumerate(model.dof_names)}
    return {x: float(np.angle(model.link_velocity[model.links.index(x), col[f"{x}.theta"]]))
            for x in model.links if f"{x}.theta" in col}


def _signature(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """s (±1 per coordinate) with b = diag(s) a diag(s), propagated along the nonzero
    couplings of a; the caller asserts the equality."""
    n = len(a)
    s = np.zeros(n)
    for start in range(n):
        if s[start]:
            continue
        s[start] = 1.0
        todo = deque([start])
        while todo:
            i = todo.popleft()
            for j in np.flatnonzero(np.abs(a[i]) > 1e-9 * np.abs(a).max()):
                if not s[j]:
                    s[j] = s[i] * math.copysign(1.0, b[i, j] / a[i, j])
                    todo.append(j)
    return s


@pytest.mark.parametrize("sigma", [60.0, -75.0])
def test_turning_the_sketch_leaves_the_lateral_model_unchanged(sigma):
    """Input 'in' or input 'carrier': the same machine, so the same model (issue 20: the axes
    come from the pitch angles, not from the inputs; the stage's axes make the shaft angle Σ
    with the input's). Matrices equal (coordinate signs all +1), frequencies and Campbell
    diagram (carrier frame G, K_Ω) equal to 1e-9."""
    from geardyn.models.core.modal import core_campbell

    cfg = parse_config(_stage_behind_bevel(sigma))
    by_in, by_carrier = model_from_config(cfg, ["in"]), model_from_config(cfg, ["carrier"])
    assert by_in.dof_names == by_carrier.dof_names
    planets = [f"st.planet{i + 1}" for i in range(NP)]
    for p in planets:  # every planet keeps its lateral DOFs whatever the sketch angle
        assert f"{p}.zeta" in by_in.dof_names and f"{p}.eta" in by_in.dof_names
    phi_in, phi_c = _axes(by_in), _axes(by_carrier)
    assert phi_in == pytest.approx(phi_c, abs=1e-12)  # the inputs do not turn the sketch
    turn = phi_in["carrier"] - phi_in["in"]  # the stage's axes make the shaft angle Σ
    assert abs(math.sin(turn)) == pytest.approx(abs(math.sin(math.radians(sigma))), rel=1e-12)
    k1, k2 = by_in.stiffness_matrix(), by_carrier.stiffness_matrix()
    s = _signature(k1 + by_in.M, k2 + by_carrier.M)
    assert np.all(s == 1.0)
    for a, b in ((by_in.M, by_carrier.M), (k1, k2),
                 (by_in.gyroscopic_matrix(), by_carrier.gyroscopic_matrix()),
                 (by_in.centripetal_matrix(), by_carrier.centripetal_matrix())):
        assert np.abs(b).max() > 0
        np.testing.assert_allclose(s[:, None] * a * s[None, :], b, rtol=0,
                                   atol=1e-10 * np.abs(b).max())
    w1 = sla.eigh(k1, by_in.M, eigvals_only=True)
    w2 = sla.eigh(k2, by_carrier.M, eigvals_only=True)
    assert np.sqrt(w1[1:]) == pytest.approx(np.sqrt(w2[1:]), rel=1e-9)
    assert abs(w1[0]) < 1e-9 * w1[-1]
    # the carrier frame holds the stage only (seed 003 eqs 3.4-3.8): K_Ω = Σ m DᵀD by hand —
    # sun m_s; carrier translation m_c + Σ m_p (the pins ride on it); carrier rotation
    # Σ m_p r_c² (orbit); planets m_p; the input shaft, not coaxial, none
    col = {nm: i for i, nm in enumerate(by_in.dof_names)}
    mp = [0.66 * (1 + 0.05 * i) for i in range(NP)]
    r_c = MOD * (ZS + ZP) / 2
    want = {"sun.x": 0.4, "sun.y": 0.4, "carrier.x": 5.4 + sum(mp), "carrier.y": 5.4 + sum(mp),
            "carrier.theta": sum(mp) * r_c**2}
    want |= {f"{p}.{d}": m for p, m in zip(planets, mp, strict=True) for d in ("zeta", "eta")}
    for model in (by_in, by_carrier):
        k_om = model.centripetal_matrix()
        got = {nm: k_om[i, i] for nm, i in col.items() if np.abs(k_om[i]).max() > 0}
        assert got == pytest.approx(want, rel=1e-12)
    # Campbell: Ω G q̇ − Ω² K_Ω q at the carrier speed (seed 003 eq 3.1)
    speeds = np.array([0.0, 300.0])
    c1 = core_campbell(by_in, "carrier", speeds).values
    c2 = core_campbell(by_carrier, "carrier", speeds).values
    assert c1[:, 1:] == pytest.approx(c2[:, 1:], rel=1e-9)
    assert not np.allclose(c1[0, 1:], c1[1, 1:])


# ---- bevel pairs: 3-D hand projection of the contact normal ---------------------------------

def _unit(angle: float) -> np.ndarray:
    return np.array([math.cos(angle), math.sin(angle), 0.0])


Z_HAT = np.array([0.0, 0.0, 1.0])


def _hand_bevel_row(model, mesh, r_a: float, delta_a: float, axis_a: np.ndarray,  # noqa: ANN001
                    moves: dict[str, list[tuple[str, np.ndarray]]]) -> np.ndarray:
    """δ = N·(u_a(P) − u_b(P)) at the mean point P = R_m ĝ (R_m = r_a / sin δ_a), with
    N = cos α ẑ + sin α ŝ, ŝ in the sketch plane, normal to the generator ĝ, from gear a
    towards gear b. ``moves``: for 'a' and 'b', (coordinate, unit-vector ω or d, kind) lists:
    a rotation ω̂ moves P by ω̂ × P, a translation d̂ by d̂."""
    col = {nm: i for i, nm in enumerate(model.dof_names)}
    g = _unit(mesh.psi)
    p = r_a / math.sin(delta_a) * g
    side_a = axis_a * math.copysign(1.0, axis_a @ g)
    s = -(side_a - (side_a @ g) * g)
    s /= np.linalg.norm(s)
    normal = math.cos(ALPHA) * Z_HAT + math.sin(ALPHA) * s
    hand = np.zeros(model.n)
    for side, sign in (("a", 1.0), ("b", -1.0)):
        for dof, vec in moves[side]:
            u = np.cross(vec, p) if dof.endswith(".theta") else vec
            hand[col[dof]] += sign * normal @ u
    return hand


def _bevel_pair(sigma: float) -> dict:
    links = [{"link": "a", "inertia_kgm2": 0.02, "mass_kg": 1.5, "bearing_n_per_m": 4e8},
             {"link": "b", "inertia_kgm2": 0.3, "mass_kg": 6.0, "bearing_n_per_m": 9e8}]
    return {
        "frame": "housing", "links": ["housing", "a", "b"],
        "bevel": [{"name": "p", "a": {"link": "a", "teeth": Z_IN},
                   "b": {"link": "b", "teeth": Z_OUT}, "shaft_angle_deg": sigma}],
        "dynamics": {"module_m": MOD, "pressure_angle_deg": math.degrees(ALPHA),
                     "lateral": True,
                     "meshes": [{"pair": "p", "stiffness_n_per_m": 3e8}], "links": links},
    }


@pytest.mark.parametrize("sigma", [60.0, -60.0, 120.0, 45.0, 90.0])
@pytest.mark.parametrize("driver", ["a", "b"])
def test_bevel_row_at_any_shaft_angle_equals_the_hand_projection(sigma, driver):
    """Σ ≠ 90°: pitch-cone angles tan δ_a = sin Σ/(z_b/z_a + cos Σ), δ_b = Σ − δ_a (ISO
    10300-1), one mean cone distance r_a/sin δ_a = r_b/sin δ_b, and the whole mesh row (Willis
    torsional part and lateral part) = ±N·(u_a(P) − u_b(P)) by hand; the sketch turned by
    choosing gear b as the input gives the same row."""
    model = model_from_config(parse_config(_bevel_pair(sigma)), [driver])
    mesh = model.meshes[0]
    phi = _axes(model)
    e = {x: _unit(phi[x]) for x in ("a", "b")}
    s_rad = math.radians(abs(sigma))
    assert abs(e["a"] @ e["b"]) == pytest.approx(abs(math.cos(s_rad)), abs=1e-12)
    delta_a = math.atan(math.sin(s_rad) / (Z_OUT / Z_IN + math.cos(s_rad)))
    delta_b = s_rad - delta_a
    g = _unit(mesh.psi)
    for x, dx in (("a", delta_a), ("b", delta_b)):  # the generator makes δ with each axis
        assert abs(g @ e[x]) == pytest.approx(abs(math.cos(dx)), abs=1e-12)
    r_a, r_b = MOD * Z_IN / 2, MOD * Z_OUT / 2
    assert r_a / math.sin(delta_a) == pytest.approx(r_b / math.sin(delta_b), rel=1e-12)
    moves = {x: [(f"{x}.theta", e[x]), (f"{x}.x", np.cross(Z_HAT, e[x])), (f"{x}.y", Z_HAT)]
             for x in ("a", "b")}
    hand = _hand_bevel_row(model, mesh, r_a, delta_a, e["a"], moves)
    sigma_row = math.copysign(1.0, mesh.a @ hand)
    np.testing.assert_allclose(mesh.a, sigma_row * hand, rtol=0, atol=1e-12)
    col = {nm: i for i, nm in enumerate(model.dof_names)}
    assert abs(mesh.a[col["a.theta"]]) == pytest.approx(r_a * math.cos(ALPHA), rel=1e-12)
    assert abs(mesh.a[col["a.y"]]) == pytest.approx(math.cos(ALPHA), rel=1e-12)
    assert abs(mesh.a[col["b.x"]]) == pytest.approx(math.sin(ALPHA) * math.cos(delta_b),
                                                    rel=1e-12)


# ---- a bevel gear on the frame, a carried pinion and a planet on one cage -------------------

Z_FIX, Z_PIN, Z_SUN, Z_PL, Z_RING = 20, 20, 30, 20, 70  # ring = sun + 2 planet
D_FIX = math.radians(30.0)  # pitch-cone angles 30° + 30°: a 60° miter pair (z_a = z_b)


def _cage(pin_first: bool, sun_bearing: bool = True, delta: float = D_FIX,
          turn: float = 1.0) -> dict:
    """Cage turning in the frame, carrying a bevel pinion rolling on a bevel gear fixed to the
    frame (gear a = the frame) and a planet between a sun and a ring fixed to the frame, the
    planet being side a of both its pairs (the [[planetary]] convenience puts it on side b).
    Hand-made pairs: the planet has no planet angle (ψ = 0 from the cage's x̂). Bevel pitch-cone
    angles δ + δ (z_a = z_b), the pinion's axis turned by ``turn`` × 2δ (seed 000 signs)."""
    pin = [{"links": ["cage", "pin"], "axis": 2}]
    pl = [{"links": ["cage", "pl"], "axis": 3}]
    links = [{"link": "cage", "inertia_kgm2": 0.02, "mass_kg": 3.0, "bearing_n_per_m": 2e8},
             {"link": "pin", "inertia_kgm2": 1e-4, "mass_kg": 0.2},
             {"link": "pl", "inertia_kgm2": 2e-4, "mass_kg": 0.4, "bearing_n_per_m": 3e8}]
    if sun_bearing:
        links.append({"link": "sun", "inertia_kgm2": 3e-4, "mass_kg": 0.5,
                      "bearing_n_per_m": 1e8})
    return {
        "frame": "housing", "links": ["housing", "cage", "sun", "pin", "pl"],
        "turning_pairs": [{"links": ["housing", "cage"], "axis": 1},
                          {"links": ["housing", "sun"], "axis": 1}]
        + (pin + pl if pin_first else pl + pin),
        "gear_pairs": [
            {"name": "fix", "a": {"link": "housing", "teeth": Z_FIX,
                                  "pitch_angle_deg": -turn * math.degrees(delta)},
             "b": {"link": "pin", "teeth": Z_PIN,
                   "pitch_angle_deg": turn * math.degrees(delta)}},
            {"name": "sun", "a": {"link": "pl", "teeth": Z_PL},
             "b": {"link": "sun", "teeth": Z_SUN}},
            {"name": "ring", "a": {"link": "pl", "teeth": Z_PL},
             "b": {"link": "housing", "teeth": Z_RING, "internal": True}}],
        "dynamics": {"module_m": MOD, "pressure_angle_deg": math.degrees(ALPHA),
                     "lateral": True,
                     "meshes": [{"pair": "fix", "stiffness_n_per_m": 2e8},
                                {"pair": "sun", "stiffness_n_per_m": 5e8},
                                {"pair": "ring", "stiffness_n_per_m": 4e8}],
                     "links": links},
    }


def _cage_model(pin_first: bool, delta: float = D_FIX, turn: float = 1.0):  # noqa: ANN202
    return model_from_config(parse_config(_cage(pin_first, True, delta, turn)), ["cage"])


def _fix_hand(model, delta: float = D_FIX) -> np.ndarray:  # noqa: ANN001
    """Hand projection for the pair 'fix': gear a fixed; the pinion turns with the cage and on
    its pin, and its centre moves with the cage's x, y (documented: a link without lateral DOFs
    moves with its carrier)."""
    phi = _axes(model)
    e_c, e_p = _unit(phi["cage"]), _unit(phi["pin"])
    mesh = next(m for m in model.meshes if m.name == "fix")
    moves = {"a": [], "b": [("cage.theta", e_c), ("pin.theta", e_p),
                            ("cage.x", np.cross(Z_HAT, e_c)), ("cage.y", Z_HAT)]}
    return _hand_bevel_row(model, mesh, MOD * Z_FIX / 2, delta, _unit(0.0), moves)


@pytest.mark.parametrize(("pin_first", "delta_deg", "turn"),
                         [(True, 30.0, 1.0), (False, 30.0, 1.0), (True, 30.0, -1.0),
                          (True, 15.0, 1.0), (True, 15.0, -1.0), (True, 40.0, 1.0)])
def test_bevel_gear_on_the_frame_against_the_hand_projection(pin_first, delta_deg, turn):
    """Gear a = the frame: the torsional columns and the out-of-sketch column of the mesh row
    equal ±N·(u_a − u_b) by hand with one sign; the pinion's axis makes 2δ with the cage's (the
    in-sketch column cage.x, with the axial part of the carried pinion, is the next test)."""
    delta = math.radians(delta_deg)
    model = _cage_model(pin_first, delta, turn)
    col = {nm: i for i, nm in enumerate(model.dof_names)}
    phi = _axes(model)
    assert abs(math.cos(phi["pin"] - phi["cage"])) == pytest.approx(abs(math.cos(2 * delta)),
                                                                     abs=1e-12)
    mesh = next(m for m in model.meshes if m.name == "fix")
    g = _unit(mesh.psi)
    assert abs(g @ _unit(phi["cage"])) == pytest.approx(math.cos(delta), abs=1e-12)
    hand = _fix_hand(model, delta)
    exact = [col[x] for x in ("cage.theta", "pin.theta", "cage.y")]
    sigma = math.copysign(1.0, mesh.a[exact] @ hand[exact])
    np.testing.assert_allclose(mesh.a[exact], sigma * hand[exact], rtol=0, atol=1e-12)
    others = [i for i in range(model.n) if i not in exact and i != col["cage.x"]]
    assert np.abs(mesh.a[others]).max() == 0.0


def test_carried_bevel_pinion_full_projection():
    """The pinion's centre moves with the cage's x̂ (in the sketch), which has a component
    along the pinion's own axis: the full contact-normal projection N·d includes
    sin α sin δ (ê·d), which the model leaves out (it holds only for d ⊥ ê)."""
    model = _cage_model(True)
    mesh = next(m for m in model.meshes if m.name == "fix")
    hand = _fix_hand(model)
    sigma = math.copysign(1.0, mesh.a @ hand)
    np.testing.assert_allclose(mesh.a, sigma * hand, rtol=0, atol=1e-12)


def test_tree_order_of_links_without_lateral_dofs():
    """A pinion without lateral DOFs declared before the planet in the tree: the planet keeps
    its ζ, η, the DOF sets and the frequencies do not depend on the declaration order (1e-9)."""
    first, last = _cage_model(True), _cage_model(False)
    want = {"cage.x", "cage.y", "sun.x", "sun.y", "pl.zeta", "pl.eta"}
    for model in (first, last):
        lateral = {nm for nm in model.dof_names if not nm.endswith(".theta")}
        assert lateral == want
    perm = [first.dof_names.index(nm) for nm in last.dof_names]
    for a, b in ((first.M, last.M), (first.stiffness_matrix(), last.stiffness_matrix()),
                 (first.gyroscopic_matrix(), last.gyroscopic_matrix())):
        assert np.abs(b).max() > 0
        np.testing.assert_allclose(a[np.ix_(perm, perm)], b, rtol=0, atol=1e-12 * np.abs(b).max())
    w1 = sla.eigh(first.stiffness_matrix(), first.M, eigvals_only=True)
    w2 = sla.eigh(last.stiffness_matrix(), last.M, eigvals_only=True)
    assert np.sqrt(w1[1:]) == pytest.approx(np.sqrt(w2[1:]), rel=1e-9)


# ---- one planet: hand rows from the carrier-frame kinematics (Lin & Parker 1999) ------------

ZS1, ZP1, ZR1 = 30, 20, 70
LINKS1 = {"carrier": (0.02, 3.0, 2e8), "sun": (3e-4, 0.5, 1e8), "pl": (2e-4, 0.4, 3e8)}


def _one_planet(convenience: bool, psi_deg: float = 0.0) -> dict:
    """A sun, a fixed ring and one planet on a carrier: through the [[planetary]] convenience
    (planet 'st.planet1' on side b of both pairs, at ψ) or through hand-made gear pairs (planet
    'pl' on side a of both, no planet angle: ψ = 0)."""
    planet = "st.planet1" if convenience else "pl"
    links = [{"link": planet if x == "pl" else x, "inertia_kgm2": j, "mass_kg": m,
              "bearing_n_per_m": k} for x, (j, m, k) in LINKS1.items()]
    dyn = {"module_m": MOD, "pressure_angle_deg": math.degrees(ALPHA), "lateral": True,
           "links": links}
    if convenience:
        dyn["meshes"] = [{"pair": "st.sun", "stiffness_n_per_m": 5e8},
                         {"pair": "st.ring", "stiffness_n_per_m": 4e8}]
        return {"frame": "housing", "links": ["housing", "sun", "carrier"],
                "planetary": [{"name": "st", "sun": "sun", "ring": "housing",
                               "carrier": "carrier", "sun_teeth": ZS1, "planet_teeth": ZP1,
                               "ring_teeth": ZR1, "n_planets": 1,
                               "planet_angles_deg": [psi_deg]}],
                "dynamics": dyn}
    dyn["meshes"] = [{"pair": "sp", "stiffness_n_per_m": 5e8},
                     {"pair": "rp", "stiffness_n_per_m": 4e8}]
    return {"frame": "housing", "links": ["housing", "carrier", "sun", "pl"],
            "turning_pairs": [{"links": ["housing", "carrier"], "axis": 1},
                              {"links": ["housing", "sun"], "axis": 1},
                              {"links": ["carrier", "pl"], "axis": 2}],
            "gear_pairs": [{"name": "sp", "a": {"link": "pl", "teeth": ZP1},
                            "b": {"link": "sun", "teeth": ZS1}},
                           {"name": "rp", "a": {"link": "pl", "teeth": ZP1},
                            "b": {"link": "housing", "teeth": ZR1, "internal": True}}],
            "dynamics": dyn}


def _zx(v: np.ndarray) -> np.ndarray:
    """ẑ × v in the lateral plane (x̂, ŷ) of the carrier (x̂, ŷ, axis right-handed)."""
    return np.array([-v[1], v[0]])


def _planet_rows(model, planet: str, psi: float, mirror: float) -> tuple[np.ndarray, ...]:  # noqa: ANN001
    """(sun–planet, ring–planet) rows n·(u_p(C) − u_g(C)) at the pitch points C of the carrier
    frame: planet centre c_p = r_c (cos ψ, sin ψ), moved by (x_c, y_c) + R(ψ)(ζ, η) + θ_c ẑ × c_p
    (pin, bearing, orbit) and turning by θ_c + θ_p; sun at the origin moved by (x_s, y_s) and
    turning by θ_s; ring fixed. Lines of action at ±α from the tangent, mirror images of each
    other about the planet's radial line (the planet's moment balance, Lin & Parker 1999 Fig. 1):
    n = R(ψ)(±sin α, cos α), ``mirror`` choosing the pair."""
    col = {nm: i for i, nm in enumerate(model.dof_names)}
    r_c, r_p = MOD * (ZS1 + ZP1) / 2, MOD * ZP1 / 2
    rot = np.array([[math.cos(psi), -math.sin(psi)], [math.sin(psi), math.cos(psi)]])
    radial = rot[:, 0]
    c_p = r_c * radial
    rows = []
    for side, sign in (("sun", 1.0), ("ring", -1.0)):
        n = rot @ np.array([mirror * sign * math.sin(ALPHA), math.cos(ALPHA)])
        c = c_p - sign * r_p * radial  # pitch point: towards the sun, or towards the ring
        row = np.zeros(model.n)
        row[col["carrier.x"]] += n[0]
        row[col["carrier.y"]] += n[1]
        row[col[f"{planet}.zeta"]] += n @ rot[:, 0]
        row[col[f"{planet}.eta"]] += n @ rot[:, 1]
        row[col["carrier.theta"]] += n @ (_zx(c_p) + _zx(c - c_p))
        row[col[f"{planet}.theta"]] += n @ _zx(c - c_p)
        if side == "sun":
            row[col["sun.x"]] -= n[0]
            row[col["sun.y"]] -= n[1]
            row[col["sun.theta"]] -= n @ _zx(c)
        rows.append(row)
    return tuple(rows)


def _match_rows(model, planet: str, psi: float, names: tuple[str, str]) -> None:  # noqa: ANN001
    meshes = {m.name: m.a for m in model.meshes}
    got = [meshes[x] for x in names]
    fits = []
    for mirror in (1.0, -1.0):
        hand = _planet_rows(model, planet, psi, mirror)
        err = max(np.abs(g - math.copysign(1.0, g @ h) * h).max() for g, h in zip(got, hand,
                                                                                 strict=True))
        fits.append(err)
    assert min(fits) < 1e-12
    assert max(fits) > 0.1  # the other flank pair is a different model


@pytest.mark.parametrize("psi_deg", [0.0, 40.0, 250.0])
def test_planet_rows_from_the_carrier_frame_kinematics(psi_deg):
    """Convenience stage, planet at ψ (on side b of both pairs)."""
    model = model_from_config(parse_config(_one_planet(True, psi_deg)), ["carrier"])
    _match_rows(model, "st.planet1", math.radians(psi_deg), ("st.sun-planet1",
                                                               "st.ring-planet1"))


def test_hand_made_planet_on_side_a_equals_the_convenience_stage():
    """Planet on side a of hand-made pairs, ring = frame on side b (ψ = 0): the hand rows, and
    the same frequencies (1e-9) as the [[planetary]] stage with its planet at ψ = 0°, 40° or
    250° (isotropic bearings: the planet's position angle does not change them)."""
    hand_made = model_from_config(parse_config(_one_planet(False)), ["carrier"])
    _match_rows(hand_made, "pl", 0.0, ("sp", "rp"))
    assert {nm for nm in hand_made.dof_names if nm.startswith("pl.")} == \
        {"pl.theta", "pl.zeta", "pl.eta"}
    w_ref = sla.eigh(hand_made.stiffness_matrix(), hand_made.M, eigvals_only=True)
    assert abs(w_ref[0]) < 1e-9 * w_ref[-1]
    for psi_deg in (0.0, 40.0, 250.0):
        model = model_from_config(parse_config(_one_planet(True, psi_deg)), ["carrier"])
        w = sla.eigh(model.stiffness_matrix(), model.M, eigvals_only=True)
        assert np.sqrt(w[1:]) == pytest.approx(np.sqrt(w_ref[1:]), rel=1e-9)


def test_bearing_springs_by_direction():
    """One bearing spring per lateral coordinate, named <link>.bearing.<x|y|zeta|eta> (the
    bearing_force variables of the result, docs/results.md), of kind 'bearing', stiffness
    bearing_n_per_m (0, the documented default, for a link that gives none), acting on its
    coordinate alone."""
    model = model_from_config(parse_config(_cage(True, sun_bearing=False)), ["cage"])
    col = {nm: i for i, nm in enumerate(model.dof_names)}
    want = {"cage.bearing.x": ("cage.x", 2e8), "cage.bearing.y": ("cage.y", 2e8),
            "sun.bearing.x": ("sun.x", 0.0), "sun.bearing.y": ("sun.y", 0.0),
            "pl.bearing.zeta": ("pl.zeta", 3e8), "pl.bearing.eta": ("pl.eta", 3e8)}
    springs = {e.name: e for e in model.springs if e.kind == "bearing"}
    assert set(springs) == set(want)
    for name, (dof, k) in want.items():
        e = springs[name]
        assert e.k == k
        unit = np.zeros(model.n)
        unit[col[dof]] = 1.0
        assert np.array_equal(e.a, unit)


def _two_stages() -> dict:
    """Two fixed-ring stages in series (the first carrier is the second sun), 3 planets each."""
    def stage(name: str, sun: str, carrier: str) -> dict:
        return {"name": name, "sun": sun, "ring": "housing", "carrier": carrier,
                "sun_teeth": ZS, "planet_teeth": ZP, "ring_teeth": ZR, "n_planets": 3}

    central = {"s1": 1.0, "c1": 2.0, "c2": 3.0}
    links = ([{"link": x, "inertia_kgm2": 0.01, "mass_kg": m, "bearing_n_per_m": 1e8}
              for x, m in central.items()]
             + [{"link": f"{s}.planet{i + 1}", "inertia_kgm2": 1e-4, "mass_kg": mp,
                 "bearing_n_per_m": 2e8} for s, mp in (("A", 0.5), ("B", 0.7)) for i in range(3)])
    return {"frame": "housing", "links": ["housing", "s1", "c1", "c2"],
            "planetary": [stage("A", "s1", "c1"), stage("B", "c1", "c2")],
            "dynamics": {"module_m": MOD, "lateral": True, "links": links,
                         "meshes": [{"pair": p, "stiffness_n_per_m": 3e8} for p in "AB"]}}


def test_each_carrier_frame_holds_its_own_planets():
    """Two carriers: one rotating frame each, turning at its carrier's rate, holding the
    central members (coaxial with it) and its own planets only; K_Ω = Σ m DᵀD by hand (seed
    003 eqs 3.4-3.8): a carrier's translation carries its planets' masses, its rotation
    Σ m_p r_c² (the orbit)."""
    model = model_from_config(parse_config(_two_stages()))
    col = {nm: i for i, nm in enumerate(model.dof_names)}
    r_c = MOD * (ZS + ZP) / 2
    planets = {"A": 0.5, "B": 0.7}
    frames = {"c1": "A", "c2": "B"}
    assert len(model.rotating) == 2
    for (rate, gyro, k_om), (carrier, stage) in zip(model.rotating, frames.items(),
                                                    strict=True):
        unit = np.zeros(model.n)
        unit[col[f"{carrier}.theta"]] = 1.0
        assert np.array_equal(rate, unit)
        mp = planets[stage]
        want = {"s1.x": 1.0, "c1.x": 2.0, "c2.x": 3.0}
        want[f"{carrier}.x"] += 3 * mp
        want |= {k.replace(".x", ".y"): v for k, v in want.items()}
        want |= {f"{stage}.planet{i + 1}.{d}": mp for i in range(3) for d in ("zeta", "eta")}
        want[f"{carrier}.theta"] = 3 * mp * r_c**2
        got = {nm: k_om[i, i] for nm, i in col.items() if np.abs(k_om[i]).max() > 0}
        assert got == pytest.approx(want, rel=1e-12)
        other = "B" if stage == "A" else "A"
        rows = [i for nm, i in col.items() if nm.startswith(f"{other}.planet")]
        assert np.abs(gyro[rows]).max() == 0.0


@pytest.mark.parametrize("position_deg", [None, 35.0])
def test_parallel_pair_row_from_the_rigid_body_kinematics(position_deg):
    """Two gears turning in the frame, b's centre at ψ from a's (position_angle_deg, default
    0): the row = ±n·(u_a(C) − u_b(C)) at the pitch point C = r_a (cos ψ, sin ψ), u = d + θ ẑ ×
    (C − centre), n on one of the two lines of action at ±α from the common tangent."""
    d = _bevel_pair(90.0)
    d["parallel"] = [{"name": "p", "a": {"link": "a", "teeth": Z_IN},
                      "b": {"link": "b", "teeth": Z_OUT}}]
    del d["bevel"]
    if position_deg is not None:
        d["dynamics"]["meshes"][0]["position_angle_deg"] = position_deg
    model = model_from_config(parse_config(d), ["a"])
    col = {nm: i for i, nm in enumerate(model.dof_names)}
    assert _axes(model)["b"] == 0.0
    psi = math.radians(position_deg or 0.0)
    radial = np.array([math.cos(psi), math.sin(psi)])
    r_a, r_b = MOD * Z_IN / 2, MOD * Z_OUT / 2
    c = r_a * radial
    c_b = (r_a + r_b) * radial
    got = model.meshes[0].a
    fits = []
    for flank in (1.0, -1.0):
        n = _zx(radial) * math.cos(ALPHA) + flank * radial * math.sin(ALPHA)
        hand = np.zeros(model.n)
        hand[[col["a.x"], col["a.y"]]] += n
        hand[[col["b.x"], col["b.y"]]] -= n
        hand[col["a.theta"]] += n @ _zx(c)
        hand[col["b.theta"]] -= n @ _zx(c - c_b)
        fits.append(np.abs(got - math.copysign(1.0, got @ hand) * hand).max())
    assert min(fits) < 1e-12
