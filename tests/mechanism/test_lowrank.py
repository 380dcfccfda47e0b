"""The Woodbury Newmark (solve/lowrank.py) gives the compiled Newmark's result: same scheme,
only the linear solve differs (constant part factored once, mesh changes as a low-rank
update)."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

from geardyn.config.loader import parse_config
from geardyn.errors import InputError
from geardyn.models.core.simulate import prepare, simulate
from geardyn.solve.integrate import MassSchedule, newmark
from geardyn.solve.lowrank import newmark_lowrank


def _prepared(examples_dir, name: str, **sim):  # noqa: ANN202
    d = tomllib.loads((examples_dir / f"{name}.toml").read_text())
    d["dynamics"]["simulation"].update(sim)
    return prepare(parse_config(d), 0.03)


@pytest.mark.parametrize(("name", "alpha"), [("reclaimer_whole_drive", 0.0),
                                             ("car_differential_dynamics", 0.1),
                                             ("alouette3_mgb_dynamics", 0.05)])
def test_lowrank_equals_the_compiled_newmark(examples_dir, name, alpha):
    """Fluid coupling (a non-symmetric damping block in the update), speed-squared load,
    speed controls, square-wave meshes with contact loss, HHT-α."""
    p = _prepared(examples_dir, name, contact_loss=True)
    dt = p.sim.dt_s
    ref = newmark(p.system, p.q0, p.v0, 0.03, dt, alpha=alpha)
    got = newmark_lowrank(p.system, p.q0, p.v0, 0.03, dt, alpha=alpha)
    assert got.status == ref.status == "ok"
    assert got.t == pytest.approx(ref.t, abs=1e-12)
    for a, b in ((got.q, ref.q), (got.v, ref.v), (got.delta, ref.delta), (got.k, ref.k)):
        assert np.abs(a - b).max() <= 1e-7 * np.abs(b).max()


def test_solver_option_runs_the_lowrank_path(examples_dir):
    d = tomllib.loads((examples_dir / "three_stage_gearbox.toml").read_text())
    d["dynamics"]["simulation"]["solver"] = "lowrank"
    ds = simulate(parse_config(d), t_end_s=0.01)
    assert ds.attrs["solver"] == "lowrank" and ds.attrs["status"] == "ok"


def test_lowrank_refuses_a_mass_schedule(examples_dir):
    p = _prepared(examples_dir, "car_differential_dynamics")
    p.system.mass_schedule = MassSchedule(np.array([0]), np.array([0]), np.array([1.0]),
                                          np.zeros((1, 2)), np.ones((1, 2)), np.array([2]))
    with pytest.raises(InputError, match="mass schedule"):
        newmark_lowrank(p.system, p.q0, p.v0, 0.01, 1e-4)


def test_gyroscopic_lateral_run(examples_dir):
    """simulation.gyroscopic on the lateral three-stage gearbox: the kernels receive one
    rotating frame per carrier; the run stays close to the one without (slow carriers)."""
    d = tomllib.loads((examples_dir / "three_stage_gearbox.toml").read_text())
    d["dynamics"]["lateral"] = True
    d["dynamics"]["links"] = [{"link": x, "bearing_n_per_m": 2e9} for x in
                              ("low_speed_carrier", "s1", "s2", "output")]
    d["dynamics"]["links"] += [{"link": f"stage{s}.planet{i}", "bearing_n_per_m": 1e9}
                               for s in (1, 2) for i in (1, 2, 3)]
    runs = {}
    for gyro in (False, True):
        d["dynamics"]["simulation"]["gyroscopic"] = gyro
        p = prepare(parse_config(d), 0.02)
        assert p.system.gyro_g.shape[0] == (2 if gyro else 0)
        runs[gyro] = newmark(p.system, p.q0, p.v0, 0.02, p.sim.dt_s)
        assert runs[gyro].status == "ok"
    with pytest.raises(InputError, match="gyroscopic"):
        newmark_lowrank(p.system, p.q0, p.v0, 0.01, p.sim.dt_s)
    a, b = runs[True].v, runs[False].v
    assert 0 < np.abs(a - b).max() < 1e-2 * np.abs(b).max()
