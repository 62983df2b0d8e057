"""Rigid blocks sliding in the plane on a poly motion: any building's floors read as polynomial
segments (:mod:`floorslide.building.poly_segments`, docs/design.md §6 and §10b).

The same model and result as :func:`floorslide.slide_plane` (isotropic Coulomb friction,
``u'' = −a(t) − mu_k·g·u'/|u'|`` while sliding, breakaway when ``|a| > max(mu_s, mu_k)·g``;
with vertical shaking ``g + a_v`` in place of ``g`` and free flight where it is ≤ 0), advanced
by the same exact step (:mod:`floorslide.contents._plane_kernel`) through each segment of the
floor's motion: the polynomials are the motion, read as given.
"""

from __future__ import annotations

import numpy as np

from floorslide.building.poly_segments import checked_chunks
from floorslide.constants import G
from floorslide.contents import _plane_kernel as pk
from floorslide.contents._plane_segment_kernels import plane_segments_kernel
from floorslide.contents.plane import DEGREE, PlaneSlideResult, _vertical, liftoff
from floorslide.contents.sliding import friction_pairs
from floorslide.errors import ModelError, SolverLimitError

__all__ = ["slide_plane_on_segments"]


def _floor_row(motion, floor) -> int:
    """The row of `floor` in the motion's floors (None: its only floor)."""
    floors = tuple(motion.floors)
    if floor is None:
        if len(floors) != 1:
            raise ModelError(f"floor is required: the motion holds floors {floors}", "floor")
        return 0
    if isinstance(floor, bool) or floor not in floors:
        raise ModelError(f"floor {floor!r} is not in the motion (it holds floors {floors})",
                         "floor")  # fmt: skip
    return floors.index(floor)


def _new_states(n: int) -> np.ndarray:
    """Blocks at rest, ``(n, NCOL)``."""
    states = np.zeros((n, pk.NCOL))
    states[:, pk.LIMIT_AT] = -1.0
    states[:, pk.T_PEAK] = np.nan
    return states


def _run(motion, row, MU, directions, histories, vert):
    """The blocks' states after the whole motion, read in one pass, for each ``(sx, sy)`` of
    `directions` (1, 1: the plane; 1, 0 or 0, 1: a component alone), and the histories of the
    first; `vert` the vertical samples or None."""
    runs = [_new_states(MU.shape[1]) for _ in directions]
    hist = np.zeros((MU.shape[1], motion.npts, 2) if histories else (0, 0, 2))
    none = np.zeros((0, 0, 2))
    accv = vert if vert is not None else np.zeros(1)
    first = True
    for seg in checked_chunks(motion):
        t0, length, coef = (np.ascontiguousarray(a, dtype=float)
                            for a in (seg.t0, seg.length, seg.coef))  # fmt: skip
        for i, ((sx, sy), states) in enumerate(zip(directions, runs, strict=True)):
            want = histories and i == 0
            plane_segments_kernel(
                t0, length, seg.step, seg.ends, coef, row, sx, sy, first, G, MU, states,
                hist if want else none, want, DEGREE, pk.MAX_EVENTS, accv, vert is not None,
                float(motion.dt),
            )  # fmt: skip
        first = False
    for states in runs:
        hit = np.flatnonzero(states[:, pk.LIMIT_AT] >= 0.0)
        if hit.size:
            i = int(hit[0])
            raise SolverLimitError(
                f"slide_plane_on_segments: more than {pk.MAX_EVENTS} stops and breakaways, or "
                f"{pk.MAX_STEPS} series steps, inside one segment at t = "
                f"{states[i, pk.LIMIT_AT]:.6g} s (mu_k = {MU[1, i]:g}): stick-slip chatter or "
                "creep the solver cannot resolve",
                "mu_k",
            )
    return runs, hist


def slide_plane_on_segments(
    motion,
    floor: int | None = None,
    mu_k=None,
    mu_s=None,
    *,
    vertical=None,
    histories: bool = False,
    compare_1d: bool = True,
) -> PlaneSlideResult:
    """Peak slide, its direction and the residual of rigid blocks sliding in the plane on one
    floor of a poly motion, exact to rounding for the motion's polynomials.

    Parameters
    ----------
    motion
        A poly motion (``dt``, ``npts``, ``floors``, ``notes``, ``poly_chunks()``:
        :mod:`floorslide.building.poly_segments`).
    floor
        The floor the blocks stand on (default: the motion's only floor).
    mu_k, mu_s
        Kinetic and static coefficients (as :func:`~floorslide.slide_plane`; breakaway at
        ``max(mu_s, mu_k)``); many values are advanced in one compiled loop.
    vertical
        Vertical ground acceleration samples (the motion's dt and length), m/s², or a Trace (as
        :func:`~floorslide.slide_plane`): friction ``mu_k·(g + a_v)``, breakaway level
        ``max(mu_s, mu_k)·(g + a_v)``, ``a_v`` linear between samples; where ``g + a_v ≤ 0``
        (lift-off) the block flies free and is reported. The building is rigid vertically.
    histories
        Also return ``u`` at the samples.
    compare_1d
        Also slide under each component alone (the same solver with the other component
        zeroed: along one axis the plane's law is the 1-D one) for ``peak_slide_1d`` and
        ``ratio_2d_1d``, in the same pass over the motion (a producer that integrates a
        building on every pass does it once).

    Returns
    -------
    PlaneSlideResult
        As :func:`~floorslide.slide_plane` (``method="exact"``).

    Raises
    ------
    ModelError
        Invalid friction, floor or vertical; segments that break the contract.
    SolverLimitError
        More than :data:`~floorslide.contents._plane_kernel.MAX_EVENTS` stops and breakaways
        of one block inside one segment.

    References
    ----------
    Jorba, À., Zou, M. (2005). A software package for the numerical integration of ODEs by means
    of high-order Taylor methods. *Experimental Mathematics* 14(1), 99–117.
    """
    if mu_k is None:
        raise ModelError("mu_k (the kinetic friction coefficient or coefficients) is required")
    mk, ms = friction_pairs(mu_k, mu_s)
    row = _floor_row(motion, floor)
    vert, notes = _vertical(vertical, motion)
    MU = np.vstack([np.maximum(mk, ms), mk])
    directions = [(1.0, 1.0), (1.0, 0.0), (0.0, 1.0)] if compare_1d else [(1.0, 1.0)]
    runs, hist = _run(motion, row, MU, directions, histories, vert)
    states = runs[0]
    one_d = np.full((mk.size, 2), np.nan)
    if compare_1d:
        one_d[:, 0] = runs[1][:, pk.PEAK]
        one_d[:, 1] = runs[2][:, pk.PEAK]
    lift_time, lift_count = liftoff(vert, motion.dt) if vert is not None else (0.0, 0)
    big = one_d.max(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(big > 0, states[:, pk.PEAK] / big, np.nan)
    duration = (motion.npts - 1) * motion.dt
    return PlaneSlideResult(
        mu_k=mk,
        mu_s=ms,
        peak_slide=states[:, pk.PEAK].copy(),
        peak_angle=np.degrees(states[:, pk.ANGLE]),
        time_of_peak=states[:, pk.T_PEAK].copy(),
        residual=states[:, [pk.UX, pk.UY]].copy(),
        slide_fraction=states[:, pk.SLIDE_TIME] / duration if duration > 0 else np.zeros(mk.size),
        slip_phases=states[:, pk.SLIPS].astype(int),
        stops=states[:, pk.STOPS].astype(int),
        peak_slide_1d=one_d,
        ratio_2d_1d=ratio,
        path=states[:, pk.PATH].copy(),
        work_floor=states[:, pk.WORK_A].copy(),
        final_velocity=states[:, [pk.VX, pk.VY]].copy(),
        duration=duration,
        u=hist if histories else None,
        notes=tuple(notes),
        work_friction=mk * states[:, pk.NPATH],
        liftoff_time=lift_time,
        liftoff_count=lift_count,
    )
