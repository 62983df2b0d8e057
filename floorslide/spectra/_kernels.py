"""Compiled kernel of exact response spectra with peaks inside steps.

A bank of linear oscillators (``q'' + 2ξω q' + ω² q = −a_f(t)``) is advanced through the record
by the exact recurrence of each oscillator coupled to its floor, at the record step (the
augmented first-order hold of ``building/exact.py``; on the ground this is the recurrence of
Nigam & Jennings 1969) — one branch-free pass over the oscillators per step that the compiler
vectorises. A step is searched for peaks inside it only when it could hold a new peak:

- a rigorous bound. On a floor, with ``ρ² = q² + (q'/ω)²``, ``dρ/dt ≤ |a_f|/ω`` (damping only
  removes energy), so inside the step ``ρ ≤ ρ₀ + dt·max|a_f|/ω``; then ``|q| ≤ ρ``,
  ``|q'| ≤ ωρ`` and ``|ω²q + 2ξωq'| ≤ ω²√(1+4ξ²)·ρ``. On the ground (linear input inside the
  step) the response is the exact particular solution ``q_p = α + βτ`` plus a damped free
  vibration ``e`` whose energy amplitude ``E`` only decreases: ``|q| ≤ max|q_p| + E``,
  ``|q'| ≤ |β| + ωE``, ``|ω²q + 2ξωq'| ≤ max|a_g| + ω²√(1+4ξ²)·E`` — much tighter;
- and, for oscillators with ``ω·dt ≤ 0.5`` (at most one critical point per step), the derivative
  of the quantity changing sign between the step ends.

A flagged step is then re-stepped on sub-steps short enough (``max(ρ_building, ω)·h ≤ 0.5``)
for the Taylor polynomial of the exact response to represent it to rounding, and its extrema
are found there.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from floorslide.building._instep import extreme_values, taylor_coefficients


@njit(cache=True)
def _floor_bound(phi_s, p_s, q_s, R, beta, K, x, a, a1, ms, hs, c, xs, xn, f0, f1):
    """max |a_f| over one record step on the building's own sub-steps (exact extrema), and the
    largest deviation of a_f from the straight line between its step-end values f0, f1."""
    n = x.size
    slope = (a1 - a) / (ms * hs)
    fs = (f1 - f0) / (ms * hs)
    for i in range(n):
        xs[i] = x[i]
    bound = 0.0
    dev = 0.0
    for r in range(ms):
        aa = a + (a1 - a) * (r / ms)
        ab = a + (a1 - a) * ((r + 1) / ms) if r + 1 < ms else a1
        for j in range(K + 1):
            c[j] = 0.0
        taylor_coefficients(R, beta, xs, aa, slope, c[: R.shape[0]])
        vmin, _, vmax, _ = extreme_values(c, K, 0.0, hs)
        bound = max(bound, vmax, -vmin)
        c[0] -= f0 + fs * (r * hs)
        c[1] -= fs
        vmin, _, vmax, _ = extreme_values(c, K, 0.0, hs)
        dev = max(dev, vmax, -vmin)
        for i in range(n):
            s_ = p_s[i] * aa + q_s[i] * ab
            for j in range(n):
                s_ += phi_s[i, j] * xs[j]
            xn[i] = s_
        for i in range(n):
            xs[i] = xn[i]
    return bound, dev


@njit(cache=True, inline="always")
def _hermite_max(f0, d0, f1, d1, h):
    """max |H| on [0, h] of the cubic Hermite interpolant of values and slopes at the ends."""
    c1 = h * d0
    c2 = -3.0 * f0 - 2.0 * c1 + 3.0 * f1 - h * d1
    c3 = 2.0 * f0 + c1 - 2.0 * f1 + h * d1
    best = max(abs(f0), abs(f1))
    # H'(t) = c1 + 2 c2 t + 3 c3 t², t in (0, 1)
    A = 3.0 * c3
    B = 2.0 * c2
    if A == 0.0:
        if B != 0.0:
            t = -c1 / B
            if 0.0 < t < 1.0:
                best = max(best, abs(f0 + t * (c1 + t * (c2 + t * c3))))
        return best
    disc = B * B - 4.0 * A * c1
    if disc < 0.0:
        return best
    sq = math.sqrt(disc)
    qq = -0.5 * (B + (sq if B >= 0.0 else -sq))
    t1 = qq / A
    t2 = c1 / qq if qq != 0.0 else -1.0
    if 0.0 < t1 < 1.0:
        best = max(best, abs(f0 + t1 * (c1 + t1 * (c2 + t1 * c3))))
    if 0.0 < t2 < 1.0:
        best = max(best, abs(f0 + t2 * (c1 + t2 * (c2 + t2 * c3))))
    return best


@njit(cache=True)
def _search_step(
    o,
    n,
    a,
    a1,
    dt,
    q0,
    v0,
    w,
    xi,
    gm,
    gK,
    CG,
    XG,
    S_Pqq,
    S_Pqx,
    S_pq,
    S_qq,
    need,
    out,
    c,
    Q,
    poly,
):
    """Peaks of oscillator `o` inside one record step, on its sub-steps.

    On every sub-step (``max(rho_building, w)·h <= 0.5``: at most one critical point) a
    quantity is searched only if its derivative changes sign there; on the ground, also only if
    the cubic Hermite interpolant of its end values and slopes plus the interpolation error bound
    ``h^4/384 · max|f^(4)|`` can exceed the peak so far (the response is the exact particular
    solution ``alpha + beta·tau`` plus a free vibration ``Re(C e^(lambda tau))`` whose k-th
    derivative is at most ``|C| w^k``). Only then is the extremum of its Taylor polynomial found.
    """
    m = gm
    K = gK
    h = dt / m
    slope = (a1 - a) / dt
    c2 = 2.0 * xi * w
    w2 = w * w
    wd = w * math.sqrt(1.0 - xi * xi)
    q = q0
    v = v0
    for r in range(m):
        aa = a + (a1 - a) * (r / m)
        ab = a + (a1 - a) * ((r + 1) / m) if r + 1 < m else a1
        have_c = False
        if n > 0:
            for j in range(K + 1):
                c[j] = CG[r, j]
            have_c = True
            f0 = c[0]
            f1 = c[K]
            for j in range(K - 1, -1, -1):
                f1 = f1 * h + c[j]
        else:
            f0 = aa
            f1 = ab
        # sub-step end state
        qn = S_Pqq[0, 0] * q + S_Pqq[0, 1] * v + S_pq[0] * aa + S_qq[0] * ab
        vn = S_Pqq[1, 0] * q + S_Pqq[1, 1] * v + S_pq[1] * aa + S_qq[1] * ab
        for j in range(n):
            qn += S_Pqx[0, j] * XG[r, j]
            vn += S_Pqx[1, j] * XG[r, j]
        dd0 = -(f0 + c2 * v + w2 * q)  # q'' at both ends
        dd1 = -(f1 + c2 * vn + w2 * qn)
        A0 = w2 * q + c2 * v
        A1 = w2 * qn + c2 * vn
        Ad0 = w2 * v + c2 * dd0
        Ad1 = w2 * vn + c2 * dd1
        nd = need[0] and ((v > 0.0) != (vn > 0.0))
        nv = need[1] and ((dd0 > 0.0) != (dd1 > 0.0))
        na = need[2] and ((Ad0 > 0.0) != (Ad1 > 0.0))
        if n == 0 and (nd or nv or na):
            bet = -slope / w2
            alp = (-aa + c2 * slope / w2) / w2
            e0 = q - alp
            ci = (e0 * (-xi * w) - (v - bet)) / wd
            cm = math.sqrt(e0 * e0 + ci * ci)
            h4 = h * h * h * h / 384.0 * cm * w2 * w2
            if nd:
                nd = _hermite_max(q, v, qn, vn, h) + h4 > out[o, 0]
            if nv:
                nv = _hermite_max(v, dd0, vn, dd1, h) + h4 * w > out[o, 1]
            if na:
                na = _hermite_max(A0, Ad0, A1, Ad1, h) + h4 * w2 * (1.0 + 2.0 * xi) > out[o, 2]
        if nd or nv or na:
            if not have_c:
                for j in range(K + 1):
                    c[j] = 0.0
                c[0] = aa
                c[1] = slope
            Q[0] = q
            Q[1] = v
            for j in range(K - 1):
                Q[j + 2] = (-c2 * (j + 1) * Q[j + 1] - w2 * Q[j] - c[j]) / ((j + 1) * (j + 2))
            if nd:
                vmin, _, vmax, _ = extreme_values(Q, K, 0.0, h)
                out[o, 0] = max(out[o, 0], vmax, -vmin)
            if nv:
                for j in range(K):
                    poly[j] = (j + 1) * Q[j + 1]
                poly[K] = 0.0
                vmin, _, vmax, _ = extreme_values(poly, K, 0.0, h)
                out[o, 1] = max(out[o, 1], vmax, -vmin)
            if na:
                for j in range(K):
                    poly[j] = w2 * Q[j] + c2 * (j + 1) * Q[j + 1]
                poly[K] = w2 * Q[K]
                vmin, _, vmax, _ = extreme_values(poly, K, 0.0, h)
                out[o, 2] = max(out[o, 2], vmax, -vmin)
        q = qn
        v = vn


@njit(cache=True)
def spectrum_kernel(
    phi,
    p,
    q,
    acc,
    dt,
    w,
    xi,
    P,
    X,
    PX,
    one_crit,
    b_phi,
    b_p,
    b_q,
    b_R,
    b_beta,
    b_K,
    b_m,
    grp,
    G_m,
    G_K,
    G_phi,
    G_p,
    G_q,
    G_R,
    G_beta,
    S_Pqq,
    S_Pqx,
    S_pq,
    S_qq,
    Ih,
    out,
):
    """Peaks of a bank of oscillators on one floor.

    Parameters
    ----------
    phi, p, q
        Exact record-step recurrence of the building (empty on the ground).
    acc, dt
        Ground acceleration samples and time step.
    w, xi
        Circular frequencies and damping ratios of the oscillators.
    P, X, PX
        Record-step recurrence of every oscillator coupled to the floor, one column per
        oscillator: ``q_{k+1} = P0 q_k + P1 q'_k + P4 a_k + X0 a_{k+1} + PX[0]·x_k`` and
        ``q'_{k+1} = P2 q_k + P3 q'_k + P5 a_k + X1 a_{k+1} + PX[1]·x_k`` (``P`` is ``(6, n)``,
        ``X`` is ``(2, n)``, ``PX`` is ``(2, n_states, n)``).
    one_crit
        Per oscillator: ``ω·dt ≤ 0.5`` (the derivative sign test is valid at the record step).
    b_*
        The building's own sub-steps (exact floor-acceleration extrema for the bound).
    grp, G_*, S_*
        Sub-step data of the in-step search: per oscillator its group (sub-step count ``G_m``,
        Taylor degree ``G_K``, the building's sub-step recurrence and Taylor rows) and its own
        coupled sub-step recurrence ``S_*``.
    Ih
        ``(3, n_osc)``: ``∫₀^dt |h|``, ``∫₀^dt |h'|`` and ``∫₀^dt |ω²h + 2ξωh'|`` of each
        oscillator's impulse response (bounds of the response to the floor's deviation from a
        straight line inside a step).
    out
        ``(n_osc, 3)``: peaks of ``|q|``, ``|q'|`` and ``|ω² q + 2ξω q'|``.
    """
    n = phi.shape[0]
    nosc = w.size
    npts = acc.size
    x = np.zeros(n)
    xn = np.empty(n)
    xs = np.empty(n)
    xs2 = np.empty(n)
    xe = np.empty(n)
    f0 = b_beta[0] * acc[0]  # the floor acceleration at t = 0 (building at rest)
    Kmax = max(G_K.max(), b_K)
    c = np.zeros(Kmax + 2)
    Q = np.zeros(Kmax + 2)
    poly = np.zeros(Kmax + 2)
    qs = np.zeros(nosc)
    vs = np.zeros(nosc)
    ds = np.zeros(nosc)
    qe = np.zeros(nosc)
    ve = np.zeros(nosc)
    flag = np.zeros(nosc, dtype=np.uint8)
    coup = np.zeros((2, nosc))
    c2 = 2.0 * xi * w
    w2 = w * w
    wd = w * np.sqrt(1.0 - xi * xi)
    dt4 = dt * dt * dt * dt / 384.0
    need = np.zeros(3, dtype=np.bool_)
    ngroups = G_m.size
    ready = np.zeros(ngroups, dtype=np.bool_)
    CG = np.zeros((ngroups, G_m.max(), G_R.shape[1]))
    XG = np.zeros((ngroups, G_m.max(), n))
    pk_d = out[:, 0]
    pk_v = out[:, 1]
    pk_a = out[:, 2]
    for k in range(npts - 1):
        a = acc[k]
        a1 = acc[k + 1]
        if n > 0:
            for i in range(n):  # building state at the step end
                s_ = p[i] * a + q[i] * a1
                for j in range(n):
                    s_ += phi[i, j] * x[j]
                xe[i] = s_
            f1 = b_beta[0] * a1  # floor acceleration at the step end
            for j in range(n):
                f1 += b_R[0, j] * xe[j]
            abound, fdev = _floor_bound(
                b_phi, b_p, b_q, b_R, b_beta, b_K, x, a, a1, b_m, dt / b_m, c, xs, xn, f0, f1
            )
            for o in range(nosc):
                coup[0, o] = 0.0
                coup[1, o] = 0.0
            for j in range(n):
                xj = x[j]
                for o in range(nosc):
                    coup[0, o] += PX[0, j, o] * xj
                    coup[1, o] += PX[1, j, o] * xj
        else:
            abound = max(abs(a), abs(a1))
            f1 = a1
            fdev = 0.0
        slope = (a1 - a) / dt  # of the ground record
        fslope = (f1 - f0) / dt  # of the straight line through the floor's step-end values
        # one vectorisable pass: exact update, end peaks, flags
        for o in range(nosc):
            q0 = qs[o]
            v0 = vs[o]
            q1 = P[0, o] * q0 + P[1, o] * v0 + P[4, o] * a + X[0, o] * a1 + coup[0, o]
            v1 = P[2, o] * q0 + P[3, o] * v0 + P[5, o] * a + X[1, o] * a1 + coup[1, o]
            d1 = -(f1 + c2[o] * v1 + w2[o] * q1)
            A1 = w2[o] * q1 + c2[o] * v1
            pk_d[o] = max(pk_d[o], abs(q1))
            pk_v[o] = max(pk_v[o], abs(v1))
            pk_a[o] = max(pk_a[o], abs(A1))
            d0 = ds[o]
            # q = q_p + e + q_δ: q_p = α + βτ the exact response to the straight line through
            # the floor's step-end accelerations, e = Re(C e^{λτ}) a damped free vibration
            # (|e^(k)| ≤ |C| ω^k) and q_δ the zero-state response to the floor's deviation δ
            # from that line (0 on the ground), |q_δ| ≤ max|δ|·∫₀^dt |h|
            bet = -fslope / w2[o]
            alp = (-f0 + c2[o] * fslope / w2[o]) / w2[o]
            e0 = q0 - alp
            ci = (e0 * (-xi[o] * w[o]) - (v0 - bet)) / wd[o]
            cm = math.sqrt(e0 * e0 + ci * ci)
            fd = max(abs(alp), abs(alp + bet * dt)) + cm + fdev * Ih[0, o] > pk_d[o]
            fv = abs(bet) + w[o] * cm + fdev * Ih[1, o] > pk_v[o]
            fa = abound + w2[o] * (1.0 + 2.0 * xi[o]) * cm + fdev * Ih[2, o] > pk_a[o]
            if one_crit[o]:
                # one critical point at most: the derivative changes sign ...
                ad0 = w2[o] * v0 + c2[o] * d0
                ad1 = w2[o] * v1 + c2[o] * d1
                fd = fd and ((v0 > 0.0) != (v1 > 0.0))
                fv = fv and ((d0 > 0.0) != (d1 > 0.0))
                fa = fa and ((ad0 > 0.0) != (ad1 > 0.0))
                if n == 0:
                    # ... and on the ground the cubic Hermite interpolant plus its error bound
                    # dt⁴/384·max|f⁗| reaches the peak
                    h4 = dt4 * cm * w2[o] * w2[o]
                    if fd:
                        fd = _hermite_max(q0, v0, q1, v1, dt) + h4 > pk_d[o]
                    if fv:
                        fv = _hermite_max(v0, d0, v1, d1, dt) + h4 * w[o] > pk_v[o]
                    if fa:
                        A0 = w2[o] * q0 + c2[o] * v0
                        ha = h4 * w2[o] * (1.0 + 2.0 * xi[o])
                        fa = _hermite_max(A0, ad0, A1, ad1, dt) + ha > pk_a[o]
            flag[o] = fd + 2 * fv + 4 * fa
            qe[o] = q1
            ve[o] = v1
            ds[o] = d1
        for g in range(ngroups):
            ready[g] = False
        for o in range(nosc):
            if flag[o]:
                need[0] = (flag[o] & 1) != 0
                need[1] = (flag[o] & 2) != 0
                need[2] = (flag[o] & 4) != 0
                g = grp[o]
                K = G_K[g]
                if n > 0 and not ready[g]:
                    # the floor on this group's sub-steps: states and Taylor coefficients,
                    # shared by every oscillator of the group
                    mg = G_m[g]
                    for i in range(n):
                        xs2[i] = x[i]
                    for r in range(mg):
                        aa = a + (a1 - a) * (r / mg)
                        ab = a + (a1 - a) * ((r + 1) / mg) if r + 1 < mg else a1
                        for i in range(n):
                            XG[g, r, i] = xs2[i]
                        for j in range(CG.shape[2]):
                            CG[g, r, j] = 0.0
                        taylor_coefficients(G_R[g], G_beta[g], xs2, aa, slope, CG[g, r])
                        for i in range(n):
                            s_ = G_p[g, i] * aa + G_q[g, i] * ab
                            for j in range(n):
                                s_ += G_phi[g, i, j] * xs2[j]
                            xn[i] = s_
                        for i in range(n):
                            xs2[i] = xn[i]
                    ready[g] = True
                _search_step(
                    o,
                    n,
                    a,
                    a1,
                    dt,
                    qs[o],
                    vs[o],
                    w[o],
                    xi[o],
                    G_m[g],
                    K,
                    CG[g],
                    XG[g],
                    S_Pqq[o],
                    S_Pqx[o],
                    S_pq[o],
                    S_qq[o],
                    need,
                    out,
                    c,
                    Q,
                    poly,
                )
        for o in range(nosc):
            qs[o] = qe[o]
            vs[o] = ve[o]
        for i in range(n):
            x[i] = xe[i]
        f0 = f1
