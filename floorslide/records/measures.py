"""Intensity measures of a ground-motion record, exact for the piecewise-linear record.

docs/design.md §2: a record is the piecewise-linear function through its samples. Within a step of
length ``h`` starting at sample ``k`` (``0 ≤ s ≤ h``, slope ``m = (a[k+1] − a[k])/h``)

.. math::

    a(s) = a_k + m s,\\qquad
    v(s) = v_k + a_k s + m s^2/2,\\qquad
    u(s) = u_k + v_k s + a_k s^2/2 + m s^3/6,

starting at rest (``v_0 = u_0 = 0``). Every measure here is computed from these closed forms,
vectorised over the steps (no Python loop over samples):

- **PGA** = max |a_k| (a linear segment peaks at its ends);
- **PGV** = max |v|, including the in-step extremum where ``a(s) = 0``
  (``s* = −a_k/m``, ``v* = v_k + a_k s*/2``) when a changes sign inside a step;
- **PGD** = max |u|, including in-step extrema at the roots of the quadratic ``v(s) = 0``;
- **Arias intensity** ``I_A = π/(2g) ∫ a² dt`` with ``∫ a² = h (a_k² + a_k a_{k+1} +
  a_{k+1}²)/3`` per step;
- **CAV** ``= ∫ |a| dt``: ``h (|a_k| + |a_{k+1}|)/2`` per step, or ``h (a_k² +
  a_{k+1}²) / (2 (|a_k| + |a_{k+1}|))`` when a changes sign inside it;
- **significant durations** D5–75 and D5–95 from the Husid curve ``E(t) = ∫_0^t a²``, which is
  cubic inside a step, ``E(s) = E_k + ((a_k + m s)^3 − a_k^3)/(3m)``; the instant it reaches a
  level ``L`` is ``s = 3Δ / (w² + w a_k + a_k²)`` with ``Δ = L − E_k`` and
  ``w = ∛(a_k³ + 3 m Δ)`` (a form without cancellation, also right for ``m = 0``).

References
----------
Arias, A. (1970). A measure of earthquake intensity. In R. J. Hansen (ed.), *Seismic Design for
Nuclear Power Plants*, MIT Press, 438–483.

Trifunac, M. D., Brady, A. G. (1975). A study on the duration of strong earthquake ground
motion. *Bulletin of the Seismological Society of America* 65(3), 581–626 (significant
duration between 5 % and 95 % of ∫a²).

EPRI (1988). *A criterion for determining exceedance of the operating basis earthquake*,
EPRI NP-5930 (cumulative absolute velocity, CAV).

Husid, R. (1969). Características de terremotos. Análisis general. *Revista del IDIEM* 8,
21–42 (the normalised cumulative ∫a² curve).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from floorslide.constants import G
from floorslide.errors import RecordError
from floorslide.inputs import RecordLike, is_stream, is_trace, trace_label, unwrap_record

MEASURE_KEYS = (
    "dt",
    "npts",
    "duration",
    "pga",
    "pga_g",
    "pgv",
    "pgd",
    "arias",
    "cav",
    "d5_75",
    "d5_95",
)
"""The numeric keys of :func:`measures`, in the order the command line prints them (the dict
also holds ``notes``)."""


def _as_record(
    trace_or_array: RecordLike, dt: float | None
) -> tuple[np.ndarray, float, tuple[str, ...]]:
    """Acceleration (float64, m/s²), dt and notes from a Trace, Stream or array, checked."""
    rec = unwrap_record(trace_or_array, dt, "trace_or_array", stacklevel=4)
    source = trace_or_array.traces[0] if is_stream(trace_or_array) else trace_or_array
    where = trace_label(source) if is_trace(source) else None
    acc, dt = np.asarray(rec.data, dtype=np.float64), rec.dt
    if dt is None:
        raise RecordError("measures of an array need dt (the time step in s)")
    if acc.ndim != 1 or acc.size == 0:
        raise RecordError(f"a record is a non-empty 1-D array, got shape {acc.shape}", where)
    if not np.isfinite(dt) or dt <= 0:
        raise RecordError(f"dt = {dt!r}: the time step must be > 0 s", where)
    if not np.all(np.isfinite(acc)):
        raise RecordError("the record holds NaN or infinite samples", where)
    return acc, float(dt), rec.notes


def velocity_displacement(acc: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Velocity and displacement at the samples, exact for the piecewise-linear record.

    Parameters
    ----------
    acc
        Acceleration samples (m/s²).
    dt
        Time step (s).

    Returns
    -------
    v, u : ndarray
        Velocity (m/s) and displacement (m) at the samples, starting at rest.
    """
    a0, a1 = acc[:-1], acc[1:]
    v = np.concatenate(([0.0], np.cumsum(0.5 * dt * (a0 + a1))))
    u_step = v[:-1] * dt + dt * dt * (2.0 * a0 + a1) / 6.0
    u = np.concatenate(([0.0], np.cumsum(u_step)))
    return v, u


def peak_velocity_displacement(acc: np.ndarray, dt: float) -> tuple[float, float]:
    """PGV and PGD of the piecewise-linear record, including peaks inside steps.

    Parameters
    ----------
    acc
        Acceleration samples (m/s²).
    dt
        Time step (s).

    Returns
    -------
    pgv, pgd : float
        max |v| (m/s) and max |u| (m) over the whole record, not only at the samples.

    Notes
    -----
    Velocity is quadratic in a step: its in-step extremum is where ``a(s) = 0``. Displacement
    is cubic: its in-step extrema are the roots of ``v_k + a_k s + (m/2) s² = 0`` in
    ``(0, h)``, found with the cancellation-free quadratic formula.
    """
    v, u = velocity_displacement(acc, dt)
    pgv = float(np.abs(v).max())
    pgd = float(np.abs(u).max())
    if acc.size < 2:
        return pgv, pgd
    a0, a1 = acc[:-1], acc[1:]
    slope = (a1 - a0) / dt
    vk, uk = v[:-1], u[:-1]

    crossing = a0 * a1 < 0
    if crossing.any():
        s = dt * a0[crossing] / (a0[crossing] - a1[crossing])
        pgv = max(pgv, float(np.abs(vk[crossing] + 0.5 * a0[crossing] * s).max()))

    qa, qb, qc = 0.5 * slope, a0, vk  # v(s) = qa s² + qb s + qc
    disc = qb * qb - 4.0 * qa * qc
    real = disc >= 0
    with np.errstate(divide="ignore", invalid="ignore"):
        q = -0.5 * (qb + np.copysign(np.sqrt(np.where(real, disc, 0.0)), qb))
        roots = (np.where(qa != 0, q / qa, np.nan), np.where(q != 0, qc / q, np.nan))
    for s in roots:
        inside = real & (s > 0) & (s < dt)
        if inside.any():
            si = s[inside]
            d = uk[inside] + si * (vk[inside] + si * (0.5 * a0[inside] + si * slope[inside] / 6))
            pgd = max(pgd, float(np.abs(d).max()))
    return pgv, pgd


def husid(acc: np.ndarray, dt: float) -> np.ndarray:
    """The cumulative ``∫_0^t a² dt`` at the samples (m²/s³), exact per linear step."""
    a0, a1 = acc[:-1], acc[1:]
    step = dt * (a0 * a0 + a0 * a1 + a1 * a1) / 3.0
    return np.concatenate(([0.0], np.cumsum(step)))


def arias_intensity(acc: np.ndarray, dt: float) -> float:
    """Arias intensity ``π/(2g) ∫ a² dt`` (m/s) of the piecewise-linear record (Arias 1970)."""
    return float(np.pi / (2.0 * G) * husid(acc, dt)[-1])


def cumulative_absolute_velocity(acc: np.ndarray, dt: float) -> float:
    """CAV ``= ∫ |a| dt`` (m/s), exact with the sign changes inside steps."""
    a0, a1 = acc[:-1], acc[1:]
    b0, b1 = np.abs(a0), np.abs(a1)
    same = a0 * a1 >= 0
    with np.errstate(divide="ignore", invalid="ignore"):
        crossing = (a0 * a0 + a1 * a1) / (2.0 * (b0 + b1))
    step = np.where(same, 0.5 * (b0 + b1), crossing)
    return float(dt * step.sum())


def husid_times(acc: np.ndarray, dt: float, fractions: Sequence[float]) -> np.ndarray:
    """Times (s from the first sample) at which ``∫_0^t a²`` reaches ``fractions`` of its total.

    Exact for the piecewise-linear record: inside the step where the level is crossed the
    cumulative integral is a cubic in time, inverted in closed form (module notes). Each time
    is the *first* instant the level is reached. NaN for a record with no energy.
    """
    energy = husid(acc, dt)
    total = energy[-1]
    levels = np.asarray(fractions, dtype=np.float64) * total
    if total <= 0:
        return np.full(levels.shape, np.nan)
    k = np.searchsorted(energy, levels, side="left")
    j = np.clip(k - 1, 0, max(acc.size - 2, 0))
    a = acc[j]
    slope = (acc[j + 1] - a) / dt
    delta = levels - energy[j]
    w = np.cbrt(a**3 + 3.0 * slope * delta)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(delta > 0, 3.0 * delta / (w * w + w * a + a * a), 0.0)
    s = np.clip(np.nan_to_num(s, nan=0.0), 0.0, dt)
    return np.where(k == 0, 0.0, j * dt + s)


def measures(
    trace_or_array: RecordLike, dt: float | None = None
) -> dict[str, float | int | tuple[str, ...]]:
    """Intensity measures of a record, exact for the piecewise-linear record.

    Parameters
    ----------
    trace_or_array
        An array of accelerations in m/s², or an ObsPy Trace or one-trace Stream: in m/s² as
        from :func:`floorslide.read_record`, or in another unit named by ``stats.units``
        (``g``, ``gal`` ...), converted to m/s² with a
        :class:`~floorslide.errors.UnitsConversionWarning` and a line in ``notes``; a trace
        without ``stats.units`` or in unknown units is refused (see :mod:`floorslide.inputs`).
    dt
        Time step in s; required for an array, optional (and checked) for a Trace.

    Returns
    -------
    dict
        ``dt`` (s), ``npts``, ``duration`` (``(npts−1)·dt``, s), ``pga`` (m/s²), ``pga_g`` (g),
        ``pgv`` (m/s), ``pgd`` (m), ``arias`` (m/s), ``cav`` (m/s), ``d5_75`` and ``d5_95``
        (s), in the order of :data:`MEASURE_KEYS`, then ``notes``: a tuple of what was done to
        the input (a Trace's unit conversion) and of the measures that are NaN and why (the
        durations of a record of zeros; measures beyond floating point for absurdly large
        samples), empty for ordinary data in m/s². The record starts at rest; nothing is
        filtered or baseline-corrected here (see :func:`floorslide.process`), so PGV and PGD
        are those of the record as given.

    Raises
    ------
    RecordError
        Empty or non-finite data, dt ≤ 0, no dt for an array, a dt that contradicts a Trace's
        ``stats.delta``, a Stream of several traces.
    UnitsError
        A Trace without ``stats.units`` or in units floorslide does not know.

    Notes
    -----
    See the module docstring for the closed forms. Cost: a few vectorised passes over the
    samples; a million samples take a fraction of a second.

    References
    ----------
    Arias (1970); Trifunac & Brady (1975); EPRI NP-5930 (1988) — see the module docstring.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(0, 10.0 + 1e-9, 0.01)
    >>> m = measures(np.sin(2 * np.pi * t), dt=0.01)
    >>> round(m["d5_95"], 9)
    9.0
    """
    acc, dt, notes = _as_record(trace_or_array, dt)
    pga = float(np.abs(acc).max())
    with np.errstate(over="ignore", invalid="ignore"):  # overflow: NaN and a note, below
        pgv, pgd = peak_velocity_displacement(acc, dt)
        t5, t75, t95 = husid_times(acc, dt, (0.05, 0.75, 0.95))
        values = {
            "dt": dt,
            "npts": int(acc.size),
            "duration": (acc.size - 1) * dt,
            "pga": pga,
            "pga_g": pga / G,
            "pgv": pgv,
            "pgd": pgd,
            "arias": arias_intensity(acc, dt),
            "cav": cumulative_absolute_velocity(acc, dt),
            "d5_75": float(t75 - t5),
            "d5_95": float(t95 - t5),
        }
    notes += _undefined(values)
    return {**values, "notes": notes}


def _undefined(values: dict) -> tuple[str, ...]:
    """Set the measures that are not numbers to NaN (in place) and say why: the significant
    durations when the Arias intensity is 0 (a record of zeros), and measures beyond floating
    point (samples so large that an integral overflows; the durations too when ∫a² does)."""
    durations = ("d5_75", "d5_95")
    if values["arias"] == 0:
        for key in durations:
            values[key] = float("nan")
        return ("d5_75, d5_95: undefined, the Arias intensity is 0 (a record of zeros)",)
    husid_overflows = not np.isfinite(values["arias"])
    beyond = [
        key
        for key in MEASURE_KEYS
        if not np.isfinite(values[key]) or (husid_overflows and key in durations)
    ]
    for key in beyond:
        values[key] = float("nan")
    if not beyond:
        return ()
    return (
        f"{', '.join(beyond)}: undefined, beyond floating point (samples up to "
        f"{values['pga']:.3g} m/s²)",
    )
