"""Torsional FE shaft elements against closed forms (issue 12, mutation-testing gaps).

``geardyn.models.core.fe_shafts``: the element matrices (Petyt 2010 §3.2: K_e = G I_p/L_e
[[1, −1], [−1, 1]], M_e = ρ I_p L_e/6 [[2, 1], [1, 2]]), the assembled line (tridiagonal closed
form), and the rank-one element springs of the model, whose sum must be the same stiffness (a
second formulation of the line's K); element names, kind, damping and the lateral warning.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from geardyn.config.dynamics import ShaftDynamics
from geardyn.models.core.assembly import Assembly
from geardyn.models.core.fe_shafts import (
    SHAFT,
    TorsionalOnlyWarning,
    add_shaft_nodes,
    element_matrices,
    inner_node_count,
    line_matrices,
    node_name,
    stamp_fe_shaft,
)

L, D_OUT, D_IN, G, RHO = 0.9, 0.06, 0.02, 79e9, 7800.0
IP = math.pi * (D_OUT**4 - D_IN**4) / 32


def _shaft(elements: int, **kw) -> ShaftDynamics:
    args = dict(name="s", a="d1", b="d2", outer_diameter_m=D_OUT, inner_diameter_m=D_IN,
                length_m=L, shear_modulus_pa=G, density_kg_m3=RHO, elements=elements)
    args.update(kw)
    return ShaftDynamics(**args)


def test_element_matrices_closed_form():
    le = L / 3
    k, m = element_matrices(_shaft(3))
    np.testing.assert_allclose(k, G * IP / le * np.array([[1, -1], [-1, 1]]), rtol=1e-14)
    np.testing.assert_allclose(m, RHO * IP * le / 6 * np.array([[2, 1], [1, 2]]), rtol=1e-14)


def test_line_matrices_tridiagonal_closed_form():
    """E = 4 elements: K = k_e tridiag(−1, [1, 2, 2, 2, 1], −1), M = m_e/6 tridiag(1, [2, 4, 4,
    4, 2], 1) with k_e = G I_p/L_e, m_e = ρ I_p L_e."""
    n = 4
    le = L / n
    kk, mm = line_matrices(_shaft(n))
    diag = np.array([1, 2, 2, 2, 1.0])
    k_ref = G * IP / le * (np.diag(diag) - np.eye(5, k=1) - np.eye(5, k=-1))
    m_ref = RHO * IP * le / 6 * (np.diag(2 * diag) + np.eye(5, k=1) + np.eye(5, k=-1))
    np.testing.assert_allclose(kk, k_ref, rtol=1e-14, atol=1e-9 * k_ref.max())
    np.testing.assert_allclose(mm, m_ref, rtol=1e-14, atol=1e-18)


def _stamped(n: int, damping: float = 0.0, lateral: bool = False):
    sh = _shaft(n, damping_nms_per_rad=damping)
    asm = Assembly()
    asm.add_dofs("d1", ["theta"], [0.0])
    asm.add_dofs("d2", ["theta"], [0.0])
    assert add_shaft_nodes(asm, [sh]) == list(range(2, 2 + n - 1))
    ends = (asm.row({"d1.theta": 1.0}), asm.row({"d2.theta": 1.0}))
    # the torsional model's call leaves ``lateral`` at its default (False)
    springs = (stamp_fe_shaft(asm, sh, *ends, lateral=True) if lateral
               else stamp_fe_shaft(asm, sh, *ends))
    return sh, asm, springs


def test_rank_one_springs_sum_to_the_line_stiffness():
    """Σ k_e a_e a_eᵀ over the element springs = the assembled line K (ends on d1, d2, inner
    nodes after them); the consistent mass block is the line M; the shaft's total stiffness
    seen end to end is G I_p/L."""
    n = 5
    sh, asm, springs = _stamped(n)
    kk, mm = line_matrices(sh)
    order = [0, *range(2, 2 + n - 1), 1]  # d1, inner nodes, d2
    k = asm.matrix("K")
    np.testing.assert_allclose(k[np.ix_(order, order)], kk, rtol=0, atol=1e-9 * kk.max())
    np.testing.assert_allclose(asm.matrix("M")[np.ix_(order, order)], mm, rtol=1e-14)
    assert sh.stiffness_nm_per_rad == pytest.approx(G * IP / L, rel=1e-14)
    assert [s.name for s in springs] == [f"s.e{i}" for i in range(1, n + 1)]
    assert {s.kind for s in springs} == {SHAFT} == {"shaft"}
    assert node_name("s", 3) == "s.n3" and inner_node_count([sh, _shaft(1)]) == n - 1


def test_element_dampers_are_stiffness_proportional():
    """c_e = E c per element: C = (c/k) K (module docstring)."""
    n, c = 4, 37.0
    sh, asm, springs = _stamped(n, damping=c)
    assert all(s.c == pytest.approx(n * c, rel=1e-14) for s in springs)
    np.testing.assert_allclose(asm.matrix("C"), c / sh.stiffness_nm_per_rad * asm.matrix("K"),
                               rtol=1e-12, atol=1e-12 * c)


def test_lateral_warning_only_in_the_lateral_model():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _stamped(2)
    with pytest.warns(TorsionalOnlyWarning, match="'s': the FE shaft is torsional only"):
        _stamped(2, lateral=True)
