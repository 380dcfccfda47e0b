"""The mechanism graph of seed 000 §2.1: links (vertices), gear pairs and turning pairs (edges).

These are plain, immutable data objects. They are produced from a validated configuration
(:mod:`geardyn.config`) or built directly in Python, and consumed by :mod:`geardyn.kinematics`.
Angles are in radians, lengths in metres.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field


def _unit(theta: float) -> complex:
    """e^{iθ}, exact for multiples of π/2 (so internal gears weigh exactly −N)."""
    c, s = math.cos(theta), math.sin(theta)
    return complex(0.0 if abs(c) < 1e-15 else c, 0.0 if abs(s) < 1e-15 else s)


@dataclass(frozen=True)
class GearMesh:
    """A gear pair between links ``link_a`` and ``link_b`` (seed 000 §2.2).

    ``theta_a`` is the pitch angle of the gear on ``link_a`` (rad, positive clockwise, from the
    gear axis to the tooth axis in contact with ``link_b``): ``|θ| < π/2`` for an external gear,
    ``π/2 < |θ| ≤ π`` for an internal one. The adjacency-table weights are
    ``T(a, b) = teeth_a·e^{iθ_a}`` and ``T(b, a) = teeth_b·e^{iθ_b}``.
    ``wheel_a``/``wheel_b`` name the toothed wheel on each link (one link may carry several
    wheels, e.g. a compound shaft), so that fault frequencies are summed per physical wheel.
    """

    name: str
    link_a: str
    link_b: str
    teeth_a: int
    teeth_b: int
    theta_a: float = 0.0
    theta_b: float = 0.0
    wheel_a: str = ""
    wheel_b: str = ""
    stage: str | None = None

    @property
    def weight_a(self) -> complex:
        """Adjacency-table entry T(a, b) = N_a e^{iθ_a} (seed 000 §2.2)."""
        return self.teeth_a * _unit(self.theta_a)

    @property
    def weight_b(self) -> complex:
        """Adjacency-table entry T(b, a) = N_b e^{iθ_b} (seed 000 §2.2)."""
        return self.teeth_b * _unit(self.theta_b)


@dataclass(frozen=True)
class TurningJoint:
    """A turning pair (revolute joint) between two links on axis level ``axis`` (seed 000 §2.1).

    Turning pairs that share a level and touch each other form a multiple turning pair.
    """

    link_a: str
    link_b: str
    axis: str


@dataclass(frozen=True)
class RollingBearing:
    """A rolling-element bearing mounted on the turning pair ``inner``–``outer``.

    Geometry in metres and radians: ``n_elements`` balls/rollers of diameter
    ``element_diameter`` on pitch diameter ``pitch_diameter`` with contact angle
    ``contact_angle`` (0 for radial roller bearings).
    """

    name: str
    inner: str
    outer: str
    n_elements: int
    element_diameter: float
    pitch_diameter: float
    contact_angle: float = 0.0
    kind: str = "ball"


@dataclass(frozen=True)
class PlanetarySet:
    """Bookkeeping of a planetary stage expanded from the convenience description.

    The graph itself (links, meshes, joints) is complete without it; it lets reports name the
    sun, ring, carrier and planets and compute planet-pass frequencies.
    """

    name: str
    sun: str
    ring: str
    carrier: str
    planets: tuple[str, ...]
    planet_angles: tuple[float, ...]
    sun_wheel: str
    ring_wheel: str


@dataclass
class MechanismGraph:
    """A complete geared mechanism: links, gear pairs, turning pairs, bearings, frame link."""

    name: str
    frame: str
    links: list[str]
    meshes: list[GearMesh] = field(default_factory=list)
    joints: list[TurningJoint] = field(default_factory=list)
    bearings: list[RollingBearing] = field(default_factory=list)
    planetary_sets: list[PlanetarySet] = field(default_factory=list)

    def index(self, link: str) -> int:
        """Position of ``link`` in :attr:`links` (the order of Ω in seed 000 §2.4)."""
        return self.links.index(link)
