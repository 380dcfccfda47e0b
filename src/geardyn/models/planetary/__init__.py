"""Lumped-parameter planetary gear dynamics (issue 4): assembly, statics, simulation."""

from geardyn.models.planetary.model import (
    Body,
    PlanetaryModel,
    RotorSpec,
    ShaftSpec,
    Spring,
    StageSpec,
    assemble,
)

__all__ = ["Body", "PlanetaryModel", "RotorSpec", "ShaftSpec", "Spring", "StageSpec", "assemble"]
