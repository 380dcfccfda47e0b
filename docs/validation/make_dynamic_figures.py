"""Regenerate the dynamic validation figures of docs/validation_dynamics.md (docs/img/dyn_*.png).

Run from the repository root: ``.venv/bin/python docs/validation/make_dynamic_figures.py``
(≈ 1 min on one core). Each figure corresponds to a seed figure described next to it in the
docs; the runs are those of tests/validation/seed003 and seed004 (same configs, longer records
where a figure needs resolution).
"""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # script only: writes PNG files
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.signal import detrend, stft  # noqa: E402

from geardyn.config.loader import parse_config  # noqa: E402
from geardyn.models.planetary.build import prepare  # noqa: E402
from geardyn.models.planetary.dynamics import simulate  # noqa: E402
from geardyn.signal.tpa import frf_from_mck, gtdt, path_contributions  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
EX, IMG = ROOT / "examples", ROOT / "docs" / "img"
ZS, ZR = 16, 65


def f_mesh(rpm: float) -> float:
    return rpm / 60 * ZS * ZR / (ZS + ZR)


def f_carrier(rpm: float) -> float:
    return rpm / 60 * ZS / (ZS + ZR)


def raw(name: str) -> dict:
    with open(EX / name, "rb") as fh:
        return tomllib.load(fh)


def run(d: dict, t_end: float, dt: float, save_every: int = 1):
    p = prepare(parse_config(d), t_end_s=t_end)
    ds = simulate(p.model, p.system, p.mesh_index, p.q0, p.v0, t_end, dt, save_every=save_every)
    return p, ds


def stationary(d: dict, rpm: float, torque: float) -> dict:
    d = copy.deepcopy(d)
    sim = d["planetary_dynamics"]["simulation"]
    body = sim["speed_controls"][0]["body"]
    sim["initial_speed_rpm"] = {body: rpm}
    sim["speed_controls"][0]["profile_rpm"] = [[0.0, rpm], [10.0, rpm]]
    sim["torques"] = [{"body": "reaction.ring", "torque_nm": torque}]
    return d


def bench_loaded(torque: float) -> dict:
    """12-DOF bench, square meshes c₀ = 1.5 with the load law (C_a = 5 µm), planet-pass force."""
    d = stationary(raw("planetary_bench_12dof.toml"), 1498.5, torque)
    for st in d["planetary_dynamics"]["stages"]:
        for key, k in (("sun_mesh", 4.46e8), ("ring_mesh", 6.28e8)):
            st[key] = {"model": "square", "k_max_n_per_m": 1.2 * k, "k_min_n_per_m": 0.8 * k,
                       "contact_ratio": 1.5, "load_law": {"tip_relief_m": 5e-6}}
        if st["stage"] == "test":
            st["planet_pass"] = {}
    return d


def spectrum(x: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    x = x - x.mean()
    w = np.hanning(x.size)
    return np.fft.rfftfreq(x.size, dt), np.abs(np.fft.rfft(x * w)) * 2 / w.sum()


def ring_acc(ds, t0: float, dof: str = "test.ring.u") -> tuple[np.ndarray, float]:
    sel = ds.sel(time=slice(t0, None))
    dt = float(sel.time.values[1] - sel.time.values[0])
    return np.gradient(sel.v.sel(dof=dof).values, dt), dt


def fig_ring_spectrum() -> None:
    """Seed 003 Figs 4.7-4.10: test-ring acceleration spectrum, 1498.5 rpm, 100 N·m."""
    fc, fm = f_carrier(1498.5), f_mesh(1498.5)
    _, ds = run(bench_loaded(100.0), 0.1 + 6 / fc, 2e-5)
    a, dt = ring_acc(ds, 0.1)
    f, amp = spectrum(a, dt)
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.6))
    for h, ax in zip((1, 2, 3), axes, strict=True):
        sel = (f > h * fm - 80) & (f < h * fm + 80)
        ax.plot(f[sel], amp[sel], lw=0.8)
        ax.axvline(h * fm, color="grey", ls=":", label=f"{h} f_m")
        dom = {1: 66, 2: 129, 3: 195}[h]
        ax.axvline(dom * fc, color="C3", ls="--", lw=0.8, label=f"{dom} f_c")
        ax.set_xlabel("frequency (Hz)")
        ax.legend(fontsize=7)
    axes[0].set_ylabel("test-ring acceleration (m/s², u = r θ)")
    fig.suptitle("Seed 003 bench, 1498.5 rpm, 100 N·m, planet-pass force (cf. Figs 4.7-4.10)")
    fig.tight_layout()
    fig.savefig(IMG / "dyn_ring_spectrum.png", dpi=110)
    plt.close(fig)


def fig_load_sweep() -> None:
    """Seed 003 Figs 4.16-4.17: ring spectra versus load."""
    fc, fm = f_carrier(1498.5), f_mesh(1498.5)
    fig, ax = plt.subplots(figsize=(8, 4.2))
    for i, torque in enumerate((100.0, 300.0, 500.0, 700.0, 900.0)):
        _, ds = run(bench_loaded(torque), 0.1 + 3 / fc, 2e-5)
        a, dt = ring_acc(ds, 0.1)
        f, amp = spectrum(a, dt)
        sel = (f > 250) & (f < 720)
        ax.plot(f[sel], amp[sel] / amp[sel].max() + i * 1.1, lw=0.8,
                label=f"{torque:.0f} N·m")
    for x in (fm, 2 * fm):
        ax.axvline(x, color="grey", ls=":")
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("normalised amplitude (offset per load)")
    ax.set_title("Test-ring acceleration vs load: dominant line f_m → 2f_m (cf. Figs 4.16-4.17)")
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(IMG / "dyn_load_sweep.png", dpi=110)
    plt.close(fig)


def fig_runup_stft() -> None:
    """Seed 003 Figs 4.24-4.26: STFT of the ring acceleration in a run-up (36-DOF)."""
    d = raw("planetary_bench_36dof.toml")
    sim = d["planetary_dynamics"]["simulation"]
    sim["initial_speed_rpm"] = {"reaction.sun": 100.0}
    sim["speed_controls"][0]["profile_rpm"] = [[0.0, 100.0], [1.5, 1498.5]]
    _, ds = run(d, 1.5, 5e-5)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4))
    for ax, dof in zip(axes, ("test.ring.u", "test.ring.x"), strict=True):
        a, dt = ring_acc(ds, 0.0, dof)
        f, t, z = stft(a, fs=1 / dt, nperseg=4096, noverlap=3584)
        sel = f < 700
        ax.pcolormesh(t, f[sel], 20 * np.log10(np.abs(z[sel]) + 1e-12), shading="auto")
        ax.set_xlabel("time (s)")
        ax.set_ylabel("frequency (Hz)")
        ax.set_title(f"{dof} acceleration (dB re 1 m/s²)")
        for fr in (26.9, 140.0):
            ax.axhline(fr, color="w", ls=":", lw=0.8)
    fig.suptitle("Run-up 100 → 1498.5 rpm in 1.5 s: vertical lines at 26.9 and 140 Hz "
                 "(thesis: 25 and 144 Hz), inclined mesh lines")
    fig.tight_layout()
    fig.savefig(IMG / "dyn_runup_stft.png", dpi=110)
    plt.close(fig)


def fig_lsr_gravity() -> None:
    """Seed 003 Fig 5.6: load sharing over one carrier period with gravity (165 rpm)."""
    rpm, dt = 165.0, 1e-4
    tc = 1 / f_carrier(rpm)
    d = stationary(raw("planetary_bench_36dof.toml"), rpm, 100.0)
    for st in d["planetary_dynamics"]["stages"]:
        st["gravity_m_per_s2"] = 9.81
    d["planetary_dynamics"]["simulation"]["rayleigh_beta"] = 0.0
    d["planetary_dynamics"]["simulation"]["modal_damping_ratio"] = 0.05
    _, ds = run(d, 0.5 + tc, dt)
    sel = ds.sel(time=slice(0.5, None))
    n = int(round(1 / f_mesh(rpm) / dt))
    fig, ax = plt.subplots(figsize=(8, 3.8))
    t = (sel.time.values - 0.5) / tc
    for i in range(3):
        x = sel.lsr_test.values[:, i]
        ax.plot(t, x, lw=0.3, color=f"C{i}", alpha=0.4)
        ax.plot(t[n // 2: n // 2 + x.size - n + 1], np.convolve(x, np.ones(n) / n, mode="valid"),
                color=f"C{i}", label=f"planet {i + 1} (mesh-averaged)")
    for z in (1 / 3, 2 / 3):
        ax.axvline(z, color="grey", ls=":")
    ax.set_xlabel("time / T_c")
    ax.set_ylabel("load sharing ratio (1)")
    ax.set_title("Test set LSR with gravity, 165 rpm, 100 N·m (cf. Fig 5.6)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(IMG / "dyn_lsr_gravity.png", dpi=110)
    plt.close(fig)


def fig_lsr_runup() -> None:
    """Seed 003 Figs 5.10-5.13: LSR during a run-up with pin errors 60/10/−60 µm."""
    d = raw("planetary_bench_36dof.toml")
    sim = d["planetary_dynamics"]["simulation"]
    sim["initial_speed_rpm"] = {"reaction.sun": 100.0}
    sim["speed_controls"][0]["profile_rpm"] = [[0.0, 100.0], [1.0, 500.0]]
    sim["torques"] = [{"body": "reaction.ring", "torque_nm": -100.0}]
    sim["modal_damping_ratio"] = 0.02
    for st in d["planetary_dynamics"]["stages"]:
        if st["stage"] == "test":
            st["pin_errors_m"] = [60e-6, 10e-6, -60e-6]
    _, ds = run(d, 1.0, 1e-4)
    fig, ax = plt.subplots(figsize=(8, 3.6))
    for i in range(3):
        ax.plot(ds.time.values, ds.lsr_test.values[:, i], lw=0.5, label=f"planet {i + 1}")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("load sharing ratio (1)")
    ax.set_title("LSR during a run-up 100 → 500 rpm, pin errors 60/10/−60 µm (cf. Figs 5.10-5.13)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(IMG / "dyn_lsr_runup.png", dpi=110)
    plt.close(fig)


def fig_gtdt() -> None:
    """Seed 003 Figs 5.16-5.17: path contributions to test planet 2 (stationary)."""
    fc = f_carrier(1498.5)
    d = stationary(raw("planetary_bench_12dof.toml"), 1498.5, 100.0)
    d["planetary_dynamics"]["stages"][1]["planet_pass"] = {}
    p, ds = run(d, 0.1 + 3 / fc, 2e-5)
    model = p.model
    sel = ds.sel(time=slice(0.1, None))
    dt = 2e-5
    q = detrend(sel.q.values, axis=0)  # vibration: the rigid-body rotation removed
    w = np.hanning(q.shape[0])[:, None]
    x = np.fft.rfft(q * w, axis=0) * 2 / w.sum()
    f = np.fft.rfftfreq(q.shape[0], dt)
    band = (f > 20) & (f < 1000)
    h = frf_from_mck(model.mass_matrix(), 2e-6 * model.stiffness_matrix(),
                     model.stiffness_matrix(), 2 * np.pi * f[band])
    ppc = np.abs(path_contributions(gtdt(h), x[band]))
    i = model.names.index("test.planet2.u")
    fig, ax = plt.subplots(figsize=(8, 3.8))
    for j, name in enumerate(model.names):
        if ppc[:, i, j].max() > 1e-8 * ppc[:, i].max():  # the others are zero (rounding)
            lab = "external (T^D_ii x_ext)" if j == i else name
            ax.semilogy(f[band], ppc[:, i, j], lw=0.7, label=lab)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("|path contribution| (m)")
    ax.set_title("GTDT path contributions to test planet 2 (12-DOF bench, cf. Figs 5.16-5.17)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(IMG / "dyn_gtdt_planet2.png", dpi=110)
    plt.close(fig)


def reclaimer(faults: list[dict], t_end: float, edit=None):
    d = raw("planetary_reclaimer.toml")
    st = d["planetary_dynamics"]["stages"][0]
    st["faults"] = faults
    st["transmission_error"] = False
    if edit:
        edit(d)
    return run(d, t_end, 1e-4, save_every=5)[1]


def fig_seed004_startup() -> None:
    """Seed 004 Figs 8-13 to 8-16 and 8-28: carrier speed, case 1 from rest and case 2."""
    def case(n: int):
        def edit(d: dict) -> None:
            sim = d["planetary_dynamics"]["simulation"]
            sim["initial_speed_rpm"] = {}
            if n == 1:
                del sim["wheel_load"]
            else:
                sim["wheel_load"]["schedule"] = True
                sim["wheel_load"]["inertia_schedule"] = True
        return edit

    fig, ax = plt.subplots(figsize=(8, 3.6))
    for n in (1, 2):
        ds = reclaimer([], 3.0, case(n))
        ax.plot(ds.time.values, ds.v.sel(dof="carrier.u").values / 0.408 * 60 / (2 * np.pi),
                lw=0.8, label=f"case {n}")
    ax.axvline(0.3, color="grey", ls=":")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("carrier speed (rpm)")
    ax.set_ylim(0, 8)
    ax.set_title("Seed 004 start-up from rest (cf. Figs 8-13 to 8-16, 8-28)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(IMG / "dyn_seed004_startup.png", dpi=110)
    plt.close(fig)


def fig_seed004_planet_crack() -> None:
    """Seed 004 Fig 9-33: planet-1 crack (40 %) signatures in the sun and planet signals."""
    h = reclaimer([], 8.0)
    c = reclaimer([{"kind": "crack", "gear": "planet", "crack_fraction": 0.4}], 8.0)
    x = 83 * c.q.sel(dof="carrier.u").values / 0.408 / (2 * np.pi)
    fig, axes = plt.subplots(3, 1, figsize=(8, 6), sharex=True)
    for ax, dof in zip(axes, ("sun.u", "planet1.u", "carrier.u"), strict=True):
        ax.plot(x, c.v.sel(dof=dof).values - h.v.sel(dof=dof).values, lw=0.6)
        ax.set_ylabel(f"Δv {dof} (m/s)", fontsize=8)
        for k in range(0, 80, 16):
            ax.axvline(k + 0.77, color="grey", ls=":", lw=0.6)
    axes[-1].set_xlabel("mesh cycles X = z_r θ_c/2π")
    axes[0].set_title("Planet-1 crack 40 %, cracked − healthy: humps every z_p/2 = 16 "
                      "mesh cycles (eq 9.2)", fontsize=10)
    fig.tight_layout()
    fig.savefig(IMG / "dyn_seed004_planet_crack.png", dpi=110)
    plt.close(fig)


def main() -> None:
    IMG.mkdir(parents=True, exist_ok=True)
    for make in (fig_ring_spectrum, fig_load_sweep, fig_runup_stft, fig_lsr_gravity,
                 fig_lsr_runup, fig_gtdt, fig_seed004_startup, fig_seed004_planet_crack):
        make()
        print(f"{make.__name__}: done")


if __name__ == "__main__":
    main()
