"""Tooth faults for the potential-energy mesh stiffness: root crack and spall (seed 002 §2.6).

* :class:`Crack` — plane root crack (Chen & Shao 2011 dead-zone model, seed 002 eq 14): it
  starts on the loaded flank at radius ``radius`` (default: the root circle), runs into the
  tooth at ``angle`` below the tooth perpendicular, with depth q(z) along the face given by a
  depth law; sections above the crack tip keep only the uncracked half plus a part of the
  cracked half bounded by a parabola from the crack tip to the tooth tip (the "dead zone").
* :class:`Spall` — rectangular spall (seed 002 eq 13): radial centre and width, depth, axial
  centre and length. In the loaded-contact solver the spall subtracts its depth from the
  deflection of the slices in contact on it (eq 13); in the linear (unloaded) stiffness table it
  removes those slices (the limit of eq 13 when the depth exceeds the slice deflection, e.g.
  seed 002's 100 µm spall against ~10-20 µm tooth deflections).

Lengths in metres, angles in radians. ``gear`` is ``"a"`` (pinion) or ``"b"``; ``tooth`` is
the tooth index (0-based; tooth 0 of each gear is in the pair that enters contact at ξ = 0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from geardyn.errors import InputError


@dataclass(frozen=True)
class Crack:
    """Root crack: depth q0 (m), angle α_c (rad), start radius r_c (m, None = root circle),
    axial extent ``width`` from the face start (m, None = the whole face), and depth law along
    the face: ``uniform`` q = q0; ``linear`` q = q0(1 − z/w); ``parabolic`` q = q0·√(1 − z/w)
    (the shape of Chen & Shao's crack front propagating along the face, z from the cracked end).
    """

    gear: Literal["a", "b"] = "a"
    tooth: int = 0
    depth: float = 0.0
    angle: float = math.radians(45.0)
    radius: float | None = None
    width: float | None = None
    law: Literal["uniform", "linear", "parabolic"] = "uniform"

    def depth_at(self, z: np.ndarray, face_width: float) -> np.ndarray:
        """Crack depth q(z) (m) at axial positions z (m from the face start)."""
        z = np.asarray(z, dtype=float)
        w = face_width if self.width is None else self.width
        if w <= 0:
            return np.zeros_like(z)
        s = np.clip(z / w, 0.0, None)
        if self.law == "uniform":
            q = np.where(s <= 1.0, self.depth, 0.0)
        elif self.law == "linear":
            q = self.depth * np.clip(1.0 - s, 0.0, 1.0)
        elif self.law == "parabolic":
            q = self.depth * np.sqrt(np.clip(1.0 - s, 0.0, 1.0))
        else:  # pragma: no cover - guarded by Literal/pydantic
            raise InputError(f"unknown crack depth law {self.law!r}")
        return q


@dataclass(frozen=True)
class Spall:
    """Rectangular spall on a flank (seed 002 §2.6): radial centre ``radius`` and width
    ``radial_width``, ``depth``, axial centre ``axial_position`` (from the face start) and
    ``axial_length`` (all m; None axial values = the whole face)."""

    gear: Literal["a", "b"] = "a"
    tooth: int = 0
    radius: float = 0.0
    radial_width: float = 0.0
    depth: float = 1e-4
    axial_position: float | None = None
    axial_length: float | None = None

    def covers(self, r: np.ndarray, z: np.ndarray, face_width: float) -> np.ndarray:
        """True where a contact at radius r and axial position z lies on the spall."""
        zc = face_width / 2 if self.axial_position is None else self.axial_position
        lz = face_width if self.axial_length is None else self.axial_length
        inr = np.abs(np.asarray(r) - self.radius) <= self.radial_width / 2.0
        inz = np.abs(np.asarray(z) - zc) <= lz / 2.0
        return inr & inz
