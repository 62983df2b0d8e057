"""Compiled event-driven kernel of a rigid block that rests, slides, rocks or slides and rocks on
a floor (Shenton & Jones 1991; Shenton 1996; the model of docs/design.md §10g).

The floor's absolute acceleration ``a_f`` is, on each segment of the floor's exact motion, a
polynomial (coefficients ``c[0..K]``) — the poly-motion contract (:mod:`floorslide.building.
poly_segments`). Each block goes through a segment in parts with ``p·L ≤`` :data:`PHASE`; on a
part its state is a Taylor series from the part's start, to a degree whose truncation is below
rounding, in the mode it is in:

- rest: nothing moves relative to the floor;
- slide: ``U'' = −a_f − σ mu_k g``, a polynomial;
- rock about corner ``s``: ``θ'' = −p² [sin u + (a_f/g) cos u]``, ``u = α s − θ`` (the series of
  :func:`floorslide.contents._rocking_kernel.theta_series`), the contact force per unit mass
  ``F = a_f + R (cos u θ')'``, ``N = g + R (sin u θ')'``;
- slide–rock: ``θ'' = −w (g − R cos u θ'²) / (R (1/3 + w sin u))``, ``w = sin u − σ mu_k
  cos u`` — its series by the recurrences of automatic Taylor differentiation (products,
  ``sin``/``cos``, division: Jorba & Zou 2005, §2) — and the corner's slip
  ``V' = −σ mu_k N − R (cos u θ')' − a_f``.

Every mode change is located by rigorous root isolation on these polynomials
(:func:`floorslide.numerics.polynomial.rise_within`): the floor reaching the rest's level, a
slide's stop, the friction limit ``|F| = mu_s N`` of a rocking block, a slip's stop, an impact
(``θ`` back to 0), overturning (``|θ| = α``), and free flight (``N`` reaching 0: not modelled,
the block stops with an error code). The rules at each (Shenton 1996's initiation from rest,
Housner's impact about the new corner) are those of docs/design.md §10g.

References
----------
Shenton, H. W., Jones, N. P. (1991). Base excitation of rigid bodies. I: Formulation.
*J. Eng. Mech.* 117(10), 2286–2306.
Shenton, H. W. (1996). Criteria for initiation of slide, rock, and slide-rock rigid-body modes.
*J. Eng. Mech.* 122(7), 690–693.
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes.
*Bull. Seismol. Soc. Am.* 53(2), 403–417.
Jorba, À., Zou, M. (2005). A software package for the numerical integration of ODEs by means of
high-order Taylor methods. *Experimental Mathematics* 14(1), 99–117.
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.contents._rocking_kernel import (
    SIGNIFICANT_SPEED,
    UNDECIDED,
    _convex_rise,
    theta_series,
)
from floorslide.numerics.polynomial import (
    max_abs_on,
    poly_der,
    poly_val,
    rise_within,
    scratch,
    taylor_shift,
)

# columns of a block's state
(MODE, SIG, TH, THD, U, V, PEAK, T_PEAK, PEAK_U, IMPACTS, T_OVER, LIMIT_AT, ERR, ERR_T,
 W_FLOOR, W_FRIC, W_IMP, E0, NLOG, LAST, SIGNIF) = range(21)  # fmt: skip
"""Mode (0 on the base, ±1 rocking about that corner, 2 overturned), slip direction σ (0 stuck,
±1), θ, θ', the slide U, the slip velocity V (U' while sliding, the corner's while slipping and
rocking), peak |θ|/α and its time, peak |U|, impacts, overturning time (−1: none), start of the
first segment where the event limit was reached (−1: never), error code (:data:`FLIGHT`,
:data:`PAINLEVE`) and its time, the energy terms per unit mass (the floor's work, friction's,
impacts' losses), the energy at the start, the number of mode changes logged, the last mode
code logged, and the significant impacts (:data:`~floorslide.contents._rocking_kernel.
SIGNIFICANT_SPEED`)."""
T_MODE = 21
"""Four columns from here: seconds spent in rest, slide, rock, slide–rock."""
N_MODE = 25
"""Four columns from here: entries into rest, slide, rock, slide–rock."""
LOG = 29
"""From here, pairs (time, mode code) of the first :data:`LOG_SIZE` mode changes."""
LOG_SIZE = 32
NCOL = LOG + 2 * LOG_SIZE

# mode codes (the results' and histories')
REST, SLIDE, ROCK, SLIDE_ROCK, OVER = 0, 1, 2, 3, 4
OVERTURNED = 2.0

# error codes
FLIGHT = 1.0
"""The normal force reached 0: the block would leave the floor (free flight, not modelled)."""
PAINLEVE = 2.0
"""``1/3 + w sin u`` fell to :data:`PAINLEVE_MARGIN`: the slide–rock equations lose their
solution (Painlevé's paradox of Coulomb friction; huge mu_k on a squat block)."""
INCONSISTENT = 3.0
"""Neither sticking nor slipping is consistent at a stop (a Painlevé-type ambiguity)."""
PAINLEVE_MARGIN = 0.01

# columns of a block's parameters
P_ALPHA, P_P, P_RAD, P_TAN, P_MUK, P_MUS, P_R, P_ENERGY = range(8)
NPAR = 8
"""Columns of a block's parameters: α, p, R (centre to corner), tan α, mu_k, mu_s, the
restitution, and 1 to account the energy terms (0: skip them)."""

PHASE = 0.25
"""Longest part of a segment, as ``p·L`` (as the rocking block's full equation; slide–rock, which
turns at up to about ``2p``, shortens a part whose series does not reach rounding: :data:`TAIL`)."""
REST_VELOCITY = 1e-12
"""An impact that leaves ``|θ'| ≤ REST_VELOCITY·p·α`` ends in rest (as §10c)."""
TAIL = 1e-16
"""Largest last two terms of ``θ``'s series on a part, as a fraction of α."""
EVENT_GAP = 1e-12
"""Shortest time between two events of a block, as a fraction of its part."""
MAX_EVENTS = 10000
"""Most events one block may have inside one part."""


@njit(cache=True, inline="always")
def mode_code(st):
    """The mode code (:data:`REST` … :data:`OVER`) of a state row."""
    m = st[MODE]
    if m == OVERTURNED:
        return OVER
    if m == 0.0:
        return REST if st[SIG] == 0.0 else SLIDE
    return ROCK if st[SIG] == 0.0 else SLIDE_ROCK


@njit(cache=True)
def _log(st, t):
    """Count an entry into the state's mode at time `t` and log it among the first changes
    (nothing when the mode is the one last logged)."""
    code = mode_code(st)
    if code == st[LAST]:
        return
    st[LAST] = code
    if code < OVER:
        st[N_MODE + code] += 1.0
    n = int(st[NLOG])
    if n < LOG_SIZE:
        st[LOG + 2 * n] = t
        st[LOG + 2 * n + 1] = code
    st[NLOG] = n + 1


@njit(cache=True)
def energy(st, par, g):
    """Mechanical energy per unit mass in the floor's frame (docs/design.md §10g):
    ``½ v_c² + (R²/6) θ'² + g (y_c − h)``."""
    R = par[P_RAD]
    h = R * np.cos(par[P_ALPHA])
    m = st[MODE]
    if m == 0.0:
        return 0.5 * st[V] * st[V]
    if m == OVERTURNED:
        m = 1.0 if st[TH] > 0.0 else -1.0  # at the overturning
    uu = par[P_ALPHA] * m - st[TH]
    su, cu = np.sin(uu), np.cos(uu)
    w = st[THD]
    vx = st[V] + R * cu * w
    vy = R * su * w
    return 0.5 * (vx * vx + vy * vy) + R * R / 6.0 * w * w + g * (R * cu - h)


@njit(cache=True)
def rock_forces(s, th, thd, a, par, g):
    """``(F, N)`` per unit mass at the stuck corner of a block rocking about `s` at ``θ, θ'``
    with the floor at `a` (§10g's rock row)."""
    p = par[P_P]
    R = par[P_RAD]
    uu = par[P_ALPHA] * s - th
    su, cu = np.sin(uu), np.cos(uu)
    thdd = -p * p * (su + a / g * cu)
    F = a + R * (cu * thdd + su * thd * thd)
    N = g + R * (su * thdd - cu * thd * thd)
    return F, N


@njit(cache=True)
def classify(st, par, a, g):
    """Put a block that is on its base and stuck (``θ = θ' = 0``, ``V = 0``) into the mode that
    Shenton's (1996) criteria give with the floor at `a` (§10g, from rest)."""
    lam = par[P_TAN]
    mus = par[P_MUS]
    st[TH] = 0.0
    st[THD] = 0.0
    st[V] = 0.0
    A = abs(a)
    if A <= g * min(mus, lam):
        st[MODE] = 0.0
        st[SIG] = 0.0
        return
    s = -1.0 if a > 0.0 else 1.0
    if mus < lam:
        st[MODE] = 0.0
        st[SIG] = s
        return
    F, N = rock_forces(s, 0.0, 0.0, a, par, g)
    if abs(F) <= mus * N:
        st[MODE] = s
        st[SIG] = 0.0
    elif par[P_MUK] > lam:
        st[MODE] = s
        st[SIG] = s
    else:
        st[MODE] = 0.0
        st[SIG] = s


@njit(cache=True)
def _stuck_or_slip(st, par, a, g):
    """A rocking block whose corner is stuck (``V = 0``): it stays stuck while
    ``|F| ≤ mu_s N``, else it slips with ``σ = −sgn F``. Returns False on free flight."""
    F, N = rock_forces(st[MODE], st[TH], st[THD], a, par, g)
    if not N > 0.0:
        return False
    st[V] = 0.0
    if abs(F) <= par[P_MUS] * N:
        st[SIG] = 0.0
    else:
        st[SIG] = -1.0 if F > 0.0 else 1.0
    return True


@njit(cache=True, inline="always")
def _sincos_order(k, t, u, S, C):
    """Order ``k ≥ 1`` of the series of ``sin u`` and ``cos u`` (``u = α s − θ``, so
    ``u_k = −t_k``) from the lower orders: ``k S_k = Σ j u_j C_{k−j}``,
    ``k C_k = −Σ j u_j S_{k−j}`` (Jorba & Zou 2005, §2)."""
    u[k] = -t[k]
    ss = 0.0
    cc = 0.0
    for j in range(1, k + 1):
        ss += j * u[j] * C[k - j]
        cc += j * u[j] * S[k - j]
    S[k] = ss / k
    C[k] = -cc / k


@njit(cache=True)
def sliderock_series(s, sig, th, thd, par, g, D, t, S, C, u, P1, P2, W, Dn, Nm, Q):
    """Taylor coefficients ``t[0..D]`` of ``θ`` about a part's start for a block sliding and
    rocking about corner ``s`` with its corner slipping in direction ``sig`` (§10g's slide–rock
    row), and the series of ``sin u``, ``cos u`` to degree ``D − 1``. Order by order (Jorba &
    Zou 2005, §2): ``sin u``/``cos u`` from ``k S_k = Σ j u_j C_{k−j}``,
    ``k C_k = −Σ j u_j S_{k−j}``; ``P1 = θ'²``, ``P2 = cos u·P1``, ``W = sin u − σ mu_k cos u``,
    ``Dn = 1/3 + sin u·W``, ``Nm = W (g − R P2)``, ``Q = Nm/Dn`` (series division), and
    ``t_{k+2} = −Q_k / (R (k+1)(k+2))``. Returns ``Dn_0`` (the Painlevé check)."""
    R = par[P_RAD]
    muk = par[P_MUK]
    t[0] = th
    t[1] = thd
    u[0] = par[P_ALPHA] * s - th
    S[0] = np.sin(u[0])
    C[0] = np.cos(u[0])
    for k in range(D - 1):
        if k >= 1:
            _sincos_order(k, t, u, S, C)
        acc = 0.0
        for j in range(k + 1):
            acc += (j + 1) * t[j + 1] * (k - j + 1) * t[k - j + 1]
        P1[k] = acc
        acc = 0.0
        for j in range(k + 1):
            acc += C[j] * P1[k - j]
        P2[k] = acc
        W[k] = S[k] - sig * muk * C[k]
        acc = 1.0 / 3.0 if k == 0 else 0.0
        for j in range(k + 1):
            acc += S[j] * W[k - j]
        Dn[k] = acc
        acc = g * W[k]
        for j in range(k + 1):
            acc -= R * W[j] * P2[k - j]
        Nm[k] = acc
        acc = Nm[k]
        for j in range(1, k + 1):
            acc -= Dn[j] * Q[k - j]
        Q[k] = acc / Dn[0]
        t[k + 2] = -Q[k] / (R * (k + 1) * (k + 2))
    if D - 1 >= 1:
        _sincos_order(D - 1, t, u, S, C)  # sin u and cos u to degree D − 1
    return Dn[0]


@njit(cache=True)
def contact_series(t, S, C, D, R, g, E, Hs, Fp, Np):
    """From ``θ`` (``t[0..D]``) and ``sin u``, ``cos u`` (to ``D − 1``): ``E = cos u·θ'`` and
    ``Hs = sin u·θ'`` (to ``D − 1``), then ``Fp = R E'`` (the horizontal force less the floor's
    part) and ``Np = g + R Hs'`` (the normal force), per unit mass, to degree ``D − 2``."""
    for k in range(D):
        e = 0.0
        hh = 0.0
        for j in range(k + 1):
            w = (k - j + 1) * t[k - j + 1]
            e += C[j] * w
            hh += S[j] * w
        E[k] = e
        Hs[k] = hh
    for k in range(D - 1):
        Fp[k] = R * (k + 1) * E[k + 1]
        Np[k] = R * (k + 1) * Hs[k + 1]
    Np[0] += g


@njit(cache=True)
def integral_of_product(a, da, b, db, T):
    """``∫₀ᵀ a(τ) b(τ) dτ`` for polynomials ``a`` (degree `da`) and ``b`` (degree `db`)."""
    tot = 0.0
    for k in range(da + db, -1, -1):
        ck = 0.0
        for j in range(max(0, k - db), min(k, da) + 1):
            ck += a[j] * b[k - j]
        tot = tot * T + ck / (k + 1)
    return tot * T


@njit(cache=True)
def _first(te, kind, cand, k):
    """Keep the earlier of the event found so far (``te``, ``kind``) and ``cand`` (kind `k`)."""
    if cand >= 0.0 and cand < te:
        return cand, k
    return te, kind


@njit(cache=True)
def _part(st, par, cw0, K, Lq, t_part, g, D, max_events, WS, work):
    """Advance one block through a part of length ``Lq`` starting at ``t_part``, the floor
    acceleration's coefficients there ``cw0[0..K]``. Returns False when the block's event limit
    was reached or an error (flight, Painlevé) stopped it."""
    alpha = par[P_ALPHA]
    p = par[P_P]
    p2 = p * p
    R = par[P_RAD]
    muk = par[P_MUK]
    mus = par[P_MUS]
    r = par[P_R]
    cw = WS[0]
    t = WS[1]
    S = WS[2]
    C = WS[3]
    uu = WS[4]
    P1 = WS[5]
    P2 = WS[6]
    Wr = WS[7]
    Dn = WS[8]
    Nm = WS[9]
    Q = WS[10]
    E = WS[11]
    Hs = WS[12]
    Fp = WS[13]
    Np = WS[14]
    q = WS[15]
    Vs = WS[16]
    Us = WS[17]
    s0 = 0.0
    fresh = False
    events = 0
    while s0 < Lq:
        L = Lq - s0
        lo = EVENT_GAP * Lq if fresh else 0.0
        if s0 > 0.0:
            taylor_shift(cw0, K, s0, cw)
        else:
            for j in range(K + 1):
                cw[j] = cw0[j]
        tnow = t_part + s0
        mode = st[MODE]
        sig = st[SIG]
        if mode == 0.0 and sig == 0.0:
            # rest: until |a_f| exceeds g·min(mu_s, tan α); a floor already beyond it starts
            # the next mode at once (the record's start, a stop, an impact to rest)
            level = g * min(mus, par[P_TAN])
            a_now = poly_val(cw, K, lo)
            if abs(a_now) > level:
                te = lo
            else:
                for j in range(K + 1):
                    q[j] = -cw[j]
                tp = rise_within(q, K, lo, L, level, work)
                tn = rise_within(cw, K, lo, L, level, work)
                te = tp
                if tn >= 0.0 and (te < 0.0 or tn < te):
                    te = tn
            if te < 0.0:
                st[T_MODE + REST] += L
                return True
            st[T_MODE + REST] += te
            s0 += te
            classify(st, par, poly_val(cw, K, te), g)
            _log(st, t_part + s0)
            fresh = True
        elif mode == 0.0:
            # slide: U'' = −a_f − σ mu_k g
            Us[0] = st[U]
            Us[1] = st[V]
            for k in range(K + 1):
                src = -cw[k]
                if k == 0:
                    src -= sig * muk * g
                Us[k + 2] = src / ((k + 1) * (k + 2))
            dU = K + 2
            for k in range(K + 2):
                q[k] = -sig * (k + 1) * Us[k + 1]
            te = rise_within(q, K + 1, lo, L, 0.0, work)
            stop = te >= 0.0
            if not stop:
                te = L
            vmax, tv = max_abs_on(Us, dU, te, st[PEAK_U], work)
            if vmax > st[PEAK_U]:
                st[PEAK_U] = vmax
            u1 = poly_val(Us, dU, te)
            # work: the floor's −∫ a_f U' and friction's mu_k g |ΔU| (U' of one sign here)
            if par[P_ENERGY] != 0.0:
                for k in range(K + 2):
                    q[k] = (k + 1) * Us[k + 1]
                st[W_FLOOR] -= integral_of_product(cw, K, q, K + 1, te)
                st[W_FRIC] += muk * g * sig * (u1 - st[U])
            st[T_MODE + SLIDE] += te
            st[U] = u1
            s0 += te
            if not stop:
                st[V] = poly_der(Us, dU, te)
                return True
            st[SIG] = 0.0
            classify(st, par, poly_val(cw, K, te), g)
            _log(st, t_part + s0)
            fresh = True
        else:
            s = mode
            if sig == 0.0:
                theta_series(s, st[TH], st[THD], alpha, p2, cw, K, g, D, True, t, S, C, uu)
            else:
                d0 = sliderock_series(s, sig, st[TH], st[THD], par, g, D, t, S, C, uu, P1, P2,
                                      Wr, Dn, Nm, Q)  # fmt: skip
                if not d0 > PAINLEVE_MARGIN:
                    st[ERR] = PAINLEVE
                    st[ERR_T] = tnow
                    return False
            # a part the series does not cover to rounding (slide–rock near its singularity,
            # 1/3 + w sin u → 0) is shortened until its last two terms are below 1e-16·α
            tail = abs(t[D]) * L**D + abs(t[D - 1]) * L ** (D - 1)
            if tail > TAIL * alpha:
                L = max(L * 0.9 * (TAIL * alpha / tail) ** (1.0 / (D - 1)), 4.0 * lo)
            # a rocking block whose corner holds on the whole part by bounds — |F| ≤ |a_f| +
            # R (|θ''| + θ'²) ≤ mu_s (g − R (|θ''| + θ'²)) ≤ mu_s N — needs no contact forces
            # (unless the energy is accounted): no friction limit, no flight there
            quiet = False
            if sig == 0.0:
                b1 = 0.0
                b2 = 0.0
                for k in range(D, 0, -1):
                    b1 = b1 * L + k * abs(t[k])
                    if k >= 2:
                        b2 = b2 * L + k * (k - 1) * abs(t[k])
                af = 0.0
                for j in range(K, -1, -1):
                    af = af * L + abs(cw[j])
                swing = R * (b2 + b1 * b1)
                quiet = g - swing > 0.0 and af + swing <= mus * (g - swing)
            energy = par[P_ENERGY] != 0.0
            if not quiet or energy:
                contact_series(t, S, C, D, R, g, E, Hs, Fp, Np)
            dF = D - 2
            # the slip's series (slide–rock): V' = −σ mu_k N − R E' − a_f
            if sig != 0.0:
                Vs[0] = st[V]
                for k in range(dF + 1):
                    src = -sig * muk * Np[k] - Fp[k]
                    if k <= K:
                        src -= cw[k]
                    Vs[k + 1] = src / (k + 1)
                Us[0] = st[U]
                for k in range(dF + 2):
                    Us[k + 1] = Vs[k] / (k + 1)
            # events: impact (s θ falls through 0), overturning (s θ reaches α), free flight
            # (N falls through 0), friction limit (|F| reaches mu_s N, stuck corner) or the
            # slip's stop (σ V falls through 0)
            for j in range(D + 1):
                q[j] = -s * t[j]
            te = L
            kind = 0
            # as the rocking block's kernel: an excursion that starts at θ = 0 and turns back
            # ends near τ* = −t₁/t₂ (soon, in a cascade of impacts): a convex rise is found by
            # Newton's method, certified; root isolation decides what that cannot
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
            if ti >= 0.0:
                te, kind = ti, 1
            for j in range(D + 1):
                q[j] = s * t[j]
            to = rise_within(q, D, lo, L, alpha, work)
            if to >= 0.0 and to <= te:
                te, kind = to, 2
            if not quiet:  # (a quiet part is a rocking one: σ = 0)
                for j in range(dF + 1):
                    q[j] = -Np[j]
                te, kind = _first(te, kind, rise_within(q, dF, lo, L, 0.0, work), 3)
                if sig == 0.0:
                    for j in range(dF + 1):
                        f = Fp[j] + (cw[j] if j <= K else 0.0)
                        q[j] = f - mus * Np[j]
                    te, kind = _first(te, kind, rise_within(q, dF, lo, L, 0.0, work), 4)
                    for j in range(dF + 1):
                        f = Fp[j] + (cw[j] if j <= K else 0.0)
                        q[j] = -f - mus * Np[j]
                    te, kind = _first(te, kind, rise_within(q, dF, lo, L, 0.0, work), 4)
            if sig != 0.0:
                for j in range(dF + 2):
                    q[j] = -sig * Vs[j]
                te, kind = _first(te, kind, rise_within(q, dF + 1, lo, L, 0.0, work), 5)
            v, tv = max_abs_on(t, D, te, st[PEAK] * alpha, work)
            if v > st[PEAK] * alpha:
                st[PEAK] = v / alpha
                st[T_PEAK] = tnow + tv
            if sig != 0.0:
                vmax, tv = max_abs_on(Us, dF + 2, te, st[PEAK_U], work)
                if vmax > st[PEAK_U]:
                    st[PEAK_U] = vmax
            if energy:
                # the floor's work −∫ a_f x_c' (x_c' = V + R E) and friction's ∫ mu_k N σ V
                for j in range(D):
                    q[j] = R * E[j]
                if sig != 0.0:
                    for j in range(dF + 2):
                        q[j] += Vs[j]
                    st[W_FRIC] += sig * muk * integral_of_product(Np, dF, Vs, dF + 1, te)
                st[W_FLOOR] -= integral_of_product(cw, K, q, D - 1, te)
            st[T_MODE + (ROCK if sig == 0.0 else SLIDE_ROCK)] += te
            s0 += te
            th1 = poly_val(t, D, te)
            thd1 = poly_der(t, D, te)
            if sig != 0.0:
                st[U] = poly_val(Us, dF + 2, te)
                st[V] = poly_val(Vs, dF + 1, te)
            if kind == 0:
                st[TH] = th1
                st[THD] = thd1
                return True
            if kind == 2:
                st[MODE] = OVERTURNED
                st[SIG] = 0.0
                st[TH] = s * alpha
                st[THD] = thd1
                st[PEAK] = 1.0
                st[T_OVER] = t_part + s0
                _log(st, t_part + s0)
                return True
            if kind == 3:
                st[ERR] = FLIGHT
                st[ERR_T] = t_part + s0
                return False
            a1 = poly_val(cw, K, te)
            if kind == 1:
                # Housner's impact about the new corner, which sticks (§10g)
                st[IMPACTS] += 1.0
                if abs(thd1) >= SIGNIFICANT_SPEED * p * alpha:
                    st[SIGNIF] += 1.0
                vin = st[V] if sig != 0.0 else 0.0
                ca = np.cos(alpha)
                ke_in = 0.5 * vin * vin + vin * R * ca * thd1 + 2.0 / 3.0 * R * R * thd1 * thd1
                w = r * thd1 + 0.75 * ca / R * vin
                st[TH] = 0.0
                st[V] = 0.0
                if -s * w <= REST_VELOCITY * p * alpha:
                    st[W_IMP] += ke_in
                    st[MODE] = 0.0
                    st[SIG] = 0.0
                    classify(st, par, a1, g)
                else:
                    st[W_IMP] += ke_in - 2.0 / 3.0 * R * R * w * w
                    st[MODE] = -s
                    st[THD] = w
                    if not _stuck_or_slip(st, par, a1, g):
                        st[ERR] = FLIGHT
                        st[ERR_T] = t_part + s0
                        return False
            elif kind == 4:
                # the friction limit: the corner slips, σ = −sgn F
                st[TH] = th1
                st[THD] = thd1
                F, _ = rock_forces(s, th1, thd1, a1, par, g)
                st[SIG] = -1.0 if F > 0.0 else 1.0
                st[V] = 0.0
            else:
                # the slip stops: stuck if the friction holds the corner, else it slips back
                st[TH] = th1
                st[THD] = thd1
                st[V] = 0.0
                if not _stuck_or_slip(st, par, a1, g):
                    st[ERR] = FLIGHT
                    st[ERR_T] = t_part + s0
                    return False
                if st[SIG] == sig:
                    st[ERR] = INCONSISTENT
                    st[ERR_T] = t_part + s0
                    return False
            if mode_code(st) != (ROCK if sig == 0.0 else SLIDE_ROCK):
                _log(st, t_part + s0)
            fresh = True
        events += 1
        if events > max_events:
            return False
    return True


@njit(cache=True)
def workspace(K, D):
    """Scratch rows of :func:`_part` and the root-isolation work."""
    n = max(K, D) + 4
    return np.zeros((18, n)), scratch(max(K, D) + 3)


@njit(cache=True)
def block_through(st, par, c, K, L, t0, g, D, max_events, cs, WS, work):
    """Advance one block through a segment ``[0, L]`` of the floor motion starting at time
    ``t0`` (acceleration coefficients ``c[0..K]``), in parts with ``p·L ≤`` :data:`PHASE`. An
    event limit reached is recorded in ``st[LIMIT_AT]``; the block stops there, as at an error or
    its overturning."""
    parts = max(1, int(np.ceil(par[P_P] * L / PHASE - 1e-12)))
    Lq = L / parts
    for qq in range(parts):
        if qq == 0:
            for j in range(K + 1):
                cs[j] = c[j]
        else:
            taylor_shift(c, K, qq * Lq, cs)
        ok = _part(st, par, cs, K, Lq, t0 + qq * Lq, g, D, max_events, WS, work)
        if not ok:
            if st[ERR] == 0.0 and st[LIMIT_AT] < 0.0:
                st[LIMIT_AT] = t0
            return False
        if st[MODE] == OVERTURNED:
            return True
    return True


@njit(cache=True)
def sliderock_on_poly(t0, length, step, ends, C, par, states, g, D, max_events, hist):
    """Advance blocks standing on one floor through one chunk of a poly motion's segments: on
    segment ``i`` the floor's acceleration is ``Σ_j C[i, j] τ^j``, ``τ ∈ [0, length[i]]``. A
    block at rest is skipped while the coefficients' bound stays at or below its rest level.
    With ``hist`` of shape ``(n_blocks, 3, npts)``: ``θ``, ``U`` and the mode code at the
    samples (``θ`` and ``U`` NaN once overturned or stopped by an error)."""
    K = C.shape[1] - 1
    nb = par.shape[0]
    WS, work = workspace(K, D)
    c = np.zeros(K + 1)
    cs = np.zeros(K + 1)
    want = hist.shape[0] == nb and nb > 0
    for i in range(t0.size):
        L = length[i]
        reach = 0.0
        for j in range(K, -1, -1):
            c[j] = C[i, j]
            reach = reach * L + abs(c[j])
        for b in range(nb):
            st = states[b]
            if st[MODE] == OVERTURNED or st[ERR] != 0.0 or st[LIMIT_AT] >= 0.0:
                continue
            pb = par[b]
            if st[MODE] == 0.0 and st[SIG] == 0.0 and reach <= g * min(pb[P_MUS], pb[P_TAN]):
                st[T_MODE + REST] += L
                continue
            block_through(st, pb, c, K, L, t0[i], g, D, max_events, cs, WS, work)
        if want and ends[i]:
            k = step[i] + 1
            for b in range(nb):
                st = states[b]
                bad = st[ERR] != 0.0 or st[LIMIT_AT] >= 0.0
                gone = st[MODE] == OVERTURNED or bad
                hist[b, 0, k] = np.nan if gone else st[TH]
                hist[b, 1, k] = np.nan if gone else st[U]
                hist[b, 2, k] = mode_code(st)
