"""Honest figures (issue 21): every figure a command writes is opened as a matplotlib object
(``Figure.savefig`` is hooked, so PNG files and the figures embedded in report.html are both
seen) and checked: every axis label and colour-bar label carries its unit in brackets (``[Hz]``,
``[-]`` for a ratio), a drawn axis has both labels (an axis shared with a labelled one
excepted), an axes with several labelled curves has a legend, and a Campbell diagram has order
lines. Small cases of ``stiffness --plot``, ``modes --campbell --out`` (lumped and FE),
``transmission --plots``, ``analyze`` and ``diagnose``."""

from __future__ import annotations

import re

import matplotlib

matplotlib.use("Agg")
import pytest  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from typer.testing import CliRunner  # noqa: E402

from geardyn.cli import app  # noqa: E402

runner = CliRunner()
UNIT = re.compile(r"\[[^\[\]]+\]")


@pytest.fixture
def figures(monkeypatch):
    """Every figure saved while the test runs (the object, before it is closed)."""
    seen: list[tuple[Figure, str]] = []
    original = Figure.savefig

    def savefig(self, fname, *args, **kwargs):  # noqa: ANN001, ANN002, ANN003, ANN202
        seen.append((self, str(getattr(fname, "name", fname))))
        return original(self, fname, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", savefig)
    return seen


def _is_colorbar(ax: Axes) -> bool:
    return hasattr(ax, "_colorbar") or ax.get_label() == "<colorbar>"


def _shared_label(ax: Axes, which: str) -> bool:
    group = ax.get_shared_x_axes() if which == "x" else ax.get_shared_y_axes()
    get = "get_xlabel" if which == "x" else "get_ylabel"
    return any(getattr(o, get)().strip() for o in group.get_siblings(ax) if o is not ax)


def _categorical(ax: Axes, which: str) -> bool:
    """Tick labels that are names (components, indicators), not numbers: the categories
    label the axis themselves."""
    axis = ax.xaxis if which == "x" else ax.yaxis
    texts = [t.get_text().replace("−", "-") for t in axis.get_ticklabels() if t.get_text()]

    def number(t: str) -> bool:
        try:
            float(t.replace("$", "").replace("\\mathdefault{", "").replace("}", ""))
        except ValueError:
            return False
        return True

    return bool(texts) and not any(number(t) for t in texts)


def _has_legend(ax: Axes, fig: Figure) -> bool:
    from matplotlib.legend import Legend

    return bool(fig.legends) or any(isinstance(a, Legend) for a in ax.get_children())


def _curves(ax: Axes) -> list:
    """Data curves of an axes (lines with more than two points; reference lines such as
    axvline/axhline and single markers are annotations)."""
    return [ln for ln in ax.get_lines() if len(ln.get_xdata()) > 2]


def problems(fig: Figure, name: str) -> list[str]:
    """What a figure breaks of the rules of the module docstring."""
    out = []
    for i, ax in enumerate(fig.axes):
        if not ax.get_visible() or not ax.axison:
            continue
        where = f"{name} axes {i} ({ax.get_title() or ax.get_label() or 'untitled'})"
        drawn = bool(ax.get_lines() or ax.collections or ax.images or ax.patches)
        if _is_colorbar(ax):
            label = ax.get_ylabel() or ax.get_xlabel()
            if not UNIT.search(label):
                out.append(f"{where}: colour bar label {label!r} has no [unit]")
            continue
        for which in ("x", "y"):
            label = (ax.get_xlabel() if which == "x" else ax.get_ylabel()).strip()
            ticks = (ax.xaxis if which == "x" else ax.yaxis).get_visible()
            if label and not UNIT.search(label):
                out.append(f"{where}: {which} label {label!r} has no [unit]")
            elif not label and drawn and ticks and not _shared_label(ax, which) \
                    and not _categorical(ax, which):
                out.append(f"{where}: no {which} label")
        labelled = [ln for ln in _curves(ax) if not ln.get_label().startswith("_")]
        if len(_curves(ax)) >= 2 and not _has_legend(ax, fig):
            out.append(f"{where}: {len(_curves(ax))} curves and no legend")
        elif len(labelled) >= 2 and not _has_legend(ax, fig):
            out.append(f"{where}: {len(labelled)} labelled curves and no legend")
        title = (ax.get_title() + " " + (fig._suptitle.get_text() if fig._suptitle else ""))
        if "campbell" in title.lower() and not any(
                "order" in ln.get_label().lower() for ln in ax.get_lines()):
            out.append(f"{where}: Campbell diagram without order lines")
    return out


def _check(figures: list[tuple[Figure, str]], at_least: int) -> None:
    assert len(figures) >= at_least, [n for _, n in figures]
    found = [p for fig, name in figures for p in problems(fig, name)]
    assert not found, "\n".join(found)


def test_rules_catch_a_bad_figure():
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1, 2], [0, 1, 2])
    ax.plot([0, 1, 2], [1, 2, 3])
    ax.set_xlabel("speed")
    ax.set_title("Campbell diagram")
    found = problems(fig, "bad")
    plt.close(fig)
    assert any("has no [unit]" in p for p in found)
    assert any("no y label" in p for p in found)
    assert any("no legend" in p for p in found)
    assert any("order lines" in p for p in found)


def test_stiffness_plot(figures, examples_dir, tmp_path):
    r = runner.invoke(app, ["stiffness", str(examples_dir / "seed002_two_stage.toml"),
                            "--pair", "low", "--plot", str(tmp_path / "k.png")])
    assert r.exit_code == 0, r.output
    _check(figures, 1)


def test_modes_and_campbell_lumped(figures, examples_dir, tmp_path):
    r = runner.invoke(app, ["modes", str(examples_dir / "planetary_bench_12dof.toml"),
                            "--campbell", "0:3000:4 rpm", "--out", str(tmp_path / "m")])
    assert r.exit_code == 0, r.output
    _check(figures, 2)


@pytest.mark.slow
def test_transmission_campbell_and_ias_figures(figures, tmp_path):
    cfg = tmp_path / "t.toml"
    assert runner.invoke(app, ["init", "transmission", str(cfg)]).exit_code == 0
    r = runner.invoke(app, ["modes", str(cfg), "--campbell", "0:2000:3 rpm",
                            "--campbell-modes", "4", "--out", str(tmp_path / "m")])
    assert r.exit_code == 0, r.output
    r = runner.invoke(app, ["transmission", str(cfg), "--revolutions", "2.5", "--plots",
                            str(tmp_path / "figs")])
    assert r.exit_code == 0, r.output
    _check(figures, 3)


@pytest.mark.slow
def test_analyze_and_diagnose_figures(figures, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert runner.invoke(app, ["init", "planetary"]).exit_code == 0
    r = runner.invoke(app, ["simulate", "planetary.toml", "--out", "run.nc"])
    assert r.exit_code == 0, r.output
    r = runner.invoke(app, ["analyze", "run.nc", "--config", "planetary.toml", "--channel",
                            "ring_acc", "--out", "rep"])
    assert r.exit_code == 0, r.output
    n = len(figures)
    r = runner.invoke(app, ["diagnose", "planetary.toml", "--out", "d"])
    assert r.exit_code == 0, r.output
    assert len(figures) > n  # the report's figures are seen too
    _check(figures, 3)
