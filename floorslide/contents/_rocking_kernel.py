"""Compiled event-driven kernel of rigid blocks rocking on one floor (Housner 1963).

A block rocking on its corner ``s = sign θ`` obeys, with ``p² = 3g/(4R)``,

- linearised (slender block): ``θ'' = p²(θ − α s) − p² a_f(t)/g`` (Housner 1963, eq. 8;
  Makris & Roussos 2000, eq. 3 linearised), a linear equation;
- full: ``θ'' = −p² [sin(α s − θ) + (a_f(t)/g) cos(α s − θ)]`` (Makris & Roussos 2000, eq. 3).

The floor's absolute acceleration ``a_f`` is, on each sub-step, the Taylor polynomial of the
floor's exact response (on the ground: the record's own linear segment), as for the sliding
kernel (:mod:`floorslide.contents._kernels`). Each block goes through a sub-step in parts
short for it (``p·L ≤`` :data:`LINEAR_PHASE` or :data:`NONLINEAR_PHASE`); on a part ``θ`` is
its Taylor series from the part's start, to a degree whose truncation is below rounding
(:func:`floorslide.building.exact.taylor_degree`). The coefficients follow from the equation:
``t_{k+2} = p² (t_k − α s δ_{k0} − c_k/g) / ((k+1)(k+2))`` linearised; for the full equation the
series of ``sin u`` and ``cos u`` (``u = α s − θ``) come from ``k S_k = Σ j u_j C_{k−j}``,
``k C_k = −Σ j u_j S_{k−j}`` (the standard recurrences of automatic Taylor differentiation:
Jorba & Zou 2005, §2), and ``t_{k+2} = −p² (S_k + Σ_j (c_j/g) C_{k−j}) / ((k+1)(k+2))``.

Events, each located by rigorous root isolation on these polynomials
(:func:`floorslide.numerics.polynomial.first_rise`):

- uplift from rest, the first instant ``a_f < −g tan α`` (then ``s = +1``) or
  ``a_f > g tan α`` (``s = −1``) — the exact criterion, for both equations; a rest that
  begins with the floor already beyond the level (a record that starts there, at t = 0; a rest
  after an impact) uplifts at once;
- impact, ``θ`` back to 0: the angular velocity is multiplied by the restitution ``r`` and the
  block goes on about the other corner; a velocity after impact at or below
  :data:`REST_VELOCITY` ``·p·α`` ends the sequence of impacts (the block is at rest, and may
  uplift again at once);
- overturning, ``|θ|`` reaches ``α`` (the centre of mass over the corner): the block's
  simulation ends there.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes.
*Bull. Seismol. Soc. Am.* 53(2), 403–417.
Makris, N., Roussos, Y. S. (2000). Rocking response of rigid blocks under near-source ground
motions. *Géotechnique* 50(3), 243–262.
Jorba, À., Zou, M. (2005). A software package for the numerical integration of ODEs by means of
high-order Taylor methods. *Experimental Mathematics* 14(1), 99–117.
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import substep_inputs, taylor_coefficients
from floorslide.numerics.polynomial import (
    _first_positive,
    max_abs_on,
    poly_der,
    poly_val,
    rise_within,
    scratch,
    taylor_shift,
)

# columns of a block's state, shared with the wrapper (contents.rocking_block)
MODE, TH, THD, PEAK, T_PEAK, IMPACTS, ROCK_TIME, T_OVER, UPLIFTS, LIMIT_AT, SIGNIFICANT = range(11)
"""Mode (0 rest, ±1 rocking about that corner, 2 overturned), θ and θ', peak |θ|/α and its
time, impacts, time spent rocking, overturning time (−1: none), uplifts from rest, start of the
first sub-step where the event limit was reached (−1: never), significant impacts
(:data:`SIGNIFICANT_TILT`)."""
NCOL = 11
OVERTURNED = 2.0

# columns of a block's parameters
P_ALPHA, P_P, P_R, P_TAN, P_PARTS = range(5)
NPAR = 5

LINEAR_PHASE = 0.5
"""Longest part of a sub-step for the linearised equation, as ``p·L``."""
NONLINEAR_PHASE = 0.25
"""Longest part for the full equation, as ``p·L`` (its series decay more slowly)."""
REST_VELOCITY = 1e-12
"""An impact that leaves ``|θ'| ≤ REST_VELOCITY·p·α`` ends in rest: the rest of the geometric
sequence of impacts (each ``r`` times the last) lasts less than ``2·10⁻¹²/(1 − r)`` of ``1/p``."""
SIGNIFICANT_TILT = 0.01
"""An impact is *significant* when the block hits at ``|θ'| ≥ p·α·√(f(2 − f))`` with ``f`` =
this: the speed at which a block rocking freely (linearised equation, Housner 1963) comes back
to ``θ = 0`` from a tilt of ``f·α`` (energy ``θ'² − p²(θ − α)²`` is conserved between
impacts). The cascade of ever smaller impacts to rest that follows is not counted."""
SIGNIFICANT_SPEED = (SIGNIFICANT_TILT * (2.0 - SIGNIFICANT_TILT)) ** 0.5
"""``√(f(2 − f))``: the significant impact speed over ``p·α``."""
EVENT_GAP = 1e-12
"""Shortest time between two events of a block, as a fraction of its part."""
ROCK_MAX_EVENTS = 10000
"""Most events one block may have inside one sub-step."""


@njit(cache=True)
def theta_series(s, th, thd, alpha, p2, cf, K, g, D, nonlinear, t, S, C, u):
    """Taylor coefficients ``t[0..D]`` of ``θ`` about a part's start (``θ = th``,
    ``θ' = thd``, rocking about corner ``s``) under the floor acceleration with coefficients
    ``cf[0..K]`` there; ``S, C, u``: scratch (the series of ``sin u``, ``cos u`` and
    ``u = α s − θ`` for the full equation)."""
    t[0] = th
    if D >= 1:
        t[1] = thd
    if not nonlinear:
        for k in range(D - 1):
            src = t[k] - cf[k] / g if k <= K else t[k]
            if k == 0:
                src -= alpha * s
            t[k + 2] = p2 * src / ((k + 1) * (k + 2))
        return
    u[0] = alpha * s - th
    S[0] = np.sin(u[0])
    C[0] = np.cos(u[0])
    for k in range(D - 1):
        acc = S[k]
        for j in range(min(k, K) + 1):
            acc += cf[j] / g * C[k - j]
        t[k + 2] = -p2 * acc / ((k + 1) * (k + 2))
        # the series of sin u and cos u to order k + 1 (u_j = −t_j for j ≥ 1, known to k + 1)
        u[k + 1] = -t[k + 1]
        ss = 0.0
        cc = 0.0
        for j in range(1, k + 2):
            ss += j * u[j] * C[k + 1 - j]
            cc += j * u[j] * S[k + 1 - j]
        S[k + 1] = ss / (k + 1)
        C[k + 1] = -cc / (k + 1)


UNDECIDED = -2.0
HORNER_ERR = 1e-15
"""Relative error bound of a Horner evaluation used to certify a sign (as
:mod:`floorslide.numerics.polynomial`'s, Higham 2002 §5.1, with a margin for degree ≤ 60)."""


@njit(cache=True)
def _convex_rise(q, deg, lo, win):
    """:func:`first_rise` of ``q`` above 0 on ``(lo, win]`` when ``q`` is certified convex on
    ``[0, win]`` (``2q₂ > Σ_{j≥3} j(j−1)|q_j| win^{j−2}``) and below 0 at ``lo``: then the set
    where ``q ≤ 0`` is an interval that holds ``lo``, so there is at most one rise — found by
    Newton's method from its right (``q`` convex and increasing there: the iterates decrease
    monotonically to it), bracketed, and settled on machine numbers (``_first_positive``, as
    root isolation settles it). The return to 0 of a rocking block's excursion is such a rise.
    Returns −1 when ``q(win) ≤ 0`` is certified (no rise), :data:`UNDECIDED` when a premise
    fails or a sign needed is within its rounding bound (then root isolation decides)."""
    if not (win > lo and q[2] > 0.0):
        return UNDECIDED
    tail = 0.0
    for j in range(deg, 2, -1):
        tail = tail * win + j * (j - 1) * abs(q[j])
    if not 2.0 * q[2] > tail * win:
        return UNDECIDED
    # signs of q at win and at lo, certified against their rounding error (Higham 2002, §5.1)
    v = poly_val(q, deg, win)
    err = 0.0
    for j in range(deg, -1, -1):
        err = err * win + abs(q[j])
    err *= HORNER_ERR * (deg + 2)
    if v <= -err:
        return -1.0
    if not v > err:
        return UNDECIDED
    a = lo
    if lo == 0.0:
        if not q[0] < 0.0:
            return UNDECIDED
    elif not poly_val(q, deg, lo) < -err:
        return UNDECIDED
    # the terms that cannot matter on [0, win] (together below 1e-18·|q₁|·win, far below the
    # rounding of any value near the root) are left out of the evaluations below
    dropped = 0.0
    d = deg
    scale = abs(q[0]) + abs(q[1]) * win
    while d > 2:
        dropped += abs(q[d]) * win**d
        if dropped > 1e-18 * scale:
            break
        d -= 1
    deg = d
    b = win
    # Newton from the right of the root — q convex and increasing there, the iterates decrease
    # to it — starting just right of the quadratic's root when q is positive there
    x = b
    disc = q[1] * q[1] - 4.0 * q[0] * q[2]
    if disc >= 0.0:
        guess = (-q[1] + np.sqrt(disc)) / (2.0 * q[2]) * (1.0 + 1e-3)  # the quadratic's root
        if lo < guess < win and poly_val(q, deg, guess) > 0.0:
            x = guess
    for _ in range(60):
        if not poly_val(q, deg, x) > 0.0:
            break  # rounding-level at the root
        b = x
        d = poly_der(q, deg, x)
        if not d > 0.0:
            break
        xn = x - poly_val(q, deg, x) / d
        if not (a < xn < x):
            break
        x = xn
    # a point just below b where q ≤ 0 (a few ulps, then farther), then bisection
    step = 4.0 * max(abs(b) * 2.220446049250313e-16, 5e-324)
    for _ in range(1100):
        c = b - step
        if c <= a:
            break
        if not poly_val(q, deg, c) > 0.0:
            a = c
            break
        b = c
        step *= 4.0
    for _ in range(200):
        m = 0.5 * (a + b)
        if m <= a or m >= b:
            break
        if poly_val(q, deg, m) > 0.0:
            b = m
        else:
            a = m
    return _first_positive(q, deg, a, b)


@njit(cache=True)
def _block_on_part(st, par, cs, K, Lq, t_part, g, D, nonlinear, max_events, t, S, C, u, q, cw,
                   work):  # fmt: skip
    """Advance one block through a part of length ``Lq`` starting at time ``t_part``, the
    floor acceleration's coefficients there ``cs[0..K]``. Returns False when the block's
    event limit was reached (its state is left at the part's start time of that event)."""
    alpha = par[P_ALPHA]
    p = par[P_P]
    p2 = p * p
    r = par[P_R]
    level = g * par[P_TAN]
    s0 = 0.0
    fresh = False
    events = 0
    while s0 < Lq:
        L = Lq - s0
        lo = EVENT_GAP * Lq if fresh else 0.0
        if s0 > 0.0:
            taylor_shift(cs, K, s0, cw)
        else:
            for j in range(K + 1):
                cw[j] = cs[j]
        mode = st[MODE]
        if mode == 0.0:
            # uplift: a_f below −g tan α (corner +1) or above g tan α (corner −1); a floor
            # already beyond the level when the rest begins (a record that starts there, t = 0;
            # a rest after an impact) lifts the block at once — a crossing search would miss a
            # floor that starts beyond the level and falls back inside the part
            a_now = poly_val(cw, K, lo)
            te = -1.0
            side = 0.0
            if a_now < -level:
                te, side = lo, 1.0
            elif a_now > level:
                te, side = lo, -1.0
            else:
                for j in range(K + 1):
                    q[j] = -cw[j]
                tp = rise_within(q, K, lo, L, level, work)
                tn = rise_within(cw, K, lo, L, level, work)
                if tp >= 0.0:
                    te, side = tp, 1.0
                if tn >= 0.0 and (te < 0.0 or tn < te):
                    te, side = tn, -1.0
            if te < 0.0:
                return True
            s0 += te
            st[MODE] = side
            st[TH] = 0.0
            st[THD] = 0.0
            st[UPLIFTS] += 1.0
            fresh = True
        else:
            s = mode
            theta_series(s, st[TH], st[THD], alpha, p2, cw, K, g, D, nonlinear, t, S, C, u)
            # impact: s·θ falls through 0; overturning: s·θ rises to α
            for j in range(D + 1):
                q[j] = -s * t[j]
            # an excursion that starts at θ = 0 (after an impact or an uplift) and turns back
            # ends near τ* = −t₁/t₂ — soon, in a cascade of impacts: root isolation searches
            # (lo, 4τ*] first (cheap on a short interval), then the rest of the part
            if t[0] == 0.0 and s * t[1] > 0.0 and s * t[2] < 0.0:
                win = min(L, -4.0 * t[1] / t[2])
                if win > lo:
                    ti = _convex_rise(q, D, lo, win)
                    if ti == UNDECIDED:
                        ti = rise_within(q, D, lo, win, 0.0, work)
                    if ti < 0.0 and win < L:
                        ti = rise_within(q, D, win, L, 0.0, work)
                else:
                    ti = rise_within(q, D, lo, L, 0.0, work)
            else:
                ti = _convex_rise(q, D, lo, L)
                if ti == UNDECIDED:
                    ti = rise_within(q, D, lo, L, 0.0, work)
            for j in range(D + 1):
                q[j] = s * t[j]
            to = rise_within(q, D, lo, L, alpha, work)
            te = L
            kind = 0
            if ti >= 0.0:
                te, kind = ti, 1
            if to >= 0.0 and to <= te:
                te, kind = to, 2
            v, tv = max_abs_on(t, D, te, st[PEAK] * alpha, work)
            if v > st[PEAK] * alpha:
                st[PEAK] = v / alpha
                st[T_PEAK] = t_part + s0 + tv
            st[ROCK_TIME] += te
            s0 += te
            if kind == 0:
                st[TH] = poly_val(t, D, te)
                st[THD] = poly_der(t, D, te)
                return True
            if kind == 2:
                st[MODE] = OVERTURNED
                st[TH] = s * alpha
                st[THD] = poly_der(t, D, te)
                st[PEAK] = 1.0
                st[T_OVER] = t_part + s0
                return True
            # impact
            st[IMPACTS] += 1.0
            w_in = poly_der(t, D, te)
            if abs(w_in) >= SIGNIFICANT_SPEED * p * alpha:
                st[SIGNIFICANT] += 1.0
            w = r * w_in
            st[TH] = 0.0
            if abs(w) <= REST_VELOCITY * p * alpha:
                st[MODE] = 0.0
                st[THD] = 0.0
            else:
                st[MODE] = -s
                st[THD] = w
            fresh = True
        events += 1
        if events > max_events:
            return False
    return True


@njit(cache=True)
def block_through(st, par, c, K, L, parts, t0, g, D, nonlinear, max_events, cs, t, S, C, u, q,
                  cw, work):  # fmt: skip
    """Advance one block (state ``st``, parameters ``par``) through a segment ``[0, L]`` of the
    floor motion starting at time ``t0``, whose acceleration there has the coefficients
    ``c[0..K]``, in `parts` equal parts (:func:`_block_on_part` on each, the polynomial shifted
    to its start). A reached event limit is recorded in ``st[LIMIT_AT]`` (the segment's start);
    the block stops there, as at its overturning."""
    Lq = L / parts
    for qq in range(parts):
        if qq == 0:
            for j in range(K + 1):
                cs[j] = c[j]
        else:
            taylor_shift(c, K, qq * Lq, cs)
        ok = _block_on_part(st, par, cs, K, Lq, t0 + qq * Lq, g, D, nonlinear, max_events, t, S,
                            C, u, q, cw, work)  # fmt: skip
        if not ok:
            if st[LIMIT_AT] < 0.0:
                st[LIMIT_AT] = t0
            return
        if st[MODE] == OVERTURNED:
            return


@njit(cache=True)
def rock_kernel(X, k0, R, beta, acc, substeps, h, g, par, states, hist, want_hist, nonlinear, D,
                max_events):  # fmt: skip
    """Rocking blocks on one floor, exact for the piecewise-linear ground record.

    Parameters
    ----------
    X, k0
        One chunk of the floor motion's building states from record step ``k0``
        (:meth:`floorslide.building.exact_motion.FloorMotion.chunks`; no columns on the
        ground); called chunk after chunk, the kernel carries everything in ``states``.
    R, beta
        Taylor rows of the floor's absolute acceleration (``(K+1, n)``, ``(K+1,)``).
    acc
        Ground acceleration samples, m/s².
    substeps, h
        Sub-steps per record step and their length, s.
    g
        Gravity, m/s².
    par
        ``(n_obj, NPAR)``: ``α``, ``p``, ``r``, ``tan α`` and the parts per sub-step.
    states
        ``(n_obj, NCOL)`` in/out, columns :data:`MODE` … :data:`LIMIT_AT`.
    hist
        ``(n_obj, npts)``: ``θ`` at the samples when ``want_hist`` (NaN once overturned).
    nonlinear
        The full equation instead of the linearised one.
    D
        Degree of the series of ``θ`` on a part.
    max_events
        Most events per block and sub-step.
    """
    K = R.shape[0] - 1
    nobj = par.shape[0]
    nsteps = (X.shape[0] - 1) // substeps
    work = scratch(max(K, D) + 2)
    c = np.zeros(K + 1)
    cs = np.zeros(K + 1)
    cw = np.zeros(K + 1)
    t = np.zeros(D + 1)
    S = np.zeros(D + 1)
    C = np.zeros(D + 1)
    u = np.zeros(D + 1)
    q = np.zeros(max(K, D) + 1)
    if k0 == 0 and want_hist:
        for i in range(nobj):
            hist[i, 0] = states[i, TH]
    for kk in range(nsteps):
        k = k0 + kk
        a = acc[k]
        a1 = acc[k + 1]
        slope = (a1 - a) / (substeps * h)
        for rr in range(substeps):
            aa, _ = substep_inputs(a, a1, rr, substeps)
            t0 = (k * substeps + rr) * h
            taylor_coefficients(R, beta, X[kk * substeps + rr], aa, slope, c)
            # Σ|c_j| h^j bounds |a_f| on the sub-step: a block at rest below its uplift level
            # there stays at rest (the common case, decided without a search)
            reach = 0.0
            for j in range(K, -1, -1):
                reach = reach * h + abs(c[j])
            for i in range(nobj):
                mode = states[i, MODE]
                if mode == OVERTURNED:
                    continue
                if mode == 0.0 and reach <= g * par[i, P_TAN]:
                    continue
                block_through(states[i], par[i], c, K, h, int(par[i, P_PARTS]), t0, g, D,
                              nonlinear, max_events, cs, t, S, C, u, q, cw, work)  # fmt: skip
            if want_hist and rr == substeps - 1:
                for i in range(nobj):
                    if states[i, MODE] == OVERTURNED:
                        hist[i, k + 1] = np.nan
                    else:
                        hist[i, k + 1] = states[i, TH]
