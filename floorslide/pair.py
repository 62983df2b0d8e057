"""Two horizontal components of one recording on one time base: the data class the numerical
core takes (:func:`floorslide.slide_plane`), free of any reader (the readers are in
:mod:`floorslide.records.pairs`; docs/design.md §10d).

Both components have the same ``dt`` (different ones are an error); the shorter is padded with
zeros to the longer — PEER publishes components of different lengths — and that is reported in
``notes``. The plane's frame is ``x`` along ``h1``, ``y`` along ``h2``; an angle is measured from
``h1`` towards ``h2``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from floorslide.errors import ModelError, RecordError


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
        return {"N": 0.0, "E": 90.0, "S": 180.0, "W": 270.0, "NS": 0.0, "EW": 90.0}.get(
            text.upper()
        )
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
        turn = (azimuths[1] - azimuths[0]) % 180.0
        between = min(turn, 180.0 - turn)  # the angle between the two axes, 0–90 degrees
        if 90.0 - between > 1e-6:
            how = (
                "parallel: both along one axis"
                if between < 1e-6
                else f"{between:g} degrees apart, {90.0 - between:g} degrees from perpendicular"
            )
            notes.append(
                f"components {names[0]} and {names[1]} are not perpendicular by their azimuths "
                f"({how}): the plane's frame takes them as x and y"
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


def as_pair(acc, dt: float | None) -> RecordPair:
    """The pair the plane's solvers take: a :class:`RecordPair` (`dt`, if given, must be its
    own), ``(a_x, a_y)`` or an array ``(2, npts)`` with `dt` (:func:`make_pair`).

    Raises
    ------
    ModelError
        No dt with arrays, a dt that differs from the pair's, anything else.
    """
    if isinstance(acc, RecordPair):
        if dt is not None and not np.isclose(float(dt), acc.dt, rtol=1e-9, atol=0.0):
            raise ModelError(f"dt={dt} differs from the pair's dt={acc.dt}", "dt")
        return acc
    if dt is None:
        raise ModelError("dt is required with arrays", "dt")
    if isinstance(acc, tuple | list) and len(acc) == 2:
        return make_pair(acc[0], acc[1], float(dt))
    arr = np.asarray(acc, dtype=float)
    if arr.ndim == 2 and arr.shape[0] == 2:
        return make_pair(arr[0], arr[1], float(dt))
    raise ModelError(
        "give the two horizontal components: a RecordPair, (a_x, a_y) or an array (2, npts)",
        "acc",
    )
