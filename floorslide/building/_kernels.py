"""Compiled loops over time for linear systems driven by piecewise-linear records.

Small dense state vectors, one pass over the samples, O(1) memory besides the outputs.
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import (
    curvature_bound_at,
    curvature_tail_weights,
    foh_step,
    substep_inputs,
    taylor_coefficients,
)
from floorslide.numerics.polynomial import max_abs_above, scratch


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


@njit(cache=True)
def foh_states(phi, p, q, acc, k0, k1, substeps, x0, X):
    """States of the exact recurrence ``x_{j+1} = Φ x_j + p a_j + q a_{j+1}`` on the sub-steps
    of record steps ``k0 … k1 − 1`` (the record interpolated linearly onto them, which leaves
    the piecewise-linear input unchanged), from ``x0`` at the start of step ``k0``:
    ``X[(k − k0)·substeps + r]`` at the start of sub-step ``r`` of step ``k``, the last row at
    the end of step ``k1 − 1``. The one building integration every exact consumer reads
    (:mod:`floorslide.building.exact_motion`)."""
    n = x0.size
    for i in range(n):
        X[0, i] = x0[i]
    row = 0
    for k in range(k0, k1):
        a = acc[k]
        a1 = acc[k + 1]
        for r in range(substeps):
            aa, ab = substep_inputs(a, a1, r, substeps)
            foh_step(phi, p, q, X[row], aa, ab, X[row + 1])
            row += 1


@njit(cache=True)
def state_outputs(X, k0, substeps, C, D, acc, out):
    """Outputs ``out[i, k] = D_i a_k + C_i·x_k`` at the record samples ``k0 …`` of one chunk of
    states ``X`` (the record-step starts are every ``substeps``-th row), summed in the order the
    kernels use, so a sample equals the value the solvers see there."""
    n = X.shape[1]
    nk = (X.shape[0] - 1) // substeps + 1
    for kk in range(nk):
        x = X[kk * substeps]
        a = acc[k0 + kk]
        for i in range(C.shape[0]):
            s = D[i] * a
            for j in range(n):
                s += C[i, j] * x[j]
            out[i, k0 + kk] = s


@njit(cache=True)
def foh_peaks(X, k0, R, beta, acc, substeps, h, peak, t_peak):
    """True peaks ``max |y(t)|`` over record steps ``k0 …`` (one chunk of states ``X`` of a
    :class:`~floorslide.building.exact_motion.BuildingMotion`), including inside steps, for
    outputs whose Taylor rows are ``R, beta`` (see :meth:`ExactStepper.taylor_rows`).

    ``peak[i]`` and ``t_peak[i]`` carry the peak of output ``i`` and its time from chunk to
    chunk (the first chunk, ``k0 = 0``, starts them at ``t = 0``). On each sub-step an output
    is searched only when its end values plus a rigorous bound of its deviation from the chord,
    ``h²/8·max|y''|`` with ``max|y''| ≤ Σ_j j(j−1)h^{j−2}|c_j|``
    (:func:`~floorslide.building._instep.curvature_bound_at`: ``c_2``, ``c_3`` exact, the
    tail bounded from the state), can exceed its peak so far; then every critical point of its
    Taylor polynomial is found (:func:`floorslide.numerics.polynomial.max_abs_above`) — no
    assumption on how many there are.
    """
    n = X.shape[1]
    m = R.shape[0]
    K = R.shape[1] - 1
    nsteps = (X.shape[0] - 1) // substeps
    c = np.empty(K + 1)
    work = scratch(K + 1)
    WX = np.zeros((m, n))
    WA = np.zeros(m)
    WS = np.zeros(m)
    for i in range(m):
        WA[i], WS[i] = curvature_tail_weights(R[i], beta[i], h, WX[i])
    y0 = np.empty(m)
    for i in range(m):
        v = beta[i, 0] * acc[k0]
        for j in range(n):
            v += R[i, 0, j] * X[0, j]
        y0[i] = v
        if k0 == 0:
            peak[i] = abs(v)
            t_peak[i] = 0.0
    for kk in range(nsteps):
        k = k0 + kk
        a = acc[k]
        a1 = acc[k + 1]
        slope = (a1 - a) / (substeps * h)
        for r in range(substeps):
            aa, ab = substep_inputs(a, a1, r, substeps)
            t0 = (k * substeps + r) * h
            row = kk * substeps + r
            x_prev = X[row]
            x = X[row + 1]
            for i in range(m):
                y1 = beta[i, 0] * ab
                for j in range(n):
                    y1 += R[i, 0, j] * x[j]
                if abs(y1) > peak[i]:
                    peak[i] = abs(y1)
                    t_peak[i] = t0 + h
                if max(abs(y0[i]), abs(y1)) > peak[i] - 0.125 * h * h * curvature_bound_at(
                    R[i], beta[i], x_prev, aa, slope, h, WX[i], WA[i], WS[i]
                ):
                    taylor_coefficients(R[i], beta[i], x_prev, aa, slope, c)
                    v, tv = max_abs_above(c, K, 0.0, h, peak[i], work)
                    if v > peak[i] and tv >= 0.0:
                        peak[i] = v
                        t_peak[i] = t0 + tv
                y0[i] = y1
