"""The opt-in planetary loads (gravity, planet-pass force, load law): off by default, checked
input, and gravity's torsional projection (closed form)."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from geardyn.config.loader import parse_config
from geardyn.errors import ConfigError, InputError
from geardyn.models.planetary.build import prepare
from geardyn.models.planetary.loads import gravity_forces, loaded_square_mesh

from ._bench import raw, stationary


def _base() -> dict:
    return stationary(raw("planetary_bench_12dof.toml"), 1498.5, 100.0)


def test_explicit_defaults_change_nothing():
    """gravity 0, no planet-pass, no load law: the integrator system is identical."""
    a = prepare(parse_config(_base()), t_end_s=0.05)
    d = _base()
    for st in d["planetary_dynamics"]["stages"]:
        st["gravity_m_per_s2"] = 0.0
        st["planet_pass"] = None
    b = prepare(parse_config(d), t_end_s=0.05)
    for name in ("M", "C", "K", "force_t", "force"):
        np.testing.assert_array_equal(getattr(a.system, name), getattr(b.system, name))
    np.testing.assert_array_equal(a.system.springs.ktab, b.system.springs.ktab)


def test_gravity_cancels_in_the_torsional_model():
    """Torsional reduction: only the planets' tangential weights reach the carrier,
    Σ_n −m_p g cos(φ + ψ_n) = 0 for equally spaced planets (closed form)."""
    p = prepare(parse_config(_base()), t_end_s=0.05)
    for stage in p.model.stages:
        f = gravity_forces(p.model, stage, np.linspace(0, 2 * np.pi, 9), 9.81)
        np.testing.assert_allclose(f, 0.0, atol=1e-12)


@pytest.mark.parametrize(
    ("edit", "field"),
    [
        (lambda st: st.update(gravity_m_per_s2=-9.81), "gravity_m_per_s2"),
        (lambda st: st.update(gravity_m_per_s2=float("nan")), "gravity_m_per_s2"),
        (lambda st: st.update(planet_pass={"amplitude_n": 0.0}), "amplitude_n"),
        (lambda st: st.update(planet_pass={"harmonics": []}), "harmonics"),
        (lambda st: st["sun_mesh"].update(load_law={"tip_relief_m": 5e-6}), "load_law"),
        (lambda st: st["ring_mesh"].update(load_law={"tip_relief_m": -1.0}), "tip_relief_m"),
    ],
)
def test_bad_input_names_the_field(edit, field):
    d = copy.deepcopy(_base())
    st = d["planetary_dynamics"]["stages"][1]
    if field == "load_law":  # a load law on a constant mesh
        st["sun_mesh"] = {"model": "constant", "stiffness_n_per_m": 4.46e8}
    edit(st)
    with pytest.raises(ConfigError, match=field):
        parse_config(d)


def test_law_input_errors():
    with pytest.raises(InputError, match="contact_ratio"):
        loaded_square_mesh(1e8, 5e7, 2.5, 100.0, 5e-6)
    with pytest.raises(InputError, match="reference_force_n"):
        loaded_square_mesh(1e8, 5e7, 1.5, 100.0, 5e-6, stiffness_exponent=0.5)
    with pytest.raises(InputError, match="mesh force"):
        loaded_square_mesh(1e8, 5e7, 1.5, float("inf"), 5e-6)
