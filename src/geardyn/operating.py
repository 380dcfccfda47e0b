"""Operating conditions: speed and torque profiles, motor curves, fluid coupling, load and
carrier-inertia schedules (SI units: s, rad, rad/s, N·m, kg·m²; rpm only where named).

Sources: seed 004 §6.3-6.7 (notes §2.9: TorM piecewise motor curve, fluid coupling eq 6.6,
bucket-wheel schedule, torqueOUT load), seed 003 eqs 1.17-1.19 (induction-motor torque–slip
curve), seed 003 ch. 4 (run-up, run-down, variable-speed ramps of the inverter).

Profiles are piecewise linear through ``[[t_s, value], …]`` and held outside their span: a run
longer than its profile keeps the last value (the speed control keeps turning at the last
speed), with a :class:`ProfileWarning` naming the profile (:func:`held_profile`).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from geardyn.errors import InputError

RPM = 2 * math.pi / 60.0


# ---- speed / torque profiles ----------------------------------------------------------------


class ProfileWarning(UserWarning):
    """A speed or torque profile does not cover the run: its end values are held."""


def profile_points(points: object, field: str = "profile") -> tuple[np.ndarray, np.ndarray]:
    """``(times s, values)`` of a piecewise-linear profile ``[[t, value], …]``, checked: at
    least one point, finite numbers, strictly increasing times (errors name ``field``)."""
    a = np.asarray(points, dtype=float) if points is not None else np.zeros((0, 2))
    if a.ndim != 2 or a.shape[1] != 2 or a.shape[0] < 1:
        raise InputError(f"{field}: a profile needs at least one [time, value] point "
                         f"(got {points!r})")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{field}: profile points must be finite (got {a.tolist()})")
    ts = a[:, 0]
    if np.any(np.diff(ts) <= 0):
        raise InputError(f"{field}: profile times must increase strictly (got {ts.tolist()})")
    return ts, a[:, 1]


def held_profile(points: object, t_end: float, field: str = "profile", unit: str = "",
                 stacklevel: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """``(times s, values)`` of a profile covering the run ``[0, t_end]``.

    Past its last point the last value is held to ``t_end`` (and before its first point the
    first value from 0); each extension emits a :class:`ProfileWarning` naming ``field``, e.g.
    ``"….profile_rpm ends at 1 s; holding 1500 rpm to t_end 2 s"``; ``stacklevel`` as in
    :func:`warnings.warn` (2: the caller of this function).
    """
    ts, ys = profile_points(points, field)
    u = f" {unit}" if unit else ""
    if ts[0] > 0.0:
        warnings.warn(f"{field} starts at {ts[0]:g} s; holding {ys[0]:g}{u} from t = 0 s",
                      ProfileWarning, stacklevel=stacklevel)
        ts, ys = np.concatenate([[0.0], ts]), np.concatenate([ys[:1], ys])
    if t_end > ts[-1]:
        warnings.warn(f"{field} ends at {ts[-1]:g} s; holding {ys[-1]:g}{u} to t_end {t_end:g} s",
                      ProfileWarning, stacklevel=stacklevel)
        ts, ys = np.concatenate([ts, [t_end]]), np.concatenate([ys, ys[-1:]])
    return ts, ys


def ramp_profile(t: np.ndarray, points: list[tuple[float, float]], field: str = "profile"
                 ) -> np.ndarray:
    """Piecewise-linear profile through (time s, value) points, held outside."""
    ts, ys = profile_points(points, field)
    return np.interp(t, ts, ys)


def run_up(t: np.ndarray, w0: float, w1: float, t0: float, t1: float) -> np.ndarray:
    """Linear run-up (or run-down when w1 < w0) from w0 at t0 to w1 at t1 (rad/s)."""
    return ramp_profile(t, [(t0, w0), (t1, w1)])


def integrate_angle(t: np.ndarray, w: np.ndarray, theta0: float = 0.0) -> np.ndarray:
    """θ(t) = θ0 + ∫ω dt (trapezoidal), used as the reference angle of a speed control."""
    out = np.empty_like(np.asarray(w, float))
    out[0] = theta0
    out[1:] = theta0 + np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t))
    return out


def reference_angle_table(ts: np.ndarray, w: np.ndarray, tol_rad: float = 1e-8,
                          max_per_segment: int = 100_000) -> tuple[np.ndarray, np.ndarray]:
    """``(t s, θ rad)`` table of θ(t) = ∫ω dt for the piecewise-linear speed ω (rad/s) through
    ``(ts, w)``, with θ(0) = 0: the reference angle of a speed control.

    Constant-speed segments need only their ends (θ is linear there); a ramp of n sub-steps
    has the linear-interpolation error |Δω|·Δt/(8n²), so n is chosen to keep it below
    ``tol_rad`` (at most ``max_per_segment``). The trapezoidal rule is exact on this grid.
    """
    pieces = [np.asarray(ts[:1], float)]
    for a, b, wa, wb in zip(ts[:-1], ts[1:], w[:-1], w[1:], strict=True):
        err = abs(wb - wa) * (b - a) / (8.0 * tol_rad)
        n = 1 if err <= 1.0 else int(min(max_per_segment, math.ceil(math.sqrt(err))))
        pieces.append(np.linspace(a, b, n + 1)[1:])
    tt = np.concatenate(pieces)
    th = integrate_angle(tt, np.interp(tt, ts, w))
    return tt, th - np.interp(0.0, tt, th)


# ---- motors -----------------------------------------------------------------------------


@dataclass(frozen=True)
class PiecewiseMotor:
    """Seed 004 §6.3 (TorM) induction motor: linear from start-up torque to the maximum at the
    breakdown speed, then linear to zero at synchronous speed (notes §2.9).

    rated_power W, rated_speed rpm, frequency Hz, poles, multipliers of the full-load torque.
    """

    rated_power: float = 450e3
    rated_speed_rpm: float = 950.0
    frequency: float = 50.0
    poles: int = 6
    efficiency: float = 0.96
    startup_factor: float = 2.3
    max_factor: float = 2.6

    @property
    def sync_rpm(self) -> float:
        """n = 120 f / p (seed 004 eq 6.1)."""
        return 120.0 * self.frequency / self.poles

    @property
    def full_load_torque(self) -> float:
        """T_fl = P η / ω_rated (seed 004 eq 6.2), N·m."""
        return self.rated_power * self.efficiency / (self.rated_speed_rpm * RPM)

    @property
    def breakdown_rpm(self) -> float:
        """n_bd = n_sync − T_max (n_sync − n_op)/T_fl (notes §2.9)."""
        return self.sync_rpm - self.max_factor * (self.sync_rpm - self.rated_speed_rpm)

    def torque(self, speed_rpm: np.ndarray | float) -> np.ndarray:
        """Motor torque (N·m) at speed (rpm), seed 004 TorM."""
        n = np.asarray(speed_rpm, float)
        tfl = self.full_load_torque
        tsu, tmax = self.startup_factor * tfl, self.max_factor * tfl
        nbd, ns = self.breakdown_rpm, self.sync_rpm
        low = (tmax - tsu) / nbd * n + tsu
        high = tfl / (ns - self.rated_speed_rpm) * (ns - n)
        return np.where((n >= 0) & (n <= nbd), low, np.where((n > nbd) & (n <= ns), high, 0.0))

    def table(self, n_points: int = 64) -> tuple[np.ndarray, np.ndarray]:
        """(ω rad/s, T N·m) samples for the integrator, incl. the breakdown corner."""
        n = np.unique(np.concatenate([np.linspace(0, self.sync_rpm * 1.2, n_points),
                                      [self.breakdown_rpm, self.sync_rpm]]))
        return n * RPM, self.torque(n)


@dataclass(frozen=True)
class KlossMotor:
    """Seed 003 eq 1.18: C_m = T_b / (1 + (s_b − s)² (a/s − b s²)), slip s = 1 − N/N_s (1.19).

    ``a`` and ``b`` are motor constants (not given in seed 003); T_b breakdown torque N·m,
    s_b breakdown slip, N_s synchronous speed rpm.
    """

    breakdown_torque: float
    breakdown_slip: float
    a: float
    b: float
    sync_rpm: float = 1500.0

    def torque(self, speed_rpm: np.ndarray | float) -> np.ndarray:
        s = 1.0 - np.asarray(speed_rpm, float) / self.sync_rpm
        s = np.where(np.abs(s) < 1e-9, 1e-9, s)
        return self.breakdown_torque / (
            1.0 + (self.breakdown_slip - s) ** 2 * (self.a / s - self.b * s**2)
        )

    def table(self, n_points: int = 128) -> tuple[np.ndarray, np.ndarray]:
        n = np.linspace(0.0, self.sync_rpm * 0.9999, n_points)
        return n * RPM, self.torque(n)


def fluid_coupling_torque(q_cc: float, w_motor: float, w_out: float) -> float:
    """Seed 004 eq 6.5-6.6: T = q_cc ω_m (ω_m − ω_out) (ω in rad/s, see notes §2.9 units)."""
    return q_cc * w_motor * (w_motor - w_out)


def coupling_slip(q_cc: float, torque: float, w_motor: float) -> float:
    """Slip S = T / (q_cc ω_m²) of the fluid coupling (seed 004 eq 6.5)."""
    return torque / (q_cc * w_motor**2)


# ---- seed 004 bucket-wheel schedule -------------------------------------------------------


@dataclass(frozen=True)
class BucketWheelSchedule:
    """Seed 004 §6.7 loading schedule in carrier angle θ_c (rad) (notes §2.9, ipdata 41-50).

    Phases: empty until π; linear fill to the full ore factor over 5/12 rev; periodic per-bucket
    ore drop (−``drop`` over a quarter bucket period, linear recovery) for 1.1 rev; linear
    unload over 5/12 rev; empty. Overload ×``overload`` between 0.5 and 0.7 rev after full.
    """

    olcc: float = 3.1
    drop: float = 0.8
    n_buckets: int = 12
    overload: float = 10.0

    def points(self) -> dict[str, float]:
        p44 = math.pi
        p45 = p44 + 2 * math.pi * 5 / 12
        p46 = p45 + 2 * math.pi * 1.1
        p47 = p46 + 2 * math.pi * 5 / 12
        p48 = 2 * math.pi / self.n_buckets
        return {"P44": p44, "P45": p45, "P46": p46, "P47": p47, "P48": p48,
                "P49": p45 + 2 * math.pi * 0.5, "P50": p45 + 2 * math.pi * 0.7, "P94": p48 / 4}

    def ore(self, theta: np.ndarray | float) -> np.ndarray:
        """Ore load in bucket-loads (0 … Olcc) at carrier angle θ (rad)."""
        d = np.asarray(theta, float)
        p = self.points()
        ph = np.mod(d - p["P45"], p["P48"])
        periodic = np.where(
            ph <= p["P94"],
            self.olcc - self.drop * ph / p["P94"],
            self.olcc - self.drop + self.drop * (ph - p["P94"]) / (p["P48"] - p["P94"]),
        )
        out = np.zeros_like(d)
        out = np.where((d > p["P44"]) & (d <= p["P45"]),
                       self.olcc * (d - p["P44"]) / (p["P45"] - p["P44"]), out)
        out = np.where((d > p["P45"]) & (d <= p["P46"]), periodic, out)
        out = np.where((d > p["P46"]) & (d <= p["P47"]),
                       periodic * (p["P47"] - d) / (p["P47"] - p["P46"]), out)
        return out

    def load_factor(self, theta: np.ndarray | float, control_ratio: float = 5.0) -> np.ndarray:
        """Multiplier of the base load torque: 1 + (k² − 1)·ore/Olcc, ×overload in P49-P50."""
        d = np.asarray(theta, float)
        p = self.points()
        f = 1.0 + (control_ratio**2 - 1.0) * self.ore(d) / self.olcc
        return np.where((d >= p["P49"]) & (d <= p["P50"]), f * self.overload, f)


def hollow_cylinder(width: float, density: float, d_out: float, d_in: float
                    ) -> tuple[float, float]:
    """(mass kg, polar inertia kg·m²) of a hollow cylinder (seed 004 eqs 6.8-6.9)."""
    m = math.pi * width * density * ((d_out / 2) ** 2 - (d_in / 2) ** 2)
    j = 0.5 * math.pi * width * density * ((d_out / 2) ** 4 - (d_in / 2) ** 4)
    return m, j
