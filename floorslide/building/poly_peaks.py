"""What a study reads off a poly motion besides its consumers: the floors' true peak
accelerations (of the horizontal vector and along each component), a motion kept in memory so
that several consumers read one integration, and one component of one floor as a 1-D motion
(docs/design.md §6, "In the plane, polynomial segments").

On a segment every floor's acceleration is a polynomial ``a_d(τ)`` (degree < ``DEGREE``), so
``|a|² = a_x² + a_y²`` is one too; its maximum is found by rigorous root isolation
(:func:`~floorslide.numerics.polynomial.max_abs_on`) wherever the bound
``|a| ≤ Σ_j |c_j| L^j`` (``|c_j|`` the vector coefficient's length) allows a new peak — the
same filter-then-isolate scheme as the linear floors' :func:`~floorslide.building.directions.
plane_peak`.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np

from floorslide._jit import njit
from floorslide.building.poly_segments import DEGREE, _floor_rows, checked_chunks
from floorslide.errors import ModelError
from floorslide.numerics.polynomial import max_abs_on, scratch

__all__ = ["KeptPolyMotion", "PolyComponent", "poly_peaks"]

MAX_KEPT_BYTES = 512 * 2**20
"""Most bytes of segments :class:`KeptPolyMotion` holds; a longer motion streams instead."""


@njit(cache=True)
def _peaks_kernel(t0, length, coef, rows, out, work, q):
    """Raise, per floor row ``rows[i]``, ``out[i] = [peak |a|, its time, peak |a_x|, its time,
    peak |a_y|, its time]`` over one chunk of segments."""
    K = coef.shape[3] - 1
    for s in range(t0.size):
        L = length[s]
        for i in range(rows.size):
            f = rows[i]
            c1 = coef[s, f, 0]
            c2 = coef[s, f, 1]
            reach = 0.0
            r1 = 0.0
            r2 = 0.0
            for j in range(K, -1, -1):
                reach = reach * L + np.hypot(c1[j], c2[j])
                r1 = r1 * L + abs(c1[j])
                r2 = r2 * L + abs(c2[j])
            if reach > out[i, 0]:
                for j in range(2 * K + 1):
                    q[j] = 0.0
                for a in range(K + 1):
                    if c1[a] == 0.0 and c2[a] == 0.0:
                        continue
                    for b in range(K + 1):
                        q[a + b] += c1[a] * c1[b] + c2[a] * c2[b]
                m, t = max_abs_on(q, 2 * K, L, out[i, 0] * out[i, 0], work)
                if m > out[i, 0] * out[i, 0]:
                    out[i, 0] = np.sqrt(m)
                    out[i, 1] = t0[s] + t
            for d in range(2):
                r = r1 if d == 0 else r2
                if r > out[i, 2 + 2 * d]:
                    m, t = max_abs_on(coef[s, f, d], K, L, out[i, 2 + 2 * d], work)
                    if m > out[i, 2 + 2 * d]:
                        out[i, 2 + 2 * d] = m
                        out[i, 3 + 2 * d] = t0[s] + t


@dataclass(frozen=True)
class PolyPeaks:
    """True peaks of floors' accelerations on a poly motion (one row per floor asked for).

    Attributes
    ----------
    floors
        The floors.
    peak, time
        ``max_t |a(t)|`` of the horizontal acceleration vector (m/s²) and when (s).
    components, component_times
        ``(nfloors, 2)``: ``max_t |a_d(t)|`` along ``x`` and ``y`` and when.
    """

    floors: tuple[int, ...]
    peak: np.ndarray
    time: np.ndarray
    components: np.ndarray
    component_times: np.ndarray


def poly_peaks(motion, floors: Sequence[int] | int | None = None) -> PolyPeaks:
    """The true peak accelerations of floors of a poly motion, inside segments: of the
    horizontal vector (the level a block's static friction must hold in the plane) and along
    each component, exact to rounding (root isolation on each segment's polynomial).

    Parameters
    ----------
    motion
        A poly motion (:mod:`floorslide.building.poly_segments`).
    floors
        Floors of the motion (default: all, in its order).
    """
    rows = _floor_rows(motion, floors)
    out = np.full((len(rows), 6), -1.0)
    out[:, 1::2] = 0.0
    K = DEGREE - 1
    work = scratch(2 * K + 2)
    q = np.zeros(2 * K + 1)
    r = np.array(rows, dtype=np.int64)
    for seg in checked_chunks(motion):
        _peaks_kernel(seg.t0, seg.length, seg.coef, r, out, work, q)
    fl = tuple(motion.floors[i] for i in rows)
    return PolyPeaks(fl, out[:, 0].copy(), out[:, 1].copy(), out[:, 2::2].copy(),
                     out[:, 3::2].copy())  # fmt: skip


class KeptPolyMotion:
    """A poly motion's segments integrated once and kept in memory, so that each consumer of a
    study (blocks, rockers, spectra, peaks, histories) reads them without integrating the
    building again. Beyond :data:`MAX_KEPT_BYTES` the segments are not kept and each pass
    streams from the wrapped motion (the same bits, more time).

    Every attribute of the wrapped motion (``dt``, ``npts``, ``floors``, ``notes``,
    ``response``, …) reads through.
    """

    def __init__(self, motion, max_bytes: int = MAX_KEPT_BYTES):
        self._motion = motion
        kept: list | None = []
        size = 0
        for seg in motion.poly_chunks():
            size += seg.coef.nbytes + 4 * seg.t0.nbytes
            if size > max_bytes:
                kept = None
                break
            kept.append(seg)
        self._kept = kept

    @property
    def kept(self) -> bool:
        """Whether the segments are held in memory."""
        return self._kept is not None

    def __getattr__(self, name):
        return getattr(self._motion, name)

    def poly_chunks(self) -> Iterator:
        """The kept chunks (or the wrapped motion's, streamed)."""
        if self._kept is None:
            return self._motion.poly_chunks()
        return iter(self._kept)


@dataclass(frozen=True)
class PolyComponent:
    """One floor of a poly motion along one horizontal component, as a 1-D floor motion for
    consumers that act in one direction (a rocking block whose faces lie along a component:
    :func:`floorslide.rock`).

    Attributes
    ----------
    motion
        The poly motion.
    floor
        The floor (one of ``motion.floors``).
    direction
        0 (``x``, ``h1``) or 1 (``y``, ``h2``).
    """

    motion: object
    floor: int
    direction: int

    def __post_init__(self) -> None:
        if self.direction not in (0, 1):
            raise ModelError(f"direction must be 0 or 1, got {self.direction!r}", "direction")
        _floor_rows(self.motion, self.floor)

    @property
    def row(self) -> int:
        """The floor's row in the motion's coefficients."""
        return tuple(self.motion.floors).index(self.floor)

    @property
    def dt(self) -> float:
        """Record step, s."""
        return float(self.motion.dt)

    @property
    def npts(self) -> int:
        """Number of samples."""
        return int(self.motion.npts)
