"""Compiled kernels of response and RotD spectra on a poly motion's segments
(:mod:`floorslide.building.poly_segments`).

On a segment the floor's acceleration is a polynomial ``p(τ) = Σ_j p_j τ^j`` (given), and the
oscillator ``q'' + 2ξω q' + ω² q = −p`` — the state ``x = (q, q')``, ``x' = A x + b p`` with
``A = [[0, 1], [−ω², −2ξω]]``, ``b = (0, −1)`` — has the Taylor series
``x_{j+1} = (A x_j + b p_j)/(j + 1)`` from its state at the segment's start. A segment is cut
into equal pieces with ``ω·L ≤`` :data:`PHASE`, on which the series is summed until two
consecutive terms (beyond the forcing's degree) are below :data:`TERM_TOL` of the terms so far:
the homogeneous part then decays like ``(ωL)^j/j!`` and the polynomial equals the exact solution
to rounding. A piece on which they have not decayed by degree :data:`NMAX` (a forcing whose own
high terms are large on it) is halved until they do. On each piece the peaks of ``q``, ``q'``,
``ω²q + 2ξωq'`` (``q'' + p``: the absolute acceleration) — and for RotD of every rotated
``q_θ = q1 cos θ + q2 sin θ`` and of ``q1² + q2²`` — are found by
:func:`floorslide.numerics.polynomial.max_abs_on` (rigorous filters, then every critical point
isolated), where a coefficient bound ``Σ_j |c_j| L^j`` allows a new peak.

References
----------
Jorba, À., Zou, M. (2005). A software package for the numerical integration of ODEs by means of
high-order Taylor methods. *Experimental Mathematics* 14(1), 99–117.
"""

from __future__ import annotations

import math

import numpy as np

from floorslide._jit import njit
from floorslide.numerics.polynomial import (
    curvature_bound,
    max_abs_on,
    poly_val,
    scratch,
    taylor_shift,
)

PHASE = 0.5
"""Longest piece of a segment, ``ω·L``, on which an oscillator's series is summed."""
NMAX = 31
"""Highest degree of an oscillator's series (``q1² + q2²`` then has degree ≤ 62, within the
root isolation's 64)."""
MAX_PIECES = 1 << 20
"""Most pieces a segment is halved into for one oscillator (a guard against a forcing that is
not finite: its series never converge)."""
TERM_TOL = 1e-18
"""The series ends when two consecutive terms ``|q_j|L^j + |q'_j|L^{j+1}`` are below this
fraction of the sum of the terms so far."""


@njit(cache=True, inline="always")
def _degree(coef, s, f, cx, cy, p):
    """The forcing ``p = cx·coef[s, f, 0] + cy·coef[s, f, 1]`` and its degree (last nonzero
    coefficient, at least 1)."""
    K = 1
    for j in range(coef.shape[3]):
        p[j] = cx * coef[s, f, 0, j] + cy * coef[s, f, 1, j]
        if j > K and p[j] != 0.0:
            K = j
    return K


@njit(cache=True)
def oscillator_series(p, K, w, xi, L, q0, v0, q, v):
    """Taylor coefficients ``q[0..N]``, ``v[0..N]`` of an oscillator's displacement and velocity
    on a piece ``[0, L]`` from ``(q0, v0)``, driven by ``−p`` (degree ``K``). Returns ``N``
    (at most :data:`NMAX`), or −1 when the terms have not decayed by then (the piece is too
    long for the forcing's own terms: the caller halves it)."""
    w2 = w * w
    zw = 2.0 * xi * w
    q[0] = q0
    v[0] = v0
    total = abs(q0) + abs(v0) * L
    Lj = 1.0
    small = 0
    N = -1
    for j in range(NMAX):
        pj = p[j] if j <= K else 0.0
        inv = 1.0 / (j + 1)
        q[j + 1] = v[j] * inv
        v[j + 1] = (-w2 * q[j] - zw * v[j] - pj) * inv
        Lj *= L
        term = abs(q[j + 1]) * Lj + abs(v[j + 1]) * Lj * L
        if j + 1 > K + 1 and term <= TERM_TOL * total:
            small += 1
            if small == 2:
                N = j + 1
                break
        else:
            small = 0
        total += term
    return N


@njit(cache=True, inline="always")
def _bound(c, N, L):
    """An upper bound of ``max |c(τ)|`` on ``[0, L]``: the smaller of ``Σ_j |c_j| L^j`` and
    the larger end value plus ``L²/8·max|c''|`` (a polynomial deviates from its chord by at most
    that; ``max|c''|`` bounded by :func:`~floorslide.numerics.polynomial.curvature_bound`)."""
    b = 0.0
    e = 0.0
    for j in range(N, -1, -1):
        b = b * L + abs(c[j])
        e = e * L + c[j]
    chord = max(abs(c[0]), abs(e)) + 0.125 * L * L * curvature_bound(c, N, L)
    return min(b, chord)


@njit(cache=True)
def spectrum_segments_kernel(t0, length, coef, f, cx, cy, w, xi, S, out, rigid, work):
    """Raise the peaks ``out[o] = (max|q|, max|q'|, max|ω²q + 2ξωq'|)`` of oscillators
    ``(w[o], xi[o])`` (states ``S[o] = (q, q')`` in/out) and ``rigid = (max|p|, its time)`` over
    one chunk of segments, the forcing ``p`` the floor row `f`'s acceleration along
    ``(cx, cy)``."""
    KM = coef.shape[3] - 1
    p = np.zeros(KM + 1)
    pp = np.zeros(KM + 1)
    q = np.zeros(NMAX + 1)
    v = np.zeros(NMAX + 1)
    s3 = np.zeros(NMAX + 1)
    for s in range(t0.size):
        L = length[s]
        K = _degree(coef, s, f, cx, cy, p)
        if _bound(p, K, L) > rigid[0]:
            m, t = max_abs_on(p, K, L, rigid[0], work)
            if m > rigid[0]:
                rigid[0] = m
                rigid[1] = t0[s] + t
        for o in range(w.size):
            wo = w[o]
            zw = 2.0 * xi[o] * wo
            w2 = wo * wo
            npc = max(1, math.ceil(wo * L / PHASE))
            hp = L / npc
            r = 0
            pos = 0.0
            while r < npc:
                taylor_shift(p, K, pos, pp)
                N = oscillator_series(pp, K, wo, xi[o], hp, S[o, 0], S[o, 1], q, v)
                if N < 0 and npc < MAX_PIECES:
                    # not converged: this piece and the rest of the segment in twice as many
                    npc = 2 * (npc - r)
                    r = 0
                    hp = (L - pos) / npc
                    continue
                N = NMAX if N < 0 else N
                r += 1
                pos = L - (npc - r) * hp
                for j in range(N + 1):
                    s3[j] = w2 * q[j] + zw * v[j]
                if _bound(q, N, hp) > out[o, 0]:
                    out[o, 0] = max(out[o, 0], max_abs_on(q, N, hp, out[o, 0], work)[0])
                if _bound(v, N, hp) > out[o, 1]:
                    out[o, 1] = max(out[o, 1], max_abs_on(v, N, hp, out[o, 1], work)[0])
                if _bound(s3, N, hp) > out[o, 2]:
                    out[o, 2] = max(out[o, 2], max_abs_on(s3, N, hp, out[o, 2], work)[0])
                S[o, 0] = poly_val(q, N, hp)
                S[o, 1] = poly_val(v, N, hp)


def new_scratch():
    """Scratch of the root isolation for polynomials up to degree ``2·NMAX``."""
    return scratch(2 * NMAX)


@njit(cache=True)
def _vector_and_angles(Q1, Q2, N, L, t_start, cs, sn, M, R2, W, o, r2, c, work, Mmin):
    """Raise oscillator (or rigid row) `o`'s peaks on one piece: ``R2[o] = max(q1² + q2²)`` and
    ``W[o] = (time, q1, q2)`` there; ``M[o, j] = max|q1 cos θ_j + q2 sin θ_j|``. ``Mmin[o]`` is
    the smallest ``M[o, j]``: no angle is looked at while ``|q_θ| ≤ |q| ≤ √(B1² + B2²)``
    (``B`` the coefficient bounds of ``q1``, ``q2``) stays below it."""
    B1 = _bound(Q1, N, L)
    B2 = _bound(Q2, N, L)
    if B1 * B1 + B2 * B2 > R2[o]:
        for j in range(2 * N + 1):
            r2[j] = 0.0
        for i in range(N + 1):
            for j in range(N + 1):
                r2[i + j] += Q1[i] * Q1[j] + Q2[i] * Q2[j]
        m, t = max_abs_on(r2, 2 * N, L, R2[o], work)
        if m > R2[o]:
            R2[o] = m
            W[o, 0] = t_start + t
            W[o, 1] = poly_val(Q1, N, t)
            W[o, 2] = poly_val(Q2, N, t)
    if B1 * B1 + B2 * B2 <= Mmin[o] * Mmin[o]:
        return
    raised = False
    for a in range(cs.size):
        if abs(cs[a]) * B1 + abs(sn[a]) * B2 <= M[o, a]:
            continue
        for j in range(N + 1):
            c[j] = cs[a] * Q1[j] + sn[a] * Q2[j]
        if _bound(c, N, L) > M[o, a]:
            m = max_abs_on(c, N, L, M[o, a], work)[0]
            if m > M[o, a]:
                M[o, a] = m
                raised = True
    if raised:
        low = M[o, 0]
        for a in range(1, cs.size):
            low = min(low, M[o, a])
        Mmin[o] = low


@njit(cache=True)
def rotd_segments_kernel(t0, length, coef, f, w, xi, cs, sn, S, M, R2, W, M0, R20, W0, work):
    """RotD peaks over one chunk of segments of floor row `f`: for oscillators ``(w[o], xi[o])``
    (states ``S[o] = (q1, q1', q2, q2')`` in/out) ``M[o, j] = max_t |q_θj|``,
    ``R2[o] = max_t (q1² + q2²)``, ``W[o] = (time, q1, q2)`` at that peak; the same of the floor
    acceleration itself in ``M0[0], R20[0], W0[0]`` (period 0)."""
    KM = coef.shape[3] - 1
    p1 = np.zeros(KM + 1)
    p2 = np.zeros(KM + 1)
    pp1 = np.zeros(KM + 1)
    pp2 = np.zeros(KM + 1)
    Q1 = np.zeros(NMAX + 1)
    V1 = np.zeros(NMAX + 1)
    Q2 = np.zeros(NMAX + 1)
    V2 = np.zeros(NMAX + 1)
    r2 = np.zeros(2 * NMAX + 1)
    c = np.zeros(max(NMAX, KM) + 1)
    low = np.empty(w.size)
    for o in range(w.size):
        low[o] = M[o].min()
    low0 = np.array([M0[0].min()])
    for s in range(t0.size):
        L = length[s]
        K1 = _degree(coef, s, f, 1.0, 0.0, p1)
        K2 = _degree(coef, s, f, 0.0, 1.0, p2)
        K = max(K1, K2)
        _vector_and_angles(p1, p2, K, L, t0[s], cs, sn, M0, R20, W0, 0, r2, c, work, low0)
        for o in range(w.size):
            wo = w[o]
            npc = max(1, math.ceil(wo * L / PHASE))
            hp = L / npc
            r = 0
            pos = 0.0
            while r < npc:
                taylor_shift(p1, K, pos, pp1)
                taylor_shift(p2, K, pos, pp2)
                N1 = oscillator_series(pp1, K, wo, xi[o], hp, S[o, 0], S[o, 1], Q1, V1)
                N2 = oscillator_series(pp2, K, wo, xi[o], hp, S[o, 2], S[o, 3], Q2, V2)
                if (N1 < 0 or N2 < 0) and npc < MAX_PIECES:
                    # not converged: this piece and the rest of the segment in twice as many
                    npc = 2 * (npc - r)
                    r = 0
                    hp = (L - pos) / npc
                    continue
                N1 = NMAX if N1 < 0 else N1
                N2 = NMAX if N2 < 0 else N2
                t_piece = t0[s] + pos
                r += 1
                pos = L - (npc - r) * hp
                N = max(N1, N2)
                for j in range(N1 + 1, N + 1):
                    Q1[j] = 0.0
                    V1[j] = 0.0
                for j in range(N2 + 1, N + 1):
                    Q2[j] = 0.0
                    V2[j] = 0.0
                _vector_and_angles(Q1, Q2, N, hp, t_piece, cs, sn, M, R2, W, o, r2, c,
                                   work, low)  # fmt: skip
                S[o, 0] = poly_val(Q1, N, hp)
                S[o, 1] = poly_val(V1, N, hp)
                S[o, 2] = poly_val(Q2, N, hp)
                S[o, 3] = poly_val(V2, N, hp)
