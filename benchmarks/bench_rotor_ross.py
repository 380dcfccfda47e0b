"""Issue 24: the two-disc rotor (examples/rotor_two_discs.toml, 12 and 24 Timoshenko elements,
3000 rpm, 2 s from rest) side by side with ROSS in one run, and the seed 002 300-revolution run.

Columns: CPU seconds per simulated second (one thread) and the 1×-amplitude error of disc 1's x
over the last 0.5 s against each code's own harmonic solution (geardyn:
:func:`geardyn.models.transmission.modal.unbalance_response`; ROSS: ``run_unbalance_response``),
at two accuracy levels (~1e-4, ~1e-6):

- geardyn ``exponential`` (exact modal integration; output every 1e-4 s / 1e-5 s, the same
  output density as ROSS ``lsim`` at that level), ``newmark`` (h = 6e-5 s / 6e-6 s: the
  trapezoidal warp (Ωh)²/12 × the response's sensitivity gives ≈ 1e-4 / 1e-6), ``explicit``
  (its stability step; one accuracy);
- ROSS ``lsim`` (h = 1e-4 s / 1e-5 s) and ``newmark`` (h = 6e-5 s; at 6e-6 s its cost is
  measured on 0.2 s and its error, the same trapezoidal warp as geardyn's Newmark at that
  step, is not re-measured).

ROSS is not a geardyn dependency: it runs in a separate Python given by the environment
variable ``ROSS_PYTHON`` (default ``../ross-venv/bin/python`` beside the repository, e.g.
``python3 -m venv ../ross-venv && ../ross-venv/bin/pip install ross-rotordynamics "plotly<6"``),
through ``benchmarks/ross_rotor.py``; without it the ROSS rows say so and the ratios are not
computed. Targets (issue 24): ≥ 3× faster than ROSS's fastest time response and ≥ 10× faster
than ROSS's Newmark at both levels on 12 and 24 elements, cost ∝ elements^≤1.3, seed 002
300-revolution run (NSC 200-900 rpm) ≤ 8 CPU s with the default mass. The seed 002 rows time
the FE transmission with the modal integrator (its default) and the explicit loop in the same
run: cost per simulated second at 400 rpm against the elements per shaft (5, 10, 20) and the
NSC run.

Measured (issue 24, session 4, final code; shared 2-core machine, load average 6-9; ROSS
2.3.0), CPU s per simulated second (1×-amplitude error):

    level el.  g. exponential   g. newmark      g. explicit    ROSS lsim       ROSS newmark
    1e-4  12   0.0132 (1.2e-7)  0.152 (1.0e-4)  1.48 (6.3e-7)  0.125 (8.2e-5)  4.03 (1.0e-4)
    1e-4  24   0.0289 (1.1e-7)  0.261 (1.0e-4)  6.26 (3.3e-7)  0.388 (8.2e-5)  6.83 (1.0e-4)
    1e-6  12   0.0889 (1.2e-7)  1.50 (9.2e-7)   1.48           1.21 (9.4e-7)   37.6 (0.2 s)
    1e-6  24   0.170 (1.2e-7)   2.53 (9.2e-7)   6.26           3.91 (9.4e-7)   62.6 (0.2 s)

    speed-up of geardyn's fastest vs ROSS lsim: 9.5× / 13.4× (1e-4), 13.6× / 23.0× (1e-6);
    vs ROSS Newmark ≥ 236×. Cost ∝ elements^p: exponential 1.13 / 0.93, newmark 0.78 / 0.76,
    explicit 2.08. Seed 002 at 400 rpm, 15 → 60 shaft elements: modal p = 0.79, explicit
    p = 2.21. Seed 002 NSC 300 rev: modal 13.2 CPU s, explicit 22.9 CPU s (target ≤ 8: not met).

Measured again 2026-11-26 (session 6, idle machine, load 0.7–1.0, ROSS 2.3.0): speed-up of
geardyn's fastest vs ROSS lsim 13.1× / 15.2× (1e-4), 18.3× / 22.3× (1e-6); vs ROSS Newmark
253× / 206× (1e-4), 394× / 320× (1e-6); cost ∝ elements^p: exponential 1.13 / 1.04, newmark
0.74 / 0.76, explicit 1.98; seed 002 at 400 rpm, 15 → 60 elements: modal p = 0.81, explicit
2.32. Seed 002 NSC 300 rev: modal **8.2 CPU s** (this row includes the model's build and
preparation: a user's run; target ≤ 8 not met), explicit 18.0 CPU s. The issue-24 row of
``bench_transmission`` times the same run on an already prepared model: 7.79–7.99 CPU s.

Measured again 2026-11-26 (session 7, fresh clone, idle machine, load 1.1, ROSS 2.3.0), after
the work around the loop was trimmed (bit-identical records): speed-up of geardyn's fastest vs
ROSS lsim 12.2× / 15.8× (1e-4), 17.2× / 23.8× (1e-6); vs ROSS Newmark 266× / 209× (1e-4),
374× / 351× (1e-6); cost ∝ elements^p: exponential 1.11 / 0.96, newmark 0.75 / 0.82, explicit
1.99; seed 002 at 400 rpm, 15 → 60 elements: modal p = 0.82, explicit 2.24. Seed 002 NSC 300
rev, a user's whole call (build, preparation, loop, records): modal **7.6 CPU s** (target ≤ 8:
met; 7.57–7.86 over 6 calls in 3 processes), explicit 20.6 CPU s.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples" / "rotor_two_discs.toml"
W = 100 * math.pi
LEVELS = {"1e-4": {"exponential": 1e-4, "newmark": 6e-5, "ross_lsim": 1e-4, "ross_newmark": 6e-5},
          "1e-6": {"exponential": 1e-5, "newmark": 6e-6, "ross_lsim": 1e-5, "ross_newmark": 6e-6}}


def ross_python() -> Path | None:
    p = Path(os.environ.get("ROSS_PYTHON", ROOT.parent / "ross-venv" / "bin" / "python"))
    return p if p.exists() else None


def _ross(py: Path, n: int, method: str, h: float, t_end: float = 2.0) -> dict:
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1",
           "MKL_NUM_THREADS": "1"}
    out = subprocess.run([str(py), str(ROOT / "benchmarks" / "ross_rotor.py"), "time", str(n),
                          method, repr(h), repr(t_end)], capture_output=True, text=True,
                         env=env, cwd="/tmp", check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def _config(n: int, **sim):  # noqa: ANN202
    from geardyn.config.loader import load_config, parse_config

    d = load_config(EX).model_dump(exclude_none=True)
    t = d["transmission"]
    t["shafts"][0]["elements"] = n
    for part, frac in ((t["discs"][0], 1 / 3), (t["discs"][1], 3 / 4), (t["unbalance"][0], 1 / 3)):
        part["at"]["node"] = round(frac * n)
    t["supports"][1]["at"]["node"] = n
    t["simulation"].update(record=["disc 1"], **sim)
    return parse_config(d)


def _one_x(t: np.ndarray, x: np.ndarray, t_end: float = 2.0) -> complex:
    sel = (t >= t_end - 0.5) & (t < t_end)
    A = np.c_[np.cos(W * t[sel]), np.sin(W * t[sel]), np.ones(sel.sum())]
    c = np.linalg.lstsq(A, x[sel], rcond=None)[0]
    return complex(c[0], -c[1])


def _geardyn(n: int, integrator: str, h: float | None) -> dict:
    from geardyn.models.transmission import build_model, prepare, simulate
    from geardyn.models.transmission.modal import unbalance_response

    sim = {"integrator": integrator}
    if h is not None:
        sim.update(time_step_s=h, record_rate_hz=1.0 / h)
    cfg = _config(n, **sim)
    model = build_model(cfg)
    prep = prepare(model)
    node = model.discs["disc 1"]
    ref = unbalance_response(model, prep, 3000.0, node, 1e-4)[6 * node]
    simulate(_config(n, **{**sim, "duration_s": 0.01}), prepared=prep, model=model)  # compiled
    c0 = time.process_time()
    ds = simulate(cfg, prepared=prep, model=model)
    cpu = time.process_time() - c0
    x = ds.displacement.sel(dof=f"rotor.n{node}.x").values
    amp = abs(_one_x(ds.time.values, x))
    return {"cpu_per_sim_s": cpu / 2.0, "rel_error": abs(amp - abs(ref)) / abs(ref),
            "step_s": ds.attrs["time_step_s"]}


def _seed002_300rev(integrator: str = "auto") -> tuple[float, str, float]:
    """(CPU s, integrator, step) of the NSC 200-900 rpm / 300 revolution run with the default
    (consistent) mass, after a short run that loads the compiled kernels."""
    from geardyn.config.loader import load_config, parse_config
    from geardyn.models.transmission import simulate

    d = load_config(ROOT / "examples" / "seed002_transmission.toml").model_dump(exclude_none=True)
    d["transmission"]["speed_law"].update(start_rpm=200.0, end_rpm=900.0, revolutions=300.0)
    d["transmission"]["simulation"]["integrator"] = integrator
    cfg = parse_config(d)
    simulate(cfg, revolutions=0.05)
    c0 = time.process_time()
    ds = simulate(cfg)
    return time.process_time() - c0, ds.attrs["integrator"], ds.attrs["time_step_s"]


def _seed002_scaling(integrator: str) -> tuple[list[dict], float]:
    """CPU s per simulated second of the seed 002 transmission at 400 rpm with 5, 10 and 20
    elements per shaft (nodes scaled, :func:`benchmarks.bench_transmission._scaled_cfg`) and
    the fitted exponent of the cost against the element count."""
    from benchmarks.bench_transmission import _scaled_cfg
    from geardyn.config.loader import parse_config
    from geardyn.models.transmission import build_model, prepare, simulate

    rows, els, cost = [], [], []
    for el in (5, 10, 20):
        d = _scaled_cfg(el).model_dump(exclude_none=True)
        d["transmission"]["simulation"]["integrator"] = integrator
        cfg = parse_config(d)
        prep = prepare(build_model(cfg), "output")
        simulate(cfg, revolutions=0.02, prepared=prep)
        c0 = time.process_time()
        ds = simulate(cfg, revolutions=0.5, prepared=prep)
        c = (time.process_time() - c0) / float(ds.time[-1])
        els.append(3 * el)
        cost.append(c)
        rows.append({"code": f"geardyn {ds.attrs['integrator']}, seed 002 at 400 rpm, "
                     f"{3 * el} shaft elements", "step_s": ds.attrs["time_step_s"],
                     "cpu_s_per_sim_s": c})
    return rows, float(np.polyfit(np.log(els), np.log(cost), 1)[0])


def run() -> list[dict]:
    rows: list[dict] = []
    py = ross_python()
    cost: dict[tuple, float] = {}
    for level, steps in LEVELS.items():
        for n in (12, 24):
            g = {k: _geardyn(n, k, steps.get(k)) for k in ("exponential", "newmark")}
            g["explicit"] = _geardyn(n, "explicit", None) if level == "1e-4" else \
                cost[("explicit-row", n)]
            cost[("explicit-row", n)] = g["explicit"]
            for k, r in g.items():
                cost[(level, n, k)] = r["cpu_per_sim_s"]
                rows.append({"level": level, "elements": n, "code": f"geardyn {k}",
                             "step_s": r["step_s"], "cpu_s_per_sim_s": r["cpu_per_sim_s"],
                             "1x_rel_error": r["rel_error"]})
            if py is None:
                rows.append({"level": level, "elements": n, "code": "ROSS",
                             "note": "skipped: no ROSS Python (set ROSS_PYTHON)"})
                continue
            lsim = _ross(py, n, "lsim", steps["ross_lsim"])
            short = level == "1e-6"
            nmk = _ross(py, n, "newmark", steps["ross_newmark"], 0.2 if short else 2.0)
            for k, r, note in (("lsim", lsim, ""), ("newmark", nmk, "cost on 0.2 s; error not "
                               "measured" if short else "")):
                rows.append({"level": level, "elements": n, "code": f"ROSS {k}",
                             "step_s": steps[f"ross_{k}"], "cpu_s_per_sim_s": r["cpu_per_sim_s"],
                             "1x_rel_error": "" if short and k == "newmark" else r["rel_error"],
                             "note": note})
            best = min(cost[(level, n, k)] for k in ("exponential", "newmark", "explicit"))
            rows.append({"level": level, "elements": n, "code": "speed-up of geardyn's fastest",
                         "note": f"vs ROSS lsim {lsim['cpu_per_sim_s'] / best:.1f}× (target ≥ 3), "
                                 f"vs ROSS Newmark {nmk['cpu_per_sim_s'] / best:.1f}× "
                                 "(target ≥ 10)"})
    for k in ("exponential", "newmark", "explicit"):
        for level in LEVELS:
            e = math.log(cost[(level, 24, k)] / cost[(level, 12, k)]) / math.log(2.0)
            rows.append({"level": level, "code": f"geardyn {k}: cost ∝ elements^p",
                         "note": f"p = {e:.2f} (12 → 24 elements; target ≤ 1.3)"})
    for k in ("modal", "explicit"):
        srows, p = _seed002_scaling(k)
        rows += srows
        rows.append({"code": f"geardyn {k}, seed 002 transmission: cost ∝ elements^p",
                     "note": f"p = {p:.2f} (15 → 60 elements; target ≤ 1.3)"})
    cpu, scheme, h = _seed002_300rev()
    cpu_x, _, hx = _seed002_300rev("explicit")
    rows.append({"code": "seed 002 NSC 200-900 rpm / 300 rev, default (consistent) mass",
                 "step_s": h, "cpu_s_per_sim_s": "",
                 "note": f"{cpu:.1f} CPU s with '{scheme}' (target ≤ 8: "
                 f"{'met' if cpu <= 8.0 else 'not met'}); explicit loop "
                 f"(h = {hx:.3g} s) {cpu_x:.1f} CPU s in the same run: {cpu_x / cpu:.2f}× "
                 f"(load average {os.getloadavg()[0]:.1f})"})
    return rows
