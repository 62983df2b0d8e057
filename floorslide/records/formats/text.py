"""Plain-text accelerograms, as an ObsPy waveform plugin (format ``"FSTEXT"``).

Accepted layouts:

- **one column** — acceleration samples, one per line; the time step comes from the caller
  (``dt=``), from a header line ``# dt: 0.01``, or from a sidecar catalog ``index.csv`` in the
  same folder (see :func:`floorslide.read_record`);
- **two columns** — time (s) and acceleration; dt is taken from the time column, which must be
  uniform (each time within 1 % of a step of ``t0 + k·dt``) and increasing, else an error says
  where it is not.

Columns are separated by whitespace and/or commas. Lines starting with ``#``, ``%`` or ``!`` are
comments; blank lines are skipped; a first non-comment line made only of names (``time,acc``)
is taken as column names. Comment lines *before the data* of the form ``# key: value`` or
``# key = value`` make the file self-describing::

    # event: Imperial Valley 1940
    # station: El Centro Array #9
    # component: 180
    # dt: 0.01          (also: delta, time_step, sampling_rate / fs in Hz)
    # units: g          (any spelling floorslide.records.units knows)
    0.0063
    0.0036
    ...

Keys are case-insensitive (spaces and hyphens read as ``_``); ``dt``/``units``/``npts`` are
used and checked, every other key is kept in ``stats.fstext.header`` and ``station``,
``network``, ``channel``, ``location`` also fill the usual ObsPy fields.

Errors (:class:`~floorslide.errors.RecordError`) name the line and column: a non-numeric value,
a row with a different number of columns, a non-uniform or decreasing time column, NaN/inf
samples, dt ≤ 0, unknown units, an empty or binary file.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from itertools import chain
from typing import IO

import numpy as np
from obspy import Stream, Trace, UTCDateTime
from obspy.core import AttribDict, Stats

from floorslide.errors import RecordError, UnitsError
from floorslide.records.formats._text import HEAD_BYTES, read_head, read_text
from floorslide.records.units import canonical_units

FORMAT = "FSTEXT"

COMMENT_CHARS = ("#", "%", "!")
_KEY_VALUE = re.compile(r"^\s*[#%!]+\s*([A-Za-z][\w \-]{0,40}?)\s*[:=]\s*(.*?)\s*$")
_NAME = re.compile(r"^[A-Za-z_][\w()\[\]/*.^\-]*$")
_DT_KEYS = ("dt", "delta", "time_step", "timestep", "sample_interval", "sampling_interval")
_RATE_KEYS = ("sampling_rate", "fs", "sample_rate", "sps")
_LEADING_NUMBER = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([A-Za-z]*)")
_TIME_TOLERANCE = 0.01  # fraction of a step a time value may be off the uniform grid
_NONBLANK = re.compile(r"^[ \t]*\S", re.MULTILINE)
_ROWS = {
    1: re.compile(r"^[ \t]*\S+[ \t]*$", re.MULTILINE),
    2: re.compile(r"^[ \t]*\S+[ \t]+\S+[ \t]*$", re.MULTILINE),
}


@dataclass
class TextRecord:
    """A parsed text record before it becomes a Trace.

    Attributes
    ----------
    data
        Acceleration samples as in the file.
    dt
        Time step in s, from the time column or the header; None if neither gives one.
    units
        Canonical units from the header, or None.
    header
        All ``key: value`` header entries (normalised keys, string values).
    columns
        1 (acceleration) or 2 (time, acceleration).
    t0
        First time of a two-column file (s), else 0.
    names
        Column names if the file has a names line.
    """

    data: np.ndarray
    dt: float | None
    units: str | None
    header: dict[str, str] = field(default_factory=dict)
    columns: int = 1
    t0: float = 0.0
    names: list[str] = field(default_factory=list)


def _is_float(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


def _tokens(line: str) -> list[str]:
    return line.replace(",", " ").split()


def _is_text(filename: str | os.PathLike | IO[bytes]) -> bool:
    """True if the file is plain numeric text with one or two columns (cheap; never raises).

    Looks at the first kilobytes only: comment and blank lines, at most one line of column
    names, then lines of one or two numbers — and at least one such line.
    """
    head = read_head(filename)
    if head is None:
        return False
    lines = head.splitlines()
    if len(head) >= HEAD_BYTES and len(lines) > 1:
        lines = lines[:-1]  # the last line may be cut
    data_lines = 0
    for line in lines[:200]:
        stripped = line.strip()
        if not stripped or stripped.startswith(COMMENT_CHARS):
            continue
        tokens = _tokens(stripped)
        numeric = [_is_float(t) for t in tokens]
        if all(numeric) and len(tokens) in (1, 2):
            data_lines += 1
            continue
        if data_lines == 0 and not any(numeric) and all(_NAME.match(t) for t in tokens):
            continue  # a line of column names
        return False
    return data_lines > 0


def _norm_key(key: str) -> str:
    return re.sub(r"[\s\-]+", "_", key.strip().lower())


def _header_dt(header: dict[str, str], where: str) -> float | None:
    """dt in s from ``dt``/``delta``/... or ``sampling_rate``/``fs`` (Hz) header entries."""
    for keys, rate in ((_DT_KEYS, False), (_RATE_KEYS, True)):
        for key in keys:
            if key not in header:
                continue
            match = _LEADING_NUMBER.match(header[key])
            unit = match.group(2).lower() if match else ""
            if match is None or unit not in (("", "hz") if rate else ("", "s", "sec")):
                raise RecordError(
                    f"header {key}: {header[key]!r} is not a number"
                    + (" in Hz" if rate else " of seconds"),
                    where=where,
                )
            value = float(match.group(1))
            if not np.isfinite(value) or value <= 0:
                raise RecordError(f"header {key}: {value:g} must be > 0", where=where)
            return 1.0 / value if rate else value
    return None


def _table(lines: list[str], start: int, where: str) -> tuple[np.ndarray, Callable[[int], int]]:
    """The numbers of the data lines (from ``lines[start]`` on) as a (rows, columns) array, and a
    function giving the 1-based file line of a row (for messages).

    Fast path, without a Python loop over lines: when the data hold no comment lines, regular
    expressions check that every non-blank line has the same number (1 or 2) of fields, and one
    ``split`` converts them all. Anything unusual (comments between data lines, a bad value, a
    ragged row, NaN) takes the line-by-line path, which says exactly where the problem is.
    """
    body = "\n".join(lines[start:])
    first = _tokens(lines[start]) if start < len(lines) else []
    if len(first) in (1, 2) and not any(c in body for c in COMMENT_CHARS):
        flat = body.replace(",", " ")
        rows = len(_NONBLANK.findall(flat))
        if len(_ROWS[len(first)].findall(flat)) == rows:
            try:
                values = np.array(flat.split(), dtype=np.float64)
            except ValueError:
                values = None
            if values is not None and np.isfinite(values).all():
                numbers: list[int] = []

                def line_of(row: int) -> int:
                    if not numbers:
                        numbers.extend(
                            i for i, line in enumerate(lines[start:], start + 1) if line.strip()
                        )
                    return numbers[row]

                return values.reshape(-1, len(first)), line_of
    return _table_by_lines(lines, start, where)


def _table_by_lines(
    lines: list[str], start: int, where: str
) -> tuple[np.ndarray, Callable[[int], int]]:
    """:func:`_table`, line by line, with the line and column of every problem."""
    rows = [
        (i, line)
        for i, line in enumerate(lines[start:], start + 1)
        if line.strip() and not line.lstrip().startswith(COMMENT_CHARS)
    ]
    if not rows:
        raise RecordError("no data lines (only comments or blank lines)", where=where)
    split = [_tokens(line) for _, line in rows]
    counts = np.fromiter(map(len, split), dtype=np.int64, count=len(split))
    ncols = int(counts[0])
    if ncols not in (1, 2):
        raise RecordError(
            f"line {rows[0][0]}: {ncols} columns; expected 1 (acceleration) or "
            "2 (time, acceleration)",
            where=where,
        )
    odd = np.flatnonzero(counts != ncols)
    if odd.size:
        line_no = rows[int(odd[0])][0]
        raise RecordError(
            f"line {line_no}: {int(counts[odd[0]])} columns where the data above have {ncols}",
            where=where,
        )
    try:
        values = np.array(list(chain.from_iterable(split)), dtype=np.float64)
    except ValueError:
        for (line_no, line), tokens in zip(rows, split, strict=True):
            for token in tokens:
                if not _is_float(token):
                    column = line.find(token) + 1
                    raise RecordError(
                        f"line {line_no}, column {column}: {token[:40]!r} is not a number",
                        where=where,
                    ) from None
        raise  # pragma: no cover - every ValueError has a bad token
    table = values.reshape(-1, ncols)
    bad = ~np.isfinite(table)
    if bad.any():
        row, col = np.argwhere(bad)[0]
        kind = "NaN" if np.isnan(table[row, col]) else "infinite"
        raise RecordError(
            f"line {rows[row][0]}: {kind} value in column {col + 1}; "
            "a record must hold finite numbers",
            where=where,
        )
    return table, lambda row: rows[row][0]


def parse_text_record(filename: str | os.PathLike) -> TextRecord:
    """Parse a text accelerogram; dt and units may come back None if the file does not say.

    Parameters
    ----------
    filename
        Path of the text file.

    Returns
    -------
    TextRecord

    Raises
    ------
    RecordError
        For a malformed file (see the module docstring).
    """
    where = str(filename)
    lines = read_text(filename).splitlines()
    header: dict[str, str] = {}
    names: list[str] = []
    start = len(lines)
    for i, line in enumerate(lines):
        stripped = line.strip()
        if not stripped:
            continue
        if stripped.startswith(COMMENT_CHARS):
            match = _KEY_VALUE.match(stripped)
            if match:
                header[_norm_key(match.group(1))] = match.group(2)
            continue
        tokens = _tokens(stripped)
        if not names and not any(_is_float(t) for t in tokens):
            if all(_NAME.match(t) for t in tokens):
                names = tokens
                continue
        start = i
        break
    table, line_of = _table(lines, start, where)
    ncols = table.shape[1]
    dt = _header_dt(header, where)
    t0 = 0.0
    if ncols == 2:
        dt, t0 = _time_column(table[:, 0], line_of, dt, where)
    units = None
    if header.get("units") or header.get("unit"):
        raw = header.get("units") or header.get("unit") or ""
        units = canonical_units_in_header(raw, where)
    data = np.ascontiguousarray(table[:, -1])
    if "npts" in header:
        try:
            npts = int(header["npts"])
        except ValueError:
            raise RecordError(
                f"header npts: {header['npts']!r} is not an integer", where=where
            ) from None
        if npts != data.size:
            raise RecordError(
                f"the header says npts={npts} but the file holds {data.size} samples"
                + (" (truncated)" if data.size < npts else ""),
                where=where,
            )
    return TextRecord(data, dt, units, header, ncols, t0, names)


def canonical_units_in_header(raw: str, where: str) -> str:
    """Canonical units of a header entry, with the file named in the error."""
    try:
        return canonical_units(raw)
    except UnitsError as exc:
        raise UnitsError(f"header units: {exc.message}", where=where) from None


def _time_column(
    times: np.ndarray, line_of: Callable[[int], int], header_dt: float | None, where: str
) -> tuple[float, float]:
    """dt and t0 of a uniform, increasing time column (RecordError otherwise)."""
    n = times.size
    if n < 2:
        raise RecordError("a two-column record needs at least two rows to give dt", where=where)
    steps = np.diff(times)
    if (steps <= 0).any():
        k = int(np.argmax(steps <= 0)) + 1
        raise RecordError(
            f"line {line_of(k)}: time {times[k]:g} s does not increase "
            f"(previous {times[k - 1]:g} s)",
            where=where,
        )
    dt = (times[-1] - times[0]) / (n - 1)
    off = np.abs(times - (times[0] + dt * np.arange(n)))
    if off.max() > _TIME_TOLERANCE * dt:
        k = int(np.argmax(off > _TIME_TOLERANCE * dt))
        raise RecordError(
            f"line {line_of(k)}: time {times[k]:g} s is {off[k]:.3g} s off the uniform grid "
            f"t0 + k*dt (dt = {dt:.6g} s); floorslide needs uniformly sampled records - "
            "resample first",
            where=where,
        )
    if header_dt is not None and abs(header_dt - dt) > 1e-4 * dt:
        raise RecordError(
            f"the header says dt = {header_dt:g} s but the time column gives {dt:.6g} s",
            where=where,
        )
    return float(dt), float(times[0])


def record_to_stream(
    record: TextRecord, where: str, dt: float | None = None, headonly: bool = False
) -> Stream:
    """A Stream of one Trace from a parsed text record (``dt`` must be known by now)."""
    step = dt if dt is not None else record.dt
    if step is None:
        raise RecordError(
            "single-column text record without a time step: give dt "
            "(read_record(..., dt=0.01) or --dt 0.01), add a '# dt: 0.01' header line, "
            "or list the file in an index.csv catalog next to it",
            where=where,
        )
    stats = Stats()
    stats.delta = step
    stats.npts = record.data.size
    for key in ("network", "station", "location", "channel"):
        if key in record.header:
            stats[key] = record.header[key]
    start = UTCDateTime(0)
    if "starttime" in record.header:
        try:
            start = UTCDateTime(record.header["starttime"])
        except (ValueError, TypeError):
            raise RecordError(
                f"header starttime: {record.header['starttime']!r} is not a date-time",
                where=where,
            ) from None
    stats.starttime = start + record.t0
    if record.units:
        stats.units = record.units
    meta = AttribDict()
    meta.header = dict(record.header)
    meta.columns = record.columns
    meta.t0 = record.t0
    meta.names = list(record.names)
    stats.fstext = meta
    if headonly:
        return Stream([Trace(header=stats)])
    return Stream([Trace(data=record.data, header=stats)])


def check_dt(given: float | None, found: float | None, source: str, where: str) -> float | None:
    """The time step, checking that a value given by the caller agrees with the file."""
    if given is None:
        return found
    if not np.isfinite(given) or given <= 0:
        raise RecordError(f"dt = {given!r}: the time step must be > 0 s", where=where)
    if found is not None and abs(given - found) > 1e-4 * found:
        raise RecordError(
            f"dt = {given:g} s was given but {source} says {found:.6g} s", where=where
        )
    return float(given)


def _read_text(
    filename: str | os.PathLike,
    headonly: bool = False,
    dt: float | None = None,
    **kwargs: object,
) -> Stream:
    """Read a plain-text accelerogram into an ObsPy Stream of one Trace.

    .. warning:: Called by :func:`obspy.read` through the ``obspy.plugin.waveform`` entry
       point; call :func:`obspy.read` (``obspy.read(path, dt=0.01)`` for a single column) or
       :func:`floorslide.read_record` instead.

    Parameters
    ----------
    filename
        Path of the text file.
    headonly
        Return the trace without data (``stats.npts`` set).
    dt
        Time step in s, needed for a single column without a ``# dt:`` header line; must agree
        with the file otherwise.
    **kwargs
        Ignored.

    Returns
    -------
    obspy.Stream
        Values as in the file, ``stats.units`` from the header if it names them, and
        ``stats.fstext`` with ``header`` (all ``key: value`` entries), ``columns``, ``t0``,
        ``names``.

    Raises
    ------
    RecordError
        For a malformed file, or a single column without dt.
    """
    where = str(filename)
    record = parse_text_record(filename)
    source = "the time column" if record.columns == 2 else "the header"
    step = check_dt(dt, record.dt, source, where)
    return record_to_stream(record, where, step, headonly)
