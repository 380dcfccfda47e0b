"""Finite-element transmission with nonlinear bearings and gear meshes (seed 002, issue 6).

- :mod:`.assembly` — shafts of Timoshenko elements, rigid wheels, bearing and mesh parameters,
  static equilibrium, modal analysis, modal damping.
- :mod:`.kernels` — numba connecting forces (bearings, gear meshes).
- :mod:`.integrate` — compiled explicit integrator with speed-tracking drive.
- :mod:`.simulate` — preparation and runs returning xarray Datasets.
"""

from geardyn.models.transmission.assembly import (
    TransmissionModel,
    build_model,
    modal_analysis,
    static_equilibrium,
)
from geardyn.models.transmission.simulate import (
    SimulationDivergedError,
    prepare,
    simulate,
)

__all__ = [
    "SimulationDivergedError",
    "TransmissionModel",
    "build_model",
    "modal_analysis",
    "prepare",
    "simulate",
    "static_equilibrium",
]
