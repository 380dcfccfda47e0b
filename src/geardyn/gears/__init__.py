"""Gear geometry and time-varying mesh stiffness (issue 3).

Physics modules, independent of configs and files (SI units throughout):

- :mod:`.geometry` — involute geometry of external/internal spur and helical pairs, checks.
- :mod:`.pe_stiffness` — potential-energy tooth compliance (seed 002 eq 6) and the mesh
  stiffness table k(θ) (:func:`mesh_stiffness`), sliced for helical gears.
- :mod:`.fillet_foundation` — Sainsot fillet-foundation compliance (seed 002 eq 7, App. 3).
- :mod:`.contact` — Hertz (constant) and Johnson (seed 002 eqs 8-9) contact laws.
- :mod:`.loaded` — static transmission error and load sharing with extended contact and
  profile corrections (seed 002 §2.5).
- :mod:`.faults` — root crack (seed 002 eq 14) and spall (eq 13).
- :mod:`.slice_coupling` — opt-in coupling of the face slices (seed 002 §2.2 unloaded-slice
  correction) as a two-parameter foundation.
- :mod:`.torsional` — seed 004 ch. 5 combined torsional mesh stiffness.
- :mod:`.phasing` — planetary mesh phases (seed 004 Tables 4-1, 4-2).
- :mod:`.simple` — square wave (seed 003 eqs 1.11-1.13) and ISO 6336-1 c', c_γα.
"""

from geardyn.gears.faults import Crack, Spall
from geardyn.gears.geometry import GearBlank, Material, MeshGeometry, mesh_geometry
from geardyn.gears.loaded import Corrections, LoadedResult, TipRelief, static_transmission_error
from geardyn.gears.pe_stiffness import (
    StiffnessTable,
    mean_stiffness,
    mesh_stiffness,
    pair_compliance_curve,
    tooth_compliance,
)
from geardyn.gears.phasing import planet_mesh_phases, sun_ring_phase
from geardyn.gears.simple import (
    iso_mesh_stiffness,
    iso_single_pair_stiffness,
    square_wave,
    square_wave_mean,
)
from geardyn.gears.slice_coupling import with_slice_coupling
from geardyn.gears.torsional import (
    TorsionalMeshParams,
    seed004_params,
    torsional_mesh_stiffness,
    torsional_stiffness_curve,
)

__all__ = [
    "Corrections",
    "Crack",
    "GearBlank",
    "LoadedResult",
    "Material",
    "MeshGeometry",
    "Spall",
    "StiffnessTable",
    "TipRelief",
    "TorsionalMeshParams",
    "iso_mesh_stiffness",
    "iso_single_pair_stiffness",
    "mean_stiffness",
    "mesh_geometry",
    "mesh_stiffness",
    "pair_compliance_curve",
    "planet_mesh_phases",
    "seed004_params",
    "square_wave",
    "square_wave_mean",
    "static_transmission_error",
    "sun_ring_phase",
    "tooth_compliance",
    "torsional_mesh_stiffness",
    "torsional_stiffness_curve",
    "with_slice_coupling",
]
