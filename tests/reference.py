"""Independent high-accuracy references for the exact solvers.

They share no code with floorslide's exact methods: SciPy's DOP853 integrates each step of the
piecewise-linear record separately (the forcing is smooth inside a step, so the 8th-order
method reaches rounding level), restarting at every sample.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp


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
