"""Kernel arguments of a model without bearings or meshes (a bare rotor), in the assembly's
own argument layout (:meth:`geardyn.models.transmission.assembly.Bearings.args`,
:meth:`~geardyn.models.transmission.assembly.Meshes.args`), shared by the tests that drive
the explicit loop directly."""

from __future__ import annotations

import numpy as np

from geardyn.models.transmission.assembly import Bearings, Meshes


def empty_bearings() -> tuple:
    zi, z = np.zeros(0, np.int64), np.zeros(0)
    return Bearings([], zi, zi, zi, z, z, z, z, z, z, z, z, z, z, z, z).args()


def empty_meshes() -> tuple:
    zi, z, z3 = np.zeros(0, np.int64), np.zeros(0), np.zeros((0, 1, 1))
    v = np.zeros((0, 1, 12))
    return Meshes([], zi, zi, v, zi, zi, z, z, z, z, z3, z3, z3, z3, z3, zi, np.zeros((0, 3)),
                  z, z, z, z3, v, z).args()
