"""The rocking kernel's shortcut for the return of an excursion (``_convex_rise``) against
rigorous root isolation (``first_rise``) on convex polynomials like θ's series: the same
machine number, "no rise" where there is none, and "undecided" where its premises fail."""

from __future__ import annotations

import numpy as np

from floorslide.contents._rocking_kernel import UNDECIDED, _convex_rise
from floorslide.numerics.polynomial import first_rise, scratch


def series(rng, deg=14):
    """A θ-like series: decaying Taylor coefficients with a positive curvature term."""
    p = rng.uniform(1.0, 8.0)
    q = rng.normal(size=deg + 1) * p ** np.arange(deg + 1) / np.cumprod([1, *range(1, deg + 1)])
    q[2] = abs(q[2]) + 0.1 * p * p
    return q


def test_same_rise_as_root_isolation_on_convex_series():
    rng = np.random.default_rng(7)
    work = scratch(16)
    decided = 0
    for _ in range(3000):
        q = series(rng)
        start_on_zero = rng.random() < 0.5
        if start_on_zero:  # an excursion just begun at θ = 0 (after an impact or an uplift)
            q[0] = 0.0
            q[1] = -abs(q[1]) - 1e-9
        else:
            q[0] = -abs(q[0]) - 1e-12
        hi = 10 ** rng.uniform(-6, -1.5)
        lo = 1e-12 * hi if start_on_zero else 0.0
        got = _convex_rise(q, 14, lo, hi)
        ref = first_rise(q, 14, lo, hi, 0.0, work)
        if got == UNDECIDED:
            continue
        decided += 1
        if ref < 0:
            assert got == -1.0, (q, lo, hi, got, ref)
        else:
            assert got == ref, (q, lo, hi, got, ref)  # measured: 2,999 of 2,999 bit for bit
    assert decided > 2000


def test_premises():
    q = np.array([0.0, -1.0, -3.0, 0.0, 0.0])  # concave
    assert _convex_rise(q, 4, 1e-12, 1.0) == UNDECIDED
    q = np.array([0.5, -1.0, 3.0, 0.0, 0.0])  # positive at the start: a rise at lo
    assert _convex_rise(q, 4, 0.0, 1.0) == UNDECIDED
    q = np.array([-1.0, 0.0, 3.0, 0.0, 0.0])  # −1 + 3τ²: rises through 0 at 1/√3
    assert abs(_convex_rise(q, 4, 0.0, 1.0) - 1 / np.sqrt(3)) <= 2e-16
    assert _convex_rise(q, 4, 0.0, 0.5) == -1.0  # not yet by 0.5
