"""Kinematics of geared mechanisms (seed 000): ratios, DOF, carriers, characteristic frequencies."""

from __future__ import annotations

from typing import TYPE_CHECKING

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

if TYPE_CHECKING:
    from geardyn.config import Mechanism


def analyze_kinematics(mechanism: Mechanism | MechanismGraph) -> KinematicAnalysis:
    """Seed 000 analysis of a validated :class:`~geardyn.config.Mechanism` or a raw graph."""
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
