"""Input speeds of spatial (bevel) mechanisms (issue 20): each input speed is taken about its
link's own axis, any determinate set of inputs gives the same motion, and the dynamic model
does not depend on which links are inputs.

The mechanism: the car differential of seed 000 (Penaud, Alazard, Amiez 2012, Table 1) with the
crown pair made a real 90° bevel (pitch angles 45° / −45° instead of 0° / 0°), so the drive
pinion's axis is perpendicular to the wheel axis. Expected numbers are closed forms:

- Willis on the crown pair (carrier: housing), with both rotations about their own axes and
  the tooth axes ψ = θ + φ equal (45° + 0° = −45° + 90°): 13 s_p + 65 s_c = 0, s_c = −s_p/5;
- the differential (equal side gears 14, pinions 10, carrier: cage): s_L + s_R = 2 s_c and
  |s_L − s_c|·14 = |spin of a planet pinion about its pin|·10;
- mesh frequency N_a |ω_a − ω_k| / 2π (seed 000 eq 2).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg as sla

from geardyn import analyze_kinematics
from geardyn.config.loader import load_config
from geardyn.errors import GeardynError, InputError
from geardyn.kinematics import characteristic_frequencies, link_speeds, mesh_frequencies
from geardyn.models.core.graph import model_from_config

L, R = 248.2817112, 286.4788976  # seed 000 eq 8: 26 and 30 rad/s in rpm
CROWN_0 = ('a = { link = "drive_pinion", teeth = 13, pitch_angle_deg = 0 }\n'
           'b = { link = "cage", teeth = 65, pitch_angle_deg = 0 }')
CROWN_90 = ('a = { link = "drive_pinion", teeth = 13, pitch_angle_deg = 45 }\n'
            'b = { link = "cage", teeth = 65, pitch_angle_deg = -45 }')
WHEELS = f"[input_speeds_rpm]\nleft_wheel = {L}\nright_wheel = {R}"


def _write(tmp_path, examples_dir, inputs: str | None = None, crown: str = CROWN_90,
           name: str = "diff.toml"):
    text = (examples_dir / "car_differential_dynamics.toml").read_text()
    old_inputs = ("[input_speeds_rpm]\nleft_wheel = 248.2817112\nright_wheel = 286.4788976")
    assert CROWN_0 in text and old_inputs in text
    text = text.replace(CROWN_0, crown).replace(old_inputs, inputs or WHEELS)
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.fixture
def bevel(tmp_path, examples_dir):
    cfg = load_config(_write(tmp_path, examples_dir))
    return cfg, analyze_kinematics(cfg)


def _signed(kin, omega, link):
    return kin.signed_speed(link, complex(omega[kin.graph.index(link)]))


def test_axes_follow_from_the_pitch_angles(bevel):
    _, kin = bevel
    deg = {x: math.degrees(v) for x, v in kin.axes.items()}
    # the first link turning in the frame (drive_pinion) is the sketch direction 0°; the crown
    # pair turns the wheel axis by θ_a − θ_b = 90°; the pinion pins by a further 90° (±45°)
    assert deg["drive_pinion"] == 0.0
    for x in ("cage", "left_wheel", "right_wheel"):
        assert deg[x] == pytest.approx(90.0, abs=1e-9)
    for x in ("pinion_a", "pinion_b"):
        assert abs(math.sin(math.radians(deg[x]))) < 1e-9


def test_drive_and_wheel_inputs_give_the_two_wheel_motion(bevel):
    _, kin = bevel
    by_wheels = link_speeds(kin, {"left_wheel": L, "right_wheel": R})
    cage = _signed(kin, by_wheels, "cage") * 30 / math.pi
    drive = _signed(kin, by_wheels, "drive_pinion") * 30 / math.pi
    assert cage == pytest.approx((L + R) / 2, rel=1e-12)  # differential
    assert drive == pytest.approx(-5.0 * cage, rel=1e-12)  # crown Willis, s_c = −s_p/5
    by_drive = link_speeds(kin, {"drive_pinion": drive, "left_wheel": L})
    np.testing.assert_allclose(by_drive, by_wheels, rtol=0, atol=1e-9 * np.abs(by_wheels).max())
    assert _signed(kin, by_drive, "right_wheel") * 30 / math.pi == pytest.approx(R, rel=1e-12)
    np.testing.assert_allclose(mesh_frequencies(kin, by_drive), mesh_frequencies(kin, by_wheels),
                               rtol=1e-12)


def test_drive_input_closed_form_right_wheel_and_meshes(bevel):
    """Drive pinion at −2000 rpm about its axis, left wheel at L: cage 400 rpm, right wheel
    2·400 − L = 551.718 rpm (not a speed taken along another axis)."""
    _, kin = bevel
    f = characteristic_frequencies(kin, {"drive_pinion": -2000.0, "left_wheel": L})
    links = f.links.set_index("link")
    assert links.loc["cage", "signed_rpm"] == pytest.approx(400.0, rel=1e-12)
    assert links.loc["right_wheel", "signed_rpm"] == pytest.approx(800.0 - L, rel=1e-12)
    assert links.loc["right_wheel", "signed_rpm"] == pytest.approx(551.7182888, abs=1e-6)
    assert links.loc["drive_pinion", "signed_rpm"] == -2000.0  # the input, about its own axis
    meshes = f.meshes.set_index("pair")
    assert meshes.loc["2-7", "mesh_hz"] == pytest.approx(13 * 2000.0 / 60, rel=1e-12)
    for pair, wheel in (("3-5", L), ("3-6", L), ("4-5", 800.0 - L), ("4-6", 800.0 - L)):
        assert meshes.loc[pair, "mesh_hz"] == pytest.approx(14 * abs(wheel - 400.0) / 60,
                                                            rel=1e-12)


def test_a_planet_pinion_spin_and_the_cage_as_inputs(bevel):
    """A link on a moving carrier as input: its speed about its own axis (the pin) is its spin
    relative to the cage; with the cage it fixes the motion."""
    _, kin = bevel
    omega = link_speeds(kin, {"cage": 300.0, "pinion_a": 70.0})
    left, right = (_signed(kin, omega, x) * 30 / math.pi for x in ("left_wheel", "right_wheel"))
    assert left + right == pytest.approx(600.0, rel=1e-12)
    assert abs(left - right) == pytest.approx(2 * 70.0 * 10 / 14, rel=1e-12)
    assert math.isnan(_signed(kin, omega, "pinion_a"))  # not along one axis: no signed speed


def test_dependent_inputs_are_refused(bevel):
    _, kin = bevel
    with pytest.raises(InputError, match="do not fix the motion"):
        link_speeds(kin, {"cage": 300.0, "drive_pinion": 1500.0})


def test_inconsistent_pitch_angles_name_the_gear_pair(tmp_path, examples_dir):
    gear = ('a = {{ link = "right_wheel", teeth = 14, pitch_angle_deg = {}, '
            'wheel = "right_side_gear" }}')
    text = _write(tmp_path, examples_dir).read_text().replace(gear.format(-45), gear.format(-30))
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(GeardynError, match=r"gear pair '4-[56]'.*pitch angles"):
        analyze_kinematics(load_config(path))


def _modes(model) -> np.ndarray:  # noqa: ANN001
    k = model.stiffness_matrix()
    w = sla.eigh(k, model.M, eigvals_only=True)
    return np.sqrt(np.clip(w, 0.0, None)) / (2 * math.pi)


def test_the_dynamic_model_does_not_depend_on_the_inputs(bevel, tmp_path, examples_dir):
    cfg, _ = bevel
    a = model_from_config(cfg, ["left_wheel", "right_wheel"])
    b = model_from_config(cfg, ["drive_pinion", "left_wheel"])
    c = model_from_config(cfg, ["cage", "pinion_a"])
    for m in (b, c):
        assert m.dof_names == a.dof_names
        np.testing.assert_allclose(m.M, a.M, rtol=0, atol=1e-12 * np.abs(a.M).max())
        np.testing.assert_allclose(m.stiffness_matrix(), a.stiffness_matrix(), rtol=0,
                                   atol=1e-9 * np.abs(a.stiffness_matrix()).max())
    f = _modes(a)
    assert np.sum(f < 1e-6 * f.max()) == 2  # two rigid-body modes: 2 DOF
    # through the config: the drive + wheel file gives the two-wheel file's modes
    drive = load_config(_write(tmp_path, examples_dir, "[input_speeds_rpm]\n"
                               f"drive_pinion = {-5 * (L + R) / 2}\nleft_wheel = {L}",
                               name="drive.toml"))
    np.testing.assert_allclose(_modes(model_from_config(drive)), f, rtol=1e-9, atol=1e-6)


def test_ratios_to_a_reference_whose_axis_is_not_0deg(examples_dir):
    """The reclaimer's shafts after the bevel stage turn about axes at 90° from the motor's
    (the sketch direction 0°): ratios to one of them are ω_link/ω_reference (seed 004 §6.5:
    13/38 at the bevel, −21/68 at the parallel pair), not speeds per unit of its signed speed
    (which would carry the factor e^{i90°})."""
    from geardyn.config.loader import load_config as load
    from geardyn.diagnosis.components import complex_link_ratios
    from geardyn.signal.resample import link_ratio

    kin = analyze_kinematics(load(examples_dir / "reclaimer_drive.toml"))
    assert math.degrees(kin.axes["motor"]) == 0.0  # the first link turning in the frame
    assert abs(math.sin(kin.axes["shaft2"])) == pytest.approx(1.0, abs=1e-12)
    assert link_ratio(kin, "motor", "motor") == 1.0
    assert link_ratio(kin, "shaft2", "shaft3") == pytest.approx(-21 / 68, rel=1e-12)
    r = complex_link_ratios(kin, "shaft2")  # a reference at 90° in the sketch
    assert r["shaft2"] == pytest.approx(1.0, abs=1e-12)
    assert r["shaft3"] == pytest.approx(-21 / 68, rel=1e-12)  # same axis direction: real
    assert abs(r["motor"]) == pytest.approx(38 / 13, rel=1e-12)
