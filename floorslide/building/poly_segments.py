"""The exact motion of floors as polynomial segments: the contract between buildings and
consumers (docs/design.md §6 and §10b), and two producers of it.

A *poly motion* is any object with attributes ``dt`` (record step, s), ``npts`` (samples),
``floors`` (the floors it holds), ``notes`` (what was done to the input, one line each) and a
method ``poly_chunks()`` yielding :class:`PolySegments` in time order that cover the record
steps ``0 … npts − 2`` (a chunk never splits a record step). On each segment every floor's
absolute acceleration in ``x`` (``h1``) and ``y`` (``h2``) *is* a polynomial in the local time
``τ ∈ [0, L]``: consumers read it as given (no resampling), whatever its degree (< ``DEGREE``)
and however many segments a record step holds.

Producers here, for general use and for testing consumers on motions whose answer is known:

- :class:`GroundPolyMotion`: the ground pair itself (piecewise-linear records);
- :class:`LinearPolyMotion`: the floors of a linear building (one model, or one per
  direction), from the exact first-order-hold states and the Taylor rows of the floors'
  absolute accelerations (:func:`floorslide.building._instep.taylor_coefficients`, the
  polynomial the plane solver reads on each sub-step).

Both can cut their segments at arbitrary points (``split``), re-expanding each polynomial about
the new start (:func:`floorslide.numerics.polynomial.taylor_shift`): the motion is the same,
its segments are not aligned with the record any more.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import substep_inputs, taylor_coefficients
from floorslide.building._kernels import foh_states
from floorslide.building.directions import per_direction
from floorslide.building.exact_motion import frozen, stepper
from floorslide.errors import ModelError
from floorslide.pair import as_pair

__all__ = [
    "DEGREE",
    "GroundPolyMotion",
    "LinearPolyMotion",
    "PolySegments",
    "check_segments",
    "checked_chunks",
    "poly_values",
    "samples_on_poly",
    "shift_rows",
]

DEGREE = 24
"""Coefficients per polynomial (degree 23 at most; trailing zeros allowed)."""
CHUNK_STEPS = 2048
"""Record steps per chunk of the producers here (each chunk costs a few Python calls: 256 made
them ~0.5 ms of a slide–rock call per 256 steps; 2048 keeps a chunk under ~1 MB per floor)."""
MAX_SPLIT = 3
"""Most pieces a producer cuts one (sub-)step into with ``split``."""


@dataclass(frozen=True)
class PolySegments:
    """One chunk of a poly motion: polynomial segments covering record steps ``k0 … k1 − 1``.

    Attributes
    ----------
    t0
        ``(nseg,)`` segment start times, s: increasing and contiguous
        (``t0[i+1] = t0[i] + length[i]`` to rounding).
    length
        ``(nseg,)`` segment lengths ``L > 0``, s.
    step
        ``(nseg,)`` int64: the record step ``k`` a segment lies in (``t ∈ [k dt, (k+1) dt]``).
    ends
        ``(nseg,)`` bool: True when the segment ends on the record sample ``(k+1)·dt``.
    coef
        ``(nseg, nfloors, 2, DEGREE)``: the absolute acceleration of floor ``f`` in direction
        ``d`` (0: ``x``/``h1``, 1: ``y``/``h2``) is ``Σ_j coef[i, f, d, j]·τ^j``, ``τ ∈ [0, L]``,
        m/s².
    floors
        The floors the rows of `coef` are.
    k0, k1
        The chunk covers record steps ``k0 … k1 − 1``.
    """

    t0: np.ndarray
    length: np.ndarray
    step: np.ndarray
    ends: np.ndarray
    coef: np.ndarray
    floors: tuple[int, ...]
    k0: int
    k1: int

    @property
    def nseg(self) -> int:
        """Number of segments."""
        return int(self.t0.size)


def check_segments(seg: PolySegments, dt: float | None = None) -> None:
    """Validate one chunk's shapes, contiguity and step bookkeeping.

    Parameters
    ----------
    seg
        The chunk.
    dt
        The record step, s: when given, each segment must lie in its record step.

    Raises
    ------
    ModelError
        In one line naming what is wrong (key ``motion``).
    """
    n = seg.t0.shape[0] if seg.t0.ndim == 1 else -1
    if n < 1:
        _bad("t0 must be a non-empty 1-D array")
    nf = len(seg.floors)
    for name in ("length", "step", "ends"):
        if getattr(seg, name).shape != (n,):
            _bad(f"{name} has shape {getattr(seg, name).shape}, expected ({n},)")
    if seg.coef.shape != (n, nf, 2, DEGREE):
        _bad(f"coef has shape {seg.coef.shape}, expected ({n}, {nf}, 2, {DEGREE})")
    if seg.step.dtype != np.int64 or seg.ends.dtype != np.bool_:
        _bad("step must be int64 and ends bool")
    if not (np.all(np.isfinite(seg.t0)) and np.all(np.isfinite(seg.coef))):
        _bad("t0 and coef must be finite")
    if not np.all(seg.length > 0.0) or not np.all(np.isfinite(seg.length)):
        _bad("every segment length must be finite and > 0")
    if not seg.k0 < seg.k1:
        _bad(f"the chunk covers steps {seg.k0}..{seg.k1 - 1}: k0 must be below k1")
    end = seg.t0 + seg.length
    tol = 1e-12 * max(1.0, float(np.max(np.abs(end))))
    gap = np.abs(seg.t0[1:] - end[:-1])
    if gap.size and np.max(gap) > tol:
        i = int(np.argmax(gap))
        _bad(f"segment {i + 1} starts at {seg.t0[i + 1]!r} s, not where segment {i} ends")
    steps = seg.step
    if steps[0] != seg.k0 or steps[-1] != seg.k1 - 1 or np.any(np.diff(steps) < 0):
        _bad(f"segment steps must run from k0={seg.k0} to k1-1={seg.k1 - 1}, non-decreasing")
    if np.any(np.diff(steps) > 1):
        _bad("a record step between k0 and k1 has no segment")
    last = np.append(np.diff(steps) > 0, True)
    if not np.array_equal(last, seg.ends):
        _bad("ends must be True exactly on each record step's last segment")
    if dt is not None:
        lo = steps * dt
        hi = (steps + 1) * dt
        tol_t = 1e-9 * dt
        if np.any(seg.t0 < lo - tol_t) or np.any(end > hi + tol_t):
            _bad(f"a segment lies outside its record step (dt = {dt:g} s)")


def checked_chunks(motion) -> Iterator[PolySegments]:
    """A poly motion's chunks, each validated (:func:`check_segments`), and together checked to
    cover the record steps ``0 … npts − 2`` in order (each chunk starting where the last ended).

    Raises
    ------
    ModelError
        In one line naming what is wrong (key ``motion``).
    """
    dt = float(motion.dt)
    npts = int(motion.npts)
    if npts < 2:
        _bad(f"the motion has {npts} samples: at least 2 are needed")
    k = 0
    for seg in motion.poly_chunks():
        check_segments(seg, dt)
        if seg.k0 != k:
            _bad(f"a chunk starts at step {seg.k0}, where step {k} was expected")
        if tuple(seg.floors) != tuple(motion.floors):
            _bad(f"a chunk holds floors {tuple(seg.floors)}, the motion {tuple(motion.floors)}")
        k = seg.k1
        yield seg
    if k != npts - 1:
        _bad(f"the chunks end at step {k}, the record at step {npts - 1}")


def _bad(message: str) -> None:
    raise ModelError(f"poly segments: {message}", "motion")


# ------------------------------------------------------------------------- producers


def _pair(h1, h2, dt):
    """The two components validated (:func:`floorslide.pair.as_pair`)."""
    if h2 is None:
        pair = as_pair(h1, dt)
    else:
        pair = as_pair((h1, h2), dt)
    if pair.npts < 2:
        raise ModelError("the records need at least 2 samples", "acc")
    return pair


def shift_rows(C: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Each polynomial ``C[i, ..., :]`` (coefficients on the last axis) re-expanded about
    ``τ = s[i]``: the coefficients of a segment's polynomials from a point inside it, for a
    producer that cuts segments (the synthetic divisions of
    :func:`~floorslide.numerics.polynomial.taylor_shift`, vectorised over rows)."""
    out = np.array(C, dtype=float, copy=True)
    deg = out.shape[-1] - 1
    tau = s.reshape((-1,) + (1,) * (out.ndim - 2))
    for i in range(deg):
        for j in range(deg - 1, i - 1, -1):
            out[..., j] += tau * out[..., j + 1]
    return out


def _split(t0, length, step, ends, coef, rng):
    """Cut every segment into 1 … :data:`MAX_SPLIT` pieces at points drawn from `rng` (within
    10–90 % of it), each piece's polynomial re-expanded about its start."""
    n = t0.size
    pieces = rng.integers(1, MAX_SPLIT + 1, size=n)
    starts = []  # each segment's piece offsets
    for i in range(n):
        cuts = np.sort(rng.uniform(0.1, 0.9, size=pieces[i] - 1)) * length[i]
        starts.append(np.concatenate([[0.0], cuts]))
    seg = np.repeat(np.arange(n), pieces)
    off = np.concatenate(starts)
    nxt = np.concatenate([np.append(s[1:], length[i]) for i, s in enumerate(starts)])
    last = np.concatenate([np.arange(p) == p - 1 for p in pieces])
    return (
        t0[seg] + off,
        nxt - off,
        step[seg],
        ends[seg] & last,
        shift_rows(coef[seg], off),
    )


def _rng(split):
    return None if split is None else np.random.default_rng(split)


class GroundPolyMotion:
    """The ground pair itself as a poly motion (floor 0): on record step ``k`` each component
    is ``a_k + (a_{k+1} − a_k)/dt·τ``.

    Parameters
    ----------
    h1, h2
        Ground accelerations along ``x`` and ``y``, m/s² (or a
        :class:`~floorslide.records.pairs.RecordPair` as `h1` with ``h2=None``).
    dt
        Time step, s (with arrays).
    split
        None, or a seed: cut each step into 1 … 3 segments at random points (the same motion
        on segments not aligned with the record).

    Attributes
    ----------
    dt, npts, floors, notes
        The poly-motion interface (record step in s, samples, ``(0,)``, notes of the pair).
    """

    def __init__(self, h1, h2=None, dt: float | None = None, *, split=None):
        pair = _pair(h1, h2, dt)
        self.h1 = np.ascontiguousarray(pair.h1, dtype=float)
        self.h2 = np.ascontiguousarray(pair.h2, dtype=float)
        self.dt = float(pair.dt)
        self.npts = int(self.h1.size)
        self.floors: tuple[int, ...] = (0,)
        self.notes: tuple[str, ...] = tuple(pair.notes)
        self.split = split

    def poly_chunks(self) -> Iterator[PolySegments]:
        """The segments, :data:`CHUNK_STEPS` record steps per chunk."""
        rng = _rng(self.split)
        steps = self.npts - 1
        dt = self.dt
        for k0 in range(0, steps, CHUNK_STEPS):
            k1 = min(k0 + CHUNK_STEPS, steps)
            k = np.arange(k0, k1, dtype=np.int64)
            coef = np.zeros((k.size, 1, 2, DEGREE))
            for d, a in enumerate((self.h1, self.h2)):
                coef[:, 0, d, 0] = a[k0:k1]
                coef[:, 0, d, 1] = (a[k0 + 1 : k1 + 1] - a[k0:k1]) / dt
            parts = (k * dt, np.full(k.size, dt), k, np.ones(k.size, dtype=bool), coef)
            if rng is not None:
                parts = _split(*parts, rng)
            yield PolySegments(*parts, floors=self.floors, k0=k0, k1=k1)


@njit(cache=True)
def _linear_coefficients(X, k0, nsteps, m, h, acc, R, beta, d, out):
    """Taylor coefficients of the floors' absolute accelerations in direction `d` on every
    sub-step of a chunk: ``out[row, f, d, :K+1]`` from the state ``X[row]`` at the sub-step's
    start (:func:`~floorslide.building._instep.taylor_coefficients`; ``R, beta`` the floors'
    Taylor rows, ``(nf, K+1, n)`` and ``(nf, K+1)``)."""
    nf = R.shape[0]
    for kk in range(nsteps):
        k = k0 + kk
        s = (acc[k + 1] - acc[k]) / (m * h)
        for r in range(m):
            a, _ = substep_inputs(acc[k], acc[k + 1], r, m)
            row = kk * m + r
            for f in range(nf):
                taylor_coefficients(R[f], beta[f], X[row], a, s, out[row, f, d])


class LinearPolyMotion:
    """The floors of a linear building under two horizontal components as a poly motion.

    Each direction's model (one building for both, or a
    :class:`~floorslide.building.directions.BuildingPair`) is stepped exactly (first-order
    hold, :func:`~floorslide.building._kernels.foh_states`) on sub-steps common to both
    (``ρ(A)·h ≤ 0.5``, the larger count of the two); on each sub-step the floors' absolute
    accelerations are their Taylor polynomials from the state at its start
    (:func:`~floorslide.building._instep.taylor_coefficients`), equal to the exact in-step
    functions to rounding — the same polynomials :func:`floorslide.slide_plane` reads.

    Parameters
    ----------
    building
        A linear building (both directions), a BuildingPair or a 2-tuple of linear buildings.
    h1, h2
        Ground accelerations along ``x`` and ``y``, m/s².
    dt
        Time step, s.
    floors
        Floors to hold (default: all, ``0 … stories``).
    split
        None, or a seed: cut each sub-step into 1 … 3 segments at random points.

    Attributes
    ----------
    dt, npts, floors, notes
        The poly-motion interface (record step in s, samples, floors held, notes of the pair).
    substeps
        Sub-steps per record step, common to both directions (a segment each, unless split).
    """

    def __init__(self, building, h1, h2=None, dt: float | None = None, floors=None, *,
                 split=None):  # fmt: skip
        pair = _pair(h1, h2, dt)
        bx, by = per_direction(building)
        if bx is None:
            raise ModelError("LinearPolyMotion needs a building (GroundPolyMotion: the ground)",
                             "building")  # fmt: skip
        self.building = building
        self.h1 = frozen(np.ascontiguousarray(pair.h1, dtype=float))
        self.h2 = frozen(np.ascontiguousarray(pair.h2, dtype=float))
        self.dt = float(pair.dt)
        self.npts = int(self.h1.size)
        self.floors: tuple[int, ...] = tuple(bx.check_floors(floors))
        self.notes: tuple[str, ...] = tuple(pair.notes)
        self.split = split
        m = max(stepper(bx, self.dt).substeps, stepper(by, self.dt).substeps)
        while max(stepper(b, self.dt, m).order for b in (bx, by)) >= DEGREE:
            m *= 2  # (ρ(A)·h ≤ 0.5 gives degree 16: never in practice)
        self.substeps = m
        self._dirs = [self._direction(b, m) for b in (bx, by)]

    def _direction(self, b, m):
        """The stepper of one direction with `m` sub-steps, and its floors' Taylor rows."""
        st = stepper(b, self.dt, m)
        C, D, _ = b.output_matrices(list(self.floors), "acceleration")
        Rs, Bs = [], []
        for i in range(len(self.floors)):  # floor by floor, as FloorMotion forms them
            R, beta = st.taylor_rows(C[i : i + 1], D[i : i + 1, 0])
            Rs.append(R[0])
            Bs.append(beta[0])
        return st, np.ascontiguousarray(Rs), np.ascontiguousarray(Bs)

    def poly_chunks(self) -> Iterator[PolySegments]:
        """The segments (a sub-step each, or pieces of it with ``split``), :data:`CHUNK_STEPS`
        record steps per chunk."""
        rng = _rng(self.split)
        steps = self.npts - 1
        m = self.substeps
        h = self._dirs[0][0].h
        nf = len(self.floors)
        x = [np.zeros(d[0].n) for d in self._dirs]
        for k0 in range(0, steps, CHUNK_STEPS):
            k1 = min(k0 + CHUNK_STEPS, steps)
            ns = k1 - k0
            coef = np.zeros((ns * m, nf, 2, DEGREE))
            for d, (st, R, beta) in enumerate(self._dirs):
                acc = self.h1 if d == 0 else self.h2
                p, q = st.input_weights()
                X = np.empty((ns * m + 1, st.n))
                foh_states(st.phi, p, q, acc, k0, k1, m, x[d], X)
                x[d] = X[-1].copy()
                _linear_coefficients(X, k0, ns, m, h, acc, R, beta, d, coef)
            if not np.all(np.isfinite(coef)):
                raise ModelError(
                    f"the building's response is not finite by t = {k1 * self.dt:.6g} s",
                    "building",
                )
            rows = np.arange(ns * m, dtype=np.int64)
            kk = k0 + rows // m
            r = rows % m
            t0 = (kk * m + r) * h
            parts = (t0, np.full(rows.size, h), kk, r == m - 1, coef)
            if rng is not None:
                parts = _split(*parts, rng)
            yield PolySegments(*parts, floors=self.floors, k0=k0, k1=k1)


def _floor_rows(motion, floors) -> list[int]:
    """Indices into ``motion.floors`` of `floors` (None: all)."""
    have = tuple(motion.floors)
    if floors is None:
        return list(range(len(have)))
    floors = [floors] if np.isscalar(floors) else list(floors)
    out = []
    for f in floors:
        if f not in have:
            raise ModelError(f"floor {f} is not in the motion (it holds floors {have})", "floor")
        out.append(have.index(f))
    return out


def poly_values(coef: np.ndarray, tau) -> np.ndarray:
    """``Σ_j coef[..., j]·τ^j`` (Horner), `tau` broadcast against ``coef[..., 0]``."""
    v = np.zeros(np.broadcast_shapes(coef.shape[:-1], np.shape(tau)))
    for j in range(coef.shape[-1] - 1, -1, -1):
        v = v * tau + coef[..., j]
    return v


def samples_on_poly(motion, floors: Sequence[int] | int | None = None) -> np.ndarray:
    """The floors' absolute accelerations at the record samples, ``(nfloors, 2, npts)``, m/s²:
    each segment ending on a sample evaluated at ``τ = L``; sample 0 the first segment at
    ``τ = 0``.

    Parameters
    ----------
    motion
        A poly motion.
    floors
        Floors of the motion (default: all of them, in its order).
    """
    rows = _floor_rows(motion, floors)
    out = np.full((len(rows), 2, motion.npts), np.nan)
    first = True
    for seg in checked_chunks(motion):
        c = seg.coef[:, rows]
        if first:
            out[:, :, 0] = c[0, :, :, 0]
            first = False
        e = np.flatnonzero(seg.ends)
        vals = poly_values(c[e], seg.length[e][:, None, None])
        out[:, :, seg.step[e] + 1] = np.moveaxis(vals, 0, -1)
    return out
