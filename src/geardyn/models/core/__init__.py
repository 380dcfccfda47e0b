"""Assembly core and graph → model builder of the general model (issue 11).

Imports are lazy (PEP 562): ``geardyn.models.core.assembly`` — used by every builder — must not
pull in the graph builder, the config models and the compiled integrator."""

from __future__ import annotations

from importlib import import_module
from typing import Any

_EXPORTS = {
    "build_model": "geardyn.models.core.graph",
    "model_from_config": "geardyn.models.core.graph",
    "Body": "geardyn.models.core.model",
    "CoreModel": "geardyn.models.core.model",
    "MeshElement": "geardyn.models.core.model",
    "Spring": "geardyn.models.core.model",
    "Assembly": "geardyn.models.core.assembly",
    "RankOne": "geardyn.models.core.assembly",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> Any:  # noqa: ANN401 - module attribute of any type
    if name in _EXPORTS:
        return getattr(import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'geardyn.models.core' has no attribute '{name}'")
