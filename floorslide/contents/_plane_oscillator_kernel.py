"""Compiled kernel of 2-DOF sliding oscillators in the plane on a poly motion's segments.

Per unit top mass (``r = m_base/m_top``, ``k = 1 + 1/r``): the top mass on an isotropic spring
and dashpot (circular frequency ``w``, damping ratio ``ξ``) over a base that slides on the floor
with isotropic Coulomb friction under the total weight ``(1 + r)·g``. With ``U``, ``V`` the base's
slide relative to the floor and its velocity, ``Z``, ``P = Z'`` the spring's deformation (top
relative to base) and its rate, ``q = 2ξw P + w² Z`` (minus the top's absolute acceleration) and
``a`` the floor's absolute acceleration (2-vectors):

- stuck (``V = 0``): ``Z'' = −a − q``; the friction the base needs is ``F = r a − q``, admissible
  while ``|F| ≤ mu_b (1 + r) g`` (``mu_b = max(mu_s, mu_k)``);
- sliding: ``V' = −(a − q/r) − f w`` and ``Z'' = −k q + f w``, ``w = V/|V|``,
  ``f = mu_k (1 + r) g / r``.

Sliding, the base is the plane's rigid block (:mod:`floorslide.contents._plane_kernel`) under the
drive ``e = a − q/r`` and the friction ``f``, with ``q`` coupled linearly through ``w``: the
Taylor recurrences of the block (Jorba & Zou 2005) gain, order by order,
``Z_{j+1} = P_j/(j+1)``, ``P_{j+1} = (−k q_j + f w_j)/(j+1)`` and ``e_j = a_j − q_j/r`` — each
known before it is needed (``q_j`` needs ``w`` up to ``j − 1``), so the start from rest
(``V = τ^m y``, ``m = 1`` beyond the kinetic level, ``m = 2`` at a breakaway with
``mu_s = mu_k``) is solved along and across its initial direction exactly as the block's
(:func:`floorslide.numerics.friction_series.start_series`). Stuck, ``Z`` is a linear oscillator
driven by the floor's polynomial, its series explicit. Steps follow the block's rule (the last
two terms of every series below :data:`~floorslide.contents._plane_kernel.STEP_TOL` of its
first three); a stop is the first root of the speed's analytic series, a breakaway the first
rise of ``|F|² − (mu_b (1 + r) g)²``, both by rigorous root isolation
(:mod:`floorslide.numerics.polynomial`); the peaks of ``|U|``, ``|Z|`` and ``|q|`` are maxima
of their squared polynomials on every step (filtered by coefficient bounds). No slow-manifold
shortcut: a base creeping barely beyond kinetic friction takes many short steps.

References
----------
Jorba, À., Zou, M. (2005). A software package for the numerical integration of ODEs by means of
high-order Taylor methods. *Experimental Mathematics* 14(1), 99–117.
Westermo, B., Udwadia, F. (1983). Periodic response of a sliding oscillator system to harmonic
excitation. *Earthquake Eng. Struct. Dyn.* 11, 135–146.
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.contents._plane_kernel import (
    EVENT_GAP,
    LIMIT_AT,
    MAX_STEPS,
    MODE,
    SLIDE_TIME,
    SLIPS,
    START,
    STEP_TOL,
    STOP_SPEED,
    STOPS,
    UX,
    UY,
    VX,
    VY,
    _advance,
    _speed_root,
    _step_size,
)
from floorslide.numerics.polynomial import max_abs_on, rise_within, scratch, taylor_shift

ZX, ZY, PX, PY, PEAK_Z, PEAK_TOP = 16, 17, 18, 19, 20, 21
"""Columns beyond the plane block's (:mod:`floorslide.contents._plane_kernel`, whose columns
0–15 hold the base: mode, slide, velocity, peak slide and its time and direction, time sliding,
slip phases, stops, event limit, start order, path): the spring's deformation ``Z`` and rate
``P``, and the peaks of ``|Z|`` and of the top's absolute acceleration ``|q|``."""
NCOL = 22
JUMP_TOL = 1e-9
"""A stuck base breaks away at a segment's start when the friction it needs there exceeds the
breakaway level by more than this share (a floor whose acceleration jumps: the mat of a
building on friction pendulums), as the plane block's
(:data:`floorslide.contents._plane_segment_kernels.JUMP_TOL`)."""

_INV = np.array([0.0] + [1.0 / k for k in range(1, 128)])


@njit(cache=True, _nrt=False)
def stick_series(ax, ay, K, st, c2, w2, D, Z, P):
    """Taylor coefficients ``Z[0..D]``, ``P[0..D]`` of the spring's deformation and rate while the
    base sticks: ``Z' = P``, ``P' = −a − 2ξw P − w² Z`` (``c2 = 2ξw``, ``w2 = w²``) from the
    state in ``st``, under the floor acceleration ``ax, ay`` (degree ``K``)."""
    Z[0, 0] = st[ZX]
    Z[0, 1] = st[ZY]
    P[0, 0] = st[PX]
    P[0, 1] = st[PY]
    for k in range(D):
        akx = ax[k] if k <= K else 0.0
        aky = ay[k] if k <= K else 0.0
        f = _INV[k + 1]
        Z[k + 1, 0] = P[k, 0] * f
        Z[k + 1, 1] = P[k, 1] * f
        P[k + 1, 0] = (-akx - c2 * P[k, 0] - w2 * Z[k, 0]) * f
        P[k + 1, 1] = (-aky - c2 * P[k, 1] - w2 * Z[k, 1]) * f


@njit(cache=True, _nrt=False)
def moving_series(ax, ay, K, st, r0, fk, c2, w2, r, kk, D, y, rho, w, Z, P):
    """Taylor coefficients of a sliding base's velocity ``y`` (``V(0) ≠ 0``, ``r0 = |V(0)|``), its
    speed ``rho`` (``w = V/|V|`` in ``w``) and the spring's ``Z``, ``P``, to degree ``D``: the
    plane block's recurrences (:func:`floorslide.contents._plane_kernel.moving_series`) with the
    drive ``e_k = a_k − q_k/r`` and ``Z_{k+1} = P_k/(k+1)``,
    ``P_{k+1} = (−kk q_k + fk w_k)/(k+1)``."""
    ir0 = 1.0 / r0
    h0 = 0.5 * ir0
    w0x = st[VX] * ir0
    w0y = st[VY] * ir0
    y[0, 0] = st[VX]
    y[0, 1] = st[VY]
    rho[0] = r0
    w[0, 0] = w0x
    w[0, 1] = w0y
    Z[0, 0] = st[ZX]
    Z[0, 1] = st[ZY]
    P[0, 0] = st[PX]
    P[0, 1] = st[PY]
    ir = 1.0 / r
    for k in range(D + 1):
        if k >= 1:
            s = 0.0
            for j in range(1, (k + 1) // 2):
                s += y[j, 0] * y[k - j, 0] + y[j, 1] * y[k - j, 1] - rho[j] * rho[k - j]
            s += s
            if k % 2 == 0:
                j = k // 2
                s += y[j, 0] * y[j, 0] + y[j, 1] * y[j, 1] - rho[j] * rho[j]
            rk = s * h0 + (w0x * y[k, 0] + w0y * y[k, 1])
            rho[k] = rk
            sx = rk * w0x
            sy = rk * w0y
            for j in range(1, k):
                sx += rho[j] * w[k - j, 0]
                sy += rho[j] * w[k - j, 1]
            w[k, 0] = (y[k, 0] - sx) * ir0
            w[k, 1] = (y[k, 1] - sy) * ir0
        if k == D:
            break
        qx = c2 * P[k, 0] + w2 * Z[k, 0]
        qy = c2 * P[k, 1] + w2 * Z[k, 1]
        akx = ax[k] if k <= K else 0.0
        aky = ay[k] if k <= K else 0.0
        f = _INV[k + 1]
        y[k + 1, 0] = (-akx + qx * ir - fk * w[k, 0]) * f
        y[k + 1, 1] = (-aky + qy * ir - fk * w[k, 1]) * f
        Z[k + 1, 0] = P[k, 0] * f
        Z[k + 1, 1] = P[k, 1] * f
        P[k + 1, 0] = (-kk * qx + fk * w[k, 0]) * f
        P[k + 1, 1] = (-kk * qy + fk * w[k, 1]) * f
    return D


@njit(cache=True, inline="always")
def _spring_order(k, c2, w2, kk, fk, w, Z, P, Q):
    """``Z_k``, ``P_k`` from order ``k − 1`` (its ``w_{k−1}`` known) and ``Q_k = c2 P_k + w2 Z_k``
    (the sliding phase's spring recurrences)."""
    f = _INV[k]
    Z[k, 0] = P[k - 1, 0] * f
    Z[k, 1] = P[k - 1, 1] * f
    P[k, 0] = (-kk * Q[k - 1, 0] + fk * w[k - 1, 0]) * f
    P[k, 1] = (-kk * Q[k - 1, 1] + fk * w[k - 1, 1]) * f
    Q[k, 0] = c2 * P[k, 0] + w2 * Z[k, 0]
    Q[k, 1] = c2 * P[k, 1] + w2 * Z[k, 1]


@njit(cache=True, _nrt=False)
def start_series(ax, ay, K, st, m, fk, c2, w2, r, kk, D, y, rho, w, Z, P, Q, E):
    """Taylor coefficients of a slip phase of the base from rest, ``V = τ^m Σ_k y_k τ^k``
    (``rho`` of ``|y|``, ``w = y/|y|``) and the spring's ``Z``, ``P`` (``Q`` their ``q``, ``E`` the
    drive ``e = a − q/r``), to degree ``D``: the recurrences of
    :func:`floorslide.numerics.friction_series.start_series` (``m = 1``: ``|e₀| > fk``; ``m = 2``:
    ``|e₀| = fk`` and ``|e|`` rising) with the drive's order ``j`` formed as soon as ``w_{j−1}``
    is known. Returns ``D``, or −1 when the start is degenerate (``ρ₀ ≤ 0``)."""
    ir = 1.0 / r
    for k in range(D + 2):
        y[k, 0] = 0.0
        y[k, 1] = 0.0
        rho[k] = 0.0
        w[k, 0] = 0.0
        w[k, 1] = 0.0
    Z[0, 0] = st[ZX]
    Z[0, 1] = st[ZY]
    P[0, 0] = st[PX]
    P[0, 1] = st[PY]
    Q[0, 0] = c2 * P[0, 0] + w2 * Z[0, 0]
    Q[0, 1] = c2 * P[0, 1] + w2 * Z[0, 1]
    E[0, 0] = ax[0] - Q[0, 0] * ir
    E[0, 1] = ay[0] - Q[0, 1] * ir
    n0 = np.hypot(E[0, 0], E[0, 1])
    if not n0 > 0.0:
        return -1
    w0x = -E[0, 0] / n0
    w0y = -E[0, 1] / n0
    w[0, 0] = w0x
    w[0, 1] = w0y
    if m == 1:
        rho[0] = n0 - fk
        if not rho[0] > 0.0:
            return -1
        y[0, 0] = rho[0] * w0x
        y[0, 1] = rho[0] * w0y
        for k in range(1, D + 1):
            _spring_order(k, c2, w2, kk, fk, w, Z, P, Q)
            ex = (ax[k] if k <= K else 0.0) - Q[k, 0] * ir
            ey = (ay[k] if k <= K else 0.0) - Q[k, 1] * ir
            rk = 0.0
            for j in range(1, k):
                rk += y[j, 0] * y[k - j, 0] + y[j, 1] * y[k - j, 1] - rho[j] * rho[k - j]
            rk /= 2.0 * rho[0]
            sx, sy = 0.0, 0.0
            for j in range(1, k):
                sx += rho[j] * w[k - j, 0]
                sy += rho[j] * w[k - j, 1]
            hx = -ex + fk * (rk * w0x + sx) / rho[0]
            hy = -ey + fk * (rk * w0y + sy) / rho[0]
            par = (hx * w0x + hy * w0y) / (k + 1)
            px, py = hx - (hx * w0x + hy * w0y) * w0x, hy - (hx * w0x + hy * w0y) * w0y
            f = 1.0 / (k + 1 + fk / rho[0])
            y[k, 0] = par * w0x + px * f
            y[k, 1] = par * w0y + py * f
            rho[k] = w0x * y[k, 0] + w0y * y[k, 1] + rk
            w[k, 0] = (y[k, 0] - rho[k] * w0x - sx) / rho[0]
            w[k, 1] = (y[k, 1] - rho[k] * w0y - sy) / rho[0]
        _spring_order(D + 1, c2, w2, kk, fk, w, Z, P, Q)
        return D
    # m == 2: y₀ = ρ₀ w₀ with ρ₀ = −½ ė₀·w₀; order k fixes y_{k−1} along w₀ and y_k across it
    _spring_order(1, c2, w2, kk, fk, w, Z, P, Q)
    a1x = (ax[1] if K >= 1 else 0.0) - Q[1, 0] * ir
    a1y = (ay[1] if K >= 1 else 0.0) - Q[1, 1] * ir
    rho[0] = -0.5 * (a1x * w0x + a1y * w0y)
    if not rho[0] > 0.0:
        return -1
    y[0, 0] = rho[0] * w0x
    y[0, 1] = rho[0] * w0y
    d = a1x * w0x + a1y * w0y
    y[1, 0] = -rho[0] * (a1x - d * w0x) / fk
    y[1, 1] = -rho[0] * (a1y - d * w0y) / fk
    for k in range(2, D + 2):
        rk1 = 0.0
        for j in range(1, k - 1):
            rk1 += y[j, 0] * y[k - 1 - j, 0] + y[j, 1] * y[k - 1 - j, 1] - rho[j] * rho[k - 1 - j]
        rk1 /= 2.0 * rho[0]
        dpar = y[k - 1, 0] * w0x + y[k - 1, 1] * w0y
        rho[k - 1] = dpar + rk1
        sx, sy = 0.0, 0.0
        for j in range(1, k - 1):
            sx += rho[j] * w[k - 1 - j, 0]
            sy += rho[j] * w[k - 1 - j, 1]
        w[k - 1, 0] = (y[k - 1, 0] - dpar * w0x - rk1 * w0x - sx) / rho[0]
        w[k - 1, 1] = (y[k - 1, 1] - dpar * w0y - rk1 * w0y - sy) / rho[0]
        # the drive's order k, now that w_{k−1} is known
        _spring_order(k, c2, w2, kk, fk, w, Z, P, Q)
        ex = (ax[k] if k <= K else 0.0) - Q[k, 0] * ir
        ey = (ay[k] if k <= K else 0.0) - Q[k, 1] * ir
        rk = 0.0
        for j in range(1, k):
            rk += y[j, 0] * y[k - j, 0] + y[j, 1] * y[k - j, 1] - rho[j] * rho[k - j]
        rk /= 2.0 * rho[0]
        sx, sy = 0.0, 0.0
        for j in range(1, k):
            sx += rho[j] * w[k - j, 0]
            sy += rho[j] * w[k - j, 1]
        wk_par = (-rk - (sx * w0x + sy * w0y)) / rho[0]
        ypar = (-(ex * w0x + ey * w0y) - fk * wk_par) / (k + 1)
        perp_x = y[k - 1, 0] - dpar * w0x
        perp_y = y[k - 1, 1] - dpar * w0y
        y[k - 1, 0] = perp_x + ypar * w0x
        y[k - 1, 1] = perp_y + ypar * w0y
        rho[k - 1] = ypar + rk1
        if k > D:
            break
        sx, sy = 0.0, 0.0
        for j in range(1, k):
            sx += rho[j] * w[k - j, 0]
            sy += rho[j] * w[k - j, 1]
        spar = sx * w0x + sy * w0y
        dax = ex - (ex * w0x + ey * w0y) * w0x
        day = ey - (ex * w0x + ey * w0y) * w0y
        y[k, 0] = (sx - spar * w0x) + rho[0] / fk * (-dax - (k + 1) * perp_x)
        y[k, 1] = (sy - spar * w0y) + rho[0] / fk * (-day - (k + 1) * perp_y)
    # ρ_D (for the stop search) and w_D are not needed beyond: ρ_D was set at k = D + 1
    return D


@njit(cache=True, _nrt=False)
def _vec_peak(C, deg, tend, peak, q, work):
    """``max(peak, max |c(τ)|)`` on ``[0, tend]`` for the vector polynomial ``C[0..deg]``
    (``(deg+1, 2)``): nothing to do when ``|c₀| + Σ_{k≥1} (|c_k,x| + |c_k,y|) tend^k ≤ peak``,
    else the maximum of ``|c|²`` by :func:`~floorslide.numerics.polynomial.max_abs_on`."""
    s = 0.0
    for k in range(deg, 0, -1):
        s = (s + abs(C[k, 0]) + abs(C[k, 1])) * tend
    if np.hypot(C[0, 0], C[0, 1]) + s <= peak:
        return peak
    n = 2 * deg
    for j in range(n + 1):
        q[j] = 0.0
    for i in range(deg + 1):
        for j in range(deg + 1):
            q[i + j] += C[i, 0] * C[j, 0] + C[i, 1] * C[j, 1]
    v2, _ = max_abs_on(q, n, tend, peak * peak, work)
    if v2 > peak * peak:
        return np.sqrt(v2)
    return peak


@njit(cache=True, inline="always")
def _horner2(C, deg, t):
    """The vector polynomial ``C[0..deg]`` at ``t``."""
    x = 0.0
    yv = 0.0
    for k in range(deg, -1, -1):
        x = x * t + C[k, 0]
        yv = yv * t + C[k, 1]
    return x, yv


@njit(cache=True, _nrt=False)
def _finish_spring(st, Z, P, Q, deg, tend, c2, w2, q, work):
    """Peaks of ``|Z|`` and ``|q|`` on ``[0, tend]`` and the spring's state at ``tend``."""
    for k in range(deg + 1):
        Q[k, 0] = c2 * P[k, 0] + w2 * Z[k, 0]
        Q[k, 1] = c2 * P[k, 1] + w2 * Z[k, 1]
    st[PEAK_Z] = _vec_peak(Z, deg, tend, st[PEAK_Z], q, work)
    st[PEAK_TOP] = _vec_peak(Q, deg, tend, st[PEAK_TOP], q, work)
    st[ZX], st[ZY] = _horner2(Z, deg, tend)
    st[PX], st[PY] = _horner2(P, deg, tend)


@njit(cache=True, _nrt=False)
def oscillator_substep(st, ax0, ay0, K, h, t0, g, mub, muk, w0, xi, r, D, ax, ay, y, rho, w, Z,
                       P, Q, E, q, ux, uy, zero, work, max_events, jump):  # fmt: skip
    """Advance one oscillator through a segment of length ``h`` from time ``t0``, the floor's
    acceleration there ``(ax0, ay0)`` (coefficients, degree ``K``). ``jump``: the breakaway
    level's margin for a stuck base at the segment's start (0 at the record's start,
    :data:`JUMP_TOL` elsewhere). False when a limit was reached."""
    c2 = 2.0 * xi * w0
    w2 = w0 * w0
    kk = 1.0 + 1.0 / r
    level = mub * (1.0 + r) * g
    fk = muk * (1.0 + r) * g / r
    s0 = 0.0
    fresh = False
    events = 0
    steps = 0
    first = True
    while s0 < h:
        L = h - s0
        lo = EVENT_GAP * h if fresh else 0.0
        if s0 > 0.0:
            taylor_shift(ax0, K, s0, ax)
            taylor_shift(ay0, K, s0, ay)
        else:
            for j in range(K + 1):
                ax[j] = ax0[j]
                ay[j] = ay0[j]
        if st[MODE] == 0.0:
            # stuck: the spring driven by the floor; the first rise of |F|² above level²
            stick_series(ax, ay, K, st, c2, w2, D, Z, P)
            H = min(_step_size(P, D, L), _step_size(Z, D, L))
            for k in range(D + 1):
                akx = ax[k] if k <= K else 0.0
                aky = ay[k] if k <= K else 0.0
                E[k, 0] = r * akx - c2 * P[k, 0] - w2 * Z[k, 0]
                E[k, 1] = r * aky - c2 * P[k, 1] - w2 * Z[k, 1]
            f0 = np.hypot(E[0, 0], E[0, 1])
            tb = -1.0
            if first and f0 > level * (1.0 + jump):
                tb = 0.0  # beyond the level at the start (a jump, or the record's start)
            else:
                s = 0.0
                for k in range(D, 0, -1):
                    s = (s + abs(E[k, 0]) + abs(E[k, 1])) * H
                if f0 + s > level:
                    for j in range(2 * D + 1):
                        q[j] = 0.0
                    for i in range(D + 1):
                        for j in range(D + 1):
                            q[i + j] += E[i, 0] * E[j, 0] + E[i, 1] * E[j, 1]
                    tb = rise_within(q, 2 * D, lo, H, level * level, work)
            first = False
            tend = tb if tb >= 0.0 else H
            if tend > 0.0:
                _finish_spring(st, Z, P, Q, D, tend, c2, w2, q, work)
            s0 += tend
            if tb >= 0.0:
                st[MODE] = 1.0
                st[SLIPS] += 1.0
                st[VX] = 0.0
                st[VY] = 0.0
                # m = 2 at a crossing of the level with mu_s = mu_k (|e₀| = fk), else m = 1
                st[START] = 2.0 if mub == muk and not (tb == 0.0 and f0 > level) else 1.0
                fresh = True
                events += 1
                if events > max_events:
                    return False
            else:
                steps += 1
                if steps > MAX_STEPS:
                    return False
                fresh = False
            continue
        first = False
        m = int(st[START])
        De = -1
        stop_now = False
        if m == 0:
            r0 = np.hypot(st[VX], st[VY])
            e0 = np.hypot(ax[0] - (c2 * st[PX] + w2 * st[ZX]) / r,
                          ay[0] - (c2 * st[PY] + w2 * st[ZY]) / r)  # fmt: skip
            if r0 <= STOP_SPEED * (e0 + fk) * h:
                stop_now = True  # the speed within rounding of zero: a stop here
            else:
                De = moving_series(ax, ay, K, st, r0, fk, c2, w2, r, kk, D, y, rho, w, Z, P)
        else:
            De = start_series(ax, ay, K, st, m, fk, c2, w2, r, kk, D, y, rho, w, Z, P, Q, E)
            if De == -1:
                # a degenerate start (the drive exactly at the kinetic level and not rising):
                # no slip — the base stays at rest here
                st[MODE] = 0.0
                st[VX] = 0.0
                st[VY] = 0.0
                st[START] = 0.0
                fresh = True
                events += 1
                if events > max_events:
                    return False
                continue
        ts = -1.0
        if not stop_now:
            H = min(_step_size(y, De, L), _step_size(P, De, L), _step_size(Z, De, L))
            ts = _speed_root(rho, De, 0.0, H, q, work)
            tend = ts if ts >= 0.0 else H
            _advance(st, y, rho, De, m, tend, zero, zero, 0, t0 + s0, ux, uy, q, work, 0.0, 0.0)
            _finish_spring(st, Z, P, Q, De, tend, c2, w2, q, work)
            st[SLIDE_TIME] += tend
            s0 += tend
        if stop_now or ts >= 0.0:
            # a stop: the base sticks if the friction it needs is within the breakaway level,
            # else it slides on at once from rest (a reversal in 1-D)
            st[VX] = 0.0
            st[VY] = 0.0
            st[STOPS] += 1.0
            ex = r * _poly1(ax0, K, s0) - c2 * st[PX] - w2 * st[ZX]
            ey = r * _poly1(ay0, K, s0) - c2 * st[PY] - w2 * st[ZY]
            if ex * ex + ey * ey <= level * level:
                st[MODE] = 0.0
                st[START] = 0.0
            else:
                st[START] = 1.0
                st[SLIPS] += 1.0
            fresh = True
            events += 1
            if events > max_events:
                return False
        else:
            steps += 1
            if steps > MAX_STEPS:
                return False
            st[START] = 0.0
            fresh = False
    return True


@njit(cache=True, inline="always")
def _poly1(c, K, t):
    """``Σ_j c_j t^j`` (Horner)."""
    v = 0.0
    for j in range(K, -1, -1):
        v = v * t + c[j]
    return v


@njit(cache=True)
def plane_oscillator_kernel(t0, length, step, ends, coef, f, first, g, MU, w0, xi, r, states,
                            hist, want_hist, D, max_events):  # fmt: skip
    """Advance 2-DOF oscillators in the plane through one chunk of segments of floor row `f`.

    ``t0, length, step, ends, coef``: the chunk's arrays
    (:class:`~floorslide.building.poly_segments.PolySegments`). ``first``: the chunk starts the
    record. ``MU = [mu_b; mu_k]`` per oscillator; ``w0, xi, r`` the clamped-base circular
    frequency, damping ratio and mass ratio; ``states`` ``(n, NCOL)`` in/out;
    ``hist[i, k] = (u_x, u_y, z_x, z_y)`` at the samples when ``want_hist``; ``D`` the series'
    least degree."""
    KM = coef.shape[3] - 1
    DM = max(D, KM + 2)
    work = scratch(2 * (DM + 2) + 2)
    c1 = np.zeros(KM + 1)
    c2 = np.zeros(KM + 1)
    ax = np.zeros(KM + 1)
    ay = np.zeros(KM + 1)
    y = np.zeros((DM + 3, 2))
    rho = np.zeros(DM + 3)
    w = np.zeros((DM + 3, 2))
    Z = np.zeros((DM + 3, 2))
    P = np.zeros((DM + 3, 2))
    Q = np.zeros((DM + 3, 2))
    E = np.zeros((DM + 3, 2))
    q = np.zeros(2 * (DM + 3) + KM + 4)
    ux = np.zeros(DM + 5)
    uy = np.zeros(DM + 5)
    zero = np.zeros(2)
    _segments(t0, length, step, ends, coef, f, first, g, MU, w0, xi, r, states, hist, want_hist,
              D, max_events, c1, c2, ax, ay, y, rho, w, Z, P, Q, E, q, ux, uy, zero,
              work)  # fmt: skip


@njit(cache=True, _nrt=False)
def _segments(t0, length, step, ends, coef, f, first, g, MU, w0, xi, r, states, hist, want_hist,
              D, max_events, c1, c2, ax, ay, y, rho, w, Z, P, Q, E, q, ux, uy, zero,
              work):  # fmt: skip
    """The loops of :func:`plane_oscillator_kernel` over segments and oscillators."""
    nobj = MU.shape[1]
    KM = coef.shape[3] - 1
    if first and want_hist:
        for i in range(nobj):
            hist[i, 0, 0] = states[i, UX]
            hist[i, 0, 1] = states[i, UY]
            hist[i, 0, 2] = states[i, ZX]
            hist[i, 0, 3] = states[i, ZY]
    for s in range(t0.size):
        K = 1
        for j in range(KM + 1):
            c1[j] = coef[s, f, 0, j]
            c2[j] = coef[s, f, 1, j]
            if j > K and (c1[j] != 0.0 or c2[j] != 0.0):
                K = j
        Ds = D if K + 2 <= D else K + 2
        jump = 0.0 if (first and s == 0) else JUMP_TOL
        for i in range(nobj):
            st = states[i]
            ok = oscillator_substep(st, c1, c2, K, length[s], t0[s], g, MU[0, i], MU[1, i], w0,
                                    xi, r, Ds, ax, ay, y, rho, w, Z, P, Q, E, q, ux, uy, zero,
                                    work, max_events, jump)  # fmt: skip
            if not ok and st[LIMIT_AT] < 0.0:
                st[LIMIT_AT] = t0[s]
        if want_hist and ends[s]:
            k = step[s] + 1
            for i in range(nobj):
                hist[i, k, 0] = states[i, UX]
                hist[i, k, 1] = states[i, UY]
                hist[i, k, 2] = states[i, ZX]
                hist[i, k, 3] = states[i, ZY]


__all__ = ["NCOL", "STEP_TOL", "plane_oscillator_kernel"]
