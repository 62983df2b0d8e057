"""One self-contained HTML report of a result file (docs/design.md §10e).

The report holds, in one file that needs nothing else to open and prints on A4: a title with
the INCOMPLETE banner when the run is not finished; the results first — the study's summary
(:mod:`floorslide.report.summary`) and the key figures —; a table of contents; one section per
topic with its design tables (split into parts that fit the page) and its figures (PNG
embedded as base64) next to them; the notes every table carries; the records with their
provenance and quality flags, the scene as run, and the software versions. It is made from
what ``table`` and ``plot`` make; it computes nothing of its own.
"""

from __future__ import annotations

import base64
import html
import platform
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path

from floorslide import outputs
from floorslide.report.columns import EMPTY_NOTES, TITLES, DesignTables
from floorslide.report.formats import _md_heading, cell_text, markdown_columns
from floorslide.report.study import Study, load_study
from floorslide.report.tables import design_tables

CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 1em auto;
       max-width: 76em; color: #111; line-height: 1.35; padding: 0 1em; }
h1 { font-size: 1.45em; margin: 0.3em 0; } h2 { border-bottom: 1px solid #ccc; margin-top: 1.8em; }
h3 { margin: 1.2em 0 0.4em; font-size: 1.05em; }
p.source { margin: 0.2em 0; color: #444; font-size: 0.9em; }
nav#contents { font-size: 0.85em; margin: 0.4em 0 0.6em; color: #444; }
nav#contents a { margin-right: 0.9em; white-space: nowrap; display: inline-block; }
table { border-collapse: collapse; margin: 0.4em 0 1em; font-size: 0.8em; }
th, td { border: 1px solid #bbb; padding: 0.15em 0.4em; text-align: right; }
th { background: #eee; font-weight: 600; vertical-align: bottom; }
td:first-child, th:first-child, td.t { text-align: left; }
td.t { white-space: nowrap; } td.long { white-space: normal; min-width: 18em; }
td.rock { color: #7a3e00; } td.key, th.key { background: #f7f7f7; }
td.p { text-align: left; overflow-wrap: anywhere; }
table.summary td, table.summary th { font-size: 1.05em; padding: 0.2em 0.55em; }
.part { color: #555; font-size: 0.8em; margin: 0.2em 0 0; }
.legend { color: #444; font-size: 0.85em; margin: 0.2em 0; max-width: 62em; }
small { font-weight: normal; color: #555; }
.banner { background: #b00; color: #fff; padding: 0.6em 1em; font-weight: bold; }
figure { margin: 0.8em 0 1.6em; page-break-inside: avoid; }
figure img { max-width: 100%; height: auto; border: 1px solid #ddd; }
figcaption { font-size: 0.8em; color: #555; }
details > summary { cursor: pointer; color: #333; font-size: 0.9em; margin: 0.4em 0; }
pre { background: #f6f6f6; padding: 0.8em; overflow-x: auto; font-size: 0.8em; }
@media print { @page { size: A4; margin: 12mm; }
               body { max-width: none; margin: 0; font-size: 9pt; } h2 { page-break-before: auto; }
               table { font-size: 6.5pt; } nav#contents { display: none; }
               td, th { padding: 0.1em 0.25em; } figure { page-break-inside: avoid; }
               tr { page-break-inside: avoid; }
               details::details-content { content-visibility: visible; display: block; } }
"""

PAGE_CHARS = 150
"""The width of a table the page holds, in characters of the tables' font (about 7 px each
on the page of :data:`CSS`, 76 em wide; headers wrap at their underscores): a wider table is
shown as several parts, each repeating the columns that name its rows
(:func:`column_parts`)."""

KEY_COLUMNS = ("record_set", "comparison", "family", "building", "building_a", "building_b",
               "floor", "content", "record", "mu_k", "mu_s", "state", "period")  # fmt: skip
"""Columns that name a row: repeated in every part of a table split to fit the page."""


GENERATOR = '<meta name="generator" content="floorslide">'
"""In the head of every report: how a report of an earlier run is recognised (and replaced)."""
ADVICE = "choose another -o, or move the file away"


def _e(text: object) -> str:
    return html.escape(str(text), quote=True)


LONG_COLUMNS = frozenset({"note", "qa", "notes", "layer"})
"""Text columns that wrap (the others keep one line)."""


def _td(value, column, row: Mapping) -> str:
    """A cell: labels (no unit) left-aligned, numbers right-aligned."""
    label = column.units == "" and not isinstance(value, bool)
    long = label and column.name in LONG_COLUMNS
    cls = ' class="long"' if long else (' class="t"' if label else "")
    return f"<td{cls}>{_e(cell_text(value, column, row))}</td>"


def _heading_cell(column, key: bool) -> str:
    """A column heading that wraps at its underscores (``peak_<wbr>slide_<wbr>median``)."""
    text = "_<wbr>".join(_e(part) for part in _md_heading(column).split("_"))
    return f'<th class="key">{text}</th>' if key else f"<th>{text}</th>"


def _width(column, rows: Sequence[Mapping]) -> int:
    """The width of a column in characters: its longest cell, or the longest piece of its
    heading (which wraps at underscores and spaces), and the cell's padding."""
    heading = max(len(w) for w in _md_heading(column).replace("_", "_ ").split())
    cells = max((len(cell_text(r[column.name], column, r)) for r in rows), default=0)
    if column.name in LONG_COLUMNS:
        cells = min(cells, 24)  # these wrap
    return max(heading, cells) + 2


def column_parts(name: str, rows: Sequence[Mapping], page: int = PAGE_CHARS) -> list[list]:
    """The columns of table `name` in parts that each fit `page` characters: every part
    starts with the columns that name a row (:data:`KEY_COLUMNS`, as many as take at most half
    the page), then as many of the others, in order, as fit; one part when all fit."""
    cols = list(markdown_columns(name, rows))
    widths = {c.name: _width(c, rows) for c in cols}
    by_name = {c.name: c for c in cols}
    return [[by_name[n] for n in part] for part in _split([c.name for c in cols], widths, page)]


def _split(names: list[str], widths: Mapping[str, int], page: int) -> list[list[str]]:
    """`names` in parts of at most `page` characters, each starting with the key columns
    (:func:`column_parts`)."""
    if sum(widths[n] for n in names) <= page:
        return [list(names)]
    keys, used = [], 0
    for n in names:
        if n in KEY_COLUMNS and used + widths[n] <= page // 2:
            keys.append(n)
            used += widths[n]
    parts, part, width = [], [], used
    for n in names:
        if n in keys:
            continue
        if part and width + widths[n] > page:
            parts.append(keys + part)
            part, width = [], used
        part.append(n)
        width += widths[n]
    if part:
        parts.append(keys + part)
    return parts


def _table(name: str, rows: Sequence[Mapping]) -> str:
    """Table `name`: one HTML table, or several parts that each fit the page
    (:func:`column_parts`); the first part carries the id ``table-<name>``."""
    if not rows:
        return "<p><em>empty</em></p>"
    parts = column_parts(name, rows)
    out = []
    for i, cols in enumerate(parts):
        keys = {c.name for c in cols if c.name in KEY_COLUMNS} if len(parts) > 1 else set()
        head = "".join(_heading_cell(c, c.name in keys) for c in cols)
        body = "".join(
            "<tr>" + "".join(_td(row[c.name], c, row) for c in cols) + "</tr>" for row in rows
        )
        ident = f' id="table-{_e(name)}"' if i == 0 else ""
        if len(parts) > 1:
            out.append(f'<p class="part">part {i + 1} of {len(parts)}</p>')
        out.append(
            f'<table{ident} class="data"><thead><tr>{head}</tr></thead><tbody>{body}</tbody>'
            "</table>"
        )
    return "".join(out)


PROVENANCE_FIRST = ("set", "record", "file", "event", "magnitude", "station", "station_id",
                    "owner", "site_class", "distance_km", "dt", "units")  # fmt: skip
"""Columns of the provenance table that come first when the catalog has them."""


def _provenance(rows: Sequence[Mapping]) -> str:
    """Each record's file and catalog metadata, as the catalog gives them."""
    if not rows:
        return (
            '<p class="empty" id="empty-provenance"><em>no record metadata stored (records '
            "from files without a catalog, or a file written before floorslide kept it)</em></p>"
        )
    keys = list(dict.fromkeys(k for r in rows for k in r))
    cols = [k for k in PROVENANCE_FIRST if k in keys] + [
        k for k in keys if k not in PROVENANCE_FIRST
    ]
    widths = {k: max([len(k)] + [min(len(str(r.get(k, ""))), 30) for r in rows]) + 2 for k in cols}
    out = ["<h3>Provenance <small>(as the catalog gives it)</small></h3>"]
    parts = _split(cols, widths, PAGE_CHARS)
    for i, part in enumerate(parts):
        head = "".join(f"<th>{_e(k)}</th>" for k in part)
        body = "".join(
            "<tr>" + "".join(f'<td class="p">{_e(r.get(k, ""))}</td>' for k in part) + "</tr>"
            for r in rows
        )
        ident = ' id="table-provenance"' if i == 0 else ""
        if len(parts) > 1:
            out.append(f'<p class="part">part {i + 1} of {len(parts)}</p>')
        out.append(f"<table{ident}><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>")
    return "".join(out)


def _versions() -> list[tuple[str, str]]:
    from importlib.metadata import PackageNotFoundError, version

    out = [("Python", platform.python_version())]
    for pkg in ("floorslide", "numpy", "scipy", "numba", "obspy", "control", "h5py", "matplotlib"):
        try:
            out.append((pkg, version(pkg)))
        except PackageNotFoundError:
            out.append((pkg, "not installed"))
    return out


SECTIONS = (
    ("slides", "Sliding contents", ("slides", "slide_ratios"),
     ("slide_vs_mu", "slide_ecdf", "slide_ratio", "oscillators")),
    ("pfa", "Floor accelerations", ("pfa", "pfa_ratios", "code"), ("pfa_profile",)),
    ("frs", "Floor response spectra", ("frs",), ("frs",)),
    ("histories", "Histories", (), ("histories",)),
    ("rocking", "Rocking and overturning", ("rocking",), ("rocking", "overturning")),
    ("isolators", "Nonlinear isolators", ("isolators",), ("hysteresis",)),
    ("plane", "Sliding in the plane (record pairs)", ("plane",), ("plane_path", "plane_ratio")),
    ("practice", "Design practice: scaling, exceedance, fragility",
     ("scaling", "suite", "exceedance", "fragility"), ("scaled_spectra", "fragility")),
)  # fmt: skip
"""The report's sections after the results: ``(anchor, heading, tables, figure kinds)``; a
figure goes to the section of its kind (the start of its file name), next to its tables."""

KEY_FIGURES = ("slide_vs_mu",)
"""Figure kinds shown again under the summary, at the top of the report."""


def _figure_kind(path: Path) -> str:
    stem = Path(path).stem
    kinds = sorted((k for sec in SECTIONS for k in sec[3]), key=len, reverse=True)
    return next((k for k in kinds if stem.startswith(k + "_")), "")


def _figure(path: Path, ident: str = "") -> str:
    data = base64.b64encode(Path(path).read_bytes()).decode("ascii")
    width = _png_width(path)
    size = f' width="{width}"' if width else ""
    anchor = f' id="{_e(ident)}"' if ident else ""
    return (
        f'<figure{anchor}><img alt="{_e(Path(path).stem)}"{size} '
        f'src="data:image/png;base64,{data}"><figcaption>{_e(Path(path).name)}</figcaption>'
        "</figure>"
    )


def _png_width(path: Path) -> int:
    """The width of a PNG in pixels (its IHDR), 0 when it cannot be read."""
    head = Path(path).read_bytes()[:24]
    if head[:8] != b"\x89PNG\r\n\x1a\n":
        return 0
    return int.from_bytes(head[16:20], "big")


def _summary_html(tables: DesignTables) -> list[str]:
    """The summary (:mod:`floorslide.report.summary`) as HTML tables, one per record set,
    content and floor."""
    from floorslide.report.summary import quality_lines, summary_blocks

    out = []
    said: set[str] = set()
    for i, b in enumerate(summary_blocks(tables)):
        out.append(f"<h3>{_e(b.heading)}</h3>")
        if b.caution:
            out.append(f'<p class="legend">{_e(b.caution)}</p>')
        head = "<th>building</th><th>PFA (g)</th>" + "".join(
            f"<th>{_e(x)}</th>" for x in b.friction_labels
        )
        body = []
        for r in b.rows:
            pfa = "—" if r.pfa_g != r.pfa_g else f"{r.pfa_g:.2f}"
            cells = "".join(
                f'<td class="rock">{_e(c)}</td>' if "rock" in c else f"<td>{_e(c)}</td>"
                for c in r.cells
            )
            body.append(f'<tr><td class="t">{_e(r.building)}</td><td>{pfa}</td>{cells}</tr>')
        out.append(
            f'<table class="summary" id="summary-{i}"><thead><tr>{head}</tr></thead>'
            f"<tbody>{''.join(body)}</tbody></table>"
        )
        if b.legend and b.legend not in said:  # once, under the first table it explains
            out.append(f'<p class="legend">{_e(b.legend)}</p>')
            said.add(b.legend)
    if "records" in tables.tables:
        lines = quality_lines(tables["records"])
        out.append(f'<p class="legend">{"<br>".join(_e(x) for x in lines)}</p>')
    return out


PIVOTED = ("slides", "frs")
"""Tables the report shows pivoted (a row per building, a column per friction value or
period) above their figures; the table itself, every column, follows folded."""


def _pivot_html(heading: str, columns: Sequence[str], rows: Sequence[tuple[str, list]]) -> str:
    head = "<th>building</th>" + "".join(f"<th>{_e(c)}</th>" for c in columns)
    body = "".join(
        f'<tr><td class="t">{_e(label)}</td>'
        + "".join(
            f'<td class="rock">{_e(c)}</td>' if "rock" in c else f"<td>{_e(c)}</td>" for c in cells
        )
        + "</tr>"
        for label, cells in rows
    )
    return (
        f'<p class="legend"><strong>{_e(heading)}</strong></p><table class="pivot">'
        f"<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"
    )


def _stat(value: float, outcome: str, scale: float, fmt: str, few: bool = False) -> str:
    from floorslide.report.columns import ROCK

    if outcome == ROCK:
        return "rocks"
    if value != value:
        return "—"
    return format(scale * value, fmt) + ("†" if few else "")


def _slides_pivots(rows: Sequence[Mapping]) -> list[str]:
    """Per record set, content and floor: a building × friction table of the median / p84
    peak slide (mm) and the records that rock."""
    from floorslide.report.summary import MAX_FRICTION_COLUMNS, _pick

    groups: dict = {}
    for r in rows:
        groups.setdefault((r["record_set"], r["content"], r["floor"]), []).append(r)
    out = []
    for (rset, content, floor), g in groups.items():
        pairs_all = sorted({(r["mu_k"], r["mu_s"]) for r in g})
        pairs = _pick(pairs_all, MAX_FRICTION_COLUMNS)
        split = any(abs(k - s) > 1e-12 for k, s in pairs)
        cols = [f"mu {k:g}/{s:g}" if split else f"mu {k:g}" for k, s in pairs]
        n = max(r["n_records"] for r in g)
        body = []
        for b in dict.fromkeys(r["building"] for r in g):
            cells = []
            for k, s in pairs:
                r = next((x for x in g if x["building"] == b and (x["mu_k"], x["mu_s"]) ==
                          (k, s)), None)  # fmt: skip
                if r is None:
                    cells.append("—")
                    continue
                med = _stat(r["peak_slide_median"], r["median_outcome"], 1000, ".1f")
                p84 = _stat(r["peak_slide_p84"], r["p84_outcome"], 1000, ".1f", r["few_records"])
                cells.append(f"{med} / {p84}" + (f" ({r['n_rock']} rock)" if r["n_rock"] else ""))
            body.append((b, cells))
        shown = f"; {len(pairs)} of {len(pairs_all)} friction values" if len(pairs) < len(
            pairs_all) else ""  # fmt: skip
        out.append(
            _pivot_html(
                f"{rset} — {content} on floor {floor}: peak slide median / p84 over {n} "
                f"records, mm (k rock: records under which it rocks){shown}",
                cols,
                body,
            )
        )
    return out


def _frs_pivots(rows: Sequence[Mapping]) -> list[str]:
    """Per record set and floor: a building × period table of the median / p84 PSA (g)."""
    groups: dict = {}
    for r in rows:
        groups.setdefault((r["record_set"], r["floor"]), []).append(r)
    out = []
    for (rset, floor), g in groups.items():
        periods = sorted({r["period"] for r in g})
        n = max(r["n_records"] for r in g)
        body = []
        for b in dict.fromkeys(r["building"] for r in g):
            cells = []
            for t in periods:
                r = next((x for x in g if x["building"] == b and x["period"] == t), None)
                cells.append(
                    "—"
                    if r is None
                    else f"{_stat(r['psa_g_median'], '', 1, '.3g')} / "
                    f"{_stat(r['psa_g_p84'], '', 1, '.3g', r['few_records'])}"
                )
            body.append((b, cells))
        z = g[0].get("damping", float("nan"))
        out.append(
            _pivot_html(
                f"{rset} — floor {floor}: PSA median / p84 over {n} records, g "
                f"({100 * z:g} % damping, unbroadened)",
                [f"T = {t:g} s" for t in periods],
                body,
            )
        )
    return out


def _table_block(tables: DesignTables, name: str) -> list[str]:
    out = [f'<h3 id="t-{_e(name)}">{_e(TITLES.get(name, name))} <small>(table "{_e(name)}")'
           "</small></h3>"]  # fmt: skip
    rows = tables[name]
    if rows and name in PIVOTED:
        out += _slides_pivots(rows) if name == "slides" else _frs_pivots(rows)
        n_cols = len(markdown_columns(name, rows))
        out.append(
            f"<details><summary>every column: table {_e(name)}, {len(rows)} rows × {n_cols} "
            f"columns</summary>{_table(name, rows)}</details>"
        )
    elif rows:
        out.append(_table(name, rows))
    else:
        note = EMPTY_NOTES.get(name, "no rows")
        out.append(f'<p class="empty" id="empty-{_e(name)}"><em>{_e(note)}</em></p>')
    return out


def report_html(
    result: str | Path | Study,
    *,
    tables: DesignTables | None = None,
    figures: Sequence[Path] | None = None,
    scene_text: str | None = None,
    workers: int = 1,
    allow_incomplete: bool = False,
) -> str:
    """The HTML text of the report of `result` (a path, or a :class:`Study` read once).

    It opens with the results: the study's summary (:mod:`floorslide.report.summary`) and
    the key figures (peak slide versus friction), then a table of contents; then one section
    per topic (:data:`SECTIONS`) with its tables — each split into parts that fit the page,
    repeating the columns that name a row (:func:`column_parts`) — and its figures next to
    them; then the notes (the conventions every table states), the records with their
    provenance and quality flags, the scene as run and the software versions.

    `tables` and `figures` made already (the demo) are used as given; otherwise they are made
    here, the figures in a temporary folder with `workers` processes.
    """
    from floorslide.report.plots import plot_figures
    from floorslide.run.store import ResultFile

    study = load_study(result)
    study.require_complete(allow_incomplete)
    if tables is None:
        tables = design_tables(study, allow_incomplete=True)
    if scene_text is None:
        scene_text = ResultFile(study.source).scene_text
    title = tables.scene_name or Path(study.source).name
    with tempfile.TemporaryDirectory() as tmp:
        paths = [
            Path(p)
            for p in (
                figures
                if figures is not None
                else plot_figures(study, tmp, allow_incomplete=True, workers=workers, tables=tables)
            )
        ]
        by_kind: dict[str, list[Path]] = {}
        for p in paths:
            by_kind.setdefault(_figure_kind(p), []).append(p)
        sections = [
            sec
            for sec in SECTIONS
            if any(n in tables.tables for n in sec[2]) or any(k in by_kind for k in sec[3])
        ]
        empty = [
            sec
            for sec in sections
            if not any(tables.tables.get(n) for n in sec[2])
            and not any(by_kind.get(k) for k in sec[3])
        ]
        sections = [sec for sec in sections if sec not in empty]
        toc = [("results", "Results")] + [(a, h.split(":")[0]) for a, h, _, _ in sections]
        if by_kind.get(""):
            toc.append(("figures", "Other figures"))
        if empty:
            toc.append(("absent", "Not in this study"))
        toc += [("notes", "Notes"), ("records", "Records"), ("scene", "Scene"),
                ("software", "Software")]  # fmt: skip
        parts = [
            "<!DOCTYPE html>",
            f'<html lang="en"><head><meta charset="utf-8">{GENERATOR}',
            '<meta name="viewport" content="width=device-width, initial-scale=1">',
            f"<title>floorslide report: {_e(title)}</title>",
            f"<style>{CSS}</style></head><body>",
            f"<h1>floorslide report: {_e(title)}</h1>",
        ]
        if study.status:
            parts.append(f'<p class="banner" id="incomplete">{_e(study.status)}</p>')
        parts.append(
            f'<p class="source">From <code>{_e(study.source)}</code>: {study.tasks_done} tasks. '
            "Every statistic is over all the records of its set; a statistic that falls on "
            "records under which the object rocks reads <em>rocks</em>, never 0 "
            '(<a href="#notes">notes</a>).</p>'
        )
        parts.append(
            '<nav id="contents">Contents: '
            + "".join(f'<a href="#{_e(a)}">{_e(h)}</a>' for a, h in toc)
            + "</nav>"
        )
        parts.append('<h2 id="results">Results</h2>')
        parts += _summary_html(tables)
        for kind in KEY_FIGURES:
            for p in by_kind.get(kind, []):
                parts.append(_figure(p))
        for anchor, heading, names, kinds in sections:
            parts.append(f'<h2 id="{_e(anchor)}">{_e(heading)}</h2>')
            blocks = [_table_block(tables, n) for n in names if n in tables.tables]
            parts += blocks[0] if blocks else []
            for kind in kinds:  # the figures next to the section's first table
                for p in by_kind.get(kind, []):
                    if kind not in KEY_FIGURES:
                        parts.append(_figure(p, f"figure-{Path(p).stem}"))
            for block in blocks[1:]:
                parts += block
            if anchor == "slides":
                parts.append(
                    '<p class="legend">peak slide versus friction: under '
                    '<a href="#results">Results</a></p>'
                )
        if by_kind.get(""):
            parts.append('<h2 id="figures">Other figures</h2>')
            parts += [_figure(p) for p in by_kind[""]]
        if empty:
            parts.append('<h2 id="absent">Not in this study</h2>')
            for _, _, names, _ in empty:
                for name in names:
                    if name in tables.tables:
                        parts += _table_block(tables, name)
    if tables.notes:
        parts.append('<h2 id="notes">Notes</h2><ul>')
        parts += [f"<li>{_e(n)}</li>" for n in tables.notes]
        parts.append("</ul>")
    parts.append('<h2 id="records">Records, provenance and quality checks</h2>')
    parts.append(_table("records", tables["records"]))
    parts.append(_provenance(study.provenance))
    parts.append("<h2>Scene</h2>")
    parts.append(f'<pre id="scene">{_e(scene_text)}</pre>')
    parts.append('<h2 id="software">Software</h2><table><tbody>')
    parts += [f"<tr><td>{_e(k)}</td><td>{_e(v)}</td></tr>" for k, v in _versions()]
    parts.append("</tbody></table></body></html>")
    return "\n".join(parts)


def write_report(result: str | Path | Study, path: str | Path, **kwargs) -> Path:
    """Write :func:`report_html` of `result` to `path` (:func:`floorslide.outputs.write_output`:
    atomically; an existing file is replaced only if it is a report floorslide wrote, and
    never the result file itself); returns it."""
    source = result.source if isinstance(result, Study) else result
    outputs.check_target(
        path, inputs=[source], replace=outputs.contains(GENERATOR.encode()), advice=ADVICE
    )
    text = report_html(result, **kwargs)
    return outputs.write_output(
        path,
        text,
        inputs=[source],
        replace=outputs.contains(GENERATOR.encode()),
        advice=ADVICE,
        what="the report",
    )
