"""Polynomials inside a step: rigorous root isolation, extrema and first crossings against
independent computations (NumPy's companion-matrix roots, dense evaluation in extended
precision with mpmath), including the cases a 'one critical point per step' assumption misses."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.polynomial import polynomial as P

from floorslide.numerics.polynomial import (
    bernstein,
    extreme_values,
    first_rise,
    real_roots,
    scratch,
    taylor_shift,
)

W = scratch()


def roots_in(c, lo, hi):
    out = np.empty(len(c))
    n = real_roots(np.asarray(c, float), len(c) - 1, lo, hi, out, W)
    return out[:n]


def test_taylor_shift_and_bernstein():
    c = np.array([1.0, -2.0, 0.5, 3.0])
    out = np.empty(4)
    taylor_shift(c, 3, 0.3, out)
    s = np.linspace(-1, 1, 7)
    np.testing.assert_allclose(P.polyval(s, out), P.polyval(0.3 + s, c), rtol=1e-13)
    b = np.empty(4)
    bernstein(c, 3, 0.2, 0.7, b)
    t = np.linspace(0, 1, 9)
    basis = np.array(
        [[mpmath.binomial(3, i) * x**i * (1 - x) ** (3 - i) for i in range(4)] for x in t]
    )
    np.testing.assert_allclose(basis.astype(float) @ b, P.polyval(0.2 + 0.5 * t, c), rtol=1e-13)


@settings(max_examples=300, deadline=None)
@given(
    st.lists(st.floats(1e-3, 0.999), min_size=1, max_size=8),
    st.floats(0.2, 5.0),
    st.integers(0, 2),
)
def test_separated_roots_are_all_found(rts, scale, n_complex):
    rts = np.sort(np.asarray(rts))
    if rts.size > 1 and np.min(np.diff(rts)) < 1e-4:
        return
    c = P.polyfromroots(rts) * scale
    for k in range(n_complex):  # complex pairs add degree, no real roots
        c = P.polymul(c, [0.3 + 0.05 * k, -1.0, 1.0])
    inside = rts
    got = roots_in(c, 0.0, 1.0)
    assert got.size == inside.size
    # forward error bound of a simple root: rounding of p (~ε·Σ|c_j|) over |p'(root)|
    cond = 1e-14 * np.abs(c).sum() / np.abs(P.polyval(inside, P.polyder(c)))
    assert np.all(np.abs(got - inside) <= np.maximum(cond, 1e-13))


@pytest.mark.parametrize("gap", [1e-3, 1e-5, 1e-7])
def test_two_close_critical_points_are_both_seen(gap):
    # p' has two roots `gap` apart inside the interval, and p's largest value sits between
    # them: a search that takes one critical point per interval misses it
    r1 = 0.6
    r2 = r1 + gap
    d = P.polyfromroots([r1, r2, 3.0, -2.0])  # p' = (x − r1)(x − r2)(x − 3)(x + 2)
    c = P.polyint(d)
    c[0] = -P.polyval(r1, c) - 1e-3  # p(r1) a little below zero at the local max
    vmin, _, vmax, _ = extreme_values(c, len(c) - 1, 0.0, 1.0, W)
    grid = np.linspace(0.0, 1.0, 200001)
    vals = P.polyval(grid, c)
    assert vmax >= vals.max() - 1e-15
    assert vmin <= vals.min() + 1e-15
    # the true interior extremum (at r1) is found
    assert abs(vmax - max(P.polyval(r1, c), vals[0], vals[-1])) < 1e-14


def reference_extremes(c, h):
    """Extremes of p on [0, h] by an independent route: a dense grid, then every grid-local
    extremum refined by a 50-digit secant search on p' (mpmath)."""
    mpmath.mp.dps = 50
    mp = [mpmath.mpf(float(x)) for x in c]

    def f(x):
        return mpmath.polyval(mp, x, asc=True) if hasattr(mpmath, "polyval") else None

    def fp(x):
        return sum((j + 1) * mp[j + 1] * x**j for j in range(len(mp) - 1))

    def val(x):
        return sum(mp[j] * x**j for j in range(len(mp)))

    grid = np.linspace(0.0, h, 4001)
    v = P.polyval(grid, c)
    cand = [mpmath.mpf(0), mpmath.mpf(h)]
    for i in range(1, grid.size - 1):
        if (v[i] - v[i - 1]) * (v[i + 1] - v[i]) <= 0:
            try:
                x = mpmath.findroot(fp, (grid[i - 1], grid[i + 1]), solver="anderson")
            except (ValueError, ZeroDivisionError):
                x = mpmath.mpf(grid[i])
            if 0 <= x <= h:
                cand.append(x)
    vals = [val(x) for x in cand]
    return float(min(vals)), float(max(vals))


@settings(max_examples=150, deadline=None)
@given(st.lists(st.floats(-1.0, 1.0), min_size=2, max_size=14), st.floats(0.05, 2.0))
def test_extreme_values_against_an_extended_precision_search(coefs, h):
    c = np.asarray(coefs) * 0.7 ** np.arange(len(coefs))
    deg = len(c) - 1
    vmin, _, vmax, _ = extreme_values(c, deg, 0.0, h, W)
    rmin, rmax = reference_extremes(c, h)
    scale = float(np.sum(np.abs(c) * max(h, 1.0) ** np.arange(len(c)))) + 1e-300
    assert vmax == pytest.approx(rmax, abs=1e-13 * scale)
    assert vmin == pytest.approx(rmin, abs=1e-13 * scale)


@settings(max_examples=300, deadline=None)
@given(
    st.lists(st.floats(-1.0, 1.0), min_size=2, max_size=12),
    st.floats(-0.5, 0.5),
)
def test_first_rise_is_the_first_upward_crossing(coefs, level):
    c = np.asarray(coefs) * 0.8 ** np.arange(len(coefs))
    deg = len(c) - 1
    h = 1.0
    x = first_rise(c, deg, 0.0, h, level, W)
    grid = np.linspace(0.0, h, 20001)
    vals = P.polyval(grid, c) - level
    # upward crossings on the grid; a start above the level that falls through it is not one
    above = vals > 0
    ups = np.nonzero(~above[:-1] & above[1:])[0]
    if above[0] and not above.all():
        first_down = np.argmin(above)
        ups = ups[ups >= first_down - 1]
    if x < 0:
        assert ups.size == 0 or all(vals[u + 1] < 1e-12 for u in ups)
        return
    q = c.copy()
    q[0] -= level
    assert P.polyval(x, q) > 0.0
    assert x <= h
    if ups.size:
        # no upward crossing before x (beyond the grid resolution)
        assert x <= grid[ups[0] + 1] + 1e-12
    # just before x it is not above the level, unless x is lo (above on the whole interval)
    if x > 0.0:
        before = np.nextafter(x, -np.inf)
        assert P.polyval(before, q) <= 1e-12


def test_first_rise_sees_a_brief_excursion_between_two_close_roots():
    # p − level is positive only on (0.5, 0.5 + 1e-6): a narrow excursion inside the interval
    c = P.polyfromroots([0.5, 0.5 + 1e-6]) * -1.0
    x = first_rise(c, 2, 0.0, 1.0, 0.0, W)
    assert 0.5 - 1e-9 <= x <= 0.5 + 1e-6  # the roots are ill-conditioned at ~1e-10
    assert first_rise(c, 2, 0.0, 1.0, 1e-12, W) == -1.0  # its top is 2.5e-13
