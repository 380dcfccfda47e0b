"""IAS outputs of a transmission run (seed 002 §3.2-3.5): encoder simulation of each shaft
(1000 pulses/rev, 80 MHz, seed 002 eq 1 via :func:`geardyn.sensors.simulate_ias`), angle-domain
order spectra referred to a shaft, angular spectrogram, cepstrum, kinematic markers."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

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
    spec = order_spectrum(w - w.mean(), 1000)
    try:
        mk = markers(cfg, shaft)
    except Exception:  # noqa: BLE001 - markers are optional decoration
        mk = None
    paths = []
    fig = plot_spectrum(spec, mk, xmax=order_max,
                        title=f"IAS order spectrum, {shaft} shaft {label}")
    p = outdir / f"ias_spectrum_{shaft}{label}.png"
    fig.savefig(p, dpi=120)
    plt.close(fig)
    paths.append(p)
    revs = w.size / 1000
    if revs >= 8:
        m = angular_spectrogram(w - w.mean(), 1000, revs_per_segment=min(8.0, revs / 4))
        fig = plot_map(m, ymax=order_max, title=f"IAS angular spectrogram, {shaft} {label}")
        p = outdir / f"ias_spectrogram_{shaft}{label}.png"
        fig.savefig(p, dpi=120)
        plt.close(fig)
        paths.append(p)
    cep = power_cepstrum(w - w.mean(), 1000.0)
    fig = plot_cepstrum(cep, qmax=3.0, title=f"IAS cepstrum (quefrency in rev), {shaft} {label}")
    p = outdir / f"ias_cepstrum_{shaft}{label}.png"
    fig.savefig(p, dpi=120)
    plt.close(fig)
    paths.append(p)
    return paths
