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
