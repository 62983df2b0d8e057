"""The layers of the package: a building hands its consumers one motion object and knows nothing
of them. No module under ``floorslide/building/`` imports ``floorslide.contents`` or
``floorslide.spectra`` (at module level or inside a function); the consumers import the
building's motion, never the other way round."""

from __future__ import annotations

import ast
from pathlib import Path

import floorslide

PACKAGE = Path(floorslide.__file__).parent


def _module(path: Path) -> str:
    return ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)


def _imports(path: Path, here: str) -> list[tuple[int, str]]:
    """Every module an ``import`` or ``from … import`` of `path` (module `here`) names,
    relative imports resolved, with its line."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here.split(".")[: -node.level]
                name = ".".join(base + ([node.module] if node.module else []))
            else:
                name = node.module or ""
            out.append((node.lineno, name))
            out += [(node.lineno, f"{name}.{a.name}") for a in node.names]
    return out


def test_buildings_import_no_consumer():
    bad = [
        f"{path.relative_to(PACKAGE.parent)}:{line} imports {name}"
        for path in sorted((PACKAGE / "building").glob("*.py"))
        for line, name in _imports(path, _module(path))
        if name.startswith(("floorslide.contents", "floorslide.spectra"))
    ]
    assert not bad, "\n".join(bad)


def test_the_rule_would_see_a_violation(tmp_path):
    """The check reads function-level and relative imports too (a test that cannot fail is
    none)."""
    fake = tmp_path / "probe.py"
    fake.write_text("def f():\n    from ..contents import sliding\n", encoding="utf-8")
    names = [n for _, n in _imports(fake, "floorslide.building.probe")]
    assert "floorslide.contents" in names and "floorslide.contents.sliding" in names
