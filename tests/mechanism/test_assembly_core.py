"""The shared assembly (models/core/assembly.py): DOF registry and element stamping.

References are independent hand computations: a two-mass chain stamped as rank-one springs and
as a 2×2 block gives the same K; a Timoshenko-like block stamped twice on overlapping DOFs sums;
the dense and sparse forms agree exactly."""

from __future__ import annotations

import numpy as np
import pytest

from geardyn.errors import ConfigError
from geardyn.models.core.assembly import Assembly, RankOne


def _chain() -> Assembly:
    asm = Assembly()
    asm.add_dofs("a", ["u"], [2.0])
    asm.add_dofs("b", ["u"], [3.0])
    return asm


def test_rank_one_equals_block_and_hand_matrix() -> None:
    k = 5e6
    asm1 = _chain()
    asm1.add_rank_one(RankOne("s", "shaft", k, asm1.row({"a.u": 1.0, "b.u": -1.0}), c=7.0))
    asm2 = _chain()
    asm2.add_block("s", "shaft", ["a.u", "b.u"], K=k * np.array([[1, -1], [-1, 1]]),
                   C=7.0 * np.array([[1, -1], [-1, 1]]))
    ref = np.array([[k, -k], [-k, k]])
    np.testing.assert_array_equal(asm1.matrix("K"), ref)
    np.testing.assert_array_equal(asm2.matrix("K"), ref)
    np.testing.assert_array_equal(asm1.matrix("C"), asm2.matrix("C"))
    np.testing.assert_array_equal(asm1.matrix("M"), np.diag([2.0, 3.0]))


def test_overlapping_blocks_sum_and_sparse_equals_dense() -> None:
    asm = Assembly()
    for i in range(3):
        asm.add_dofs(f"n{i}", ["x", "rz"], [1.0 + i, 0.1])
    ke = np.arange(16.0).reshape(4, 4)
    ke = ke + ke.T
    asm.add_block("e0", "shaft", [0, 1, 2, 3], K=ke, M=np.eye(4))
    asm.add_block("e1", "shaft", [2, 3, 4, 5], K=ke, M=np.eye(4))
    k = asm.matrix("K")
    assert k[2, 2] == ke[2, 2] + ke[0, 0] and k[0, 5] == 0.0
    np.testing.assert_array_equal(asm.matrix("K", sparse=True).toarray(), k)
    np.testing.assert_array_equal(asm.matrix("M", sparse=True).toarray(), asm.matrix("M"))
    np.testing.assert_array_equal(asm.matrix("K", kinds=["disc"]), np.zeros((6, 6)))
    assert np.trace(asm.matrix("M")) == pytest.approx(6.0 + 0.3 + 8.0, rel=1e-15)


def test_registry_errors_name_the_dof() -> None:
    asm = _chain()
    with pytest.raises(ConfigError, match="'a.u' is defined twice"):
        asm.add_dofs("a", ["u"])
    with pytest.raises(ConfigError, match="unknown DOF 'c.u'"):
        asm.row({"c.u": 1.0})
    with pytest.raises(ConfigError, match="mass must be finite"):
        asm.add_dofs("d", ["u"], [float("nan")])
    with pytest.raises(ValueError, match="is \\(3, 3\\) for 2 DOFs"):
        asm.add_block("e", "shaft", [0, 1], K=np.eye(3))
