"""Target spectra and amplitude scaling of records to them (docs/design.md §10e).

A target is the two-point design spectrum of ASCE 7-22 §11.4.6 from ``S_DS``, ``S_D1`` and
``T_L``, or a table of ``(T, S_a)``. A record's spectrum is scaled by one factor: the one that
minimises the mean squared misfit of the logarithms over a period range (closed form: the
geometric mean of the target-to-record ratios), or the one that matches the target at one
period. A suite of scaled records is checked as ASCE 7-22 §16.2.3 does: its mean spectrum must
not fall below 90 % of the target anywhere in the range.

Spectral accelerations are in units of g throughout (as codes give them).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from floorslide.errors import ModelError
from floorslide.text_numbers import parse_number, underscore_hint

FACTOR_LIMITS = (0.25, 4.0)
"""Scale factors outside this range are flagged: a record scaled that far is a different
earthquake (its duration and frequency content no longer match the amplitude)."""

SUITE_FRACTION = 0.9
"""ASCE 7-22 §16.2.3: the suite's mean spectrum is at least 90 % of the target over the range."""

MAX_TARGET_BYTES = 10 * 2**20
"""Largest target-spectrum CSV read (10 MiB, about 300 000 rows): a target spectrum has at
most a few thousand rows; a larger file is not one (and is refused before it is read)."""

MAX_TARGET_ROWS = 100_000
"""Most ``(T, S_a)`` rows a target-spectrum CSV may hold."""


@dataclass(frozen=True)
class TargetSpectrum:
    """A target response spectrum ``S_a(T)`` in g.

    Use :meth:`two_point` or :meth:`from_table`. Between the periods of a table ``S_a`` is
    interpolated linearly in log–log coordinates (``T = 0`` linearly); a period outside the table
    is an error.
    """

    periods: np.ndarray
    sa: np.ndarray
    name: str = ""
    params: dict = field(default_factory=dict)

    @classmethod
    def two_point(cls, sds: float, sd1: float, tl: float) -> TargetSpectrum:
        """The design spectrum of ASCE 7-22 §11.4.6 (Fig. 11.4-1).

        ``T_0 = 0.2·S_D1/S_DS``, ``T_S = S_D1/S_DS``; ``S_a = S_DS(0.4 + 0.6T/T_0)`` below
        ``T_0``, ``S_DS`` up to ``T_S``, ``S_D1/T`` up to ``T_L`` and ``S_D1·T_L/T²`` beyond.
        Held as its exact values on a fine grid of corners and log-spaced periods to 20 s;
        :meth:`__call__` evaluates the formula itself.
        """
        for name, v in (("sds", sds), ("sd1", sd1), ("tl", tl)):
            if not (isinstance(v, int | float) and math.isfinite(v) and v > 0):
                raise ModelError(f"{name} must be a number > 0, got {v!r}", name)
        t0, ts = 0.2 * sd1 / sds, sd1 / sds
        if ts >= tl:
            raise ModelError(f"T_S = S_D1/S_DS = {ts:g} s must be below T_L = {tl:g} s", "tl")
        grid = np.unique(np.concatenate([[0.0, t0, ts, tl], np.geomspace(0.01, 20.0, 200)]))
        sa = _two_point(grid, sds, sd1, tl)
        return cls(grid, sa, f"ASCE 7 two-point (S_DS {sds:g}, S_D1 {sd1:g}, T_L {tl:g} s)",
                   {"sds": sds, "sd1": sd1, "tl": tl})  # fmt: skip

    @classmethod
    def from_table(cls, periods, sa, name: str = "table") -> TargetSpectrum:
        """A target given as ``(T, S_a)`` rows: periods ≥ 0 strictly increasing, ``S_a`` > 0."""
        T = np.asarray(periods, dtype=float).ravel()
        S = np.asarray(sa, dtype=float).ravel()
        if T.size != S.size or T.size < 2:
            raise ModelError("a target table needs at least two (T, S_a) rows", "target")
        if not (np.all(np.isfinite(T)) and np.all(np.isfinite(S))):
            raise ModelError("a target table holds a value that is not a number", "target")
        if T[0] < 0 or np.any(np.diff(T) <= 0):
            k = int(np.argmax(np.diff(T) <= 0)) + 1 if T[0] >= 0 else 0
            raise ModelError(
                f"target periods must be ≥ 0 and strictly increasing (row {k + 1}: T = {T[k]:g})",
                "target",
            )
        if np.any(S <= 0):
            k = int(np.argmax(S <= 0))
            raise ModelError(f"target S_a must be > 0 (row {k + 1}: S_a = {S[k]:g})", "target")
        return cls(T, S, name)

    def __call__(self, T) -> np.ndarray:
        """``S_a`` (g) at the periods `T` (s)."""
        T = np.asarray(T, dtype=float)
        if self.params:
            p = self.params
            return _two_point(T, p["sds"], p["sd1"], p["tl"])
        lo, hi = self.periods[0], self.periods[-1]
        if np.any(T < lo) or np.any(T > hi):
            raise ModelError(
                f"periods {T.min():g}–{T.max():g} s reach outside the target's {lo:g}–{hi:g} s",
                "target",
            )
        return _loglog_interp(T, self.periods, self.sa)


def _cells(body: str) -> list[str]:
    """The fields of a CSV line: separated by commas, semicolons or tabs, else white space."""
    if any(sep in body for sep in ",;\t"):
        cells = [c.strip() for c in body.replace(";", ",").replace("\t", ",").split(",")]
        return [c for c in cells if c]
    return body.split()


def _is_word(cell: str) -> bool:
    """Whether a field is a column name rather than a (mistyped) number: not a number, not even
    without its underscores (``T_s`` is a name, ``0_05`` a number with an underscore)."""
    for text in (cell, cell.replace("_", "")):
        try:
            float(text)
        except ValueError:
            continue
        return False
    return True


def read_target_csv(path: str | os.PathLike) -> TargetSpectrum:
    """A target spectrum from a CSV file of ``T, S_a`` rows (s, g).

    Two fields per row (``0,05;1,2`` with decimal commas is refused, not read as 0 and 5),
    separated by commas, semicolons, tabs or white space; ``#`` starts a comment;
    lines of column names (``T_s, Sa_g``) may come before the first row; periods must increase
    and ``S_a`` be > 0 (:meth:`TargetSpectrum.from_table`). The file is read line by line: a
    file above :data:`MAX_TARGET_BYTES` or with more than :data:`MAX_TARGET_ROWS` rows is
    refused, and so are UTF-16, binary and non-UTF-8 files and numbers with underscores
    (Python reads ``0_05`` as 5; :mod:`floorslide.text_numbers`).

    Raises
    ------
    ModelError
        ``where`` is ``"target"``; the message names the file (and the line) and what was
        expected.
    """
    path = Path(path)
    name = path.name
    expected = "a target spectrum is a UTF-8 CSV of T (s), S_a (g) rows"

    def fail(problem: str, line: int = 0) -> ModelError:
        return ModelError(
            f"{name} line {line}: {problem}" if line else f"{name}: {problem}", "target"
        )

    periods: list[float] = []
    sa: list[float] = []
    try:
        size = path.stat().st_size
        if size > MAX_TARGET_BYTES:
            raise fail(
                f"{size:,} bytes; {expected}, at most {MAX_TARGET_BYTES // 2**20} MiB "
                f"and {MAX_TARGET_ROWS:,} rows"
            )
        with open(path, "rb") as fh:
            head = fh.read(4096)
            if head.startswith((b"\xff\xfe", b"\xfe\xff")):
                raise fail(f"UTF-16 text; {expected}: save it as UTF-8")
            if b"\x00" in head:
                raise fail(f"binary data, not text; {expected}")
            fh.seek(0)
            for k, raw in enumerate(fh, start=1):
                try:
                    line = raw.decode("utf-8")
                except UnicodeDecodeError:
                    raise fail(f"not UTF-8 text; {expected}", k) from None
                body = line.removeprefix("\ufeff").split("#", 1)[0].strip()
                if not body:
                    continue
                cells = _cells(body)
                if not periods and all(_is_word(c) for c in cells):
                    continue  # column names
                row = _row(cells, k, expected, fail)
                if periods and row[0] <= periods[-1]:
                    raise fail(
                        f"periods must increase, got T = {row[0]:g} s after {periods[-1]:g} s", k
                    )
                if len(periods) == MAX_TARGET_ROWS:
                    raise fail(f"more than {MAX_TARGET_ROWS:,} rows; {expected}")
                periods.append(row[0])
                sa.append(row[1])
    except OSError as exc:
        raise fail(f"cannot read the file ({exc.strerror or exc})") from None
    try:
        return TargetSpectrum.from_table(periods, sa, name=name)
    except ModelError as exc:
        raise fail(exc.message) from None


def _row(cells: list[str], k: int, expected: str, fail) -> tuple[float, float]:
    """``(T, S_a)`` of the fields of line `k`, or the error `fail` makes."""
    if len(cells) != 2:
        shown = ", ".join(cells)
        shown = shown if len(shown) <= 60 else shown[:60] + "…"
        raise fail(f"{len(cells)} field{'' if len(cells) == 1 else 's'} ({shown!r}); {expected}", k)
    values = []
    for cell in cells:
        try:
            values.append(parse_number(cell))
        except ValueError:
            shown = cell if len(cell) <= 30 else cell[:30] + "…"
            raise fail(f"{shown!r} is not a number{underscore_hint(cell)}", k) from None
    t, s = values
    if not (math.isfinite(t) and math.isfinite(s)):
        raise fail("T and S_a must be finite numbers", k)
    if s < 0:
        raise fail(f"S_a must be > 0 g, got {s:g} (negative)", k)
    return t, s


def _two_point(T, sds, sd1, tl):
    T = np.asarray(T, dtype=float)
    t0, ts = 0.2 * sd1 / sds, sd1 / sds
    with np.errstate(divide="ignore"):
        return np.where(
            T < t0,
            sds * (0.4 + 0.6 * T / t0),
            np.where(T <= ts, sds, np.where(T <= tl, sd1 / T, sd1 * tl / T**2)),
        )


def _loglog_interp(T, Tk, Sk):
    """Linear interpolation of ``ln S`` in ``ln T`` (linear in T on a first interval from 0)."""
    T = np.asarray(T, dtype=float)
    out = np.empty_like(T)
    pos = Tk > 0
    if Tk[0] == 0:
        first = T <= Tk[1]
        out[first] = np.interp(T[first], Tk[:2], Sk[:2])
    else:
        first = np.zeros(T.shape, dtype=bool)
    rest = ~first
    out[rest] = np.exp(np.interp(np.log(T[rest]), np.log(Tk[pos]), np.log(Sk[pos])))
    return out


def outside_limits(factor: float, limits: tuple[float, float] = FACTOR_LIMITS) -> bool:
    """Whether a scale factor lies outside ``[low, high]`` (a warning, not an error)."""
    return not (limits[0] <= factor <= limits[1])


@dataclass(frozen=True)
class ScaleFit:
    """The scale factor of one record and how well the scaled record fits the target.

    Attributes
    ----------
    factor
        Amplitude scale factor.
    misfit
        Root mean square of ``ln(f·S_a,record / S_a,target)`` over the range (0 when the
        spectra are proportional).
    method
        ``"range"`` (least squares in the logarithms) or ``"period"`` (match at one period).
    outside_limits
        The factor lies outside :data:`FACTOR_LIMITS`.
    """

    factor: float
    misfit: float
    method: str
    outside_limits: bool


def scale_factor(
    periods,
    psa,
    target: TargetSpectrum,
    *,
    period_range: tuple[float, float] | None = None,
    period: float | None = None,
    limits: tuple[float, float] = FACTOR_LIMITS,
) -> ScaleFit:
    """The amplitude scale factor of one record's spectrum ``psa(periods)`` (g) to `target`.

    With `period_range` ``(T_lo, T_hi)``: the factor minimising
    ``Σ_i (ln f + ln S_r(T_i) − ln S_t(T_i))²`` over the record's periods in the range, i.e.
    ``ln f = mean_i(ln S_t(T_i) − ln S_r(T_i))``. With `period`: ``f = S_t(T*)/S_r(T*)``, the
    record's spectrum interpolated in log–log coordinates.
    """
    T = np.asarray(periods, dtype=float).ravel()
    S = np.asarray(psa, dtype=float).ravel()
    if (period_range is None) == (period is None):
        raise ModelError("give either period_range or period", "scale")
    if period is not None:
        if not (T[0] <= period <= T[-1]):
            raise ModelError(
                f"period {period:g} s is outside the spectrum's {T[0]:g}–{T[-1]:g} s",
                "scale.period",
            )
        sr = float(_loglog_interp(np.array([period]), T, S)[0])
        st = float(target(np.array([period]))[0])
        if not sr > 0:
            raise ModelError(f"the record's S_a at {period:g} s is 0: it cannot be scaled", "scale")
        f = st / sr
        return ScaleFit(f, 0.0, "period", outside_limits(f, limits))
    lo, hi = period_range
    if not (0 <= lo < hi):
        raise ModelError(f"period range {lo:g}–{hi:g} s is not increasing", "scale.periods")
    inside = (T >= lo) & (T <= hi) & (T > 0)
    if inside.sum() < 2:
        raise ModelError(
            f"fewer than two spectrum periods in the range {lo:g}–{hi:g} s", "scale.periods"
        )
    resid = np.log(target(T[inside])) - np.log(S[inside])
    ln_f = float(np.mean(resid))
    misfit = float(np.sqrt(np.mean((resid - ln_f) ** 2)))
    f = math.exp(ln_f)
    return ScaleFit(f, misfit, "range", outside_limits(f, limits))


def suite_check(
    periods, scaled_psa, target: TargetSpectrum, period_range: tuple[float, float]
) -> tuple[bool, float, float]:
    """ASCE 7-22 §16.2.3: the mean of the scaled spectra (rows of `scaled_psa`) against
    :data:`SUITE_FRACTION` of the target over `period_range`.

    Returns
    -------
    passes, ratio, at
        Whether the mean spectrum is ≥ 90 % of the target at every period in the range; the
        smallest ratio mean/target there; the period where it occurs.
    """
    T = np.asarray(periods, dtype=float).ravel()
    mean = np.mean(np.atleast_2d(np.asarray(scaled_psa, dtype=float)), axis=0)
    inside = (T >= period_range[0]) & (T <= period_range[1])
    if not inside.any():
        raise ModelError("no spectrum period inside the scaling range", "scale.periods")
    ratio = mean[inside] / target(T[inside])
    k = int(np.argmin(ratio))
    # to rounding: a suite raised to exactly 90 % (match_suite) passes
    return bool(ratio[k] >= SUITE_FRACTION * (1 - 1e-12)), float(ratio[k]), float(T[inside][k])
