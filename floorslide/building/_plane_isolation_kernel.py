"""Compiled kernel of a shear building on friction pendulums under two horizontal components:
the bearing's friction circle coupled with the superstructure in both directions, exact to
rounding for the piecewise-linear records.

Each direction ``d`` has its own linear superstructure on the shared mat (state
``x_d = [u_d; u_d']``, ``n`` degrees of freedom, ``u_d[0]`` the mat relative to the ground)::

    x_d' = A_d x_d + b_d a_d(t) + e (−mu N(t) w_d − (k a_v(t)/g) u_d[0]),   w = V/|V|

with ``A_d`` the sliding system (the pendulum's ``k = W/R`` and damping in it), ``e`` the mat's
velocity row scaled by ``1/m_b``, ``V = (u_x[0]', u_y[0]')`` the mat's velocity and
``N = W (1 + a_v/g)`` the normal force (``a_v`` the vertical ground acceleration: the
pendulum's restoring force scales with it too). While stuck, ``V ≡ 0`` and the friction the mat
needs is ``m_b G(t)``, ``G`` the mat's acceleration from everything but friction; the mat breaks
away when ``|G|`` reaches ``mu_s N/m_b`` (the friction circle).

No closed form exists while sliding, so each step is integrated by its Taylor series (automatic
differentiation, Jorba & Zou 2005): the state's coefficients order by order from
``(j+1) x_{j+1} = A x_j + b a_j + e(·)_j``, with the friction direction's coefficients from the
recurrences of :mod:`floorslide.contents._plane_kernel` (``ρ = |V|``, ``w = V/ρ``); the degree
is :data:`DEGREE` and the step the largest on which its last two terms are below
:data:`STEP_TOL` of its first three (for the state and for its derivative, which carries the
floors' accelerations). A slip phase from rest is ``V = τ^m y`` (``m = 1`` above the kinetic
level, ``m = 2`` at a breakaway with ``mu_s = mu``): its series is that of
:func:`~floorslide.contents._plane_kernel.start_series` for the mat driven by ``−G``, and since
``G``'s order ``k`` depends on ``V`` only to order ``k − 1``, iterating the two fixes one more
order per sweep (:func:`_start_coefficients`). The stuck building is stepped by the same series
with the mat's rows held.

Events are located rigorously (:func:`floorslide.numerics.polynomial.rise_within`) on the
series: a stop is the first root of ``ρ(τ)``, where the mat sticks if ``|G| ≤ mu_s N/m_b`` or
else slides on at once; a breakaway is the first rise of ``|G|² − (mu_s N/m_b)²``.

Every step is a *segment* of the building's exact motion, recorded with the Taylor
coefficients of the floors' absolute accelerations on it
(:class:`floorslide.building.poly_segments.PolySegments`): what every consumer reads.

References
----------
Jorba, À., Zou, M. (2005). A software package for the numerical integration of ODEs by means of
high-order Taylor methods. *Experimental Mathematics* 14(1), 99–117.
Mokha, A., Constantinou, M. C., Reinhorn, A. M. (1993). Verification of friction model of
Teflon bearings under triaxial load. *J. Struct. Eng.* 119(1), 240–261 (the friction circle of
a sliding bearing under two components).
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.numerics.friction_series import slow_series, start_series
from floorslide.numerics.polynomial import max_abs_on, poly_val, rise_within, scratch

DEGREE = 24
"""Degree of the state's Taylor series on a step (the floors' accelerations: one less)."""
STEP_TOL = 1e-17
"""Jorba & Zou's step rule: the last two terms on the step below this share of the first
three."""
EVENT_GAP = 1e-12
"""Shortest time between two events, as a share of the sub-step."""
STOP_SPEED = 1e-11
"""A sliding speed at or below ``STOP_SPEED·(|G| + c)·h`` is a stop: the mat would stop (or
turn) within ``STOP_SPEED·h``, moving by at most ``STOP_SPEED²·(|G| + c)·h²``; the direction of
a velocity that small turns on a time scale where the series (whose coefficients grow as
``(|G|/|V|)^j``) would overflow. A series that overflows is a stop too."""
STIFF = 60.0
"""A slip step is stiff when ``|G|·L/|V| > STIFF`` (``L`` the rest of the sub-step): the
direction of a slow mat relaxes at the rate ``|G|/|V|`` and the series reach only about
``6|V|/|G|`` — a slow-manifold step is tried then (:func:`_slow_coefficients`)."""
SLOW_TOL = 2.0**-26
"""A slow-manifold step is taken only when the slow point differs from the mat's velocity by
at most this share of the speed, sideways (its speed then changes by at most its rounding)."""
SPEED_TOL = 1e-12
"""A sliding speed at or below this share of the mat's largest speed so far is a stop too: the
rounding of a velocity that has come down from its peak (a mat that stops where the drive is
exactly the friction limit, as a pendulum at rest at ``mu·R``, would otherwise creep on at that
rounding level, on steps of ``|V|/(mu g)``)."""
CREEP_TOL = 1e-15
"""A mat whose slip over the rest of the sub-step is certainly below this share of its
displacement (peak or current) is held stuck (:func:`_negligible`): a demand that grazes the
friction circle (a stop where the drive is the friction limit, a flexible superstructure
ringing on a mat at the limit) would otherwise start slips at rounding-level speeds, whose
direction turns on steps of ``|V|/(mu g)`` — without end."""
BREAK_TOL = 1e-14
"""The mat breaks away when ``|G|`` exceeds the friction circle by more than this share of it:
a mat stuck exactly at the limit (a pendulum at rest at ``mu·R``) has ``|G|`` at the limit up
to rounding, which is not a breakaway (it would break away and stop again without end)."""
DROP_TOL = 2.0**-60
"""A recorded floor coefficient whose term on its segment is at most this share of the
polynomial's size there is set to zero (below rounding: :func:`_record`)."""
MAX_STEPS = 200_000
"""Most series steps in one sub-step."""
STICK, SLIP = 0, 1

# columns of the carried state (see plane_run)
C_MODE, C_START, C_FRESH, C_EVENTS, C_STEPS = range(5)
# columns of the peaks
P_DISP, P_TIME, P_ANGLE, P_FORCE, P_FTIME, P_WORK, P_SLIDE_TIME, P_SPEED = range(8)
NPEAK = 8
# event kinds
EV_BREAK, EV_STICK, EV_ON = 1, 2, 3


@njit(cache=True)
def _series(mode, start, X, x0, A, bv, ga, ev, kv, n, D, c0, c1, y, rho, w, a2, yold):
    """Taylor coefficients ``X[d, j, :]`` (``j ≤ D``) of the state about the current point.

    ``mode``: STICK (the mat's rows held), SLIP from a moving state (``start = 0``) or from rest
    (``start = m``). ``x0[d]``: the state; ``A[d]``, ``bv[d]`` the direction's system and
    ground column; ``ga[d] = (a, slope)`` the ground about the point; ``ev = (av, av')`` the
    vertical ground acceleration, ``kv = k/(m_b g)``; ``c0 + c1 τ`` the kinetic friction per
    unit mat mass. Returns the degree of the speed's series in ``rho`` (SLIP; −1 when a start
    is degenerate) — ``ρ`` of ``V`` (moving) or of ``y = V/τ^m`` (from rest) — or 0."""
    N = 2 * n
    for d in range(2):
        for i in range(N):
            X[d, 0, i] = x0[d, i]
    if mode == SLIP and start > 0:
        return _start_coefficients(start, X, A, bv, ga, ev, kv, n, D, c0, c1, y, rho, w, a2,
                                   yold)  # fmt: skip
    frictionless = c0 == 0.0 and c1 == 0.0
    r0 = 0.0
    if mode == SLIP and not frictionless:
        vx = X[0, 0, n]
        vy = X[1, 0, n]
        r0 = np.hypot(vx, vy)
        if not r0 > 0.0:
            return -1
        rho[0] = r0
        w[0, 0] = vx / r0
        w[0, 1] = vy / r0
    for j in range(D):
        if mode == SLIP and not frictionless and j > 0:
            # ρ_j and w_j from V_0..V_j (Jorba & Zou's recurrences for |V| and V/|V|)
            s = 0.0
            for i in range(1, j):
                s += X[0, i, n] * X[0, j - i, n] + X[1, i, n] * X[1, j - i, n] - rho[i] * rho[j - i]
            rj = s / (2.0 * r0) + (w[0, 0] * X[0, j, n] + w[0, 1] * X[1, j, n])
            rho[j] = rj
            sx = rj * w[0, 0]
            sy = rj * w[0, 1]
            for i in range(1, j):
                sx += rho[i] * w[j - i, 0]
                sy += rho[i] * w[j - i, 1]
            w[j, 0] = (X[0, j, n] - sx) / r0
            w[j, 1] = (X[1, j, n] - sy) / r0
        inv = 1.0 / (j + 1)
        for d in range(2):
            Ad = A[d]
            aj = ga[d, j] if j < 2 else 0.0
            for i in range(N):
                if mode == STICK and (i == 0 or i == n):
                    X[d, j + 1, i] = 0.0
                    continue
                s = bv[d, i] * aj
                for q in range(N):
                    s += Ad[i, q] * X[d, j, q]
                if i == n:
                    s -= _vertical_term(X, d, j, ev, kv)
                    if mode == SLIP and not frictionless:
                        s -= c0 * w[j, d]
                        if j > 0:
                            s -= c1 * w[j - 1, d]
                X[d, j + 1, i] = s * inv
    if mode == SLIP and not frictionless:
        # ρ_D for the stop search over the whole degree
        s = 0.0
        for i in range(1, D):
            s += X[0, i, n] * X[0, D - i, n] + X[1, i, n] * X[1, D - i, n] - rho[i] * rho[D - i]
        rho[D] = s / (2.0 * r0) + (w[0, 0] * X[0, D, n] + w[0, 1] * X[1, D, n])
        return D
    return 0


@njit(cache=True, inline="always")
def _vertical_term(X, d, j, ev, kv):
    """Order ``j`` of ``(k a_v/(m_b g)) u_d[0]``: the pendulum's restoring force scales with
    ``g + a_v``."""
    if kv == 0.0:
        return 0.0
    s = ev[0] * X[d, j, 0]
    if j > 0:
        s += ev[1] * X[d, j - 1, 0]
    return kv * s


@njit(cache=True)
def _mat_drive(X, A, bv, ga, ev, kv, n, j, d):
    """Order ``j`` of ``G_d``, the mat's acceleration from everything but friction."""
    N = 2 * n
    s = bv[d, n] * (ga[d, j] if j < 2 else 0.0)
    for q in range(N):
        s += A[d][n, q] * X[d, j, q]
    return s - _vertical_term(X, d, j, ev, kv)


@njit(cache=True)
def _start_coefficients(m, X, A, bv, ga, ev, kv, n, D, c0, c1, y, rho, w, a2, yold):
    """The series of a slip phase from rest, ``V = τ^m y`` (module notes): sweeps of the
    building's recurrences with the mat's velocity given and
    :func:`~floorslide.building._plane_start.start_series` for the mat under ``−G``, until
    the coefficients repeat (order ``k`` is fixed after ``k + 1`` sweeps)."""
    N = 2 * n
    for j in range(D + 1):
        y[j, 0] = 0.0
        y[j, 1] = 0.0
    for sweep in range(D + 3):
        # the building's series with the mat's velocity V_j = y_{j−m}
        for j in range(D):
            inv = 1.0 / (j + 1)
            for d in range(2):
                X[d, j, n] = y[j - m, d] if j >= m else 0.0
                a2[j, d] = -_mat_drive(X, A, bv, ga, ev, kv, n, j, d)
                Ad = A[d]
                aj = ga[d, j] if j < 2 else 0.0
                for i in range(N):
                    if i == n:
                        continue
                    if i == 0:
                        X[d, j + 1, 0] = X[d, j, n] * inv
                        continue
                    s = bv[d, i] * aj
                    for q in range(N):
                        s += Ad[i, q] * X[d, j, q]
                    X[d, j + 1, i] = s * inv
        for d in range(2):
            X[d, D, n] = y[D - m, d]
            a2[D, d] = -_mat_drive(X, A, bv, ga, ev, kv, n, D, d)
        for j in range(D + 1):
            yold[j, 0] = y[j, 0]
            yold[j, 1] = y[j, 1]
        if start_series(a2, D, m, c0, D, y, rho, w, c1) < 0:
            return -1
        same = True
        for j in range(D + 1):
            if y[j, 0] != yold[j, 0] or y[j, 1] != yold[j, 1]:
                same = False
                break
        if same and sweep > 0:
            break
    for d in range(2):
        for j in range(D + 1):
            X[d, j, n] = y[j - m, d] if j >= m else 0.0
    return D


@njit(cache=True)
def _slow_coefficients(X, x0, A, bv, ga, ev, kv, n, D, c0, L, y, yold, rho, sl, a2):
    """The series of a slow mat on its slow manifold — the solution whose direction follows
    the drive's without the fast transient — through a point beside its velocity:
    :func:`~floorslide.numerics.friction_series.slow_series` for the mat under ``−G``, swept
    with the building's recurrences (the mat's velocity given) until both repeat. Returns
    ``(D, φ₀)`` (``φ₀`` the slow point's angle from the mat's velocity), or ``(−1, 0)``."""
    N = 2 * n
    for d in range(2):
        for i in range(N):
            X[d, 0, i] = x0[d, i]
    vx = x0[0, n]
    vy = x0[1, n]
    for j in range(D + 1):
        y[j, 0] = 0.0
        y[j, 1] = 0.0
    y[0, 0] = vx
    y[0, 1] = vy
    phi0 = 0.0
    for sweep in range(D + 6):
        for j in range(D):
            inv = 1.0 / (j + 1)
            for d in range(2):
                X[d, j, n] = y[j, d]
                a2[j, d] = -_mat_drive(X, A, bv, ga, ev, kv, n, j, d)
                Ad = A[d]
                aj = ga[d, j] if j < 2 else 0.0
                for i in range(N):
                    if i == n:
                        continue
                    t = bv[d, i] * aj
                    for q in range(N):
                        t += Ad[i, q] * X[d, j, q]
                    X[d, j + 1, i] = t * inv
        for d in range(2):
            X[d, D, n] = y[D, d]
            a2[D, d] = -_mat_drive(X, A, bv, ga, ev, kv, n, D, d)
        for j in range(D + 1):
            yold[j, 0] = y[j, 0]
            yold[j, 1] = y[j, 1]
        De, phi0 = slow_series(a2[:, 0], a2[:, 1], D, vx, vy, c0, D, L, y, rho, sl)
        if De < 0:
            return -1, 0.0
        change = 0.0
        size = 0.0
        Lj = 1.0
        for j in range(D + 1):
            change += (abs(y[j, 0] - yold[j, 0]) + abs(y[j, 1] - yold[j, 1])) * Lj
            size += (abs(y[j, 0]) + abs(y[j, 1])) * Lj
            Lj *= L
        if sweep > 0 and change <= 2.0**-52 * size:
            for d in range(2):
                for j in range(D + 1):
                    X[d, j, n] = y[j, d]
            return D, phi0
    return -1, 0.0


@njit(cache=True)
def _step(X, D, n, L):
    """Jorba & Zou's step (as :func:`floorslide.contents._plane_kernel._step_size`) on the
    state's series and on its derivative's, at most ``L``."""
    N = 2 * n
    nrm = np.zeros(D + 1)
    for j in range(D + 1):
        s = 0.0
        for d in range(2):
            for i in range(N):
                v = abs(X[d, j, i])
                if v > s:
                    s = v
        nrm[j] = s
    return step_rule(nrm, D, L)


@njit(cache=True)
def step_rule(nrm, D, L):
    """Jorba & Zou's step on series of norms ``nrm[j]``: the last two terms below
    :data:`STEP_TOL` of the first three, for the series and its derivative; at most ``L``."""
    H = L
    for _ in range(3):
        H0 = H
        tol = STEP_TOL * (nrm[0] + H * (nrm[1] + H * nrm[2]))
        tol1 = STEP_TOL * (nrm[1] + H * (2.0 * nrm[2] + H * 3.0 * nrm[3]))
        for k in (D, D - 1):
            nk = nrm[k]
            if nk * H**k > tol > 0.0:
                H = (tol / nk) ** (1.0 / k)
            if k * nk * H ** (k - 1) > tol1 > 0.0:
                H = (tol1 / (k * nk)) ** (1.0 / (k - 1))
        if H == H0:
            break
    return H


@njit(cache=True)
def _state_at(X, D, n, tau, out):
    """The state at ``tau`` from its series."""
    N = 2 * n
    for d in range(2):
        for i in range(N):
            r = X[d, D, i]
            for j in range(D - 1, -1, -1):
                r = r * tau + X[d, j, i]
            out[d, i] = r


@njit(cache=True)
def _drive_coefficients(X, A, bv, ga, ev, kv, n, D, G):
    """``G[d, j]``: the series of the mat's acceleration from everything but friction."""
    for d in range(2):
        for j in range(D + 1):
            G[d, j] = _mat_drive(X, A, bv, ga, ev, kv, n, j, d)


@njit(cache=True)
def _breakaway(G, D, cs0, cs1, lo, H, q, work):
    """First ``τ`` in ``[lo, H]`` where ``|G|²`` rises through ``(cs0 + cs1 τ)²`` — the mat
    breaks away — or −1."""
    reach = 0.0
    for j in range(D, -1, -1):
        reach = reach * H + np.hypot(G[0, j], G[1, j])
    low = min(cs0, cs0 + cs1 * H)
    if reach < low:
        return -1.0
    deg = 2 * D
    for j in range(deg + 1):
        q[j] = 0.0
    for i in range(D + 1):
        for j in range(D + 1):
            q[i + j] += G[0, i] * G[0, j] + G[1, i] * G[1, j]
    q[0] -= cs0 * cs0
    q[1] -= 2.0 * cs0 * cs1
    q[2] -= cs1 * cs1
    return rise_within(q, deg, lo, H, 0.0, work)


@njit(cache=True)
def _stop(rho, De, lo, H, q, work):
    """First root of the speed's series on ``[lo, H]`` — a stop — or −1."""
    reach = 0.0
    for j in range(De, 0, -1):
        reach = (reach + abs(rho[j])) * H
    if reach < rho[0]:
        return -1.0
    for k in range(De + 1):
        q[k] = -rho[k]
    return rise_within(q, De, lo, H, 0.0, work)


@njit(cache=True)
def _record(SEG, COEF, nseg, X, D, n, floors, ga, t0, L, k, ends):
    """Record a segment: its start, length, record step, end flag and the floors' absolute
    accelerations' coefficients ``(j+1) v_{j+1} + a_j``."""
    if nseg >= SEG.shape[0]:
        return
    SEG[nseg, 0] = t0
    SEG[nseg, 1] = L
    SEG[nseg, 2] = k
    SEG[nseg, 3] = 1.0 if ends else 0.0
    for f in range(floors.size):
        i = n + floors[f]
        size = 0.0
        for d in range(2):
            Lj = 1.0
            for j in range(D):
                c = (j + 1) * X[d, j + 1, i]
                if j < 2:
                    c += ga[d, j]
                COEF[nseg, f, d, j] = c
                size += abs(c) * Lj
                Lj *= L
        # terms below rounding on the segment are dropped: where the speed is small, the
        # friction direction's series amplify the rounding of the cross velocity into large
        # high-order coefficients whose contribution on [0, L] is nil, but which would make a
        # consumer's own series (of the floor's derivatives) stiff
        for d in range(2):
            Lj = 1.0
            for j in range(D):
                if abs(COEF[nseg, f, d, j]) * Lj <= DROP_TOL * size:
                    COEF[nseg, f, d, j] = 0.0
                Lj *= L


@njit(cache=True)
def _track_peaks(X, D, n, L, t0, peak, q, work):
    """Raise the peak mat displacement ``|u_b|`` on the step (true peak inside it)."""
    reach = 0.0
    for j in range(D, -1, -1):
        reach = reach * L + np.hypot(X[0, j, 0], X[1, j, 0])
    if reach <= peak[P_DISP]:
        return
    deg = 2 * D
    for j in range(deg + 1):
        q[j] = 0.0
    for i in range(D + 1):
        for j in range(D + 1):
            q[i + j] += X[0, i, 0] * X[0, j, 0] + X[1, i, 0] * X[1, j, 0]
    v, t = max_abs_on(q, deg, L, peak[P_DISP] ** 2, work)
    if v > peak[P_DISP] ** 2:
        peak[P_DISP] = np.sqrt(v)
        peak[P_TIME] = t0 + t
        ux = poly_val(X[0, :, 0], D, t)
        uy = poly_val(X[1, :, 0], D, t)
        peak[P_ANGLE] = np.arctan2(uy, ux)


@njit(cache=True)
def plane_run(A, bv, As, consts, floors, acc1, acc2, accv, has_vert, substeps, h, k0, k1, x,
              carry, XS, MODES, peak, EV, SEG, COEF):  # fmt: skip
    """Integrate the building over record steps ``k0 … k1 − 1`` from state ``x`` (``(2, 2n)``,
    updated), the carried ``carry`` (mode, start order, fresh flag, events, steps; updated).

    ``A[d]``, ``As[d]``: the sliding and stuck systems of direction ``d``, ``bv[d]`` its ground
    column; ``consts = [n, m_b, mu·W, mu_s·W, W, k/(m_b g), W/g]``. ``XS[k]``/``MODES[k]``:
    the state and mode at record sample ``k`` (rows ``k0 + 1 … k1``; row 0 at ``k0 = 0``);
    ``peak`` (:data:`P_DISP` …) raised; events ``EV[i] = (t, kind)`` (as many as fit; ``carry``
    counts them); segments into ``SEG`` (``t0, L, step, ends``) and ``COEF`` (``(nseg, floors,
    2, DEGREE)``) when they have rows. Returns the number of segments (more than ``SEG`` holds:
    run again with room), or ``−1 − row`` when sub-step ``row`` needed more than
    :data:`MAX_STEPS` steps."""
    n = int(consts[0])
    mb = consts[1]
    muW = consts[2]
    musW = consts[3]
    kv = consts[5]
    Wg = consts[6]  # W/g: N = W + (W/g) a_v
    W = consts[4]
    N = 2 * n
    D = DEGREE
    X = np.zeros((2, D + 1, N))
    y = np.zeros((D + 2, 2))
    yold = np.zeros((D + 2, 2))
    rho = np.zeros(D + 2)
    w = np.zeros((D + 2, 2))
    a2 = np.zeros((D + 2, 2))
    sl = np.zeros((5, D + 2))
    G = np.zeros((2, D + 1))
    q = np.zeros(2 * D + 1)
    work = scratch(2 * D + 1)
    ga = np.zeros((2, 2))
    ev = np.zeros(2)
    xn = np.zeros((2, N))
    mode = int(carry[C_MODE])
    start = int(carry[C_START])
    fresh = carry[C_FRESH] != 0.0
    n_ev = int(carry[C_EVENTS])
    nseg = 0
    if k0 == 0:
        for d in range(2):
            for i in range(N):
                XS[0, d, i] = x[d, i]
        MODES[0] = mode
    for k in range(k0, k1):
        s1 = (acc1[k + 1] - acc1[k]) / (substeps * h)
        s2 = (acc2[k + 1] - acc2[k]) / (substeps * h)
        sv = (accv[k + 1] - accv[k]) / (substeps * h) if has_vert else 0.0
        for r in range(substeps):
            row = k * substeps + r
            t_sub = row * h
            s0 = 0.0
            steps = 0
            while s0 < h:
                L = h - s0
                ga[0, 0] = acc1[k] + s1 * (r * h + s0)
                ga[0, 1] = s1
                ga[1, 0] = acc2[k] + s2 * (r * h + s0)
                ga[1, 1] = s2
                if has_vert:
                    ev[0] = accv[k] + sv * (r * h + s0)
                    ev[1] = sv
                nN0 = W + Wg * ev[0]
                nN1 = Wg * ev[1]
                c0 = muW / W * nN0 / mb
                c1 = muW / W * nN1 / mb
                cs0 = musW / W * nN0 / mb
                cs1 = musW / W * nN1 / mb
                lo = EVENT_GAP * h if fresh else 0.0
                fresh = False
                Asys = As if mode == STICK else A
                De = -2
                if mode == SLIP and start == 0 and c0 != 0.0 and c1 == 0.0:
                    r0 = np.hypot(x[0, n], x[1, n])
                    kvs = kv if has_vert else 0.0
                    g0 = np.hypot(_drive_now(x, A, bv, ga, ev, kvs, n, 0),
                                  _drive_now(x, A, bv, ga, ev, kvs, n, 1))  # fmt: skip
                    if g0 * L > STIFF * r0:
                        De, phi0 = _slow_coefficients(X, x, A, bv, ga, ev, kvs, n, D, c0, L, y,
                                                      yold, rho, sl, a2)  # fmt: skip
                        if De < 0 or 2.0 * abs(np.sin(0.5 * phi0)) > SLOW_TOL:
                            De = -2
                if De == -2:
                    De = _series(mode, start, X, x, Asys, bv, ga, ev, kv if has_vert else 0.0, n,
                                 D, c0, c1, y, rho, w, a2, yold)  # fmt: skip
                if mode == SLIP and De < 0:
                    # a degenerate start (the demand fell back inside the circle at once): stick
                    mode = STICK
                    start = 0
                    fresh = True
                    continue
                H = _step(X, D, n, L)
                te = -1.0
                kind = 0
                if not H > 0.0:  # (NaN too) a series that overflowed: the speed is at rounding
                    if not (mode == SLIP and start == 0):
                        return -1 - row
                    H = 0.0
                    te = 0.0
                if mode == STICK:
                    _drive_coefficients(X, A, bv, ga, ev, kv if has_vert else 0.0, n, D, G)
                    te = _breakaway(G, D, cs0 * (1.0 + BREAK_TOL), cs1 * (1.0 + BREAK_TOL), lo,
                                    H, q, work)  # fmt: skip
                    kind = EV_BREAK
                    if te >= 0.0 and _negligible(G, D, H, L, 0.0, c0, c1, x, n, peak):
                        te = -1.0  # a grazing demand: the slip it would make is below rounding
                elif c0 != 0.0 or c1 != 0.0:
                    if start == 0 and te < 0.0:
                        _drive_coefficients(X, A, bv, ga, ev, kv if has_vert else 0.0, n, D, G)
                        top = STOP_SPEED * (np.hypot(G[0, 0], G[1, 0]) + c0) * h
                        if rho[0] <= max(top, SPEED_TOL * peak[P_SPEED]) or _negligible(
                            G, D, H, L, rho[0], c0, c1, x, n, peak
                        ):
                            te = 0.0
                    if te < 0.0:
                        te = _stop(rho, De, lo, H, q, work)
                    kind = EV_STICK
                tau = H if te < 0.0 else te
                if tau > 0.0:
                    ends = tau >= L and r == substeps - 1
                    _record(SEG, COEF, nseg, X, D, n, floors, ga, t_sub + s0, tau, k, ends)
                    nseg += 1
                    _track_peaks(X, D, n, tau, t_sub + s0, peak, q, work)
                    if mode == SLIP:
                        peak[P_SLIDE_TIME] += tau
                        if De > 0:
                            peak[P_WORK] += mb * _path_work(rho, De, start, c0, c1, tau)
                    if te < 0.0 and tau >= L:
                        _state_at(X, D, n, L, xn)
                    else:
                        _state_at(X, D, n, tau, xn)
                    for d in range(2):
                        for i in range(N):
                            x[d, i] = xn[d, i]
                    if mode == SLIP:
                        start = 0
                        speed = np.hypot(x[0, n], x[1, n])
                        if speed > peak[P_SPEED]:
                            peak[P_SPEED] = speed
                steps += 1
                if steps > MAX_STEPS:
                    return -1 - row
                if te < 0.0:
                    s0 = h if tau >= L else s0 + tau
                    continue
                # an event at s0 + te
                s0 = s0 + te
                fresh = True
                if mode == SLIP:
                    # a stop: stick if the demand is inside the circle, else slide on
                    for d in range(2):
                        x[d, n] = 0.0
                    ga[0, 0] = acc1[k] + s1 * (r * h + s0)
                    ga[1, 0] = acc2[k] + s2 * (r * h + s0)
                    if has_vert:
                        ev[0] = accv[k] + sv * (r * h + s0)
                    gx = _drive_now(x, A, bv, ga, ev, kv if has_vert else 0.0, n, 0)
                    gy = _drive_now(x, A, bv, ga, ev, kv if has_vert else 0.0, n, 1)
                    lim = musW / W * (W + Wg * ev[0]) / mb
                    gn = np.hypot(gx, gy)
                    L = h - s0
                    U = max(peak[P_DISP], np.hypot(x[0, 0], x[1, 0]))
                    c0 = muW / W * (W + Wg * ev[0]) / mb
                    if gn <= lim * (1.0 + BREAK_TOL) or 0.5 * (gn - c0) * L * L <= CREEP_TOL * U:
                        mode = STICK
                        start = 0
                        kind = EV_STICK
                    else:
                        start = 1
                        kind = EV_ON
                else:
                    mode = SLIP
                    start = 2 if musW == muW else 1
                if n_ev < EV.shape[0]:
                    EV[n_ev, 0] = t_sub + s0
                    EV[n_ev, 1] = kind
                n_ev += 1
        for d in range(2):
            for i in range(N):
                XS[k + 1, d, i] = x[d, i]
        MODES[k + 1] = mode
    carry[C_MODE] = mode
    carry[C_START] = start
    carry[C_FRESH] = 1.0 if fresh else 0.0
    carry[C_EVENTS] = n_ev
    return nseg


@njit(cache=True)
def _negligible(G, D, H, L, r0, c0, c1, x, n, peak):
    """Whether a mat at speed ``r0`` (0: stuck) under the drive ``G`` (series on ``[0, H]``)
    certainly slips by at most :data:`CREEP_TOL` of its displacement over the rest ``L`` of the
    sub-step: its speed grows at most at ``(|G| − c)⁺``, so it moves at most
    ``r0·L + ½ (max|G| − c)⁺ L²``, ``max|G|`` bounded by ``Σ_j |G_j| H^j`` (the drive of the
    held mat changes on the building's time scale, which ``H`` resolves; a creeping mat's
    steps are far shorter than the sub-step, where the bound is taken to hold)."""
    U = max(peak[P_DISP], np.hypot(x[0, 0], x[1, 0]))
    if not U > 0.0:
        return False
    A = 0.0
    for j in range(D, -1, -1):
        A = A * H + np.hypot(G[0, j], G[1, j])
    ex = A - min(c0, c0 + c1 * H)
    if ex < 0.0:
        ex = 0.0
    return r0 * L + 0.5 * ex * L * L <= CREEP_TOL * U


@njit(cache=True)
def _path_work(rho, De, m, c0, c1, tau):
    """``∫₀^τ (c0 + c1 s)·|V(s)| ds`` with ``|V| = s^m Σ_j ρ_j s^j``: the friction work per unit
    mat mass on a slip step."""
    s = 0.0
    for j in range(De, -1, -1):
        p = j + m + 1
        s = s * tau + rho[j] * (c0 / p + c1 * tau / (p + 1))
    return s * tau ** (m + 1)


@njit(cache=True)
def _drive_now(x, A, bv, ga, ev, kv, n, d):
    """``G_d`` at a state ``x`` (the ground ``ga[d, 0]``, vertical ``ev[0]``)."""
    N = 2 * n
    s = bv[d, n] * ga[d, 0]
    for q in range(N):
        s += A[d][n, q] * x[d, q]
    return s - kv * ev[0] * x[d, 0]
