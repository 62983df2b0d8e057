"""Finding the records among files and folders given on the command line.

:func:`discover` turns paths into a list of :class:`RecordSource` (a record file, or one row
of a catalog) and a list of problems, so that a batch reports every bad path and still reads
the others (docs/design.md §9):

- a **file** is a record, or a catalog if it is a CSV with the columns ``file, dt, units``
  (then each of its rows is a source) or ``file_h1, file_h2 ..., dt, units`` (a catalog of
  components: each component file of each row is a source);
- a **directory** is searched recursively (hidden files and folders skipped): its catalogs
  give their rows, and every other file is a record — except files a catalog lists (read once,
  through the catalog, with its metadata) and documentation or other non-record files
  (``*.md``, ``*.rst``, ``*.pdf``, images, ``*.py``, ``*.json``, ``*.toml``/``*.yaml``,
  ``README*``, ``LICENSE*`` ...). A directory with no record in it is a problem;
- a file named on its own that is documentation (``*.md``, ``README``, ``PROVENANCE`` ...:
  what a shell glob such as ``records/*`` brings along) is skipped, but another non-record
  file (a scene ``*.toml``, a result ``*.h5``, ``*.json``, ``*.py`` ...) is a problem, with a
  hint at what it is; and when nothing but documentation was named, that is a problem too —
  a command that inspects nothing never succeeds silently;
- a path that does not exist is a problem; a file listed twice is read once.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from obspy import Stream

from floorslide.errors import RecordError
from floorslide.records.catalog import CatalogEntry, is_catalog, load_catalog
from floorslide.records.read import read_record

DOCUMENTATION = frozenset(
    {
        ".md",
        ".rst",
        ".pdf",
        ".html",
        ".htm",
        ".png",
        ".jpg",
        ".jpeg",
        ".gif",
        ".svg",
        ".doc",
        ".docx",
        ".log",
    }
)
"""File suffixes (lower case) of documentation: skipped in folders and when named."""

NOT_RECORDS = DOCUMENTATION | frozenset(
    {
        ".py",
        ".pyc",
        ".ipynb",
        ".json",
        ".toml",
        ".yaml",
        ".yml",
        ".cfg",
        ".ini",
        ".h5",
        ".hdf5",
        ".xls",
        ".xlsx",
        ".zip",
        ".gz",
        ".tar",
    }
)
"""File suffixes (lower case) that are never records: skipped in folders, a problem when
named (unless documentation)."""

HINTS = {
    ".toml": "a scene file? run it with floorslide run",
    ".h5": "a result file? read it with floorslide table or floorslide plot",
    ".hdf5": "a result file? read it with floorslide table or floorslide plot",
}
"""What a non-record file named on the command line probably is."""

NOT_RECORD_NAMES = ("readme", "license", "licence", "provenance", "changelog", "copying")
"""File name stems (lower case, prefix match) that are documentation, not records."""


@dataclass(frozen=True)
class RecordSource:
    """Something to read one record from: a file, or a catalog row.

    Attributes
    ----------
    path
        The record file.
    entry
        The catalog row, if the record comes from a catalog.
    """

    path: Path
    entry: CatalogEntry | None = None

    @property
    def label(self) -> str:
        """The record as shown to the user (its path)."""
        return str(self.path)

    def read(
        self,
        format: str | None = None,
        units: str | None = None,
        dt: float | None = None,
        component: str | None = None,
    ) -> Stream:
        """Read it: a catalog row with its own columns (the options are not used), a file with
        :func:`~floorslide.records.read.read_record` and the options."""
        if self.entry is not None:
            return self.entry.read()
        return read_record(self.path, format=format, units=units, dt=dt, component=component)


def is_documentation(path: Path) -> bool:
    """True for files that are never records (documentation, images, code, archives ...)."""
    name = path.name.lower()
    return path.suffix.lower() in NOT_RECORDS or name.startswith(NOT_RECORD_NAMES)


def _is_prose(path: Path) -> bool:
    """Documentation proper (skipped even when named: shell globs bring it along)."""
    return path.suffix.lower() in DOCUMENTATION or path.name.lower().startswith(NOT_RECORD_NAMES)


def _not_a_record(path: Path) -> RecordError:
    suffix = path.suffix.lower()
    hint = HINTS.get(suffix, "give record files, catalogs or folders")
    return RecordError(f"not a record ({suffix[1:]} file); {hint}", where=str(path))


def _walk(folder: Path) -> list[Path]:
    files = []
    for root, dirs, names in os.walk(folder):
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))
        files.extend(Path(root) / n for n in sorted(names) if not n.startswith("."))
    return files


def discover(paths: Iterable[str | os.PathLike]) -> tuple[list[RecordSource], list[RecordError]]:
    """Records to read from files, catalogs and directories (see the module notes).

    Parameters
    ----------
    paths
        Files and directories, in the order given.

    Returns
    -------
    sources : list of RecordSource
        In the order of the arguments (directories sorted by path), each record once.
    problems : list of RecordError
        Paths that do not exist, directories without records, malformed catalogs.
    """
    problems: list[RecordError] = []
    groups: list[tuple[list[Path], list[CatalogEntry]]] = []
    listed: set[Path] = set()
    skipped: list[Path] = []
    for given in paths:
        path = Path(given)
        if not path.exists():
            problems.append(RecordError("no such file or directory", where=str(path)))
            continue
        if path.is_dir():
            files = [f for f in _walk(path) if not is_documentation(f)]
        elif _is_prose(path):
            skipped.append(path)
            continue
        elif is_documentation(path):
            problems.append(_not_a_record(path))
            continue
        else:
            files = [path]
        catalogs = [f for f in files if f.suffix.lower() == ".csv" and is_catalog(f)]
        entries: list[CatalogEntry] = []
        for catalog in catalogs:
            try:
                rows = load_catalog(catalog, components=True)
            except RecordError as exc:
                problems.append(exc)
                continue
            entries.extend(rows)
            listed.update(entry.path.resolve() for entry in rows)
        plain = [f for f in files if f not in catalogs]
        if path.is_dir() and not plain and not entries:
            problems.append(RecordError("no records found in this directory", where=str(path)))
        groups.append((plain, entries))

    sources: list[RecordSource] = []
    seen: set[Path] = set()
    seen_rows: set[tuple[Path, int, str]] = set()
    if skipped and not groups and not problems:
        names = ", ".join(str(p) for p in skipped)
        problems.append(RecordError(f"no record to read: {names} (documentation, skipped)"))
    for plain, entries in groups:
        for entry in entries:
            row = (entry.catalog.resolve(), entry.line, entry.column)
            if row not in seen_rows:
                seen_rows.add(row)
                sources.append(RecordSource(entry.path, entry))
        for file in plain:
            resolved = file.resolve()
            if resolved in listed or resolved in seen:
                continue
            seen.add(resolved)
            sources.append(RecordSource(file))
    return sources, problems
