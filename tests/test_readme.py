"""The README's tour runs as written: every ``$ floorslide ...`` command and the Python block of
its "A tour" section, from the repository root (CI runs the README's two set-up commands before
this suite, in the same virtual environment)."""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys

import pytest

from tests.conftest import ROOT

README = ROOT / "README.md"


def tour_section() -> str:
    text = README.read_text(encoding="utf-8")
    start = text.index("\n## A tour")
    end = text.index("\n## ", start + 5)
    return text[start:end]


def tour_commands() -> list[str]:
    blocks = re.findall(r"```console\n(.*?)```", tour_section(), flags=re.S)
    commands = []
    for block in blocks:
        block = re.sub(r"\\\n\s*", " ", block)  # shell line continuations
        for line in block.splitlines():
            if line.startswith("$ floorslide"):
                commands.append(line[2:].split("  #")[0].strip())
    return commands


def tour_python() -> list[str]:
    return re.findall(r"```python\n(.*?)```", tour_section(), flags=re.S)


def _env() -> dict:
    return dict(os.environ, PYTHONPATH=str(ROOT))


def test_tour_has_commands_and_code():
    assert len(tour_commands()) >= 3
    assert tour_python()


@pytest.mark.parametrize("command", tour_commands())
def test_tour_command(command):
    args = shlex.split(command)
    out = subprocess.run(
        [sys.executable, "-m", "floorslide.cli", *args[1:]],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env=_env(),
        timeout=600,
    )
    assert out.returncode == 0, f"{command}: {out.stderr[-2000:]}"
    assert out.stdout.strip()
    assert "Traceback" not in out.stderr


@pytest.mark.parametrize("index", range(len(tour_python())))
def test_tour_python(index):
    code = tour_python()[index]
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env=_env(),
        timeout=600,
    )
    assert out.returncode == 0, out.stderr[-2000:]


def test_readme_is_a_landing_page():
    """What it is, the two set-up commands, a picture, a table, a tour, links into the docs —
    the rest is in the documentation site."""
    text = README.read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 250
    assert "pip install . && floorslide demo" in text
    assert "](docs/site/getting-started.md" in text and "![" in text and "\n|---|" in text


def test_ci_runs_the_readme_commands():
    """.ci/run runs the README's two set-up commands exactly as written."""
    text = README.read_text(encoding="utf-8")
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    commands = re.findall(r"```console\n(pip install [^\n]*)\n```", text)[:2]
    assert commands == [
        "pip install . && floorslide demo",
        'pip install -e ".[test]" && python -m pytest -q',
    ], commands
    for command in commands:
        assert f"\n{command}\n" in ci, command
