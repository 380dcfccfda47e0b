"""Independent computations shared by validation tests (closed forms, no model eigen-solver)."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from geardyn.config import load_config
from geardyn.config.gears import pair_model
from geardyn.models.transmission.assembly import build_model, connecting_forces, static_equilibrium


def rigid_axial_mode_hz(config: Path, shaft: str = "output") -> float:
    """Axial rigid-body mode (Hz) of ``shaft`` on its bearings: f = √(k_z/m)/2π.

    m in closed form: the hollow shaft ρ π (D² − d²)/4 · L plus each wheel on it as a solid disc
    between its bore and pitch radius, ρ π (r_p² − r_bore²) b (the model's wheel definition);
    k_z by a central difference of the connecting (bearing + mesh) forces on the shaft's axial
    DOFs at the static state. The shaft's axial elastic stiffness (E A / L ~ 10⁹ N/m) is taken as
    rigid, so this checks the assembled mass and the eigen-solution of the linearised line.
    """
    cfg = load_config(config)
    t = cfg.transmission
    sh = next(s for s in t.shafts if s.name == shaft)
    mass = sh.density_kg_m3 * math.pi / 4 * (sh.outer_diameter_m**2 - sh.inner_diameter_m**2) * (
        sh.length_m
    )
    for w in t.wheels:
        if w.at.shaft != shaft:
            continue
        g = pair_model(cfg, w.pair).geometry
        i = 0 if w.gear == "a" else 1
        blank = (g.a, g.b)[i]
        rp = (g.a.teeth, g.b.teeth)[i] * g.normal_module / math.cos(g.helix_angle) / 2
        r_in = blank.rim_radius or 0.0
        mass += blank.material.density * math.pi * (rp**2 - r_in**2) * g.face_width
    model = build_model(cfg)
    q0 = static_equilibrium(model, model.load_torque)
    dofs = np.array([6 * n + 2 for n in model.shaft_nodes[shaft]])
    h = 1e-8
    v = np.zeros(model.ndof)
    qp, qm = q0.copy(), q0.copy()
    qp[dofs] += h
    qm[dofs] -= h
    k = -(connecting_forces(model, qp, v)[dofs].sum() - connecting_forces(model, qm, v)[dofs].sum())
    k /= 2 * h
    return math.sqrt(k / mass) / (2 * math.pi)


def printed_mode_hz(output: str, mode: int) -> float:
    """Frequency (Hz) of row ``mode`` of the CLI's natural-frequency table."""
    for line in output.splitlines():
        m = re.match(r"\s*[│|]\s*(\d+)\s*[│|]\s*([\d.]+)\s*[│|]", line)
        if m and int(m.group(1)) == mode:
            return float(m.group(2))
    raise AssertionError(f"mode {mode} not in the output")
