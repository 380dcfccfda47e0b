"""[[gear_geometry]] config section, the example configs, and 'geardyn stiffness'."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from geardyn.cli import app
from geardyn.config import load_config
from geardyn.config.gears import pair_model, pair_names
from geardyn.config.loader import parse_config
from geardyn.errors import ConfigError
from geardyn.gears.pe_stiffness import mesh_stiffness

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
WITH_GEOMETRY = sorted(p for p in EXAMPLES.glob("*.toml") if "gear_geometry" in p.read_text())

BASE = {
    "frame": "housing",
    "links": ["housing", "in", "out"],
    "parallel": [
        {"name": "low", "a": {"link": "in", "teeth": 42}, "b": {"link": "out", "teeth": 55}}
    ],
}


def test_examples_with_geometry_exist():
    names = {p.name for p in WITH_GEOMETRY}
    assert {"seed002_two_stage.toml", "seed004_planetary.toml"} <= names


@pytest.mark.parametrize("path", WITH_GEOMETRY, ids=[p.stem for p in WITH_GEOMETRY])
def test_every_geometry_example_builds_tables(path):
    cfg = load_config(path)
    for name in pair_names(cfg):
        pm = pair_model(cfg, name)
        t = mesh_stiffness(pm.geometry, n_per_cycle=16, n_cycles=2, faults=pm.faults)
        assert np.all(t.total > 0)


def test_seed004_example_reproduces_table_4_2():
    cfg = load_config(EXAMPLES / "seed004_planetary.toml")
    sun = pair_model(cfg, "plan.sun-planet2").geometry
    ring = pair_model(cfg, "plan.ring-planet3")
    assert ring.swapped and ring.geometry.internal
    assert sun.contact_ratio == pytest.approx(1.60569, abs=1e-5)
    assert ring.geometry.contact_ratio == pytest.approx(2.26669, abs=1e-5)
    assert len(pair_names(cfg)) == 6


def test_seed002_example_stages():
    cfg = load_config(EXAMPLES / "seed002_two_stage.toml")
    high = pair_model(cfg, "high").geometry
    low = pair_model(cfg, "low")
    assert high.teeth == (31, 53) and low.geometry.teeth == (42, 55)
    assert abs(high.helix_angle) > 0 and low.geometry.helix_angle == 0
    assert len(low.faults) == 2 and low.torque == 200.0


def _with(entry: dict) -> dict:
    d = dict(BASE)
    d["gear_geometry"] = [entry]
    return d


def test_contact_ratio_error_names_field_and_rule():
    entry = {
        "pair": "low",
        "normal_module_m": 0.003,
        "face_width_m": 0.02,
        "a": {"addendum_coef": 0.4},
        "b": {"addendum_coef": 0.4},
    }
    with pytest.raises(ConfigError) as exc:
        parse_config(_with(entry))
    msg = str(exc.value)
    assert "gear_geometry[0]" in msg and "gear pair 'low'" in msg
    assert "transverse contact ratio" in msg and "< 1" in msg


@pytest.mark.parametrize(
    "entry, fragment",
    [
        ({"pair": "nope", "normal_module_m": 0.003, "face_width_m": 0.02}, "no gear pair"),
        ({"pair": "low", "normal_module_m": -0.003, "face_width_m": 0.02}, "normal_module_m"),
        (
            {
                "pair": "low",
                "normal_module_m": 0.003,
                "face_width_m": 0.02,
                "cracks": [{"tooth": 99, "depth_m": 1e-3}],
            },
            "cracks[0].tooth 99",
        ),
        (
            {
                "pair": "low",
                "normal_module_m": 0.003,
                "face_width_m": 0.02,
                "b": {"normal_module_m": 0.004},
            },
            "base pitches differ",
        ),
        (
            {"pair": "low", "normal_module_m": 0.003, "face_width_m": 0.02, "a": {"colour": 1}},
            "unknown field",
        ),
    ],
)
def test_bad_geometry_messages(entry, fragment):
    with pytest.raises(ConfigError) as exc:
        parse_config(_with(entry))
    assert fragment in str(exc.value)


def test_cli_stiffness_plot(tmp_path):
    out = tmp_path / "k.png"
    res = CliRunner().invoke(
        app,
        [
            "stiffness",
            str(EXAMPLES / "seed002_two_stage.toml"),
            "--pair",
            "low",
            "--plot",
            str(out),
            "--samples",
            "32",
        ],
    )
    assert res.exit_code == 0, res.output
    assert out.stat().st_size > 1000
    assert "contact_ratio" in res.output


def test_cli_unknown_pair_is_one_message():
    res = CliRunner().invoke(
        app, ["stiffness", str(EXAMPLES / "seed002_two_stage.toml"), "--pair", "middle"]
    )
    assert res.exit_code == 2
    assert "no gear pair of that name" in res.output
    assert "Traceback" not in res.output


@pytest.mark.parametrize(
    "fault, fragment",
    [
        ({"spalls": [{"radius_m": 0.2, "radial_width_m": 0.001}]}, "outside the contact zone"),
        ({"cracks": [{"depth_m": 0.02}]}, "cuts through"),
        ({"cracks": [{"depth_m": 1e-3, "radius_m": 0.5}]}, "between the root and tip"),
    ],
)
def test_faults_that_cannot_act_are_rejected(fault, fragment):
    entry = {"pair": "low", "normal_module_m": 0.003, "face_width_m": 0.02, **fault}
    with pytest.raises(ConfigError) as exc:
        parse_config(_with(entry))
    assert fragment in str(exc.value) and "gear_geometry[0]" in str(exc.value)


def test_trochoid_fillet_from_the_config_equals_the_python_blank():
    """`root_fillet = "trochoid"` (and the rack tip radius) in [[gear_geometry]] reach the PE
    stiffness: the table equals the one of the Python GearBlank of tests/gears/test_trochoid.py
    (validated there against ROSS), and differs from the involute-root default."""
    from geardyn.gears.geometry import GearBlank, Material, mesh_geometry

    base = {"frame": "housing", "links": ["housing", "in", "out"],
            "parallel": [{"name": "p", "a": {"link": "in", "teeth": 62},
                          "b": {"link": "out", "teeth": 62}}]}
    wheel = {"rim_radius_m": 0.0175, "youngs_modulus_pa": 206e9, "poisson_ratio": 0.3,
             "density_kg_m3": 7810.0, "root_fillet": "trochoid"}
    entry = {"pair": "p", "normal_module_m": 0.002, "face_width_m": 0.02, "a": wheel,
             "b": wheel}
    d = dict(base, gear_geometry=[entry])
    cfg = parse_config(d)
    pm = pair_model(cfg, "p")
    mat = Material(206e9, 0.3, 7810.0)
    bl = GearBlank(62, rim_radius=0.0175, material=mat, root_fillet="trochoid")
    ref = mesh_geometry(bl, bl, 0.002, np.radians(20.0), 0.020)
    k_cfg = mesh_stiffness(pm.geometry, n_per_cycle=16).total
    k_ref = mesh_stiffness(ref, n_per_cycle=16).total
    np.testing.assert_allclose(k_cfg, k_ref, rtol=1e-12)
    inv = dict(wheel, root_fillet="involute")
    pm_inv = pair_model(parse_config(dict(base, gear_geometry=[dict(entry, a=inv, b=inv)])), "p")
    assert mesh_stiffness(pm_inv.geometry, n_per_cycle=16).total.mean() < k_cfg.mean() / 1.05
    # a rack tip radius is a length > 0, and only two fillet kinds exist
    for bad, field in (({"rack_tip_radius_m": -1e-4}, "rack_tip_radius_m"),
                       ({"root_fillet": "circular"}, "root_fillet")):
        with pytest.raises(ConfigError, match=field):
            parse_config(dict(base, gear_geometry=[dict(entry, a=dict(wheel, **bad))]))
