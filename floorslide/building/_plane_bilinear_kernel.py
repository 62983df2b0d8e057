"""Compiled kernel of a shear building on lead-rubber (bilinear) bearings under two horizontal
components: an elastic–perfectly-plastic element with a circular yield surface, in parallel
with a linear spring and damper, coupled with the superstructure in both directions, exact to
rounding for the piecewise-linear records.

Each direction ``d`` has its own linear superstructure on the shared mat; the bearing's force on
the mat is ``f = k_2 u_b + c u_b' + Q z`` (``u_b = (u_x[0], u_y[0])``, ``Q`` the characteristic
strength, ``z = q/Q`` the plastic element's force over its strength, ``|z| ≤ 1``). With the
state ``x_d = [u_d; u_d'; z_d]`` (``2n + 1`` entries, ``u_d[0]`` the mat relative to the
ground)::

    x_d' = A_d x_d + b_d a_d(t)                 (rows of u and u', A_d with k_2 and −Q/m_b)
    z'   = u_b'/D_y                             elastic: |z| < 1, or |z| = 1 and z·u_b' ≤ 0
    z'   = (u_b' − (z·u_b') z)/D_y              plastic: |z| = 1 and z·u_b' > 0

(``D_y = Q/(k_1 − k_2)``): Park, Wen & Ang's (1986) biaxial model in its limit of a sharp
yield surface, the associated flow rule of rate-independent plasticity with a circular yield
surface ``|q| = Q`` and no hardening of the element (Simo & Hughes 1998, §2.3, eqs. 2.3.1–2.3.6
in the plane; the linear spring ``k_2`` in parallel gives the bilinear loop). On the elastic
branch the whole building is linear (``z`` one more state); on the plastic branch ``z`` turns
with the mat's velocity and the system is quadratic in the state.

Both branches are integrated by their Taylor series (automatic differentiation, Jorba & Zou
2005), as the friction pendulum's slip (:mod:`floorslide.building._plane_isolation_kernel`):
order by order from ``(j+1) x_{j+1} = A x_j + b a_j`` and, plastic,
``(j+1) D_y z_{j+1} = v_j − Σ_i s_i z_{j−i}`` with ``s = z·v`` (``s_j = Σ_i z_i·v_{j−i}``, the
Cauchy products of the two series; ``v`` the mat's velocity). The degree is :data:`DEGREE`, the
step the largest on which the last two terms are below :data:`STEP_TOL` of the first three,
separately for the building's states (and their derivative, which carries the floors'
accelerations) and for ``z``, whose scale (1) is not the displacements'.

Events are located rigorously (:func:`floorslide.numerics.polynomial.rise_within`) on the series:
*yield* (elastic → plastic) where ``|z|² − 1`` first rises through 0; *unloading* (plastic →
elastic) where ``s = z·v`` first falls through 0. On the plastic branch ``|z| = 1`` is an
invariant of the flow (``d|z|²/dt = 2 s (1 − |z|²)/D_y``); its series keep it to rounding, and
``z`` is set back to unit length (``z/|z|``) at the end of every plastic step and at every
yield, so the rounding never accumulates. Every step is a *segment* of the building's exact
motion, recorded with the Taylor coefficients of the floors' absolute accelerations on it
(:func:`floorslide.building._plane_isolation_kernel._record`), as the pendulum's.

References
----------
Park, Y. J., Wen, Y. K., Ang, A. H.-S. (1986). Random vibration of hysteretic systems under
bi-directional ground motions. *Earthq. Eng. Struct. Dyn.* 14(4), 543–557.
Simo, J. C., Hughes, T. J. R. (1998). *Computational Inelasticity*, Springer, §2.3.
Jorba, À., Zou, M. (2005). A software package for the numerical integration of ODEs by means of
high-order Taylor methods. *Experimental Mathematics* 14(1), 99–117.
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.building._plane_isolation_kernel import (
    DEGREE,
    EVENT_GAP,
    P_FORCE,
    P_FTIME,
    P_SLIDE_TIME,
    P_WORK,
    _record,
    _track_peaks,
    step_rule,
)
from floorslide.numerics.polynomial import max_abs_on, rise_within, scratch

MAX_STEPS = 200_000
"""Most series steps in one sub-step."""
ELASTIC, PLASTIC = 0, 1
# columns of the carried state (see bilinear_run)
C_MODE, C_FRESH, C_EVENTS = range(3)
NCARRY = 3
# event kinds
EV_YIELD, EV_UNLOAD = 1, 2


@njit(cache=True)
def _series(plastic, X, x0, A, bv, ga, n, D, dy, s):
    """Taylor coefficients ``X[d, j, :]`` (``j ≤ D``) of the state ``[u; u'; z]`` about the
    current point ``x0`` (module notes); on the plastic branch ``s[j]`` (``j ≤ D``) those of
    ``s = z·v``. ``ga[d] = (a, slope)``: the ground about the point."""
    iz = 2 * n
    N1 = iz + 1
    rdy = 1.0 / dy
    for d in range(2):
        for i in range(N1):
            X[d, 0, i] = x0[d, i]
    for j in range(D):
        inv = 1.0 / (j + 1)
        if plastic:
            t = 0.0
            for i in range(j + 1):
                t += X[0, i, iz] * X[0, j - i, n] + X[1, i, iz] * X[1, j - i, n]
            s[j] = t
        for d in range(2):
            Ad = A[d]
            aj = ga[d, j] if j < 2 else 0.0
            for i in range(n):
                X[d, j + 1, i] = X[d, j, n + i] * inv
            for i in range(n, iz):
                t = bv[d, i] * aj
                for q in range(N1):
                    t += Ad[i, q] * X[d, j, q]
                X[d, j + 1, i] = t * inv
            t = X[d, j, n]
            if plastic:
                for i in range(j + 1):
                    t -= s[i] * X[d, j - i, iz]
            X[d, j + 1, iz] = t * inv * rdy
    if plastic:
        t = 0.0
        for i in range(D + 1):
            t += X[0, i, iz] * X[0, D - i, n] + X[1, i, iz] * X[1, D - i, n]
        s[D] = t


@njit(cache=True)
def _step(X, D, n, L, nrm, nz):
    """The step on the building's states (with their derivative) and, apart, on ``z``."""
    iz = 2 * n
    for j in range(D + 1):
        a = 0.0
        b = 0.0
        for d in range(2):
            for i in range(iz):
                v = abs(X[d, j, i])
                if v > a:
                    a = v
            v = abs(X[d, j, iz])
            if v > b:
                b = v
        nrm[j] = a
        nz[j] = b
    return min(step_rule(nrm, D, L), step_rule(nz, D, L))


@njit(cache=True)
def _state_at(X, D, N1, tau, out):
    """The state at ``tau`` from its series."""
    for d in range(2):
        for i in range(N1):
            r = X[d, D, i]
            for j in range(D - 1, -1, -1):
                r = r * tau + X[d, j, i]
            out[d, i] = r


@njit(cache=True)
def _yield_time(X, D, n, lo, H, q, work):
    """First ``τ`` in ``[lo, H]`` where ``|z|²`` rises through 1 — the bearing yields — or −1
    (skipped when ``Σ_j |z_j| H^j < 1`` bounds ``|z|`` below 1 on the step)."""
    iz = 2 * n
    reach = 0.0
    for j in range(D, -1, -1):
        reach = reach * H + np.hypot(X[0, j, iz], X[1, j, iz])
    if reach < 1.0:
        return -1.0
    deg = 2 * D
    for j in range(deg + 1):
        q[j] = 0.0
    for i in range(D + 1):
        for j in range(D + 1):
            q[i + j] += X[0, i, iz] * X[0, j, iz] + X[1, i, iz] * X[1, j, iz]
    q[0] -= 1.0
    return rise_within(q, deg, lo, H, 0.0, work)


@njit(cache=True)
def _unload_time(s, D, lo, H, q, work):
    """First ``τ`` in ``[lo, H]`` where ``s = z·v`` falls through 0 — the bearing unloads — or
    −1."""
    for j in range(D + 1):
        q[j] = -s[j]
    return rise_within(q, D, lo, H, 0.0, work)


@njit(cache=True)
def _integral(s, D, tau):
    """``∫₀^τ Σ_j s_j t^j dt``."""
    r = 0.0
    for j in range(D, -1, -1):
        r = r * tau + s[j] / (j + 1)
    return r * tau


@njit(cache=True)
def _track_force(X, D, n, L, t0, k2, c, Q, peak, f, q, work):
    """Raise the peak bearing force ``|k_2 u_b + c u_b' + Q z|`` on the step (true peak inside
    it, as :func:`floorslide.building._plane_isolation_kernel._track_peaks` the displacement's;
    ``f`` scratch ``(2, D + 1)``)."""
    iz = 2 * n
    reach = 0.0
    for j in range(D, -1, -1):
        for d in range(2):
            f[d, j] = k2 * X[d, j, 0] + c * X[d, j, n] + Q * X[d, j, iz]
        reach = reach * L + np.hypot(f[0, j], f[1, j])
    if reach <= peak[P_FORCE]:
        return
    deg = 2 * D
    for j in range(deg + 1):
        q[j] = 0.0
    for i in range(D + 1):
        for j in range(D + 1):
            q[i + j] += f[0, i] * f[0, j] + f[1, i] * f[1, j]
    v, t = max_abs_on(q, deg, L, peak[P_FORCE] ** 2, work)
    if v > peak[P_FORCE] ** 2:
        peak[P_FORCE] = np.sqrt(v)
        peak[P_FTIME] = t0 + t


@njit(cache=True)
def _unit(x, iz):
    """``z ← z/|z|`` (the plastic branch's invariant ``|z| = 1``, restored to rounding)."""
    r = np.hypot(x[0, iz], x[1, iz])
    if r > 0.0:
        x[0, iz] /= r
        x[1, iz] /= r


@njit(cache=True)
def bilinear_run(A, bv, consts, floors, acc1, acc2, substeps, h, k0, k1, x, carry, XS, MODES,
                 peak, EV, SEG, COEF):  # fmt: skip
    """Integrate the building over record steps ``k0 … k1 − 1`` from state ``x`` (``(2, 2n+1)``:
    ``[u; u'; z]`` per direction, updated) and ``carry`` (mode, fresh flag, events; updated).

    ``A[d]``, ``bv[d]``: direction ``d``'s system (``k_2`` on the mat, ``−Q/m_b`` on ``z``) and
    ground column; ``consts = [n, D_y, Q, k_2, c]``. ``XS[k]``/``MODES[k]``: the state and
    branch at record sample ``k`` (rows ``k0 + 1 … k1``; row 0 at ``k0 = 0``); ``peak`` (the
    pendulum kernel's columns: ``P_DISP``, ``P_TIME``, ``P_ANGLE``; ``P_FORCE``, ``P_FTIME``
    the peak force ``|f|`` inside steps and its time; ``P_WORK`` the plastic work
    ``Q ∫ z·v dt``, ``P_SLIDE_TIME`` the time yielding) raised; events ``EV[i] = (t, kind)``
    (as many as fit; ``carry`` counts them); segments into ``SEG`` (``t0, L, step, ends``) and
    ``COEF`` (``(nseg, floors, 2, DEGREE)``) when they have rows. Returns the number of
    segments (more than ``SEG`` holds: run again with room), or ``−1 − row`` when sub-step
    ``row`` needed more than :data:`MAX_STEPS` steps (or its series overflowed)."""
    n = int(consts[0])
    dy = consts[1]
    Q = consts[2]
    k2 = consts[3]
    cv = consts[4]
    iz = 2 * n
    N1 = iz + 1
    D = DEGREE
    X = np.zeros((2, D + 1, N1))
    s = np.zeros(D + 1)
    nrm = np.zeros(D + 1)
    nz = np.zeros(D + 1)
    q = np.zeros(2 * D + 1)
    f = np.zeros((2, D + 1))
    work = scratch(2 * D + 1)
    ga = np.zeros((2, 2))
    xn = np.zeros((2, N1))
    mode = int(carry[C_MODE])
    fresh = carry[C_FRESH] != 0.0
    n_ev = int(carry[C_EVENTS])
    nseg = 0
    if k0 == 0:
        for d in range(2):
            for i in range(N1):
                XS[0, d, i] = x[d, i]
        MODES[0] = mode
    for k in range(k0, k1):
        s1 = (acc1[k + 1] - acc1[k]) / (substeps * h)
        s2 = (acc2[k + 1] - acc2[k]) / (substeps * h)
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
                lo = EVENT_GAP * h if fresh else 0.0
                fresh = False
                plastic = mode == PLASTIC
                _series(plastic, X, x, A, bv, ga, n, D, dy, s)
                H = _step(X, D, n, L, nrm, nz)
                if not H > 0.0:  # (NaN too) a series that overflowed
                    return -1 - row
                if plastic:
                    te = _unload_time(s, D, lo, H, q, work)
                    kind = EV_UNLOAD
                else:
                    te = _yield_time(X, D, n, lo, H, q, work)
                    kind = EV_YIELD
                tau = H if te < 0.0 else te
                if tau > 0.0:
                    ends = tau >= L and r == substeps - 1
                    _record(SEG, COEF, nseg, X, D, n, floors, ga, t_sub + s0, tau, k, ends)
                    nseg += 1
                    _track_peaks(X, D, n, tau, t_sub + s0, peak, q, work)
                    _track_force(X, D, n, tau, t_sub + s0, k2, cv, Q, peak, f, q, work)
                    if plastic:
                        peak[P_SLIDE_TIME] += tau
                        peak[P_WORK] += Q * _integral(s, D, tau)
                    _state_at(X, D, N1, L if te < 0.0 and tau >= L else tau, xn)
                    for d in range(2):
                        for i in range(N1):
                            x[d, i] = xn[d, i]
                    if plastic:
                        _unit(x, iz)
                steps += 1
                if steps > MAX_STEPS:
                    return -1 - row
                if te < 0.0:
                    s0 = h if tau >= L else s0 + tau
                    continue
                # an event at s0 + te
                s0 = s0 + te
                fresh = True
                _unit(x, iz)
                mode = ELASTIC if plastic else PLASTIC
                if n_ev < EV.shape[0]:
                    EV[n_ev, 0] = t_sub + s0
                    EV[n_ev, 1] = kind
                n_ev += 1
        for d in range(2):
            for i in range(N1):
                XS[k + 1, d, i] = x[d, i]
        MODES[k + 1] = mode
    carry[C_MODE] = mode
    carry[C_FRESH] = 1.0 if fresh else 0.0
    carry[C_EVENTS] = n_ev
    return nseg
