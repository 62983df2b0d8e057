"""floorslide init: a commented scene template that loads and plans on the bundled records,
written through floorslide.outputs, never over a file it did not write (docs/design.md §3)."""

from __future__ import annotations

from floorslide.scene.planner import plan
from floorslide.scene.schema import load_scene
from floorslide.scene.template import MARKER
from tests.conftest import floorslide_cli


def run(*args, cwd=None):
    """``floorslide ARGS`` (the entry point, in this process: :func:`floorslide_cli`)."""
    return floorslide_cli(*args, cwd=cwd)


def test_init_writes_a_template_that_plans_on_the_bundled_records(tmp_path):
    out = run("init", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    path = tmp_path / "scene.toml"
    text = path.read_text(encoding="utf-8")
    assert text.startswith(MARKER + "\n") and "floorslide run scene.toml --dry-run" in text
    sc = load_scene(path)
    assert sc.warnings == ()
    p = plan(sc, evaluate=False)
    assert len(p.records) == 18 and {b.base for b in sc.buildings} == {"fixed", "isolated", "fps"}
    dry = run("run", str(path), "--dry-run")
    assert dry.returncode == 0, dry.stderr
    assert "72 tasks" in dry.stdout and "warning" not in dry.stderr


def test_init_replaces_only_an_unedited_template(tmp_path):
    path = tmp_path / "study.toml"
    assert run("init", str(path)).returncode == 0
    assert run("init", str(path)).returncode == 0  # unedited: nothing is lost
    path.write_text(path.read_text() + "\n# my note\n")
    again = run("init", str(path))
    assert again.returncode == 2
    assert again.stderr.count("\n") == 1 and str(path) in again.stderr
    assert path.read_text().endswith("# my note\n")
    other = tmp_path / "mine.toml"
    other.write_text("[scene]\n")
    refused = run("init", str(other))
    assert refused.returncode == 2 and other.read_text() == "[scene]\n"
