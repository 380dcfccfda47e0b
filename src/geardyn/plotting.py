"""Figures: shared helpers and the figure of a simulation result.

Every geardyn figure follows the same rules (STYLE habit 3):

- plotting functions and result ``.plot()`` methods take ``ax=None`` and return the matplotlib
  :class:`~matplotlib.figure.Figure`; they never save, show or switch the backend (a new
  figure is made with :func:`matplotlib.pyplot.subplots`, so it uses whatever backend is
  active); :func:`save_figure` writes a figure for the CLI and closes it;
- axes are labelled ``long name [units]`` from the variables' ``long_name``/``units`` attrs,
  as xarray's ``label_from_attrs`` does (:func:`axis_label`), ``[-]`` for dimensionless or
  categorical axes; colour bars are labelled, levels in dB with their reference (:func:`db_label`).

:func:`plot_result` draws a dataset in the geardyn result layout (``docs/results.md``): shaft
speeds, mesh forces and sensor channels. It is also ``ds.geardyn.plot()`` (xarray accessor).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr

from geardyn.errors import InputError

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.colorbar import Colorbar
    from matplotlib.figure import Figure

DIMENSIONLESS = ("", "1", "-")


def unit_text(units: object) -> str:
    """``[units]`` of a label; ``[-]`` for dimensionless quantities."""
    u = "" if units is None else str(units).strip()
    return "[-]" if u in DIMENSIONLESS else f"[{u}]"


def axis_label(obj: xr.DataArray | xr.Variable | dict, name: str | None = None,
               units: str | None = None) -> str:
    """``long name [units]`` of a variable or coordinate (or of an attrs dict).

    The name is ``long_name``, else ``standard_name``, else ``name`` (or the variable's own
    name, ``_`` read as a space); ``units`` overrides the attribute.
    """
    attrs = obj if isinstance(obj, dict) else dict(obj.attrs)
    text = attrs.get("long_name") or attrs.get("standard_name")
    if not text:
        text = str(name or getattr(obj, "name", None) or "value").replace("_", " ")
    return f"{text} {unit_text(attrs.get('units') if units is None else units)}"


def db_label(what: str = "amplitude", units: str | None = None) -> str:
    """Colour-bar label of a level in dB re 1 ``units`` (e.g. ``amplitude [dB re 1 m/s²]``)."""
    ref = f" re 1 {units}" if units and str(units).strip() not in DIMENSIONLESS else ""
    return f"{what} [dB{ref}]"


def new_axes(ax: Axes | None = None, figsize: tuple[float, float] = (10.0, 4.0)
             ) -> tuple[Figure, Axes]:
    """``(figure, axes)``: those of ``ax``, or a new single-axes figure (current backend)."""
    if ax is not None:
        return ax.figure, ax
    import matplotlib.pyplot as plt

    fig, new = plt.subplots(figsize=figsize, layout="constrained")
    return fig, new


def labelled_colorbar(mappable: Any, ax: Axes, label: str) -> Colorbar:
    """Colour bar of ``mappable`` next to ``ax`` with ``label`` (levels: :func:`db_label`)."""
    cb = ax.figure.colorbar(mappable, ax=ax)
    cb.set_label(label)
    return cb


def save_figure(fig: Figure, path: str | Path, dpi: int = 110) -> Path:
    """Write ``fig`` (format from the suffix) and close it; returns the path. For the CLI."""
    import matplotlib.pyplot as plt

    from geardyn.checkpoint import save_figure as save_atomic

    out = Path(path)
    save_atomic(fig, out, dpi=dpi)

    plt.close(fig)
    return out


def heatmap(values: np.ndarray, rows: Sequence[str], cols: Sequence[str], ax: Axes,
            row_label: str, col_label: str, bar_label: str, title: str = "") -> Any:
    """Rows × columns table as a colour map with tick labels and a labelled colour bar."""
    im = ax.imshow(values, aspect="auto", cmap="viridis", interpolation="nearest")
    ax.set_xticks(range(len(cols)), list(cols), rotation=90, fontsize=6)
    ax.set_yticks(range(len(rows)), list(rows), fontsize=6)
    ax.set_xlabel(col_label)
    ax.set_ylabel(row_label)
    ax.set_title(title, fontsize=9)
    labelled_colorbar(im, ax, bar_label)
    return im


def axes_row(ax: Axes | Sequence[Axes] | None, n: int, figsize: tuple[float, float]
             ) -> tuple[Figure, list[Axes]]:
    """``n`` axes side by side: those given (one axes or a sequence of ``n``), else a new
    figure."""
    if ax is None:
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(1, n, figsize=figsize, layout="constrained", squeeze=False)
        return fig, list(axes[0])
    axes = [ax] if hasattr(ax, "plot") else list(ax)  # type: ignore[arg-type]
    if len(axes) != n:
        raise InputError(f"ax: this figure draws on {n} axes, got {len(axes)}")
    return axes[0].figure, axes


# ---- modal results -----------------------------------------------------------------------


def plot_mode_frequencies(freq_hz: np.ndarray, mode_type: np.ndarray,
                          ax: Axes | None = None) -> Figure:
    """Natural frequency [Hz] against mode number, one marker colour and legend entry per
    mode type (:meth:`geardyn.solve.modal.ModalResult.plot`)."""
    fig, ax = new_axes(ax, (8, 4))
    for t in dict.fromkeys(mode_type):
        sel = np.nonzero(mode_type == t)[0]
        ax.plot(sel + 1, freq_hz[sel], "o", ms=4, label=str(t))
    ax.set_xlabel("mode number [-]")
    ax.set_ylabel("natural frequency [Hz]")
    ax.legend(title="mode type", fontsize=8, title_fontsize=8)
    ax.grid(True, alpha=0.3)
    return fig


def plot_mode_energies(freq_hz: np.ndarray, mode_number: np.ndarray,
                       tables: dict[str, tuple[np.ndarray, Sequence[str], str, str]],
                       ax: Axes | Sequence[Axes] | None = None) -> Figure:
    """One heat map per energy table ``name → (percent (mode, column), column names, column
    axis label, title)``, rows labelled ``mode: frequency`` (seed 003 Tables 3.4-3.5)."""
    fig, axes = axes_row(ax, len(tables), (7.0 * len(tables), 0.25 * len(freq_hz) + 2.5))
    rows = [f"{m}: {f:.0f}" for m, f in zip(mode_number, freq_hz, strict=True)]
    for a, (name, (vals, cols, col_label, title)) in zip(axes, tables.items(), strict=True):
        heatmap(vals, rows, cols, a, "mode: natural frequency [Hz]", col_label,
                f"{name} energy [% of the mode]", title)
    return fig


# ---- simulation results ------------------------------------------------------------------


def _selection(what: str, wanted: Sequence[str] | None, have: list[str]) -> list[str]:
    if wanted is None:
        return have
    if isinstance(wanted, str):
        wanted = [wanted]
    bad = [w for w in wanted if w not in have]
    if bad:
        raise InputError(f"{what}: {', '.join(repr(b) for b in bad)} not in the result "
                         f"({what}: {', '.join(have) if have else 'none'})")
    return list(wanted)


def _coord_names(ds: xr.Dataset, dim: str) -> list[str]:
    return [str(v) for v in ds[dim].values] if dim in ds.coords else []


def _legend(ax: Axes, n: int) -> None:
    """Legend outside the axes (right), so that it never hides a curve."""
    if n > 1:
        ax.legend(fontsize=7, ncol=max(1, (n + 11) // 12), loc="upper left",
                  bbox_to_anchor=(1.01, 1.0), frameon=False)


def _time_panel(ax: Axes, ds: xr.Dataset, var: str, dim: str, names: list[str],
                time_range: tuple[float, float] | None) -> None:
    da = ds[var]
    for i, n in enumerate(names):  # colours repeat after 10 lines: change the line style
        ax.plot(ds["time"].values, da.sel({dim: n}).values, lw=0.8, label=n,
                ls=("-", "--", ":", "-.")[(i // 10) % 4])
    ax.set_xlabel(axis_label(ds["time"], "time", ds["time"].attrs.get("units", "s")))
    ax.set_ylabel(axis_label(da))
    if time_range is not None:
        ax.set_xlim(*time_range)
    _legend(ax, len(names))


def _channel_panel(ax: Axes, da: xr.DataArray, name: str,
                   time_range: tuple[float, float] | None) -> None:
    dim = da.dims[0]
    sampling = str(da.attrs.get("sampling", "time"))
    if sampling == "events":
        ax.plot(da.values, np.ones(da.size), "|", ms=12, label=name)
        ax.set_xlabel(axis_label(da, "pulse time"))
        ax.set_ylabel("pulse [-]")
        ax.set_yticks([])
    else:
        x = da[dim]
        ax.plot(x.values, da.values, lw=0.6)
        ax.set_xlabel(axis_label(x, str(dim).rsplit(".", 1)[-1]))
        ax.set_ylabel(axis_label(da, name))
    shaft = da.attrs.get("shaft")
    ax.set_title(f"sensor '{name}'" + (f" (shaft {shaft})" if shaft else ""), fontsize=9)
    if time_range is not None and (sampling == "events" or str(dim).endswith(".time")):
        ax.set_xlim(*time_range)


def plot_result(ds: xr.Dataset, shafts: Sequence[str] | None = None,
                meshes: Sequence[str] | None = None, channels: Sequence[str] | None = None,
                time_range: tuple[float, float] | None = None) -> Figure:
    """Figure of a simulation result (geardyn result layout, ``docs/results.md``).

    One panel of shaft speeds (``speed_rpm``, else ``speed``) against time for ``shafts``, one
    of ``mesh_force`` for ``meshes``, and one per sensor channel (``sensors.<name>``, against
    its own time or angle) for ``channels``. ``None`` selects all, ``[]`` drops the panel;
    unknown names raise :class:`~geardyn.errors.InputError` listing the available ones.
    ``time_range`` ``(t0, t1)`` [s] limits the time axes.

    Examples
    --------
    >>> fig = plot_result(ds, shafts=["sun", "carrier"], meshes=[], channels=["ring_acc"])
    ... # doctest: +SKIP
    """
    from geardyn.results import PREFIX
    from geardyn.results import channels as channel_names

    panels: list[tuple[str, Any]] = []
    speed = "speed_rpm" if "speed_rpm" in ds.data_vars else "speed"
    if speed in ds.data_vars:
        sel = _selection("shafts", shafts, _coord_names(ds, "shaft"))
        if sel:
            panels.append(("time", (speed, "shaft", sel)))
    elif shafts:
        raise InputError("shafts: the result has no 'speed_rpm' or 'speed' variable")
    if "mesh_force" in ds.data_vars:
        sel = _selection("meshes", meshes, _coord_names(ds, "mesh"))
        if sel:
            panels.append(("time", ("mesh_force", "mesh", sel)))
    elif meshes:
        raise InputError("meshes: the result has no 'mesh_force' variable")
    for name in _selection("channels", channels, channel_names(ds)):
        panels.append(("channel", name))
    if not panels:
        raise InputError("nothing to plot: the result has none of 'speed_rpm', 'speed', "
                         "'mesh_force' or sensor channels for this selection "
                         f"(variables: {', '.join(map(str, ds.data_vars)) or 'none'})")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(panels), 1, figsize=(10, 2.6 * len(panels) + 0.6),
                             layout="constrained", squeeze=False)
    for ax, (kind, spec) in zip(axes[:, 0], panels, strict=True):
        if kind == "time":
            _time_panel(ax, ds, *spec, time_range)
        else:
            _channel_panel(ax, ds[PREFIX + spec], spec, time_range)
        ax.grid(True, alpha=0.3)
    model = ds.attrs.get("model")
    status = ds.attrs.get("status")
    if model or status:
        fig.suptitle(f"{model or 'simulation'} result" + (f" (status {status})" if status
                                                           else ""))
    return fig


@xr.register_dataset_accessor("geardyn")
class GeardynAccessor:
    """``ds.geardyn``: geardyn methods on a result dataset (``ds.geardyn.plot(...)``)."""

    def __init__(self, ds: xr.Dataset) -> None:
        self._ds = ds

    def plot(self, shafts: Sequence[str] | None = None, meshes: Sequence[str] | None = None,
             channels: Sequence[str] | None = None,
             time_range: tuple[float, float] | None = None) -> Figure:
        """:func:`plot_result` of this dataset."""
        return plot_result(self._ds, shafts, meshes, channels, time_range)
