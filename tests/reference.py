"""Independent high-accuracy references for the exact solvers.

They share no code with floorslide's exact methods: SciPy's DOP853 integrates each step of the
piecewise-linear record separately (the forcing is smooth inside a step, so the 8th-order
method reaches rounding level), restarting at every sample.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar


def linear_response(A, b, acc, dt, rtol=1e-13, atol=1e-16, dense=False):
    """States of ``x' = A x + b a(t)`` at the samples, ``a`` piecewise linear, step by step.

    With ``dense=True`` also returns the per-step dense-output callables.
    """
    A = np.asarray(A, dtype=float)
    b = np.asarray(b, dtype=float).ravel()
    n = A.shape[0]
    X = np.zeros((acc.size, n))
    x = np.zeros(n)
    sols = []
    for k in range(acc.size - 1):
        a0 = acc[k]
        s = (acc[k + 1] - a0) / dt

        def f(t, y, a0=a0, s=s):
            return A @ y + b * (a0 + s * t)

        sol = solve_ivp(f, (0.0, dt), x, method="DOP853", rtol=rtol, atol=atol, dense_output=dense)
        x = sol.y[:, -1]
        X[k + 1] = x
        if dense:
            sols.append(sol.sol)
    return (X, sols) if dense else X


def sliding_oscillator(acc, dt, mu, f, xi, r, g=9.80665, rtol=1e-12, max_step=None, system=None):
    """2-DOF sliding oscillator by DOP853 with event location, step by step: on the ground, or
    on a floor whose absolute acceleration is ``a_f = ca·x + da·a(t)`` with ``x' = A x + b a(t)``
    (``system = (A, b, ca, da)``, integrated together with the oscillator on the augmented
    state ``[x, u, v, z, zd]``).

    Returns (peak |u|, residual u, peak |z|). Oscillator state [u, v, z, zd] per unit top mass.
    """
    if system is None:
        A, b, ca, da = np.zeros((0, 0)), np.zeros(0), np.zeros(0), 1.0
    else:
        A, b, ca, da = system
        A = np.asarray(A, dtype=float)
        b, ca = np.asarray(b, dtype=float).ravel(), np.asarray(ca, dtype=float).ravel()
    n = A.shape[0]
    U, V, Z, ZD = n, n + 1, n + 2, n + 3
    w = 2 * np.pi * f
    c2, w2 = 2 * xi * w, w * w
    fb = mu * (1 + r) * g
    y = np.zeros(n + 4)
    mode = 0
    peak_u = peak_z = 0.0
    max_step = max_step or dt / 16
    for k in range(acc.size - 1):
        a0, s = acc[k], (acc[k + 1] - acc[k]) / dt

        def floor(tt, yy, a0=a0, s=s):
            return ca @ yy[:n] + da * (a0 + s * tt)

        t = 0.0
        for _ in range(1000):
            if mode == 0:
                # the floor already beyond the friction limit when sticking begins (a record
                # that starts mid-motion): the base breaks away at once
                F0 = r * floor(t, y) - c2 * y[ZD] - w2 * y[Z]
                if F0 > fb or F0 < -fb:
                    mode = -1 if F0 > fb else 1
                    continue

                def rhs(tt, yy, a0=a0, s=s, floor=floor):
                    out = np.zeros(n + 4)
                    out[:n] = A @ yy[:n] + b * (a0 + s * tt)
                    out[Z] = yy[ZD]
                    out[ZD] = -floor(tt, yy) - c2 * yy[ZD] - w2 * yy[Z]
                    return out

                def up(tt, yy, floor=floor):
                    return r * floor(tt, yy) - c2 * yy[ZD] - w2 * yy[Z] - fb

                def lo(tt, yy, floor=floor):
                    return -(r * floor(tt, yy) - c2 * yy[ZD] - w2 * yy[Z]) - fb

                up.terminal = lo.terminal = True
                up.direction = lo.direction = 1.0
                events = [up, lo]
            else:
                sg = float(mode)

                def rhs(tt, yy, a0=a0, s=s, sg=sg, floor=floor):
                    q = c2 * yy[ZD] + w2 * yy[Z]
                    out = np.zeros(n + 4)
                    out[:n] = A @ yy[:n] + b * (a0 + s * tt)
                    out[U] = yy[V]
                    out[V] = -floor(tt, yy) + q / r - sg * mu * g * (1 + r) / r
                    out[Z] = yy[ZD]
                    out[ZD] = -q * (1 + 1 / r) + sg * mu * g * (1 + r) / r
                    return out

                def stop(tt, yy, sg=sg):
                    return sg * yy[V] + 1e-13

                stop.terminal = True
                stop.direction = -1.0
                events = [stop]
            sol = solve_ivp(
                rhs,
                (t, dt),
                y,
                method="DOP853",
                rtol=rtol,
                atol=1e-15,
                events=events,
                max_step=max_step,
                dense_output=True,
            )
            ts = np.linspace(t, sol.t[-1], 33)
            dense = sol.sol(ts)
            peak_u = max(peak_u, np.abs(dense[U]).max())
            i = int(np.argmax(np.abs(dense[Z])))
            lo_, hi_ = ts[max(i - 1, 0)], ts[min(i + 1, ts.size - 1)]
            if hi_ > lo_:  # refine the in-segment extremum of |z| on the dense output
                best = minimize_scalar(
                    lambda tt, sol=sol: -abs(sol.sol(tt)[Z]),
                    bounds=(lo_, hi_),
                    method="bounded",
                    options={"xatol": 1e-14},
                )
                peak_z = max(peak_z, -best.fun)
            peak_z = max(peak_z, np.abs(dense[Z]).max())
            y = sol.y[:, -1].copy()
            t = sol.t[-1]
            if sol.status != 1:
                break
            y[V] = 0.0
            if mode == 0:  # breakaway: which limit was crossed
                mode = -1 if sol.t_events[0].size else 1
            else:  # stop: stick, or reverse if friction cannot hold the base
                F = r * floor(t, y) - c2 * y[ZD] - w2 * y[Z]
                mode = -1 if F > fb else (1 if F < -fb else 0)
            if t >= dt * (1 - 1e-13):
                break
    return peak_u, y[U], peak_z


def linear_peaks(A, b, C, acc, dt, rtol=1e-13, candidates=4):
    """True peaks max_t |C x(t)| of ``x' = A x + b a(t)`` (a piecewise linear) by DOP853 step by
    step with dense output: 17 points per step locate candidate steps, a bounded scalar
    minimisation refines the extremum inside the best `candidates` steps of each output."""
    A = np.asarray(A, dtype=float)
    b = np.asarray(b, dtype=float).ravel()
    C = np.atleast_2d(C)
    n = A.shape[0]
    x = np.zeros(n)
    best = [[] for _ in range(C.shape[0])]
    taus = np.linspace(0.0, dt, 17)
    for k in range(acc.size - 1):
        a0 = acc[k]
        s = (acc[k + 1] - a0) / dt

        def f(t, y, a0=a0, s=s):
            return A @ y + b * (a0 + s * t)

        sol = solve_ivp(f, (0.0, dt), x, method="DOP853", rtol=rtol, atol=1e-16, dense_output=True)
        Y = C @ sol.sol(taus)
        for i in range(C.shape[0]):
            best[i].append((np.abs(Y[i]).max(), k, sol.sol))
            if len(best[i]) > 4 * candidates:
                best[i] = sorted(best[i], key=lambda e: -e[0])[:candidates]
        x = sol.y[:, -1]
    peaks = np.zeros(C.shape[0])
    for i in range(C.shape[0]):
        for val, _, dense in sorted(best[i], key=lambda e: -e[0])[:candidates]:
            peaks[i] = max(peaks[i], val)
            grid = np.abs(C[i] @ dense(taus))
            j = int(np.argmax(grid))
            lo, hi = taus[max(j - 1, 0)], taus[min(j + 1, taus.size - 1)]
            res = minimize_scalar(
                lambda t, dense=dense, i=i: -abs(C[i] @ dense(t)),
                bounds=(lo, hi),
                method="bounded",
                options={"xatol": 1e-15},
            )
            peaks[i] = max(peaks[i], -res.fun)
    return peaks


def _smallest_root(a2, a1, a0, lo, hi):
    """Smallest root of ``a2 σ² + a1 σ + a0`` in ``(lo, hi]`` (stable quadratic formula), or
    None."""
    roots = []
    if a2 == 0.0:
        if a1 != 0.0:
            roots = [-a0 / a1]
    else:
        disc = a1 * a1 - 4.0 * a2 * a0
        if disc >= 0.0:
            sq = np.sqrt(disc)
            q = -0.5 * (a1 + (sq if a1 >= 0.0 else -sq))
            roots = [q / a2] + ([a0 / q] if q != 0.0 else [])
    inside = [r for r in roots if lo < r <= hi]
    return min(inside) if inside else None


def rigid_block_ground(acc, dt, mu_k, mu_s=None, g=9.80665):
    """Rigid block with Coulomb friction on a piecewise-linear ground motion, in closed form.

    Written apart from floorslide's kernels (no polynomial root finder, no shared convention
    code): inside a step the ground acceleration is ``a1 + s·σ``, the breakaway instant solves a
    linear equation, the stop instant a quadratic, and a block whose ground is already beyond
    ``mu_s·g`` when a stick phase begins (a record that starts mid-motion) breaks away at once.
    Returns ``(peak |u|, u at the end)``.
    """
    mu_s = mu_k if mu_s is None else mu_s
    fb = max(mu_s, mu_k) * g
    fk = mu_k * g
    mode, v, u, peak = 0, 0.0, 0.0, 0.0
    for k in range(acc.size - 1):
        a0 = float(acc[k])
        s = (float(acc[k + 1]) - a0) / dt
        tau = 0.0
        for _ in range(100):
            if tau >= dt:
                break
            a_now = a0 + s * tau
            if mode == 0:
                if a_now > fb:
                    mode = -1
                    continue
                if a_now < -fb:
                    mode = 1
                    continue
                # first instant |a| passes fb on the way out
                t_ev = dt
                new = 0
                if s > 0.0:
                    t_up = (fb - a0) / s
                    if tau <= t_up < dt:
                        t_ev, new = t_up, -1
                elif s < 0.0:
                    t_lo = (-fb - a0) / s
                    if tau <= t_lo < dt:
                        t_ev, new = t_lo, 1
                tau = t_ev
                mode = new
                continue
            # slip with sign mode: v(σ) = v - (a_now + sg fk) σ - s σ²/2
            sg = float(mode)
            c1 = a_now + sg * fk
            if v == 0.0 and sg * c1 > 0.0:
                c1 = 0.0  # a slip from rest at its breakaway instant: rounding must not stop it
            span = dt - tau
            sig = _smallest_root(-0.5 * s, -c1, v, 0.0, span)
            end = span if sig is None else sig
            u = u + v * end - c1 * end * end / 2.0 - s * end**3 / 6.0
            peak = max(peak, abs(u))
            if sig is None:
                v = v - c1 * span - s * span * span / 2.0
                tau = dt
                continue
            tau = tau + sig
            v = 0.0
            a_now = a0 + s * tau
            if a_now > fb:
                mode = -1
            elif a_now < -fb:
                mode = 1
            else:
                mode = 0
    return peak, u


def rigid_block_on_system(A, b, ca, da, acc, dt, mu_k, mu_s=None, g=9.80665, rtol=1e-12):
    """Rigid block with Coulomb friction on a floor whose absolute acceleration is
    ``a_f = ca·x + da·a(t)`` with ``x' = A x + b a(t)`` (a building, a(t) piecewise linear), by
    DOP853 on the augmented state ``[x, u, v]`` with event location, restarted at every sample
    and every event (``max_step = dt/64`` so that brief excursions are seen).

    Written apart from floorslide's kernels; a stick phase that begins with the floor already
    beyond the friction limit breaks away at once. Returns ``(peak |u|, u at the end)``; within
    a slip phase ``u`` is monotone, so its peaks are at phase ends.
    """
    A = np.asarray(A, dtype=float)
    b = np.asarray(b, dtype=float).ravel()
    ca = np.asarray(ca, dtype=float).ravel()
    n = A.shape[0]
    mu_s = mu_k if mu_s is None else mu_s
    fb = max(mu_s, mu_k) * g
    fk = mu_k * g
    y = np.zeros(n + 2)
    mode, peak = 0, 0.0
    for k in range(acc.size - 1):
        a0 = float(acc[k])
        s = (float(acc[k + 1]) - a0) / dt
        t = 0.0
        for _ in range(1000):
            af = ca @ y[:n] + da * (a0 + s * t)
            if mode == 0 and abs(af) > fb:
                mode = -1 if af > 0 else 1
                continue
            sg = float(mode)

            def rhs(tt, yy, a0=a0, s=s, sg=sg):
                ag = a0 + s * tt
                out = np.empty(n + 2)
                out[:n] = A @ yy[:n] + b * ag
                out[n] = yy[n + 1]
                out[n + 1] = 0.0 if sg == 0.0 else -(ca @ yy[:n] + da * ag) - sg * fk
                return out

            if mode == 0:

                def up(tt, yy, a0=a0, s=s):
                    return ca @ yy[:n] + da * (a0 + s * tt) - fb

                def lo(tt, yy, a0=a0, s=s):
                    return -(ca @ yy[:n] + da * (a0 + s * tt)) - fb

                up.terminal = lo.terminal = True
                up.direction = lo.direction = 1.0
                events = [up, lo]
            else:

                def stop(tt, yy, sg=sg):
                    return sg * yy[n + 1]

                stop.terminal = True
                stop.direction = -1.0
                events = [stop]
            sol = solve_ivp(
                rhs,
                (t, dt),
                y,
                method="DOP853",
                rtol=rtol,
                atol=1e-15,
                events=events,
                max_step=dt / 64,
            )
            y = sol.y[:, -1].copy()
            t = sol.t[-1]
            peak = max(peak, abs(y[n]))
            if sol.status != 1:
                break
            if mode == 0:
                mode = -1 if sol.t_events[0].size else 1
            else:
                y[n + 1] = 0.0
                af = ca @ y[:n] + da * (a0 + s * t)
                mode = -1 if af > fb else (1 if af < -fb else 0)
            if t >= dt * (1 - 1e-13):
                break
    return peak, y[n]


def rigid_block_vertical(acc, vert, dt, mu, g=9.80665, rtol=1e-12):
    """Rigid block on the ground with vertical shaking: friction ``mu·N``, ``N = g + a_v(t)``;
    no friction while ``N ≤ 0`` (lift-off). DOP853 with event location on ``[u, v]``, restarted
    at every sample and event; the peak of ``|u|`` is searched on the dense output of every
    segment (in flight the velocity can reverse, so ``u`` has interior extrema).
    Returns ``(peak |u|, u at the end)``. Written apart from floorslide's kernels."""
    y = np.zeros(2)
    mode = 0  # 0 stick, ±1 slip, 2 flight
    peak = 0.0
    for k in range(acc.size - 1):
        a0, s = float(acc[k]), (float(acc[k + 1]) - float(acc[k])) / dt
        n0, sn = g + float(vert[k]), (float(vert[k + 1]) - float(vert[k])) / dt
        t = 0.0
        for _ in range(1000):
            N = n0 + sn * t
            af = a0 + s * t
            flying = N < -1e-12 * g or (abs(N) <= 1e-12 * g and sn < 0.0)
            if flying:
                mode = 2
            elif mode == 2:  # landing
                mode = 0 if y[1] == 0.0 else (1 if y[1] > 0 else -1)
            if mode == 0 and abs(af) > mu * N:
                mode = -1 if af > 0 else 1
            sg = float(mode)

            def rhs(tt, yy, sg=sg, a0=a0, s=s, n0=n0, sn=sn):
                if sg == 0.0:
                    return [0.0, 0.0]
                if sg == 2.0:
                    return [yy[1], -(a0 + s * tt)]
                return [yy[1], -(a0 + s * tt) - sg * mu * max(n0 + sn * tt, 0.0)]

            # the contact force changes sign where N = n0 + sn·t = 0 (N is linear in a step)
            t_end = dt
            if sn != 0.0 and t * (1 + 1e-12) < -n0 / sn < dt:
                t_end = -n0 / sn
            events = []
            if mode == 0:

                def up(tt, yy, a0=a0, s=s, n0=n0, sn=sn):
                    return (a0 + s * tt) - mu * (n0 + sn * tt)

                def lo(tt, yy, a0=a0, s=s, n0=n0, sn=sn):
                    return -(a0 + s * tt) - mu * (n0 + sn * tt)

                up.terminal = lo.terminal = True
                up.direction = lo.direction = 1.0
                events += [up, lo]
            elif mode in (1, -1):

                def stop(tt, yy, sg=sg):
                    return sg * yy[1]

                stop.terminal = True
                stop.direction = -1.0
                events.append(stop)
            sol = solve_ivp(
                rhs,
                (t, t_end),
                y,
                method="DOP853",
                rtol=rtol,
                atol=1e-15,
                events=events or None,
                max_step=dt / 64,
                dense_output=True,
            )
            ts = np.linspace(t, sol.t[-1], 65)
            u = sol.sol(ts)[0]
            i = int(np.argmax(np.abs(u)))
            peak = max(peak, abs(u[i]))
            if 0 < i < ts.size - 1:
                best = minimize_scalar(
                    lambda tt, sol=sol: -abs(sol.sol(tt)[0]),
                    bounds=(ts[i - 1], ts[i + 1]),
                    method="bounded",
                    options={"xatol": 1e-14},
                )
                peak = max(peak, -best.fun)
            y = sol.y[:, -1].copy()
            t_new = sol.t[-1]
            if sol.status != 1:
                t = t_new
                if t >= dt * (1 - 1e-13):
                    break
                continue  # N crossed zero: into or out of flight, decided at the top
            if mode == 0:
                mode = -1 if sol.t_events[0].size else 1
            elif mode in (1, -1):
                y[1] = 0.0
                N = n0 + sn * t_new
                af = a0 + s * t_new
                mode = -1 if af > mu * N else (1 if af < -mu * N else 0)
            t = t_new
            if t >= dt * (1 - 1e-13):
                break
    return peak, y[0]
