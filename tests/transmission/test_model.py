"""Assembled seed 002 transmission: static mesh check vs the mesh-stiffness module, modal
analysis, energy balance, IAS orders, faults."""

from __future__ import annotations

import math

import numpy as np
import pytest

from geardyn.config.loader import load_config
from geardyn.errors import ConfigError
from geardyn.models.transmission.assembly import (
    build_model,
    mesh_state,
    rigid_rotation,
    static_equilibrium,
)
from geardyn.models.transmission.kernels import bearing_forces
from geardyn.models.transmission.simulate import prepare, speed_ratios

EX = "examples/seed002_transmission.toml"


@pytest.fixture(scope="module")
def cfg(examples_dir):
    return load_config(examples_dir / "seed002_transmission.toml")


@pytest.fixture(scope="module")
def model(cfg):
    return build_model(cfg)


def test_static_mesh_force_and_te_match_gears_modules(model) -> None:
    """Under a constant load torque the mesh forces balance the torques (F = T / r_b) and the
    static mesh deflection equals the static transmission error of
    geardyn.gears.static_transmission_error (seed 002 eq 9 with the mesh-stiffness module's
    structural stiffness; spur stage with off-line-of-action contact, eq 11) at the loaded
    phase: spur stage within 0.5 %, helical stage (kinematic zone) within 5 % (5 FE slices vs
    the module's 20 lagged slices)."""
    from geardyn.gears import static_transmission_error

    t_load = 100.0
    r = speed_ratios(model, "output")
    gl, gh = model.meshes.geometry
    f_low = t_load / gl.base_radius[1]
    f_high = f_low * gl.base_radius[0] / gh.base_radius[1]
    ste = [
        static_transmission_error(gl, f_low * gl.base_radius[0], extended=True,
                                  n_per_cycle=256),
        static_transmission_error(gh, f_high * gh.base_radius[0], extended=False,
                                  n_per_cycle=256),
    ]
    for j in range(8):
        phi = 0.02 + j * 2 * math.pi / 55 / 8
        q = static_equilibrium(model, t_load, q0=rigid_rotation(model, r, phi))
        force, defl, xi = mesh_state(model, q)
        assert force[0] == pytest.approx(f_low, rel=1e-6)
        assert force[1] == pytest.approx(f_high, rel=1e-6)
        for i, tol in ((0, 5e-3), (1, 0.05)):
            ref = np.interp(xi[i] % 1.0, ste[i].mesh_cycle, ste[i].ste, period=1.0)
            assert defl[i] == pytest.approx(ref, rel=tol), (i, xi[i])
        # helical stage: the input-shaft bearings (ball + roller flanges) carry F tan β_b
        f = np.zeros(model.ndof)
        bl = np.zeros((model.bearings.node.size, 3))
        bearing_forces(q, np.zeros_like(q), f, np.zeros(5), *model.bearings.args(), bl)
        fz = sum(f[6 * model.node_of("input", k) + 2] for k in (1, 5))
        fax = math.tan(gh.base_helix_angle) * f_high
        assert abs(fz) == pytest.approx(fax, rel=1e-3)  # 1 kN/m static regularisation


def test_linearised_modes_and_time_step(model) -> None:
    p = prepare(model, "output")
    f = p.frequencies_hz
    assert f[0] < 1e-2  # the free rotation of the drive line
    assert f[1] > 20.0
    assert 1e-6 < p.dt_stable < 1e-4
    # damping: the rigid rotation is undamped, elastic modes get ζ = 0.01
    from geardyn.models.transmission.assembly import modal_analysis

    _, phi = modal_analysis(model.M, p.K_lin)
    zeta = np.diag(phi.T @ p.C @ phi)[1:6] / (2 * 2 * math.pi * f[1:6])
    assert zeta == pytest.approx(0.01, rel=1e-6)
    assert abs(phi[:, 0] @ p.C @ phi[:, 0]) < 1e-6


def test_mesh_must_be_driven_by_gear_a(cfg) -> None:
    data = cfg.model_dump(exclude_none=True)
    t = data["transmission"]
    t["drive"]["at"] = {"shaft": "output", "node": 0}
    t["load"]["at"] = {"shaft": "input", "node": 0}
    from geardyn.config.loader import parse_config

    with pytest.raises(ConfigError, match="driving gear"):
        build_model(parse_config(data))


def test_config_errors_name_the_field(cfg) -> None:
    from geardyn.config.loader import parse_config

    data = cfg.model_dump(exclude_none=True)
    data["transmission"]["shafts"][2]["position_m"] = [0.1455, 0.14]
    with pytest.raises(ConfigError, match="centre distance"):
        parse_config(data)
    data = cfg.model_dump(exclude_none=True)
    data["transmission"]["bearings"][0]["at"]["node"] = 9
    with pytest.raises(ConfigError, match=r"bearings\[0\].*node"):
        parse_config(data)


def test_campbell_reduces_to_modes_at_rest_and_splits_with_speed(model) -> None:
    from geardyn.models.transmission.assembly import campbell

    p = prepare(model, "output")
    r = speed_ratios(model, "output")
    cd = campbell(model, p.K_lin, np.array([0.0, 900.0, 20000.0]), r, n_modes=10)
    f_rest = p.frequencies_hz[p.frequencies_hz > 0.5][:10]
    assert np.allclose(cd.sel(speed_rpm=0.0).values, f_rest, rtol=1e-6)
    # gyroscopic coupling moves the frequencies with speed, but only slightly at 900 rpm
    d900 = np.abs(cd.sel(speed_rpm=900.0).values / f_rest - 1)
    d20k = np.abs(cd.sel(speed_rpm=20000.0).values / f_rest - 1)
    assert d900.max() < 0.02
    assert d20k.max() > d900.max()
    # the gyroscopic matrices are skew-symmetric (no work)
    for g in model.gyroscopic.values():
        assert np.abs(g + g.T).max() == 0.0


def test_static_equilibrium_falls_back_to_load_continuation(examples_dir):
    """A drawn baseline member of the seed 002 transmission (bearing clearances 30–42 µm, load
    × 0.98 × 0.82, speed × 0.85; the detectability study's FEt-02, run 2) on which plain Newton
    stalls at a contact kink: the load applied in four steps converges, to the same equilibrium
    that a long plain Newton (3000 iterations) reaches."""
    import numpy as np

    from geardyn.diagnosis import pipeline
    from geardyn.diagnosis.ensemble import member_configs
    from geardyn.models.transmission.assembly import (
        _equilibrium_newton,
        build_model,
        static_equilibrium,
    )
    from geardyn.studies.detectability import design
    from geardyn.studies.runner import healthy_configuration

    conf = next(c for c in design() if c.id == "FEt-02")
    healthy = healthy_configuration(conf)
    member = member_configs(healthy, pipeline.options(healthy))[4]
    model = build_model(member.config)
    assert _equilibrium_newton(model, model.load_torque, None, 1e-10, 500) is None
    q = static_equilibrium(model, model.load_torque)
    long = _equilibrium_newton(model, model.load_torque, None, 1e-10, 3000)
    assert long is not None
    assert np.max(np.abs(q - long)) < 1e-8 * max(np.max(np.abs(long)), 1e-12) + 1e-12
