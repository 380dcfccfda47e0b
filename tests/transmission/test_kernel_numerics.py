"""Numerics of the compiled kernels: the inline logarithm of the eq 9 Newton iterations and the
vectorised eq 9 solve against the C library and the one-slice solver."""

from __future__ import annotations

import math
import warnings

import numpy as np

from geardyn.models.transmission.kernels import johnson_force, log_inline


def test_inline_log_within_one_ulp_of_the_c_library() -> None:
    """fdlibm / musl log (Sun Microsystems 1993): within 1 ulp of math.log over the positive
    normal range; ln 1 = 0 exactly."""
    rng = np.random.default_rng(24)
    xs = np.concatenate(
        [
            np.exp(rng.uniform(-700.0, 700.0, 50_000)),
            rng.uniform(0.5, 2.0, 50_000),
            [1.0, 2.0, 0.5, 1e300, 1e-300],
        ]
    )
    for x in xs:
        got, ref = log_inline(float(x)), math.log(float(x))
        assert abs(got - ref) <= math.ulp(ref), (x, got, ref)
    for k in (-1000, -1, 1, 52, 1000):
        ref = math.log(2.0**k)
        assert abs(log_inline(2.0**k) - ref) <= math.ulp(ref)
    assert log_inline(1.0) == 0.0


def test_johnson_force_solves_eq9() -> None:
    """The eq 9 solve (seed 002: δ = F/k_s + F/(π L E*)(ln(4π L E* ΔR/F) − 1)) with the inline
    logarithm: the residual of the returned force is below 1e-9 of δ for tooth loads."""
    ks, width, estar, rsum = 2e8, 0.005, 1.1e11, 0.02
    c = math.pi * width * estar
    for f_true in (10.0, 300.0, 2000.0, 8000.0):
        delta = f_true / ks + f_true / c * (math.log(4 * c * rsum / f_true) - 1.0)
        f = johnson_force(delta, ks, width, estar, rsum)
        res = f / ks + f / c * (math.log(4 * c * rsum / f) - 1.0) - delta
        assert abs(res) < 1e-9 * delta
        assert abs(f - f_true) < 1e-8 * f_true


def test_lane_mesh_kernel_equals_the_slice_kernel(examples_dir) -> None:
    """The modal integrator's mesh kernel (eq 9 for all (pair, slice) lanes at once, inline
    logarithm) against the per-pair kernel on the seed 002 transmission at its static preload,
    with the shafts turned through a mesh cycle: the same forces to rounding (1e-12 of the
    largest), the same mesh forces and dissipation powers."""
    from geardyn.config.loader import load_config
    from geardyn.models.transmission import build_model, prepare
    from geardyn.models.transmission.kernels import mesh_forces, mesh_forces_lanes
    from geardyn.models.transmission.simulate import speed_ratios

    model = build_model(load_config(examples_dir / "seed002_transmission.toml"))
    prep = prepare(model, "output")
    ma = model.meshes.args()
    ratio = speed_ratios(model, "output")
    rigid = np.zeros(prep.q0.size)  # the gear train's rigid rotation (output: 1 rad)
    for s, nodes in model.shaft_nodes.items():
        for nd in nodes:
            rigid[6 * nd + 5] = model.shaft_sign[s] * ratio[s]
    rng = np.random.default_rng(2)
    for turn in np.linspace(0.0, 0.3, 13):
        q = prep.q0 + turn * rigid  # the mesh phases move, the deflections stay
        v = rng.normal(0.0, 1e-3, q.size)
        out = []
        for kernel in (mesh_forces, mesh_forces_lanes):
            f, diss, mf = np.zeros_like(q), np.zeros(5), np.zeros(model.meshes.na.size)
            kernel(q, v, f, diss, *ma, mf)
            out.append((f, diss, mf))
        (f0, d0, m0), (f1, d1, m1) = out
        assert np.max(np.abs(f1 - f0)) <= 1e-12 * np.max(np.abs(f0))
        assert np.allclose(m1, m0, rtol=1e-12, atol=0.0)
        assert np.allclose(d1, d0, rtol=1e-10, atol=1e-12)


def test_finite_difference_columns_equal_the_connecting_forces(examples_dir) -> None:
    """The compiled finite-difference evaluations (static equilibrium, tangent stiffness) give
    bit for bit the forces of one :func:`connecting_forces` call per perturbed DOF, and a DOF
    outside :func:`kernel_dofs` (those the bearing and mesh kernels read) leaves every force
    unchanged, bit for bit: its Jacobian column is exactly zero."""
    from geardyn.config.loader import load_config
    from geardyn.models.transmission import build_model
    from geardyn.models.transmission.assembly import (
        connecting_forces,
        kernel_dofs,
        perturbed_forces,
        static_equilibrium,
    )

    model = build_model(load_config(examples_dir / "seed002_transmission.toml"))
    q = static_equilibrium(model, model.load_torque)
    v = np.random.default_rng(3).normal(0.0, 1e-3, q.size)
    h = 1e-9
    cols = np.arange(q.size)
    got = perturbed_forces(model, q, v, cols, h)
    read = set(kernel_dofs(model).tolist())
    f0 = connecting_forces(model, q, v)
    for j in cols:
        qp = q.copy()
        qp[j] += h
        ref = connecting_forces(model, qp, v)
        assert np.array_equal(got[:, j], ref), j
        if j not in read:
            assert np.array_equal(ref, f0), j
    assert 0 < len(read) < q.size


def test_record_post_processing_equals_numpy() -> None:
    """The compiled passes over the records give numpy's values bit for bit: signed shaft
    angles and speeds, speed in rpm (× 30/π), and the largest |mesh force| per mesh with
    NaN ignored (np.nanmax of np.abs; NaN for a column of NaN only)."""
    from geardyn.models.transmission.simulate import _max_abs_columns, _shaft_records
    from geardyn.results import RAD_S_TO_RPM

    rng = np.random.default_rng(5)
    rec = rng.normal(0.0, 100.0, (1500, 20))  # 1500 rows: blocks of 512 and a remainder
    sign = np.array([1.0, -1.0, 1.0])
    angle, speed, rpm = _shaft_records(rec, 2, 7, sign)
    assert np.array_equal(angle, rec[:, 2:5] * sign)
    assert np.array_equal(speed, rec[:, 7:10] * sign)
    assert np.array_equal(rpm, rec[:, 7:10] * sign * RAD_S_TO_RPM)
    f = rec[:, 16:20].copy()
    f[::7, 1] = np.nan
    f[:, 2] = np.nan
    f[3, 3] = -np.inf
    got = _max_abs_columns(rec[:, 16:20])
    assert np.array_equal(got, np.max(np.abs(rec[:, 16:20]), axis=0))
    got = _max_abs_columns(f)
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        ref = np.nanmax(np.abs(f), axis=0)
    assert np.array_equal(got, ref, equal_nan=True)
