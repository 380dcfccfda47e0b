"""Configuration: TOML files validated by pydantic; the same objects are usable from Python.

A config file describes a machine. The mechanism (links, gear pairs, turning pairs, bearings,
stages; Penaud et al. 2012) sits at the top level; analysis-specific sections are optional tables.
"""

from geardyn.config.loader import GeardynConfig, format_validation_error, load_config, parse_config
from geardyn.config.mechanism import (
    Bearing,
    BearingGeometry,
    BevelStage,
    GearPair,
    GearSide,
    Link,
    Mechanism,
    ParallelStage,
    PlanetaryStage,
    StageSide,
    TurningPair,
)

__all__ = [
    "Bearing",
    "BearingGeometry",
    "BevelStage",
    "GearPair",
    "GearSide",
    "GeardynConfig",
    "Link",
    "Mechanism",
    "ParallelStage",
    "PlanetaryStage",
    "StageSide",
    "TurningPair",
    "format_validation_error",
    "load_config",
    "parse_config",
]
