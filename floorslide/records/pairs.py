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
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from floorslide.errors import RecordError


@dataclass(frozen=True)
class RecordPair:
    """Two horizontal components of one recording on one time base.

    Attributes
    ----------
    h1, h2
        Accelerations along the two horizontal axes, m/s² (equal lengths).
    dt
        Time step, s.
    vertical
        The vertical component (same length), m/s², or None.
    names
        The components' names (``("052", "142")``, ``("E", "N")``).
    azimuths
        The components' azimuths in degrees when their names are numbers, else None.
    label
        Where the pair came from (``catalog:line`` or the file names).
    notes
        What was done to the components (padding), or noticed (not perpendicular).
    """

    h1: np.ndarray
    h2: np.ndarray
    dt: float
    vertical: np.ndarray | None = None
    names: tuple[str, str] = ("h1", "h2")
    azimuths: tuple[float, float] | None = None
    label: str = ""
    notes: tuple[str, ...] = field(default=())

    @property
    def npts(self) -> int:
        """Number of samples of each component."""
        return int(self.h1.size)

    @property
    def duration(self) -> float:
        """Duration, s."""
        return (self.npts - 1) * self.dt

    @property
    def plane(self) -> np.ndarray:
        """Both components as one array ``(2, npts)``: ``x`` (h1) and ``y`` (h2)."""
        return np.vstack([self.h1, self.h2])

    def along(self, angle: float) -> np.ndarray:
        """The acceleration along the direction at `angle` degrees from ``h1`` towards ``h2``:
        ``h1·cos θ + h2·sin θ``."""
        th = np.deg2rad(float(angle))
        return self.h1 * np.cos(th) + self.h2 * np.sin(th)

    def rotated(self, angle: float) -> RecordPair:
        """The same motion on axes turned by `angle` degrees (from ``h1`` towards ``h2``): its
        ``h1`` is :meth:`along` ``(angle)``, its ``h2`` along ``angle + 90``."""
        az = None
        if self.azimuths is not None:
            # h2 90° clockwise of h1 (compass) turns the azimuths by +angle, 90° anticlockwise
            # by −angle; components not perpendicular keep no azimuths
            step = (self.azimuths[1] - self.azimuths[0]) % 360.0
            turn = 1.0 if abs(step - 90.0) < 1e-6 else -1.0 if abs(step - 270.0) < 1e-6 else 0.0
            if turn:
                az = tuple(float((a + turn * angle) % 360.0) for a in self.azimuths)
        return RecordPair(
            self.along(angle),
            self.along(angle + 90.0),
            self.dt,
            self.vertical,
            (f"{self.names[0]}{angle:+g}", f"{self.names[1]}{angle:+g}"),
            az,
            self.label,
            (*self.notes, f"axes turned by {angle:g} degrees from h1 towards h2"),
        )


def _azimuth(name: str) -> float | None:
    text = name.strip()
    try:
        value = float(text)
    except ValueError:
        return {"N": 0.0, "E": 90.0, "S": 180.0, "W": 270.0}.get(text.upper())
    return value if np.isfinite(value) else None


def make_pair(
    h1,
    h2,
    dt: float,
    vertical=None,
    *,
    names: tuple[str, str] = ("h1", "h2"),
    label: str = "",
    dt2: float | None = None,
    dt_v: float | None = None,
) -> RecordPair:
    """A :class:`RecordPair` from arrays (m/s²): the shorter components padded with zeros to
    the longest, and said so; ``dt2`` / ``dt_v`` (the other components' steps, when known)
    must equal ``dt`` to 1e-9 relative.

    Raises
    ------
    RecordError
        Components of different dt, empty or non-finite ones.
    """
    where = label or None
    for name, other in (("h2", dt2), ("vertical", dt_v)):
        if other is not None and not abs(float(other) - float(dt)) <= 1e-9 * float(dt):
            raise RecordError(
                f"the components have different time steps: h1 {dt:g} s, {name} {other:g} s "
                "(resample one of them first)",
                where,
            )
    if not (np.isfinite(dt) and dt > 0):
        raise RecordError(f"dt must be > 0 s, got {dt!r}", where)
    comps = {"h1": h1, "h2": h2}
    if vertical is not None:
        comps["vertical"] = vertical
    arrays = {}
    for name, value in comps.items():
        a = np.asarray(value, dtype=float).ravel()
        if a.size < 2:
            raise RecordError(
                f"component {name} has {a.size} samples; at least 2 are needed", where
            )
        if not np.all(np.isfinite(a)):
            raise RecordError(f"component {name} holds NaN or infinite values", where)
        arrays[name] = a
    n = max(a.size for a in arrays.values())
    notes = []
    for name, a in arrays.items():
        if a.size < n:
            notes.append(
                f"{name} ({names[0] if name == 'h1' else names[1] if name == 'h2' else 'v'}): "
                f"{a.size} samples, padded with {n - a.size} zero(s) to {n} (the longest "
                "component's length)"
            )
            arrays[name] = np.concatenate([a, np.zeros(n - a.size)])
    az = (_azimuth(names[0]), _azimuth(names[1]))
    azimuths = None
    if az[0] is not None and az[1] is not None:
        azimuths = (az[0] % 360.0, az[1] % 360.0)
        off = abs(((azimuths[1] - azimuths[0]) % 180.0) - 90.0)
        if off > 1e-6:
            notes.append(
                f"components {names[0]} and {names[1]} are not perpendicular by their azimuths "
                f"({off:g} degrees off): the plane's frame takes them as x and y"
            )
    return RecordPair(
        arrays["h1"],
        arrays["h2"],
        float(dt),
        arrays.get("vertical"),
        (str(names[0]), str(names[1])),
        azimuths,
        label,
        tuple(notes),
    )


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
