"""IAS outputs of a transmission run (seed 002 §3.2-3.5): encoder simulation of each shaft
(1000 pulses/rev, 80 MHz, seed 002 eq 1 via :func:`geardyn.sensors.simulate_ias`), angle-domain
order spectra referred to a shaft, angular spectrogram, cepstrum, kinematic markers."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from geardyn.checkpoint import save_figure
from geardyn.errors import InputError


def ias(ds: xr.Dataset, shaft: str, pulses_per_rev: int = 1000, f_clock: float = 80e6):
    """Simulated IAS measurement (:class:`geardyn.sensors.IASMeasurement`) of ``shaft``."""
    from geardyn.sensors.encoder import simulate_ias

    if shaft not in ds.shaft.values:
        raise InputError(f"shaft '{shaft}' not in the result (have {list(ds.shaft.values)})")
    th = ds.angle.sel(shaft=shaft).values
    return simulate_ias(ds.time.values, th - th[0], pulses_per_rev=pulses_per_rev,
                        f_clock=f_clock)


def ias_angle_signal(
    ds: xr.Dataset, shaft: str = "output", reference: str | None = None,
    samples_per_rev: int = 1000, skip_revs: float = 1.0, **kw,
) -> np.ndarray:
    """IAS of ``shaft`` (rad/s) on a uniform angle grid of the ``reference`` shaft (default:
    the same shaft), first ``skip_revs`` reference revolutions dropped (start transient)."""
    from geardyn.signal.resample import resample_ias_to_angle

    m = ias(ds, shaft, **kw)
    ang = m.angle
    if reference is not None and reference != shaft:
        th_s = ds.angle.sel(shaft=shaft).values
        th_r = ds.angle.sel(shaft=reference).values
        ang = np.interp(ang, th_s - th_s[0], th_r - th_r[0])
    w = resample_ias_to_angle(ang, m.ias, samples_per_rev)
    return w[int(skip_revs * samples_per_rev) :]


def ias_order_spectrum(ds: xr.Dataset, shaft: str = "output", **kw) -> xr.DataArray:
    """Angle-domain order spectrum (events/rev of the shaft) of the simulated IAS."""
    from geardyn.signal.spectra import order_spectrum

    spr = kw.get("samples_per_rev", 1000)
    w = ias_angle_signal(ds, shaft, **kw)
    return order_spectrum(w - w.mean(), spr)


def markers(cfg, reference: str = "output"):  # noqa: ANN001, ANN201
    """Kinematic markers (mesh orders + sidebands, BPFO/BPFI of the [[bearings]]) in orders of
    the ``reference`` link (geardyn.kinematics / geardyn.signal.annotate)."""
    from geardyn.kinematics import analyze_kinematics, characteristic_frequencies
    from geardyn.signal.annotate import spectral_markers

    an = analyze_kinematics(cfg)
    speeds = dict(cfg.input_speeds_rpm) if cfg.input_speeds_rpm else {}
    cf = characteristic_frequencies(an, speeds, order_reference=reference)
    return spectral_markers(cf, shaft_harmonics=1, mesh_harmonics=2, sidebands=2,
                            bearing_harmonics=3)


def write_figures(ds: xr.Dataset, cfg, outdir: Path, shaft: str = "output",  # noqa: ANN001
                  order_max: float = 150.0, label: str = "") -> list[Path]:
    """Order spectrum with markers, angular spectrogram and cepstrum of the IAS of ``shaft``
    (PNG files in ``outdir``)."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    from geardyn.signal.cepstrum import power_cepstrum
    from geardyn.signal.plots import plot_cepstrum, plot_map, plot_spectrum
    from geardyn.signal.spectra import angular_spectrogram, order_spectrum

    outdir.mkdir(parents=True, exist_ok=True)
    w = ias_angle_signal(ds, shaft)
    if w.size < 4:
        th = ds.angle.sel(shaft=shaft).values
        revs = abs(th[-1] - th[0]) / (2 * np.pi)
        raise InputError(f"IAS figures of '{shaft}': the run turns it {revs:.3g} revolution(s); "
                         "the figures drop the first one and need more (raise the revolutions)")
    spec = order_spectrum(w - w.mean(), 1000)
    try:
        mk = markers(cfg, shaft)
    except Exception:  # noqa: BLE001 - markers are optional decoration
        mk = None
    paths = []
    fig = plot_spectrum(spec, mk, xmax=order_max,
                        title=f"IAS order spectrum, {shaft} shaft {label}")
    p = outdir / f"ias_spectrum_{shaft}{label}.png"
    save_figure(fig, p, dpi=120)
    plt.close(fig)
    paths.append(p)
    revs = w.size / 1000
    if revs >= 8:
        m = angular_spectrogram(w - w.mean(), 1000, revs_per_segment=min(8.0, revs / 4))
        fig = plot_map(m, ymax=order_max, title=f"IAS angular spectrogram, {shaft} {label}")
        p = outdir / f"ias_spectrogram_{shaft}{label}.png"
        save_figure(fig, p, dpi=120)
        plt.close(fig)
        paths.append(p)
    cep = power_cepstrum(w - w.mean(), 1000.0)
    fig = plot_cepstrum(cep, qmax=3.0, title=f"IAS cepstrum (quefrency in rev), {shaft} {label}")
    p = outdir / f"ias_cepstrum_{shaft}{label}.png"
    save_figure(fig, p, dpi=120)
    plt.close(fig)
    paths.append(p)
    return paths


def _cfg_variant(cfg, start_rpm: float, end_rpm: float, revs: float, spall: bool = False,  # noqa: ANN001, ANN202
                 crack_m: float = 0.0):
    from geardyn.config.loader import parse_config

    d = cfg.model_dump(exclude_none=True)
    d["transmission"]["speed_law"].update(start_rpm=start_rpm, end_rpm=end_rpm,
                                          revolutions=revs)
    if spall:
        b = d["transmission"]["bearings"][0]
        b["outer_spall"] = {"angle_deg": spall if not isinstance(spall, bool) else 0.0,
                            "angular_length_deg": 360.0 / b["elements"] / 3, "depth_m": 100e-6}
    if crack_m > 0:
        low = next(g for g in d["gear_geometry"] if g["pair"] == "low")
        low["cracks"] = [{"gear": "b", "tooth": 0, "depth_m": crack_m, "angle_deg": 45.0}]
    return parse_config(d)


def seed002_figures(cfg, outdir: Path, nsc: bool = True) -> list[Path]:  # noqa: ANN001
    """The seed 002 figure set for the example transmission: ASC/NSC order spectra of the
    low-speed shaft IAS (Figs 10-11), NSC angular spectrogram (Fig 9), healthy vs outer-race
    spall (Fig 14) and vs root crack (Fig 16), cepstrum (Fig 19)."""
    import math

    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    from geardyn.bearings.frequencies import bearing_frequencies
    from geardyn.models.transmission.assembly import build_model, static_equilibrium
    from geardyn.models.transmission.simulate import simulate
    from geardyn.signal.cepstrum import power_cepstrum
    from geardyn.signal.spectra import angular_spectrogram, order_spectrum

    outdir.mkdir(parents=True, exist_ok=True)
    b0 = cfg.transmission.bearings[0]
    bpfo = bearing_frequencies(1.0, 0.0, b0.elements, b0.element_diameter_m,
                               b0.pitch_diameter_m).bpfo
    # mesh orders on the output shaft of the example (low stage 42/55, high stage 31/53)
    m_low = 55.0
    m_high = 55.0 * 53.0 / 42.0
    paths: list[Path] = []

    def spec(ds):  # noqa: ANN001, ANN202
        w = ias_angle_signal(ds, "output")
        return w, order_spectrum(w - w.mean(), 1000)

    def mark(ax, omax: float) -> None:  # noqa: ANN001
        for k in range(1, int(omax / bpfo) + 1):
            ax.axvline(k * bpfo, color="tab:green", lw=0.6, ls=":")
        for mo, c in ((m_low, "tab:red"), (m_high, "tab:purple")):
            ax.axvline(mo, color=c, lw=0.8, ls="--")
            for s in (-2, -1, 1, 2):
                ax.axvline(mo + s * bpfo, color=c, lw=0.5, ls=":")

    def save(fig, name: str) -> None:  # noqa: ANN001
        p = outdir / name
        save_figure(fig, p, dpi=110)
        plt.close(fig)
        paths.append(p)

    asc = simulate(_cfg_variant(cfg, 360.0, 430.0, 20.0))
    w_asc, s_asc = spec(asc)
    runs = {"ASC [360-430 rpm / 20 rev]": s_asc}
    if nsc:
        nsc_ds = simulate(_cfg_variant(cfg, 200.0, 900.0, 300.0))
        w_nsc, s_nsc = spec(nsc_ds)
        runs["NSC [200-900 rpm / 300 rev]"] = s_nsc
        m = angular_spectrogram(w_nsc - w_nsc.mean(), 1000, revs_per_segment=8.0)
        fig, ax = plt.subplots(figsize=(10, 4), constrained_layout=True)
        db = 20 * np.log10(np.maximum(m.values, m.values.max() * 1e-5))
        ax.pcolormesh(m.angle.values, m.order.values, db, shading="auto", cmap="viridis")
        ax.set_ylim(0, 150)
        ax.set_xlabel("low-speed shaft angle [rev] (speed 200 → 900 rpm)")
        ax.set_ylabel("order [ev/rev]")
        ax.set_title("low-speed shaft IAS angular spectrogram, NSC "
                     "(cf. Thibault et al. 2024, Fig 9)")
        save(fig, "transmission_nsc_spectrogram.png")
    fig, axs = plt.subplots(len(runs), 1, figsize=(10, 3.2 * len(runs)),
                            constrained_layout=True, squeeze=False)
    for ax, (name, s) in zip(axs[:, 0], runs.items(), strict=True):
        ax.semilogy(s.order.values, s.values, lw=0.6, color="0.2")
        mark(ax, 80)
        ax.set_xlim(0, 80)
        ax.set_title(f"low-speed shaft IAS order spectrum, {name} "
                     "(cf. Thibault et al. 2024, Figs 10-11)")
        ax.set_ylabel("amplitude [rad/s]")
    axs[-1, 0].set_xlabel("order [ev/rev of the low-speed shaft]; green: BPFO harmonics, "
                          "red/purple: low/high mesh ± BPFO")
    save(fig, "transmission_asc_vs_nsc.png")
    # faults (ASC): outer-race spall in the load direction, root crack on the 55-tooth wheel
    model = build_model(cfg)
    q = static_equilibrium(model, model.load_torque)
    nd = model.node_of(b0.at.shaft, b0.at.node)
    ang = math.degrees(math.atan2(q[6 * nd + 1], q[6 * nd]))
    _, s_sp = spec(simulate(_cfg_variant(cfg, 360.0, 430.0, 20.0, spall=ang)))
    _, s_cr = spec(simulate(_cfg_variant(cfg, 360.0, 430.0, 20.0, crack_m=0.001)))
    for name, s_f, title in (("spall", s_sp, "outer-race spall on the low-speed ball bearing "
                                                "(cf. Thibault et al. 2024, Fig 14)"),
                             ("crack", s_cr, "root crack 1 mm on the 55-tooth wheel "
                                             "(cf. Thibault et al. 2024, Fig 16)")):
        fig, ax = plt.subplots(figsize=(10, 3.5), constrained_layout=True)
        ax.semilogy(s_asc.order.values, s_asc.values, lw=0.6, color="tab:blue", label="healthy")
        ax.semilogy(s_f.order.values, s_f.values, lw=0.6, color="tab:red", alpha=0.8,
                    label=name)
        if name == "spall":
            mark(ax, 80)
        else:
            for k in range(1, 41):
                ax.axvline(k, color="0.7", lw=0.3)
        ax.set_xlim(0, 80)
        ax.legend()
        ax.set_title(f"low-speed shaft IAS, {title}")
        ax.set_xlabel("order [ev/rev]")
        save(fig, f"transmission_{name}.png")
    fig, ax = plt.subplots(figsize=(10, 3.5), constrained_layout=True)
    for s_w, lab in ((w_asc, "healthy"),):
        cep = power_cepstrum(s_w - s_w.mean(), 1000.0)
        ax.plot(cep.quefrency.values[5:3000], cep.values[5:3000], lw=0.6, label=lab)
    ax.set_xlabel("quefrency [rev of the low-speed shaft]")
    ax.set_title("IAS power cepstrum, ASC healthy")
    save(fig, "transmission_cepstrum.png")
    return paths
