"""Compiled event-driven integration of a building on nonlinear isolation with a heavy rigid
block on one floor, one system (1-D).

The discrete mode is the pair (isolator branch, block phase). The isolator's branches are those
of :mod:`floorslide.building._nonlinear_kernel` (``ELASTIC``/``PLASTIC_POS``/``PLASTIC_NEG`` of a
lead-rubber layer, ``SLIP_POS``/``SLIP_NEG``/``STICK`` of a friction pendulum); the block is
stuck (its floor carries its mass) or sliding (its floor carries the constant reaction ``m·f``
of its friction, ``f = ±mu_k·g``). Each of the six pairs is linear time-invariant, so every
sub-step is stepped by the pair's exact first-order-hold recurrence and, inside it, known as the
pair's Taylor polynomials. The augmented state is ``[u (n); u' (n); F0; s; s'; f]``: the
building's displacements relative to the ground (``u[0]`` the isolator's), the layer's constant
force on its branch (``F0``, as in the building's kernel), the block's slide relative to its
floor and its velocity, and ``f`` (m/s²).

Events, the first crossing of a level by one of the pair's polynomials
(:func:`floorslide.numerics.polynomial.rise_within`):

- the isolator's, exactly those of the building alone (:func:`_nonlinear_kernel._event`:
  yield, unloading, breakaway, stop) — the friction a stuck pendulum needs is the pair's, which
  carries the block's mass or its friction reaction when the block stands on the base mat;
- the block's: breakaway when the floor acceleration of the pair with the block stuck leaves
  ``[−mu_s·g, mu_s·g]``, stop when ``s'`` returns to 0 (then stuck if the stuck pair needs at
  most ``mu_s·g`` there, else the other way).

After every event the other part is settled at once (:func:`_settle`): a change of one can put
the other beyond its friction limit on the spot (a pendulum's breakaway makes the base mat's
acceleration jump; a block on the mat that starts or stops sliding changes the friction the
stuck pendulum needs). The floor's absolute acceleration and the isolator's displacement are
searched for their true peaks on every segment between events
(:func:`floorslide.numerics.polynomial.max_abs_on`).
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import foh_step, substep_inputs, taylor_coefficients
from floorslide.building._nonlinear_kernel import (
    ELASTIC,
    NO_EVENT,
    PLASTIC_NEG,
    PLASTIC_POS,
    SLIP_NEG,
    SLIP_POS,
    STICK,
    _event,
    _state_at,
)
from floorslide.numerics.polynomial import max_abs_on, rise_within, scratch

STUCK, SLIDING = 0, 1
"""Block phases: the second index of a pair (``pair = 2·mat_of[branch] + phase``)."""
EVENT_GAP = 1e-12
"""Shortest time between two events, in sub-steps (as the building's kernel)."""
SETTLE_ROUNDS = 4
"""Most rounds of :func:`_settle` after an event (each part can switch once per round)."""

# entries of the kernel's result vector ``out`` (the first ten as the linear coupled kernel's)
(PEAK_SLIDE, T_PEAK, PFA, T_PFA, BLOCK_PEAK_ACC, SLIDE_TIME, SLIPS, EVENTS, LIMIT_AT, MODE,
 ISO_PEAK, T_ISO_PEAK, ISO_EVENTS, BRANCH) = range(14)  # fmt: skip
NOUT = 14


class CoupledNonlinearSetup(NamedTuple):
    """Everything the kernel needs but the record, for one building, floor, block and dt;
    built by :func:`floorslide.contents.coupled_nonlinear.setup`. Leading axis of the stacks:
    the pair ``2·mat_of[branch] + phase``."""

    phi: Any
    """``Φ(h)`` per pair, ``(P, N, N)``."""
    p: Any
    """``p`` of ``x_{j+1} = Φ x_j + p a_j + q a_{j+1}`` per pair, ``(P, N)``."""
    q: Any
    """``q`` of the same recurrence."""
    state_rows: Any
    """Taylor rows of every state per pair, ``(P, N, K+1, N)``."""
    state_beta: Any
    """Their ground terms, ``(P, N, K+1)``."""
    friction_rows: Any
    """Taylor rows of the friction a stuck pendulum needs (zero on the other pairs),
    ``(P, K+1, N)``."""
    friction_beta: Any
    """Their ground terms, ``(P, K+1)``."""
    floor_rows: Any
    """Taylor rows of the block's floor's absolute acceleration per pair, ``(P, K+1, N)``."""
    floor_beta: Any
    """Their ground terms, ``(P, K+1)``."""
    mat_of: Any
    """Index of an isolator branch's matrices (−1: not a branch of this layer), ``(7,)``."""
    substeps: int
    """Sub-steps per record step."""
    h: float
    """Sub-step length, s."""
    limits: Any
    """``[mu_s·g, mu_k·g]`` of the block, m/s²; then the layer's ``[k1 − k2, D_y, Q, mu·W,
    mu_s·W]`` (the building's kernel's ``consts``)."""
    n: int
    """Degrees of freedom of the building (``x[0]`` the isolator's displacement)."""
    max_events: int
    """Most events in one sub-step (beyond it ``out[LIMIT_AT]`` records where, and the run
    stops)."""


@njit(cache=True)
def _row_value(R, B, x, a):
    """A function's value from its Taylor rows (row 0 and ground term 0) at state ``x``."""
    s = B[0] * a
    for j in range(x.size):
        s += R[0, j] * x[j]
    return s


@njit(cache=True)
def _settle(S, branch, mode, x, a, out):
    """Switch at once what the last event put beyond its friction limit, at state ``x`` and
    ground ``a``: a stuck pendulum whose needed friction exceeds ``mu_s·W`` slides, a stuck
    block whose floor acceleration exceeds ``mu_s·g`` slides (``x`` updated). Returns the new
    ``(branch, mode)``."""
    n = S.n
    iF = 2 * n
    i_v, i_f = 2 * n + 2, 2 * n + 3
    mus_g = S.limits[0]
    muk_g = S.limits[1]
    muW = S.limits[5]
    musW = S.limits[6]
    for _ in range(SETTLE_ROUNDS):
        changed = False
        if branch == STICK:
            P = 2 * S.mat_of[STICK] + (0 if mode == 0 else 1)
            F = _row_value(S.friction_rows[P], S.friction_beta[P], x, a)
            if F > musW or F < -musW:
                branch = SLIP_POS if F > 0.0 else SLIP_NEG
                x[iF] = muW if F > 0.0 else -muW
                x[n] = 0.0
                out[ISO_EVENTS] += 1
                changed = True
        if mode == 0:
            P = 2 * S.mat_of[branch]
            af = _row_value(S.floor_rows[P], S.floor_beta[P], x, a)
            if af > mus_g or af < -mus_g:
                mode = -1 if af > 0.0 else 1
                x[i_v] = 0.0
                x[i_f] = mode * muk_g
                out[SLIPS] += 1
                out[EVENTS] += 1
                changed = True
        if not changed:
            break
    return branch, mode


@njit(cache=True)
def coupled_nonlinear_run(S, acc, x, branch, out, hist_s, hist_v, hist_a, hist_mode, hist_u0):
    """Integrate building, layer and block over the whole record from state ``x`` (updated)
    and the layer's `branch` at t = 0, the block stuck at the start (then settled: a record
    that starts beyond a friction limit breaks it away at once).

    ``out``: ``NOUT`` results (the module's constants): as the linear coupled kernel's, then the
    isolator's true peak ``|u_0|`` and its time, its events, its final branch. Histories at the
    samples (slide, its velocity, the floor's absolute acceleration, the block's mode 0 / ±1,
    the isolator's displacement) when they have a column per sample, else untouched. Just after
    an event the searches start ``EVENT_GAP·h`` later (see the building's kernel).
    """
    N = x.size
    n = S.n
    K = S.floor_rows.shape[1] - 1
    h = S.h
    m = S.substeps
    mus_g = S.limits[0]
    muk_g = S.limits[1]
    kk = S.limits[2]
    dy = S.limits[3]
    Q = S.limits[4]
    muW = S.limits[5]
    musW = S.limits[6]
    iF = 2 * n
    i_s, i_v, i_f = 2 * n + 1, 2 * n + 2, 2 * n + 3
    c = np.empty(K + 1)
    work = scratch(K + 1)
    y = np.empty(N)
    npts = acc.size
    want = hist_s.size == npts
    out[:] = 0.0
    out[LIMIT_AT] = -1.0
    mode = 0
    branch, mode = _settle(S, branch, mode, x, acc[0], out)
    P = 2 * S.mat_of[branch] + (0 if mode == 0 else 1)
    a_start = _row_value(S.floor_rows[P], S.floor_beta[P], x, acc[0])
    out[PFA] = abs(a_start)
    out[BLOCK_PEAK_ACC] = abs(a_start) if mode == 0 else muk_g
    out[PEAK_SLIDE] = abs(x[i_s])
    out[ISO_PEAK] = abs(x[0])
    fresh = False
    if want:
        hist_s[0] = x[i_s]
        hist_v[0] = x[i_v]
        hist_a[0] = a_start
        hist_mode[0] = mode
        hist_u0[0] = x[0]
    for k in range(npts - 1):
        a = acc[k]
        a1 = acc[k + 1]
        slope = (a1 - a) / (m * h)
        for r in range(m):
            aa, ab = substep_inputs(a, a1, r, m)
            t0 = (k * m + r) * h
            s0 = 0.0
            events_here = 0
            while True:
                P = 2 * S.mat_of[branch] + (0 if mode == 0 else 1)
                L = h - s0
                a_s = aa + slope * s0
                lo = EVENT_GAP * h if fresh else 0.0
                fresh = False
                # the layer's first event
                p_el = -x[iF] / kk if branch == ELASTIC else 0.0
                t_iso, kind_iso = _event(
                    branch, S.state_rows[P], S.state_beta[P], S.friction_rows[P],
                    S.friction_beta[P], x, a_s, slope, L, K, p_el, dy, musW, lo, n, c, work,
                )  # fmt: skip
                # the block's first event
                t_blk = -1.0
                kind_blk = 0
                if lo < L:
                    if mode == 0:
                        taylor_coefficients(S.floor_rows[P], S.floor_beta[P], x, a_s, slope, c)
                        t_up = rise_within(c, K, lo, L, mus_g, work)
                        for j in range(K + 1):
                            c[j] = -c[j]
                        t_dn = rise_within(c, K, lo, L, mus_g, work)
                        if t_up >= 0.0 and (t_dn < 0.0 or t_up <= t_dn):
                            t_blk, kind_blk = t_up, -1
                        elif t_dn >= 0.0:
                            t_blk, kind_blk = t_dn, 1
                    else:
                        taylor_coefficients(
                            S.state_rows[P, i_v], S.state_beta[P, i_v], x, a_s, slope, c
                        )
                        if mode > 0:
                            for j in range(K + 1):
                                c[j] = -c[j]
                        t_blk = rise_within(c, K, lo, L, 0.0, work)
                te = -1.0
                which = 0  # 1 the layer, 2 the block
                if t_iso != NO_EVENT:
                    te, which = t_iso, 1
                if t_blk >= 0.0 and (te < 0.0 or t_blk < te):
                    te, which = t_blk, 2
                seg = L if te < 0.0 else te
                if te < 0.0 and events_here == 0:
                    foh_step(S.phi[P], S.p[P], S.q[P], x, aa, ab, y)
                else:
                    _state_at(S.state_rows[P], S.state_beta[P], x, a_s, slope, seg, K, y, c)
                # true peaks on the segment: the floor's acceleration, the isolator's
                # displacement
                taylor_coefficients(S.floor_rows[P], S.floor_beta[P], x, a_s, slope, c)
                stuck = mode == 0
                level = min(out[PFA], out[BLOCK_PEAK_ACC]) if stuck else out[PFA]
                v, tv = max_abs_on(c, K, seg, level, work)
                if v > out[PFA]:
                    out[PFA] = v
                    out[T_PFA] = t0 + s0 + tv
                if stuck and v > out[BLOCK_PEAK_ACC]:
                    out[BLOCK_PEAK_ACC] = v
                taylor_coefficients(S.state_rows[P, 0], S.state_beta[P, 0], x, a_s, slope, c)
                v, tv = max_abs_on(c, K, seg, out[ISO_PEAK], work)
                if v > out[ISO_PEAK]:
                    out[ISO_PEAK] = v
                    out[T_ISO_PEAK] = t0 + s0 + tv
                if mode != 0:
                    out[SLIDE_TIME] += seg
                    if muk_g > out[BLOCK_PEAK_ACC]:
                        out[BLOCK_PEAK_ACC] = muk_g
                for i in range(N):
                    x[i] = y[i]
                if abs(x[i_s]) > out[PEAK_SLIDE]:
                    out[PEAK_SLIDE] = abs(x[i_s])
                    out[T_PEAK] = t0 + s0 + seg
                if te < 0.0:
                    break
                a_e = a_s + slope * te
                if which == 1:
                    out[ISO_EVENTS] += 1
                    if branch == ELASTIC:
                        if kind_iso > 0:
                            branch = PLASTIC_POS
                            x[iF] = Q
                        else:
                            branch = PLASTIC_NEG
                            x[iF] = -Q
                    elif branch == PLASTIC_POS or branch == PLASTIC_NEG:
                        pl = x[0] - dy if branch == PLASTIC_POS else x[0] + dy
                        x[n] = 0.0
                        x[iF] = -kk * pl
                        branch = ELASTIC
                    elif branch == SLIP_POS or branch == SLIP_NEG:
                        x[n] = 0.0
                        Ps = 2 * S.mat_of[STICK] + (0 if mode == 0 else 1)
                        F = _row_value(S.friction_rows[Ps], S.friction_beta[Ps], x, a_e)
                        if abs(F) <= musW:
                            branch = STICK
                        elif F > 0.0:
                            branch = SLIP_POS
                            x[iF] = muW
                        else:
                            branch = SLIP_NEG
                            x[iF] = -muW
                    else:  # STICK: breakaway in the direction of the demand
                        if kind_iso > 0:
                            branch = SLIP_POS
                            x[iF] = muW
                        else:
                            branch = SLIP_NEG
                            x[iF] = -muW
                else:
                    out[EVENTS] += 1
                    x[i_v] = 0.0
                    if mode == 0:
                        mode = kind_blk
                        x[i_f] = kind_blk * muk_g
                        out[SLIPS] += 1
                    else:
                        Pk = 2 * S.mat_of[branch]
                        need = _row_value(S.floor_rows[Pk], S.floor_beta[Pk], x, a_e)
                        if need > mus_g:
                            new = -1
                        elif need < -mus_g:
                            new = 1
                        else:
                            new = 0
                        if new != 0:
                            out[SLIPS] += 1
                        mode = new
                        x[i_f] = mode * muk_g
                branch, mode = _settle(S, branch, mode, x, a_e, out)
                s0 = s0 + te
                fresh = True
                events_here += 1
                if events_here > S.max_events:
                    out[LIMIT_AT] = t0
                    out[MODE] = mode
                    out[BRANCH] = branch
                    return
                if s0 >= h:
                    break
        if want:
            P = 2 * S.mat_of[branch] + (0 if mode == 0 else 1)
            hist_s[k + 1] = x[i_s]
            hist_v[k + 1] = x[i_v]
            hist_a[k + 1] = _row_value(S.floor_rows[P], S.floor_beta[P], x, a1)
            hist_mode[k + 1] = mode
            hist_u0[k + 1] = x[0]
    out[MODE] = mode
    out[BRANCH] = branch
