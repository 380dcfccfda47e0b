"""Malformed inputs over the newer sections and options (issue 20): sweep spec, diagnosis,
sensors, dynamics, unit strings, CLI options, unreadable files.

Same rules and row format as :mod:`tests.corpus.test_corpus` (``(id, base, edits, args,
expected)``), plus:

- ``SW`` as ``base``: a small sweep spec over the seed 004 diagnosis example (:func:`_spec`),
  edited and written to ``{cfg}``; default command ``geardyn sweep {cfg} --out … --check``;
- ``RAWB``: ``edits["bytes"]`` written as the file (a spec or config that is not UTF-8, a
  corrupt checkpoint…);
- ``{long}`` in an argument: a file name of 300 characters in ``{tmp}``.

Each case must end non-zero within 60 s, with no traceback and no internal error, and the
message must name the field or the option typed (and the rule). None runs a simulation: every
one fails during validation or a resource estimate made before any allocation.
"""

from __future__ import annotations

import copy
import time
from pathlib import Path
from typing import Any

import pytest

from geardyn.cli import app
from tests.corpus.test_corpus import (
    DC,
    DEL,
    EXAMPLES,
    G2,
    GG,
    INF,
    NAN,
    PB,
    RAW,
    SIM,
    SIMULATE,
    ST,
    TR,
    _base,
    _normal,
    _set,
    runner,
    signals,  # noqa: F401 - fixture
    to_toml,
)

SW = "SWEEP"
RAWB = "RAWB"
CD = "car_differential"
CDD = "car_differential_dynamics"
SWC = ["sweep", "{cfg}", "--out", "{tmp}/s.zarr", "--check"]
SWRUN = ["sweep", "{cfg}", "--out", "{tmp}/s.zarr"]
DIAG = ["diagnose", "{cfg}", "--out", "{tmp}/diag"]
MODES = ["modes", "{cfg}"]
KIN_CD = ["kinematics", str(EXAMPLES / f"{CD}.toml")]
DYN = "dynamics.simulation"
CRACK = "planetary_dynamics.stages[0].faults[0].crack_fraction"
NESTED = "a = " + "[" * 5000 + "]" * 5000 + "\n"
LONG = "x" * 300


def _spec() -> dict[str, Any]:
    return {"sweep": {"base": str(EXAMPLES / f"{DC}.toml"), "name": "corpus"},
            "run": {"t_end_s": 2.0},
            "axes": [{"name": "crack", "path": CRACK, "values": [0.1, 0.2]}]}


SPEED_AXIS = {"name": "speed", "path": "planetary_dynamics.simulation.initial_speed_rpm.motor",
              "values": [950.0, 1000.0]}

CASES: list[tuple[str, str | None, dict, list[str] | None, tuple[str, ...]]] = [
    # ---- sweep spec: axes ------------------------------------------------------------------
    ("sw-range-overflow", SW, {"axes[0].values": DEL,
                               "axes[0].range": {"start": 0.0, "stop": 1e308, "step": 1e-300}},
     SWC, ("axes[0].range", "values", "max_cases")),
    ("sw-range-3e8", SW, {"axes[0].values": DEL,
                          "axes[0].range": {"start": 0.0, "stop": 3e8, "step": 1.0}},
     SWC, ("axes[0].range", "300000001 values", "max_cases")),
    ("sw-range-num-3e8", SW, {"axes[0].values": DEL,
                              "axes[0].range": {"start": 0.0, "stop": 0.3, "num": 300000000}},
     SWC, ("axes[0].range", "max_cases")),
    ("sw-sample-n-3e8", SW, {"axes[0].values": DEL,
                             "axes[0].sample": {"low": 0.0, "high": 0.3, "n": 300000000}},
     SWC, ("axes[0].sample", "max_cases")),
    ("sw-range-step-zero", SW, {"axes[0].values": DEL,
                                "axes[0].range": {"start": 0.0, "stop": 0.3, "step": 0.0}},
     SWC, ("'crack'.range.step", "greater than 0")),
    ("sw-range-stop-below", SW, {"axes[0].values": DEL,
                                 "axes[0].range": {"start": 0.3, "stop": 0.1, "num": 3}},
     SWC, ("'crack'.range", "below start")),
    ("sw-range-num-and-step", SW, {"axes[0].values": DEL, "axes[0].range": {
        "start": 0.0, "stop": 0.3, "num": 3, "step": 0.1}}, SWC, ("'crack'.range", "exactly one")),
    ("sw-range-nan", SW, {"axes[0].values": DEL,
                          "axes[0].range": {"start": NAN, "stop": 0.3, "num": 3}},
     SWC, ("'crack'.range.start", "finite")),
    ("sw-range-inf", SW, {"axes[0].values": DEL,
                          "axes[0].range": {"start": 0.0, "stop": INF, "num": 3}},
     SWC, ("'crack'.range.stop", "finite")),
    ("sw-range-num-zero", SW, {"axes[0].values": DEL,
                               "axes[0].range": {"start": 0.0, "stop": 0.3, "num": 0}},
     SWC, ("'crack'.range.num", "greater than or equal to 1")),
    ("sw-sample-high-low", SW, {"axes[0].values": DEL,
                                "axes[0].sample": {"low": 0.3, "high": 0.1, "n": 3}},
     SWC, ("'crack'.sample", "must exceed low")),
    ("sw-sample-method", SW, {"axes[0].values": DEL,
                              "axes[0].sample": {"low": 0.1, "high": 0.3, "n": 3,
                                                 "method": "sobol"}},
     SWC, ("'crack'.sample.method", "sobol")),
    ("sw-sample-n-zero", SW, {"axes[0].values": DEL,
                              "axes[0].sample": {"low": 0.1, "high": 0.3, "n": 0}},
     SWC, ("'crack'.sample.n", "greater than or equal to 1")),
    ("sw-axis-no-source", SW, {"axes[0].values": DEL}, SWC, ("axes[0]", "exactly one")),
    ("sw-axis-two-sources", SW, {"axes[0].range": {"start": 0.1, "stop": 0.3, "num": 3}}, SWC,
     ("axes[0]", "exactly one", "values, range")),
    ("sw-axis-empty", SW, {"axes[0].values": []}, SWC, ("axes[0]", "empty")),
    ("sw-axis-bad-name", SW, {"axes[0].name": "1crack"}, SWC, ("'1crack'.name", "pattern")),
    ("sw-axis-reserved-name", SW, {"axes[0].name": "status"}, SWC, ("status", "reserved")),
    ("sw-axis-duplicate-name", SW, {"axes[1]": {"name": "crack", "path": CRACK,
                                                "values": [0.3]}}, SWC,
     ("crack", "distinct")),
    ("sw-axis-unknown-path", SW, {"axes[0].path": "planetary_dynamics.nope"}, SWC,
     ("axis 'crack'", "nope")),
    ("sw-axis-index-out", SW, {"axes[0].path": "planetary_dynamics.stages[5].carrier_radius_m"},
     SWC, ("axis 'crack'", "stages")),
    ("sw-axis-bad-path-syntax", SW, {"axes[0].path": "planetary_dynamics..stages"}, SWC,
     ("axis 'crack'", "path")),
    ("sw-axis-string-for-number", SW, {"axes[0].values": ["a", "b"]}, SWC,
     ("axis 'crack'", "not a number")),
    ("sw-axis-nan-value", SW, {"axes[0].values": [0.1, NAN]}, SWC, ("axis 'crack'", "not finite")),
    ("sw-axis-value-invalid", SW, {"axes[0].values": [0.1, 1.5]}, SWC,
     ("axis 'crack' = 1.5", "crack_fraction")),
    ("sw-axis-value-units", SW, {"axes[0].path": "planetary_dynamics.stages[0].carrier_radius_m",
                                 "axes[0].values": [0.408, 3.0e3]}, SWC,
     ("axis 'crack'", "carrier_radius_m", "implausible")),
    ("sw-labels-count", SW, {"axes[0].labels": ["a"]}, SWC, ("axis 'crack'", "1 labels")),
    ("sw-group-unequal", SW, {"axes[0].group": "g",
                              "axes[1]": {**SPEED_AXIS, "group": "g", "values": [950.0]}},
     SWC, ("group 'g'", "equal lengths")),
    ("sw-zip-unequal", SW, {"sweep.combine": "zip",
                            "axes[1]": {**SPEED_AXIS, "values": [950.0]}},
     SWC, ("zip", "same number of values")),
    ("sw-combine-bad", SW, {"sweep.combine": "cross"}, SWC, ("sweep.combine", "cross")),
    ("sw-replicates-zero", SW, {"sweep.replicates": 0}, SWC, ("sweep.replicates",)),
    ("sw-replicates-huge", SW, {"sweep.replicates": 10**12}, SWC, ("max_cases",)),
    ("sw-seed-negative", SW, {"sweep.seed": -1}, SWC, ("sweep.seed",)),
    ("sw-seed-float", SW, {"sweep.seed": 1.5}, SWC, ("sweep.seed",)),
    ("sw-max-cases", SW, {"sweep.max_cases": 1}, SWC, ("2 values", "max_cases = 1")),
    ("sw-max-cases-zero", SW, {"sweep.max_cases": 0}, SWC, ("sweep.max_cases",)),
    ("sw-product-too-many", SW, {"axes[0].values": [0.1] * 200,
                                 "axes[1]": {**SPEED_AXIS, "values": [950.0] * 200}}, SWC,
     ("40000 cases", "max_cases")),
    # ---- sweep spec: sections ----------------------------------------------------------------
    ("sw-base-missing", SW, {"sweep.base": "nope.toml"}, SWC, ("sweep.base", "does not exist")),
    ("sw-base-not-toml", SW, {"sweep.base": "{sig}/s.npy"}, SWC, ("not valid toml",)),
    ("sw-base-is-dir", SW, {"sweep.base": "{tmp}"}, SWC, ("sweep.base", "{tmp}")),
    ("sw-base-long-name", SW, {"sweep.base": "{long}.toml"}, SWC, ("sweep.base", "255")),
    ("sw-base-number", SW, {"sweep.base": 5}, SWC, ("sweep.base", "string")),
    ("sw-sweep-missing", SW, {"sweep": DEL}, SWC, ("sweep", "required")),
    ("sw-axes-missing", SW, {"axes": DEL}, SWC, ("axes", "required")),
    ("sw-axes-empty", SW, {"axes": []}, SWC, ("axes", "at least 1")),
    ("sw-axes-not-list", SW, {"axes": "crack"}, SWC, ("axes",)),
    ("sw-unknown-section", SW, {"extra": {"a": 1}}, SWC, ("extra", "unknown field")),
    ("sw-unknown-field", SW, {"sweep.colour": "red"}, SWC, ("sweep.colour", "unknown field")),
    ("sw-axis-unknown-field", SW, {"axes[0].unit": "m"}, SWC, ("'crack'.unit", "unknown field")),
    ("sw-name-number", SW, {"sweep.name": 5}, SWC, ("sweep.name", "string")),
    ("sw-run-t-end-negative", SW, {"run.t_end_s": -1.0}, SWC, ("run.t_end_s", "greater than 0")),
    ("sw-run-t-end-nan", SW, {"run.t_end_s": NAN}, SWC, ("run.t_end_s", "finite")),
    ("sw-run-t-end-1e12", SW, {"run.t_end_s": 1e12}, SWC, ("run.t_end_s", "implausible")),
    ("sw-run-t-end-string", SW, {"run.t_end_s": "2 m"}, SWC, ("run.t_end_s", "not a time")),
    ("sw-run-revolutions-planetary", SW, {"run.revolutions": 5.0}, SWC,
     ("run.revolutions", "transmission")),
    ("sw-run-revolutions-negative", SW, {"run.revolutions": -5.0}, SWC,
     ("run.revolutions", "greater than 0")),
    ("sw-run-unknown", SW, {"run.dt_s": 1e-5}, SWC, ("run.dt_s", "unknown field")),
    ("sw-channels-unknown", SW, {"outputs": {"channels": {"names": ["ghost"]}}}, SWC,
     ("outputs.channels.names", "ghost", "not a sensor")),
    ("sw-channels-every-zero", SW, {"outputs": {"channels": {"names": ["ring_acc"],
                                                             "every": 0}}}, SWC,
     ("outputs.channels.every",)),
    ("sw-channels-samples-zero", SW, {"outputs": {"channels": {"names": ["ring_acc"],
                                                               "samples": 0}}}, SWC,
     ("outputs.channels.samples",)),
    ("sw-channels-samples-huge", SW, {"outputs": {"channels": {"names": ["ring_acc"],
                                                               "samples": 10**12}}}, SWC,
     ("outputs.channels.samples", "limit")),
    ("sw-states-variable", SW, {"outputs": {"states": {"variables": ["torque"]}}}, SWC,
     ("outputs.states.variables", "torque")),
    ("sw-states-step-zero", SW, {"outputs": {"states": {"variables": ["speed"],
                                                        "step_s": 0.0}}}, SWC,
     ("outputs.states.step_s", "greater than 0")),
    ("sw-states-step-1e-12", SW, {"outputs": {"states": {"variables": ["speed"],
                                                         "step_s": 1e-12}}}, SWC,
     ("outputs.states.step_s", "limit")),
    ("sw-indicators-channel", SW, {"outputs": {"indicators": {"channel": "ghost"}}}, SWC,
     ("outputs.indicators.channel", "ghost")),
    ("sw-indicators-blocks-zero", SW, {"outputs": {"indicators": {"blocks": 0}}}, SWC,
     ("outputs.indicators.blocks",)),
    ("sw-indicators-blocks-many", SW, {"outputs": {"indicators": {"blocks": 100}}}, SWC,
     ("outputs.indicators.blocks", "64")),
    ("sw-indicators-skip-negative", SW, {"outputs": {"indicators": {"skip_s": -1.0}}}, SWC,
     ("outputs.indicators.skip_s",)),
    ("sw-indicators-no-sensors", SW, {"sweep.base": str(EXAMPLES / f"{PB}.toml"),
                                      "axes[0].path": f"{SIM}.dt_s",
                                      "axes[0].values": [2e-5, 1e-5]}, SWC,
     ("outputs.indicators", "no [[sensors]]")),
    ("sw-verdicts-unknown-axis", SW, {"outputs": {"verdicts": {"healthy": {"ghost": 0.1}}}},
     SWC, ("outputs.verdicts", "ghost", "not an axis")),
    ("sw-verdicts-value", SW, {"outputs": {"verdicts": {"healthy": {"crack": 0.5}}}}, SWC,
     ("outputs.verdicts.healthy", "0.5", "not a value")),
    ("sw-verdicts-k-zero", SW, {"outputs": {"verdicts": {"healthy": {"crack": 0.1},
                                                         "threshold_k": 0.0}}}, SWC,
     ("outputs.verdicts.threshold_k",)),
    ("sw-verdicts-sigma-floor", SW, {"outputs": {"verdicts": {"healthy": {"crack": 0.1},
                                                              "sigma_floor": 1.5}}}, SWC,
     ("outputs.verdicts.sigma_floor",)),
    ("sw-verdicts-no-indicators", SW, {"outputs": {"verdicts": {"healthy": {"crack": 0.1}},
                                                   "indicators": {"enabled": False}}}, SWC,
     ("outputs.verdicts", "indicators")),
    ("sw-sensor-rate-alloc", SW, {"axes[0].path": "sensors[0].sample_rate_hz",
                                  "axes[0].values": [5000.0, 5e8], "run.t_end_s": 30.0}, SWC,
     ("sample_rate_hz", "samples", "limit")),
    # ---- sweep: files and options --------------------------------------------------------------
    ("sw-spec-not-utf8", RAWB, {"bytes": b"[sweep]\nname = \"\xff\xfe\"\n"}, SWC,
     ("not utf-8",)),
    ("sw-spec-invalid-toml", RAW, {"text": "[sweep\n"}, SWC, ("not valid toml",)),
    ("sw-spec-nested", RAW, {"text": NESTED}, SWC, ("nested",)),
    ("sw-spec-missing", None, {}, ["sweep", "{tmp}/none.toml", "--out", "{tmp}/s.zarr"],
     ("does not exist",)),
    ("sw-spec-directory", None, {}, ["sweep", "{tmp}", "--out", "{tmp}/s.zarr"],
     ("directory",)),
    ("sw-spec-long-name", None, {}, ["sweep", "{long}.toml", "--out", "{tmp}/s.zarr"],
     ("SPEC", "file name", "255")),
    ("sw-out-long-name", SW, {}, ["sweep", "{cfg}", "--out", "{long}.zarr"],
     ("--out", "file name", "255")),
    ("sw-out-missing-dir", SW, {}, ["sweep", "{cfg}", "--out", "{tmp}/no/s.zarr"],
     ("--out", "does not exist")),
    ("sw-out-is-file", SW, {}, ["sweep", "{cfg}", "--out", "{sig}/s.npy"],
     ("--out", "not a directory")),
    ("sw-workers-zero", SW, {}, [*SWRUN, "--workers", "0"], ("--workers", "≥ 1")),
    ("sw-workers-negative", SW, {}, [*SWRUN, "-n", "-2"], ("--workers", "≥ 1")),
    ("sw-workers-and-scheduler", SW, {}, [*SWRUN, "--workers", "2", "--scheduler",
                                          "tcp://127.0.0.1:8786"], ("--workers", "--scheduler")),
    ("sw-scheduler-words", SW, {}, [*SWRUN, "--scheduler", "my cluster"],
     ("--scheduler", "address")),
    ("sw-scheduler-port", SW, {}, [*SWRUN, "--scheduler", "tcp://127.0.0.1:99999"],
     ("--scheduler", "port")),
    ("sw-scheduler-protocol", SW, {}, [*SWRUN, "--scheduler", "ftp://127.0.0.1:8786"],
     ("--scheduler", "ftp")),
    ("sw-scheduler-refused", SW, {}, [*SWRUN, "--scheduler", "tcp://127.0.0.1:9"],
     ("--scheduler", "cannot connect")),
    # ---- unit strings in configs -----------------------------------------------------------------
    ("unit-ppm-speed", CD, {"input_speeds_rpm.left_wheel": "32.4263 ppm"}, None,
     ("input_speeds_rpm.left_wheel", "ppm is dimensionless")),
    ("unit-percent-length", G2, {f"{GG}.normal_module_m": "40.8 percent"},
     ["stiffness", "{cfg}", "--samples", "8"],
     ("gear_geometry[0].normal_module_m", "percent is dimensionless")),
    ("unit-percent-angle", G2, {f"{GG}.normal_pressure_angle_deg": "30 percent"},
     ["stiffness", "{cfg}", "--samples", "8"], ("normal_pressure_angle_deg", "dimensionless")),
    ("unit-divide-zero", PB, {f"{ST}.carrier_radius_m": "3 m / 0"}, MODES,
     ("carrier_radius_m", "division by zero")),
    ("unit-power-tower", PB, {f"{ST}.carrier_radius_m": "10**10**9 mm"}, MODES,
     ("carrier_radius_m", "powers of powers")),
    ("unit-power-big", PB, {f"{ST}.sun.inertia_kgm2": "2 kg*m**9"}, MODES,
     ("sun.inertia_kgm2", "power 9")),
    ("unit-too-long", PB, {f"{ST}.sun.mass_kg": "9" + " " * 100 + "kg"}, MODES,
     ("sun.mass_kg", "80 characters")),
    ("unit-overflow", PB, {f"{ST}.sun.mass_kg": "1e999 kg"}, MODES, ("sun.mass_kg", "finite")),
    ("unit-nan-word", PB, {f"{ST}.sun.mass_kg": "nan kg"}, MODES,
     ("sun.mass_kg", "number followed by a unit")),
    ("unit-arithmetic", PB, {f"{ST}.sun.mass_kg": "2*3 kg"}, MODES,
     ("sun.mass_kg", "number followed by a unit")),
    ("unit-ppm-inertia", PB, {f"{ST}.sun.inertia_kgm2": "5 ppm"}, MODES,
     ("sun.inertia_kgm2", "ppm is dimensionless")),
    ("unit-percent-stiffness", PB, {f"{ST}.planet_bearing_n_per_m": "3 percent"}, MODES,
     ("planet_bearing_n_per_m", "dimensionless")),
    ("unit-ratio-length", PB, {f"{SIM}.modal_damping_ratio": "2 mm"}, SIMULATE,
     ("modal_damping_ratio", "not a dimensionless")),
    ("unit-ratio-angle", DC, {"sensors[0].transfer_path[0].damping_ratio": "1 rad"}, DIAG,
     ("damping_ratio", "not a dimensionless")),
    ("unit-torque-angle", PB, {f"{SIM}.torques[0].torque_nm": "5 rad"}, SIMULATE,
     ("torque_nm", "not a torque")),
    ("unit-time-ppm", PB, {f"{SIM}.dt_s": "20 ppm"}, SIMULATE, ("dt_s", "dimensionless")),
    ("unit-rate-percent", DC, {"sensors[0].sample_rate_hz": "5 percent"}, DIAG,
     ("sample_rate_hz", "dimensionless")),
    ("unit-unknown-name", DC, {"diagnosis.skip_s": "3 fortnights"}, DIAG, ("skip_s",)),
    ("cli-input-ppm", None, {}, [*KIN_CD, "-i", "left_wheel=32.4263 ppm", "-i",
                                 "right_wheel=300"], ("--input", "ppm is dimensionless")),
    ("cli-input-power-tower", None, {}, [*KIN_CD, "-i", "left_wheel=10**10**9 rpm", "-i",
                                         "right_wheel=300"], ("--input", "powers of powers")),
    ("cli-input-divide-zero", None, {}, [*KIN_CD, "-i", "left_wheel=3 rpm / 0", "-i",
                                         "right_wheel=300"], ("--input", "division by zero")),
    ("cli-input-long", None, {}, [*KIN_CD, "-i", "left_wheel=1" + " " * 90 + "rpm", "-i",
                                  "right_wheel=300"], ("--input", "80 characters")),
    ("cli-input-huge-number", None, {}, [*KIN_CD, "-i", "left_wheel=" + "1" * 300, "-i",
                                         "right_wheel=300"], ("--input", "implausible")),
    # ---- plausibility ranges (geometry, inertias, tooth counts) --------------------------------
    ("teeth-1e18", CD, {"gear_pairs[0].a.teeth": 10**18}, None, ("teeth", "10000")),
    ("planet-teeth-1e18", DC, {"planetary[0].planet_teeth": 10**18}, DIAG,
     ("planet_teeth", "10000")),
    ("inertia-1e-300", PB, {f"{ST}.sun.inertia_kgm2": 1e-300}, MODES,
     ("sun.inertia_kgm2", "implausible")),
    ("mass-1e-300", PB, {f"{ST}.planet.mass_kg": 1e-300}, MODES,
     ("planet.mass_kg", "implausible")),
    ("rotor-inertia-1e-300", DC, {"planetary_dynamics.rotors[0].inertia_kgm2": 1e-300}, DIAG,
     ("'motor'.inertia_kgm2", "implausible")),
    ("dyn-link-inertia-1e-300", CDD, {"dynamics.links[0].inertia_kgm2": 1e-300}, MODES,
     ("dynamics.links[0].inertia_kgm2", "implausible")),
    ("rim-above-root", G2, {f"{GG}.a.rim_radius_m": 0.5}, ["stiffness", "{cfg}", "--samples",
                                                           "8"],
     ("rim_radius_m", "root radius")),
    # ---- dynamics ([dynamics], planetary_dynamics) -------------------------------------------
    ("dyn-t-end-1e12", CDD, {f"{DYN}.t_end_s": 1e12}, SIMULATE, ("t_end_s", "implausible")),
    ("dyn-dt-1e-12", CDD, {f"{DYN}.dt_s": 1e-12}, SIMULATE, ("dt_s", "steps", "limit")),
    ("dyn-dt-nan", CDD, {f"{DYN}.dt_s": NAN}, SIMULATE, ("dt_s", "finite")),
    ("dyn-module-negative", CDD, {"dynamics.module_m": -0.005}, MODES, ("module_m",)),
    ("dyn-face-width-units", CDD, {"dynamics.face_width_m": "20 rpm"}, MODES,
     ("face_width_m", "not a length")),
    ("dyn-link-unknown", CDD, {"dynamics.links[0].link": "ghost"}, MODES, ("ghost",)),
    ("dyn-mesh-unknown", CDD, {"dynamics.meshes[0].pair": "ghost"}, MODES, ("ghost",)),
    ("dyn-torque-body", CDD, {f"{DYN}.torques[0].body": "ghost"}, SIMULATE, ("ghost",)),
    ("dyn-save-every-zero", CDD, {f"{DYN}.save_every": 0}, SIMULATE, ("save_every",)),
    ("pb-dt-1e-12", PB, {f"{SIM}.dt_s": 1e-12}, SIMULATE, ("dt_s", "steps", "limit")),
    ("pb-record-alloc", PB, {f"{SIM}.t_end_s": 9e6, f"{SIM}.dt_s": 1e-5}, SIMULATE,
     ("t_end_s", "limit")),
    ("sensor-rate-alloc", DC, {"sensors[0].sample_rate_hz": 5e8}, DIAG,
     ("'ring_acc'.sample_rate_hz", "samples", "limit")),
    ("cli-simulate-t-end-1e12", PB, {}, [*SIMULATE, "--t-end", "1e12"],
     ("--t-end", "implausible")),
    ("cli-simulate-revolutions-planetary", PB, {}, [*SIMULATE, "--revolutions", "5"],
     ("--revolutions", "transmission")),
    ("cli-simulate-checkpoint-nan", PB, {}, [*SIMULATE, "--checkpoint-every", "nan"],
     ("--checkpoint-every", "finite")),
    ("cli-simulate-out-long", PB, {}, ["simulate", "{cfg}", "--out", "{long}.nc"],
     ("--out", "file name", "255")),
    ("cli-simulate-corrupt-checkpoint", PB, {}, [*SIMULATE, "--resume"],
     ("--resume", "checkpoint", "unreadable")),
    ("cli-modes-campbell-count", PB, {}, [*MODES, "--campbell", "0:3000:1000000000 rpm"],
     ("--campbell", "limit")),
    ("cli-modes-campbell-1e12", PB, {}, [*MODES, "--campbell", "0:1e12:5 rpm"],
     ("--campbell", "implausible")),
    ("cli-modes-campbell-nan", PB, {}, [*MODES, "--campbell", "0:nan:5 rpm"],
     ("--campbell", "finite")),
    ("cli-modes-campbell-unit", PB, {}, [*MODES, "--campbell", "0:3000:5 furlongs"],
     ("--campbell", "unit")),
    ("cli-modes-campbell-modes-zero", PB, {}, [*MODES, "--campbell", "0:3000:5 rpm",
                                               "--campbell-modes", "0"],
     ("--campbell-modes",)),
    ("cli-transmission-campbell-1e12", TR, {}, ["transmission", "{cfg}", "--modes-only",
                                                "--campbell", "1e12"],
     ("--campbell", "implausible")),
    ("cli-transmission-revolutions-1e12", TR, {}, ["transmission", "{cfg}", "--revolutions",
                                                   "1e12"], ("--revolutions", "limit")),
    ("cli-stiffness-samples-huge", G2, {}, ["stiffness", "{cfg}", "--samples", "1000000000"],
     ("--samples", "≤ 65536")),
    ("cli-stiffness-cycles-huge", G2, {}, ["stiffness", "{cfg}", "--samples", "64",
                                           "--cycles", "1e9"], ("--cycles", "≤ 10000")),
    ("cli-config-long-name", None, {}, ["kinematics", "{long}.toml"],
     ("CONFIG", "file name", "255")),
    ("cli-config-nested", RAW, {"text": NESTED}, None, ("nested",)),
    ("cli-config-not-utf8", RAWB, {"bytes": b"name = \"\xff\"\nframe = \"a\"\n"}, None,
     ("not valid toml", "utf-8")),
    # ---- diagnose: options named as typed ------------------------------------------------------
    ("diag-k-nan", DC, {}, [*DIAG, "--k", "nan"], ("--k", "finite")),
    ("diag-k-negative", DC, {}, [*DIAG, "--k", "-1"], ("--k", "> 0")),
    ("diag-blocks-zero", DC, {}, [*DIAG, "--blocks", "0"], ("--blocks", "≥ 1")),
    ("diag-blocks-many", DC, {}, [*DIAG, "--blocks", "100"], ("--blocks", "64")),
    ("diag-skip-negative", DC, {}, [*DIAG, "--skip", "-1"], ("--skip", "≥ 0")),
    ("diag-sigma-floor", DC, {}, [*DIAG, "--sigma-floor", "2"], ("--sigma-floor", "1")),
    ("diag-t-end-zero", DC, {}, [*DIAG, "--t-end", "0"], ("--t-end", "> 0")),
    ("diag-t-end-1e12", DC, {}, [*DIAG, "--t-end", "1e12"], ("--t-end", "implausible")),
    ("diag-record-seed", DC, {}, [*DIAG, "--record-seed", "-3"], ("--record-seed", "≥ 0")),
    ("diag-seeds-negative", DC, {}, [*DIAG, "--seeds", "0,-1"], ("--seeds", "0")),
    ("diag-record-seed-in-baseline", DC, {}, [*DIAG, "--seeds", "0,1", "--record-seed", "1"],
     ("--record-seed", "baseline")),
    ("diag-p-fa-high", DC, {}, [*DIAG, "--false-alarm-probability", "2"],
     ("--false-alarm-probability", "diagnosis.false_alarm_probability", "0.2")),
    ("diag-seeds-repeated", DC, {}, [*DIAG, "--seeds", "0,1,1"], ("--seeds", "distinct")),
    ("diag-revolutions-planetary", DC, {}, [*DIAG, "--revolutions", "5"], ("--revolutions",)),
    ("diag-out-long", DC, {}, ["diagnose", "{cfg}", "--out", "{long}"],
     ("--out", "file name", "255")),
    ("diag-baseline-corrupt", DC, {}, [*DIAG, "--baseline", "{sig}/bad.nc", "--record",
                                       "{sig}/bad.nc"], ("baseline", "cannot read", "netcdf")),
    # ---- analyze: unreadable files and resource limits ---------------------------------------
    ("an-signal-empty-file", None, {}, ["analyze", "{sig}/empty.npy", "--config",
                                        str(EXAMPLES / "hammami_back_to_back.toml"), "--fs",
                                        "20000", "-s", "motor=1500"], ("signal",)),
    ("an-signal-corrupt-npz", None, {}, ["analyze", "{sig}/corrupt.npz", "--config",
                                         str(EXAMPLES / "hammami_back_to_back.toml"), "--fs",
                                         "20000", "-s", "motor=1500"], ("signal",)),
    ("an-signal-long-name", None, {}, ["analyze", "{long}.npy", "--config",
                                       str(EXAMPLES / "hammami_back_to_back.toml"), "--fs",
                                       "20000", "-s", "motor=1500"],
     ("SIGNAL", "file name", "255")),
    ("an-spr-huge", None, {}, ["analyze", "{sig}/s.npy", "--config",
                               str(EXAMPLES / "hammami_back_to_back.toml"), "--fs", "20000",
                               "-s", "motor=1500", "--samples-per-rev", "1000000000", "--out",
                               "{tmp}/rep"], ("--samples-per-rev", "≤ 65536")),
    ("an-fs-huge", None, {}, ["analyze", "{sig}/s.npy", "--config",
                              str(EXAMPLES / "hammami_back_to_back.toml"), "--fs", "1e12",
                              "-s", "motor=1500", "--out", "{tmp}/rep"],
     ("--fs", "implausible")),
]


def _fill(text: str, cfg: Path, tmp: Path, sig: Path) -> str:
    return text.format(cfg=cfg, tmp=tmp, sig=sig, long=tmp / LONG)


def _write_case(tmp_path: Path, sig: Path, base: str | None, edits: dict) -> Path:
    cfg = tmp_path / "case.toml"
    if base == RAW:
        cfg.write_text(edits["text"])
    elif base == RAWB:
        cfg.write_bytes(edits["bytes"])
    elif base == SW:
        data = copy.deepcopy(_spec())
        for path, value in edits.items():
            if isinstance(value, str):
                value = _fill(value, cfg, tmp_path, sig)
            if path.startswith("axes[") and path[5] != "0" and value is not DEL:
                data["axes"].append(value)  # a second axis
                continue
            _set(data, path, value)
        cfg.write_text(to_toml(data))
    elif base is not None:
        data = _base(base)
        for path, value in edits.items():
            _set(data, path, value)
        cfg.write_text(to_toml(data))
    return cfg


def _prepare(name: str, tmp_path: Path, sig: Path) -> None:
    """Files some cases need beside the config."""
    if name == "cli-simulate-corrupt-checkpoint":
        (tmp_path / "run.nc.ckpt.npz").write_bytes(b"PK\x03\x04 garbage, not a zip archive")
    (sig / "empty.npy").write_bytes(b"")
    (sig / "corrupt.npz").write_bytes(b"PK\x03\x04 not really a zip")


@pytest.mark.parametrize(("name", "base", "edits", "args", "expected"),
                         CASES, ids=[c[0] for c in CASES])
def test_malformed_input(tmp_path, signals, name, base, edits, args, expected):  # noqa: F811
    cfg = _write_case(tmp_path, signals, base, edits)
    _prepare(name, tmp_path, signals)
    line = [_fill(a, cfg, tmp_path, signals) for a in (args or ["kinematics", "{cfg}"])]
    start = time.monotonic()
    r = runner.invoke(app, line, terminal_width=200)
    took = time.monotonic() - start
    out = r.output
    assert r.exit_code not in (0, None), f"accepted (exit 0): {out[-800:]}"
    assert r.exception is None or isinstance(r.exception, SystemExit), repr(r.exception)
    assert "Traceback" not in out
    assert "internal error" not in out, out[-800:]
    assert took < 60.0, f"took {took:.1f} s"
    text = _normal(out)
    missing = [w for w in expected if _normal(_fill(w, cfg, tmp_path, signals)) not in text]
    assert not missing, f"message lacks {missing}: {out[-1200:]}"


def test_newer_corpus_is_large_and_covers_the_newer_inputs():
    assert len(CASES) >= 120
    assert len({c[0] for c in CASES}) == len(CASES)
    commands = {(c[3] or ["kinematics"])[0] for c in CASES}
    assert {"sweep", "diagnose", "simulate", "modes", "analyze", "stiffness",
            "transmission", "kinematics"} <= commands
    assert sum(c[1] == SW for c in CASES) >= 40
