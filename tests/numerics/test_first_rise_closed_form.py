"""The closed forms of ``first_rise`` for degrees 1 and 2 (``_rise_low``) against root isolation
(``_first_rise_isolating``, the rigorous reference) and an extended-precision evaluation.

Degree 1 must agree bit for bit. Degree 2 must agree on event / no event and on the event time
to a few units in the last place (both settle on adjacent machine numbers around the root,
where rounding may make the evaluated polynomial flicker), and every decision the closed form
takes must carry its certificate: ``q(x) > 0`` at the returned ``x`` and ``q ≤ 0`` just before
it. Cases whose signs are within rounding (double roots, roots at the ends, tangencies,
overflow) must be left to root isolation (``UNDECIDED``).
"""

from __future__ import annotations

import mpmath
import numpy as np
import pytest

from floorslide.numerics.polynomial import (
    UNDECIDED,
    _first_rise_isolating,
    _rise_low,
    first_rise,
    poly_val,
    scratch,
)

W = scratch()


def _both(c, lo, hi, level=0.0):
    c = np.asarray(c, float)
    deg = c.size - 1
    return first_rise(c, deg, lo, hi, level, W), _first_rise_isolating(c, deg, lo, hi, level, W)


def _random_cases(rng, deg, n):
    """Random polynomials of degree ``deg`` with scales over 14 decades, some with a root put
    at lo, at hi, inside, or a double root, and some shifted to a level."""
    for _ in range(n):
        c = rng.normal(size=deg + 1) * 10.0 ** rng.integers(-7, 8, size=deg + 1)
        lo = 0.0 if rng.random() < 0.4 else float(rng.random() * 10.0 ** rng.integers(-3, 2))
        hi = lo + float(rng.random() * 10.0 ** rng.integers(-4, 1)) + 1e-12
        kind = rng.integers(0, 6)
        r = [lo, hi, lo + (hi - lo) * rng.random()][min(kind, 2)] if kind < 4 else None
        if r is not None:
            c[0] = -sum(c[j] * r**j for j in range(1, deg + 1))
        if kind == 4 and deg == 2:  # a double root (tangency) inside, or nearly
            r = lo + (hi - lo) * rng.random()
            c = c[2] * np.array([r * r, -2.0 * r, 1.0])
            c[0] += rng.choice([0.0, 1.0, -1.0]) * abs(c[0]) * 10.0 ** rng.integers(-16, -8)
        level = 0.0 if rng.random() < 0.7 else float(rng.normal() * 10.0 ** rng.integers(-3, 3))
        if level != 0.0:
            c[0] += level
        yield c, lo, hi, level


def _root_tolerance(q, x):
    """How far apart two valid answers may be at a root ``x`` of ``q``: 64 units in the last
    place, or the width of the band where rounding blurs the sign of ``q`` (its evaluation
    error bound over the slope, or over the curvature near a double root), the larger."""
    err = 1e-15 * (abs(q[0]) + abs(q[1]) * abs(x) + abs(q[2]) * x * x) + 1e-300
    slope = abs(q[1] + 2.0 * q[2] * x)
    band = min(err / slope if slope > 0.0 else np.inf, (err / abs(q[2])) ** 0.5)
    return max(64 * np.spacing(abs(x)), 4.0 * band)


def _ulps(a, b):
    return abs(a - b) / np.spacing(max(abs(a), abs(b), 1e-300))


def test_degree_one_is_root_isolation_bit_for_bit():
    rng = np.random.default_rng(20)
    for c, lo, hi, level in _random_cases(rng, 1, 60_000):
        fast, ref = _both(c, lo, hi, level)
        assert fast == ref, (c.tolist(), lo, hi, level, fast, ref)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_degree_two_agrees_with_root_isolation(seed):
    rng = np.random.default_rng(seed)
    decided = 0
    for c, lo, hi, level in _random_cases(rng, 2, 40_000):
        fast, ref = _both(c, lo, hi, level)
        q = c.copy()
        q[0] -= level
        if _rise_low(q[0], q[1], q[2], 2, lo, hi) != UNDECIDED:
            decided += 1
        assert (fast < 0.0) == (ref < 0.0), (c.tolist(), lo, hi, level, fast, ref)
        if fast >= 0.0:
            tol = _root_tolerance(q, fast)
            assert abs(fast - ref) <= tol, (c.tolist(), lo, hi, level, fast, ref, tol)
    assert decided > 20_000  # the closed form does decide most cases


def _certificate(q, lo, hi, x):
    """A rise returned at ``x``: ``q(x) > 0`` evaluated, and ``q ≤ 0`` at the machine number
    before it unless that is ``lo`` (``lo`` itself: ``q > 0`` on the whole interval)."""
    if x == lo:
        return poly_val(q, 2, lo) > 0.0
    before = np.nextafter(x, -np.inf)
    return lo < x <= hi and poly_val(q, 2, x) > 0.0 and not poly_val(q, 2, before) > 0.0


def test_degree_two_decisions_carry_their_certificate():
    """Every rise the closed form returns is certified by the evaluated signs around it; every
    "no rise" is confirmed by a dense extended-precision scan (no excursion above rounding)."""
    rng = np.random.default_rng(7)
    mpmath.mp.prec = 200
    for i, (c, lo, hi, level) in enumerate(_random_cases(rng, 2, 6_000)):
        q = c.copy()
        q[0] -= level
        r = _rise_low(q[0], q[1], q[2], 2, lo, hi)
        if r == UNDECIDED:
            continue
        if r >= 0.0:
            assert _certificate(q, lo, hi, r), (q.tolist(), lo, hi, r)
            continue
        if i % 6:
            continue  # the scan is slow: a sixth of the "no rise" cases
        # no rise: after the first point where q ≤ 0 (or from lo), q never exceeds the rounding
        # bound of its evaluation; the exact extremum included
        qm = [mpmath.mpf(float(x)) for x in q]
        bound = 1e-15 * (abs(q[0]) + abs(q[1]) * hi + abs(q[2]) * hi * hi) + 1e-300
        ts = [mpmath.mpf(lo) + (mpmath.mpf(hi) - lo) * k / 400 for k in range(401)]
        crit = -qm[1] / (2 * qm[2])
        if lo < crit < hi:
            ts = sorted([*ts, crit])
        vals = [qm[0] + qm[1] * t + qm[2] * t * t for t in ts]
        been_low = poly_val(q, 2, lo) <= 0.0
        for v in vals:
            if v <= 0:
                been_low = True
            elif been_low:
                assert v <= bound, (q.tolist(), lo, hi, float(v), bound)


ADVERSARIAL = [
    # (coefficients, lo, hi, expected: "none" | "lo" | a root, or None when undecided is allowed)
    ([-1.0, 0.0, 1.0], 0.0, 2.0, 1.0),  # rises through 1
    ([-1.0, 0.0, 1.0], 0.5, 2.0, 1.0),
    ([1.0, 0.0, -1.0], 0.0, 2.0, "none"),  # falls through 1: no rise
    ([1.0, -3.0, 1.0], 0.0, 3.0, (3 + 5**0.5) / 2),  # falls, then rises
    ([-0.21, 1.0, -1.0], 0.0, 1.0, 0.3),  # a brief excursion above 0 on (0.3, 0.7)
    ([-0.2499, 1.0, -1.0], 0.0, 1.0, 0.5 - 0.0001**0.5),  # a very brief excursion
    ([-0.25, 1.0, -1.0], 0.0, 1.0, None),  # touches 0 at 0.5 (double root)
    ([0.25, -1.0, 1.0], 0.0, 1.0, None),  # touches 0 from above at 0.5
    ([0.0, 0.0, 1.0], 0.0, 1.0, None),  # double root at lo
    ([-1.0, 0.0, 1.0], 0.0, 1.0, None),  # root at hi
    ([1e-300, -1e-150, 1e-300], 0.0, 1.0, None),  # tiny coefficients
    ([-1e100, 1e100, 1e100], 0.0, 1.0, (5**0.5 - 1) / 2),  # huge coefficients
    ([-1e200, 1e200, 1e200], 0.0, 1.0, None),  # the discriminant overflows
    ([-1e-8, 0.0, 1e8], 0.0, 1e-3, 1e-8),  # a root far from the interval's scale
    ([2.0, 1.0, 1.0], 0.0, 1.0, "lo"),  # above 0 throughout
    ([-2.0, 1.0, -1.0], 0.0, 1.0, "none"),  # below 0 throughout
]


@pytest.mark.parametrize("c, lo, hi, expected", ADVERSARIAL)
def test_adversarial_cases(c, lo, hi, expected):
    fast, ref = _both(c, lo, hi)
    q = np.asarray(c, float)
    r = _rise_low(q[0], q[1], q[2], 2, lo, hi)
    assert (fast < 0.0) == (ref < 0.0)
    if fast >= 0.0:
        assert _ulps(fast, ref) <= 64
    if expected == "none":
        assert fast == -1.0 and r == -1.0
    elif expected == "lo":
        assert fast == lo and r == lo
    elif expected is None:
        # a sign within rounding: left to root isolation, or certified all the same
        assert r == UNDECIDED or r == ref or _ulps(r, ref) <= 64
    else:
        assert r != UNDECIDED, "a well-conditioned case must be decided in closed form"
        assert abs(r - expected) <= 4e-15 * max(abs(expected), 1e-300) + 8 * np.spacing(expected)
        assert _certificate(q, lo, hi, r)


def test_rounding_blurred_roots_are_left_to_root_isolation():
    """A double root, a root at hi and non-finite input are never decided in closed form."""
    assert _rise_low(-0.25, 1.0, -1.0, 2, 0.0, 1.0) == UNDECIDED
    assert _rise_low(0.25, -1.0, 1.0, 2, 0.0, 1.0) == UNDECIDED
    assert _rise_low(1.0, -1.0, 0.0, 1, 0.0, 1.0) == UNDECIDED  # linear, root at hi
    assert _rise_low(np.nan, 1.0, 1.0, 2, 0.0, 1.0) == UNDECIDED
    assert _rise_low(-1.0, np.inf, 1.0, 2, 0.0, 1.0) == UNDECIDED
    assert _rise_low(-1.0, 1.0, 1.0, 2, 0.0, np.inf) == UNDECIDED


def test_a_wrong_closed_form_would_be_caught():
    """The comparison above is not vacuous: a closed form that took the wrong root of a
    quadratic (the falling one) or missed a brief excursion would fail it."""
    c = np.array([1.0, -3.0, 1.0])  # falls at 0.38, rises at 2.62
    fast, ref = _both(c, 0.0, 3.0)
    wrong = (3 - 5**0.5) / 2
    assert _ulps(fast, ref) <= 64 and _ulps(wrong, ref) > 1e6
    c = np.array([-0.2499, 1.0, -1.0])  # the excursion lasts 0.02
    fast, ref = _both(c, 0.0, 1.0)
    assert fast > 0.0 and ref > 0.0
