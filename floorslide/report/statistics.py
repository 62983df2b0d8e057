"""Statistics over the records of a set: empirical mean, median and 84th percentile, with
rocking objects as an outcome of their own; ratios of statistics; FRS interpolation.

References
----------
Hyndman, R. J., Fan, Y. (1996). Sample quantiles in statistical packages. *The American
Statistician* 50(4), 361–365 (definition 7 is NumPy's ``"linear"``).

Shenton, H. W. (1996). Criteria for initiation of slide, rock, and slide-rock rigid-body modes.
*J. Eng. Mech.* 122(7), 690–693.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from floorslide.report.columns import PERCENTILE, ROCK

_TOL = 1e-9


def summarize(values: Iterable[float]) -> tuple[float, float, float]:
    """Mean, median and 84th percentile of the finite values (NaN, NaN, NaN if none).

    The percentile is ``numpy.percentile(x, 84)`` with the ``"linear"`` method (Hyndman & Fan
    1996, definition 7).
    """
    x = np.asarray(list(values), dtype=float)
    x = x[np.isfinite(x)]
    if x.size == 0:
        return (math.nan, math.nan, math.nan)
    return (
        float(np.mean(x)),
        float(np.median(x)),
        float(np.percentile(x, PERCENTILE, method="linear")),
    )


@dataclass(frozen=True)
class Placement:
    """Where the statistics of a set of records fall when rocking records are an outcome of
    their own, ranked above every slide.

    ``mean``, ``median`` and ``p84`` are True when that statistic depends on a rocking record
    (its value is unknown: the object is not a slider there). The mean depends on every
    record; a quantile depends on the one or two sorted records it interpolates between.
    """

    n: int
    n_rock: int
    mean: bool
    median: bool
    p84: bool

    def rocks(self, stat: str) -> bool:
        """Whether statistic ``"mean"``, ``"median"`` or ``"p84"`` falls on rocking records."""
        return bool(getattr(self, stat))


def _on_rock(n: int, n_rock: int, q: float) -> bool:
    """Whether the empirical ``q``-th percentile (linear, definition 7) of `n` sorted outcomes,
    of which the top `n_rock` are rocking records, uses a rocking record."""
    if n_rock == 0:
        return False
    if n_rock >= n:
        return True
    h = (n - 1) * q / 100.0
    j = math.floor(h)
    known = n - n_rock
    return j >= known or (h > j and j + 1 >= known)


def placement(n: int, n_rock: int) -> Placement:
    """:class:`Placement` of the statistics of `n` records, `n_rock` of them rocking."""
    return Placement(n, n_rock, n_rock > 0, _on_rock(n, n_rock, 50.0), _on_rock(n, n_rock, 84.0))


def summarize_outcomes(values: Sequence[float], rock: Sequence[bool]) -> dict[str, float]:
    """Mean, median and 84th percentile over every record, rocking records included as the
    outcome ranked above every value.

    Parameters
    ----------
    values
        One value per record (NaN where the object rocks).
    rock
        One flag per record: the object rocks (not simulated as a slider).

    Returns
    -------
    dict
        ``{"mean", "median", "p84"}``: NaN where the statistic falls on rocking records (see
        :func:`placement`) or no value is known; else exactly what :func:`summarize` gives
        over the same records (the rocking ones sit above every value and are not reached).
    """
    x = np.asarray(values, dtype=float)
    r = np.asarray(rock, dtype=bool)
    place = placement(x.size, int(r.sum()))
    if not place.mean:
        mean, median, p84 = summarize(x)
        return {"mean": mean, "median": median, "p84": p84}
    known = x[~r]
    known = known[np.isfinite(known)]
    out = {"mean": math.nan, "median": math.nan, "p84": math.nan}
    if known.size == 0:
        return out
    # the rocking records as copies of the largest known value on top: a quantile that does
    # not reach them is the same as over the full sorted list
    padded = np.concatenate([known, np.full(x.size - known.size, known.max())])
    for stat, q in (("median", 50.0), ("p84", PERCENTILE)):
        if not place.rocks(stat):
            out[stat] = float(np.percentile(padded, q, method="linear"))
    return out


def outcome(place: Placement, stat: str, value: float) -> str:
    """``rock`` if the statistic falls on rocking records, else ``slide`` (> 0) or ``rest``."""
    if place.rocks(stat):
        return ROCK
    return "slide" if value > 0 else "rest"


def ratio(a: float, b: float) -> float:
    """``a / b`` with the table's conventions: NaN if either is NaN or both are zero, ``inf``
    for ``a > 0 = b``."""
    if not (math.isfinite(a) and math.isfinite(b)):
        return math.nan
    if b == 0.0:
        return math.nan if a == 0.0 else math.copysign(math.inf, a)
    return a / b


def interpolate_spectrum(grid: np.ndarray, values: np.ndarray, periods: Sequence[float]):
    """Ordinates at `periods`, interpolated linearly in ``ln T`` between stored periods.

    A period equal to a stored one (to 1e-9 relative) takes its value exactly; periods
    outside the grid give NaN. A stored period 0 (the peak of the motion) is used only for a
    requested period 0.
    """
    grid = np.asarray(grid, dtype=float)
    values = np.asarray(values, dtype=float)
    order = np.argsort(grid)
    grid, values = grid[order], values[order]
    pos = grid > 0
    out = np.full(len(periods), np.nan)
    for j, p in enumerate(periods):
        exact = np.nonzero(np.abs(grid - p) <= _TOL * max(p, 1e-300))[0]
        if exact.size:
            out[j] = values[exact[0]]
        elif p > 0 and pos.sum() >= 2 and grid[pos][0] <= p <= grid[pos][-1]:
            out[j] = np.interp(np.log(p), np.log(grid[pos]), values[pos])
    return out
