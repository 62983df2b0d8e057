"""Record catalogs (flatfiles): a CSV with one row per record.

A catalog has at least the columns ``file``, ``dt`` and ``units``; every other column (event,
station, magnitude, distance, set, ...) is metadata, kept with the record. For example the
bundled ``data/records/slammer/index.csv``::

    file,set,event,magnitude,station,station_id,...,dt,npts,units,pga_g
    ImperialValley_1979_EMO-270.txt,pulse-like,Imperial Valley 1979,6.5,Meloland Overpass,...

Rules:

- ``file`` is relative to the catalog's folder and stays inside it (``../x`` is refused), or
  an absolute path, used as is;
- ``dt`` (s) and ``units`` may be left empty for a self-describing format (AT2, COSMOS, text
  with a header), and must agree with the file when both are given;
- optional columns ``format`` and ``component`` are passed to
  :func:`~floorslide.records.read.read_record`;
- column names are matched case-insensitively, values are kept as the strings of the CSV
  (standard CSV quoting, so ``"Saratoga, Aloha Ave."`` is one field); rows starting with ``#``
  are comments;
- every column of the row is kept in ``trace.stats.catalog`` (strings), the catalog and line in
  ``trace.stats.catalog_file`` / ``trace.stats.catalog_line``, and the ``event``, ``station``
  and ``component`` columns fill ``stats.record.event`` / ``.station`` / ``.component`` where
  the file itself does not name them.

:func:`read_catalog` reads the records; :func:`load_catalog` returns the rows as
:class:`CatalogEntry` objects without reading them (for progress bars, dry runs, or reading
one at a time). The same rows serve as *sidecar* for :func:`~floorslide.records.read.read_record`
when it reads a bare text file listed in an ``index.csv`` next to it.

**Catalogs of components** (a row per station with ``file_h1``, ``file_h2`` — and any
``file_<name>`` — instead of ``file``, as PEER pair flatfiles are) are recognised:
:func:`load_catalog` with ``components=True`` (what ``floorslide inspect`` uses) gives one entry
per component file, whose row has the component's own columns under their plain names
(``file_h1`` → ``file``, ``npts_h1`` → ``npts``, ``comp_h1`` → ``comp``). Elsewhere (scenes,
:func:`read_catalog`) such a catalog is refused with an error that says so: treating the
components of a record as separate records is a choice a study must make explicitly.
"""

from __future__ import annotations

import csv
import os
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal, overload

import numpy as np
from obspy import Stream, Trace
from obspy.core import AttribDict

from floorslide.errors import RecordError, UnitsError
from floorslide.records.units import canonical_units
from floorslide.text_numbers import UNDERSCORE_HINT, parse_count, parse_number

REQUIRED_COLUMNS = ("file", "dt", "units")

COMPONENT_FILE = re.compile(r"^file_([a-z0-9]+)$")
"""A ``file_<component>`` column of a catalog of components (``file_h1``, ``file_h2``, ...)."""


def component_columns(columns: Iterable[str]) -> list[str]:
    """The ``file_<component>`` columns of a catalog header (lower-case names)."""
    return [c for c in columns if COMPONENT_FILE.match(c)]


def _hint(exc: ValueError) -> str:
    return f" ({UNDERSCORE_HINT})" if str(exc) == UNDERSCORE_HINT else ""


@dataclass(frozen=True, eq=False)
class CatalogEntry:
    """One row of a record catalog.

    Attributes
    ----------
    catalog
        The catalog file.
    line
        1-based line of the row in the catalog.
    path
        The record file (resolved against the catalog's folder).
    row
        All columns of the row, as strings, keyed by lower-case column name (for a catalog of
        components: with the component's own columns under their plain names).
    column
        The column that names the file: ``file``, or ``file_h1``, ``file_h2`` ... in a catalog
        of components.
    """

    catalog: Path
    line: int
    path: Path
    row: dict[str, str] = field(default_factory=dict)
    column: str = "file"

    @property
    def where(self) -> str:
        """``catalog:line`` (and the file column, in a catalog of components) for messages."""
        extra = f" ({self.column})" if self.column != "file" else ""
        return f"{self.catalog}:{self.line}{extra}"

    @property
    def dt(self) -> float | None:
        """Time step in s from the ``dt`` column (None if empty)."""
        text = self.row.get("dt", "").strip()
        if not text:
            return None
        try:
            value = parse_number(text)
        except ValueError as exc:
            raise RecordError(
                f"dt {text!r} is not a number of seconds{_hint(exc)}", self.where
            ) from None
        if not np.isfinite(value) or value <= 0:
            raise RecordError(f"dt {text}: the time step must be > 0 s", self.where)
        return value

    @property
    def units(self) -> str | None:
        """Canonical units from the ``units`` column (None if empty)."""
        text = self.row.get("units", "").strip()
        if not text:
            return None
        try:
            return canonical_units(text)
        except UnitsError as exc:
            raise UnitsError(exc.message, self.where) from None

    @property
    def format(self) -> str | None:
        """The ``format`` column, if present and not empty."""
        return self.row.get("format", "").strip() or None

    @property
    def component(self) -> str | None:
        """The ``component`` column, if present and not empty."""
        return self.row.get("component", "").strip() or None

    def read(self) -> Stream:
        """Read the record of this row (with its metadata attached).

        Raises
        ------
        RecordError
            Naming the record file, with the catalog line appended.
        """
        from floorslide.records.read import _read_record

        try:
            stream = _read_record(
                self.path, self.format, self.units, self.dt, self.component, sidecar=False
            )
        except RecordError as exc:
            raise type(exc)(
                f"{exc.message} (listed in {self.catalog.name} line {self.line})",
                where=exc.where or str(self.path),
            ) from None
        for trace in stream:
            self.check_npts(trace)
            self.attach(trace)
        return stream

    def check_npts(self, trace: Trace) -> None:
        """Refuse a record whose sample count differs from the row's ``npts`` column (when the
        catalog has one): a truncated file must never read as a shorter record."""
        text = self.row.get("npts", "").strip()
        if not text:
            return
        try:
            expected = parse_count(text)
        except ValueError as exc:
            raise RecordError(
                f"npts {text!r} is not a whole number{_hint(exc)}", self.where
            ) from None
        if trace.stats.npts != expected:
            raise RecordError(
                f"holds {trace.stats.npts} samples but {self.catalog.name} line {self.line} says "
                f"npts={expected} (truncated or not the catalogued file)",
                where=str(self.path),
            )

    def attach(self, trace: Trace) -> None:
        """Keep this row's columns in ``trace.stats`` (see the module notes)."""
        stats = trace.stats
        stats.catalog = AttribDict(dict(self.row))
        stats.catalog_file = str(self.catalog)
        stats.catalog_line = self.line
        record = stats.setdefault("record", AttribDict())
        for key in ("event", "station", "component"):
            value = self.row.get(key, "").strip()
            if value and not record.get(key):
                record[key] = value


@dataclass(frozen=True)
class RecordFailure:
    """A catalog row whose record could not be read (``errors="collect"``).

    Attributes
    ----------
    entry
        The catalog row.
    error
        What went wrong; ``str(error)`` is the one-line message naming the file.
    """

    entry: CatalogEntry
    error: RecordError

    @property
    def path(self) -> Path:
        """The record file of the failed row."""
        return self.entry.path

    def __str__(self) -> str:
        return str(self.error)


def _header(path: Path) -> list[str] | None:
    """The lower-cased column names of a CSV file's first line, or None if unreadable."""
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            first = fh.readline(65536)
    except (OSError, UnicodeDecodeError):
        return None
    if not first.strip():
        return None
    try:
        cells = next(csv.reader([first], skipinitialspace=True))
    except csv.Error:
        return None
    return [c.strip().lower() for c in cells]


def is_catalog(path: str | os.PathLike) -> bool:
    """True if ``path`` is a CSV whose header has the columns ``file``, ``dt`` and ``units`` —
    or ``dt``, ``units`` and ``file_<component>`` columns (a catalog of components).

    Cheap (reads the first line) and never raises.
    """
    path = Path(path)
    if not path.is_file():
        return False
    columns = _header(path)
    if columns is None or "dt" not in columns or "units" not in columns:
        return False
    return "file" in columns or bool(component_columns(columns))


def _matches(row: Mapping[str, str], where: Mapping[str, object]) -> bool:
    for key, wanted in where.items():
        value = row.get(key, "").strip()
        if isinstance(wanted, str) or not isinstance(wanted, Iterable):
            if value != str(wanted).strip():
                return False
        elif value not in {str(w).strip() for w in wanted}:
            return False
    return True


def load_catalog(
    path: str | os.PathLike,
    where: Mapping[str, object] | None = None,
    *,
    components: bool = False,
) -> list[CatalogEntry]:
    """The rows of a record catalog, filtered, without reading the records.

    Parameters
    ----------
    path
        The catalog CSV file.
    where
        Filter on columns: ``{"set": "pulse-like"}`` keeps the rows whose ``set`` is
        ``pulse-like``; a list value keeps any of its values (``{"station_id": ["EMO-270",
        "EDA-270"]}``). Values are compared as strings (``6.5`` matches ``"6.5"``, not
        ``"6.50"``); several keys must all match.
    components
        Accept a catalog of components (``file_h1``, ``file_h2`` ... instead of ``file``):
        one entry per non-empty component file of each row (see the module notes). Without
        it, such a catalog is an error.

    Returns
    -------
    list of CatalogEntry
        In the order of the file (components in the order of their columns).

    Raises
    ------
    RecordError
        If the catalog is missing, unreadable, lacks a required column, has a malformed row
        (wrong number of fields, empty ``file``), ``where`` names a column it does not have,
        or it is a catalog of components and ``components`` is false.
    """
    path = Path(path)
    where_str = str(path)
    if not path.exists():
        raise RecordError("no such catalog file", where=where_str)
    if path.is_dir():
        raise RecordError("is a directory, not a catalog CSV file", where=where_str)
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            rows = list(_rows(fh, path, components))
    except UnicodeDecodeError:
        raise RecordError("not a text CSV file", where=where_str) from None
    except OSError as exc:
        raise RecordError(f"cannot read catalog: {exc.strerror or exc}", where_str) from None
    except csv.Error as exc:
        raise RecordError(f"malformed CSV: {exc}", where=where_str) from None
    if not rows:
        raise RecordError("empty catalog (no header line)", where=where_str)
    columns = rows[0][1]
    if where:
        unknown = [key for key in where if key.lower() not in columns]
        if unknown:
            raise RecordError(
                f"where: no column {unknown[0]!r} in the catalog (columns: {', '.join(columns)})",
                where=where_str,
            )
        where = {key.lower(): value for key, value in where.items()}
    entries = []
    seen: dict[tuple[Path, str], CatalogEntry] = {}
    for line, cells in rows[1:]:
        if len(cells) != len(columns):
            raise RecordError(
                f"{len(cells)} fields where the header has {len(columns)}",
                where=f"{path}:{line}",
            )
        row = dict(zip(columns, (c.strip() for c in cells), strict=True))
        if "file" in row:
            if not row["file"]:
                raise RecordError("empty 'file' column", where=f"{path}:{line}")
            found = [CatalogEntry(path, line, _record_path(path, row["file"], line, "file"), row)]
        else:
            named = [c for c in component_columns(columns) if row[c]]
            if not named:
                raise RecordError(
                    f"empty {', '.join(map(repr, component_columns(columns)))} columns",
                    where=f"{path}:{line}",
                )
            found = []
            for column in named:
                own = _component_row(row, column)
                record = _record_path(path, own["file"], line, column)
                found.append(CatalogEntry(path, line, record, own, column))
        for entry in found:
            _check_duplicate(entry, seen)
        if where and not _matches(row, where):
            continue
        entries.extend(found)
    return entries


def _record_path(catalog: Path, text: str, line: int, column: str) -> Path:
    """The record file a catalog row names: a relative path under the catalog's folder, or an
    absolute path, used as given (a user's own catalog may point anywhere, in plain sight).

    A relative path that leaves the catalog's folder (``../../etc/passwd``) is refused: a
    catalog handed on with its records must not reach files outside them, and reading an
    arbitrary file as a record would quote its text in the errors and the result file.
    """
    path = Path(text)
    if path.is_absolute():
        return path
    parts = Path(os.path.normpath(text)).parts
    if parts and parts[0] == os.pardir:
        raise RecordError(
            f"{column} {text[:80]!r} leaves the catalog's folder; a relative path is read "
            "inside it: move the catalog up to a folder that holds its records, or give an "
            "absolute path",
            where=f"{catalog}:{line}",
        )
    return catalog.parent / path


def _check_duplicate(entry: CatalogEntry, seen: dict[tuple[Path, str], CatalogEntry]) -> None:
    """Refuse a second row (or component column) for the same file and component: it would be
    read, and counted in every statistic, twice (docs/design.md §9)."""
    key = (entry.path.resolve(), (entry.component or "").upper())
    first = seen.setdefault(key, entry)
    if first is entry:
        return
    what = repr(entry.row.get("file", entry.path.name))
    if entry.component:
        what += f" (component {entry.component})"
    places = (
        f"lines {first.line} and {entry.line} both list"
        if first.line != entry.line
        else f"line {entry.line} lists {what} twice ({first.column}, {entry.column}):"
    )
    if first.line != entry.line:
        places += f" {what}:"
    raise RecordError(
        f"{places} a record must be listed once (a multi-component file needs a component "
        "column to list each component)",
        where=str(entry.catalog),
    )


def _component_row(row: dict[str, str], column: str) -> dict[str, str]:
    """The row of one component: its ``<name>_<component>`` columns also under ``<name>``."""
    suffix = "_" + column[len("file_") :]
    own = dict(row)
    for key, value in row.items():
        if key.endswith(suffix) and len(key) > len(suffix):
            own[key[: -len(suffix)]] = value
    return own


def _rows(fh, path: Path, components: bool = False):
    """(line, cells) of the header and the data rows; checks the required columns."""
    reader = csv.reader(fh, skipinitialspace=True)
    header_seen = False
    for cells in reader:
        if not cells or not "".join(cells).strip() or cells[0].lstrip().startswith("#"):
            continue
        if not header_seen:
            columns = [c.strip().lower() for c in cells]
            missing = [c for c in REQUIRED_COLUMNS if c not in columns]
            per_component = component_columns(columns)
            if missing == ["file"] and per_component and not components:
                raise RecordError(
                    f"a catalog of components ({', '.join(per_component)} on each row): read "
                    "here, each row must be one record with a 'file' column (floorslide "
                    "inspect reads every component)",
                    where=str(path),
                )
            if missing == ["file"] and per_component:
                missing = []
            if missing:
                found = ", ".join(c for c in columns if c)[:80] or "none"  # not a whole line
                raise RecordError(
                    f"not a record catalog: no column {', '.join(map(repr, missing))}; a "
                    f"catalog needs the columns {', '.join(REQUIRED_COLUMNS)} (or "
                    f"file_h1, file_h2 ..., dt, units); line {reader.line_num} has: {found}",
                    where=str(path),
                )
            duplicated = sorted({c for c in columns if columns.count(c) > 1})
            if duplicated:
                raise RecordError(f"duplicated column {duplicated[0]!r}", where=str(path))
            header_seen = True
            yield reader.line_num, columns
            continue
        yield reader.line_num, cells


def find_entry(catalog: str | os.PathLike, record: str | os.PathLike) -> CatalogEntry | None:
    """The row of ``catalog`` that lists the file ``record``, or None (never raises for a
    catalog that is not one: a sidecar is optional)."""
    target = Path(record).resolve()
    try:
        entries = load_catalog(catalog)
    except RecordError:
        return None
    for entry in entries:
        if entry.path.resolve() == target:
            return entry
    return None


@overload
def read_catalog(
    path: str | os.PathLike,
    where: Mapping[str, object] | None = None,
    errors: Literal["raise"] = "raise",
) -> list[Trace]: ...


@overload
def read_catalog(
    path: str | os.PathLike,
    where: Mapping[str, object] | None = None,
    *,
    errors: Literal["collect"],
) -> tuple[list[Trace], list[RecordFailure]]: ...


def read_catalog(
    path: str | os.PathLike,
    where: Mapping[str, object] | None = None,
    errors: Literal["raise", "collect"] = "raise",
) -> list[Trace] | tuple[list[Trace], list[RecordFailure]]:
    """Read the records a catalog lists.

    Parameters
    ----------
    path
        The catalog CSV (see the module notes for its columns).
    where
        Filter on catalog columns, e.g. ``{"set": "pulse-like"}`` (see :func:`load_catalog`).
    errors
        ``"raise"`` (default): the first unreadable record raises its RecordError.
        ``"collect"``: unreadable records are skipped and returned as :class:`RecordFailure`
        objects, so that a batch keeps going (docs/design.md §9).

    Returns
    -------
    list of obspy.Trace
        With ``errors="raise"``: the traces, in catalog order (a multi-trace file without a
        ``component`` column gives all its traces), data in m/s² as from
        :func:`~floorslide.records.read.read_record`, and the row in ``stats.catalog``.
    tuple of (list of obspy.Trace, list of RecordFailure)
        With ``errors="collect"``.

    Raises
    ------
    RecordError
        For a malformed catalog (always), or an unreadable record (``errors="raise"``).

    Examples
    --------
    >>> traces = read_catalog("data/records/slammer/index.csv", where={"set": "pulse-like"})
    >>> len(traces), traces[0].stats.catalog.event
    (18, 'Imperial Valley 1979')
    >>> traces, failures = read_catalog("data/records/slammer/index.csv", errors="collect")
    >>> len(traces), failures
    (36, [])
    """
    if errors not in ("raise", "collect"):
        raise ValueError(f"errors must be 'raise' or 'collect', not {errors!r}")
    traces: list[Trace] = []
    failures: list[RecordFailure] = []
    for entry in load_catalog(path, where):
        try:
            traces.extend(entry.read())
        except RecordError as exc:
            if errors == "raise":
                raise
            failures.append(RecordFailure(entry, exc))
    return (traces, failures) if errors == "collect" else traces
