"""`geardyn modes --campbell SPEEDS` for the FE transmission (seed 002), the planetary model
(seed 003 eq 3.1) and the model of any mechanism: the printed/written rows equal the library
functions; the FE Campbell at 0 rpm equals the FE modes; on the seed 002 example the gyroscopic
split raises the forward whirl and lowers the backward one; FE modes on named DOFs with
element energies that add up to the modal energy."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from geardyn.cli import app
from geardyn.cli.modes import campbell_table, parse_speeds
from geardyn.config.loader import load_config, parse_config
from geardyn.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
EX = ROOT / "examples"
runner = CliRunner()


def _csv(path: Path) -> tuple[list[str], np.ndarray]:
    lines = path.read_text().strip().splitlines()
    return lines[0].split(","), np.array([[float(x) for x in ln.split(",")] for ln in lines[1:]])


@pytest.fixture(scope="module")
def fe():
    from geardyn.models.transmission import build_model, prepare

    cfg = load_config(EX / "seed002_transmission.toml")
    model = build_model(cfg)
    return cfg, model, prepare(model, cfg.transmission.speed_law.reference.shaft)


def test_parse_speeds() -> None:
    s, u = parse_speeds("0:3000:7 rpm")
    assert u == "rpm" and s == pytest.approx(np.linspace(0, 3000, 7))
    s, u = parse_speeds("10,20.5 rad/s")
    assert u == "rad/s" and s == pytest.approx([10, 20.5])
    assert parse_speeds("0:50:2 hz")[1] == "Hz" and parse_speeds("100")[1] == "rpm"
    for bad, msg in (("0:3000 rpm", "START:STOP:COUNT"), ("0:1:0", "COUNT must be ≥ 1"),
                     ("0:1:3 furlongs", "unknown speed unit"), ("nan,1", "finite"),
                     ("a b c", "expected")):
        with pytest.raises(InputError, match=msg):
            parse_speeds(bad)


def test_fe_campbell_cli_rows_equal_the_library_and_the_modes(fe, tmp_path) -> None:
    """Seed 002: the CSV rows written by `modes --campbell` equal
    models.transmission.assembly.campbell (gyroscopic matrices of every shaft at its kinematic
    speed); at 0 rpm they are the FE natural frequencies (linearised at the preload, rigid
    drive-line mode left out) to 1e-9; the figure is written."""
    from geardyn.models.transmission.assembly import campbell
    from geardyn.models.transmission.simulate import speed_ratios

    cfg, model, prep = fe
    r = runner.invoke(app, ["modes", str(EX / "seed002_transmission.toml"), "--campbell",
                            "0:3000:4 rpm", "--campbell-modes", "8", "--out", str(tmp_path),
                            "--max-hz", "400"], env={"COLUMNS": "200"})
    assert r.exit_code == 0, r.output
    assert "Campbell" in r.output and "speed (rpm)" in r.output and "f8 (Hz)" in r.output
    head, rows = _csv(tmp_path / "campbell.csv")
    assert head == ["speed_rpm"] + [f"f{m}_hz" for m in range(1, 9)]
    assert rows[:, 0] == pytest.approx([0, 1000, 2000, 3000])
    want = campbell(model, prep.K_lin, rows[:, 0], speed_ratios(model, "output"), n_modes=8)
    assert np.array_equal(rows[:, 1:], want.values)
    f0 = prep.frequencies_hz[prep.frequencies_hz > 0.5][:8]
    assert rows[0, 1:] == pytest.approx(f0, rel=1e-9)
    assert not np.allclose(rows[0, 1:], rows[-1, 1:], rtol=1e-6, atol=0)  # speed matters
    assert (tmp_path / "campbell.png").stat().st_size > 1000
    # the modes table lists the same frequencies (named DOFs, element strain energies)
    assert "output.n" in r.output and "bearing." in r.output


def test_fe_forward_whirl_rises_backward_whirl_falls(fe) -> None:
    """Seed 002 at 20,000 rpm of the output shaft: the lateral pair of the intermediate shaft
    near 327/332 Hz splits; the mode whose frequency rises whirls with the shaft's spin
    (forward), the one that falls against it (backward) — the gyroscopic stiffening of
    rotordynamics (Friswell et al. 2010 §3.5). Whirl sense from an independent eigenvector
    solve: orbit of the intermediate shaft's nodes, sign of ⟨x ẏ − y ẋ⟩ = −ω Im(X̄ Y)."""
    cfg, model, prep = fe
    rpm = 20000.0
    cd = campbell_table("transmission", cfg, model, np.array([0.0, rpm]), "rpm", 8,
                        prepared=prep)
    f0, f1 = cd.values
    j = int(np.argmax(np.abs(f1 - f0)[:6]))  # the pair with the largest split
    lo, hi = (j, j + 1) if f1[j] < f0[j] else (j - 1, j)
    assert f1[lo] < f0[lo] - 1.0 and f1[hi] > f0[hi] + 1.0  # Hz
    n = model.ndof
    om = rpm * math.pi / 30
    G = sum(model.shaft_sign[s] * prep.speed_ratio[s] * om * g
            for s, g in model.gyroscopic.items())
    minv = np.linalg.inv(model.M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-minv @ prep.K_lin, -minv @ G]])
    lam, vec = np.linalg.eig(A)
    ids = model.shaft_nodes["intermediate"]
    for k, sense in ((lo, -1.0), (hi, +1.0)):
        i = int(np.argmin(np.abs(lam.imag / (2 * math.pi) - f1[k])))
        assert abs(lam[i].imag / (2 * math.pi) - f1[k]) < 1e-6 * f1[k]
        X = vec[[6 * nd for nd in ids], i]
        Y = vec[[6 * nd + 1 for nd in ids], i]
        ccw = -np.sum(np.imag(np.conj(X) * Y)) / np.sum(np.abs(X) ** 2 + np.abs(Y) ** 2)
        assert np.sign(ccw) * model.shaft_sign["intermediate"] == sense
        assert abs(ccw) > 0.1  # a clear orbit sense, not a straight line


def test_fe_modes_energies(fe) -> None:
    """FE modes: same frequencies as the preparation; per elastic mode the kinetic energy
    ½ω² (mass-normalised) equals the strain energy summed over the Timoshenko elements,
    bearings and meshes (the tangent stiffness split per element, 1e-6); shapes on the named
    DOFs."""
    from geardyn.models.transmission.modal import fe_modes

    cfg, model, prep = fe
    res = fe_modes(model, prep)
    assert res.freq_hz == pytest.approx(prep.frequencies_hz, rel=1e-12, abs=1e-9)
    el = res.freq_hz > 0.5
    ek = 0.5 * (2 * math.pi * res.freq_hz[el]) ** 2
    assert res.kinetic[el].sum(1) == pytest.approx(ek, rel=1e-9)
    assert res.strain[el].sum(1) == pytest.approx(ek, rel=1e-6)
    assert res.mode_type[0] == "rigid" and set(res.mode_type[1:]) <= {
        "torsional", "lateral", "axial", "mixed"}
    assert {"bearing", "mesh", "shaft"} == set(res.spring_bins)
    ds = res.to_dataset()
    assert list(ds["dof"].values) == model.dof_names


def test_planetary_campbell_cli_equals_solve_modal(tmp_path) -> None:
    """Planetary (seed 003 eq 3.1): rows of `modes --campbell` (carrier speed in rpm) equal
    solve.modal.campbell at the same speeds in rad/s."""
    from geardyn.models.planetary.build import model_from_config
    from geardyn.models.planetary.modal import campbell

    path = EX / "planetary_lin_parker.toml"
    r = runner.invoke(app, ["modes", str(path), "--campbell", "0:3000:3 rpm", "--out",
                            str(tmp_path)])
    assert r.exit_code == 0, r.output
    head, rows = _csv(tmp_path / "campbell.csv")
    assert head[0] == "speed_rpm" and len(head) == 11
    want = campbell(model_from_config(load_config(path)), rows[:, 0] * math.pi / 30, 10)
    assert np.array_equal(rows[:, 1:], want.values)
    r = runner.invoke(app, ["modes", str(path), "--campbell", "0:1:2", "--speed-of", "sun"])
    assert r.exit_code == 2 and "--speed-of" in r.output


def test_mechanism_campbell_equals_core_campbell(tmp_path) -> None:
    """Any mechanism: `campbell_table` of a lateral planetary stage (carrier frame G, K_Ω) in
    rad/s equals models.core.modal.core_campbell; the CLI end to end on the Alouette III
    gearbox (torsional: no gyroscopic terms, frequencies independent of speed)."""
    from geardyn.models.core import model_from_config
    from geardyn.models.core.modal import core_campbell
    from tests.mechanism.test_model import _lateral_config

    cfg = parse_config(_lateral_config(True))
    model = model_from_config(cfg)
    speeds = np.array([0.0, 200.0, 600.0])
    cd = campbell_table("mechanism", cfg, model, speeds, "rad/s", 6, "carrier")
    assert np.array_equal(cd.values, core_campbell(model, "carrier", speeds, 6).values)
    assert cd.attrs["speed_units"] == "rad/s" and cd.attrs["units"] == "Hz"
    assert not np.allclose(cd.values[0], cd.values[-1])
    path = EX / "alouette3_mgb_dynamics.toml"
    r = runner.invoke(app, ["modes", str(path), "--campbell", "0,100,300 rad/s", "--out",
                            str(tmp_path), "--campbell-modes", "4"])
    assert r.exit_code == 0, r.output
    head, rows = _csv(tmp_path / "campbell.csv")
    assert head[0] == "speed_rad_per_s"
    mcfg = load_config(path)
    m = model_from_config(mcfg)
    body = next(k for k in mcfg.input_speeds_rpm if k in m.bodies)
    assert np.array_equal(rows[:, 1:], core_campbell(m, body, rows[:, 0], 4).values)
    assert np.allclose(rows[0, 1:], rows[-1, 1:], rtol=1e-9)
    r = runner.invoke(app, ["modes", str(path), "--out", str(tmp_path)])
    assert r.exit_code == 2 and "--force" in r.output  # one overwrite policy (issue 21)
    r = runner.invoke(app, ["modes", str(path), "--out", str(tmp_path), "--force"])
    assert r.exit_code == 0, r.output  # --out alone: modes.nc and modes.png, no stale Campbell
    assert sorted(p.name for p in tmp_path.iterdir()) == ["modes.nc", "modes.png"]
