"""Compiled batched kernel of the 2-DOF sliding oscillator: all friction values in one call,
most parts cleared by exact propagators and rigorous chord bounds.

The model and the state columns are those of :mod:`floorslide.contents._oscillator_kernel`
(per unit top mass; ``y = [u, v, z, zd]``; ``q = 2ξw z' + w² z``): in stick

    z'' = −a_f − q,                  F = r a_f − q,   admissible while |F| ≤ mu_s (1+r) g,   (1)

and in slip with sign ``s``

    v' = −a_f + q/r − s mu_k (1+r) g / r,   z'' = −q (1 + 1/r) + s mu_k (1+r) g / r.         (2)

Both phases are linear with constant coefficients, driven by the floor acceleration ``a_f``
(on each part of a sub-step the polynomial ``Σ_l c_l τ^l``, shared by every oscillator) and, in
slip, by the constant friction force. On a part of length ``ho`` (``ρ·ho ≤ 0.5``) the end state
is therefore

    y(ho) = Φ_p y(0) + Σ_l G_p[:, l] c_l + s mu_k g e,                                        (3)

with ``Φ_p, G_p, e`` the part's propagators of phase ``p`` — the Taylor series of the event
kernel (:func:`~floorslide.contents._oscillator_kernel._phase_series`) applied to unit inputs
and summed at ``ho``, so the same truncated exact solution, computed once per (``ho``, ``w``,
``ξ``, ``r``) instead of once per part and friction value (:func:`phase_propagators`). The
floor terms ``Σ_l G_p c_l`` are formed once per part for all oscillators.

A part needs the event kernel (:func:`~floorslide.contents._oscillator_kernel.event_part`:
root isolation of events and peaks) only if something may happen inside it. That is decided
by the chord bound: for a function ``p`` on ``[0, ho]``,

    max |p| ≤ max(|p(0)|, |p(ho)|) + ho²/8 · max |p''|,                                       (4)

and ``min p ≥ min(p(0), p(ho)) − ho²/8 · max |p''|``. Every output (``F``, ``v``, ``z``, ``q``)
is, on the part, a polynomial whose coefficients are linear in the inputs (the start state,
the floor coefficients, the friction force), so

    max |p''| ≤ Σ_i W_i |x_i|,   W_i = Σ_{j≥2} j (j−1) ho^{j−2} |p_j(e_i)|,                     (5)

with weights ``W`` computed with the propagators (the floor's share once per part). A stick
part is cleared when (4) keeps ``|F|`` below the static limit and ``|z|``, ``|q|`` at or below
their peaks so far; a slip part when ``s·v`` stays positive (no stop: ``u`` is then monotone,
its peak at an end) and ``|z|``, ``|q|`` and the base's acceleration stay at or below their
peaks. The base's acceleration in stick is the floor's, whose peak on the part is computed at
most once per part for all oscillators (:func:`~floorslide.numerics.polynomial.max_abs_on`,
as the event kernel does). Every other part goes through the event kernel from the same state
columns: events and new peaks are found exactly as before; a cleared part changes no peak and
no phase, and its end state (3) equals the event kernel's to rounding (a different order of
the same operations: differences at the rounding level, ~1e-16 of the state per part).
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import poly_val, substep_inputs, taylor_coefficients
from floorslide.contents._oscillator_kernel import (
    O_MODE,
    O_PEAK_BASE,
    O_PEAK_TOP,
    O_PEAK_U,
    O_PEAK_Z,
    O_SLIDE_TIME,
    O_U,
    O_V,
    O_Z,
    O_ZD,
    _phase_series,
    _shift,
    _update_peak,
    event_part,
)
from floorslide.numerics.polynomial import curvature_bound, max_abs_on, scratch

STICK, SLIP = 0, 1
"""Phase index of the propagators."""
B_EVENT, B_Z, B_Q = 0, 1, 2
"""Bounded outputs: the event function (``F`` in stick, ``v`` in slip), ``z`` and ``q``."""
W_FRICTION = 4
"""Column of the friction force's weight; the state's are 0–3, the floor's shares are
formed per part (:func:`part_inputs`)."""
SAFETY = 1.0 + 1e-9
"""Factor on every curvature bound (covers the rounding of the weights and of (5))."""
MARGIN = 1e-12
"""Relative margin of a cleared part: its bound must stay this far inside the limit (scaled by
the magnitudes), so that the event kernel's own rounding could not have found an event there."""

# packed per-part floor inputs (:func:`part_inputs`)
S_AF0, S_AF1 = 0, 1
"""Floor acceleration at the part's start and end."""
S_BST = 2
"""Stick floor response: z, zd (2 entries)."""
S_BSL = 4
"""Slip floor response: u, v, z, zd (4 entries)."""
S_WST = 8
"""Floor share of the stick curvature bounds of F, z, q (3 entries)."""
S_WSL = 11
"""Floor share of the slip curvature bounds of v, z, q (3 entries)."""
S_FLOOR_HI = 14
"""Upper bound of the floor's ``|a_f|`` on the part, by (4)."""
S_FLOOR_PEAK = 15
"""The floor's exact ``max |a_f|`` on the part, or −1 until some oscillator needs it."""
S_NCOL = 16

# what became of each oscillator's part (:func:`stick_part`, :func:`slip_part`), counted by the
# kernel
CLEARED = 0
"""Cleared by the bounds."""
C_EVENT, C_Z, C_Q, C_BASE = 1, 2, 3, 4
"""Sent to the event kernel: an event (breakaway, stop) may lie in the part, or a new peak of
``|z|``, of the top's or of the base's acceleration."""
C_NCOL = 10
"""Counter columns: ``C_* `` for stick, ``5 + C_*`` for slip."""


@njit(cache=True)
def phase_propagators(ho, K, w, xi, r):
    """Propagators (3) and curvature weights (5) of both phases on a part of length ``ho``.

    Returns
    -------
    PHI : (2, 4, 4)
        ``PHI[p] y0``: the end state from the start state (no floor motion, no friction). Neither
        phase's derivatives depend on ``u``, nor on ``v`` but ``u' = v``: the first two
        columns are ``[1, 0, 0, 0]`` and ``[ho, 1, 0, 0]`` (the kernel adds increments to
        ``u`` and ``v`` instead of multiplying them by 1).
    GF : (2, 4, K+1)
        ``GF[p][:, l]``: the end state from rest under the floor acceleration ``τ^l``.
    EF : (4,)
        End state from rest in slip under the friction of ``s·mu_k·g = 1`` (eq. (2)).
    WS : (2, 3, 5)
        Weights (5) of the event function, ``z`` and ``q`` on the start state (columns 0–3)
        and on the friction force ``s·mu_k·g`` (column :data:`W_FRICTION`).
    WF : (2, 3, K+1)
        Weights (5) on the floor coefficients ``|c_l|``.
    """
    PHI = np.zeros((2, 4, 4))
    GF = np.zeros((2, 4, K + 1))
    EF = np.zeros(4)
    WS = np.zeros((2, 3, 5))
    WF = np.zeros((2, 3, K + 1))
    Y = np.zeros((4, K + 1))
    y = np.zeros(4)
    cs = np.zeros(K + 1)
    ends = np.zeros(4)
    wsum = np.zeros(3)
    c2 = 2.0 * xi * w
    w2 = w * w
    for p in range(2):
        for inp in range(4 + K + 1 + p):
            y[:] = 0.0
            cs[:] = 0.0
            fk = 0.0
            if inp < 4:
                y[inp] = 1.0
            elif inp < 5 + K:
                cs[inp - 4] = 1.0
            else:
                fk = 1.0
            _phase_series(y, p, cs, K, w, xi, r, fk, False, Y)
            for i in range(4):
                ends[i] = poly_val(Y[i], K, ho)
            wsum[:] = 0.0
            hj = 1.0
            for j in range(2, K + 1):
                f = j * (j - 1) * hj
                ev = r * cs[j] - c2 * Y[3, j] - w2 * Y[2, j] if p == STICK else Y[1, j]
                wsum[B_EVENT] += f * abs(ev)
                wsum[B_Z] += f * abs(Y[2, j])
                wsum[B_Q] += f * abs(c2 * Y[3, j] + w2 * Y[2, j])
                hj *= ho
            for i in range(4):
                if inp < 4:
                    PHI[p, i, inp] = ends[i]
                elif inp < 5 + K:
                    GF[p, i, inp - 4] = ends[i]
                else:
                    EF[i] = ends[i]
            for b in range(3):
                if inp < 4:
                    WS[p, b, inp] = wsum[b] * SAFETY
                elif inp < 5 + K:
                    WF[p, b, inp - 4] = wsum[b] * SAFETY
                else:
                    WS[p, b, W_FRICTION] = wsum[b] * SAFETY
    return PHI, GF, EF, WS, WF


@njit(cache=True, _nrt=False)
def part_inputs(cs, kf, K, ho, GF, WF, sh):
    """The floor's share of one part, common to every oscillator, into ``sh`` (columns
    ``S_*``): the floor responses ``Σ_l G_p[:, l] c_l`` of (3), the floor shares
    ``Σ_l W_l |c_l|`` of the bounds (5), the floor acceleration at both ends and the bound (4)
    of its peak. ``cs``: the floor polynomial on the part (degree ``kf ≤ K``)."""
    for i in range(S_NCOL):
        sh[i] = 0.0
    for l in range(kf + 1):
        c = cs[l]
        ac = abs(c)
        sh[S_BST] += GF[STICK, 2, l] * c
        sh[S_BST + 1] += GF[STICK, 3, l] * c
        for i in range(4):
            sh[S_BSL + i] += GF[SLIP, i, l] * c
        for b in range(3):
            sh[S_WST + b] += WF[STICK, b, l] * ac
            sh[S_WSL + b] += WF[SLIP, b, l] * ac
    sh[S_AF0] = cs[0]
    sh[S_AF1] = poly_val(cs, K, ho)
    sh[S_FLOOR_HI] = max(abs(sh[S_AF0]), abs(sh[S_AF1])) + 0.125 * ho * ho * SAFETY * (
        curvature_bound(cs, K, ho)
    )
    sh[S_FLOOR_PEAK] = -1.0


@njit(cache=True, _nrt=False)
def stick_part(states, o, sh, PHI, WS, r, c2, w2, fb, k8):
    """Advance stuck oscillator ``o`` through a part if (4) clears it: ``|F| < fb`` throughout
    (no breakaway) and ``|z|``, ``|q|`` at or below their peaks. Returns :data:`CLEARED`, or,
    changing nothing, why the part needs the event kernel (``C_*``). The base's acceleration
    (the floor's) is left to the caller."""
    z0 = states[o, O_Z]
    zd0 = states[o, O_ZD]
    az0 = abs(z0)
    azd0 = abs(zd0)
    z1 = PHI[STICK, 2, 2] * z0 + PHI[STICK, 2, 3] * zd0 + sh[S_BST]
    zd1 = PHI[STICK, 3, 2] * z0 + PHI[STICK, 3, 3] * zd0 + sh[S_BST + 1]
    q0 = c2 * zd0 + w2 * z0
    q1 = c2 * zd1 + w2 * z1
    # breakaway: F = r a_f − q, eq. (1)
    f0 = r * sh[S_AF0] - q0
    f1 = r * sh[S_AF1] - q1
    m2 = WS[STICK, B_EVENT, 2] * az0 + WS[STICK, B_EVENT, 3] * azd0 + sh[S_WST + B_EVENT]
    if max(abs(f0), abs(f1)) + k8 * m2 > fb * (1.0 - MARGIN):
        return C_EVENT
    m2 = WS[STICK, B_Z, 2] * az0 + WS[STICK, B_Z, 3] * azd0 + sh[S_WST + B_Z]
    if max(az0, abs(z1)) + k8 * m2 > states[o, O_PEAK_Z]:
        return C_Z
    m2 = WS[STICK, B_Q, 2] * az0 + WS[STICK, B_Q, 3] * azd0 + sh[S_WST + B_Q]
    if max(abs(q0), abs(q1)) + k8 * m2 > states[o, O_PEAK_TOP]:
        return C_Q
    states[o, O_Z] = z1
    states[o, O_ZD] = zd1
    return CLEARED


@njit(cache=True, _nrt=False)
def slip_part(states, o, sh, PHI, EF, WS, r, c2, w2, fkg, ho, k8):
    """Advance slipping oscillator ``o`` (sign ``s`` of its velocity) through a part if (4)
    clears it: ``s·v > 0`` throughout (no stop; ``u`` monotone, its peak at an end) and ``|z|``,
    ``|q|`` and ``|q/r − s mu_k (1+r) g/r|`` (the base's acceleration) at or below their peaks.
    Returns :data:`CLEARED`, or, changing nothing, why the part needs the event kernel
    (``C_*``)."""
    s = states[o, O_MODE]
    f = s * fkg
    u0 = states[o, O_U]
    v0 = states[o, O_V]
    z0 = states[o, O_Z]
    zd0 = states[o, O_ZD]
    # the end state, eq. (3); no derivative depends on u, none on v but u' = v (eq. (2)), so
    # u and v get increments: one rounding of the (drifting) u and v per part, as in the
    # series' Horner sums
    v1 = v0 + (PHI[SLIP, 1, 2] * z0 + PHI[SLIP, 1, 3] * zd0 + sh[S_BSL + 1] + f * EF[1])
    z1 = PHI[SLIP, 2, 2] * z0 + PHI[SLIP, 2, 3] * zd0 + sh[S_BSL + 2] + f * EF[2]
    zd1 = PHI[SLIP, 3, 2] * z0 + PHI[SLIP, 3, 3] * zd0 + sh[S_BSL + 3] + f * EF[3]
    av = abs(v0)
    az = abs(z0)
    azd = abs(zd0)
    af = abs(f)
    q0 = c2 * zd0 + w2 * z0
    q1 = c2 * zd1 + w2 * z1
    fr = f * (1.0 + r) / r
    # no stop: s·v > 0 on the whole part, by the chord bound (4) or, better just after a
    # breakaway (v small, |v'| large), by Taylor's bounds from each end over its half:
    # s·v(t) ≥ s·v(0) + s·v'(0) t − m2 t²/2 on [0, ho/2], concave, so ≥ its value at an end
    # (and likewise from ho backwards on [ho/2, ho])
    m2 = WS[SLIP, B_EVENT, 1] * av + WS[SLIP, B_EVENT, 2] * az + WS[SLIP, B_EVENT, 3] * azd
    m2 += WS[SLIP, B_EVENT, W_FRICTION] * af + sh[S_WSL + B_EVENT]
    p0 = s * v0
    p1 = s * v1
    low = min(p0, p1) - k8 * m2
    tol = MARGIN * (av + abs(v1) + k8 * m2)
    if low <= tol:
        # v' = −a_f + q/r − s mu_k (1+r) g/r, eq. (2)
        d0 = s * (-sh[S_AF0] + q0 / r - fr)
        d1 = s * (-sh[S_AF1] + q1 / r - fr)
        half = 0.5 * ho
        low = min(p0, p0 + d0 * half - k8 * m2, p1, p1 - d1 * half - k8 * m2)
        if low <= tol:
            return C_EVENT
    m2 = WS[SLIP, B_Z, 1] * av + WS[SLIP, B_Z, 2] * az + WS[SLIP, B_Z, 3] * azd
    m2 += WS[SLIP, B_Z, W_FRICTION] * af + sh[S_WSL + B_Z]
    if max(az, abs(z1)) + k8 * m2 > states[o, O_PEAK_Z]:
        return C_Z
    m2 = WS[SLIP, B_Q, 1] * av + WS[SLIP, B_Q, 2] * az + WS[SLIP, B_Q, 3] * azd
    m2 += WS[SLIP, B_Q, W_FRICTION] * af + sh[S_WSL + B_Q]
    if max(abs(q0), abs(q1)) + k8 * m2 > states[o, O_PEAK_TOP]:
        return C_Q
    # the base's acceleration q/r − s mu_k (1+r) g/r: its curvature is q's over r
    if max(abs(q0 / r - fr), abs(q1 / r - fr)) + k8 * m2 / r > states[o, O_PEAK_BASE]:
        return C_BASE
    du = PHI[SLIP, 0, 1] * v0 + PHI[SLIP, 0, 2] * z0 + PHI[SLIP, 0, 3] * zd0
    u1 = u0 + (du + sh[S_BSL] + f * EF[0])
    states[o, O_U] = u1
    states[o, O_V] = v1
    states[o, O_Z] = z1
    states[o, O_ZD] = zd1
    if abs(u1) > states[o, O_PEAK_U]:
        states[o, O_PEAK_U] = abs(u1)
    states[o, O_SLIDE_TIME] += ho
    return CLEARED


@njit(cache=True)
def quiet_part(cs, K, ho, o, w, xi, r, g, muk, states, Y, poly, y, pk, work):
    """Advance oscillator ``o`` through a part that has no event (its bound cleared it) but may
    hold a new peak, as the event kernel does a part without events: the phase's Taylor series
    on the part (floor polynomial ``cs``), every peak on it by
    :func:`~floorslide.numerics.polynomial.max_abs_on`, the end state from the series. The
    event kernel's work without its event searches (``y``, ``pk``: scratch of 4)."""
    c2 = 2.0 * xi * w
    w2 = w * w
    mode = int(states[o, O_MODE])
    fkg = muk[o] * g
    for i in range(4):
        y[i] = states[o, O_U + i]
        pk[i] = states[o, O_PEAK_U + i]
    _phase_series(y, mode, cs, K, w, xi, r, fkg, False, Y)
    for j in range(K + 1):
        poly[j] = Y[0, j]
    _update_peak(poly, K, 0.0, ho, pk, 0, work)
    for j in range(K + 1):
        poly[j] = Y[2, j]
    _update_peak(poly, K, 0.0, ho, pk, 1, work)
    for j in range(K + 1):
        poly[j] = -(c2 * Y[3, j] + w2 * Y[2, j])
    _update_peak(poly, K, 0.0, ho, pk, 2, work)
    if mode == 0:
        for j in range(K + 1):
            poly[j] = cs[j]
        _update_peak(poly, K, 0.0, ho, pk, 3, work)
    else:
        sgn = float(mode)
        for j in range(K + 1):
            poly[j] = (c2 * Y[3, j] + w2 * Y[2, j]) / r
        poly[0] -= sgn * fkg * (1.0 + r) / r
        _update_peak(poly, K, 0.0, ho, pk, 3, work)
        states[o, O_SLIDE_TIME] += ho
    for i in range(4):
        states[o, O_U + i] = poly_val(Y[i], K, ho)
        states[o, O_PEAK_U + i] = pk[i]


@njit(cache=True)
def oscillator_batch_kernel(X, k0, R, beta, acc, substeps, h, m_o, K, w, xi, r, g, mub, muk,
                            PHI, GF, EF, WS, WF, states, hist, want_hist, max_events,
                            counts):  # fmt: skip
    """Advance 2-DOF sliding oscillators (one per friction pair) through the record, as
    :func:`~floorslide.contents._oscillator_kernel.oscillator_kernel` (same arguments, same
    state columns and histories) with the propagators and weights of
    :func:`phase_propagators` for parts of length ``h/m_o``: per part, the floor's share is
    formed once (:func:`part_inputs`), then each oscillator is cleared by :func:`stick_part` /
    :func:`slip_part` or advanced by the event kernel
    (:func:`~floorslide.contents._oscillator_kernel.event_part`). ``counts``
    (:data:`C_NCOL`): parts cleared and parts sent to the event kernel, by reason and phase,
    incremented.
    """
    nobj = muk.size
    nsteps = (X.shape[0] - 1) // substeps
    ho = h / m_o
    k8 = 0.125 * ho * ho
    c = np.zeros(K + 1)
    cs = np.zeros(K + 1)
    cs_ev = np.zeros(K + 1)
    Y = np.zeros((4, K + 1))
    poly = np.zeros(K + 1)
    y = np.zeros(4)
    pk = np.zeros(4)
    sh = np.zeros(S_NCOL)
    work = scratch(K + 1)
    c2 = 2.0 * xi * w
    w2 = w * w
    kr = R.shape[0] - 1
    for kk in range(nsteps):
        k = k0 + kk
        a = acc[k]
        a1 = acc[k + 1]
        slope = (a1 - a) / (substeps * h)
        for sub in range(substeps):
            aa, _ = substep_inputs(a, a1, sub, substeps)
            for j in range(K + 1):
                c[j] = 0.0
            taylor_coefficients(R, beta, X[kk * substeps + sub], aa, slope, c[: kr + 1])
            for so in range(m_o):
                base = so * ho
                if base == 0.0:
                    for j in range(K + 1):
                        cs[j] = c[j]
                else:
                    _shift(c, K, base, cs)
                part_inputs(cs, kr, K, ho, GF, WF, sh)
                t_part = (k * substeps + sub) * h + base
                for o in range(nobj):
                    mode = states[o, O_MODE]
                    if mode == 0.0:
                        fb = mub[o] * (1.0 + r) * g
                        why = stick_part(states, o, sh, PHI, WS, r, c2, w2, fb, k8)
                        counts[why] += 1
                        if why == CLEARED and sh[S_FLOOR_HI] > states[o, O_PEAK_BASE]:
                            if sh[S_FLOOR_PEAK] < 0.0:
                                # the value the event kernel finds when it exceeds a peak
                                fpk, _ = max_abs_on(cs, K, ho, -1.0, work)
                                sh[S_FLOOR_PEAK] = fpk
                            if sh[S_FLOOR_PEAK] > states[o, O_PEAK_BASE]:
                                states[o, O_PEAK_BASE] = sh[S_FLOOR_PEAK]
                    else:
                        why = slip_part(states, o, sh, PHI, EF, WS, r, c2, w2, muk[o] * g,
                                        ho, k8)  # fmt: skip
                        counts[5 + why] += 1
                    if why != CLEARED and why != C_EVENT:
                        quiet_part(cs, K, ho, o, w, xi, r, g, muk, states, Y, poly, y, pk, work)
                    elif why == C_EVENT:
                        event_part(c, K, base, ho, o, w, xi, r, g, mub, muk, states, t_part,
                                   max_events, cs_ev, Y, poly, y, pk, work, True)  # fmt: skip
            if want_hist and sub == substeps - 1:
                af_end = poly_val(c, K, h)
                for o in range(nobj):
                    mode = states[o, O_MODE]
                    q_ = c2 * states[o, O_ZD] + w2 * states[o, O_Z]
                    hist[o, k + 1, 0] = states[o, O_U]
                    hist[o, k + 1, 1] = states[o, O_Z]
                    hist[o, k + 1, 2] = -q_
                    if mode == 0.0:
                        hist[o, k + 1, 3] = af_end
                    else:
                        hist[o, k + 1, 3] = q_ / r - mode * muk[o] * g * (1.0 + r) / r
