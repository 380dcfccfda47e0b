"""Opt-in loads and mesh laws of the planetary model (issue 12): gravity, planet-pass ring
force, load-dependent square-wave mesh stiffness. SI units; angles in rad.

All three are off by default and leave the assembled matrices untouched; they act through the
time-tabulated force of the integrator or through the mesh stiffness tables.

- **Gravity** (seed 003 ch. 5 §2.1.2, Figs 5.4-5.6): weight of every body of a stage, expressed
  in the carrier-fixed frame of the Lin & Parker coordinates. The carrier frame turns with the
  carrier, so the weight turns at −Ω_c in that frame (once per carrier revolution).
- **Planet-pass ring force** (seed 003 eqs 4.10-4.14): F_j(t) added to the ring rotation DOF,
  the Hann-windowed ring-planet mesh force of the planet passing the sensor
  (:func:`geardyn.sensors.planet_pass.planet_pass_signal`, centred gate).
- **Load-dependent mesh** (seed 003 §1.2 item 5, Figs 4.14-4.15, figure-only in the thesis):
  the loaded contact ratio grows because the static deflection closes the tip-relief gap of the
  next pair earlier and opens the leaving pair later (law of :func:`loaded_square_mesh`).
"""

from __future__ import annotations

import math

import numpy as np

from geardyn.errors import InputError
from geardyn.models.planetary.model import PlanetaryModel


def gravity_forces(
    model: PlanetaryModel,
    stage: str,
    carrier_angle: np.ndarray,
    g: float = 9.81,
    angle0: float = 0.0,
) -> np.ndarray:
    """Weight of the stage's bodies in solved coordinates, shape (len(carrier_angle), n) (N).

    Fixed frame: X horizontal, Y up, gravity (0, −g). The carrier frame is turned by
    φ = θ_c + ``angle0`` (``angle0``: angle of the carrier x axis above the horizontal when
    θ_c = 0), so a central member of mass m gets F_x = −m g sin φ, F_y = −m g cos φ and planet n
    (radial ζ at φ + ψ_n) F_ζ = −m g sin(φ + ψ_n), F_η = −m g cos(φ + ψ_n). Rotation DOFs get
    none (centres of mass on the axes). In a torsional reduction the forces are projected
    (Tᵀ f): the planets' tangential weights give a carrier torque that cancels for equally
    spaced planets.
    """
    if g < 0 or not math.isfinite(g):
        raise InputError(f"gravity: g must be a finite number ≥ 0 (got {g!r} m/s²)")
    if stage not in model.stages:
        raise InputError(f"gravity: unknown stage '{stage}' (stages: {', '.join(model.stages)})")
    info = model.stages[stage]
    phi = np.asarray(carrier_angle, float) + angle0
    full = np.zeros((phi.size, model.n_full))
    for role, name in info.bodies.items():
        b = model.bodies[name]
        ang = phi
        if role.startswith("planet"):
            ang = phi + info.psi[int(role[6:]) - 1]
        full[:, b.dofs[0]] = -b.mass * g * np.sin(ang)
        full[:, b.dofs[1]] = -b.mass * g * np.cos(ang)
    return full @ model.transform


def loaded_square_mesh(
    k_max: float,
    k_min: float,
    contact_ratio: float,
    force_n: float,
    tip_relief_m: float,
    relief_roll_ratio: float = 0.25,
    reference_force_n: float | None = None,
    stiffness_exponent: float = 0.0,
) -> tuple[float, float, float]:
    """Square-wave mesh parameters (k_max, k_min in N/m, contact ratio c) at mesh force F (N).

    Law (documented choice; seed 003 §1.2 item 5 only states that contact ratio and stiffness
    rise with load):

    - static deflection δ = F / k̄₀ with k̄₀ = k_max(c₀ − 1) + k_min(2 − c₀) (seed 003 eq 1.12);
    - each end of the path of contact carries a tip relief of depth C_a over a roll length
      ρ p_b; the deflection closes the relief gap over the fraction min(δ/C_a, 1) of it, so
      c(F) = min(2, c₀ + 2 ρ min(δ/C_a, 1));
    - optional stiffness growth k(F) = k (F/F_ref)^n (n = ``stiffness_exponent``, F_ref =
      ``reference_force_n`` at which k_max, k_min are given; n = 0 keeps them).
    """
    for name, v in (("k_max", k_max), ("k_min", k_min), ("tip_relief_m", tip_relief_m)):
        if not (math.isfinite(v) and v > 0):
            raise InputError(f"load law: {name} must be a finite number > 0 (got {v!r})")
    if not 1.0 <= contact_ratio <= 2.0:
        raise InputError(f"load law: contact_ratio must be in [1, 2] (got {contact_ratio!r})")
    if not (math.isfinite(force_n) and force_n >= 0):
        raise InputError(f"load law: the mesh force must be finite and ≥ 0 N (got {force_n!r})")
    if not 0 < relief_roll_ratio <= 0.5:
        raise InputError(f"load law: relief_roll_ratio must be in (0, 0.5] (got "
                         f"{relief_roll_ratio!r})")
    k_mean = k_max * (contact_ratio - 1) + k_min * (2 - contact_ratio)
    delta = force_n / k_mean
    c = min(2.0, contact_ratio + 2 * relief_roll_ratio * min(delta / tip_relief_m, 1.0))
    scale = 1.0
    if stiffness_exponent:
        if reference_force_n is None or not reference_force_n > 0:
            raise InputError("load law: stiffness_exponent needs reference_force_n > 0 (N)")
        scale = (max(force_n, 1e-12) / reference_force_n) ** stiffness_exponent
    return k_max * scale, k_min * scale, c


def integrated_angle(t: np.ndarray, ts: np.ndarray, rate: np.ndarray) -> np.ndarray:
    """θ(t) = ∫₀ᵗ rate dt (rad) of a piecewise-linear rate table (ts, rate in rad/s), held
    at its ends; exact trapezoidal integral on the union of both grids."""
    grid = np.unique(np.concatenate([np.asarray(ts, float), np.asarray(t, float), [0.0]]))
    grid = grid[grid >= 0]
    r = np.interp(grid, ts, rate)
    theta = np.concatenate([[0.0], np.cumsum(0.5 * (r[1:] + r[:-1]) * np.diff(grid))])
    return np.interp(t, grid, theta)
