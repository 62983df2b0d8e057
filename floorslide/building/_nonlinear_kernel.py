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
from floorslide.contents._kernels import objects_on_substep
from floorslide.contents._oscillator_kernel import O_MODE, O_U, O_Z, O_ZD, _advance_part, _shift
from floorslide.contents._rocking_kernel import MODE as RK_MODE
from floorslide.contents._rocking_kernel import OVERTURNED as RK_OVERTURNED
from floorslide.contents._rocking_kernel import P_P, P_TAN, block_through
from floorslide.contents._rocking_kernel import ROCK_MAX_EVENTS as RK_MAX_EVENTS
from floorslide.contents._rocking_kernel import TH as RK_TH
from floorslide.numerics.polynomial import (
    max_abs_on,
    poly_val,
    rise_within,
    scratch,
)

# branch codes: as floorslide.building.isolators
LINEAR, ELASTIC, PLASTIC_POS, PLASTIC_NEG, SLIP_POS, SLIP_NEG, STICK = 0, 1, 2, 3, 4, 5, 6
NO_EVENT = 1e300
BLOCK_MAX_EVENTS = 10000
FLEX_MAX_EVENTS = 1000
"""Most friction events of a block / a 2-DOF oscillator in one segment or part (as
``floorslide.contents.events``)."""
"""Most friction events of a block in one segment (as ``floorslide.contents.events``)."""
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


@njit(cache=True, inline="always")
def _bound_on(p, deg, L):
    """``Σ_j |p_j| L^j ≥ max|p|`` on ``[0, L]``."""
    s = 0.0
    for j in range(deg, -1, -1):
        s = s * L + abs(p[j])
    return s


@njit(cache=True, inline="always")
def _pack_segment(XW, pk, x, y, a0, a1, slope, L, t0, g):
    """Into the block pass's packed arguments: the building's states at a segment's ends, the
    ground's values and slope there, its length and start time, and the normal force's
    integrals over it (no vertical shaking: ``N = g``)."""
    for j in range(x.size):
        XW[0, j] = x[j]
        XW[1, j] = y[j]
    pk[0], pk[1], pk[2], pk[3], pk[4] = a0, a1, slope, L, t0
    pk[13] = g * L
    pk[14] = g * L * L / 2.0


@njit(cache=True, inline="always")
def _blocks_substep(G, OR, OB, m, XW, BLK, MU, bstates, buf, rw, pk, flags, n, h):
    """Advance the rigid blocks through a whole sub-step without events of the building, or a
    segment of one of length ``h`` (the curvature-tail weights of the whole sub-step in ``G``
    bound a shorter segment too), floor by floor, as on a linear building
    (:func:`floorslide.contents._kernels.objects_on_substep`: closed forms where a rigorous
    enclosure of the floor acceleration decides, the event-driven step otherwise).

    ``XW[0], XW[1]``: the building's states at the segment's ends (branch matrices ``m``);
    ``pk[0:5]``, ``pk[9:16]``: ground values, slope, ``h``, start time and the normal force's
    terms, set by the caller. Block ``i`` stands on floor ``BLK[1, i]`` (state index), output
    row ``BLK[0, i]`` (sorted); the floor's relative displacement and velocity are the states
    ``f`` and ``n + f``. Arguments packed as the block pass wants them (few fields per call)."""
    N = XW.shape[1]
    nblk = BLK.shape[1]
    aa, ab, slope = pk[0], pk[1], pk[2]
    i0 = 0
    while i0 < nblk:
        o = BLK[0, i0]
        i1 = i0
        while i1 < nblk and BLK[0, i1] == o:
            i1 += 1
        f = BLK[1, i0]
        for j in range(N):
            XW[2, j] = G[m, o + 1, TIGHT, j]
        pk[5] = G[m, o + 1, TIGHT, N]
        pk[6] = G[m, o + 1, TIGHT, N + 1]
        vr0 = XW[0, n + f]
        pk[7] = XW[1, n + f] - vr0 + 0.5 * h * (aa + ab)
        dD = XW[1, f] - XW[0, f] - vr0 * h
        pk[8] = dD + aa * h * h / 2.0 + slope * h * h * h / 6.0
        flags[4] = i0
        flags[5] = i1
        objects_on_substep(OR[m, o], OB[m, o], XW, MU, bstates, buf, rw, pk, flags)
        i0 = i1


@njit(cache=True, inline="always")
def _rider_series(cs, K, D, z2w, w2, q, v, d, dv):
    """Taylor series of a rider on a part from its state ``(q, q')`` there, driven by the floor
    polynomial ``cs`` (degree ``K``, shifted to the part's start): ``d_0 = q, d_1 = q'``,
    ``d_{k+2} = −(c_k + 2ξω(k+1) d_{k+1} + ω² d_k)/((k+1)(k+2))`` up to degree ``D``, and its
    derivative's coefficients ``dv`` (degree ``D − 1``)."""
    d[0] = q
    d[1] = v
    for k in range(D - 1):
        ck = cs[k] if k <= K else 0.0
        d[k + 2] = -(ck + z2w * (k + 1) * d[k + 1] + w2 * d[k]) / ((k + 1) * (k + 2))
    for j in range(D):
        dv[j] = (j + 1) * d[j + 1]
    dv[D] = 0.0


@njit(cache=True)
def _oscillators(OR, OB, x, a_s, slope, L, K, osc_out, osc_w, osc_xi, osc_rho, S, P, D, c,
                 CS, d, dv, da, work):  # fmt: skip
    """Advance linear oscillators through a segment ``[0, L]`` on the floors of output rows
    ``osc_out``: ``q'' + 2ξω q' + ω² q = −a_f(τ)`` with ``a_f`` the floor's Taylor polynomial
    (degree ``K``). Oscillator ``i`` goes through the segment in equal parts no longer than
    ``MAX_PHASE/osc_rho[i]`` (its own ``ρ·h ≤ 0.5``; the building keeps its own sub-steps):
    on a part starting at ``τ_b`` the floor polynomial is shifted there (``CS``, one shift per
    floor and part grid: oscillators come sorted by floor, then by ``osc_rho``) and ``q`` is
    the series ``Σ d_j s^j`` of :func:`_rider_series` (exact to rounding at degree ``D``).
    ``S[:, i] = (q, q')`` in/out; ``P[:, i]`` the peaks of ``|q|``, ``|q'|`` and of the
    absolute acceleration ``|ω² q + 2ξω q'|``, searched inside a part only when the bound
    ``Σ|d_j| h^j`` exceeds the peak so far.

    This is the series path: segments of a sub-step with an event of the building, and every
    sub-step when :func:`nonlinear_run` is told so (``osc_fast`` false); full sub-steps
    otherwise take :func:`_riders_fast`."""
    last = -1
    last_parts = -1
    for i in range(osc_w.size):
        o = osc_out[i]
        if o != last:
            taylor_coefficients(OR[o], OB[o], x, a_s, slope, c)
            last = o
            last_parts = -1
        parts = max(1, int(np.ceil(L * osc_rho[i] / 0.5 - 1e-12)))
        hp = L / parts
        if parts != last_parts:
            for sp in range(parts):
                _shift(c, K, sp * hp, CS[sp])
            last_parts = parts
        w = osc_w[i]
        z2w = 2.0 * osc_xi[i] * w
        w2 = w * w
        for sp in range(parts):
            _rider_series(CS[sp], K, D, z2w, w2, S[0, i], S[1, i], d, dv)
            for j in range(D + 1):
                da[j] = -(w2 * d[j] + z2w * dv[j])
            if _bound_on(d, D, hp) > P[0, i]:
                v, _ = max_abs_on(d, D, hp, P[0, i], work)
                if v > P[0, i]:
                    P[0, i] = v
            if _bound_on(dv, D - 1, hp) > P[1, i]:
                v, _ = max_abs_on(dv, D - 1, hp, P[1, i], work)
                if v > P[1, i]:
                    P[1, i] = v
            if _bound_on(da, D, hp) > P[2, i]:
                v, _ = max_abs_on(da, D, hp, P[2, i], work)
                if v > P[2, i]:
                    P[2, i] = v
            S[0, i] = poly_val(d, D, hp)
            S[1, i] = poly_val(dv, D - 1, hp)


# rows of the riders' constants (see _rider_weights): ω, ω², 2ξω, 1/ω², 2ξ/ω³, ξω, 1/ω_d,
# bounds of ∫_0^h |g| for g the impulse responses of q, q' and ω²q + 2ξωq', and 1 where the
# filter of _rider_flags applies (ξ < 1), else 0
R_W, R_W2, R_C2, R_IW2, R_AS, R_XIW, R_IWD, R_IH0, R_IH1, R_IH2, R_OK = range(11)
NRC = 11
MARGIN = 1.0 + 1e-6
"""Relative margin of the bounds of :func:`_rider_flags` (for the rounding of the values they
are formed from)."""


@njit(cache=True)
def _rider_weights(OR, OB, h, osc_out, osc_w, osc_xi, osc_rho, D):
    """The riders' exact update over a full sub-step of length ``h`` on each branch, and the
    constants of their peak filter (:func:`_rider_flags`).

    On a sub-step without events the floor acceleration is linear in the building's start
    state ``x``, the ground value ``a`` at the start and the ground's slope ``s``, and so is a
    rider's response: ``(q, q')(h) = Φ·(q, q')(0) + W_m·[x; a; s]``. ``PH[:, i]`` holds
    ``Φ`` (``Φ00, Φ01, Φ10, Φ11``) and ``OW[m, :, :, i]`` the ``2 × (N + 2)`` weights
    ``W_m`` of branch ``m``, made by superposition: the series update of :func:`_oscillators`
    (linear in its inputs) run on unit inputs, in the same parts. ``RC[:, i]``: the
    constants (rows ``R_*``)."""
    nb, N = OR.shape[0], OR.shape[3]
    K = OR.shape[2] - 1
    nosc = osc_w.size
    PH = np.zeros((4, nosc))
    OW = np.zeros((nb, 2, N + 2, nosc))
    RC = np.zeros((NRC, nosc))
    c = np.zeros(K + 1)
    cs = np.zeros(K + 1)
    d = np.zeros(D + 2)
    dv = np.zeros(D + 2)
    e = np.zeros(N)
    for i in range(nosc):
        w = osc_w[i]
        xi = osc_xi[i]
        z2w = 2.0 * xi * w
        w2 = w * w
        parts = max(1, int(np.ceil(h * osc_rho[i] / 0.5 - 1e-12)))
        hp = h / parts
        # Φ: the free response to a unit q, then a unit q'
        for col in range(2):
            q = 1.0 if col == 0 else 0.0
            v = 1.0 - q
            for j in range(K + 1):
                cs[j] = 0.0
            for _ in range(parts):
                _rider_series(cs, K, D, z2w, w2, q, v, d, dv)
                q = poly_val(d, D, hp)
                v = poly_val(dv, D - 1, hp)
            PH[col, i] = q
            PH[2 + col, i] = v
        # W_m: the response from rest to a unit x_j, a, s
        o = osc_out[i]
        for m in range(nb):
            for col in range(N + 2):
                for j in range(N):
                    e[j] = 0.0
                a = 0.0
                s = 0.0
                if col < N:
                    e[col] = 1.0
                elif col == N:
                    a = 1.0
                else:
                    s = 1.0
                taylor_coefficients(OR[m, o], OB[m, o], e, a, s, c)
                q = 0.0
                v = 0.0
                for sp in range(parts):
                    _shift(c, K, sp * hp, cs)
                    _rider_series(cs, K, D, z2w, w2, q, v, d, dv)
                    q = poly_val(d, D, hp)
                    v = poly_val(dv, D - 1, hp)
                OW[m, 0, col, i] = q
                OW[m, 1, col, i] = v
        RC[R_W, i] = w
        RC[R_W2, i] = w2
        RC[R_C2, i] = z2w
        RC[R_IW2, i] = 1.0 / w2
        RC[R_AS, i] = 2.0 * xi / (w2 * w)
        RC[R_XIW, i] = xi * w
        if xi < 1.0:
            wd = w * np.sqrt(1.0 - xi * xi)
            RC[R_IWD, i] = 1.0 / wd
            RC[R_IH0, i] = h * min(0.5 * h, 1.0 / wd)
            RC[R_IH1, i] = h * w / wd
            RC[R_IH2, i] = h * w2 / wd
            RC[R_OK, i] = 1.0
    return PH, OW, RC


@njit(cache=True, _nrt=False)
def _rider_flags(i0, i1, S, P, PH, U, RC, S0, FL, f0, f1, fdev, h):
    """The update and peak filter of :func:`_riders_fast` for the riders ``i0 … i1 − 1`` of
    one floor on a full sub-step of length ``h``: ``S[:, i] ← Φ_i S[:, i] + U[:, i]``
    (``U = W_m·[x; a; s]``; the start state is kept in ``S0``), the peaks raised to the end
    values, and ``FL[i]`` the quantities whose peak may still grow inside the sub-step (bit 0:
    ``|q|``, bit 1: ``|q'|``, bit 2: ``|A|``, ``A = ω² q + 2ξω q'``); returns the number of
    flags set.

    The floor acceleration is ``f0, f1`` at the ends and deviates from the chord between them
    by ``δ(τ)``, ``|δ| ≤ fdev = h²/8·M_f`` (``M_f ≥ max|a_f''|``, the building's bound), so
    ``|a_f| ≤ max(|f0|, |f1|) + fdev``, ``|δ''| ≤ M_f`` and ``|δ'| ≤ h·M_f`` (``δ`` vanishes
    at both ends, so ``δ'`` vanishes in between). Inside the sub-step
    ``q = α + βτ + e(τ) + q_δ(τ)``: the particular solution for the chord (``β = −ṡ/ω²``,
    ``α = 2ξṡ/ω³ − f0/ω²``, ``ṡ`` its slope; no second derivative), a damped free vibration
    ``e = Re(C e^{λτ})`` (``|λ| = ω``) with ``|e^(k)| ≤ |C| ω^k`` and
    ``|(ω² e + 2ξω e')^(k)| ≤ |C|·|ω² + 2ξωλ|·ω^k = |C| ω^(k+2)``, and the response from rest
    to the deviation, ``|q_δ| ≤ fdev·∫_0^h|g_0|``, ``|q_δ'| ≤ fdev·∫_0^h|g_1|``,
    ``|A_δ| ≤ fdev·∫_0^h|g_A|`` (impulse responses bounded by ``|g_0| ≤ min(t, 1/ω_d)``,
    ``|g_1| ≤ ω/ω_d``, ``|g_A| = |ω² g_0 + 2ξω g_1| ≤ ω²/ω_d``), and from its equation
    ``q_δ'' = −δ − A_δ``, ``q_δ''' = −δ' − ω² q_δ' − 2ξω q_δ''``,
    ``q_δ⁗ = −δ'' − ω² q_δ'' − 2ξω q_δ'''``: bounds ``D_2, D_3, D_4``. A quantity is flagged
    only when all three tests fail:

    - its bound (``max|α + βτ| + |C| + |q_δ|^``, ``|β| + ω|C| + |q_δ'|^``,
      ``max(|f0|, |f1|) + ω²|C| + |A_δ|^``) exceeds its peak;
    - its end values plus its chord deviation ``h²/8·max|f''|`` exceed the peak
      (``|q''| ≤ ω²|C| + D_2``, ``|q'''| ≤ ω³|C| + D_3``,
      ``|A''| ≤ ω⁴|C| + ω² D_2 + 2ξω D_3``);
    - its derivative may vanish inside: it changes sign between the ends, or an end value is
      within the derivative's own chord deviation of zero (``h²/8`` times ``|q'''|^``,
      ``|q⁗| ≤ ω⁴|C| + D_4``, ``|A'''| ≤ ω⁵|C| + ω² D_3 + 2ξω D_4``). A derivative of one
      sign at both ends farther from zero than its chord deviation cannot vanish: the
      quantity is monotone and its ends, already in the peak, are its extremes.

    Riders with ``ξ ≥ 1`` are always flagged (row ``R_OK``). The bounds carry the relative
    margin :data:`MARGIN`. Three loops (update, peaks at the ends, filter) so that each
    writes few arrays and the compiler vectorises the filter. Compiled without reference
    counting."""
    k8 = 0.125 * h * h * MARGIN
    fsl = (f1 - f0) / h
    amax = max(abs(f0), abs(f1))
    mf = 8.0 * fdev / (h * h)  # the bound of |a_f''|
    Sq, Sv, S0q, S0v = S[0], S[1], S0[0], S0[1]
    Pd, Pv, Pa = P[0], P[1], P[2]
    for i in range(i0, i1):
        q0 = Sq[i]
        v0 = Sv[i]
        S0q[i] = q0
        S0v[i] = v0
        Sq[i] = PH[0, i] * q0 + PH[1, i] * v0 + U[0, i]
        Sv[i] = PH[2, i] * q0 + PH[3, i] * v0 + U[1, i]
    for i in range(i0, i1):
        Pd[i] = max(Pd[i], abs(Sq[i]))
        Pv[i] = max(Pv[i], abs(Sv[i]))
        Pa[i] = max(Pa[i], abs(RC[R_W2, i] * Sq[i] + RC[R_C2, i] * Sv[i]))
    nf = 0
    for i in range(i0, i1):
        q0 = S0q[i]
        v0 = S0v[i]
        q1 = Sq[i]
        v1 = Sv[i]
        w = RC[R_W, i]
        w2 = RC[R_W2, i]
        c2 = RC[R_C2, i]
        A0 = w2 * q0 + c2 * v0
        A1 = w2 * q1 + c2 * v1
        iw2 = RC[R_IW2, i]
        bet = -fsl * iw2
        alp = fsl * RC[R_AS, i] - f0 * iw2
        e0 = q0 - alp
        ci = (v0 - bet + RC[R_XIW, i] * e0) * RC[R_IWD, i]
        cm = np.sqrt(e0 * e0 + ci * ci) * MARGIN
        # the response to the deviation and its derivatives
        dq = fdev * RC[R_IH0, i]
        dv = fdev * RC[R_IH1, i]
        da = fdev * RC[R_IH2, i]
        d2 = fdev + da
        d3 = h * mf + w2 * dv + c2 * d2
        d4 = mf + w2 * d2 + c2 * d3
        w3 = w2 * w
        w4 = w2 * w2
        bd = (max(abs(alp), abs(alp + bet * h)) + cm + dq) * MARGIN
        bv = (abs(bet) + w * cm + dv) * MARGIN
        ba = (amax + w2 * cm + da) * MARGIN
        m2 = w2 * cm + d2
        m3 = w3 * cm + d3
        m4 = w4 * cm + d4
        m2a = w4 * cm + w2 * d2 + c2 * d3
        m3a = w4 * w * cm + w2 * d3 + c2 * d4
        d0 = -(f0 + A0)
        d1 = -(f1 + A1)
        ad0 = w2 * v0 + c2 * d0
        ad1 = w2 * v1 + c2 * d1
        zd = (v0 * v1 <= 0.0) | (min(abs(v0), abs(v1)) <= k8 * m3)
        zv = (d0 * d1 <= 0.0) | (min(abs(d0), abs(d1)) <= k8 * m4)
        za = (ad0 * ad1 <= 0.0) | (min(abs(ad0), abs(ad1)) <= k8 * m3a)
        pd = Pd[i]
        pv = Pv[i]
        pa = Pa[i]
        ld = max(abs(q0), abs(q1)) + k8 * m2 > pd
        lv = max(abs(v0), abs(v1)) + k8 * m3 > pv
        la = max(abs(A0), abs(A1)) + k8 * m2a > pa
        no = RC[R_OK, i] == 0.0
        fd = ((bd > pd) & ld & zd) | no
        fv = ((bv > pv) & lv & zv) | no
        fa = ((ba > pa) & la & za) | no
        f = fd + 2 * fv + 4 * fa
        FL[i] = f
        nf += f
    return nf


@njit(cache=True, _nrt=False)
def _riders_fast(m, GT, OR, OB, OW, x, ax, aa, slope, h, K, z0, z1, osc_out, osc_w, osc_xi,
                 osc_rho, S, P, D, PH, RC, Z, U, S0, FL, c, CS, d, dv, da, work,
                 stats):  # fmt: skip
    """Advance the riders through a full sub-step without events (the common case) by their
    exact linear update, and search inside it only the quantities whose peak a rigorous
    filter cannot rule out (:func:`_rider_flags`), floor by floor.

    ``OW[m]``: the weights ``W_m`` of branch ``m`` (:func:`_rider_weights`), applied to
    ``Z = [x; a; s]``; ``z0[o + 1]``, ``z1[o + 1]``: the floor acceleration (output row ``o``)
    at the sub-step's ends (:func:`_fast_substep`); its chord deviation is the building's
    tight bound (:func:`_tight_deviation`; ``GT[m]`` the branch's chord rows). A flagged
    quantity is searched as in :func:`_oscillators` (the series from the start state ``S0``,
    in the same parts, a part only when its bound ``Σ|d_j| h^j`` exceeds the peak); the end
    state stays the update's. ``stats`` counts sub-steps, rider·sub-steps, flagged
    rider·sub-steps and polynomial searches. Compiled without reference counting (it runs on
    every sub-step; the branch's blocks are taken here, where views cost nothing)."""
    GTm, ORm, OBm, OWm = GT[m], OR[m], OB[m], OW[m]
    N = x.size
    nosc = osc_w.size
    for j in range(N):
        Z[j] = x[j]
        ax[j] = abs(x[j])
    Z[N] = aa
    Z[N + 1] = slope
    stats[0] += 1
    stats[1] += nosc
    i0 = 0
    while i0 < nosc:
        o = osc_out[i0]
        i1 = i0
        while i1 < nosc and osc_out[i1] == o:
            i1 += 1
        for r in range(2):
            for i in range(i0, i1):
                U[r, i] = 0.0
            for j in range(N + 2):
                zj = Z[j]
                for i in range(i0, i1):
                    U[r, i] += OWm[r, j, i] * zj
        fdev = _tight_deviation(GTm, o + 1, x, ax, aa, slope, h)
        nf = _rider_flags(i0, i1, S, P, PH, U, RC, S0, FL, z0[o + 1], z1[o + 1], fdev, h)
        if nf > 0:
            taylor_coefficients(ORm[o], OBm[o], x, aa, slope, c)
            last_parts = -1
            for i in range(i0, i1):
                fl = FL[i]
                if fl == 0:
                    continue
                stats[2] += 1
                parts = max(1, int(np.ceil(h * osc_rho[i] / 0.5 - 1e-12)))
                hp = h / parts
                if parts != last_parts:
                    for sp in range(parts):
                        _shift(c, K, sp * hp, CS[sp])
                    last_parts = parts
                w = osc_w[i]
                z2w = 2.0 * osc_xi[i] * w
                w2 = w * w
                q = S0[0, i]
                v = S0[1, i]
                for sp in range(parts):
                    _rider_series(CS[sp], K, D, z2w, w2, q, v, d, dv)
                    if fl & 1 and _bound_on(d, D, hp) > P[0, i]:
                        stats[3] += 1
                        val, _ = max_abs_on(d, D, hp, P[0, i], work)
                        if val > P[0, i]:
                            P[0, i] = val
                    if fl & 2 and _bound_on(dv, D - 1, hp) > P[1, i]:
                        stats[3] += 1
                        val, _ = max_abs_on(dv, D - 1, hp, P[1, i], work)
                        if val > P[1, i]:
                            P[1, i] = val
                    if fl & 4:
                        for j in range(D + 1):
                            da[j] = -(w2 * d[j] + z2w * dv[j])
                        if _bound_on(da, D, hp) > P[2, i]:
                            stats[3] += 1
                            val, _ = max_abs_on(da, D, hp, P[2, i], work)
                            if val > P[2, i]:
                                P[2, i] = val
                    if sp + 1 < parts:
                        q = poly_val(d, D, hp)
                        v = poly_val(dv, D - 1, hp)
        i0 = i1


@njit(cache=True)
def _flexible(OR, OB, x, a_s, slope, L, K, t_abs, o2, w2, xi2, r2, g, mub2, muk2, S2, ho2, K2,
              c2, cs, Y, poly, y, pk, work2):  # fmt: skip
    """Advance 2-DOF sliding oscillators (one kind, many friction pairs) through a segment
    ``[0, L]`` on the floor of output row ``o2``: in parts no longer than ``ho2`` (where the
    oscillator's phases have ``ρ·h ≤ 0.5``), each by the 2-DOF kernel's own exact event-driven
    step (:func:`floorslide.contents._oscillator_kernel._advance_part`)."""
    kr = OR.shape[1] - 1
    for j in range(K2 + 1):
        c2[j] = 0.0
    taylor_coefficients(OR[o2], OB[o2], x, a_s, slope, c2[: kr + 1])
    parts = max(1, int(np.ceil(L / ho2 - 1e-12)))
    hp = L / parts
    for sp in range(parts):
        base = sp * hp
        for o in range(muk2.size):
            _advance_part(c2, K2, base, hp, o, w2, xi2, r2, g, mub2, muk2, S2, t_abs + base,
                          FLEX_MAX_EVENTS, cs, Y, poly, y, pk, work2)  # fmt: skip


# columns of a function's chord-bound row (see _chord_rows), after its N state coefficients
VALUE, C2, C3, TIGHT, LOOSE = 0, 1, 2, 3, 4


@njit(cache=True)
def _rockers(OR, OB, x, a0, slope, L, K, t0, rk_out, rk_par, rk_states, g, D, nonlinear, phase,
             max_events, RB):  # fmt: skip
    """Advance the rocking blocks riding along through a segment ``[0, L]`` of the building
    from state ``x`` (ground ``a0 + slope·τ``): block ``i`` stands on the floor of output row
    ``rk_out[i]`` (sorted), parameters ``rk_par[i]`` and state ``rk_states[i]`` (the columns
    of :mod:`floorslide.contents._rocking_kernel`); each goes through the segment in parts
    with ``p·L ≤ phase`` (:func:`~floorslide.contents._rocking_kernel.block_through`).
    ``RB``: scratch rows (floor coefficients and their shifts, the series of θ, sin, cos, u, a
    polynomial, the root-isolation work)."""
    c, cs, cw = RB[0, : K + 1], RB[1, : K + 1], RB[2, : K + 1]
    t, S, C, u = RB[3, : D + 1], RB[4, : D + 1], RB[5, : D + 1], RB[6, : D + 1]
    q = RB[7]
    work = RB[8:]
    last = -1
    reach = 0.0
    for i in range(rk_out.size):
        st = rk_states[i]
        if st[RK_MODE] == RK_OVERTURNED:
            continue
        o = rk_out[i]
        if o != last:
            taylor_coefficients(OR[o], OB[o], x, a0, slope, c)
            last = o
            reach = 0.0
            for j in range(K, -1, -1):
                reach = reach * L + abs(c[j])
        par = rk_par[i]
        if st[RK_MODE] == 0.0 and reach <= g * par[P_TAN]:
            continue
        parts = max(1, int(np.ceil(par[P_P] * L / phase - 1e-12)))
        block_through(st, par, c, K, L, parts, t0, g, D, nonlinear, max_events, cs, t, S, C, u,
                      q, cw, work)  # fmt: skip


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


@njit(cache=True)
def _flexible_sample(H2, k, S2, muk2, flex, g, af):
    """Histories of the 2-DOF oscillators at record sample ``k``, as the linear path keeps them
    (:func:`floorslide.contents._oscillator_kernel.oscillator_kernel`): base slide ``u``, spring
    deformation ``z``, the top mass's absolute acceleration ``−(2ξω ż + ω² z)`` and the base's
    (the floor's `af` while stuck; the spring and kinetic friction forces over its mass while
    sliding)."""
    w, xi, r = flex[1], flex[2], flex[3]
    for o in range(S2.shape[0]):
        q_ = 2.0 * xi * w * S2[o, O_ZD] + w * w * S2[o, O_Z]
        H2[o, k, 0] = S2[o, O_U]
        H2[o, k, 1] = S2[o, O_Z]
        H2[o, k, 2] = -q_
        mode = S2[o, O_MODE]
        if mode == 0.0:
            H2[o, k, 3] = af
        else:
            H2[o, k, 3] = q_ / r - mode * muk2[o] * g * (1.0 + r) / r


@njit(cache=True, _nrt=False)
def _fast_step(m, branch, PHT, PP, QQ, G, GT, x, y, ax, aa, ab, slope, h, iF, kk, dy, musW, peak,
               t_peak, t0, z0, z1, need, dl, z_valid):  # fmt: skip
    """One sub-step of :func:`_fast_run` when something rides along (the caller advances the
    riders): the exact step to ``y``, then :func:`_fast_substep`; ``z0`` formed first unless
    `z_valid`. Compiled without reference counting, apart from the caller's loop."""
    _foh_t(PHT[m], PP[m], QQ[m], x, aa, ab, y)
    p = -x[iF] / kk if branch == ELASTIC else 0.0
    if not z_valid:
        Gm = G[m]
        for f in range(z0.size):
            z0[f] = _value(Gm[f], x, aa)
    return _fast_substep(
        branch, GT[m], x, y, ax, aa, ab, slope, h, p, dy, musW, peak, t_peak, t0, z0, z1, need, dl
    )


@njit(cache=True, _nrt=False)
def _fast_run(k, r, substeps, mat_of, PHT, PP, QQ, G, GT, acc, h, x, y, ax, branch, iF, kk, dy,
              musW, peak, t_peak, z0, z1, need, dl, z_valid, X, BR, Yo, want_outputs, out,
              riders, OR, OB, K, osc_out, osc_w, osc_xi, osc_rho, osc_S, osc_P, D, PH, OW, RC,
              oZ, oU, oS0, oFL, oax, co, CS, d, dv, da, ow, osc_stats):  # fmt: skip
    """The sub-steps of a building with nothing riding along but linear oscillators (when
    `riders`; advanced by :func:`_riders_fast`, the arguments from ``OR`` on), from sub-step
    ``r`` of record step ``k`` on, in one compiled loop while :func:`_fast_substep` clears
    them (no event, no output search); the samples ``X``, ``BR``, ``Yo`` are written as it
    goes. It stops
    before a sub-step the bound cannot clear (``out = [k, r, -1]``, the state untouched) or
    after one whose outputs need a search (``out = [k, r, count]``: ``x`` the start state,
    ``y`` the end, ``z1`` the functions' end values; the caller finishes that sub-step);
    ``out[2] = -2`` at the record's end. ``PHT``: the transition matrices transposed
    (:func:`_foh_t`); ``GT``: :func:`_chord_rows` with the functions last. Compiled without
    reference counting: the views made here cost nothing."""
    npts = acc.size
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
    while k < npts - 1:
        a = acc[k]
        a1 = acc[k + 1]
        slope = (a1 - a) / (substeps * h)
        while r < substeps:
            aa = a + (a1 - a) * (r / substeps)
            ab = a + (a1 - a) * ((r + 1) / substeps) if r + 1 < substeps else a1
            t0 = (k * substeps + r) * h
            _foh_t(pht, pp, qq, x, aa, ab, y)
            p = -x[iF] / kk if branch == ELASTIC else 0.0
            ns = _fast_substep(branch, GTm, x, y, ax, aa, ab, slope, h, p, dy, musW, peak, t_peak,
                               t0, z0, z1, need, dl)  # fmt: skip
            if ns != 0:
                out[0], out[1], out[2] = k, r, ns
                return
            if riders:
                _riders_fast(m, GT, OR, OB, OW, x, oax, aa, slope, h, K, z0, z1, osc_out,
                             osc_w, osc_xi, osc_rho, osc_S, osc_P, D, PH, RC, oZ, oU, oS0,
                             oFL, co, CS, d, dv, da, ow, osc_stats)  # fmt: skip
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
    out[0], out[1], out[2] = k, r, -2


@njit(cache=True)
def nonlinear_run(
    mat_of,
    PHI,
    PP,
    QQ,
    RR,
    BB,
    ER,
    EB,
    OR,
    OB,
    K,
    consts,
    acc,
    substeps,
    h,
    x0,
    branch0,
    X,
    BR,
    ev_row,
    ev_tau,
    ev_branch,
    peak,
    t_peak,
    max_events,
    blk_out,
    blk_floor,
    mub,
    muk,
    allow_pos,
    allow_neg,
    g,
    bstates,
    n,
    hist_u,
    osc_out,
    osc_w,
    osc_xi,
    osc_rho,
    osc_S,
    osc_P,
    D,
    flex,
    mub2,
    muk2,
    S2,
    Yo,
    H2,
    rk_out,
    rk_par,
    rk_states,
    rk_D,
    rk_nonlinear,
    rk_phase,
    rk_hist,
    osc_fast,
    osc_stats,
):
    """Integrate the building over the record.

    ``mat_of[branch]`` (−1 for a branch the layer does not have) is the index of the
    branch's matrices in the stacks ``PHI, PP, QQ``
    (exact sub-step recurrence), ``RR, BB`` (full-state Taylor rows), ``ER, EB`` (the friction
    a stuck pendulum needs, as Taylor rows) and ``OR, OB`` (Taylor rows of the outputs whose
    true peaks are tracked in ``peak``/``t_peak``). ``consts = [k1 − k2, D_y, Q, mu·W,
    mu_s·W]`` and, from index 5, the linear functional of the needed friction (state
    coefficients, then the ground's). ``X[k]``/``BR[k]`` receive the state and branch at
    record sample ``k`` (memory O(samples)); events: the sub-step, the time in it and the
    branch after. Returns the number of events, or ``-1 − row`` when more than
    ``max_events`` happen in sub-step ``row``. The state is ``[u (n); u' (n); F0; extra]``:
    ``n`` degrees of freedom of the building, the layer's constant force, then states that
    ride along without acting back (response-spectrum oscillators on a floor).

    Rigid blocks ride along (none when ``muk`` is empty): block ``i`` stands on the floor of
    output row ``blk_out[i]`` (sorted; ``blk_floor[i]`` the floor's state index), friction
    ``mub``/``muk``, state ``bstates[i]`` (the columns of :mod:`floorslide.contents._kernels`),
    advanced exactly through every segment (a sub-step without events of the building as on a
    linear building, :func:`_blocks_substep`); when ``hist_u`` has a row per block, their
    slides at the samples are written there. ``Yo[k]`` (when it has a row per sample)
    receives the outputs' values at record sample ``k``; ``H2[o, k]`` (when it has a column per
    sample) the 2-DOF oscillators' histories (:func:`_flexible_sample`).
    Linear oscillators ride along the same way (none when ``osc_w`` is empty; see
    :func:`_oscillators`): the floor response spectra of the floors of rows ``osc_out``,
    states ``osc_S[:, i] = (q, q')`` and peaks ``osc_P[:, i]`` (``|q|, |q'|``, the absolute
    acceleration). With ``osc_fast`` a sub-step without events advances them by their exact
    linear update and searches only where a rigorous filter cannot rule out a new peak
    (:func:`_riders_fast`); without it every segment takes the series path. ``osc_stats``
    receives :func:`_riders_fast`'s counters.
    2-DOF sliding oscillators too (none when ``muk2`` is empty): ``flex = [row, ω, ξ, r,
    part length, degree]``, friction ``mub2``/``muk2``, states ``S2`` (the columns of
    :mod:`floorslide.contents._oscillator_kernel`).
    Rocking blocks too (none when ``rk_out`` is empty; :func:`_rockers`): on the floors of
    output rows ``rk_out`` (sorted), parameters ``rk_par``, states ``rk_states`` (the columns
    of :mod:`floorslide.contents._rocking_kernel`), series degree ``rk_D``, the full equation
    when ``rk_nonlinear``, parts of ``p·L ≤ rk_phase``; ``rk_hist[i, k]`` (when it has a row
    per block) receives ``θ`` at sample ``k`` (NaN once overturned).

    Just after an event the search for the next one starts ``EVENT_GAP·h`` later: a branch
    entered at a level crossing (a breakaway at exactly the friction limit, a stop at exactly
    zero velocity) starts on its level up to rounding, and a rounding-level sign there is not
    an event (it would switch back at once, without end). A true event that close to the last
    one is seen as ``EVENT_GAP·h`` later, a rounding-level shift.
    """
    N = x0.size
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
    nblk = muk.size
    rw = scratch(K + 3)
    # packed arguments of the block pass (see _blocks_substep)
    XW = np.zeros((3, N))
    BLK = np.empty((2, nblk), dtype=np.int64)
    MU = np.empty((2, nblk))
    for i in range(nblk):
        BLK[0, i] = blk_out[i]
        BLK[1, i] = blk_floor[i]
        MU[0, i] = mub[i]
        MU[1, i] = muk[i]
    buf = np.empty(5 * K + 17 + bstates.shape[1])
    pk = np.zeros(16)
    pk[9], pk[11], pk[12], pk[15] = g, g, g, g
    flags = np.array([0, int(allow_pos), int(allow_neg), BLOCK_MAX_EVENTS, 0, 0], dtype=np.int64)
    nosc = osc_w.size
    co = np.empty(max(K, D) + 2)
    most_parts = 1
    for i in range(nosc):
        most_parts = max(most_parts, int(np.ceil(h * osc_rho[i] / 0.5 - 1e-12)))
    CS = np.zeros((most_parts, K + 1))
    d = np.empty(D + 2)
    dv = np.empty(D + 2)
    da = np.empty(D + 2)
    ow = scratch(D + 1)
    fast_riders = nosc > 0 and osc_fast
    if fast_riders:
        PH, OW, RC = _rider_weights(OR, OB, h, osc_out, osc_w, osc_xi, osc_rho, D)
    else:
        PH, OW, RC = np.zeros((4, 0)), np.zeros((0, 2, N + 2, 0)), np.zeros((NRC, 0))
    oZ = np.zeros(N + 2)
    oU = np.zeros((2, nosc))
    oS0 = np.zeros((2, nosc))
    oFL = np.zeros(nosc, dtype=np.int64)
    oax = np.zeros(N)
    n2 = muk2.size
    o2 = int(flex[0])
    K2 = int(flex[5])
    c2 = np.zeros(K2 + 1)
    cs2 = np.zeros(K2 + 1)
    Y2 = np.zeros((4, K2 + 1))
    poly2 = np.zeros(K2 + 1)
    y2 = np.zeros(4)
    pk2 = np.zeros(4)
    work2 = scratch(K2 + 1)
    x = x0.copy()
    y = np.empty(N)
    G = _chord_rows(RR, BB, ER, EB, OR, OB, n, h, mat_of)
    nout = peak.size
    ax = np.empty(N)
    z0 = np.empty(nout + 1)  # the event function, then the outputs
    z1 = np.empty(nout + 1)
    dl = np.empty(nout + 1)
    GT = np.ascontiguousarray(G.transpose(0, 2, 3, 1))
    PHT = np.ascontiguousarray(PHI.transpose(0, 2, 1))
    need = np.zeros(nout, dtype=np.bool_)
    z_valid = False  # z0 holds the outputs' values at the sub-step's start
    branch = branch0
    npts = acc.size
    n_ev = 0
    for i in range(N):
        X[0, i] = x[i]
    BR[0] = branch
    want_outputs = Yo.shape[0] == npts
    if want_outputs:
        for i in range(nout):
            Yo[0, i] = _value(G[mat_of[branch], i + 1], x, acc[0])
    want_h2 = n2 > 0 and H2.shape[1] == npts
    if want_h2:
        af0 = _value(G[mat_of[branch], o2 + 1], x, acc[0])
        for o in range(n2):
            H2[o, 0, 3] = af0
    fresh = False
    nrk = rk_out.size
    sw = scratch(max(K, rk_D) + 2)  # the rockers' scratch rows, then their root-isolation work
    RB = np.zeros((8 + sw.shape[0], max(sw.shape[1], max(K, rk_D) + 3)))
    # nothing rides along but (with fast_riders) linear oscillators
    alone = nblk == 0 and (nosc == 0 or fast_riders) and n2 == 0 and nrk == 0
    fo = np.zeros(3, dtype=np.int64)
    k = 0
    r = 0
    while k < npts - 1:
        # a building alone (or carrying linear oscillators only) takes its common sub-steps in
        # one compiled loop (_fast_run), which
        # stops before a sub-step its bound cannot clear (then ``pre = -1``) or after one whose
        # outputs need a search (``pre = 1``; ``x`` still the start state, ``y`` the end)
        pre = 0
        if alone and not fresh:
            _fast_run(k, r, substeps, mat_of, PHT, PP, QQ, G, GT, acc, h, x, y, ax, branch, iF,
                      kk, dy, musW, peak, t_peak, z0, z1, need, dl, z_valid, X, BR, Yo,
                      want_outputs, fo, fast_riders, OR, OB, K, osc_out, osc_w, osc_xi,
                      osc_rho, osc_S, osc_P, D, PH, OW, RC, oZ, oU, oS0, oFL, oax, co, CS, d,
                      dv, da, ow, osc_stats)  # fmt: skip
            z_valid = True
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
        took_fast = False
        if not fresh:
            # the common case first: a rigorous bound shows no event on the whole sub-step;
            # then the end state is the exact step's and only the outputs whose bound allows
            # a new peak are searched
            m = mat_of[branch]
            if pre == 0:
                nsearch = _fast_step(m, branch, PHT, PP, QQ, G, GT, x, y, ax, aa, ab, slope, h,
                                     iF, kk, dy, musW, peak, t_peak, t0, z0, z1, need, dl,
                                     z_valid)  # fmt: skip
            else:
                nsearch = fo[2] if pre > 0 else -1
            if nsearch >= 0:
                for i in range(nout if nsearch > 0 else 0):
                    if need[i]:
                        _search_peak(OR[m], OB[m], i, x, aa, slope, h, K, peak, t_peak, t0,
                                     c, work)  # fmt: skip
                if nblk > 0:
                    _pack_segment(XW, pk, x, y, aa, ab, slope, h, t0, g)
                    _blocks_substep(G, OR, OB, m, XW, BLK, MU, bstates, buf, rw, pk, flags,
                                    n, h)  # fmt: skip
                if fast_riders:
                    _riders_fast(m, GT, OR, OB, OW, x, oax, aa, slope, h, K, z0, z1, osc_out,
                                 osc_w, osc_xi, osc_rho, osc_S, osc_P, D, PH, RC, oZ, oU, oS0,
                                 oFL, co, CS, d, dv, da, ow, osc_stats)  # fmt: skip
                elif nosc > 0:
                    _oscillators(OR[m], OB[m], x, aa, slope, h, K, osc_out, osc_w, osc_xi,
                                 osc_rho, osc_S, osc_P, D, co, CS, d, dv, da, ow)  # fmt: skip
                if n2 > 0:
                    _flexible(OR[m], OB[m], x, aa, slope, h, K, t0, o2, flex[1], flex[2],
                              flex[3], g, mub2, muk2, S2, flex[4], K2, c2, cs2, Y2, poly2,
                              y2, pk2, work2)  # fmt: skip
                if nrk > 0:
                    _rockers(OR[m], OB[m], x, aa, slope, h, K, t0, rk_out, rk_par, rk_states, g,
                             rk_D, rk_nonlinear, rk_phase, RK_MAX_EVENTS, RB)  # fmt: skip
                for i in range(N):
                    x[i] = y[i]
                for f in range(nout + 1):
                    z0[f] = z1[f]
                z_valid = True
                took_fast = True
        if not took_fast:
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
                    if nblk > 0:
                        _pack_segment(XW, pk, x, y, a_s, a_end, slope, L, t0 + s0, g)
                        _blocks_substep(G, OR, OB, m, XW, BLK, MU, bstates, buf, rw, pk, flags,
                                        n, L)  # fmt: skip
                    if fast_riders and events_here == 0:
                        # no event after all: a whole sub-step of one branch, as on the fast
                        # path (the functions' end values formed here)
                        for f in range(nout + 1):
                            z0[f] = _value(G[m, f], x, aa)
                            z1[f] = _value(G[m, f], y, ab)
                        _riders_fast(m, GT, OR, OB, OW, x, oax, aa, slope, h, K, z0, z1,
                                     osc_out, osc_w, osc_xi, osc_rho, osc_S, osc_P, D, PH, RC,
                                     oZ, oU, oS0, oFL, co, CS, d, dv, da, ow,
                                     osc_stats)  # fmt: skip
                    elif nosc > 0:
                        _oscillators(OR[m], OB[m], x, a_s, slope, L, K, osc_out, osc_w, osc_xi,
                                     osc_rho, osc_S, osc_P, D, co, CS, d, dv, da, ow)  # fmt: skip
                    if n2 > 0:
                        _flexible(OR[m], OB[m], x, a_s, slope, L, K, t0 + s0, o2, flex[1],
                                  flex[2], flex[3], g, mub2, muk2, S2, flex[4], K2, c2, cs2, Y2,
                                  poly2, y2, pk2, work2)  # fmt: skip
                    if nrk > 0:
                        _rockers(OR[m], OB[m], x, a_s, slope, L, K, t0 + s0, rk_out, rk_par,
                                 rk_states, g, rk_D, rk_nonlinear, rk_phase, RK_MAX_EVENTS,
                                 RB)  # fmt: skip
                    for i in range(N):
                        x[i] = y[i]
                    break
                _state_at(RR[m], BB[m], x, a_s, slope, te, K, y, c)
                _segment_peaks(G[m], GT[m], OR[m], OB[m], x, y, ax, a_s, a_s + slope * te, slope,
                               te, K, peak, t_peak, t0 + s0, c, work)  # fmt: skip
                if nblk > 0:
                    _pack_segment(XW, pk, x, y, a_s, a_s + slope * te, slope, te, t0 + s0, g)
                    _blocks_substep(G, OR, OB, m, XW, BLK, MU, bstates, buf, rw, pk, flags, n,
                                    te)  # fmt: skip
                if nosc > 0:
                    _oscillators(OR[m], OB[m], x, a_s, slope, te, K, osc_out, osc_w, osc_xi,
                                 osc_rho, osc_S, osc_P, D, co, CS, d, dv, da, ow)  # fmt: skip
                if n2 > 0:
                    _flexible(OR[m], OB[m], x, a_s, slope, te, K, t0 + s0, o2, flex[1],
                              flex[2], flex[3], g, mub2, muk2, S2, flex[4], K2, c2, cs2, Y2,
                              poly2, y2, pk2, work2)  # fmt: skip
                if nrk > 0:
                    _rockers(OR[m], OB[m], x, a_s, slope, te, K, t0 + s0, rk_out, rk_par,
                             rk_states, g, rk_D, rk_nonlinear, rk_phase, RK_MAX_EVENTS,
                             RB)  # fmt: skip
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
        if want_h2:
            if want_outputs:
                af = Yo[k + 1, o2]
            else:
                af = _value(G[mat_of[branch], o2 + 1], x, a1)
            _flexible_sample(H2, k + 1, S2, muk2, flex, g, af)
        if hist_u.shape[0] == nblk and nblk > 0:
            for i in range(nblk):
                hist_u[i, k + 1] = bstates[i, 2]
        if nrk > 0 and rk_hist.shape[0] == nrk:
            for i in range(nrk):
                if rk_states[i, RK_MODE] == RK_OVERTURNED:
                    rk_hist[i, k + 1] = np.nan
                else:
                    rk_hist[i, k + 1] = rk_states[i, RK_TH]
        k += 1
    return n_ev
