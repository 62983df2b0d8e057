"""Compiled event-driven kernel of rigid blocks sliding with Coulomb friction on one floor.

One loop over (sub-)steps reads the floor's exact state (one chunk of a
:class:`~floorslide.building.exact_motion.FloorMotion`, integrated once) and advances every object
on it. The floor's absolute acceleration inside a sub-step is the Taylor polynomial of the exact
response (:mod:`floorslide.building.exact`); on the ground it is the record's own linear segment
(a motion with no states). Per object and sub-step, cheap exact tests decide most cases (a
sticking block whose floor stays below its breakaway level; a slipping block whose relative
velocity provably keeps its sign); only the rest go through the event search on polynomials.

Object modes: 0 stick, +1 / −1 slip with relative velocity of that sign, 2 flight (lift-off:
no normal force, no friction).
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import (
    curvature_bound_at,
    curvature_tail_weights,
    poly_val,
    substep_inputs,
    taylor_coefficients,
)
from floorslide.numerics.polynomial import (
    curvature_bound,
    extreme_values,
    first_rise,
    max_abs_above,
    scratch,
)

STICK = 0
FLIGHT = 2

# columns of an object's state, shared by the kernel and its wrapper (``contents.sliding``)
MODE, VEL, DISP, PEAK_DISP, T_PEAK, SLIDE_TIME, SLIPS, PEAK_ACC, LIMIT_AT = range(9)
"""Mode (0 stick, ±1 slip, 2 flight; a float), relative velocity and slide, peak |slide| and
its time, time spent sliding, slip phases, peak absolute acceleration of the object, start of
the first sub-step where the event limit was reached (−1: never)."""
NCOL = 9


@njit(cache=True, inline="always")
def _dot_state(row, x):
    s = 0.0
    for j in range(x.size):
        s += row[j] * x[j]
    return s


@njit(cache=True, inline="always")
def _tighten(level, R, beta, x_prev, aa, slope, c, K, h, A0, A1, rw):
    """A tighter enclosure ``(amin, amax, level)`` of the floor acceleration on a sub-step than
    the one of ``level``: from 0, the curvature bound of its Taylor coefficients (computed into
    ``c``); from 1, its exact extremes (level 2)."""
    if level == 0:
        taylor_coefficients(R, beta, x_prev, aa, slope, c)
        dev = 0.125 * h * h * curvature_bound(c, K, h)
        if dev > 0.0:
            return min(A0, A1) - dev, max(A0, A1) + dev, 1
    amin, _, amax, _ = extreme_values(c, K, 0.0, h, rw)
    return min(amin, A0, A1), max(amax, A0, A1), 2


@njit(cache=True)
def _general(
    c,
    K,
    h,
    n0,
    sn,
    has_vert,
    g,
    mub,
    muk,
    allow_pos,
    allow_neg,
    t0,
    state,
    work,
    rw,
    max_events,
):
    """Advance one object through a sub-step by events, exactly.

    ``c`` holds the Taylor coefficients (degree ``K``) of the floor's absolute acceleration in
    the sub-step; the normal acceleration is ``n0 + sn·τ`` (``g`` without vertical motion).
    ``state``: one object's row (columns :data:`MODE` … :data:`LIMIT_AT`).
    ``work`` is scratch of length ≥ 4K + 16, ``rw`` that of the root isolation
    (:func:`floorslide.numerics.polynomial.scratch`).
    """
    mode = int(state[MODE])
    v = state[VEL]
    u = state[DISP]
    tau = 0.0
    if not has_vert:
        n0 = g
        sn = 0.0
    deg_v = K + 1
    deg_u = K + 2
    pa = work[0 : K + 1]
    pv = work[K + 1 : K + 3 + K]
    pu = work[2 * K + 3 : 3 * K + 6]
    guard = 0
    while tau < h:
        if guard >= max_events:
            if state[LIMIT_AT] < 0.0:
                state[LIMIT_AT] = t0
            break
        guard += 1
        # normal-force interval [tau, tau_end]
        tau_end = h
        if has_vert and sn != 0.0:
            tz = -n0 / sn
            if tau < tz < h:
                tau_end = tz
        n_mid = n0 + sn * 0.5 * (tau + tau_end)
        airborne = has_vert and n_mid <= 0.0
        if airborne:
            # flight: v' = -A, no friction, no events
            for j in range(deg_v + 1):
                pv[j] = 0.0
            for j in range(K + 1):
                pv[j + 1] = -c[j] / (j + 1)
            pv[0] = v - poly_val(pv, deg_v, tau)
            for j in range(deg_u + 1):
                pu[j] = 0.0
            for j in range(deg_v + 1):
                pu[j + 1] = pv[j] / (j + 1)
            # u(τ) = u + pu(τ) − pu(tau): the velocity may reverse in flight, so |u| can peak
            # inside it (every critical point, rigorous)
            pu[0] = u - poly_val(pu, deg_u, tau)
            m, tm = max_abs_above(pu, deg_u, tau, tau_end, state[PEAK_DISP], rw)
            if m > state[PEAK_DISP]:
                state[PEAK_DISP] = m
                state[T_PEAK] = t0 + (tm if tm >= 0.0 else tau_end)
            u = poly_val(pu, deg_u, tau_end)
            v = poly_val(pv, deg_v, tau_end)
            mode = FLIGHT
            tau = tau_end
            if abs(u) > state[PEAK_DISP]:
                state[PEAK_DISP] = abs(u)
                state[T_PEAK] = t0 + tau
            continue
        if mode == FLIGHT:
            if v > 0.0:
                mode = 1
                state[SLIPS] += 1
            elif v < 0.0:
                mode = -1
                state[SLIPS] += 1
            else:
                mode = STICK
        if mode == STICK:
            # a floor already beyond the breakaway level when a stick phase begins (a record
            # that starts mid-motion, t = 0) moves the block at once
            a_now = poly_val(c, K, tau)
            fb_now = mub * (n0 + sn * tau)
            if a_now > fb_now and allow_neg:
                mode = -1
                v = 0.0
                state[SLIPS] += 1
                continue
            if a_now < -fb_now and allow_pos:
                mode = 1
                v = 0.0
                state[SLIPS] += 1
                continue
            # first instant the floor acceleration leaves [-mub N, mub N] in an allowed way
            t_up = -1.0
            t_lo = -1.0
            if allow_neg:
                for j in range(K + 1):
                    pa[j] = c[j]
                pa[0] -= mub * n0
                if K >= 1:
                    pa[1] -= mub * sn
                t_up = first_rise(pa, K, tau, tau_end, 0.0, rw)
            if allow_pos:
                for j in range(K + 1):
                    pa[j] = -c[j]
                pa[0] -= mub * n0
                if K >= 1:
                    pa[1] -= mub * sn
                t_lo = first_rise(pa, K, tau, tau_end, 0.0, rw)
            t_ev = -1.0
            new_mode = STICK
            if t_up >= 0.0 and (t_lo < 0.0 or t_up <= t_lo):
                t_ev = t_up
                new_mode = -1
            elif t_lo >= 0.0:
                t_ev = t_lo
                new_mode = 1
            t_stop = tau_end if t_ev < 0.0 else t_ev
            # the object moves with its floor on [tau, t_stop]
            a_abs, _ = max_abs_above(c, K, tau, t_stop, state[PEAK_ACC], rw)
            # friction transmits at most mub·N (this only trims the rounding-level overshoot at
            # a breakaway and a floor already beyond breakaway at t = 0)
            a_abs = min(a_abs, mub * max(n0 + sn * tau, n0 + sn * t_stop))
            if a_abs > state[PEAK_ACC]:
                state[PEAK_ACC] = a_abs
            if t_ev < 0.0:
                tau = tau_end
            else:
                tau = t_ev
                mode = new_mode
                v = 0.0
                state[SLIPS] += 1
            continue
        # slipping in direction s
        s = float(mode)
        for j in range(deg_v + 1):
            pv[j] = 0.0
        for j in range(K + 1):
            pv[j + 1] = -c[j] / (j + 1)
        pv[1] -= s * muk * n0
        pv[2] -= s * muk * sn * 0.5
        pv[0] = v - poly_val(pv, deg_v, tau)
        # stop: first τ where -s·v(τ) rises above 0
        for j in range(deg_v + 1):
            pa_j = -s * pv[j]
            work[3 * K + 6 + j] = pa_j
        pstop = work[3 * K + 6 : 3 * K + 7 + deg_v]
        t_s = first_rise(pstop, deg_v, tau, tau_end, 0.0, rw)
        t_stop = tau_end if t_s < 0.0 else t_s
        for j in range(deg_u + 1):
            pu[j] = 0.0
        for j in range(deg_v + 1):
            pu[j + 1] = pv[j] / (j + 1)
        u = u + poly_val(pu, deg_u, t_stop) - poly_val(pu, deg_u, tau)
        fk = muk * max(n0 + sn * tau, n0 + sn * t_stop)
        if fk > state[PEAK_ACC]:
            state[PEAK_ACC] = fk
        state[SLIDE_TIME] += t_stop - tau
        if abs(u) > state[PEAK_DISP]:
            state[PEAK_DISP] = abs(u)
            state[T_PEAK] = t0 + t_stop
        if t_s < 0.0:
            v = poly_val(pv, deg_v, tau_end)
            tau = tau_end
            continue
        # the relative velocity reached zero: stick, or slip on the other way (Westermo &
        # Udwadia 1983) if the floor acceleration exceeds the breakaway level right now
        v = 0.0
        tau = t_s
        a_now = poly_val(c, K, tau)
        fb = mub * (n0 + sn * tau)
        if a_now > fb and allow_neg:
            mode = -1
            state[SLIPS] += 1
        elif a_now < -fb and allow_pos:
            mode = 1
            state[SLIPS] += 1
        else:
            mode = STICK
    state[MODE] = mode
    state[VEL] = v
    state[DISP] = u


@njit(cache=True, _nrt=False)
def objects_on_substep(R, beta, XW, MU, states, buf, rw, p, flags):
    """Advance rigid blocks on one floor through one sub-step of a linear building (or of one
    branch of a piecewise-linear one), exactly; returns the floor acceleration at its end.

    The floor's absolute acceleration on the sub-step is the output with Taylor rows ``R,
    beta`` of the building going from state ``x_prev`` to ``x`` (ground ``aa`` → ``ab``,
    ``slope``); ``WX, WA, WS`` its curvature-tail weights on ``h``
    (:func:`~floorslide.building._instep.curvature_tail_weights`). ``dV``, ``dD``: the changes
    of the floor's absolute velocity and of its displacement minus ``v_0·h`` over the sub-step
    (the integrals a sliding block needs); ``n0, sn, nmin, nmax, nint, nint2``: the normal
    acceleration ``n0 + sn·τ``, its extremes and its first and second integrals on the
    sub-step. Objects that provably stay stuck, or slide one way throughout, are advanced in
    closed form from a rigorous enclosure of the floor acceleration, tightened only when a
    decision needs it; every other one by the event-driven :func:`_general`.

    The arguments come packed, because a numba call whose arguments flatten to ~100 fields
    costs ~150 ns whatever it does (measured; four arrays and a few scalars: ~5 ns): ``XW`` =
    ``[x_prev, x, WX]``; ``MU`` = ``[mub, muk]`` (breakaway and kinetic friction, one column
    per object); ``buf`` scratch of length ≥ ``5K + 17 + NCOL`` (the Taylor coefficients, the
    event step's work, one state row); ``rw`` the root isolation's scratch; ``p`` =
    ``[aa, ab, slope, h, t0, WA, WS, dV, dD, n0, sn, nmin, nmax, nint, nint2, g]``; ``flags`` =
    ``[has_vert, allow_pos, allow_neg, max_events, i0, i1]``: the objects ``i0 … i1 − 1`` (the
    columns of ``MU``, the rows of ``states``) stand on this floor. :func:`slide_kernel` calls
    it on every sub-step, and so does the kernel of buildings on nonlinear isolation
    (:mod:`floorslide.building._nonlinear_kernel`) on every segment between the layer's events.
    Compiled without reference counting (no arrays are made here).
    """
    K = R.shape[0] - 1
    x_prev = XW[0]
    x = XW[1]
    WX = XW[2]
    mub = MU[0]
    muk = MU[1]
    aa, ab, slope, h, t0 = p[0], p[1], p[2], p[3], p[4]
    WA, WS, dV, dD = p[5], p[6], p[7], p[8]
    n0, sn, nmin, nmax, nint, nint2, g = p[9], p[10], p[11], p[12], p[13], p[14], p[15]
    has_vert = flags[0] != 0
    allow_pos = flags[1] != 0
    allow_neg = flags[2] != 0
    max_events = flags[3]
    c = buf[: K + 1]
    work = buf[K + 1 : 5 * K + 17]
    st = buf[5 * K + 17 : 5 * K + 17 + NCOL]
    # shared floor quantities of this sub-step: end values, and a rigorous enclosure
    # [amin, amax] of the floor acceleration on it, tightened only when a decision
    # needs it (level 0: curvature bound from the state, O(n); 1: from the Taylor
    # coefficients; 2: the exact extremes, every critical point)
    A0 = _dot_state(R[0], x_prev) + beta[0] * aa
    A1 = _dot_state(R[0], x) + beta[0] * ab
    dev = 0.125 * h * h * curvature_bound_at(R, beta, x_prev, aa, slope, h, WX, WA, WS)
    amin = min(A0, A1) - dev
    amax = max(A0, A1) + dev
    level = 0 if dev > 0.0 else 2
    have_c = False
    for i in range(flags[4], flags[5]):
        mode = states[i, MODE]
        if mode == 0.0 and nmin > 0.0:
            fb = mub[i] * nmin
            while True:
                ok = (amax <= fb or not allow_neg) and (amin >= -fb or not allow_pos)
                if ok or level == 2:
                    break
                amin, amax, level = _tighten(level, R, beta, x_prev, aa, slope, c, K, h, A0, A1, rw)
                have_c = True
            if ok:
                while max(amax, -amin) > states[i, PEAK_ACC] and level < 2:
                    amin, amax, level = _tighten(
                        level, R, beta, x_prev, aa, slope, c, K, h, A0, A1, rw
                    )
                    have_c = True
                ab_abs = max(amax, -amin)
                if ab_abs > states[i, PEAK_ACC]:
                    states[i, PEAK_ACC] = ab_abs
                continue
        elif (mode == 1.0 or mode == -1.0) and nmin > 0.0:
            sgn = mode
            v = states[i, VEL]
            v_end = v - dV - sgn * muk[i] * nint
            fk = muk[i] * nmin
            if sgn * v_end > 0.0:
                while True:
                    monotone = (amin > -fk) if sgn > 0.0 else (amax < fk)
                    if monotone or level == 2:
                        break
                    amin, amax, level = _tighten(
                        level, R, beta, x_prev, aa, slope, c, K, h, A0, A1, rw
                    )
                    have_c = True
                if monotone:
                    u = states[i, DISP] + v * h - dD - sgn * muk[i] * nint2
                    states[i, VEL] = v_end
                    states[i, DISP] = u
                    states[i, SLIDE_TIME] += h
                    if abs(u) > states[i, PEAK_DISP]:
                        states[i, PEAK_DISP] = abs(u)
                        states[i, T_PEAK] = t0 + h
                    if muk[i] * nmax > states[i, PEAK_ACC]:
                        states[i, PEAK_ACC] = muk[i] * nmax
                    continue
        if not have_c:
            taylor_coefficients(R, beta, x_prev, aa, slope, c)
            have_c = True
        for j in range(NCOL):
            st[j] = states[i, j]
        _general(
            c,
            K,
            h,
            n0,
            sn,
            has_vert,
            g,
            mub[i],
            muk[i],
            allow_pos,
            allow_neg,
            t0,
            st,
            work,
            rw,
            max_events,
        )
        for j in range(NCOL):
            states[i, j] = st[j]
    return A1


@njit(cache=True)
def slide_kernel(
    X,
    k0,
    R,
    beta,
    rv,
    rd,
    acc,
    vert,
    has_vert,
    substeps,
    h,
    g,
    mub,
    muk,
    allow_pos,
    allow_neg,
    states,
    hist_u,
    hist_v,
    hist_a,
    want_hist,
    liftoff,
    max_events,
):
    """Rigid blocks on one floor, exact for the piecewise-linear ground record.

    Parameters
    ----------
    X, k0
        One chunk of the floor motion's building states from record step ``k0``
        (:meth:`floorslide.building.exact_motion.FloorMotion.chunks`: ``X[(k − k0)·substeps + r]``
        at the start of sub-step ``r`` of step ``k``; no columns on the ground). The kernel
        advances the objects through the chunk's steps; called chunk after chunk, it carries
        everything in ``states`` and ``liftoff``.
    R, beta
        Taylor rows of the floor's absolute acceleration (``(K+1, n)``, ``(K+1,)``).
    rv, rd
        Rows of the floor's velocity and displacement relative to the ground.
    acc
        Ground acceleration samples, m/s².
    vert
        Vertical ground acceleration samples (used when ``has_vert``), m/s².
    substeps, h
        Sub-steps per record step and their length, s.
    g
        Gravity, m/s².
    mub, muk
        Breakaway ``max(mu_s, mu_k)`` and kinetic friction coefficients, one per object.
    allow_pos, allow_neg
        Whether slip with positive / negative relative velocity is allowed.
    states
        ``(n_obj, NCOL)`` in/out, columns :data:`MODE` … :data:`LIMIT_AT` (a reached event
        limit is reported by the caller).
    hist_u, hist_v, hist_a
        ``(n_obj, npts)`` histories at the samples when ``want_hist``.
    liftoff
        ``[lift-off time, number of lift-off intervals, in lift-off at the chunk end]``
        in/out.
    max_events
        Most events per object and sub-step (:mod:`floorslide.contents.events`).
    """
    n = X.shape[1]
    K = R.shape[0] - 1
    nobj = muk.size
    nsteps = (X.shape[0] - 1) // substeps
    rw = scratch(K + 3)
    # packed arguments of the per-sub-step block pass (objects_on_substep): the states at the
    # sub-step's ends and the tail weights of the curvature bound of the floor acceleration on
    # a sub-step, the friction coefficients, scratch, the scalars and the flags
    XW = np.zeros((3, n))
    WA, WS = curvature_tail_weights(R, beta, h, XW[2])
    MU = np.empty((2, nobj))
    for i in range(nobj):
        MU[0, i] = mub[i]
        MU[1, i] = muk[i]
    buf = np.empty(5 * K + 17 + NCOL)
    pk = np.zeros(16)
    pk[5], pk[6], pk[15] = WA, WS, g
    flags = np.array(
        [int(has_vert), int(allow_pos), int(allow_neg), max_events, 0, nobj], dtype=np.int64
    )
    in_lift = liftoff[2] != 0.0
    if k0 == 0:
        # floor values at the very start (the building at rest)
        a_start = beta[0] * acc[0]
        n_start = g + vert[0] if has_vert else g
        for i in range(nobj):
            # friction transmits at most mub·N: a block on a floor already beyond it at t = 0
            # slides from the start
            a_obj = min(abs(a_start), mub[i] * max(n_start, 0.0))
            if a_obj > states[i, PEAK_ACC]:
                states[i, PEAK_ACC] = a_obj
            if want_hist:
                hist_u[i, 0] = states[i, DISP]
                hist_v[i, 0] = states[i, VEL]
                hist_a[i, 0] = a_start
    for kk in range(nsteps):
        k = k0 + kk
        a = acc[k]
        a1 = acc[k + 1]
        slope = (a1 - a) / (substeps * h)
        if has_vert:
            va = vert[k]
            vslope = (vert[k + 1] - va) / (substeps * h)
        else:
            va = 0.0
            vslope = 0.0
        for r in range(substeps):
            aa, ab = substep_inputs(a, a1, r, substeps)
            t0 = (k * substeps + r) * h
            x_prev = X[kk * substeps + r]
            x = X[kk * substeps + r + 1]
            vr0 = _dot_state(rv, x_prev)
            dV = _dot_state(rv, x) - vr0 + 0.5 * h * (aa + ab)
            dD = _dot_state(rd, x) - _dot_state(rd, x_prev) - vr0 * h
            dD += aa * h * h / 2.0 + slope * h * h * h / 6.0
            if has_vert:
                n0 = g + va + vslope * (r * h)
                sn = vslope
                n1 = n0 + sn * h
                nmin = min(n0, n1)
                nmax = max(n0, n1)
                if nmin <= 0.0:
                    if not in_lift:
                        liftoff[1] += 1
                    in_lift = True
                    liftoff[0] += h if nmax <= 0.0 else h * (-min(n0, n1)) / (nmax - nmin)
                    if nmax > 0.0:
                        in_lift = n1 <= 0.0
                else:
                    in_lift = False
                nint = 0.5 * (n0 + n1) * h
                nint2 = n0 * h * h / 2.0 + sn * h * h * h / 6.0
            else:
                n0 = g
                sn = 0.0
                nmin = g
                nmax = g
                nint = g * h
                nint2 = g * h * h / 2.0
            for j in range(n):
                XW[0, j] = x_prev[j]
                XW[1, j] = x[j]
            pk[0], pk[1], pk[2], pk[3], pk[4] = aa, ab, slope, h, t0
            pk[7], pk[8] = dV, dD
            pk[9], pk[10], pk[11], pk[12], pk[13], pk[14] = n0, sn, nmin, nmax, nint, nint2
            A1 = objects_on_substep(R, beta, XW, MU, states, buf, rw, pk, flags)
            if want_hist and r == substeps - 1:
                for i in range(nobj):
                    hist_u[i, k + 1] = states[i, DISP]
                    hist_v[i, k + 1] = states[i, VEL]
                    m = states[i, MODE]
                    if m == 0.0:
                        hist_a[i, k + 1] = A1
                    elif m == FLIGHT:
                        hist_a[i, k + 1] = 0.0
                    else:
                        nn = n0 + sn * h
                        hist_a[i, k + 1] = -m * muk[i] * (nn if nn > 0.0 else 0.0)
    liftoff[2] = 1.0 if in_lift else 0.0
