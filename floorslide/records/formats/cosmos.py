"""COSMOS V1/V2 strong-motion records (``.V2``, ``.V2c``, ``.V1``), as an ObsPy waveform plugin
(format ``"COSMOSV2"``).

(The USGS "SMC" format, ``.smc``, is a different layout and is not read here.)

A COSMOS file is one or more channel records, each self-describing::

    Corrected acceleration    (Format v01.20 with 13 text lines)
    Record of ... Earthquake of ...                       <- text header, 13 lines in v01.20
    ...
    Values used when parameter or data value is unknown/unspecified:   -999, -999.00
     100 Integer-header values follow on  10 lines, Format= (10I8)
     ...
     100 Real-header values follow on  20 lines, Format= (5F15.6)
     ...
       6 Comment line(s) follow, each starting with a "|":
    | ...
       42000 acceleration pts, approx  210 secs, units=cm/sec2(04),Format=(1E15.6)
     3.437285e-04
     ...
    End-of-data for Chan  1 acceleration

Each count line says how many values or lines follow and in which Fortran format, so the file is
read by following them; the data are read as whitespace-separated numbers and, if fields touch,
in the fixed-width columns of their Fortran format. A file may hold several channels, and
processed (V2) files from CGS also hold the integrated velocity and displacement after each
acceleration record: only acceleration records are returned, one Trace per channel.

Header values used (1-based numbering of the COSMOS tables, as in the format document):
Int(1) processing stage (0 raw counts, 1 V1, 2 V2, 3 spectra), Int(3) physical units code,
Int(40, 42–45) start year, month, day, hour, minute; Real(30) start second, Real(62) sample
interval in **milliseconds**, Real(63) record length (= npts·dt), Real(1–3) station latitude,
longitude, elevation, Real(10–13) event latitude, longitude, depth, magnitude, Real(17)
epicentral distance, Real(54)/Real(57) high-/low-pass corners. The units code of the data line
(``units=cm/sec2(04)``; Table 2: 2 g, 4 cm/s², 7 in/s², 10 gal, 11 mg) gives the units.

Errors (:class:`~floorslide.errors.RecordError`): a count line missing or malformed, fewer or
more values than announced, a sample interval missing, ≤ 0, or inconsistent with the record
length, raw counts (V0) or a non-acceleration file, NaN/inf samples.

References
----------
COSMOS (2001). *COSMOS Strong Motion Data Format*, version 1.20, Consortium of Organizations for
Strong-Motion Observation Systems, https://www.cosmos-eq.org (tables of the integer and real
headers; Table 2, physical units). The layout above follows real V2 files as served by the
Center for Engineering Strong Motion Data (CESMD) and USGS.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from typing import IO

import numpy as np
from obspy import Stream, Trace, UTCDateTime
from obspy.core import AttribDict, Stats

from floorslide.errors import RecordError, UnitsError
from floorslide.records.formats._text import (
    check_finite,
    parse_count_field,
    parse_fixed_width,
    parse_floats,
    read_head,
    read_text,
)
from floorslide.records.units import canonical_units

FORMAT = "COSMOSV2"

_FIRST = re.compile(r"\(Format\s+v\s*(\d+(?:\.\d+)?)\s+with\s+(\d+)\s+text\s+lines\)", re.I)
# a count field: a whole number in any spelling ("3949", "3949.", "3.949E+03"), read by
# parse_count_field (a fraction is refused there, not taken for another line)
_N = r"([+]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)"
_INT_HDR = re.compile(rf"^\s*{_N}\s+Integer-header\s+values\s+follow\s+on\s+{_N}\s+lines", re.I)
_REAL_HDR = re.compile(rf"^\s*{_N}\s+Real-header\s+values\s+follow\s+on\s+{_N}\s+lines", re.I)
_COMMENTS = re.compile(rf"^\s*{_N}\s+Comment\s+line", re.I)
_DATA = re.compile(
    rf"^\s*{_N}\s+([A-Za-z]+)\s+(?:pts|points)\b"
    r"(?:.*?approx\s+([\d.]+)\s*sec)?"
    r"(?:.*?units\s*=\s*([^(,]*?)\s*(?:\(\s*(\d+)\s*\))?\s*(?:,|$))?",
    re.I,
)
_FORTRAN = re.compile(r"Format\s*=\s*\(\s*(\d*)\s*([EFIGD])\s*(\d+)", re.I)
_END = re.compile(r"^\s*End[- ]of[- ]data", re.I)
_MISSING = re.compile(r"unknown/unspecified:\s*(-?\d+)\s*,\s*(-?[\d.]+)", re.I)
_STATION = re.compile(r"Code:\s*([A-Za-z0-9_]*)\s*-\s*([A-Za-z0-9_]+)")
_COMPONENT = re.compile(r"Sta\s+Chan\s*[^:]*:\s*(.*?)\s*(?:\(|Location:|$)", re.I)
_SCNL = re.compile(r"<SCNL>\s*([^\s.]*)\.([^\s.]*)\.([^\s.]*)\.([^\s.]*)")
# the processed record's peak the text header states: "Max = -306.831 cm/sec2 at 2.150 sec"
# (not "Uncor max", the raw record's)
_PEAK = re.compile(r"\bMax\s*=\s*([-+]?[\d.]+(?:[eE][-+]?\d+)?)\s*(\S+)\s+at\s+([\d.]+)\s*sec")

# COSMOS Table 2 (physical units), acceleration entries only.
_UNIT_CODES = {2: "g", 4: "gal", 7: "in/s**2", 10: "gal", 11: "mg"}
_STAGES = {0: "V0", 1: "V1", 2: "V2", 3: "V3"}


def _is_cosmos_v2(filename: str | os.PathLike | IO[bytes]) -> bool:
    """True if the file looks like a COSMOS record (cheap; never raises).

    The first line of a COSMOS file names the format: ``(Format v01.20 with 13 text lines)``.
    """
    head = read_head(filename, 1024)
    if head is None:
        return False
    first = head.split("\n", 1)[0]
    return _FIRST.search(first) is not None


@dataclass
class _Block:
    """One channel's headers while reading."""

    text: list[str]
    ints: np.ndarray
    reals: np.ndarray
    comments: list[str]
    missing_int: int
    missing_real: float
    version: str

    def int_(self, number: int) -> int | None:
        """Int(number), 1-based as in the COSMOS tables; None if absent or unknown."""
        if number > self.ints.size:
            return None
        value = int(self.ints[number - 1])
        return None if value == self.missing_int else value

    def real(self, number: int) -> float | None:
        """Real(number), 1-based; None if absent or unknown."""
        if number > self.reals.size:
            return None
        value = float(self.reals[number - 1])
        return None if math.isclose(value, self.missing_real) else value


class _Reader:
    """Walks the lines of a COSMOS file record by record."""

    def __init__(self, lines: list[str], where: str):
        self.lines = lines
        self.where = where
        self.pos = 0

    def fail(self, problem: str) -> RecordError:
        return RecordError(problem, where=self.where)

    def count(self, text: str, what: str) -> int:
        """A count field of the line just read (``3949``, ``3949.``, ``3.949E+03``)."""
        return parse_count_field(text, f"line {self.pos}: {what}", self.where)

    def line(self, what: str) -> str:
        if self.pos >= len(self.lines):
            raise self.fail(f"truncated: the file ends where {what} was expected")
        self.pos += 1
        return self.lines[self.pos - 1]

    def skip_blank(self) -> None:
        while self.pos < len(self.lines) and not self.lines[self.pos].strip():
            self.pos += 1

    def values(self, count: int, nlines: int, header: str, what: str) -> np.ndarray:
        start = self.pos
        if start + nlines > len(self.lines):
            raise self.fail(f"truncated: the file ends inside the {what}")
        body = self.lines[start : start + nlines]
        self.pos += nlines
        values = parse_floats(body, start + 1, self.where, commas=False)
        if values.size != count:
            fmt = _FORTRAN.search(header)
            if fmt is None or not fmt.group(1):
                raise self.fail(
                    f"line {start}: {what} announces {count} values, found {values.size}"
                )
            values = parse_fixed_width(
                body, int(fmt.group(3)), int(fmt.group(1)), count, start + 1, self.where
            )
        return values

    def headers(self) -> _Block:
        first = self.line("a COSMOS header")
        match = _FIRST.search(first)
        if match is None:
            raise self.fail(
                f"line {self.pos}: not a COSMOS header line "
                "(expected '... (Format v01.20 with 13 text lines)')"
            )
        version, ntext = match.group(1), int(match.group(2))
        text = [first] + [self.line("the text header") for _ in range(ntext - 1)]
        missing_int, missing_real = -999, -999.0
        for line in text:
            found = _MISSING.search(line)
            if found:
                missing_int, missing_real = int(found.group(1)), float(found.group(2))

        header = self.line("the integer-header line")
        match = _INT_HDR.match(header)
        if match is None:
            raise self.fail(
                f"line {self.pos}: expected 'NNN Integer-header values follow on NN lines', "
                f"found {header.strip()[:60]!r}"
            )
        ints = self.values(
            self.count(match.group(1), "the number of integer-header values"),
            self.count(match.group(2), "the number of integer-header lines"),
            header,
            "integer header",
        )

        header = self.line("the real-header line")
        match = _REAL_HDR.match(header)
        if match is None:
            raise self.fail(
                f"line {self.pos}: expected 'NNN Real-header values follow on NN lines', "
                f"found {header.strip()[:60]!r}"
            )
        reals = self.values(
            self.count(match.group(1), "the number of real-header values"),
            self.count(match.group(2), "the number of real-header lines"),
            header,
            "real header",
        )

        header = self.line("the comment-count line")
        match = _COMMENTS.match(header)
        if match is None:
            raise self.fail(
                f"line {self.pos}: expected 'N Comment line(s) follow', "
                f"found {header.strip()[:60]!r}"
            )
        ncomments = self.count(match.group(1), "the number of comment lines")
        comments = [self.line("a comment line") for _ in range(ncomments)]
        return _Block(text, ints, reals, comments, missing_int, missing_real, version)

    def data(self) -> tuple[re.Match, str, np.ndarray]:
        header = self.line("the data line ('NNN acceleration pts, ...')")
        match = _DATA.match(header)
        if match is None:
            raise self.fail(
                f"line {self.pos}: expected 'NNN acceleration pts, approx NN secs, units=...', "
                f"found {header.strip()[:60]!r}"
            )
        npts = self.count(match.group(1), "the number of points")
        start = self.pos
        end = start
        while end < len(self.lines):
            line = self.lines[end]
            if _END.match(line) or _DATA.match(line) or "(Format" in line:
                break
            end += 1
        body = self.lines[start:end]
        self.pos = end
        values = parse_floats(body, start + 1, self.where, commas=False)
        if values.size != npts:
            fmt = _FORTRAN.search(header)
            if values.size > npts and fmt and fmt.group(1):
                per_line, width = int(fmt.group(1)), int(fmt.group(3))
                values = parse_fixed_width(body, width, per_line, npts, start + 1, self.where)
            if values.size < npts:
                raise self.fail(
                    f"truncated: line {start} announces {npts} {match.group(2).lower()} values "
                    f"but only {values.size} follow"
                )
            if values.size != npts:
                raise self.fail(
                    f"line {start} announces {npts} values but {values.size} follow; "
                    "header and data disagree"
                )
        check_finite(values, self.where)
        if self.pos >= len(self.lines):
            # a file always ends with the block's 'End-of-data' line: without it, a cut inside
            # the last value would read as a different number
            raise self.fail(
                f"truncated: the file ends without the 'End-of-data' line after the "
                f"{match.group(2).lower()} values of line {start}"
            )
        if _END.match(self.lines[self.pos]):
            self.pos += 1
        return match, header, values


def _units(match: re.Match, block: _Block, where: str) -> str:
    """Canonical units of a data block, from its code (Table 2) or its text."""
    code = int(match.group(5)) if match.group(5) else block.int_(3)
    text = (match.group(4) or "").strip()
    if code in (50, 51, 22):
        raise RecordError(
            "raw counts or volts (COSMOS V0); floorslide reads V1/V2 records in physical units",
            where=where,
        )
    units = _UNIT_CODES.get(code) if code is not None else None
    if units is None and text:
        try:
            units = canonical_units(text)
        except UnitsError:
            raise UnitsError(
                f"unknown units {text!r} (COSMOS code {code}) in the data line", where=where
            ) from None
    if units is None:
        raise UnitsError(f"no units for the data (COSMOS units code {code})", where=where)
    return units


def _delta(block: _Block, npts: int, approx: str | None, where: str) -> float:
    """Sample interval in s from Real(62) (ms), checked against Real(63) and 'approx N secs'."""
    ms = block.real(62)
    if ms is None:
        raise RecordError(
            "the sample interval is missing (COSMOS real header value 62, in ms)", where=where
        )
    dt = ms / 1000.0
    if not np.isfinite(dt) or dt <= 0:
        raise RecordError(f"sample interval {ms} ms: the time step must be > 0", where=where)
    length = block.real(63)
    if length is not None and length > 0 and abs(length - npts * dt) > 1.01 * dt + 1e-9:
        raise RecordError(
            f"record length {length} s (real header 63) disagrees with "
            f"{npts} samples x {dt} s = {npts * dt:g} s",
            where=where,
        )
    if approx:
        seconds = float(approx)
        if abs(seconds - npts * dt) > max(2.0, 0.05 * npts * dt):
            raise RecordError(
                f"the data line says approx {approx} s but {npts} samples x {dt} s = "
                f"{npts * dt:g} s; header and data disagree",
                where=where,
            )
    return dt


def _starttime(block: _Block) -> UTCDateTime | None:
    parts = [block.int_(n) for n in (40, 42, 43, 44, 45)]
    if any(p is None for p in parts):
        return None
    second = block.real(30) or 0.0
    try:
        return UTCDateTime(*parts) + second  # type: ignore[arg-type]
    except (ValueError, TypeError):
        return None


def _stats(block: _Block, match: re.Match, dt: float, npts: int, units: str) -> Stats:
    text = block.text + [""] * 13
    stats = Stats()
    stats.delta = dt
    stats.npts = npts
    stats.units = units
    start = _starttime(block)
    if start is not None:
        stats.starttime = start
    meta = AttribDict()
    stage = block.int_(1)
    meta.process_level = _STAGES.get(stage, "") if stage is not None else ""
    meta.format_version = block.version
    meta.data_type = text[0].split("(")[0].strip()
    meta.event = re.sub(r"^\s*Record of\s*", "", text[1]).strip()
    meta.origin = re.sub(r"^\s*Origin:\s*", "", text[3]).strip()
    station = _STATION.search(text[4])
    network, code = (station.group(1), station.group(2)) if station else ("", "")
    meta.station_name = text[4][40:].strip() if len(text[4]) > 40 else ""
    component = _COMPONENT.search(text[8])
    meta.component = re.sub(r"\s*deg\b.*", "", component.group(1)).strip() if component else ""
    channel = location = ""
    for comment in block.comments:
        scnl = _SCNL.search(comment)
        if scnl:
            code, channel, network, location = scnl.groups()
            location = "" if location == "--" else location
    stats.network, stats.station, stats.channel, stats.location = network, code, channel, location
    if not meta.component:
        meta.component = channel
    meta.units_text = (match.group(4) or "").strip()
    meta.units_code = int(match.group(5)) if match.group(5) else block.int_(3)
    for name, number in (
        ("station_latitude", 1),
        ("station_longitude", 2),
        ("station_elevation", 3),
        ("event_latitude", 10),
        ("event_longitude", 11),
        ("event_depth_km", 12),
        ("magnitude", 13),
        ("epicentral_distance_km", 17),
        ("highpass_hz", 54),
        ("lowpass_hz", 57),
    ):
        value = block.real(number)
        if value is not None:
            meta[name] = value
    meta.comments = [c.rstrip() for c in block.comments]
    meta.header = [line.rstrip() for line in block.text]
    peak = next((m for m in map(_PEAK.search, block.text) if m is not None), None)
    if peak is not None and not math.isclose(float(peak.group(1)), block.missing_real):
        stats.stated_peak = AttribDict(
            value=float(peak.group(1)),
            units=peak.group(2),
            time=float(peak.group(3)),
            text=" ".join(peak.group(0).split()),
        )
    stats.cosmos = meta
    return stats


def _read_cosmos_v2(
    filename: str | os.PathLike, headonly: bool = False, **kwargs: object
) -> Stream:
    """Read a COSMOS V1/V2 file into an ObsPy Stream, one Trace per acceleration channel.

    .. warning:: Called by :func:`obspy.read` through the ``obspy.plugin.waveform`` entry
       point; call :func:`obspy.read` or :func:`floorslide.read_record` instead.

    Parameters
    ----------
    filename
        Path of the COSMOS file.
    headonly
        Return traces without data (``stats.npts`` set); the samples are parsed anyway, since
        they delimit the records.
    **kwargs
        Ignored.

    Returns
    -------
    obspy.Stream
        Values as in the file (cm/s² for most V2 files), ``stats.units`` the canonical unit name,
        network/station/channel/location from the ``<SCNL>`` comment or the station line,
        ``stats.cosmos`` with the event, station name, component, coordinates, filter corners,
        comments and text header.

    Raises
    ------
    RecordError
        For every malformed file (see the module docstring).
    """
    where = str(filename)
    reader = _Reader(read_text(filename).splitlines(), where)
    traces: list[Trace] = []
    skipped: list[str] = []
    while True:
        reader.skip_blank()
        if reader.pos >= len(reader.lines):
            break
        block = reader.headers()
        stage = block.int_(1)
        if stage == 0:
            raise RecordError(
                "raw counts (COSMOS V0); floorslide reads V1/V2 records in physical units",
                where=where,
            )
        if stage == 3:
            raise RecordError("response spectra (COSMOS V3), not a time series", where=where)
        while True:  # data blocks sharing these headers (acceleration, velocity, ...)
            match, _header, values = reader.data()
            quantity = match.group(2).lower()
            if quantity.startswith("acc"):
                dt = _delta(block, values.size, match.group(3), where)
                units = _units(match, block, where)
                stats = _stats(block, match, dt, values.size, units)
                traces.append(Trace(header=stats) if headonly else Trace(values, stats))
            else:
                skipped.append(quantity)
            reader.skip_blank()
            if reader.pos >= len(reader.lines) or not _DATA.match(reader.lines[reader.pos]):
                break
    if not traces:
        found = ", ".join(sorted(set(skipped))) or "no data"
        raise RecordError(
            f"no acceleration record in this COSMOS file (found: {found})", where=where
        )
    return Stream(traces)
