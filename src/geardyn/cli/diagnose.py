"""``geardyn diagnose CONFIG.toml --out DIR``: healthy baseline, record, thresholds and verdict.

Without files, simulates the healthy variant of the config (every fault removed) for each
baseline seed and the configured machine with the record seed. With ``--record FILE`` (a
measured file of any format mapped by the config's ``[measurement]`` section, or a geardyn
result), judges that record against simulated healthy runs, or against ``--baseline FILE …``
(measured or simulated files), or both (``--baseline … --simulate-baseline``;
:mod:`geardyn.diagnosis.measured`). Writes
``DIR/verdict.json`` and ``DIR/report.html`` (the folder whole or not at all; an existing
non-empty one only with ``--force``) and prints the verdict per component. Exit code 0
whether or not an alarm is raised; 2 on error.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import typer
from rich.markup import escape
from rich.table import Table

from geardyn.cli import app
from geardyn.cli.common import check_report_dir, console, friendly_errors, report_folder
from geardyn.errors import ConfigError, InputError

#: Widest table printed (characters); wider verdict tables wrap their text columns.
TABLE_WIDTH = 100

_STYLE = {"alarm": "bold red", "healthy": "green", "uncertain": "bold yellow", "unknown": "dim"}


def parse_seeds(text: str | None) -> list[int] | None:
    """``'0,1,2'`` → ``[0, 1, 2]`` (None stays None)."""
    if text is None:
        return None
    try:
        seeds = [int(s) for s in text.split(",") if s.strip()]
    except ValueError:
        raise InputError(f"--seeds: expected comma-separated integers, e.g. 0,1,2; got "
                         f"{text!r}") from None
    if not seeds:
        raise InputError("--seeds: give at least one seed, e.g. 0,1,2")
    bad = [x for x in seeds if x < 0]
    if bad:
        raise InputError(f"--seeds: seeds must be ≥ 0, got {', '.join(map(str, bad))}")
    return seeds


#: [diagnosis] field → the diagnose option that overrides it.
OPTION_OF = {"threshold_k": "--k", "false_alarm_probability": "--false-alarm-probability",
             "sigma_floor": "--sigma-floor", "baseline_seeds": "--seeds",
             "record_seed": "--record-seed", "blocks": "--blocks", "skip_s": "--skip",
             "t_end_s": "--t-end", "revolutions": "--revolutions", "channel": "--channel",
             "reference": "--reference"}


def check_overrides(cfg, **given: Any) -> None:  # noqa: ANN001
    """The options given, validated as the [diagnosis] fields they override before any run;
    each problem names the option typed and the field (``--k (diagnosis.threshold_k): …``)."""
    from geardyn.diagnosis.pipeline import options

    given = {k: v for k, v in given.items() if v is not None}
    try:
        opts = options(cfg, **given)
    except ConfigError as exc:
        lines = []
        for p in exc.problems:
            field = p.split(":", 1)[0].removeprefix("diagnosis.").split(".")[0].split("[")[0]
            opt = OPTION_OF.get(field) if field in given else None
            lines.append(f"{opt} ({p.split(':', 1)[0]}):{p.split(':', 1)[1]}" if opt and ":" in p
                         else p)
        raise InputError("\n".join(lines)) from None
    if "record_seed" in given and opts.record_seed in opts.baseline_seeds:
        raise InputError(f"--record-seed: {opts.record_seed} is also a baseline seed "
                         f"{opts.baseline_seeds}; the record must be an independent run")


def _number(m: float) -> str:
    return f"{m:.3g}" if math.isfinite(m) else "–"


def render_verdict(verdict, out: Path) -> None:  # noqa: ANN001 - diagnosis.Verdict
    """Verdict table (component, kind, state, worst indicator and its margin, isolation evidence
    and its margin), the notes and where the files are."""
    t = Table(title=f"verdict: {verdict.machine} (channel {', '.join(verdict.channels)}, "
              f"k = {verdict.rule.k:.3g})", title_justify="left")
    longest = max((len(str(n)) for n in verdict.components), default=9)
    for c in ("component", "kind", "state", "worst indicator", "detection margin [-]",
              "isolation evidence", "isolation margin [-]"):
        # component names whole (never cut with "…"), the margin headers wrap instead
        t.add_column(c, justify="right" if "margin" in c else "left",
                     no_wrap=c in ("kind", "state", "worst indicator"), overflow="fold",
                     min_width=min(longest, 40) if c == "component" else None)
    for _, r in verdict.table().iterrows():
        t.add_row(escape(str(r["component"])), r["kind"],
                  f"[{_STYLE[r['state']]}]{r['state']}[/]", escape(str(r["worst_indicator"])),
                  _number(r["margin"]), escape(str(r["isolation"])),
                  _number(r["isolation_margin"]))
    if console.measure(t).maximum > TABLE_WIDTH:  # wrap the text columns, fit 100 columns
        t.width = TABLE_WIDTH
    console.print(t)
    for note in verdict.notes:
        console.print(f"[dim]note: {escape(note)}[/]")
    s = verdict.summary()
    det = verdict.detection or {}
    if det:
        said = "[bold red]fault detected[/]" if det["detected"] else "[green]nothing detected[/]"
        console.print(f"detection: {said} (false-alarm probability "
                      f"{det['false_alarm_probability']:.3g} over {det['tests']} tests, "
                      f"α = {det['alpha_per_test']:.2g} each)")
    if s["verdict"] == "alarm":
        conf = s.get("confidence")
        console.print(f"location: [bold red]{escape(', '.join(s['location']))}[/]"
                      + (f" (posterior {conf:.3f})" if conf is not None else ""))
    elif s["verdict"] == "uncertain":
        console.print("[bold yellow]detected, location uncertain[/]: candidates "
                      f"{escape(', '.join(s['candidates']))}")
    else:
        console.print("[green]no component in alarm[/]")
    if "localised" in s:
        exp = ", ".join(s["expected"]) or "none (healthy machine)"
        ok = "[green]alarms match[/]" if s["localised"] else "[yellow]alarms do not match[/]"
        console.print(f"configured fault(s) on: {escape(exp)}; {ok}")
    console.print(f"wrote {out / 'verdict.json'} and report {out / 'report.html'}")


def _check_skip(cfg, skip: float | None, t_end: float | None) -> None:  # noqa: ANN001
    """The discarded start (--skip / diagnosis.skip_s) must be shorter than the planetary run
    (--t-end / diagnosis.t_end_s / the simulation's t_end_s), checked before any run."""
    spec = getattr(cfg, "diagnosis", None)
    skip_s = skip if skip is not None else (spec.skip_s if spec is not None else 0.0)
    pd = getattr(cfg, "planetary_dynamics", None)
    sim_end = pd.simulation.t_end_s if pd is not None and pd.simulation is not None else None
    dy = getattr(cfg, "dynamics", None)
    if sim_end is None and dy is not None and dy.simulation is not None:
        sim_end = dy.simulation.t_end_s  # the mechanism model ([dynamics])
    end = t_end if t_end is not None else (
        spec.t_end_s if spec is not None and spec.t_end_s is not None else sim_end)
    if end is not None and end > 0 and skip_s is not None and math.isfinite(skip_s) \
            and skip_s >= end:
        raise InputError(f"--skip (diagnosis.skip_s): the discarded start {skip_s:g} s must be "
                         f"shorter than the run ({end:g} s, --t-end / diagnosis.t_end_s)")


def _check_channel(cfg, channel: str | None) -> None:  # noqa: ANN001
    """--channel of a simulated run: one of the config's [[sensors]] recording a signal."""
    sensors = {s.name: s for s in getattr(cfg, "sensors", [])}
    if channel is None or not sensors:
        return
    usable = [n for n, s in sensors.items() if s.kind != "tacho"]
    if channel not in usable:
        raise InputError(f"--channel: '{channel}' is not a signal sensor of the config "
                         f"(sensors: {', '.join(usable) or 'none'})")


@app.command("diagnose")
@friendly_errors
def diagnose_cmd(
    config: Path = typer.Argument(..., help="TOML config (machine, faults, \\[\\[sensors]])"),
    out: Path = typer.Option(..., "--out", "-o", help="output directory (verdict.json, "
                             "report.html)"),
    baseline: list[Path] = typer.Option(None, "--baseline", help="healthy record (measured "
                                        "file or result .nc); repeat for several"),
    record: Path | None = typer.Option(None, "--record", help="record to judge: a measured "
                                       "file mapped by \\[measurement] (CSV, WAV, MAT, TDMS, "
                                       "UFF, MDF4, HDF5, NetCDF…) or a result .nc"),
    simulate_baseline: bool | None = typer.Option(
        None, "--simulate-baseline/--no-simulate-baseline",
        help="with --record: also simulate the healthy machine as baseline (default: only "
        "when no --baseline file is given)"),
    channel: str | None = typer.Option(None, "--channel", help="sensor channel (default: "
                                       "\\[diagnosis].channel or the first)"),
    reference: str | None = typer.Option(None, "--reference", help="order reference link"),
    k: float | None = typer.Option(None, "--k", help="fixed threshold factor, mean + k·σ (default: "
                                   "from the false-alarm probability)"),
    p_fa: float | None = typer.Option(None, "--false-alarm-probability",
                                      help="machine false-alarm probability (default 0.01)"),
    sigma_floor: float | None = typer.Option(None, "--sigma-floor",
                                             help="σ ≥ this fraction of |mean| (default 0.05)"),
    seeds: str | None = typer.Option(None, "--seeds", help="baseline seeds, e.g. 0,1,2"),
    record_seed: int | None = typer.Option(None, "--record-seed", help="seed of the record"),
    blocks: int | None = typer.Option(None, "--blocks", help="blocks of revolutions per record"),
    skip: float | None = typer.Option(None, "--skip", help="start transient discarded \\[s]"),
    t_end: float | None = typer.Option(None, "--t-end", help="planetary or \\[dynamics] "
                                       "model: simulated duration \\[s]"),
    revolutions: float | None = typer.Option(None, "--revolutions", help="FE transmission: "
                                             "revolutions of the speed-law reference"),
    residuals: bool | None = typer.Option(
        None, "--residuals/--no-residuals",
        help="reference-residual indicators RR_kurtosis/RR_rms (≥ 2 baselines)"),
    force: bool = typer.Option(False, "--force", help="replace an existing --out folder "
                               "(its earlier files are removed, so no stale report stays)"),
    workers: int | None = typer.Option(
        None, "--workers", "-n", help="processes simulating the healthy baseline runs "
        "without --record (default: one per core; the verdict is the same for any number)"),
) -> None:
    """Healthy baseline, thresholds and a verdict per component; writes verdict.json and a
    self-contained report.html."""
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    from geardyn.config import load_config
    from geardyn.config.sensors import sensor_name_problems
    from geardyn.diagnosis.measured import diagnose_record
    from geardyn.diagnosis.pipeline import check_output_dir as make_output_dir
    from geardyn.diagnosis.pipeline import diagnose

    # --k, --skip, --seeds… are validated as the [diagnosis] fields they override (the
    # message names the field and the option) and --out by make_output_dir, before any run
    if baseline and record is None:
        raise InputError("--baseline needs --record: the healthy files are compared with a "
                         "record file (or give neither and both are simulated)")
    from geardyn.diagnosis.parallel import check_workers

    n_workers = check_workers(workers, "--workers")
    if simulate_baseline is not None and record is None:
        raise InputError("--simulate-baseline: applies with --record (without --record the "
                         "baseline is always simulated)")
    cfg = load_config(config)
    from geardyn.diagnosis.verdict import provenance

    config_id = provenance(cfg, config)["config"]  # the bytes judged, hashed before any run
    problems = sensor_name_problems(cfg)
    if problems:
        raise ConfigError(problems, source=str(config))
    check_overrides(cfg, threshold_k=k, false_alarm_probability=p_fa,
                    sigma_floor=sigma_floor, baseline_seeds=parse_seeds(seeds),
                    record_seed=record_seed, blocks=blocks, skip_s=skip, t_end_s=t_end,
                    revolutions=revolutions)
    if record is None:  # simulated runs: model, sensors, length, channels checked first
        from geardyn.diagnosis.pipeline import check_ready, options

        check_ready(cfg, options(cfg, channel=channel, reference=reference, t_end_s=t_end,
                                 revolutions=revolutions))
        _check_skip(cfg, skip, t_end)
        _check_channel(cfg, channel)
        from geardyn.resources import check_run

        check_run(cfg, None, t_end, revolutions, t_end_name="--t-end",
                  revolutions_name="--revolutions")
    make_output_dir(out)
    check_report_dir(out, "--out", force)  # one overwrite policy: an earlier folder needs --force
    with report_folder(out) as folder, Progress(  # written whole or not at all, no stale file
            TextColumn("{task.description}"), BarColumn(), TimeElapsedColumn(),
            console=console, transient=True) as prog:
        task = prog.add_task("diagnosis", total=1.0)

        def progress(message: str, fraction: float) -> None:
            prog.update(task, description=message, completed=fraction)

        common = {"channel": channel, "reference": reference, "k": k,
                  "false_alarm_probability": p_fa,
                  "sigma_floor": sigma_floor, "n_blocks": blocks, "skip_s": skip,
                  "reference_residuals": residuals, "progress": progress}
        if record is not None:
            simulated = simulate_baseline if simulate_baseline is not None else not baseline
            if record_seed is not None or (not simulated and any(
                    v is not None for v in (seeds, t_end, revolutions))):
                raise InputError("--seeds/--record-seed/--t-end/--revolutions are for "
                                 "simulated runs; they do not apply with --baseline/--record "
                                 "files (add --simulate-baseline to simulate the baseline too)")
            verdict = diagnose_record(cfg, record, folder, baseline_paths=baseline or (),
                                      simulate=simulated, baseline_seeds=parse_seeds(seeds),
                                      t_end_s=t_end, revolutions=revolutions, **common)
        else:
            verdict = diagnose(cfg, folder, baseline_seeds=parse_seeds(seeds),
                               record_seed=record_seed, t_end_s=t_end,
                               revolutions=revolutions, workers=n_workers, **common)
        verdict.provenance["config"] = config_id  # verdict.json names the config it judged
        verdict.write(folder)
    render_verdict(verdict, out)
