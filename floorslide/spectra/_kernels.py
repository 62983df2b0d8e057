"""Compiled kernel of exact response spectra with peaks inside steps.

A bank of linear oscillators (``q'' + 2ξω q' + ω² q = −a_f(t)``) is advanced through the record
by the exact recurrence of the oscillator coupled to the floor (Nigam & Jennings 1969 on the
ground; the augmented first-order hold on a building floor). Per sub-step a rigorous bound
decides whether a peak can be exceeded inside it; only then is the in-step response expanded in
its Taylor polynomial (from the exact state, see ``building/exact.py``) and its extrema found.

Bound: with ``ρ² = q² + (q'/ω)²``, ``dρ/dt ≤ |a_f|/ω`` (the damping only removes energy), so
inside a sub-step of length h, ``ρ ≤ ρ₀ + h·max|a_f|/ω``; then ``|q| ≤ ρ``, ``|q'| ≤ ωρ`` and
``|ω²q + 2ξωq'| ≤ ω²√(1+4ξ²)·ρ``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from floorslide.building._instep import extreme_values, taylor_coefficients


@njit(cache=True)
def spectrum_kernel(phi, p, q, R, beta, acc, substeps, h, K, w, xi, Pqq, Pqx, pq, qq, out):
    """Peaks of a bank of oscillators on one floor.

    Parameters
    ----------
    phi, p, q
        Exact sub-step recurrence of the building (empty on the ground).
    R, beta
        Taylor rows of the floor's absolute acceleration, degree ``K`` (``(K+1, n)``).
    acc
        Ground acceleration samples.
    substeps, h
        Sub-steps per record step and their length.
    w, xi
        Circular frequencies and damping ratios of the oscillators.
    Pqq, Pqx, pq, qq
        Exact sub-step recurrence of each oscillator coupled to the floor:
        ``[q, q']_{j+1} = Pqq [q, q']_j + Pqx x_j + pq a_j + qq a_{j+1}``.
    out
        ``(n_osc, 3)``: peaks of ``|q|``, ``|q'|`` and ``|ω² q + 2ξω q'|``.
    """
    n = phi.shape[0]
    nosc = w.size
    npts = acc.size
    kr = R.shape[0] - 1
    x = np.zeros(n)
    x_prev = np.zeros(n)
    xn = np.empty(n)
    c = np.zeros(K + 1)
    have_c = False
    Q = np.zeros(K + 1)
    poly = np.zeros(K + 1)
    state = np.zeros((nosc, 3))
    for i in range(nosc):
        out[i, 0] = 0.0
        out[i, 1] = 0.0
        out[i, 2] = 0.0
    # absolute acceleration of the oscillator at rest at t = 0 is 0; the floor starts at rest
    for k in range(npts - 1):
        a = acc[k]
        a1 = acc[k + 1]
        slope = (a1 - a) / (substeps * h)
        for sub in range(substeps):
            aa = a + (a1 - a) * (sub / substeps)
            ab = a + (a1 - a) * ((sub + 1) / substeps) if sub + 1 < substeps else a1
            for i in range(n):
                x_prev[i] = x[i]
            for i in range(n):
                s_ = p[i] * aa + q[i] * ab
                for j in range(n):
                    s_ += phi[i, j] * x_prev[j]
                xn[i] = s_
            for i in range(n):
                x[i] = xn[i]
            # bound of |a_f| on the sub-step: ends plus the Taylor remainder-free interior check
            f0 = beta[0] * aa
            f1 = beta[0] * ab
            for j in range(n):
                f0 += R[0, j] * x_prev[j]
                f1 += R[0, j] * x[j]
            have_c = False
            if n > 0:
                for j in range(K + 1):
                    c[j] = 0.0
                taylor_coefficients(R, beta, x_prev, aa, slope, c[: kr + 1])
                have_c = True
                amin, _, amax, _ = extreme_values(c, K, 0.0, h)
                abound = max(amax, -amin)
            else:
                abound = max(abs(f0), abs(f1))
            for o in range(nosc):
                q0 = state[o, 0]
                v0 = state[o, 1]
                d0 = state[o, 2]  # q'' at the sub-step start
                wo = w[o]
                c2 = 2.0 * xi[o] * wo
                w2 = wo * wo
                # exact update
                q1 = Pqq[o, 0, 0] * q0 + Pqq[o, 0, 1] * v0 + pq[o, 0] * aa + qq[o, 0] * ab
                v1 = Pqq[o, 1, 0] * q0 + Pqq[o, 1, 1] * v0 + pq[o, 1] * aa + qq[o, 1] * ab
                for j in range(n):
                    q1 += Pqx[o, 0, j] * x_prev[j]
                    v1 += Pqx[o, 1, j] * x_prev[j]
                d1 = -(f1 + c2 * v1 + w2 * q1)
                A1 = w2 * q1 + c2 * v1
                # peaks at the sub-step end
                if abs(q1) > out[o, 0]:
                    out[o, 0] = abs(q1)
                if abs(v1) > out[o, 1]:
                    out[o, 1] = abs(v1)
                if abs(A1) > out[o, 2]:
                    out[o, 2] = abs(A1)
                # an interior extremum needs the derivative to change sign inside the sub-step
                # (at most one critical point per sub-step, ω h ≤ 0.5) ...
                sd = (v0 > 0.0) != (v1 > 0.0)
                sv = (d0 > 0.0) != (d1 > 0.0)
                sa = ((w2 * v0 + c2 * d0) > 0.0) != ((w2 * v1 + c2 * d1) > 0.0)
                if sd or sv or sa:
                    # ... and the rigorous energy bound to allow a new peak
                    rho = math.sqrt(q0 * q0 + (v0 / wo) * (v0 / wo)) + h * abound / wo
                    need_d = sd and rho > out[o, 0]
                    need_v = sv and wo * rho > out[o, 1]
                    need_a = sa and w2 * math.sqrt(1.0 + 4.0 * xi[o] * xi[o]) * rho > out[o, 2]
                else:
                    need_d = need_v = need_a = False
                if need_d or need_v or need_a:
                    if not have_c:
                        for j in range(K + 1):
                            c[j] = 0.0
                        c[0] = aa
                        if K >= 1:
                            c[1] = slope
                        have_c = True
                    # Taylor coefficients of q on the sub-step (from the exact start state)
                    Q[0] = q0
                    if K >= 1:
                        Q[1] = v0
                    for j in range(K - 1):
                        Q[j + 2] = (-c2 * (j + 1) * Q[j + 1] - w2 * Q[j] - c[j]) / (
                            (j + 1) * (j + 2)
                        )
                    if need_d:
                        vmin, _, vmax, _ = extreme_values(Q, K, 0.0, h)
                        m = max(vmax, -vmin)
                        if m > out[o, 0]:
                            out[o, 0] = m
                    if need_v:
                        for j in range(K):
                            poly[j] = (j + 1) * Q[j + 1]
                        poly[K] = 0.0
                        vmin, _, vmax, _ = extreme_values(poly, K, 0.0, h)
                        m = max(vmax, -vmin)
                        if m > out[o, 1]:
                            out[o, 1] = m
                    if need_a:
                        for j in range(K):
                            poly[j] = w2 * Q[j] + c2 * (j + 1) * Q[j + 1]
                        poly[K] = w2 * Q[K]
                        vmin, _, vmax, _ = extreme_values(poly, K, 0.0, h)
                        m = max(vmax, -vmin)
                        if m > out[o, 2]:
                            out[o, 2] = m
                state[o, 0] = q1
                state[o, 1] = v1
                state[o, 2] = d1
