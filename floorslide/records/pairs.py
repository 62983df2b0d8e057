"""Two horizontal components of one recording (+ an optional vertical): record pairs.

A pair holds its components on one time base (docs/design.md §10d): both of the same ``dt``
(different ones are an error), the shorter padded with zeros to the longer — PEER publishes
components of different lengths — and that is reported in ``notes``. The plane's frame is
``x`` along ``h1``, ``y`` along ``h2``; an angle is measured from ``h1`` towards ``h2``
(:meth:`RecordPair.along`, :meth:`RecordPair.rotated`). Where the catalog names the components
by azimuth (``comp_h1 = 052``, ``comp_h2 = 142``) they are kept in ``azimuths``, and a pair
whose azimuths are not perpendicular is said so in ``notes``.

Pairs come from a catalog of components (``file_h1``, ``file_h2`` and optionally ``file_v``
columns, as ``data/records/pairs/index.csv``: :func:`read_pairs`), from two (three) files
(:func:`read_pair`) or from arrays (:func:`make_pair`).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from floorslide.errors import RecordError
from floorslide.pair import RecordPair, make_pair

__all__ = ["RecordPair", "make_pair", "read_pair", "read_pairs"]


def _one(stream, path) -> tuple[np.ndarray, float, str]:
    if len(stream) != 1:
        raise RecordError(f"{len(stream)} traces; a pair takes one per file", str(path))
    tr = stream[0]
    comp = ""
    rec = getattr(tr.stats, "record", None)
    if rec is not None:
        comp = str(getattr(rec, "component", "") or "")
    return np.asarray(tr.data, dtype=float), float(tr.stats.delta), comp or tr.stats.channel


def read_pair(
    path_h1: str | os.PathLike,
    path_h2: str | os.PathLike,
    path_v: str | os.PathLike | None = None,
    *,
    format: str | None = None,
    units: str | None = None,
    dt: float | None = None,
) -> RecordPair:
    """A pair from two (three) record files, each read by
    :func:`~floorslide.records.read.read_record` (in m/s²)."""
    from floorslide.records.read import read_record

    a1, dt1, c1 = _one(read_record(path_h1, format=format, units=units, dt=dt), path_h1)
    a2, dt2, c2 = _one(read_record(path_h2, format=format, units=units, dt=dt), path_h2)
    av = dtv = None
    if path_v is not None:
        av, dtv, _ = _one(read_record(path_v, format=format, units=units, dt=dt), path_v)
    label = f"{Path(path_h1).name} + {Path(path_h2).name}"
    return make_pair(
        a1, a2, dt1, av, names=(c1 or "h1", c2 or "h2"), label=label, dt2=dt2, dt_v=dtv
    )


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
        e1, e2, ev = cols["file_h1"], cols["file_h2"], cols.get("file_v")
        s1, s2 = e1.read(), e2.read()
        a1, dt1, _ = _one(s1, e1.path)
        a2, dt2, _ = _one(s2, e2.path)
        av = dtv = None
        if ev is not None:
            av, dtv, _ = _one(ev.read(), ev.path)
        names = (e1.row.get("comp", "") or "h1", e2.row.get("comp", "") or "h2")
        out.append(
            make_pair(a1, a2, dt1, av, names=names, label=f"{catalog}:{line}", dt2=dt2, dt_v=dtv)
        )
    return out
