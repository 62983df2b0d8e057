"""The project's own design document exists, and every "docs/design.md §n" reference in code,
help texts, README, the documentation site and CHANGELOG points to a section of it (none to a
file users do not have)."""

from __future__ import annotations

import re

from tests.conftest import ROOT

DOC = ROOT / "docs" / "design.md"
SOURCES = [
    ROOT / "README.md",
    ROOT / "CHANGELOG.md",
    *sorted((ROOT / "docs" / "site").rglob("*.md")),
    *sorted((ROOT / "floorslide").rglob("*.py")),
]


def sections() -> set[int]:
    return {int(n) for n in re.findall(r"^## §(\d+) ", DOC.read_text(encoding="utf-8"), re.M)}


def test_design_doc_has_the_sections():
    assert {1, 2, 3, 4, 5, 6, 7, 8, 9, 10} <= sections()


def test_every_reference_points_into_the_design_doc():
    have = sections()
    bad = []
    for path in SOURCES:
        text = path.read_text(encoding="utf-8")
        for n in re.findall(r"docs/design\.md §(\d+)", text):
            if int(n) not in have:
                bad.append(f"{path.name}: §{n}")
        if re.search(r"\bDESIGN(\.md)? ?§", text):
            bad.append(f"{path.name}: bare DESIGN reference")
    assert not bad, bad


def test_scene_keys_are_documented():
    from floorslide.scene import schema

    doc = DOC.read_text(encoding="utf-8")
    text = doc[doc.index("## §4 ") : doc.index("## §5 ")]
    keys = (
        schema.RECORD_KEYS
        | schema.PROCESSING_KEYS
        | schema.FIXED_KEYS
        | schema.ISOLATED_KEYS
        | schema.CONTENT_KEYS
        | schema.SPECTRA_KEYS
        | schema.REPORT_KEYS
    )
    missing = sorted(k for k in keys if not re.search(rf"\b{k}\b", text))
    assert not missing, missing


def test_every_command_is_documented():
    from floorslide.cli import cli

    text = DOC.read_text(encoding="utf-8")
    missing = [name for name in cli.commands if f"`floorslide {name}" not in text]
    assert not missing, missing


def test_every_command_option_is_documented():
    """Each visible option of each command (e.g. ``run --overwrite``, ``--scheduler-timeout``)
    appears in §3 by one of its names."""
    from floorslide.cli import cli

    doc = DOC.read_text(encoding="utf-8")
    text = doc[doc.index("## §3 ") : doc.index("## §4 ")]
    missing = [
        f"{name} {param.opts[0]}"
        for name, command in cli.commands.items()
        for param in command.params
        if param.param_type_name == "option" and not getattr(param, "hidden", False)
        if not any(opt in text for opt in param.opts)
    ]
    assert not missing, missing
