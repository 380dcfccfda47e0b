"""Kinematics of geared mechanisms (seed 000): ratios, DOF, carriers, characteristic frequencies.

The names below are loaded on first use (PEP 562 module ``__getattr__``): loading a config
imports :mod:`geardyn.kinematics.graph` only, not the analysis and frequency modules, which
pull in pandas (~0.6 s).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from geardyn.config import Mechanism
    from geardyn.kinematics.frequencies import (
        CharacteristicFrequencies,
        characteristic_frequencies,
        frequency_tracks,
        link_speeds,
        mesh_frequencies,
    )
    from geardyn.kinematics.graph import (
        GearMesh,
        MechanismGraph,
        PlanetarySet,
        RollingBearing,
        TurningJoint,
    )
    from geardyn.kinematics.willis import KinematicAnalysis, analyze_graph

_LAZY = {
    "CharacteristicFrequencies": "frequencies",
    "characteristic_frequencies": "frequencies",
    "frequency_tracks": "frequencies",
    "link_speeds": "frequencies",
    "mesh_frequencies": "frequencies",
    "GearMesh": "graph",
    "MechanismGraph": "graph",
    "PlanetarySet": "graph",
    "RollingBearing": "graph",
    "TurningJoint": "graph",
    "KinematicAnalysis": "willis",
    "analyze_graph": "willis",
}


def __getattr__(name: str) -> Any:  # noqa: ANN401
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'geardyn.kinematics' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"geardyn.kinematics.{module}"), name)
    globals()[name] = value
    return value


def analyze_kinematics(mechanism: Mechanism | MechanismGraph) -> KinematicAnalysis:
    """Seed 000 analysis of a validated :class:`~geardyn.config.Mechanism` or a raw graph."""
    from geardyn.kinematics.graph import MechanismGraph
    from geardyn.kinematics.willis import analyze_graph

    graph = mechanism if isinstance(mechanism, MechanismGraph) else mechanism.graph()
    return analyze_graph(graph)


__all__ = [
    "CharacteristicFrequencies",
    "GearMesh",
    "KinematicAnalysis",
    "MechanismGraph",
    "PlanetarySet",
    "RollingBearing",
    "TurningJoint",
    "analyze_graph",
    "analyze_kinematics",
    "characteristic_frequencies",
    "frequency_tracks",
    "link_speeds",
    "mesh_frequencies",
]
