"""Bevel pairs in the lateral model through their pitch-cone geometry (lateral.py
``bevel_translation``).

Reference: an independent hand projection in 3-D. A 90° pair, pitch-cone angles
tan δ_a = z_a/z_b (ISO 10300-1 / Niemann-Winter: δ_a + δ_b = Σ), mean point P on the pitch
cone generator at the mean cone distance R_m = r_a / sin δ_a, contact normal
N = cos α ẑ + sin α ŝ (ŝ in the plane of the axes, normal to the generator, from gear a to
gear b: the tangential, radial F_t tan α cos δ and axial F_t tan α sin δ force components of
a straight bevel pair), and δ = N·(u_a(P) − u_b(P)) with the rigid-body displacement
u = θ ê × P + d of each gear. The model's row must be ±δ (one sign for the whole row).
Invariants: the rigid-body modes stay the kinematic nullspace; very stiff bearings give back
the torsional frequency, softer ones lower it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg as sla

from geardyn.config.loader import parse_config
from geardyn.kinematics.willis import analyze_graph
from geardyn.models.core import model_from_config

ZA, ZB, MOD, ALPHA, K_MESH = 20, 50, 0.004, math.radians(20.0), 3e8


def _bevel(bearing: float | None = 1e9, lateral: bool = True) -> dict:
    links = [{"link": "a", "inertia_kgm2": 0.02}, {"link": "b", "inertia_kgm2": 0.3}]
    for lk in links:
        if bearing is not None:
            lk["bearing_n_per_m"] = bearing
    return {
        "frame": "housing", "links": ["housing", "a", "b"],
        "bevel": [{"name": "p", "a": {"link": "a", "teeth": ZA},
                   "b": {"link": "b", "teeth": ZB}}],
        "dynamics": {"module_m": MOD, "pressure_angle_deg": 20.0, "lateral": lateral,
                     "meshes": [{"pair": "p", "stiffness_n_per_m": K_MESH}], "links": links},
    }


def _unit(angle: float) -> np.ndarray:
    return np.array([math.cos(angle), math.sin(angle), 0.0])


def test_bevel_mesh_row_equals_the_hand_projection():
    model = model_from_config(parse_config(_bevel()))
    mesh = model.meshes[0]
    col = {nm: i for i, nm in enumerate(model.dof_names)}
    # axes of the two shafts from the kinematics (Ω of each link per unit of its coordinate)
    phi = {x: float(np.angle(model.link_velocity[model.links.index(x), col[f"{x}.theta"]]))
           for x in ("a", "b")}
    e = {x: _unit(phi[x]) for x in phi}
    assert abs(e["a"] @ e["b"]) < 1e-12  # a 90° pair
    g = _unit(mesh.psi)  # pitch-cone generator (seed 000 tooth axis), gears towards +g
    delta = {"a": math.atan(ZA / ZB), "b": math.atan(ZB / ZA)}
    for x in ("a", "b"):  # the generator makes the pitch-cone angle with each axis
        assert math.acos(abs(g @ e[x])) == pytest.approx(delta[x], rel=1e-12)
    r_a, r_b = MOD * ZA / 2, MOD * ZB / 2
    r_m = r_a / math.sin(delta["a"])
    assert r_m == pytest.approx(r_b / math.sin(delta["b"]), rel=1e-12)
    p = r_m * g
    z = np.array([0.0, 0.0, 1.0])
    side_a = e["a"] * math.copysign(1.0, e["a"] @ g)
    s = -(side_a - (side_a @ g) * g)
    s /= np.linalg.norm(s)  # in the plane, normal to the generator, from a towards b
    normal = math.cos(ALPHA) * z + math.sin(ALPHA) * s
    x_hat = {x: np.cross(z, e[x]) for x in e}  # documented lateral axes: x̂ in the sketch, ŷ = ẑ

    def displacement(x: str, dof: str) -> np.ndarray:
        return {"theta": np.cross(e[x], p), "x": x_hat[x], "y": z}[dof]

    hand = np.zeros(model.n)
    for x, sign in (("a", 1.0), ("b", -1.0)):
        for dof in ("theta", "x", "y"):
            hand[col[f"{x}.{dof}"]] = sign * normal @ displacement(x, dof)
    got = mesh.a
    sigma = math.copysign(1.0, got @ hand)
    np.testing.assert_allclose(got, sigma * hand, rtol=0, atol=1e-12 * np.abs(hand).max())
    # magnitudes by hand: base radii; sin α cos δ radially, cos α out of the sketch
    assert abs(got[col["a.theta"]]) == pytest.approx(r_a * math.cos(ALPHA), rel=1e-12)
    assert abs(got[col["b.x"]]) == pytest.approx(math.sin(ALPHA) * math.cos(delta["b"]),
                                                 rel=1e-12)
    assert abs(got[col["a.y"]]) == pytest.approx(math.cos(ALPHA), rel=1e-12)


def _rigid_angles(model, graph) -> float:  # noqa: ANN001
    null = sla.null_space(model.stiffness_matrix(), rcond=1e-10)
    kin = analyze_graph(graph)
    assert null.shape[1] == kin.dof
    return float(sla.subspace_angles(sla.orth(model.link_velocity @ null), kin.nullspace).max())


def test_bevel_pair_keeps_the_kinematic_rigid_mode_and_the_torsional_limit():
    cfg = parse_config(_bevel())
    assert _rigid_angles(model_from_config(cfg), cfg.graph()) < 1e-8
    torsional = model_from_config(parse_config(_bevel(None, lateral=False)))
    rb = [MOD * z * math.cos(ALPHA) / 2 for z in (ZA, ZB)]
    w2_t = K_MESH * (rb[0] ** 2 / 0.02 + rb[1] ** 2 / 0.3)  # two discs on the mesh spring
    assert sla.eigh(torsional.stiffness_matrix(), torsional.M, eigvals_only=True)[1] == \
        pytest.approx(w2_t, rel=1e-12)

    def torsional_mode(bearing: float) -> float:
        """ω² of the mode with the largest torsional energy share."""
        m = model_from_config(parse_config(_bevel(bearing)))
        w2, phi = sla.eigh(m.stiffness_matrix(), m.M)
        share = np.abs(phi[:2]) ** 2 * np.diag(m.M)[:2, None]
        return float(w2[int(np.argmax(share.sum(0)[1:])) + 1])

    stiff, soft = torsional_mode(1e14), torsional_mode(1e8)
    assert stiff == pytest.approx(w2_t, rel=1e-4)  # rigid bearings: the torsional model
    assert soft < stiff  # flexible bearings lower it (Rayleigh)


def test_differential_pinions_move_with_their_carrier(examples_dir):
    """Seed 000 car differential (Table 1) with lateral DOFs: the pinion meshes (pinions
    without lateral DOFs, carried by the cage) load the cage's bearings, and the rigid-body
    modes still span the kinematic nullspace (principal angles < 1e-8)."""
    import tomllib

    d = tomllib.loads((examples_dir / "car_differential_dynamics.toml").read_text())
    d["dynamics"]["lateral"] = True
    cfg0 = parse_config(d)
    given = {lk["link"] for lk in d["dynamics"].get("links", [])}
    for lk in d["dynamics"].setdefault("links", []):
        lk["bearing_n_per_m"] = 1e9
    d["dynamics"]["links"] += [{"link": x, "bearing_n_per_m": 1e9} for x in cfg0.graph().links
                               if x not in given and x != cfg0.frame]
    cfg = parse_config(d)
    model = model_from_config(cfg)
    lateral = [i for i, nm in enumerate(model.dof_names) if nm.endswith((".x", ".y"))]
    bevel = [m for m in model.meshes if np.abs(m.a[lateral]).max() > 0]
    assert len(bevel) == len(model.meshes)  # every mesh of the differential is a bevel pair
    assert _rigid_angles(model, cfg.graph()) < 1e-8
