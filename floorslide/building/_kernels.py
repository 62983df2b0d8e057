"""Compiled loops over time for linear systems driven by piecewise-linear records.

Small dense state vectors, one pass over the samples, O(1) memory besides the outputs.
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import (
    extreme_values,
    foh_step,
    substep_inputs,
    taylor_coefficients,
)


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
            aa, ab = substep_inputs(a, a1, r, substeps)
            foh_step(phi, p, q, x, aa, ab, y)
            for i in range(n):
                x[i] = y[i]
    return x


@njit(cache=True, inline="always")
def _value_and_slope(R, beta, i, x, a, slope):
    """``y`` and ``y'`` of output ``i`` at a (sub-)step boundary from its Taylor rows."""
    y = beta[i, 0] * a
    d = beta[i, 1] * a + beta[i, 0] * slope
    for j in range(x.size):
        y += R[i, 0, j] * x[j]
        d += R[i, 1, j] * x[j]
    return y, d


@njit(cache=True)
def foh_peaks(phi, p, q, R, beta, acc, substeps, h, x0, peak, t_peak):
    """True peaks ``max |y(t)|`` over the whole record, including inside steps, for outputs
    whose Taylor rows are ``R, beta`` (see :meth:`ExactStepper.taylor_rows`).

    ``peak[i]`` and ``t_peak[i]`` receive the peak of output ``i`` and its time. Values and
    slopes are evaluated at the sub-step boundaries; where the slope changes sign inside a
    sub-step, the full Taylor polynomial locates the extremum.
    """
    n = x0.size
    m = R.shape[0]
    K = R.shape[1] - 1
    npts = acc.size
    x = x0.copy()
    x_prev = x0.copy()
    y = np.empty(n)
    c = np.empty(K + 1)
    y0 = np.empty(m)
    d0 = np.empty(m)
    slope = (acc[1] - acc[0]) / (substeps * h) if npts > 1 else 0.0
    for i in range(m):
        y0[i], d0[i] = _value_and_slope(R, beta, i, x, acc[0], slope)
        peak[i] = abs(y0[i])
        t_peak[i] = 0.0
    for k in range(npts - 1):
        a = acc[k]
        a1 = acc[k + 1]
        slope = (a1 - a) / (substeps * h)
        for r in range(substeps):
            aa, ab = substep_inputs(a, a1, r, substeps)
            t0 = (k * substeps + r) * h
            for i in range(n):
                x_prev[i] = x[i]
            foh_step(phi, p, q, x_prev, aa, ab, y)
            for i in range(n):
                x[i] = y[i]
            for i in range(m):
                if r == 0:  # the slope of the record changes at samples: recompute y'(0)
                    y0[i], d0[i] = _value_and_slope(R, beta, i, x_prev, aa, slope)
                y1, d1 = _value_and_slope(R, beta, i, x, ab, slope)
                if abs(y1) > peak[i]:
                    peak[i] = abs(y1)
                    t_peak[i] = t0 + h
                if (d0[i] > 0.0 and d1 < 0.0) or (d0[i] < 0.0 and d1 > 0.0):
                    taylor_coefficients(R[i], beta[i], x_prev, aa, slope, c)
                    vmin, tmin, vmax, tmax = extreme_values(c, K, 0.0, h)
                    if -vmin > peak[i]:
                        peak[i] = -vmin
                        t_peak[i] = t0 + tmin
                    if vmax > peak[i]:
                        peak[i] = vmax
                        t_peak[i] = t0 + tmax
                y0[i] = y1
                d0[i] = d1
