"""Reading accelerograms: any file → :class:`obspy.Stream` in m/s² with its metadata.

:func:`read_record` reads PEER ``.AT2``, COSMOS V1/V2 and plain text with floorslide's own
readers (also registered as ObsPy plugins, so :func:`obspy.read` reads them too), and every
format ObsPy reads (MiniSEED, SAC, K-NET/KiK-net, GSE2, SEG-Y ...) through ObsPy, unchanged, and,
with the optional extra ``floorslide[gmprocess]``, the formats USGS gmprocess reads (DMG/CSMIP,
GeoNet, CWB, UNAM, SMC, ESM ...; see :mod:`floorslide.records.gmprocess_formats`) for a file
neither knows. It then does only what makes the data a record in SI:

- data as float64 in m/s², ``stats.units = "m/s**2"``, ``stats.original_units`` the units of the
  file, and one note in ``stats.processing`` when a conversion factor was applied;
- source metadata kept: the format's own ``stats.<format>`` dictionary (``stats.at2``,
  ``stats.cosmos``, ``stats.fstext``, ``stats.sac``, ``stats.knet`` ...), the usual ObsPy
  fields (network, station, channel, starttime), and ``stats.record``, the same few facts for
  every format: ``path``, ``format``, ``event``, ``station``, ``component`` (empty strings when
  the source does not say; ObsPy's ``stats.component`` is the last letter of the channel code,
  hence a separate place);
- nothing else: no demeaning, filtering or trimming (see :func:`floorslide.process`).

Units come from the file where the format states them (AT2 header line, COSMOS units code, a
``# units:`` line in a text file; K-NET/KiK-net are counts with ObsPy's ``calib`` to m/s², the
file's units being gal) and otherwise from ``units=``. A file that does not state its units and
no ``units=`` is an error — units are never guessed (MiniSEED and SAC hold counts or unknown
units: give ``units=``; the SAC value ``IDEP = IACC`` nominally means nm/s², which writers often
ignore, so it is not trusted either). A ``units=`` or ``dt=`` that contradicts the file is an
error too.

**Sidecar catalog.** A single-column text file does not know its time step or units. When
neither the file's header nor the caller gives them, :func:`read_record` looks for ``index.csv``
in the same folder; if that catalog (see :mod:`floorslide.records.catalog`) lists the file, its
row supplies ``dt``, ``units`` (and ``format``/``component`` if those columns exist) and all its
columns are kept in ``stats.catalog``, exactly as :func:`~floorslide.records.catalog.read_catalog`
does.
"""

from __future__ import annotations

import os
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import obspy
from obspy import Stream, Trace
from obspy.core import AttribDict

from floorslide.errors import RecordError, UnitsError, excerpt
from floorslide.records import gmprocess_formats
from floorslide.records.formats import at2, cosmos, text
from floorslide.records.units import FACTORS, SI_UNITS, canonical_units

if TYPE_CHECKING:
    from floorslide.records.catalog import CatalogEntry

try:
    _VERSION = version("floorslide")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    _VERSION = "unknown"

PROCESSING_PREFIX = f"floorslide {_VERSION}"
"""Prefix of the notes floorslide leaves in ``stats.processing`` (ObsPy uses ``ObsPy x.y``)."""

OWN_FORMATS = {
    at2.FORMAT: (at2._is_at2, at2._read_at2),
    cosmos.FORMAT: (cosmos._is_cosmos_v2, cosmos._read_cosmos_v2),
    text.FORMAT: (text._is_text, text._read_text),
}
"""floorslide's own formats, in the order auto-detection tries them."""

FORMAT_ALIASES = {
    "at2": at2.FORMAT,
    "peer": at2.FORMAT,
    "cosmos": cosmos.FORMAT,
    "cosmosv2": cosmos.FORMAT,
    "cosmos_v2": cosmos.FORMAT,
    "v2": cosmos.FORMAT,
    "v2c": cosmos.FORMAT,
    "text": text.FORMAT,
    "txt": text.FORMAT,
    "fstext": text.FORMAT,
    "csv": text.FORMAT,
    "mseed": "MSEED",
    "miniseed": "MSEED",
    "knet": "KNET",
    "kiknet": "KNET",
    "gmprocess": gmprocess_formats.FORMAT,
}
"""Format names accepted by ``format=`` besides ObsPy's own (case-insensitive)."""

SUFFIX_FORMATS = {
    ".at2": at2.FORMAT,
    ".v1": cosmos.FORMAT,
    ".v2": cosmos.FORMAT,
    ".v1c": cosmos.FORMAT,
    ".v2c": cosmos.FORMAT,
    ".txt": text.FORMAT,
    ".dat": text.FORMAT,
    ".csv": text.FORMAT,
    ".asc": text.FORMAT,
}
"""File extensions that name one of floorslide's formats. When neither floorslide's checks nor
ObsPy recognise a file by its content, a file with one of these extensions is read as that
format, so that the error says what is wrong with it (e.g. the line and column of a bad value)
rather than "unknown format"."""


DISPLAY_NAMES = {text.FORMAT: "text"}
"""Formats whose internal (ObsPy plugin) name is not the one users know: floorslide's plain
text is the ObsPy plugin ``FSTEXT`` and ``text`` to users."""


def format_name(fmt: str) -> str:
    """The name a user knows a format by, as ``floorslide inspect`` shows it and ``--format``
    takes it: ``text`` for floorslide's plain text, otherwise the format's own name (``AT2``,
    ``COSMOSV2``, ``MSEED``, ``KNET`` ...)."""
    return DISPLAY_NAMES.get(fmt, fmt)


class _UnknownFormat(RecordError):
    """No reader recognises the file."""


SIDECAR = "index.csv"
"""Name of the sidecar catalog looked for next to a text record that lacks dt or units."""

_SAC_IACC = 8  # SAC header IDEP value "acceleration (nm/s**2)"

PEAK_TOLERANCE = 0.01
"""Relative difference allowed between the peak a file's header states and the peak of its
samples (the header prints it rounded; a wrong channel, scale or units is far off)."""


def read_record(
    path: str | os.PathLike,
    format: str | None = None,
    units: str | None = None,
    dt: float | None = None,
    component: str | None = None,
) -> Stream:
    """Read an accelerogram file into a Stream whose data are acceleration in m/s².

    Parameters
    ----------
    path
        The record file.
    format
        Format name: ``"AT2"``, ``"COSMOSV2"`` (also ``"COSMOS"``, ``"V2"``), ``"FSTEXT"`` (also
        ``"TEXT"``), any ObsPy format (``"MSEED"``, ``"SAC"``, ``"KNET"`` ...), or
        ``"gmprocess"`` (read by gmprocess, the optional extra; also ``"gmprocess:dmg"`` ...
        as ``floorslide inspect`` shows it); default: detected from the content.
    units
        Units of the values in the file (``"g"``, ``"gal"``, ``"m/s**2"``, ``"mm/s**2"``, or a
        spelling :func:`~floorslide.records.units.canonical_units` knows). Needed when the
        format does not state them; must agree with the file when it does.
    dt
        Time step in s, for a single-column text file without a ``# dt:`` header; must agree
        with the file when it states one.
    component
        For a file holding several traces: keep those whose component matches (the format's
        component name, the channel code, or its last letter, e.g. ``"N"`` for ``HNN``;
        case-insensitive). For a single-trace file it must match the file's component if the
        file names one, and is recorded as ``stats.record.component`` if not.

    Returns
    -------
    obspy.Stream
        One Trace per component read. Each has float64 data in m/s², ``stats.units =
        "m/s**2"``, ``stats.original_units``, ``stats.record`` (``path, format, event, station,
        component``; empty strings when unknown), the format's own metadata (``stats.at2``,
        ``stats.cosmos``, ``stats.sac`` ...) and, when a sidecar catalog supplied dt/units,
        ``stats.catalog`` (see the module notes).

    Raises
    ------
    RecordError
        For a missing file, a directory, an empty, binary, truncated or malformed file, NaN
        or infinite samples, dt ≤ 0, a component that is not in the file — one line naming
        the file and the problem.
    UnitsError
        For unknown units, units neither in the file nor given, or units that contradict it.

    Examples
    --------
    >>> st = read_record("RSN6_IMPVALL.I_I-ELC180.AT2")          # doctest: +SKIP
    >>> st = read_record("elcentro.txt", dt=0.01, units="g")    # doctest: +SKIP
    >>> ag, dt = st[0].data, st[0].stats.delta                  # doctest: +SKIP
    """
    return _read_record(path, format, units, dt, component, sidecar=True)


def _read_record(
    path: str | os.PathLike,
    format: str | None,
    units: str | None,
    dt: float | None,
    component: str | None,
    sidecar: bool,
) -> Stream:
    """:func:`read_record`, with the sidecar lookup optional (catalog rows turn it off)."""
    path = Path(path)
    where = str(path)
    _check_path(path)
    given_units = None
    if units is not None:
        try:
            given_units = canonical_units(units)
        except UnitsError as exc:
            raise UnitsError(exc.message, where=where) from None
    if dt is not None:
        dt = _check_given_dt(dt, where)
    fmt = resolve_format(format, where) if format else detect_format(path)
    stream = None
    if fmt is None:
        try:
            stream = _read_with_obspy(path, None, where)
        except _UnknownFormat as unknown:
            # gmprocess (the optional extra) before the suffix fallback: a DMG ".V2", a CWB
            # ".dat" or an ESM ".ASC" would otherwise be read as COSMOS or text and fail there.
            # A file with one of floorslide's suffixes that gmprocess fails on too is most
            # likely a malformed file of that format: its reader's error says what is wrong.
            by_suffix = SUFFIX_FORMATS.get(path.suffix.lower())
            try:
                stream = gmprocess_formats.read_gmprocess(path, where, detect=True)
            except RecordError:
                if by_suffix is None:
                    raise
                stream = None
            if stream is None:
                fmt = by_suffix
                if fmt is None:
                    raise _UnknownFormat(
                        gmprocess_formats.unknown_format_message(unknown.message), where=where
                    ) from None
            else:
                fmt = stream[0].stats._format
        else:
            fmt = stream[0].stats.get("_format") if len(stream) else None
    elif fmt == gmprocess_formats.FORMAT or fmt.startswith(gmprocess_formats.FORMAT_PREFIX):
        stream = gmprocess_formats.read_gmprocess(path, where)
        got = stream[0].stats._format
        if fmt != gmprocess_formats.FORMAT and got != fmt:
            raise RecordError(f"format {fmt!r} was given but gmprocess reads {got!r}", where=where)
        fmt = got
    entry = None
    if fmt == text.FORMAT:
        record = text.parse_text_record(path)
        if sidecar:
            entry, problem = _sidecar(path)
            missing = (record.dt is None and dt is None) or (
                record.units is None and given_units is None
            )
            if problem and missing:
                raise RecordError(
                    f"its dt or units are not given, and the {SIDECAR} next to it cannot be "
                    f"used: {problem}",
                    where=where,
                )
            if entry is not None:
                _check_sidecar(entry, record, dt, given_units, where)
                dt = dt if dt is not None else entry.dt
                if given_units is None and entry.units is not None:
                    given_units = entry.units
                component = component if component is not None else entry.component
        source = "the time column" if record.columns == 2 else "the header"
        step = text.check_dt(dt, record.dt, source, where)
        stream = text.record_to_stream(record, where, step)
        dt = None  # already checked against the file
    elif fmt in OWN_FORMATS:
        stream = OWN_FORMATS[fmt][1](path)
    elif stream is None:
        stream = _read_with_obspy(path, fmt, where)
    if len(stream) == 0:
        raise RecordError("no traces in the file", where=where)
    for trace in stream:
        trace.stats._format = fmt
        _normalise(trace, str(fmt), given_units, dt, where)
    stream = _select(stream, component, where)
    if entry is not None:
        for trace in stream:
            entry.check_npts(trace)
            entry.attach(trace)
    return stream


def _check_path(path: Path) -> None:
    where = str(path)
    if not path.exists():
        raise RecordError("no such file", where=where)
    if path.is_dir():
        raise RecordError(
            "is a directory; give a record file (floorslide inspect expands directories)",
            where=where,
        )
    try:
        size = path.stat().st_size
    except OSError as exc:
        raise RecordError(f"cannot read file: {exc.strerror or exc}", where=where) from None
    if size == 0:
        raise RecordError("empty file", where=where)


def _check_given_dt(dt: float, where: str) -> float:
    try:
        value = float(dt)
    except (TypeError, ValueError):
        raise RecordError(f"dt = {dt!r} is not a number of seconds", where=where) from None
    if not np.isfinite(value) or value <= 0:
        raise RecordError(f"dt = {dt!r}: the time step must be > 0 s", where=where)
    return value


def resolve_format(format: str, where: str = "") -> str:
    """The canonical name of a format given by the user (floorslide's or ObsPy's)."""
    key = format.strip()
    if key.lower() in FORMAT_ALIASES:
        return FORMAT_ALIASES[key.lower()]
    if key.lower().startswith(gmprocess_formats.FORMAT_PREFIX):  # as inspect shows it
        return key.lower()
    from obspy.core.util.base import ENTRY_POINTS

    known = {name.upper() for name in ENTRY_POINTS["waveform"]}
    if key.upper() in known:
        return key.upper()
    raise RecordError(
        f"unknown format {format!r}; floorslide reads AT2, COSMOSV2, text (plain text), "
        "the ObsPy formats (MSEED, SAC, KNET, GSE2, SEGY, ...) and, with the optional extra "
        "floorslide[gmprocess], gmprocess's (format 'gmprocess')",
        where=where or None,
    )


def detect_format(path: str | os.PathLike) -> str | None:
    """floorslide's own format of a file if it is one (cheap checks), else None (ObsPy decides)."""
    for name, (is_format, _) in OWN_FORMATS.items():
        if is_format(path):
            return name
    return None


def _read_with_obspy(path: Path, fmt: str | None, where: str) -> Stream:
    if fmt is None and _looks_like_catalog(path):
        raise RecordError(
            "is a record catalog, not a record; read it with read_catalog() "
            "(floorslide inspect reads catalogs)",
            where=where,
        )
    try:
        return obspy.read(str(path), format=fmt)
    except RecordError:
        raise
    except TypeError as exc:
        if fmt is None and "Unknown format" in str(exc):
            raise _UnknownFormat(
                "not a record in any format floorslide or ObsPy knows (PEER AT2, COSMOS V2, "
                "plain text with 1 or 2 numeric columns, MiniSEED, SAC, K-NET, ...)",
                where=where,
            ) from None
        raise RecordError(f"cannot read as {fmt}: {_one_line(exc)}", where=where) from None
    # Third-party readers raise arbitrary exception types on malformed input (struct.error,
    # IndexError, KeyError, custom ones ...); each becomes one RecordError naming the file.
    except Exception as exc:
        raise RecordError(
            f"cannot read as {fmt or 'detected format'}: {type(exc).__name__}: {_one_line(exc)}",
            where=where,
        ) from None


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())[:200] or type(exc).__name__


def _looks_like_catalog(path: Path) -> bool:
    from floorslide.records.catalog import is_catalog

    return is_catalog(path)


def _stated_units(trace: Trace, fmt: str, where: str) -> tuple[str | None, float]:
    """Units the file states for its values (canonical) and a pre-factor for counts formats."""
    stats = trace.stats
    if fmt == "KNET":
        # ObsPy: data are counts, calib = scale factor (gal/count) x 0.01 -> m/s**2.
        return "gal", float(stats.calib) * 100.0
    raw = stats.get("units")
    if raw:
        try:
            return canonical_units(raw), 1.0
        except UnitsError:
            raise UnitsError(
                f"the file gives unknown units {excerpt(raw)}; expected one of "
                f"{', '.join(FACTORS)}",
                where=where,
            ) from None
    return None, 1.0


def _stated_peak(trace: Trace, fmt: str) -> tuple[float, float | None, str, bool] | None:
    """The peak acceleration the file states for this trace, as ``(m/s², time in s or None,
    what the file says, whether it is the peak of the record less its mean)``, or None: a
    COSMOS text header's ``Max = … at … sec``, a K-NET header's ``Max. Acc. (gal)`` (of the
    record less its mean: raw K-NET records carry an offset), a DMG or GeoNet header read
    through gmprocess (``stats.stated_peak``, set by the readers)."""
    stats = trace.stats
    if fmt == "KNET" and "accmax" in stats.get("knet", {}):
        value = float(stats.knet.accmax)
        return value * FACTORS["gal"], None, f"Max. Acc. (gal) {value:g}", True
    said = stats.get("stated_peak")
    if not said:
        return None
    try:
        factor = FACTORS[canonical_units(str(said.units))]
    except UnitsError:
        return None  # units the check cannot read: no check
    time = said.get("time")
    value = abs(float(said.value)) * factor
    return value, None if time is None else float(time), said.text, False


def _check_stated_peak(trace: Trace, fmt: str, where: str) -> None:
    """Refuse samples that disagree with the peak acceleration the file's header states
    (:func:`_stated_peak`; docs/design.md §9): their largest magnitude must be within
    :data:`PEAK_TOLERANCE` of it and, when the header says when, reached within
    ``2·dt + 0.01 s`` of that time. A damaged time step (GeoNet ``0.0200`` → ``0.2000``) or
    damaged samples read silently as another record otherwise."""
    stated = _stated_peak(trace, fmt)
    if stated is None:
        return
    value, time, said, demeaned = stated
    data = trace.data - trace.data.mean() if demeaned else trace.data
    index = int(np.argmax(np.abs(data)))
    peak, dt = float(abs(data[index])), float(trace.stats.delta)
    found = (
        f"the samples{' less their mean' if demeaned else ''} peak at {peak:.6g} m/s² at "
        f"{index * dt:g} s (dt = {dt:g} s)"
    )
    if not value > 0 or abs(peak - value) > PEAK_TOLERANCE * value:
        raise RecordError(
            f"the header states the peak acceleration ({said!r}, {value:.6g} m/s²) but "
            f"{found}: header and samples disagree",
            where=where,
        )
    if time is None:
        return
    reach = 2.0 * dt + 0.01
    lo, hi = max(0, int(np.ceil((time - reach) / dt))), int(np.floor((time + reach) / dt)) + 1
    near = float(np.abs(data[lo:hi]).max()) if lo < min(hi, data.size) else 0.0
    if near < (1.0 - PEAK_TOLERANCE) * value:
        raise RecordError(
            f"the header states the peak acceleration at {time:g} s ({said!r}) but {found}: "
            "a damaged time step or damaged samples; header and samples disagree",
            where=where,
        )


def _normalise(
    trace: Trace, fmt: str, given_units: str | None, dt: float | None, where: str
) -> None:
    """Units to m/s², checks, and the normalised metadata of one trace (in place)."""
    stats = trace.stats
    if stats.npts == 0:
        raise RecordError("empty trace (no samples)", where=where)
    if not np.isfinite(stats.delta) or stats.delta <= 0:
        raise RecordError(f"time step {stats.delta!r} s: must be > 0", where=where)
    if dt is not None and abs(dt - stats.delta) > 1e-4 * stats.delta:
        raise RecordError(
            f"dt = {dt:g} s was given but the file says {stats.delta:.6g} s", where=where
        )
    stated, prefactor = _stated_units(trace, fmt, where)
    if stated is not None and given_units is not None and stated != given_units:
        raise UnitsError(
            f"units {given_units!r} were given but the file says {stated!r}", where=where
        )
    original = stated or given_units
    if original is None:
        hint = ""
        if fmt == "SAC" and int(stats.get("sac", {}).get("idep", -12345)) == _SAC_IACC:
            hint = " (its SAC header says IDEP=IACC, nominally nm/s**2, which writers often ignore)"
        raise UnitsError(
            f"{fmt} file without stated units{hint}; give them with units= / --units "
            f"({', '.join(list(FACTORS)[:5])})",
            where=where,
        )
    data = np.asarray(trace.data, dtype=np.float64)
    bad = ~np.isfinite(data)
    if bad.any():
        index = int(np.argmax(bad))
        raise RecordError(
            f"sample {index + 1}: {'NaN' if np.isnan(data[index]) else 'infinite'} value; "
            "a record must hold finite numbers",
            where=where,
        )
    factor = prefactor * FACTORS[original]
    trace.data = np.ascontiguousarray(data * factor) if factor != 1.0 else data.copy()
    if fmt == "KNET":
        stats.calib = 1.0
    stats.units = SI_UNITS
    stats.original_units = original
    if factor != 1.0:
        source = "counts x calib" if fmt == "KNET" else original
        note = (
            f"{PROCESSING_PREFIX}: convert_units(from={source!r}, to={SI_UNITS!r}, "
            f"factor={factor!r})"
        )
        stats.setdefault("processing", []).append(note)
    _check_stated_peak(trace, fmt, where)
    event, station, comp = _source_metadata(trace, fmt)
    stats.record = AttribDict(path=where, format=fmt, event=event, station=station, component=comp)


def _source_metadata(trace: Trace, fmt: str) -> tuple[str, str, str]:
    """Event, station and component as the format states them ('' when it does not)."""
    stats = trace.stats
    event, station, comp = "", stats.get("station", ""), ""
    if fmt == at2.FORMAT:
        meta = stats.at2
        event = meta.event
        if meta.date and meta.date not in event:
            event = f"{event}, {meta.date}"
        station, comp = meta.station, meta.component
    elif fmt == cosmos.FORMAT:
        meta = stats.cosmos
        event = meta.event
        station = stats.station or meta.station_name
        comp = meta.component
    elif fmt == text.FORMAT:
        header = stats.fstext.header
        event = header.get("event", "")
        station = header.get("station", station)
        comp = header.get("component", "")
    elif fmt == "KNET":
        knet = stats.get("knet", {})
        if "evot" in knet:
            event = f"{knet['evot']} M{knet.get('mag', '?')}"
    elif fmt == "SAC":
        name = str(stats.get("sac", {}).get("kevnm", "")).strip()
        event = "" if name in ("", "-12345") else name
    elif fmt.startswith(gmprocess_formats.FORMAT_PREFIX):
        event, station, comp = gmprocess_formats.source_metadata(trace)
    return event, station or "", comp or stats.get("channel", "")


def _names(trace: Trace) -> set[str]:
    channel = trace.stats.get("channel", "") or ""
    names = {trace.stats.record.get("component", ""), channel, channel[-1:]}
    return {n.strip().upper() for n in names if n and n.strip()}


def _select(stream: Stream, component: str | None, where: str) -> Stream:
    """The traces of ``stream`` matching ``component`` (see :func:`read_record`)."""
    if component is None or not str(component).strip():
        return stream
    wanted = str(component).strip().upper()
    if len(stream) == 1 and not _names(stream[0]):
        stream[0].stats.record.component = str(component).strip()
        return stream
    kept = [tr for tr in stream if wanted in _names(tr)]
    if not kept:
        have = sorted({tr.stats.record.component or tr.stats.channel for tr in stream})
        raise RecordError(
            f"no component {component!r} in this file; it holds {', '.join(map(str, have))}",
            where=where,
        )
    return Stream(kept)


def find_sidecar_entry(path: str | os.PathLike) -> CatalogEntry | None:
    """The row of ``index.csv`` next to ``path`` that lists it, or None (also when that
    catalog cannot be read)."""
    return _sidecar(Path(path))[0]


def _sidecar(path: Path) -> tuple[CatalogEntry | None, str | None]:
    """The row of the sidecar catalog that lists ``path`` (None if there is none), and why the
    sidecar cannot be used when it is a catalog that does not load (duplicate rows, a
    malformed line ...). A catalog of components serves too: its row for this component."""
    from floorslide.records.catalog import is_catalog, load_catalog

    sidecar = path.parent / SIDECAR
    if not sidecar.is_file() or not is_catalog(sidecar):
        return None, None
    try:
        entries = load_catalog(sidecar, components=True)
    except RecordError as exc:
        return None, str(exc)
    target = path.resolve()
    return next((e for e in entries if e.path.resolve() == target), None), None


def _check_sidecar(
    entry: CatalogEntry, record: text.TextRecord, dt: float | None, units: str | None, where: str
) -> None:
    """A dt or units given, or stated by the file, that contradicts its sidecar row is an
    error, as a contradiction with a file's header is (never applied silently)."""
    row = f"{entry.catalog.name} line {entry.line}"
    listed_dt, listed_units = entry.dt, entry.units
    if listed_dt is not None:
        for value, who in ((dt, "was given"), (record.dt, "is in the file")):
            if value is not None and abs(value - listed_dt) > 1e-4 * listed_dt:
                raise RecordError(
                    f"dt = {value:g} s {who} but {row} says {listed_dt:g} s", where=where
                )
    if listed_units is not None:
        for value, who in ((units, "were given"), (record.units, "are in the file")):
            if value is not None and value != listed_units:
                raise UnitsError(
                    f"units {value!r} {who} but {row} says {listed_units!r}", where=where
                )
