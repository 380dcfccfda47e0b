"""Torsional FE shafts between links in the general [dynamics] model (issue 11): element
convergence to the continuous shaft (closed forms), the two-disc shaft, the massless and
one-element limits, kinematic invariants of an example mechanism, config errors."""

from __future__ import annotations

import math
import tomllib
import warnings

import numpy as np
import pytest
import scipy.linalg as sla
import xarray as xr
from scipy.optimize import brentq
from typer.testing import CliRunner

from geardyn.cli import app
from geardyn.config.dynamics import ShaftDynamics
from geardyn.config.loader import parse_config
from geardyn.errors import ConfigError
from geardyn.kinematics.willis import analyze_graph
from geardyn.models.core import model_from_config
from geardyn.models.core.assembly import Assembly
from geardyn.models.core.fe_shafts import TorsionalOnlyWarning, add_shaft_nodes, stamp_fe_shaft
from geardyn.models.core.simulate import integrate, prepare

L, D_OUT, G, RHO = 1.2, 0.05, 80e9, 7850.0
C_WAVE = math.sqrt(G / RHO)  # torsional wave speed (m/s)
IP = math.pi * D_OUT**4 / 32
J_SHAFT = RHO * IP * L  # polar inertia of the whole shaft (kg·m²)
K_SHAFT = G * IP / L


def _shaft(elements: int, **kw: float) -> ShaftDynamics:
    args = dict(name="s", a="d1", b="d2", outer_diameter_m=D_OUT, length_m=L,
                shear_modulus_pa=G, density_kg_m3=RHO, elements=elements)
    args.update(kw)
    return ShaftDynamics(**args)  # type: ignore[arg-type]


def _line(sh: ShaftDynamics, discs: tuple[float, float] | None) -> Assembly:
    """The shaft alone on an assembly: end a on DOF d1.theta; end b on d2.theta (discs J1, J2)
    or on the frame (discs None: fixed at b, free at a)."""
    asm = Assembly()
    asm.add_dofs("d1", ["theta"], [discs[0] if discs else 0.0])
    if discs:
        asm.add_dofs("d2", ["theta"], [discs[1]])
    add_shaft_nodes(asm, [sh])
    end_b = asm.row({"d2.theta": 1.0}) if discs else np.zeros(asm.n)
    stamp_fe_shaft(asm, sh, asm.row({"d1.theta": 1.0}), end_b)
    return asm


def _omega(asm: Assembly) -> np.ndarray:
    w2 = sla.eigh(asm.matrix("K"), asm.matrix("M"), eigvals_only=True)
    return np.sqrt(np.clip(w2, 0.0, None))


# ---- (a) uniform shaft, fixed–free -----------------------------------------------------------

def test_fixed_free_shaft_equals_the_discrete_dispersion_relation():
    """Uniform mesh of N linear elements, consistent mass: θ_j = sin(jμ) solves every node
    equation with ω² = (6 c²/h²)(1 − cos μ)/(2 + cos μ), and the free end needs cos(Nμ) = 0,
    μ_n = (2n − 1)π/(2N) (derived from the element matrices; an independent closed form of the
    assembled FE problem). Frequencies to 1e-10."""
    n_el = 12
    h = L / n_el
    w = _omega(_line(_shaft(n_el), None))
    mu = (2 * np.arange(1, n_el + 1) - 1) * math.pi / (2 * n_el)
    want = np.sqrt(6 * C_WAVE**2 / h**2 * (1 - np.cos(mu)) / (2 + np.cos(mu)))
    assert w == pytest.approx(want, rel=1e-10)


def test_fixed_free_shaft_converges_to_the_closed_form_at_the_h2_rate():
    """ω_n = (2n − 1)π/(2L) √(G/ρ) of the continuous shaft (fixed–free torsion, e.g. Rao,
    *Vibration of Continuous Systems*, torsional vibration of shafts). Consistent mass is a
    Rayleigh–Ritz bound: ω_h > ω_n, relative error ≈ (k_n h)²/24 with k_n = ω_n / c, so halving
    h divides it by 4 (observed order 2 ± 0.02 from 4 to 64 elements)."""
    exact = (2 * np.arange(1, 3) - 1) * math.pi / (2 * L) * C_WAVE
    errors = []
    for n_el in (4, 8, 16, 32, 64):
        w = _omega(_line(_shaft(n_el), None))[:2]
        assert (w > exact).all()
        errors.append(w / exact - 1)
    errors = np.array(errors)
    order = np.log2(errors[:-1] / errors[1:])
    assert order == pytest.approx(2.0, abs=0.02)
    # leading term (k h)²/24 at 64 elements, to 0.5 %
    kh = exact / C_WAVE * L / 64
    assert errors[-1] == pytest.approx(kh**2 / 24, rel=5e-3)


# ---- (b) shaft with two end discs ----------------------------------------------------------

def two_disc_roots(r1: float, r2: float, count: int = 2) -> np.ndarray:
    """Roots x = βL > 0 of the continuous shaft with end discs J1 = r1 J_s, J2 = r2 J_s
    (J_s = ρ I_p L). θ = A cos βx + B sin βx, discs −J1 ω² θ(0) = G I_p θ'(0) and J2 ω² θ(L) =
    G I_p θ'(L), a_i = J_i ω²/(G I_p β) = r_i βL, give (a1 + a2) cos βL + (1 − a1 a2) sin βL = 0,
    i.e. tan x = (r1 + r2) x / (r1 r2 x² − 1) (derived here; the classical shaft with two end
    discs); ω = x c / L."""
    def f(x: float) -> float:
        return (r1 + r2) * x * math.cos(x) + (1 - r1 * r2 * x * x) * math.sin(x)

    grid = np.linspace(1e-6, 20.0, 20001)
    vals = np.array([f(x) for x in grid])
    roots = [brentq(f, grid[i], grid[i + 1], xtol=1e-15)
             for i in np.flatnonzero(np.sign(vals[:-1]) != np.sign(vals[1:]))]
    return np.array(roots[:count])


def test_two_disc_roots_reduce_to_the_two_inertia_spring():
    """Massless limit of the transcendental equation (J_s ≪ J1, J2): ω² = k (1/J1 + 1/J2)."""
    r1, r2 = 2e6, 5e5
    x = two_disc_roots(r1, r2, 1)[0]
    assert x**2 == pytest.approx((r1 + r2) / (r1 * r2), rel=1e-6)


def test_shaft_with_end_discs_converges_to_the_transcendental_roots():
    """End discs J1 = 2 J_s, J2 = J_s / 2 (the shaft's own inertia matters): the first two
    elastic FE frequencies converge to x_n c / L from above at the h² rate."""
    r1, r2 = 2.0, 0.5
    exact = two_disc_roots(r1, r2) * C_WAVE / L
    errors = []
    for n_el in (4, 8, 16, 32):
        w = _omega(_line(_shaft(n_el), (r1 * J_SHAFT, r2 * J_SHAFT)))
        assert w[0] == pytest.approx(0.0, abs=1e-6 * exact[0])  # free–free: rigid rotation
        assert (w[1:3] > exact).all()
        errors.append(w[1:3] / exact - 1)
    errors = np.array(errors)
    assert errors[-1].max() < 2e-3
    assert np.log2(errors[:-1] / errors[1:]) == pytest.approx(2.0, abs=0.05)


def test_one_element_is_the_two_inertia_system_with_consistent_mass():
    """elements = 1: M = [[J1 + J_s/3, J_s/6], [J_s/6, J2 + J_s/3]], K = k [[1, −1], [−1, 1]]:
    ω² = k (M11 + M22 + 2 M12) / det M (1e-12); massless shaft (ρ → 1e-6 kg/m³): the spring
    closed form ω² = k (1/J1 + 1/J2) (1e-9)."""
    j1, j2 = 0.8, 0.3
    w = _omega(_line(_shaft(1), (j1, j2)))
    m11, m22, m12 = j1 + J_SHAFT / 3, j2 + J_SHAFT / 3, J_SHAFT / 6
    want = K_SHAFT * (m11 + m22 + 2 * m12) / (m11 * m22 - m12**2)
    assert w[1] ** 2 == pytest.approx(want, rel=1e-12)
    w0 = _omega(_line(_shaft(1, density_kg_m3=1e-6), (j1, j2)))
    assert w0[1] ** 2 == pytest.approx(K_SHAFT * (1 / j1 + 1 / j2), rel=1e-9)


def test_damping_is_stiffness_proportional_and_condenses_to_the_end_damper():
    """C = (c/k) K on the shaft's elements; the massless line's dynamic stiffness K + iωC,
    condensed on its two ends (inner nodes eliminated), is the end-to-end spring–damper
    (k + iωc)[[1, −1], [−1, 1]] at every ω (1e-12)."""
    c = 35.0
    sh = _shaft(5, damping_nms_per_rad=c)
    asm = _line(sh, (1.0, 1.0))
    kk, cc = asm.matrix("K"), asm.matrix("C")
    assert cc == pytest.approx(c / K_SHAFT * kk, rel=1e-12, abs=1e-12 * c)
    for omega in (10.0, 1e3):
        z = kk + 1j * omega * cc
        ends, inner = [0, 1], list(range(2, asm.n))
        cond = (z[np.ix_(ends, ends)] - z[np.ix_(ends, inner)]
                @ np.linalg.solve(z[np.ix_(inner, inner)], z[np.ix_(inner, ends)]))
        want = (K_SHAFT + 1j * omega * c) * np.array([[1, -1], [-1, 1]])
        assert np.abs(cond - want).max() < 1e-12 * abs(K_SHAFT + 1j * omega * c)


# ---- through the config: a gear pair and a two-disc FE shaft ---------------------------------

def _pair_with_fe_shaft(**shaft: object) -> dict:
    geometry = dict(outer_diameter_m=D_OUT, length_m=L, shear_modulus_pa=G,
                    density_kg_m3=RHO, elements=8)
    geometry.update(shaft)
    return {
        "frame": "housing",
        "links": ["housing", "a", "b"],
        "parallel": [{"name": "p", "a": {"link": "a", "teeth": 20},
                      "b": {"link": "b", "teeth": 50}}],
        "dynamics": {
            "module_m": 0.004,
            "meshes": [{"pair": "p", "stiffness_n_per_m": 3e8}],
            "links": [{"link": "a", "inertia_kgm2": 0.02}, {"link": "b", "inertia_kgm2": 0.3}],
            "rotors": [{"name": "d1", "inertia_kgm2": 2 * J_SHAFT},
                       {"name": "d2", "inertia_kgm2": 0.5 * J_SHAFT}],
            "shafts": [{"name": "s", "a": "d1", "b": "d2", **geometry}],
        },
    }


def test_fe_shaft_through_the_config_has_the_shaft_frequencies():
    """The model built from the config names the inner nodes s.n1 … s.n7, keeps the mesh
    closed form ω² = k (r_ba²/J_a + r_bb²/J_b) (1e-12), and its other elastic frequencies are
    those of the two-disc shaft alone (1e-9)."""
    model = model_from_config(parse_config(_pair_with_fe_shaft()))
    assert [f"s.n{i}.theta" for i in range(1, 8)] == model.dof_names[-7:]
    w2 = sla.eigh(model.stiffness_matrix(), model.M, eigvals_only=True)
    rb = [0.004 * z * math.cos(math.radians(20)) / 2 for z in (20, 50)]
    w_mesh = math.sqrt(3e8 * (rb[0] ** 2 / 0.02 + rb[1] ** 2 / 0.3))
    alone = _omega(_line(_shaft(8), (2 * J_SHAFT, 0.5 * J_SHAFT)))
    want = np.sort(np.concatenate([[0.0, w_mesh], alone])) ** 2
    assert w2 == pytest.approx(want, rel=1e-9, abs=1e-12 * want.max())


def test_fe_shaft_to_the_frame_is_a_disc_on_a_clamped_shaft():
    """b = the frame (a fixed end) with disc d1 = J1 at the other end: the classical root of
    x tan x = J_s / J1 (x = ωL/c; the r2 → ∞ limit of the two-disc equation), approached from
    above at the h² rate (8 → 16 → 32 elements; 1.4e-5 at 32)."""
    j1 = 0.7 * J_SHAFT

    def f(x: float) -> float:
        return x * math.sin(x) - J_SHAFT / j1 * math.cos(x)

    exact = brentq(f, 1e-6, math.pi / 2 - 1e-12, xtol=1e-15) * C_WAVE / L
    errors = []
    for n_el in (8, 16, 32):
        d = _pair_with_fe_shaft(b="housing", elements=n_el)
        d["dynamics"]["rotors"] = [{"name": "d1", "inertia_kgm2": j1}]
        model = model_from_config(parse_config(d))
        idx = [i for i, nm in enumerate(model.dof_names) if nm.startswith(("d1.", "s.n"))]
        kk, mm = model.stiffness_matrix(), model.M
        others = [i for i in range(model.n) if i not in idx]
        assert np.abs(kk[np.ix_(idx, others)]).max() == 0.0  # the shaft is on its own
        w = math.sqrt(sla.eigh(kk[np.ix_(idx, idx)], mm[np.ix_(idx, idx)],
                               eigvals_only=True)[0])
        assert w > exact
        errors.append(w / exact - 1)
    assert errors[-1] < 1e-4
    assert np.log2(np.array(errors[:-1]) / errors[1:]) == pytest.approx(2.0, abs=0.05)


# ---- (c) an example mechanism with an FE main shaft -------------------------------------------

EXAMPLE = "three_stage_gearbox_fe_shaft"


def _example(examples_dir) -> dict:
    return tomllib.loads((examples_dir / f"{EXAMPLE}.toml").read_text())


def test_example_rigid_modes_span_the_kinematic_nullspace(examples_dir):
    """Seed 000 eq 5 with the FE main shaft: null(K) mapped to link velocities spans the
    kinematic nullspace (principal angles < 1e-8), no extra rigid mode, and in it the five
    inner nodes turn with the rotor and the low-speed carrier (1e-10)."""
    cfg = parse_config(_example(examples_dir))
    model = model_from_config(cfg)
    kin = analyze_graph(cfg.graph())
    null = sla.null_space(model.stiffness_matrix(), rcond=1e-10)
    assert null.shape[1] == kin.dof == 1
    angles = sla.subspace_angles(sla.orth(model.link_velocity @ null), kin.nullspace)
    assert angles.max() < 1e-8
    v = null[:, 0] / null[model.dof_names.index("rotor.theta"), 0]
    nodes = [v[model.dof_names.index(f"main_shaft.n{i}.theta")] for i in range(1, 6)]
    assert nodes == pytest.approx([1.0] * 5, abs=1e-10)
    assert float(model.body("low_speed_carrier").rotation @ v) == pytest.approx(1.0, abs=1e-10)
    assert np.linalg.eigvalsh(model.M).min() > 0


def test_example_steady_state_ratios_with_the_fe_shaft(examples_dir):
    """3 s from rest with the example's drives, meshes at mean stiffness, the rotor mode damped
    critically as in test_simulate (c = 4e7 N·m·s/rad, here stiffness-proportional along the
    shaft): link velocities equal the kinematic ones to 1e-6 (measured 2e-11) and the inner
    nodes turn at the rotor speed to 1e-6 (measured 4e-9)."""
    d = _example(examples_dir)
    for m in d["dynamics"]["meshes"]:
        m["model"] = "constant"
    d["dynamics"]["simulation"]["initial_state"] = "rest"
    d["dynamics"]["shafts"][0]["damping_nms_per_rad"] = 4e7
    cfg = parse_config(d)
    p = prepare(cfg, 3.0)
    res = integrate(p)
    assert res.status == "ok"
    kin = analyze_graph(cfg.graph())
    omega = p.model.link_velocity @ res.v[-1]
    want = kin.speeds({x: omega[kin.graph.index(x)].real for x in cfg.input_speeds_rpm})
    assert np.abs(omega - want).max() / np.abs(want).max() < 1e-6
    names = p.model.dof_names
    v = res.v[-1]
    rotor = v[names.index("rotor.theta")]
    for i in range(1, 6):
        assert v[names.index(f"main_shaft.n{i}.theta")] / rotor == pytest.approx(1.0, abs=1e-6)
    # the run starts with the inner nodes at the rigid-body speed (rigid_velocity)
    assert p.v0[names.index("main_shaft.n3.theta")] == pytest.approx(p.v0[names.index(
        "rotor.theta")], rel=1e-9)


def test_example_runs_with_both_solvers_and_closes_its_energy_balance(examples_dir):
    """0.03 s of the example (square-wave meshes, speed control): the low-rank (Woodbury)
    solver equals the compiled Newmark loop (1e-7), and ``simulate`` keeps status ok: the
    energy balance (kinetic energy with the shaft's consistent mass, the element springs'
    strain energy, the shaft damping) closes."""
    from geardyn.models.core.simulate import simulate
    from geardyn.solve.integrate import newmark
    from geardyn.solve.lowrank import newmark_lowrank

    cfg = parse_config(_example(examples_dir))
    p = prepare(cfg, 0.03)
    dt = p.sim.dt_s
    ref = newmark(p.system, p.q0, p.v0, 0.03, dt)
    got = newmark_lowrank(p.system, p.q0, p.v0, 0.03, dt)
    assert got.status == ref.status == "ok"
    for a, b in ((got.q, ref.q), (got.v, ref.v), (got.delta, ref.delta)):
        assert np.abs(a - b).max() <= 1e-7 * np.abs(b).max()
    ds = simulate(cfg, t_end_s=0.03)
    assert ds.attrs["status"] == "ok", ds.attrs["diagnosis"]
    assert "main_shaft.n3.theta" in ds["dof"].values


def _shaft_mode_hz(examples_dir, tmp_path, elements: int) -> tuple[float, float]:
    """(frequency Hz, kinetic fraction in the inner nodes) of the shaft's own first mode (the
    lowest with over half its kinetic energy in the inner nodes) from ``geardyn modes
    --netcdf``."""
    text = (examples_dir / f"{EXAMPLE}.toml").read_text()
    assert text.count("elements = 6\n") == 1
    path = tmp_path / f"fe{elements}.toml"
    path.write_text(text.replace("elements = 6\n", f"elements = {elements}\n"))
    out = tmp_path / f"modes{elements}.nc"
    res = CliRunner().invoke(app, ["modes", str(path), "--netcdf", str(out)])
    assert res.exit_code == 0, res.output
    with xr.open_dataset(out) as ds:
        nodes = [str(x) for x in ds["dof"].values if str(x).startswith("main_shaft.n")]
        share = ds["kinetic_fraction"].sel(dof=nodes).sum("dof").values
        i = int(np.flatnonzero(share > 0.5)[0])  # the lowest mode mostly in the shaft
        return float(ds["frequency"].values[i]), float(share[i])


def test_example_modes_show_the_shaft_torsional_mode(examples_dir, tmp_path):
    """``geardyn modes`` lists the main shaft's own torsional mode: most of its kinetic energy in
    the inner nodes, above the fixed–fixed bound c/(2L) = 535 Hz (both ends held by the 4e6
    kg·m² rotor and the gearbox), converging from above at the h² rate (6 → 12 → 24 elements:
    successive differences ratio 4 ± 0.3); the spring-shaft example has no mode there."""
    c = math.sqrt(210e9 / (2 * 1.3) / 7850.0)
    fixed_fixed = c / (2 * 3.0)
    f = {}
    for n_el in (6, 12, 24):
        f[n_el], share = _shaft_mode_hz(examples_dir, tmp_path, n_el)
        assert fixed_fixed < f[n_el] < 1.1 * fixed_fixed
    assert f[6] > f[12] > f[24]
    assert (f[6] - f[12]) / (f[12] - f[24]) == pytest.approx(4.0, abs=0.3)
    spring = model_from_config(parse_config(tomllib.loads(
        (examples_dir / "three_stage_gearbox.toml").read_text())))
    w2 = sla.eigh(spring.stiffness_matrix(), spring.M, eigvals_only=True)
    f_spring = np.sqrt(np.clip(w2, 0, None)) / (2 * math.pi)
    assert not ((f_spring > 0.9 * fixed_fixed) & (f_spring < 1.2 * fixed_fixed)).any()


def test_lateral_model_warns_that_the_fe_shaft_is_torsional_only(examples_dir):
    """lateral = true: a TorsionalOnlyWarning names the shaft; the rigid-body modes stay the
    kinematic nullspace (principal angles < 1e-8)."""
    d = _example(examples_dir)
    d["dynamics"]["lateral"] = True
    cfg0 = parse_config(d)
    d["dynamics"]["links"] = [{"link": x, "bearing_n_per_m": 1e9} for x in cfg0.graph().links
                              if x != cfg0.frame]
    cfg = parse_config(d)
    with pytest.warns(TorsionalOnlyWarning, match="main_shaft"):
        model = model_from_config(cfg)
    kin = analyze_graph(cfg.graph())
    null = sla.null_space(model.stiffness_matrix(), rcond=1e-10)
    assert null.shape[1] == kin.dof
    assert sla.subspace_angles(sla.orth(model.link_velocity @ null), kin.nullspace).max() < 1e-8


# ---- config ---------------------------------------------------------------------------------

def test_geometry_in_pint_units_and_from_e_and_nu():
    """"500 mm" and "210 GPa" convert like the other fields; G = E / (2 (1 + ν))."""
    d = _pair_with_fe_shaft(outer_diameter_m="50 mm", inner_diameter_m="2 cm",
                            shear_modulus_pa=None, youngs_modulus_pa="210 GPa",
                            poisson_ratio=0.3)
    del d["dynamics"]["shafts"][0]["shear_modulus_pa"]
    sh = parse_config(d).dynamics.shafts[0]
    assert sh.outer_diameter_m == pytest.approx(0.05) and sh.inner_diameter_m == pytest.approx(
        0.02)
    assert sh.shear_modulus == pytest.approx(210e9 / 2.6, rel=1e-12)
    assert sh.polar_moment_m4 == pytest.approx(math.pi * (0.05**4 - 0.02**4) / 32, rel=1e-12)
    assert sh.stiffness_nm_per_rad == pytest.approx(sh.shear_modulus * sh.polar_moment_m4 / L,
                                                    rel=1e-12)


@pytest.mark.parametrize(("change", "message"), [
    ({"torsional_nm_per_rad": 1e4}, "not both: remove .*outer_diameter_m"),
    ({"outer_diameter_m": None}, "missing outer_diameter_m"),
    ({"youngs_modulus_pa": 2e11}, "shear_modulus_pa: .*exactly one"),
    ({"shear_modulus_pa": None, "poisson_ratio": 0.3}, "shear_modulus_pa: .*exactly one"),
    ({"inner_diameter_m": 0.06}, "inner_diameter_m: the bore"),
    ({"elements": 0}, "elements"),
    ({"length_m": float("nan")}, "length_m"),
])
def test_bad_shaft_descriptions_are_config_errors(change, message):
    d = _pair_with_fe_shaft()
    sh = d["dynamics"]["shafts"][0]
    for key, value in change.items():
        if value is None:
            sh.pop(key)
        else:
            sh[key] = value
    with pytest.raises(ConfigError, match=message) as err:
        parse_config(d)
    assert "dynamics.shafts[0]" in str(err.value)


def test_neither_stiffness_nor_geometry_and_self_joined_shafts_are_refused():
    d = _pair_with_fe_shaft()
    d["dynamics"]["shafts"] = [{"name": "s", "a": "d1", "b": "d2"}]
    with pytest.raises(ConfigError, match="torsional_nm_per_rad .* or its geometry"):
        parse_config(d)
    d["dynamics"]["shafts"] = [{"name": "s", "a": "d1", "b": "d1", "torsional_nm_per_rad": 1.0}]
    with pytest.raises(ConfigError, match="joins 'd1' to itself"):
        parse_config(d)
    d = _pair_with_fe_shaft()
    d["dynamics"]["shafts"].append(dict(d["dynamics"]["shafts"][0], a="a"))
    with pytest.raises(ConfigError, match="'s' is used by another shaft"):
        parse_config(d)


def test_spring_shafts_are_unchanged():
    """A torsional_nm_per_rad shaft stays one rank-one spring (no node, no mass)."""
    d = _pair_with_fe_shaft()
    d["dynamics"]["shafts"] = [{"name": "s", "a": "d1", "b": "d2",
                                "torsional_nm_per_rad": K_SHAFT}]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        model = model_from_config(parse_config(d))
    assert model.n == 4 and [s.name for s in model.springs] == ["s"]
