"""The design tables (and the per-record table) as Markdown, CSV, JSON and pandas DataFrames.

Every format carries what docs/design.md §10 asks a report to state: the conventions (notes: the
statistic, the records per set, how rocking objects enter the statistics, broadening), and an
INCOMPLETE label when the result file's run is not finished — a title and a bold line in
Markdown, a first line ``# INCOMPLETE: …`` in every CSV (``pandas.read_csv(path,
comment="#")`` skips it), ``"status"`` and ``"complete": false`` in JSON, ``df.attrs["status"]``
on DataFrames.

An empty table whose emptiness means something (the ``isolators`` table of a study without
nonlinear isolation, the ``rocking`` table of one without rocking results) says so: ``_No
rows: …_`` in Markdown, a line ``# …`` above the CSV header, a note in JSON and on DataFrames.

Cells: NaN is ``—`` in Markdown, an empty cell in CSV and ``null`` in JSON; ``inf`` is ``∞``,
``inf`` and ``null``. A statistic that falls on rocking records is ``rocks`` in Markdown (its
``*_outcome`` column says ``rock`` in every format); in Markdown a p84 over fewer than
:data:`~floorslide.report.columns.MIN_RECORDS` records is marked ``†``.
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from floorslide import outputs
from floorslide.errors import one_line
from floorslide.report.columns import (
    COLUMNS,
    EMPTY_NOTES,
    MIN_RECORDS,
    OSCILLATOR_COLUMNS,
    PAIR_FRS_COLUMNS,
    PERCENTILE,
    ROCK,
    STATS,
    TABLE_NAMES,
    TITLES,
    Column,
    DesignTables,
)

_PLAIN = (
    "mu_k",
    "mu_s",
    "period",
    "damping",
    "isolation_period",
    "broadening",
    "mu",
    "q_ratio",
    "alpha",
    "yield_disp",
    "capacity",
    "isolation_damping",
)
_LAYER_PARAMETERS = ("q_ratio", "yield_disp", "alpha", "mu", "mu_s", "radius", "capacity")


def _rocks(column: str, row: Mapping) -> bool:
    """Whether the statistic in `column` falls on rocking records (its outcome is rock)."""
    for stat in STATS:
        if column.endswith(f"_{stat}") and f"{stat}_outcome" in row:
            return row[f"{stat}_outcome"] == ROCK
        for side in ("a", "b"):
            if column.endswith(f"_{stat}_{side}") and f"{stat}_outcome_{side}" in row:
                return row[f"{stat}_outcome_{side}"] == ROCK
        if column.endswith(f"_{stat}_ratio") and f"{stat}_outcome_a" in row:
            return ROCK in (row[f"{stat}_outcome_a"], row[f"{stat}_outcome_b"])
    return False


_MD_ESCAPES = {"\\": "\\\\", "|": "\\|", "[": "\\[", "]": "\\]", "`": "\\`"}
_HTML_ESCAPES = {"&": "&amp;", "<": "&lt;", ">": "&gt;"}


def md_text(text: object) -> str:
    """`text` (a scene's or catalog's string: an id, a name, a path, a note quoting them) as
    literal Markdown text on one line: HTML-significant characters as entities (``<script>``
    shows, never runs, in a viewer that renders HTML), ``|`` escaped (no extra table cell),
    ``[``/``]`` and backticks escaped (no link, image or code span), a backslash doubled, and
    control characters (a newline ends a table row) shown as escapes (``\\n``)."""
    out = []
    for ch in one_line(str(text)):
        out.append(_HTML_ESCAPES.get(ch) or _MD_ESCAPES.get(ch) or ch)
    return "".join(out)


def cell_text(value, column: Column, row: Mapping) -> str:
    """A table cell as plain text (Markdown and HTML escape it their own way): NaN as ``—``
    (``rocks`` where the statistic falls on rocking records), ``inf`` as ``∞``, ``†`` on a
    p84 from few records, a tuple as ``a; b; c``."""
    if isinstance(value, tuple | list):
        return "; ".join(f"{v:g}" if isinstance(v, float) else str(v) for v in value)
    if isinstance(value, bool | np.bool_):
        return "yes" if value else ""
    if isinstance(value, float):
        if math.isnan(value):
            return "rocks" if _rocks(column.name, row) else "—"
        if math.isinf(value):
            return "∞" if value > 0 else "-∞"
        if column.name in _PLAIN or column.name.startswith("isolation_period"):
            return f"{value:g}"
        text = f"{value:.4g}"
        few = row.get("few_records") and ("_p84" in column.name)
        return text + "†" if few else text
    return str(value)


def _md_cell(value, column: Column, row: Mapping) -> str:
    return md_text(cell_text(value, column, row))


def _md_heading(column: Column) -> str:
    if column.units in ("", "1"):
        return column.name
    return f"{column.name} ({column.units.replace('**2', '²')})"


def markdown_columns(name: str, rows: Sequence[Mapping]) -> tuple[Column, ...]:
    """The columns Markdown shows: all but those no row fills (the oscillator columns of a
    study without oscillators, the broadened PSA of a study without broadening, the
    parameters of a kind of isolation layer the study does not have)."""
    cols = COLUMNS[name]
    if name == "slides" and not any(r.get("model") == "oscillator" for r in rows):
        cols = tuple(c for c in cols if c.name not in OSCILLATOR_COLUMNS)
    if name == "frs" and not any(r.get("broadening") for r in rows):
        cols = tuple(c for c in cols if not c.name.startswith("psa_broadened"))
    if name == "frs" and not any(r.get("orientation") for r in rows):
        cols = tuple(c for c in cols if c.name not in PAIR_FRS_COLUMNS)
    if name == "isolators" and rows:
        unused = {k for k in _LAYER_PARAMETERS if all(math.isnan(float(r[k])) for r in rows)}
        cols = tuple(c for c in cols if c.name not in unused)
    return cols


def format_markdown_table(name: str, rows: Sequence[Mapping]) -> str:
    """One table as GitHub Markdown; NaN as ``—`` (``rocks`` where the statistic falls on
    rocking records), ``inf`` as ``∞``, ``†`` on a p84 from few records."""
    cols = markdown_columns(name, rows)
    lines = [
        "| " + " | ".join(_md_heading(c) for c in cols) + " |",
        "|" + "|".join("---" for _ in cols) + "|",
    ]
    for row in rows:
        lines.append("| " + " | ".join(_md_cell(row[c.name], c, row) for c in cols) + " |")
    if not rows:
        lines.append("| " + " | ".join("" for _ in cols) + " |")
    return "\n".join(lines)


def format_markdown(tables: DesignTables, names: Sequence[str] = TABLE_NAMES) -> str:
    """The design tables as one Markdown document: a title, the conventions, one section per
    table (an INCOMPLETE file says so in its title and first line)."""
    title = md_text(tables.scene_name or Path(tables.source).name)
    out = [f"{MARKDOWN_TITLE}{title}" + (" — INCOMPLETE" if tables.status else ""), ""]
    out.append(f"From {md_text(tables.source)}.")
    out.append("")
    if tables.status:
        out += [f"**{md_text(tables.status)}**", ""]
    for note in tables.notes:
        out.append(f"- {md_text(note)}")
    if tables.comparisons:
        comps = "; ".join(
            f"{c.spec} ({', '.join(c.a)} over {', '.join(c.b)})" for c in tables.comparisons
        )
        out.append(f"- comparisons: {md_text(comps)}")
    for name in names:
        out += ["", f"## {TITLES[name]}" + (" (INCOMPLETE)" if tables.status else ""), ""]
        rows = tables[name]
        if not rows:
            out.append(f"_No rows: {EMPTY_NOTES[name]}._" if name in EMPTY_NOTES else "_No rows._")
            continue
        out.append(format_markdown_table(name, rows))
    return "\n".join(out) + "\n"


def _csv_cell(value) -> str:
    if isinstance(value, tuple | list):
        return "; ".join(_csv_cell(v) for v in value)
    if isinstance(value, float):
        if math.isnan(value):
            return ""
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    return str(value)


def format_rows_csv(columns: Sequence[Column], rows: Sequence[Mapping], status: str = "") -> str:
    """Rows as CSV: a header of column names, full-precision numbers, NaN as an empty cell,
    ``inf`` as ``inf``; an INCOMPLETE `status` as a first line ``# INCOMPLETE: …``."""
    buf = io.StringIO()
    if status:
        buf.write(f"# {status}\n")
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow([c.name for c in columns])
    for row in rows:
        writer.writerow([_csv_cell(row[c.name]) for c in columns])
    return buf.getvalue()


def format_csv(name: str, rows: Sequence[Mapping], status: str = "") -> str:
    """One design table as CSV (see :func:`format_rows_csv`); an empty table whose emptiness
    means something (:data:`~floorslide.report.columns.EMPTY_NOTES`) says it in a line
    ``# …`` above the header (``pandas.read_csv(path, comment="#")`` skips it)."""
    text = format_rows_csv(COLUMNS[name], rows, status)
    if rows or name not in EMPTY_NOTES:
        return text
    head, sep, rest = text.partition("\n") if status else ("", "", text)
    return f"{head}{sep}# {EMPTY_NOTES[name]}\n{rest}"


def format_csv_sections(tables: DesignTables, names: Sequence[str] = TABLE_NAMES) -> str:
    """Several tables as CSV on one stream: each preceded by a line ``# table: NAME`` and
    followed by a blank line."""
    parts = [f"# table: {name}\n{format_csv(name, tables[name], tables.status)}" for name in names]
    return "\n".join(parts)


MARKDOWN_TITLE = "# Design tables: "
"""The first line of the Markdown tables begins so (:func:`format_markdown`)."""
JSON_START = '{\n "source": '
"""The JSON tables and per-record rows begin so (:func:`format_json`,
:func:`format_rows_json`)."""


def replace_rule(text: str) -> outputs.Replace:
    """Which existing file an output of `text` may replace (:mod:`floorslide.outputs`): the
    Markdown tables or JSON floorslide wrote, or a CSV with the same header (the same table,
    written before); never anything else."""
    if text.startswith(MARKDOWN_TITLE):
        return outputs.starts_with(MARKDOWN_TITLE.encode())
    if text.startswith(JSON_START):
        return outputs.starts_with(JSON_START.encode())
    return outputs.same_first_line(text)


def write_text(path: str | Path, text: str, *, inputs: Sequence[str | Path] = ()) -> Path:
    """Write `text` to `path` (folders created) through :func:`floorslide.outputs.write_output`:
    atomically, replacing only a file of the same kind floorslide wrote (:func:`replace_rule`),
    never one of `inputs`.

    Raises
    ------
    OutputExistsError
        `path` holds something else (exit code 2).
    OutputError
        It cannot be written: one line naming the path.
    """
    return outputs.write_output(
        path, text, inputs=inputs, replace=replace_rule(text), advice="choose another -o"
    )


def write_csv(
    tables: DesignTables,
    directory: str | Path,
    names: Sequence[str] = TABLE_NAMES,
    *,
    inputs: Sequence[str | Path] = (),
):
    """Write one ``NAME.csv`` per table into `directory` (created), each as
    :func:`write_text` does; returns the paths."""
    directory = Path(directory)
    return [
        write_text(
            directory / f"{name}.csv", format_csv(name, tables[name], tables.status), inputs=inputs
        )
        for name in names
    ]


def _json_value(value):
    if isinstance(value, np.generic):
        return _json_value(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _json_columns(columns: Sequence[Column]) -> list[dict]:
    return [{"name": c.name, "units": c.units, "description": c.description} for c in columns]


def to_json(tables: DesignTables, names: Sequence[str] = TABLE_NAMES) -> dict:
    """The tables as a JSON-ready dict: ``source``, ``scene``, ``status`` (``""`` or the
    INCOMPLETE label), ``complete``, ``tasks_done``, ``tasks_planned``, ``notes``, ``periods``,
    ``damping``, ``percentile``, ``min_records``, ``comparisons``, ``columns`` (name → list of
    ``{name, units, description}``) and ``tables`` (name → rows); NaN and inf become
    ``null``."""
    return {
        "source": tables.source,
        "scene": tables.scene_name,
        "status": tables.status,
        "complete": tables.complete,
        "tasks_done": tables.tasks_done,
        "tasks_planned": tables.tasks_planned,
        "notes": list(tables.notes),
        "periods": list(tables.periods),
        "damping": tables.damping,
        "percentile": PERCENTILE,
        "min_records": MIN_RECORDS,
        "comparisons": [
            {"spec": c.spec, "a": list(c.a), "b": list(c.b)} for c in tables.comparisons
        ],
        "columns": {name: _json_columns(COLUMNS[name]) for name in names},
        "tables": {
            name: [{k: _json_value(v) for k, v in row.items()} for row in tables[name]]
            for name in names
        },
    }


def format_json(tables: DesignTables, names: Sequence[str] = TABLE_NAMES) -> str:
    """:func:`to_json` as text (strict JSON: no NaN)."""
    return json.dumps(to_json(tables, names), indent=1, allow_nan=False)


def format_rows_json(
    columns: Sequence[Column], rows: Sequence[Mapping], source: str, status: str = ""
) -> str:
    """Rows (e.g. the per-record table) as strict JSON: ``{"source", "status", "complete",
    "columns", "rows"}``."""
    data = {
        "source": source,
        "status": status,
        "complete": not status,
        "columns": _json_columns(columns),
        "rows": [{c.name: _json_value(row[c.name]) for c in columns} for row in rows],
    }
    return json.dumps(data, indent=1, allow_nan=False)


def to_pandas(tables: DesignTables, name: str | None = None):
    """One design table (`name`) or all of them (dict by name) as :class:`pandas.DataFrame`.

    Columns as in :data:`~floorslide.report.columns.COLUMNS` (NaN where a statistic is
    undefined or falls on rocking records: see the ``*_outcome`` columns); ``df.attrs`` holds
    ``units``, ``notes``, ``status`` and ``source``.
    """
    import pandas as pd

    def frame(n: str):
        df = pd.DataFrame(list(tables[n]), columns=[c.name for c in COLUMNS[n]])
        df.attrs.update(
            units={c.name: c.units for c in COLUMNS[n]},
            notes=list(tables.notes),
            status=tables.status,
            source=tables.source,
        )
        return df

    if name is not None:
        if name not in COLUMNS:
            raise KeyError(f"no table {name!r}; tables: {', '.join(TABLE_NAMES)}")
        return frame(name)
    return {n: frame(n) for n in TABLE_NAMES}
