"""Floor response spectra on a segmented floor motion — a floor of a building on nonlinear
isolation.

Every oscillator ``(T, ξ)`` goes through the recorded segments of the floor's exact motion
(:class:`floorslide.building.nonlinear_motion.NonlinearMotion`; the building is integrated once,
without them): on a whole sub-step without isolator events by its exact linear update
(precomputed per branch) and a rigorous filter that leaves few sub-steps to search; through a
segment between events by the Taylor series of its exact response to the floor's in-step
polynomial, in parts short for it (``ω h ≤ 0.5``). :func:`floorslide.response_spectrum` calls
:func:`spectrum_on_segments` when handed such a floor.
"""

from __future__ import annotations

import functools

import numpy as np

from floorslide.spectra import _segment_kernels as sk

__all__ = ["LAST_STATS", "spectrum_on_segments"]

BY_SERIES = False
"""Private switch: advance every oscillator by the series on every segment (the reference path
of the tests) instead of the exact linear update on whole sub-steps."""

EVENT_MEMORY = 64 * 2**20
"""Bytes the first pass may keep of the segments between events (5 numbers per oscillator and
segment; beyond it the second pass repeats their series)."""

LAST_STATS = np.zeros(4, dtype=np.int64)
"""Counters of the last call (sub-steps on the fast path, oscillator·sub-steps there, flagged
oscillator·sub-steps, polynomial searches): for profiling and tests."""


def _weights(OR, OB, h, out, w, xi, rho, D):
    """:func:`~floorslide.spectra._segment_kernels._rider_weights`, cached (a study asks for the
    same periods and damping ratios on the same building record after record)."""
    key = (OR.shape, OB.shape, float(h), int(D))
    arrays = (OR, OB, out, w, xi, rho)
    return _cached_weights(key, *(np.ascontiguousarray(a).tobytes() for a in arrays))


@functools.lru_cache(maxsize=8)
def _cached_weights(key, OR_b, OB_b, out_b, w_b, xi_b, rho_b):
    (or_shape, ob_shape, h, D) = key
    # (writable copies, as the kernels are compiled for; the arrays returned are shared
    # between calls and only read)
    OR = np.frombuffer(OR_b).reshape(or_shape).copy()
    OB = np.frombuffer(OB_b).reshape(ob_shape).copy()
    out = np.frombuffer(out_b, dtype=np.int64).copy()
    w, xi, rho = (np.frombuffer(b).copy() for b in (w_b, xi_b, rho_b))
    return sk._rider_weights(OR, OB, h, out, w, xi, rho, D)


def spectrum_on_segments(fm, T: np.ndarray, Z: np.ndarray, notes: tuple[str, ...] = ()):
    """Pseudo and true spectra of the floor `fm` of a segmented motion at periods `T` (s; 0 gives
    the floor's true peak acceleration) and damping ratios `Z`. Returns a
    :class:`~floorslide.spectra.core.Spectrum`."""
    from floorslide.building.exact import taylor_degree
    from floorslide.spectra.core import Spectrum

    mo = fm.motion
    kn = mo.kernel
    shape = (Z.size, T.size)
    sd, sv, sa = np.zeros(shape), np.zeros(shape), np.zeros(shape)
    cells = [(i, j) for i in range(Z.size) for j in range(T.size) if T[j] > 0]
    if cells:
        w = np.array([2 * np.pi / T[j] for _i, j in cells])
        xi = np.array([Z[i] for i, _j in cells])
        rho = w * np.where(xi > 1.0, xi + np.sqrt(np.abs(xi**2 - 1.0)), 1.0)
        order = np.argsort(rho, kind="stable")  # one floor: by their own rate
        w, xi, rho = w[order], xi[order], rho[order]
        out = np.full(w.size, fm.row, dtype=np.int64)
        phase = min(0.5, float(rho.max()) * mo.h)
        D = max(kn.K, taylor_degree(phase)) + 2
        S = np.zeros((2, w.size))
        P = np.zeros((3, w.size))
        stats = np.zeros(4, dtype=np.int64)
        fast = not BY_SERIES
        if fast:
            PH, OW, RC = _weights(kn.OR, kn.OB, mo.h, out, w, xi, rho, D)
        else:
            PH, OW, RC = np.zeros((4, 0)), np.zeros((0, 2, kn.N + 2, 0)), np.zeros((sk.NRC, 0))
        GT = kn.GT
        TH = np.zeros((3, w.size))
        SPLIT = np.zeros(w.size, dtype=np.int64)
        none = np.zeros((0, 5, w.size))
        kept = []  # per chunk, what the first pass found on the segments between events
        if fast:
            # two passes (see _segment_kernels): the peaks at the ends, then the filters and
            # searches against them; the oscillators start again at rest
            FB = np.zeros((kn.G.shape[1], sk.NFBR))
            room = EVENT_MEMORY // (5 * 8 * w.size)
            for SI, SF, SX, SY, count in mo.chunks():
                ne = int(np.count_nonzero(SI[:count, 2] != 1))
                EV = np.zeros((ne, 5, w.size)) if 0 < ne <= room else none
                room -= EV.shape[0]
                kept.append(EV)
                sk.peaks_at_ends(SI, SF, SX, SY, count, kn.G, GT, kn.OR, kn.OB, kn.K, mo.h, out,
                                 w, xi, rho, S, P, D, PH, OW, RC, FB, EV)  # fmt: skip
            sk.rider_thresholds(P, RC, out, FB, TH, SPLIT)
            S[:] = 0.0
        for c, (SI, SF, SX, SY, count) in enumerate(mo.chunks()):
            EV = kept[c] if c < len(kept) else none
            sk.oscillators_on_segments(SI, SF, SX, SY, count, kn.G, GT, kn.OR, kn.OB, kn.K, mo.h,
                                       out, w, xi, rho, S, P, D, fast, PH, OW, RC,
                                       stats, TH, SPLIT, fast, EV)  # fmt: skip
        LAST_STATS[:] = stats
        peaks = P.T[np.argsort(order, kind="stable")]
        for (i, j), (q, v, a) in zip(cells, peaks, strict=True):
            sd[i, j], sv[i, j], sa[i, j] = q, v, a
    sa[:, T == 0] = fm.peak()[0]
    w_all = np.where(T > 0, 2 * np.pi / np.where(T > 0, T, 1.0), 0.0)
    psa = np.where(T > 0, w_all * w_all * sd, sa)
    return Spectrum(T, Z, psa, sa, sv, sd, w_all * sd, method="exact", notes=tuple(notes))
