"""High-level simulation of the FE transmission: static preload, linearised modal analysis,
modal damping, speed-law run, results as an xarray Dataset (SI units)."""

from __future__ import annotations

import math
import time as _time
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np
import xarray as xr
from numba import njit

from geardyn.elements.beam import ShaftSection, timoshenko_element
from geardyn.errors import ConfigError, GeardynError, InputError
from geardyn.models.transmission.assembly import (
    TransmissionModel,
    build_model,
    connecting_forces,
    kernel_dofs,
    modal_analysis,
    modal_damping_matrix,
    perturbed_forces,
    static_equilibrium,
)
from geardyn.results import RAD_S_TO_RPM, finish, shaft_variables
from geardyn.solve import explicit  # module, not names: geardyn.solve.explicit imports .kernels
from geardyn.solve.control import RunControl
from geardyn.solve.sanity import check_energy, check_time_step


class SimulationDivergedError(GeardynError):
    """The time integration blew up; ``result`` holds what was computed up to then."""

    def __init__(self, msg: str, result: xr.Dataset) -> None:
        super().__init__(msg)
        self.result = result

    def __reduce__(self) -> tuple:
        """Pickled with its partial result (raised in a worker process, it reaches the caller
        whole)."""
        return (type(self), (str(self), self.result))


@dataclass
class Prepared:
    """Model ready to integrate: static state, linearised stiffness, damping, time step."""

    model: TransmissionModel
    q0: np.ndarray
    K_lin: np.ndarray
    C: np.ndarray
    frequencies_hz: np.ndarray
    dt_stable: float
    speed_ratio: dict[str, float] = field(default_factory=dict)


def with_mass(model: TransmissionModel, t) -> TransmissionModel:  # noqa: ANN001
    """``model`` with the shaft-element mass of ``t.mass`` (TransmissionConfig): for "lumped",
    the consistent element masses are replaced by the HRZ diagonal ones
    (:func:`geardyn.elements.beam.timoshenko_element`); wheels are diagonal already, so M
    becomes diagonal. A model whose M is diagonal already is returned as is."""
    if getattr(t, "mass", "consistent") == "consistent":
        return model
    M = model.M
    if np.count_nonzero(M - np.diag(np.diag(M))) == 0:
        return model
    d = np.diag(M).copy()
    for s in t.shafts:
        sec = ShaftSection(s.outer_diameter_m, s.inner_diameter_m, s.youngs_modulus_pa,
                           s.poisson_ratio, s.density_kg_m3)
        _, mc = timoshenko_element(s.length_m / s.elements, sec)
        _, ml = timoshenko_element(s.length_m / s.elements, sec, "lumped")
        ids = model.shaft_nodes[s.name]
        for e in range(s.elements):
            a = 6 * ids[e]
            d[a : a + 12] += np.diag(ml) - np.diag(mc)
    M = np.diag(d)
    for disc in getattr(t, "discs", []):  # an offset disc keeps its x–θy, y–θx coupling
        if disc.offset_m != 0.0:
            m = disc.properties()[0]
            a = 6 * model.node_of(disc.at.shaft, disc.at.node)
            M[a, a + 4] += m * disc.offset_m
            M[a + 4, a] += m * disc.offset_m
            M[a + 1, a + 3] -= m * disc.offset_m
            M[a + 3, a + 1] -= m * disc.offset_m
    return replace(model, M=M)


def connecting_jacobian(model: TransmissionModel, q: np.ndarray, h: float = 1e-9) -> np.ndarray:
    """−∂F_connecting/∂q by finite differences (tangent stiffness of bearings and meshes)."""
    n = model.ndof
    v = np.zeros(n)
    args = (model.bearings.args(), model.meshes.args())
    f0 = connecting_forces(model, q, v, args)
    # the columns of the DOFs the forces read; the others are −(f0 − f0)/h = −0.0 exactly
    cols = kernel_dofs(model)
    J = np.full((n, n), -0.0)
    J[:, cols] = -(perturbed_forces(model, q, v, cols, h, args) - f0[:, None]) / h
    return 0.5 * (J + J.T)


def speed_ratios(model: TransmissionModel, reference_shaft: str) -> dict[str, float]:
    """|ω_shaft / ω_reference| from the tooth numbers of the meshes."""
    mh = model.meshes
    node_shaft = {n: s for s, ids in model.shaft_nodes.items() for n in ids}
    ratio = {reference_shaft: 1.0}
    for _ in range(len(mh.names) + 1):
        for i, g in enumerate(mh.geometry):
            sa, sb = node_shaft[int(mh.na[i])], node_shaft[int(mh.nb[i])]
            za, zb = g.a.teeth, g.b.teeth
            if sa in ratio and sb not in ratio:
                ratio[sb] = ratio[sa] * za / zb
            elif sb in ratio and sa not in ratio:
                ratio[sa] = ratio[sb] * zb / za
    return ratio


def prepare(model: TransmissionModel, reference_shaft: str | None = None) -> Prepared:
    """Static equilibrium under the load torque, tangent stiffness, modes, damping, step
    (one BLAS thread: the same bits in any process, see :mod:`geardyn.solve.determinism`)."""
    from geardyn.solve.determinism import single_thread_blas

    with single_thread_blas():
        q0 = static_equilibrium(model, model.load_torque)
        K_lin = model.K + connecting_jacobian(model, q0)
        K_sym = K_lin if model.C_lin is None else 0.5 * (K_lin + K_lin.T)
        f, phi = modal_analysis(model.M, K_sym)
        C = modal_damping_matrix(model.M, K_sym, model.modal_damping)
        dt = explicit.stable_time_step(model.M, K_sym)
        if model.C_lin is not None:
            # supports and dashpots: their damping adds to the modal one; the explicit limit
            # of the highest modes with their damping ratio ξ = φᵀ C φ / (2ω) (mass-normalised
            # φ, :func:`geardyn.solve.explicit.damped_step_limit`)
            C = C + model.C_lin
            w = 2 * math.pi * f[-4:]
            xi = np.einsum("ij,ik,kj->j", phi[:, -4:], C, phi[:, -4:]) / (2 * w)
            dt *= 0.5 * explicit.damped_step_limit(float(max(0.0, xi.max())))
    ref = reference_shaft or next(iter(model.shaft_nodes))
    return Prepared(model, q0, K_lin, C, f, dt, speed_ratios(model, ref))


def damping_operator(prep: Prepared, cutoff_hz: float | None
                     ) -> tuple[np.ndarray | explicit.ModalDamping, float]:
    """Damping of the loop and the explicit stability limit [s]: without a cutoff the dense
    modal damping matrix ``prep.C`` and ``prep.dt_stable`` = 2/ω_max; with one,
    :func:`geardyn.solve.explicit.modal_damping` (ratio ζ below the cutoff, ζ f/f_c above) and
    the loop's damped limit :func:`geardyn.solve.explicit.damped_step_limit` (ξ) / ω_max for
    the ratio ξ of the highest mode (it binds: ξ grows with ω)."""
    m = prep.model
    if cutoff_hz is None and m.modal_damping == 0.0:
        # no modal damping: only the supports' and dashpots' (sparse), no dense n² product
        n = m.ndof
        S = m.C_lin if m.C_lin is not None else np.zeros((n, n))
        return explicit.ModalDamping(S, np.zeros((n, 0)), np.zeros(0), np.zeros(n),
                                     np.asarray(prep.frequencies_hz)), prep.dt_stable
    if cutoff_hz is None:
        return prep.C, prep.dt_stable
    elastic = np.sort(np.asarray(prep.frequencies_hz, float))
    elastic = elastic[elastic >= 0.5]  # above the drive line's rigid-body rotation
    if elastic.size and cutoff_hz <= elastic[0]:
        raise ConfigError(
            f"transmission.modal_damping_cutoff_hz: {cutoff_hz:g} Hz is at or below the lowest "
            f"elastic mode ({elastic[0]:.4g} Hz): every mode would get ζ·f/f_c, up to "
            f"{m.modal_damping * elastic[-1] / cutoff_hz:.3g} on the highest, and the damped "
            "explicit step would shrink accordingly; choose a cutoff above the modes of "
            "interest (e.g. 2-4 kHz for Thibault et al. 2024)")
    op = explicit.modal_damping(m.M, 0.5 * (prep.K_lin + prep.K_lin.T), m.modal_damping,
                                cutoff_hz)
    xi = float(op.ratios[-1])
    if m.C_lin is not None:  # supports and dashpots: in the sparse part
        op = op._replace(stiffness=np.asarray(op.stiffness) + m.C_lin)
    return op, prep.dt_stable * 0.5 * explicit.damped_step_limit(xi)


def simulate(
    cfg,  # noqa: ANN001 - GeardynConfig
    revolutions: float | None = None,
    prepared: Prepared | None = None,
    model: TransmissionModel | None = None,
    control: RunControl | None = None,
    check_step: bool = False,
) -> xr.Dataset:
    """Run the speed law of ``cfg.transmission`` (``revolutions`` of the reference shaft
    overrides the config), or, without a speed law, the plain torque laws (constant drive and
    load torques) for ``simulation.duration_s`` from ``simulation.initial_rpm`` of the drive.

    Returns time histories of every shaft's angle and speed at its first node, drive torque,
    bearing loads, mesh forces; energy terms in ``attrs``. ``control``: progress, cost
    estimate, stop requests (status ``interrupted``), checkpoints and resume of the chunked
    loop. ``check_step`` (the CLI and :func:`geardyn.run.run_simulation`): the time step is
    checked first (above the explicit stability limit, or under two steps per mesh cycle:
    InputError naming ``time_step_s``; without it such a run diverges). A run whose mesh
    deflection exceeds 0.1 module or whose energy balance does not close ends ``suspect``."""
    t = cfg.transmission
    sl = t.speed_law
    model = model or (prepared.model if prepared else build_model(cfg))
    built = model
    model = with_mass(model, t)
    if model is not built:  # a consistent-mass model for a lumped config: prepare it again
        prepared = None
    if sl is None:
        # plain torque laws: constant drive and load torques from an initial drive speed
        if t.simulation.duration_s is None or t.simulation.initial_rpm is None:
            raise InputError(
                "transmission.simulation: without a speed_law, give duration_s and initial_rpm "
                "(plain torque laws: constant drive.torque_nm and load.torque_nm)"
            )
        ref_shaft, ref_local = t.drive.at.shaft, t.drive.at.node
    else:
        ref_shaft, ref_local = sl.reference.shaft, sl.reference.node
    t0 = _time.perf_counter()
    prep = prepared or prepare(model, ref_shaft)
    t_prep = _time.perf_counter() - t0
    ratios = speed_ratios(model, ref_shaft)
    if sl is not None:
        n_rev = revolutions or t.simulation.revolutions or sl.revolutions
        w0, w1 = sl.start_rpm * math.pi / 30, sl.end_rpm * math.pi / 30
        duration = 2 * math.pi * n_rev / (0.5 * (w0 + w1))
    else:
        w0 = w1 = t.simulation.initial_rpm * math.pi / 30
        duration = t.simulation.duration_s
    damping, dt_limit = damping_operator(prep, getattr(t, "modal_damping_cutoff_hz", None))
    for sp in model.supports:  # the explicit limit with the stiffest tabulated coefficients
        if sp.table is not None and t.simulation.integrator != "exponential":
            ix = np.ix_(sp.dofs, sp.dofs)
            for dk in sp.table[1]:
                Kt = 0.5 * (prep.K_lin + prep.K_lin.T)
                Kt[ix] += 0.5 * (dk + dk.T)
                dt_limit = min(dt_limit, explicit.stable_time_step(model.M, Kt)
                               * dt_limit / prep.dt_stable)
    w_top = max(abs(w0), abs(w1))
    mesh_period = _mesh_period(model, ratios, w_top)
    scheme, dt_newmark = choose_integrator(t.simulation, dt_limit, mesh_period,
                                           w_top * max(ratios.values()) / (2 * math.pi),
                                           float(model.meshes.npc.max(initial=0.0)))
    gyro0 = None
    if t.simulation.gyroscopic:
        gyro0 = sum(model.shaft_sign[s] * ratios.get(s, 0.0) * w0 * g
                    for s, g in model.gyroscopic.items())
    if t.simulation.integrator in ("auto", "exponential"):
        from geardyn.models.transmission.exact import exponential_reason

        reason = exponential_reason(model, t, w0, w1, dense_damping(damping), gyro0)
        if t.simulation.integrator == "exponential" and reason:
            raise ConfigError("transmission.simulation.integrator: 'exponential' applies to "
                              f"linear rotors at constant speed only: {reason}")
        if not reason:
            scheme = "exponential"
    if t.simulation.integrator in ("auto", "modal") and scheme != "exponential":
        reason = modal_reason(model, t, damping, gyro0, sl is not None and sl.start_rpm
                              != sl.end_rpm)
        if t.simulation.integrator == "modal" and reason:
            raise ConfigError("transmission.simulation.integrator: 'modal' needs modal "
                              f"damping and no speed-dependent terms: {reason}")
        if not reason:
            scheme = "modal"
    if scheme == "newmark":
        dt = t.simulation.time_step_s or dt_newmark
    elif scheme == "exponential":
        dt = t.simulation.time_step_s or 1.0 / t.simulation.record_rate_hz
    elif scheme == "modal":
        def speed_ratio(time_s: float) -> float:  # reference speed law / top speed
            w = w0 + (w1 - w0) * min(1.0, max(0.0, time_s / duration))
            return abs(w) / w_top if w_top > 0 else 0.0

        tick, rec_ticks, schedule, dt = modal_step(
            t.simulation, mesh_period, w_top * max(ratios.values()) / (2 * math.pi),
            float(model.meshes.npc.max(initial=0.0)), speed_ratio)
    else:
        dt = t.simulation.time_step_s or 0.8 * dt_limit
    if check_step:
        check_time_step(dt, "transmission.simulation.time_step_s" if t.simulation.time_step_s
                        else f"transmission.simulation.time_step_s (default: {scheme} step)",
                        mesh_period_s=mesh_period,
                        stable_limit_s=dt_limit if scheme == "explicit" else None)
    n_steps = int(math.ceil(duration / dt))
    rec_every = max(1, int(round(1.0 / (t.simulation.record_rate_hz * dt))))
    if scheme == "modal":  # whole records: the run ends on a record tick at or after duration
        n_ticks = int(math.ceil(duration * t.simulation.record_rate_hz - 1e-9)) * rec_ticks \
            if not t.simulation.time_step_s else n_steps
    # rigid-body initial speeds on θz
    v = np.zeros(model.ndof)
    for s, ids in model.shaft_nodes.items():
        for nd in ids:
            v[6 * nd + 5] = model.shaft_sign[s] * ratios[s] * w0
    drive_shaft = t.drive.at.shaft
    if sl is not None:
        # controller (bandwidth ω_c, damping 0.7) on the reference speed, actuating the drive
        r = v / w0
        j_eq = float(r @ model.M @ r)
        g = 1.0 / ratios[drive_shaft]
        wc = 2 * math.pi * sl.bandwidth_hz
        kp, ki = 2 * 0.7 * wc * j_eq * g, wc * wc * j_eq * g
        losses = sum(
            model.bearings.visc[i] * (ratios[_shaft_of(model, int(nd))] * w0) ** 2
            for i, nd in enumerate(model.bearings.node)
        )
        t_drive0 = (model.load_torque * w0 + losses) / (ratios[drive_shaft] * w0)
        t_drive0 += j_eq * g * (w1 - w0) / duration
    else:
        kp = ki = 0.0
        t_drive0 = model.drive_torque
    shafts = list(model.shaft_nodes)
    extra, support_ix = recorded_dofs(model, t.simulation.record)
    rec_dofs = np.array([6 * model.shaft_nodes[s][0] + 5 for s in shafts] + extra,
                        dtype=np.int64)
    ref_node = model.node_of(ref_shaft, ref_local)
    gargs = explicit.gyroscopic_args(model.gyroscopic, {s: [6 * nd + 5 for nd in ids]
                                                       for s, ids in model.shaft_nodes.items()}
                                     ) if t.simulation.gyroscopic else None
    tables = [sp for sp in model.supports if sp.table is not None]
    varying = (sl is not None and sl.start_rpm != sl.end_rpm) or model.drive_torque != 0.0 \
        or model.load_torque != 0.0
    if not varying:
        tables = []
    xargs = load_args(model, t, tables) if (t.unbalance or t.external_loads or tables) \
        else None
    common = (model.bearings.args(), model.meshes.args(),
              6 * model.drive_node + 5, 6 * model.load_node + 5, 6 * ref_node + 5,
              model.node_sign(model.drive_node), model.node_sign(model.load_node),
              model.node_sign(ref_node), model.load_torque,
              np.array([0.0, duration, duration * 10 + 1.0]), np.array([w0, w1, w1]),
              kp, ki, t_drive0, 0.0, MAX_DISPLACEMENT_M, rec_dofs)
    t1 = _time.perf_counter()
    newton = None
    if scheme == "exponential":
        from geardyn.models.transmission.exact import run_exponential

        rec, energy, q, vend = run_exponential(model, t, dense_damping(damping), gyro0,
                                               prep.q0.copy(), v, dt, n_steps, rec_dofs)
        rec = rec[::rec_every]
        n_done, status = n_steps, 0
    elif scheme == "modal":
        from geardyn.solve import modal_fe
        from geardyn.solve.determinism import single_thread_blas

        ports = modal_fe.port_dofs(model, [common[2], common[3], common[4]])
        # the modes and the step coefficients (batched 5 × 5 exponentials, also computed
        # between chunks when the step changes) on one BLAS thread: the same bits in any
        # process, and no thread start-up per tiny product (≈ 0.9 CPU s per coefficient set
        # with two OpenBLAS threads on a loaded machine, 2 ms with one)
        with single_thread_blas():
            setup = modal_fe.ModalSetup(model.M, model.K, prep.K_lin, dense_damping(damping),
                                        ports, rec_dofs, tick)
            rec, energy, n_done, status, q, vend, _, t_end = modal_fe.run_loop(
                setup, prep.q0.copy(), v, n_ticks, rec_ticks, schedule, *common,
                control=control)
    elif scheme == "newmark":
        from geardyn.solve import implicit_fe

        rec, energy, n_done, status, q, vend, _, newton = implicit_fe.run_loop(
            prep.q0.copy(), v, dt, n_steps, rec_every, model.M, model.K, prep.K_lin, damping,
            sparse_damping(damping), *common, control=control, gargs=gargs, xargs=xargs,
            gyro0=gyro0)
    else:
        Minv = np.linalg.inv(model.M)
        rec, energy, n_done, status, q, vend, _ = explicit.run_loop(
            prep.q0.copy(), v, dt, n_steps, rec_every, Minv, model.K, damping, *common,
            control=control, gargs=gargs, xargs=xargs)
    t_run = _time.perf_counter() - t1
    t_reached = t_end if scheme == "modal" else n_done * dt
    of_total = "" if scheme == "modal" else f" of {n_steps}"
    ds = records_dataset(rec, model, t, shafts, len(extra), support_ix)
    names = ["input_J", "output_J", "bearing_viscous_J", "rolling_resistance_J",
             "gear_friction_J", "squeeze_film_J", "modal_damping_J", "external_loads_J"]
    ds.attrs.update({f"energy_{k}": float(e) for k, e in zip(names, energy, strict=True)})
    ke0 = 0.5 * v @ model.M @ v
    ke1 = 0.5 * vend @ model.M @ vend
    ds.attrs.update({
        "kinetic_energy_start_J": float(ke0), "kinetic_energy_end_J": float(ke1),
        "time_step_s": dt, "steps": int(n_done), "wall_prepare_s": t_prep, "integrator": scheme,
        "wall_integrate_s": t_run, "reference_shaft": ref_shaft,
        "natural_frequencies_hz": prep.frequencies_hz[prep.frequencies_hz > 1.0][:30],
    })
    if scheme == "exponential":
        ds.attrs["energy_balance"] = ("exact integration: the damping dissipation "
                                      "(energy_modal_damping_J) is the balance of the others")
    if newton is not None:
        ds.attrs["newton_iterations_per_step"] = float(newton[0] / max(1, n_done))
        ds.attrs["newton_unconverged_steps"] = int(newton[1])
    finish(ds, "transmission", ref_shaft)
    if status == 2:
        ds.attrs["status"] = "interrupted"
        ds.attrs["diagnosis"] = (
            f"{(control.stop_reason if control else '') or 'interrupted'} at t = "
            f"{t_reached:.6g} s (step {n_done}{of_total}): the computed part is kept")
    elif status == 0:
        ds.attrs["energy_stored_start_J"] = stored_energy(model, prep.q0, v)
        ds.attrs["energy_stored_end_J"] = stored_energy(model, q, vend)
        _output_checks(ds, model)
    if status == 1:
        ds.attrs["status"] = "diverged"
        ds.attrs["diagnosis"] = (f"diverged at t = {t_reached:.6f} s (step {n_done}): "
                                 "displacements exceeded 50 mm or accelerations overflowed")
        raise SimulationDivergedError(
            f"simulation diverged at t = {t_reached:.6f} s (step {n_done}): displacements "
            "exceeded 50 mm or accelerations overflowed; reduce simulation.time_step_s or check "
            "clearances/loads. The partial result is attached (.result).",
            ds,
        )
    return ds


#: Newmark steps per period of the highest resolved frequency (average acceleration: period
#: error (ω dt)²/12 = 0.8 % there, Géradin & Rixen 2015 §7.3; below it falls as f²).
STEPS_PER_PERIOD = 20
#: Default resolved frequency: mesh harmonics up to this fraction of the mesh-stiffness table's
#: points per cycle (a quarter: the table's content up to half its Nyquist order), shaft
#: orders up to :data:`SHAFT_ORDERS`.
MESH_HARMONICS_PER_POINT = 0.25
SHAFT_ORDERS = 10
#: ``auto`` takes Newmark when its step is this many times the explicit one (a Newmark step
#: costs ≈ 2-3 force evaluations and a banded solve).
AUTO_RATIO = 4.0


def choose_integrator(sim, dt_limit: float, mesh_period: float | None,  # noqa: ANN001
                      shaft_hz: float, table_points: float = 0.0) -> tuple[str, float]:
    """(scheme, Newmark step [s]) for ``sim`` (SimulationConfig): the Newmark step resolves
    ``resolved_frequency_hz`` with :data:`STEPS_PER_PERIOD` steps, by default the highest of
    the mesh harmonic :data:`MESH_HARMONICS_PER_POINT` × ``table_points`` (points per mesh
    cycle of the stiffness tables) at the top mesh frequency and :data:`SHAFT_ORDERS` × the
    top shaft speed; ``auto`` picks Newmark when that step is :data:`AUTO_RATIO` × the explicit
    one (0.8 × ``dt_limit``) or more."""
    f = sim.resolved_frequency_hz
    if f is None:
        harmonics = max(1.0, MESH_HARMONICS_PER_POINT * table_points)
        f = max(harmonics / mesh_period if mesh_period else 0.0, SHAFT_ORDERS * shaft_hz)
    if not f > 0:
        f = 0.5 / dt_limit  # at rest, no mesh: the explicit step's scale
    dt_newmark = 1.0 / (STEPS_PER_PERIOD * f)
    scheme = sim.integrator
    if scheme == "auto":
        scheme = "newmark" if dt_newmark >= AUTO_RATIO * 0.8 * dt_limit else "explicit"
    return scheme, dt_newmark


#: Modal integrator: steps per period of the highest resolved frequency. The linear structure
#: is integrated exactly, so the step only has to follow the port forces; at the default
#: resolved frequency (a quarter of the stiffness table's points per mesh cycle) four points
#: per period are one step per point of the mesh-stiffness table, between which the stiffness
#: is interpolated linearly (the mesh force has a kink at every table point: a step must not
#: straddle two of them).
MODAL_STEPS_PER_PERIOD = 4


def modal_step(sim, mesh_period: float | None, shaft_hz: float,  # noqa: ANN001
               table_points: float, speed_ratio: Callable[[float], float] | None = None,
               ) -> tuple[float, int, Callable[[float, float], int], float]:
    """(tick [s], ticks per record, schedule, step at the top speed [s]) of the modal
    integrator. The step resolves ``resolved_frequency_hz`` (default as
    :func:`choose_integrator`: at the top speed) with :data:`MODAL_STEPS_PER_PERIOD` steps per
    period, for the whole run: a step following the speed alone (the table criterion at the
    current mesh frequency) was less accurate than the explicit loop at low speed (Thibault
    et al. 2024 at 200-250 rpm, 50-60 µs: mesh forces 0.81 % against 0.45 %, bearing loads
    0.93 % against 0.32 %), as the port forces also carry the structure's own vibration,
    whose frequencies do not fall with the speed. ``structural_frequency_hz`` given (and the
    default resolved frequency): the step follows the speed — the table criterion at the
    highest speed of each part of the run, ``speed_ratio(t)`` = speed / top speed — but never
    exceeds 1/(4 f_s), so that f_s is resolved at every speed. Records keep
    ``record_rate_hz`` exactly: a tick divides the record interval, the step is a whole
    number (≥ 3) of ticks, at least 3/4 of the criterion's step. ``time_step_s`` given: that
    step, a record every round(1/(rate · step)) steps (as the other integrators).
    ``schedule(t0, t1)``: the step in ticks for the part of the run between t0 and t1 [s]."""
    t_rec = 1.0 / sim.record_rate_hz
    if sim.time_step_s:
        return (sim.time_step_s, max(1, int(round(t_rec / sim.time_step_s))),
                lambda _a, _b: 1, sim.time_step_s)
    f = sim.resolved_frequency_hz
    follow = f is None and sim.structural_frequency_hz is not None and speed_ratio is not None
    if f is None:
        harmonics = max(1.0, MESH_HARMONICS_PER_POINT * table_points)
        f = max(harmonics / mesh_period if mesh_period else 0.0, SHAFT_ORDERS * shaft_hz)
    if not f > 0:
        f, follow = 0.5 / t_rec, False
    h = 1.0 / (MODAL_STEPS_PER_PERIOD * f)
    per_rec = max(1, math.ceil(3.0 * t_rec / h - 1e-9))
    tick = t_rec / per_rec
    m = max(1, int(math.floor(h / tick + 1e-9)))
    if not follow:
        return tick, per_rec, lambda _a, _b: m, m * tick
    ratio = speed_ratio  # narrowed for the closure
    h_s = 1.0 / (MODAL_STEPS_PER_PERIOD * sim.structural_frequency_hz)
    m_max = max(m, int(math.floor(h_s / tick + 1e-9)))

    def schedule(t0: float, t1: float) -> int:
        r = max(ratio(t0), ratio(t1))  # type: ignore[misc]
        if not r > 0:
            return m_max
        return min(m_max, max(m, int(math.floor(h / r / tick + 1e-9))))

    return tick, per_rec, schedule, m * tick


def modal_reason(model: TransmissionModel, t, damping, gyro0,  # noqa: ANN001
                 speed_varies: bool) -> str:
    """Why the modal integrator does not apply ('' when it does): it needs a damping
    diagonal in the modes of (M, K_lin) and no speed-dependent linear terms."""
    if gyro0 is not None:
        return "gyroscopic terms (speed-dependent, not modal)"
    if t.unbalance or t.external_loads:
        return "unbalances and external loads are not port forces of this integrator"
    if any(sp.table is not None for sp in model.supports) and (
            speed_varies or model.drive_torque != 0.0 or model.load_torque != 0.0):
        return "supports tabulated against speed"
    if model.C_lin is not None and np.any(model.C_lin):
        return "support or dashpot damping (not diagonal in the modes)"
    return ""


def dense_damping(damping) -> np.ndarray:  # noqa: ANN001
    """The loop's damping as one dense matrix (a :class:`~geardyn.solve.explicit.ModalDamping`
    summed: S + B diag(w) Bᵀ)."""
    if isinstance(damping, explicit.ModalDamping):
        B = np.asarray(damping.basis, float)
        return np.asarray(damping.stiffness, float) + (B * damping.weights) @ B.T
    return np.asarray(damping, float)


def sparse_damping(damping) -> np.ndarray | None:  # noqa: ANN001
    """The sparse part of the loop's damping for the Newmark step matrix: the
    stiffness-proportional + supports part of a :class:`~geardyn.solve.explicit.ModalDamping`;
    a dense damping matrix enters the step matrix only if it is sparse (supports and dashpots
    alone), else it stays in the residual (modified Newton)."""
    if isinstance(damping, explicit.ModalDamping):
        return np.asarray(damping.stiffness, float)
    C = np.asarray(damping, float)
    return C if np.count_nonzero(C) <= 0.1 * C.size else None


def recorded_dofs(model: TransmissionModel, names: list[str]
                  ) -> tuple[list[int], list[tuple[str, list[int]]]]:
    """Global DOFs recorded besides the shaft angles for ``simulation.record``: a DOF name
    (``{shaft}.n{i}.{x,y,z,rx,ry,rz}``), a disc name (its node's x, y) or a support name (its
    node's x, y, θx, θy, for its force). Returns (DOFs in record order, per support its name
    and the positions of its four DOFs in that list)."""
    dof_names = model.dof_names
    index = {n: i for i, n in enumerate(dof_names)}
    supports = {s.name: s for s in model.supports}
    dofs: list[int] = []

    def add(j: int) -> int:
        if j not in dofs:
            dofs.append(j)
        return dofs.index(j)

    sup: list[tuple[str, list[int]]] = []
    for i, name in enumerate(names):
        if name in index:
            add(index[name])
        elif name in model.discs:
            for k in (0, 1):
                add(6 * model.discs[name] + k)
        elif name in supports:
            sp = supports[name]
            ix = [add(int(j)) for j in sp.dofs]
            if sp.table is not None:  # its speed, for the tabulated coefficients
                ix.append(add(6 * sp.node + 5))
            sup.append((name, ix))
        else:
            known = sorted([*model.discs, *supports])
            raise ConfigError(
                f"transmission.simulation.record[{i}]: '{name}' is no DOF "
                "('{shaft}.n{i}.{x,y,z,rx,ry,rz}', e.g. " f"'{dof_names[0]}'), disc or support "
                f"(discs and supports: {', '.join(known) or 'none'})")
    return dofs, sup


def records_dataset(rec: np.ndarray, model: TransmissionModel, t, shafts: list[str],  # noqa: ANN001
                    n_extra: int, support_ix: list[tuple[str, list[int]]]) -> xr.Dataset:
    """The run's Dataset from the record columns of :func:`geardyn.solve.explicit.run_chunk`
    (``rec_dofs`` = the shafts' θz, then ``n_extra`` recorded DOFs): shaft angles and speeds,
    bearings, meshes, recorded displacements/velocities and support forces."""
    nd = len(shafts)
    nr = nd + n_extra
    nb = model.bearings.node.size
    time = rec[:, 0]
    sign = np.array([model.shaft_sign[s] for s in shafts])
    links = {sc.name: (sc.link or sc.name) for sc in t.shafts}
    o_b = 2 + 2 * nr
    angle, speed, rpm = _shaft_records(rec, 2, 2 + nr, sign)
    variables = {
        "drive_torque": ("time", rec[:, 1], {"units": "N·m", "long_name": "drive torque"}),
        **shaft_variables(time, shafts, angle, speed, rpm),
        "bearing_load": (("time", "bearing"), rec[:, o_b : o_b + nb],
                         {"units": "N", "long_name": "Σ rolling-element loads"}),
        "bearing_force": (("time", "bearing", "axis"),
                          # view of the x then y column blocks (no copy)
                          rec[:, o_b + nb : o_b + 3 * nb].reshape(rec.shape[0], 2, nb)
                          .transpose(0, 2, 1),
                          {"units": "N", "long_name": "force of the bearing on the housing"}),
        "mesh_force": (("time", "mesh"), rec[:, o_b + 3 * nb :],
                       {"units": "N", "long_name": "normal force, transverse LOA"}),
    }
    coords = {"time": ("time", time, {"units": "s"}), "shaft": shafts,
              "link": ("shaft", [links.get(s, s) for s in shafts]),
              "bearing": model.bearings.names, "mesh": model.meshes.names,
              "axis": ["x", "y"]}
    if n_extra:
        names = [model.dof_names[j] for j in _extra_dofs(t, model)]
        units = ["m" if n.rsplit(".", 1)[1] in ("x", "y", "z") else "rad" for n in names]
        q = rec[:, 2 + nd : 2 + nr]
        v = rec[:, 2 + nr + nd : 2 + 2 * nr]
        variables["displacement"] = (("time", "dof"), q, {
            "units": "m (x, y, z), rad (rx, ry, rz)", "long_name": "recorded DOFs"})
        variables["velocity"] = (("time", "dof"), v, {
            "units": "m/s (x, y, z), rad/s (rx, ry, rz)", "long_name": "recorded DOF rates"})
        coords["dof"] = names
        coords["dof_units"] = ("dof", units)
    if support_ix:
        sup = {s.name: s for s in model.supports}
        f = np.zeros((rec.shape[0], len(support_ix), 2))
        for k, (name, ix) in enumerate(support_ix):
            s = sup[name]
            u = rec[:, 2 + nd + np.array(ix[:4])]
            ud = rec[:, 2 + nr + nd + np.array(ix[:4])]
            K = np.broadcast_to(s.K, (rec.shape[0], 4, 4))
            C = np.broadcast_to(s.C, (rec.shape[0], 4, 4))
            if s.table is not None:  # coefficients at the recorded speed of its node
                rpm = np.abs(rec[:, 2 + nr + nd + ix[4]]) * 30 / np.pi
                K = K + _table_interp(rpm, s.table[0], s.table[1])
                C = C + _table_interp(rpm, s.table[0], s.table[2])
            f[:, k, :] = (np.einsum("trc,tc->tr", K, u) + np.einsum("trc,tc->tr", C, ud))[:, :2]
        variables["support_force"] = (("time", "support", "axis"), f, {
            "units": "N", "long_name": "force of the support on the housing, K u + C u̇"})
        coords["support"] = [n for n, _ in support_ix]
    return xr.Dataset(variables, coords=coords)


def _shaft_records(rec: np.ndarray, ca: int, cs: int, sign: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(angle, speed, speed in rpm) of the shafts, (rows, shafts) each: the values of
    ``rec[:, ca : ca + nd] * sign``, ``rec[:, cs : cs + nd] * sign`` and ``speed *``
    :data:`~geardyn.results.RAD_S_TO_RPM` in one compiled pass over the records, into one
    array on ordinary pages (:func:`geardyn.solve.explicit.record_array`: no synchronous
    huge-page compaction on first touch, 0.2-0.5 s for these 118 MB of the 300-revolution
    seed 002 run on a loaded machine)."""
    nr = rec.shape[0]
    out = explicit.record_array((3 * nr, sign.size)).reshape(3, nr, sign.size)
    _fill_shaft_records(rec, ca, cs, np.asarray(sign, float), RAD_S_TO_RPM, out[0], out[1],
                        out[2])
    return out[0], out[1], out[2]


@njit(cache=True)
def _fill_shaft_records(rec, ca, cs, sign, to_rpm, angle, speed, rpm
                        ):  # pragma: no cover - compiled
    """The loop of :func:`_shaft_records`, by blocks of 512 rows (a column at a time inside
    a block: the block's rows stay in cache, and no per-row loop over the few shafts)."""
    nr = rec.shape[0]
    for r0 in range(0, nr, 512):
        r1 = min(nr, r0 + 512)
        for k in range(sign.size):
            sk = sign[k]
            for r in range(r0, r1):
                angle[r, k] = rec[r, ca + k] * sk
                w = rec[r, cs + k] * sk
                speed[r, k] = w
                rpm[r, k] = w * to_rpm


@njit(cache=True)
def _max_abs_columns(a):  # pragma: no cover - compiled
    """Per column the largest |a| over the rows, NaN ignored (np.nanmax of np.abs: NaN for a
    column of NaN only), one pass over a row-major (or strided) array without a copy."""
    nr, nc = a.shape
    out = np.full(nc, np.nan)
    for r in range(nr):
        for c in range(nc):
            x = abs(a[r, c])
            if x >= out[c] or (out[c] != out[c] and x == x):
                out[c] = x
    return out


def _table_interp(rpm: np.ndarray, speeds: np.ndarray, mats: np.ndarray) -> np.ndarray:
    """(n, 4, 4) linear interpolation of ``mats`` (nt, 4, 4) at ``rpm`` (held outside)."""
    flat = mats.reshape(mats.shape[0], -1)
    out = np.stack([np.interp(rpm, speeds, flat[:, j]) for j in range(flat.shape[1])], axis=1)
    return out.reshape(-1, 4, 4)


def _extra_dofs(t, model: TransmissionModel) -> list[int]:  # noqa: ANN001
    return recorded_dofs(model, t.simulation.record)[0]


#: Largest translation of a node [m] before the run counts as diverged.
MAX_DISPLACEMENT_M = 0.05
#: A mesh deflection beyond this fraction of the normal module is not a gear mesh any more.
MAX_DEFLECTION_PER_MODULE = 0.1


def _mesh_period(model: TransmissionModel, ratios: dict[str, float], w_max: float
                 ) -> float | None:
    """Shortest mesh period [s] at reference speed ``w_max`` [rad/s]: f = z_a |ω_a| / 2π."""
    node_shaft = {n: s for s, ids in model.shaft_nodes.items() for n in ids}
    f = 0.0
    for i, g in enumerate(model.meshes.geometry):
        r = ratios.get(node_shaft.get(int(model.meshes.na[i]), ""), 0.0)
        f = max(f, g.a.teeth * abs(r * w_max) / (2 * math.pi))
    return 1.0 / f if f > 0 else None


def mean_mesh_stiffness(model: TransmissionModel) -> np.ndarray:
    """Mean over one mesh cycle of each mesh's structural stiffness Σ_p K_tot,p [N/m]
    (the pair stiffness table of :func:`geardyn.gears.mesh_stiffness`)."""
    mh = model.meshes
    out = np.zeros(len(mh.names))
    for i in range(len(mh.names)):
        out[i] = float(np.mean(np.sum(mh.ks[i, : int(mh.tlen[i])], axis=-1)))
    return out


def stored_energy(model: TransmissionModel, q: np.ndarray, v: np.ndarray) -> float:
    """Kinetic ½vᵀMv plus the elastic energy of the shafts ½qᵀKq [J]. The contact energy of
    bearings and meshes is not booked: its change over a run is within the balance residual
    (2e-5 of the energy exchanged on the seed 002 example, tests/robust/test_sanity.py)."""
    return 0.5 * float(v @ model.M @ v) + 0.5 * float(q @ model.K @ q)


def _output_checks(ds: xr.Dataset, model: TransmissionModel) -> None:
    """Status ``suspect`` when a mesh deflects more than 0.1 module (deflection estimated as
    force / mean mesh stiffness) or the energy balance does not close."""
    problems = []
    k = mean_mesh_stiffness(model)
    f = np.asarray(ds["mesh_force"].values, float)
    fmax = _max_abs_columns(f) if f.shape[0] else None  # no |f| copy of the records
    for i, g in enumerate(model.meshes.geometry):
        if fmax is None or k[i] <= 0:
            continue
        d = float(fmax[i]) / k[i]
        m = g.normal_module
        if not math.isfinite(d) or d > MAX_DEFLECTION_PER_MODULE * m:
            problems.append(f"mesh '{model.meshes.names[i]}': deflection up to {d * 1e3:.3g} mm "
                            f"(force / mean mesh stiffness) for a module of {m * 1e3:.3g} mm "
                            f"(more than {MAX_DEFLECTION_PER_MODULE:g} × module)")
    e = energy_terms(ds)
    problem = check_energy(e) if e else ""
    if problem:
        problems.append(problem)
    if problems:
        ds.attrs["status"] = "suspect"
        ds.attrs["diagnosis"] = "; ".join(problems) + "; the computed part is kept"


def energy_terms(ds: xr.Dataset) -> dict[str, float]:
    """The FE run's energy balance in the terms of :func:`geardyn.solve.sanity.check_energy`:
    applied = input − output work, dissipated = Σ dissipation channels, stored = kinetic +
    shaft elastic energy (in ``kinetic_*``)."""
    a = ds.attrs
    if "energy_stored_end_J" not in a:
        return {}
    diss = sum(float(a[f"energy_{k}"]) for k in ("bearing_viscous_J", "rolling_resistance_J",
                                                 "gear_friction_J", "squeeze_film_J",
                                                 "modal_damping_J"))
    ext = float(a.get("energy_external_loads_J", 0.0))
    return {"applied_J": float(a["energy_input_J"]) - float(a["energy_output_J"]) + ext,
            "gross_applied_J": abs(float(a["energy_input_J"])) + abs(float(a["energy_output_J"]))
            + abs(ext),
            "dissipated_J": diss, "kinetic_start_J": float(a["energy_stored_start_J"]),
            "kinetic_end_J": float(a["energy_stored_end_J"]), "potential_start_J": 0.0,
            "potential_end_J": 0.0}


_DOF = {"x": 0, "y": 1, "z": 2, "rx": 3, "ry": 4, "rz": 5}


def load_args(model: TransmissionModel, t, tables: list | None = None  # noqa: ANN001
              ) -> tuple:
    """Applied-load arguments of the loop (:func:`.integrate.applied_loads`) from
    ``transmission.unbalance``, ``transmission.external_loads`` and the speed tables of the
    supports in ``tables`` (:class:`.assembly.SupportPart` with a table)."""
    u_dof = np.array([6 * model.node_of(u.at.shaft, u.at.node) for u in t.unbalance], np.int64)
    u_me = np.array([u.mass_eccentricity_kg_m for u in t.unbalance], float)
    u_ph = np.radians([u.phase_deg for u in t.unbalance]).astype(float)
    xl = t.external_loads
    nodes = [model.node_of(x.at.shaft, x.at.node) for x in xl]
    x_dof = np.array([6 * nd + _DOF[x.dof] for nd, x in zip(nodes, xl, strict=True)], np.int64)
    return (u_dof, u_me, u_ph, x_dof,
            np.array([x.value for x in xl], float), np.array([x.amplitude for x in xl], float),
            np.array([x.frequency_hz for x in xl], float),
            np.array([x.order for x in xl], float),
            np.array([6 * nd + 5 for nd in nodes], np.int64),
            np.radians([x.phase_deg for x in xl]).astype(float)) + _table_args(tables or [])


def _table_args(tables: list) -> tuple:
    """(DOFs (n, 4), θz DOF (n), speeds rpm (n, nt), ΔK, ΔC (n, nt, 4, 4)) padded to the
    longest table by repeating its last point."""
    if not tables:
        return explicit.no_support_tables()
    nt = max(sp.table[0].size for sp in tables)

    def pad(a: np.ndarray) -> np.ndarray:
        return np.concatenate([a, np.repeat(a[-1:], nt - a.shape[0], axis=0)])

    rpm = np.array([pad(sp.table[0]) for sp in tables])
    # repeated last speeds: nudge them up so the interpolation never divides by zero
    for i, sp in enumerate(tables):
        k = sp.table[0].size
        rpm[i, k:] = rpm[i, k - 1] + np.arange(1, nt - k + 1)
    return (np.array([sp.dofs for sp in tables], np.int64),
            np.array([6 * sp.node + 5 for sp in tables], np.int64), rpm,
            np.array([pad(sp.table[1]) for sp in tables]),
            np.array([pad(sp.table[2]) for sp in tables]))


def _shaft_of(model: TransmissionModel, node: int) -> str:
    for s, ids in model.shaft_nodes.items():
        if node in ids:
            return s
    raise InputError(f"node {node} on no shaft")
