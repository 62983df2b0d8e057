"""The self-contained HTML report (issue 18): its structure checked by an HTML parser, and its
rendering in a real headless browser (Chromium) checked not to be blank."""

from __future__ import annotations

import base64
import shutil
import subprocess
from html.parser import HTMLParser

import numpy as np
import pytest

from floorslide.errors import IncompleteResultError
from floorslide.report.html import report_html, write_report
from floorslide.run.store import ResultFile

PNG = b"\x89PNG\r\n\x1a\n"


class _Outline(HTMLParser):
    """Headings, table ids, image sources, external references and the scene block."""

    def __init__(self) -> None:
        super().__init__()
        self.headings: list[str] = []
        self.tables: list[str] = []
        self.images: list[str] = []
        self.external: list[str] = []
        self.banner = False
        self.scene = ""
        self._tag = ""
        self._in_scene = False

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self._tag = tag
        if tag == "table" and "id" in a:
            self.tables.append(a["id"])
        if tag == "img":
            self.images.append(a.get("src", ""))
        for key in ("src", "href"):
            if a.get(key, "").startswith(("http:", "https:", "//")):
                self.external.append(a[key])
        if tag in ("link", "script"):
            self.external.append(tag)
        if a.get("id") == "incomplete":
            self.banner = True
        self._in_scene = a.get("id") == "scene"

    def handle_endtag(self, tag):
        if tag == "pre":
            self._in_scene = False

    def handle_data(self, data):
        if self._tag in ("h1", "h2") and data.strip():
            self.headings.append(data.strip())
        if self._in_scene:
            self.scene += data


def test_report_structure(study, tmp_path):
    path = write_report(study.path, tmp_path / "report.html", workers=2)
    text = path.read_text(encoding="utf-8")
    out = _Outline()
    out.feed(text)
    assert out.headings[0].startswith("floorslide report")
    for section in ("Results", "Sliding contents", "Floor response spectra", "Notes",
                    "Records, provenance and quality checks", "Scene", "Software"):  # fmt: skip
        assert section in out.headings
    assert {"table-slides", "table-pfa", "table-frs", "table-records"} <= set(out.tables)
    assert out.images and not out.external and not out.banner
    for src in out.images:  # every figure embedded, a real PNG
        assert src.startswith("data:image/png;base64,")
        assert base64.b64decode(src.split(",", 1)[1])[:8] == PNG
    assert out.scene.strip() == ResultFile(study.path).scene_text.strip()


def test_incomplete_file_carries_the_banner(partial_study):
    with pytest.raises(IncompleteResultError):
        report_html(partial_study.path)
    out = _Outline()
    out.feed(report_html(partial_study.path, allow_incomplete=True))
    assert out.banner


def _browser() -> str | None:
    for name in ("chromium", "chromium-browser", "google-chrome", "chrome"):
        found = shutil.which(name)
        if found:
            return found
    return None


def rendered_ink(path, tmp_path) -> float:
    """The fraction of dark pixels of `path` rendered by headless Chromium (skips, saying so,
    without a browser)."""
    browser = _browser()
    if browser is None:
        pytest.skip(
            "no Chromium or Chrome installed: the rendering test needs one (.ci/run installs it)"
        )
    shot = tmp_path / "shot.png"
    subprocess.run(
        [browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
         # no connections to the network (closed on CI), a fresh profile
         "--disable-quic", "--no-first-run", "--disable-background-networking",
         "--disable-component-update", "--disable-sync",
         f"--user-data-dir={tmp_path / 'profile'}",
         f"--screenshot={shot}", "--window-size=1200,1600", path.resolve().as_uri()],
        check=True, capture_output=True, timeout=120,
    )  # fmt: skip
    from matplotlib.image import imread

    img = imread(shot)
    gray = img[..., :3].mean(axis=2)
    assert gray.shape[0] >= 1000 and gray.shape[1] >= 1000
    return float(np.mean(gray < 0.9))  # dark pixels: text, tables, figure lines


def test_report_renders_in_a_headless_browser(study, tmp_path):
    path = write_report(study.path, tmp_path / "report.html")
    inked = rendered_ink(path, tmp_path)
    assert inked > 0.01, f"the rendered report looks blank ({inked:.4f} of pixels inked)"


def test_cli_report_command(monkeypatch, capsys, study, partial_study, tmp_path):
    from tests.report.test_cli_report import invoke

    target = tmp_path / "r.html"
    code, out, _ = invoke(monkeypatch, capsys, "report", study.path, "-o", target, "--workers", 1)
    assert code == 0 and out.strip() == str(target) and target.read_text().startswith("<!DOCTYPE")
    code, _, err = invoke(monkeypatch, capsys, "report", partial_study.path, "-o", target)
    assert code == 4 and "INCOMPLETE" in err
    code, _, err = invoke(
        monkeypatch, capsys, "report", partial_study.path, "-o", target, "--allow-incomplete"
    )
    assert code == 0 and 'id="incomplete"' in target.read_text()
