"""Compiled helpers for functions known in closed form inside one time step.

Inside a step of a piecewise-linear ground record, every response of a linear system is an
entire function of the time ``τ`` since the step began. The exact stepper (``exact.py``)
represents it near the step start by its Taylor polynomial ``p(τ) = Σ_j c_j τ^j`` whose
coefficients come from the exact state, on sub-steps short enough (``ρ(A)·h ≤ 0.5``) that the
truncated series equals the function to rounding. These helpers evaluate such polynomials,
find their extrema and the first instant they cross a level — the events and peaks inside
steps that sliding, spectra and floor motions need.

All functions assume at most one critical point of ``p`` inside the interval searched, which the
sub-step length guarantees for the responses met here (each sub-step is a small fraction of the
shortest period of the system).
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit

_MAX_ITER = 200


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


@njit(cache=True, inline="always")
def substep_inputs(a, a1, r, m):
    """Ground values at the ends of sub-step ``r`` of ``m`` equal sub-steps of a record step from
    ``a`` to ``a1`` (the record is linear there; the last end is ``a1`` itself)."""
    aa = a + (a1 - a) * (r / m)
    ab = a + (a1 - a) * ((r + 1) / m) if r + 1 < m else a1
    return aa, ab


@njit(cache=True, inline="always")
def foh_step(phi, p, q, x, aa, ab, out):
    """``out = Φx + p·aa + q·ab``: the exact first-order-hold step of a linear system's state over
    a (sub-)step whose input goes linearly from ``aa`` to ``ab`` (``out`` must not be ``x``)."""
    n = x.size
    for i in range(n):
        s = p[i] * aa + q[i] * ab
        for j in range(n):
            s += phi[i, j] * x[j]
        out[i] = s


@njit(cache=True)
def critical_point(c, deg, lo, hi):
    """The root of ``p'`` in ``[lo, hi]`` given that ``p'`` changes sign there (safeguarded
    Newton on ``p'`` with bisection fallback)."""
    dlo = poly_der(c, deg, lo)
    a, b = lo, hi
    x = 0.5 * (a + b)
    for _ in range(_MAX_ITER):
        d = poly_der(c, deg, x)
        if d == 0.0:
            return x
        if (d > 0.0) == (dlo > 0.0):
            a = x
        else:
            b = x
        d2 = poly_der2(c, deg, x)
        xn = x - d / d2 if d2 != 0.0 else 0.5 * (a + b)
        if not (a < xn < b):
            xn = 0.5 * (a + b)
        if abs(xn - x) <= 4e-16 * max(abs(xn), abs(hi)) or b - a <= 4e-16 * max(abs(b), 1e-300):
            return xn
        x = xn
    return x


@njit(cache=True)
def first_rise(c, deg, lo, hi, level):
    """First ``x`` in ``(lo, hi]`` where ``p(x) > level``, or ``-1.0`` if there is none.

    ``p(x) ≤ level`` is assumed just after ``lo``. The instant returned is the smallest machine
    number found with ``p(x) > level`` (to within a few ulps of the true crossing).
    """
    f_hi = poly_val(c, deg, hi) - level
    if f_hi > 0.0:
        a, b = lo, hi
    else:
        d_lo = poly_der(c, deg, lo)
        d_hi = poly_der(c, deg, hi)
        if not (d_lo > 0.0 and d_hi < 0.0):
            return -1.0
        xc = critical_point(c, deg, lo, hi)
        if not (poly_val(c, deg, xc) - level > 0.0):
            return -1.0
        a, b = lo, xc
    # invariant: p(a) <= level (or a == lo), p(b) > level
    x = b
    for _ in range(_MAX_ITER):
        if b - a <= 2e-16 * max(abs(a), abs(b)) + 1e-300:
            break
        f = poly_val(c, deg, x) - level
        d = poly_der(c, deg, x)
        xn = x - f / d if d != 0.0 else 0.5 * (a + b)
        if not (a < xn < b) or abs(xn - x) > 0.5 * (b - a):
            xn = 0.5 * (a + b)
        fn = poly_val(c, deg, xn) - level
        if fn > 0.0:
            b = xn
        else:
            a = xn
        if xn == x:
            break
        x = xn
    return b


@njit(cache=True)
def extreme_values(c, deg, lo, hi):
    """Minimum and maximum of ``p`` on ``[lo, hi]`` and where they are (ends or the interior
    critical point)."""
    v_lo = poly_val(c, deg, lo)
    v_hi = poly_val(c, deg, hi)
    if v_lo <= v_hi:
        vmin, tmin, vmax, tmax = v_lo, lo, v_hi, hi
    else:
        vmin, tmin, vmax, tmax = v_hi, hi, v_lo, lo
    d_lo = poly_der(c, deg, lo)
    d_hi = poly_der(c, deg, hi)
    if (d_lo > 0.0 and d_hi < 0.0) or (d_lo < 0.0 and d_hi > 0.0):
        xc = critical_point(c, deg, lo, hi)
        vc = poly_val(c, deg, xc)
        if vc > vmax:
            vmax, tmax = vc, xc
        if vc < vmin:
            vmin, tmin = vc, xc
    return vmin, tmin, vmax, tmax


@njit(cache=True)
def taylor_coefficients(R, beta, x, a0, slope, out):
    """Taylor coefficients at a step start of an output ``y = r·x + d·a_g`` of
    ``x' = A x + b a_g`` with ``a_g(τ) = a0 + slope·τ``.

    ``R[j] = r A^j / j!`` and ``beta[j] = r A^{j-1} b / j!`` (``beta[0] = d``) are precomputed
    by :meth:`ExactStepper.taylor_rows`; the ``j``-th coefficient is
    ``R[j]·x + beta[j]·a0 + gamma[j]·slope`` with ``gamma[j] = beta[j-1]/j``.
    """
    K = R.shape[0]
    n = x.size
    for j in range(K):
        s = 0.0
        for i in range(n):
            s += R[j, i] * x[i]
        s += beta[j] * a0
        if j >= 1:
            s += beta[j - 1] / j * slope
        out[j] = s


def np_poly_extrema(c: np.ndarray, lo: float, hi: float) -> tuple[float, float, float, float]:
    """Python wrapper of :func:`extreme_values` for tests."""
    c = np.ascontiguousarray(c, dtype=float)
    return extreme_values(c, c.size - 1, lo, hi)
