"""More strong-motion formats through USGS gmprocess, the optional extra ``floorslide[gmprocess]``.

`gmprocess <https://code.usgs.gov/ghsc/esi/groundmotion-processing>`_ (USGS, public domain) reads
the formats of many strong-motion networks that neither floorslide nor ObsPy know: DMG/CSMIP
V1/V2, GeoNet V1A/V2A, Taiwan CWB, Mexico UNAM, USGS SMC, ESM, BHRC, RENADIC, NSMN, USC ...
When it is installed (``pip install "floorslide[gmprocess]"``), :func:`floorslide.read_record`
gives it every file that floorslide's own readers and ObsPy do not recognise (``format=
"gmprocess"`` sends a file there directly), and turns what it reads into floorslide's record
convention:

- acceleration only: gmprocess says what each trace holds (``stats.standard.units_type``);
  velocity and displacement traces are dropped, and a file without acceleration is an error;
- units from what gmprocess states for the data it returns (``stats.standard.units``, which its
  readers set to ``cm/s^2`` or ``cm/s/s`` after converting the file's own units, e.g. GeoNet's
  mm/s²), parsed by :func:`~floorslide.records.units.canonical_units` — never assumed: a unit
  that is not an acceleration unit is an error. :func:`floorslide.read_record` then converts to
  m/s² and notes the factor in ``stats.processing``, as for every format;
- metadata kept: network, station, location, channel and start time as gmprocess gives them,
  ``stats.gmprocess`` (a plain dict of gmprocess's ``stats.standard`` and ``stats.coordinates``
  fields and the gmprocess version), and ``stats.record.format = "gmprocess:<its format>"``
  (``gmprocess:dmg``, ``gmprocess:geonet``, ``gmprocess:cwb``, ``gmprocess:unam`` ...).

Without gmprocess, a file that no reader knows is the usual one-line error, which then names the
extra. gmprocess is imported only when a file needs it (its first read takes seconds: it tries
its readers one by one and imports them as it goes).
"""

from __future__ import annotations

import logging
import math
import re
import warnings
from contextlib import contextmanager
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

import numpy as np
from obspy import Stream, Trace
from obspy.core import AttribDict

from floorslide.errors import RecordError, UnitsError
from floorslide.records.units import FACTORS, canonical_units

FORMAT = "gmprocess"
"""The ``format=`` name that sends a file to gmprocess; read traces carry ``gmprocess:<name>``."""

FORMAT_PREFIX = f"{FORMAT}:"

INSTALL_HINT = (
    "more formats (DMG/CSMIP V1/V2, GeoNet V1A/V2A, CWB, UNAM, SMC, ESM, BHRC, RENADIC ...) are "
    'read with the optional extra: pip install "floorslide[gmprocess]"'
)
"""What an error says when a file would need gmprocess and it is not installed."""

_ACC = "acc"
_STANDARD_SKIP: set[str] = set()  # every stats.standard field is kept


class GmprocessUnknown(RecordError):
    """gmprocess is installed but does not recognise the file."""


def _import_read_data():
    """gmprocess's reader, or None when gmprocess is not installed.

    Raises
    ------
    RecordError
        If gmprocess is installed but cannot be imported (a missing or broken dependency).
    """
    try:
        from gmprocess.io.read import read_data
    except ModuleNotFoundError as exc:
        if exc.name == "gmprocess" or (exc.name or "").startswith("gmprocess."):
            return None
        raise RecordError(
            f"gmprocess is installed but cannot be imported ({exc}); reinstall it: "
            'pip install "floorslide[gmprocess]"'
        ) from None
    except Exception as exc:  # an import can fail in any way in a third-party package
        raise RecordError(
            f"gmprocess is installed but cannot be imported ({type(exc).__name__}: "
            f"{' '.join(str(exc).split())[:200]}); reinstall it: "
            'pip install "floorslide[gmprocess]"'
        ) from None
    return read_data


def available() -> bool:
    """Whether gmprocess can be imported (imports it: this takes a moment the first time)."""
    return _import_read_data() is not None


def gmprocess_version() -> str:
    """The installed gmprocess version, or ``"unknown"``."""
    try:
        return version("gmprocess")
    except PackageNotFoundError:
        return "unknown"


def unknown_format_message(base: str) -> str:
    """The message for a file that floorslide and ObsPy do not know and gmprocess could not
    read either: ``base`` plus the install hint when gmprocess is missing, or plus the fact that
    gmprocess does not know it either."""
    if _import_read_data() is None:
        return f"{base}; {INSTALL_HINT}"
    return (
        f"{base}; nor does gmprocess {gmprocess_version()} (DMG/CSMIP, GeoNet, CWB, UNAM, SMC, "
        "ESM ...)"
    )


def read_gmprocess(path: str | Path, where: str, detect: bool = False) -> Stream | None:
    """Read a file with gmprocess, as acceleration traces in floorslide's record convention.

    Parameters
    ----------
    path
        The record file.
    where
        How errors name the file.
    detect
        True when floorslide is only trying gmprocess on a file nobody else knew: then a missing
        gmprocess, or a file gmprocess does not recognise, returns None instead of raising.

    Returns
    -------
    obspy.Stream or None
        One Trace per acceleration channel, data float64 in the units gmprocess states (in
        ``stats.units``; :func:`floorslide.read_record` converts them to m/s²),
        ``stats.gmprocess`` and ``stats._format = "gmprocess:<name>"``. None only with
        ``detect=True`` (see above).

    Raises
    ------
    RecordError
        gmprocess missing (naming the extra), not recognising the file, failing on it, or the
        file holding no acceleration — one line naming the file.
    UnitsError
        gmprocess states units that are not an acceleration unit floorslide knows.
    """
    read_data = _import_read_data()
    if read_data is None:
        if detect:
            return None
        raise RecordError(
            f"format {FORMAT!r} needs gmprocess, which is not installed; {INSTALL_HINT}",
            where=where,
        )
    try:
        with warnings.catch_warnings(), _capture_logs() as notes:
            # gmprocess's format checks leave files open (ResourceWarning); its readers log what
            # they assume through the root logger. Neither reaches the caller's console: the
            # log lines are kept with the traces (stats.gmprocess["log"]).
            warnings.simplefilter("ignore")
            streams = read_data(str(path))
    except (KeyboardInterrupt, SystemExit):
        raise
    except BaseException as exc:  # some gmprocess readers raise a bare BaseException
        text = " ".join(str(exc).split())
        if "No format found" in text:
            if detect:
                return None
            raise GmprocessUnknown(
                f"not a record in any format gmprocess {gmprocess_version()} knows", where=where
            ) from None
        raise RecordError(
            f"cannot read with gmprocess {gmprocess_version()}: {type(exc).__name__}: "
            f"{text[:200] or type(exc).__name__}",
            where=where,
        ) from None
    stream = to_record_stream(streams, where)
    for trace in stream:
        trace.stats.gmprocess["log"] = list(notes)
    _attach_stated_peaks(stream, path)
    return stream


STATED_PEAK = {
    "dmg": re.compile(
        r"PEAK\s+ACCELERATION\s*=\s*([-+]?[\d.]+(?:[eE][-+]?\d+)?)\s+(\S+)\s+AT\s+([\d.]+)\s+SEC"
    ),
    "geonet": re.compile(
        r"Acceleration:\s+Peak\s+([-+]?[\d.]+(?:[eE][-+]?\d+)?)\s+(\S+)\s+at\s+([\d.]+)\s*s\b"
    ),
}
"""The header line stating a channel's peak acceleration and its time, per gmprocess format
(DMG/CSMIP: ``PEAK ACCELERATION =  -267.957    CM/SEC/SEC  AT   10.940   SEC.``; GeoNet
V1A/V2A: ``Acceleration:  Peak  -2080.5 mm/s/s at  23.28 s``): one per channel, in the
channels' order. gmprocess reads neither; :func:`floorslide.records.read.read_record`
checks the samples against them (a damaged GeoNet time step read silently otherwise)."""


def _attach_stated_peaks(stream: Stream, path: str | Path) -> None:
    """``stats.stated_peak`` of each trace from its header line (:data:`STATED_PEAK`), when the
    file states one per acceleration trace read (else none: they cannot be matched)."""
    by_format: dict[str, list[Trace]] = {}
    for trace in stream:
        by_format.setdefault(trace.stats._format.removeprefix(FORMAT_PREFIX), []).append(trace)
    for name, traces in by_format.items():
        pattern = STATED_PEAK.get(name)
        if pattern is None:
            continue
        try:
            with open(path, encoding="latin-1") as fh:
                found = [m for m in map(pattern.search, fh) if m is not None]
        except OSError:
            return
        if len(found) != len(traces):
            continue
        for trace, match in zip(traces, found, strict=True):
            trace.stats.stated_peak = AttribDict(
                value=float(match.group(1)),
                units=match.group(2),
                time=float(match.group(3)),
                text=" ".join(match.group(0).split()),
            )


@contextmanager
def _capture_logs():
    """Collect what is logged to the root logger meanwhile (gmprocess logs with
    ``logging.warning``), without printing it; the list of messages is yielded.

    While a handler is attached, ``logging.warning`` does not call ``logging.basicConfig``,
    which would otherwise install a console handler on the root logger for good.
    """
    messages: list[str] = []

    class _Keep(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            try:
                messages.append(f"{record.levelname}: {record.getMessage()}")
            except Exception:  # a malformed log call in a third-party package
                messages.append(f"{record.levelname}: {record.msg!r}")

    root = logging.getLogger()
    handler = _Keep(level=logging.WARNING)
    root.addHandler(handler)
    try:
        yield messages
    finally:
        root.removeHandler(handler)


def to_record_stream(streams: Any, where: str) -> Stream:
    """gmprocess's StationStreams (a list, or one stream) as one Stream of acceleration Traces.

    Parameters
    ----------
    streams
        What ``gmprocess.io.read.read_data`` returns: a list of StationStreams whose traces carry
        ``stats.standard`` (``units_type``, ``units``, ``source_format`` ...) and
        ``stats.coordinates``.
    where
        How errors name the file.

    Returns
    -------
    obspy.Stream
        Plain ObsPy Traces (not StationTraces): float64 data as gmprocess returned them,
        network/station/location/channel/starttime/delta, ``stats.units`` the units gmprocess
        states, ``stats.gmprocess`` and ``stats._format``.

    Raises
    ------
    RecordError
        No trace, or no acceleration trace (the types found are named).
    UnitsError
        Units gmprocess states that are not an acceleration unit floorslide knows.
    """
    if isinstance(streams, Stream):
        streams = [streams]
    traces = [trace for stream in streams or [] for trace in stream]
    if not traces:
        raise RecordError("gmprocess read no traces from the file", where=where)
    kept = [tr for tr in traces if _standard(tr).get("units_type") == _ACC]
    if not kept:
        kinds = sorted({str(_standard(tr).get("units_type") or "unstated") for tr in traces})
        raise RecordError(
            f"no acceleration in the file: gmprocess reads it as {', '.join(kinds)} only",
            where=where,
        )
    gmp_version = gmprocess_version()
    return Stream([_to_trace(tr, where, gmp_version) for tr in kept])


def _standard(trace: Trace) -> dict:
    return dict(trace.stats.get("standard", None) or {})


def _to_trace(trace: Trace, where: str, gmp_version: str) -> Trace:
    """One gmprocess StationTrace as a plain ObsPy Trace with floorslide's metadata."""
    stats = trace.stats
    standard = _standard(trace)
    raw_units = str(standard.get("units") or "").strip()
    try:
        canonical = canonical_units(raw_units)
    except UnitsError:
        raise UnitsError(
            f"gmprocess gives units {raw_units!r} for {stats.get('channel', '?')}; expected an "
            f"acceleration unit ({', '.join(FACTORS)})",
            where=where,
        ) from None
    source_format = str(standard.get("source_format") or "unknown").strip().lower()
    out = Trace(data=np.array(trace.data, dtype=np.float64, copy=True))
    for key in ("network", "station", "location", "channel", "starttime"):
        if key in stats:
            out.stats[key] = stats[key]
    out.stats.delta = float(stats.delta)
    meta = {key: _plain(value) for key, value in standard.items() if key not in _STANDARD_SKIP}
    for key, value in dict(stats.get("coordinates", None) or {}).items():
        meta[key] = _plain(value)
    meta["units_canonical"] = canonical
    meta["gmprocess_version"] = gmp_version
    out.stats.gmprocess = AttribDict(meta)
    out.stats.units = raw_units
    out.stats._format = f"{FORMAT_PREFIX}{source_format}"
    return out


def _plain(value: Any) -> Any:
    """A value of gmprocess's metadata as a plain Python value (no NumPy scalars or datetimes
    that a JSON report could not hold)."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and math.isnan(value):
        return None
    if isinstance(value, (str, int, float, bool)) or value is None:
        return value
    return str(value)


def source_metadata(trace: Trace) -> tuple[str, str, str]:
    """Event, station and component of a trace read through gmprocess ('' when unknown).

    gmprocess keeps no event in what its readers return (it takes events from its own
    catalogue files), so the event is empty; the station is the station code (its name is in
    ``stats.gmprocess["station_name"]``); the component is the channel code (``HN1``, ``HNZ``
    ...), whose orientation is ``stats.gmprocess["horizontal_orientation"]``.
    """
    stats = trace.stats
    return "", str(stats.get("station", "") or ""), str(stats.get("channel", "") or "")
