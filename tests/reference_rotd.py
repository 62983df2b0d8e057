"""Independent reference of rotated oscillator peaks (RotD spectra) on a floor of a building with
a model per direction, where no single 1-D spectrum gives the rotated response.

It shares no code with floorslide's kernels: each direction's building and a bank of oscillators
on its floor are one linear system ``z' = A z + b a(t)`` (from the models' public state-space
matrices), stepped exactly by SciPy's matrix exponential of the augmented system (input linear
in each record step) on a dense grid of ``sub`` points per step (phase ``≤ 0.05`` per point);
inside every dense interval where a peak may be (its ends within ``h²/4·max|q''|`` of the dense
maximum: twice the most the response can bulge above its chord there, with ``max|q''|`` read on
the dense grid), each state is interpolated on 12 Chebyshev points
(exact to rounding: the response is an entire function, degree-11 truncation ≈ 0.05¹²/12!) and
the peak of every rotation ``q1 cos θ + q2 sin θ``, and of ``q1² + q2²``, is found from the
roots of the interpolant's derivative (NumPy's Chebyshev series).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
from numpy.polynomial import Chebyshev

NODES = 12
PHASE = 0.05


def stacked_system(building, floor, periods, damping):
    """``A``, ``b`` of ``z = [x, q_1, q_1', …]``: the building's states (none on the ground) and
    one oscillator per period on the floor (``q'' = −a_f − 2ξωq' − ω²q``), and the fastest rate
    (spectral radius, 1/s)."""
    if building is None:
        A0, b0, ca, da = np.zeros((0, 0)), np.zeros(0), np.zeros(0), 1.0
    else:
        A0, B0 = building.state_matrices()
        C, D, _ = building.output_matrices([floor], "acceleration")
        b0, ca, da = B0[:, 0], C[0], D[0, 0]
    n, m = A0.shape[0], len(periods)
    A = np.zeros((n + 2 * m, n + 2 * m))
    b = np.zeros(n + 2 * m)
    A[:n, :n] = A0
    b[:n] = b0
    for k, T in enumerate(periods):
        w = 2 * np.pi / T
        i = n + 2 * k
        A[i, i + 1] = 1.0
        A[i + 1, :n] = -ca
        A[i + 1, i] = -(w**2)
        A[i + 1, i + 1] = -2 * damping * w
        b[i + 1] = -da
    return A, b, float(np.abs(np.linalg.eigvals(A)).max())


def _flow(A, b, tau):
    """``E`` with ``z(τ) = E @ [z(0), u0, s]`` for the input ``u0 + s·t``."""
    N = A.shape[0]
    M = np.zeros((N + 2, N + 2))
    M[:N, :N] = A
    M[:N, N] = b
    M[N, N + 1] = 1.0
    return scipy.linalg.expm(M * tau)[:N]


def rotated_peaks(buildings, floor, acc1, acc2, dt, periods, damping, angles):
    """Peaks ``max_t |q1 cos θ + q2 sin θ|`` (``(len(periods), len(angles))``) and
    ``max_t |(q1, q2)|`` (``len(periods)``) of oscillators on `floor` of ``buildings = (b1, b2)``
    (each direction's model, or ``(None, None)`` on the ground) under ``acc1``, ``acc2``."""
    systems = [stacked_system(b, floor, periods, damping) for b in buildings]
    rate = max(s[2] for s in systems)
    sub = max(1, int(np.ceil(rate * dt / PHASE)))
    hd = dt / sub
    npts = acc1.size
    m = len(periods)
    nodes = hd / 2 * (1 - np.cos(np.pi * (np.arange(NODES) + 0.5) / NODES))
    dense, inner, slopes, starts = [], [], [], []
    for (A, b, _), acc in zip(systems, (acc1, acc2), strict=True):
        N = A.shape[0]
        E = _flow(A, b, hd)
        s = np.diff(acc) / dt
        u = np.empty((npts - 1) * sub + 1)
        Z = np.zeros(((npts - 1) * sub + 1, N))
        z = np.zeros(N)
        for k in range(npts - 1):
            for r in range(sub):
                j = k * sub + r
                u[j] = acc[k] + s[k] * (r * hd)
                z = E[:, :N] @ z + E[:, N] * u[j] + E[:, N + 1] * s[k]
                Z[j + 1] = z
        n = N - 2 * m
        # q'' of every oscillator at the dense points: rows n + 1, n + 3, … of z' = A z + b u
        zdot = Z @ A.T + np.outer(np.append(u[:-1], acc[-1]), b)
        dense.append((Z[:, n::2], np.abs(zdot[:, n + 1 :: 2]).max(axis=0)))
        inner.append([_flow(A, b, t) for t in nodes])
        slopes.append(np.repeat(s, sub))
        starts.append((Z, u))
    cache = {}

    def cheb(d, i):
        """The oscillators' ``q`` of direction ``d`` on dense interval ``i`` (Chebyshev series)."""
        key = (d, i)
        if key not in cache:
            Z, u = starts[d]
            N = Z.shape[1]
            y = np.array([F @ np.concatenate([Z[i], [u[i], slopes[d][i]]]) for F in inner[d]])
            q = y[:, N - 2 * m :: 2]
            cache[key] = [Chebyshev.fit(nodes, col, NODES - 1, domain=[0, hd]) for col in q.T]
        return cache[key]

    def peak_on(poly):
        ends = max(abs(poly(0.0)), abs(poly(hd)))
        r = poly.deriv().roots()
        r = r[np.isreal(r)].real
        r = r[(r > 0) & (r < hd)]
        return max(ends, np.abs(poly(r)).max(initial=0.0))

    (q1, dd1), (q2, dd2) = dense
    k4 = hd * hd / 4
    rad = np.deg2rad(angles)
    peaks = np.zeros((m, len(angles)))
    mags = np.zeros(m)
    for p in range(m):
        for j, th in enumerate(rad):
            c, s = np.cos(th), np.sin(th)
            v = np.abs(c * q1[:, p] + s * q2[:, p])
            ends = np.maximum(v[:-1], v[1:])
            best = v.max()
            window = k4 * (abs(c) * dd1[p] + abs(s) * dd2[p])
            for i in np.flatnonzero(ends >= best - window):
                best = max(best, peak_on(c * cheb(0, i)[p] + s * cheb(1, i)[p]))
            peaks[p, j] = best
        v = np.hypot(q1[:, p], q2[:, p])
        ends = np.maximum(v[:-1], v[1:])
        best2 = v.max() ** 2
        for i in np.flatnonzero(ends >= v.max() - k4 * np.hypot(dd1[p], dd2[p])):
            P1, P2 = cheb(0, i)[p], cheb(1, i)[p]
            best2 = max(best2, peak_on(P1 * P1 + P2 * P2))
        mags[p] = np.sqrt(best2)
    return peaks, mags
