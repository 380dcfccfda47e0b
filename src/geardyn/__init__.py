"""geardyn: dynamics and condition monitoring of gear transmissions.

Public entry points:

- :func:`geardyn.load_config` reads a TOML description and validates it.
- :class:`geardyn.Mechanism` is the validated kinematic description (usable from Python).
- :func:`geardyn.analyze_kinematics` runs the seed 000 method (adjacency table, reference links,
  Willis constraint matrix, nullspace) and returns ratios and characteristic frequencies.

Names are imported on first use (:data:`_LAZY`: name → module), so ``import geardyn`` loads
neither pandas, xarray nor matplotlib. The xarray accessor ``ds.geardyn`` (plot of a result,
:mod:`geardyn.plotting`) is registered as soon as xarray is imported.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
from typing import Any

from geardyn.errors import ConfigError, GeardynError, InputError, KinematicsError

__version__ = "0.1.0"

#: public name → module defining it (imported on first access). One line per name.
_LAZY: dict[str, str] = {
    "GeardynConfig": "geardyn.config",
    "Mechanism": "geardyn.config",
    "load_config": "geardyn.config",
    "KinematicAnalysis": "geardyn.kinematics",
    "analyze_kinematics": "geardyn.kinematics",
    "GeardynAccessor": "geardyn.plotting",
    "open_dataset": "geardyn.sweep.store",
}


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'geardyn' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


class _RegisterAccessor(importlib.abc.MetaPathFinder):
    """Registers ``ds.geardyn`` (import of :mod:`geardyn.plotting`) right after xarray is
    imported, wherever that import happens."""

    def find_spec(self, fullname: str, path: Any, target: Any = None) -> Any:
        if fullname != "xarray":
            return None
        sys.meta_path.remove(self)
        spec = importlib.util.find_spec("xarray")
        if spec is None or spec.loader is None or not hasattr(spec.loader, "exec_module"):
            return spec
        exec_module = spec.loader.exec_module

        def exec_then_register(module: Any) -> None:
            exec_module(module)
            importlib.import_module("geardyn.plotting")

        spec.loader.exec_module = exec_then_register  # type: ignore[method-assign]
        return spec


if "xarray" in sys.modules:
    importlib.import_module("geardyn.plotting")
elif not any(isinstance(f, _RegisterAccessor) for f in sys.meta_path):
    sys.meta_path.insert(0, _RegisterAccessor())

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
    "open_dataset",
    "__version__",
]
