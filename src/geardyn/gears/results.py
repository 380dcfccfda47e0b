"""Stiffness tables as xarray datasets (dims ``angle`` and ``pair``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import xarray as xr

if TYPE_CHECKING:
    from geardyn.gears.pe_stiffness import StiffnessTable


def table_to_dataset(t: StiffnessTable) -> xr.Dataset:
    """Dataset with ``total`` (N/m), ``torsional`` (N·m/rad, referred to gear a),
    ``pair_stiffness`` (N/m, per tooth pair by age: 0 = newest), tooth indices and contact
    position; coordinates ``angle`` (rad, gear a) and ``mesh_cycle``."""
    g = t.geometry
    ds = xr.Dataset(
        {
            "total": (("angle",), t.total, {"units": "N/m", "long_name": "mesh stiffness"}),
            "torsional": (("angle",), t.torsional, {"units": "N m/rad"}),
            "pair_stiffness": (("angle", "pair"), t.pair_stiffness, {"units": "N/m"}),
            "tooth_a": (("angle", "pair"), t.tooth_a),
            "tooth_b": (("angle", "pair"), t.tooth_b),
            "contact_position": (("angle", "pair"), t.contact, {"units": "m"}),
        },
        coords={
            "angle": ("angle", t.angle_a, {"units": "rad", "long_name": "rotation of gear a"}),
            "mesh_cycle": ("angle", t.mesh_cycle),
            "pair": ("pair", np.arange(t.pair_stiffness.shape[1])),
        },
        attrs={
            "pair_name": g.label,
            "teeth_a": g.a.teeth,
            "teeth_b": g.b.teeth,
            "contact_ratio": g.contact_ratio,
            "overlap_ratio": g.overlap_ratio,
            "base_radius_a_m": g.base_radius[0],
            "faults": "; ".join(repr(f) for f in t.faults),
            "slice_coupling": int(t.slice_coupling),
        },
    )
    return ds
