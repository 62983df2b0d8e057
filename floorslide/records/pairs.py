"""Two horizontal components of one recording (+ an optional vertical): record pairs.

A pair holds its components on one time base (docs/design.md §10d): both of the same ``dt``
(different ones are an error), the shorter padded with zeros to the longer — PEER publishes
components of different lengths — and that is reported in ``notes``. The plane's frame is
``x`` along ``h1``, ``y`` along ``h2``; an angle is measured from ``h1`` towards ``h2``
(:meth:`RecordPair.along`, :meth:`RecordPair.rotated`). Where the catalog names the components
by azimuth (``comp_h1 = 052``, ``comp_h2 = 142``) they are kept in ``azimuths``, and a pair
whose azimuths are not perpendicular is said so in ``notes``.

Pairs come from a catalog of components (``file_h1``, ``file_h2`` and optionally ``file_v``
columns, as ``data/records/pairs/index.csv``: :func:`read_pairs`), from two (three) files, one
multi-channel file or a K-NET recording's ``.NS``/``.EW`` files (:func:`read_pair`), or from
arrays (:func:`make_pair`).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np

from floorslide.errors import RecordError
from floorslide.pair import RecordPair, make_pair

__all__ = [
    "RecordPair",
    "check_components",
    "is_pair_catalog",
    "make_pair",
    "pair_id",
    "pair_rows",
    "read_pair",
    "read_pairs",
]


START_TOLERANCE = 60.0
"""Most seconds the start times of the two components of one recording may differ (when both
files state one): one instrument starts its channels together; components that start
minutes or hours apart are of different recordings (an aftershock, another earthquake)."""


def _said(trace, key: str) -> str:
    """``stats.record.<key>`` (event, station, path, component) as a comparable text ('' when
    the file does not say)."""
    rec = getattr(trace.stats, "record", None)
    value = rec.get(key, "") if rec is not None else ""
    return " ".join(str(value or "").split())


def _start(trace):
    """The start time a file states, or None (readers without one leave ObsPy's 1970-01-01)."""
    from obspy import UTCDateTime

    start = trace.stats.starttime
    return None if start == UTCDateTime(0) else start


def check_components(trace1, trace2, label1: str, label2: str, where: str | None = None) -> None:
    """Refuse two Traces that cannot be the two horizontal components of one recording.

    The rule (docs/design.md §10d), each a one-line :class:`~floorslide.errors.RecordError`
    naming both (``label1 + label2``, or ``where`` — a catalog line — and then the labels in
    the message):

    - the same file and component twice, or two components holding the same samples (one
      component given twice: its "pair" would be one motion along 45°, not the recording);
    - files whose metadata name different stations or different events (``stats.record``:
      the AT2 title, COSMOS and K-NET headers, a text header, the catalog's columns), compared
      without regard to case and spacing, when both name one;
    - start times more than :data:`START_TOLERANCE` apart, when both files state one.
    """
    both = f" ({label1}, {label2})" if where else ""
    where = where or f"{label1} + {label2}"
    path1, path2 = _said(trace1, "path"), _said(trace2, "path")
    same_file = bool(path1 and path2) and Path(path1).resolve() == Path(path2).resolve()
    if same_file and _said(trace1, "component") == _said(trace2, "component"):
        problem = (
            "the same file is given as both horizontal components; a pair is two components "
            "of one recording (the second horizontal's file as RECORD2, or file_h2)"
        )
        raise RecordError(problem + both, where)
    if trace1.stats.delta == trace2.stats.delta and np.array_equal(trace1.data, trace2.data):
        problem = (
            f"both components hold the same {trace1.stats.npts} samples: one component given "
            "twice, not two horizontal components of one recording"
        )
        raise RecordError(problem + both, where)
    for key in ("station", "event"):
        a, b = _said(trace1, key), _said(trace2, key)
        if a and b and a.casefold() != b.casefold():
            problem = (
                f"the components are of different {key}s ({a!r} and {b!r}); a pair is two "
                "horizontal components of one recording"
            )
            raise RecordError(problem + both, where)
    t1, t2 = _start(trace1), _start(trace2)
    if t1 is not None and t2 is not None and abs(t2 - t1) > START_TOLERANCE:
        problem = (
            f"the components start {abs(t2 - t1):.0f} s apart ({t1}, {t2}; at most "
            f"{START_TOLERANCE:g} s for one recording): two different recordings"
        )
        raise RecordError(problem + both, where)


def _one(stream, path) -> tuple[np.ndarray, float, str]:
    if len(stream) != 1:
        raise RecordError(f"{len(stream)} traces; a pair takes one per file", str(path))
    tr = stream[0]
    comp = ""
    rec = getattr(tr.stats, "record", None)
    if rec is not None:
        comp = str(getattr(rec, "component", "") or "")
    return np.asarray(tr.data, dtype=float), float(tr.stats.delta), comp or tr.stats.channel


_VERTICAL = {"UP", "UD", "DOWN", "DN", "Z", "V", "VER", "VERT", "VERTICAL"}
_KNET = re.compile(r"^(?P<stem>.+)\.(?P<dir>NS|EW|UD)(?P<n>[12]?)$", re.I)


def _component(tr) -> str:
    rec = getattr(tr.stats, "record", None)
    name = str(getattr(rec, "component", "") or "") if rec is not None else ""
    return (name or tr.stats.channel or "").strip()


def is_vertical(tr) -> bool:
    """Whether a Trace is a vertical component, by its component name (``Up``, ``UD``, ``V``
    ...) or a channel code ending in ``Z``."""
    name = _component(tr).upper().replace("DEG", "").strip()
    chan = (tr.stats.channel or "").upper()
    return name in _VERTICAL or name.startswith(("UP", "DOWN")) or chan.endswith("Z")


def _split(stream, path) -> tuple[list, object | None]:
    """The horizontal traces and the vertical one (or None) of a multi-channel stream."""
    vertical = [tr for tr in stream if is_vertical(tr)]
    horizontal = [tr for tr in stream if not is_vertical(tr)]
    names = ", ".join(_component(tr) or "?" for tr in stream)
    if len(horizontal) != 2 or len(vertical) > 1:
        raise RecordError(
            f"{len(horizontal)} horizontal and {len(vertical)} vertical component(s) ({names}); "
            "a pair takes two horizontal and at most one vertical",
            str(path),
        )
    return horizontal, (vertical[0] if vertical else None)


def knet_siblings(path: str | os.PathLike) -> tuple[Path, Path, Path | None] | None:
    """The ``.NS``, ``.EW`` and ``.UD`` files of a K-NET recording (``.NS1``/``.NS2`` ... for
    KiK-net's borehole and surface sensors) given any one of them, or None when the name is not
    K-NET's; the vertical is None when its file is absent."""
    p = Path(path)
    m = _KNET.match(p.name)
    if m is None:
        return None
    upper = m.group("dir").isupper()

    def sib(d: str) -> Path:
        return p.with_name(f"{m.group('stem')}.{d if upper else d.lower()}{m.group('n')}")

    ns, ew, ud = sib("NS"), sib("EW"), sib("UD")
    missing = [q.name for q in (ns, ew) if not q.is_file()]
    if missing:
        raise RecordError(
            f"K-NET pair: {', '.join(missing)} not found beside it (the pair is the .NS and "
            ".EW files of one recording)",
            str(path),
        )
    return ns, ew, (ud if ud.is_file() else None)


def read_pair(
    path_h1: str | os.PathLike,
    path_h2: str | os.PathLike | None = None,
    path_v: str | os.PathLike | None = None,
    *,
    format: str | None = None,
    units: str | None = None,
    dt: float | None = None,
) -> RecordPair:
    """A pair from two (three) record files, each read by
    :func:`~floorslide.records.read.read_record` (in m/s²), or from one file:

    - a multi-channel file (a COSMOS V2 file with three channels, a MiniSEED or SAC stream of
      ``HNN``/``HNE``/``HNZ`` ...): its two horizontal traces in the file's order, and its
      vertical (a component named ``Up``/``UD``/``V`` or a channel ending in ``Z``);
    - one file of a K-NET/KiK-net recording (``X.NS``, ``X.EW`` or ``X.UD``): the ``.NS``
      and ``.EW`` files beside it (``h1`` = NS, ``h2`` = EW) and ``.UD`` when present.

    Raises
    ------
    RecordError
        A file that cannot be read, one file with other than two horizontal components, a
        K-NET file whose partner is missing, components of different dt.
    """
    from floorslide.records.read import read_record

    def read(path):
        return read_record(path, format=format, units=units, dt=dt)

    if path_h2 is None:
        if path_v is not None:
            raise RecordError("path_v given without path_h2", str(path_v))
        stream = read(path_h1)
        if len(stream) == 1:
            sibs = knet_siblings(path_h1)
            if sibs is None:
                raise RecordError(
                    "one component in the file; a pair needs the second horizontal component "
                    "(read_pair(h1, h2)) or a multi-channel file",
                    str(path_h1),
                )
            return read_pair(*sibs, format=format, units=units, dt=dt)
        (t1, t2), tv = _split(stream, path_h1)
        check_components(t1, t2, f"{path_h1} ({_component(t1)})", f"{path_h1} ({_component(t2)})")
        name = Path(path_h1).name
        return make_pair(
            np.asarray(t1.data, dtype=float),
            np.asarray(t2.data, dtype=float),
            float(t1.stats.delta),
            None if tv is None else np.asarray(tv.data, dtype=float),
            names=(_component(t1) or "h1", _component(t2) or "h2"),
            label=name,
            dt2=float(t2.stats.delta),
            dt_v=None if tv is None else float(tv.stats.delta),
        )
    s1, s2 = read(path_h1), read(path_h2)
    a1, dt1, c1 = _one(s1, path_h1)
    a2, dt2, c2 = _one(s2, path_h2)
    check_components(s1[0], s2[0], str(path_h1), str(path_h2))
    av = dtv = None
    if path_v is not None:
        av, dtv, _ = _one(read(path_v), path_v)
    label = f"{Path(path_h1).name} + {Path(path_h2).name}"
    return make_pair(
        a1, a2, dt1, av, names=(c1 or "h1", c2 or "h2"), label=label, dt2=dt2, dt_v=dtv
    )


def is_pair_catalog(catalog: str | os.PathLike) -> bool:
    """Whether a catalog CSV names its records by component (``file_h1``, ``file_h2``
    columns): a set of pairs. False for a catalog with a ``file`` column or one that cannot be
    read (its reader then says why)."""
    import csv

    try:
        with open(catalog, newline="", encoding="utf-8-sig") as fh:
            for row in csv.reader(fh):
                if row and not row[0].lstrip().startswith("#"):
                    cols = {c.strip().lower() for c in row}
                    return "file_h1" in cols and "file_h2" in cols
    except (OSError, UnicodeDecodeError, csv.Error):
        return False
    return False


def pair_id(path_h1: str | os.PathLike, path_h2: str | os.PathLike) -> str:
    """A pair's record id: the common start of its components' file names (without extension)
    up to a separator (``RSN1084_NORTHR_SCS052`` + ``…SCS142`` → ``RSN1084_NORTHR_SCS``), or
    both names joined by ``+`` when they share none."""
    a, b = Path(path_h1).stem, Path(path_h2).stem
    n = 0
    while n < min(len(a), len(b)) and a[n] == b[n]:
        n += 1
    common = a[:n].rstrip("_-. ")
    return common if len(common) >= 3 and common != a and common != b else f"{a}+{b}"


def pair_rows(catalog: str | os.PathLike, where=None) -> list[dict]:
    """The rows of a catalog of components, not read: per row its ``line``, ``id``
    (:func:`pair_id`) and the :class:`~floorslide.records.catalog.CatalogEntry` of each
    component (``file_h1``, ``file_h2``, ``file_v`` or None)."""
    from floorslide.records.catalog import load_catalog

    entries = load_catalog(catalog, where=where, components=True)
    rows: dict[int, dict[str, object]] = {}
    for e in entries:
        rows.setdefault(e.line, {})[e.column] = e
    out = []
    for line, cols in rows.items():
        if "file_h1" not in cols or "file_h2" not in cols:
            raise RecordError(
                "a pair needs file_h1 and file_h2 (a catalog of components)",
                f"{catalog}:{line}",
            )
        e1, e2 = cols["file_h1"], cols["file_h2"]
        out.append(
            dict(line=line, id=pair_id(e1.path, e2.path), h1=e1, h2=e2, v=cols.get("file_v"))
        )
    return out


def read_pairs(catalog: str | os.PathLike, where=None) -> list[RecordPair]:
    """The pairs of a catalog of components (a row per recording, columns ``file_h1``,
    ``file_h2``, optionally ``file_v``, and ``dt``, ``units``; ``comp_h1``/``comp_h2`` name
    the components), filtered by `where` as :func:`~floorslide.records.catalog.load_catalog`.

    Raises
    ------
    RecordError
        A catalog without ``file_h1`` and ``file_h2``, a file that cannot be read, components
        of different dt; naming the catalog line.
    """
    out = []
    for row in pair_rows(catalog, where):
        e1, e2, ev = row["h1"], row["h2"], row["v"]
        s1, s2 = e1.read(), e2.read()
        a1, dt1, _ = _one(s1, e1.path)
        a2, dt2, _ = _one(s2, e2.path)
        where = f"{catalog}:{row['line']}"
        check_components(s1[0], s2[0], e1.path.name, e2.path.name, where)
        av = dtv = None
        if ev is not None:
            av, dtv, _ = _one(ev.read(), ev.path)
        names = (e1.row.get("comp", "") or "h1", e2.row.get("comp", "") or "h2")
        out.append(
            make_pair(
                a1, a2, dt1, av, names=names, label=f"{catalog}:{row['line']}", dt2=dt2, dt_v=dtv
            )
        )
    return out
