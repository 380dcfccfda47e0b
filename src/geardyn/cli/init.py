"""``geardyn init TEMPLATE [FILE]``: write a commented starter config (parallel, planetary,
FE transmission, differential) with a dynamic model, sensors and ``[diagnosis]``, that
simulates and diagnoses as it is."""

from __future__ import annotations

from pathlib import Path

import typer

from geardyn.cli import app
from geardyn.cli.common import check_output_file, console, friendly_errors
from geardyn.errors import InputError


@app.command("init")
@friendly_errors
def init_cmd(
    template: str = typer.Argument(..., help="parallel, planetary, transmission or differential"),
    file: Path | None = typer.Argument(None, help="file to write (default: TEMPLATE.toml)"),
    force: bool = typer.Option(False, "--force", help="overwrite an existing file"),
) -> None:
    """Write a commented starter config from a template."""
    from geardyn.templates import TEMPLATES, render

    if template not in TEMPLATES:
        choices = "; ".join(f"{k} ({v[0]})" for k, v in TEMPLATES.items())
        raise InputError(f"TEMPLATE: unknown template '{template}'; choose one of: {choices}")
    path = file or Path(f"{template}.toml")
    if path.suffix.lower() != ".toml":
        raise InputError(f"FILE: '{path}' should end in .toml")
    if path.exists() and not force:
        raise InputError(f"FILE: '{path}' exists; choose another name or pass --force")
    check_output_file(path, "FILE")
    from geardyn.checkpoint import write_text

    write_text(path, render(template, str(path)))
    console.print(f"wrote {path} ({TEMPLATES[template][0]}); edit it, then e.g.\n"
                  f"  geardyn simulate {path} --out run.nc\n"
                  f"  geardyn diagnose {path} --out diagnosis")
