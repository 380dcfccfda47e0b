"""``geardyn schema [--out FILE]``: the JSON Schema of a config file, from the pydantic models
(for editor completion, e.g. Taplo / Even Better TOML ``#:schema`` or a ``[[schema]]`` rule)."""

from __future__ import annotations

import json
from pathlib import Path

import typer

from geardyn.cli import app
from geardyn.cli.common import check_output_file, console, friendly_errors


def config_schema() -> dict:
    """JSON Schema (draft 2020-12) of :class:`geardyn.config.GeardynConfig` in validation mode:
    numbers may also be written as strings with a unit (``"3 mm"``), see docs/config.md."""
    from geardyn.config import GeardynConfig
    from geardyn.config.units import annotate_schema

    schema = GeardynConfig.model_json_schema(mode="validation")
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema["title"] = "geardyn config"
    return annotate_schema(schema)


@app.command("schema")
@friendly_errors
def schema_cmd(
    out: Path | None = typer.Option(None, "--out", "-o", help="write the schema to this file "
                                    "(default: print it)"),
) -> None:
    """JSON Schema of the config file (editor completion)."""
    if out is not None:
        check_output_file(out, "--out")
    text = json.dumps(config_schema(), indent=2)
    if out is None:
        typer.echo(text)
    else:
        from geardyn.checkpoint import write_text

        write_text(out, text + "\n")
        console.print(f"schema written to {out}")
