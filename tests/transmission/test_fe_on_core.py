"""The FE transmission (seed 002) built on the one assembly core: named 6-DOF nodes, Timoshenko
elements and wheel discs stamped as blocks; the matrices equal the direct assembly of seed 002
eqs 2-3 and carry the rigid-body invariants of free shafts."""

from __future__ import annotations

import numpy as np
import pytest

from geardyn.config.gears import pair_model
from geardyn.config.loader import load_config
from geardyn.elements.beam import ShaftSection, timoshenko_gyroscopic
from geardyn.elements.disc import disc_gyroscopic, rigid_disc, solid_disc_properties
from geardyn.errors import InputError
from geardyn.models.transmission.assembly import NODE_DOFS, assemble_shaft, build_model


@pytest.fixture(scope="module")
def cfg(examples_dir):
    return load_config(examples_dir / "seed002_transmission.toml")


@pytest.fixture(scope="module")
def model(cfg):
    return build_model(cfg)


def _section(s) -> ShaftSection:  # noqa: ANN001
    return ShaftSection(s.outer_diameter_m, s.inner_diameter_m, s.youngs_modulus_pa,
                        s.poisson_ratio, s.density_kg_m3)


def _wheels(cfg):  # noqa: ANN001, ANN202
    """(shaft, node, mass, polar inertia, diametral inertia) of every wheel (solid discs)."""
    out = []
    for w in cfg.transmission.wheels:
        g = pair_model(cfg, w.pair).geometry
        side = 0 if w.gear == "a" else 1
        blank = (g.a, g.b)[side]
        out.append((w.at.shaft, w.at.node, *solid_disc_properties(
            g.pitch_radius[side], blank.rim_radius or 0.0, g.face_width,
            blank.material.density)))
    return out


def _direct(cfg):  # noqa: ANN001, ANN202
    """The direct (pre-core) assembly: each shaft's banded K, M placed at its first node,
    wheels' rigid-disc M and gyroscopic G added on their node (the saved reference path)."""
    t = cfg.transmission
    first, n0 = {}, 0
    for s in t.shafts:
        first[s.name] = n0
        n0 += s.elements + 1
    n = 6 * n0
    K, M = np.zeros((n, n)), np.zeros((n, n))
    G = {s.name: np.zeros((n, n)) for s in t.shafts}
    for s in t.shafts:
        k, m = assemble_shaft(_section(s), s.length_m, s.elements)
        a = 6 * first[s.name]
        K[a:a + k.shape[0], a:a + k.shape[0]] += k
        M[a:a + k.shape[0], a:a + k.shape[0]] += m
        ge = timoshenko_gyroscopic(s.length_m / s.elements, _section(s))
        for e in range(s.elements):
            G[s.name][a + 6 * e:a + 6 * e + 12, a + 6 * e:a + 6 * e + 12] += ge
    for shaft, nd, mass, ip, idia in _wheels(cfg):
        d = 6 * (first[shaft] + nd)
        M[d:d + 6, d:d + 6] += rigid_disc(mass, ip, idia)
        G[shaft][d:d + 6, d:d + 6] += disc_gyroscopic(ip)
    return K, M, G


def test_matrices_equal_the_direct_assembly(cfg, model) -> None:
    """M, K and the per-shaft G of the core equal the direct assembly (≤ 1e-12 relative)."""
    K, M, G = _direct(cfg)
    for name, a, b in (("K", model.K, K), ("M", model.M, M)):
        assert np.abs(a - b).max() <= 1e-12 * np.abs(b).max(), name
    assert set(model.gyroscopic) == set(G)
    for s, g in G.items():
        assert np.abs(model.gyroscopic[s] - g).max() <= 1e-12 * np.abs(g).max(), s
        assert np.array_equal(model.gyroscopic[s], model.assembly.matrix("G", kinds=[s]))


def test_named_dofs_follow_the_element_order(cfg, model) -> None:
    """6 DOFs per node named {shaft}.n{i}.{x,y,z,rx,ry,rz} in the Timoshenko element order; the
    index of a name is the one the integrator uses (6 node + k)."""
    names = model.dof_names
    assert len(names) == model.ndof == 6 * sum(s.elements + 1 for s in cfg.transmission.shafts)
    assert len(set(names)) == len(names)
    for s, ids in model.shaft_nodes.items():
        for j, nd in enumerate(ids):
            for k, lab in enumerate(NODE_DOFS):
                assert names[6 * nd + k] == f"{s}.n{j}.{lab}"
                assert model.dof(s, j, lab) == 6 * nd + k == model.assembly.dof(f"{s}.n{j}.{lab}")
    with pytest.raises(InputError, match="unknown shaft 'nope'"):
        model.dof("nope", 0, "x")
    with pytest.raises(InputError, match="DOF label"):
        model.dof("input", 0, "theta")
    with pytest.raises(InputError, match="nodes 0"):
        model.dof("input", 99, "x")


def test_rigid_body_invariants(cfg, model) -> None:
    """Free shafts (bearings and meshes are connecting forces, not in K): K has 6 rigid-body
    modes per shaft; a rigid translation carries the closed-form mass ρ A L + Σ m_wheel and a
    rigid spin the polar inertia ρ J L + Σ I_p,wheel (solid discs, π ρ (r² − r_i²) b); each
    shaft's G is skew and acts only on its own DOFs."""
    K, M = model.K, model.M
    assert np.allclose(K, K.T, rtol=0, atol=1e-9 * np.abs(K).max())
    assert np.allclose(M, M.T, rtol=0, atol=1e-15 * np.abs(M).max())
    assert np.linalg.eigvalsh(M).min() > 0
    w = np.linalg.eigvalsh(np.linalg.solve(np.linalg.cholesky(M), np.linalg.solve(
        np.linalg.cholesky(M), K).T))
    assert np.sum(np.abs(w) < 1e-6 * w.max()) == 6 * len(cfg.transmission.shafts)
    wheels = _wheels(cfg)
    for s in cfg.transmission.shafts:
        ids = model.shaft_nodes[s.name]
        sec = _section(s)
        disc = [wh for wh in wheels if wh[0] == s.name]
        mass = s.density_kg_m3 * sec.area * s.length_m + sum(wh[2] for wh in disc)
        polar = s.density_kg_m3 * sec.polar_moment * s.length_m + sum(wh[3] for wh in disc)
        for lab, ref in (("x", mass), ("y", mass), ("z", mass), ("rz", polar)):
            u = np.zeros(model.ndof)
            u[[model.dof(s.name, j, lab) for j in range(len(ids))]] = 1.0
            assert u @ M @ u == pytest.approx(ref, rel=1e-12), (s.name, lab)
            assert np.abs(K @ u).max() <= 1e-9 * np.abs(K).max(), (s.name, lab)
        g = model.gyroscopic[s.name]
        assert np.array_equal(g, -g.T)
        own = [i for i, nm in enumerate(model.dof_names) if nm.startswith(f"{s.name}.n")]
        off = np.ones(model.ndof, bool)
        off[own] = False
        assert not g[off].any() and not g[:, off].any()
    total = sum(model.gyroscopic.values())
    assert np.allclose(total, model.assembly.matrix("G"), rtol=0, atol=1e-15)
