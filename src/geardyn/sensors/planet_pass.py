"""Planet-pass transfer-path modulation seen by a ring-mounted accelerometer.

Seed 003 eqs 4.10-4.14 (after Inalpolat & Kahraman 2009), implemented as recommended in
``shared/notes/seed003_notes.md`` §5.1 item 10:

* (4.10) Hanning window ``w(θ) = ½(1 − cos(N θ))`` in carrier angle θ (period ``2π/N``, i.e.
  ``T_c/N`` in time); (4.11) shifted by each planet angle ψ_n.
* (4.12) gating: *fixed* — each planet is gated to the ``2π/N`` interval centred on its passage
  at the sensor, ``θ ≡ ψ_n + π/N`` (mod 2π), so every lobe is complete. ``gating="thesis"``
  keeps the printed (4.12) gate ``[(n−1)2π/N, n·2π/N)`` that ignores ψ and cuts the lobes.
* (4.13) force ``F(θ) = Σ_n w_n(θ) U_n(θ) Σ_h A_h cos(h Z_r (θ + s ψ_n) + φ_h)``. Under variable
  speed the carrier angle θ_c(t) replaces ``ω_c t`` (notes §2.5).

Mesh-phase sign ``s`` (``mesh_phase_sign``): the printed (4.13) has ``+Z_r ψ_n`` while the window
is shifted by ``+ψ_n``. A planet that passes the sensor at carrier angle ψ_n sits at ``θ − ψ_n``,
so its ring-mesh phase is ``Z_r(θ − ψ_n)``: ``s = −1`` (default). Only this sign reproduces the
measured dominant components of seed 003 §4.1 (66, 129 and 195 carrier orders at 1498.5 rpm,
325.6/636.4/962.0 Hz); the printed sign puts them at 64/67, 131 and 195 carrier orders.

Coupled into the simulated bench (seed 003 eq 4.14) by the opt-in ``planet_pass`` of a
``[[planetary_dynamics.stages]]`` entry (``geardyn.models.planetary.build``): the force is
added to the ring rotation DOF; the model's planet n sits at θ_c + ψ_n, so it is passed here
with planet angles −ψ_n (planets at θ − ψ'), which makes the mesh term the model's ring-mesh
phase.

Units: angle [rad]; output in the unit of the amplitudes ``A_h`` (force [N] or acceleration).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from geardyn.errors import InputError
from geardyn.signal._checks import array1d, positive_int
from geardyn.signal._checks import planet_angles as planet_angles_checked


def planet_pass_signal(
    carrier_angle: np.ndarray,
    n_planets: int,
    ring_teeth: int,
    amplitudes: Sequence[float] = (1.0,),
    planet_angles: Sequence[float] | None = None,
    phases: Sequence[float] | None = None,
    sensor_angle: float = 0.0,
    mesh_phase_sign: int = -1,
    gating: str = "centred",
) -> np.ndarray:
    """Ring-mounted sensor signal of the planet–ring meshes (seed 003 eqs 4.10-4.13, fixed gate).

    ``carrier_angle`` [rad] relative to the fixed ring (``θ_c(t)``, any speed law);
    ``amplitudes`` ``A_h`` of mesh harmonics ``h = 1, 2, …``; ``planet_angles`` ψ_n [rad]
    (default equally spaced ``2π(n−1)/N``); ``sensor_angle`` [rad] shifts all passages.
    Returns the summed signal ``F(θ_c)`` (same shape as ``carrier_angle``).
    """
    th = array1d("carrier_angle", carrier_angle, 1, "carrier angle")
    n = positive_int("n_planets", n_planets, "number of planets")
    zr = positive_int("ring_teeth", ring_teeth, "ring tooth count")
    amp = array1d("amplitudes", amplitudes, 1, "harmonic amplitudes")
    psi = planet_angles_checked(planet_angles, n)
    ph = np.zeros(amp.size) if phases is None else array1d("phases", phases, amp.size)
    if ph.size != amp.size:
        raise InputError("phases: needs one phase per harmonic amplitude")
    if mesh_phase_sign not in (-1, 1):
        raise InputError(f"mesh_phase_sign: must be -1 or +1, got {mesh_phase_sign!r}")
    windows = planet_pass_windows(th, n, psi, sensor_angle, gating)
    out = np.zeros_like(th)
    for j in range(n):
        mesh = np.zeros_like(th)
        for h, (a, p) in enumerate(zip(amp, ph, strict=True), start=1):
            mesh += a * np.cos(h * zr * (th + mesh_phase_sign * psi[j]) + p)
        out += windows[j] * mesh
    return out


def planet_pass_windows(
    carrier_angle: np.ndarray,
    n_planets: int,
    planet_angles: Sequence[float] | np.ndarray | None = None,
    sensor_angle: float = 0.0,
    gating: str = "centred",
) -> np.ndarray:
    """Transfer-path weights ``w_n(θ_c)`` of each planet for a ring-mounted sensor, shape
    (n_planets, len(carrier_angle)): Hann lobe ``½(1 − cos(N·rel))`` (seed 003 eqs
    4.10-4.11) gated to the ``2π/N`` interval in which planet n is nearest the sensor (4.12,
    ``centred`` gate; ``thesis`` keeps the printed gate). Planet n passes the sensor at carrier
    angle ``sensor_angle + ψ_n + π/N``, where its weight is 1."""
    th = array1d("carrier_angle", carrier_angle, 1, "carrier angle")
    n = positive_int("n_planets", n_planets, "number of planets")
    psi = planet_angles_checked(planet_angles, n)
    if gating not in ("centred", "thesis"):
        raise InputError(f"gating: must be 'centred' or 'thesis', got {gating!r}")
    two_pi = 2.0 * np.pi
    lobe = two_pi / n
    out = np.zeros((n, th.size))
    for j in range(n):
        rel = th - sensor_angle - psi[j]  # planet j reaches the window start at rel = 0
        w = 0.5 * (1.0 - np.cos(n * rel))  # (4.10)-(4.11)
        if gating == "centred":
            gate = np.mod(rel, two_pi) < lobe  # lobe centred on passage ψ_j + π/N
        else:  # printed (4.12): planet j gated to [(j)2π/N, (j+1)2π/N) regardless of ψ
            gate = np.floor(np.mod(th - sensor_angle, two_pi) / lobe) == j
        out[j] = w * gate
    return out


def dominant_carrier_orders(ring_teeth: int, n_planets: int, harmonics: int = 3) -> list[int]:
    """Dominant planet-pass component near each mesh harmonic (seed 003 §4.1 rule).

    For equally spaced planets, only carrier orders that are multiples of ``N`` survive; the
    largest near harmonic ``h`` is the multiple of ``N`` nearest to ``h·Z_r`` (for Z_r = 65,
    N = 3: 66, 129, 195, i.e. +1, −1, 0 carrier orders).
    """
    zr = positive_int("ring_teeth", ring_teeth, "ring tooth count")
    n = positive_int("n_planets", n_planets, "number of planets")
    hmax = positive_int("harmonics", harmonics, "number of harmonics")
    return [int(n * round(h * zr / n)) for h in range(1, hmax + 1)]
