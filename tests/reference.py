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


def sliding_oscillator(acc, dt, mu, f, xi, r, g=9.80665, rtol=1e-12, max_step=None):
    """2-DOF sliding oscillator on the ground by DOP853 with event location, step by step.

    Returns (peak |u|, residual u, peak |z|). State [u, v, z, zd] per unit top mass.
    """
    w = 2 * np.pi * f
    c2, w2 = 2 * xi * w, w * w
    fb = mu * (1 + r) * g
    y = np.zeros(4)
    mode = 0
    peak_u = peak_z = 0.0
    max_step = max_step or dt / 16
    for k in range(acc.size - 1):
        a0, s = acc[k], (acc[k + 1] - acc[k]) / dt
        t = 0.0
        for _ in range(1000):
            if mode == 0:

                def rhs(tt, yy, a0=a0, s=s):
                    return [0.0, 0.0, yy[3], -(a0 + s * tt) - c2 * yy[3] - w2 * yy[2]]

                def up(tt, yy, a0=a0, s=s):
                    return r * (a0 + s * tt) - c2 * yy[3] - w2 * yy[2] - fb

                def lo(tt, yy, a0=a0, s=s):
                    return -(r * (a0 + s * tt) - c2 * yy[3] - w2 * yy[2]) - fb

                up.terminal = lo.terminal = True
                up.direction = lo.direction = 1.0
                events = [up, lo]
            else:
                sg = float(mode)

                def rhs(tt, yy, a0=a0, s=s, sg=sg):
                    q = c2 * yy[3] + w2 * yy[2]
                    return [
                        yy[1],
                        -(a0 + s * tt) + q / r - sg * mu * g * (1 + r) / r,
                        yy[3],
                        -q * (1 + 1 / r) + sg * mu * g * (1 + r) / r,
                    ]

                def stop(tt, yy, sg=sg):
                    return sg * yy[1] + 1e-13

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
            peak_u = max(peak_u, np.abs(dense[0]).max())
            i = int(np.argmax(np.abs(dense[2])))
            lo_, hi_ = ts[max(i - 1, 0)], ts[min(i + 1, ts.size - 1)]
            if hi_ > lo_:  # refine the in-segment extremum of |z| on the dense output
                best = minimize_scalar(
                    lambda tt, sol=sol: -abs(sol.sol(tt)[2]),
                    bounds=(lo_, hi_),
                    method="bounded",
                    options={"xatol": 1e-14},
                )
                peak_z = max(peak_z, -best.fun)
            peak_z = max(peak_z, np.abs(dense[2]).max())
            y = sol.y[:, -1].copy()
            t = sol.t[-1]
            if sol.status != 1:
                break
            y[1] = 0.0
            if mode == 0:  # breakaway: which limit was crossed
                mode = -1 if sol.t_events[0].size else 1
            else:  # stop: stick, or reverse if friction cannot hold the base
                F = r * (a0 + s * t) - c2 * y[3] - w2 * y[2]
                mode = -1 if F > fb else (1 if F < -fb else 0)
            if t >= dt * (1 - 1e-13):
                break
    return peak_u, y[0], peak_z


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
