"""Seed 002 Table 2 gear stages used by several gear tests (low 42/55 spur, high 31/53 helical)."""

from __future__ import annotations

import math

from geardyn.gears.geometry import GearBlank, Material, mesh_geometry

A20 = math.radians(20.0)
STEEL = Material(202e9, 0.255)


def seed002_low(**kw):
    return mesh_geometry(
        GearBlank(42, tip_radius=0.066, root_radius=0.0585, rim_radius=0.03, material=STEEL),
        GearBlank(55, tip_radius=0.0855, root_radius=0.0768, rim_radius=0.03, material=STEEL),
        0.003,
        A20,
        0.025,
        label="low",
        **kw,
    )


def seed002_high(beta_deg=20.0):
    return mesh_geometry(
        GearBlank(31, tip_radius=0.0525, root_radius=0.045, rim_radius=0.03, material=STEEL),
        GearBlank(53, tip_radius=0.0876, root_radius=0.080, rim_radius=0.03, material=STEEL),
        0.003,
        A20,
        0.025,
        math.radians(beta_deg),
        label="high",
    )
