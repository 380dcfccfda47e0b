"""One assembly core (issue 11): the Lin & Parker planetary builder and the general mechanism
path register the same stage on the same :class:`Assembly` and give the same model.

References: the coupled Lin & Parker matrices of ``models/planetary/model.py`` (validated
against seed 003 in tests/validation/seed003) mapped to the general path's coordinates by the
hand-written map q_LP = T q (u = r θ; planets' angles relative to the carrier; ζ, η on the
pin plus the carrier's translation and orbit r_c θ_c). The simulations are compared through
the same map: Newmark's step is invariant under the congruence Tᵀ(·)T, so two equal systems
give equal trajectories up to rounding (1e-9 asked).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from geardyn.config.loader import parse_config
from geardyn.errors import ConfigError
from geardyn.models.core import model_from_config
from geardyn.models.core.assembly import Assembly, RankOne
from geardyn.models.core.system import linear_system
from geardyn.models.planetary.dynamics import MeshLaw, build_system
from geardyn.models.planetary.model import StageSpec, assemble
from geardyn.solve.integrate import newmark

from .test_model import (
    ALPHA,
    JC,
    JP,
    JR,
    JS,
    KB,
    KPB,
    KR,
    KRT,
    KS,
    MC,
    MP,
    MR,
    MS,
    NP,
    ZP,
    ZR,
    ZS,
    _lateral_config,
    _radii,
)

PSI = [2 * math.pi * i / NP for i in range(NP)]
AMP = 0.2  # relative amplitude of the sine mesh-stiffness tables
SAMPLES = 64  # graph.SAMPLES_PER_CYCLE


def _lin_parker(k_mesh: tuple[float, float] = (KS, KR)):  # noqa: ANN202
    rs, rp, rr, rc = _radii()

    def member(j: float, r: float, m: float, kb: float, kt: float = 0.0) -> dict:
        return dict(mass=m, inertia=j, radius=r, bearing=kb, torsional=kt)

    spec = StageSpec("st", NP, PSI, sun=member(JS, rs, MS, KB), ring=member(JR, rr, MR, KB, KRT),
                     carrier=member(JC, rc, MC, KB), planet=member(JP, rp, MP, 0.0),
                     alpha_s=ALPHA, alpha_r=ALPHA, k_sun_mesh=k_mesh[0], k_ring_mesh=k_mesh[1],
                     planet_bearing=KPB, z_sun=ZS, z_ring=ZR, z_planet=ZP, prefix=False)
    return assemble([spec], reduction="none")


def _general(mesh_model: str = "constant"):  # noqa: ANN202
    d = _lateral_config(True)
    d["dynamics"]["mesh_damping_ratio"] = 0.0
    for m in d["dynamics"]["meshes"]:
        m.update(model=mesh_model, amplitude=AMP, damping_ratio=0.0)
    return model_from_config(parse_config(d))


def _map(lp, model) -> np.ndarray:  # noqa: ANN001
    """T (LP DOFs × general DOFs) with q_LP = T q_general (module docstring)."""
    rs, rp, rr, rc = _radii()
    col = {nm: i for i, nm in enumerate(model.dof_names)}
    radius = {"sun": rs, "carrier": rc, "ring": rr}
    t = np.zeros((lp.n_full, model.n))
    for i, nm in enumerate(lp.dof_names):
        body, dof = nm.split(".")
        if body in radius:
            t[i, col[f"{body}.{'theta' if dof == 'u' else dof}"]] = (
                radius[body] if dof == "u" else 1.0)
            continue
        p = int(body[len("planet"):]) - 1
        c, s = math.cos(PSI[p]), math.sin(PSI[p])
        if dof == "u":
            t[i, [col[f"st.{body}.theta"], col["carrier.theta"]]] = rp
        elif dof == "zeta":
            t[i, [col[f"st.{body}.zeta"], col["carrier.x"], col["carrier.y"]]] = (1.0, c, s)
        else:
            t[i, [col[f"st.{body}.eta"], col["carrier.x"], col["carrier.y"],
                  col["carrier.theta"]]] = (1.0, -s, c, rc)
    return t


def _close(got: np.ndarray, want: np.ndarray, rel: float) -> bool:
    return bool(np.abs(got - want).max() <= rel * np.abs(want).max())


def test_both_builders_fill_one_assembly_with_the_same_matrices():
    """Same Assembly type; M, K, G, K_Ω equal through the DOF map (1e-9); one rotating frame
    each (the carrier's) with the same rate; the same element count by kind."""
    lp, model = _lin_parker(), _general()
    assert type(lp.assembly) is Assembly and type(model.assembly) is Assembly
    assert all(isinstance(e, RankOne) for e in lp.assembly.rank_one + model.assembly.rank_one)
    t = _map(lp, model)
    for key in ("M", "K", "G", "K_omega"):
        want = model.assembly.matrix(key)
        assert np.abs(want).max() > 0, key
        assert _close(t.T @ lp.assembly.matrix(key) @ t, want, 1e-9), key
    (name_lp, rate_lp, _, _), = lp.assembly.frame_terms()
    (name_g, rate_g, _, _), = model.assembly.frame_terms()
    assert (name_lp, name_g) == ("st", "carrier")
    assert _close(rate_lp @ t, rate_g, 1e-12)
    # 2 NP meshes; per member bearings: 2 per central member, 2 per planet, 1 ring support
    kinds_lp = [e.kind for e in lp.assembly.rank_one]
    kinds_g = [e.kind for e in model.assembly.rank_one]
    assert kinds_g.count("mesh") == kinds_lp.count("mesh_sun") + kinds_lp.count("mesh_ring")
    assert kinds_g.count("bearing") == kinds_lp.count("bearing") + kinds_lp.count(
        "planet_bearing") == 6 + 2 * NP


def _sine(k_mean: float, reverse: bool = False) -> np.ndarray:
    x = np.arange(SAMPLES) / SAMPLES
    tab = k_mean * (1 + AMP * np.sin(2 * math.pi * x))
    return np.roll(tab[::-1], 1) if reverse else tab  # tab(−X) on the same grid


def test_both_linear_systems_give_the_same_simulation():
    """The first 0.05 s of a run with sine mesh stiffness, gyroscopic terms, Rayleigh and
    modal damping, a torque on the sun and the balancing load on the carrier (the stage turns
    on at its start speed, ~47 sun mesh cycles): q_LP = T q_general (1e-9).

    The general path counts the ring mesh cycles the other way (X_ring = z_r(θ_r − θ_c)/2π,
    the planetary model's z_r(θ_c − θ_r)/2π), so the planetary ring law gets the table at −X;
    the planet phases are the same seed 004 Table 4-1 offsets (−rr here, +rr there)."""
    model = _general("sine")
    k_s, k_r = (float(np.mean(_sine(k))) for k in (KS, KR))
    lp = _lin_parker((k_s, k_r))
    t = _map(lp, model)
    laws = {("st", "sun"): MeshLaw(_sine(KS)), ("st", "ring"): MeshLaw(_sine(KR, True))}
    rs, _rp, _rr, rc = _radii()
    f_lp = np.zeros((2, lp.n_full))
    f_lp[:, lp.dof_names.index("sun.u")] = 40.0 / rs  # 40 N·m on the sun
    f_lp[:, lp.dof_names.index("carrier.u")] = -40.0 * (ZS + ZR) / ZS / rc  # ring held
    damping = dict(rayleigh=(2.0, 1e-6), modal_damping=0.01, gyroscopic=True,
                   force_t=np.array([0.0, 1.0]))
    sys_lp, _idx = build_system(lp, laws, force=f_lp, **damping)  # type: ignore[arg-type]
    sys_g = model.system(force=f_lp @ t, **damping)  # generalised forces Tᵀ f
    # the congruence holds for the constant parts too
    for key in ("M", "C", "K"):
        assert _close(t.T @ getattr(sys_lp, key) @ t, getattr(sys_g, key), 1e-9), key
    # rigid start: the sun at 300 rad/s with the ring held by its support (kinematic ratios)
    v_g = np.zeros(model.n)
    w_c = 300.0 * ZS / (ZS + ZR)
    v_g[model.dof_names.index("sun.theta")] = 300.0
    v_g[model.dof_names.index("carrier.theta")] = w_c
    for i in range(NP):  # planets relative to the carrier: ω_p − ω_c = −(ω_s − ω_c) z_s/z_p
        v_g[model.dof_names.index(f"st.planet{i + 1}.theta")] = -(300.0 - w_c) * ZS / ZP
    assert np.abs(model.stiffness_matrix() @ v_g).max() < 1e-6 * np.abs(
        model.stiffness_matrix()).max() * np.abs(v_g).max()
    dt, t_end = 2e-5, 0.05
    r_lp = newmark(sys_lp, np.zeros(lp.n_full), t @ v_g, t_end, dt, save_every=50)
    r_g = newmark(sys_g, np.zeros(model.n), v_g, t_end, dt, save_every=50)
    assert r_lp.status == r_g.status == "ok"
    assert r_g.t[-1] == pytest.approx(t_end)
    assert _close(r_g.q @ t.T, r_lp.q, 1e-9)
    assert _close(r_g.v @ t.T, r_lp.v, 1e-9)
    # the elastic part alone: every mesh's dynamic transmission error, matched by name (the
    # two builders may orient a mesh's line of action oppositely)
    names_lp = [lp.springs[i].name for i in _idx]
    for j, m in enumerate(model.meshes):
        role, planet = m.name.split(".")[1].split("-")
        i = names_lp.index(f"{planet}.mesh_{role}")
        sign = np.sign(sys_lp.springs.a[i] @ t @ sys_g.springs.a[j])
        assert _close(r_g.delta[:, j], sign * r_lp.delta[:, i], 1e-9), m.name
    # the meshes did vary and the frames did turn: not a trivially rigid run
    assert np.ptp(r_lp.k[:, 0]) > 0.1 * KS
    assert np.abs(r_g.q[-1, model.dof_names.index("carrier.x")]) > 0


def test_linear_system_from_an_assembly_by_hand():
    """linear_system on a two-DOF assembly against hand matrices: K₀ without the varying
    element, C = αM + βK_mean + c aaᵀ + a support damper, one frame's G, K_Ω at its rate."""
    asm = Assembly()
    asm.add_dofs("a", ["x", "y"], [2.0, 2.0])
    asm.add_rank_one(RankOne("bearing", "bearing", 1e6, asm.row({"a.x": 1.0}), c=3.0))
    mesh = asm.add_rank_one(RankOne("mesh", "mesh", 4e6, asm.row({"a.x": 1.0, "a.y": -1.0})))
    asm.add_frame("c", asm.row({"a.y": 0.5}))
    asm.add_mapped("a.frame", "rotating_frame", np.eye(2), frame="c",
                   G=2.0 * np.array([[0.0, -2.0], [2.0, 0.0]]), K_omega=2.0 * np.eye(2))
    row = dict(a=mesh.a, b=np.zeros(2), k=np.array([4e6]))
    sys = linear_system(asm, [row], [1], rayleigh=(0.5, 1e-4),
                        support_damping={"a.y": 7.0}, gyroscopic=True)
    k_mean = np.array([[1e6 + 4e6, -4e6], [-4e6, 4e6]])
    np.testing.assert_array_equal(sys.K, [[1e6, 0.0], [0.0, 0.0]])
    np.testing.assert_allclose(sys.C, 0.5 * np.diag([2.0, 2.0]) + 1e-4 * k_mean
                               + np.diag([3.0, 7.0]), rtol=1e-15)
    np.testing.assert_array_equal(sys.gyro_g[0], [[0.0, -4.0], [4.0, 0.0]])
    np.testing.assert_array_equal(sys.gyro_k[0], np.diag([2.0, 2.0]))
    np.testing.assert_array_equal(sys.gyro_rate[0], [0.0, 0.5])
    assert sys.springs.a.shape == (1, 2)
    with pytest.raises(ConfigError, match="support_damping: unknown DOF 'a.z'"):
        linear_system(asm, support_damping={"a.z": 1.0})
    with pytest.raises(ConfigError, match="rotating frame 'c' is defined twice"):
        asm.add_frame("c", np.zeros(2))
    with pytest.raises(ValueError, match="unknown rotating frame 'd'"):
        asm.add_block("e", "rotating_frame", [0], frame="d", G=np.zeros((1, 1)))
    with pytest.raises(ValueError, match="map of 3 columns for 2 DOFs"):
        asm.add_mapped("e", "inertia", np.ones((1, 3)), M=np.eye(1))
