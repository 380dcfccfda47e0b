"""General torsional model (graph → model, issue 11): rigid-body modes, closed forms and the
equality with the Lin & Parker planetary assembly."""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest
import scipy.linalg as sla

from geardyn.config.loader import parse_config
from geardyn.errors import ConfigError
from geardyn.kinematics.willis import analyze_graph
from geardyn.models.core import model_from_config
from geardyn.models.planetary.model import StageSpec, assemble

KINEMATIC_EXAMPLES = ["car_differential", "alouette3_mgb", "reclaimer_drive",
                      "planetary_reclaimer", "seed004_planetary", "planetary_lin_parker"]
DYNAMIC_EXAMPLES = ["car_differential_dynamics", "alouette3_mgb_dynamics",
                    "reclaimer_whole_drive", "three_stage_gearbox"]


def _mechanism_only(examples_dir, name: str) -> dict:
    d = tomllib.loads((examples_dir / f"{name}.toml").read_text())
    for key in ("planetary_dynamics", "sensors", "diagnosis", "gear_geometry", "transmission"):
        d.pop(key, None)
    return d


def _with_dynamics(examples_dir, name: str) -> dict:
    d = _mechanism_only(examples_dir, name)
    d.setdefault("dynamics", {"module_m": 0.005})
    return d


def rigid_modes(model) -> np.ndarray:  # noqa: ANN001
    """Null space of K (the rigid-body mode shapes of the undamped model)."""
    return sla.null_space(model.stiffness_matrix(), rcond=1e-10)


@pytest.mark.parametrize("name", KINEMATIC_EXAMPLES + DYNAMIC_EXAMPLES)
def test_rigid_body_modes_span_the_kinematic_nullspace(examples_dir, name):
    """Seed 000 eq 5: the rigid-body modes, mapped to link angular velocities (Ω = P q̇), span
    ker M of the kinematic constraint matrix; principal angles < 1e-8."""
    cfg = parse_config(_with_dynamics(examples_dir, name))
    model = model_from_config(cfg)
    kin = analyze_graph(cfg.graph())
    null = rigid_modes(model)
    # a rotor held only by a drive (motor behind a fluid coupling) adds its own rigid mode
    held = {s.name for s in model.springs} and {b for sh in cfg.dynamics.shafts
                                                 for b in (sh.a, sh.b)}
    free = [r.name for r in cfg.dynamics.rotors if r.name not in held]
    assert null.shape[1] == kin.dof + len(free)
    angles = sla.subspace_angles(sla.orth(model.link_velocity @ null), kin.nullspace)
    assert angles.max() < 1e-8
    # and the mass matrix is symmetric positive definite
    assert np.allclose(model.M, model.M.T, rtol=0, atol=1e-12 * np.abs(model.M).max())
    assert np.linalg.eigvalsh(model.M).min() > 0


def _pair(kind: str, za: int = 20, zb: int = 50) -> dict:
    stage = {"name": "p", "a": {"link": "a", "teeth": za}, "b": {"link": "b", "teeth": zb}}
    return {
        "frame": "housing",
        "links": ["housing", "a", "b"],
        kind: [stage],
        "dynamics": {
            "module_m": 0.004, "pressure_angle_deg": 20.0,
            "meshes": [{"pair": "p", "stiffness_n_per_m": 3e8}],
            "links": [{"link": "a", "inertia_kgm2": 0.02}, {"link": "b", "inertia_kgm2": 0.3}],
        },
    }


@pytest.mark.parametrize("kind", ["parallel", "bevel"])
def test_two_gears_on_rigid_shafts(kind):
    """ω² = k (r_ba²/J_a + r_bb²/J_b) (one elastic mode of two discs joined by the mesh
    spring; r_b = m z cos α / 2, the mean cone radius for the bevel pair)."""
    model = model_from_config(parse_config(_pair(kind)))
    w2 = sla.eigh(model.stiffness_matrix(), model.M, eigvals_only=True)
    rb = [0.004 * z * math.cos(math.radians(20)) / 2 for z in (20, 50)]
    want = 3e8 * (rb[0] ** 2 / 0.02 + rb[1] ** 2 / 0.3)
    assert w2[0] == pytest.approx(0.0, abs=1e-9 * want)
    assert w2[1] == pytest.approx(want, rel=1e-12)


# ---- planetary stage: Kahraman (1994) torsional model and Lin & Parker (1999) -------------

ZS, ZP, ZR, NP = 25, 35, 95, 4
MOD, ALPHA = 0.001, math.radians(24.6)
JS, JC, JP, JR, MP = 2.015e-4, 2.264e-2, 6.18e-4, 2.238e-2, 0.66
KS, KR = 5e8, 4e8


def _stage_config(ring_free: bool = False, k_rt: float = 7.462e6) -> dict:
    links = ["housing", "sun", "carrier"] + (["ring"] if ring_free else [])
    dyn = {
        "module_m": MOD, "pressure_angle_deg": math.degrees(ALPHA),
        "meshes": [{"pair": "st.sun", "stiffness_n_per_m": KS},
                   {"pair": "st.ring", "stiffness_n_per_m": KR}],
        "links": [{"link": "sun", "inertia_kgm2": JS}, {"link": "carrier", "inertia_kgm2": JC}]
        + [{"link": f"st.planet{i + 1}", "inertia_kgm2": JP, "mass_kg": MP} for i in range(NP)]
        + ([{"link": "ring", "inertia_kgm2": JR}] if ring_free else []),
    }
    if ring_free:
        dyn["shafts"] = [{"name": "ring_support", "a": "ring", "b": "housing",
                          "torsional_nm_per_rad": k_rt}]
    return {
        "frame": "housing", "links": links,
        "planetary": [{"name": "st", "sun": "sun", "ring": "ring" if ring_free else "housing",
                       "carrier": "carrier", "sun_teeth": ZS, "planet_teeth": ZP,
                       "ring_teeth": ZR, "n_planets": NP}],
        "dynamics": dyn,
    }


def _radii() -> tuple[float, float, float, float]:
    rs, rp, rr = (MOD * z * math.cos(ALPHA) / 2 for z in (ZS, ZP, ZR))
    rc = MOD * (ZS + ZP) / 2  # planet-circle radius; r_c cos α = r_bs + r_bp exactly
    return rs, rp, rr, rc


def kahraman_torsional_eigenvalues() -> np.ndarray:
    """Closed-form ω² (rad²/s²) of the purely torsional fixed-ring model (Kahraman 1994;
    Lin & Parker 1999 §4), N identical equally spaced planets:

    * planet modes (sun and carrier at rest, Σ planet motions = 0), multiplicity N − 1:
      ω² = (k_s + k_r) r_bp² / J_p;
    * rotational modes: with coordinates (θ_s, θ_c, θ_p) (all planets alike) the meshes deflect
      along s = (r_bs, −(r_bs + r_bp), r_bp) and r = (0, −(r_br − r_bp), −r_bp) (ring fixed; the
      Lin & Parker deflections with r_c cos α = r_bs + r_bp = r_br − r_bp) and
      M = diag(J_s, J_c + N m_p r_c², N J_p), K = N k_s s sᵀ + N k_r r rᵀ. K has rank 2, so
      besides ω = 0 the roots of λ² − T λ + D = 0 with T = tr(M⁻¹K) =
      N Σ_i (k_s s_i² + k_r r_i²)/M_i and, by Cauchy–Binet, D = N² k_s k_r Σ_{i<j}
      (s_i r_j − s_j r_i)²/(M_i M_j).
    """
    rs, rp, rr, rc = _radii()
    s = np.array([rs, -(rs + rp), rp])
    r = np.array([0.0, -(rr - rp), -rp])
    m = np.array([JS, JC + NP * MP * rc**2, NP * JP])
    t = NP * np.sum((KS * s**2 + KR * r**2) / m)
    d = NP**2 * KS * KR * sum((s[i] * r[j] - s[j] * r[i]) ** 2 / (m[i] * m[j])
                              for i in range(3) for j in range(i + 1, 3))
    root = math.sqrt(t * t - 4 * d)
    planet = (KS + KR) * rp**2 / JP
    return np.sort([0.0, (t - root) / 2, (t + root) / 2] + [planet] * (NP - 1))


def test_kahraman_closed_form_against_a_direct_eigensolve():
    """The closed form itself, checked by an independent small computation: numpy's
    eigenvalues of the hand-built 3×3 rotational model and of the planet-mode equation."""
    rs, rp, rr, rc = _radii()
    s = np.array([rs, -(rs + rp), rp])
    r = np.array([0.0, -(rr - rp), -rp])
    m = np.diag([JS, JC + NP * MP * rc**2, NP * JP])
    k = NP * KS * np.outer(s, s) + NP * KR * np.outer(r, r)
    # the deflection vectors vanish on the kinematic rigid motion (fixed ring: ω_s/ω_c =
    # 1 + z_r/z_s, ω_p/ω_c = 1 − z_r/z_p), independently of the builder
    rigid = np.array([1 + ZR / ZS, 1.0, 1 - ZR / ZP])
    assert abs(s @ rigid) < 1e-15 and abs(r @ rigid) < 1e-15
    direct = np.sort(sla.eigh(k, m, eigvals_only=True))
    closed = kahraman_torsional_eigenvalues()
    rot = np.delete(closed, np.where(np.isclose(closed, (KS + KR) * rp**2 / JP))[0])
    assert direct[1:] == pytest.approx(rot[1:], rel=1e-10)


def test_fixed_ring_stage_has_the_kahraman_eigenvalues():
    model = model_from_config(parse_config(_stage_config()))
    w2 = np.sort(sla.eigh(model.stiffness_matrix(), model.M, eigvals_only=True))
    want = kahraman_torsional_eigenvalues()
    assert w2[0] == pytest.approx(0.0, abs=1e-9 * want[-1])
    assert w2[1:] == pytest.approx(want[1:], rel=1e-9)


def _lin_parker(ring_free: bool, k_rt: float = 7.462e6) -> tuple[np.ndarray, np.ndarray, list]:
    """Today's planetary assembly (models/planetary/model.py, torsional reduction of the
    Lin & Parker model) for the same stage; a fixed ring drops its u DOF."""
    rs, rp, rr, rc = _radii()

    def member(j: float, r: float, m: float = 1.0, kt: float = 0.0) -> dict:
        return dict(mass=m, inertia=j, radius=r, bearing=1e8, torsional=kt)

    spec = StageSpec("st", NP, [2 * math.pi * i / NP for i in range(NP)],
                     sun=member(JS, rs), ring=member(JR, rr, kt=k_rt if ring_free else 0.0),
                     carrier=member(JC, rc), planet=member(JP, rp, MP),
                     alpha_s=ALPHA, alpha_r=ALPHA, k_sun_mesh=KS, k_ring_mesh=KR,
                     planet_bearing=1e8, z_sun=ZS, z_ring=ZR, z_planet=ZP, prefix=False)
    lp = assemble([spec], reduction="torsional")
    m, k, names = lp.mass_matrix(), lp.stiffness_matrix(), lp.names
    if not ring_free:
        keep = [i for i, n in enumerate(names) if n != "ring.u"]
        m, k, names = m[np.ix_(keep, keep)], k[np.ix_(keep, keep)], [names[i] for i in keep]
    return m, k, names


@pytest.mark.parametrize("ring_free", [False, True])
def test_general_path_equals_the_lin_parker_assembly(ring_free):
    """A [[planetary]] stage through the general path gives the matrices and frequencies of
    today's Lin & Parker assembly (torsional reduction), to 1e-9."""
    model = model_from_config(parse_config(_stage_config(ring_free)))
    m_lp, k_lp, names = _lin_parker(ring_free)
    rs, rp, rr, rc = _radii()
    # q_LP (u = r θ, planets absolute) = T q (planets relative to the carrier)
    radius = {"sun": rs, "carrier": rc, "ring": rr}
    t = np.zeros((len(names), model.n))
    for i, nm in enumerate(names):
        body = nm.split(".")[0]
        if body.startswith("planet"):
            t[i, model.dof_names.index(f"st.{body}.theta")] = rp
            t[i, model.dof_names.index("carrier.theta")] = rp
        else:
            t[i, model.dof_names.index(f"{body}.theta")] = radius[body]
    scale_m, scale_k = np.abs(model.M).max(), np.abs(model.stiffness_matrix()).max()
    assert np.abs(t.T @ m_lp @ t - model.M).max() < 1e-9 * scale_m
    assert np.abs(t.T @ k_lp @ t - model.stiffness_matrix()).max() < 1e-9 * scale_k
    w2_gen = sla.eigh(model.stiffness_matrix(), model.M, eigvals_only=True)
    w2_lp = sla.eigh(k_lp, m_lp, eigvals_only=True)
    rigid = w2_lp < 1e-9 * w2_lp.max()
    assert rigid.sum() == 1  # sun and carrier turn freely (the ring is held)
    assert np.abs(w2_gen[rigid]).max(initial=0.0) < 1e-9 * w2_lp.max()
    # natural frequencies (Hz) of the elastic modes
    f_gen, f_lp = (np.sqrt(w[~rigid]) / (2 * np.pi) for w in (w2_gen, w2_lp))
    assert f_gen == pytest.approx(f_lp, rel=1e-9)


def test_link_without_gear_needs_an_inertia():
    d = _pair("parallel")
    d["links"].append("idle")
    d["turning_pairs"] = [{"links": ["idle", "housing"], "axis": "z"}]
    with pytest.raises(ConfigError, match="link 'idle' carries no gear"):
        model_from_config(parse_config(d))


def test_dynamics_section_names_unknown_items():
    d = _pair("parallel")
    d["dynamics"]["meshes"].append({"pair": "nope"})
    d["dynamics"]["shafts"] = [{"name": "s", "a": "a", "b": "ghost",
                                "torsional_nm_per_rad": 1.0}]
    with pytest.raises(ConfigError) as exc:
        parse_config(d)
    text = str(exc.value)
    assert "dynamics.meshes[1].pair: unknown gear pair or stage 'nope'" in text
    assert "dynamics.shafts[0] 's'.b: unknown body 'ghost'" in text


def test_mesh_stiffness_from_the_gear_geometry_pe_table():
    """model = 'gear_geometry': the mesh uses the potential-energy table of the pair's
    [[gear_geometry]] entry (geardyn.gears.pe_stiffness, validated in tests/gears), one mesh
    cycle, and its mean; the rigid-body mode still follows the kinematics."""
    from geardyn.config.gears import pair_model
    from geardyn.gears.pe_stiffness import mesh_stiffness

    d = _pair("parallel", 23, 67)
    d["dynamics"]["meshes"] = [{"pair": "p", "model": "gear_geometry"}]
    # the entry's module (3 mm) sizes the pair, not the section's 4 mm
    d["gear_geometry"] = [{"pair": "p", "normal_module_m": 0.003, "face_width_m": 0.03}]
    cfg = parse_config(d)
    model = model_from_config(cfg)
    table = mesh_stiffness(pair_model(cfg, "p").geometry, n_per_cycle=64).total
    mesh = model.meshes[0]
    assert mesh.k == pytest.approx(table, rel=1e-12)
    assert mesh.k_mean == pytest.approx(float(np.mean(table)), rel=1e-12)
    assert 1e8 < mesh.k_mean < 1e10  # a 30 mm wide steel spur pair (c_γ·b ≈ 6e8 N/m)
    assert mesh.base_radius_a == pytest.approx(0.003 * 23 * math.cos(math.radians(20)) / 2)
    null = rigid_modes(model)
    assert null.shape[1] == 1
    assert null[0, 0] / null[1, 0] == pytest.approx(-67 / 23, rel=1e-12)


def test_helical_pair_from_the_gear_geometry_uses_transverse_base_radii():
    """A helical [[gear_geometry]] pair (β = 20°): the torsional mesh row uses the transverse
    base radii r_b = m_n z cos α_t / (2 cos β), tan α_t = tan α_n / cos β (ISO 21771), the same
    as the involute geometry of geardyn.gears (the PE table is along the transverse line of
    action), and the torsional frequency is √(k̄ (r_ba²/J_a + r_bb²/J_b))."""
    from geardyn.config.gears import pair_model

    d = _pair("parallel", 23, 67)
    d["dynamics"]["meshes"] = [{"pair": "p", "model": "gear_geometry"}]
    d["gear_geometry"] = [{"pair": "p", "normal_module_m": 0.003, "face_width_m": 0.03,
                           "helix_angle_deg": 20.0}]
    cfg = parse_config(d)
    model = model_from_config(cfg)
    mesh = model.meshes[0]
    beta, an = math.radians(20.0), math.radians(20.0)
    at = math.atan(math.tan(an) / math.cos(beta))
    rb = [0.003 * z * math.cos(at) / (2 * math.cos(beta)) for z in (23, 67)]
    assert (mesh.base_radius_a, mesh.base_radius_b) == pytest.approx(rb, rel=1e-12)
    g = pair_model(cfg, "p").geometry
    assert (mesh.base_radius_a, mesh.base_radius_b) == pytest.approx(g.base_radius, rel=1e-12)
    ja, jb = (model.body(x).inertia for x in (mesh.link_a, mesh.link_b))
    w2 = sla.eigh(model.stiffness_matrix(), model.mass_matrix(), eigvals_only=True)
    assert w2.max() == pytest.approx(mesh.k_mean * (rb[0] ** 2 / ja + rb[1] ** 2 / jb),
                                     rel=1e-9)


MS, MC, MR = 0.4, 5.43, 2.35  # kg (Lin & Parker style stage of examples/planetary_lin_parker)
KB, KPB, KRT = 1e8, 2e8, 7.462e6


def _lateral_config(ring_free: bool) -> dict:
    d = _stage_config(ring_free, KRT)
    dyn = d["dynamics"]
    dyn["lateral"] = True
    mass = {"sun": MS, "carrier": MC, "ring": MR}
    for lk in dyn["links"]:
        lk["bearing_n_per_m"] = KPB if ".planet" in lk["link"] else KB
        if lk["link"] in mass:
            lk["mass_kg"] = mass[lk["link"]]
    return d


@pytest.mark.parametrize("ring_free", [False, True])
def test_lateral_general_path_equals_the_coupled_lin_parker_model(ring_free):
    """With lateral DOFs, a [[planetary]] stage through the general path gives the matrices
    and frequencies of today's coupled Lin & Parker assembly (reduction 'none': x, y, u of
    sun/ring/carrier, ζ, η, u of the planets; seed 003 eqs 3.2-3.26), to 1e-9."""
    model = model_from_config(parse_config(_lateral_config(ring_free)))
    rs, rp, rr, rc = _radii()

    def member(j: float, r: float, m: float, kb: float, kt: float = 0.0) -> dict:
        return dict(mass=m, inertia=j, radius=r, bearing=kb, torsional=kt)

    psi = [2 * math.pi * i / NP for i in range(NP)]
    spec = StageSpec("st", NP, psi, sun=member(JS, rs, MS, KB),
                     ring=member(JR, rr, MR, KB, KRT if ring_free else 0.0),
                     carrier=member(JC, rc, MC, KB), planet=member(JP, rp, MP, 0.0),
                     alpha_s=ALPHA, alpha_r=ALPHA, k_sun_mesh=KS, k_ring_mesh=KR,
                     planet_bearing=KPB, z_sun=ZS, z_ring=ZR, z_planet=ZP, prefix=False)
    lp = assemble([spec], reduction="none")
    m_lp, k_lp, names = lp.mass_matrix(), lp.stiffness_matrix(), lp.names
    if not ring_free:
        keep = [i for i, nm in enumerate(names) if not nm.startswith("ring.")]
        m_lp, k_lp, names = m_lp[np.ix_(keep, keep)], k_lp[np.ix_(keep, keep)], \
            [names[i] for i in keep]
    col = {nm: i for i, nm in enumerate(model.dof_names)}
    radius = {"sun": rs, "carrier": rc, "ring": rr}
    t = np.zeros((len(names), model.n))
    for i, nm in enumerate(names):
        body, dof = nm.split(".")
        if body in radius:
            t[i, col[f"{body}.{'theta' if dof == 'u' else dof}"]] = radius[body] if dof == "u" \
                else 1.0
            continue
        p = int(body[len("planet"):]) - 1
        c, s = math.cos(psi[p]), math.sin(psi[p])
        if dof == "u":  # absolute planet rotation
            t[i, col[f"st.{body}.theta"]] = rp
            t[i, col["carrier.theta"]] = rp
        elif dof == "zeta":
            t[i, col[f"st.{body}.zeta"]] = 1.0
            t[i, col["carrier.x"]], t[i, col["carrier.y"]] = c, s
        else:  # eta: pin displacement + carrier rotation r_c θ_c
            t[i, col[f"st.{body}.eta"]] = 1.0
            t[i, col["carrier.x"]], t[i, col["carrier.y"]] = -s, c
            t[i, col["carrier.theta"]] = rc
    kk = model.stiffness_matrix()
    assert np.abs(t.T @ m_lp @ t - model.M).max() < 1e-9 * np.abs(model.M).max()
    assert np.abs(t.T @ k_lp @ t - kk).max() < 1e-9 * np.abs(kk).max()
    # gyroscopic and centripetal matrices of the carrier frame (seed 003 eqs 3.4-3.8)
    g_lp, ko_lp = lp.gyroscopic_matrix(), lp.centripetal_matrix()
    if not ring_free:
        g_lp, ko_lp = g_lp[np.ix_(keep, keep)], ko_lp[np.ix_(keep, keep)]
    g, ko = model.gyroscopic_matrix(), model.centripetal_matrix()
    assert np.abs(g).max() > 0
    assert np.abs(t.T @ g_lp @ t - g).max() < 1e-12 * np.abs(g).max()
    assert np.abs(t.T @ ko_lp @ t - ko).max() < 1e-12 * np.abs(ko).max()
    (rate, _, _), = model.rotating  # one carrier frame, turning at the carrier's speed
    assert np.array_equal(rate, model.bodies["carrier"].rotation)
    w2_gen = sla.eigh(kk, model.M, eigvals_only=True)
    w2_lp = sla.eigh(k_lp, m_lp, eigvals_only=True)
    rigid = w2_lp < 1e-9 * w2_lp.max()
    assert rigid.sum() == 1
    assert np.abs(w2_gen[rigid]).max() < 1e-9 * w2_lp.max()
    f_gen, f_lp = (np.sqrt(w[~rigid]) / (2 * np.pi) for w in (w2_gen, w2_lp))
    assert f_gen == pytest.approx(f_lp, rel=1e-9)


@pytest.mark.parametrize("name", ["three_stage_gearbox", "alouette3_mgb_dynamics",
                                  "car_differential_dynamics"])
def test_lateral_model_keeps_the_kinematic_rigid_modes(examples_dir, name):
    """Lateral DOFs held by bearings add no rigid-body mode (principal angles < 1e-8)."""
    d = _mechanism_only(examples_dir, name)
    cfg0 = parse_config(d)
    d["dynamics"]["lateral"] = True
    given = {lk["link"] for lk in d["dynamics"].get("links", [])}
    d["dynamics"].setdefault("links", [])
    for lk in d["dynamics"]["links"]:
        lk["bearing_n_per_m"] = 1e9
    d["dynamics"]["links"] += [{"link": x, "bearing_n_per_m": 1e9}
                               for x in cfg0.graph().links
                               if x not in given and x != cfg0.frame]
    cfg = parse_config(d)
    model = model_from_config(cfg)
    assert any(nm.endswith((".x", ".zeta")) for nm in model.dof_names)
    kin = analyze_graph(cfg.graph())
    null = rigid_modes(model)
    held = {b for sh in cfg.dynamics.shafts for b in (sh.a, sh.b)}
    free = [r.name for r in cfg.dynamics.rotors if r.name not in held]
    assert null.shape[1] == kin.dof + len(free)
    angles = sla.subspace_angles(sla.orth(model.link_velocity @ null), kin.nullspace)
    assert angles.max() < 1e-8


@pytest.mark.parametrize(("ring", "carrier", "dof"), [("ring", "housing", 1),  # star gear
                                                      ("ring", "carrier", 2)])  # differential
def test_other_planetary_arrangements(ring, carrier, dof):
    """Star (carrier fixed: ω_r/ω_s = −z_s/z_r) and two-DOF differential stages: rigid modes =
    kinematic nullspace; the star's rigid mode has the textbook ratio."""
    links = ["housing", "sun", ring] + ([carrier] if carrier != "housing" else [])
    d = {"frame": "housing", "links": links,
         "planetary": [{"name": "st", "sun": "sun", "ring": ring, "carrier": carrier,
                        "sun_teeth": ZS, "planet_teeth": ZP, "ring_teeth": ZR,
                        "n_planets": NP}],
         "dynamics": {"module_m": MOD}}
    cfg = parse_config(d)
    model = model_from_config(cfg)
    kin = analyze_graph(cfg.graph())
    null = rigid_modes(model)
    assert null.shape[1] == kin.dof == dof
    assert sla.subspace_angles(model.link_velocity @ null, kin.nullspace).max() < 1e-8
    if dof == 1:
        om = model.link_velocity @ null[:, 0]
        g = cfg.graph()
        assert (om[g.index("ring")] / om[g.index("sun")]).real == pytest.approx(-ZS / ZR,
                                                                                rel=1e-12)


def test_campbell_of_the_lateral_stage_equals_lin_parker():
    """Frequencies against carrier speed with the carrier frame's G and K_Ω (seed 003 eq 3.1):
    the general lateral model gives solve.modal.campbell of the coupled Lin & Parker model."""
    from geardyn.models.core.modal import core_campbell
    from geardyn.models.planetary.modal import campbell

    model = model_from_config(parse_config(_lateral_config(True)))
    rs, rp, rr, rc = _radii()

    def member(j: float, r: float, m: float, kb: float, kt: float = 0.0) -> dict:
        return dict(mass=m, inertia=j, radius=r, bearing=kb, torsional=kt)

    spec = StageSpec("st", NP, [2 * math.pi * i / NP for i in range(NP)],
                     sun=member(JS, rs, MS, KB), ring=member(JR, rr, MR, KB, KRT),
                     carrier=member(JC, rc, MC, KB), planet=member(JP, rp, MP, 0.0),
                     alpha_s=ALPHA, alpha_r=ALPHA, k_sun_mesh=KS, k_ring_mesh=KR,
                     planet_bearing=KPB, z_sun=ZS, z_ring=ZR, z_planet=ZP, prefix=False)
    lp = assemble([spec], reduction="none")
    speeds = np.array([0.0, 200.0, 600.0])
    got = core_campbell(model, "carrier", speeds).values
    want = campbell(lp, speeds).values
    assert got[:, 1:] == pytest.approx(want[:, 1:], rel=1e-9)
    assert not np.allclose(want[0], want[-1])  # the speed does split the frequencies
