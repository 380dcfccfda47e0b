"""Mesh phasing of planetary gear sets (seed 004 §4.2, Table 4-1 and Table 4-2; seed 003 §1).

Phases are in mesh cycles (fractions of a mesh period). For planet n at angle ψ_n (rad, from
planet 1, counter-clockwise positive): the sun–planet phase is frac(−z_s ψ_n/2π) and the
ring–planet phase frac(z_r ψ_n/2π) (seed 004 Table 4-1; seed 003 notes §2.2 with Parker's sign).
The sun-to-ring relative phase follows seed 004 Table 4-2.
"""

from __future__ import annotations

import math

import numpy as np


def planet_mesh_phases(
    sun_teeth: int, ring_teeth: int, planet_angles: np.ndarray | list[float]
) -> tuple[np.ndarray, np.ndarray]:
    """(sun_phase, ring_phase) of each planet's meshes relative to planet 1, in [0, 1).

    seed 004 Table 4-1: rsn = −z_s ψ_n/2π and rrn = z_r ψ_n/2π, fractional parts.
    """
    psi = np.asarray(planet_angles, dtype=float) - float(np.asarray(planet_angles)[0])
    rs = np.mod(-sun_teeth * psi / (2 * math.pi), 1.0)
    rr = np.mod(ring_teeth * psi / (2 * math.pi), 1.0)
    # exact multiples of 1 come out as 1 − ε; fold them to 0
    rs[np.isclose(rs, 1.0, atol=1e-12)] = 0.0
    rr[np.isclose(rr, 1.0, atol=1e-12)] = 0.0
    return rs, rr


def sun_ring_phase(
    module: float,
    pressure_angle: float,
    planet_base_radius: float,
    ring_start_to_pitch: float,
    base_pitch: float,
    thesis_quirk: bool = True,
) -> float:
    """Sun-to-ring mesh phase rrs (mesh cycles), seed 004 Table 4-2 procedure (notes §2.6).

    P_sP_r = R_pb tan α + R_pb(π − 2α) + R_pb tan α; t_b = m(π/2 + 2 inv α) — the thesis
    evaluated inv α as 1/α[deg] (MATLAB ``inv(20)``), reproduced with ``thesis_quirk``;
    Q_2B_r = P_sP_r − B_rP_r − t_b; B_rQ_3 = p_b − p_b·frac(Q_2B_r/p_b);
    |rrs| = |B_rQ_3 − B_rP_r|/p_b, positive when B_rQ_3 ≤ B_rP_r.
    ``ring_start_to_pitch`` is B_rP_r (m), the ring mesh's start of contact to pitch point.
    """
    a = pressure_angle
    rpb = planet_base_radius
    p_sp_r = rpb * math.tan(a) + rpb * (math.pi - 2 * a) + rpb * math.tan(a)
    inv_a = 1.0 / math.degrees(a) if thesis_quirk else math.tan(a) - a
    t_b = module * (math.pi / 2 + 2 * inv_a)
    q2br = p_sp_r - ring_start_to_pitch - t_b
    frac = q2br / base_pitch - math.floor(q2br / base_pitch)
    brq3 = base_pitch - base_pitch * frac
    mag = abs(brq3 - ring_start_to_pitch) / base_pitch
    return mag if brq3 - ring_start_to_pitch <= 0 else -mag
