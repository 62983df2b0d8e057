"""The documentation site (docs/site) holds what it promises: its Python examples run as
written, its API reference covers every public name, and no user-facing text speaks of issue
numbers. (CI builds the site itself with ``sphinx-build -W``.)"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from tests.conftest import ROOT

SITE = ROOT / "docs" / "site"
PAGES = sorted(SITE.rglob("*.md"))
SKIP = "<!-- not run by tests/test_docs.py"
"""An HTML comment (invisible on the site) right before a block that is not run, with why."""


def examples(page: Path) -> list[str]:
    """The ``python`` code blocks of a page that are run, in order."""
    text = page.read_text(encoding="utf-8")
    blocks = []
    for m in re.finditer(r"```python\n(.*?)```", text, flags=re.S):
        before = text[: m.start()].rstrip().splitlines()[-1:] or [""]
        if not before[0].startswith(SKIP):
            blocks.append(m.group(1))
    return blocks


RUN = [p for p in PAGES if examples(p)]

SMALL_DEMO = """
[[records]]
set = "broad-band"
catalog = "{catalog}"
where = {{ station_id = ["ELC-180", "TAF-021", "PET-090"] }}

[[buildings]]
id = "fixed"
kind = "fixed"
stories = 1
period = 0.2
damping = 0.02

[[buildings]]
id = "isolated"
kind = "isolated"
superstructure = "fixed"
period = [2.0, 3.0]
damping = 0.10

[[contents]]
id = "cabinet"
floors = "roof"
mu = [0.05, 0.2, 0.4]
width = 0.6
height = 1.8

[spectra]
floors = "all"
periods = {{ min = 0.05, max = 3.0, n = 12 }}

[report]
compare = ["isolated:fixed"]
history_record = "ImperialValley_1940_ELC-180"
"""
"""A small study in the demo's image (same ids) for the examples that read a result file."""


def _env() -> dict:
    return dict(os.environ, PYTHONPATH=str(ROOT), MPLBACKEND="Agg")


@pytest.fixture(scope="module")
def workdir(tmp_path_factory) -> Path:
    """A folder like the repository's root for the examples: ``data`` and ``tests`` linked,
    and ``floorslide-demo/results.h5`` from a small study."""
    work = tmp_path_factory.mktemp("docs")
    for name in ("data", "tests"):
        (work / name).symlink_to(ROOT / name)
    scene = work / "small.toml"
    catalog = (ROOT / "data" / "records" / "slammer" / "index.csv").as_posix()
    scene.write_text(SMALL_DEMO.format(catalog=catalog), encoding="utf-8")
    (work / "floorslide-demo").mkdir()
    out = subprocess.run(
        [sys.executable, "-m", "floorslide.cli", "run", str(scene), "-o",
         str(work / "floorslide-demo" / "results.h5"), "--workers", "1"],
        capture_output=True, text=True, cwd=work, env=_env(), timeout=900,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr[-2000:]
    return work


DRIVER = textwrap.dedent(
    """
    import sys
    blocks = {blocks!r}
    namespace = {{"__name__": "__main__"}}
    for i, code in enumerate(blocks):
        try:
            exec(compile(code, f"{page} (block {{i + 1}})", "exec"), namespace)
        except Exception:
            print(f"block {{i + 1}} of {page} failed:\\n{{code}}", file=sys.stderr)
            raise
    """
)


@pytest.mark.parametrize("page", RUN, ids=[p.relative_to(SITE).as_posix() for p in RUN])
def test_examples_run(page, workdir):
    """Every Python block of the page runs, in order in one interpreter (a block may use what an
    earlier one of its page made), from a folder like the repository's root."""
    code = DRIVER.format(blocks=examples(page), page=page.relative_to(SITE).as_posix())
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        cwd=workdir,
        env=_env(),
        timeout=900,
    )
    assert out.returncode == 0, out.stderr[-3000:]


def test_pages_have_examples():
    names = {p.relative_to(SITE).as_posix() for p in RUN}
    assert {"getting-started.md", "guide/records.md", "guide/result-file.md"} <= names


def test_api_reference_covers_every_public_name():
    import floorslide

    text = (SITE / "api.rst").read_text(encoding="utf-8")
    listed = set(re.findall(r"^   (\w+)$", text, flags=re.M))
    assert set(floorslide.__all__) <= listed, sorted(set(floorslide.__all__) - listed)
    assert listed <= set(floorslide.__all__), sorted(listed - set(floorslide.__all__))


def test_no_issue_numbers_for_users():
    """User-facing text (README, the site, the changelog, the design document, help texts)
    never says "issue 17": a user has no issue tracker to look in."""
    sources = [ROOT / "README.md", ROOT / "CHANGELOG.md", ROOT / "docs" / "design.md", *PAGES]
    bad = [
        f"{p.relative_to(ROOT)}: {m.group(0)}"
        for p in sources
        for m in re.finditer(r"(?i)\bissues? \d+", p.read_text(encoding="utf-8"))
    ]
    assert not bad, bad


def test_no_issue_numbers_in_help():
    from click.testing import CliRunner

    from floorslide.cli import cli

    runner = CliRunner()
    for name in [None, *cli.commands]:
        out = runner.invoke(cli, [name, "--help"] if name else ["--help"])
        assert out.exit_code == 0, name
        assert not re.search(r"(?i)\bissues? \d+", out.output), name


def test_first_study_scene_plans(tmp_path):
    """The scene of "Your first study in five steps" is valid and plans, on the bundled PEER
    records as its ``records/`` folder."""
    text = (SITE / "getting-started.md").read_text(encoding="utf-8")
    part = text[text.index("## Your first study") :]
    scene = textwrap.dedent(re.search(r"```toml\n(.*?)```", part, flags=re.S).group(1))
    (tmp_path / "records").symlink_to(ROOT / "data" / "records" / "pairs")
    (tmp_path / "my-study.toml").write_text(scene, encoding="utf-8")
    out = subprocess.run(
        [sys.executable, "-m", "floorslide.cli", "run", "my-study.toml", "--dry-run"],
        capture_output=True, text=True, cwd=tmp_path, env=_env(), timeout=900,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr[-2000:]
    assert "20 records × 4 buildings = 80 tasks" in out.stdout, out.stdout
