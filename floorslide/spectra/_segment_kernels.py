"""Linear oscillators (floor response spectra) on a building whose motion is a list of
segments — a building on nonlinear isolation (:class:`floorslide.building.nonlinear_motion.
NonlinearMotion`): each oscillator is advanced through every segment of the building's exact
motion, by its exact linear update on a whole sub-step without isolator events (with a rigorous
filter that leaves few sub-steps to search, :func:`_riders_fast`) and by the Taylor series of its
exact response to the floor's in-step polynomial through a segment between events
(:func:`_oscillators`). The building is integrated once, without them; they read its segments.
The oscillators go through the segments twice: first for their peaks at the ends
(:func:`peaks_at_ends`), then with the filters and searches against those peaks (see the notes
before :func:`_rider_screen`).
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import taylor_coefficients
from floorslide.building._nonlinear_kernel import _tight_deviation, _value
from floorslide.contents._oscillator_kernel import _shift
from floorslide.numerics.polynomial import max_abs_on, poly_val, scratch


@njit(cache=True, inline="always")
def _bound_on(p, deg, L):
    """``Σ_j |p_j| L^j ≥ max|p|`` on ``[0, L]``."""
    s = 0.0
    for j in range(deg, -1, -1):
        s = s * L + abs(p[j])
    return s


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
                 CS, d, dv, da, work, EV, e, use_ev):  # fmt: skip
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
    otherwise take :func:`_riders_fast`.

    With `use_ev`, ``EV[e]`` holds what the first pass found on this segment
    (:func:`peaks_at_ends`): an oscillator whose bounds there are all within its peaks takes
    the end state found then (the series would search none of its parts and end there)."""
    last = -1
    last_parts = -1
    for i in range(osc_w.size):
        if use_ev and EV[e, 2, i] <= P[0, i] and EV[e, 3, i] <= P[1, i] and EV[e, 4, i] <= P[2, i]:
            S[0, i] = EV[e, 0, i]
            S[1, i] = EV[e, 1, i]
            continue
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
    _rider_update(i0, i1, S, P, PH, U, RC, S0)
    return _rider_tests(i0, i1, S, P, RC, S0, FL, f0, f1, fdev, h)


@njit(cache=True, _nrt=False)
def _rider_update(i0, i1, S, P, PH, U, RC, S0):
    """The update of :func:`_rider_flags`: ``S[:, i] ← Φ_i S[:, i] + U[:, i]`` (start state
    kept in ``S0``) and the peaks raised to the end values. (On views of the riders' range,
    indexed from 0: a loop from a variable start is not vectorised.)"""
    Sq, Sv, S0q, S0v = S[0, i0:i1], S[1, i0:i1], S0[0, i0:i1], S0[1, i0:i1]
    Pd, Pv, Pa = P[0, i0:i1], P[1, i0:i1], P[2, i0:i1]
    ph0, ph1, ph2, ph3 = PH[0, i0:i1], PH[1, i0:i1], PH[2, i0:i1], PH[3, i0:i1]
    u0, u1 = U[0, i0:i1], U[1, i0:i1]
    rw2, rc2 = RC[R_W2, i0:i1], RC[R_C2, i0:i1]
    for i in range(i1 - i0):
        q0 = Sq[i]
        v0 = Sv[i]
        S0q[i] = q0
        S0v[i] = v0
        Sq[i] = ph0[i] * q0 + ph1[i] * v0 + u0[i]
        Sv[i] = ph2[i] * q0 + ph3[i] * v0 + u1[i]
    for i in range(i1 - i0):
        Pd[i] = max(Pd[i], abs(Sq[i]))
        Pv[i] = max(Pv[i], abs(Sv[i]))
        Pa[i] = max(Pa[i], abs(rw2[i] * Sq[i] + rc2[i] * Sv[i]))


@njit(cache=True, _nrt=False)
def _rider_inputs(OWm, Z, U, i0, i1):
    """``U[:, i] = W_m·Z`` for the riders ``i0 … i1 − 1`` (the sum over ``Z``'s entries in
    order; on views indexed from 0, as :func:`_rider_update`)."""
    for r in range(2):
        Ur = U[r, i0:i1]
        for i in range(i1 - i0):
            Ur[i] = 0.0
        for j in range(Z.size):
            zj = Z[j]
            OWj = OWm[r, j, i0:i1]
            for i in range(i1 - i0):
                Ur[i] += OWj[i] * zj


@njit(cache=True, _nrt=False)
def _rider_tests(i0, i1, S, P, RC, S0, FL, f0, f1, fdev, h):
    """The filter of :func:`_rider_flags` for riders already updated (:func:`_rider_update`)."""
    k8 = 0.125 * h * h * MARGIN
    fsl = (f1 - f0) / h
    amax = max(abs(f0), abs(f1))
    mf = 8.0 * fdev / (h * h)  # the bound of |a_f''|
    Sq, Sv, S0q, S0v = S[0, i0:i1], S[1, i0:i1], S0[0, i0:i1], S0[1, i0:i1]
    Pd, Pv, Pa = P[0, i0:i1], P[1, i0:i1], P[2, i0:i1]
    RCb = RC[:, i0:i1]
    fl = FL[i0:i1]
    nf = 0
    for i in range(i1 - i0):
        q0 = S0q[i]
        v0 = S0v[i]
        q1 = Sq[i]
        v1 = Sv[i]
        w = RCb[R_W, i]
        w2 = RCb[R_W2, i]
        c2 = RCb[R_C2, i]
        A0 = w2 * q0 + c2 * v0
        A1 = w2 * q1 + c2 * v1
        iw2 = RCb[R_IW2, i]
        bet = -fsl * iw2
        alp = fsl * RCb[R_AS, i] - f0 * iw2
        e0 = q0 - alp
        ci = (v0 - bet + RCb[R_XIW, i] * e0) * RCb[R_IWD, i]
        cm = np.sqrt(e0 * e0 + ci * ci) * MARGIN
        # the response to the deviation and its derivatives
        dq = fdev * RCb[R_IH0, i]
        dv = fdev * RCb[R_IH1, i]
        da = fdev * RCb[R_IH2, i]
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
        no = RCb[R_OK, i] == 0.0
        fd = ((bd > pd) & ld & zd) | no
        fv = ((bv > pv) & lv & zv) | no
        fa = ((ba > pa) & la & za) | no
        f = fd + 2 * fv + 4 * fa
        fl[i] = f
        nf += f
    return nf


@njit(cache=True, _nrt=False)
def _riders_fast(m, GT, OR, OB, OW, x, ax, aa, slope, h, K, z0, z1, osc_out, osc_w, osc_xi,
                 osc_rho, S, P, D, PH, RC, Z, U, S0, FL, c, CS, d, dv, da, work,
                 stats, TH, SPLIT, screen):  # fmt: skip
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
    i0 = np.int64(0)
    while i0 < nosc:
        o = osc_out[i0]
        i1 = i0
        while i1 < nosc and osc_out[i1] == o:
            i1 += 1
        _rider_inputs(OWm, Z, U, i0, i1)
        fdev = _tight_deviation(GTm, o + 1, x, ax, aa, slope, h)
        if screen:
            # the second pass: the filter only where the screen lets a sub-step through
            # (riders from `split` on have screens that let most sub-steps through: the
            # filter, vectorised, on all of them)
            _rider_update(i0, i1, S, P, PH, U, RC, S0)
            split = SPLIT[i0]
            nf = 0
            if split < i1:
                nf = _rider_tests(split, i1, S, P, RC, S0, FL, z0[o + 1], z1[o + 1], fdev, h)
            if split > i0 and _rider_screen(i0, split, S, RC, S0, FL, TH) > 0:
                for i in range(i0, split):
                    if FL[i] != 0:
                        nf += _rider_tests(
                            i, i + 1, S, P, RC, S0, FL, z0[o + 1], z1[o + 1], fdev, h
                        )
        else:
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
def oscillators_on_segments(SI, SF, SX, SY, nseg, G, GT, OR, OB, K, h, osc_out, osc_w, osc_xi,
                            osc_rho, S, P, D, fast, PH, OW, RC, stats, TH, SPLIT, screen,
                            EV):  # fmt: skip
    """Advance linear oscillators through the segments ``0 … nseg − 1`` of a building's motion
    (the arrays of :class:`~floorslide.building.nonlinear_motion.NonlinearMotion`: ``SI[s] =
    (row, branch matrices, whole sub-step, ends its sub-step)``, ``SF[s] = (a_s, a_end, slope,
    L, t)``, start and end states ``SX[s]``, ``SY[s]``). A whole sub-step of one branch takes
    the exact linear update and filter of :func:`_riders_fast` when `fast` (weights ``PH``,
    ``OW``, ``RC`` of :func:`_rider_weights`; the floor's values at the ends formed from the
    chord rows ``G``), any other segment the series of :func:`_oscillators`. ``S``/``P``: the
    oscillators' states and peaks, carried from one call to the next; ``h`` the sub-step."""
    N = SX.shape[1]
    nosc = osc_w.size
    nf = G.shape[1]
    most_parts = 1
    for i in range(nosc):
        most_parts = max(most_parts, int(np.ceil(h * osc_rho[i] / 0.5 - 1e-12)))
    CS = np.zeros((most_parts, K + 1))
    co = np.empty(max(K, D) + 2)
    d = np.empty(D + 2)
    dv = np.empty(D + 2)
    da = np.empty(D + 2)
    ow = scratch(D + 1)
    oZ = np.zeros(N + 2)
    oU = np.zeros((2, nosc))
    oS0 = np.zeros((2, nosc))
    oFL = np.zeros(nosc, dtype=np.int64)
    oax = np.zeros(N)
    z0 = np.zeros(nf)
    z1 = np.zeros(nf)
    use_ev = fast and EV.shape[0] > 0
    e = np.int64(0)
    for s in range(nseg):
        m = SI[s, 1]
        x = SX[s]
        a_s = SF[s, 0]
        slope = SF[s, 2]
        L = SF[s, 3]
        if fast and SI[s, 2] == 1:
            y = SY[s]
            a_e = SF[s, 1]
            last = -1
            for i in range(nosc):
                o = osc_out[i]
                if o != last:
                    z0[o + 1] = _value(G[m, o + 1], x, a_s)
                    z1[o + 1] = _value(G[m, o + 1], y, a_e)
                    last = o
            _riders_fast(m, GT, OR, OB, OW, x, oax, a_s, slope, L, K, z0, z1, osc_out, osc_w,
                         osc_xi, osc_rho, S, P, D, PH, RC, oZ, oU, oS0, oFL, co, CS, d, dv, da,
                         ow, stats, TH, SPLIT, screen)  # fmt: skip
        else:
            _oscillators(OR[m], OB[m], x, a_s, slope, L, K, osc_out, osc_w, osc_xi, osc_rho, S,
                         P, D, co, CS, d, dv, da, ow, EV, e, use_ev)  # fmt: skip
            e += 1


# The two passes on segments (as the linear kernel's, :mod:`floorslide.spectra._kernels`): a
# first pass (peaks_at_ends) takes every oscillator through the segments without a search and
# keeps its peaks at the sub-steps' and parts' ends, lower bounds of the true peaks; the second
# (oscillators_on_segments with `screen`) filters the whole sub-steps against those peaks, first
# by a screen (rider_thresholds: the end values against the peak less a record-wide bound of the
# chord deviation the filter of _rider_tests allows), then by that filter where the screen lets
# a sub-step through. Against the whole record's peaks the filters flag few sub-steps.
# record-wide bounds per floor row, over the whole sub-steps: max|a_f| at their ends, the
# chords' slope, the chord deviation, 8·deviation/h (h·max|a_f''|), and the sub-step
FBR_F, FBR_S, FBR_DEV, FBR_HMF, FBR_H = range(5)
NFBR = 5


@njit(cache=True, _nrt=False)
def _rider_screen(i0, i1, S, RC, S0, FL, TH):
    """Flags of the riders ``i0 … i1 − 1`` already updated (:func:`_rider_update`) whose end
    values of a quantity exceed its screen threshold ``TH`` (:func:`rider_thresholds`); a
    sub-step not flagged passes none of the tests of :func:`_rider_tests`. Returns the number of
    flags set. Branch-free: the compiler vectorises it."""
    Sq, Sv, S0q, S0v = S[0, i0:i1], S[1, i0:i1], S0[0, i0:i1], S0[1, i0:i1]
    rw2, rc2 = RC[R_W2, i0:i1], RC[R_C2, i0:i1]
    td, tv, ta = TH[0, i0:i1], TH[1, i0:i1], TH[2, i0:i1]
    fl = FL[i0:i1]
    nf = 0
    for i in range(i1 - i0):
        q0 = S0q[i]
        v0 = S0v[i]
        q1 = Sq[i]
        v1 = Sv[i]
        w2 = rw2[i]
        c2 = rc2[i]
        A0 = w2 * q0 + c2 * v0
        A1 = w2 * q1 + c2 * v1
        fd = max(abs(q0), abs(q1)) > td[i]
        fv = max(abs(v0), abs(v1)) > tv[i]
        fa = max(abs(A0), abs(A1)) > ta[i]
        f = fd + 2 * fv + 4 * fa
        fl[i] = f
        nf += f
    return nf


SCREEN_MARGIN = 1.0 + 1e-6
"""Relative margin of the screen's deviation bounds (rounding of the record-wide bounds)."""


WEAK = 0.75
"""A rider's screen is weak when a threshold is below this fraction of its peak (it would let
many sub-steps through): such riders take the filter on every sub-step."""


@njit(cache=True)
def rider_thresholds(P, RC, osc_out, FB, TH, SPLIT):
    """The screen thresholds ``TH[:, i]`` of :func:`_rider_screen` after the first pass: each
    quantity's peak at the ends ``P`` less the largest chord deviation the tests of
    :func:`_rider_tests` allow it in any whole sub-step (``h²/8`` times ``m2, m3, m2a`` there),
    bounded from ``FB`` (:func:`peaks_at_ends`, rows ``FBR_*`` per floor row): a sub-step's
    start state is an end state, so ``|q0| ≤ P[0]``, ``|q'0| ≤ P[1]``; with the largest
    ``|a_f|``, chord slope and deviation the particular solution, ``|C|`` and the deviation's
    response are bounded. Riders the filter does not apply to (``R_OK`` 0) get ``−∞``.

    ``SPLIT[i0]``, for the riders ``i0 … i1 − 1`` of one floor (sorted by their rate), is the
    first of the last run of riders whose screen is weak (:data:`WEAK`)."""
    for i in range(P.shape[1]):
        if RC[R_OK, i] == 0.0:
            TH[0, i] = -np.inf
            TH[1, i] = -np.inf
            TH[2, i] = -np.inf
            continue
        fb = osc_out[i] + 1
        w = RC[R_W, i]
        w2 = RC[R_W2, i]
        c2 = RC[R_C2, i]
        iw2 = RC[R_IW2, i]
        bet = FB[fb, FBR_S] * iw2
        alp = FB[fb, FBR_S] * RC[R_AS, i] + FB[fb, FBR_F] * iw2
        e0 = P[0, i] + alp
        ci = (P[1, i] + bet + RC[R_XIW, i] * e0) * RC[R_IWD, i]
        cm = np.sqrt(e0 * e0 + ci * ci) * MARGIN
        fdev = FB[fb, FBR_DEV]
        dv = fdev * RC[R_IH1, i]
        d2 = fdev + fdev * RC[R_IH2, i]
        d3 = FB[fb, FBR_HMF] + w2 * dv + c2 * d2
        m2 = w2 * cm + d2
        m3 = w2 * w * cm + d3
        m2a = w2 * w2 * cm + w2 * d2 + c2 * d3
        k8 = 0.125 * FB[fb, FBR_H] * FB[fb, FBR_H] * MARGIN * SCREEN_MARGIN
        TH[0, i] = P[0, i] - k8 * m2
        TH[1, i] = P[1, i] - k8 * m3
        TH[2, i] = P[2, i] - k8 * m2a
    nosc = P.shape[1]
    i0 = np.int64(0)
    while i0 < nosc:
        i1 = i0
        while i1 < nosc and osc_out[i1] == osc_out[i0]:
            i1 += 1
        split = i1
        while split > i0 and (
            TH[0, split - 1] < WEAK * P[0, split - 1]
            or TH[1, split - 1] < WEAK * P[1, split - 1]
            or TH[2, split - 1] < WEAK * P[2, split - 1]
        ):
            split -= 1
        SPLIT[i0] = split
        i0 = i1


@njit(cache=True)
def peaks_at_ends(SI, SF, SX, SY, nseg, G, GT, OR, OB, K, h, osc_out, osc_w, osc_xi, osc_rho, S,
                  P, D, PH, OW, RC, FB, EV):  # fmt: skip
    """The first pass through the segments ``0 … nseg − 1`` (arguments as
    :func:`oscillators_on_segments`, the fast path): every oscillator advanced as there — the
    same updates and series, the same states — with no filter and no search; ``P`` raised to
    the values at the ends of the whole sub-steps and of the series' parts, and the bounds
    ``FB`` of the whole sub-steps raised (rows ``FBR_*`` per floor row) for
    :func:`rider_thresholds`. When ``EV`` has a row per segment between events, ``EV[e]``
    receives, for the ``e``-th such segment, each oscillator's end state and the largest
    bounds ``Σ|d_j| h^j`` of its three quantities over the series' parts (those
    :func:`_oscillators` compares with the peaks), so that the second pass need not repeat
    the series where they are within the peaks."""
    N = SX.shape[1]
    keep = EV.shape[0] > 0
    e = np.int64(0)
    nosc = osc_w.size
    most_parts = 1
    for i in range(nosc):
        most_parts = max(most_parts, int(np.ceil(h * osc_rho[i] / 0.5 - 1e-12)))
    CS = np.zeros((most_parts, K + 1))
    c = np.empty(max(K, D) + 2)
    d = np.empty(D + 2)
    dv = np.empty(D + 2)
    da = np.empty(D + 2)
    Z = np.zeros(N + 2)
    U = np.zeros((2, nosc))
    S0 = np.zeros((2, nosc))
    ax = np.zeros(N)
    for s in range(nseg):
        m = SI[s, 1]
        x = SX[s]
        a_s = SF[s, 0]
        slope = SF[s, 2]
        L = SF[s, 3]
        if SI[s, 2] == 1:
            y = SY[s]
            a_e = SF[s, 1]
            for j in range(N):
                Z[j] = x[j]
                ax[j] = abs(x[j])
            Z[N] = a_s
            Z[N + 1] = slope
            OWm = OW[m]
            i0 = np.int64(0)
            while i0 < nosc:
                o = osc_out[i0]
                i1 = i0
                while i1 < nosc and osc_out[i1] == o:
                    i1 += 1
                f0 = _value(G[m, o + 1], x, a_s)
                f1 = _value(G[m, o + 1], y, a_e)
                fdev = _tight_deviation(GT[m], o + 1, x, ax, a_s, slope, L)
                fb = o + 1
                FB[fb, FBR_F] = max(FB[fb, FBR_F], abs(f0), abs(f1))
                FB[fb, FBR_S] = max(FB[fb, FBR_S], abs((f1 - f0) / L))
                FB[fb, FBR_DEV] = max(FB[fb, FBR_DEV], fdev)
                FB[fb, FBR_HMF] = max(FB[fb, FBR_HMF], L * (8.0 * fdev / (L * L)))
                FB[fb, FBR_H] = max(FB[fb, FBR_H], L)
                _rider_inputs(OWm, Z, U, i0, i1)
                _rider_update(i0, i1, S, P, PH, U, RC, S0)
                i0 = i1
            continue
        # a segment between events: the series of _oscillators, peaks at the parts' ends
        last = -1
        last_parts = -1
        for i in range(nosc):
            o = osc_out[i]
            if o != last:
                taylor_coefficients(OR[m, o], OB[m, o], x, a_s, slope, c)
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
            b0 = 0.0
            b1 = 0.0
            b2 = 0.0
            for sp in range(parts):
                _rider_series(CS[sp], K, D, z2w, w2, S[0, i], S[1, i], d, dv)
                if keep:
                    for j in range(D + 1):
                        da[j] = -(w2 * d[j] + z2w * dv[j])
                    b0 = max(b0, _bound_on(d, D, hp))
                    b1 = max(b1, _bound_on(dv, D - 1, hp))
                    b2 = max(b2, _bound_on(da, D, hp))
                q = poly_val(d, D, hp)
                v = poly_val(dv, D - 1, hp)
                S[0, i] = q
                S[1, i] = v
                P[0, i] = max(P[0, i], abs(q))
                P[1, i] = max(P[1, i], abs(v))
                P[2, i] = max(P[2, i], abs(w2 * q + z2w * v))
            if keep:
                EV[e, 0, i] = S[0, i]
                EV[e, 1, i] = S[1, i]
                EV[e, 2, i] = b0
                EV[e, 3, i] = b1
                EV[e, 4, i] = b2
        e += 1
