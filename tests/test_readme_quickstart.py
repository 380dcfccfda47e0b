"""The README quick start runs as written (issue 21): every command of its first block, in
order, in a fresh temporary folder holding only a link to examples/, with exit code 0."""

from __future__ import annotations

import os
import shlex
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from geardyn.cli import app

ROOT = Path(__file__).resolve().parents[1]


def quick_start_commands(readme: Path = ROOT / "README.md") -> list[list[str]]:
    """The command lines of the first code block after '## Quick start' (comments removed)."""
    text = readme.read_text(encoding="utf-8")
    section = text[text.index("## Quick start"):]
    start = section.index("```\n") + 4
    block = section[start:section.index("```", start)]
    return [shlex.split(line, comments=True) for line in block.splitlines() if line.strip()]


def test_quick_start_block_is_found():
    cmds = quick_start_commands()
    assert len(cmds) >= 10
    assert all(c[0] in (".venv/bin/geardyn", ".venv/bin/python") for c in cmds)
    outs = [c[c.index("--out") + 1] for c in cmds if "--out" in c]
    assert len(outs) == len(set(outs)), "two quick-start commands write the same output"


@pytest.mark.slow
def test_quick_start_runs_as_written(tmp_path, monkeypatch):
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    monkeypatch.chdir(tmp_path)
    runner = CliRunner()
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(ROOT / "src"), os.environ.get("PYTHONPATH", "")])}
    for cmd in quick_start_commands():
        line = shlex.join(cmd)
        if cmd[0] == ".venv/bin/python":
            r = subprocess.run([sys.executable, *cmd[1:]], cwd=tmp_path, env=env,
                               capture_output=True, text=True, timeout=300)
            assert r.returncode == 0, f"{line}\n{r.stdout}\n{r.stderr}"
        else:
            r = runner.invoke(app, cmd[1:])
            assert r.exit_code == 0, f"{line}\n{r.output}"
