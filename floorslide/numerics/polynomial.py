"""Polynomials inside one time step: values, rigorous root isolation, extrema, first crossings.

Inside a (sub-)step every exact response of floorslide is, to rounding, a polynomial
``p(τ) = Σ_{j≤deg} c_j τ^j`` of modest degree (the Taylor polynomial of the exact solution on a
sub-step short enough that the truncated series equals it, :mod:`floorslide.numerics.stepping`).
Events (breakaway, stop, uplift, impact) and peaks inside steps are roots and extrema of such
polynomials. Nothing here assumes how many critical points an interval holds: roots are
isolated rigorously with Descartes' rule of signs on the Bernstein coefficients of the
polynomial over the interval, subdividing by de Casteljau's algorithm until every piece holds
none or exactly one sign change (the Vincent–Collins–Akritas method), and each isolated root is
then refined by safeguarded bisection to adjacent machine numbers.

Rounding: the Bernstein coefficients carry rounding errors of order ``ε·Σ|c_j|h^j``; a root
pair closer together than that may be seen as a double root or missed, which changes a peak or
an event time only at that rounding level.

References
----------
Collins, G. E., Akritas, A. G. (1976). Polynomial real root isolation using Descartes' rule of
signs. *Proc. ACM Symposium on Symbolic and Algebraic Computation*, 272–275.
Farouki, R. T., Rajan, V. T. (1987). On the numerical condition of polynomials in Bernstein form.
*Computer Aided Geometric Design* 4(3), 191–216.
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit

MAX_DEGREE = 64
"""Largest polynomial degree handled (Taylor degrees are at most 60)."""
MAX_DEPTH = 60
"""Deepest bisection of an interval in root isolation (intervals shrink by 2⁻⁶⁰)."""
_RECIP = np.array([0.0] + [1.0 / m for m in range(1, MAX_DEGREE + 2)])
"""``1/m`` (``_RECIP[0]`` unused): the Bernstein conversion multiplies instead of dividing."""
R_COEF, R_ROOTS, R_LEFT, R_RIGHT = MAX_DEPTH + 3, MAX_DEPTH + 4, MAX_DEPTH + 5, MAX_DEPTH + 6
"""Rows of the scratch array (:func:`scratch`) beyond those of the root isolation."""


@njit(cache=True, inline="always")
def poly_val(c, deg, x):
    """Value of ``Σ_{j≤deg} c[j] x^j`` (Horner)."""
    r = c[deg]
    for j in range(deg - 1, -1, -1):
        r = r * x + c[j]
    return r


@njit(cache=True, inline="always")
def poly_der(c, deg, x):
    """Derivative of ``Σ_{j≤deg} c[j] x^j`` at ``x``."""
    if deg == 0:
        return 0.0
    r = deg * c[deg]
    for j in range(deg - 1, 0, -1):
        r = r * x + j * c[j]
    return r


@njit(cache=True, inline="always")
def poly_der2(c, deg, x):
    """Second derivative of ``Σ_{j≤deg} c[j] x^j`` at ``x``."""
    if deg < 2:
        return 0.0
    r = deg * (deg - 1) * c[deg]
    for j in range(deg - 1, 1, -1):
        r = r * x + j * (j - 1) * c[j]
    return r


@njit(cache=True)
def derivative(c, deg, out):
    """Coefficients of ``p'`` (degree ``deg − 1``, at least 0) in ``out``; returns its degree."""
    if deg == 0:
        out[0] = 0.0
        return 0
    for j in range(deg):
        out[j] = (j + 1) * c[j + 1]
    return deg - 1


@njit(cache=True)
def taylor_shift(c, deg, tau, out):
    """Coefficients of ``p(tau + σ)`` in σ (repeated synthetic division, O(deg²))."""
    for j in range(deg + 1):
        out[j] = c[j]
    if tau == 0.0:
        return
    for i in range(deg):
        for j in range(deg - 1, i - 1, -1):
            out[j] += tau * out[j + 1]


@njit(cache=True)
def bernstein(c, deg, lo, hi, out):
    """Bernstein coefficients of ``p`` on ``[lo, hi]``, ``p(lo + (hi − lo)s) = Σ b_i B_{i,deg}(s)``.

    The power coefficients of ``p(lo + w s)`` are converted with
    ``b_i = Σ_{k≤i} C(i,k)/C(deg,k)·a_k`` (Farouki & Rajan 1987). The polynomial lies between the
    smallest and the largest ``b_i`` on the interval (convex hull property).
    """
    taylor_shift(c, deg, lo, out)
    w = hi - lo
    s = 1.0
    for k in range(deg + 1):
        out[k] *= s
        s *= w
    # in place, from the top: b_i only needs a_0..a_i
    for i in range(deg, -1, -1):
        acc = 0.0
        r = 1.0
        for k in range(i + 1):
            acc += r * out[k]
            r *= (i - k) * _RECIP[deg - k]
        out[i] = acc


@njit(cache=True, inline="always")
def _variations(b, deg):
    """Sign changes in ``b[0..deg]``, zeros skipped."""
    v = 0
    last = 0.0
    for i in range(deg + 1):
        x = b[i]
        if x == 0.0:
            continue
        if last != 0.0 and (x > 0.0) != (last > 0.0):
            v += 1
        last = x
    return v


@njit(cache=True)
def _refine(c, deg, a, b, sa, sb):
    """The root of ``p`` inside ``(a, b)`` where ``p`` has the sign of ``sa`` just after ``a`` and
    of ``sb`` just before ``b`` (opposite): bisection, with Newton steps accepted while they stay
    inside the bracket, down to adjacent machine numbers. Ends are never evaluated."""
    if (sa > 0.0) == (sb > 0.0):
        # rounding put the sign change at an end (a root at, or within rounding of, an end
        # point, e.g. a subdivision point): the end where |p| is smaller
        return a if abs(poly_val(c, deg, a)) <= abs(poly_val(c, deg, b)) else b
    up = sa < 0.0  # p rises through the root
    x = 0.5 * (a + b)
    for _ in range(400):
        f = poly_val(c, deg, x)
        if f == 0.0:
            return x
        if (f > 0.0) == up:
            b = x
        else:
            a = x
        d = poly_der(c, deg, x)
        xn = x - f / d if d != 0.0 else 0.5 * (a + b)
        if not (a < xn < b) or abs(xn - x) > 0.5 * (b - a):
            xn = 0.5 * (a + b)
        if xn <= a or xn >= b:
            break
        x = xn
    return x


@njit(cache=True)
def real_roots(c, deg, lo, hi, roots, work):
    """All real roots of ``p`` in the open interval ``(lo, hi)``, ascending, in ``roots``;
    returns how many (at most ``roots.size``).

    ``work`` is scratch of shape ``(MAX_DEPTH + 3, ≥ deg + 1)``. A root of even multiplicity
    (touching zero) is reported once; a cluster narrower than ``2⁻⁶⁰(hi − lo)`` counts as one.
    """
    if hi <= lo:
        return 0
    while deg > 0 and c[deg] == 0.0:  # vanishing leading coefficients
        deg -= 1
    if deg == 0:
        return 0
    bernstein(c, deg, lo, hi, work[0])
    return _isolate(c, deg, lo, hi, roots, work)


@njit(cache=True)
def _isolate(c, deg, lo, hi, roots, work):
    """:func:`real_roots` given the Bernstein coefficients on ``[lo, hi]`` in ``work[0]``."""
    n = 0
    w = hi - lo
    tmp = work[MAX_DEPTH + 2]
    lefts = work[R_LEFT]
    rights = work[R_RIGHT]
    lefts[0] = 0.0
    rights[0] = 1.0
    top = 1
    while top > 0 and n < roots.size:
        top -= 1
        b = work[top]
        l_ = lefts[top]
        r_ = rights[top]
        v = _variations(b, deg)
        if v == 0:
            continue
        xl = lo + w * l_
        xr = lo + w * r_
        if v == 1 or top >= MAX_DEPTH or r_ - l_ < 1e-18:
            if v == 1:
                # the sign of p just inside each end: its first / last non-zero Bernstein
                # coefficient (an end value may be an exact zero: a root at the end, which
                # Descartes' rule does not count)
                i = 0
                while b[i] == 0.0:
                    i += 1
                j = deg
                while b[j] == 0.0:
                    j -= 1
                x = _refine(c, deg, xl, xr, b[i], b[j])
            else:  # a cluster or a multiple root
                x = 0.5 * (xl + xr)
            if lo < x < hi:
                roots[n] = x
                n += 1
            continue
        # de Casteljau at s = 1/2: right half into work[top], left half into work[top + 1]
        for i in range(deg + 1):
            tmp[i] = b[i]
        lhalf = work[top + 1]
        lhalf[0] = tmp[0]
        b[deg] = tmp[deg]
        for r in range(1, deg + 1):
            for i in range(deg - r + 1):
                tmp[i] = 0.5 * (tmp[i] + tmp[i + 1])
            lhalf[r] = tmp[0]
            b[deg - r] = tmp[deg - r]
        mid = 0.5 * (l_ + r_)
        if lhalf[deg] == 0.0:  # p vanishes exactly at the midpoint
            xm = lo + w * mid
            if lo < xm < hi and n < roots.size:
                roots[n] = xm
                n += 1
        lefts[top] = mid
        rights[top] = r_
        lefts[top + 1] = l_
        rights[top + 1] = mid
        top += 2
    # sort (insertion: few roots) and drop repeats
    for i in range(1, n):
        x = roots[i]
        j = i - 1
        while j >= 0 and roots[j] > x:
            roots[j + 1] = roots[j]
            j -= 1
        roots[j + 1] = x
    m = 0
    for i in range(n):
        if m == 0 or roots[i] > roots[m - 1]:
            roots[m] = roots[i]
            m += 1
    return m


@njit(cache=True)
def scratch(deg=MAX_DEGREE):
    """Scratch array for :func:`real_roots` and the functions built on it (polynomials of degree
    up to ``deg``); callable from compiled code."""
    return np.zeros((MAX_DEPTH + 7, max(deg + 2, MAX_DEPTH + 3)))


@njit(cache=True, inline="always")
def curvature_bound(c, deg, hi):
    """Upper bound of ``|p''|`` on ``[0, hi]``: ``Σ_{j≥2} j(j−1)|c_j| hi^{j−2}``."""
    s = 0.0
    for j in range(deg, 1, -1):
        s = s * hi + j * (j - 1) * abs(c[j])
    return s


@njit(cache=True)
def max_abs_above(c, deg, lo, hi, level, work):
    """``max |p|`` on ``[lo, hi]`` (``0 ≤ lo ≤ hi``) when it exceeds ``level``; otherwise some
    value ``≤ level`` (the larger end value).

    A rigorous filter first: ``p`` deviates from its chord by at most ``(hi − lo)²/8·max|p''|``
    (bounded by :func:`curvature_bound`), so when the ends plus that deviation stay at or below
    ``level`` no search is needed; otherwise every critical point is found
    (:func:`extreme_values`); from ``lo = 0`` the filters of :func:`max_abs_on` apply. Returns
    the value and where it is (``-1.0`` for "not searched").
    """
    if lo == 0.0:
        return max_abs_on(c, deg, hi, level, work)
    v0 = abs(poly_val(c, deg, lo))
    v1 = abs(poly_val(c, deg, hi))
    ends = max(v0, v1)
    w = hi - lo
    if ends + 0.125 * w * w * curvature_bound(c, deg, hi) <= level:
        return ends, -1.0
    vmin, tmin, vmax, tmax = extreme_values(c, deg, lo, hi, work)
    if vmax >= -vmin:
        return vmax, tmax
    return -vmin, tmin


@njit(cache=True)
def extreme_values(c, deg, lo, hi, work):
    """Minimum and maximum of ``p`` on ``[lo, hi]`` and where they are: the ends and every
    critical point inside (roots of ``p'`` isolated rigorously). ``work``: :func:`scratch`."""
    v_lo = poly_val(c, deg, lo)
    v_hi = poly_val(c, deg, hi)
    if v_lo <= v_hi:
        vmin, tmin, vmax, tmax = v_lo, lo, v_hi, hi
    else:
        vmin, tmin, vmax, tmax = v_hi, hi, v_lo, lo
    if deg < 2 or hi <= lo:
        return vmin, tmin, vmax, tmax
    d = work[R_COEF]
    dd = derivative(c, deg, d)
    roots = work[R_ROOTS]
    k = real_roots(d, dd, lo, hi, roots[:dd], work)
    for i in range(k):
        x = roots[i]
        v = poly_val(c, deg, x)
        if v > vmax:
            vmax, tmax = v, x
        if v < vmin:
            vmin, tmin = v, x
    return vmin, tmin, vmax, tmax


@njit(cache=True)
def first_rise(c, deg, lo, hi, level, work):
    """First instant ``x`` in ``(lo, hi]`` where ``p`` rises above ``level``: the smallest
    machine number found with ``p(x) > level`` just after an upward crossing, or ``-1.0`` if
    there is none.

    Callers start at a level crossing (a breakaway, a stop), where rounding may put ``p(lo)`` a
    little on either side of the level: a ``p`` that starts at or below the level and rises is a
    rise at ``lo``; one that starts above it and falls through it is not a rise (that start is
    rounding). If ``p > level`` on the whole interval, ``lo`` is returned.

    Degrees 1 and 2 (the rigid block on the ground: a linear floor acceleration, a quadratic
    relative velocity) are decided in closed form by :func:`_rise_low` whenever its certified
    signs allow, else, like every higher degree, by root isolation
    (:func:`_first_rise_isolating`).
    """
    d = deg
    while d > 0 and c[d] == 0.0:
        d -= 1
    if d == 1 or d == 2:
        r = _rise_low(c[0] - level, c[1], c[2] if d == 2 else 0.0, d, lo, hi)
        if r != UNDECIDED:
            return r
    return _first_rise_isolating(c, deg, lo, hi, level, work)


@njit(cache=True, inline="always")
def rise_within(c, deg, lo, hi, level, work):
    """:func:`first_rise` of ``p`` above `level` on ``(lo, hi]``, skipped (−1) when the bound
    ``p(0) + Σ_{j≥1} |c_j| hi^j ≤ level`` shows that ``p`` stays at or below `level` on all of
    ``[0, hi]`` — valid for any ``lo`` (after an event too, where :func:`first_rise`, starting
    at ``lo > 0``, applies no such filter itself)."""
    reach = 0.0
    for j in range(deg, 0, -1):
        reach = (reach + abs(c[j])) * hi
    if c[0] + reach <= level:
        return -1.0
    return first_rise(c, deg, lo, hi, level, work)


@njit(cache=True)
def _first_rise_isolating(c, deg, lo, hi, level, work):
    """:func:`first_rise` by rigorous root isolation (any degree; the reference of the closed
    forms of :func:`_rise_low`)."""
    q = work[R_COEF]
    for j in range(deg + 1):
        q[j] = c[j]
    q[0] -= level
    while deg > 0 and q[deg] == 0.0:
        deg -= 1
    if deg == 0:
        return lo if q[0] > 0.0 else -1.0
    # quick rigorous rejections: p(lo) + Σ_{j≥1}|c_j|(hi − lo)^j ≤ level (O(deg)), then every
    # Bernstein coefficient ≤ 0 (convex hull) ⇒ p ≤ level on [lo, hi]
    if lo == 0.0:
        span = 0.0
        hj = 1.0
        for j in range(1, deg + 1):
            hj *= hi
            span += abs(q[j]) * hj
        if q[0] + span <= 0.0:
            return -1.0
    b = work[0]
    bernstein(q, deg, lo, hi, b)
    top = b[0]
    for i in range(1, deg + 1):
        top = max(top, b[i])
    if top <= 0.0:
        return -1.0
    roots = work[R_ROOTS]
    k = _isolate(q, deg, lo, hi, roots[:deg], work)
    above_lo = poly_val(q, deg, lo) > 0.0
    if k == 0:
        # one sign on the whole interval
        if poly_val(q, deg, 0.5 * (lo + hi)) > 0.0:
            return lo if above_lo else _first_positive(q, deg, lo, hi)
        return -1.0
    # before the first root: a rise right at lo if p starts at (or below) the level; if it
    # starts above and then falls through it, that start is rounding (or the caller's case of
    # a motion already beyond the level) and is not a rise
    probe = 0.5 * (lo + roots[0])
    if not above_lo and probe > lo and poly_val(q, deg, probe) > 0.0:
        return _first_positive(q, deg, lo, probe)
    for i in range(k):
        x = roots[i]
        nxt = roots[i + 1] if i + 1 < k else hi
        probe = 0.5 * (x + nxt) if nxt > x else hi
        if probe > x and poly_val(q, deg, probe) > 0.0:
            return _first_positive(q, deg, x, probe)
    return -1.0


UNDECIDED = -2.0
"""Returned by :func:`_rise_low` when a sign it needs is within its rounding bound."""
_HORNER_ERR = 1e-15
"""Relative error bound of a Horner evaluation of degree ≤ 2, and of the discriminant, above
``γ_4 = 4u/(1 − 4u) ≈ 4.4·10⁻¹⁶`` (Higham 2002, §5.1 and §1.8)."""
_TINY = 1e-300
"""Absolute slack added to every error bound (underflow in the products)."""
_SETTLE_STEPS = 16
"""Most machine numbers :func:`_settle` steps through before giving up."""


@njit(cache=True, inline="always")
def _val2(q0, q1, q2, x):
    """``q0 + q1 x + q2 x²`` by Horner, the same operations as :func:`poly_val` (degree 2; with
    ``q2 = 0`` the same value as degree 1 for finite ``x``)."""
    return (q2 * x + q1) * x + q0


@njit(cache=True, inline="always")
def _bound2(q0, q1, q2, x):
    """A bound of the rounding error of :func:`_val2` at ``x`` (Higham 2002, eq. (5.3):
    ``γ_{2n}·Σ|q_j||x|^j``), with slack for underflow."""
    ax = abs(x)
    return _HORNER_ERR * ((abs(q2) * ax + abs(q1)) * ax + abs(q0)) + _TINY


@njit(cache=True)
def _settle(q0, q1, q2, lo, hi, x):
    """The machine number ``x' ∈ (lo, hi]`` nearest the estimate ``x`` of a rising root such
    that ``q(x') > 0`` and ``q`` at the machine number before ``x'`` is ``≤ 0`` (or that number
    is ``lo``), both as evaluated by :func:`poly_val`; :data:`UNDECIDED` if that takes more than
    :data:`_SETTLE_STEPS` steps (a root so ill-conditioned that rounding blurs it over many
    machine numbers: root isolation decides)."""
    first = np.nextafter(lo, np.inf)
    if not x >= first:  # also NaN
        x = first
    if x > hi:
        x = hi
    for _ in range(_SETTLE_STEPS):
        if not _val2(q0, q1, q2, x) > 0.0:
            if x >= hi:
                return UNDECIDED
            x = np.nextafter(x, np.inf)
            continue
        xp = np.nextafter(x, -np.inf)
        if _val2(q0, q1, q2, xp) > 0.0:
            if xp <= lo:  # above 0 from lo on: not a rise through this root
                return UNDECIDED
            x = xp
            continue
        return x
    return UNDECIDED


@njit(cache=True)
def _rise_low(q0, q1, q2, deg, lo, hi):
    """:func:`first_rise` of ``q = q0 + q1 τ (+ q2 τ²)`` above 0 on ``(lo, hi]`` in closed form,
    for ``deg`` 1 (``q1 ≠ 0``) or 2 (``q2 ≠ 0``); :data:`UNDECIDED` when a sign it needs cannot
    be certified (then root isolation decides).

    Degree 1: the evaluated ``q`` (one product, one sum, both correctly rounded) is monotone in
    ``τ``, so, the sign of ``q(hi)`` being certified, a rise exists iff ``q(hi) > 0`` with
    ``q1 > 0``, and the smallest machine number with ``q > 0`` is found by stepping from
    ``−q0/q1`` (a few units in the last place): the result of root isolation, bit for bit.

    Degree 2: after the quick rejections of root isolation (replayed operation for operation),
    every decision rests on a sign certified by a rigorous error bound — of ``q`` at the ends
    and of ``q'`` there (Horner, Higham 2002 §5.1), and of the discriminant
    ``D = q1² − 4 q0 q2`` (the sign of the extremum ``−D/(4 q2)``). Ends of opposite signs hold
    one root between them (rising or falling); ends of one sign hold none or two, two only if
    the vertex is inside (``q'`` is linear: its signs at the ends tell) and ``D > 0``. That
    leaves at most one candidate rising root, computed stably without cancellation
    (``s = −(q1 + sign(q1)√D)/2``, roots ``s/q2`` and ``q0/s``: Higham 2002, §1.8; Press et al.
    2007, §5.6) and settled on machine numbers by :func:`_settle`. A start within rounding of
    0 (a stop, a breakaway) is decided by its evaluated sign, as root isolation does. Any other
    sign within its bound (a double root, a root at ``hi``, a tangency, overflow, NaN) gives
    :data:`UNDECIDED`.

    References
    ----------
    Higham, N. J. (2002). *Accuracy and Stability of Numerical Algorithms*, 2nd ed., SIAM.
    Press, W. H., Teukolsky, S. A., Vetterling, W. T., Flannery, B. P. (2007). *Numerical
    Recipes*, 3rd ed., Cambridge University Press.
    """
    if not (abs(q0) < np.inf and abs(q1) < np.inf and abs(q2) < np.inf):
        return UNDECIDED
    if not (abs(lo) < np.inf and abs(hi) < np.inf and lo < hi):
        return UNDECIDED
    # first the two quick rejections of root isolation, operation for operation (the same
    # decisions, bit for bit): p(0) + Σ|q_j| hi^j ≤ 0 from lo = 0, then every Bernstein
    # coefficient on [lo, hi] ≤ 0 (convex hull; the start counts as evaluated there: a start at
    # the level within rounding, a stop or a breakaway, is no rise)
    w = hi - lo
    if deg == 1:
        if lo == 0.0 and q0 + abs(q1) * hi <= 0.0:
            return -1.0
        b0 = q0 + lo * q1
        if max(b0, b0 + q1 * w) <= 0.0:
            return -1.0
        f_hi = q1 * hi + q0
        e_hi = _bound2(q0, q1, 0.0, hi)
        if not abs(f_hi) > e_hi:  # a root at (or within rounding of) hi
            return UNDECIDED
        if q1 > 0.0:
            if f_hi < 0.0:
                return -1.0
            if q1 * lo + q0 > 0.0:
                return lo
            return _settle(q0, q1, 0.0, lo, hi, -q0 / q1)
        # falling: above 0 on the whole interval, or no rise
        return lo if f_hi > 0.0 else -1.0
    if lo == 0.0 and q0 + (abs(q1) * hi + abs(q2) * (hi * hi)) <= 0.0:
        return -1.0
    lq2 = lo * q2
    t1 = q1 + lq2
    b0 = q0 + lo * t1  # p(lo) (Horner)
    o1 = (t1 + lq2) * w
    if max(b0, max(b0 + 0.5 * o1, (b0 + o1) + q2 * (w * w))) <= 0.0:
        return -1.0
    f_lo = b0
    e_lo = _bound2(q0, q1, q2, lo)
    f_hi = _val2(q0, q1, q2, hi)
    e_hi = _bound2(q0, q1, q2, hi)
    pos_lo = f_lo > e_lo
    neg_lo = f_lo < -e_lo
    pos_hi = f_hi > e_hi
    neg_hi = f_hi < -e_hi
    convex = q2 > 0.0
    if neg_lo and pos_hi:  # an odd number of roots inside: one, rising
        return _settle(q0, q1, q2, lo, hi, _quadratic_root(q0, q1, q2, convex))
    if pos_lo and neg_hi:  # one root inside, falling
        return -1.0
    # q' = q1 + 2 q2 τ (linear) at the ends: 2 q2 τ is exact but for under/overflow
    g_lo = 2.0 * q2 * lo + q1
    g_hi = 2.0 * q2 * hi + q1
    eg_lo = _HORNER_ERR * (2.0 * abs(q2 * lo) + abs(q1)) + _TINY
    eg_hi = _HORNER_ERR * (2.0 * abs(q2 * hi) + abs(q1)) + _TINY
    inc_lo = g_lo > eg_lo
    dec_lo = g_lo < -eg_lo
    inc_hi = g_hi > eg_hi
    dec_hi = g_hi < -eg_hi
    vertex_inside = (dec_lo and inc_hi) or (inc_lo and dec_hi)
    disc = q1 * q1 - 4.0 * q0 * q2
    e_disc = _HORNER_ERR * (q1 * q1 + 4.0 * abs(q0 * q2)) + _TINY
    if pos_lo and pos_hi:  # no root inside, or two
        if not convex or inc_lo or dec_hi:  # concave, or monotone: above 0 throughout
            return lo
        if vertex_inside:
            if disc < -e_disc:  # minimum above 0
                return lo
            if disc > e_disc:  # falls, then rises through the larger root
                return _settle(q0, q1, q2, lo, hi, _quadratic_root(q0, q1, q2, True))
        return UNDECIDED
    if neg_lo and neg_hi:  # no root inside, or a brief excursion above 0
        if convex or dec_lo or inc_hi:  # convex, or monotone: below 0 throughout
            return -1.0
        if vertex_inside:
            if disc < -e_disc:  # maximum below 0
                return -1.0
            if disc > e_disc:  # rises through the smaller root
                return _settle(q0, q1, q2, lo, hi, _quadratic_root(q0, q1, q2, False))
        return UNDECIDED
    # q(lo) within rounding of 0 (a start at a stop or a breakaway); q(hi) certified
    if not (pos_lo or neg_lo):
        if pos_hi:
            if not convex or inc_lo:  # above 0 on (lo, hi] but within rounding of lo
                if f_lo > 0.0:
                    return lo
                return _settle(q0, q1, q2, lo, hi, _quadratic_root(q0, q1, q2, convex))
            if dec_lo and inc_hi and disc > e_disc:  # falls from lo, rises through the larger
                return _settle(q0, q1, q2, lo, hi, _quadratic_root(q0, q1, q2, True))
            return UNDECIDED
        if neg_hi and f_lo > 0.0 and (convex or (dec_lo and dec_hi)):
            # starts above 0 (as evaluated) and stays below q(lo) (convex: q ≤ max of the
            # ends; or decreasing), the set where q ≤ 0 an interval ending at hi: no rise
            return -1.0
    return UNDECIDED


@njit(cache=True, inline="always")
def _quadratic_root(q0, q1, q2, larger):
    """The larger or smaller real root of ``q0 + q1 τ + q2 τ²`` (``q2 ≠ 0``, discriminant known
    positive), without cancellation: ``s = −(q1 + sign(q1)√D)/2``, roots ``s/q2`` and ``q0/s``
    (Higham 2002, §1.8). NaN if ``s`` vanishes (then :func:`_settle` starts at ``lo``)."""
    disc = q1 * q1 - 4.0 * q0 * q2
    sq = np.sqrt(max(disc, 0.0))
    s = -0.5 * (q1 + sq) if q1 >= 0.0 else -0.5 * (q1 - sq)
    if s == 0.0:
        return np.nan
    r1 = s / q2
    r2 = q0 / s
    if larger:
        return max(r1, r2)
    return min(r1, r2)


@njit(cache=True)
def _first_positive(q, deg, a, b):
    """Smallest machine number in ``(a, b]`` found with ``q > 0``, given ``q(b) > 0`` and a root
    of ``q`` refined to (nearly) adjacent machine numbers at ``a``: steps up from ``a`` by
    doubling distances, then bisects the last bracket."""
    if poly_val(q, deg, a) > 0.0:
        return a  # the root is at most an ulp or two below
    lo = a
    step = np.nextafter(a, np.inf) - a
    hi = a + step
    while hi < b and not poly_val(q, deg, hi) > 0.0:
        lo = hi
        step *= 2.0
        hi = a + step
    if hi >= b:
        hi = b
    for _ in range(200):
        m = 0.5 * (lo + hi)
        if m <= lo or m >= hi:
            break
        if poly_val(q, deg, m) > 0.0:
            hi = m
        else:
            lo = m
    return hi


@njit(cache=True)
def newton_peak(c, K, h, t0, d_lo):
    """``|p|`` at the single root of ``p'`` in ``(0, h)`` and that root, given that ``p'`` is
    monotone there and changes sign (``d_lo = p'(0)``): Newton from ``t0``, safeguarded by
    bisection (``p'`` and ``p''`` evaluated together, two independent Horner chains)."""
    lo = 0.0
    hi = h
    x = t0 if 0.0 < t0 < h else 0.5 * h
    for _ in range(100):
        d = K * c[K]
        d2 = K * (K - 1) * c[K]
        for j in range(K - 1, 1, -1):
            d = d * x + j * c[j]
            d2 = d2 * x + j * (j - 1) * c[j]
        d = d * x + c[1]
        if d == 0.0:
            break
        if (d > 0.0) == (d_lo > 0.0):
            lo = x
        else:
            hi = x
        xn = x - d / d2 if d2 != 0.0 else 0.5 * (lo + hi)
        if not (lo < xn < hi):
            xn = 0.5 * (lo + hi)
        if abs(xn - x) <= 4e-16 * max(abs(xn), h) or hi - lo <= 4e-16 * h:
            x = xn
            break
        x = xn
    return abs(poly_val(c, K, x)), x


@njit(cache=True)
def max_abs_on(c, K, h, level, work):
    """``max |p|`` on ``[0, h]`` and where it is when it can exceed ``level`` (else a value
    ``≤ level``), with no assumption on the number of critical points.

    Rigorous filters first, cheapest first, with ``M_k`` the bound ``Σ_j j!/(j−k)!·|c_j|h^{j−k}``
    of ``|p^(k)|`` on the sub-step: the chord (ends ``+ h²/8·M_2 ≤ level``: nothing to find);
    ``p'`` of one sign at both ends and farther from zero than ``h²/8·M_3`` (``p`` monotone);
    ``|p''(0)| > h·M_3`` (``p'`` monotone: at most one critical point, found by Newton).
    Otherwise every critical point is isolated (:func:`extreme_values`).
    """
    v0 = abs(c[0])
    v1 = abs(poly_val(c, K, h))
    ends, t_end = (v0, 0.0) if v0 >= v1 else (v1, h)
    if K < 2:
        return ends, t_end
    m2 = 0.0
    m3 = 0.0
    for j in range(K, 1, -1):
        m2 = m2 * h + j * (j - 1) * abs(c[j])
        if j >= 3:
            m3 = m3 * h + j * (j - 1) * (j - 2) * abs(c[j])
    k8 = 0.125 * h * h
    if ends + k8 * m2 <= level:
        return ends, t_end
    d0 = c[1]
    d1 = poly_der(c, K, h)
    if d0 * d1 > 0.0 and min(abs(d0), abs(d1)) > k8 * m3:
        return ends, t_end
    if abs(2.0 * c[2]) > h * m3:
        if d0 * d1 < 0.0:
            v, x = newton_peak(c, K, h, 0.5 * h, d0)
            if v > ends:
                return v, x
        return ends, t_end
    vmin, tmin, vmax, tmax = extreme_values(c, K, 0.0, h, work)
    if vmax >= -vmin:
        return vmax, tmax
    return -vmin, tmin
