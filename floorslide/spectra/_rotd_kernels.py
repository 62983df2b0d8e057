"""Compiled kernels of RotD spectra (Boore 2010): peaks of every rotated oscillator response,
and of the vector response, found inside steps.

For one oscillator the two directions' responses ``q1(t)``, ``q2(t)`` are stepped exactly through
the record (on a floor: the oscillator coupled to each direction's building, the record-step
recurrence of :func:`floorslide.spectra.core._kernel_data`) and kept at the steps' ends. The
response along the angle ``θ`` is ``q_θ = q1·cos θ + q2·sin θ`` (linearity), so its samples cost
two multiplications; those of the vector ``|q| = |(q1, q2)|`` one more. The maxima at the
samples come first: a sample whose magnitude is at most the smallest angle's maximum so far
cannot raise any angle's maximum (``|q_θ| ≤ |q|``), so only the few largest samples are rotated
through every angle.

Inside a step each direction's response is the exact particular solution for the straight
line through the floor's step-end accelerations, ``α + βτ``, plus a damped free vibration
``e = Re(C e^{λτ})`` (``|e| ≤ |C|``, ``|e^(k)| ≤ ω^k|C|``) plus, on a floor, the response to the
floor's deviation ``δ`` from that line (``|q_δ| ≤ max|δ|·∫|h|``): as in
:mod:`floorslide.spectra._kernels`. Hence rigorous radii ``ρ`` (of ``q − chord``) and ``σ``
(of ``q' − chord``) per direction; along ``θ`` they are ``|cos θ|ρ1 + |sin θ|ρ2``. A step is
searched for the angle ``θ`` only when

- its end values plus that radius exceed the angle's maximum so far (the vector's ends plus
  ``hypot(ρ1, ρ2)`` decide first for all angles at once, and for ``|q|``);
- ``q_θ'`` may vanish in it (it changes sign, or comes within ``σ_θ`` of zero at an end);
- the bound ``max|α_θ + β_θτ| + |C_θ| + max|δ_θ|·∫|h|`` (all linear in the two directions)
  exceeds it too.

A searched step is cut into the oscillator's sub-steps (``max(ω, ρ_building)·h ≤ 0.5``), on which
each direction's response is its Taylor polynomial (equal to it to rounding); the peak of the
rotated polynomial, or of ``q1² + q2²`` (degree 2K), is then found by
:func:`floorslide.numerics.polynomial.max_abs_on` (rigorous filters, then every critical point
isolated). The rigid oscillator (period 0) is the floor acceleration itself: linear inside a
step on the ground (the maxima are at samples), a polynomial on a floor's sub-step.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import foh_step, substep_inputs, taylor_coefficients
from floorslide.numerics.polynomial import curvature_bound, max_abs_on, poly_val, scratch
from floorslide.spectra._kernels import _floor_bound, _sample

_MARGIN = 1.0 + 1e-6
"""Relative margin of the radii: the end values they are added to carry rounding errors."""

_C8 = np.cos(np.arange(8) * np.pi / 8)
_S8 = np.sin(np.arange(8) * np.pi / 8)
"""Eight directions (22.5° apart) whose sample maxima seed the rotated maxima."""


class Direction(NamedTuple):
    """One horizontal direction: its ground record and its building's data (empty arrays on the
    ground), for one grid of oscillators.

    ``F``/``S`` hold the oscillators' record-step / sub-step recurrence as rows
    ``[Φ00, Φ01, Φ10, Φ11, p0, p1, r0, r1]``: ``q⁺ = Φ00 q + Φ01 q' + p0 a + r0 a⁺ + FX[0]·x``,
    ``q'⁺ = Φ10 q + Φ11 q' + p1 a + r1 a⁺ + FX[1]·x`` (``x``: the building's state); ``G_*`` the
    building's sub-step recurrence and Taylor rows per group of sub-step counts (on the ground,
    ``G_beta = [1, 0, …]``: the record itself); ``b_*`` the floor-acceleration bound of a step
    (:func:`floorslide.spectra._kernels._floor_bound`); ``R``, ``beta``, ``order`` the floor
    acceleration's Taylor rows on the steps (the rigid oscillator).
    """

    acc: Any
    F: Any
    FX: Any
    S: Any
    SX: Any
    G_phi: Any
    G_p: Any
    G_q: Any
    G_R: Any
    G_beta: Any
    b_phi: Any
    b_p: Any
    b_q: Any
    b_R: Any
    b_beta: Any
    b_K: Any
    b_m: Any
    R: Any
    beta: Any
    order: Any


class Bank(NamedTuple):
    """The oscillators and the angles: circular frequencies ``w`` and damping ratios ``xi``;
    ``IH0``, ``IH1`` the integrals ``∫|h|``, ``∫|h'|`` of their impulse responses over a step;
    per oscillator its sub-step group ``grp`` (``G_m`` sub-steps) and Taylor degree ``K``;
    ``cs``, ``sn`` the cosines and sines of the angles."""

    w: Any
    xi: Any
    IH0: Any
    IH1: Any
    grp: Any
    G_m: Any
    K: Any
    cs: Any
    sn: Any


@njit(cache=True)
def _update_angles(x, y, cs, sn, M):
    """``M[j] = max(M[j], |x cos θ_j + y sin θ_j|)``."""
    for j in range(M.size):
        p = abs(x * cs[j] + y * sn[j])
        if p > M[j]:
            M[j] = p


@njit(cache=True)
def _sample_maxima(B, n, stride, cs, sn, M, R2, o):
    """Maxima at the samples ``B[0:n:stride]`` (columns 0 and 2: the two directions) of every
    rotated response (``M``, updated) and of the squared magnitude (``R2[o]``, updated); returns
    the row of a new maximum of the magnitude, or −1.

    The largest magnitude and the largest values along eight directions seed ``M``; then only
    the samples whose magnitude exceeds the smallest ``M`` (a bound no rotation of a smaller
    sample can beat) are rotated through every angle."""
    best = -1
    r2 = R2[o]
    top = np.zeros(8)
    at = np.full(8, -1)
    for i in range(0, n, stride):
        x = B[i, 0]
        y = B[i, 2]
        r = x * x + y * y
        if r > r2:
            r2 = r
            best = i
        for d in range(8):
            p = abs(x * _C8[d] + y * _S8[d])
            if p > top[d]:
                top[d] = p
                at[d] = i
    R2[o] = r2
    if best >= 0:
        _update_angles(B[best, 0], B[best, 2], cs, sn, M)
    for d in range(8):
        if at[d] >= 0:
            _update_angles(B[at[d], 0], B[at[d], 2], cs, sn, M)
    low = M.min()
    low2 = low * low
    for i in range(0, n, stride):
        x = B[i, 0]
        y = B[i, 2]
        if x * x + y * y > low2:
            _update_angles(x, y, cs, sn, M)
    return best


@njit(cache=True)
def _floor_values(d, X, g, h, L, exact, FK, c, xs, xn):
    """The floor acceleration at the step ends ``FK[i, 0]`` and, when `exact`, per step its bound
    ``FK[i, 1]``, its largest deviation from the chord ``FK[i, 2]`` and the bound of its rate
    ``FK[i, 3]`` (on the ground: the record, linear in each step)."""
    n = X.shape[1]
    if n == 0:
        for i in range(L + 1):
            FK[i, 0] = g[i]
        if exact:
            for i in range(L):
                FK[i, 1] = max(abs(g[i]), abs(g[i + 1]))
                FK[i, 2] = 0.0
                FK[i, 3] = abs(g[i + 1] - g[i]) / h
        return
    for i in range(L + 1):
        f = d.b_beta[0] * g[i]
        for j in range(n):
            f += d.b_R[0, j] * X[i, j]
        FK[i, 0] = f
    if exact:
        for i in range(L):
            ab, dev, jb = _floor_bound(
                d.b_phi, d.b_p, d.b_q, d.b_R, d.b_beta, d.b_K, X[i], g[i], g[i + 1], d.b_m,
                h / d.b_m, c, xs, xn, FK[i, 0], FK[i + 1, 0],
            )  # fmt: skip
            FK[i, 1] = ab
            FK[i, 2] = dev
            FK[i, 3] = jb


@njit(cache=True)
def _states(o, d, X, g, L, q, v, B, col):
    """The oscillator's response to one direction at every step end of the chunk, from
    ``(q, v)``, into ``B[:, col]`` (displacement) and ``B[:, col + 1]`` (velocity)."""
    F = d.F
    FX = d.FX
    n = X.shape[1]
    p00, p01, p10, p11 = F[o, 0], F[o, 1], F[o, 2], F[o, 3]
    a0, a1, r0, r1 = F[o, 4], F[o, 5], F[o, 6], F[o, 7]
    B[0, col] = q
    B[0, col + 1] = v
    for i in range(L):
        qn = p00 * q + p01 * v + a0 * g[i] + r0 * g[i + 1]
        vn = p10 * q + p11 * v + a1 * g[i] + r1 * g[i + 1]
        for j in range(n):
            qn += FX[o, 0, j] * X[i, j]
            vn += FX[o, 1, j] * X[i, j]
        q = qn
        v = vn
        B[i + 1, col] = q
        B[i + 1, col + 1] = v


@njit(cache=True)
def _substep_polys(o, i, bank, d, X, g, B, col, h, m, K, Q, c, xs, xn):
    """Taylor polynomials (degree ``K``) of the oscillator's response to one direction on the
    ``m`` sub-steps of step ``i``, into ``Q[r, :K + 1]``: from the state at each sub-step start
    (the exact sub-step recurrence) and the floor acceleration's Taylor coefficients there
    (``q'' = −f − 2ξω q' − ω² q``)."""
    n = X.shape[1]
    gi = bank.grp[o]
    w = bank.w[o]
    w2 = w * w
    c2 = 2.0 * bank.xi[o] * w
    S = d.S
    SX = d.SX
    R = d.G_R[gi]
    beta = d.G_beta[gi]
    a = g[i]
    a1 = g[i + 1]
    slope = (a1 - a) / h
    q = B[i, col]
    v = B[i, col + 1]
    for j in range(n):
        xs[j] = X[i, j]
    for r in range(m):
        aa, ab = substep_inputs(a, a1, r, m)
        for j in range(c.size):
            c[j] = 0.0
        taylor_coefficients(R, beta, xs, aa, slope, c)
        Q[r, 0] = q
        Q[r, 1] = v
        for j in range(K - 1):
            Q[r, j + 2] = (-c2 * (j + 1) * Q[r, j + 1] - w2 * Q[r, j] - c[j]) / ((j + 1) * (j + 2))
        qn = S[o, 0] * q + S[o, 1] * v + S[o, 4] * aa + S[o, 6] * ab
        vn = S[o, 2] * q + S[o, 3] * v + S[o, 5] * aa + S[o, 7] * ab
        for j in range(n):
            qn += SX[o, 0, j] * xs[j]
            vn += SX[o, 1, j] * xs[j]
        if r + 1 < m:
            foh_step(d.G_phi[gi], d.G_p[gi], d.G_q[gi], xs, aa, ab, xn)
            for j in range(n):
                xs[j] = xn[j]
        q = qn
        v = vn


@njit(cache=True)
def _search_angles(flags, nflag, cs, sn, Q1, Q2, m, K, hs, M, poly, work):
    """Peaks of the rotated polynomials ``cos θ_j·Q1[r] + sin θ_j·Q2[r]`` of the flagged angles
    on every sub-step (``M`` updated)."""
    for f in range(nflag):
        j = flags[f]
        c = cs[j]
        s = sn[j]
        for r in range(m):
            for k in range(K + 1):
                poly[k] = c * Q1[r, k] + s * Q2[r, k]
            pk, _ = max_abs_on(poly, K, hs, M[j], work)
            if pk > M[j]:
                M[j] = pk


@njit(cache=True)
def _search_magnitude(Q1, Q2, m, K, hs, t0, R2, W, o, poly, work):
    """Peak of ``q1² + q2²`` (the product polynomials, degree ``2K``) on every sub-step;
    ``R2[o]`` and, at a new peak, ``W[o] = (time, q1, q2)`` updated."""
    for r in range(m):
        for k in range(2 * K + 1):
            poly[k] = 0.0
        for a in range(K + 1):
            x1 = Q1[r, a]
            x2 = Q2[r, a]
            for b in range(K + 1):
                poly[a + b] += x1 * Q1[r, b] + x2 * Q2[r, b]
        pk, x = max_abs_on(poly, 2 * K, hs, R2[o], work)
        if pk > R2[o]:
            R2[o] = pk
            W[o, 0] = t0 + r * hs + x
            W[o, 1] = poly_val(Q1[r], K, x)
            W[o, 2] = poly_val(Q2[r], K, x)


@njit(cache=True, inline="always")
def _direction_bounds(q0, v0, f0, f1, ab, dev, jb, h, w, xi, ih0, ih1):
    """Rigorous bounds of one direction's response over a step (see the module notes): the
    particular solution ``α + βτ`` for the floor's chord, the free vibration's ``e(0)`` and
    ``ė``-part ``ci`` (``|C| = hypot(e0, ci)``), the radius ``ρ`` of ``q − chord`` and the
    radius ``σ`` of ``q' − chord``."""
    w2 = w * w
    c2 = 2.0 * xi * w
    fs = (f1 - f0) / h
    bet = -fs / w2
    alp = fs * c2 / (w2 * w2) - f0 / w2
    e0 = q0 - alp
    ci = (v0 - bet + xi * w * e0) / (w * math.sqrt(1.0 - xi * xi))
    cm = math.sqrt(e0 * e0 + ci * ci)
    k8 = 0.125 * h * h
    kw = min(k8 * w2, 2.0)
    rho = cm * kw + 2.0 * dev * ih0
    sig = w * cm * kw + 2.0 * dev * ih1
    if dev > 0.0:
        # on a floor, also the chord deviation dt²/8·max|q''| (max|q'''| for q') with the bounds
        # from the equation of motion (as _kernels._stage_floor)
        bd = max(abs(alp), abs(alp + bet * h)) + cm + dev * ih0
        bv = abs(bet) + w * cm + dev * ih1
        m2q = ab + c2 * bv + w2 * bd
        m2v = jb + c2 * m2q + w2 * bv
        rho = min(rho, k8 * m2q)
        sig = min(sig, k8 * m2v)
    return alp, bet, e0, ci, cm, rho * _MARGIN, sig * _MARGIN


@njit(cache=True)
def _oscillator_instep(
    o, bank, d1, d2, X1, X2, g1, g2, FK1, FK2, B, L, h, t0, search_all, M, R2, W, ws
):  # fmt: skip
    """The in-step search of oscillator ``o`` through the chunk (see the module notes); with
    `search_all`, of every step along every angle (tests: the skip rules change nothing)."""
    flags, Q1, Q2, poly, cf, xs, xn, work = ws
    w = bank.w[o]
    xi = bank.xi[o]
    ih0 = bank.IH0[o]
    ih1 = bank.IH1[o]
    cs = bank.cs
    sn = bank.sn
    m = bank.G_m[bank.grp[o]]
    K = bank.K[o]
    hs = h / m
    Mo = M[o]
    nang = Mo.size
    low = Mo.min()
    r100 = math.sqrt(R2[o])
    for i in range(L):
        q1a = B[i, 0]
        v1a = B[i, 1]
        q2a = B[i, 2]
        v2a = B[i, 3]
        q1b = B[i + 1, 0]
        v1b = B[i + 1, 1]
        q2b = B[i + 1, 2]
        v2b = B[i + 1, 3]
        dev1 = FK1[i, 2]
        dev2 = FK2[i, 2]
        al1, be1, e01, ci1, cm1, rho1, sig1 = _direction_bounds(
            q1a, v1a, FK1[i, 0], FK1[i + 1, 0], FK1[i, 1], dev1, FK1[i, 3], h, w, xi, ih0, ih1
        )
        al2, be2, e02, ci2, cm2, rho2, sig2 = _direction_bounds(
            q2a, v2a, FK2[i, 0], FK2[i + 1, 0], FK2[i, 1], dev2, FK2[i, 3], h, w, xi, ih0, ih1
        )
        # |q| along the step: the chord's larger end plus the radius, or the particular
        # solution's larger end plus the free vibration and the deviation's response
        top = max(math.hypot(q1a, q2a), math.hypot(q1b, q2b)) + math.hypot(rho1, rho2)
        part = max(math.hypot(al1, al2), math.hypot(al1 + be1 * h, al2 + be2 * h))
        top = min(top, part + math.hypot(cm1, cm2) + math.hypot(dev1, dev2) * ih0)
        if search_all:
            top = np.inf
        if top <= low:
            continue
        nflag = 0
        for j in range(nang):
            Mj = Mo[j]
            if search_all:
                flags[nflag] = j
                nflag += 1
                continue
            if Mj >= top:
                continue
            c = cs[j]
            s = sn[j]
            ac = abs(c)
            asn = abs(s)
            qa = c * q1a + s * q2a
            qb = c * q1b + s * q2b
            if max(abs(qa), abs(qb)) + ac * rho1 + asn * rho2 <= Mj:
                continue
            va = c * v1a + s * v2a
            vb = c * v1b + s * v2b
            if va * vb > 0.0 and min(abs(va), abs(vb)) > ac * sig1 + asn * sig2:
                continue  # monotone: its peak is at an end
            al = c * al1 + s * al2
            be = c * be1 + s * be2
            e0 = c * e01 + s * e02
            ci = c * ci1 + s * ci2
            bd = max(abs(al), abs(al + be * h)) + math.sqrt(e0 * e0 + ci * ci)
            if (bd + (ac * dev1 + asn * dev2) * ih0) * _MARGIN <= Mj:
                continue
            flags[nflag] = j
            nflag += 1
        vec = top > r100
        if nflag == 0 and not vec:
            continue
        _substep_polys(o, i, bank, d1, X1, g1, B, 0, h, m, K, Q1, cf, xs, xn)
        _substep_polys(o, i, bank, d2, X2, g2, B, 2, h, m, K, Q2, cf, xs, xn)
        if nflag:
            _search_angles(flags, nflag, cs, sn, Q1, Q2, m, K, hs, Mo, poly, work)
            low = Mo.min()
        if vec:
            _search_magnitude(Q1, Q2, m, K, hs, t0 + i * h, R2, W, o, poly, work)
            r100 = math.sqrt(R2[o])


@njit(cache=True)
def rotd_kernel(bank, d1, d2, X1, X2, k0, up, h, exact, search_all, ST, M, R2, W):
    """Advance every oscillator (``T > 0``) through one chunk of the record and update its
    peaks.

    Parameters
    ----------
    bank, d1, d2
        :class:`Bank` and the two :class:`Direction` s.
    X1, X2
        The chunk of each direction's building states from record step ``k0``
        (:meth:`floorslide.building.exact_motion.FloorMotion.chunks`: row ``i`` at the step
        grid's point ``k0·up + i``; no columns on the ground).
    up, h
        Steps per record step and their length (the building's own sub-steps on a floor).
    exact
        Search inside steps (else peaks at the record's samples only).
    search_all
        Search every step along every angle (tests: the skip rules change nothing).
    ST
        ``(n_osc, 4)``: ``q1, q1', q2, q2'`` at the chunk start, updated to its end.
    M
        ``(n_osc, n_angles)``: peaks of ``|q_θ|`` (updated).
    R2, W
        Peak of ``q1² + q2²`` (``n_osc``) and its time and ``(q1, q2)`` there (``(n_osc, 3)``).
    """
    nosc = bank.w.size
    kf0 = k0 * up
    L = X1.shape[0] - 1
    g1 = np.empty(L + 1)
    g2 = np.empty(L + 1)
    for i in range(L + 1):
        g1[i] = _sample(d1.acc, kf0 + i, up)
        g2[i] = _sample(d2.acc, kf0 + i, up)
    n = max(X1.shape[1], X2.shape[1])
    Kmax = max(bank.K.max(), d1.G_R.shape[1], d2.G_R.shape[1], d1.b_R.shape[0], d2.b_R.shape[0])
    Kmax = max(Kmax, d1.b_K + 2, d2.b_K + 2)
    c = np.zeros(Kmax + 2)
    xs = np.zeros(n)
    xn = np.zeros(n)
    FK1 = np.zeros((L + 1, 4))
    FK2 = np.zeros((L + 1, 4))
    _floor_values(d1, X1, g1, h, L, exact, FK1, c, xs, xn)
    _floor_values(d2, X2, g2, h, L, exact, FK2, c, xs, xn)
    B = np.empty((L + 1, 4))
    mmax = bank.G_m.max()
    ws = (
        np.zeros(M.shape[1], dtype=np.int64),
        np.zeros((mmax, Kmax + 2)),
        np.zeros((mmax, Kmax + 2)),
        np.zeros(2 * Kmax + 4),
        c,
        xs,
        xn,
        scratch(2 * Kmax + 2),
    )
    stride = 1 if exact else up
    for o in range(nosc):
        _states(o, d1, X1, g1, L, ST[o, 0], ST[o, 1], B, 0)
        _states(o, d2, X2, g2, L, ST[o, 2], ST[o, 3], B, 2)
        best = _sample_maxima(B, L + 1, stride, bank.cs, bank.sn, M[o], R2, o)
        if best >= 0:
            W[o, 0] = (kf0 + best) * h
            W[o, 1] = B[best, 0]
            W[o, 2] = B[best, 2]
        if exact:
            _oscillator_instep(
                o, bank, d1, d2, X1, X2, g1, g2, FK1, FK2, B, L, h, kf0 * h, search_all, M, R2, W,
                ws,
            )  # fmt: skip
        for j in range(4):
            ST[o, j] = B[L, j]


@njit(cache=True)
def rigid_kernel(d1, d2, X1, X2, k0, up, h, exact, search_all, cs, sn, M, R2, W):
    """Peaks of the floor acceleration itself (the rigid oscillator, period 0) through one
    chunk: along every angle (``M[0]``) and of its magnitude squared (``R2[0]``, ``W[0]``).

    On the ground the record is linear inside a step, and so is every rotation of it: the
    maxima are at the samples (and the magnitude, convex along a segment, too). On a floor the
    acceleration on a step is its Taylor polynomial (``R``, ``beta``, ``order``); a step is
    searched when its end values plus its chord deviation ``h²/8·max|f''|`` exceed a maximum.
    """
    kf0 = k0 * up
    L = X1.shape[0] - 1
    n1 = X1.shape[1]
    n2 = X2.shape[1]
    g1 = np.empty(L + 1)
    g2 = np.empty(L + 1)
    for i in range(L + 1):
        g1[i] = _sample(d1.acc, kf0 + i, up)
        g2[i] = _sample(d2.acc, kf0 + i, up)
    B = np.zeros((L + 1, 4))
    for i in range(L + 1):
        f = d1.beta[0] * g1[i]
        for j in range(n1):
            f += d1.R[0, j] * X1[i, j]
        B[i, 0] = f
        f = d2.beta[0] * g2[i]
        for j in range(n2):
            f += d2.R[0, j] * X2[i, j]
        B[i, 2] = f
    best = _sample_maxima(B, L + 1, 1 if exact else up, cs, sn, M[0], R2, 0)
    if best >= 0:
        W[0, 0] = (kf0 + best) * h
        W[0, 1] = B[best, 0]
        W[0, 2] = B[best, 2]
    if not exact or (n1 == 0 and n2 == 0):
        return
    K = max(d1.order, d2.order)
    P1 = np.zeros((1, 2 * K + 2))
    P2 = np.zeros((1, 2 * K + 2))
    poly = np.zeros(2 * K + 4)
    work = scratch(2 * K + 2)
    flags = np.zeros(M.shape[1], dtype=np.int64)
    Mo = M[0]
    low = Mo.min()
    r100 = math.sqrt(R2[0])
    for i in range(L):
        for j in range(P1.shape[1]):
            P1[0, j] = 0.0
            P2[0, j] = 0.0
        taylor_coefficients(d1.R, d1.beta, X1[i], g1[i], (g1[i + 1] - g1[i]) / h, P1[0])
        taylor_coefficients(d2.R, d2.beta, X2[i], g2[i], (g2[i + 1] - g2[i]) / h, P2[0])
        rho1 = 0.125 * h * h * curvature_bound(P1[0], K, h) * _MARGIN
        rho2 = 0.125 * h * h * curvature_bound(P2[0], K, h) * _MARGIN
        top = max(math.hypot(B[i, 0], B[i, 2]), math.hypot(B[i + 1, 0], B[i + 1, 2]))
        top += math.hypot(rho1, rho2)
        if search_all:
            top = np.inf
        if top <= low:
            continue
        nflag = 0
        for j in range(Mo.size):
            if Mo[j] >= top and not search_all:
                continue
            c = cs[j]
            s = sn[j]
            ends = max(abs(c * B[i, 0] + s * B[i, 2]), abs(c * B[i + 1, 0] + s * B[i + 1, 2]))
            if ends + abs(c) * rho1 + abs(s) * rho2 > Mo[j] or search_all:
                flags[nflag] = j
                nflag += 1
        if nflag:
            _search_angles(flags, nflag, cs, sn, P1, P2, 1, K, h, Mo, poly, work)
            low = Mo.min()
        if top > r100:
            _search_magnitude(P1, P2, 1, K, h, (kf0 + i) * h, R2, W, 0, poly, work)
            r100 = math.sqrt(R2[0])
