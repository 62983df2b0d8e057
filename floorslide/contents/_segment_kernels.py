"""Contents — rigid blocks, 2-DOF sliding oscillators, rocking blocks — on a building whose
motion is a list of segments: a building on nonlinear isolation
(:class:`floorslide.building.nonlinear_motion.NonlinearMotion`). The building is integrated once,
without them, and records each segment of its exact motion (a whole sub-step of one branch, or
the piece of one between isolator events: its branch, its start and end states, the ground
there); each kind of content is advanced through those segments by its own exact step on the
floor's in-step polynomial, as on a linear building.
"""

from __future__ import annotations

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import taylor_coefficients
from floorslide.building._nonlinear_kernel import TIGHT
from floorslide.contents._kernels import objects_on_substep
from floorslide.contents._oscillator_kernel import O_MODE, O_U, O_Z, O_ZD, _advance_part
from floorslide.contents._rocking_kernel import MODE as RK_MODE
from floorslide.contents._rocking_kernel import OVERTURNED as RK_OVERTURNED
from floorslide.contents._rocking_kernel import P_P, P_TAN, block_through
from floorslide.contents._rocking_kernel import TH as RK_TH
from floorslide.numerics.polynomial import scratch

BLOCK_MAX_EVENTS = 10000
"""Most friction events of a block in one segment (as ``floorslide.contents.events``)."""
FLEX_MAX_EVENTS = 1000
"""Most friction events of a 2-DOF oscillator in one part."""


@njit(cache=True, inline="always")
def _pack_segment(XW, pk, x, y, a0, a1, slope, L, t0, g):
    """Into the block pass's packed arguments: the building's states at a segment's ends, the
    ground's values and slope there, its length and start time, and the normal force's
    integrals over it (no vertical shaking: ``N = g``)."""
    for j in range(x.size):
        XW[0, j] = x[j]
        XW[1, j] = y[j]
    pk[0], pk[1], pk[2], pk[3], pk[4] = a0, a1, slope, L, t0
    pk[13] = g * L
    pk[14] = g * L * L / 2.0


@njit(cache=True, inline="always")
def _blocks_substep(G, OR, OB, m, XW, BLK, MU, bstates, buf, rw, pk, flags, n, h):
    """Advance the rigid blocks through a whole sub-step without events of the building, or a
    segment of one of length ``h`` (the curvature-tail weights of the whole sub-step in ``G``
    bound a shorter segment too), floor by floor, as on a linear building
    (:func:`floorslide.contents._kernels.objects_on_substep`: closed forms where a rigorous
    enclosure of the floor acceleration decides, the event-driven step otherwise).

    ``XW[0], XW[1]``: the building's states at the segment's ends (branch matrices ``m``);
    ``pk[0:5]``, ``pk[9:16]``: ground values, slope, ``h``, start time and the normal force's
    terms, set by the caller. Block ``i`` stands on floor ``BLK[1, i]`` (state index), output
    row ``BLK[0, i]`` (sorted); the floor's relative displacement and velocity are the states
    ``f`` and ``n + f``. Arguments packed as the block pass wants them (few fields per call)."""
    N = XW.shape[1]
    nblk = BLK.shape[1]
    aa, ab, slope = pk[0], pk[1], pk[2]
    i0 = 0
    while i0 < nblk:
        o = BLK[0, i0]
        i1 = i0
        while i1 < nblk and BLK[0, i1] == o:
            i1 += 1
        f = BLK[1, i0]
        for j in range(N):
            XW[2, j] = G[m, o + 1, TIGHT, j]
        pk[5] = G[m, o + 1, TIGHT, N]
        pk[6] = G[m, o + 1, TIGHT, N + 1]
        vr0 = XW[0, n + f]
        pk[7] = XW[1, n + f] - vr0 + 0.5 * h * (aa + ab)
        dD = XW[1, f] - XW[0, f] - vr0 * h
        pk[8] = dD + aa * h * h / 2.0 + slope * h * h * h / 6.0
        flags[4] = i0
        flags[5] = i1
        objects_on_substep(OR[m, o], OB[m, o], XW, MU, bstates, buf, rw, pk, flags)
        i0 = i1


@njit(cache=True)
def _flexible(OR, OB, x, a_s, slope, L, K, t_abs, o2, w2, xi2, r2, g, mub2, muk2, S2, ho2, K2,
              c2, cs, Y, poly, y, pk, work2):  # fmt: skip
    """Advance 2-DOF sliding oscillators (one kind, many friction pairs) through a segment
    ``[0, L]`` on the floor of output row ``o2``: in parts no longer than ``ho2`` (where the
    oscillator's phases have ``ρ·h ≤ 0.5``), each by the 2-DOF kernel's own exact event-driven
    step (:func:`floorslide.contents._oscillator_kernel._advance_part`)."""
    kr = OR.shape[1] - 1
    for j in range(K2 + 1):
        c2[j] = 0.0
    taylor_coefficients(OR[o2], OB[o2], x, a_s, slope, c2[: kr + 1])
    parts = max(1, int(np.ceil(L / ho2 - 1e-12)))
    hp = L / parts
    for sp in range(parts):
        base = sp * hp
        for o in range(muk2.size):
            _advance_part(c2, K2, base, hp, o, w2, xi2, r2, g, mub2, muk2, S2, t_abs + base,
                          FLEX_MAX_EVENTS, cs, Y, poly, y, pk, work2)  # fmt: skip


@njit(cache=True)
def _flexible_sample(H2, k, S2, muk2, flex, g, af):
    """Histories of the 2-DOF oscillators at record sample ``k``, as the linear path keeps them
    (:func:`floorslide.contents._oscillator_kernel.oscillator_kernel`): base slide ``u``, spring
    deformation ``z``, the top mass's absolute acceleration ``−(2ξω ż + ω² z)`` and the base's
    (the floor's `af` while stuck; the spring and kinetic friction forces over its mass while
    sliding)."""
    w, xi, r = flex[1], flex[2], flex[3]
    for o in range(S2.shape[0]):
        q_ = 2.0 * xi * w * S2[o, O_ZD] + w * w * S2[o, O_Z]
        H2[o, k, 0] = S2[o, O_U]
        H2[o, k, 1] = S2[o, O_Z]
        H2[o, k, 2] = -q_
        mode = S2[o, O_MODE]
        if mode == 0.0:
            H2[o, k, 3] = af
        else:
            H2[o, k, 3] = q_ / r - mode * muk2[o] * g * (1.0 + r) / r


@njit(cache=True)
def _rockers(OR, OB, x, a0, slope, L, K, t0, rk_out, rk_par, rk_states, g, D, nonlinear, phase,
             max_events, RB):  # fmt: skip
    """Advance the rocking blocks riding along through a segment ``[0, L]`` of the building
    from state ``x`` (ground ``a0 + slope·τ``): block ``i`` stands on the floor of output row
    ``rk_out[i]`` (sorted), parameters ``rk_par[i]`` and state ``rk_states[i]`` (the columns
    of :mod:`floorslide.contents._rocking_kernel`); each goes through the segment in parts
    with ``p·L ≤ phase`` (:func:`~floorslide.contents._rocking_kernel.block_through`).
    ``RB``: scratch rows (floor coefficients and their shifts, the series of θ, sin, cos, u, a
    polynomial, the root-isolation work)."""
    c, cs, cw = RB[0, : K + 1], RB[1, : K + 1], RB[2, : K + 1]
    t, S, C, u = RB[3, : D + 1], RB[4, : D + 1], RB[5, : D + 1], RB[6, : D + 1]
    q = RB[7]
    work = RB[8:]
    last = -1
    reach = 0.0
    for i in range(rk_out.size):
        st = rk_states[i]
        if st[RK_MODE] == RK_OVERTURNED:
            continue
        o = rk_out[i]
        if o != last:
            taylor_coefficients(OR[o], OB[o], x, a0, slope, c)
            last = o
            reach = 0.0
            for j in range(K, -1, -1):
                reach = reach * L + abs(c[j])
        par = rk_par[i]
        if st[RK_MODE] == 0.0 and reach <= g * par[P_TAN]:
            continue
        parts = max(1, int(np.ceil(par[P_P] * L / phase - 1e-12)))
        block_through(st, par, c, K, L, parts, t0, g, D, nonlinear, max_events, cs, t, S, C, u,
                      q, cw, work)  # fmt: skip


@njit(cache=True)
def block_workspace(K, ncol, g, allow_pos, allow_neg):
    """The block pass's packed arguments and scratch, made once per run (they carry between
    calls of :func:`blocks_on_segments`)."""
    buf = np.empty(5 * K + 17 + ncol)
    rw = scratch(K + 3)
    pk = np.zeros(16)
    pk[9], pk[11], pk[12], pk[15] = g, g, g, g
    flags = np.array([0, int(allow_pos), int(allow_neg), BLOCK_MAX_EVENTS, 0, 0], dtype=np.int64)
    return buf, rw, pk, flags


@njit(cache=True)
def blocks_on_segments(SI, SF, SX, SY, nseg, substeps, G, OR, OB, n, BLK, MU, bstates, buf, rw,
                       pk, flags, g, hist_u, accv, has_vert, dt):  # fmt: skip
    """Advance rigid blocks through the segments ``0 … nseg − 1`` of a building's motion
    (``SI[s] = (row, branch matrices, whole sub-step, ends its sub-step)``, ``SF[s] = (a_s,
    a_end, slope, L, t)``, states ``SX[s]``, ``SY[s]`` at its ends): each by
    :func:`_blocks_substep`, as on a linear building. Block ``i`` stands on floor ``BLK[1, i]``
    (state index), output row ``BLK[0, i]`` (sorted), friction ``MU[:, i]`` (breakaway,
    kinetic); ``bstates`` the columns of :mod:`floorslide.contents._kernels`. With a row of
    ``hist_u`` per block, the slides at the record samples a segment ends are written there.
    With `has_vert`, the normal force per unit mass is ``g + a_v``, ``a_v`` the vertical record
    ``accv`` linear between its samples (step `dt`): its value and slope at the segment's start,
    its range and integrals over the segment go to the block pass as on a linear building
    (:func:`floorslide.contents._kernels.slide_kernel`); the building is rigid vertically."""
    N = SX.shape[1]
    nblk = BLK.shape[1]
    XW = np.zeros((3, N))
    want = hist_u.shape[0] == nblk and nblk > 0
    flags[0] = 1 if has_vert else 0
    for s in range(nseg):
        m = SI[s, 1]
        L = SF[s, 3]
        _pack_segment(XW, pk, SX[s], SY[s], SF[s, 0], SF[s, 1], SF[s, 2], L, SF[s, 4], g)
        if has_vert:
            k = SI[s, 0] // substeps
            sn = (accv[k + 1] - accv[k]) / dt
            n0 = g + accv[k] + sn * (SF[s, 4] - k * dt)
            n1 = n0 + sn * L
            pk[9], pk[10], pk[11], pk[12] = n0, sn, min(n0, n1), max(n0, n1)
            pk[13] = 0.5 * (n0 + n1) * L
            pk[14] = n0 * L * L / 2.0 + sn * L * L * L / 6.0
        _blocks_substep(G, OR, OB, m, XW, BLK, MU, bstates, buf, rw, pk, flags, n, L)
        if want and SI[s, 3] == 1 and (SI[s, 0] + 1) % substeps == 0:
            k = (SI[s, 0] + 1) // substeps
            for i in range(nblk):
                hist_u[i, k] = bstates[i, 2]


@njit(cache=True)
def flexible_workspace(K2):
    """Scratch of the 2-DOF pass (carried between calls of :func:`flexible_on_segments`)."""
    return (np.zeros(K2 + 1), np.zeros(K2 + 1), np.zeros((4, K2 + 1)), np.zeros(K2 + 1),
            np.zeros(4), np.zeros(4), scratch(K2 + 1))  # fmt: skip


@njit(cache=True)
def flexible_on_segments(SI, SF, SX, nseg, substeps, OR, OB, K, flex, g, mub2, muk2, S2, c2, cs2,
                         Y2, poly2, y2, pk2, work2, H2, af):  # fmt: skip
    """Advance 2-DOF sliding oscillators through the segments ``0 … nseg − 1`` of a building's
    motion (as :func:`blocks_on_segments`) by :func:`_flexible`; ``flex = [row, ω, ξ, r, part
    length, degree]``. With a column of ``H2`` per sample, their histories at the samples
    (:func:`_flexible_sample`, the floor acceleration there ``af[k]``)."""
    o2 = int(flex[0])
    K2 = int(flex[5])
    want = muk2.size > 0 and H2.shape[0] == muk2.size and af.size > 0 and H2.shape[1] == af.size
    for s in range(nseg):
        m = SI[s, 1]
        _flexible(OR[m], OB[m], SX[s], SF[s, 0], SF[s, 2], SF[s, 3], K, SF[s, 4], o2, flex[1],
                  flex[2], flex[3], g, mub2, muk2, S2, flex[4], K2, c2, cs2, Y2, poly2, y2, pk2,
                  work2)  # fmt: skip
        if want and SI[s, 3] == 1 and (SI[s, 0] + 1) % substeps == 0:
            k = (SI[s, 0] + 1) // substeps
            _flexible_sample(H2, k, S2, muk2, flex, g, af[k])


@njit(cache=True)
def rocker_workspace(K, D):
    """Scratch rows of the rocking pass (:func:`_rockers`)."""
    sw = scratch(max(K, D) + 2)
    return np.zeros((8 + sw.shape[0], max(sw.shape[1], max(K, D) + 3)))


@njit(cache=True)
def rockers_on_segments(SI, SF, SX, nseg, substeps, OR, OB, K, rk_out, rk_par, rk_states, g, D,
                        nonlinear, phase, max_events, RB, rk_hist):  # fmt: skip
    """Advance rocking blocks through the segments ``0 … nseg − 1`` of a building's motion (as
    :func:`blocks_on_segments`) by :func:`_rockers`; with a row of ``rk_hist`` per block,
    ``θ`` at the samples (NaN once overturned)."""
    nrk = rk_out.size
    want = nrk > 0 and rk_hist.shape[0] == nrk
    for s in range(nseg):
        m = SI[s, 1]
        _rockers(OR[m], OB[m], SX[s], SF[s, 0], SF[s, 2], SF[s, 3], K, SF[s, 4], rk_out, rk_par,
                 rk_states, g, D, nonlinear, phase, max_events, RB)  # fmt: skip
        if want and SI[s, 3] == 1 and (SI[s, 0] + 1) % substeps == 0:
            k = (SI[s, 0] + 1) // substeps
            for i in range(nrk):
                if rk_states[i, RK_MODE] == RK_OVERTURNED:
                    rk_hist[i, k] = np.nan
                else:
                    rk_hist[i, k] = rk_states[i, RK_TH]


@njit(cache=True)
def rockers_on_poly(t0, length, step, ends, C, rk_par, rk_states, g, D, nonlinear, phase,
                    max_events, RB, rk_hist):  # fmt: skip
    """Advance rocking blocks standing on one floor through one chunk of a poly motion's
    segments (:mod:`floorslide.building.poly_segments`) along one component: on segment ``s``
    the floor's acceleration is ``Σ_j C[s, j] τ^j``, ``τ ∈ [0, length[s]]``; each block goes
    through it in parts with ``p·L ≤ phase``
    (:func:`~floorslide.contents._rocking_kernel.block_through`), a block at rest skipped while
    the coefficient bound stays below its uplift level. With a row of ``rk_hist`` per block,
    ``θ`` at the samples (NaN once overturned)."""
    K = C.shape[1] - 1
    c, cs, cw = RB[0, : K + 1], RB[1, : K + 1], RB[2, : K + 1]
    t, S, Cc, u = RB[3, : D + 1], RB[4, : D + 1], RB[5, : D + 1], RB[6, : D + 1]
    q = RB[7]
    work = RB[8:]
    nrk = rk_par.shape[0]
    want = nrk > 0 and rk_hist.shape[0] == nrk
    for s in range(t0.size):
        L = length[s]
        reach = 0.0
        for j in range(K, -1, -1):
            c[j] = C[s, j]
            reach = reach * L + abs(c[j])
        for i in range(nrk):
            st = rk_states[i]
            if st[RK_MODE] == RK_OVERTURNED:
                continue
            par = rk_par[i]
            if st[RK_MODE] == 0.0 and reach <= g * par[P_TAN]:
                continue
            parts = max(1, int(np.ceil(par[P_P] * L / phase - 1e-12)))
            block_through(st, par, c, K, L, parts, t0[s], g, D, nonlinear, max_events, cs, t, S,
                          Cc, u, q, cw, work)  # fmt: skip
        if want and ends[s]:
            k = step[s] + 1
            for i in range(nrk):
                if rk_states[i, RK_MODE] == RK_OVERTURNED:
                    rk_hist[i, k] = np.nan
                else:
                    rk_hist[i, k] = rk_states[i, RK_TH]
