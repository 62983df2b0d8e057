"""Compiled event-driven integration of a linear building with a heavy rigid block on one floor.

The block (mass ``m``, Coulomb friction ``mu_s``/``mu_k``) and the building are one system.
Between events it is linear time-invariant on one of two *branches*, each stepped by its exact
first-order-hold recurrence (:mod:`floorslide.building.exact`):

- ``STICK``: the block moves with its floor, which carries ``m`` more mass;
- ``SLIDE`` (``+1`` or ``−1``, the sign of the relative velocity): the building carries a
  constant force ``m·f`` on the floor, ``f = ±mu_k·g`` (the block's friction, reversed), and
  the block's slide obeys ``s'' = −a_f − f``.

The augmented state is ``[u (n); u' (n); s; s'; f]``: the building's displacements relative to
the ground, the block's slide relative to its floor and its velocity, and the constant ``f``
(an acceleration, m/s²: the force per unit block mass, so that ``m → 0`` stays well scaled).
Inside a sub-step every component is the branch's Taylor polynomial (exact to rounding on
sub-steps with ``ρ(A)·h ≤ 0.5``); an event — breakaway (the floor acceleration of the stuck
system leaving ``[−mu_s·g, mu_s·g]``) or stop (``s'`` reaching 0) — is the first crossing of a
level by one such polynomial, found by rigorous root isolation
(:func:`floorslide.numerics.polynomial.rise_within`), as in the kernel of nonlinear isolation
(:mod:`floorslide.building._nonlinear_kernel`). The floor's absolute acceleration, which jumps
at events when ``mu_s > mu_k``, is searched for its true peak on every segment between events
(:func:`floorslide.numerics.polynomial.max_abs_on`); ``|s|`` is monotone on a slide segment and
constant on a stuck one, so its peak is at the segment ends.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import (
    curvature_bound_at,
    curvature_tail_weights,
    foh_step,
    substep_inputs,
    taylor_coefficients,
)
from floorslide.numerics.polynomial import max_abs_on, poly_val, rise_within, scratch

STICK, SLIDE = 0, 1
"""Branch indices of the stacked matrices (a slide's sign is the mode ``±1``)."""
EVENT_GAP = 1e-12
"""Shortest time between two events, in sub-steps (as the kernel of nonlinear isolation: a
branch entered at a level crossing starts on its level up to rounding)."""

# entries of the kernel's result vector ``out``
(PEAK_SLIDE, T_PEAK, PFA, T_PFA, BLOCK_PEAK_ACC, SLIDE_TIME, SLIPS, EVENTS, LIMIT_AT,
 MODE) = range(10)  # fmt: skip
NOUT = 10


class CoupledSetup(NamedTuple):
    """Everything the kernel needs but the record, for one building, floor, block and dt;
    built by :func:`floorslide.contents.coupled._setup`. Leading axis of the stacks: the branch
    (:data:`STICK`, :data:`SLIDE`)."""

    phi: Any
    """``Φ(h)`` per branch, ``(2, N, N)``."""
    p: Any
    """``p`` of ``x_{j+1} = Φ x_j + p a_j + q a_{j+1}`` per branch, ``(2, N)``."""
    q: Any
    """``q`` of the same recurrence, ``(2, N)``."""
    state_rows: Any
    """Taylor rows of every state component per branch, ``(2, N, K+1, N)``."""
    state_beta: Any
    """Their ground terms, ``(2, N, K+1)``."""
    event_rows: Any
    """Taylor rows of the event function per branch, ``(2, K+1, N)``: the floor's absolute
    acceleration of the stuck system, the block's relative velocity while it slides."""
    event_beta: Any
    """Their ground terms, ``(2, K+1)``."""
    floor_rows: Any
    """Taylor rows of the floor's absolute acceleration per branch, ``(2, K+1, N)``."""
    floor_beta: Any
    """Their ground terms, ``(2, K+1)``."""
    substeps: int
    """Sub-steps per record step."""
    h: float
    """Sub-step length, s."""
    limits: Any
    """``[mu_s·g, mu_k·g]``, m/s²."""
    index: Any
    """``[i_s, i_v, i_f]``: the state components of the slide, its velocity and ``f``."""
    max_events: int
    """Most events in one sub-step (beyond it ``out[LIMIT_AT]`` records where, and the run
    stops)."""


@njit(cache=True)
def _state_at(R, B, x, a0, slope, s, K, out, c):
    """All states at ``s`` from the branch's full-state Taylor rows ``R[i], B[i]``."""
    for i in range(x.size):
        taylor_coefficients(R[i], B[i], x, a0, slope, c)
        out[i] = poly_val(c, K, s)


@njit(cache=True)
def _floor_peak(S, b, x, a0, slope, L, K, out, t0, stuck, c, work):
    """Update the floor's peak absolute acceleration (and the block's, when it is stuck) on a
    segment ``[0, L]`` of branch ``b`` from state ``x``."""
    taylor_coefficients(S.floor_rows[b], S.floor_beta[b], x, a0, slope, c)
    level = min(out[PFA], out[BLOCK_PEAK_ACC]) if stuck else out[PFA]
    v, t = max_abs_on(c, K, L, level, work)
    if v > out[PFA]:
        out[PFA] = v
        out[T_PFA] = t0 + t
    if stuck and v > out[BLOCK_PEAK_ACC]:
        out[BLOCK_PEAK_ACC] = v


@njit(cache=True)
def _floor_value(S, b, x, a):
    """The floor's absolute acceleration on branch ``b`` at state ``x``, ground ``a``."""
    R = S.floor_rows[b]
    s = S.floor_beta[b, 0] * a
    for j in range(x.size):
        s += R[0, j] * x[j]
    return s


@njit(cache=True)
def coupled_run(S, acc, x, out, hist_s, hist_v, hist_a, hist_mode):
    """Integrate building and block over the whole record from state ``x`` (updated; the
    block stuck at the start, as a building at rest holds it).

    Parameters
    ----------
    S
        :class:`CoupledSetup`.
    acc
        Ground acceleration samples, m/s² (piecewise linear between them).
    x
        Augmented state ``[u; u'; s; s'; f]`` at t = 0, in/out.
    out
        ``NOUT`` results (see the module's constants): peak ``|s|`` and its time, the floor's
        true peak absolute acceleration and its time, the block's peak absolute acceleration,
        the time spent sliding, slip phases (breakaways and reversals), events, the start of
        the sub-step where ``S.max_events`` was exceeded (−1: never), the final mode.
    hist_s, hist_v, hist_a, hist_mode
        Histories at the samples (slide, its velocity, the floor's absolute acceleration, the
        mode 0 / ±1) when they have a column per sample, else untouched.

    Notes
    -----
    Just after an event the search for the next starts ``EVENT_GAP·h`` later: a branch entered
    at a level crossing (a breakaway at exactly the friction limit, a stop at exactly zero
    velocity) starts on its level up to rounding, and a rounding-level sign there is not an
    event (it would switch back at once, without end).
    """
    N = x.size
    K = S.floor_rows.shape[1] - 1
    h = S.h
    m = S.substeps
    mus_g = S.limits[0]
    muk_g = S.limits[1]
    i_s, i_v, i_f = S.index[0], S.index[1], S.index[2]
    c = np.empty(K + 1)
    work = scratch(K + 1)
    y = np.empty(N)
    npts = acc.size
    want = hist_s.size == npts
    mode = 0
    fresh = False
    # the stuck branch's chord bound of the floor's acceleration (the fast path below)
    WX = np.empty(N)
    phi0, p0, q0 = S.phi[STICK], S.p[STICK], S.q[STICK]
    fr0, fb0 = S.floor_rows[STICK], S.floor_beta[STICK]
    WA, WS = curvature_tail_weights(fr0, fb0, h, WX)
    z_ok = False  # z0 holds the floor's acceleration at the sub-step's start
    z0 = 0.0
    out[:] = 0.0
    out[LIMIT_AT] = -1.0
    a_start = _floor_value(S, STICK, x, acc[0])
    out[PFA] = abs(a_start)
    out[BLOCK_PEAK_ACC] = abs(a_start)
    out[PEAK_SLIDE] = abs(x[i_s])
    if want:
        hist_s[0] = x[i_s]
        hist_v[0] = x[i_v]
        hist_a[0] = a_start
        hist_mode[0] = 0
    for k in range(npts - 1):
        a = acc[k]
        a1 = acc[k + 1]
        slope = (a1 - a) / (m * h)
        for r in range(m):
            aa, ab = substep_inputs(a, a1, r, m)
            t0 = (k * m + r) * h
            s0 = 0.0
            events_here = 0
            if mode == 0 and not fresh:
                # the common sub-step: the block stuck, and the floor's acceleration — the
                # friction it needs, per unit mass — bounded on the whole sub-step by its ends
                # and the chord bound (ends + h²/8·max|a_f''|) below both mu_s·g and the peaks
                # found so far: no event, no new peak; the state is stepped exactly as the
                # search below would step it (bit for bit), without a Taylor polynomial
                foh_step(phi0, p0, q0, x, aa, ab, y)
                if not z_ok:
                    z0 = fb0[0] * aa
                    for j in range(N):
                        z0 += fr0[0, j] * x[j]
                z1 = fb0[0] * ab
                for j in range(N):
                    z1 += fr0[0, j] * y[j]
                M2 = curvature_bound_at(fr0, fb0, x, aa, slope, h, WX, WA, WS)
                bound = max(abs(z0), abs(z1)) + h * h / 8.0 * M2
                if bound <= mus_g and bound <= min(out[PFA], out[BLOCK_PEAK_ACC]):
                    for i in range(N):
                        x[i] = y[i]
                    z0 = z1
                    z_ok = True
                    continue
            z_ok = False
            while True:
                b = STICK if mode == 0 else SLIDE
                L = h - s0
                a_s = aa + slope * s0
                lo = EVENT_GAP * h if fresh else 0.0
                fresh = False
                te = -1.0
                kind = 0
                if lo < L:
                    taylor_coefficients(S.event_rows[b], S.event_beta[b], x, a_s, slope, c)
                    if mode == 0:
                        # the floor needs more than mu_s·g of friction to carry the block:
                        # upward, the block lags behind (slides −); downward, it slides +
                        t_up = rise_within(c, K, lo, L, mus_g, work)
                        for j in range(K + 1):
                            c[j] = -c[j]
                        t_dn = rise_within(c, K, lo, L, mus_g, work)
                        if t_up >= 0.0 and (t_dn < 0.0 or t_up <= t_dn):
                            te, kind = t_up, -1
                        elif t_dn >= 0.0:
                            te, kind = t_dn, 1
                    else:
                        # the relative velocity comes back through zero
                        if mode > 0:
                            for j in range(K + 1):
                                c[j] = -c[j]
                        te = rise_within(c, K, lo, L, 0.0, work)
                seg = L if te < 0.0 else te
                if te < 0.0 and events_here == 0:
                    foh_step(S.phi[b], S.p[b], S.q[b], x, aa, ab, y)
                else:
                    _state_at(S.state_rows[b], S.state_beta[b], x, a_s, slope, seg, K, y, c)
                _floor_peak(S, b, x, a_s, slope, seg, K, out, t0 + s0, mode == 0, c, work)
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
                # an event at s0 + te
                x[i_v] = 0.0
                if mode == 0:
                    mode = kind
                    x[i_f] = kind * muk_g
                    out[SLIPS] += 1
                else:
                    a_e = a_s + slope * te
                    need = _floor_value(S, STICK, x, a_e)
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
                s0 = s0 + te
                fresh = True
                out[EVENTS] += 1
                events_here += 1
                if events_here > S.max_events:
                    out[LIMIT_AT] = t0
                    out[MODE] = mode
                    return
                if s0 >= h:
                    break
        if want:
            hist_s[k + 1] = x[i_s]
            hist_v[k + 1] = x[i_v]
            hist_a[k + 1] = _floor_value(S, STICK if mode == 0 else SLIDE, x, a1)
            hist_mode[k + 1] = mode
    out[MODE] = mode
