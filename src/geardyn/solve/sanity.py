"""Numerical sanity of a time integration: the time step before the run, the energy balance
after it (issue 13).

Time step (before the run). With ``T_min`` the shortest natural period of the mean-stiffness
model and ``T_mesh`` the shortest mesh period (highest mesh frequency expected in the run):

* refused (:class:`~geardyn.errors.InputError`) when ``dt`` exceeds ``T_mesh / 2`` (the mesh
  stiffness variation is sampled less than twice per cycle: it aliases), or ``T_min /
  MIN_STEPS_PER_PERIOD_REFUSE`` (the highest mode is stepped over several times per step: the
  Newmark average-acceleration (trapezoidal) rule, whose discrete frequency obeys
  ω̃Δt = 2 atan(ωΔt/2), shifts it by more than 70 %), or the stability limit ``2/ω_max`` of an
  explicit scheme;
* warned (coarse) when fewer than :data:`STEPS_PER_PERIOD_WARN` steps fall in ``T_min`` (highest
  mode off by more than 35 %) or fewer than :data:`STEPS_PER_MESH_WARN` in ``T_mesh``.

Energy balance (after the run): the work of the applied forces W_app, the dissipated work
W_diss and the parametric work W_par of the time-varying mesh stiffness and errors must equal
the change of the stored (kinetic + potential) energy,
``W_app − W_diss + W_par = ΔT + ΔV``, within :data:`ENERGY_TOLERANCE` of the energy scale
(gross work exchanged with the outside + dissipated + |parametric| + |ΔT| + |ΔV|). The works
are integrated by the trapezoidal rule, independently of the integrator's own update, so the
residual measures how well the step resolves the motion: it falls as the step shrinks
(first or second order) and grows when the step is too coarse.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence

import numpy as np

from geardyn.errors import InputError

#: Refuse a step with fewer than this many steps per shortest natural period (ωΔt > 4π).
MIN_STEPS_PER_PERIOD_REFUSE = 0.5
#: Warn below this many steps per shortest natural period (ωΔt > π).
STEPS_PER_PERIOD_WARN = 2.0
#: Refuse below this many steps per mesh period (Nyquist).
MIN_STEPS_PER_MESH_REFUSE = 2.0
#: Warn below this many steps per mesh period.
STEPS_PER_MESH_WARN = 20.0
#: Largest energy-balance residual, as a fraction of the energy scale, of a run kept ``ok``.
ENERGY_TOLERANCE = 0.05


class TimeStepWarning(UserWarning):
    """The time step is coarse for the model's periods (the run goes on)."""


def check_time_step(dt: float, field: str, shortest_period_s: float | None = None,
                    mesh_period_s: float | None = None, stable_limit_s: float | None = None
                    ) -> list[str]:
    """Refuse (InputError) or warn (:class:`TimeStepWarning`) about time step ``dt`` [s] of
    config field ``field`` against the periods of the model (module docstring); returns the
    warnings issued."""
    refuse: list[str] = []
    warn: list[str] = []
    if stable_limit_s is not None and dt > stable_limit_s:
        refuse.append(f"above the stability limit 2/ω_max = {stable_limit_s:.4g} s of the "
                      "explicit scheme (the run would diverge)")
    if shortest_period_s is not None and math.isfinite(shortest_period_s):
        steps = shortest_period_s / dt
        if steps < MIN_STEPS_PER_PERIOD_REFUSE:
            refuse.append(
                f"the shortest natural period is {shortest_period_s:.4g} s "
                f"({1 / shortest_period_s:.4g} Hz): {steps:.3g} steps per period, fewer than "
                f"{MIN_STEPS_PER_PERIOD_REFUSE:g} (limit dt ≤ "
                f"{shortest_period_s / MIN_STEPS_PER_PERIOD_REFUSE:.4g} s)")
        elif steps < STEPS_PER_PERIOD_WARN:
            lim = shortest_period_s / STEPS_PER_PERIOD_WARN
            warn.append(f"{steps:.3g} steps per shortest natural period "
                        f"({shortest_period_s:.4g} s, {1 / shortest_period_s:.4g} Hz); the "
                        f"highest modes are resolved with dt ≤ {lim:.4g} s")
    if mesh_period_s is not None and math.isfinite(mesh_period_s) and mesh_period_s > 0:
        steps = mesh_period_s / dt
        if steps < MIN_STEPS_PER_MESH_REFUSE:
            refuse.append(
                f"the shortest mesh period is {mesh_period_s:.4g} s ({1 / mesh_period_s:.4g} Hz):"
                f" {steps:.3g} steps per mesh cycle, fewer than {MIN_STEPS_PER_MESH_REFUSE:g} "
                f"(the mesh stiffness would alias; limit dt ≤ "
                f"{mesh_period_s / MIN_STEPS_PER_MESH_REFUSE:.4g} s)")
        elif steps < STEPS_PER_MESH_WARN:
            warn.append(f"{steps:.3g} steps per mesh cycle ({mesh_period_s:.4g} s); "
                        f"dt ≤ {mesh_period_s / STEPS_PER_MESH_WARN:.4g} s gives "
                        f"{STEPS_PER_MESH_WARN:g}")
    if refuse:
        raise InputError(f"{field}: the time step {dt:g} s is too large: " + "; ".join(refuse))
    for w in warn:
        warnings.warn(f"{field}: coarse time step {dt:g} s: {w}", TimeStepWarning, stacklevel=2)
    return warn


def energy_residual(energy: dict[str, float]) -> tuple[float, float]:
    """(residual, scale) [J] of the balance W_app − W_diss + W_par − ΔT − ΔV (module
    docstring); keys as :attr:`geardyn.solve.integrate.IntegrationResult.energy`."""
    d_kin = energy["kinetic_end_J"] - energy["kinetic_start_J"]
    d_pot = energy["potential_end_J"] - energy["potential_start_J"]
    res = (energy["applied_J"] - energy["dissipated_J"] + energy.get("parametric_J", 0.0)
           - d_kin - d_pot)
    scale = (energy.get("gross_applied_J", abs(energy["applied_J"])) + energy["dissipated_J"]
             + abs(energy.get("parametric_J", 0.0)) + abs(d_kin) + abs(d_pot))
    return res, scale


def check_energy(energy: dict[str, float], tolerance: float = ENERGY_TOLERANCE) -> str:
    """'' when the energy balance closes within ``tolerance`` of its scale, else the problem."""
    if not energy:
        return ""
    res, scale = energy_residual(energy)
    if not math.isfinite(res):
        return "energy balance: non-finite energies"
    if scale <= 0.0 or abs(res) <= tolerance * scale:
        return ""
    return (f"energy balance off by {res:.4g} J, {abs(res) / scale:.1%} of the energy exchanged "
            f"({scale:.4g} J; tolerance {tolerance:.0%}): the time step does not resolve the "
            "motion")


def mean_stiffness(sys) -> np.ndarray:  # noqa: ANN001 - LinearSystem
    """K₀ + Σ k̄ a aᵀ (mean of each variable spring's table) + the speed controls' stiffness."""
    from geardyn.solve.integrate import SPEED_CONTROL

    k = np.array(sys.K, float, copy=True)
    s = sys.springs
    for e in range(s.a.shape[0]):
        k += float(np.mean(s.ktab[e, : s.klen[e]])) * np.outer(s.a[e], s.a[e])
    d = sys.drives
    for i in range(len(d.kind)):
        if d.kind[i] == SPEED_CONTROL:
            k[d.a[i], d.a[i]] += d.p0[i] * d.ha[i] ** 2
    return k


def shortest_period(sys) -> float | None:  # noqa: ANN001 - LinearSystem
    """Shortest natural period 2π/ω_max [s] of the undamped mean-stiffness model (eigenvalues
    of (K̄, M)); None when the model has no elastic mode."""
    import scipy.linalg as sla

    w2 = sla.eigh(mean_stiffness(sys), np.asarray(sys.M, float), eigvals_only=True)
    w2max = float(np.max(w2)) if w2.size else 0.0
    if not (math.isfinite(w2max) and w2max > 0.0):
        return None
    return 2.0 * math.pi / math.sqrt(w2max)


def mesh_period(sys, speeds: Sequence[np.ndarray]) -> float | None:  # noqa: ANN001
    """Shortest mesh period [s] over the velocity states ``speeds``: a variable spring's mesh
    coordinate X = bᵀq counts mesh cycles, so its mesh frequency is |bᵀv| [Hz]."""
    b = sys.springs.b
    if b.shape[0] == 0 or not len(speeds):
        return None
    f = float(np.max(np.abs(np.asarray(speeds, float) @ b.T)))
    return 1.0 / f if f > 0.0 and math.isfinite(f) else None
