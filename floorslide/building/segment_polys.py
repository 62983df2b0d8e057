"""The motion of a building on nonlinear isolation in one direction, as a poly motion.

:class:`~floorslide.building.nonlinear_motion.NonlinearMotion` records segments — a sub-step of
one branch, or the piece of one between isolator events — with the branch, the state at the
segment's start and the ground's value and slope there. On a segment a floor's absolute
acceleration is the Taylor polynomial ``Σ_j (R_j x + β_j a_s + β_{j−1}/j · slope) τ^j`` of the
branch's rows (:func:`floorslide.building._instep.taylor_coefficients`), exact to rounding.
:class:`SegmentedPolyMotion` hands these polynomials out as :class:`~floorslide.building.
poly_segments.PolySegments` (the ``y`` component zero), so that any consumer of poly motions
(docs/design.md §10b) reads a building on nonlinear isolation as it reads the others.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from floorslide._jit import njit
from floorslide.building._instep import taylor_coefficients
from floorslide.building.poly_segments import DEGREE, PolySegments
from floorslide.errors import ModelError

__all__ = ["SegmentedPolyMotion"]


@njit(cache=True)
def _segment_coefficients(SI, SF, SX, count, OR, OB, rows, out):
    """``out[s, f, 0, :K+1]``: the coefficients of floor row ``rows[f]`` on segment `s`."""
    K = OR.shape[2] - 1
    for s in range(count):
        m = SI[s, 1]
        for f in range(rows.size):
            o = rows[f]
            taylor_coefficients(
                OR[m, o], OB[m, o], SX[s], SF[s, 0], SF[s, 2], out[s, f, 0, : K + 1]
            )


class SegmentedPolyMotion:
    """A :class:`~floorslide.building.nonlinear_motion.NonlinearMotion` as a poly motion.

    Parameters
    ----------
    motion
        The building's motion (:meth:`floorslide.NonlinearIsolatedBuilding.motion`).
    floors
        Floors to hold (default: the motion's).

    Attributes
    ----------
    dt, npts, floors, notes
        The poly-motion interface.
    """

    def __init__(self, motion, floors=None):
        self.motion = motion
        self.dt = float(motion.dt)
        self.npts = int(motion.npts)
        have = tuple(motion.floors)
        floors = have if floors is None else tuple(int(f) for f in floors)
        for f in floors:
            if f not in have:
                raise ModelError(
                    f"floor {f} is not among the floors the motion was built for {have}", "floor"
                )
        self.floors: tuple[int, ...] = floors
        self._rows = np.array([have.index(f) for f in floors], dtype=np.int64)
        self.notes: tuple[str, ...] = tuple(motion.notes)
        if motion.kernel.K + 1 > DEGREE:
            raise ModelError(
                f"the building's in-step polynomials have degree {motion.kernel.K}, above the "
                f"poly-motion limit {DEGREE - 1}",
                "building",
            )

    def poly_chunks(self) -> Iterator[PolySegments]:
        """The segments, chunk by chunk of the motion."""
        mo = self.motion
        kn = mo.kernel
        m = mo.substeps
        for SI, SF, SX, _SY, count in mo.chunks():
            if count == 0:
                continue
            coef = np.zeros((count, self._rows.size, 2, DEGREE))
            _segment_coefficients(SI, SF, SX, count, kn.OR, kn.OB, self._rows, coef)
            sub = SI[:count, 0]
            step = (sub // m).astype(np.int64)
            ends = (SI[:count, 3] == 1) & ((sub + 1) % m == 0)
            yield PolySegments(
                t0=np.array(SF[:count, 4]),
                length=np.array(SF[:count, 3]),
                step=step,
                ends=np.asarray(ends, dtype=bool),
                coef=coef,
                floors=self.floors,
                k0=int(step[0]),
                k1=int(step[-1]) + 1,
            )
