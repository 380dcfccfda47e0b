"""Result layout (docs/results.md) and simulated sensors (``[[sensors]]``).

References: the accelerance of a single-DOF mode (closed form), the seed 004 sun/carrier ratio
(5.36842, Table 6-2 tooth numbers), the planet-pass window of seed 003 eqs 4.10-4.12, the
elapsed-time IAS of seed 002 eq 1 (exact for a constant speed), action–reaction of bearing
forces, and bitwise determinism for a given seed.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import geardyn
from geardyn import results
from geardyn.cli import app
from geardyn.config.loader import parse_config
from geardyn.errors import ConfigError, InputError
from geardyn.run import add_sensors, run_simulation
from geardyn.sensors.planet_pass import planet_pass_windows
from geardyn.sensors.transfer import apply_transfer_path

runner = CliRunner()

RING_ACC = {"name": "ring_acc", "kind": "accelerometer", "location": "ring",
            "sample_rate_hz": 5000.0, "noise_rms": 0.01,
            "transfer_path": [{"frequency_hz": 1200.0, "damping_ratio": 0.05,
                               "modal_mass_kg": 50.0}]}
CARRIER_ENC = {"name": "carrier_enc", "kind": "encoder", "shaft": "carrier",
               "pulses_per_rev": 1000, "clock_hz": 80e6}
SUN_TACHO = {"name": "sun_tacho", "kind": "tacho", "shaft": "sun"}


def _reclaimer(examples_dir, sensors, t_end=1.5):
    d = geardyn.load_config(examples_dir / "planetary_reclaimer.toml").model_dump(
        exclude_none=True)
    d["planetary_dynamics"]["simulation"]["t_end_s"] = t_end
    d["sensors"] = sensors
    return parse_config(d)


@pytest.mark.parametrize("ratio", [1.0, 0.1, 3.0])
def test_transfer_path_matches_single_dof_accelerance(ratio):
    """Steady response to F sin(2πft): |a| = F |H(f)|, H = s²/(m(s² + 2ζωs + ω²)) (closed form;
    at resonance 1/(2ζm)). Tolerance 1 % (pre-warped bilinear transform at fs = 40 f_n)."""
    fn, zeta, m, fs = 500.0, 0.05, 2.0, 20000.0
    f = ratio * fn
    t = np.arange(int(4.0 * fs)) / fs
    a = apply_transfer_path(np.sin(2 * np.pi * f * t), fs,
                            [{"frequency_hz": fn, "damping_ratio": zeta, "modal_mass_kg": m}])
    w, wn = 2 * np.pi * f, 2 * np.pi * fn
    h = w**2 / (m * math.hypot(wn**2 - w**2, 2 * zeta * wn * w))
    steady = a[t > 2.0]
    amp = 0.5 * (steady.max() - steady.min())
    assert amp == pytest.approx(h, rel=0.01)
    if ratio == 1.0:
        assert h == pytest.approx(1 / (2 * zeta * m))


def test_transfer_path_rejects_mode_above_nyquist():
    with pytest.raises(InputError, match="frequency_hz"):
        apply_transfer_path(np.ones(100), 1000.0, [{"frequency_hz": 600.0}])


def test_planet_pass_windows_seed003():
    """Seed 003 eqs 4.10-4.12 (centred gate): planet n has weight 1 at carrier angle
    sensor + ψ_n + π/N, the others 0; the lobes tile the carrier revolution."""
    n, sensor = 3, 0.3
    psi = 2 * np.pi * np.arange(n) / n
    th = sensor + psi + np.pi / n
    w = planet_pass_windows(th, n, psi, sensor)
    assert w == pytest.approx(np.eye(n), abs=1e-12)
    grid = np.linspace(0, 2 * np.pi, 3001)
    ww = planet_pass_windows(grid, n, psi, sensor)
    assert np.all((ww > 0).sum(axis=0) <= 1)  # one planet in view at a time


def test_layout_and_sensors_planetary(examples_dir):
    """Seed 004 gearbox with a ring accelerometer, a carrier encoder and a sun tacho."""
    cfg = _reclaimer(examples_dir, [RING_ACC, CARRIER_ENC, SUN_TACHO], t_end=4.0)
    ds = run_simulation(cfg, seed=3)
    assert results.is_result(ds) and ds.attrs["model"] == "planetary"
    assert ds.attrs["status"] == "ok" and ds.attrs["seed"] == 3
    assert ds.attrs["reference_shaft"] == "sun"
    assert {"sun", "carrier", "motor", "planet1"} <= set(results.shafts(ds))
    for v, u in (("angle", "rad"), ("speed", "rad/s"), ("speed_rpm", "rpm"),
                 ("mesh_force", "N")):
        assert ds[v].attrs["units"] == u
    # rigid-body kinematics: sun/carrier speed ratio = 1 + 83/19 = 5.36842 (seed 004 Table 6-2)
    late = ds.time > 1.0
    w = ds.speed.where(late, drop=True)
    ratio = float(w.sel(shaft="sun").mean() / w.sel(shaft="carrier").mean())
    assert ratio == pytest.approx(1 + 83 / 19, rel=1e-4)
    rpm = ds.speed_rpm.sel(shaft="sun").values
    assert rpm == pytest.approx(ds.speed.sel(shaft="sun").values * 30 / np.pi)
    assert results.channels(ds) == ["ring_acc", "carrier_enc", "sun_tacho"]
    acc = results.channel(ds, "ring_acc")
    assert acc.units == "m/s^2" and acc.sampling == "time" and acc.shaft == "sun"
    assert acc.sample_rate_hz == 5000.0 and acc.values.size == acc.time.size
    enc = results.channel(ds, "carrier_enc")
    assert enc.units == "rad/s" and enc.sampling == "angle" and enc.shaft == "carrier"
    # elapsed-time IAS (seed 002 eq 1): mean of the samples = encoder angle / elapsed time
    dtheta = 2 * np.pi / 1000
    assert np.mean(enc.values[-50:]) == pytest.approx(
        50 * dtheta / (enc.time[-1] - enc.time[-51]), rel=1e-3)
    wc = float(np.interp(enc.time[-1], ds.time.values, ds.speed.sel(shaft="carrier").values))
    assert enc.values[-1] == pytest.approx(wc, rel=1e-3)
    tacho = results.channel(ds, "sun_tacho")
    ts, th = results.shaft_angle(ds, "sun")
    assert np.interp(tacho.values, ts, th) == pytest.approx(
        2 * np.pi * np.arange(tacho.values.size), abs=1e-6)


def test_sensors_are_deterministic_per_seed(examples_dir):
    cfg = _reclaimer(examples_dir, [RING_ACC], t_end=0.3)
    a = run_simulation(cfg, seed=7)["sensors.ring_acc"].values
    b = run_simulation(cfg, seed=7)["sensors.ring_acc"].values
    c = run_simulation(cfg, seed=8)["sensors.ring_acc"].values
    assert np.array_equal(a, b)
    # only the noise differs: the difference is white noise of the stated RMS (0.01 × √2)
    assert np.std(a - c) == pytest.approx(0.01 * math.sqrt(2), rel=0.05)


def test_bearing_accelerometer_planetary_and_bad_location(examples_dir):
    acc = {"name": "sun_brg", "kind": "accelerometer", "location": "sun", "direction": "x"}
    ds = run_simulation(_reclaimer(examples_dir, [acc], t_end=0.2), seed=0)
    ch = results.channel(ds, "sun_brg")
    assert ch.units == "N"  # no transfer path: the bearing force itself
    f = ds.bearing_force.sel(bearing="sun.bearing.x").values
    assert ch.values == pytest.approx(np.interp(ch.time, ds.time.values, f))
    bad = dict(acc, location="gearbox lid")
    with pytest.raises(InputError, match="unknown location 'gearbox lid'"):
        run_simulation(_reclaimer(examples_dir, [bad], t_end=0.05), seed=0)


@pytest.mark.parametrize(
    ("sensor", "message"),
    [
        ({"name": "e", "kind": "encoder"}, "needs shaft"),
        ({"name": "a", "kind": "accelerometer"}, "needs location"),
        ({"name": "a b", "kind": "tacho", "shaft": "sun"}, "name"),
        ({"name": "e", "kind": "encoder", "shaft": "sun", "clock_hz": float("nan")}, "clock_hz"),
        ({"name": "e", "kind": "encoder", "shaft": "sun", "graduation_error_rad": float("inf")},
         "graduation_error_rad"),
        ({"name": "e", "kind": "encoder", "shaft": "sun", "pulses_per_rev": 100,
          "graduation_error_rad": 0.1}, "half a graduation"),
        ({"name": "a", "kind": "accelerometer", "location": "ring",
          "transfer_path": [{"frequency_hz": -1.0}]}, "frequency_hz"),
        ({"name": "a", "kind": "accelerometer", "location": "ring", "stage": "nope"},
         "unknown planetary stage"),
    ],
)
def test_sensor_config_errors_name_the_field(examples_dir, sensor, message):
    with pytest.raises(ConfigError, match=message):
        _reclaimer(examples_dir, [sensor])


def test_unknown_shaft_for_encoder(examples_dir):
    enc = dict(CARRIER_ENC, shaft="bucket")
    with pytest.raises(InputError, match="'bucket' is not a shaft"):
        run_simulation(_reclaimer(examples_dir, [enc], t_end=0.05), seed=0)


def test_stopped_shaft_sets_status():
    """A shaft that stops while an encoder looks at it: status 'stopped', the channel keeps the
    turning part."""
    t = np.linspace(0, 2, 2001)
    w = np.where(t < 1.0, 10.0 * (1 - t), 0.0)  # decelerates to rest at t = 1 s
    th = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t))])
    ds = xr.Dataset(results.shaft_variables(t, ["s"], th[:, None], w[:, None]),
                    coords={"time": t, "shaft": ["s"]})
    results.finish(ds, "test", "s")

    class Cfg:
        sensors = [geardyn.config.loader.SensorSpec(name="enc", kind="encoder", shaft="s",
                                                     pulses_per_rev=64)]

    with pytest.warns(UserWarning, match="stops at t"):
        add_sensors(Cfg(), ds, seed=0)
    assert ds.attrs["status"] == "stopped" and "stops" in ds.attrs["diagnosis"]
    enc = results.channel(ds, "enc")
    assert enc.time.max() < 1.0


SENSORS_TOML = """
[[sensors]]
name = "ring_acc"
kind = "accelerometer"
location = "ring"
sample_rate_hz = 5000.0
transfer_path = [ { frequency_hz = 1200.0, damping_ratio = 0.05, modal_mass_kg = 50.0 } ]
noise_rms = 0.01

[[sensors]]
name = "sun_enc"
kind = "encoder"
shaft = "sun"

[[sensors]]
name = "sun_tacho"
kind = "tacho"
shaft = "sun"
"""


def test_simulate_and_analyze_cli_on_result(tmp_path, examples_dir):
    """`simulate` writes the layout; `analyze` refuses a file with several channels without
    --channel (listing them), refuses a tacho channel, and analyses a chosen channel."""
    text = (examples_dir / "planetary_reclaimer.toml").read_text()
    text = text.replace("t_end_s = 0.05", "t_end_s = 6.0") + SENSORS_TOML
    cfg = tmp_path / "cfg.toml"
    cfg.write_text(text)
    out = tmp_path / "run.nc"
    r = runner.invoke(app, ["simulate", str(cfg), "--out", str(out), "--seed", "2"])
    assert r.exit_code == 0, r.output
    assert "ring_acc, sun_enc, sun_tacho" in r.output
    ds = xr.open_dataset(out)
    assert results.is_result(ds) and results.channels(ds) == ["ring_acc", "sun_enc",
                                                               "sun_tacho"]
    ds.close()
    r = runner.invoke(app, ["analyze", str(out), "-c", str(cfg), "--out", str(tmp_path / "a")])
    assert r.exit_code == 2 and "ring_acc, sun_enc, sun_tacho" in r.output
    r = runner.invoke(app, ["analyze", str(out), "-c", str(cfg), "--channel", "sun_tacho",
                            "--out", str(tmp_path / "a")])
    assert r.exit_code == 2 and "tacho" in r.output
    r = runner.invoke(app, ["analyze", str(out), "-c", str(cfg), "--channel", "ring_acc",
                            "--speed", "sun=30", "--out", str(tmp_path / "a")])
    assert r.exit_code == 2 and "drop these options" in r.output
    for ch in ("ring_acc", "sun_enc"):
        r = runner.invoke(app, ["analyze", str(out), "-c", str(cfg), "--channel", ch,
                                "--out", str(tmp_path / ch)])
        assert r.exit_code == 0, r.output
        assert f"channel '{ch}'" in r.output
        assert (tmp_path / ch / "order_spectrum.png").is_file()


def test_read_signal_refuses_nd_variables(tmp_path):
    from geardyn.signal_io import read_signal

    ds = xr.Dataset({"q": (("time", "dof"), np.zeros((64, 3))),
                     "a": (("time",), np.zeros(64)), "b": (("time",), np.ones(64))},
                    coords={"time": np.arange(64) / 100.0})
    p = tmp_path / "x.nc"
    ds.to_netcdf(p, engine="h5netcdf")
    with pytest.raises(InputError, match="choose one with --channel .*: a, b"):
        read_signal(p)
    # a 2-D variable is no signal channel: refused, naming it and the channels there are
    with pytest.raises(InputError, match="channel 'q'.*channels a, b"):
        read_signal(p, channel="q")
    assert read_signal(p, channel="b").x.size == 64


def test_ring_sensor_faces_the_planet_at_its_position():
    """Planet n sits at θ_c + ψ_n (model geometry): a ring sensor at α weights planet n by 1
    when θ_c + ψ_n = α, by ½(1 + cos(N·Δ)) within ±π/N, and by 0 further away."""
    from geardyn.sensors.channels import ring_sensor_windows

    psi = np.radians([0.0, 120.0, 240.0])
    alpha = np.radians(35.0)
    w = ring_sensor_windows(alpha - psi, psi, alpha)
    assert w == pytest.approx(np.eye(3), abs=1e-12)
    d = np.radians(20.0)
    w = ring_sensor_windows(np.array([alpha + d]), psi, alpha)[:, 0]
    assert w == pytest.approx([0.5 * (1 + math.cos(3 * d)), 0.0, 0.0], abs=1e-12)


def test_fe_transmission_result_layout_and_analyze(tmp_path, examples_dir):
    """FE model: the result layout (per-shaft angle/speed, housing forces of every bearing),
    sensors on it, and `analyze` per channel on the file written by `geardyn transmission`.
    Invariant: the bearings' housing forces balance (no gravity, mesh forces are internal):
    their sum is small against each bearing's load."""
    cfg_path = examples_dir / "seed002_diagnose_spall.toml"
    out = tmp_path / "fe.nc"
    r = runner.invoke(app, ["transmission", str(cfg_path), "--revolutions", "3",
                            "--netcdf", str(out)])
    assert r.exit_code == 0, r.output
    ds = xr.load_dataset(out)
    assert results.is_result(ds) and ds.attrs["model"] == "transmission"
    assert results.channels(ds) == ["acc_output", "enc_output", "enc_intermediate",
                                    "te_low", "te_high", "tacho_output"]
    assert list(ds.link.values) == ["output", "intermediate", "input"]
    f = ds.bearing_force.where(ds.time > 0.1, drop=True).mean("time")  # (bearing, axis)
    total = np.hypot(*f.sum("bearing").values)
    assert total < 0.02 * float(np.hypot(f.sel(axis="x"), f.sel(axis="y")).max())
    # speed ratio of the meshes: output / intermediate = 42/55 (seed 002 Table 2)
    w = ds.speed.where(ds.time > 0.1, drop=True).mean("time")
    assert float(w.sel(shaft="output") / w.sel(shaft="intermediate")) == pytest.approx(
        42 / 55, rel=1e-3)
    for ch in ("acc_output", "enc_intermediate"):
        r = runner.invoke(app, ["analyze", str(out), "-c", str(cfg_path), "--channel", ch,
                                "--out", str(tmp_path / ch)])
        assert r.exit_code == 0, r.output
    r = runner.invoke(app, ["analyze", str(out), "-c", str(cfg_path), "--out",
                            str(tmp_path / "x")])
    assert r.exit_code == 2 and "acc_output, enc_output, enc_intermediate, te_low" in r.output


def test_transmission_error_sensor_closed_form():
    """Encoder-pair TE, TE = θ_a − (z_b/z_a)·θ_b: shafts turning at 42:55 with a torsional
    oscillation A sin(2πft) on wheel a (f ≪ edge rate) give TE = A sin(2πft) − its mean, to the
    linear interpolation between edges (error ≤ A(2πf/edge rate)²/8 ≈ 1e-9 rad here) and the
    80 MHz clock (each edge within one tick: ≤ (ω_a + (z_b/z_a)|ω_b|)/f_clock = 1.26e-6 rad).
    """
    from geardyn.sensors.channels import SensorContext, apply_sensors

    t = np.linspace(0.0, 2.0, 200_001)
    w_a, amp, f = 2 * np.pi * 8.0, 2e-5, 30.0
    th_a = w_a * t + amp * np.sin(2 * np.pi * f * t)
    th_b = -(42 / 55) * w_a * t  # counter-rotating wheel b
    speed = np.stack([np.gradient(th_a, t), np.gradient(th_b, t)], axis=1)
    ds = xr.Dataset(results.shaft_variables(t, ["pin", "gear"], np.stack([th_a, th_b], 1), speed),
                    coords={"time": t, "shaft": ["pin", "gear"]})
    results.finish(ds, "test", "pin")
    spec = geardyn.config.loader.SensorSpec(name="te", kind="transmission_error", pair="p",
                                             pulses_per_rev=1000, clock_hz=80e6)
    apply_sensors(ds, [spec], 0, SensorContext("pin", meshes={"p": ("pin", 42, "gear", 55)}))
    ch = results.channel(ds, "te")
    ref = amp * np.sin(2 * np.pi * f * ch.time)
    bound = 2 * w_a / 80e6
    err = (ch.values - ch.values.mean()) - (ref - ref.mean())
    assert np.max(np.abs(err)) < bound
    assert np.std(err) < 0.5 * bound  # quantisation, not a systematic error
    assert ch.shaft == "pin" and ch.units == "rad"


def test_transmission_error_needs_a_known_pair(examples_dir):
    with pytest.raises(ConfigError, match="unknown gear pair 'nope'"):
        _reclaimer(examples_dir, [{"name": "te", "kind": "transmission_error", "pair": "nope"}])
