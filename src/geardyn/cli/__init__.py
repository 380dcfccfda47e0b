"""Command-line interface: ``geardyn kinematics|stiffness|modes|simulate|transmission|analyze|
diagnose|demo|init|schema``.

Each command lives in its own module and registers itself on :data:`app` with
``@app.command("name")``. The modules are imported lazily: :data:`COMMANDS` maps each command
name to its module and a one-line summary (shown by ``geardyn --help`` without importing
anything), so ``geardyn --help`` and every command import only what they use. To add a
command, write its module and add ONE line to :data:`COMMANDS`.

Errors from geardyn are printed as one clear message (exit code 2).
"""

from __future__ import annotations

import importlib
import math
import re
from typing import Any

import typer
from typer.core import TyperCommand, TyperGroup

#: command name → (module registering it with ``@app.command(name)``, one-line summary).
COMMANDS: dict[str, tuple[str, str]] = {
    "kinematics": ("geardyn.cli.kinematics",
                   "Degrees of freedom, carriers, velocity ratios and characteristic frequencies."),
    "stiffness": ("geardyn.cli.stiffness",
                  "Gear-pair geometry and potential-energy mesh stiffness."),
    "modes": ("geardyn.cli.modes", "Natural frequencies, mode types and Campbell table of the "
              "config's dynamic model (planetary, mechanism, FE)."),
    "simulate": ("geardyn.cli.simulate", "Time simulation of the config's dynamic model."),
    "transmission": ("geardyn.cli.transmission",
                     "Alias of `simulate` for the FE transmission (Thibault et al. 2024), "
                     "modes first."),
    "analyze": ("geardyn.cli.analyze",
                "Order spectrum, spectrogram, TSA, cepstrum and indicators of a signal."),
    "diagnose": ("geardyn.cli.diagnose",
                 "Healthy baseline, thresholds and a verdict per component."),
    "demo": ("geardyn.cli.demo", "Run the examples of the sources and print their results."),
    "init": ("geardyn.cli.init", "Write a commented starter config from a template."),
    "schema": ("geardyn.cli.schema", "JSON Schema of the config file (editor completion)."),
    "trend": ("geardyn.cli.trend", "Trend of measured records: indicators in one store, "
              "warning/alarm levels, first crossings."),
    "sweep": ("geardyn.cli.sweep", "Parameter sweep on dask.distributed into a Zarr data set."),
}

_UNESCAPED_BRACKET = re.compile(r"(?<!\\)\[")


def escape_markup(text: str | None) -> str | None:
    """Escape rich markup in a help text (``[planetary]`` is a TOML table, not a style);
    brackets already escaped (``\\[``) stay as they are."""
    return None if text is None else _UNESCAPED_BRACKET.sub(r"\\[", text)


#: Range of numeric options, the same for every command that has them (checked while parsing,
#: before any work): option → (rule, bound).
OPTION_RULES: dict[str, tuple[str, float]] = {
    "--revolutions": (">", 0), "--t-end": (">", 0), "--fs": (">", 0), "--cycles": (">", 0),
    "--clock": (">", 0), "--k": (">", 0), "--seed": ("≥", 0), "--record-seed": ("≥", 0),
    "--skip": ("≥", 0), "--samples": ("≥", 4), "--samples-per-rev": ("≥", 4),
    "--ppr": ("≥", 1), "--ias-ppr": ("≥", 1), "--blocks": ("≥", 1), "--modes": ("≥", 1),
    "--max-hz": (">", 0), "--campbell": (">", 0), "--checkpoint-every": (">", 0),
    "--sigma-floor": ("≥", 0),
}

#: Upper bounds of numeric options: option → (bound, rule, unit). Rule "implausible": the
#: plausibility limit of the config field the option overrides (``--t-end`` as every ``_s``
#: field, 1e7 s; ``--campbell`` as every ``_rpm`` field, 1e6 rpm; ``--fs`` as every ``_hz``
#: field, 1e9 Hz; :data:`geardyn.config.units.SUFFIXES`); "≤" / "<": the range of that field.
OPTION_MAX: dict[str, tuple[float, str, str]] = {
    "--t-end": (1e7, "implausible", "s"), "--campbell": (1e6, "implausible", "rpm"),
    "--fs": (1e9, "implausible", "Hz"), "--blocks": (64, "≤", ""),
    "--sigma-floor": (1.0, "<", ""),
}

#: Longest file name (one path component, bytes) and path the file systems accept (POSIX
#: NAME_MAX and PATH_MAX of Linux).
NAME_MAX, PATH_MAX = 255, 4096

#: Options naming an output FILE: its directory must exist and the path must not be a
#: directory (checked while parsing, before any work).
FILE_OPTIONS = {"--plot", "--netcdf"}


def _file_callback(previous: Any) -> Any:
    """A parameter callback refusing an output file in a missing directory."""

    def check(ctx: Any, param: Any, value: Any) -> Any:
        if value is not None:
            from pathlib import Path

            path = Path(value)
            if path.is_dir():
                raise typer.BadParameter(f"'{path}' is a directory, expected a file name",
                                         param=param)
            if not path.parent.is_dir():
                raise typer.BadParameter(f"directory '{path.parent}' does not exist",
                                         param=param)
        return previous(ctx, param, value) if previous is not None else value

    return check


def _name_callback(previous: Any) -> Any:
    """A parameter callback refusing a path with a component longer than :data:`NAME_MAX`
    bytes or longer than :data:`PATH_MAX` (the system would fail with ENAMETOOLONG)."""

    def check(ctx: Any, param: Any, value: Any) -> Any:
        values = value if isinstance(value, list | tuple) else [value]
        for v in values:
            if v is None:
                continue
            text = str(v)
            longest = max((len(c.encode("utf-8", "surrogateescape")) for c in text.split("/")),
                          default=0)
            if longest > NAME_MAX:
                raise typer.BadParameter(f"a file name of {longest} characters is longer than "
                                         f"the {NAME_MAX} the file system accepts", param=param)
            if len(text.encode("utf-8", "surrogateescape")) > PATH_MAX:
                raise typer.BadParameter(f"a path of {len(text)} characters is longer than the "
                                         f"{PATH_MAX} the system accepts", param=param)
        return previous(ctx, param, value) if previous is not None else value

    return check


def _number_callback(previous: Any, rule: tuple[str, float] | None,
                     top: tuple[float, str, str] | None = None) -> Any:
    """A parameter callback refusing nan/inf in a numeric option (click accepts them) and
    values outside :data:`OPTION_RULES` and :data:`OPTION_MAX`, then calling the option's own
    callback."""

    def check(ctx: Any, param: Any, value: Any) -> Any:
        values = value if isinstance(value, list | tuple) else [value]
        for v in values:
            if isinstance(v, float) and not math.isfinite(v):
                raise typer.BadParameter(f"must be a finite number, got {v}", param=param)
            if not isinstance(v, int | float) or isinstance(v, bool):
                continue
            if rule is not None:
                op, bound = rule
                if not (v > bound if op == ">" else v >= bound):
                    raise typer.BadParameter(f"must be {op} {bound:g}, got {v:g}", param=param)
            if top is not None:
                bound, op, unit = top
                if op == "implausible" and abs(v) > bound:
                    raise typer.BadParameter(f"{v:g} {unit} is implausible (limit {bound:g} "
                                             f"{unit}; a unit slip?)", param=param)
                if (op == "≤" and v > bound) or (op == "<" and v >= bound):
                    raise typer.BadParameter(f"must be {op} {bound:g}, got {v:g}", param=param)
        return previous(ctx, param, value) if previous is not None else value

    return check


#: Commands that validate their numeric options themselves, as the config fields they
#: override (the message names both): no generic range check at parse time. (``diagnose``
#: checks its options at parse time like every command, naming the option typed, then as the
#: [diagnosis] fields they override.)
SELF_VALIDATING: set[str] = set()


def _finish(cmd: Any) -> Any:
    """Escape the help texts and make every float option refuse non-finite numbers."""
    if getattr(cmd, "_geardyn_finished", False):
        return cmd
    checked = cmd.name not in SELF_VALIDATING
    cmd.help = escape_markup(cmd.help)
    cmd.short_help = escape_markup(cmd.short_help)
    for param in cmd.params:
        if getattr(param, "help", None):
            param.help = escape_markup(param.help)
        annotation = str(getattr(getattr(param, "type_descriptor", None), "annotation", ""))
        opts = getattr(param, "opts", [])
        rule = next((OPTION_RULES[o] for o in opts if o in OPTION_RULES), None)
        top = next((OPTION_MAX[o] for o in opts if o in OPTION_MAX), None)
        if checked and ("float" in annotation or ("int" in annotation and (rule or top))):
            param.callback = _number_callback(param.callback, rule, top)
        if "Path" in annotation and set(opts) & FILE_OPTIONS:
            param.callback = _file_callback(param.callback)
        if "Path" in annotation:
            param.callback = _name_callback(param.callback)
    cmd._geardyn_finished = True
    return cmd


class LazyGroup(TyperGroup):
    """A typer group whose commands are imported on first use (see :data:`COMMANDS`)."""

    _listing = False

    def list_commands(self, ctx: Any) -> list[str]:
        return list(COMMANDS) + [n for n in self.commands if n not in COMMANDS]

    def get_command(self, ctx: Any, cmd_name: str) -> Any | None:
        if cmd_name in self.commands:
            return _finish(self.commands[cmd_name])
        if cmd_name not in COMMANDS:
            return None
        module, summary = COMMANDS[cmd_name]
        if self._listing:  # the group's help: the summary, without importing the module
            return TyperCommand(cmd_name, help=summary, short_help=summary)
        importlib.import_module(module)
        from typer.main import get_command_from_info

        for info in app.registered_commands:
            if info.name == cmd_name:
                cmd = get_command_from_info(
                    info, pretty_exceptions_short=app.pretty_exceptions_short,
                    rich_markup_mode=app.rich_markup_mode,
                )
                self.commands[cmd_name] = cmd
                return _finish(cmd)
        return None

    def format_help(self, ctx: Any, formatter: Any) -> None:
        self._listing = True
        try:
            super().format_help(ctx, formatter)
        finally:
            self._listing = False


app = typer.Typer(
    name="geardyn",
    help="Dynamics and condition monitoring of gear transmissions.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    cls=LazyGroup,
)


def _version(value: bool) -> None:
    if value:
        from geardyn import __version__

        typer.echo(f"geardyn {__version__}")
        raise typer.Exit()


@app.callback()
def _main(
    debug: bool = typer.Option(False, "--debug", help="show tracebacks of unexpected errors"),
    version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                 help="print the version and exit"),
) -> None:
    """Dynamics and condition monitoring of gear transmissions."""
    import os

    from geardyn.cli.common import DEBUG

    DEBUG["on"] = debug or bool(os.environ.get("GEARDYN_DEBUG"))


__all__ = ["COMMANDS", "app"]
