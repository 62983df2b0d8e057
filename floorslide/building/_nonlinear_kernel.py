"""Compiled event-driven integration of a building on a piecewise-linear isolation layer.

Between events the building is linear time-invariant (one of a few *branches*: elastic or
yielding rubber, sliding or stuck pendulum), so on each sub-step its state is stepped by the
branch's exact first-order-hold recurrence and, inside the sub-step, known as the branch's
Taylor polynomials (exact to rounding on sub-steps with ``ρ(A)·h ≤ 0.5``; see
:mod:`floorslide.building.exact`). An event — yield, unloading, breakaway, stop, reversal — is
the first crossing of a level by one such polynomial (isolator displacement, its velocity, or
the friction a stuck pendulum needs), found by rigorous root isolation
(:func:`floorslide.numerics.polynomial.first_rise`); the state there is the polynomials'
value, the branch changes, and the rest of the sub-step continues from it. The augmented
state's last component is the layer's constant force on the branch (``F0``: ``−(k1 − k2)·p``
elastic, ``±Q`` yielding, ``±mu·W`` sliding).

The building is integrated alone: nothing rides along. Each *segment* of its motion — a whole
sub-step of one branch, or the piece of a sub-step between events — can be recorded (its
sub-step, branch, the states at its ends, the ground there), and every consumer (rigid blocks,
2-DOF oscillators, rocking blocks, floor spectra) reads those segments
(:class:`floorslide.building.nonlinear_motion.NonlinearMotion`).
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import (
    curvature_tail_weights,
    foh_step,
    substep_inputs,
    taylor_coefficients,
)
from floorslide.numerics.polynomial import max_abs_on, poly_val, rise_within, scratch

# branch codes: as floorslide.building.isolators
LINEAR, ELASTIC, PLASTIC_POS, PLASTIC_NEG, SLIP_POS, SLIP_NEG, STICK = 0, 1, 2, 3, 4, 5, 6
NO_EVENT = 1e300
EVENT_GAP = 1e-12
"""Shortest time between two events, in sub-steps (see :func:`nonlinear_run`)."""


@njit(cache=True)
def _state_at(R, B, x, a0, slope, s, K, out, c):
    """All states at ``s`` from the branch's full-state Taylor rows ``R[i], B[i]``."""
    for i in range(x.size):
        taylor_coefficients(R[i], B[i], x, a0, slope, c)
        out[i] = poly_val(c, K, s)


@njit(cache=True)
def _event(branch, R, B, ER, EB, x, a0, slope, L, K, p, dy, limit, lo, n, c, work):
    """First event of `branch` in ``(lo, L]`` from state `x`: ``(time, kind)`` with kind +1 or
    −1 (the level crossed upward or downward), ``(NO_EVENT, 0)`` if none. Just after an event
    ``lo`` is a rounding-level time (see :func:`nonlinear_run`), else 0. ``n``: the
    building's degrees of freedom (``x[0]`` the isolator displacement, ``x[n]`` its velocity)."""
    if lo >= L:
        return NO_EVENT, 0
    if branch == LINEAR:
        return NO_EVENT, 0
    if branch == ELASTIC:
        taylor_coefficients(R[0], B[0], x, a0, slope, c)
        t_up = rise_within(c, K, lo, L, p + dy, work)
        for j in range(K + 1):
            c[j] = -c[j]
        t_dn = rise_within(c, K, lo, L, -(p - dy), work)
    elif branch == STICK:
        taylor_coefficients(ER, EB, x, a0, slope, c)
        t_up = rise_within(c, K, lo, L, limit, work)
        for j in range(K + 1):
            c[j] = -c[j]
        t_dn = rise_within(c, K, lo, L, limit, work)
    else:
        taylor_coefficients(R[n], B[n], x, a0, slope, c)
        t_up = -1.0
        if branch == PLASTIC_POS or branch == SLIP_POS:  # velocity falls through 0
            for j in range(K + 1):
                c[j] = -c[j]
            t_dn = rise_within(c, K, lo, L, 0.0, work)
        else:  # velocity rises through 0
            t_dn = -1.0
            t_up = rise_within(c, K, lo, L, 0.0, work)
    best, kind = NO_EVENT, 0
    if t_up >= 0.0:
        best, kind = t_up, 1
    if t_dn >= 0.0 and t_dn < best:
        best, kind = t_dn, -1
    return best, kind


@njit(cache=True)
def _needed_friction(fr, fd, x, a):
    """Friction force a stuck pendulum needs to keep the mat on the ground."""
    s = fd * a
    for i in range(fr.size):
        s += fr[i] * x[i]
    return s


@njit(cache=True)
def _search_peak(OR, OB, i, x, a0, slope, h, K, peak, t_peak, t0, c, work):
    """Search output ``i`` (Taylor rows ``OR[i], OB[i]``) on a segment ``[0, h]`` for a new
    peak."""
    taylor_coefficients(OR[i], OB[i], x, a0, slope, c)
    v, t = max_abs_on(c, K, h, peak[i], work)
    if v > peak[i]:
        peak[i] = v
        t_peak[i] = t0 + t


# columns of a function's chord-bound row (see _chord_rows), after its N state coefficients
VALUE, C2, C3, TIGHT, LOOSE = 0, 1, 2, 3, 4


@njit(cache=True)
def _chord_rows(RR, BB, ER, EB, OR, OB, n, h, mat_of):
    """Per branch, the rows that bound its event function and its outputs on a whole sub-step
    of length ``h`` (:func:`_fast_substep`).

    ``G[m, f, part]`` for function ``f`` of the branch with matrices ``m`` (``f = 0``: the
    event function — isolator displacement on ``ELASTIC``, its velocity on the yielding and
    sliding branches, the friction a stuck pendulum needs on ``STICK``; ``f ≥ 1``: output
    ``f − 1``), ``part`` one of :data:`VALUE` (Taylor row 0: the value), :data:`C2`, :data:`C3`
    (rows 2 and 3), :data:`TIGHT` (the tail weights ``j ≥ 4`` of
    :func:`~floorslide.building._instep.curvature_tail_weights`) and :data:`LOOSE`
    (``2|row 2| + 6h|row 3| + tail``, which bounds ``max|f''|`` from ``|x|`` alone). Each row
    holds ``N`` state coefficients, then those of the ground value and of its slope.
    ``mat_of[b]`` is −1 for a branch ``b`` the layer does not have."""
    nb, N = RR.shape[0], RR.shape[1]
    K = RR.shape[2] - 1
    nf = OR.shape[1] + 1
    G = np.zeros((nb, nf, 5, N + 2))
    WX = np.zeros(N)
    for b in range(mat_of.size):
        if mat_of[b] < 0:
            continue
        m = mat_of[b]
        for f in range(nf):
            if f == 0:
                if b == STICK:
                    R, B = ER[m], EB[m]
                elif b == ELASTIC or b == LINEAR:
                    R, B = RR[m, 0], BB[m, 0]
                else:
                    R, B = RR[m, n], BB[m, n]
            else:
                R, B = OR[m, f - 1], OB[m, f - 1]
            g = G[m, f]
            for j in range(N):
                g[VALUE, j] = R[0, j]
            g[VALUE, N] = B[0]
            if K >= 2:
                for j in range(N):
                    g[C2, j] = R[2, j]
                g[C2, N] = B[2]
                g[C2, N + 1] = B[1] / 2.0
            if K >= 3:
                for j in range(N):
                    g[C3, j] = R[3, j]
                g[C3, N] = B[3]
                g[C3, N + 1] = B[2] / 3.0
            wa, ws = curvature_tail_weights(R, B, h, WX)
            for j in range(N):
                g[TIGHT, j] = WX[j]
            g[TIGHT, N] = wa
            g[TIGHT, N + 1] = ws
            for j in range(N + 2):
                g[LOOSE, j] = 2.0 * abs(g[C2, j]) + 6.0 * h * abs(g[C3, j]) + g[TIGHT, j]
    return G


@njit(cache=True, _nrt=False)
def _tight_deviation(GT, f, x, ax, aa, slope, h):
    """``h²/8 · max|f''|`` bounded on a sub-step for function ``f`` of the branch with
    chord-bound rows ``GT`` (:func:`_chord_rows`, functions last) from its start state ``x``
    (``ax = |x|``), with ``c_2, c_3`` formed exactly (the states of a building cancel in
    them): the deviation of ``f`` from its chord. The loose bound (from ``|x|`` alone) is
    formed for all functions at once in :func:`_fast_substep`."""
    N = x.size
    c2 = GT[C2, N, f] * aa + GT[C2, N + 1, f] * slope
    c3 = GT[C3, N, f] * aa + GT[C3, N + 1, f] * slope
    tail = GT[TIGHT, N, f] * abs(aa) + GT[TIGHT, N + 1, f] * abs(slope)
    for j in range(N):
        c2 += GT[C2, j, f] * x[j]
        c3 += GT[C3, j, f] * x[j]
        tail += GT[TIGHT, j, f] * ax[j]
    return 0.125 * h * h * (2.0 * abs(c2) + 6.0 * h * abs(c3) + tail)


@njit(cache=True)
def _segment_peaks(Gm, GTm, OR, OB, x, y, ax, a0, a1, slope, L, K, peak, t_peak, t0, c, work):
    """Update the outputs' true peaks on a segment ``[0, L]`` (``L ≤ h``) of a sub-step that
    holds an event or that the bound of :func:`_fast_substep` could not clear, from state
    ``x`` (ground ``a0``) to ``y`` (ground ``a1``): an output is searched
    (:func:`_search_peak`) only when its ends plus its deviation from the chord can exceed its
    peak so far — the sub-step's chord bounds (``Gm``, ``GTm``: the branch's
    :func:`_chord_rows`, both layouts) hold on any part of it."""
    N = x.size
    for j in range(N):
        ax[j] = abs(x[j])
    k8 = 0.125 * L * L
    for i in range(peak.size):
        f = i + 1
        top = max(abs(_value(Gm[f], x, a0)), abs(_value(Gm[f], y, a1)))
        s = GTm[LOOSE, N, f] * abs(a0) + GTm[LOOSE, N + 1, f] * abs(slope)
        for j in range(N):
            s += GTm[LOOSE, j, f] * ax[j]
        if top + k8 * s <= peak[i]:
            continue
        if top + _tight_deviation(GTm, f, x, ax, a0, slope, L) <= peak[i]:
            continue
        _search_peak(OR, OB, i, x, a0, slope, L, K, peak, t_peak, t0, c, work)


@njit(cache=True, _nrt=False)
def _value(g, x, a):
    """The function's value ``row 0 · x + d·a``."""
    N = x.size
    s = g[VALUE, N] * a
    for j in range(N):
        s += g[VALUE, j] * x[j]
    return s


@njit(cache=True, _nrt=False, inline="always")
def _foh_t(pht, p, q, x, aa, ab, out):
    """:func:`~floorslide.building._instep.foh_step` with the transition matrix transposed
    (``pht[j, i] = Φ[i, j]``): the same operations per component in the same order (the
    same bits), the components accumulated together (vectorised; no chain of dependent
    additions per component)."""
    n = x.size
    for i in range(n):
        out[i] = p[i] * aa + q[i] * ab
    for j in range(n):
        xj = x[j]
        for i in range(n):
            out[i] += pht[j, i] * xj


@njit(cache=True, _nrt=False, inline="always")
def _fast_substep(branch, GT, x, y, ax, aa, ab, slope, h, p, dy, limit, peak, t_peak, t0, z0,
                  z1, need, dl):  # fmt: skip
    """The common case of a sub-step, without searching: returns −1 unless a rigorous bound
    shows that `branch` has no event on the whole sub-step from state `x` to `y` (the exact
    step's end); then updates the outputs' peaks with their end values and flags in `need`
    the outputs whose ends plus chord deviation can exceed their peak so far — only those are
    searched (:func:`_search_peak`); returns how many.

    ``GT`` is the branch's :func:`_chord_rows` block with the functions last
    (``GT[part, coefficient, f]``, ``f = 0`` the event function, ``f ≥ 1`` the outputs), so
    that all functions' end values and loose deviation bounds (from ``|x|`` alone) are formed
    together; a function whose loose bound does not decide is checked with the tight one
    (:func:`_tight_deviation`). ``z0[f]`` holds the functions' values at the start; their
    end values go to ``z1``. A function stays inside its range — the event function strictly
    inside the branch's, an output at or below its peak — when its ends plus the deviation
    from the chord do. An output is searched only when that bound exceeds its peak (so never
    while it is identically zero). ``dl``: scratch, one per function. Compiled without
    reference counting: no arrays are made here."""
    N = x.size
    nf = z1.size
    aab = abs(aa)
    asl = abs(slope)
    for j in range(N):
        ax[j] = abs(x[j])
    for f in range(nf):
        z1[f] = GT[VALUE, N, f] * ab
        dl[f] = GT[LOOSE, N, f] * aab + GT[LOOSE, N + 1, f] * asl
    for j in range(N):
        yj = y[j]
        aj = ax[j]
        for f in range(nf):
            z1[f] += GT[VALUE, j, f] * yj
            dl[f] += GT[LOOSE, j, f] * aj
    if branch != LINEAR:
        if branch == STICK:
            lo, hi = -limit, limit
        elif branch == ELASTIC:
            lo, hi = p - dy, p + dy
        elif branch == PLASTIC_POS or branch == SLIP_POS:
            lo, hi = 0.0, np.inf
        else:
            lo, hi = -np.inf, 0.0
        top = max(z0[0], z1[0])
        bot = min(z0[0], z1[0])
        dev = 0.125 * h * h * dl[0]
        if not (top + dev < hi and bot - dev > lo):
            dev = _tight_deviation(GT, 0, x, ax, aa, slope, h)
            if not (top + dev < hi and bot - dev > lo):
                return -1
    count = 0
    for i in range(peak.size):
        v1 = z1[i + 1]
        if abs(v1) > peak[i]:
            peak[i] = abs(v1)
            t_peak[i] = t0 + h
        top = max(abs(z0[i + 1]), abs(v1))
        need[i] = top + 0.125 * h * h * dl[i + 1] > peak[i] and (
            top + _tight_deviation(GT, i + 1, x, ax, aa, slope, h) > peak[i]
        )
        if need[i]:
            count += 1
    return count


# columns of a recorded segment: SI (integers) and SF (floats); see nonlinear_run
S_ROW, S_MAT, S_WHOLE, S_ENDS = 0, 1, 2, 3
F_A0, F_A1, F_SLOPE, F_LEN, F_T = 0, 1, 2, 3, 4


@njit(cache=True, _nrt=False, inline="always")
def _record(SI, SF, SX, SY, j, row, m, whole, x, y, a0, a1, slope, L, t):
    """Record segment ``j`` (when the arrays have room for it; the caller counts)."""
    if j < SI.shape[0]:
        SI[j, S_ROW] = row
        SI[j, S_MAT] = m
        SI[j, S_WHOLE] = whole
        SI[j, S_ENDS] = 0
        SF[j, F_A0] = a0
        SF[j, F_A1] = a1
        SF[j, F_SLOPE] = slope
        SF[j, F_LEN] = L
        SF[j, F_T] = t
        for i in range(x.size):
            SX[j, i] = x[i]
            SY[j, i] = y[i]


@njit(cache=True, _nrt=False)
def _fast_run(k, r, k1, substeps, mat_of, PHT, PP, QQ, G, GT, acc, h, x, y, ax, branch, iF, kk,
              dy, musW, peak, t_peak, z0, z1, need, dl, z_valid, X, BR, Yo, want_outputs, out,
              SI, SF, SX, SY, nseg):  # fmt: skip
    """The common sub-steps, from sub-step ``r`` of record step ``k`` on (up to record step
    ``k1``), in one compiled loop while :func:`_fast_substep` clears them (no event, no output
    search); the samples ``X``, ``BR``, ``Yo`` are written as it goes, and each sub-step is
    recorded as a whole segment (:func:`_record`, from index ``nseg``). It stops before a
    sub-step the bound cannot clear (``out = [k, r, -1, nseg]``, the state untouched) or after
    one whose outputs need a search (``out = [k, r, count, nseg]``: ``x`` the start state,
    ``y`` the end, ``z1`` the functions' end values; the caller finishes and records that
    sub-step); ``out[2] = -2`` at record step ``k1``. ``PHT``: the transition matrices
    transposed (:func:`_foh_t`); ``GT``: :func:`_chord_rows` with the functions last.
    Compiled without reference counting: the views made here cost nothing."""
    m = mat_of[branch]
    Gm = G[m]
    GTm = GT[m]
    pht, pp, qq = PHT[m], PP[m], QQ[m]
    nout = peak.size
    N = x.size
    if not z_valid:
        a = acc[k]
        a1 = acc[k + 1]
        aa = a + (a1 - a) * (r / substeps)
        for f in range(nout + 1):
            z0[f] = _value(Gm[f], x, aa)
    while k < k1:
        a = acc[k]
        a1 = acc[k + 1]
        slope = (a1 - a) / (substeps * h)
        while r < substeps:
            aa = a + (a1 - a) * (r / substeps)
            ab = a + (a1 - a) * ((r + 1) / substeps) if r + 1 < substeps else a1
            row = k * substeps + r
            t0 = row * h
            _foh_t(pht, pp, qq, x, aa, ab, y)
            p = -x[iF] / kk if branch == ELASTIC else 0.0
            ns = _fast_substep(branch, GTm, x, y, ax, aa, ab, slope, h, p, dy, musW, peak, t_peak,
                               t0, z0, z1, need, dl)  # fmt: skip
            if ns != 0:
                out[0], out[1], out[2], out[3] = k, r, ns, nseg
                return
            _record(SI, SF, SX, SY, nseg, row, m, 1, x, y, aa, ab, slope, h, t0)
            if nseg < SI.shape[0]:
                SI[nseg, S_ENDS] = 1
            nseg += 1
            for i in range(N):
                x[i] = y[i]
            for f in range(nout + 1):
                z0[f] = z1[f]
            r += 1
        k += 1
        r = 0
        for i in range(N):
            X[k, i] = x[i]
        BR[k] = branch
        if want_outputs:
            for i in range(nout):
                Yo[k, i] = z0[i + 1]
    out[0], out[1], out[2], out[3] = k, r, -2, nseg


@njit(cache=True)
def nonlinear_run(mat_of, PHI, PP, QQ, RR, BB, ER, EB, OR, OB, G, K, consts, acc, substeps, h, n,
                  k0, k1, x, carry, X, BR, Yo, ev_row, ev_tau, ev_branch, peak, t_peak,
                  max_events, SI, SF, SX, SY):  # fmt: skip
    """Integrate the building over record steps ``k0 … k1 − 1``, from state ``x`` (updated).

    ``mat_of[branch]`` (−1 for a branch the layer does not have) is the index of the
    branch's matrices in the stacks ``PHI, PP, QQ`` (exact sub-step recurrence), ``RR, BB``
    (full-state Taylor rows), ``ER, EB`` (the friction a stuck pendulum needs, as Taylor rows),
    ``OR, OB`` (Taylor rows of the outputs whose true peaks are tracked in ``peak``/``t_peak``)
    and ``G`` (their chord-bound rows, :func:`_chord_rows`). ``consts = [k1 − k2, D_y, Q,
    mu·W, mu_s·W]`` and, from index 5, the linear functional of the needed friction (state
    coefficients, then the ground's). The state is ``[u (n); u' (n); F0; extra]``: ``n``
    degrees of freedom of the building, the layer's constant force on the branch, then states
    that ride along without acting back (an oscillator appended as states). ``carry = [branch,
    fresh, events so far]`` is carried from one call to the next, as ``x``.

    ``X[k]``/``BR[k]``/``Yo[k]`` receive the state, branch and outputs at record sample ``k``
    (``Yo`` when it has a row per sample); events (at most ``ev_row.size`` kept): the sub-step,
    the time in it and the branch after. With rows in ``SI``, every segment of the motion is
    recorded there (:func:`_record`): ``SI[j] = (row, matrices, whole sub-step, ends its
    sub-step)``, ``SF[j] = (a_s, a_end, slope, L, t)`` (ground at its ends, its slope, length
    and start time), ``SX[j]``/``SY[j]`` the states at its ends — the segments every consumer
    reads. Returns the number of segments (more than ``SI`` holds: run again with room for
    them), or ``-1 − row`` when more than ``max_events`` happen in sub-step ``row``.

    Just after an event the search for the next one starts ``EVENT_GAP·h`` later: a branch
    entered at a level crossing (a breakaway at exactly the friction limit, a stop at exactly
    zero velocity) starts on its level up to rounding, and a rounding-level sign there is not
    an event (it would switch back at once, without end). A true event that close to the last
    one is seen as ``EVENT_GAP·h`` later, a rounding-level shift.
    """
    N = x.size
    iF = 2 * n  # the layer's constant force on the branch
    kk = consts[0]
    dy = consts[1]
    Q = consts[2]
    muW = consts[3]
    musW = consts[4]
    fr = consts[5 : 5 + N]
    fd = consts[5 + N]
    c = np.empty(K + 1)
    work = scratch(K + 1)
    y = np.empty(N)
    nout = peak.size
    ax = np.empty(N)
    z0 = np.empty(nout + 1)  # the event function, then the outputs
    z1 = np.empty(nout + 1)
    dl = np.empty(nout + 1)
    GT = np.ascontiguousarray(G.transpose(0, 2, 3, 1))
    PHT = np.ascontiguousarray(PHI.transpose(0, 2, 1))
    need = np.zeros(nout, dtype=np.bool_)
    z_valid = np.bool_(False)  # z0 holds the outputs' values at the sub-step's start
    branch = carry[0]
    fresh = carry[1] != 0
    n_ev = carry[2]
    nseg = np.int64(0)
    want_outputs = Yo.shape[0] == acc.size
    if k0 == 0:
        for i in range(N):
            X[0, i] = x[i]
        BR[0] = branch
        if want_outputs:
            for i in range(nout):
                Yo[0, i] = _value(G[mat_of[branch], i + 1], x, acc[0])
    fo = np.zeros(4, dtype=np.int64)
    k = k0
    r = np.int64(0)
    while k < k1:
        # the common sub-steps in one compiled loop (_fast_run), which stops before a
        # sub-step its bound cannot clear (then ``pre = -1``) or after one whose outputs need a
        # search (``pre = 1``; ``x`` still the start state, ``y`` the end)
        pre = 0
        if not fresh:
            _fast_run(k, r, k1, substeps, mat_of, PHT, PP, QQ, G, GT, acc, h, x, y, ax, branch,
                      iF, kk, dy, musW, peak, t_peak, z0, z1, need, dl, z_valid, X, BR, Yo,
                      want_outputs, fo, SI, SF, SX, SY, nseg)  # fmt: skip
            z_valid = True
            nseg = fo[3]
            if fo[2] == -2:
                break
            k = fo[0]
            r = fo[1]
            pre = 1 if fo[2] > 0 else -1
        a = acc[k]
        a1 = acc[k + 1]
        slope = (a1 - a) / (substeps * h)
        row = k * substeps + r
        aa, ab = substep_inputs(a, a1, r, substeps)
        t0 = row * h
        s0 = 0.0
        events_here = 0
        if pre > 0:
            # a whole sub-step without events whose outputs need a search
            m = mat_of[branch]
            for i in range(nout):
                if need[i]:
                    _search_peak(OR[m], OB[m], i, x, aa, slope, h, K, peak, t_peak, t0, c, work)
            _record(SI, SF, SX, SY, nseg, row, m, 1, x, y, aa, ab, slope, h, t0)
            nseg += 1
            for i in range(N):
                x[i] = y[i]
            for f in range(nout + 1):
                z0[f] = z1[f]
            z_valid = True
        else:
            z_valid = False
            while True:
                m = mat_of[branch]
                L = h - s0
                a_s = aa + slope * s0
                p = -x[iF] / kk if branch == ELASTIC else 0.0
                lo = EVENT_GAP * h if fresh else 0.0
                te, kind = _event(
                    branch, RR[m], BB[m], ER[m], EB[m], x, a_s, slope, L, K, p, dy, musW, lo, n,
                    c, work,
                )  # fmt: skip
                fresh = False
                if te == NO_EVENT:
                    if events_here == 0:
                        foh_step(PHI[m], PP[m], QQ[m], x, aa, ab, y)
                        a_end = ab
                    else:
                        _state_at(RR[m], BB[m], x, a_s, slope, L, K, y, c)
                        a_end = a_s + slope * L
                    _segment_peaks(G[m], GT[m], OR[m], OB[m], x, y, ax, a_s, a_end, slope, L, K,
                                   peak, t_peak, t0 + s0, c, work)  # fmt: skip
                    whole = 1 if events_here == 0 else 0
                    _record(SI, SF, SX, SY, nseg, row, m, whole, x, y, a_s, a_end, slope, L,
                            t0 + s0)  # fmt: skip
                    nseg += 1
                    for i in range(N):
                        x[i] = y[i]
                    break
                _state_at(RR[m], BB[m], x, a_s, slope, te, K, y, c)
                _segment_peaks(G[m], GT[m], OR[m], OB[m], x, y, ax, a_s, a_s + slope * te, slope,
                               te, K, peak, t_peak, t0 + s0, c, work)  # fmt: skip
                _record(SI, SF, SX, SY, nseg, row, m, 0, x, y, a_s, a_s + slope * te, slope, te,
                        t0 + s0)  # fmt: skip
                nseg += 1
                for i in range(N):
                    x[i] = y[i]
                a_e = a_s + slope * te
                if branch == ELASTIC:
                    if kind > 0:
                        branch = PLASTIC_POS
                        x[iF] = Q
                    else:
                        branch = PLASTIC_NEG
                        x[iF] = -Q
                elif branch == PLASTIC_POS or branch == PLASTIC_NEG:
                    pl = x[0] - dy if branch == PLASTIC_POS else x[0] + dy
                    x[n] = 0.0
                    x[iF] = -kk * pl
                    branch = ELASTIC
                elif branch == SLIP_POS or branch == SLIP_NEG:
                    x[n] = 0.0
                    F = _needed_friction(fr, fd, x, a_e)
                    if abs(F) <= musW:
                        branch = STICK
                    elif F > 0.0:
                        branch = SLIP_POS
                        x[iF] = muW
                    else:
                        branch = SLIP_NEG
                        x[iF] = -muW
                else:  # STICK: breakaway in the direction of the demand
                    if kind > 0:
                        branch = SLIP_POS
                        x[iF] = muW
                    else:
                        branch = SLIP_NEG
                        x[iF] = -muW
                s0 = s0 + te
                fresh = True
                if n_ev < ev_row.size:
                    ev_row[n_ev] = row
                    ev_tau[n_ev] = s0
                    ev_branch[n_ev] = branch
                n_ev += 1
                events_here += 1
                if events_here > max_events:
                    return -1 - row
                if s0 >= h:
                    break
        if nseg - 1 < SI.shape[0]:
            SI[nseg - 1, S_ENDS] = 1
        r += 1
        if r < substeps:
            continue
        r = 0
        for i in range(N):
            X[k + 1, i] = x[i]
        BR[k + 1] = branch
        if want_outputs:
            mk = mat_of[branch]
            for i in range(nout):
                Yo[k + 1, i] = _value(G[mk, i + 1], x, a1)
        k += 1
    carry[0] = branch
    carry[1] = 1 if fresh else 0
    carry[2] = n_ev
    return nseg
