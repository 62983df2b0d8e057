"""Compiled kernel of rigid blocks sliding in the plane: isotropic Coulomb friction under two
horizontal components, exact to rounding.

While a block slides, ``v' = −a(t) − mu_k·g·v/|v|`` (``v`` its velocity relative to the floor,
``a`` the floor's absolute acceleration, both 2-vectors). No closed form exists, so each slip
phase is integrated by its Taylor series (automatic differentiation: Jorba & Zou 2005) on the
floor's exact in-step polynomials: with ``r = |v|`` and ``w = v/r``, the recurrences
``r_k = (Σ_{j=0}^{k} v_j·v_{k−j} − Σ_{j=1}^{k−1} r_j r_{k−j})/(2 r_0)``,
``w_k = (v_k − Σ_{j=1}^{k} r_j w_{k−j})/r_0`` and ``(k+1) v_{k+1} = −a_k − mu_k g w_k`` give the
coefficients to a degree ``D`` whose terms have decayed below rounding on the step taken (step
size from the coefficients' decay, Jorba & Zou's rule ``h = ρ/e²``). From rest the series is
singular (``w`` undefined at ``v = 0``): the phase starts as ``v = τ^m y`` — ``m = 1`` when the
floor is beyond the kinetic level (``|a₀| > mu_k g``: ``y₀ = −(|a₀| − mu_k g)â₀``), ``m = 2`` at a
breakaway with ``mu_s = mu_k`` (``|a₀| = mu_k g``: ``y₀ = ½(ȧ₀·â₀)·(−â₀)``) — and the same
recurrences, split along ``w₀`` and across it, give ``y``'s coefficients explicitly.

A stop is the first root of the analytic ``r(τ)`` (it crosses zero; ``|v|`` only touches it),
located by rigorous root isolation on its series; there the block sticks if ``|a| ≤ mu_b g``,
else it slides on at once. A breakaway is the first instant ``|a|² > (mu_b g)²``, a polynomial
of the floor's coefficients. ``mu_b = max(mu_s, mu_k)``.

Slow blocks. The direction of a sliding block relaxes towards that of ``−a`` at the rate
``|a|/|v|``: at low speed the equation is stiff, and the series above (whose steps must resolve
that rate) reach only ≈ 6|v|/|a| — after a breakaway, before a stop, and wherever the floor
drives a block barely beyond kinetic friction (it creeps). Once the transient of the last change
of the floor's motion has decayed below rounding, the block is on its slow manifold, and one
series of that manifold (:func:`slow_series`: speed and angle, the angle's stiff order solved
implicitly) takes the whole sub-step or runs into the stop. And a block certain to stop within
the sub-step after sliding at most 1e-16 of its slide is stopped at once
(:func:`_negligible_stop`): the stop is a branch point of ``v``, which steps only approach.
Both replace thousands of steps in the worst cases; the velocity they start from is within
``2^-26`` of the block's (sideways: the speed within its rounding), the slide they drop below
1e-16 of the slide.

The helpers are compiled without numba's reference counting (no arrays are made in them;
numba would otherwise count every array argument in and out on every call).

References
----------
Jorba, À., Zou, M. (2005). A software package for the numerical integration of ODEs by means of
high-order Taylor methods. *Experimental Mathematics* 14(1), 99–117.
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import substep_inputs
from floorslide.building._plane_peak import plane_coefficients
from floorslide.numerics.friction_series import SLOW_SWEEPS, slow_series, start_series  # noqa: F401
from floorslide.numerics.polynomial import max_abs_on, poly_val, rise_within, scratch, taylor_shift

# columns of a block's state
MODE, UX, UY, VX, VY, PEAK, T_PEAK, ANGLE, SLIDE_TIME, SLIPS, STOPS, LIMIT_AT, START = range(13)
PATH, WORK_A, NPATH = 13, 14, 15
"""Mode (0 stuck, 1 sliding), the slide u and velocity v (2-vectors), peak |u|, its time and
direction (rad from h1 towards h2), time sliding, breakaways from stick, stops, start of the
first sub-step where the event limit was reached (−1: never), the order ``m`` of the current
slip phase's start from rest (0: from a moving state), the path slid ``∫|v| dt`` and the work
of the floor's acceleration ``∫ a·v dt`` (per unit mass: with the friction work
``mu_k g ∫|v| dt`` they balance the kinetic energy, ``½|v|² = −mu_k g·PATH − WORK_A``), and
``∫N|v| dt`` over the phases in contact (``N = g + a_v`` the normal acceleration: with vertical
shaking the balance is ``½|v|² = −mu_k·NPATH − WORK_A``)."""
NCOL = 16
MAX_EVENTS = 10000
"""Most events (stops, breakaways, restarts) of one block inside one sub-step."""
MAX_STEPS = 1_000_000
"""Most series steps of one block inside one sub-step. Steps shrink with the speed where the
floor drives the block barely beyond kinetic friction (``|a| ≈ mu_k g``: the block creeps, its
direction follows the floor's on a time scale of ``|v|/(mu_k g)``); such a sub-step can take
thousands of steps."""
EVENT_GAP = 1e-12
"""Shortest time between two events, as a fraction of the sub-step."""
STOP_SPEED = 1e-12
"""A sliding speed at or below ``STOP_SPEED·(|a| + mu_k g)·h`` (``h`` the sub-step) is a stop:
the direction of a velocity that small turns on a time scale below rounding (near a stop with a
rounding-level sideways velocity the series' radius shrinks with the speed, and the steps would
crawl); it is the 2-D form of the 1-D solver's stop at zero velocity."""


@njit(cache=True, inline="always")
def _ipow(x, n):
    """``x**n`` for an integer ``n ≥ 0`` by squaring (numba calls ``pow`` for a run-time
    exponent)."""
    r = 1.0
    while n > 0:
        if n & 1:
            r *= x
        x *= x
        n >>= 1
    return r


_INV = np.array([0.0] + [1.0 / k for k in range(1, 128)])
"""``1/k`` (``_INV[0]`` unused): the recurrences multiply instead of dividing."""
STOP_TOL = 1e-16
"""A sliding block whose stop is certain within the rest of the sub-step, and whose remaining
path is at most ``STOP_TOL`` of its slide (peak or current), is stopped at once: the slide
dropped is below the rounding of the slide itself (:func:`_negligible_stop`)."""
STEP_TOL = 1e-17
"""Jorba & Zou's step rule: the last two terms of the series on the step are below ``STEP_TOL``
of its first three (:func:`_step_size`)."""
SLOW_TOL = 2.0**-26
"""A slow-manifold step (:func:`slow_series`) is taken only when it moves the block's velocity by
at most ``SLOW_TOL`` of the speed, sideways (its speed then changes by at most ``SLOW_TOL²/2``,
the rounding of the speed), and when the fast transient so dropped slides the block by at most
:data:`STOP_TOL` of its slide."""
STIFF = 60.0
"""A slip step is stiff when ``|a|·L/|v| > STIFF`` (``L`` the rest of the sub-step): the
direction of a slow block relaxes at the rate ``|a|/|v|``, and the series of
:func:`moving_series` reach only ≈ 6·|v|/|a| — a slow-manifold step is tried then."""
SHORT_TOL = 1e-18
"""The series stops at a lower degree (at least 8) when two consecutive terms on the whole rest
of the sub-step are below ``SHORT_TOL`` of its first two: the step then takes the rest of the
sub-step, as :func:`_step_size` would grant."""


@njit(cache=True, _nrt=False)
def moving_series(ax, ay, K, vx, vy, r0, mug, D, L, y, rho, w, mug1=0.0):
    """Taylor coefficients ``y[0..De]`` of a sliding block's velocity ``v`` about its current
    point (``v(0) = (vx, vy) ≠ 0``, ``r0 = |v(0)|``) and those of ``ρ = |v|`` (``rho``;
    ``w = v/ρ`` in ``w``),
    under the floor acceleration with coefficients ``ax[0..K]``, ``ay[0..K]`` there.

    The recurrences (Jorba & Zou 2005), order by order: ``(k+1) v_{k+1} = −a_k − mug w_k``,
    ``ρ_k = w₀·v_k + Σ_{j=1}^{k−1} (v_j·v_{k−j} − ρ_j ρ_{k−j}) / (2ρ₀)`` (the sum is symmetric
    in ``j ↔ k−j``: half of it is formed, doubled), ``w_k = (v_k − Σ_{j=1}^{k} ρ_j w_{k−j})/ρ₀``.
    The degree is ``D``, or lower (``De ≥ 8``) as soon as two consecutive terms on ``[0, L]``
    are below :data:`SHORT_TOL` of the first two (``L > 0``). Returns ``De`` (``ρ`` is formed to
    ``De`` too, for the stop search), or −1 when ``v(0) = 0``. With vertical shaking the friction
    per unit direction is ``mug + mug1·τ`` (``mu_k·N(τ)``): ``(k+1) v_{k+1}`` gains
    ``−mug1·w_{k−1}``."""
    if not r0 > 0.0:
        return -1
    ir0 = 1.0 / r0
    h0 = 0.5 * ir0
    w0x = vx * ir0
    w0y = vy * ir0
    y[0, 0] = vx
    y[0, 1] = vy
    rho[0] = r0
    w[0, 0] = w0x
    w[0, 1] = w0y
    y1x = -ax[0] - mug * w0x
    y1y = -ay[0] - mug * w0y
    y[1, 0] = y1x
    y[1, 1] = y1y
    # the early end: squared terms on [0, L] against (SHORT_TOL·(|v₀| + |v₁| L))² (|v₁| bounded
    # from below by its larger component)
    tiny = SHORT_TOL * (r0 + max(abs(y1x), abs(y1y)) * L)
    tiny2 = tiny * tiny
    L2 = L * L
    L2k = L2
    t_prev = (y1x * y1x + y1y * y1y) * L2k
    De = D
    for k in range(1, D):
        # ρ_k
        s = 0.0
        for j in range(1, (k + 1) // 2):
            s += y[j, 0] * y[k - j, 0] + y[j, 1] * y[k - j, 1] - rho[j] * rho[k - j]
        s += s
        if k % 2 == 0:
            j = k // 2
            s += y[j, 0] * y[j, 0] + y[j, 1] * y[j, 1] - rho[j] * rho[j]
        rk = s * h0 + (w0x * y[k, 0] + w0y * y[k, 1])
        rho[k] = rk
        # w_k
        sx = rk * w0x
        sy = rk * w0y
        for j in range(1, k):
            sx += rho[j] * w[k - j, 0]
            sy += rho[j] * w[k - j, 1]
        wkx = (y[k, 0] - sx) * ir0
        wky = (y[k, 1] - sy) * ir0
        w[k, 0] = wkx
        w[k, 1] = wky
        # v_{k+1}
        akx = ax[k] if k <= K else 0.0
        aky = ay[k] if k <= K else 0.0
        if mug1 != 0.0:
            ykx = (-akx - mug * wkx - mug1 * w[k - 1, 0]) * _INV[k + 1]
            yky = (-aky - mug * wky - mug1 * w[k - 1, 1]) * _INV[k + 1]
        else:
            ykx = (-akx - mug * wkx) * _INV[k + 1]
            yky = (-aky - mug * wky) * _INV[k + 1]
        y[k + 1, 0] = ykx
        y[k + 1, 1] = yky
        L2k *= L2
        t = (ykx * ykx + yky * yky) * L2k
        if k + 1 >= 8 and t <= tiny2 and t_prev <= tiny2:
            De = k + 1
            break
        t_prev = t
    # ρ_De, for the stop search over the whole degree
    s = 0.0
    for j in range(1, De):
        s += y[j, 0] * y[De - j, 0] + y[j, 1] * y[De - j, 1] - rho[j] * rho[De - j]
    rho[De] = s * h0 + (w0x * y[De, 0] + w0y * y[De, 1])
    return De


@njit(cache=True, _nrt=False)
def frictionless_series(ax, ay, K, vx, vy, moving, D, L, y, rho, w):
    """Taylor coefficients of a block sliding without kinetic friction (``mu_k = 0``:
    ``v' = −a``, a polynomial): ``v(τ) = τ^m Σ_k y_k τ^k`` to degree ``D`` and those of
    ``ρ = |y|`` (``w = y/ρ`` in ``w``), for the path ``∫|v|`` and the step size. Moving
    (``v(0) = (vx, vy) ≠ 0``): ``m = 0``, ``y₀ = v(0)``, ``y_{k+1} = −a_k/(k+1)``. From rest:
    ``m = j + 1`` with ``a_j`` the floor's first coefficient whose term on the step ``[0, L]``
    exceeds :data:`STEP_TOL` of the largest, ``y_k = −a_{k+j}/(k+j+1)`` (the terms before it are
    rounding — a building's floor at rest starts with coefficients of order 1e-17 of the others,
    which as ``y₀`` would shrink the steps until ``τ^m`` underflows).
    The friction-free motion has no stop (its speed vanishes only where both components do at
    once, which a real record does not make happen). Returns ``m``, or −1 when the block is at
    rest on a floor at rest (every coefficient zero)."""
    for k in range(D + 1):
        y[k, 0] = 0.0
        y[k, 1] = 0.0
    if moving and vx == 0.0 and vy == 0.0:
        moving = False  # a velocity that came out exactly zero (a step's τ^m underflowed)
    if moving:
        m = 0
        y[0, 0] = vx
        y[0, 1] = vy
        for k in range(min(K, D - 1) + 1):
            y[k + 1, 0] = -ax[k] * _INV[k + 1]
            y[k + 1, 1] = -ay[k] * _INV[k + 1]
    else:
        big = 0.0
        Lj = 1.0
        for i in range(K + 1):
            big = max(big, (abs(ax[i]) + abs(ay[i])) * Lj)
            Lj *= L
        if not big > 0.0:
            return -1
        j = 0
        Lj = 1.0
        while (abs(ax[j]) + abs(ay[j])) * Lj <= STEP_TOL * big:
            j += 1
            Lj *= L
        m = j + 1
        for k in range(min(K - j, D) + 1):
            y[k, 0] = -ax[k + j] * _INV[k + j + 1]
            y[k, 1] = -ay[k + j] * _INV[k + j + 1]
    r0 = np.hypot(y[0, 0], y[0, 1])
    rho[0] = r0
    w[0, 0] = y[0, 0] / r0
    w[0, 1] = y[0, 1] / r0
    for k in range(1, D + 1):
        s = 0.0
        for i in range(1, k):
            s += y[i, 0] * y[k - i, 0] + y[i, 1] * y[k - i, 1] - rho[i] * rho[k - i]
        rk = s * 0.5 / r0 + (w[0, 0] * y[k, 0] + w[0, 1] * y[k, 1])
        rho[k] = rk
        sx = rk * w[0, 0]
        sy = rk * w[0, 1]
        for i in range(1, k):
            sx += rho[i] * w[k - i, 0]
            sy += rho[i] * w[k - i, 1]
        w[k, 0] = (y[k, 0] - sx) / r0
        w[k, 1] = (y[k, 1] - sy) / r0
    return m


@njit(cache=True, _nrt=False)
def _speed_step(rho, D, L):
    """The step on which the speed's series ``ρ`` (of degree ``D``) has its last two terms
    below :data:`STEP_TOL` of its first three (Jorba & Zou's rule, as :func:`_step_size`): the
    velocity of a friction-free block is a polynomial, but its speed ``|v|`` has branch points
    where ``v`` passes near zero, which bound the steps its path integral may take."""
    H = L
    for _ in range(2):
        H0 = H
        tol = STEP_TOL * (abs(rho[0]) + H * (abs(rho[1]) + H * abs(rho[2])))
        for k in (D, D - 1):
            nk = abs(rho[k])
            if nk * _ipow(H, k) > tol > 0.0:
                H = (tol / nk) ** (1.0 / k)
        if H == H0:
            break
    return H


@njit(cache=True, _nrt=False)
def _floor_square(ax, ay, K, q):
    """Coefficients of ``|a|² = a_x² + a_y²`` (degree 2K) into ``q``."""
    for j in range(2 * K + 1):
        q[j] = 0.0
    for i in range(K + 1):
        for j in range(K + 1):
            q[i + j] += ax[i] * ax[j] + ay[i] * ay[j]


@njit(cache=True, _nrt=False)
def _step_size(y, D, L):
    """Jorba & Zou's step: the largest ``H ≤ L`` on which the last two terms of the series are
    below :data:`STEP_TOL` of its first three (two passes, the scale taken on the step itself;
    the root is taken only for a term that limits the step). Norms are bounded without a
    square root: ``|x| + |y|`` from above for the terms, ``max(|x|, |y|)`` from below for the
    scale (a step at most that much shorter)."""
    H = L
    n0 = max(abs(y[0, 0]), abs(y[0, 1]))
    n1 = max(abs(y[1, 0]), abs(y[1, 1]))
    n2 = max(abs(y[2, 0]), abs(y[2, 1]))
    for _ in range(2):
        H0 = H
        tol = STEP_TOL * (n0 + H * (n1 + H * n2))
        for k in (D, D - 1):
            nk = abs(y[k, 0]) + abs(y[k, 1])
            if nk * _ipow(H, k) > tol > 0.0:  # (the test, not the root, for the next term)
                H = (tol / nk) ** (1.0 / k)
        if H == H0:
            break  # the same scale again: the same step
    return H


@njit(cache=True, inline="always")
def _negligible_stop(r0, ax, ay, K, L, mug, peak, ux, uy):
    """Whether a block sliding at speed ``r0`` under the floor acceleration ``ax, ay`` (degree
    K, on ``[0, L]``) certainly stops within ``T ≤ L`` after sliding at most ``STOP_TOL·U``
    (``U`` the larger of its peak slide and its slide ``(ux, uy)``), and then sticks
    (``mub ≥ mu_k``): if ``|a| ≤ A < mug`` on ``[0, T]``, the speed falls at least at
    ``mug − A`` (``r' = −a·w − mug``), so the block stops before ``r0/(mug − A)`` after a path
    ``≤ r0²/(2(mug − A))`` (``(½r²)' ≤ −(mug − A) r``), where it sticks. ``A`` is bounded by
    ``Σ_j |a_j| T^j`` on ``T = 2 r0/(mug − |a₀|)``. Returns that ``T`` (the time to the stop is
    at most it), or −1."""
    if r0 * r0 > 2.0 * mug * STOP_TOL * max(peak, abs(ux) + abs(uy)):
        return -1.0  # (a quick test first, with |u| ≤ |ux| + |uy|)
    U = max(peak, np.hypot(ux, uy))
    a0 = np.hypot(ax[0], ay[0])
    if not mug > a0:
        return -1.0
    T = 2.0 * r0 / (mug - a0)
    if T > L:
        return -1.0
    A = 0.0
    for j in range(K, -1, -1):
        A = A * T + np.hypot(ax[j], ay[j])
    if not (A < mug and r0 <= (mug - A) * T):
        return -1.0
    if r0 * r0 > 2.0 * (mug - A) * STOP_TOL * U:
        return -1.0
    return T


@njit(cache=True, _nrt=False)
def _advance(st, y, rho, De, m, tend, ax, ay, K, t_start, ux, uy, q, work, n0, n1):
    """Move a block's state along its slip step ``v(τ) = τ^m Σ_k y_k τ^k`` (speed
    ``τ^m Σ_k ρ_k τ^k``) over ``[0, tend]``: slide and velocity at ``tend``, the path
    ``∫|v|``, the floor's work ``∫ a·v`` (``a`` of degree K) and the peak ``|u|`` on the step
    (``t_start`` the step's start), and ``∫N|v|`` with the normal acceleration ``N = n0 + n1·τ``
    (0 in flight). ``ux, uy, q, work``: scratch (``q`` of size ≥ De + K + 1)."""
    # one Horner pass for the values at tend and the integrals ∫ τ^{k+m} = tend^{k+m+1}/(k+m+1)
    ix = 0.0  # Σ y_k tend^k/(k+m+1), and of |y_k|, and of ρ_k
    iy = 0.0
    bx = 0.0
    by = 0.0
    ip = 0.0
    ip2 = 0.0  # Σ ρ_k tend^k/(k+m+2), for ∫N|v|
    jx = 0.0  # Σ y_k tend^k/(k+m+2), for the floor's work
    jy = 0.0
    vx = 0.0  # Σ y_k tend^k
    vy = 0.0
    dv = 0.0  # Σ_{k≥1} (|y_k,x| + |y_k,y|) tend^k ≥ |v(τ) − v(0)| / τ^m
    for k in range(De, -1, -1):
        f = _INV[k + m + 1]
        g = _INV[k + m + 2]
        yx = y[k, 0]
        yy = y[k, 1]
        ix = ix * tend + yx * f
        iy = iy * tend + yy * f
        bx = bx * tend + abs(yx) * f
        by = by * tend + abs(yy) * f
        ip = ip * tend + rho[k] * f
        ip2 = ip2 * tend + rho[k] * g
        jx = jx * tend + yx * g
        jy = jy * tend + yy * g
        vx = vx * tend + yx
        vy = vy * tend + yy
        if k > 0:
            dv = (dv + abs(yx) + abs(yy)) * tend
    tm = _ipow(tend, m)
    tm1 = tm * tend
    path = ip * tm1
    # ∫ a·v = Σ_n c_n tend^{n+m+1}/(n+m+1), c_n = Σ_i a_i·y_{n−i}: for a linear floor
    # acceleration (the ground) from the pass above; else c accumulated a_i·y row by row (each
    # row independent terms, not one long sum per c_n), then one Horner pass
    if K <= 1:
        work_a = (ax[0] * ix + ay[0] * iy) * tm1
        if K == 1:
            work_a += (ax[1] * jx + ay[1] * jy) * tm1 * tend
    else:
        for n in range(De + K + 1):
            q[n] = 0.0
        for i in range(K + 1):
            cx = ax[i]
            cy = ay[i]
            for k in range(De + 1):
                q[i + k] += cx * y[k, 0] + cy * y[k, 1]
        work_a = 0.0
        for n in range(De + K, -1, -1):
            work_a = work_a * tend + q[n] * _INV[n + m + 1]
        work_a *= tm1
    st[PATH] += path
    st[NPATH] += n0 * path + n1 * ip2 * tm1 * tend
    st[WORK_A] += work_a
    u0x = st[UX]
    u0y = st[UY]
    uex = u0x + ix * tm1
    uey = u0y + iy * tm1
    # peak |u|: two bounds of |u| on the step first (|u0| + ∫|v|, and the coefficients'
    # magnitudes); then, moving away (u·v > 0 on the whole step, from
    # u·v ≥ u0·v0 − |u0| δv − ∫|v|·(|v0| + δv), δv ≥ |v − v0|), the end; else the maximum of
    # |u|² on the step, exactly
    peak2 = st[PEAK] * st[PEAK]
    u0 = abs(u0x) + abs(u0y)  # ≥ |u0|: the tests below stay valid
    if (u0 + path) * (u0 + path) > peak2:
        bx = abs(u0x) + bx * tm1
        by = abs(u0y) + by * tm1
        if bx * bx + by * by > peak2:
            moving_out = False
            if m == 0:
                uv = u0x * y[0, 0] + u0y * y[0, 1]
                moving_out = uv - u0 * dv - path * (rho[0] + dv) > 0.0
            deg = De + m + 1
            if moving_out:
                v2 = uex * uex + uey * uey
                tv = tend
            else:
                # u(τ) = u0 + Σ y_k τ^{k+m+1}/(k+m+1)
                for k in range(m + 1):
                    ux[k] = 0.0
                    uy[k] = 0.0
                ux[0] = u0x
                uy[0] = u0y
                for k in range(De + 1):
                    ux[k + m + 1] = y[k, 0] * _INV[k + m + 1]
                    uy[k + m + 1] = y[k, 1] * _INV[k + m + 1]
                for j in range(2 * deg + 1):
                    q[j] = 0.0
                for i in range(deg + 1):
                    for j in range(deg + 1):
                        q[i + j] += ux[i] * ux[j] + uy[i] * uy[j]
                v2, tv = max_abs_on(q, 2 * deg, tend, peak2, work)
            if v2 > peak2:
                st[PEAK] = np.sqrt(v2)
                st[T_PEAK] = t_start + tv
                if moving_out:
                    st[ANGLE] = np.arctan2(uey, uex)
                else:
                    st[ANGLE] = np.arctan2(poly_val(uy, deg, tv), poly_val(ux, deg, tv))
    st[UX] = uex
    st[UY] = uey
    st[VX] = vx * tm
    st[VY] = vy * tm


@njit(cache=True, inline="always")
def _speed_root(rho, De, lo, H, q, work):
    """The first root of the speed's series ``ρ`` (degree ``De``) on ``[lo, H]`` — a stop — or
    −1: none when ``ρ₀ > Σ_{j≥1} |ρ_j| H^j``, else by root isolation (``q`` scratch)."""
    reach = 0.0
    for j in range(De, 0, -1):
        reach = (reach + abs(rho[j])) * H
    if reach < rho[0]:
        return -1.0
    for k in range(De + 1):
        q[k] = -rho[k]
    return rise_within(q, De, lo, H, 0.0, work)


@njit(cache=True, _nrt=False)
def _block_substep(st, ax0, ay0, K, h, t0, g, mub, muk, D, ax, ay, A, y, rho, w, sl, q, ux,
                   uy, work, max_events, vert, n0, n1):  # fmt: skip
    """Advance one block through a sub-step of length ``h`` from time ``t0``, the floor's
    acceleration there ``(ax0, ay0)`` (coefficients, degree K). False when the event limit
    was reached.

    With vertical shaking (``vert``) the normal acceleration is ``N = n0 + n1·τ > 0`` on the
    (part of the) sub-step (the caller splits it where ``N`` changes sign and flies the block
    where ``N ≤ 0``: :func:`_flight`); friction is ``mu_k·N``, the breakaway level ``mu_b·N``;
    the slow-manifold steps and negligible stops (which assume a constant friction) are off.
    Without, ``N = g``."""
    level = mub * g
    mug = muk * g
    mug1 = 0.0
    nn = g  # N at the current point
    if vert:
        mug1 = muk * n1
    s0 = 0.0
    fresh = False
    events = 0
    steps = 0
    decay = 0.0  # the decay exponent of a fast transient since the last slow-manifold trial
    decay_need = 0.0  # the exponent needed before the next trial
    while s0 < h:
        L = h - s0
        lo = EVENT_GAP * h if fresh else 0.0
        # the floor's acceleration about the current point
        if s0 > 0.0:
            taylor_shift(ax0, K, s0, ax)
            taylor_shift(ay0, K, s0, ay)
        else:
            for j in range(K + 1):
                ax[j] = ax0[j]
                ay[j] = ay0[j]
        if vert:
            nn = n0 + n1 * s0
            level = mub * nn
            mug = muk * nn
        if st[MODE] == 0.0:
            # stuck: the first instant |a|² rises above the breakaway level
            _floor_square(ax, ay, K, q)
            if vert:
                # |a|² − (mu_b N)², N = nn + n1 σ
                for j in range(2 * K + 1, 3):
                    q[j] = 0.0
                mb2 = mub * mub
                q[0] -= mb2 * nn * nn
                q[1] -= 2.0 * mb2 * nn * n1
                q[2] -= mb2 * n1 * n1
                tb = rise_within(q, max(2 * K, 2), lo, L, 0.0, work)
            else:
                tb = rise_within(q, 2 * K, lo, L, level * level, work)
            if tb < 0.0:
                return True
            s0 += tb
            if vert:
                nn = n0 + n1 * s0
                level = mub * nn
                mug = muk * nn
            st[MODE] = 1.0
            st[SLIPS] += 1.0
            st[VX] = 0.0
            st[VY] = 0.0
            st[START] = 2.0 if mub == muk and mug > 0.0 else 1.0
            fresh = True
            continue
        m = int(st[START])
        if muk == 0.0:
            # no kinetic friction: v' = −a, no stop, no stiffness
            m = frictionless_series(ax, ay, K, st[VX], st[VY], m == 0, D, L, y, rho, w)
            if m < 0:
                return True  # at rest on a floor at rest for the rest of the sub-step
            H = min(_step_size(y, D, L), _speed_step(rho, D, L))
            _advance(st, y, rho, D, m, H, ax, ay, K, t0 + s0, ux, uy, q, work, nn,
                     n1 if vert else 0.0)  # fmt: skip
            st[SLIDE_TIME] += H
            s0 += H
            st[START] = 0.0
            fresh = False
            steps += 1
            if steps > MAX_STEPS:
                return False
            continue
        stop_now = False
        stiff = False
        r0 = 0.0
        a0 = 0.0
        if m == 0:
            r0 = np.hypot(st[VX], st[VY])
            a0 = max(abs(ax[0]), abs(ay[0]))  # |a| within √2, from below
            stiff = a0 * L > STIFF * r0 and not vert
            if r0 <= STOP_SPEED * (a0 + mug) * h:
                # the speed within rounding of zero: a stop here (a velocity that passes that
                # close to zero turns on a time scale below rounding; steps would crawl)
                stop_now = True
            elif not vert:
                T = _negligible_stop(r0, ax, ay, K, L, mug, st[PEAK], st[UX], st[UY])
                if T >= 0.0:
                    # a certain stop whose remaining slide is below the slide's rounding (the
                    # series would only crawl towards it: the stop is a branch point of v)
                    stop_now = True
                    # the time to it (≤ T): that of a straight deceleration, the first order
                    dec = mug + (ax[0] * st[VX] + ay[0] * st[VY]) / r0
                    st[SLIDE_TIME] += min(r0 / dec, T)
        slow = False
        must_stop = False
        if stop_now:
            De = -2
        elif m == 0:
            De = -1
            if stiff and decay >= decay_need:
                # stiff: the block's direction relaxes much faster than the step; a step on the
                # slow manifold, once the transient of the last change of the floor's motion has
                # died out (the sideways offset of the slow point is that transient)
                U = max(st[PEAK], np.hypot(st[UX], st[UY]))
                rho1 = -(ax[0] * st[VX] + ay[0] * st[VY]) / r0 - mug
                # (a) the transient's slide below STOP_TOL of the slide: it decays at the rate
                # |a|/ρ, ρ = r0 + ρ'τ, as (1 + ρ'τ/r0)^(−|a|/ρ'), which slides the block by
                # off·r0/(|a| − ρ') ≤ off·r0/mug in all (ρ' ≤ |a| − mug); (b) the speed moved
                # by ≤ SLOW_TOL²/2 of itself; (b') decelerating, and the step ends in a stop:
                # the speed moved by off²/(2 r0) moves that stop by ≤ off²/(2|ρ'|) only, and
                # is then gone
                tol_a = 0.5 * STOP_TOL * U * mug / r0
                tol_b = SLOW_TOL * r0
                tol_c = np.sqrt(0.5 * STOP_TOL * U * -rho1) if rho1 < 0.0 else 0.0
                best = min(tol_a, max(tol_b, tol_c))
                # the angle to the slow point to first order (the direction of −a, lagging by
                # r0 θ'/|a|, θ' the rate at which a turns; measured within a few % of the lag),
                # to skip trials bound to fail
                an2 = ax[0] * ax[0] + ay[0] * ay[0]
                an = np.sqrt(an2)
                vx0 = st[VX]
                vy0 = st[VY]
                pred = np.arctan2(ax[0] * vy0 - ay[0] * vx0, -(ax[0] * vx0 + ay[0] * vy0))
                lag = 0.0
                if K >= 1 and an2 > 0.0:
                    lag = r0 * (ax[0] * ay[1] - ay[0] * ax[1]) / (an2 * an)
                off = 2.0 * r0 * abs(np.sin(0.5 * (pred - lag)))
                if off <= 4.0 * best + 0.1 * r0 * abs(lag):
                    De, phi0 = slow_series(ax, ay, K, st[VX], st[VY], mug, D, L, y, rho, sl)
                    if De >= 0:
                        off = 2.0 * r0 * abs(np.sin(0.5 * phi0))  # |v_slow − v|
                        if off <= min(tol_a, tol_b):
                            slow = True
                        elif off <= min(tol_a, tol_c):
                            slow = True
                            must_stop = True
                    else:
                        decay_need = np.inf  # no slow manifold found: explicit steps
                if not slow and decay_need < np.inf:
                    # explicit steps until the transient has decayed by e^−need
                    decay_need = np.log(off / best) + 1.0 if best > 0.0 else np.inf
                    decay = 0.0
                    De = -1
            if not slow:
                De = moving_series(ax, ay, K, st[VX], st[VY], r0, mug, D, L, y, rho, w, mug1)
        else:
            for k in range(K + 1):
                A[k, 0] = ax[k]
                A[k, 1] = ay[k]
            De = start_series(A, K, m, mug, D, y, rho, w, mug1)
        if De == -1:
            # a degenerate start (the floor exactly at the kinetic level and not rising):
            # no slip — the block stays at rest here
            st[MODE] = 0.0
            st[VX] = 0.0
            st[VY] = 0.0
            st[START] = 0.0
            fresh = True
            events += 1
            if events > max_events:
                return False
            continue
        ts = -1.0
        if De >= 0:
            H = _step_size(y, De, L) if De == D or m != 0 or slow else L
            # a stop: the first root of ρ on [0, H] (r = τ^m ρ crosses zero there)
            ts = _speed_root(rho, De, 0.0, H, q, work)
            if must_stop and ts < 0.0:
                # no stop on the slow step after all: an explicit step instead
                De = moving_series(ax, ay, K, st[VX], st[VY], r0, mug, D, L, y, rho, w, mug1)
                slow = False
                decay_need = np.inf
                H = _step_size(y, De, L) if De == D else L
                ts = _speed_root(rho, De, 0.0, H, q, work)
            tend = ts if ts >= 0.0 else H
            _advance(st, y, rho, De, m, tend, ax, ay, K, t0 + s0, ux, uy, q, work, nn,
                     n1 if vert else 0.0)  # fmt: skip
            st[SLIDE_TIME] += tend
            s0 += tend
        if De == -2 or ts >= 0.0:
            # a stop: the block sticks if the floor is at or below the breakaway level there,
            # else it slides on at once, from rest, beyond the kinetic level
            st[VX] = 0.0
            st[VY] = 0.0
            st[STOPS] += 1.0
            ex = poly_val(ax0, K, s0)
            ey = poly_val(ay0, K, s0)
            if vert:
                level = mub * (n0 + n1 * s0)
            if ex * ex + ey * ey <= level * level:
                st[MODE] = 0.0
                st[START] = 0.0
            else:
                st[START] = 1.0
            fresh = True
            events += 1
            if events > max_events:
                return False
        else:
            steps += 1
            if steps > MAX_STEPS:
                return False
            st[START] = 0.0  # (_advance set the velocity)
            if m == 0 and not slow and stiff:
                # the decay of a fast transient over the step: e^−∫|a|/|v|
                decay += a0 * tend / max(rho[0], abs(st[VX]) + abs(st[VY]))
            fresh = False
    return True


@njit(cache=True, _nrt=False)
def _flight(st, ax0, ay0, K, h, t0, D, ax, ay, y, rho, w, q, ux, uy, work):
    """Advance one block through a sub-step part of length ``h`` (from time ``t0``, floor
    coefficients ``ax0, ay0``) where the normal force is zero (lift-off, ``g + a_v ≤ 0``): no
    friction, so no sticking — ``v' = −a`` exactly (:func:`frictionless_series`); a block at rest
    moves with the floor's first change (a breakaway, counted). Where the speed's analytic
    series ``ρ`` has a root (the velocity passes through zero: along one line exactly, else
    within rounding) the step ends there and the block goes on from rest (else its steps would
    crawl towards the branch point of ``|v|``); a speed at or below
    ``STOP_SPEED·|a|·h`` is taken as zero, as in contact. False when the step limit was
    reached."""
    s0 = 0.0
    steps = 0
    while s0 < h:
        L = h - s0
        if s0 > 0.0:
            taylor_shift(ax0, K, s0, ax)
            taylor_shift(ay0, K, s0, ay)
        else:
            for j in range(K + 1):
                ax[j] = ax0[j]
                ay[j] = ay0[j]
        r0 = np.hypot(st[VX], st[VY])
        if r0 <= STOP_SPEED * (abs(ax[0]) + abs(ay[0])) * h:
            st[VX] = 0.0
            st[VY] = 0.0
            r0 = 0.0
        m = frictionless_series(ax, ay, K, st[VX], st[VY], r0 > 0.0, D, L, y, rho, w)
        if m < 0:
            return True  # at rest on a floor at rest for the rest of the part
        if st[MODE] == 0.0:
            st[MODE] = 1.0
            st[SLIPS] += 1.0
        H = min(_step_size(y, D, L), _speed_step(rho, D, L))
        # the first root of ρ on the step (where ρ's series has converged: beyond, its roots
        # are spurious)
        ts = _speed_root(rho, D, EVENT_GAP * h if m == 0 else 0.0, H, q, work)
        if ts >= 0.0:
            H = ts
        _advance(st, y, rho, D, m, H, ax, ay, K, t0 + s0, ux, uy, q, work, 0.0, 0.0)
        if ts >= 0.0:
            st[VX] = 0.0
            st[VY] = 0.0
        s0 += H
        st[START] = 0.0
        steps += 1
        if steps > MAX_STEPS:
            return False
    return True


@njit(cache=True, _nrt=False)
def _vertical_substep(st, c1, c2, c1s, c2s, K, h, t0, n0, n1, g, mub, muk, D, ax, ay, A, y, rho,
                      w, sl, q, ux, uy, work, max_events):  # fmt: skip
    """One block through a sub-step with vertical shaking, ``N = n0 + n1·τ``: split at the root
    of ``N`` (linear: exact), flown where ``N ≤ 0`` (:func:`_flight`), in contact elsewhere
    (:func:`_block_substep`). False when a limit was reached."""
    tz = -1.0
    if n1 != 0.0:
        tz = -n0 / n1
        if not (0.0 < tz < h):
            tz = -1.0
    p = 0.0
    ok = True
    for piece in range(2):
        if piece == 1 and tz < 0.0:
            break
        hp = (tz if tz >= 0.0 else h) if piece == 0 else h - tz
        if piece == 0:
            for j in range(K + 1):
                c1s[j] = c1[j]
                c2s[j] = c2[j]
            np0 = n0
        else:
            p = tz
            taylor_shift(c1, K, p, c1s)
            taylor_shift(c2, K, p, c2s)
            np0 = 0.0  # N at its root
        if np0 + n1 * 0.5 * hp <= 0.0:
            ok = _flight(st, c1s, c2s, K, hp, t0 + p, D, ax, ay, y, rho, w, q, ux, uy, work)
        else:
            ok = _block_substep(st, c1s, c2s, K, hp, t0 + p, g, mub, muk, D, ax, ay, A, y, rho,
                                w, sl, q, ux, uy, work, max_events, True, np0, n1)  # fmt: skip
        if not ok:
            return False
    return True


@njit(cache=True)
def plane_kernel(X1, X2, k0, R1, b1, R2, b2, acc1, acc2, substeps, h, g, MU, states, hist,
                 want_hist, D, max_events, accv, has_vert):  # fmt: skip
    """Rigid blocks sliding in the plane on one floor, exact to rounding for the
    piecewise-linear ground records of the two directions.

    ``X1, X2``: one chunk each of the floor motions of direction 1 (driven by ``acc1``) and 2
    (by ``acc2``) from record step ``k0``, on the same sub-steps
    (:meth:`floorslide.building.exact_motion.FloorMotion.chunks`); ``R1, b1`` / ``R2, b2``
    their Taylor rows of the floor's absolute acceleration. ``MU = [mu_b; mu_k]`` per block;
    ``states`` ``(n, NCOL)`` in/out; ``hist[i, k] = (u_x, u_y)`` at the samples when
    ``want_hist``. ``accv``: the vertical ground acceleration samples when ``has_vert`` (the
    normal acceleration is ``g + accv``, linear between samples; the building is rigid
    vertically)."""
    K = max(R1.shape[0], R2.shape[0]) - 1
    degmax = 2 * (D + 3) + 2
    work = scratch(max(degmax, 2 * K + 2))
    c1 = np.zeros(K + 1)
    c2 = np.zeros(K + 1)
    ax = np.zeros(K + 1)
    ay = np.zeros(K + 1)
    A = np.zeros((K + 1, 2))
    y = np.zeros((D + 2, 2))
    rho = np.zeros(D + 2)
    w = np.zeros((D + 2, 2))
    sl = np.zeros((5, D + 2))
    q = np.zeros(max(degmax, D + K) + 1)
    ux = np.zeros(D + 4)
    uy = np.zeros(D + 4)
    c1s = np.zeros(K + 1)
    c2s = np.zeros(K + 1)
    _plane_steps(X1, X2, k0, R1, b1, R2, b2, acc1, acc2, substeps, h, g, MU, states, hist,
                 want_hist, D, max_events, K, c1, c2, ax, ay, A, y, rho, w, sl, q, ux, uy,
                 work, accv, has_vert, c1s, c2s)  # fmt: skip


@njit(cache=True, _nrt=False)
def _plane_steps(X1, X2, k0, R1, b1, R2, b2, acc1, acc2, substeps, h, g, MU, states, hist,
                 want_hist, D, max_events, K, c1, c2, ax, ay, A, y, rho, w, sl, q, ux, uy,
                 work, accv, has_vert, c1s, c2s):  # fmt: skip
    """The loops of :func:`plane_kernel` over sub-steps and blocks, given its scratch;
    compiled without reference counting (the rows and views made here cost nothing)."""
    nobj = MU.shape[1]
    nsteps = (X1.shape[0] - 1) // substeps
    if k0 == 0:
        # a floor beyond the breakaway level at t = 0 sets the block sliding from the start
        a1 = b1[0] * acc1[0]
        a2 = b2[0] * acc2[0]
        nstart = g + accv[0] if has_vert else g
        for i in range(nobj):
            if (states[i, MODE] == 0.0 and nstart > 0.0
                    and a1 * a1 + a2 * a2 > (MU[0, i] * nstart) ** 2):  # fmt: skip
                states[i, MODE] = 1.0
                states[i, SLIPS] += 1.0
                states[i, START] = 1.0
            if want_hist:
                hist[i, 0, 0] = states[i, UX]
                hist[i, 0, 1] = states[i, UY]
    for kk in range(nsteps):
        k = k0 + kk
        s1 = (acc1[k + 1] - acc1[k]) / (substeps * h)
        s2 = (acc2[k + 1] - acc2[k]) / (substeps * h)
        va = 0.0
        vslope = 0.0
        if has_vert:
            va = accv[k]
            vslope = (accv[k + 1] - va) / (substeps * h)
        for r in range(substeps):
            t0 = (k * substeps + r) * h
            a1, _ = substep_inputs(acc1[k], acc1[k + 1], r, substeps)
            a2, _ = substep_inputs(acc2[k], acc2[k + 1], r, substeps)
            row = kk * substeps + r
            reach = plane_coefficients(R1, b1, X1[row], a1, s1, R2, b2, X2[row], a2, s2, h, c1, c2)
            nlow = g
            n0 = g
            if has_vert:
                # N = g + a_v, linear on the sub-step (as the 1-D solver's)
                n0 = g + va + vslope * (r * h)
                nlow = min(n0, n0 + vslope * h)
            for i in range(nobj):
                if states[i, MODE] == 0.0 and nlow > 0.0 and reach <= MU[0, i] * nlow:
                    continue  # |a| ≤ Σ_j |c_j| h^j stays below the breakaway level
                st = states[i]
                if has_vert:
                    ok = _vertical_substep(st, c1, c2, c1s, c2s, K, h, t0, n0, vslope, g,
                                           MU[0, i], MU[1, i], D, ax, ay, A, y, rho, w, sl, q,
                                           ux, uy, work, max_events)  # fmt: skip
                else:
                    ok = _block_substep(st, c1, c2, K, h, t0, g, MU[0, i], MU[1, i], D, ax, ay,
                                        A, y, rho, w, sl, q, ux, uy, work, max_events, False, g,
                                        0.0)  # fmt: skip
                if not ok and st[LIMIT_AT] < 0.0:
                    st[LIMIT_AT] = t0
            if want_hist and r == substeps - 1:
                for i in range(nobj):
                    hist[i, k + 1, 0] = states[i, UX]
                    hist[i, k + 1, 1] = states[i, UY]
