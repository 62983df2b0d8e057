"""The report opens with results and fits the page: checked on its HTML (always) and on its
layout in headless Chromium (a 1280 × 800 screen: the first screen holds a result, no table
is wider than the page, no horizontal scroll bar, figures at a readable size)."""

from __future__ import annotations

import json
import subprocess
from html.parser import HTMLParser

import pytest

from floorslide.report import design_tables
from floorslide.report.columns import TABLE_NAMES
from floorslide.report.html import PAGE_CHARS, _width, column_parts, write_report
from floorslide.report.summary import summary_blocks
from tests.report.test_html_report import _browser

SCREEN = (1280, 800)


class _Order(HTMLParser):
    """The order of the report's headings, tables, figures and links."""

    def __init__(self) -> None:
        super().__init__()
        self.events: list[tuple[str, str]] = []
        self.ids: set[str] = set()
        self.links: list[str] = []
        self._tag = ""

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self._tag = tag
        if "id" in a:
            self.ids.add(a["id"])
        if tag == "a" and a.get("href", "").startswith("#"):
            self.links.append(a["href"][1:])
        if tag == "table":
            self.events.append(("table", a.get("class", "") + " " + a.get("id", "")))
        if tag == "img":
            self.events.append(("img", a.get("alt", "")))

    def handle_data(self, data):
        if self._tag in ("h1", "h2") and data.strip():
            self.events.append((self._tag, data.strip()))


@pytest.fixture(scope="module")
def report(study, tmp_path_factory):
    return write_report(study.path, tmp_path_factory.mktemp("layout") / "report.html", workers=2)


def test_the_report_opens_with_the_summary_and_a_key_figure(report):
    order = _Order()
    order.feed(report.read_text(encoding="utf-8"))
    events = order.events
    assert events[0][0] == "h1" and events[1] == ("h2", "Results")
    # right under it: the summary's tables, then peak slide versus friction
    assert events[2][0] == "table" and "summary" in events[2][1]
    first_img = next(e for e in events if e[0] == "img")
    assert first_img[1].startswith("slide_vs_mu_")
    assert events.index(first_img) < events.index(("h2", "Sliding contents"))
    # the notes (caveats) come after the results, and every link of the contents resolves
    assert events.index(("h2", "Notes")) > events.index(("h2", "Results"))
    assert {"results", "slides", "notes", "records", "scene", "software"} <= set(order.links)
    assert set(order.links) <= order.ids


def test_figures_sit_next_to_their_tables(report):
    order = _Order()
    order.feed(report.read_text(encoding="utf-8"))
    heads = [i for i, e in enumerate(order.events) if e[0] == "h2"]

    def section(img_prefix):
        i = next(k for k, e in enumerate(order.events) if e == ("img", img_prefix))
        return order.events[max(h for h in heads if h < i)][1]

    assert section("frs_broad-band") == "Floor response spectra"
    assert section("pfa_profile_broad-band") == "Floor accelerations"
    assert section("slide_ecdf_broad-band") == "Sliding contents"


def test_every_table_is_split_to_fit_the_page(study):
    tables = design_tables(study.path)
    split = []
    for name in TABLE_NAMES:
        rows = tables[name]
        if not rows:
            continue
        parts = column_parts(name, rows)
        for cols in parts:
            assert sum(_width(c, rows) for c in cols) <= PAGE_CHARS, (name, cols)
        if len(parts) > 1:
            split.append(name)
            keys = [c.name for c in parts[0] if c in parts[1]]
            assert {"record_set", "building", "floor", "content", "mu_k"} <= set(keys) or (
                name != "slides"
            )
    assert "slides" in split  # 30 columns: today more than a page


LAYOUT_SCRIPT = """<script>
window.addEventListener('load', () => {
  const W = document.documentElement.clientWidth;
  const tables = [...document.querySelectorAll('table')].map(t => {
    const r = t.getBoundingClientRect();
    return {id: t.id, cls: t.className, left: r.left, right: r.right, top: r.top};
  });
  const imgs = [...document.querySelectorAll('figure img')].map(i => ({
    alt: i.alt, shown: i.getBoundingClientRect().width, natural: i.naturalWidth}));
  const out = document.createElement('pre');
  out.id = 'layout';
  out.textContent = JSON.stringify({W, scroll: document.documentElement.scrollWidth,
                                    tables, imgs});
  document.body.appendChild(out);
});
</script>"""


def measure(path, tmp_path) -> dict:
    """The report's layout in headless Chromium at :data:`SCREEN` (skips without a browser)."""
    browser = _browser()
    if browser is None:
        pytest.skip(
            "no Chromium or Chrome installed: the layout test needs one (.ci/run installs it)"
        )
    probe = tmp_path / "probe.html"
    text = path.read_text(encoding="utf-8").replace("</body>", LAYOUT_SCRIPT + "</body>")
    probe.write_text(text, encoding="utf-8")
    done = subprocess.run(
        [browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
         "--disable-quic", "--no-first-run", "--disable-background-networking",
         "--disable-component-update", "--disable-sync",
         f"--user-data-dir={tmp_path / 'profile'}", "--virtual-time-budget=5000",
         f"--window-size={SCREEN[0]},{SCREEN[1]}", "--dump-dom", probe.resolve().as_uri()],
        check=True, capture_output=True, timeout=120, text=True,
    )  # fmt: skip
    start = done.stdout.index('<pre id="layout">') + len('<pre id="layout">')
    import html

    return json.loads(html.unescape(done.stdout[start : done.stdout.index("</pre>", start)]))


def test_the_first_screen_holds_a_result_and_nothing_is_wider_than_the_page(
    study, report, tmp_path
):
    layout = measure(report, tmp_path)
    width = layout["W"]
    assert layout["scroll"] <= width, "the page scrolls sideways"
    wide = [t for t in layout["tables"] if t["right"] > width - 1 or t["left"] < 0]
    assert not wide, f"tables wider than the page: {wide}"
    summary = [t for t in layout["tables"] if "summary" in t["cls"]]
    assert summary and summary[0]["top"] < SCREEN[1] - 150  # the first screen: a result
    assert len(summary) == len(summary_blocks(design_tables(study.path)))
    for img in layout["imgs"]:  # readable: no figure shrunk below 2/3 of its size
        assert img["shown"] >= 0.66 * img["natural"], img


def test_slides_and_spectra_are_pivoted_with_every_column_folded_below(report):
    text = report.read_text(encoding="utf-8")
    sliding = text[text.index('<h2 id="slides">') : text.index('<h2 id="pfa">')]
    assert sliding.index('class="pivot"') < sliding.index("<details>")
    assert sliding.index("<details>") < sliding.index('id="table-slides"')
    # a building per row, a friction value per column: median / p84 in mm
    assert "<th>building</th><th>mu 0.05</th><th>mu 0.1</th><th>mu 0.2</th>" in sliding
    assert ">rocks / rocks (3 rock)<" in sliding  # pulse-like fixed at mu 0.05: every record
    spectra = text[text.index('<h2 id="frs">') :]
    assert spectra.index('class="pivot"') < spectra.index('id="table-frs"')
    assert "<th>T = 0.1 s</th>" in spectra
