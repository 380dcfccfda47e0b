"""``geardyn trend CONFIG RECORDS… --store history.zarr --healthy N --out DIR``.

Adds each record (files, folders, glob patterns; any format of docs/measured.md, mapped by the
config's ``[measurement]`` section) once to the trend store, sets warning and alarm levels from
the first ``--healthy`` records (by timestamp) or from simulated healthy runs
(``--simulate-baseline``), and writes ``DIR/trend.csv`` (state per record and component),
``DIR/levels.csv``, ``DIR/crossings.csv`` and ``DIR/report.html``; prints the first record
crossing each level. Exit code 0 whether or not a level is crossed; 2 on error.
"""

from __future__ import annotations

from pathlib import Path

import typer
from rich.markup import escape
from rich.table import Table

from geardyn.cli import app
from geardyn.cli.common import console, friendly_errors
from geardyn.errors import InputError


@app.command("trend")
@friendly_errors
def trend_cmd(
    config: Path = typer.Argument(..., help="TOML config (machine, \\[measurement] mapping)"),
    records: list[str] = typer.Argument(..., help="record files, folders or glob patterns"),
    store: Path = typer.Option(..., "--store", help="trend store (Zarr folder; created if "
                               "missing)"),
    out: Path = typer.Option(Path("trend"), "--out", "-o", help="output directory"),
    healthy: int | None = typer.Option(None, "--healthy", help="the first N records (by "
                                       "timestamp) are the healthy reference"),
    simulate_baseline: bool = typer.Option(False, "--simulate-baseline", help="levels from "
                                           "simulated healthy runs of the config instead"),
    p_warning: float = typer.Option(0.1, "--warning-probability", help="machine false-alarm "
                                    "probability of the warning level"),
    p_alarm: float | None = typer.Option(None, "--false-alarm-probability", help="of the alarm "
                                         "level (default \\[diagnosis] false_alarm_probability)"),
    channel: str | None = typer.Option(None, "--channel", help="channel (default: \\[diagnosis]"
                                       ".channel or the first signal channel)"),
    skip: float | None = typer.Option(None, "--skip", help="start of each record discarded "
                                      "\\[s]"),
    blocks: int | None = typer.Option(None, "--blocks", help="blocks of revolutions per record"),
    workers: int | None = typer.Option(None, "--workers", help="LocalCluster worker processes "
                                       "(default: one per core; 1: in this process)"),
    scheduler: str | None = typer.Option(None, "--scheduler", help="address of a running dask "
                                         "scheduler"),
) -> None:
    """Indicators of a series of records in one store, warning/alarm levels, first crossings
    and a report."""
    from geardyn.checkpoint import write_text
    from geardyn.config import load_config
    from geardyn.diagnosis.pipeline import check_output_dir, options
    from geardyn.trend import TrendStore, expand_records, judge_records, update_store
    from geardyn.trend.levels import component_states, first_crossings
    from geardyn.trend.report import write_trend_report

    if (healthy is None) == (not simulate_baseline):
        raise InputError("--healthy N or --simulate-baseline: say where the healthy reference "
                         "comes from (the first N records, or simulated healthy runs)")
    if healthy is not None and healthy < 2:
        raise InputError(f"--healthy: at least 2 healthy records are needed, got {healthy}")
    if workers is not None and workers < 1:
        raise InputError(f"--workers: must be ≥ 1, got {workers}")
    cfg = load_config(config)
    if getattr(cfg, "measurement", None) is None:
        raise InputError(f"{config}: no [measurement] section; map the records' channels onto "
                         "the model (docs/measured.md)")
    opts = options(cfg, channel=channel, skip_s=skip, blocks=blocks,
                   false_alarm_probability=p_alarm)
    check_output_dir(out)
    paths = expand_records(records)
    st = TrendStore(store)
    with console.status("reading records") as status:
        done = update_store(st, paths, cfg, opts, workers=workers, scheduler=scheduler,
                            progress=lambda m, f: status.update(f"{m} ({f:.0%})"))
    console.print(f"store {store}: {len(done['added'])} record(s) added, "
                  f"{len(done['present'])} already there, {len(done['failed'])} not read")
    for f in done["failed"]:
        console.print(f"[yellow]not read:[/] {escape(f)}")
    history = st.table()
    if history.empty:
        raise InputError(f"--store: {store} holds no record")
    ref, source = _reference(history, healthy, cfg, opts)
    from geardyn.trend.levels import trend_levels

    levels = trend_levels(ref, p_warning, opts.false_alarm_probability, opts.sigma_floor,
                          source)
    judged = judge_records(history, levels)
    states = component_states(judged)
    crossings = first_crossings(states)
    write_text(out / "trend.csv", states.to_csv(index=False))
    write_text(out / "levels.csv", levels.table.to_csv(index=False))
    write_text(out / "crossings.csv", crossings.to_csv(index=False))
    write_trend_report(out, judged, states, crossings, levels, done["failed"])
    t = Table(title=f"first crossings (levels from {source})", title_justify="left")
    for c in ("component", "level", "record", "time", "indicator", "z [σ]"):
        t.add_column(c)
    for _, r in crossings.iterrows():
        t.add_row(escape(r["component"]), r["level"], escape(Path(r["file"]).name),
                  str(r["timestamp"]), escape(r["indicator"]), f"{r['z']:.3g}")
    console.print(t if len(crossings) else "[green]no component crossed a level[/]")
    console.print(f"wrote {out / 'trend.csv'}, levels.csv, crossings.csv and report "
                  f"{out / 'report.html'}")


def _reference(history, healthy: int | None, cfg, opts):  # noqa: ANN001, ANN202
    """Reference tables (one per healthy record or simulated run, block 0) and a description."""
    if healthy is not None:
        keys = list(dict.fromkeys(history["key"]))
        if len(keys) < healthy:
            raise InputError(f"--healthy: {healthy} healthy records asked, the store holds "
                             f"{len(keys)}")
        first = keys[:healthy]
        tables = [history[history["key"] == k].assign(block=0) for k in first]
        last = history[history["key"] == first[-1]]["timestamp"].iloc[0]
        return tables, f"the first {healthy} records (to {last})"
    from geardyn.diagnosis.measured import simulated_reference

    name = str(history["channel"].iloc[0])
    tables = [f.table.groupby(["component", "kind", "indicator", "channel"], sort=False)
              ["value"].median().reset_index().assign(block=0)
              for f in simulated_reference(cfg, opts, name)]
    return tables, f"{len(tables)} simulated healthy runs"
