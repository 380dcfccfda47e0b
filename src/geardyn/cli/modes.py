"""``geardyn modes CONFIG`` — natural frequencies, mode types and energies of the config's
dynamic model: the planetary model (``[planetary_dynamics]``, Hammami 2015, ch. 3), the general
model of any mechanism (``[dynamics]``, docs/dynamics.md) or the FE shaft lines
(``[transmission]``, Thibault et al. 2024, linearised at the static preload), with optional
mode-shape /
energy plots and a Campbell table (``--campbell "0:3000:7 rpm"``: frequencies against speed with
the gyroscopic terms); ``--out DIR`` writes modes.nc, modes.png and, with ``--campbell``,
campbell.csv and campbell.png."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import typer
from rich.table import Table

from geardyn.cli import app
from geardyn.cli.common import check_report_dir, console, friendly_errors, report_folder
from geardyn.errors import ConfigError, InputError

#: Models of ``--model`` (the names of ``geardyn simulate --model``).
MODEL_KINDS = ("planetary", "mechanism", "transmission")
#: Speed units of ``--campbell`` → rad/s per unit.
SPEED_UNITS = {"rpm": math.pi / 30.0, "rad/s": 1.0, "hz": 2.0 * math.pi, "rev/s": 2.0 * math.pi}
#: Most speeds of one Campbell table: one eigenproblem each; a diagram is resolved with tens to
#: hundreds of speeds, so this bounds the work (and the table), not the physics.
MAX_CAMPBELL_SPEEDS = 10_000
#: Highest Campbell speed (rpm): the plausibility limit of every speed field
#: (:data:`geardyn.config.units.SUFFIXES`, ``_rpm``).
MAX_CAMPBELL_RPM = 1e6


def model_kind(cfg, kind: str | None) -> str:  # noqa: ANN001
    """The model ``modes`` analyses: ``kind`` if given (its section must exist), else the one
    section the config has (planetary before mechanism); a lumped model and a
    ``[transmission]`` together need ``--model``."""
    have = [k for k, sec in (("planetary", "planetary_dynamics"), ("mechanism", "dynamics"),
                             ("transmission", "transmission"))
            if getattr(cfg, sec, None) is not None]
    if kind is not None:
        if kind not in MODEL_KINDS:
            raise InputError(f"--model: must be one of {', '.join(MODEL_KINDS)}, got {kind!r}")
        if kind not in have:
            section = {"planetary": "planetary_dynamics", "mechanism": "dynamics"}.get(kind, kind)
            raise ConfigError(f"--model {kind}: the config has no [{section}] section")
        return kind
    if not have:
        raise ConfigError("the config has none of [planetary_dynamics], [dynamics] and "
                          "[transmission] (see docs/dynamics.md, docs/transmission.md)")
    if "transmission" in have and len(have) > 1:
        raise ConfigError(f"the config describes {len(have)} models ({', '.join(have)}): choose "
                          f"one with --model {' | '.join(have)}")
    return have[0]


def parse_speeds(spec: str) -> tuple[np.ndarray, str]:
    """``"START:STOP:COUNT UNIT"`` (COUNT equally spaced speeds) or ``"S1,S2,… UNIT"``, UNIT
    one of rpm (default), rad/s, Hz, rev/s → (speeds in UNIT, unit)."""
    text = spec.strip()
    parts = text.split()
    unit = "rpm"
    if len(parts) == 2:
        text, unit = parts
    elif len(parts) != 1:
        raise InputError(f"--campbell: expected 'START:STOP:COUNT UNIT' (e.g. '0:3000:7 rpm'), "
                         f"got {spec!r}")
    if unit.lower() not in SPEED_UNITS:
        raise InputError(f"--campbell: unknown speed unit {unit!r} (one of rpm, rad/s, Hz, "
                         "rev/s)")
    unit = "Hz" if unit.lower() == "hz" else unit.lower()
    try:
        if ":" in text:
            a, b, n = text.split(":")
            count = int(n)
            if count < 1:
                raise InputError(f"--campbell: COUNT must be ≥ 1, got {count}")
            if count > MAX_CAMPBELL_SPEEDS:
                raise InputError(f"--campbell: COUNT {count} is above the limit of "
                                 f"{MAX_CAMPBELL_SPEEDS} speeds (one eigenproblem each)")
            speeds = np.linspace(float(a), float(b), count)
        else:
            speeds = np.array([float(x) for x in text.split(",") if x])
    except InputError:
        raise
    except ValueError:
        raise InputError(f"--campbell: expected 'START:STOP:COUNT UNIT' or 'S1,S2,… UNIT' "
                         f"(e.g. '0:3000:7 rpm'), got {spec!r}") from None
    if speeds.size == 0 or not np.all(np.isfinite(speeds)):
        raise InputError(f"--campbell: speeds must be finite numbers, got {spec!r}")
    if speeds.size > MAX_CAMPBELL_SPEEDS:
        raise InputError(f"--campbell: {speeds.size} speeds are above the limit of "
                         f"{MAX_CAMPBELL_SPEEDS} (one eigenproblem each)")
    top = float(np.abs(speeds).max()) * SPEED_UNITS[unit.lower()] * 30.0 / math.pi
    if top > MAX_CAMPBELL_RPM:
        raise InputError(f"--campbell: {top:g} rpm is implausible (limit "
                         f"{MAX_CAMPBELL_RPM:g} rpm; a unit slip?)")
    return speeds, unit


def campbell_table(kind: str, cfg, model, speeds: np.ndarray, unit: str,  # noqa: ANN001
                   n_modes: int, speed_of: str | None = None, prepared=None):  # noqa: ANN001, ANN201
    """Campbell DataArray (speed [unit], mode) in Hz of the model of ``kind``: FE (reference
    shaft ``speed_of``, default the speed law's), planetary (the carrier speed, Hammami 2015, eq
    3.1 via :func:`geardyn.models.planetary.modal.campbell`) or mechanism (the speed of body
    ``speed_of``, default the first driven link,
    :func:`geardyn.models.core.modal.core_campbell`)."""
    rad = speeds * SPEED_UNITS[unit.lower()]
    if kind == "transmission":
        from geardyn.models.transmission.modal import fe_campbell

        cd = fe_campbell(model, prepared, rad * 30.0 / math.pi, n_modes=n_modes,
                         reference=speed_of)
        of = cd.attrs["speed_of"]
        cd = cd.rename({"speed_rpm": "speed"})
        cd["mode"] = np.arange(1, cd.sizes["mode"] + 1)
    elif kind == "planetary":
        from geardyn.models.planetary.modal import campbell

        if speed_of is not None:
            raise InputError("--speed-of: the planetary model's Campbell speed is the carrier "
                             "speed (Hammami 2015, eq 3.1); leave --speed-of out")
        cd = campbell(model, rad, n_modes).rename({"carrier_speed": "speed"})
        of = "carrier"
    else:
        from geardyn.models.core.modal import core_campbell

        of = speed_of or _first_driven(cfg, model)
        if of not in model.bodies:
            raise InputError(f"--speed-of: unknown body '{of}' (one of "
                             f"{', '.join(model.bodies)})")
        try:
            cd = core_campbell(model, of, rad, n_modes).copy()
        except InputError as exc:
            raise InputError(f"--campbell: {str(exc).removeprefix('campbell: ')}") from None
    cd = cd.assign_coords(speed=("speed", speeds, {"units": unit}))
    cd.attrs.update({"units": "Hz", "speed_units": unit, "speed_of": of})
    cd.attrs.pop("carrier_speed_units", None)
    cd.name = "frequency"
    return cd


def _first_driven(cfg, model) -> str:  # noqa: ANN001
    for link in getattr(cfg, "input_speeds_rpm", None) or {}:
        if link in model.bodies:
            return link
    return next(b for b in model.bodies if b != getattr(model, "frame", ""))


def print_campbell(cd) -> None:  # noqa: ANN001
    """Rich table of :func:`campbell_table`: one row per speed, one column per mode (Hz)."""
    unit = cd.attrs["speed_units"]
    t = Table(title=f"Campbell: natural frequencies (Hz) against the speed of "
                    f"'{cd.attrs['speed_of']}' ({unit}), gyroscopic terms included",
              title_justify="left")
    t.add_column(f"speed ({unit})", justify="right")
    for m in cd["mode"].values:
        t.add_column(f"f{int(m)} (Hz)", justify="right")
    for i, sp in enumerate(cd["speed"].values):
        t.add_row(f"{sp:g}", *[f"{x:.2f}" for x in cd.values[i]])
    console.print(t)


def campbell_orders(cfg, speed_of: str) -> list[tuple[float, str]]:  # noqa: ANN001
    """Excitation orders of a Campbell diagram, per revolution of ``speed_of``: once and twice
    per revolution and, when the config's kinematics relate the link ``speed_of`` to its
    meshes (Penaud, Alazard & Amiez 2012), every distinct mesh order. (order, label) pairs."""
    orders = [(1.0, "order 1"), (2.0, "order 2")]
    try:
        from geardyn.kinematics import analyze_kinematics, characteristic_frequencies

        kin = analyze_kinematics(cfg)
        freqs = characteristic_frequencies(kin, dict(cfg.input_speeds_rpm),
                                           order_reference=speed_of)
    except Exception:  # noqa: BLE001 - no kinematics for this link: the 1× and 2× lines only
        return orders
    seen: dict[float, list[str]] = {}
    for pair, order in zip(freqs.meshes["pair"], freqs.meshes["mesh_order"], strict=True):
        if np.isfinite(order) and order > 0:
            seen.setdefault(round(float(order), 4), []).append(str(pair))
    for order, pairs in sorted(seen.items()):
        names = f"mesh {', '.join(pairs)}" if len(pairs) <= 2 else f"{len(pairs)} meshes"
        orders.append((order, f"order {order:g} ({names})"))
    return orders


def write_campbell(cd, out: Path, orders: list[tuple[float, str]] | None = None  # noqa: ANN001
                   ) -> list[Path]:
    """campbell.csv (header with units) and campbell.png (frequency [Hz] against speed, with
    the excitation ``orders`` as lines f = order × speed, default once and twice per
    revolution; a mode crossing a line is a possible resonance)."""
    from geardyn.checkpoint import write_text
    from geardyn.plotting import save_figure

    unit = cd.attrs["speed_units"]
    modes = [int(m) for m in cd["mode"].values]
    lines = [",".join([f"speed_{unit.replace('/', '_per_')}"] + [f"f{m}_hz" for m in modes])]
    for i, sp in enumerate(cd["speed"].values):
        lines.append(",".join([repr(float(sp))] + [repr(float(x)) for x in cd.values[i]]))
    csv = out / "campbell.csv"
    write_text(csv, "\n".join(lines) + "\n")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 5), layout="constrained")
    for j, m in enumerate(modes):
        ax.plot(cd["speed"].values, cd.values[:, j], "o-", ms=3, lw=1, label=f"mode {m}")
    speed = cd["speed"].values
    rev_per_s = np.abs(speed) * SPEED_UNITS[unit.lower()] / (2.0 * math.pi)
    top = float(np.nanmax(cd.values)) * 1.05 if np.isfinite(cd.values).any() else 1.0
    for order, label in orders if orders is not None else [(1.0, "order 1"), (2.0, "order 2")]:
        ax.plot(speed, order * rev_per_s, "--", lw=0.8, color="0.4", label=label)
    ax.set_ylim(0.0, top if top > 0 else 1.0)
    ax.set_xlabel(f"speed of {cd.attrs['speed_of']} [{unit}]")
    ax.set_ylabel("natural frequency [Hz]")
    ax.set_title("Campbell diagram (gyroscopic terms included; dashed: excitation orders)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    png = out / "campbell.png"
    save_figure(fig, png)
    return [csv, png]


@app.command("modes")
@friendly_errors
def modes_cmd(
    config: Path = typer.Argument(..., help="TOML config with a [planetary_dynamics], "
                                  "[dynamics] or [transmission] section"),
    reduction: str | None = typer.Option(
        None, "--reduction", help="override: none | torsional | transverse (planetary model)"),
    model_kind_opt: str | None = typer.Option(
        None, "--model", help="planetary | mechanism | transmission (default: the model the "
        "config describes; planetary before mechanism; a lumped model and [transmission] "
        "together need --model)"),
    max_hz: float | None = typer.Option(None, "--max-hz", help="list modes up to this (Hz)"),
    plot: Path | None = typer.Option(None, "--plot", hidden=True, help="deprecated: "
                                     "--out DIR writes modes.png"),
    netcdf: Path | None = typer.Option(None, "--netcdf", hidden=True, help="deprecated: "
                                       "--out DIR writes modes.nc"),
    campbell_spec: str | None = typer.Option(
        None, "--campbell", help="Campbell table at these speeds: 'START:STOP:COUNT UNIT' or "
        "'S1,S2,… UNIT', UNIT rpm (default) | rad/s | Hz | rev/s, e.g. '0:3000:7 rpm'; speed of "
        "the carrier (planetary), of --speed-of (mechanism body, FE shaft)"),
    speed_of: str | None = typer.Option(
        None, "--speed-of", help="Campbell speed: FE reference shaft (default: the speed "
        "law's) or mechanism body (default: the first driven link)"),
    campbell_modes: int = typer.Option(10, "--campbell-modes", min=1,
                                       help="modes in the Campbell table"),
    out: Path | None = typer.Option(
        None, "--out", help="output folder: modes.nc (frequencies, shapes, energy fractions), "
        "modes.png (kinetic/strain energy per mode, up to --max-hz) and, with --campbell, "
        "campbell.csv and campbell.png; written whole (an existing non-empty one needs "
        "--force)"),
    force: bool = typer.Option(False, "--force", help="replace an existing --out folder "
                               "(its earlier files are removed, so no stale figure stays)"),
) -> None:
    """Natural frequencies, multiplicities, mode types, dominant motion and strain energy;
    Campbell table (frequencies against speed with gyroscopic terms)."""
    from geardyn.config import load_config

    if out is not None:
        check_report_dir(out, "--out", force)
    for old_name, value, new in (("--netcdf", netcdf, "modes.nc"), ("--plot", plot,
                                                                   "modes.png")):
        if value is not None:
            console.print(f"[yellow]note:[/] {old_name} is deprecated; use --out DIR (writes "
                          f"{new}, and the Campbell files with --campbell)", highlight=False)
    speeds = parse_speeds(campbell_spec) if campbell_spec is not None else None
    cfg = load_config(config)
    kind = model_kind(cfg, model_kind_opt)
    prepared = None
    if kind == "mechanism":
        from geardyn.models.core import model_from_config as core_model
        from geardyn.models.core.modal import core_modes

        model = core_model(cfg)
        res = core_modes(model)
        title = f"modes of {config.name} ({model.n} DOF, torsional model of the mechanism)"
        plot_model = None
    elif kind == "transmission":
        from geardyn.models.transmission import build_model, prepare
        from geardyn.models.transmission.modal import fe_modes

        model = build_model(cfg)
        law = cfg.transmission.speed_law
        prepared = prepare(model, law.reference.shaft if law else None)
        res = fe_modes(model, prepared)
        title = (f"modes of {config.name} ({model.ndof} DOF, FE shaft lines linearised at the "
                 "static preload, gyroscopic terms neglected)")
        plot_model = None
    else:
        from geardyn.models.planetary.build import model_from_config
        from geardyn.models.planetary.modal import modes

        model = model_from_config(cfg, reduction)
        res = modes(model)
        title = (f"modes of {config.name} ({len(model.names)} DOF, reduction "
                 f"{model.reduction})")
        plot_model = model
    t = Table(title=title, title_justify="left")
    for c in ("mode", "f (Hz)", "mult.", "type", "dominant motion", "dominant strain energy"):
        t.add_column(c, justify="right" if c in ("mode", "f (Hz)", "mult.") else "left")
    for row in res.table():
        if max_hz is not None and row["freq_hz"] > max_hz:
            break
        t.add_row(str(row["mode"]), f"{row['freq_hz']:.1f}", str(row["multiplicity"]),
                  row["type"], row["dominant_motion"], row["dominant_strain"])
    console.print(t)
    if netcdf is not None:
        from geardyn.checkpoint import write_atomic

        write_atomic(netcdf, lambda tmp: res.to_dataset().to_netcdf(tmp, engine="h5netcdf"))
        console.print(f"wrote {netcdf}")
    if plot is not None:
        from geardyn.plotting import save_figure

        save_figure(res.plot(model=plot_model, max_hz=max_hz), plot)
        console.print(f"wrote {plot}")
    cd = None
    if speeds is not None:
        cd = campbell_table(kind, cfg, model, speeds[0], speeds[1], campbell_modes, speed_of,
                            prepared)
        print_campbell(cd)
    if out is not None:
        from geardyn.checkpoint import write_atomic
        from geardyn.plotting import save_figure

        with report_folder(out) as folder:  # the whole folder or nothing, no stale figure
            write_atomic(folder / "modes.nc",
                         lambda tmp: res.to_dataset().to_netcdf(tmp, engine="h5netcdf"))
            save_figure(res.plot(model=plot_model, max_hz=max_hz), folder / "modes.png")
            names = ["modes.nc", "modes.png"]
            if cd is not None:
                orders = campbell_orders(cfg, cd.attrs["speed_of"])
                names += [p.name for p in write_campbell(cd, folder, orders)]
        console.print(f"wrote {', '.join(names)} to {out}/")
