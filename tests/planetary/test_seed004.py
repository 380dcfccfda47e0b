"""Seed 004 reclaimer gearbox: steady-state ratios and mesh frequency vs the kinematics module;
tooth-fault signature counts (seed 004 eqs 9.1-9.3, Table 9-17) in the carrier torsional
signal resampled to the carrier angle (geardyn.signal)."""

from __future__ import annotations

import copy
import math
import tomllib

import numpy as np
import pytest
from scipy.signal import find_peaks

from geardyn.config.loader import parse_config
from geardyn.kinematics import analyze_kinematics, characteristic_frequencies
from geardyn.models.planetary.build import prepare
from geardyn.models.planetary.dynamics import simulate
from geardyn.signal import resample_to_angle

from .conftest import EX

ZS, ZP, ZR = 19, 32, 83
DT, SAVE = 1e-4, 5


@pytest.fixture(scope="module")
def raw():
    with open(EX / "planetary_reclaimer.toml", "rb") as fh:
        return tomllib.load(fh)


def _run(raw, faults, t_end, te=False):
    d = copy.deepcopy(raw)
    st = d["planetary_dynamics"]["stages"][0]
    st["faults"] = faults
    st["transmission_error"] = te
    cfg = parse_config(d)
    p = prepare(cfg)
    ds = simulate(p.model, p.system, p.mesh_index, p.q0, p.v0, t_end, DT, save_every=SAVE)
    assert ds.attrs["status"] == "ok", ds.attrs["diagnosis"]
    return cfg, p, ds


@pytest.fixture(scope="module")
def healthy(raw):
    return _run(raw, [], 10.0)


def test_steady_state_ratios_and_mesh_frequency(healthy):
    cfg, p, ds = healthy
    last = ds.sel(time=slice(8.0, None))
    rb = {b: p.model.body(b).radius for b in ("sun", "carrier", "planet1")}
    w = {b: float(last.v.sel(dof=f"{b}.u").mean()) / rb[b] for b in rb}
    sun_rpm = w["sun"] * 60 / (2 * math.pi)
    kin = characteristic_frequencies(analyze_kinematics(cfg), {"sun": sun_rpm})
    links = kin.links.set_index("link")
    ratio = links["signed_rpm"].astype(float) / sun_rpm
    assert w["carrier"] / w["sun"] == pytest.approx(ratio["carrier"], rel=1e-4)
    assert w["carrier"] / w["sun"] == pytest.approx(1 / 5.3684, rel=1e-4)  # Table 6-3
    assert w["planet1"] / w["sun"] == pytest.approx(ratio["planetary.planet1"], rel=1e-3)
    # motor → sun through the fluid coupling: 29.2971 with a small slip
    w_m = float(last.v.sel(dof="motor.theta").mean())
    slip = 1 - 29.2971 * w["sun"] / w_m
    assert 0 < slip < 0.03
    # mesh frequency from the simulated stiffness (period between contact-change edges)
    k = last.mesh_stiffness.sel(mesh="planet1.mesh_sun").values
    t = last.time.values
    mid = 0.5 * (k.max() + k.min())
    up = np.flatnonzero((k[1:] >= mid) & (k[:-1] < mid))
    f_sim = (len(up) - 1) / (t[up[-1]] - t[up[0]])
    f_kin = float(kin.meshes.set_index("pair").loc["planetary.sun-planet1", "mesh_hz"])
    assert f_sim == pytest.approx(f_kin, rel=2e-3)
    assert f_kin == pytest.approx(ZR * w["carrier"] / (2 * math.pi), rel=1e-6)


@pytest.mark.parametrize(
    ("fault", "per_rev"),
    [
        # Table 9-17: 13.1052 sun-crack humps per carrier rev
        ({"kind": "crack", "gear": "sun", "crack_fraction": 0.4}, (5.3684 - 1) * 3),
        ({"kind": "crack", "gear": "ring", "crack_fraction": 0.4}, 3.0),  # one per planet pass
        # eq 9.3: z_r/z_p = 2.5938 (bigger humps: the sun mesh)
        ({"kind": "crack", "gear": "planet", "crack_fraction": 0.4}, ZR / ZP),
        ({"kind": "spall", "gear": "sun", "spall_depth_m": 2e-4}, (5.3684 - 1) * 3),
    ],
)
def test_fault_signature_counts(raw, healthy, fault, per_rev):
    """Difference of the carrier torsional velocity (cracked − healthy), resampled to the
    carrier angle: disturbances recur every 360°/per_rev of carrier rotation."""
    _, p, h = healthy
    _, _, c = _run(raw, [fault], 10.0)
    rc = p.model.body("carrier").radius
    theta = c.q.sel(dof="carrier.u").values / rc
    diff = (c.v.sel(dof="carrier.u") - h.v.sel(dof="carrier.u")).values
    spr = 3600
    sig = resample_to_angle(np.abs(diff), 1 / (DT * SAVE), theta, samples_per_rev=spr,
                            anti_alias=False)
    x = sig.x
    # events: clusters of large peaks; spacing in carrier degrees
    pk, _ = find_peaks(x, height=0.3 * x.max())
    starts = pk[np.concatenate([[True], np.diff(pk) > spr / per_rev / 3])]
    assert len(starts) >= 3
    spacing_deg = np.median(np.diff(starts)) * 360 / spr
    assert 360 / spacing_deg == pytest.approx(per_rev, rel=0.02)


def _prepared(raw, edit):
    from geardyn.models.planetary.build import rigid_velocity

    d = copy.deepcopy(raw)
    d["planetary_dynamics"]["stages"][0]["faults"] = []
    edit(d)
    p = prepare(parse_config(d), t_end_s=0.01)
    return p, rigid_velocity(p.model, {"sun": 32.4263})


def test_planet_bearing_damper_is_relative_and_per_bearing(raw):
    """``planet_bearing_damping_ns_per_m`` (Wang 2010 Table 7-1 c_px, c_py) adds c a aᵀ for
    each of the 2N planet-bearing springs (deflection δ = aᵀq, seed 003 eq 3.10 layout): the
    change of C is c Σ a aᵀ exactly, a damper of c on each bearing's own relative motion, and
    it does not act on the rigid-body rotation."""
    c = 1e6

    def with_c(d):
        d["planetary_dynamics"]["stages"][0]["planet_bearing_damping_ns_per_m"] = c

    p0, v = _prepared(raw, lambda d: None)
    p1, _ = _prepared(raw, with_c)
    a = p0.model.spring_vectors()
    rows = [a[i] for i, s in enumerate(p0.model.springs) if s.kind == "planet_bearing"]
    assert len(rows) == 6
    dc = p1.system.C - p0.system.C
    np.testing.assert_allclose(dc, c * sum(np.outer(r, r) for r in rows), rtol=0, atol=1e-9 * c)
    assert np.abs(dc @ v).max() < 1e-9 * c * np.abs(v).max()
    # one bearing's relative velocity of 1 m/s (planet 1 radial, carrier at rest) → force c
    j = p0.model.dof("planet1.zeta")
    e = np.zeros(len(p0.model.names))
    e[j] = 1.0
    assert dc[j] @ e == pytest.approx(c)


def test_planet_bearing_damping_bad_input_names_the_field(tmp_path):
    from geardyn.config import load_config
    from geardyn.errors import ConfigError

    text = (EX / "planetary_reclaimer.toml").read_text()
    for val, word in (("-1.0", "greater than or equal to 0"), ("nan", "finite")):
        bad = tmp_path / "bad.toml"
        bad.write_text(text.replace("planet_bearing_n_per_m = 1e8",
                                    f"planet_bearing_n_per_m = 1e8\n"
                                    f"planet_bearing_damping_ns_per_m = {val}", 1))
        with pytest.raises(ConfigError) as err:
            load_config(bad)
        assert "planet_bearing_damping_ns_per_m" in str(err.value)
        assert word in str(err.value)
