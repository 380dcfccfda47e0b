"""The detectability study of the diagnosis (issue 18): design, statistics and its page.

**Design** (:func:`design`). Three machines — the seed 004 reclaimer planetary gearbox
(3 planets, 19/32/83, examples/seed004_diagnose_sun_crack.toml), the 4-planet stage of
examples/planet_crack_4_planets.toml (21/31/83) and the seed 002 two-stage FE transmission
(examples/seed002_diagnose_spall.toml) — each in many *configurations* drawn uniformly at
random from stated ranges: operating point (speed × U(0.8, 1.2), load × U(0.6, 1.2)), sensor
(ring angle U(0°, 360°) or bearing housing and direction), housing-mode frequency and damping
ratio, sensor noise × U(0.5, 3). Each configuration has its own healthy baseline ensemble
(``[diagnosis.ensemble]`` defaults, as ``geardyn diagnose``) and is judged on four healthy
records (seeds 100–103) and nine faulty ones (three fault kinds × three sizes, seed 100), each
record another machine of the same fleet (perturbation seed 1000 + configuration index; its
run seed, which draws the manufacturing errors and the sensor noise, mixed with the
configuration: :func:`geardyn.sweep.diagnosis.fleet_run_seed`):
planetary machines a tooth crack of 10, 20, 30 % of the tooth thickness on the sun, the ring
or one planet (drawn per configuration); the FE transmission an outer-race spall on the output
ball bearing in its load zone (5°, 10.9°, 20° long, 100 µm deep), a spall on tooth 1 of the
55-tooth wheel (100 µm deep, 3.1, 6.25, 12.5 mm of the 25 mm face: deeper spalls
than the contact's approach all lose contact alike) and a root crack on its tooth 0 (0.5, 1, 2 mm).

**Halves.** Before anything runs, the configurations of each machine are permuted with the
study seed and split in two: the *tune* half (looked at while developing) and the *report* half
(the figures of the page). The page reports the report half; the tune half is listed apart.

**Statistics** (:func:`statistics`): false-alarm rate of the healthy records against the stated
false-alarm probability; probability of detection per fault kind and size and against the
record's SNR; isolation accuracy among detected faults (planet level apart); detected faults
reported healthy (0 by construction: :mod:`geardyn.diagnosis.localise`). Intervals are
Clopper–Pearson 95 % (Clopper & Pearson 1934).

**Planetary run length** (:func:`geardyn.sweep.verdicts.diagnosis_run_length_s`): what the
verdict needs — 2 planet-separated rows per planet (the evidence that names a planet) and 4
own revolutions of every rotating component after ``skip_s``, at the ensemble's slowest speed —
set per configuration; not tuned on results.

Run: ``python -m geardyn.studies.detectability --out study --docs docs``. It runs through
``geardyn sweep`` (:mod:`geardyn.studies.sweeps`): one spec per machine (and faulty planet),
``study/<machine>.toml`` next to its store ``study/<machine>.zarr`` (``[outputs.diagnosis]``,
:mod:`geardyn.sweep.diagnosis`), run as ``geardyn sweep SPEC --out STORE`` runs it — resumable,
a ``--scheduler`` address runs it on a cluster —; ``--docs`` writes the page, its figures and
its rows (``docs/data/detectability_rows.json.gz``).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from geardyn.studies.runner import Configuration, RecordSpec

#: Study seed (draws of the configurations and of the halves).
SEED = 2026
#: Healthy record seeds and the seed of the faulty records (paired with the first healthy).
HEALTHY_SEEDS = (100, 101, 102, 103)
FAULT_SEED = 100
#: Perturbation seed of the record machines of configuration i: FLEET_SEED + i (each
#: configuration's records are other machines of the fleet; the baselines use seed 0).
FLEET_SEED = 1000
#: Configurations per machine.
CONFIGURATIONS = {"planetary 3 planets": 10, "planetary 4 planets": 8, "FE transmission": 10}
#: Crack sizes of the planetary machines (fraction of the tooth thickness, seed 004 ch. 9).
CRACK_FRACTIONS = (0.1, 0.2, 0.3)
#: FE transmission fault sizes (seed 002 §4.3 and §3.5.2 sizes at the middle).
BEARING_SPALL_DEG = (5.0, 10.909, 20.0)
TOOTH_SPALL_LENGTH_M = (3.125e-3, 6.25e-3, 12.5e-3)
TOOTH_CRACK_M = (0.5e-3, 1.0e-3, 2.0e-3)

#: Unit of each fault kind's size.
SIZE_UNITS = {"sun crack": "1 (of the tooth thickness)", "ring crack": "1 (of the tooth "
              "thickness)", "planet crack": "1 (of the tooth thickness)",
              "bearing outer-race spall": "deg", "tooth spall": "m (axial length)",
              "tooth crack": "m (depth)"}

_ROOT = Path(__file__).resolve().parents[3]


def _examples() -> Path:
    return _ROOT / "examples"


def _planetary_records(planet: int) -> tuple[RecordSpec, ...]:
    path = "planetary_dynamics.stages[0].faults"
    recs = [RecordSpec("healthy", "healthy", 0.0, {}, s) for s in HEALTHY_SEEDS]
    for gear in ("sun", "ring", "planet"):
        for c in CRACK_FRACTIONS:
            fault: dict[str, Any] = {"kind": "crack", "gear": gear, "crack_fraction": c}
            if gear == "planet":
                fault["planet"] = planet
            recs.append(RecordSpec(f"{gear} crack {c:.0%}", f"{gear} crack", c,
                                   {path: [fault]}, FAULT_SEED))
    return tuple(recs)


def _fe_records(bearing: int, pair: int) -> tuple[RecordSpec, ...]:
    recs = [RecordSpec("healthy", "healthy", 0.0, {}, s) for s in HEALTHY_SEEDS]
    for deg in BEARING_SPALL_DEG:
        recs.append(RecordSpec(
            f"outer-race spall {deg:.3g}°", "bearing outer-race spall", deg,
            {f"transmission.bearings[{bearing}].outer_spall":
             {"angle_deg": 110.0, "angular_length_deg": deg, "depth_m": 100e-6}}, FAULT_SEED))
    for length in TOOTH_SPALL_LENGTH_M:
        recs.append(RecordSpec(
            f"tooth spall {length * 1e3:.3g} mm", "tooth spall", length,
            {f"gear_geometry[{pair}].spalls": [
                {"gear": "b", "tooth": 1, "radius_m": 0.0825, "radial_width_m": 0.0029,
                 "depth_m": 100e-6, "axial_position_m": 0.0125,
                 "axial_length_m": length}]}, FAULT_SEED))
    for d in TOOTH_CRACK_M:
        recs.append(RecordSpec(
            f"tooth crack {d * 1e3:.1f} mm", "tooth crack", d,
            {f"gear_geometry[{pair}].cracks": [
                {"gear": "b", "tooth": 0, "depth_m": d, "angle_deg": 45.0}]}, FAULT_SEED))
    return tuple(recs)


def _halves(n: int, rng: np.random.Generator) -> list[str]:
    order = rng.permutation(n)
    half = ["report"] * n
    for i in order[: n // 2]:
        half[int(i)] = "tune"
    return half


def design(seed: int = SEED, counts: dict[str, int] | None = None) -> list[Configuration]:
    """The study's configurations (module docstring), the same for the same seed."""
    from geardyn.config.loader import load_config

    counts = dict(CONFIGURATIONS if counts is None else counts)
    rng = np.random.default_rng(seed)
    out: list[Configuration] = []
    ex = _examples()
    for machine, n in counts.items():
        halves = _halves(n, rng)
        for i in range(n):
            f = float(rng.uniform(0.8, 1.2))
            g = float(rng.uniform(0.6, 1.2))
            mode_damping = float(rng.uniform(0.02, 0.10))
            noise = float(rng.uniform(0.5, 3.0))
            cid = f"{machine.split()[0][:2]}{machine.split()[1][0]}-{i:02d}"
            if machine.startswith("planetary"):
                base = ex / ("seed004_diagnose_sun_crack.toml" if "3" in machine
                             else "planet_crack_4_planets.toml")
                cfg = load_config(base)
                n_planets = cfg.planetary[0].n_planets
                angle = float(rng.uniform(0.0, 360.0))
                mode_hz = float(rng.uniform(600.0, 2000.0))
                planet = int(rng.integers(1, n_planets + 1))
                acc = next(j for j, s in enumerate(cfg.sensors) if s.name == "ring_acc")
                s0 = cfg.sensors[acc]
                update = {f"sensors[{acc}].sensor_angle_deg": angle,
                          f"sensors[{acc}].transfer_path[0].frequency_hz": mode_hz,
                          f"sensors[{acc}].transfer_path[0].damping_ratio": mode_damping,
                          f"sensors[{acc}].noise_rms": s0.noise_rms * noise}
                params = {"sensor": f"ring {angle:.0f}°", "mode_hz": mode_hz,
                          "mode_damping": mode_damping, "noise_factor": noise,
                          "planets": n_planets, "faulty_planet": planet}
                records = _planetary_records(planet)
            else:
                base = ex / "seed002_diagnose_spall.toml"
                cfg = load_config(base)
                names = [b.name for b in cfg.transmission.bearings]
                housing = str(rng.choice(["output ball", "intermediate ball", "input ball"]))
                direction = str(rng.choice(["x", "y"]))
                mode_hz = float(rng.uniform(2000.0, 6000.0))
                acc = next(j for j, s in enumerate(cfg.sensors) if s.name == "acc_output")
                s0 = cfg.sensors[acc]
                update = {f"sensors[{acc}].location": housing,
                          f"sensors[{acc}].direction": direction,
                          f"sensors[{acc}].transfer_path[0].frequency_hz": mode_hz,
                          f"sensors[{acc}].transfer_path[0].damping_ratio": mode_damping,
                          f"sensors[{acc}].noise_rms": s0.noise_rms * noise}
                params = {"sensor": f"{housing} {direction}", "mode_hz": mode_hz,
                          "mode_damping": mode_damping, "noise_factor": noise,
                          "planets": 0, "faulty_planet": 0}
                pair = next(j for j, p in enumerate(cfg.gear_geometry) if p.pair == "low")
                records = _fe_records(names.index("output ball"), pair)
            out.append(Configuration(cid, machine, halves[i], str(base), update, f, g,
                                     records, params, fleet_seed=FLEET_SEED + len(out)))
    return out


# ---- statistics ------------------------------------------------------------------------

def clopper_pearson(k: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """Exact binomial interval of k successes in n (Clopper & Pearson 1934)."""
    from scipy.stats import beta

    if n == 0:
        return math.nan, math.nan
    a = (1.0 - level) / 2.0
    lo = 0.0 if k == 0 else float(beta.ppf(a, k, n - k + 1))
    hi = 1.0 if k == n else float(beta.ppf(1.0 - a, k + 1, n - k))
    return lo, hi


def _true(v: Any) -> bool:  # noqa: ANN401
    """A flag of a row: True only for a true boolean (None, NaN: not true)."""
    return isinstance(v, bool | np.bool_) and bool(v)


def _rate(mask: pd.Series) -> dict[str, float]:
    k, n = int(np.sum(mask.to_numpy(bool))), int(mask.size)
    lo, hi = clopper_pearson(k, n)
    return {"k": k, "n": n, "rate": k / n if n else math.nan, "low": lo, "high": hi}


def statistics(rows: pd.DataFrame, half: str | None = "report") -> dict[str, Any]:
    """The study's figures over the rows of ``half`` (None: all)."""
    df = rows if half is None else rows[rows["half"] == half]
    ok = df[df["status"] == "ok"]
    healthy = ok[ok["fault_type"] == "healthy"]
    faults = ok[ok["fault_type"] != "healthy"]
    detected = faults[faults["detected"].map(_true).to_numpy(bool)]
    out: dict[str, Any] = {
        "records": int(len(df)), "failed": int((df["status"] != "ok").sum()),
        "configurations": int(df["config"].nunique()),
        "false_alarm": _rate(healthy["detected"].map(_true)),
        "false_alarm_by_machine": {m: _rate(g["detected"].map(_true))
                                   for m, g in healthy.groupby("machine")},
        "detection": _rate(faults["detected"].map(_true)),
        "isolation": _rate(detected["localised"].map(_true)),
        "detected_reported_healthy": int((detected["verdict"] == "healthy").sum()),
        "pod": {}, "isolation_by_kind": {}, "pod_snr": {},
    }
    for (m, kind, sev), g in faults.groupby(["machine", "fault_type", "severity"]):
        out["pod"][(m, kind, sev)] = _rate(g["detected"].map(_true))
    for (m, kind), g in detected.groupby(["machine", "fault_type"]):
        out["isolation_by_kind"][(m, kind)] = _rate(g["localised"].map(_true))
    planets = detected[detected["fault_type"] == "planet crack"]
    planets = planets[planets["localised"].map(_true).to_numpy(bool)]
    out["planet_named"] = _rate(planets["planet_named"].map(_true))
    out["planet_named_by_machine"] = {
        m: _rate(g["planet_named"].map(_true))
        for m, g in planets.groupby("machine")}
    snr = faults["snr"].astype(float)
    edges = [0.0, 1.0, 10.0, 100.0, 1e3, 1e4, 1e5, np.inf]
    for lo, hi in zip(edges[:-1], edges[1:], strict=True):
        g = faults[(snr >= lo) & (snr < hi)]
        if len(g):
            out["pod_snr"][(lo, hi)] = _rate(g["detected"].map(_true))
    return out


# ---- page ------------------------------------------------------------------------------

def _ci(r: dict[str, float], pct: bool = True) -> str:
    if not r["n"]:
        return "—"
    f = (lambda x: f"{100 * x:.1f} %") if pct else (lambda x: f"{x:.3f}")
    return f"{r['k']}/{r['n']} = {f(r['rate'])} [{f(r['low'])}, {f(r['high'])}]"


def figures(rows: pd.DataFrame, img: Path, half: str = "report") -> list[str]:
    """POD against fault size (per machine and kind) and against SNR, report half."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    st = statistics(rows, half)
    img.mkdir(parents=True, exist_ok=True)
    names = []
    kinds = sorted({(m, k) for m, k, _ in st["pod"]})
    fig, axes = plt.subplots(1, 3, figsize=(13, 4), sharey=True)
    for ax, machine in zip(axes, CONFIGURATIONS, strict=True):
        for m, k in kinds:
            if m != machine:
                continue
            pts = sorted((s, r) for (mm, kk, s), r in st["pod"].items() if (mm, kk) == (m, k))
            x = np.arange(len(pts))
            y = np.array([r["rate"] for _, r in pts])
            err = np.array([[r["rate"] - r["low"] for _, r in pts],
                            [r["high"] - r["rate"] for _, r in pts]])
            ax.errorbar(x, y, yerr=err, marker="o", capsize=3, label=k)
        ax.set_xticks(range(3))
        ax.set_xticklabels(["size 1", "size 2", "size 3"])
        ax.set_xlabel("fault size level [-] (see table)")
        ax.set_title(machine)
        ax.set_ylim(-0.05, 1.05)
        ax.legend(fontsize=8)
    axes[0].set_ylabel("probability of detection [-] (95 % CI)")
    fig.tight_layout()
    name = "detectability_pod_size.png"
    fig.savefig(img / name, dpi=110)
    plt.close(fig)
    names.append(name)
    fig, ax = plt.subplots(figsize=(6, 4))
    pts = sorted(st["pod_snr"].items())
    xs = [math.sqrt(max(lo, 0.1) * (hi if math.isfinite(hi) else lo * 10)) for (lo, hi), _ in pts]
    ys = [r["rate"] for _, r in pts]
    err = [[r["rate"] - r["low"] for _, r in pts], [r["high"] - r["rate"] for _, r in pts]]
    ax.errorbar(xs, ys, yerr=err, marker="o", capsize=3)
    ax.set_xscale("log")
    ax.set_xlabel("record SNR [-] (fault signature power / sensor noise power)")
    ax.set_ylabel("probability of detection [-] (95 % CI)")
    ax.set_ylim(-0.05, 1.05)
    fig.tight_layout()
    name = "detectability_pod_snr.png"
    fig.savefig(img / name, dpi=110)
    plt.close(fig)
    names.append(name)
    return names


def _run_lengths(rows: pd.DataFrame) -> str:
    """The planetary run lengths of the rows (``run_s``, written since the run length is set
    from the planet-separation requirement; older rows ran the examples' 50 s)."""
    need = ("the verdict's requirement (`geardyn.sweep.verdicts.diagnosis_run_length_s`: 2 "
            "planet-separated rows per planet and 4 own revolutions of every component after "
            "`skip_s`, at the ensemble's slowest speed)")
    plan = rows[rows["machine"].astype(str).str.startswith("planetary")]
    run = (pd.to_numeric(plan["run_s"], errors="coerce").dropna() if "run_s" in plan
           else pd.Series(dtype=float))
    if len(run):
        return (f"Planetary runs: {run.min():.1f}–{run.max():.1f} s per configuration, from "
                f"{need}.")
    return ("Planetary runs: 50 s, the examples' length (these rows predate the run length "
            f"set from {need}: at 50 s a planet has fewer than 2 planet-separated rows, so no "
            "planet can be named).")


def page(rows: pd.DataFrame, p_fa: float, command: str, cpu_s: float) -> str:
    """docs/detectability.md from the study rows."""
    rep = statistics(rows, "report")
    tune = statistics(rows, "tune")
    fa = rep["false_alarm"]
    lines = [
        "# Detectability study",
        "",
        "<!-- generated by `python -m geardyn.studies.detectability`; do not edit -->",
        "",
        "How often `geardyn diagnose` detects and localises faults on machines nobody tuned it "
        "for, and how often it raises a false alarm. Design, halves and statistics: "
        "`geardyn.studies.detectability` (module docstring).",
        "",
        f"Regenerate: `{command}` ({cpu_s / 3600:.1f} CPU hours for the whole study).",
        "",
        "The command writes one `geardyn sweep` spec per machine (and faulty planet) into the "
        "study folder, `study/<machine>.toml` next to its store `study/<machine>.zarr`, with "
        "`[outputs.diagnosis]`: each record judged as `geardyn diagnose` judges its config, "
        "against the baseline ensemble of its own healthy config "
        "([sweeps.md](sweeps.md#each-case-judged-as-geardyn-diagnose-judges-it-outputsdiagnosis))"
        "; the configurations are one zipped axis group (labels `configuration`, `half`), the "
        "records another (`record`, `fault_type`, `severity`). `geardyn sweep "
        "study/<machine>.toml --out study/<machine>.zarr` runs or resumes one alone "
        "(`--scheduler` for a cluster, as the study command); the rows of this page are kept "
        "in `docs/data/detectability_rows.json.gz`.",
        "",
        "## Design",
        "",
        "| machine | configurations | records per configuration | faults (three sizes each) |",
        "|---|---|---|---|",
        f"| planetary 3 planets (seed 004, 19/32/83) | {CONFIGURATIONS['planetary 3 planets']} | "
        f"{len(HEALTHY_SEEDS)} healthy + 9 faulty | tooth crack 10/20/30 % on sun, ring, "
        "one planet |",
        f"| planetary 4 planets (21/31/83) | {CONFIGURATIONS['planetary 4 planets']} | "
        f"{len(HEALTHY_SEEDS)} healthy + 9 faulty | tooth crack 10/20/30 % on sun, ring, "
        "one planet |",
        f"| FE transmission (seed 002) | {CONFIGURATIONS['FE transmission']} | "
        f"{len(HEALTHY_SEEDS)} healthy + 9 "
        "faulty | outer-race spall 5/10.9/20°; tooth spall 3.1/6.25/12.5 mm long; root crack "
        "0.5/1/2 mm |",
        "",
        "Drawn per configuration (uniform): speed × [0.8, 1.2], load × [0.6, 1.2], sensor "
        "(ring angle 0–360° or bearing housing and direction), housing-mode frequency "
        "(600–2000 Hz planetary, 2–6 kHz FE) and damping ratio (0.02–0.10), sensor noise × "
        "[0.5, 3]. Each configuration is judged against its own healthy baseline ensemble "
        "(defaults of `[diagnosis.ensemble]`).",
        "",
        _run_lengths(rows),
        "",
        f"## Results (report half: {rep['configurations']} configurations, {rep['records']} "
        f"records, {rep['failed']} failed runs)",
        "",
        "Counts k/n = rate [95 % Clopper–Pearson interval].",
        "",
        "| figure | report half | target |",
        "|---|---|---|",
        f"| false-alarm rate of healthy records | {_ci(fa)} | ≤ {100 * p_fa:.0f} % "
        f"(stated false-alarm probability {p_fa:g}), within × 2 |",
        f"| detection of faults (all sizes) | {_ci(rep['detection'])} | — |",
        f"| isolation among detected faults | {_ci(rep['isolation'])} | ≥ 95 % |",
        f"| planet named among localised planet faults | {_ci(rep['planet_named'])} | "
        "reported apart |",
        f"| detected faults reported healthy | {rep['detected_reported_healthy']} | 0 |",
        "",
        "### Probability of detection by fault and size",
        "",
        "| machine | fault | size | unit | detected |",
        "|---|---|---|---|---|",
    ]
    for (m, k, s), r in sorted(rep["pod"].items()):
        lines.append(f"| {m} | {k} | {s:g} | {SIZE_UNITS.get(k, '')} | {_ci(r)} |")
    lines += ["", "![POD against size](img/detectability_pod_size.png)", "",
              "### Probability of detection against SNR", "",
              "| SNR | detected |", "|---|---|"]
    for (lo, hi), r in sorted(rep["pod_snr"].items()):
        lines.append(f"| [{lo:g}, {hi:g}) | {_ci(r)} |")
    lines += ["", "![POD against SNR](img/detectability_pod_snr.png)", "",
              "### Isolation among detected faults", "", "| machine | fault | localised |",
              "|---|---|---|"]
    for (m, k), r in sorted(rep["isolation_by_kind"].items()):
        lines.append(f"| {m} | {k} | {_ci(r)} |")
    lines += ["", "False alarms by machine (report half):", ""]
    for m, r in sorted(rep["false_alarm_by_machine"].items()):
        lines.append(f"* {m}: {_ci(r)}")
    fa = rows[(rows["half"] == "report") & (rows["fault_type"] == "healthy")
              & rows["detected"].map(_true)]
    if len(fa):
        lines += ["", "The false alarms (report half): the first alarm and its margin "
                  "(value / threshold)", ""]
        for _, r in fa.iterrows():
            lines.append(f"* {r.get('config', '')} {r.get('record', '')} (seed "
                         f"{r.get('seed', '')}): {r.get('first_alarm', '')} "
                         f"{float(r.get('first_margin', math.nan)):.2f}, verdict "
                         f"{r.get('verdict', '')}")
    failed = rows[rows["status"] != "ok"]
    reasons = failed.groupby("status")["config"].agg(lambda c: sorted(set(c)))
    lines += ["", "## Limitations of this run", "",
              "* The record machines are other machines of the baseline's fleet (perturbation "
              f"seed drawn from {FLEET_SEED} and the configuration); the healthy records of one "
              "configuration share its operating point and sensor, so they are not independent "
              "of each other: the false-alarm interval treats them as if they were. Each "
              "configuration has run seeds of its own (manufacturing errors and sensor noise "
              "are not shared between configurations).",
              "* Healthy populations have heavier tails than the log-normal bound of each test "
              "assumes (kurtosis-type and bearing-line indicators over the manufacturing-error, "
              "clearance and operating-point draws); the thresholds' family floor is what keeps "
              "the false-alarm rate near the stated probability (measured in "
              "[diagnosis.md](diagnosis.md#known-limitations)). 56 healthy records cannot show "
              "a rate below about 5 %: the interval above is what they prove.",
              "* Failed runs (kept as rows, not judged):" + ("" if len(reasons) else " none.")]
    for reason, confs in reasons.items():
        lines.append(f"  {int((failed['status'] == reason).sum())} × `{reason[:100]}` "
                     f"({', '.join(confs)})")
    lines += ["", f"## Tune half ({tune['configurations']} configurations, not the figures "
              "above)", "",
              f"False alarms {_ci(tune['false_alarm'])}; detection {_ci(tune['detection'])}; "
              f"isolation {_ci(tune['isolation'])}; planet named "
              f"{_ci(tune['planet_named'])}; detected faults reported healthy "
              f"{tune['detected_reported_healthy']}.", ""]
    return "\n".join(lines)


def study_specs(confs: Sequence[Configuration], *,
                extra: dict[str, dict[str, Any]] | None = None,
                run_length: bool = True) -> list[Any]:
    """The sweep specs of the study (:func:`geardyn.studies.sweeps.specs`): each record a
    machine of its configuration's fleet (``record_machine = "fleet"``, seed
    :data:`FLEET_SEED`), the planetary run length from the verdict's requirement
    (``run_length``); ``extra``: machine → (config path → value) on its configurations."""
    from geardyn.studies.sweeps import specs

    return specs(confs, seed=SEED, diagnosis={"record_machine": "fleet",
                                              "fleet_seed": FLEET_SEED},
                 extra=extra, run_length=run_length)


def run_sweeps(confs: Sequence[Configuration], out: str | Path, *, scheduler: str | None = None,
               workers: int | None = 2, only: set[str] | None = None,
               progress: Any = None, **options: Any) -> list[dict[str, Any]]:  # noqa: ANN401
    """Write the study's specs into ``out`` and run them as ``geardyn sweep SPEC --out
    STORE`` does (resumable); returns the rows of every stored case. ``options``: those of
    :func:`study_specs`."""
    from geardyn.studies.sweeps import rows, run_specs, write_specs

    paths = write_specs(study_specs(confs, **options), out)
    run_specs(paths, scheduler=scheduler, workers=workers, only=only, progress=progress)
    return rows(paths, confs)


def write_rows(rows: list[dict[str, Any]], path: str | Path) -> None:
    """The rows as gzip-compressed JSON (docs/data/detectability_rows.json.gz)."""
    import gzip
    import json

    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    with gzip.open(p, "wt") as fh:
        json.dump(rows, fh, default=lambda v: v.item() if isinstance(v, np.generic) else str(v))


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m geardyn.studies.detectability",
                                 description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="study folder: one sweep spec and store per "
                    "machine (OUT/<machine>.toml, OUT/<machine>.zarr; resumable)")
    ap.add_argument("--docs", default=None, help="docs folder: writes detectability.md, "
                    "img/detectability_*.png and data/detectability_rows.json.gz")
    ap.add_argument("--scheduler", default=None, help="Dask scheduler address (default: a "
                    "LocalCluster)")
    ap.add_argument("--workers", type=int, default=2, help="LocalCluster worker processes")
    ap.add_argument("--only", default=None, help="comma-separated configuration ids to run")
    args = ap.parse_args(argv)
    if args.workers < 1:
        ap.error(f"--workers: must be >= 1, got {args.workers}")
    confs = design()
    only = None
    if args.only:
        only = {i.strip() for i in args.only.split(",") if i.strip()}
        unknown = sorted(only - {c.id for c in confs})
        if unknown or not only:
            ap.error(f"--only: unknown configuration id(s) {', '.join(unknown) or '(none)'}; "
                     f"the design has {', '.join(c.id for c in confs)}")
    t0 = time.time()
    rows = pd.DataFrame(run_sweeps(
        confs, args.out, scheduler=args.scheduler,
        workers=None if args.scheduler else args.workers, only=only,
        progress=lambda m: print(f"[{time.time() - t0:7.0f} s] {m}", flush=True)))
    if rows.empty:
        print("no rows stored yet")
        return 0
    if args.docs:
        docs = Path(args.docs)
        figures(rows, docs / "img")
        cpu = float(rows.drop_duplicates("config")["baseline_cpu_s"].fillna(0).sum()
                    + rows["record_cpu_s"].fillna(0).sum())
        (docs / "detectability.md").write_text(page(
            rows, 0.01, "python -m geardyn.studies.detectability --out study --docs docs",
            cpu))
        write_rows(rows.to_dict("records"), docs / "data" / "detectability_rows.json.gz")
    st = statistics(rows, None)
    print(f"records {st['records']} (failed {st['failed']}); false alarms "
          f"{_ci(st['false_alarm'])}; detection {_ci(st['detection'])}; isolation "
          f"{_ci(st['isolation'])}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
