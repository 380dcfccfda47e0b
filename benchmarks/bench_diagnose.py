"""``diagnose`` wall time on the seed 004 reclaimer gearbox with a 20 % sun-tooth crack
(``examples/seed004_diagnose_sun_crack.toml``: ring accelerometer, ``[diagnosis]`` settings),
one core: healthy baseline runs (3 seeds) + the faulty record, indicators per component,
thresholds, verdict.json and report.html. Target: under 60 s (issue 9).

Rows: the whole ``diagnose`` call (simulated seconds per run from ``[diagnosis].t_end_s``) and
its parts (one simulation; features of one run; verdict + report), and the verdict itself
(components in alarm, sun margin; localised: alarms only on the sun wheel or its shaft).
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

from geardyn.config.loader import load_config
from geardyn.diagnosis.pipeline import diagnose, options
from geardyn.run import run_simulation

EX = Path(__file__).resolve().parents[1] / "examples" / "seed004_diagnose_sun_crack.toml"
TARGET_S = 60.0


def _timed(fn, *args, **kwargs):  # noqa: ANN001, ANN002, ANN003, ANN202
    t0 = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - t0


def run() -> list[dict]:
    from geardyn.diagnosis.features import features_from_result

    cfg = load_config(EX)
    opts = options(cfg)
    run_simulation(cfg, seed=0, t_end_s=0.5)  # compile / load the numba cache
    ds, t_sim = _timed(run_simulation, cfg, seed=opts.record_seed, t_end_s=opts.t_end_s)
    channel = opts.channel or next(str(v)[8:] for v in ds.data_vars if
                                   str(v).startswith("sensors."))
    _, t_feat = _timed(features_from_result, ds, cfg, channel, reference=opts.reference,
                       skip_s=opts.skip_s, n_blocks=opts.blocks)
    with tempfile.TemporaryDirectory() as tmp:
        verdict, t_all = _timed(diagnose, cfg, tmp)
        html_kb = (Path(tmp) / "report.html").stat().st_size / 1024
    n_runs = len(opts.baseline_seeds) + 1
    sun = verdict.components.get("planetary.sun")
    worst = sun.isolation or sun.worst if sun is not None else None
    t_end = opts.t_end_s or cfg.planetary_dynamics.simulation.t_end_s
    return [
        {"case": f"diagnose: {n_runs} runs × {t_end:g} s simulated, verdict + report",
         "measured": f"{t_all:.1f} s wall", "target": f"< {TARGET_S:g} s",
         "met": t_all < TARGET_S},
        {"case": "  one simulation with sensors", "measured": f"{t_sim:.2f} s wall",
         "target": "", "met": ""},
        {"case": "  features of one run (all components)", "measured": f"{t_feat:.2f} s wall",
         "target": "", "met": ""},
        {"case": "  rest (isolation blocks, thresholds, verdict, report)",
         "measured": f"{t_all - n_runs * (t_sim + t_feat):.2f} s wall ({html_kb:.0f} kB page)",
         "target": "", "met": ""},
        {"case": "verdict", "measured": f"alarms {verdict.alarms}; sun "
         f"{worst[0]} margin {worst[1]:.3g}" if worst else f"alarms {verdict.alarms}",
         "target": "alarms on the sun (wheel or shaft) only",
         "met": verdict.summary()["localised"]},
    ]
