"""Shared runs of the seed 004 (Wang 2010) reclaimer planetary stage
(examples/planetary_reclaimer.toml: z_s = 19, z_p = 32, z_r = 83, 3 planets, motor + fluid
coupling), without transmission error (the thesis's crack cases use case 2 without error)."""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import numpy as np
import xarray as xr

from geardyn.config.loader import parse_config
from geardyn.models.planetary.build import Prepared, prepare
from geardyn.models.planetary.dynamics import simulate

EX = Path(__file__).resolve().parents[3] / "examples"
ZS, ZP, ZR = 19, 32, 83
DT, SAVE = 1e-4, 5
R_C = 0.408  # carrier radius (m) of the example


def raw() -> dict:
    with open(EX / "planetary_reclaimer.toml", "rb") as fh:
        return tomllib.load(fh)


def run(faults: list[dict], t_end: float, te: bool = False, edit=None
        ) -> tuple[Prepared, xr.Dataset]:
    d = copy.deepcopy(raw())
    st = d["planetary_dynamics"]["stages"][0]
    st["faults"] = faults
    st["transmission_error"] = te
    if edit is not None:
        edit(d)
    p = prepare(parse_config(d), t_end_s=t_end)
    ds = simulate(p.model, p.system, p.mesh_index, p.q0, p.v0, t_end, DT, save_every=SAVE)
    assert ds.attrs["status"] == "ok", ds.attrs["diagnosis"]
    return p, ds


def mesh_cycles(ds: xr.Dataset) -> np.ndarray:
    """Ring-mesh cycle count X = z_r θ_c/2π (the ring is held; = the sun-mesh count)."""
    return ZR * ds.q.sel(dof="carrier.u").values / R_C / (2 * np.pi)
