"""The Taylor series of a slip phase from rest under isotropic Coulomb friction in the plane.

A body at rest that starts to slide under a drive ``−a(τ)`` (per unit mass; ``a`` a known series)
against kinetic friction ``mug + mug1·τ`` has ``v' = −a − (mug + mug1 τ)·v/|v|``, singular at
``v = 0``: the phase starts as ``v = τ^m y`` and the recurrences of the moving series (Jorba &
Zou 2005), split along ``w₀`` and across it, give ``y``'s coefficients explicitly. Shared by the
rigid block in the plane (:mod:`floorslide.contents._plane_kernel`) and the mat of a building on
friction pendulums under two components (:mod:`floorslide.building._plane_isolation_kernel`).

References
----------
Jorba, À., Zou, M. (2005). A software package for the numerical integration of ODEs by means of
high-order Taylor methods. *Experimental Mathematics* 14(1), 99–117.
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit

_INV = np.array([0.0] + [1.0 / k for k in range(1, 128)])
"""``1/k`` (``_INV[0]`` unused): the recurrences multiply instead of dividing."""
SLOW_SWEEPS = 40
"""Most sweeps of :func:`slow_series`."""


@njit(cache=True, _nrt=False)
def start_series(a, K, m, mug, D, y, rho, w, mug1=0.0):
    """Taylor coefficients ``y[0..D]`` of a slip phase's velocity from rest,
    ``v(τ) = τ^m Σ_k y_k τ^k``, and those of ``ρ = |y|`` (``rho``; ``w = y/ρ``, scratch), under
    the floor acceleration with coefficients ``a[0..K]`` (``(K+1, 2)``) there: ``m = 1`` with
    ``|a₀| > mug``; ``m = 2`` at a breakaway with ``|a₀| = mug`` and ``|a|`` rising. The
    recurrences of :func:`moving_series`, split along ``w₀`` and across it, give each order
    explicitly. Returns ``D``, or −1 when the start is degenerate (``ρ₀ ≤ 0``).

    With vertical shaking the friction is ``mug + mug1·τ``: its term ``mug1·w_{k−1}`` at order
    ``k`` is known when ``y_k`` is solved for (``m = 1``: it joins ``−a_k``; ``m = 2``: ``w_{k−1}``
    does not depend on ``y_{k−1}``'s part along ``w₀``, and at order 1 ``ρ₀ = −½(ȧ₀·w₀ + mug1)``,
    ``mug1·w₀`` having no part across ``w₀``)."""
    for k in range(D + 1):
        y[k, 0] = 0.0
        y[k, 1] = 0.0
        rho[k] = 0.0
        w[k, 0] = 0.0
        w[k, 1] = 0.0
    n0 = np.hypot(a[0, 0], a[0, 1])
    if not n0 > 0.0:
        return -1
    w0x, w0y = -a[0, 0] / n0, -a[0, 1] / n0
    w[0, 0], w[0, 1] = w0x, w0y
    if m == 1:
        rho[0] = n0 - mug
        if not rho[0] > 0.0:
            return -1
        y[0, 0], y[0, 1] = rho[0] * w0x, rho[0] * w0y
        for k in range(1, D + 1):
            rk = 0.0
            for j in range(1, k):
                rk += y[j, 0] * y[k - j, 0] + y[j, 1] * y[k - j, 1] - rho[j] * rho[k - j]
            rk /= 2.0 * rho[0]
            sx, sy = 0.0, 0.0
            for j in range(1, k):
                sx += rho[j] * w[k - j, 0]
                sy += rho[j] * w[k - j, 1]
            ax = a[k, 0] if k <= K else 0.0
            ay = a[k, 1] if k <= K else 0.0
            hx = -ax + mug * (rk * w0x + sx) / rho[0]
            hy = -ay + mug * (rk * w0y + sy) / rho[0]
            if mug1 != 0.0:
                hx -= mug1 * w[k - 1, 0]
                hy -= mug1 * w[k - 1, 1]
            par = (hx * w0x + hy * w0y) / (k + 1)
            px, py = hx - (hx * w0x + hy * w0y) * w0x, hy - (hx * w0x + hy * w0y) * w0y
            f = 1.0 / (k + 1 + mug / rho[0])
            y[k, 0] = par * w0x + px * f
            y[k, 1] = par * w0y + py * f
            rho[k] = w0x * y[k, 0] + w0y * y[k, 1] + rk
            w[k, 0] = (y[k, 0] - rho[k] * w0x - sx) / rho[0]
            w[k, 1] = (y[k, 1] - rho[k] * w0y - sy) / rho[0]
        return D
    # m == 2: y₀ = ρ₀ w₀ with ρ₀ = ½ ȧ₀·â₀; order k fixes y_{k−1} along w₀ and y_k across it
    a1x = a[1, 0] if K >= 1 else 0.0
    a1y = a[1, 1] if K >= 1 else 0.0
    rho[0] = -0.5 * (a1x * w0x + a1y * w0y)
    if mug1 != 0.0:
        rho[0] -= 0.5 * mug1
    if not rho[0] > 0.0:
        return -1
    y[0, 0], y[0, 1] = rho[0] * w0x, rho[0] * w0y
    d = a1x * w0x + a1y * w0y
    y[1, 0] = -rho[0] * (a1x - d * w0x) / mug
    y[1, 1] = -rho[0] * (a1y - d * w0y) / mug
    for k in range(2, D + 2):
        # a. w_{k−1} (independent of y_{k−1}'s part along w₀) and ρ_{k−1} without that part
        rk1 = 0.0
        for j in range(1, k - 1):
            rk1 += y[j, 0] * y[k - 1 - j, 0] + y[j, 1] * y[k - 1 - j, 1] - rho[j] * rho[k - 1 - j]
        rk1 /= 2.0 * rho[0]
        dpar = y[k - 1, 0] * w0x + y[k - 1, 1] * w0y
        rho[k - 1] = dpar + rk1
        sx, sy = 0.0, 0.0
        for j in range(1, k - 1):
            sx += rho[j] * w[k - 1 - j, 0]
            sy += rho[j] * w[k - 1 - j, 1]
        w[k - 1, 0] = (y[k - 1, 0] - dpar * w0x - rk1 * w0x - sx) / rho[0]
        w[k - 1, 1] = (y[k - 1, 1] - dpar * w0y - rk1 * w0y - sy) / rho[0]
        # b, c. R_k and S_k·w₀ (y_{k−1}'s part along w₀ cancels in them)
        rk = 0.0
        for j in range(1, k):
            rk += y[j, 0] * y[k - j, 0] + y[j, 1] * y[k - j, 1] - rho[j] * rho[k - j]
        rk /= 2.0 * rho[0]
        sx, sy = 0.0, 0.0
        for j in range(1, k):
            sx += rho[j] * w[k - j, 0]
            sy += rho[j] * w[k - j, 1]
        wk_par = (-rk - (sx * w0x + sy * w0y)) / rho[0]
        # d. y_{k−1} along w₀
        ax = a[k, 0] if k <= K else 0.0
        ay = a[k, 1] if k <= K else 0.0
        ypar = (-(ax * w0x + ay * w0y) - mug * wk_par) / (k + 1)
        if mug1 != 0.0:
            ypar -= mug1 * (w[k - 1, 0] * w0x + w[k - 1, 1] * w0y) / (k + 1)
        perp_x = y[k - 1, 0] - dpar * w0x
        perp_y = y[k - 1, 1] - dpar * w0y
        y[k - 1, 0] = perp_x + ypar * w0x
        y[k - 1, 1] = perp_y + ypar * w0y
        rho[k - 1] = ypar + rk1
        if k > D:
            break
        # e. y_k across w₀
        sx, sy = 0.0, 0.0
        for j in range(1, k):
            sx += rho[j] * w[k - j, 0]
            sy += rho[j] * w[k - j, 1]
        spar = sx * w0x + sy * w0y
        dax = ax - (ax * w0x + ay * w0y) * w0x
        day = ay - (ax * w0x + ay * w0y) * w0y
        if mug1 != 0.0:
            wpar = w[k - 1, 0] * w0x + w[k - 1, 1] * w0y
            dax += mug1 * (w[k - 1, 0] - wpar * w0x)
            day += mug1 * (w[k - 1, 1] - wpar * w0y)
        y[k, 0] = (sx - spar * w0x) + rho[0] / mug * (-dax - (k + 1) * perp_x)
        y[k, 1] = (sy - spar * w0y) + rho[0] / mug * (-day - (k + 1) * perp_y)
    return D


@njit(cache=True, _nrt=False)
def slow_series(ax, ay, K, vx, vy, mug, D, L, y, rho, sl):
    """Taylor coefficients ``y[0..D]`` of a slow block's velocity on its slow manifold — the
    solution whose direction follows the floor's without the fast transient — through a point
    beside ``(vx, vy)``, and those of its speed ``ρ`` (``rho``); ``sl`` is scratch ``(5, D+2)``.

    In the frame ``e = v/|v|``, ``n`` (``e`` turned by +90°), ``v = ρ (cos φ e + sin φ n)`` with
    ``α = a·e``, ``β = a·n``: ``ρ' = −(α cos φ + β sin φ) − mug`` and
    ``ρ φ' = α sin φ − β cos φ``. The second is stiff (``φ`` relaxes at the rate ``|a|/ρ``); its
    order ``k`` is solved for ``φ_k`` instead of ``φ_{k+1}``:
    ``φ_k (a·w₀ − k ρ₁) = ρ₀ (k+1) φ_{k+1} + …`` (lower orders), order 0 for the slow
    direction, ``sin(φ₀ − γ) = −ρ₀ φ₁/|a₀|`` (``γ`` that of ``−a₀``), and the small term in
    ``φ_{k+1}`` is taken from the previous sweep (Gauss–Seidel; it contracts by about
    ``(k+1) ρ₀/(|a| R)``, ``R`` the reach of the series). ``ρ_{k+1}`` follows explicitly, with
    ``sin φ``, ``cos φ`` by their recurrences — no division by the small speed anywhere.

    The block's own velocity is ``ρ₀ e`` (``φ = 0``); the slow point differs from it by
    ``2ρ₀ |sin(φ₀/2)|``, sideways (``φ₀ ≈ π`` for a block moving along the floor's
    acceleration, away from the slow manifold). Returns ``(D, φ₀)``, or ``(−1, 0)`` when the
    slow manifold is not found (no floor acceleration, a near-resonant order, no convergence)."""
    phi = sl[0]
    sn = sl[1]
    cs = sl[2]
    al = sl[3]
    be = sl[4]
    r0 = np.hypot(vx, vy)
    ex = vx / r0
    ey = vy / r0
    for k in range(D + 2):
        al[k] = 0.0
        be[k] = 0.0
        phi[k] = 0.0
    for k in range(min(K, D) + 1):
        al[k] = ax[k] * ex + ay[k] * ey
        be[k] = ay[k] * ex - ax[k] * ey
    A0 = np.hypot(al[0], be[0])
    if not A0 > 0.0:
        return -1, 0.0
    gam = np.arctan2(-be[0], -al[0])  # the direction of −a₀ in the frame
    rho[0] = r0
    # the change of a sweep, Σ_k |Δφ_k| L^k (radians on the step), against Σ_k |φ_k| L^k
    for sweep in range(SLOW_SWEEPS):
        x = r0 * phi[1] / A0
        if not abs(x) < 1.0:
            return -1, 0.0
        f0 = gam - np.arcsin(x)
        change = abs(f0 - phi[0])
        size = abs(f0)
        phi[0] = f0
        sn[0] = np.sin(f0)
        cs[0] = np.cos(f0)
        d0 = al[0] * cs[0] + be[0] * sn[0]  # a₀·w₀
        rho[1] = -d0 - mug
        Lk = 1.0
        for k in range(1, D + 1):
            Lk *= L
            # sin φ, cos φ at order k but for their φ_k terms
            sp = 0.0
            cp = 0.0
            for j in range(1, k):
                sp += j * phi[j] * cs[k - j]
                cp += j * phi[j] * sn[k - j]
            sp *= _INV[k]
            cp *= -_INV[k]
            # order k of ρ φ' = α sin φ − β cos φ, for φ_k
            lhs = al[0] * sp - be[0] * cp
            for i in range(1, min(k, K) + 1):
                lhs += al[i] * sn[k - i] - be[i] * cs[k - i]
            rhs = r0 * (k + 1) * phi[k + 1]
            for j in range(2, k + 1):
                rhs += rho[j] * (k - j + 1) * phi[k - j + 1]
            den = d0 - k * rho[1]
            if not abs(den) > 1e-3 * A0:
                return -1, 0.0
            fk = (rhs - lhs) / den
            change += abs(fk - phi[k]) * Lk
            size += abs(fk) * Lk
            phi[k] = fk
            sn[k] = fk * cs[0] + sp
            cs[k] = cp - fk * sn[0]
            # ρ_{k+1} = −Σ_i (α_i cos φ + β_i sin φ)_{k−i} / (k+1)
            if k < D:
                t = 0.0
                for i in range(min(k, K) + 1):
                    t += al[i] * cs[k - i] + be[i] * sn[k - i]
                rho[k + 1] = -t * _INV[k + 1]
        if sweep > 0 and change <= 2.0**-52 * size:
            # v = ρ w, back in x, y
            for k in range(D + 1):
                pc = 0.0
                ps = 0.0
                for j in range(k + 1):
                    pc += rho[j] * cs[k - j]
                    ps += rho[j] * sn[k - j]
                y[k, 0] = pc * ex - ps * ey
                y[k, 1] = pc * ey + ps * ex
            return D, phi[0]
    return -1, 0.0
