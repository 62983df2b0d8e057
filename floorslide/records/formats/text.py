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

import math
import os
import re
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import IO, BinaryIO

import numpy as np
from obspy import Stream, Trace, UTCDateTime
from obspy.core import AttribDict, Stats

from floorslide.errors import RecordError, UnitsError
from floorslide.records.formats._text import (
    HEAD_BYTES,
    UNDERSCORE_HINT,
    count_mismatch,
    decode,
    open_text,
    parse_count_field,
    read_head,
)
from floorslide.records.units import canonical_units
from floorslide.text_numbers import is_count, parse_number

FORMAT = "FSTEXT"

COMMENT_CHARS = ("#", "%", "!")
_KEY_VALUE = re.compile(r"^\s*[#%!]+\s*([A-Za-z][\w \-]{0,40}?)\s*[:=]\s*(.*?)\s*$")
_NAME = re.compile(r"^[A-Za-z_][\w()\[\]/*.^\-]*$")
_DT_KEYS = ("dt", "delta", "time_step", "timestep", "sample_interval", "sampling_interval")
_RATE_KEYS = ("sampling_rate", "fs", "sample_rate", "sps")
_LEADING_NUMBER = re.compile(
    r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)(?![\d_.])\s*([A-Za-z]*)"
)
_TIME_TOLERANCE = 0.01  # fraction of a step a time value may be off the uniform grid
_PLAIN_NUMBER_BYTES = b"0123456789+-.eE \t\r\n\f\v,"
# a line of one field; possessive quantifiers (no backtracking) and a leading line feed make the
# search fast; the first line of a block is tested apart
_ONE_FIELD_ROW = re.compile(rb"\n[ \t\r\f\v]*+[^\s]++[ \t\r\f\v]*+(?:\n|\Z)")
_BLANK_LINE = re.compile(rb"^[ \t\r\f\v]*$", re.MULTILINE)
_BLANK_BETWEEN = re.compile(rb"\n[ \t\r\f\v]*\n")
_MILLISECONDS = re.compile(r"(?:^|[^a-z])(?:ms|msec|millisec\w*)(?:[^a-z]|$)", re.IGNORECASE)

CHUNK_BYTES = 1 << 22
"""Data lines are parsed in blocks of about this many bytes (4 MiB)."""

TIME_BLOCK = 1 << 20
"""Samples of a time column checked at a time."""

MAX_TIME_STEP = 0.5
"""A time column stepping by this much (s) or more is refused: no accelerogram is sampled at
2 Hz or less, and such a column is almost surely in milliseconds."""

COUNT_SPIKE = 100.0
"""A whole-number first value this many times the largest other value is a count line."""


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


@dataclass
class _Chunk:
    """Where one block of data lines lies: bytes ``[start, end)`` of the file, 1-based number of
    its first line, index of its first row (for messages)."""

    start: int
    end: int
    line: int
    row: int


class _Preamble:
    """The lines before the data: header entries, column names, where the data start (read
    from the open file `fh`, from byte `offset`)."""

    def __init__(self, fh: BinaryIO, offset: int):
        self.header: dict[str, str] = {}
        self.names: list[str] = []
        self.names_line = 0
        self.tokens: list[str] = []  # the fields of the first data line
        self.line = 0  # its 1-based line number
        self.start = offset  # its byte offset (the end of the file if there are no data)
        self.end = offset  # where it ends
        self.empty = True  # nothing but white space before the data
        fh.seek(offset)
        number, pos = 0, offset
        for raw in iter(fh.readline, b""):
            number += 1
            end = pos + len(raw)
            stripped = decode(raw).strip()
            self.empty = self.empty and not stripped
            if stripped.startswith(COMMENT_CHARS):
                match = _KEY_VALUE.match(stripped)
                if match:
                    self.header[_norm_key(match.group(1))] = match.group(2)
            elif stripped:
                tokens = _tokens(stripped)
                if (
                    not self.names
                    and not any(_is_float(t) for t in tokens)
                    and all(_NAME.match(t) for t in tokens)
                ):
                    self.names, self.names_line = tokens, number
                else:
                    self.tokens, self.line, self.start, self.end = tokens, number, pos, end
                    return
            pos = end
        self.start = self.end = pos


def _blocks(fh: BinaryIO, start: int, line: int) -> Iterator[tuple[bytes, int, int]]:
    """``(block, byte offset, first line)`` of successive blocks of whole lines of about
    :data:`CHUNK_BYTES`, from byte ``start`` (line ``line``) to the end of the file."""
    fh.seek(start)
    rest = b""
    while True:
        piece = fh.read(CHUNK_BYTES)
        buffer = rest + piece if rest else piece
        if not piece:
            if buffer:
                yield buffer, start, line
            return
        cut = buffer.rfind(b"\n") + 1
        if cut == 0:
            rest = buffer  # a line longer than a block
            continue
        block, rest = buffer[:cut], buffer[cut:]
        yield block, start, line
        start += len(block)
        line += block.count(b"\n")


def _count_lines(fh: BinaryIO, start: int) -> int:
    """Line feeds from byte `start` to the end of the file, + 1 (an upper bound of the rows)."""
    fh.seek(start)
    return 1 + sum(piece.count(b"\n") for piece in iter(lambda: fh.read(CHUNK_BYTES), b""))


def _fast_values(chunk: bytes, ncols: int) -> np.ndarray | None:
    """The numbers of a block of data lines, row by row, or None if anything is unusual
    (comments, names, NaN, a ragged row, a bad value: :func:`_values_by_lines` says where).

    No Python object per line: a byte translation finds any character that is not part of a
    plain number, one regular-expression search finds a two-column file's one-field rows, and
    NumPy converts the whole block (correctly rounded, as ``float``). Every non-blank line then
    holds exactly ``ncols`` numbers when their count is ``ncols`` × the non-blank lines (each
    line has at least one field, and in two columns none has exactly one).
    """
    if chunk.translate(None, _PLAIN_NUMBER_BYTES):
        return None
    if b"," in chunk:
        chunk = chunk.replace(b",", b" ")
    if ncols == 2 and _ONE_FIELD_ROW.search(b"\n" + chunk[: chunk.find(b"\n") + 1]):
        return None  # the block's first line
    if ncols == 2 and _ONE_FIELD_ROW.search(chunk):
        return None
    rows = _nonblank_lines(chunk)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", DeprecationWarning)
            values = np.fromstring(chunk, dtype=np.float64, sep=" ")
    except (ValueError, DeprecationWarning):
        return None
    if values.size != rows * ncols or not np.isfinite(values).all():
        return None
    return values


def _nonblank_lines(chunk: bytes) -> int:
    """The number of lines of `chunk` that are not blank (quick searches when none is)."""
    newline = chunk.find(b"\n")
    first = chunk if newline < 0 else chunk[: newline + 1]
    last = chunk[chunk.rfind(b"\n") + 1 :]
    if not first.strip() or (last and not last.strip()) or _BLANK_BETWEEN.search(chunk):
        return chunk.count(b"\n") + 1 - len(_BLANK_LINE.findall(chunk))
    return chunk.count(b"\n") + (not chunk.endswith(b"\n"))


def _values_by_lines(chunk: bytes, line: int, ncols: int, where: str) -> np.ndarray:
    """:func:`_fast_values`, line by line, with the line and column of every problem."""
    values: list[float] = []
    for number, text in enumerate(decode(chunk).split("\n"), line):
        stripped = text.strip()
        if not stripped or stripped.startswith(COMMENT_CHARS):
            continue
        tokens = _tokens(stripped)
        if len(tokens) != ncols:
            raise RecordError(
                f"line {number}: {len(tokens)} columns where the data above have {ncols}",
                where=where,
            )
        for col, token in enumerate(tokens):
            value = _float_or_none(token)
            if value is None:
                hint = f" ({UNDERSCORE_HINT})" if "_" in token else ""
                raise RecordError(
                    f"line {number}, column {text.find(token) + 1}: {token[:40]!r} is not a "
                    f"number{hint}",
                    where=where,
                )
            if not math.isfinite(value):
                kind = "NaN" if math.isnan(value) else "infinite"
                raise RecordError(
                    f"line {number}: {kind} value in column {col + 1}; "
                    "a record must hold finite numbers",
                    where=where,
                )
            values.append(value)
    return np.array(values, dtype=np.float64)


def _float_or_none(token: str) -> float | None:
    """``float(token)``, or None for a token that is not a number (or has underscores)."""
    try:
        return parse_number(token)
    except ValueError:
        return None


def _table(fh: BinaryIO, pre: _Preamble, where: str) -> tuple[np.ndarray, Callable[[int], int]]:
    """The numbers of the data lines as a (rows, columns) array, and a function giving the
    1-based file line of a row (for messages; it reads the file again).

    The data are read and parsed block by block (:data:`CHUNK_BYTES`) into one preallocated
    array, each block by :func:`_fast_values` or, when that declines, line by line: reading
    takes about the samples and a few blocks in memory — neither the whole file nor a Python
    object per line (docs/design.md §8).
    """
    if not pre.tokens:
        if pre.empty:
            raise RecordError("empty file", where=where)
        raise RecordError("no data lines (only comments or blank lines)", where=where)
    ncols = len(pre.tokens)
    if ncols not in (1, 2):
        raise RecordError(
            f"line {pre.line}: {ncols} columns; expected 1 (acceleration) or "
            "2 (time, acceleration)",
            where=where,
        )
    out = np.empty(_count_lines(fh, pre.start) * ncols, dtype=np.float64)
    chunks: list[_Chunk] = []
    filled = 0
    for block, start, line in _blocks(fh, pre.start, pre.line):
        values = _fast_values(block, ncols)
        if values is None:
            values = _values_by_lines(block, line, ncols, where)
        chunks.append(_Chunk(start, start + len(block), line, filled // ncols))
        out[filled : filled + values.size] = values
        filled += values.size
    out.resize((filled,), refcheck=False)  # shrinks in place: no copy

    def line_of(row: int) -> int:
        chunk = next(c for c in reversed(chunks) if c.row <= row)
        fh.seek(chunk.start)
        text = decode(fh.read(chunk.end - chunk.start))
        seen = chunk.row
        for number, line in enumerate(text.split("\n"), chunk.line):
            stripped = line.strip()
            if stripped and not stripped.startswith(COMMENT_CHARS):
                if seen == row:
                    return number
                seen += 1
        return chunk.line  # pragma: no cover - every row is on a line

    return out.reshape(-1, ncols), line_of


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
    fh, offset = open_text(filename)
    with fh:
        try:
            pre = _Preamble(fh, offset)
            _check_count_line_above_two_columns(fh, pre, where)
            table, line_of = _table(fh, pre, where)
            header = pre.header
            ncols = table.shape[1]
            if ncols == 1:
                _check_count_line(table[:, 0], pre, where)
            dt = _header_dt(header, where)
            t0 = 0.0
            if ncols == 2:
                _check_time_label(pre, where)
                dt, t0 = _time_column(table[:, 0], line_of, dt, where)
        except OSError as exc:
            raise RecordError(f"cannot read file: {exc.strerror or exc}", where=where) from None
    units = None
    if header.get("units") or header.get("unit"):
        raw_units = header.get("units") or header.get("unit") or ""
        units = canonical_units_in_header(raw_units, where)
    data = np.ascontiguousarray(table[:, -1])
    if "npts" in header:
        npts = parse_count_field(header["npts"], "header npts:", where)
        if npts != data.size:
            raise count_mismatch("the header says npts=", npts, data.size, where)
    return TextRecord(data, dt, units, header, ncols, t0, pre.names)


def _count_hint(count: str) -> str:
    return f"delete that line, or make it a header line '# npts: {count}' (then it is checked)"


def _is_count_token(token: str) -> bool:
    """Whether a field is written as a count: a whole number ≥ 1 in any spelling (``2000``,
    ``2000.``, ``2.0E+03``; :func:`floorslide.text_numbers.parse_count`)."""
    return is_count(token) and parse_number(token) >= 1


def _check_count_line_above_two_columns(fh: BinaryIO, pre: _Preamble, where: str) -> None:
    """A lone whole number above two-column data is a sample-count line, not data."""
    if len(pre.tokens) != 1 or not _is_count_token(pre.tokens[0]):
        return
    following = _Preamble(fh, pre.end)
    if len(following.tokens) == 2 and not following.names:
        raise RecordError(
            f"line {pre.line}: a lone whole number ({pre.tokens[0]}) above two-column data: a "
            f"sample count, not a sample; {_count_hint(pre.tokens[0])}",
            where=where,
        )


def _check_count_line(values: np.ndarray, pre: _Preamble, where: str) -> None:
    """Refuse a first value that is a sample count rather than a sample.

    A first value written as a whole number ≥ 1 (``3949``, ``3949.``, ``3.949E+03``) that
    equals the number of values after it is a count line (``3949`` above 3949 samples), not a
    3949 g spike. When the other values are not all whole numbers, a whole first value is a
    count line too, one that disagrees with the values present, when it is

    - above every other value's magnitude and above their number (a count of a truncated
      file: ``2000.`` above 1500 samples in gal would otherwise be a 2000 gal PGA), or
    - at least :data:`COUNT_SPIKE` times the largest of the other values.

    Both numbers are named in the error.
    """
    token = pre.tokens[0]
    if values.size < 2 or not _is_count_token(token):
        return
    first, rest = float(values[0]), values[1:]
    if first == rest.size:
        raise RecordError(
            f"line {pre.line}: {token} is the number of values after it, a sample count, not "
            f"a sample; {_count_hint(token)}",
            where=where,
        )
    if np.all(rest == np.round(rest)):
        return  # whole-number samples (counts of a digitiser): a count cannot be told apart
    largest = max(float(rest.max()), -float(rest.min()))
    if first > largest and first > rest.size:
        why = f"above every value after it (largest {largest:.3g})"
    elif first >= COUNT_SPIKE * largest:
        why = f"{COUNT_SPIKE:g}x the largest other value, {largest:.3g}"
    else:
        return
    disagree = "a truncated file?" if rest.size < first else "count and data disagree;"
    raise RecordError(
        f"line {pre.line}: {token} looks like a sample count, not a sample (a whole number "
        f"{why}), but {rest.size} values follow it: {disagree} {_count_hint(token)}",
        where=where,
    )


def _check_time_label(pre: _Preamble, where: str) -> None:
    """Refuse a time column labelled in milliseconds: floorslide reads times in seconds."""
    unit = pre.header.get("time_units") or pre.header.get("time_unit") or ""
    if _MILLISECONDS.search(unit):
        label, line = f"time units: {unit}", "the header"
    elif pre.names and _MILLISECONDS.search(pre.names[0]):
        label, line = repr(pre.names[0]), f"line {pre.names_line}"
    else:
        return
    raise RecordError(
        f"{line}: the time column is in milliseconds ({label}); floorslide reads times in "
        "seconds: convert the column to seconds, or drop it and state dt ('# dt: 0.005' or "
        "--dt 0.005)",
        where=where,
    )


def canonical_units_in_header(raw: str, where: str) -> str:
    """Canonical units of a header entry, with the file named in the error."""
    try:
        return canonical_units(raw)
    except UnitsError as exc:
        raise UnitsError(f"header units: {exc.message}", where=where) from None


def _time_column(
    times: np.ndarray, line_of: Callable[[int], int], header_dt: float | None, where: str
) -> tuple[float, float]:
    """dt and t0 of a uniform, increasing time column in seconds (RecordError otherwise).

    Checked block by block (:data:`TIME_BLOCK` samples), so that the temporaries stay small
    for a long record.
    """
    n = times.size
    if n < 2:
        raise RecordError("a two-column record needs at least two rows to give dt", where=where)
    for lo in range(0, n - 1, TIME_BLOCK):
        steps = np.diff(times[lo : lo + TIME_BLOCK + 1])
        if (steps <= 0).any():
            k = lo + int(np.argmax(steps <= 0)) + 1
            raise RecordError(
                f"line {line_of(k)}: time {times[k]:g} s does not increase "
                f"(previous {times[k - 1]:g} s)",
                where=where,
            )
    dt = (times[-1] - times[0]) / (n - 1)
    for lo in range(0, n, TIME_BLOCK):
        block = times[lo : lo + TIME_BLOCK]
        off = np.abs(block - (times[0] + dt * np.arange(lo, lo + block.size)))
        if off.max() > _TIME_TOLERANCE * dt:
            k = lo + int(np.argmax(off > _TIME_TOLERANCE * dt))
            raise RecordError(
                f"line {line_of(k)}: time {times[k]:g} s is {off[k - lo]:.3g} s off the uniform "
                f"grid t0 + k*dt (dt = {dt:.6g} s); floorslide needs uniformly sampled records "
                "- resample first",
                where=where,
            )
    if dt >= MAX_TIME_STEP:
        raise RecordError(
            f"line {line_of(1)}: the time column steps by {dt:.6g} s, implausible for an "
            f"accelerogram (dt >= {MAX_TIME_STEP:g} s; milliseconds?): give the times in "
            "seconds, or drop the time column and state dt ('# dt: ...' or --dt)",
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
