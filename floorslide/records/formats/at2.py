"""PEER NGA ``.AT2`` acceleration records, as an ObsPy waveform plugin (format ``"AT2"``).

A PEER file is four text lines and the samples, row by row::

    PEER NGA STRONG MOTION DATABASE RECORD
    Imperial Valley-02, 5/19/1940, El Centro Array #9, 180
    ACCELERATION TIME SERIES IN UNITS OF G
    NPTS=  3908, DT=   .0100 SEC,
      .2669000E-02  .2654000E-02  .2583000E-02 ...

The NPTS/DT line comes in several spellings in real files, all read here: the NGA-West2 one
above, the NGA-West1 / PEER-2000 one ``3908    0.0100    NPTS, DT`` (values first, labels
after, in either order), and compact ones such as ``NPTS=3908 DT=0.01`` or ``DT= .005 NPTS= 8000``.
The units come from the ``... IN UNITS OF G`` line; event, date, station and component from the
title line (``event, date, station, component`` in NGA-West2, ``event date time, station,
component`` in older files).

The reader is strict where a lenient one would lose data silently: fewer or more values than
NPTS, a missing or non-numeric NPTS/DT, DT ≤ 0, NaN/inf samples, a velocity or displacement
file (``.VT2``/``.DT2``) — each is a :class:`~floorslide.errors.RecordError` naming the file and
the problem. Values are returned as they are in the file (usually g), with ``stats.units`` set to
the canonical unit name; :func:`floorslide.read_record` converts them to m/s².

References
----------
PEER (2013). *PEER NGA-West2 Database*, Pacific Earthquake Engineering Research Center report
2013/03 (Ancheta et al.), and the format of the ``.AT2`` files served by
https://ngawest2.berkeley.edu (record header, NPTS/DT line, 5 values per row).
"""

from __future__ import annotations

import os
import re
from typing import IO

import numpy as np
from obspy import Stream, Trace
from obspy.core import AttribDict, Stats

from floorslide.errors import RecordError, UnitsError, excerpt
from floorslide.records.formats._text import (
    check_finite,
    count_mismatch,
    locate_token,
    parse_count_field,
    parse_float_field,
    parse_floats,
    read_head,
    read_text,
)
from floorslide.records.units import canonical_units

FORMAT = "AT2"

_NPTS_EQ = re.compile(r"\bNPTS\s*[=:]?\s*([^\s,=:]*)", re.IGNORECASE)
_DT_EQ = re.compile(r"\bDT\s*[=:]?\s*([^\s,=:]*)", re.IGNORECASE)
_TRAILING = re.compile(
    r"^\s*([^\s,]+)[\s,]+([^\s,]+)[\s,]+(NPTS|DT)\s*[,\s]\s*(NPTS|DT)\b", re.IGNORECASE
)
_HAS_NPTS = re.compile(r"\bNPTS\b", re.IGNORECASE)
_HAS_DT = re.compile(r"\bDT\b", re.IGNORECASE)
_UNITS = re.compile(r"\bUNITS\s+OF\s+([A-Za-z0-9/*^']+)", re.IGNORECASE)
_DATE = re.compile(r"\b\d{1,4}[/-]\d{1,2}[/-]\d{1,4}\b")
# the shape of a value in the fixed Fortran format of the data: digits after the point, exponent
_SHAPE = re.compile(r"^[+-]?\d*\.?(\d*)(?:[EeDd]([+-]?)(\d+))?$")
_HEADER_LINES = 8  # the NPTS/DT line is looked for among the first lines only
_COMMENT = ("#", "%", "!")


def _find_npts_line(lines: list[str]) -> int | None:
    """Index of the NPTS/DT header line among the first lines, or None."""
    for i, line in enumerate(lines[:_HEADER_LINES]):
        if line.lstrip().startswith(_COMMENT):
            continue
        if _HAS_NPTS.search(line) or (_HAS_DT.search(line) and "SEC" in line.upper()):
            return i
    return None


def _is_at2(filename: str | os.PathLike | IO[bytes]) -> bool:
    """True if the file looks like a PEER ``.AT2`` record (cheap; never raises).

    Looks at the first few kilobytes only: a text file with an NPTS/DT header line (one
    naming NPTS, or DT in SEC) among its first lines, after a title line. A malformed NPTS/DT
    line still counts, so that the reader can say what is wrong with it.
    """
    head = read_head(filename)
    if head is None:
        return False
    index = _find_npts_line(head.splitlines())
    return index is not None and index > 0


def _parse_npts_dt(line: str, where: str) -> tuple[int, float]:
    """NPTS and DT from the header line, in any of the spellings real files use."""
    trailing = _TRAILING.match(line)
    if trailing and trailing.group(3).upper() != trailing.group(4).upper():
        values = {trailing.group(3).upper(): trailing.group(1)}
        values[trailing.group(4).upper()] = trailing.group(2)
        npts_text, dt_text = values["NPTS"], values["DT"]
    else:
        npts_match, dt_match = _NPTS_EQ.search(line), _DT_EQ.search(line)
        if npts_match is None or not npts_match.group(1):
            raise RecordError(
                f"header line {excerpt(line.strip(), 60)} gives no NPTS "
                "(expected e.g. 'NPTS=  5590, DT=   .0100 SEC,')",
                where=where,
            )
        if dt_match is None or not dt_match.group(1):
            raise RecordError(
                f"header line {excerpt(line.strip(), 60)} gives no DT "
                "(expected e.g. 'NPTS=  5590, DT=   .0100 SEC,')",
                where=where,
            )
        npts_text, dt_text = npts_match.group(1), dt_match.group(1)
    npts = parse_count_field(npts_text, "NPTS", where)
    if npts <= 0:
        raise RecordError(f"NPTS = {npts}: a record needs at least one sample", where=where)
    dt = parse_float_field(dt_text, "DT", where)
    if not np.isfinite(dt) or dt <= 0:
        raise RecordError(f"DT = {dt_text}: the time step must be > 0 s", where=where)
    return npts, dt


def _parse_title(title: str) -> dict[str, str]:
    """Event, date, station and component from the title line (line 2)."""
    parts = [p.strip() for p in title.split(",")]
    out = {"event": "", "date": "", "station": "", "component": ""}
    if len(parts) < 3:
        out["event"] = title.strip()
        return out
    out["component"] = parts[-1]
    if _DATE.fullmatch(parts[1]) and len(parts) >= 4:  # NGA-West2: event, date, station, comp
        out["event"], out["date"] = parts[0], parts[1]
        out["station"] = ", ".join(parts[2:-1])
        return out
    out["event"] = parts[0]  # older: "EVENT MM/DD/YY HHMM, STATION, COMP"
    out["station"] = ", ".join(parts[1:-1])
    date = _DATE.search(parts[0])
    if date:
        out["date"] = date.group()
    return out


def _header_units(header: list[str], where: str) -> str | None:
    """Units named by the header (``... IN UNITS OF G``), canonical if known, else raw."""
    text = " ".join(header).upper()
    for quantity, extension in (("VELOCITY", ".VT2"), ("DISPLACEMENT", ".DT2")):
        if f"{quantity} TIME" in text:
            raise RecordError(
                f"the header says this is a {quantity.lower()} time series ({extension}); "
                "floorslide reads acceleration records (.AT2)",
                where=where,
            )
    match = _UNITS.search(" ".join(header))
    if match is None:
        return None
    raw = match.group(1).rstrip(".")
    try:
        return canonical_units(raw)
    except UnitsError:
        return raw


def _read_at2(filename: str | os.PathLike, headonly: bool = False, **kwargs: object) -> Stream:
    """Read a PEER ``.AT2`` file into an ObsPy Stream of one Trace.

    .. warning:: Called by :func:`obspy.read` through the ``obspy.plugin.waveform`` entry
       point; call :func:`obspy.read` or :func:`floorslide.read_record` instead.

    Parameters
    ----------
    filename
        Path of the ``.AT2`` file.
    headonly
        Read the header only (``stats.npts`` from NPTS, no data).
    **kwargs
        Ignored (ObsPy passes its own keywords to every reader).

    Returns
    -------
    obspy.Stream
        One trace, values as in the file (usually g), ``stats.delta`` = DT, ``stats.units`` the
        canonical name of the header's units (or the raw text if unknown; absent if the header
        names none), and ``stats.at2`` with ``title, event, date, station, component, units,
        header`` (the header lines).

    Raises
    ------
    RecordError
        For every malformed file (see the module docstring).
    """
    where = str(filename)
    text = read_text(filename)
    lines = text.splitlines()
    index = _find_npts_line(lines)
    if index is None:
        raise RecordError(
            f"no NPTS/DT line in the first {_HEADER_LINES} lines; not a PEER .AT2 record "
            "(expected a header line such as 'NPTS=  5590, DT=   .0100 SEC,')",
            where=where,
        )
    npts, dt = _parse_npts_dt(lines[index], where)
    header = lines[: index + 1]
    title = header[1].strip() if index >= 2 else (header[0].strip() if index >= 1 else "")
    units = _header_units(header[:index], where)

    meta = AttribDict(_parse_title(title))
    meta.title = title
    meta.units = units or ""
    meta.header = [line.rstrip() for line in header]
    stats = Stats()
    stats.delta = dt
    stats.npts = npts
    stats.at2 = meta  # names, not SEED codes: the network/station/channel fields stay empty
    if units:
        stats.units = units
    if headonly:
        return Stream([Trace(header=stats)])

    body = lines[index + 1 :]
    first_line = index + 2
    data = parse_floats(body, first_line, where, commas=False)
    if data.size != npts:
        raise count_mismatch("the header says NPTS=", npts, data.size, where)
    check_finite(data, where, lambda i: locate_token(body, first_line, i))
    _check_not_cut(body, text, first_line, where)
    stats.npts = data.size
    return Stream([Trace(data=data, header=stats)])


def _check_not_cut(body: list[str], text: str, first_line: int, where: str) -> None:
    """A file cut inside its last value reads as a different number with the right count
    ('-.5959150E-04' cut to '-.5959150'). When the file does not end with a line break, its last
    value must have the shape of its first (digits after the point, exponent): the data are
    written in one fixed Fortran format."""
    if text.endswith(("\n", "\r")):
        return
    tokens = [t for line in body for t in line.split()]
    if len(tokens) < 2:
        return
    first, last = _SHAPE.match(tokens[0]), _SHAPE.match(tokens[-1])
    if (
        first
        and last
        and first.groups() != last.groups()
        and (
            len(last.group(1)) < len(first.group(1))
            or (first.group(3) and not last.group(3))
            or len(last.group(3) or "") < len(first.group(3) or "")
        )
    ):
        raise RecordError(
            f"truncated: the file ends inside its last value {tokens[-1]!r} (line "
            f"{first_line + len(body) - 1}; the values are written like {tokens[0]!r})",
            where=where,
        )
