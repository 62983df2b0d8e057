"""Compiled kernel of rigid blocks sliding in the plane on a poly motion's segments
(:mod:`floorslide.building.poly_segments`).

The plane solver's step through one sub-step (:func:`floorslide.contents._plane_kernel.
_block_substep`: slip phases by their Taylor series, stops and breakaways by rigorous root
isolation) already reads the floor's acceleration as two polynomials on an interval; here those
polynomials are the segments' own coefficients instead of the building's Taylor rows. Each
segment's degree ``K`` is that of its last nonzero coefficient (at least 1); the series of a
slip phase is carried to degree ``max(D, K + 1)`` so that every coefficient of the floor enters
it.
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.contents._plane_kernel import (
    LIMIT_AT,
    MODE,
    SLIPS,
    START,
    UX,
    UY,
    _block_substep,
    _vertical_substep,
)
from floorslide.numerics.polynomial import scratch

JUMP_TOL = 1e-9
"""A stuck block breaks away at a segment's start when the floor's acceleration there exceeds
the breakaway level by more than this share: a jump (the mat of a building on friction
pendulums, whose acceleration jumps at the bearing's stops and breakaways). A continuous floor
motion reaches the level inside the segment before, where the solver locates it."""


@njit(cache=True)
def plane_segments_kernel(t0, length, step, ends, coef, f, sx, sy, first, g, MU, states, hist,
                          want_hist, D, max_events, accv, has_vert, dt):  # fmt: skip
    """Advance blocks in the plane through one chunk of segments of floor row `f`.

    ``t0, length, step, ends, coef``: the chunk's arrays
    (:class:`~floorslide.building.poly_segments.PolySegments`); the floor's acceleration on
    segment ``i`` is ``(sx·Σ_j coef[i, f, 0, j] τ^j, sy·Σ_j coef[i, f, 1, j] τ^j)`` (``sx, sy``
    1 or 0: a component alone for the 1-D comparison). ``first``: the chunk starts the record
    (a floor beyond the breakaway level at ``t = 0`` sets the block sliding from the start).
    ``MU = [mu_b; mu_k]`` per block, ``states`` ``(n, NCOL)`` in/out, ``hist[i, k] = (u_x, u_y)``
    at the samples when ``want_hist``; ``D`` the slip series' least degree. ``accv``: the
    vertical ground acceleration samples (step `dt`) when ``has_vert``: the normal acceleration
    is ``g + accv``, linear between samples (the building rigid vertically), as in
    :func:`~floorslide.contents._plane_kernel.plane_kernel`."""
    KM = coef.shape[3] - 1
    DM = max(D, KM + 1)
    degmax = 2 * (DM + 3) + 2
    work = scratch(max(degmax, 2 * KM + 2))
    c1 = np.zeros(KM + 1)
    c2 = np.zeros(KM + 1)
    ax = np.zeros(KM + 1)
    ay = np.zeros(KM + 1)
    A = np.zeros((KM + 1, 2))
    y = np.zeros((DM + 2, 2))
    rho = np.zeros(DM + 2)
    w = np.zeros((DM + 2, 2))
    sl = np.zeros((5, DM + 2))
    q = np.zeros(max(degmax, DM + KM) + 1)
    ux = np.zeros(DM + 4)
    uy = np.zeros(DM + 4)
    c1s = np.zeros(KM + 1)
    c2s = np.zeros(KM + 1)
    _segment_steps(t0, length, step, ends, coef, f, sx, sy, first, g, MU, states, hist,
                   want_hist, D, max_events, c1, c2, ax, ay, A, y, rho, w, sl, q, ux, uy,
                   work, accv, has_vert, dt, c1s, c2s)  # fmt: skip


@njit(cache=True, _nrt=False)
def _segment_steps(t0, length, step, ends, coef, f, sx, sy, first, g, MU, states, hist,
                   want_hist, D, max_events, c1, c2, ax, ay, A, y, rho, w, sl, q, ux, uy,
                   work, accv, has_vert, dt, c1s, c2s):  # fmt: skip
    """The loops of :func:`plane_segments_kernel` over segments and blocks, given its scratch."""
    nobj = MU.shape[1]
    nseg = t0.size
    KM = coef.shape[3] - 1
    if first:
        a1 = sx * coef[0, f, 0, 0]
        a2 = sy * coef[0, f, 1, 0]
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
    for s in range(nseg):
        K = 1
        for j in range(KM + 1):
            c1[j] = sx * coef[s, f, 0, j]
            c2[j] = sy * coef[s, f, 1, j]
            if j > K and (c1[j] != 0.0 or c2[j] != 0.0):
                K = j
        Ds = D if K < D else K + 1
        h = length[s]
        reach = 0.0
        for j in range(K, -1, -1):
            reach = reach * h + np.hypot(c1[j], c2[j])
        nlow = g
        n0 = g
        vslope = 0.0
        if has_vert:
            # N = g + a_v, linear on the record step (as the plane solver's)
            k = step[s]
            vslope = (accv[k + 1] - accv[k]) / dt
            n0 = g + accv[k] + vslope * (t0[s] - k * dt)
            nlow = min(n0, n0 + vslope * h)
        a0 = c1[0] * c1[0] + c2[0] * c2[0]
        for i in range(nobj):
            if (states[i, MODE] == 0.0 and n0 > 0.0
                    and a0 > (MU[0, i] * n0 * (1.0 + JUMP_TOL)) ** 2):  # fmt: skip
                # the floor's acceleration jumped beyond the breakaway level at the segment's
                # start (a bearing's stop or breakaway): the block starts to slide from rest
                states[i, MODE] = 1.0
                states[i, SLIPS] += 1.0
                states[i, START] = 1.0
            if states[i, MODE] == 0.0 and nlow > 0.0 and reach <= MU[0, i] * nlow:
                continue  # |a| ≤ Σ_j |c_j| h^j stays below the breakaway level
            st = states[i]
            if has_vert:
                ok = _vertical_substep(st, c1, c2, c1s, c2s, K, h, t0[s], n0, vslope, g,
                                       MU[0, i], MU[1, i], Ds, ax, ay, A, y, rho, w, sl, q, ux,
                                       uy, work, max_events)  # fmt: skip
            else:
                ok = _block_substep(st, c1, c2, K, h, t0[s], g, MU[0, i], MU[1, i], Ds, ax, ay,
                                    A, y, rho, w, sl, q, ux, uy, work, max_events, False, g,
                                    0.0)  # fmt: skip
            if not ok and st[LIMIT_AT] < 0.0:
                st[LIMIT_AT] = t0[s]
        if want_hist and ends[s]:
            k = step[s] + 1
            for i in range(nobj):
                hist[i, k, 0] = states[i, UX]
                hist[i, k, 1] = states[i, UY]
