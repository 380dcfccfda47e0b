"""Output forms (JSON, xarray, speed profiles) and the stage conveniences."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from geardyn import analyze_kinematics, load_config
from geardyn.config import BevelStage, parse_config
from geardyn.kinematics import characteristic_frequencies, frequency_tracks


@pytest.fixture(scope="module")
def reclaimer(examples_dir):
    return analyze_kinematics(load_config(examples_dir / "reclaimer_drive.toml"))


def test_json_and_xarray_agree(reclaimer):
    f = characteristic_frequencies(reclaimer, {"motor": 950.0})
    d = json.loads(f.to_json())
    ds = f.to_xarray()
    assert d["dof"] == ds.attrs["dof"] == 1
    m0 = d["meshes"][0]
    assert float(ds["mesh_mesh_hz"].sel(mesh=m0["pair"])) == pytest.approx(m0["mesh_hz"])
    assert float(ds["link_rpm"].sel(link="motor")) == pytest.approx(950.0)


def test_speed_profile_tracks_scale_linearly(reclaimer):
    t = np.linspace(0.0, 10.0, 11)
    rpm = 95.0 * t  # run-up 0 → 950 rpm
    ds = frequency_tracks(reclaimer, {"motor": rpm}, t)
    f950 = characteristic_frequencies(reclaimer, {"motor": 950.0})
    fm = f950.meshes.set_index("pair")["mesh_hz"]
    for pair in ("G1-G2", "planetary.ring-planet2"):
        np.testing.assert_allclose(ds["mesh_hz"].sel(mesh=pair), fm[pair] * t / 10.0, rtol=1e-12)
    assert ds["link_hz"].sel(link="motor").values[-1] == pytest.approx(950 / 60)


def test_speed_profile_bad_shapes(reclaimer):
    from geardyn.errors import InputError

    with pytest.raises(InputError, match="time: must have one value per speed sample"):
        frequency_tracks(reclaimer, {"motor": np.ones(5)}, np.arange(4.0))


def test_bevel_stage_pitch_angles():
    st = BevelStage(name="b", a={"link": "x", "teeth": 13}, b={"link": "y", "teeth": 38})
    ta, tb = st.pitch_angles()
    # pitch cones of a 90° pair: tan δ1 = z1/z2 (e.g. ISO 23509); δ1 + δ2 = 90°
    assert -ta == pytest.approx(math.atan(13 / 38), rel=1e-12)
    assert tb - ta == pytest.approx(math.pi / 2, rel=1e-12)


def test_stepped_planetary_ratio():
    # ring fixed, stepped planets: ω_s/ω_c = 1 + z_r·z_ps/(z_s·z_pr) = 1 + 72·36/(18·18) = 9
    cfg = parse_config(
        {
            "frame": "housing",
            "links": ["housing", "sun", "carrier"],
            "planetary": [
                {
                    "name": "st",
                    "sun": "sun",
                    "ring": "housing",
                    "carrier": "carrier",
                    "sun_teeth": 18,
                    "planet_teeth": [36, 18],
                    "ring_teeth": 72,
                    "n_planets": 3,
                }
            ],
        }
    )
    r = analyze_kinematics(cfg).velocity_ratios(["sun"])[:, 0]
    g = cfg.graph()
    assert r[g.index("carrier")] == pytest.approx(1 / 9, rel=1e-12)


@pytest.mark.parametrize("fixed", ["ring", "sun", "carrier"])
@pytest.mark.parametrize(
    ("zs", "zp", "zr", "n"), [(16, 24, 65, 3), (19, 32, 83, 3), (21, 21, 63, 4)]
)
def test_simple_planetary_matches_willis_formula(fixed, zs, zp, zr, n):
    # Willis (seed 003 eq 1.4 with K_W = −Z_s/Z_r): ω_r − ω_c = −(Z_s/Z_r)(ω_s − ω_c)
    names = {m: ("housing" if m == fixed else m) for m in ("sun", "ring", "carrier")}
    stage = {
        "name": "ps",
        **names,
        "sun_teeth": zs,
        "planet_teeth": zp,
        "ring_teeth": zr,
        "n_planets": n,
    }
    links = ["housing", *[m for m in ("sun", "ring", "carrier") if m != fixed]]
    cfg = parse_config({"frame": "housing", "links": links, "planetary": [stage]})
    kin = analyze_kinematics(cfg)
    assert kin.dof == 1
    free = [x for x in ("sun", "ring", "carrier") if x != fixed]
    w = kin.speeds({free[0]: 1.0})
    g = cfg.graph()
    ws, wr, wc = (w[g.index(names[x])].real for x in ("sun", "ring", "carrier"))
    assert wr - wc == pytest.approx(-zs / zr * (ws - wc), abs=1e-12)
    # planet: ω_p − ω_c = −(Z_s/Z_p)(ω_s − ω_c)
    wp = w[g.index("ps.planet1")].real
    assert wp - wc == pytest.approx(-zs / zp * (ws - wc), abs=1e-12)
