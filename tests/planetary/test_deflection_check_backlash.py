"""The run's mesh-deflection check (run.py) counts tooth compression, not the backlash gap:
a mesh inside its gap or on its back flank with a small compression is not `suspect`, a
back-flank compression above 0.1 module still is."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from geardyn.config.loader import load_config, parse_config
from geardyn.run import _check_mesh_deflection

EX = Path(__file__).resolve().parents[2] / "examples" / "planetary_bench_12dof.toml"


def _case(backlash_m: float, deflection_m: float) -> xr.Dataset:
    d = load_config(EX).model_dump(exclude_none=True)
    stage = d["planetary_dynamics"]["stages"][0]
    stage["sun_mesh"]["backlash_m"] = backlash_m
    cfg = parse_config(d)
    st = stage["stage"]  # two stages: mesh names carry the stage prefix
    names = [f"{st}.planet1.mesh_sun", f"{st}.planet1.mesh_ring"]
    ds = xr.Dataset({"mesh_deflection": (("time", "mesh"),
                                         np.array([[1e-7, 1e-7], [deflection_m, 1e-7]]))},
                    coords={"mesh": names}, attrs={"status": "ok"})
    _check_mesh_deflection(ds, cfg)
    return ds


def test_gap_and_small_back_flank_compression_are_not_suspect() -> None:
    b = 2e-3  # about 0.5 module: far more than 0.1 module of "deflection" if counted
    assert _case(b, -0.5 * b).attrs["status"] == "ok"  # teeth apart
    assert _case(b, -b - 1e-6).attrs["status"] == "ok"  # back flank, 1 µm compression


def test_back_flank_compression_over_a_tenth_of_a_module_is_suspect() -> None:
    b = 2e-3
    ds = _case(b, -b - 2e-3)
    assert ds.attrs["status"] == "suspect" and "mesh deflection" in ds.attrs["diagnosis"]
    assert _case(0.0, -2e-3).attrs["status"] == "suspect"  # no backlash: |δ| counts
