"""geardyn: dynamics and condition monitoring of gear transmissions.

Public entry points:

- :func:`geardyn.load_config` reads a TOML description and validates it.
- :class:`geardyn.Mechanism` is the validated kinematic description (usable from Python).
- :func:`geardyn.analyze_kinematics` runs the seed 000 method (adjacency table, reference links,
  Willis constraint matrix, nullspace) and returns ratios and characteristic frequencies.
"""

from geardyn.config import GeardynConfig, Mechanism, load_config
from geardyn.errors import ConfigError, GeardynError, InputError, KinematicsError
from geardyn.kinematics import KinematicAnalysis, analyze_kinematics
from geardyn.plotting import GeardynAccessor as GeardynAccessor  # registers ds.geardyn

__version__ = "0.1.0"

__all__ = [
    "ConfigError",
    "GeardynConfig",
    "GeardynError",
    "InputError",
    "KinematicAnalysis",
    "KinematicsError",
    "Mechanism",
    "analyze_kinematics",
    "load_config",
    "__version__",
]
