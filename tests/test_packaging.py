"""Every sub-package of floorslide is listed in pyproject.toml: a missing one installs fine in
editable mode (the tests) and breaks a regular install (``pip install .``, the README's quick
start) with an ImportError."""

from __future__ import annotations

import tomllib

from tests.conftest import ROOT


def test_every_subpackage_is_installed():
    listed = set(
        tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"]
    )
    found = {
        ".".join(p.parent.relative_to(ROOT).parts)
        for p in (ROOT / "floorslide").rglob("__init__.py")
        if "__pycache__" not in p.parts
    }
    assert found - listed == set()
