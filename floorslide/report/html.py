"""One self-contained HTML report of a result file (docs/design.md §10e, issue 18).

The report holds, in one file that needs nothing else to open and prints on A4: a title with
the INCOMPLETE banner when the run is not finished, the notes every table carries, each design
table, every figure (PNG embedded as base64), the records with their provenance and quality
flags, the scene as run, and the software versions. It is made from what ``table`` and
``plot`` make; it computes nothing of its own.
"""

from __future__ import annotations

import base64
import html
import platform
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path

from floorslide import outputs
from floorslide.report.columns import EMPTY_NOTES, TABLE_NAMES, TITLES, DesignTables
from floorslide.report.formats import _md_heading, cell_text, markdown_columns
from floorslide.report.study import Study, load_study
from floorslide.report.tables import design_tables

CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 2em auto;
       max-width: 70em; color: #111; line-height: 1.4; padding: 0 1em; }
h1 { font-size: 1.6em; } h2 { border-bottom: 1px solid #ccc; margin-top: 2em; }
table { border-collapse: collapse; margin: 0.5em 0 1.5em; font-size: 0.85em; }
th, td { border: 1px solid #bbb; padding: 0.2em 0.5em; text-align: right; }
th { background: #eee; } td:first-child, th:first-child, td.t { text-align: left; }
td.t { white-space: nowrap; } td.long { white-space: normal; min-width: 22em; }
.wide { overflow-x: auto; max-width: 100%; } small { font-weight: normal; color: #555; }
.banner { background: #b00; color: #fff; padding: 0.6em 1em; font-weight: bold; }
figure { margin: 1em 0 2em; page-break-inside: avoid; }
figure img { max-width: 100%; border: 1px solid #ddd; }
pre { background: #f6f6f6; padding: 0.8em; overflow-x: auto; font-size: 0.8em; }
@media print { @page { size: A4; margin: 12mm; }
               body { max-width: none; margin: 0; font-size: 9pt; } h2 { page-break-before: auto; }
               .wide { overflow: visible; } table { font-size: 6.5pt; }
               td, th { padding: 0.1em 0.25em; } figure { page-break-inside: avoid; }
               tr { page-break-inside: avoid; } }
"""


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


def _table(name: str, rows: Sequence[Mapping]) -> str:
    if not rows:
        return "<p><em>empty</em></p>"
    cols = markdown_columns(name, rows)
    head = "".join(f"<th>{_e(_md_heading(c))}</th>" for c in cols)
    body = "".join(
        "<tr>" + "".join(_td(row[c.name], c, row) for c in cols) + "</tr>" for row in rows
    )
    return (
        f'<div class="wide"><table id="table-{_e(name)}"><thead><tr>{head}</tr></thead>'
        f"<tbody>{body}</tbody></table></div>"
    )


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
    head = "".join(f"<th>{_e(k)}</th>" for k in cols)
    body = "".join(
        "<tr>" + "".join(f'<td class="t">{_e(r.get(k, ""))}</td>' for k in cols) + "</tr>"
        for r in rows
    )
    return (
        '<h3>Provenance <small>(as the catalog gives it)</small></h3><div class="wide">'
        f'<table id="table-provenance"><thead><tr>{head}</tr></thead><tbody>{body}</tbody>'
        "</table></div>"
    )


def _versions() -> list[tuple[str, str]]:
    from importlib.metadata import PackageNotFoundError, version

    out = [("Python", platform.python_version())]
    for pkg in ("floorslide", "numpy", "scipy", "numba", "obspy", "control", "h5py", "matplotlib"):
        try:
            out.append((pkg, version(pkg)))
        except PackageNotFoundError:
            out.append((pkg, "not installed"))
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
    parts = [
        "<!DOCTYPE html>",
        f'<html lang="en"><head><meta charset="utf-8">{GENERATOR}',
        f"<title>floorslide report: {_e(title)}</title>",
        f"<style>{CSS}</style></head><body>",
        f"<h1>floorslide report: {_e(title)}</h1>",
    ]
    if study.status:
        parts.append(f'<p class="banner" id="incomplete">{_e(study.status)}</p>')
    parts.append(f"<p>From <code>{_e(study.source)}</code>: {study.tasks_done} tasks.</p>")
    if tables.notes:
        parts.append("<h2>Notes</h2><ul>")
        parts += [f"<li>{_e(n)}</li>" for n in tables.notes]
        parts.append("</ul>")
    practice = ("scaling", "suite", "code", "exceedance", "fragility")
    for anchor, heading, names in (
        ("tables", "Design tables", [n for n in TABLE_NAMES if n not in (*practice, "records")]),
        ("practice", "Design practice: scaling, code comparison, exceedance, fragility", practice),
    ):
        parts.append(f'<h2 id="{anchor}">{_e(heading)}</h2>')
        for name in names:
            parts.append(
                f'<h3>{_e(TITLES.get(name, name))} <small>(table "{_e(name)}")</small></h3>'
            )
            if tables[name]:
                parts.append(_table(name, tables[name]))
            else:
                note = EMPTY_NOTES.get(name, "no rows")
                parts.append(f'<p class="empty" id="empty-{_e(name)}"><em>{_e(note)}</em></p>')
    with tempfile.TemporaryDirectory() as tmp:
        paths = (
            list(figures)
            if figures is not None
            else plot_figures(study, tmp, allow_incomplete=True, workers=workers)
        )
        parts.append("<h2>Figures</h2>")
        for p in paths:
            data = base64.b64encode(Path(p).read_bytes()).decode("ascii")
            parts.append(
                f'<figure><img alt="{_e(Path(p).stem)}" src="data:image/png;base64,{data}">'
                f"<figcaption>{_e(Path(p).name)}</figcaption></figure>"
            )
    parts.append("<h2>Records, provenance and quality checks</h2>")
    parts.append(_table("records", tables["records"]))
    parts.append(_provenance(study.provenance))
    parts.append("<h2>Scene</h2>")
    parts.append(f'<pre id="scene">{_e(scene_text)}</pre>')
    parts.append("<h2>Software</h2><table><tbody>")
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
