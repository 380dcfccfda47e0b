"""Time-synchronous averaging (TSA) and the derived regular / residual / difference signals.

* TSA (seed 003 eq 1.25): ``TSA(θ) = (1/N_b) Σ_n x(θ + n·2π)`` over ``N_b`` whole revolutions of
  an angle-domain signal; non-synchronous content (noise, other shafts) falls as ``1/√N_b``.
* Regular signal: the TSA's shaft-order harmonics at the mesh orders (``k·Z``) only.
* Residual signal: TSA minus shaft orders 1…``shaft_harmonics`` and the mesh harmonics.
* Difference signal: residual minus the first-order sidebands ``k·Z ± 1`` of every mesh
  harmonic (Zakrajsek, Townsend & Decker 1993, NASA TM-106032 definitions).
* ``teeth`` may be one tooth count or several (every wheel on the averaged shaft): the mesh
  harmonics and sidebands of **every** wheel are then removed, so that the difference signal of
  a shaft carrying a 19- and a 71-tooth wheel keeps neither mesh (otherwise the other wheel's
  mesh, a sine, pins FM4 near 1.5 and hides a fault).
* Planetary TSA (McFadden 1991 / McFadden & Howard "window function" technique): per-planet
  windows, centred on each planet's passage at the sensor, are averaged in the planet's tooth
  frame, separating the vibration of one planet (or of the sun) from the others.

All signals are in angle (samples per revolution of the averaged gear/shaft); units of ``x``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from geardyn.errors import InputError
from geardyn.signal._checks import array1d, positive_int
from geardyn.signal._checks import planet_angles as planet_angles_checked


def tsa(x: np.ndarray, samples_per_rev: int) -> np.ndarray:
    """Synchronous average of an angle-domain signal over its whole revolutions
    (seed 003 eq 1.25). Returns one revolution (``samples_per_rev`` samples)."""
    a = array1d("x", x, 1)
    spr = positive_int("samples_per_rev", samples_per_rev, "samples per revolution", minimum=2)
    nrev = a.size // spr
    if nrev < 1:
        raise InputError(f"x: needs at least one revolution ({spr} samples), got {a.size}")
    return a[: nrev * spr].reshape(nrev, spr).mean(axis=0)


def tsa_from_tacho(
    x: np.ndarray, fs: float, tacho_times: np.ndarray, samples_per_rev: int = 1024
) -> np.ndarray:
    """TSA of a time signal using once-per-rev tacho times [s]: each revolution is resampled to
    ``samples_per_rev`` points (linear phase within the revolution) and averaged."""
    from geardyn.signal.resample import resample_to_angle

    sig = resample_to_angle(
        x, fs, pulse_times=tacho_times, pulses_per_rev=1, samples_per_rev=samples_per_rev
    )
    start = (-int(round(sig.angle0 / (2 * np.pi) * samples_per_rev))) % samples_per_rev
    return tsa(sig.x[start:], samples_per_rev)


def _keep_orders(a: np.ndarray, orders: set[int], keep: bool) -> np.ndarray:
    spec = np.fft.rfft(a)
    mask = np.zeros(spec.size, dtype=bool)
    for o in orders:
        if 0 <= o < spec.size:
            mask[o] = True
    out = spec * mask if keep else spec * ~mask
    return np.fft.irfft(out, a.size)


def keep_orders(a: np.ndarray, orders: Sequence[int]) -> np.ndarray:
    """The part of a one-revolution signal at the integer ``orders`` only (FFT mask)."""
    return _keep_orders(array1d("a", a, 4), {int(o) for o in orders}, keep=True)


def tooth_counts(teeth: int | Sequence[int]) -> tuple[int, ...]:
    """Tooth count(s) of the wheels on one averaged shaft as a tuple of ints ≥ 1 (``teeth`` may
    be one int or a sequence; duplicates are kept once, order preserved)."""
    if isinstance(teeth, (int, np.integer)):
        return (positive_int("teeth", teeth, "tooth count"),)
    try:
        items = list(teeth)
    except TypeError:
        raise InputError(
            f"teeth: must be a tooth count or a sequence of them, got {teeth!r}"
        ) from None
    if not items:
        raise InputError("teeth: needs at least one tooth count, got an empty sequence")
    return tuple(dict.fromkeys(positive_int("teeth", z, "tooth count") for z in items))


def _mesh_orders(n: int, teeth: int | Sequence[int], mesh_harmonics: int | None) -> list[int]:
    """Orders ``k·Z`` (k = 1…``mesh_harmonics`` or up to Nyquist) of every wheel, sorted."""
    nyq = n // 2
    out: set[int] = set()
    for z in tooth_counts(teeth):
        kmax = nyq // z if mesh_harmonics is None else mesh_harmonics
        out.update(k * z for k in range(1, kmax + 1) if k * z <= nyq)
    return sorted(out)


def regular_signal(
    tsa_signal: np.ndarray, teeth: int | Sequence[int], mesh_harmonics: int | None = None
) -> np.ndarray:
    """Mesh-harmonic content of a one-revolution TSA (orders ``k·Z`` of every wheel in
    ``teeth``; Zakrajsek, Townsend & Decker 1993)."""
    a = array1d("tsa_signal", tsa_signal, 4)
    return _keep_orders(a, set(_mesh_orders(a.size, teeth, mesh_harmonics)), keep=True)


def residual_signal(
    tsa_signal: np.ndarray,
    teeth: int | Sequence[int],
    mesh_harmonics: int | None = None,
    shaft_harmonics: int = 1,
) -> np.ndarray:
    """TSA without the mean, shaft orders ``1..shaft_harmonics`` and the mesh harmonics of every
    wheel in ``teeth`` (Zakrajsek, Townsend & Decker 1993)."""
    a = array1d("tsa_signal", tsa_signal, 4)
    remove = {0, *range(1, shaft_harmonics + 1), *_mesh_orders(a.size, teeth, mesh_harmonics)}
    return _keep_orders(a, remove, keep=False)


def difference_signal(
    tsa_signal: np.ndarray,
    teeth: int | Sequence[int],
    mesh_harmonics: int | None = None,
    shaft_harmonics: int = 1,
    sidebands: int = 1,
) -> np.ndarray:
    """Residual signal without the first ``sidebands`` sideband orders ``k·Z ± j`` of every mesh
    harmonic of every wheel in ``teeth`` (Zakrajsek, Townsend & Decker 1993)."""
    a = array1d("tsa_signal", tsa_signal, 4)
    mesh = _mesh_orders(a.size, teeth, mesh_harmonics)
    remove = {0, *range(1, shaft_harmonics + 1), *mesh}
    for m in mesh:
        for j in range(1, sidebands + 1):
            remove |= {m - j, m + j}
    return _keep_orders(a, remove, keep=False)


def planetary_tsa(
    x: np.ndarray,
    samples_per_carrier_rev: int,
    ring_teeth: int,
    gear_teeth: int,
    n_planets: int,
    planet: int = 0,
    planet_angles: np.ndarray | None = None,
    sensor_angle: float = 0.0,
    window_teeth: int = 2,
    detrend: int | None = None,
) -> np.ndarray:
    """Planet-separated TSA (McFadden's window technique) of a ring-sensor signal sampled at
    ``samples_per_carrier_rev`` per carrier revolution (ring fixed).

    On every carrier revolution, planet ``planet`` passes the sensor at carrier angle
    ``sensor_angle + ψ_planet`` (``sensor_angle``: carrier angle [rad] at which planet 0 is
    closest to the sensor; for :func:`geardyn.sensors.planet_pass_signal` that is its
    ``sensor_angle + π/N``); a Hann window spanning ``window_teeth`` ring-mesh
    periods (``2π/Z_r`` carrier rad each) is cut around that instant and placed, in the frame of
    the averaged gear (``gear_teeth`` teeth: the planet's ``Z_p`` or the sun's ``Z_s``), at the
    mesh count reached, modulo one gear revolution. Averaging the windowed pieces (weighted by
    the summed window) gives one revolution of that gear with ``gear_teeth × samples per
    ring-mesh period`` samples. ``samples_per_carrier_rev`` must be a multiple of ``ring_teeth``.
    Revolutions of the gear that are never visited (few carrier revolutions) raise an error.
    ``detrend``: polynomial degree (0: mean, 2: mean, slope and curvature) removed from each
    piece by window-weighted least squares before averaging, so that the level changes between
    passes and the planet-pass lobe of the transfer path (seed 003 eq 4.10) do not leave steps —
    low orders that dominate the difference signal when few pieces cover each tooth.
    None (default): pieces as they are.
    """
    a = array1d("x", x, 4)
    spc = positive_int("samples_per_carrier_rev", samples_per_carrier_rev, minimum=4)
    zr = positive_int("ring_teeth", ring_teeth, "ring tooth count")
    zg = positive_int("gear_teeth", gear_teeth, "tooth count of the averaged gear")
    n = positive_int("n_planets", n_planets, "number of planets")
    wt = positive_int("window_teeth", window_teeth, "window length in tooth periods")
    if spc % zr:
        raise InputError(
            f"samples_per_carrier_rev: must be a multiple of ring_teeth={zr}, got {spc}"
        )
    if not 0 <= planet < n:
        raise InputError(f"planet: must be in 0..{n - 1}, got {planet}")
    psi = planet_angles_checked(planet_angles, n)
    spt = spc // zr  # samples per ring-mesh period
    m = zg * spt  # samples per averaged-gear revolution (mesh-count frame)
    half = wt * spt // 2
    win = np.hanning(2 * half + 3)[1:-1]  # no zero end points
    acc = np.zeros(m)
    wsum = np.zeros(m)
    nrev = a.size // spc
    centre0 = (sensor_angle + psi[planet]) / (2 * np.pi) * spc
    for k in range(-1, nrev + 1):
        c = int(round(centre0 + k * spc))
        lo, hi = c - half, c + half + 1
        if lo < 0 or hi > a.size:
            continue
        # The planet meshes with the ring once per ring-mesh period: the mesh count (in
        # samples) reached at sample c is c itself; its position in the gear frame is c mod m.
        idx = (np.arange(lo, hi)) % m
        piece = a[lo:hi]
        if detrend is not None:
            u = np.linspace(-1.0, 1.0, piece.size)
            coef = np.polyfit(u, piece, int(detrend), w=np.sqrt(win))
            piece = piece - np.polyval(coef, u)
        np.add.at(acc, idx, piece * win)
        np.add.at(wsum, idx, win)
    if np.any(wsum <= 1e-9):
        raise InputError(
            "x: too few carrier revolutions to cover every tooth of the averaged gear; "
            "record more revolutions or widen window_teeth"
        )
    return acc / wsum
