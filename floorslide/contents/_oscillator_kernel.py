"""Compiled event-driven kernel of the 2-DOF sliding oscillator (Westermo & Udwadia 1983;
Brochard & Gantenbein 1989).

Per unit top mass: a top mass on a spring (circular frequency ``w``, damping ratio ``xi``) over a
base of mass ratio ``r = m_base/m_top`` that slides on its floor with Coulomb friction under the
normal force ``(1 + r)·g``. State ``y = [u, v, z, zd]``: base slide relative to the floor and its
velocity, spring deformation (top relative to base) and its rate.

Stick (``v = 0``): ``z'' = −a_f − 2ξw z' − w² z``; the friction force needed is
``F = r a_f − 2ξw z' − w² z`` (per unit top mass), admissible while ``|F| ≤ mu_s (1+r) g``.
Slip with sign ``s``: ``v' = −a_f + q/r − s mu_k (1+r) g / r`` and
``z'' = −q (1 + 1/r) + s mu_k (1+r) g / r`` with ``q = 2ξw z' + w² z``.

Inside each sub-step the state is the Taylor polynomial of the exact solution of the linear
system of the current phase, driven by the floor's Taylor polynomial; events (breakaway, stop,
reversal) are roots of polynomials; no penalty stiffness anywhere.
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import (
    poly_der,
    poly_val,
    substep_inputs,
    taylor_coefficients,
)
from floorslide.numerics.polynomial import first_rise, max_abs_above, scratch

# columns of an oscillator's state, shared by the kernel and its wrapper (``contents.oscillator``)
O_MODE = 0
"""Phase: 0 stick, ±1 slip with that sign of the base's relative velocity (a float)."""
O_U, O_V, O_Z, O_ZD = 1, 2, 3, 4
"""Base slide and its velocity, spring deformation and its rate."""
O_PEAK_U, O_PEAK_Z, O_PEAK_TOP, O_PEAK_BASE = 5, 6, 7, 8
"""Peaks of |u|, |z|, and of the top and base absolute accelerations."""
O_SLIDE_TIME, O_SLIPS, O_LIMIT_AT = 9, 10, 11
"""Time spent sliding, slip phases, start of the first sub-step where the event limit was
reached (−1: never)."""
O_NCOL = 12


@njit(cache=True)
def _shift(c, K, tau, out):
    """Coefficients of ``p(tau + σ)`` in σ (Taylor shift, Horner scheme)."""
    for j in range(K + 1):
        out[j] = c[j]
    for i in range(K):
        for j in range(K - 1, i - 1, -1):
            out[j] += tau * out[j + 1]


@njit(cache=True)
def _phase_series(y, mode, cs, K, w, xi, r, fk, start, Y):
    """Taylor coefficients ``Y[4, K+1]`` of the state in the current phase, driven by the floor
    acceleration polynomial ``cs`` (local time).

    A slip phase that `start`s from rest at a breakaway has ``v'(0) = 0`` exactly when the
    friction force sits at its limit; rounding must not give ``v'(0)`` the sign opposite to the
    slip, which would stop it at once and chatter (Zeno) — such a slope is set to 0.
    """
    for i in range(4):
        Y[i, 0] = y[i]
    c2 = 2.0 * xi * w
    w2 = w * w
    for j in range(K):
        v, z, zd = Y[1, j], Y[2, j], Y[3, j]
        q = c2 * zd + w2 * z
        const = 1.0 if j == 0 else 0.0
        if mode == 0:
            du = 0.0
            dv = 0.0
            dzd = -cs[j] - q
        else:
            s = float(mode)
            du = v
            dv = -cs[j] + q / r - const * s * fk * (1.0 + r) / r
            dzd = -q * (1.0 + 1.0 / r) + const * s * fk * (1.0 + r) / r
            if start and j == 0 and s * dv < 0.0:
                dv = 0.0
        Y[0, j + 1] = du / (j + 1)
        Y[1, j + 1] = dv / (j + 1)
        Y[2, j + 1] = zd / (j + 1)
        Y[3, j + 1] = dzd / (j + 1)


@njit(cache=True)
def _update_peak(poly, K, lo, hi, peaks, idx, work):
    """``peaks[idx] = max(peaks[idx], max |poly| on [lo, hi])`` (rigorous, every critical
    point)."""
    m, _ = max_abs_above(poly, K, lo, hi, peaks[idx], work)
    if m > peaks[idx]:
        peaks[idx] = m


SETTLE_STEPS = 16
"""Most machine numbers :func:`monotone_rise` steps through to settle a root."""


@njit(cache=True)
def monotone_rise(c, K, hi, work):
    """:func:`~floorslide.numerics.polynomial.first_rise` of ``p = Σ c_j τ^j`` above 0 on
    ``(0, hi]``, by Newton's method when ``p`` is certified increasing.

    When ``p(0) < 0`` and ``p' > 0`` on ``[0, hi]`` — by the chord bound
    ``min p' ≥ min(p'(0), p'(hi)) − hi²/8 · Σ_{j≥3} j(j−1)(j−2)|c_j| hi^{j−3}`` — ``p`` has at
    most one root there, a rise: none if ``p(hi)`` is certified ``≤ 0`` (its Horner rounding
    bound, Higham 2002 §5.1), else it is found by Newton's method safeguarded by bisection and
    settled on the smallest machine number with ``p > 0`` (the one after it ``≤ 0``), as root
    isolation settles it where the evaluated ``p`` is monotone. Any other case (a start at or
    above 0, no certified slope, a root within rounding of ``hi``, a root that does not settle
    within :data:`SETTLE_STEPS` machine numbers) goes to ``first_rise``. The events of a
    2-DOF oscillator (a stop, a breakaway) are simple roots crossed at a certified slope
    nearly always: one Newton solve instead of root isolation's Bernstein subdivision.
    """
    p0 = c[0]
    if not p0 < 0.0:
        return first_rise(c, K, 0.0, hi, 0.0, work)
    # first_rise's own quick rejection, operation for operation: p ≤ 0 on [0, hi]
    span = 0.0
    hj = 1.0
    for j in range(1, K + 1):
        hj *= hi
        span += abs(c[j]) * hj
    if p0 + span <= 0.0:
        return -1.0
    m3 = 0.0
    for j in range(K, 2, -1):
        m3 = m3 * hi + j * (j - 1) * (j - 2) * abs(c[j])
    d0 = c[1]
    d1 = poly_der(c, K, hi)
    if not min(d0, d1) - 0.125 * hi * hi * m3 > 0.0:
        return first_rise(c, K, 0.0, hi, 0.0, work)
    p1 = poly_val(c, K, hi)
    err = 4.0 * (K + 1) * 1.12e-16 * (abs(p0) + span) + 1e-300
    if p1 < -err:
        return -1.0
    if not p1 > err:
        return first_rise(c, K, 0.0, hi, 0.0, work)
    lo = 0.0
    up = hi
    x = hi * (-p0 / (p1 - p0))
    if not 0.0 < x < hi:
        x = 0.5 * hi
    for _ in range(100):
        f = poly_val(c, K, x)
        if f > 0.0:
            up = x
        else:
            lo = x
        xn = x - f / poly_der(c, K, x)
        if abs(xn - x) <= 4.0 * (np.nextafter(x, np.inf) - x):
            x = xn  # converged to a few machine numbers: settled below
            break
        if not lo < xn < up:
            xn = 0.5 * (lo + up)
        if xn <= lo or xn >= up:
            break
        x = xn
    # settle: p(x) > 0 and p(x⁻) ≤ 0, x⁻ the machine number before x
    x = min(max(x, np.nextafter(0.0, 1.0)), hi)
    for _ in range(SETTLE_STEPS):
        if not poly_val(c, K, x) > 0.0:
            if x >= hi:
                break
            x = np.nextafter(x, np.inf)
            continue
        xp = np.nextafter(x, -np.inf)
        if xp > 0.0 and poly_val(c, K, xp) > 0.0:
            x = xp
            continue
        return x
    return first_rise(c, K, 0.0, hi, 0.0, work)


@njit(cache=True)
def _advance_part(c, K, base, ho, o, w, xi, r, g, mub, muk, states, t_part, max_events, cs, Y,
                  poly, y, pk, work):  # fmt: skip
    """Advance oscillator ``o`` through one part ``[base, base + ho]`` of a piece on which the
    floor's absolute acceleration is the polynomial ``c`` (degree ``K``, origin at the piece's
    start), by events: the phase's Taylor series, breakaway, stop and reversal as first
    crossings (by root isolation), peaks inside. ``t_part``: the part's start in the record
    (for the event limit). Shared by :func:`oscillator_kernel` and the nonlinear-isolation
    kernel (:func:`event_part` with root isolation throughout)."""
    return event_part(c, K, base, ho, o, w, xi, r, g, mub, muk, states, t_part, max_events, cs,
                      Y, poly, y, pk, work, False)  # fmt: skip


@njit(cache=True)
def event_part(c, K, base, ho, o, w, xi, r, g, mub, muk, states, t_part, max_events, cs, Y,
               poly, y, pk, work, newton):  # fmt: skip
    """:func:`_advance_part`; with ``newton``, each event is first sought by
    :func:`monotone_rise` (the batched kernel, :mod:`floorslide.contents._oscillator_batch`)."""
    c2 = 2.0 * xi * w
    w2 = w * w
    mode = int(states[o, O_MODE])
    for i in range(4):
        y[i] = states[o, O_U + i]
    for i in range(4):
        pk[i] = states[o, O_PEAK_U + i]
    fb = mub[o] * (1.0 + r) * g
    fk = muk[o]
    tau = 0.0
    guard = 0
    start = False
    while tau < ho:
        if guard >= max_events:
            if states[o, O_LIMIT_AT] < 0.0:
                states[o, O_LIMIT_AT] = t_part
            break
        guard += 1
        _shift(c, K, base + tau, cs)
        _phase_series(y, mode, cs, K, w, xi, r, fk * g, start, Y)
        start = False
        span = ho - tau
        t_ev = -1.0
        new_mode = mode
        if mode == 0:
            # F(σ) = r a_f − 2ξw z' − w² z; beyond ±fb already when the stick phase
            # begins (a record that starts mid-motion): the base moves at once
            f_now = r * cs[0] - c2 * Y[3, 0] - w2 * Y[2, 0]
            t_up = -1.0
            t_lo = -1.0
            if f_now > fb:
                t_up = 0.0
            elif f_now < -fb:
                t_lo = 0.0
            else:
                for j in range(K + 1):
                    poly[j] = r * cs[j] - c2 * Y[3, j] - w2 * Y[2, j]
                poly[0] -= fb
                if newton:
                    t_up = monotone_rise(poly, K, span, work)
                else:
                    t_up = first_rise(poly, K, 0.0, span, 0.0, work)
                for j in range(K + 1):
                    poly[j] = -(r * cs[j] - c2 * Y[3, j] - w2 * Y[2, j])
                poly[0] -= fb
                if newton:
                    t_lo = monotone_rise(poly, K, span, work)
                else:
                    t_lo = first_rise(poly, K, 0.0, span, 0.0, work)
            if t_up >= 0.0 and (t_lo < 0.0 or t_up <= t_lo):
                t_ev, new_mode = t_up, -1
            elif t_lo >= 0.0:
                t_ev, new_mode = t_lo, 1
        else:
            sgn = float(mode)
            for j in range(K + 1):
                poly[j] = -sgn * Y[1, j]
            if newton:
                t_ev = monotone_rise(poly, K, span, work)
            else:
                t_ev = first_rise(poly, K, 0.0, span, 0.0, work)
        t_end = span if t_ev < 0.0 else t_ev
        # peaks on [0, t_end]
        for j in range(K + 1):
            poly[j] = Y[0, j]
        _update_peak(poly, K, 0.0, t_end, pk, 0, work)
        for j in range(K + 1):
            poly[j] = Y[2, j]
        _update_peak(poly, K, 0.0, t_end, pk, 1, work)
        for j in range(K + 1):
            poly[j] = -(c2 * Y[3, j] + w2 * Y[2, j])
        _update_peak(poly, K, 0.0, t_end, pk, 2, work)
        if mode == 0 and t_end > 0.0:
            for j in range(K + 1):
                poly[j] = cs[j]
            _update_peak(poly, K, 0.0, t_end, pk, 3, work)
        elif mode != 0:
            sgn = float(mode)
            for j in range(K + 1):
                poly[j] = (c2 * Y[3, j] + w2 * Y[2, j]) / r
            poly[0] -= sgn * fk * g * (1.0 + r) / r
            _update_peak(poly, K, 0.0, t_end, pk, 3, work)
            states[o, O_SLIDE_TIME] += t_end
        for i in range(4):
            y[i] = poly_val(Y[i], K, t_end)
        tau += t_end
        if t_ev < 0.0:
            break
        if mode != 0:
            y[1] = 0.0
            # stop: stick, or reverse at once if friction cannot hold the base
            fnow = r * poly_val(cs, K, t_end) - c2 * y[3] - w2 * y[2]
            if fnow > fb:
                new_mode = -1
            elif fnow < -fb:
                new_mode = 1
            else:
                new_mode = 0
        else:
            y[1] = 0.0
        if new_mode != 0:
            states[o, O_SLIPS] += 1
            start = True
        mode = new_mode
    states[o, O_MODE] = mode
    for i in range(4):
        states[o, O_U + i] = y[i]
    for i in range(4):
        states[o, O_PEAK_U + i] = pk[i]
    return mode


@njit(cache=True)
def oscillator_kernel(
    X,
    k0,
    R,
    beta,
    acc,
    substeps,
    h,
    m_o,
    K,
    w,
    xi,
    r,
    g,
    mub,
    muk,
    states,
    hist,
    want_hist,
    max_events,
):
    """Advance 2-DOF sliding oscillators (one per friction pair) through the record.

    ``X, k0``: one chunk of the floor motion's building states from record step ``k0``
    (:meth:`floorslide.building.exact_motion.FloorMotion.chunks`, on its sub-steps of length
    ``h``, ``substeps`` per record step; no columns on the ground), whose Taylor rows ``R,
    beta`` give the floor acceleration polynomial on each sub-step. Each sub-step is split into
    ``m_o`` equal parts on which the oscillator's phases have ``ρ·h/m_o ≤ 0.5``; the floor
    polynomial is shifted to each part (it equals the floor motion on the whole sub-step). ``K``:
    Taylor degree of the phase series (at least the floor's). ``states[i]``: columns
    :data:`O_MODE` … :data:`O_LIMIT_AT`, carried from chunk to chunk; ``hist[i, k]`` = [u, z,
    a_top, a_base] at the samples when ``want_hist``.
    """
    nobj = muk.size
    nsteps = (X.shape[0] - 1) // substeps
    ho = h / m_o
    c = np.zeros(K + 1)
    cs = np.zeros(K + 1)
    Y = np.zeros((4, K + 1))
    poly = np.zeros(K + 1)
    y = np.zeros(4)
    pk = np.zeros(4)
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
                for o in range(nobj):
                    t_part = (k * substeps + sub) * h + base
                    mode = _advance_part(c, K, base, ho, o, w, xi, r, g, mub, muk, states,
                                         t_part, max_events, cs, Y, poly, y, pk, work)  # fmt: skip
                    fk = muk[o]
                    if want_hist and sub == substeps - 1 and so == m_o - 1:
                        af_end = poly_val(c, K, h)
                        q_ = c2 * y[3] + w2 * y[2]
                        hist[o, k + 1, 0] = y[0]
                        hist[o, k + 1, 1] = y[2]
                        hist[o, k + 1, 2] = -q_
                        if mode == 0:
                            hist[o, k + 1, 3] = af_end
                        else:
                            hist[o, k + 1, 3] = q_ / r - float(mode) * fk * g * (1.0 + r) / r
