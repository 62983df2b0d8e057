"""Compiled loops over time for linear systems driven by piecewise-linear records.

Small dense state vectors, one pass over the samples, O(1) memory besides the outputs.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from floorslide.building._instep import extreme_values, taylor_coefficients


@njit(cache=True)
def foh_outputs(phi, p, q, C, D, acc, substeps, x0, out):
    """Outputs ``out[:, k] = C x_k + D a_k`` at the record samples of the exact recurrence
    ``x_{j+1} = Φ x_j + p a_j + q a_{j+1}`` on sub-steps (the record is interpolated linearly
    onto them, which leaves the piecewise-linear input unchanged). Returns the final state."""
    n = x0.size
    m = C.shape[0]
    npts = acc.size
    x = x0.copy()
    y = np.empty(n)
    for k in range(npts):
        a = acc[k]
        for i in range(m):
            s = D[i] * a
            for j in range(n):
                s += C[i, j] * x[j]
            out[i, k] = s
        if k == npts - 1:
            break
        a1 = acc[k + 1]
        for r in range(substeps):
            aa = a + (a1 - a) * (r / substeps)
            ab = a + (a1 - a) * ((r + 1) / substeps) if r + 1 < substeps else a1
            for i in range(n):
                s = p[i] * aa + q[i] * ab
                for j in range(n):
                    s += phi[i, j] * x[j]
                y[i] = s
            for i in range(n):
                x[i] = y[i]
    return x


@njit(cache=True)
def foh_peaks(phi, p, q, R, beta, acc, substeps, h, x0, peak, t_peak):
    """True peaks ``max |y(t)|`` over the whole record, including inside steps, for outputs
    whose Taylor rows are ``R, beta`` (see :meth:`ExactStepper.taylor_rows`).

    ``peak[i]`` and ``t_peak[i]`` receive the peak of output ``i`` and its time."""
    n = x0.size
    m = R.shape[0]
    K = R.shape[1] - 1
    npts = acc.size
    x = x0.copy()
    y = np.empty(n)
    c = np.empty(K + 1)
    for i in range(m):
        peak[i] = -1.0
        t_peak[i] = 0.0
    if npts == 1:
        for i in range(m):
            taylor_coefficients(R[i], beta[i], x, acc[0], 0.0, c)
            peak[i] = abs(c[0])
        return
    for k in range(npts - 1):
        a = acc[k]
        a1 = acc[k + 1]
        slope = (a1 - a) / (substeps * h)
        for r in range(substeps):
            aa = a + (a1 - a) * (r / substeps)
            ab = a + (a1 - a) * ((r + 1) / substeps) if r + 1 < substeps else a1
            t0 = (k * substeps + r) * h
            for i in range(m):
                taylor_coefficients(R[i], beta[i], x, aa, slope, c)
                vmin, tmin, vmax, tmax = extreme_values(c, K, 0.0, h)
                if -vmin > peak[i]:
                    peak[i] = -vmin
                    t_peak[i] = t0 + tmin
                if vmax > peak[i]:
                    peak[i] = vmax
                    t_peak[i] = t0 + tmax
            for i in range(n):
                s = p[i] * aa + q[i] * ab
                for j in range(n):
                    s += phi[i, j] * x[j]
                y[i] = s
            for i in range(n):
                x[i] = y[i]
