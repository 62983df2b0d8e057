"""Compiled helpers for functions known in closed form inside one time step.

Inside a step of a piecewise-linear ground record, every response of a linear system is an
entire function of the time ``τ`` since the step began. The exact stepper (``exact.py``)
represents it near the step start by its Taylor polynomial ``p(τ) = Σ_j c_j τ^j`` whose
coefficients come from the exact state, on sub-steps short enough (``ρ(A)·h ≤ 0.5``) that the
truncated series equals the function to rounding. These helpers step the state and form those
coefficients; the roots, extrema and first crossings of the polynomials (events and peaks
inside steps) are found rigorously by :mod:`floorslide.numerics.polynomial`, which also holds
the polynomial evaluation re-exported here.
"""

from __future__ import annotations

from floorslide._jit import njit
from floorslide.numerics.polynomial import poly_der, poly_der2, poly_val

__all__ = [
    "foh_step",
    "poly_der",
    "poly_der2",
    "poly_val",
    "substep_inputs",
    "taylor_coefficients",
]


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


@njit(cache=True)
def curvature_tail_weights(R, beta, h, WX):
    """Weights of the tail ``j ≥ 4`` of the bound ``max|y''| ≤ Σ_j j(j−1)h^{j−2}|c_j|`` on a
    sub-step of length ``h`` for an output with Taylor rows ``R, beta`` (see
    :func:`taylor_coefficients`): ``|c_j| ≤ Σ_i |R_ji||x_i| + |β_j||a| + |β_{j−1}|/j·|slope|``.
    ``WX`` receives the per-state weights; returns ``(WA, WS)``, those of ``|a|`` and
    ``|slope|``. The terms ``j = 2, 3`` are formed exactly by :func:`curvature_bound_at` (the
    states of a building cancel in them: bounding them by absolute values would be loose)."""
    n = WX.size
    K = R.shape[0] - 1
    for i in range(n):
        WX[i] = 0.0
    WA = 0.0
    WS = 0.0
    hj = h * h
    for j in range(4, K + 1):
        wj = j * (j - 1) * hj
        for i in range(n):
            WX[i] += wj * abs(R[j, i])
        WA += wj * abs(beta[j])
        WS += wj * abs(beta[j - 1]) / j
        hj *= h
    return WA, WS


@njit(cache=True, inline="always")
def curvature_bound_at(R, beta, x, a, slope, h, WX, WA, WS):
    """Upper bound of ``|y''|`` on a sub-step from its start state ``x``, ground value ``a`` and
    slope: ``2|c_2| + 6h|c_3|`` exactly, plus the tail weighted by
    :func:`curvature_tail_weights`; O(n)."""
    K = R.shape[0] - 1
    n = x.size
    tail = WA * abs(a) + WS * abs(slope)
    c2 = 0.0
    c3 = 0.0
    if K >= 2:
        c2 = beta[2] * a + beta[1] / 2.0 * slope
        for i in range(n):
            c2 += R[2, i] * x[i]
    if K >= 3:
        c3 = beta[3] * a + beta[2] / 3.0 * slope
        for i in range(n):
            c3 += R[3, i] * x[i]
    for i in range(n):
        tail += WX[i] * abs(x[i])
    return 2.0 * abs(c2) + 6.0 * h * abs(c3) + tail
