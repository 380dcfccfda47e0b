"""Structural finite elements (SI units): Timoshenko shaft element (6 DOF/node) and rigid disc.

DOF order per node: (x, y, z, θx, θy, θz) with z the shaft axis; θz is the full rotation of the
section (rigid body + torsion, seed 002 §2.1).
"""

from geardyn.elements.beam import (
    ShaftSection,
    shear_coefficient,
    timoshenko_element,
    timoshenko_gyroscopic,
)
from geardyn.elements.disc import disc_gyroscopic, rigid_disc

__all__ = [
    "ShaftSection",
    "disc_gyroscopic",
    "rigid_disc",
    "shear_coefficient",
    "timoshenko_element",
    "timoshenko_gyroscopic",
]
