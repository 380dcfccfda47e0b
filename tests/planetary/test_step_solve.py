"""The Newmark step's linear solve: Woodbury update of the constant step matrix (``lowrank``)
against the dense LU of the whole matrix (``dense``) — two independent pieces of linear
algebra for the same scheme — and both against scipy's LSODA on the plain-numpy right-hand
side (an independent integrator and implementation of the equations)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from geardyn.config.loader import load_config
from geardyn.models.planetary.build import prepare
from geardyn.solve.integrate import newmark, reference_rhs
from geardyn.warmup import small_system

from .conftest import EX


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


@pytest.mark.parametrize("alpha", [0.0, 0.1])
def test_lowrank_equals_dense_small_system(alpha: float) -> None:
    """Meshes (one losing contact), motor curve, fluid coupling (non-symmetric damping block),
    speed-squared load, speed control and a mass schedule: the Woodbury solve gives the dense
    LU's trajectory to rounding (1e-9), for Newmark and HHT-α."""
    sys_ = small_system()
    q0, v0 = np.zeros(4), np.array([1.0, 1.0, 1.0, 1.0])
    a = newmark(sys_, q0, v0, 0.05, 1e-4, alpha=alpha, solve="lowrank")
    b = newmark(sys_, q0, v0, 0.05, 1e-4, alpha=alpha, solve="dense")
    assert a.status == b.status == "ok"
    assert _rel(a.q, b.q) < 1e-9 and _rel(a.v, b.v) < 1e-9
    assert np.array_equal(a.k == 0, b.k == 0) and (a.k == 0).any()  # same contact losses
    assert _rel(a.k, b.k) < 1e-9
    for key, val in b.energy.items():
        assert a.energy[key] == pytest.approx(val, rel=1e-8, abs=1e-12), key


@pytest.mark.parametrize("gyro", [False, True])
def test_small_system_against_lsoda(gyro: bool) -> None:
    """Both solves (the dense one only, with gyroscopic terms) follow LSODA (rtol 1e-9) on the
    independent numpy right-hand side; Newmark's truncation error at ωΔt ≈ 0.05 bounds the
    difference (2e-3 of the speed scale). Constant mesh stiffness here: LSODA cannot step over
    the tables' discontinuities."""
    sys_ = small_system(gyro)
    sys_.springs.ktab[0, 1] = sys_.springs.ktab[0, 0]
    sys_.springs.etab[:] = 0.0
    q0, v0 = np.zeros(4), np.array([1.0, 1.0, 1.0, 1.0])
    t = np.arange(0.0, 0.05 + 1e-12, 1e-3)
    sol = solve_ivp(reference_rhs(sys_), (0.0, 0.05), np.concatenate([q0, v0]), t_eval=t,
                    method="LSODA", rtol=1e-9, atol=1e-12)
    assert sol.success
    for solve in ("dense",) if gyro else ("lowrank", "dense"):
        r = newmark(sys_, q0, v0, 0.05, 1e-4, save_every=10, solve=solve)
        assert _rel(r.v, sol.y[4:].T) < 2e-3, solve


def test_reclaimer_lowrank_equals_dense() -> None:
    """Seed 004 reclaimer (piecewise-constant mesh stiffness, errors, crack, motor, coupling,
    load): the default (Woodbury) run equals the dense LU run; mesh forces to 1e-8."""
    p = prepare(load_config(EX / "planetary_reclaimer.toml"))
    a = newmark(p.system, p.q0, p.v0, 0.2, 1e-4, save_every=10)
    b = newmark(p.system, p.q0, p.v0, 0.2, 1e-4, save_every=10, solve="dense")
    assert _rel(a.q, b.q) < 1e-10 and _rel(a.v, b.v) < 1e-10
    assert _rel(a.k * a.delta, b.k * b.delta) < 1e-8


def test_gyroscopic_terms_use_the_dense_solve() -> None:
    """Gyroscopic terms change the whole step matrix: ``lowrank`` is refused, ``auto`` takes
    the dense LU (same bytes as ``dense``)."""
    sys_ = small_system(gyro=True)
    q0, v0 = np.zeros(4), np.array([1.0, 1.0, 1.0, 1.0])
    with pytest.raises(ValueError, match="gyroscopic"):
        newmark(sys_, q0, v0, 0.01, 1e-4, solve="lowrank")
    a = newmark(sys_, q0, v0, 0.01, 1e-4)
    b = newmark(sys_, q0, v0, 0.01, 1e-4, solve="dense")
    assert np.array_equal(a.q, b.q)
    with pytest.raises(ValueError, match="solve"):
        newmark(sys_, q0, v0, 0.01, 1e-4, solve="cholesky")
