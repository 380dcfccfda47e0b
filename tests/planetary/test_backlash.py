"""Backlash and back-flank contact in the lumped planetary model (issue 12): ``backlash_m`` of
a stage's ``sun_mesh`` / ``ring_mesh`` in ``[planetary_dynamics]``.

Force law on the mesh deflection δ (Lin & Parker sign convention of the model): F = k δ for
δ ≥ 0, 0 for −b < δ < 0, k (δ + b) for δ ≤ −b (Kahraman & Singh 1990, seed 004 §2.2 ref. 9).
The solver-level closed forms (clearance oscillator period and impact times, solve_ivp, mirror
symmetry, b = 0 regression) are in tests/mechanism/test_backlash_core.py.
"""

from __future__ import annotations

import copy
import tomllib

import numpy as np
import pytest

from geardyn.config.loader import parse_config
from geardyn.errors import ConfigError
from geardyn.models.planetary.build import prepare
from geardyn.run import run_simulation
from geardyn.solve.integrate import newmark
from geardyn.solve.sanity import energy_residual

B = 20e-6  # m


@pytest.fixture(scope="module")
def bench(examples_dir) -> dict:
    return tomllib.loads((examples_dir / "planetary_bench_12dof.toml").read_text())


def _with_backlash(d: dict, sun: object = B, ring: object = B) -> dict:
    d = copy.deepcopy(d)
    for sd in d["planetary_dynamics"]["stages"]:
        sd["sun_mesh"]["backlash_m"] = sun
        sd["ring_mesh"]["backlash_m"] = ring
    return d


def test_backlash_config_reaches_its_meshes(bench) -> None:
    """Per stage and mesh kind, with units; negative or non-finite values are ConfigErrors
    naming the field."""
    d = copy.deepcopy(bench)
    d["planetary_dynamics"]["stages"][0]["sun_mesh"]["backlash_m"] = "20 um"
    d["planetary_dynamics"]["stages"][1]["ring_mesh"]["backlash_m"] = "0.015 mm"
    p = prepare(parse_config(d), 0.002)
    names = [p.model.springs[i].name for i in p.mesh_index]
    want = [20e-6 if n.startswith("reaction.") and n.endswith("mesh_sun")
            else 15e-6 if n.startswith("test.") and n.endswith("mesh_ring") else 0.0
            for n in names]
    assert sum(w > 0 for w in want) == 6
    assert p.system.springs.backlash == pytest.approx(want, rel=1e-12)
    for bad in (-1e-6, "-2 um", float("inf")):
        d["planetary_dynamics"]["stages"][1]["sun_mesh"]["backlash_m"] = bad
        with pytest.raises(ConfigError,
                           match=r"planetary_dynamics\.stages\[1\]\.sun_mesh\.backlash_m"):
            parse_config(d)


def test_loaded_mesh_without_back_contact_equals_contact_loss(examples_dir) -> None:
    """Under the Lin & Parker example's load the teeth never come near the back flank
    (δ > −b/2 throughout): the backlash law then is the contact-loss law exactly (same
    arrays)."""
    d = tomllib.loads((examples_dir / "planetary_lin_parker.toml").read_text())
    runs = {}
    for key, b, cl in (("contact_loss", 0.0, True), ("backlash", B, False)):
        dd = _with_backlash(d, b, b)
        dd["planetary_dynamics"]["simulation"]["contact_loss"] = cl
        p = prepare(parse_config(dd), 0.004)
        runs[key] = newmark(p.system, p.q0, p.v0, 0.004, 2e-5)
    bl, cl = runs["backlash"], runs["contact_loss"]
    assert bl.delta.min() > -B / 2 and bl.delta.max() > 0
    for a, b in ((bl.q, cl.q), (bl.v, cl.v), (bl.k, cl.k), (bl.delta, cl.delta)):
        assert np.array_equal(a, b)


@pytest.fixture(scope="module")
def braking(bench) -> tuple:
    """The 12-DOF bench under a light load (5 N·m on the reaction ring) whose sun speed
    control brakes from 1000 to 900 rpm in 2 ms: the carrier's inertia drives the meshes onto
    their back flanks."""
    d = _with_backlash(bench)
    sim = d["planetary_dynamics"]["simulation"]
    sim["torques"][0]["torque_nm"] = 5.0
    sim["speed_controls"][0]["profile_rpm"] = [[0.0, 1000.0], [0.004, 1000.0],
                                               [0.006, 900.0], [0.02, 900.0]]
    cfg = parse_config(d)
    return cfg, run_simulation(cfg, t_end_s=0.02)


def test_braking_reaches_both_flanks(braking) -> None:
    """Every reaction-stage mesh touches both flanks and separates; the recorded force is the
    contact law (back flank negative, none in the gap, |F|/compression a value of the square
    wave); the run's checks pass (status ok: energy balance within 2e-3, measured 3.8e-5)."""
    cfg, ds = braking
    assert ds.attrs["status"] == "ok", ds.attrs.get("diagnosis")
    en = {k[len("energy_"):]: v for k, v in ds.attrs.items() if k.startswith("energy_")}
    res, scale = energy_residual(en)
    assert abs(res) < 2e-3 * scale
    d = ds["mesh_deflection"].values
    f = ds["mesh_force"].values
    names = [str(m) for m in ds["mesh"].values]
    reaction = [i for i, n in enumerate(names) if n.startswith("reaction.")]
    back, gap, drive = d <= -B, (d > -B) & (d < 0), d > 0
    for i in reaction:
        assert back[:, i].sum() >= 10 and gap[:, i].sum() >= 100 and drive[:, i].sum() >= 10
    assert np.all(f[back] < 0) and np.all(f[gap] == 0) and np.all(f[drive] > 0)
    sd = cfg.planetary_dynamics.stages[0]
    kmin = min(sd.sun_mesh.k_min_n_per_m, sd.ring_mesh.k_min_n_per_m)
    kmax = max(sd.sun_mesh.k_max_n_per_m, sd.ring_mesh.k_max_n_per_m)
    on = back | drive
    ratio = np.abs(f[on]) / np.abs(np.where(back, d + B, d)[on])
    assert ratio.min() > kmin * (1 - 1e-9) and ratio.max() < kmax * (1 + 1e-9)


def test_braking_dense_and_woodbury_agree(braking) -> None:
    """The dense and the Woodbury Newmark step give the braking run with impacts on both
    flanks: q and v within 1e-9 of their largest value (measured 1.6e-13, 2.5e-11), the mesh
    forces within 1e-8 of the largest (measured 2.1e-9 at one sample near a contact change,
    9e-11 without backlash)."""
    cfg, ds = braking
    p = prepare(cfg, 0.02)
    dt = cfg.planetary_dynamics.simulation.dt_s
    dense = newmark(p.system, p.q0, p.v0, 0.02, dt, solve="dense")
    wood = newmark(p.system, p.q0, p.v0, 0.02, dt, solve="lowrank")
    fd, fw = dense.k * dense.delta, wood.k * wood.delta
    assert np.abs(fw - fd).max() < 1e-8 * np.abs(fd).max()
    assert np.abs(wood.q - dense.q).max() < 1e-9 * np.abs(dense.q).max()
    assert np.abs(wood.v - dense.v).max() < 1e-9 * np.abs(dense.v).max()
    assert np.abs(fd - ds["mesh_force"].values).max() < 1e-8 * np.abs(fd).max()
