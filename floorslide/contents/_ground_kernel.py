"""Compiled kernel of rigid blocks sliding with Coulomb friction on the ground (no building).

On the ground the floor acceleration inside a record step is the record's own linear segment,
``a(τ) = a_k + s_k·τ`` with ``s_k = (a_{k+1} − a_k)/Δt``, and without vertical shaking the
normal acceleration is ``g``. Everything the event-driven solver of
:mod:`floorslide.contents._kernels` finds by polynomial root isolation is then closed form
(docs/design.md §2, with ``N = g``):

* stick → slip when ``|a(τ)|`` reaches the breakaway level ``mu_b·g``
  (``mu_b = max(mu_s, mu_k)``): the root of a linear function;
* during slip with relative velocity of sign ``σ``,
  ``v(τ) = v_0 − a_k τ − s_k τ²/2 − σ mu_k g τ`` (a quadratic) and
  ``u(τ) = u_0 + v_0 τ − a_k τ²/2 − s_k τ³/6 − σ mu_k g τ²/2`` (a cubic);
* slip → stop at the first root of the quadratic ``v`` (then stick, or slip the other way if
  ``|a| > mu_b·g`` there: Westermo & Udwadia 1983); ``|u|`` is monotone while ``v`` keeps its
  sign, so the peak slide is at a stop or a step end.

This kernel is that solver specialised to the ground: the same decisions, in the same floating
point operations, as the general kernel run on the ground's motion (a floor with no states,
Taylor degree ``K = 1``, one sub-step per record step), so its results are the same bits
(checked by ``tests/contents/test_ground_fast_path.py``). What makes it faster:

* a stuck block crosses a sub-block of :data:`SUB` steps at once when the ground's extreme
  samples there stay within ``±mu_b·g`` (``a`` is linear in a step: its extremes are samples);
* objects are advanced one at a time through a block of :data:`BLOCK` steps (their state in
  registers); with several objects the step quantities (the slope ``s_k`` and the changes of
  the ground velocity ``ΔV_k = Δt (a_k + a_{k+1})/2`` and of its displacement
  ``ΔD_k = a_k Δt²/2 + s_k Δt³/6``) are formed once per block for all of them;
* a slipping block whose relative velocity provably keeps its sign through the step is
  advanced in closed form: by the general kernel's quick formula when friction dominates the
  ground throughout, else by its event loop's own formulas when the quick rejections of the
  stop search (:func:`_rejected`, replayed operation for operation) show that there is no stop;
* the other steps (breakaway, stop, reversal, or a stop search those rejections cannot
  decide) go through :func:`_events`, the event loop of the general kernel with ``K = 1``:
  its roots are found by the same :func:`~floorslide.numerics.polynomial.first_rise` (closed
  form for degrees 1 and 2, root isolation when a sign is within rounding), called only when
  its quick rejections do not already answer "none".

Vertical shaking (normal force ``g + a_v``, lift-off) is not handled here: those calls use the
general kernel.

References
----------
Westermo, B., Udwadia, F. (1983). Periodic response of a sliding oscillator system to harmonic
excitation. *Earthquake Eng. Struct. Dyn.* 11, 135–146.
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.contents._kernels import (
    DISP,
    LIMIT_AT,
    MODE,
    NCOL,
    PEAK_ACC,
    PEAK_DISP,
    SLIDE_TIME,
    SLIPS,
    STICK,
    T_PEAK,
    VEL,
)
from floorslide.numerics.polynomial import first_rise, scratch

BLOCK = 1024
"""Record steps whose shared ground quantities are formed at once (they stay in the L1 cache
while every object crosses the block)."""

SUB = 16
"""Record steps per sub-block: a stuck block crosses a whole sub-block at once when the
ground stays within its breakaway level there (the sub-block's extreme samples)."""

NOT_FINITE = 1
"""Returned by :func:`ground_kernel` when the record holds NaN or infinite samples, or samples
beyond the limit it is given (:data:`floorslide.constants.MAX_ACCELERATION`; nothing is
computed)."""

LIMIT_REACHED = 2
"""Returned by :func:`ground_kernel` when an object reached the event limit (its
``LIMIT_AT`` column says where)."""


@njit(cache=True)
def _events(a0, slope, h, g, mub, muk, allow_pos, allow_neg, t0, st, q, rw, max_events):
    """Advance one block through one record step event by event, exactly.

    The event loop of :func:`floorslide.contents._kernels._general` on the ground without
    vertical shaking: floor acceleration ``a0 + slope·τ`` (Taylor degree 1), normal
    acceleration ``g``; operation for operation the same arithmetic (terms that vanish
    identically there, such as the slope of the normal force, are dropped only where that
    cannot change a bit: ``g + 0·τ = g`` for finite ``τ ≥ 0``).

    Parameters
    ----------
    a0, slope
        Floor acceleration at the step start and its slope, m/s², m/s³ (its Taylor
        coefficients, formed as the general kernel forms them).
    h
        Step length, s.
    g
        Gravity, m/s².
    mub, muk
        Breakaway ``max(mu_s, mu_k)`` and kinetic friction coefficients.
    allow_pos, allow_neg
        Whether slip with positive / negative relative velocity is allowed.
    t0
        Time of the step start, s.
    st
        One object's state row (columns :data:`~floorslide.contents._kernels.MODE` …
        :data:`~floorslide.contents._kernels.LIMIT_AT`), in/out.
    q, rw
        Scratch: three coefficients, and the root isolation's
        (:func:`~floorslide.numerics.polynomial.scratch`).
    max_events
        Most events in the step (:mod:`floorslide.contents.events`); reaching it records
        ``t0`` in ``st[LIMIT_AT]`` and leaves the rest of the step undone.
    """
    mode = int(st[MODE])
    v = st[VEL]
    u = st[DISP]
    fb = mub * g  # breakaway level mu_b·(g + 0·τ)
    fk = muk * g
    tau = 0.0
    guard = 0
    while tau < h:
        if guard >= max_events:
            if st[LIMIT_AT] < 0.0:
                st[LIMIT_AT] = t0
            break
        guard += 1
        tau_end = h
        if mode == STICK:
            # a floor already beyond the breakaway level when a stick phase begins moves the
            # block at once
            a_now = slope * tau + a0
            if a_now > fb and allow_neg:
                mode = -1
                v = 0.0
                st[SLIPS] += 1
                continue
            if a_now < -fb and allow_pos:
                mode = 1
                v = 0.0
                st[SLIPS] += 1
                continue
            # first instant a(τ) leaves [−mu_b g, mu_b g] in an allowed way: the root of a
            # linear function (first_rise decides degree 1 in closed form)
            t_up = -1.0
            t_lo = -1.0
            # (slope − mu_b·0 is slope, bit for bit); the search only runs when first_rise's
            # quick rejections do not already answer "none" (_rejected)
            if allow_neg:
                q0 = a0 - mub * g
                if not _rejected(q0, slope, 0.0, tau, tau_end):
                    q[0] = q0
                    q[1] = slope
                    t_up = first_rise(q, 1, tau, tau_end, 0.0, rw)
            if allow_pos:
                q0 = -a0 - mub * g
                if not _rejected(q0, -slope, 0.0, tau, tau_end):
                    q[0] = q0
                    q[1] = -slope
                    t_lo = first_rise(q, 1, tau, tau_end, 0.0, rw)
            t_ev = -1.0
            new_mode = STICK
            if t_up >= 0.0 and (t_lo < 0.0 or t_up <= t_lo):
                t_ev = t_up
                new_mode = -1
            elif t_lo >= 0.0:
                t_ev = t_lo
                new_mode = 1
            t_stop = tau_end if t_ev < 0.0 else t_ev
            # the block moves with the ground on [tau, t_stop]: |a| peaks at an end (linear),
            # and friction transmits at most mu_b·g
            a_abs = max(abs(slope * tau + a0), abs(slope * t_stop + a0))
            a_abs = min(a_abs, fb)
            if a_abs > st[PEAK_ACC]:
                st[PEAK_ACC] = a_abs
            if t_ev < 0.0:
                tau = tau_end
            else:
                tau = t_ev
                mode = new_mode
                v = 0.0
                st[SLIPS] += 1
            continue
        # slipping in direction s: v(τ) = p0 + p1 τ + p2 τ² (the general kernel's series of
        # the relative velocity, its coefficients formed by the same operations)
        s = float(mode)
        p1 = -a0 / 1
        p2 = -slope / 2
        p1 -= s * muk * g
        p2 -= s * muk * 0.0 * 0.5  # the normal force's slope term (sign of a zero included)
        p0 = v - ((p2 * tau + p1) * tau + 0.0)
        # stop: first τ where −s·v(τ) rises above 0 (a quadratic: closed form in first_rise)
        t_s = -1.0
        if not _rejected(-s * p0, -s * p1, -s * p2, tau, tau_end):
            q[0] = -s * p0
            q[1] = -s * p1
            q[2] = -s * p2
            t_s = first_rise(q, 2, tau, tau_end, 0.0, rw)
        t_stop = tau_end if t_s < 0.0 else t_s
        # u(τ) = u + U(τ) − U(tau), U the integral of v (Horner, as poly_val)
        w1 = p0 / 1
        w2 = p1 / 2
        w3 = p2 / 3
        u = u + (((w3 * t_stop + w2) * t_stop + w1) * t_stop + 0.0)
        u = u - (((w3 * tau + w2) * tau + w1) * tau + 0.0)
        if fk > st[PEAK_ACC]:
            st[PEAK_ACC] = fk
        st[SLIDE_TIME] += t_stop - tau
        # |u| is monotone while v keeps its sign: its peak is at the stop or the step end
        if abs(u) > st[PEAK_DISP]:
            st[PEAK_DISP] = abs(u)
            st[T_PEAK] = t0 + t_stop
        if t_s < 0.0:
            v = (p2 * tau_end + p1) * tau_end + p0
            tau = tau_end
            continue
        # the relative velocity reached zero: stick, or slip on the other way if the floor
        # acceleration exceeds the breakaway level right now
        v = 0.0
        tau = t_s
        a_now = slope * tau + a0
        if a_now > fb and allow_neg:
            mode = -1
            st[SLIPS] += 1
        elif a_now < -fb and allow_pos:
            mode = 1
            st[SLIPS] += 1
        else:
            mode = STICK
    st[MODE] = mode
    st[VEL] = v
    st[DISP] = u


@njit(cache=True, inline="always")
def _rejected(q0, q1, q2, lo, hi):
    """True when :func:`~floorslide.numerics.polynomial.first_rise` of ``q0 + q1 τ + q2 τ²``
    (degree 2, or 1 with ``q2 = 0``) above 0 on ``(lo, hi]`` answers "none" by one of its quick
    rejections, replayed operation for operation for the degree left once zero leading
    coefficients are dropped: ``p(0) + Σ|q_j| hi^j ≤ 0`` from ``lo = 0``, then every Bernstein
    coefficient on ``[lo, hi]`` ``≤ 0`` (degrees 1, 2: :func:`~floorslide.numerics.polynomial.
    _rise_low`, finite inputs only), or ``q0 ≤ 0`` (degree 0). False when they do not decide:
    then the search itself must run."""
    if q2 == 0.0 and q1 == 0.0:
        return not q0 > 0.0
    if not (
        abs(q0) < np.inf
        and abs(q1) < np.inf
        and abs(q2) < np.inf
        and abs(lo) < np.inf
        and abs(hi) < np.inf
        and lo < hi
    ):
        return False
    w = hi - lo
    if q2 != 0.0:
        if lo == 0.0 and q0 + (abs(q1) * hi + abs(q2) * (hi * hi)) <= 0.0:
            return True
        lq2 = lo * q2
        t1 = q1 + lq2
        b0 = q0 + lo * t1
        o1 = (t1 + lq2) * w
        return max(b0, max(b0 + 0.5 * o1, (b0 + o1) + q2 * (w * w))) <= 0.0
    if lo == 0.0 and q0 + abs(q1) * hi <= 0.0:
        return True
    b0 = q0 + lo * q1
    return max(b0, b0 + q1 * w) <= 0.0


@njit(cache=True, inline="always")
def _slip_no_stop(mode, c0, c1, v, u, muk, g, h):
    """A whole step of slip in direction ``mode`` (±1) by the formulas of :func:`_events`
    (from ``τ = 0``, Taylor coefficients ``c0, c1`` of the floor acceleration), when its stop
    search provably finds no stop (:func:`_rejected`): ``(True, u_end, v_end)``; else
    ``(False, u, v)``.

    With ``τ = 0`` two of its terms are exact zeros: ``v − V(0)`` and ``u − U(0)`` (``V``,
    ``U`` its Horner polynomials without constant term, ``±0 + 0.0 = +0.0`` at ``τ = 0``) are
    ``v`` and ``u`` bit for bit.
    """
    s = mode
    p1 = -c0 / 1
    p2 = -c1 / 2
    p1 -= s * muk * g
    p2 -= s * muk * 0.0 * 0.5
    if not _rejected(-s * v, -s * p1, -s * p2, 0.0, h):
        return False, u, v
    w1 = v / 1
    w2 = p1 / 2
    w3 = p2 / 3
    u_end = u + (((w3 * h + w2) * h + w1) * h + 0.0)
    v_end = (p2 * h + p1) * h + v
    return True, u_end, v_end


@njit(cache=True, inline="always")
def _beyond(acc, limit):
    """Whether `acc` holds a NaN, an infinity or a sample beyond ``±limit[0]``, by integer
    operations that vectorise: with the sign bit cleared, the bit patterns of doubles order as
    their magnitudes, infinity and NaN above every finite one (IEEE 754)."""
    bits = acc.view(np.int64)
    top = limit.view(np.int64)[0]
    mask = 0x7FFFFFFFFFFFFFFF
    bad = 0
    for k in range(bits.size):
        bad += (bits[k] & mask) > top
    return bad != 0


@njit(cache=True, inline="always")
def _changes(aa, ab, h):
    """The slope of the ground acceleration on a step from ``aa`` to ``ab`` and the changes of
    the ground velocity, ``ΔV = h (aa + ab)/2``, and of its displacement minus ``v_0 h``,
    ``ΔD = aa h²/2 + slope h³/6``, over it: the operations of
    :func:`~floorslide.contents._kernels.slide_kernel` on a floor with no states (whose state
    terms are exact zeros: ``0.0 + x`` keeps their only trace, a −0 made +0)."""
    slope = (ab - aa) / h
    dv = 0.0 + 0.5 * h * (aa + ab)
    dd = 0.0 + (aa * h * h / 2.0 + slope * h * h * h / 6.0)
    return slope, dv, dd


@njit(cache=True)
def ground_kernel(acc, MU, P, states, hist):
    """Rigid blocks on the ground, exact for the piecewise-linear record, without vertical
    shaking: the general :func:`~floorslide.contents._kernels.slide_kernel` on the ground's
    motion, specialised (same results, bit for bit; see the module notes).

    Parameters
    ----------
    acc
        Ground acceleration samples, m/s² (at least one).
    MU
        ``(m ≥ 2, n_obj)``: rows 0 and 1 the breakaway ``max(mu_s, mu_k)`` and kinetic friction
        coefficients (further rows are not read).
    P
        ``[dt, g, allow_pos, allow_neg, max_events, want_hist, max_acc]``: the record step,
        gravity, the allowed slip directions (1 or 0), the most events per object and step
        (:mod:`floorslide.contents.events`), whether to fill `hist` (one array: a numba call
        costs per argument) and the largest ``|sample|`` taken
        (:data:`floorslide.constants.MAX_ACCELERATION`).
    states
        ``(n_obj, NCOL)`` out, columns :data:`~floorslide.contents._kernels.MODE` …
        :data:`~floorslide.contents._kernels.LIMIT_AT` (the blocks start at rest).
    hist
        ``(3, n_obj, npts)``: ``u``, ``v`` and the object's absolute acceleration at the
        samples, when ``want_hist`` (else any shape).

    Returns
    -------
    int
        0; :data:`NOT_FINITE` when `acc` holds NaN or infinite samples or samples beyond
        ``max_acc`` (nothing is done);
        :data:`LIMIT_REACHED` when an object reached the event limit (the caller raises).

    Notes
    -----
    Objects cross the record block by block (:data:`BLOCK` steps), one after the other, each
    step decided as :func:`~floorslide.contents._kernels.objects_on_substep` decides it on the
    ground:

    * a stuck block whose ground acceleration stays within ``±mu_b·g`` at both step ends
      (``a`` is linear) stays stuck, its acceleration peaking at an end — checked for a whole
      sub-block of :data:`SUB` steps at once from its extreme samples (the same values: a
      maximum of exact numbers);
    * a block slipping with relative velocity of sign ``σ`` whose velocity at the step end,
      ``v_1 = v_0 − ΔV_k − σ mu_k g Δt``, has kept the sign, with friction dominating the
      ground throughout (``σ a > −mu_k g`` at both ends: ``v`` monotone), moves by
      ``u_1 = u_0 + v_0 Δt − ΔD_k − σ mu_k g Δt²/2``;
    * otherwise the general kernel runs its event loop on the step; here that loop's formulas
      are applied at once when its stop search provably finds no stop (:func:`_slip_no_stop`),
      else :func:`_events` runs it.

    With several objects the step quantities ``s_k, ΔV_k, ΔD_k`` (:func:`_changes`) are
    formed once per block, when a first object slips in it; a single object forms them where
    it needs them.
    """
    h = P[0]
    g = P[1]
    allow_pos = P[2] != 0.0
    allow_neg = P[3] != 0.0
    max_events = int(P[4])
    want_hist = P[5] != 0.0
    npts = acc.size
    if _beyond(acc, P[6:7]):
        return NOT_FINITE
    nobj = MU.shape[1]
    for i in range(nobj):
        for j in range(NCOL):
            states[i, j] = 0.0
        states[i, LIMIT_AT] = -1.0
    nsteps = npts - 1
    shared = nobj > 1
    # the ground's normal acceleration integrated over a step, once and twice (as
    # slide_kernel forms them without vertical shaking)
    nint = g * h
    nint2 = g * h * h / 2.0
    rw = scratch(4)  # the root isolation's scratch (made here: a loop that makes it costs 3x)
    q = np.zeros(3)
    st = np.empty(NCOL)
    SL = np.empty(BLOCK)
    dV = np.empty(BLOCK)
    dD = np.empty(BLOCK)
    bmin = np.empty(BLOCK // SUB)
    bmax = np.empty(BLOCK // SUB)
    # the start (the ground at rest): friction transmits at most mu_b·g
    a_start = 1.0 * acc[0]
    for i in range(nobj):
        a_obj = min(abs(a_start), MU[0, i] * max(g, 0.0))
        if a_obj > states[i, PEAK_ACC]:
            states[i, PEAK_ACC] = a_obj
        if want_hist:
            hist[0, i, 0] = states[i, DISP]
            hist[1, i, 0] = states[i, VEL]
            hist[2, i, 0] = a_start
    for k0 in range(0, nsteps, BLOCK):
        k1 = min(k0 + BLOCK, nsteps)
        # the extreme samples of each whole sub-block (steps k0 + j·SUB … + SUB − 1)
        nsub = (k1 - k0) // SUB
        for j in range(nsub):
            lo = acc[k0 + j * SUB]
            hi = lo
            for k in range(k0 + j * SUB + 1, k0 + (j + 1) * SUB + 1):
                lo = min(lo, acc[k])
                hi = max(hi, acc[k])
            bmin[j] = lo
            bmax[j] = hi
        formed = False
        for i in range(nobj):
            mub = MU[0, i]
            muk = MU[1, i]
            fb = mub * g  # breakaway level
            fk = muk * g  # kinetic friction
            # σ·mu_k·g·Δt and σ·mu_k·g·Δt²/2 for σ = ±1
            kv_pos = 1.0 * muk * nint
            kv_neg = -1.0 * muk * nint
            ku_pos = 1.0 * muk * nint2
            ku_neg = -1.0 * muk * nint2
            mode = states[i, MODE]
            v = states[i, VEL]
            u = states[i, DISP]
            peak = states[i, PEAK_DISP]
            t_peak = states[i, T_PEAK]
            slide_time = states[i, SLIDE_TIME]
            peak_acc = states[i, PEAK_ACC]
            k = k0
            while k < k1:
                j = k - k0
                if mode == 0.0 and j % SUB == 0 and j < nsub * SUB:
                    lo = bmin[j // SUB]
                    hi = bmax[j // SUB]
                    if (hi <= fb or not allow_neg) and (lo >= -fb or not allow_pos):
                        # stuck through the whole sub-block
                        a_abs = max(hi, -lo)
                        if a_abs > peak_acc:
                            peak_acc = a_abs
                        if want_hist:
                            for kk in range(k + 1, k + SUB + 1):
                                hist[0, i, kk] = u
                                hist[1, i, kk] = v
                                hist[2, i, kk] = 0.0 + acc[kk]
                        k += SUB
                        continue
                a0 = acc[k]
                a1 = acc[k + 1]
                amin = min(a0, a1)
                amax = max(a0, a1)
                done = False
                if mode == 0.0:
                    if (amax <= fb or not allow_neg) and (amin >= -fb or not allow_pos):
                        a_abs = max(amax, -amin)
                        if a_abs > peak_acc:
                            peak_acc = a_abs
                        done = True
                elif mode == 1.0 or mode == -1.0:
                    if shared:
                        if not formed:
                            for kk in range(k0, k1):
                                SL[kk - k0], dV[kk - k0], dD[kk - k0] = _changes(
                                    acc[kk], acc[kk + 1], h
                                )
                            formed = True
                        slope = SL[j]
                        dv = dV[j]
                        dd = dD[j]
                    else:
                        slope, dv, dd = _changes(a0, a1, h)
                    pos = mode > 0.0
                    v_end = v - dv - (kv_pos if pos else kv_neg)
                    if mode * v_end > 0.0 and ((amin > -fk) if pos else (amax < fk)):
                        u = u + v * h - dd - (ku_pos if pos else ku_neg)
                        v = v_end
                        slide_time += h
                        if abs(u) > peak:
                            peak = abs(u)
                            t_peak = k * h + h
                        if fk > peak_acc:
                            peak_acc = fk
                        done = True
                    else:
                        # the general kernel hands this step to its event loop; when that
                        # loop's stop search provably finds no stop, its formulas are applied
                        # here (the Taylor coefficients as taylor_coefficients forms them)
                        ok, u1, v1 = _slip_no_stop(
                            mode, 0.0 + (a0 + (a1 - a0) * 0.0), 0.0 + slope, v, u, muk, g, h
                        )
                        if ok:
                            u = u1
                            v = v1
                            if fk > peak_acc:
                                peak_acc = fk
                            slide_time += h
                            if abs(u) > peak:
                                peak = abs(u)
                                t_peak = k * h + h
                            done = True
                if not done:
                    st[MODE] = mode
                    st[VEL] = v
                    st[DISP] = u
                    st[PEAK_DISP] = peak
                    st[T_PEAK] = t_peak
                    st[SLIDE_TIME] = slide_time
                    st[SLIPS] = states[i, SLIPS]
                    st[PEAK_ACC] = peak_acc
                    st[LIMIT_AT] = states[i, LIMIT_AT]
                    # the Taylor coefficients of the step's acceleration as the general kernel
                    # forms them (taylor_coefficients on the ground: a −0 becomes +0)
                    _events(
                        0.0 + (a0 + (a1 - a0) * 0.0),
                        0.0 + (a1 - a0) / h,
                        h,
                        g,
                        mub,
                        muk,
                        allow_pos,
                        allow_neg,
                        k * h,
                        st,
                        q,
                        rw,
                        max_events,
                    )
                    mode = st[MODE]
                    v = st[VEL]
                    u = st[DISP]
                    peak = st[PEAK_DISP]
                    t_peak = st[T_PEAK]
                    slide_time = st[SLIDE_TIME]
                    states[i, SLIPS] = st[SLIPS]
                    peak_acc = st[PEAK_ACC]
                    states[i, LIMIT_AT] = st[LIMIT_AT]
                if want_hist:
                    hist[0, i, k + 1] = u
                    hist[1, i, k + 1] = v
                    if mode == 0.0:
                        hist[2, i, k + 1] = 0.0 + a1
                    else:
                        hist[2, i, k + 1] = -mode * muk * g
                k += 1
            states[i, MODE] = mode
            states[i, VEL] = v
            states[i, DISP] = u
            states[i, PEAK_DISP] = peak
            states[i, T_PEAK] = t_peak
            states[i, SLIDE_TIME] = slide_time
            states[i, PEAK_ACC] = peak_acc
    for i in range(nobj):
        if states[i, LIMIT_AT] >= 0.0:
            return LIMIT_REACHED
    return 0
