"""Compiled kernel of exact response spectra with peaks inside steps.

A bank of linear oscillators (``q'' + 2ξω q' + ω² q = −a_f(t)``) is advanced through the record
by the exact recurrence of each oscillator coupled to its floor (the augmented first-order hold
of ``building/exact.py``; on the ground this is the recurrence of Nigam & Jennings 1969). On a
floor the record is stepped on the building's own sub-steps (``ρ(A)·h ≤ 0.5``; the ground is
linear inside a record step, so this is the same input).

The record is gone through twice. The first pass (:func:`sample_peaks`) steps the oscillators
at the samples alone and keeps their peaks there, lower bounds of the true peaks; the second
(:func:`spectrum_kernel`) steps them again (the same states, bit for bit) and tests each step
against those peaks: first a screen of its end values against the peak less a record-wide
bound of the chord deviation (:func:`screen_thresholds`), then, for the few steps that pass it,
the tests below. Against the whole record's peaks they flag a few steps per oscillator near
its peak; against the running peaks (one pass) they flagged most steps early in the record.

Every step is one branch-free pass over the oscillators that the compiler vectorises: the
oscillators' data are held in blocks of ``NB`` as rows of a compile-time stride, and each block
goes through a chunk of the record while its rows stay in the L1 cache. The pass flags the
quantities (``|q|``, ``|q'|``, ``|ω²q + 2ξωq'|``) whose peak could grow inside the step, by
rigorous bounds of the exact response: inside a step it is ``α + βτ`` (the particular solution
for the straight line through the input's step-end values) plus a damped free vibration
``e = Re(C e^{λτ})`` (``|e^(k)| ≤ |C|ω^k``) plus, on a floor, the zero-state response to the
floor's deviation ``δ`` from that line (``|q_δ| ≤ max|δ|·∫|h|``). A quantity is flagged when

- its bound ``max|particular| + |C|ω^k (+ max|δ|·∫|h^(k)|)`` exceeds its peak;
- on the ground, also its end values plus the linear interpolation error ``h²/8·max|f''|``;
- on the ground, for oscillators with ``ω·h ≤ 0.5``, also the sign of its first or second
  derivative changes between the step ends (every derivative of the free vibration has at
  most one zero in such a step, so a quantity whose second derivative keeps its sign has at
  most one critical point, found by the sign of its derivative). On a floor there is no such
  rule (the floor is a sum of modes): the bound alone decides.

Only flagged steps are searched, on sub-steps short enough (``max(ρ_building, ω)·h ≤ 0.5``) for
the Taylor polynomial of the exact response to equal it to rounding: on the ground after a
second filter (the cubic Hermite interpolant of the ends plus its error bound
``h⁴/384·max|f⁗|``), by Newton from the Hermite peak where the response provably has one
critical point in the sub-step, else by rigorous root isolation
(:mod:`floorslide.numerics.polynomial`); on a floor by the chord bound and rigorous root
isolation. A test checks that searching every step gives the same spectra.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import (
    foh_step,
    poly_der,
    poly_der2,
    substep_inputs,
    taylor_coefficients,
)
from floorslide.numerics.polynomial import extreme_values, max_abs_on, newton_peak, scratch


@njit(cache=True)
def _floor_bounds(phi_s, p_s, q_s, R, beta, K, x, a, a1, ms, hs, c, xs, xn, f0, f1):
    """Bounds of the floor acceleration ``a_f`` over one step (the building's own ``ms``
    sub-steps of ``hs``): its largest deviation from the straight line between its step-end
    values ``f0, f1``, ``δ ≤ (ms·hs)²/8·max|a_f''|``, and ``max|a_f| ≤ max(|f0|, |f1|) + δ``.
    On each sub-step ``a_f`` is its Taylor polynomial ``Σ c_j τ^j`` (equal to it to rounding),
    so ``|a_f''| ≤ Σ j(j−1)|c_j| hs^{j−2}``; likewise ``|a_f'| ≤ Σ j|c_j| hs^{j−1}``, the third
    value returned, and ``|a_f'''| ≤ Σ j(j−1)(j−2)|c_j| hs^{j−3}``, the fourth."""
    n = x.size
    slope = (a1 - a) / (ms * hs)
    for i in range(n):
        xs[i] = x[i]
    m2 = 0.0
    m1 = 0.0
    m3 = 0.0
    for r in range(ms):
        aa, ab = substep_inputs(a, a1, r, ms)
        for j in range(K + 1):
            c[j] = 0.0
        taylor_coefficients(R, beta, xs, aa, slope, c[: R.shape[0]])
        s2 = 0.0
        for j in range(K, 1, -1):
            s2 = s2 * hs + j * (j - 1) * abs(c[j])
        m2 = max(m2, s2)
        s1 = 0.0
        for j in range(K, 0, -1):
            s1 = s1 * hs + j * abs(c[j])
        m1 = max(m1, s1)
        s3 = 0.0
        for j in range(K, 2, -1):
            s3 = s3 * hs + j * (j - 1) * (j - 2) * abs(c[j])
        m3 = max(m3, s3)
        if r + 1 < ms:
            foh_step(phi_s, p_s, q_s, xs, aa, ab, xn)
            for i in range(n):
                xs[i] = xn[i]
    dev = (ms * hs) ** 2 / 8.0 * m2
    return max(abs(f0), abs(f1)) + dev, dev, m1, m3


@njit(cache=True)
def _floor_piece(setup, X, row0, AK, L, dt, f0, FK, W, c, xs, xn):
    """The floor acceleration and its bounds on the ``L`` steps of a piece, into rows
    ``0 … L − 1`` of ``FK``: ``f0, f1`` at the step's ends, then ``max|a_f|``, the deviation
    from the chord, ``max|a_f'|`` and ``max|a_f'''|`` of :func:`_floor_bounds`. ``X[row0 + k]``
    is the building state at the start of step ``k``, ``AK[k]`` the ground there; ``f0`` the
    floor acceleration at the piece's start; returns that at its end.

    When the building takes one sub-step per step (the kernel's grid is the building's own),
    the same arithmetic as :func:`_floor_bounds`, operation for operation, is done for all the
    piece's steps at once, step index innermost so that the compiler vectorises it (``W``:
    scratch of at least ``(K + n + 4, L + 1)``); else step by step."""
    b_R = setup.b_R
    b_beta = setup.b_beta
    K = setup.b_K
    n = X.shape[1]
    if setup.b_m != 1:
        for k in range(L):
            a = AK[k]
            a1 = AK[k + 1]
            xe = X[row0 + k + 1]
            f1 = b_beta[0] * a1
            for j in range(n):
                f1 += b_R[0, j] * xe[j]
            abound, fdev, jbound, m3f = _floor_bounds(
                setup.b_phi,
                setup.b_p,
                setup.b_q,
                b_R,
                b_beta,
                K,
                X[row0 + k],
                a,
                a1,
                setup.b_m,
                dt / setup.b_m,
                c,
                xs,
                xn,
                f0,
                f1,
            )
            FK[k, 0] = f0
            FK[k, 1] = f1
            FK[k, 2] = abound
            FK[k, 3] = fdev
            FK[k, 4] = jbound
            FK[k, 5] = m3f
            f0 = f1
        return f0
    hs = dt / setup.b_m
    KR = b_R.shape[0]
    # rows of W: the states (n), the floor values, three sums, the Taylor coefficients (K + 1)
    F, S1, S2, S3, CT = n, n + 1, n + 2, n + 3, n + 4
    for i in range(n):
        for k in range(L + 1):
            W[i, k] = X[row0 + k, i]
    W[F, 0] = f0
    for k in range(1, L + 1):
        W[F, k] = b_beta[0] * AK[k]
    for i in range(n):
        r = b_R[0, i]
        for k in range(1, L + 1):
            W[F, k] += r * W[i, k]
    for j in range(K + 1):
        for k in range(L):
            W[CT + j, k] = 0.0
    for j in range(min(KR, K + 1)):
        for i in range(n):
            r = b_R[j, i]
            for k in range(L):
                W[CT + j, k] += r * W[i, k]
        bj = b_beta[j]
        for k in range(L):
            W[CT + j, k] += bj * (AK[k] + (AK[k + 1] - AK[k]) * 0.0)
        if j >= 1:
            gj = b_beta[j - 1] / j
            for k in range(L):
                W[CT + j, k] += gj * ((AK[k + 1] - AK[k]) / (1 * hs))
    for k in range(L):
        W[S1, k] = 0.0
        W[S2, k] = 0.0
        W[S3, k] = 0.0
    for j in range(K, 0, -1):
        for k in range(L):
            W[S1, k] = W[S1, k] * hs + j * abs(W[CT + j, k])
        if j >= 2:
            for k in range(L):
                W[S2, k] = W[S2, k] * hs + j * (j - 1) * abs(W[CT + j, k])
        if j >= 3:
            for k in range(L):
                W[S3, k] = W[S3, k] * hs + j * (j - 1) * (j - 2) * abs(W[CT + j, k])
    e8 = (1 * hs) ** 2 / 8.0
    for k in range(L):
        dev = e8 * max(0.0, W[S2, k])
        FK[k, 0] = W[F, k]
        FK[k, 1] = W[F, k + 1]
        FK[k, 2] = max(abs(W[F, k]), abs(W[F, k + 1])) + dev
        FK[k, 3] = dev
        FK[k, 4] = max(0.0, W[S1, k])
        FK[k, 5] = max(0.0, W[S3, k])
    return W[F, L]


@njit(cache=True)
def _floor_bound(phi_s, p_s, q_s, R, beta, K, x, a, a1, ms, hs, c, xs, xn, f0, f1):
    """Bounds of the floor acceleration ``a_f`` over one step (the building's own ``ms``
    sub-steps of ``hs``): its largest deviation from the straight line between its step-end
    values ``f0, f1``, ``δ ≤ (ms·hs)²/8·max|a_f''|``, and ``max|a_f| ≤ max(|f0|, |f1|) + δ``.
    On each sub-step ``a_f`` is its Taylor polynomial ``Σ c_j τ^j`` (equal to it to rounding),
    so ``|a_f''| ≤ Σ j(j−1)|c_j| hs^{j−2}``; likewise ``|a_f'| ≤ Σ j|c_j| hs^{j−1}``, the third
    value returned."""
    abound, dev, m1, _ = _floor_bounds(
        phi_s, p_s, q_s, R, beta, K, x, a, a1, ms, hs, c, xs, xn, f0, f1
    )
    return abound, dev, m1


@njit(cache=True, inline="always")
def _hermite_max(f0, d0, f1, d1, h):
    """max |H| on [0, h] of the cubic Hermite interpolant of values and slopes at the ends, and
    where it is (``-1.0`` when at an end)."""
    c1 = h * d0
    c2 = -3.0 * f0 - 2.0 * c1 + 3.0 * f1 - h * d1
    c3 = 2.0 * f0 + c1 - 2.0 * f1 + h * d1
    best = max(abs(f0), abs(f1))
    where = -1.0
    # H'(t) = c1 + 2 c2 t + 3 c3 t², t in (0, 1)
    A = 3.0 * c3
    B = 2.0 * c2
    if A == 0.0:
        if B != 0.0:
            t = -c1 / B
            if 0.0 < t < 1.0:
                v = abs(f0 + t * (c1 + t * (c2 + t * c3)))
                if v > best:
                    best, where = v, t * h
        return best, where
    disc = B * B - 4.0 * A * c1
    if disc < 0.0:
        return best, where
    sq = math.sqrt(disc)
    qq = -0.5 * (B + (sq if B >= 0.0 else -sq))
    t1 = qq / A
    t2 = c1 / qq if qq != 0.0 else -1.0
    if 0.0 < t1 < 1.0:
        v = abs(f0 + t1 * (c1 + t1 * (c2 + t1 * c3)))
        if v > best:
            best, where = v, t1 * h
    if 0.0 < t2 < 1.0:
        v = abs(f0 + t2 * (c1 + t2 * (c2 + t2 * c3)))
        if v > best:
            best, where = v, t2 * h
    return best, where


@njit(cache=True)
def _interior_peak(c, K, h, t0, work):
    """``max |p|`` over the critical points of ``p = Σ_{j≤K} c_j τ^j`` inside ``(0, h)``, for the
    response of one oscillator on the ground (``p`` is a linear function plus a damped sinusoid
    with ``ω·h ≤ 0.5``, so ``p''`` has at most one zero in the sub-step).

    When ``p'`` changes sign between the ends and ``p''`` does not, ``p'`` is monotone and has
    exactly one root: Newton on ``p'`` from the estimate ``t0``, safeguarded by bisection. In
    every other case (``p''`` changes sign: ``p'`` may have two roots or none; rounding at an
    end) every critical point is isolated rigorously (:func:`extreme_values`).
    """
    d_lo = poly_der(c, K, 0.0)
    d_hi = poly_der(c, K, h)
    e_lo = poly_der2(c, K, 0.0)
    e_hi = poly_der2(c, K, h)
    single = (d_lo > 0.0) != (d_hi > 0.0) and d_lo != 0.0 and d_hi != 0.0
    if not single or (e_lo > 0.0) != (e_hi > 0.0) or e_lo == 0.0 or e_hi == 0.0:
        vmin, _, vmax, _ = extreme_values(c, K, 0.0, h, work)
        return max(vmax, -vmin)
    return newton_peak(c, K, h, t0, d_lo)[0]


@njit(cache=True)
def _search_step(
    o,
    g,
    n,
    a,
    a1,
    dt,
    q0,
    v0,
    w,
    xi,
    gm,
    gK,
    CG,
    XG,
    cready,
    G_R,
    G_beta,
    f0,
    f1,
    S_Pqq,
    S_Pqx,
    S_pq,
    S_qq,
    need,
    curv,
    out,
    c,
    Q,
    poly,
    work,
):
    """Peaks of oscillator `o` on a floor inside one record step, on its sub-steps.

    On every sub-step (``max(rho_building, w)·h <= 0.5``) the response of the oscillator is its
    Taylor polynomial, from the floor's Taylor coefficients ``CG[g]`` on that sub-step (``g``
    the oscillator's group; ``o`` indexes the oscillator's data; the arrays are passed whole,
    not as views, which would cost a reference count each call). The floor
    motion is a sum of the building's modes, with no bound on the critical points a quantity
    may have in a sub-step; each needed quantity is therefore first filtered by a rigorous
    bound (its end values plus the chord deviation ``h²/8·max|p''|``) and, when that can exceed
    its peak, searched (:func:`~floorslide.numerics.polynomial.max_abs_on`). ``n`` is the number
    of building states; the ground has its own :func:`_ground_search`.

    The chord test is made twice. First, before any Taylor polynomial is formed, with the
    bounds ``curv`` of the quantities' second derivatives over the whole record step (those of
    :func:`_stage_floor`, from the equation of motion, :func:`_floor_curvatures`): a sub-step
    ``m`` times shorter than the step has a chord deviation ``m²`` times smaller, so most
    sub-steps of a short-period oscillator are settled by their end values alone. Only a
    sub-step that fails it gets its polynomials — and the floor's Taylor coefficients on it,
    ``CG[g, r]``, computed on first use from the group's rows ``G_R[g], G_beta[g]`` and the
    sub-step's start state ``XG[g, r]``, marked in ``cready[g, r]`` and shared by the group's
    oscillators — and the sharper test of ``max_abs_on``.

    Between the two, a second rigorous filter that needs no polynomial either: the cubic
    Hermite interpolant of each quantity's values and slopes at the sub-step's ends (slopes from
    the equation of motion, with the floor acceleration ``f0, f1`` at the step's ends and
    ``G_R[g, 0]·x + G_beta[g, 0]·a`` at inner sub-step ends) plus its error ``h⁴/384·max|p''''|``
    (``curv[3]`` bounds ``|q''''|``, ``curv[4]`` ``|q⁽⁵⁾|``). That error is ``~(ωh)²/48`` of
    the chord's, so it settles most of the steps the record-step tests flag.
    """
    m = gm
    K = gK
    h = dt / m
    c2 = 2.0 * xi * w
    w2 = w * w
    k8 = 0.125 * h * h
    slope = (a1 - a) / dt
    h4 = h * h * h * h / 384.0
    e4q = h4 * curv[3]
    e4v = h4 * curv[4]
    e4a = h4 * (w2 * curv[3] + c2 * curv[4])
    q = q0
    v = v0
    fs = f0
    for r in range(m):
        aa, ab = substep_inputs(a, a1, r, m)
        # floor acceleration at the sub-step's end
        if r + 1 < m:
            fe = G_beta[g, 0] * ab
            for j in range(n):
                fe += G_R[g, 0, j] * XG[g, r + 1, j]
        else:
            fe = f1
        # sub-step end state
        qn = S_Pqq[o, 0, 0] * q + S_Pqq[o, 0, 1] * v + S_pq[o, 0] * aa + S_qq[o, 0] * ab
        vn = S_Pqq[o, 1, 0] * q + S_Pqq[o, 1, 1] * v + S_pq[o, 1] * aa + S_qq[o, 1] * ab
        for j in range(n):
            qn += S_Pqx[o, 0, j] * XG[g, r, j]
            vn += S_Pqx[o, 1, j] * XG[g, r, j]
        # chord pre-filter (rigorous: curv bounds the second derivatives on the whole step)
        nd = need[0] and max(abs(q), abs(qn)) + k8 * curv[0] > out[o, 0]
        nv = need[1] and max(abs(v), abs(vn)) + k8 * curv[1] > out[o, 1]
        na = (
            need[2] and max(abs(w2 * q + c2 * v), abs(w2 * qn + c2 * vn)) + k8 * curv[2] > out[o, 2]
        )
        if nd or nv or na:
            # Hermite filter (values and slopes at both ends, q'' from the equation of motion)
            d0 = -(fs + w2 * q + c2 * v)
            d1 = -(fe + w2 * qn + c2 * vn)
            if nd:
                nd = _hermite_max(q, v, qn, vn, h)[0] + e4q > out[o, 0]
            if nv:
                nv = _hermite_max(v, d0, vn, d1, h)[0] + e4v > out[o, 1]
            if na:
                A0 = w2 * q + c2 * v
                A1 = w2 * qn + c2 * vn
                na = (
                    _hermite_max(A0, w2 * v + c2 * d0, A1, w2 * vn + c2 * d1, h)[0] + e4a
                    > out[o, 2]
                )
        if nd or nv or na:
            if not cready[g, r]:
                for j in range(CG.shape[2]):
                    CG[g, r, j] = 0.0
                taylor_coefficients(G_R[g], G_beta[g], XG[g, r], aa, slope, CG[g, r])
                cready[g, r] = True
            for j in range(K + 1):
                c[j] = CG[g, r, j]
            Q[0] = q
            Q[1] = v
            for j in range(K - 1):
                Q[j + 2] = (-c2 * (j + 1) * Q[j + 1] - w2 * Q[j] - c[j]) / ((j + 1) * (j + 2))
            if nd:
                pk, _ = max_abs_on(Q, K, h, out[o, 0], work)
                out[o, 0] = max(out[o, 0], abs(qn), pk)
            if nv:
                for j in range(K):
                    poly[j] = (j + 1) * Q[j + 1]
                poly[K] = 0.0
                pk, _ = max_abs_on(poly, K, h, out[o, 1], work)
                out[o, 1] = max(out[o, 1], abs(vn), pk)
            if na:
                for j in range(K):
                    poly[j] = w2 * Q[j] + c2 * (j + 1) * Q[j + 1]
                poly[K] = w2 * Q[K]
                pk, _ = max_abs_on(poly, K, h, out[o, 2], work)
                out[o, 2] = max(out[o, 2], abs(w2 * qn + c2 * vn), pk)
        q = qn
        v = vn
        fs = fe


@njit(cache=True, inline="always")
def _floor_curvatures(C, o, q0, v0, dt, f0, f1, fdev, abound, jbound, m3f, curv):
    """Bounds over one record step of ``|q''|``, ``|q'''|`` and ``|(ω²q + 2ξωq')''|`` for
    oscillator ``o`` of a block on a floor, from its state ``q0, v0`` at the step start, into
    ``curv``: the quantities ``m2q, m2v, m2a`` of :func:`_stage_floor` (same formulas), then
    bounds of ``|q''''|`` (``m4q``, as there) and ``|q⁽⁵⁾| ≤ max|a_f'''| + 2ξω·m4q + ω²·m2v``
    (``m3f`` bounds ``|a_f'''|``, from :func:`_floor_bounds`)."""
    w2 = C[W2 * NB + o]
    c2 = C[C2 * NB + o]
    fslope = (f1 - f0) / dt
    iw2 = C[IW2 * NB + o]
    bet = -fslope * iw2
    alp = fslope * C[AS * NB + o] - f0 * iw2
    e0 = q0 - alp
    ci = (v0 - bet + C[XIW * NB + o] * e0) * C[IWD * NB + o]
    cm = math.sqrt(e0 * e0 + ci * ci)
    bd = max(abs(alp), abs(alp + bet * dt)) + cm + fdev * C[IH0 * NB + o]
    bv = abs(bet) + C[W * NB + o] * cm + fdev * C[IH1 * NB + o]
    m2q = abound + c2 * bv + w2 * bd
    m2v = jbound + c2 * m2q + w2 * bv
    curv[0] = m2q
    curv[1] = m2v
    curv[2] = w2 * m2q + c2 * m2v
    m4q = 8.0 * fdev / (dt * dt) + c2 * m2v + w2 * m2q
    curv[3] = m4q
    curv[4] = m3f + c2 * m4q + w2 * m2v


@njit(cache=True, inline="always")
def _sample(acc, k, up):
    """Sample ``k`` of the record on a grid ``up`` times finer (linear interpolation: the same
    piecewise-linear function)."""
    j = k // up
    r = k - j * up
    if r == 0:
        return acc[j]
    return acc[j] + (acc[j + 1] - acc[j]) * (r / up)


@njit(cache=True)
def _ground_search(
    f,
    a,
    a1,
    dt,
    m,
    K,
    q0,
    v0,
    w,
    xi,
    s00,
    s01,
    s10,
    s11,
    sp0,
    sp1,
    sq0,
    sq1,
    pk,
    Q,
    poly,
    work,
):
    """Peaks of one oscillator on the ground inside one record step, on its ``m`` sub-steps.

    ``f`` says which quantities to search (bit 0: ``|q|``, 1: ``|q'|``, 2: ``|ω²q + 2ξωq'|``);
    ``s..`` is the oscillator's exact sub-step recurrence ``q⁺ = s00 q + s01 q' + sp0 a + sq0 a⁺``,
    ``q'⁺ = s10 q + s11 q' + sp1 a + sq1 a⁺``; ``pk`` holds the three peaks so far and is
    updated. On a sub-step a quantity is searched only if its derivative changes sign there, or
    its second derivative does and its derivative comes within its chord deviation
    ``h²/8·max|f'''|`` of zero at an end (with neither, it has no critical point: every
    derivative of the free vibration has at most one zero when ``ω·h ≤ 0.5``, and a derivative
    of one sign at both ends farther from zero than its chord deviation keeps its sign) and
    the cubic Hermite interpolant of its end values and slopes plus the interpolation error bound
    ``h⁴/384·max|f⁗|`` can exceed its peak (the response is the exact particular solution
    ``α + βτ`` plus a free vibration ``Re(C e^{λτ})`` whose k-th derivative is at most
    ``|C|ω^k``); then the extremum of its Taylor polynomial of degree ``K`` (equal to the
    response to rounding on the sub-step) are found (:func:`_interior_peak`).
    """
    h = dt / m
    slope = (a1 - a) / dt
    c2 = 2.0 * xi * w
    w2 = w * w
    wd = w * math.sqrt(1.0 - xi * xi)
    q = q0
    v = v0
    for r in range(m):
        aa, ab = substep_inputs(a, a1, r, m)
        qn = s00 * q + s01 * v + sp0 * aa + sq0 * ab
        vn = s10 * q + s11 * v + sp1 * aa + sq1 * ab
        dd0 = -(aa + c2 * v + w2 * q)  # q'' at both ends
        dd1 = -(ab + c2 * vn + w2 * qn)
        A0 = w2 * q + c2 * v
        A1 = w2 * qn + c2 * vn
        Ad0 = w2 * v + c2 * dd0
        Ad1 = w2 * vn + c2 * dd1
        # third derivative of q and second of w²q + 2ξwq' at both ends: a quantity whose
        # derivative keeps its sign may still have two critical points when its second
        # derivative changes sign
        ddd0 = -slope - c2 * dd0 - w2 * v
        ddd1 = -slope - c2 * dd1 - w2 * vn
        Add0 = w2 * dd0 + c2 * ddd0
        Add1 = w2 * dd1 + c2 * ddd1
        sd = (v > 0.0) != (vn > 0.0)
        sa = (Ad0 > 0.0) != (Ad1 > 0.0)
        nd = (f & 1) != 0 and (sd or (dd0 > 0.0) != (dd1 > 0.0))
        nv = (f & 2) != 0 and ((dd0 > 0.0) != (dd1 > 0.0))
        na = (f & 4) != 0 and (sa or (Add0 > 0.0) != (Add1 > 0.0))
        td = tv = ta = -1.0
        if nd or nv or na:
            bet = -slope / w2
            alp = (-aa + c2 * slope / w2) / w2
            e0 = q - alp
            ci = (e0 * (-xi * w) - (v - bet)) / wd
            cm = math.sqrt(e0 * e0 + ci * ci)
            h4 = h * h * h * h / 384.0 * cm * w2 * w2
            # a derivative of one sign at both ends and farther from zero than its chord
            # deviation h²/8·max|f'''| keeps its sign: no critical point (|q'''| ≤ |C|ω³ and
            # |(ω²q + 2ξωq')'''| ≤ |C|ω⁵(1 + 2ξ), the free vibration's: the particular solution
            # is linear)
            k3 = 0.125 * h * h * cm * w2 * w * (1.0 + 1e-6)  # margin: rounding of the ends
            if nd and not sd:
                nd = min(abs(v), abs(vn)) <= k3
            if na and not sa:
                na = min(abs(Ad0), abs(Ad1)) <= k3 * w2 * (1.0 + 2.0 * xi)
            if nd:
                hd, td = _hermite_max(q, v, qn, vn, h)
                nd = hd + h4 > pk[0]
            if nv:
                hv, tv = _hermite_max(v, dd0, vn, dd1, h)
                nv = hv + h4 * w > pk[1]
            if na:
                ha, ta = _hermite_max(A0, Ad0, A1, Ad1, h)
                na = ha + h4 * w2 * (1.0 + 2.0 * xi) > pk[2]
        if nd or nv or na:
            Q[0] = q
            Q[1] = v
            # q'' = −a(τ) − c2 q' − w² q with a(τ) = aa + slope·τ
            Q[2] = (-c2 * Q[1] - w2 * Q[0] - aa) / 2.0
            if K >= 3:
                Q[3] = (-c2 * 2.0 * Q[2] - w2 * Q[1] - slope) / 6.0
            for j in range(2, K - 1):
                Q[j + 2] = (-c2 * (j + 1) * Q[j + 1] - w2 * Q[j]) / ((j + 1) * (j + 2))
            if nd:
                pk[0] = max(pk[0], abs(q), abs(qn), _interior_peak(Q, K, h, td, work))
            if nv:
                for j in range(K):
                    poly[j] = (j + 1) * Q[j + 1]
                poly[K] = 0.0
                pk[1] = max(pk[1], abs(v), abs(vn), _interior_peak(poly, K, h, tv, work))
            if na:
                for j in range(K):
                    poly[j] = w2 * Q[j] + c2 * (j + 1) * Q[j + 1]
                poly[K] = w2 * Q[K]
                pk[2] = max(pk[2], abs(A0), abs(A1), _interior_peak(poly, K, h, ta, work))
        q = qn
        v = vn


# Oscillators are processed in blocks of NB, their data held row by row in flat arrays whose row
# stride NB is a compile-time constant: the compiler then sees that rows never overlap and
# vectorises the per-step pass over the oscillators (with runtime strides it gives up: "too many
# memory checks"). A block's rows fit in the L1 cache; blocks go through the record one by one.
NB = 32
# record steps per chunk (on a floor the building is stepped once per chunk for every block)
CHUNK = 1024
# a block runs the full skip tests vectorised for the rest of a chunk when the screen let more
# than 1/SCREEN_RATIO of its oscillator·steps through in the chunk's first SCREEN_TRIAL steps
SCREEN_TRIAL = 64
SCREEN_RATIO = 8
# coefficient rows: exact record-step recurrence, then constants of the skip tests
P0, P1, P2, P3, P4, P5, X0, X1 = range(8)
W, W2, C2, IW2, AS, XIW, IWD, KD2, KV2, KA2, SA, SA2, ONE, IH0, IH1, IH2 = range(8, 24)
NCOEF = 24
# state rows: q, q', q'' at the step end; peaks; q, q' at the step start; coupling terms;
# screen thresholds of |q|, |q'|, |ω²q + 2ξωq'| (see screen_thresholds)
_Q, _V, _D, _PD, _PV, _PA, _QS, _VS, _CP0, _CP1, _TD, _TV, _TA = range(13)
NSTATE = 13
# record-wide bounds of the motion, from sample_peaks: max|f|, max|f'| over the steps' chords,
# and on a floor the largest of the steps' max|a_f|, deviation from the chord, max|a_f'|
FB_F, FB_S, FB_AB, FB_DEV, FB_J = range(5)
NFB = 5


_MARGIN2 = (1.0 + 1e-6) ** 2
"""Squared relative margin of the chord-deviation tests of :func:`_stage_ground`."""


@njit(cache=True)
def _stage_ground(C, S, flag, nb, a, a1, dt):
    """Advance the first ``nb`` oscillators of a block by one record step on the ground and flag
    those whose peaks may grow inside it; returns the number of flags set (bit 0: ``|q|``, bit 1:
    ``|q'|``, bit 2: ``|ω²q + 2ξωq'|``).

    Inside the step the response is ``q = α + βτ + e(τ)``: the exact particular solution for the
    linear input plus a damped free vibration ``e = Re(C e^{λτ})`` with ``|e^(k)| ≤ |C| ω^k``. A
    quantity is flagged when both its bound ``max|particular| + |C|·ω^k`` and its end values plus
    the linear interpolation error ``dt²/8·max|f''|`` exceed its peak so far and, for
    oscillators with ``ω·dt ≤ 0.5`` (row ``ONE``), it may have a critical point in the step:
    its derivative changes sign between the ends, or comes within its own chord deviation
    ``dt²/8·max|f'''|`` of zero at an end (``|f'''| ≤ |C|ω^(k+3)``: the particular solution is
    linear), for ``|q|`` only when ``q''`` changes sign as well (``q'' = e''`` has at most one
    zero in such a step). A derivative of one sign at both ends and farther from zero than its
    chord deviation keeps its sign: this replaces the sign test of the second derivative, whose
    third derivatives cost more in this vectorised pass than the few extra steps searched.
    Comparisons are made on squares (no square root).
    Branch-free on purpose: the compiler vectorises it (and spelled out: the update it shares
    with :func:`_stage_floor` in an inlined helper stops the vectoriser).
    """
    nf = 0
    amax = max(abs(a), abs(a1))
    slope = (a1 - a) / dt
    for o in range(nb):
        q0 = S[_Q * NB + o]
        v0 = S[_V * NB + o]
        w2 = C[W2 * NB + o]
        c2 = C[C2 * NB + o]
        q1 = C[P0 * NB + o] * q0 + C[P1 * NB + o] * v0 + C[P4 * NB + o] * a + C[X0 * NB + o] * a1
        v1 = C[P2 * NB + o] * q0 + C[P3 * NB + o] * v0 + C[P5 * NB + o] * a + C[X1 * NB + o] * a1
        A0 = w2 * q0 + c2 * v0
        A1 = w2 * q1 + c2 * v1
        d0 = -(a + A0)
        d1 = -(a1 + A1)
        pd = max(S[_PD * NB + o], abs(q1))
        pv = max(S[_PV * NB + o], abs(v1))
        pa = max(S[_PA * NB + o], abs(A1))
        S[_PD * NB + o] = pd
        S[_PV * NB + o] = pv
        S[_PA * NB + o] = pa
        iw2 = C[IW2 * NB + o]
        bet = -slope * iw2
        alp = slope * C[AS * NB + o] - a * iw2
        e0 = q0 - alp
        ci = (v0 - bet + C[XIW * NB + o] * e0) * C[IWD * NB + o]
        cm2 = e0 * e0 + ci * ci
        # particular solution + free vibration: |C|·ω^k > peak − max|particular|
        rd = pd - max(abs(alp), abs(alp + bet * dt))
        rv = pv - abs(bet)
        ra = pa - amax
        bd = (rd < 0.0) | (cm2 > rd * rd)
        bv = (rv < 0.0) | (w2 * cm2 > rv * rv)
        ba = (ra < 0.0) | (C[SA2 * NB + o] * cm2 > ra * ra)
        # ends + dt²/8·|C|ω^(k+2) > peak (linear interpolation error); with one critical point
        # at most, the derivative changes sign
        sd = pd - max(abs(q0), abs(q1))
        sv = pv - max(abs(v0), abs(v1))
        sa = pa - max(abs(A0), abs(A1))
        ad0 = w2 * v0 + c2 * d0
        ad1 = w2 * v1 + c2 * d1
        kv = C[KV2 * NB + o] * cm2
        ld = C[KD2 * NB + o] * cm2 > sd * sd
        lv = kv > sv * sv
        la = C[KA2 * NB + o] * cm2 > sa * sa
        many = C[ONE * NB + o] == 0.0
        # a quantity has a critical point in the step only if its derivative changes sign
        # between the ends, or comes within its chord deviation dt²/8·max|f'''| of zero (one
        # sign at both ends and farther from zero than that: one sign throughout). The
        # particular solution is linear, so f''' is the free vibration's: |q'''| ≤ |C|ω³ (row
        # KV2), |(ω²q + 2ξωq')'''| ≤ |C|ω⁵(1 + 2ξ) (KA2·ω²). For |q| the sign of q'' is checked
        # too (already at hand): with w·dt ≤ 0.5, q'' = e'' has at most one zero in the step,
        # so a q'' of one sign at both ends makes q' monotone
        # (with a relative margin of 10⁻⁶ for the rounding of the end values)
        kvm = kv * _MARGIN2
        ka = C[KA2 * NB + o] * cm2 * w2 * _MARGIN2
        near_d = (v0 * v0 <= kvm) | (v1 * v1 <= kvm)
        near_a = (ad0 * ad0 <= ka) | (ad1 * ad1 <= ka)
        fd = bd & ld & (many | (v0 * v1 <= 0.0) | ((d0 * d1 <= 0.0) & near_d))
        fv = bv & lv & (many | (d0 * d1 <= 0.0))
        fa = ba & la & (many | (ad0 * ad1 <= 0.0) | near_a)
        f = fd + 2 * fv + 4 * fa
        flag[o] = f
        nf += f
        S[_QS * NB + o] = q0
        S[_VS * NB + o] = v0
        S[_Q * NB + o] = q1
        S[_V * NB + o] = v1
    return nf


@njit(cache=True)
def _stage_floor(C, S, flag, nb, a, a1, dt, f0, f1, fdev, abound, jbound):
    """Advance the first ``nb`` oscillators of a block by one record step on a floor (coupled to
    the building state through rows ``_CP0, _CP1``) and flag those whose peaks may grow inside
    it; returns the number of flags set.

    The ground values ``a, a1`` drive the update; the floor acceleration is ``f0, f1`` at the
    step ends, deviates from the line through them by at most ``fdev``, is at most ``abound``
    in magnitude and changes at a rate of at most ``jbound``. A quantity is flagged when both
    its bound (particular solution for that line + free vibration + response to the deviation,
    ``fdev·∫|h|``, see the module notes) and its end values plus its chord deviation
    (``dt²/8`` times a bound of its second derivative from the equation of motion) exceed its
    peak so far, and its derivative may vanish in the step: it changes sign between the ends, or
    one end value is within the chord deviation of the derivative (``dt²/8`` times a bound of
    the quantity's third derivative), so that a pair of close zeros cannot be excluded. (No
    plain sign rule: on a floor a quantity may have several critical points in a step.)
    Branch-free on purpose: the compiler vectorises it.
    """
    nf = 0
    fslope = (f1 - f0) / dt
    # loop invariants hoisted by hand: a division inside the loop stops the vectoriser
    k8 = 0.125 * dt * dt
    m2f = 8.0 * fdev / (dt * dt)  # bound of |a_f''| on the step
    for o in range(nb):
        q0 = S[_Q * NB + o]
        v0 = S[_V * NB + o]
        w2 = C[W2 * NB + o]
        c2 = C[C2 * NB + o]
        q1 = (
            C[P0 * NB + o] * q0
            + C[P1 * NB + o] * v0
            + C[P4 * NB + o] * a
            + C[X0 * NB + o] * a1
            + S[_CP0 * NB + o]
        )
        v1 = (
            C[P2 * NB + o] * q0
            + C[P3 * NB + o] * v0
            + C[P5 * NB + o] * a
            + C[X1 * NB + o] * a1
            + S[_CP1 * NB + o]
        )
        A1 = w2 * q1 + c2 * v1
        pd = max(S[_PD * NB + o], abs(q1))
        pv = max(S[_PV * NB + o], abs(v1))
        pa = max(S[_PA * NB + o], abs(A1))
        S[_PD * NB + o] = pd
        S[_PV * NB + o] = pv
        S[_PA * NB + o] = pa
        iw2 = C[IW2 * NB + o]
        bet = -fslope * iw2
        alp = fslope * C[AS * NB + o] - f0 * iw2
        e0 = q0 - alp
        ci = (v0 - bet + C[XIW * NB + o] * e0) * C[IWD * NB + o]
        cm = math.sqrt(e0 * e0 + ci * ci)
        bd = max(abs(alp), abs(alp + bet * dt)) + cm + fdev * C[IH0 * NB + o]
        bv = abs(bet) + C[W * NB + o] * cm + fdev * C[IH1 * NB + o]
        ba = abound + C[SA * NB + o] * cm + fdev * C[IH2 * NB + o]
        # no sign rule on a floor (the floor motion is a sum of modes: a quantity may have
        # several critical points in a step whatever its derivatives do at the ends); instead
        # its end values plus the chord deviation dt²/8·max|f''|, with max|f''| bounded from the
        # equation of motion: |q''| ≤ max|a_f| + 2ξω·max|q'| + ω²·max|q|, |q(3)| ≤ max|a_f'| +
        # 2ξω·max|q''| + ω²·max|q'|, |(ω²q + 2ξωq')''| ≤ ω²·max|q''| + 2ξω·max|q(3)|
        m2q = abound + c2 * bv + w2 * bd
        m2v = jbound + c2 * m2q + w2 * bv
        m2a = w2 * m2q + c2 * m2v
        A0 = w2 * q0 + c2 * v0
        # and its derivative may vanish in the step: it changes sign, or is within the chord
        # deviation of its own derivative's bound (q(4) ≤ max|a_f''| + 2ξω·max|q(3)| + ω²·max|q''|)
        m4q = m2f + c2 * m2v + w2 * m2q
        m3a = w2 * m2v + c2 * m4q
        d0 = -(f0 + A0)
        d1 = -(f1 + A1)
        ad0 = w2 * v0 + c2 * d0
        ad1 = w2 * v1 + c2 * d1
        zd = (v0 * v1 <= 0.0) | (abs(v0) <= k8 * m2v) | (abs(v1) <= k8 * m2v)
        zv = (d0 * d1 <= 0.0) | (abs(d0) <= k8 * m4q) | (abs(d1) <= k8 * m4q)
        za = (ad0 * ad1 <= 0.0) | (abs(ad0) <= k8 * m3a) | (abs(ad1) <= k8 * m3a)
        ld = (abs(q0) + k8 * m2q > pd) | (abs(q1) + k8 * m2q > pd)
        lv = (abs(v0) + k8 * m2v > pv) | (abs(v1) + k8 * m2v > pv)
        la = (abs(A0) + k8 * m2a > pa) | (abs(A1) + k8 * m2a > pa)
        fd = (bd > pd) & ld & zd
        fv = (bv > pv) & lv & zv
        fa = (ba > pa) & la & za
        f = fd + 2 * fv + 4 * fa
        flag[o] = f
        nf += f
        S[_QS * NB + o] = q0
        S[_VS * NB + o] = v0
        S[_Q * NB + o] = q1
        S[_V * NB + o] = v1
    return nf


# The two passes of a spectrum. A first pass (sample_peaks) steps every oscillator through the
# whole record at the samples alone: its peaks at the samples, which are lower bounds of the
# true peaks. With them known in advance, a step can contain a larger peak only where a
# quantity's end value comes within a record-wide bound of its chord deviation of that lower
# bound (screen_thresholds): the second pass (spectrum_kernel) steps the oscillators again (the
# same recurrence, the same states bit for bit), compares each step's end values with these
# thresholds (_screen_ground, _screen_floor: an update and three comparisons per oscillator),
# applies the full skip tests of _stage_ground and _stage_floor to the few steps that pass
# (_ground_test, _floor_test, the same tests with the same arithmetic) and searches the steps
# those flag. Against the peaks of the samples of the whole record the tests flag a few steps
# per oscillator near its peak, where with the running peaks they flagged most steps early in
# the record; the peaks found are the same numbers (every peak is the largest of the sample
# values and of the interior critical values of the steps searched, and a step skipped is
# proven not to exceed the samples' peak).


@njit(cache=True)
def _screen_ground(C, S, flag, nb, a, a1):
    """Advance the first ``nb`` oscillators of a block by one record step on the ground (the
    recurrence of :func:`_stage_ground`) and flag those whose step-end values of a quantity
    exceed its screen threshold (rows ``_TD, _TV, _TA``: the peak of the samples less the
    largest chord deviation the quantity can have in a step, :func:`screen_thresholds`); a step
    not flagged has no interior value above that peak. Returns the number of flags set.
    Branch-free: the compiler vectorises it."""
    nf = 0
    for o in range(nb):
        q0 = S[_Q * NB + o]
        v0 = S[_V * NB + o]
        w2 = C[W2 * NB + o]
        c2 = C[C2 * NB + o]
        q1 = C[P0 * NB + o] * q0 + C[P1 * NB + o] * v0 + C[P4 * NB + o] * a + C[X0 * NB + o] * a1
        v1 = C[P2 * NB + o] * q0 + C[P3 * NB + o] * v0 + C[P5 * NB + o] * a + C[X1 * NB + o] * a1
        A0 = w2 * q0 + c2 * v0
        A1 = w2 * q1 + c2 * v1
        fd = max(abs(q0), abs(q1)) > S[_TD * NB + o]
        fv = max(abs(v0), abs(v1)) > S[_TV * NB + o]
        fa = max(abs(A0), abs(A1)) > S[_TA * NB + o]
        f = fd + 2 * fv + 4 * fa
        flag[o] = f
        nf += f
        S[_QS * NB + o] = q0
        S[_VS * NB + o] = v0
        S[_Q * NB + o] = q1
        S[_V * NB + o] = v1
    return nf


@njit(cache=True)
def _screen_floor(C, S, flag, nb, a, a1):
    """As :func:`_screen_ground` on a floor: the recurrence of :func:`_stage_floor` (coupled to
    the building state through rows ``_CP0, _CP1``) and the same screen."""
    nf = 0
    for o in range(nb):
        q0 = S[_Q * NB + o]
        v0 = S[_V * NB + o]
        w2 = C[W2 * NB + o]
        c2 = C[C2 * NB + o]
        q1 = (
            C[P0 * NB + o] * q0
            + C[P1 * NB + o] * v0
            + C[P4 * NB + o] * a
            + C[X0 * NB + o] * a1
            + S[_CP0 * NB + o]
        )
        v1 = (
            C[P2 * NB + o] * q0
            + C[P3 * NB + o] * v0
            + C[P5 * NB + o] * a
            + C[X1 * NB + o] * a1
            + S[_CP1 * NB + o]
        )
        A0 = w2 * q0 + c2 * v0
        A1 = w2 * q1 + c2 * v1
        fd = max(abs(q0), abs(q1)) > S[_TD * NB + o]
        fv = max(abs(v0), abs(v1)) > S[_TV * NB + o]
        fa = max(abs(A0), abs(A1)) > S[_TA * NB + o]
        f = fd + 2 * fv + 4 * fa
        flag[o] = f
        nf += f
        S[_QS * NB + o] = q0
        S[_VS * NB + o] = v0
        S[_Q * NB + o] = q1
        S[_V * NB + o] = v1
    return nf


@njit(cache=True)
def _ground_test(C, S, o, a, a1, dt):
    """The flags of :func:`_stage_ground` for oscillator ``o`` of a block already advanced
    through the step (its start and end states in rows ``_QS, _VS`` and ``_Q, _V``): the same
    tests in the same arithmetic, for one oscillator (the steps :func:`_screen_ground` passes)."""
    amax = max(abs(a), abs(a1))
    slope = (a1 - a) / dt
    q0 = S[_QS * NB + o]
    v0 = S[_VS * NB + o]
    q1 = S[_Q * NB + o]
    v1 = S[_V * NB + o]
    w2 = C[W2 * NB + o]
    c2 = C[C2 * NB + o]
    A0 = w2 * q0 + c2 * v0
    A1 = w2 * q1 + c2 * v1
    d0 = -(a + A0)
    d1 = -(a1 + A1)
    pd = max(S[_PD * NB + o], abs(q1))
    pv = max(S[_PV * NB + o], abs(v1))
    pa = max(S[_PA * NB + o], abs(A1))
    iw2 = C[IW2 * NB + o]
    bet = -slope * iw2
    alp = slope * C[AS * NB + o] - a * iw2
    e0 = q0 - alp
    ci = (v0 - bet + C[XIW * NB + o] * e0) * C[IWD * NB + o]
    cm2 = e0 * e0 + ci * ci
    rd = pd - max(abs(alp), abs(alp + bet * dt))
    rv = pv - abs(bet)
    ra = pa - amax
    bd = (rd < 0.0) | (cm2 > rd * rd)
    bv = (rv < 0.0) | (w2 * cm2 > rv * rv)
    ba = (ra < 0.0) | (C[SA2 * NB + o] * cm2 > ra * ra)
    sd = pd - max(abs(q0), abs(q1))
    sv = pv - max(abs(v0), abs(v1))
    sa = pa - max(abs(A0), abs(A1))
    ad0 = w2 * v0 + c2 * d0
    ad1 = w2 * v1 + c2 * d1
    kv = C[KV2 * NB + o] * cm2
    ld = C[KD2 * NB + o] * cm2 > sd * sd
    lv = kv > sv * sv
    la = C[KA2 * NB + o] * cm2 > sa * sa
    many = C[ONE * NB + o] == 0.0
    kvm = kv * _MARGIN2
    ka = C[KA2 * NB + o] * cm2 * w2 * _MARGIN2
    near_d = (v0 * v0 <= kvm) | (v1 * v1 <= kvm)
    near_a = (ad0 * ad0 <= ka) | (ad1 * ad1 <= ka)
    fd = bd & ld & (many | (v0 * v1 <= 0.0) | ((d0 * d1 <= 0.0) & near_d))
    fv = bv & lv & (many | (d0 * d1 <= 0.0))
    fa = ba & la & (many | (ad0 * ad1 <= 0.0) | near_a)
    return fd + 2 * fv + 4 * fa


@njit(cache=True)
def _floor_test(C, S, o, dt, f0, f1, fdev, abound, jbound):
    """The flags of :func:`_stage_floor` for oscillator ``o`` of a block already advanced through
    the step (as :func:`_ground_test`): the same tests in the same arithmetic."""
    fslope = (f1 - f0) / dt
    k8 = 0.125 * dt * dt
    m2f = 8.0 * fdev / (dt * dt)
    q0 = S[_QS * NB + o]
    v0 = S[_VS * NB + o]
    q1 = S[_Q * NB + o]
    v1 = S[_V * NB + o]
    w2 = C[W2 * NB + o]
    c2 = C[C2 * NB + o]
    A1 = w2 * q1 + c2 * v1
    pd = max(S[_PD * NB + o], abs(q1))
    pv = max(S[_PV * NB + o], abs(v1))
    pa = max(S[_PA * NB + o], abs(A1))
    iw2 = C[IW2 * NB + o]
    bet = -fslope * iw2
    alp = fslope * C[AS * NB + o] - f0 * iw2
    e0 = q0 - alp
    ci = (v0 - bet + C[XIW * NB + o] * e0) * C[IWD * NB + o]
    cm = math.sqrt(e0 * e0 + ci * ci)
    bd = max(abs(alp), abs(alp + bet * dt)) + cm + fdev * C[IH0 * NB + o]
    bv = abs(bet) + C[W * NB + o] * cm + fdev * C[IH1 * NB + o]
    ba = abound + C[SA * NB + o] * cm + fdev * C[IH2 * NB + o]
    m2q = abound + c2 * bv + w2 * bd
    m2v = jbound + c2 * m2q + w2 * bv
    m2a = w2 * m2q + c2 * m2v
    A0 = w2 * q0 + c2 * v0
    m4q = m2f + c2 * m2v + w2 * m2q
    m3a = w2 * m2v + c2 * m4q
    d0 = -(f0 + A0)
    d1 = -(f1 + A1)
    ad0 = w2 * v0 + c2 * d0
    ad1 = w2 * v1 + c2 * d1
    zd = (v0 * v1 <= 0.0) | (abs(v0) <= k8 * m2v) | (abs(v1) <= k8 * m2v)
    zv = (d0 * d1 <= 0.0) | (abs(d0) <= k8 * m4q) | (abs(d1) <= k8 * m4q)
    za = (ad0 * ad1 <= 0.0) | (abs(ad0) <= k8 * m3a) | (abs(ad1) <= k8 * m3a)
    ld = (abs(q0) + k8 * m2q > pd) | (abs(q1) + k8 * m2q > pd)
    lv = (abs(v0) + k8 * m2v > pv) | (abs(v1) + k8 * m2v > pv)
    la = (abs(A0) + k8 * m2a > pa) | (abs(A1) + k8 * m2a > pa)
    fd = (bd > pd) & ld & zd
    fv = (bv > pv) & lv & zv
    fa = (ba > pa) & la & za
    return fd + 2 * fv + 4 * fa


@njit(cache=True)
def _advance_ground(C, S, nb, a, a1):
    """Advance the first ``nb`` oscillators of a block by one record step on the ground (the
    recurrence of :func:`_stage_ground`, the same arithmetic) and raise their peaks at the
    samples. Branch-free: the compiler vectorises it."""
    for o in range(nb):
        q0 = S[_Q * NB + o]
        v0 = S[_V * NB + o]
        q1 = C[P0 * NB + o] * q0 + C[P1 * NB + o] * v0 + C[P4 * NB + o] * a + C[X0 * NB + o] * a1
        v1 = C[P2 * NB + o] * q0 + C[P3 * NB + o] * v0 + C[P5 * NB + o] * a + C[X1 * NB + o] * a1
        A1 = C[W2 * NB + o] * q1 + C[C2 * NB + o] * v1
        S[_PD * NB + o] = max(S[_PD * NB + o], abs(q1))
        S[_PV * NB + o] = max(S[_PV * NB + o], abs(v1))
        S[_PA * NB + o] = max(S[_PA * NB + o], abs(A1))
        S[_Q * NB + o] = q1
        S[_V * NB + o] = v1


@njit(cache=True)
def _advance_floor(C, S, nb, a, a1):
    """As :func:`_advance_ground` on a floor (the recurrence of :func:`_stage_floor`)."""
    for o in range(nb):
        q0 = S[_Q * NB + o]
        v0 = S[_V * NB + o]
        q1 = (
            C[P0 * NB + o] * q0
            + C[P1 * NB + o] * v0
            + C[P4 * NB + o] * a
            + C[X0 * NB + o] * a1
            + S[_CP0 * NB + o]
        )
        v1 = (
            C[P2 * NB + o] * q0
            + C[P3 * NB + o] * v0
            + C[P5 * NB + o] * a
            + C[X1 * NB + o] * a1
            + S[_CP1 * NB + o]
        )
        A1 = C[W2 * NB + o] * q1 + C[C2 * NB + o] * v1
        S[_PD * NB + o] = max(S[_PD * NB + o], abs(q1))
        S[_PV * NB + o] = max(S[_PV * NB + o], abs(v1))
        S[_PA * NB + o] = max(S[_PA * NB + o], abs(A1))
        S[_Q * NB + o] = q1
        S[_V * NB + o] = v1


@njit(cache=True, inline="always")
def _coupling(Sb, PXb, X, row, n):
    """Rows ``_CP0, _CP1`` of a block: the building state's part of the oscillators' record-step
    update, from the state ``X[row]`` at the step start."""
    for o in range(NB):
        Sb[_CP0 * NB + o] = 0.0
        Sb[_CP1 * NB + o] = 0.0
    for j in range(n):
        xj = X[row, j]
        for o in range(NB):
            Sb[_CP0 * NB + o] += PXb[(2 * j) * NB + o] * xj
            Sb[_CP1 * NB + o] += PXb[(2 * j + 1) * NB + o] * xj


@njit(cache=True)
def sample_peaks(setup, X, k0, acc, up, dt, S, FB):
    """First pass of a spectrum, through one chunk of the floor motion (arguments as
    :func:`spectrum_kernel`): every oscillator stepped at the record step by its exact
    recurrence, its peaks at the samples raised in ``S``, and the record-wide bounds of the
    motion raised in ``FB`` (``float[NFB]``, zeros before the first chunk: rows ``FB_*``; on a
    floor the bounds of :func:`_floor_bounds` on every step). Then :func:`screen_thresholds`."""
    C = setup.C
    PX = setup.PX
    b_R = setup.b_R
    b_beta = setup.b_beta
    n = X.shape[1]
    nblk = C.shape[0]
    nosc = setup.w.size
    kf0 = k0 * up
    kf1 = kf0 + X.shape[0] - 1
    xn = np.empty(n)
    xs = np.empty(n)
    Kmax = max(setup.G_K.max(), setup.b_K)
    c = np.zeros(Kmax + 2)
    f0 = b_beta[0] * _sample(acc, kf0, up)
    for j in range(n):
        f0 += b_R[0, j] * X[0, j]
    L = CHUNK
    AK = np.zeros(L + 1)
    FK = np.zeros((L, 6))
    W = np.zeros((n + setup.b_K + 5, L + 1))
    for c0 in range(kf0, kf1, L):
        c1 = min(c0 + L, kf1)
        for k in range(c0, c1 + 1):
            AK[k - c0] = _sample(acc, k, up)
        if n == 0:
            for k in range(c0, c1):
                a = AK[k - c0]
                a1 = AK[k + 1 - c0]
                FB[FB_F] = max(FB[FB_F], abs(a), abs(a1))
                FB[FB_S] = max(FB[FB_S], abs((a1 - a) / dt))
        else:
            f0 = _floor_piece(setup, X, c0 - kf0, AK, c1 - c0, dt, f0, FK, W, c, xs, xn)
            for k in range(c1 - c0):
                FB[FB_F] = max(FB[FB_F], abs(FK[k, 0]), abs(FK[k, 1]))
                FB[FB_S] = max(FB[FB_S], abs((FK[k, 1] - FK[k, 0]) / dt))
                FB[FB_AB] = max(FB[FB_AB], FK[k, 2])
                FB[FB_DEV] = max(FB[FB_DEV], FK[k, 3])
                FB[FB_J] = max(FB[FB_J], FK[k, 4])
        for blk in range(nblk):
            Cb = C[blk]
            Sb = S[blk]
            PXb = PX[blk]
            nb = min(NB, nosc - blk * NB)
            for k in range(c0, c1):
                if n > 0:
                    _coupling(Sb, PXb, X, k - kf0, n)
                    _advance_floor(Cb, Sb, nb, AK[k - c0], AK[k + 1 - c0])
                else:
                    _advance_ground(Cb, Sb, nb, AK[k - c0], AK[k + 1 - c0])


_SCREEN_MARGIN = 1e-6
"""Relative margin of the screen thresholds over the largest chord deviation (rounding)."""


@njit(cache=True)
def screen_thresholds(C, S, nosc, FB, dt, on_floor):
    """After :func:`sample_peaks`: the screen thresholds of every oscillator (rows ``_TD, _TV,
    _TA`` of ``S``), and the oscillators set back at rest for the second pass.

    A threshold is the peak of the quantity's samples less a bound of the deviation from its
    chord that the skip test of :func:`_stage_ground` or :func:`_stage_floor` allows it in any
    step, from record-wide bounds: the steps' start states are samples, so ``|q0| ≤ max|q|`` and
    ``|q'0| ≤ max|q'|`` of the samples; with ``FB`` (the largest ``|f|``, chord slope, and on a
    floor ``max|a_f|``, deviation and ``max|a_f'|`` of any step) the particular solution and the
    free vibration's amplitude ``|C|`` of every step are bounded, and with them the tests'
    curvatures (the ground: ``ω²·dt²/8·|C|`` for ``|q|``, ``ω``, ``ω²(1 + 2ξ)`` times that for
    ``|q'|`` and ``|ω²q + 2ξωq'|``; a floor: ``dt²/8`` times ``m2q, m2v, m2a`` of
    :func:`_stage_floor`). A step whose end values are at most the thresholds passes none of
    those tests, so the screen skips only steps the tests skip."""
    fmax = FB[FB_F]
    smax = FB[FB_S]
    k8 = 0.125 * dt * dt
    margin = 1.0 + _SCREEN_MARGIN
    for og in range(nosc):
        blk = og // NB
        o = og - blk * NB
        Cb = C[blk]
        Sb = S[blk]
        w = Cb[W * NB + o]
        w2 = Cb[W2 * NB + o]
        c2 = Cb[C2 * NB + o]
        pd = Sb[_PD * NB + o]
        pv = Sb[_PV * NB + o]
        pa = Sb[_PA * NB + o]
        iw2 = Cb[IW2 * NB + o]
        bet = smax * iw2
        alp = smax * Cb[AS * NB + o] + fmax * iw2
        e0 = pd + alp
        ci = (pv + bet + Cb[XIW * NB + o] * e0) * Cb[IWD * NB + o]
        cm = math.sqrt(e0 * e0 + ci * ci)
        if on_floor:
            fdev = FB[FB_DEV]
            bd = alp + bet * dt + cm + fdev * Cb[IH0 * NB + o]
            bv = bet + w * cm + fdev * Cb[IH1 * NB + o]
            m2q = FB[FB_AB] + c2 * bv + w2 * bd
            m2v = FB[FB_J] + c2 * m2q + w2 * bv
            m2a = w2 * m2q + c2 * m2v
        else:
            m2q = w2 * cm
            m2v = w2 * w * cm
            m2a = w2 * Cb[SA * NB + o] * cm
        Sb[_TD * NB + o] = pd - k8 * m2q * margin
        Sb[_TV * NB + o] = pv - k8 * m2v * margin
        Sb[_TA * NB + o] = pa - k8 * m2a * margin
        Sb[_Q * NB + o] = 0.0
        Sb[_V * NB + o] = 0.0


def spectrum_state(nblk: int, f0: float) -> np.ndarray:
    """The initial state of :func:`spectrum_kernel`'s oscillators (at rest, ``q'' = −f0`` with
    ``f0`` the floor acceleration at ``t = 0``), ``(nblk, NSTATE·NB)``."""
    S = np.zeros((nblk, NSTATE * NB))
    S[:, _D * NB : (_D + 1) * NB] = -f0
    # no screen until screen_thresholds sets one: every step goes to the full tests
    S[:, _TD * NB : (_TA + 1) * NB] = -np.inf
    return S


class SpectrumSetup(NamedTuple):
    """Everything the spectrum kernel needs but the record, for one grid of periods and damping
    ratios on one floor (or the ground) and one step; built by ``core._kernel_data``. The field
    descriptions are those of :func:`spectrum_kernel`'s parameters."""

    C: Any
    PX: Any
    w: Any
    xi: Any
    b_phi: Any
    b_p: Any
    b_q: Any
    b_R: Any
    b_beta: Any
    b_K: Any
    b_m: Any
    grp: Any
    G_m: Any
    G_K: Any
    K_osc: Any
    G_phi: Any
    G_p: Any
    G_q: Any
    G_R: Any
    G_beta: Any
    S_Pqq: Any
    S_Pqx: Any
    S_pq: Any
    S_qq: Any


@njit(cache=True)
def spectrum_kernel(setup, X, k0, acc, up, dt, search_all, S, out, counts):
    """Peaks of a bank of oscillators on one floor.

    Every oscillator is advanced at the record step by its exact recurrence (coupled to the
    building on a floor) in a vectorised pass (``_stage_ground``, ``_stage_floor``); the steps it
    flags are then searched on the oscillator's sub-steps by :func:`_search_step`.

    Parameters
    ----------
    setup
        :class:`SpectrumSetup`; its fields:
    X, k0
        One chunk of the floor motion's building states from record step ``k0``
        (:meth:`floorslide.building.exact_motion.FloorMotion.chunks`; row ``j`` at fine-grid
        sample ``k0·up + j``; no columns on the ground): the building is not stepped here.
    acc, up, dt
        Ground acceleration samples; the kernel steps through the record on a grid ``up`` times
        finer (the same piecewise-linear function, values interpolated on the fly), of step
        ``dt`` (on a floor, ``up`` is the number of the building's own sub-steps per record
        step, so that the building's spectral radius times ``dt`` is at most 0.5).
    C
        ``(n_blocks, NCOEF·NB)``: per oscillator, in rows of ``NB``, its record-step recurrence
        and the constants of the skip tests (see ``core._blocks``).
    PX
        ``(n_blocks, 2·n_states·NB)``: coupling of each oscillator's record-step update to the
        building state (rows ``2j`` and ``2j+1`` for state ``j``); empty on the ground.
    w, xi
        Circular frequencies and damping ratios of the oscillators.
    b_*
        The building's own sub-steps (exact floor-acceleration extrema for the bound).
    grp, G_*, S_*
        Sub-step data of the in-step search: per oscillator its group (sub-step count ``G_m``,
        Taylor degree ``G_K``, the building's sub-step recurrence and Taylor rows) and its own
        coupled sub-step recurrence ``S_*``.
    K_osc
        Per oscillator, the Taylor degree of its response on its sub-steps (at most its group's).
    search_all
        Search every step of every oscillator (tests: the skip rules change nothing).
    S
        ``(n_blocks, NSTATE·NB)``: the oscillators' states and peaks, carried from chunk to
        chunk (:func:`spectrum_state` makes the initial one).
    out
        ``(n_osc, 3)``: peaks of ``|q|``, ``|q'|`` and ``|ω² q + 2ξω q'|``.
    counts
        ``int64[2]``, incremented: oscillator-steps searched, floor sub-step data computed.
    """
    C = setup.C
    PX = setup.PX
    w = setup.w
    xi = setup.xi
    b_R = setup.b_R
    b_beta = setup.b_beta
    b_K = setup.b_K
    grp = setup.grp
    G_m = setup.G_m
    G_K = setup.G_K
    K_osc = setup.K_osc
    G_phi = setup.G_phi
    G_p = setup.G_p
    G_q = setup.G_q
    G_R = setup.G_R
    G_beta = setup.G_beta
    S_Pqq = setup.S_Pqq
    S_Pqx = setup.S_Pqx
    S_pq = setup.S_pq
    S_qq = setup.S_qq
    n = X.shape[1]
    nblk = C.shape[0]
    nosc = w.size
    kf0 = k0 * up  # first fine-grid sample of the chunk
    kf1 = kf0 + X.shape[0] - 1
    xn = np.empty(n)
    xs = np.empty(n)
    xs2 = np.empty(n)
    f0 = b_beta[0] * _sample(acc, kf0, up)  # the floor acceleration at the chunk start
    for j in range(n):
        f0 += b_R[0, j] * X[0, j]
    Kmax = max(G_K.max(), b_K)
    c = np.zeros(Kmax + 2)
    Q = np.zeros(Kmax + 2)
    poly = np.zeros(Kmax + 2)
    work = scratch(Kmax + 2)
    flag = np.zeros(NB, dtype=np.int64)
    need = np.zeros(3, dtype=np.bool_)
    pk = np.zeros(3)
    ngroups = G_m.size
    ready = np.zeros(ngroups, dtype=np.bool_)
    CG = np.zeros((ngroups, G_m.max(), G_R.shape[1]))
    XG = np.zeros((ngroups, G_m.max(), n))
    cready = np.zeros((ngroups, G_m.max()), dtype=np.bool_)
    curv = np.zeros(5)
    L = CHUNK
    # floor: f0, f1, max|a_f|, deviation from the line, max|a_f'|, max|a_f'''|
    FK = np.zeros((L, 6))
    W = np.zeros((n + b_K + 5, L + 1))
    AK = np.zeros(L + 1)  # the record on the kernel's grid through the piece
    for c0 in range(kf0, kf1, L):
        c1 = min(c0 + L, kf1)
        for k in range(c0, c1 + 1):
            AK[k - c0] = _sample(acc, k, up)
        # the floor through this piece, once for every block
        if n > 0:
            f0 = _floor_piece(setup, X, c0 - kf0, AK, c1 - c0, dt, f0, FK, W, c, xs, xn)
        # each block of oscillators through the chunk, its data staying in the L1 cache
        for blk in range(nblk):
            Cb = C[blk]
            Sb = S[blk]
            PXb = PX[blk]
            nb = min(NB, nosc - blk * NB)
            # the screen, or where it lets many steps through (short periods) the full tests
            # vectorised: decided per block and piece by the screen's first SCREEN_TRIAL steps
            full = search_all
            passed = 0
            for k in range(c0, c1):
                a = AK[k - c0]
                a1 = AK[k + 1 - c0]
                if (
                    not full
                    and k - c0 == SCREEN_TRIAL
                    and passed * SCREEN_RATIO > SCREEN_TRIAL * nb
                ):
                    full = True
                if n > 0:
                    _coupling(Sb, PXb, X, k - kf0, n)
                    if full:
                        nf = _stage_floor(
                            Cb,
                            Sb,
                            flag,
                            nb,
                            a,
                            a1,
                            dt,
                            FK[k - c0, 0],
                            FK[k - c0, 1],
                            FK[k - c0, 3],
                            FK[k - c0, 2],
                            FK[k - c0, 4],
                        )
                    else:
                        nf = _screen_floor(Cb, Sb, flag, nb, a, a1)
                        if nf > 0:
                            nf = 0
                            for o in range(nb):
                                if flag[o] != 0:
                                    passed += 1
                                    flag[o] = _floor_test(
                                        Cb,
                                        Sb,
                                        o,
                                        dt,
                                        FK[k - c0, 0],
                                        FK[k - c0, 1],
                                        FK[k - c0, 3],
                                        FK[k - c0, 2],
                                        FK[k - c0, 4],
                                    )
                                    nf += flag[o]
                    for g in range(ngroups):
                        ready[g] = False
                elif full:
                    nf = _stage_ground(Cb, Sb, flag, nb, a, a1, dt)
                else:
                    nf = _screen_ground(Cb, Sb, flag, nb, a, a1)
                    if nf > 0:
                        nf = 0
                        for o in range(nb):
                            if flag[o] != 0:
                                passed += 1
                                flag[o] = _ground_test(Cb, Sb, o, a, a1, dt)
                                nf += flag[o]
                if nf == 0 and not search_all:
                    continue
                for o in range(nb):
                    f = 7 if search_all else flag[o]
                    if f == 0:
                        continue
                    og = blk * NB + o
                    counts[0] += 1
                    if n == 0:
                        pk[0] = Sb[_PD * NB + o]
                        pk[1] = Sb[_PV * NB + o]
                        pk[2] = Sb[_PA * NB + o]
                        _ground_search(
                            f,
                            a,
                            a1,
                            dt,
                            G_m[grp[og]],
                            K_osc[og],
                            Sb[_QS * NB + o],
                            Sb[_VS * NB + o],
                            w[og],
                            xi[og],
                            S_Pqq[og, 0, 0],
                            S_Pqq[og, 0, 1],
                            S_Pqq[og, 1, 0],
                            S_Pqq[og, 1, 1],
                            S_pq[og, 0],
                            S_pq[og, 1],
                            S_qq[og, 0],
                            S_qq[og, 1],
                            pk,
                            Q,
                            poly,
                            work,
                        )
                        Sb[_PD * NB + o] = pk[0]
                        Sb[_PV * NB + o] = pk[1]
                        Sb[_PA * NB + o] = pk[2]
                        continue
                    need[0] = (f & 1) != 0
                    need[1] = (f & 2) != 0
                    need[2] = (f & 4) != 0
                    out[og, 0] = Sb[_PD * NB + o]
                    out[og, 1] = Sb[_PV * NB + o]
                    out[og, 2] = Sb[_PA * NB + o]
                    g = grp[og]
                    if n > 0 and not ready[g]:
                        # the floor's states on this group's sub-steps, shared by the
                        # oscillators of the group in this block (its Taylor coefficients are
                        # computed by _search_step on the sub-steps that need them)
                        counts[1] += 1
                        mg = G_m[g]
                        for i in range(n):
                            xs2[i] = X[k - kf0, i]
                        for r in range(mg):
                            aa, ab = substep_inputs(a, a1, r, mg)
                            for i in range(n):
                                XG[g, r, i] = xs2[i]
                            cready[g, r] = False
                            if r + 1 < mg:
                                foh_step(G_phi[g], G_p[g], G_q[g], xs2, aa, ab, xn)
                                for i in range(n):
                                    xs2[i] = xn[i]
                        ready[g] = True
                    _floor_curvatures(
                        Cb,
                        o,
                        Sb[_QS * NB + o],
                        Sb[_VS * NB + o],
                        dt,
                        FK[k - c0, 0],
                        FK[k - c0, 1],
                        FK[k - c0, 3],
                        FK[k - c0, 2],
                        FK[k - c0, 4],
                        FK[k - c0, 5],
                        curv,
                    )
                    _search_step(
                        og,
                        g,
                        n,
                        a,
                        a1,
                        dt,
                        Sb[_QS * NB + o],
                        Sb[_VS * NB + o],
                        w[og],
                        xi[og],
                        G_m[g],
                        K_osc[og],
                        CG,
                        XG,
                        cready,
                        G_R,
                        G_beta,
                        FK[k - c0, 0],
                        FK[k - c0, 1],
                        S_Pqq,
                        S_Pqx,
                        S_pq,
                        S_qq,
                        need,
                        curv,
                        out,
                        c,
                        Q,
                        poly,
                        work,
                    )
                    Sb[_PD * NB + o] = out[og, 0]
                    Sb[_PV * NB + o] = out[og, 1]
                    Sb[_PA * NB + o] = out[og, 2]
    for og in range(nosc):
        blk = og // NB
        o = og - blk * NB
        out[og, 0] = S[blk, _PD * NB + o]
        out[og, 1] = S[blk, _PV * NB + o]
        out[og, 2] = S[blk, _PA * NB + o]
