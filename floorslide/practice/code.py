"""The code's floor amplification of nonstructural components, ASCE 7-22 §13.3.1.

``H_f = 1 + a_1·(z/h) + a_2·(z/h)^10`` with ``a_1 = 1/T_a ≤ 2.5`` and
``a_2 = max(0, 1 − (0.4/T_a)²)`` (ASCE 7-22 Eq. 13.3-4); where ``T_a`` is not known,
``H_f = 1 + 2.5(z/h)`` (Eq. 13.3-5). ``T_a`` is the approximate fundamental period of
§12.8.2.1, ``C_t·h_n^x``. For a building on isolation ASCE 7-22 §17.2.1 (and §13.3.1) take the
component's acceleration from the response history analysis of the isolated structure rather
than from ``H_f``: the formula is drawn for fixed-base buildings only.
"""

from __future__ import annotations

import numpy as np

from floorslide.errors import ModelError

PERIOD_COEFFICIENTS = {
    "steel_moment_frame": (0.028, 0.8),
    "concrete_moment_frame": (0.016, 0.9),
    "steel_eccentrically_braced": (0.03, 0.75),
    "steel_buckling_restrained_braced": (0.03, 0.75),
    "other": (0.02, 0.75),
}
"""``(C_t, x)`` of ASCE 7-22 Table 12.8-2, for ``h_n`` in feet (:func:`asce7_approximate_period`
converts from metres)."""

_FT_PER_M = 1.0 / 0.3048


def asce7_approximate_period(height_m: float, system: str = "other") -> float:
    """``T_a = C_t·h_n^x`` (ASCE 7-22 Eq. 12.8-8; ``h_n`` in feet as the table's
    coefficients are), for a structural `system` of :data:`PERIOD_COEFFICIENTS`."""
    if system not in PERIOD_COEFFICIENTS:
        raise ModelError(
            f"unknown structural system {system!r}; one of {', '.join(PERIOD_COEFFICIENTS)}",
            "system",
        )
    if not (np.isfinite(height_m) and height_m > 0):
        raise ModelError(f"height must be > 0 m, got {height_m!r}", "height")
    ct, x = PERIOD_COEFFICIENTS[system]
    return float(ct * (height_m * _FT_PER_M) ** x)


def asce7_floor_amplification(z_over_h, period: float | None = None) -> np.ndarray:
    """``H_f`` of ASCE 7-22 Eq. 13.3-4 at relative heights `z_over_h` (0 ground … 1 roof), or
    Eq. 13.3-5 when `period` (``T_a``, s) is None."""
    r = np.asarray(z_over_h, dtype=float)
    if np.any(r < 0) or np.any(r > 1):
        raise ModelError("z/h must lie in [0, 1]", "z_over_h")
    if period is None:
        return 1.0 + 2.5 * r
    if not (np.isfinite(period) and period > 0):
        raise ModelError(f"T_a must be > 0 s, got {period!r}", "period")
    a1 = min(1.0 / period, 2.5)
    a2 = max(0.0, 1.0 - (0.4 / period) ** 2)
    return 1.0 + a1 * r + a2 * r**10


def relative_heights(stories: int, storey_heights=None) -> np.ndarray:
    """``z/h`` of floors 0 … `stories` (0 at the ground or base mat, 1 at the roof), the
    height ``z`` of each floor over the roof's ``h`` (ASCE 7-22 §13.3.1).

    Parameters
    ----------
    stories
        Number of storeys.
    storey_heights
        Height of each storey, m, from the first up (one number: every storey the same); None
        for equal storeys (``z/h = floor/stories``).

    Examples
    --------
    >>> relative_heights(3, [5.0, 3.0, 2.0]).tolist()
    [0.0, 0.5, 0.8, 1.0]
    """
    n = int(stories)
    if n < 1:
        raise ModelError(f"stories must be ≥ 1, got {stories!r}", "stories")
    if storey_heights is None:
        return np.arange(n + 1) / n
    h = np.ravel(np.asarray(storey_heights, dtype=float))
    if h.size == 1:
        h = np.full(n, h[0])
    if h.shape != (n,):
        raise ModelError(
            f"one height per storey: {h.size} heights for {n} storeys", "storey_heights"
        )
    if not (np.all(np.isfinite(h)) and np.all(h > 0)):
        raise ModelError("storey heights must be > 0 m", "storey_heights")
    z = np.concatenate([[0.0], np.cumsum(h)])
    return z / z[-1]
