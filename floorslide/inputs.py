"""What the solvers accept as a record: samples and ``dt``, an ObsPy Trace, or a one-trace Stream.

docs/design.md §10: a solver given an ObsPy ``Trace`` takes its time step from ``stats.delta`` and
its
units from ``stats.units``; data in a unit other than m/s² are converted, never used raw, and
the conversion is recorded. The rules, for every solver (:func:`~floorslide.slide`,
:func:`~floorslide.slide_oscillator`, :func:`~floorslide.response_spectrum`,
:func:`~floorslide.floor_motions`, :func:`~floorslide.peak_floor_acceleration`,
:func:`~floorslide.measures`):

- **array** (any 1-D array-like): the samples in m/s² as given; ``dt`` is required. Arrays are
  used exactly as before (bit-identical results).
- **Trace**: ``dt`` may be left out (``None``); given, it must equal ``stats.delta``.
  ``stats.units`` must be set: ``m/s**2`` (in any spelling :func:`floorslide.units.canonical_units`
  knows) is used as is; another known unit (``g``, ``gal``, ``mg``, ``mm/s**2`` ...) is
  converted to m/s², with a :class:`~floorslide.errors.UnitsConversionWarning` and a line in
  the result's ``notes``; an unknown unit is refused with a one-line
  :class:`~floorslide.errors.UnitsError` naming it. A Trace **without** ``stats.units`` is
  refused too: ObsPy's own readers (MiniSEED, SAC, K-NET ...) do not set it, their data may be
  counts, gal or g, and floorslide never guesses. Set ``tr.stats.units`` or read the file with
  :func:`floorslide.read_record`, which always gives m/s² and ``stats.units = "m/s**2"``.
  A Trace with gaps (masked samples, e.g. after ``Stream.merge``) is refused.
- **Stream**: one trace, treated as that Trace; several traces are refused with a one-line
  error naming them (choose one, e.g. ``st.select(component="N")[0]``).

Duck-typed: a Stream is anything with ``.traces``, a Trace anything with ``.stats`` and
``.data``. This module imports neither ObsPy nor the numerical core (STYLE: the core stays free
of ObsPy), only NumPy, :mod:`floorslide.units` and :mod:`floorslide.errors`.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Protocol, TypeAlias

import numpy as np
from numpy.typing import ArrayLike

from floorslide.constants import MAX_ACCELERATION, G
from floorslide.errors import ModelError, RecordError, UnitsConversionWarning, UnitsError
from floorslide.units import FACTORS, SI_UNITS, canonical_units


class TraceLike(Protocol):
    """What floorslide needs of an ObsPy ``Trace``: ``stats`` (``delta``, ``units``) and
    ``data``."""

    stats: Any
    data: Any


class StreamLike(Protocol):
    """What floorslide needs of an ObsPy ``Stream``: its ``traces``."""

    traces: Sequence[TraceLike]


RecordLike: TypeAlias = ArrayLike | TraceLike | StreamLike
"""A record as the solvers accept it: samples (m/s²), an ObsPy Trace or a one-trace Stream."""

DT_RTOL = 1e-9
"""Relative tolerance within which a ``dt`` given with a Trace must equal ``stats.delta``."""


@dataclass(frozen=True)
class RecordInput:
    """A record unwrapped from what the caller gave.

    Attributes
    ----------
    data
        The samples: the caller's array as given, or a Trace's data (converted to m/s², float64,
        when its units were not m/s²).
    dt
        Time step, s (``None`` when an array came without one).
    notes
        What was done to the input (unit conversions), one line each.
    """

    data: Any
    dt: float | None
    notes: tuple[str, ...] = ()


def _stat(stats: Any, key: str) -> Any:
    """``stats[key]`` of an ObsPy ``Stats`` (or any mapping / object), None if absent."""
    getter = getattr(stats, "get", None)
    if callable(getter):
        return getter(key)
    return getattr(stats, key, None)


def trace_label(trace: TraceLike) -> str | None:
    """How a trace is named in messages: the file it was read from (``stats.record.path``, set
    by :func:`floorslide.read_record`), else its SEED id (``NET.STA.LOC.CHA``), else None."""
    record = _stat(trace.stats, "record")
    path = _stat(record, "path") if record is not None else None
    if path:
        return str(path)
    trace_id = getattr(trace, "id", "")
    if isinstance(trace_id, str) and trace_id.strip("."):
        return trace_id
    return None


def _component(trace: TraceLike, index: int) -> str:
    """A trace's component as its source names it: ``stats.record.component``, the channel,
    the format's own header (``stats.at2.component`` ...), else its position."""
    stats = trace.stats
    record = _stat(stats, "record")
    name = _stat(record, "component") if record is not None else None
    name = name or _stat(stats, "channel")
    fmt = _stat(stats, "_format")
    if not name and isinstance(fmt, str):
        header = _stat(stats, fmt.lower())
        name = _stat(header, "component") if header is not None else None
    return str(name or f"trace {index + 1}")


def is_trace(obj: object) -> bool:
    """True for an ObsPy Trace (anything with ``stats`` and ``data``)."""
    return hasattr(obj, "stats") and hasattr(obj, "data")


def is_stream(obj: object) -> bool:
    """True for an ObsPy Stream (anything with ``traces`` and no ``stats``)."""
    return hasattr(obj, "traces") and not hasattr(obj, "stats")


def unwrap_record(
    acc: RecordLike, dt: float | None, name: str = "acc", *, stacklevel: int = 3
) -> RecordInput:
    """Samples, time step and notes of what a solver was given (see the module notes).

    Parameters
    ----------
    acc
        An array of samples (returned as given), an ObsPy Trace or a one-trace Stream.
    dt
        Time step, s: required with an array (checked by the caller), optional with a Trace
        (must then equal ``stats.delta``).
    name
        The argument's name, for messages and notes (``"acc"``, ``"vertical"`` ...).
    stacklevel
        Passed to :func:`warnings.warn`, so the warning points at the user's call.

    Returns
    -------
    RecordInput

    Raises
    ------
    RecordError
        A Stream that is empty or holds several traces; a ``dt`` that contradicts
        ``stats.delta``; a Trace with gaps.
    UnitsError
        A Trace without ``stats.units`` or with units floorslide does not know.

    Warns
    -----
    UnitsConversionWarning
        When a Trace's data were converted to m/s² (the same text is in ``notes``).
    """
    if is_stream(acc):
        traces = list(acc.traces)
        if not traces:
            raise RecordError(f"{name} is an empty Stream (no traces)")
        if len(traces) > 1:
            names = ", ".join(_component(tr, i) for i, tr in enumerate(traces))
            raise RecordError(
                f"{name} is a Stream of {len(traces)} traces ({names}); give one trace, "
                "e.g. st.select(component='N')[0]"
            )
        acc = traces[0]
    if not is_trace(acc):
        return RecordInput(acc, dt)
    trace: TraceLike = acc  # type: ignore[assignment]
    where = trace_label(trace)
    stats = trace.stats
    delta = float(_stat(stats, "delta"))
    if dt is not None:
        try:
            given = float(dt)
        except (TypeError, ValueError):
            raise RecordError(f"dt = {dt!r} is not a number of seconds", where) from None
        if not abs(given - delta) <= DT_RTOL * abs(delta):
            raise RecordError(
                f"dt = {given:g} s was given but the trace's stats.delta is {delta:g} s "
                "(leave dt out to use the trace's)",
                where,
            )
    units = _stat(stats, "units")
    if units is None or (isinstance(units, str) and not units.strip()):
        calib = _stat(stats, "calib")
        counts = (
            f" (stats.calib = {calib:g}: the data are probably counts)"
            if isinstance(calib, float | int) and calib != 1
            else ""
        )
        raise UnitsError(
            f"the trace given as {name} has no stats.units, so the units of its data are "
            f"unknown{counts}; ObsPy's own readers (MiniSEED, SAC, K-NET ...) do not set them: "
            "read the file with floorslide.read_record(path, units=...) or set tr.stats.units "
            "('g', 'gal', 'm/s**2', 'mm/s**2')",
            where,
        )
    try:
        canonical = canonical_units(units)
    except UnitsError as exc:
        raise UnitsError(
            f"stats.units of the trace given as {name}: {exc.message}", where
        ) from None
    data = trace.data
    if np.ma.isMaskedArray(data) and np.ma.is_masked(data):
        raise RecordError(
            f"the trace given as {name} has gaps (masked samples); fill or split them first",
            where,
        )
    factor = FACTORS[canonical]
    if factor == 1.0:
        return RecordInput(np.ma.getdata(data), delta)
    converted = np.asarray(np.ma.getdata(data), dtype=np.float64) * factor
    source = f" of {where}" if where else ""
    note = f"{name}: data{source} converted from {str(units)!r} to {SI_UNITS!r} (factor {factor!r})"
    warnings.warn(note, UnitsConversionWarning, stacklevel=stacklevel)
    return RecordInput(converted, delta, (note,))


def check_amplitude(peak: float, name: str = "acc") -> None:
    """Refuse a record whose largest ``|sample|`` (m/s²) is beyond
    :data:`~floorslide.constants.MAX_ACCELERATION`, where the solvers' arithmetic would
    overflow (a ModelError naming `name`)."""
    if not peak <= MAX_ACCELERATION:
        raise ModelError(
            f"its samples reach {peak:.4g} m/s² ({peak / G:.4g} g), beyond the "
            f"{MAX_ACCELERATION / G:g} g the solvers take (no ground motion comes near; their "
            "arithmetic would overflow): check the units and the scaling",
            name,
        )


def check_record(acc: ArrayLike, dt: float | None, name: str = "acc") -> tuple[np.ndarray, float]:
    """A ground record as a finite 1-D float64 array and a positive time step.

    Raises
    ------
    ModelError
        Not a non-empty 1-D array, NaN or infinite samples or samples beyond
        :data:`~floorslide.constants.MAX_ACCELERATION`, no dt, dt ≤ 0.
    """
    a = np.ascontiguousarray(acc, dtype=float)
    if a.ndim != 1 or a.size == 0:
        raise ModelError(f"{name} must be a non-empty 1-D array of samples", name)
    # min/max propagate NaN and ±inf without an O(n) temporary
    lo, hi = a.min(), a.max()
    if not (np.isfinite(lo) and np.isfinite(hi)):
        raise ModelError(f"{name} has NaN or infinite samples", name)
    check_amplitude(max(-lo, hi), name)
    if dt is None:
        raise ModelError(
            f"dt (the time step, s) is required when {name} is an array of samples "
            "(an ObsPy Trace carries its own)",
            "dt",
        )
    dt = float(dt)
    if not np.isfinite(dt) or dt <= 0:
        raise ModelError(f"dt must be > 0, got {dt}", "dt")
    return a, dt


def as_record(
    acc: RecordLike, dt: float | None, name: str = "acc", *, stacklevel: int = 4
) -> tuple[np.ndarray, float, tuple[str, ...]]:
    """:func:`unwrap_record` then :func:`check_record`: the samples in m/s² (float64,
    contiguous), the time step and the notes.

    ``stacklevel`` counts from this function (default: the caller of the solver that called it).
    """
    rec = unwrap_record(acc, dt, name, stacklevel=stacklevel)
    a, step = check_record(rec.data, rec.dt, name)
    return a, step, rec.notes
