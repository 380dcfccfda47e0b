"""The trend report: levels, first crossings and one figure per component (standardised
deviation of each indicator from the healthy mean, in σ, against time, with the warning and
alarm levels), as a self-contained HTML page (figures embedded as PNG)."""

from __future__ import annotations

import html
from pathlib import Path

import pandas as pd

from geardyn.trend.levels import Levels


def component_figure(judged: pd.DataFrame, component: str, levels: Levels):  # noqa: ANN201
    """z = (value − μ)/σ of every indicator of ``component`` against the record time."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9, 3.2), layout="constrained")
    ax = fig.add_subplot()
    g = judged[judged["component"] == component]
    for ind, d in g.groupby("indicator", sort=True):
        d = d.sort_values("timestamp")
        ax.plot(d["timestamp"], d["z"], marker="o", ms=3, lw=1, label=str(ind))
    for k, name, style in ((levels.k_warning, "warning", "--"), (levels.k_alarm, "alarm", "-")):
        ax.axhline(k, color="tab:orange" if name == "warning" else "tab:red", ls=style, lw=1,
                   label=f"{name} level (P = {getattr(levels, 'p_' + name):g})")
    ax.set_yscale("symlog", linthresh=max(1.0, levels.k_alarm))  # levels and growth both seen
    ax.set_ylabel("(indicator − healthy mean) / σ [σ]")
    ax.set_xlabel("record time")
    ax.set_title(f"{component}: indicators against the healthy reference ({levels.source})")
    ax.legend(fontsize=7, ncol=4, loc="upper left")
    fig.autofmt_xdate()
    return fig


def write_trend_report(out: Path, judged: pd.DataFrame, states: pd.DataFrame,
                       crossings: pd.DataFrame, levels: Levels, failed: list[str]) -> Path:
    """``out/report.html`` (atomic write)."""
    from geardyn.checkpoint import write_text
    from geardyn.diagnosis.report import figure_uri

    parts = [f"<h1>Trend of {judged['key'].nunique()} records</h1>",
             f"<p>Levels from {html.escape(levels.source)}: warning at k = "
             f"{levels.k_warning:.3g} (machine false-alarm probability {levels.p_warning:g}), "
             f"alarm at k = {levels.k_alarm:.3g} ({levels.p_alarm:g}) over {levels.tests} "
             "indicators per record (Šidák 1967); σ with the small-sample factor of the "
             "threshold rule (docs/diagnosis.md). Indicator values are dimensionless.</p>",
             "<h2>First record crossing each level</h2>",
             crossings.to_html(index=False, border=0) if len(crossings) else
             "<p>No component crossed a level.</p>"]
    if failed:
        parts += ["<h2>Records not read</h2><ul>"] + [f"<li>{html.escape(f)}</li>"
                                                      for f in failed] + ["</ul>"]
    parts.append("<h2>Components</h2>")
    for comp in dict.fromkeys(states["component"]):
        fig = component_figure(judged, comp, levels)
        parts.append(f'<img alt="{html.escape(comp)}" src="{figure_uri(fig)}">')
    parts.append("<h2>State per record and component</h2>")
    parts.append(states.to_html(index=False, border=0, float_format=lambda v: f"{v:.3g}"))
    page = ("<!doctype html><html><head><meta charset='utf-8'><title>geardyn trend</title>"
            "<style>body{font-family:sans-serif;max-width:1100px;margin:auto}"
            "table{border-collapse:collapse;font-size:12px}td,th{padding:2px 6px}</style>"
            "</head><body>" + "".join(parts) + "</body></html>")
    out.mkdir(parents=True, exist_ok=True)
    write_text(out / "report.html", page)
    return out / "report.html"
