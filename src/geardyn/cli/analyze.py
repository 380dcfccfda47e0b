"""``geardyn analyze SIGNAL --config CONFIG.toml --speed LINK=RPM --out report/``.

Reads a signal (WAV/CSV/NumPy/NetCDF), resamples it to the angle of the reference shaft (from a
constant speed or tacho/encoder pulses), and writes: an annotated order spectrum, a spectrogram,
the TSA of the reference shaft, its cepstrum, an indicator table and the marker table (figures
as PNG, tables as CSV, the order spectrum as NetCDF). With ``--ias-ppr R`` the SIGNAL file holds
encoder edge times [s] of the reference shaft instead, and the analysed signal is its IAS by
the elapsed-time method (Thibault et al. 2024, eq 1), optionally latched on a ``--clock`` counter.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd
import typer

from geardyn.cli import app
from geardyn.cli.common import (
    check_number,
    check_report_dir,
    console,
    friendly_errors,
    parse_assignments,
    report_folder,
)
from geardyn.cli.long_record import (
    LONG_SAMPLES,
    block_spectrogram,
    central_excerpt,
    chunked_indicators,
    resample_chunked,
)
from geardyn.config import load_config
from geardyn.errors import InputError
from geardyn.kinematics import analyze_kinematics, characteristic_frequencies

if TYPE_CHECKING:
    import xarray as xr

    from geardyn.kinematics import CharacteristicFrequencies


def _choose_spr(max_mesh_order: float, fs: float, f_ref_max: float) -> int:
    """Samples per revolution keeping the sensor's whole band: fs/f_ref at the highest speed
    (the order spectrum then reaches the Nyquist frequency, where housing resonances and
    bearing lines live, not only the meshes), rounded up to a power of 2, at least 16.
    ``max_mesh_order`` is kept for the callers; the mesh range lies inside that band or is
    warned about (beyond the valid orders)."""
    del max_mesh_order
    return int(2 ** math.ceil(math.log2(max(16.0, fs / f_ref_max))))


def _reference(speeds: dict[str, float], reference: str | None, cfg) -> str:
    if speeds:
        return next(iter(speeds))
    ref = reference or (next(iter(cfg.input_speeds_rpm)) if cfg.input_speeds_rpm else None)
    if ref is None:
        raise InputError("--reference: name the link that carries the tacho/encoder")
    return ref


@app.command("analyze")
@friendly_errors
def analyze(
    signal: Path = typer.Argument(..., help="signal file: .csv/.tsv, .wav, .npy/.npz, .mat, "
                                  ".tdms, .uff, .mf4, .h5, .nc (docs/measured.md)"),
    config: Path = typer.Option(..., "--config", "-c", help="mechanism TOML (kinematics)"),
    speed: list[str] = typer.Option(
        None, "--speed", "-s", help="constant speed LINK=RPM of the reference shaft"
    ),
    tacho: Path | None = typer.Option(
        None, "--tacho", help="pulse-time file [s] of the reference shaft (tacho or encoder)"
    ),
    pulses_per_rev: int = typer.Option(1, "--ppr", help="pulses per revolution of --tacho"),
    reference: str | None = typer.Option(
        None, "--reference", "-r", help="reference link of --tacho/--ias-ppr (default: first "
        "input of the config)"
    ),
    ias_ppr: int | None = typer.Option(
        None, "--ias-ppr", help="SIGNAL is encoder edge times [s] with this many pulses/rev: "
        "analyse the IAS (elapsed-time method, Thibault et al. 2024, eq 1)"
    ),
    clock: float | None = typer.Option(
        None, "--clock", help="counter clock [Hz] latching the encoder edges (--ias-ppr)"
    ),
    fs: float | None = typer.Option(None, "--fs", help="sample rate [Hz] if not in the file"),
    channel: str | None = typer.Option(None, "--channel", help="channel name or index"),
    sensitivity: str | None = typer.Option(
        None, "--sensitivity", help="transducer sensitivity, e.g. '100 mV/g' (file values in V "
        "unless the file states its units)"),
    full_scale: str | None = typer.Option(
        None, "--full-scale", help="audio files: the quantity at digital full scale, e.g. "
        "'10 V'"),
    samples_per_rev: int | None = typer.Option(
        None, "--samples-per-rev", help="angular samples per revolution of the reference "
        "shaft after order tracking (orders up to half of it are valid; default: from the "
        "sample rate and the highest mesh order)"),
    out: Path = typer.Option(Path("report"), "--out", "-o", help="output directory (written "
                             "whole: an existing non-empty one needs --force)"),
    force: bool = typer.Option(False, "--force", help="replace an existing --out folder "
                               "(its earlier files are removed, so no stale figure stays)"),
) -> None:
    """Order spectrum (annotated), spectrogram, TSA, cepstrum and indicators of a signal."""
    check_number(fs, "--fs", gt=0, le=1e9, unit="Hz")
    check_number(clock, "--clock", gt=0, le=1e12, unit="Hz")
    check_number(pulses_per_rev, "--ppr", ge=1, le=1e6)
    check_number(ias_ppr, "--ias-ppr", ge=1, le=1e6)
    check_number(samples_per_rev, "--samples-per-rev", ge=4, le=1 << 16)
    check_report_dir(out, "--out", force)
    cfg = load_config(config)
    kin = analyze_kinematics(cfg)
    speeds = parse_assignments(speed, "--speed")
    result = _open_result(signal)
    if result is None and getattr(cfg, "measurement", None) is not None and ias_ppr is None:
        result = _mapped_record(signal, cfg, speeds, tacho)
    sim_channel = ref_angle = None
    if result is not None:
        sim_channel, ref_angle = _result_channel(result, channel, reference, fs, speeds, tacho,
                                                 ias_ppr, signal)
        reference = sim_channel.shaft
    if len(speeds) > 1:
        raise InputError("--speed: give the speed of one reference link only")
    for link, v in speeds.items():
        if v <= 0:
            raise InputError(f"--speed: {link} speed must be > 0 rpm, got {v:g}")
    source = _ias_source(sim_channel, ref_angle, signal, speeds, reference, cfg, ias_ppr, clock)
    if source is not None:
        sig = _ias_on_angle(kin, *source)
    else:
        sig = _signal_on_angle(kin, cfg, signal, sim_channel, ref_angle, speeds, reference, fs,
                               channel, sensitivity, full_scale, tacho, pulses_per_rev,
                               samples_per_rev)
    figs, rows, spec, markers = _report(cfg, sig)
    from geardyn.checkpoint import write_atomic, write_text
    from geardyn.plotting import save_figure

    with report_folder(out) as folder:  # the whole folder or nothing, no stale figures
        for name, fig in figs.items():
            save_figure(fig, folder / name, dpi=110)
        write_text(folder / "indicators.csv", pd.DataFrame(rows).to_csv(index=False))
        write_text(folder / "markers.csv", markers.to_csv(index=False))
        write_atomic(folder / "order_spectrum.nc",
                     lambda tmp: spec.to_netcdf(tmp, engine="scipy"))
    console.print(
        f"[bold]{sig.label}[/]: reference '{sig.ref}' {sig.rpm:.6g} rpm; "
        f"{sig.revolutions:.1f} revs at {sig.spr} samples/rev (orders ≤ {sig.max_valid:.4g} "
        "valid)"
    )
    top = spec.where(spec["order"] > 0.5, 0).to_series().nlargest(5)
    console.print("largest orders: " + ", ".join(f"{o:.4g} ({a:.3g})" for o, a in top.items()))
    console.print(f"wrote {', '.join(sorted(figs))}, indicators.csv, markers.csv, "
                  f"order_spectrum.nc to {out}/")


@dataclass
class AngleSignal:
    """The analysed signal on the angle grid of the reference shaft and what the report
    needs of it (one per record: an encoder IAS or a time signal resampled to the angle)."""

    ref: str
    """Reference link (order 1)."""
    rpm: float
    """Mean speed of the reference [rpm]."""
    freqs: CharacteristicFrequencies
    """Characteristic frequencies at that speed, orders of ``ref``."""
    spr: int
    """Angular samples per revolution."""
    x_ang: np.ndarray
    """The signal on the angle grid."""
    raw: np.ndarray
    """The signal as recorded (its raw indicators)."""
    max_valid: float
    """Highest valid order."""
    revolutions: float
    """Revolutions of ``ref`` on the grid."""
    start: int
    """First grid sample at a whole revolution (TSA start)."""
    spectrogram: xr.DataArray
    order_map: xr.DataArray | None
    """Order–speed map of a run-up / run-down (None at a steady speed)."""
    samples: tuple
    """(values, time [s], reference angle [rad]) for the per-component TSAs."""
    label: str
    units: str
    """The channel's unit on every amplitude axis ("rad/s" for an IAS)."""
    fs: float | None = None
    """Sample rate [Hz] of a time signal (None for an IAS)."""


def _ias_source(sim_channel, ref_angle, signal: Path, speeds: dict[str, float],  # noqa: ANN001
                reference: str | None, cfg, ias_ppr: int | None,  # noqa: ANN001
                clock: float | None) -> tuple | None:
    """An IAS to analyse, (ias [rad/s], samples per rev, samples, label, reference link): a
    simulated encoder channel, or encoder edge times (``--ias-ppr``) by the elapsed-time
    method (Thibault et al. 2024, eq 1); None for a time signal."""
    from geardyn.sensors import elapsed_time_ias
    from geardyn.signal_io import read_pulse_times

    if sim_channel is not None and sim_channel.sampling == "angle":  # simulated encoder IAS
        label = (f"channel '{sim_channel.name}' of {signal.name} "
                 f"({sim_channel.attrs.get('long_name', 'IAS')})")
        return (sim_channel.values, int(sim_channel.pulses_per_rev or 1),
                (sim_channel.values, sim_channel.time, ref_angle), label, sim_channel.shaft)
    if ias_ppr is None:
        return None
    if ias_ppr < 1:
        raise InputError(f"--ias-ppr: pulses per revolution must be >= 1, got {ias_ppr}")
    ref = _reference(speeds, reference, cfg)
    try:
        edges = read_pulse_times(signal)
    except InputError as exc:
        raise InputError(f"--ias-ppr: SIGNAL must hold encoder edge times [s]: {exc}") from None
    meas = elapsed_time_ias(edges, ias_ppr, clock)
    label = f"IAS of '{ref}' ({ias_ppr} pulses/rev"
    label += f", {clock:g} Hz clock)" if clock else ", ideal clock)"
    return meas.ias, int(ias_ppr), (meas.ias, meas.time, meas.angle), label, ref


def _ias_on_angle(kin, ias: np.ndarray, spr: int, samples: tuple, label: str,  # noqa: ANN001
                  ref: str) -> AngleSignal:
    """An IAS: one sample per encoder interval, the angle grid itself."""
    from geardyn.signal import angular_spectrogram

    rpm = 60.0 * float(np.mean(ias)) / (2 * np.pi)
    revolutions = ias.size / spr
    spectrogram = angular_spectrogram(
        ias, spr, revs_per_segment=max(1.0, min(8.0, revolutions / 8)),
        speed=60.0 * ias / (2 * np.pi),
    )
    return AngleSignal(ref, rpm, characteristic_frequencies(kin, {ref: rpm}, order_reference=ref),
                       spr, ias, ias, spr / 2.0, revolutions, 0, spectrogram, None, samples,
                       label, "rad/s")


def _pulses_and_speed(cfg, signal: Path, sim_channel, ref_angle, speeds: dict[str, float],  # noqa: ANN001
                      reference: str | None, fs: float | None, channel: str | None,
                      sensitivity: str | None, full_scale: str | None, tacho: Path | None,
                      pulses_per_rev: int) -> tuple:
    """The time record, its tacho pulse times [s] (None at a stated constant speed), the
    reference link and its mean speed [rpm], after the checks of the record against the
    speed source (pulses within the record, speeds that agree, at least one revolution)."""
    from geardyn.signal_io import SignalRecord, read_pulse_times, read_signal

    if sim_channel is not None:
        rec = SignalRecord(sim_channel.values, float(sim_channel.sample_rate_hz),
                           sim_channel.name, sim_channel.units)
        pulses = None
        ref = sim_channel.shaft
        speeds = {ref: 60.0 * float(np.mean(np.gradient(ref_angle, sim_channel.time)))
                  / (2 * np.pi)}
    else:
        rec = read_signal(signal, fs, channel, sensitivity=sensitivity,
                          full_scale=full_scale)
        pulses = read_pulse_times(tacho) if tacho is not None else None
    if sim_channel is None and pulses is None and rec.pulse_times is not None:
        if speeds:  # --speed with a tacho stored in the file: they must agree
            tp = rec.pulse_times
            check_speed_agrees(speeds, 60.0 * (tp.size - 1) / max(pulses_per_rev, 1)
                               / (tp[-1] - tp[0]), pulses_per_rev)
        else:
            pulses = rec.pulse_times
    if pulses is None and not speeds:
        raise InputError("--speed or --tacho: the reference shaft speed is needed")
    ref = _reference(speeds, reference, cfg)
    if pulses is None:
        rpm = speeds[ref]
        revs = rpm / 60.0 * rec.x.shape[0] / rec.fs
        if revs < 1:
            raise InputError(f"--speed: at {rpm:g} rpm the record ({rec.x.shape[0] / rec.fs:g} "
                             f"s) covers {revs:.3g} revolutions of '{ref}'; at least one "
                             "is needed (check the speed unit: rpm)")
        return rec, pulses, ref, rpm
    if pulses_per_rev < 1:
        raise InputError(f"--ppr: pulses per revolution must be >= 1, got {pulses_per_rev}")
    rpm = 60.0 * (pulses.size - 1) / pulses_per_rev / (pulses[-1] - pulses[0])
    if sim_channel is None:
        from geardyn.io.speed import trim_pulses

        origin = "--tacho" if tacho is not None else f"pulse_times of {signal.name}"
        duration = (rec.x.size - 1) / rec.fs
        kept = trim_pulses(pulses, 0.0, duration)  # a longer tacho: trimmed
        tol = max(2.0 * float(np.max(np.diff(pulses))), 0.02 * duration)
        if pulses[0] < -tol or pulses[-1] > duration + tol:
            console.print(
                f"[yellow]warning:[/] {origin}: the pulses span {pulses[0]:.6g}–"
                f"{pulses[-1]:.6g} s, the signal 0–{duration:.6g} s ({rec.x.size} "
                f"samples at {rec.fs:g} Hz): {kept.size} of {pulses.size} pulses "
                "kept; if the tacho and the signal were recorded together, check "
                "--fs")
        pulses = kept
        if pulses.size < 3:
            raise InputError(f"{origin}: fewer than 3 pulses fall within the signal "
                             f"(0–{(rec.x.size - 1) / rec.fs:.6g} s)")
        rpm = 60.0 * (pulses.size - 1) / pulses_per_rev / (pulses[-1] - pulses[0])
        check_tacho_span(pulses, rec.x.size, rec.fs, origin)
        check_speed_agrees(speeds, rpm, pulses_per_rev)
    return rec, pulses, ref, rpm


def _signal_on_angle(kin, cfg, signal: Path, sim_channel, ref_angle,  # noqa: ANN001
                     speeds: dict[str, float], reference: str | None, fs: float | None,
                     channel: str | None, sensitivity: str | None, full_scale: str | None,
                     tacho: Path | None, pulses_per_rev: int,
                     samples_per_rev: int | None) -> AngleSignal:
    """A time signal resampled to the angle of the reference shaft (order tracking; chunked
    for a long record), its spectrogram and, in a run-up / run-down, its order–speed map."""
    from geardyn.signal import angular_spectrogram, resample_to_angle, stft
    from geardyn.signal.resample import angle_from_pulses

    rec, pulses, ref, rpm = _pulses_and_speed(cfg, signal, sim_channel, ref_angle, speeds,
                                              reference, fs, channel, sensitivity, full_scale,
                                              tacho, pulses_per_rev)
    freqs = characteristic_frequencies(kin, {ref: rpm}, order_reference=ref)
    max_mesh = float(freqs.meshes["mesh_order"].max()) if len(freqs.meshes) else 50.0
    long = sim_channel is None and rec.x.shape[0] > LONG_SAMPLES
    if sim_channel is not None:
        angle = ref_angle
        f_ref_max = float(np.max(np.gradient(ref_angle, sim_channel.time))) / (2 * np.pi)
    elif pulses is None:
        angle = None if long else 2 * np.pi * rpm / 60.0 * np.arange(rec.x.size) / rec.fs
        f_ref_max = rpm / 60.0
    else:
        angle = None
        f_ref_max = float(np.max(1.0 / np.diff(pulses))) / pulses_per_rev
    spr = samples_per_rev or _choose_spr(max_mesh, rec.fs, f_ref_max)
    if long:  # bounded memory: chunked order tracking (cli.long_record)
        angle_of_time, i0, i1 = _angle_law(rpm, pulses, pulses_per_rev, rec.fs,
                                           rec.x.shape[0])
        sig = resample_chunked(rec.x, rec.fs, angle_of_time, spr, i0, i1)
    elif angle is not None:
        sig = resample_to_angle(rec.x, rec.fs, angle, samples_per_rev=spr)
    else:
        sig = resample_to_angle(rec.x, rec.fs, pulse_times=pulses,
                                pulses_per_rev=pulses_per_rev, samples_per_rev=spr)
    order_map = None
    if (pulses is not None or sim_channel is not None) and sig.revolutions >= 16:
        rpm_k = 60.0 / (spr * np.gradient(sig.time))
        if rpm_k.max() > 1.05 * rpm_k.min():  # run-up / run-down: order–speed map
            order_map = angular_spectrogram(
                sig.x, spr, revs_per_segment=max(1.0, min(8.0, sig.revolutions / 16)),
                speed=rpm_k,
            )
    start = (-int(round(sig.angle0 / (2 * np.pi) * spr))) % spr
    nper = int(2 ** math.floor(math.log2(max(16, min(rec.x.size // 8, rec.fs)))))
    label = f"{signal.name} ({rec.x.size} samples at {rec.fs:g} Hz)"
    if long:
        spectrogram = block_spectrogram(rec.x, rec.fs, nper)
        e0, e1 = central_excerpt(i0, i1)
        t_e = np.arange(e0, e1) / rec.fs
        samples = (np.asarray(rec.x[e0:e1], dtype=float), t_e, angle_of_time(t_e))
        console.print(f"[yellow]note:[/] long record: per-component indicators from its "
                      f"central {t_e[0]:.6g}–{t_e[-1]:.6g} s ({e1 - e0} samples); order "
                      "spectrum, TSA and raw indicators from the whole record")
    else:
        spectrogram = stft(rec.x, rec.fs, nperseg=nper)
        t_s = np.arange(rec.x.size) / rec.fs
        if angle is not None:
            samples = (rec.x, t_s, angle)
        else:
            inside = (t_s >= pulses[0]) & (t_s <= pulses[-1])
            samples = (rec.x[inside], t_s[inside],
                       angle_from_pulses(pulses, t_s[inside], pulses_per_rev))
    if sim_channel is not None:
        label = f"channel '{sim_channel.name}' of {label}"
    units = (sim_channel.units if sim_channel is not None else rec.units) or "unit not stated"
    return AngleSignal(ref, rpm, freqs, spr, sig.x, rec.x, sig.max_valid_order,
                       sig.revolutions, start, spectrogram, order_map, samples, label, units,
                       rec.fs)


def _report(cfg, sig: AngleSignal) -> tuple[dict, list[dict], xr.DataArray, pd.DataFrame]:  # noqa: ANN001
    """Figures (name → figure), indicator rows, order spectrum and marker table of ``sig``:
    the order spectrum around the meshes and over the sensor's band, the spectrogram, the
    order–speed map and waterfall of a run-up, the TSA of the reference and of each component,
    the power cepstrum; warns when the mesh orders exceed the valid range."""
    from geardyn.signal import (
        order_spectrum,
        power_cepstrum,
        signal_indicators,
        spectral_markers,
        tsa,
    )
    from geardyn.signal.plots import (
        plot_cepstrum,
        plot_map,
        plot_spectrum,
        plot_tsa,
        plot_waterfall,
    )

    ref, spr, units, max_valid = sig.ref, sig.spr, sig.units, sig.max_valid
    if sig.revolutions < 1:
        raise InputError(f"{sig.label}: the record covers {sig.revolutions:.2f} revolutions of "
                         f"'{ref}'; at least one is needed (record longer or choose a faster "
                         "shaft)")
    max_mesh = float(sig.freqs.meshes["mesh_order"].max()) if len(sig.freqs.meshes) else 50.0
    if max_mesh > max_valid:
        console.print(
            f"[yellow]warning:[/] mesh order {max_mesh:.4g} is beyond the valid order range "
            f"(≤ {max_valid:.4g}); increase --samples-per-rev (or the encoder resolution)"
        )
    spec = order_spectrum(sig.x_ang, spr)
    spec.attrs["units"] = units
    markers = spectral_markers(sig.freqs)
    xmax = min(max_valid, spr / 2, 3.3 * max_mesh)
    figs = {
        "order_spectrum.png": plot_spectrum(
            spec, markers, xmax, f"Order spectrum of {sig.label} around the meshes, orders of "
            f"'{ref}' at {sig.rpm:.6g} rpm", units=units)
    }
    if sig.fs is not None:  # the whole band the sensor records, up to its Nyquist frequency
        from geardyn.diagnosis.report import sensor_band, sensor_band_figure

        band = sensor_band(min(max_valid, float(spec["order"].values[-1])), sig.rpm / 60.0,
                           sig.fs)
        figs["order_spectrum_band.png"] = sensor_band_figure(spec, None, band, markers, ref)
    # spectrograms over the whole recorded band (Nyquist), not an order range below it
    sig.spectrogram.attrs["units"] = units
    figs["spectrogram.png"] = plot_map(sig.spectrogram, title="Spectrogram", units=units)
    if sig.order_map is not None:
        sig.order_map.attrs["units"] = units
        omax = min(max_valid, float(sig.order_map["order"].values[-1]))
        figs["order_speed_map.png"] = plot_map(sig.order_map, ymax=omax,
                                               title="Order–speed map", units=units)
        figs["waterfall.png"] = plot_waterfall(sig.order_map, ymax=omax, title="Waterfall")
    raw = sig.raw
    raw_indicators = (chunked_indicators(raw) if raw.shape[0] > LONG_SAMPLES
                      else signal_indicators(raw))
    rows = [{"signal": "raw", "component": "", "kind": "", **raw_indicators}]
    x_ang, start = sig.x_ang, sig.start
    if x_ang.size - start >= spr:
        avg = tsa(x_ang[start:], spr)
        figs["tsa.png"] = plot_tsa(avg, f"TSA of '{ref}' ({(x_ang.size - start) // spr} revs)",
                                   units=units)
        rows.append({"signal": f"TSA {ref} (reference grid)", "component": "", "kind": "",
                     **signal_indicators(avg)})
    rows += _component_rows(cfg, ref, sig.samples, sig.label, figs, units)
    cep = power_cepstrum(x_ang - x_ang.mean(), spr)
    figs["cepstrum.png"] = plot_cepstrum(cep, qmax=min(5.0, sig.revolutions / 2),
                                         title="Power cepstrum (quefrency in revolutions)")
    return figs, rows, spec, markers


def _angle_law(rpm: float, pulses: np.ndarray | None, pulses_per_rev: int, fs: float,
               n: int):  # noqa: ANN202 - (angle of time, first sample, end sample)
    """The reference angle [rad] as a function of time [s] (constant speed, or the pulse
    spline of :func:`geardyn.signal.resample.angle_from_pulses`) and the sample range it
    covers."""
    from geardyn.signal.resample import angle_from_pulses

    if pulses is None:
        w = 2 * np.pi * rpm / 60.0
        return (lambda t: w * t), 0, n
    i0 = max(0, math.ceil(pulses[0] * fs))
    i1 = min(n, math.floor(pulses[-1] * fs) + 1)
    return (lambda t: angle_from_pulses(pulses, t, pulses_per_rev)), i0, i1


def check_tacho_span(pulses: np.ndarray, n: int, fs: float, origin: str) -> None:
    """A tacho must cover the record: at each end, the part of the signal without pulses (or
    the pulses beyond the signal) may not exceed two pulse intervals or 2 % of the record.
    A tacho covering a quarter of the signal, or a wrong --fs stretching the signal, is
    refused rather than analysed silently on part of the data."""
    duration = (n - 1) / fs
    tol = max(2.0 * float(np.max(np.diff(pulses))), 0.02 * duration)
    gap_start, gap_end = float(pulses[0]), duration - float(pulses[-1])
    if abs(gap_start) > tol or abs(gap_end) > tol:
        lo, hi = max(0.0, float(pulses[0])), min(duration, float(pulses[-1]))
        share = max(0.0, hi - lo) / duration if duration > 0 else 0.0
        raise InputError(
            f"{origin}: the pulses span {pulses[0]:.6g}–{pulses[-1]:.6g} s but the signal spans "
            f"0–{duration:.6g} s ({n} samples at {fs:g} Hz; the pulses cover {share:.0%} of it); "
            "a tacho must cover the whole record (tolerance "
            f"{tol:.3g} s at each end): crop the signal to the pulses, or check --fs")


def check_speed_agrees(speeds: dict[str, float], tacho_rpm: float, pulses_per_rev: int) -> None:
    """``--speed`` given with a tacho must agree with the tacho's mean speed (2 %)."""
    for link, rpm in speeds.items():
        if abs(rpm - tacho_rpm) > 0.02 * tacho_rpm:
            raise InputError(
                f"--speed: {link}={rpm:g} rpm contradicts the tacho's mean speed "
                f"{tacho_rpm:.6g} rpm (--ppr {pulses_per_rev}; tolerance 2 %); drop --speed "
                "(the tacho gives the speed) or check --ppr")


def _open_result(path: Path):  # noqa: ANN202 - xarray.Dataset | None
    """The file as a geardyn simulation result (docs/results.md), or None for other files."""
    if path.suffix.lower() not in (".nc", ".netcdf", ".h5") or not path.is_file():
        return None
    import xarray as xr

    from geardyn.results import is_result

    try:
        ds = xr.open_dataset(path)
    except Exception:  # noqa: BLE001 - not NetCDF4/3: read_signal reports it
        return None
    if not is_result(ds):
        ds.close()
        return None
    return ds.load()


def _mapped_record(path: Path, cfg, speeds: dict, tacho: Path | None):  # noqa: ANN001, ANN202
    """A measured file through the config's [measurement] mapping (geardyn.io.read_record):
    the result layout with the shaft angles from its tacho, encoder, profile or speed."""
    from geardyn.io import read_record

    if speeds or tacho is not None:
        raise InputError("--speed/--tacho: the config's [measurement] section maps the record "
                         "and gives its speed (tacho/encoder channel, profile_rpm or "
                         "speed_rpm); drop these options or the section")
    ds = read_record(path, cfg=cfg)
    if "angle" not in ds:
        raise InputError(f"{path}: the [measurement] mapping gives no speed; add a tacho or "
                         "encoder channel, profile_rpm or speed_rpm")
    return ds


def _result_channel(ds, channel: str | None, reference: str | None, fs: float | None,  # noqa: ANN001
                    speeds: dict, tacho: Path | None, ias_ppr: int | None, path: Path):
    """The channel to analyse in a simulation result and the angle [rad] of its reference
    shaft at each of its samples (sign handled: the shaft turns forward)."""
    from geardyn.results import channel as get_channel
    from geardyn.results import channels, shaft_angle

    names = channels(ds)
    if not names:
        raise InputError(f"{path}: the simulation result has no sensor channel; add "
                         "[[sensors]] to the config and simulate again")
    if channel is None and ds.attrs.get("model") == "measured":  # a tacho is no signal
        signals = [n for n in names if get_channel(ds, n).kind != "tacho"]
        names = signals if len(signals) == 1 else names
    if channel is None:
        if len(names) > 1:
            raise InputError(f"--channel: {path} holds {len(names)} channels; choose one of: "
                             f"{', '.join(names)}")
        channel = names[0]
    ch = get_channel(ds, channel)
    if ch.kind == "tacho":
        raise InputError(f"--channel: '{ch.name}' is a tacho (pulse times), a speed reference "
                         f"rather than a signal; choose one of: "
                         f"{', '.join(n for n in names if n != ch.name)}")
    if speeds or tacho is not None or ias_ppr is not None:
        raise InputError("--speed/--tacho/--ias-ppr: a simulation result carries its shaft "
                         "angles and sensor settings; drop these options")
    if fs is not None and ch.sample_rate_hz is not None and abs(fs - ch.sample_rate_hz) > \
            1e-9 * ch.sample_rate_hz:
        raise InputError(f"--fs: {fs:g} Hz contradicts the channel's {ch.sample_rate_hz:g} Hz")
    if reference is not None and reference != ch.shaft:
        ch.shaft = reference
    t, th = shaft_angle(ds, ch.shaft)
    if np.mean(np.diff(th)) < 0:
        th = -th
    if ch.sampling == "time" and ds.attrs.get("model") == "measured":  # the speed's span
        inside = (ch.time >= t[0]) & (ch.time <= t[-1])
        ch.values, ch.time = ch.values[inside], ch.time[inside]
    ref_angle = np.interp(ch.time, t, th)
    if ch.sampling == "time" and not np.all(np.diff(ref_angle) > 0):
        raise InputError(f"channel '{ch.name}': shaft '{ch.shaft}' stops or turns backwards "
                         "during the record; crop the run (status: "
                         f"{ds.attrs.get('status', '?')})")
    return ch, ref_angle


def _component_rows(cfg, ref: str, samples, label: str, figs: dict,  # noqa: ANN001
                    units: str = "") -> list[dict]:
    """Indicators of every shaft, wheel, planetary member and bearing from the kinematics
    (:func:`geardyn.diagnosis.features.extract_features`: TSA on each shaft's own angle, sign
    handled, difference signals without every mesh of the shaft); one TSA figure per shaft."""
    from geardyn.diagnosis.components import machine_components
    from geardyn.diagnosis.features import extract_features
    from geardyn.signal.plots import plot_tsa

    try:
        comps = machine_components(cfg, ref)
    except InputError as exc:  # e.g. a 2-DOF mechanism: the reference alone fixes no ratio
        console.print(f"[yellow]per-component indicators skipped:[/] {exc}")
        return []
    x, t, ang = samples
    feats = extract_features(np.asarray(x, float), np.asarray(t, float), np.asarray(ang, float),
                             comps, channel=label, n_blocks=1)
    for note in feats.notes:
        console.print(f"[yellow]note:[/] {note}")
    for name, da in feats.tsa.items():
        kind = comps[name].kind if name in {c.name for c in comps.items} else ""
        if kind == "shaft":
            safe = "".join(ch if ch.isalnum() or ch in "-_" else "_" for ch in name)
            figs[f"tsa_{safe}.png"] = plot_tsa(np.asarray(da.values), f"TSA of shaft '{name}' "
                                               "(own angle)", units=units or None)
    wide = feats.table.pivot_table(index=["component", "kind"], columns="indicator",
                                   values="value", aggfunc="median").reset_index()
    return [{"signal": f"TSA {r['component']}", **r} for r in wide.to_dict("records")]
