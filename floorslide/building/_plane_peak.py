"""Compiled kernel: the true peak of a floor's horizontal acceleration vector under two
components, inside steps (docs/design.md §10d).

On each sub-step the two directions' absolute accelerations are polynomials (their Taylor
series on the exact floor motion, :func:`~floorslide.building._instep.taylor_coefficients`), so
``|a|² = a_x² + a_y²`` is one too; its maximum is found by rigorous root isolation
(:func:`~floorslide.numerics.polynomial.max_abs_on`) wherever the bound
``|a| ≤ Σ_j |c_j| h^j`` (``|c_j|`` the length of the vector coefficient) allows a new peak.
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import substep_inputs, taylor_coefficients
from floorslide.numerics.polynomial import max_abs_on, scratch


@njit(cache=True, inline="always")
def plane_coefficients(R1, b1, x1, a1, s1, R2, b2, x2, a2, s2, h, c1, c2):
    """The Taylor coefficients ``c1``, ``c2`` of the two directions' floor accelerations on a
    sub-step of length ``h`` (states ``x1``, ``x2`` at its start, ground values ``a1``, ``a2``
    and slopes ``s1``, ``s2``; :func:`~floorslide.building._instep.taylor_coefficients`), and
    the bound ``Σ_j |c_j| h^j ≥ |a|`` on it (``|c_j|`` the vector coefficient's length)."""
    K = c1.size - 1
    for j in range(K + 1):
        c1[j] = 0.0
        c2[j] = 0.0
    taylor_coefficients(R1, b1, x1, a1, s1, c1)
    taylor_coefficients(R2, b2, x2, a2, s2, c2)
    reach = 0.0
    for j in range(K, -1, -1):
        reach = reach * h + np.hypot(c1[j], c2[j])
    return reach


@njit(cache=True)
def plane_peak_kernel(X1, X2, k0, R1, b1, R2, b2, acc1, acc2, substeps, h, out):
    """Raise ``out = [peak |a|, its time]`` over one chunk of the two directions' floor motions
    (``X1``, ``X2`` from record step ``k0``, the same sub-steps; ``R, b`` their Taylor rows of
    the floor's absolute acceleration; ``acc1``, ``acc2`` the ground records)."""
    K = max(R1.shape[0], R2.shape[0]) - 1
    c1 = np.zeros(K + 1)
    c2 = np.zeros(K + 1)
    q = np.zeros(2 * K + 1)
    work = scratch(2 * K + 2)
    nsteps = (X1.shape[0] - 1) // substeps
    if k0 == 0:
        a = np.hypot(b1[0] * acc1[0], b2[0] * acc2[0])
        if a > out[0]:
            out[0] = a
            out[1] = 0.0
    for kk in range(nsteps):
        k = k0 + kk
        s1 = (acc1[k + 1] - acc1[k]) / (substeps * h)
        s2 = (acc2[k + 1] - acc2[k]) / (substeps * h)
        for r in range(substeps):
            a1, _ = substep_inputs(acc1[k], acc1[k + 1], r, substeps)
            a2, _ = substep_inputs(acc2[k], acc2[k + 1], r, substeps)
            row = kk * substeps + r
            reach = plane_coefficients(R1, b1, X1[row], a1, s1, R2, b2, X2[row], a2, s2, h, c1, c2)
            if reach <= out[0]:
                continue
            for j in range(2 * K + 1):
                q[j] = 0.0
            for i in range(K + 1):
                for j in range(K + 1):
                    q[i + j] += c1[i] * c1[j] + c2[i] * c2[j]
            m, t = max_abs_on(q, 2 * K, h, out[0] * out[0], work)
            if m > out[0] * out[0]:
                out[0] = np.sqrt(m)
                out[1] = (k * substeps + r) * h + t
