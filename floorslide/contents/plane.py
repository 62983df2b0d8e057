"""Rigid blocks sliding in the plane under two horizontal components (isotropic Coulomb
friction): the exact-to-rounding solver and its comparison with the 1-D slides.

Conventions (docs/design.md §10d): the plane's frame has ``x`` along the pair's ``h1`` and ``y``
along ``h2``; ``u`` is the block's displacement relative to its floor; while sliding
``u'' = −a(t) − mu_k·N(t)·u'/|u'|``; a block at rest breaks away when
``|a| > max(mu_s, mu_k)·N`` (the magnitude of the floor's horizontal acceleration), ``N = g`` or,
with vertical shaking, ``g + a_v(t)`` (no friction and no sticking where ``N ≤ 0``: lift-off).
Running each component alone and taking the larger slide is not the same: friction couples the
directions (the friction circle).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from floorslide.building.directions import plane_motions
from floorslide.building.plane_isolation import PlaneIsolatedMotion, couples_directions
from floorslide.constants import G
from floorslide.contents import _plane_kernel as pk
from floorslide.contents import plane_approx
from floorslide.contents.sliding import friction_pairs, slide
from floorslide.errors import ModelError, SolverLimitError
from floorslide.inputs import DT_RTOL, as_record, is_stream, is_trace
from floorslide.pair import as_pair

DEGREE = 20
"""Degree of the Taylor series of a slip phase (steps are sized so that its last terms are below
1e-17 of its first: Jorba & Zou 2005)."""

METHODS = ("exact", *plane_approx.METHODS)
"""``method=`` of :func:`slide_plane`: the exact solver and the approximate ones of
:mod:`floorslide.contents.plane_approx`."""


@dataclass(frozen=True)
class PlaneSlideResult:
    """Sliding in the plane, one entry per friction pair (mu_k, mu_s).

    Attributes
    ----------
    mu_k, mu_s
        Kinetic and static friction coefficients.
    peak_slide
        ``max |u|`` found inside steps, m.
    peak_angle
        Direction of the slide at its peak, degrees from ``h1`` towards ``h2``.
    time_of_peak
        When, s.
    residual
        ``u`` at the end of the record, ``(n, 2)``, m.
    slide_fraction
        Fraction of the record spent sliding.
    slip_phases, stops
        Breakaways from rest, and stops.
    peak_slide_1d
        The 1-D slides of each component alone (``(n, 2)``, m; :func:`floorslide.slide`).
    ratio_2d_1d
        ``peak_slide / max(peak_slide_1d)`` (NaN where both 1-D slides are 0).
    path, work_floor
        The path slid ``∫|u'| dt`` (m) and the work of the floor's acceleration ``∫ a·u' dt``
        (m²/s², per unit mass): ``½|u'(end)|² = −mu_k g·path − work_floor`` (energy balance)
        without vertical shaking.
    work_friction
        The work of friction ``mu_k ∫N|u'| dt`` (m²/s², per unit mass; ``N = g``, or ``g + a_v``
        in contact): ``½|u'(end)|² = −work_friction − work_floor``, with or without vertical.
    final_velocity
        ``u'`` at the end, ``(n, 2)``, m/s.
    duration
        Duration of the record, s.
    liftoff_time, liftoff_count
        Total time with ``g + a_v ≤ 0`` (no normal force, s) and the number of such intervals
        (0 without vertical shaking), as :func:`floorslide.slide`.
    u
        ``(n, npts, 2)`` slides at the samples, when requested.
    notes
        What was done to the components (padding).
    method
        How it was computed (``"exact"`` or an approximate method: NaN, or −1 for counts,
        where a method cannot give a field; :mod:`floorslide.contents.plane_approx`).
    """

    mu_k: np.ndarray
    mu_s: np.ndarray
    peak_slide: np.ndarray
    peak_angle: np.ndarray
    time_of_peak: np.ndarray
    residual: np.ndarray
    slide_fraction: np.ndarray
    slip_phases: np.ndarray
    stops: np.ndarray
    peak_slide_1d: np.ndarray
    ratio_2d_1d: np.ndarray
    path: np.ndarray
    work_floor: np.ndarray
    final_velocity: np.ndarray
    duration: float
    u: np.ndarray | None = field(default=None, repr=False)
    notes: tuple[str, ...] = ()
    method: str = "exact"
    work_friction: np.ndarray | None = None
    liftoff_time: float = 0.0
    liftoff_count: int = 0


def _on_nonlinear_isolation(
    pair, building, floor, mk, ms, vert, notes, method, histories, compare_1d
) -> PlaneSlideResult:
    """Blocks on a floor of a building on friction pendulums under the pair: the building's
    exact motion in the plane (:class:`~floorslide.building.plane_isolation.PlaneIsolatedMotion`,
    the vertical scaling its bearings' friction too), read by the plane solver on its segments
    (:func:`~floorslide.contents.plane_segments.slide_plane_on_segments`)."""
    from floorslide.contents.plane_segments import slide_plane_on_segments

    if method != "exact":
        raise ModelError(
            f"method={method!r} is not available on nonlinear isolation in the plane (the "
            "exact solver reads the building's motion)",
            "method",
        )
    motion = PlaneIsolatedMotion(building, pair.h1, pair.h2, pair.dt, vertical=vert)
    res = slide_plane_on_segments(
        motion, 0 if floor is None else floor, mk, ms, vertical=vert, histories=histories,
        compare_1d=compare_1d,
    )  # fmt: skip
    extra = tuple(notes)  # the pair's and the vertical's
    return dataclasses.replace(res, notes=extra + tuple(n for n in res.notes if n not in extra))


def slide_plane(
    acc,
    dt: float | None = None,
    mu_k=None,
    mu_s=None,
    *,
    building=None,
    floor: int | None = None,
    vertical=None,
    histories: bool = False,
    compare_1d: bool = True,
    method: str = "exact",
    substeps: int = 4,
    rtol: float = 1e-6,
    integrator: str = "RK45",
) -> PlaneSlideResult:
    """Peak slide, its direction and the residual of rigid blocks sliding in the plane (isotropic
    Coulomb friction) under two horizontal components.

    Parameters
    ----------
    acc
        A :class:`~floorslide.records.pairs.RecordPair`, ``(a_x, a_y)`` or an array
        ``(2, npts)`` of ground accelerations (m/s²) along ``h1`` and ``h2``.
    dt
        Time step, s (with arrays).
    mu_k, mu_s
        Kinetic and static coefficients (as :func:`~floorslide.slide`); many values are advanced
        in one compiled loop.
    building, floor
        Put the blocks on `floor` of a linear `building`: one model for both directions, or a
        :class:`~floorslide.building.directions.BuildingPair` (a model per direction; uncoupled,
        no torsion). Each direction's floor motion is its exact response to that component.
    vertical
        Vertical ground acceleration samples (same dt and length as the pair), m/s², or a Trace
        (as :func:`~floorslide.slide`; pass ``pair.vertical`` to use a pair's own): friction
        becomes ``mu_k·(g + a_v)`` and the breakaway level ``max(mu_s, mu_k)·(g + a_v)``;
        where ``g + a_v ≤ 0`` (lift-off) the block flies free (``u'' = −a``) and is reported.
        The building is rigid vertically. Exact method only; the 1-D comparison slides use it
        too.
    histories
        Also return ``u`` at the samples.
    compare_1d
        Also slide each component alone (:func:`~floorslide.slide`) for ``ratio_2d_1d``.
    method
        ``"exact"`` (default); approximate (:mod:`floorslide.contents.plane_approx`, for the
        accuracy-versus-cost study): ``"components"`` (each component slid alone by the exact
        1-D solver, the two slides taken as a vector — the common practice, a different model),
        ``"newmark"`` (Moreau–Jean steps of ``dt/substeps`` with the friction as a return
        map), ``"solve_ivp"`` (SciPy's `integrator` at `rtol` with events).
    substeps, rtol, integrator
        Settings of the approximate methods.

    Returns
    -------
    PlaneSlideResult

    Raises
    ------
    ModelError
        Invalid friction, floor or input.
    SolverLimitError
        More than :data:`~floorslide.contents._plane_kernel.MAX_EVENTS` stops and breakaways of
        one block inside one sub-step.

    References
    ----------
    Jorba, À., Zou, M. (2005). A software package for the numerical integration of ODEs by means
    of high-order Taylor methods. *Experimental Mathematics* 14(1), 99–117.
    """
    pair = as_pair(acc, dt)
    if mu_k is None:
        raise ModelError("mu_k (the kinetic friction coefficient or coefficients) is required")
    mk, ms = friction_pairs(mu_k, mu_s)
    if method not in METHODS:
        raise ModelError(f"unknown method {method!r}; expected one of {', '.join(METHODS)}")
    vert, notes = _vertical(vertical, pair)
    if vert is not None and method != "exact":
        raise ModelError(
            f"vertical= is not available with method={method!r} (the exact solver takes it)",
            "vertical",
        )
    if couples_directions(building):
        return _on_nonlinear_isolation(
            pair, building, floor, mk, ms, vert, notes, method, histories, compare_1d
        )
    fm1, fm2 = plane_motions(building, pair.h1, pair.h2, pair.dt, floor, max_bytes=0, copy=False)
    if method != "exact":
        return _approximate(
            pair, mk, ms, building, floor, fm1, fm2, method, histories, compare_1d,
            substeps, rtol, integrator,
        )  # fmt: skip
    MU = np.vstack([np.maximum(mk, ms), mk])
    states = np.zeros((mk.size, pk.NCOL))
    states[:, pk.LIMIT_AT] = -1.0
    states[:, pk.T_PEAK] = np.nan
    npts = pair.npts
    hist = np.zeros((mk.size, npts, 2) if histories else (0, 0, 2))
    for (k0, X1), (_, X2) in zip(fm1.chunks(), fm2.chunks(), strict=True):
        pk.plane_kernel(
            X1, X2, k0, fm1.R, fm1.beta, fm2.R, fm2.beta, pair.h1, pair.h2, fm1.substeps, fm1.h,
            G, MU, states, hist, histories, DEGREE, pk.MAX_EVENTS,
            vert if vert is not None else np.zeros(1), vert is not None,
        )  # fmt: skip
    hit = np.flatnonzero(states[:, pk.LIMIT_AT] >= 0.0)
    if hit.size:
        i = int(hit[0])
        raise SolverLimitError(
            f"slide_plane: more than {pk.MAX_EVENTS} stops and breakaways, or {pk.MAX_STEPS} "
            f"series steps, inside one sub-step at t = {states[i, pk.LIMIT_AT]:.6g} s "
            f"(mu_k = {mk[i]:g}): stick-slip chatter or creep the solver cannot resolve",
            "mu_k",
        )
    one_d = np.full((mk.size, 2), np.nan)
    if compare_1d:
        one_d[:, 0] = slide(fm1, None, mk, ms, vertical=vert).peak_slide
        one_d[:, 1] = slide(fm2, None, mk, ms, vertical=vert).peak_slide
    big = one_d.max(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(big > 0, states[:, pk.PEAK] / big, np.nan)
    lift_time, lift_count = liftoff(vert, pair.dt) if vert is not None else (0.0, 0)
    duration = (npts - 1) * pair.dt
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
        notes=notes,
        work_friction=mk * states[:, pk.NPATH],
        liftoff_time=lift_time,
        liftoff_count=lift_count,
    )


def _vertical(vertical, pair):
    """The vertical samples (or None) and the notes, checked as :func:`floorslide.slide` does."""
    notes = pair.notes
    if vertical is None:
        return None, notes
    dt = pair.dt
    samples = not (is_trace(vertical) or is_stream(vertical))
    vert, vdt, vnotes = as_record(vertical, dt if samples else None, "vertical")
    if not abs(vdt - dt) <= DT_RTOL * dt:
        raise ModelError(f"vertical has dt = {vdt:g} s, the horizontal record {dt:g} s", "vertical")
    if vert.size != pair.npts:
        raise ModelError(
            f"vertical has {vert.size} samples, the horizontal record {pair.npts}", "vertical"
        )
    return np.ascontiguousarray(vert, dtype=float), notes + tuple(vnotes)


def liftoff(vert: np.ndarray, dt: float) -> tuple[float, int]:
    """Total time with ``g + a_v ≤ 0`` (``a_v`` linear between samples) and the number of such
    intervals, as the 1-D kernel counts them (an interval continues across a sample where
    ``N ≤ 0``)."""
    n = G + np.asarray(vert, dtype=float)
    n0, n1 = n[:-1], n[1:]
    lo = np.minimum(n0, n1)
    hi = np.maximum(n0, n1)
    lifted = lo <= 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        part = np.where(hi <= 0.0, 1.0, -lo / (hi - lo))
    time = float(np.sum(np.where(lifted, part, 0.0)) * dt)
    ends_lifted = np.concatenate([[False], lifted & (n1 <= 0.0)])[:-1]
    count = int(np.sum(lifted & ~ends_lifted))
    return time, count


def _approximate(
    pair, mk, ms, building, floor, fm1, fm2, method, histories, compare_1d, substeps, rtol,
    integrator,
) -> PlaneSlideResult:  # fmt: skip
    """:func:`slide_plane` by an approximate method, with the same 1-D comparison."""
    r = plane_approx.approximate(
        method, pair.h1, pair.h2, pair.dt, mk, ms, building, floor, fm1, fm2, G, histories,
        substeps, rtol, integrator,
    )  # fmt: skip
    one_d = r.peak_slide_1d
    if one_d is None:
        one_d = np.full((mk.size, 2), np.nan)
        if compare_1d:
            one_d[:, 0] = slide(fm1, None, mk, ms).peak_slide
            one_d[:, 1] = slide(fm2, None, mk, ms).peak_slide
    big = one_d.max(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(big > 0, r.peak_slide / big, np.nan)
    return PlaneSlideResult(
        mu_k=mk,
        mu_s=ms,
        peak_slide=r.peak_slide,
        peak_angle=r.peak_angle,
        time_of_peak=r.time_of_peak,
        residual=r.residual,
        slide_fraction=r.slide_fraction,
        slip_phases=r.slip_phases,
        stops=r.stops,
        peak_slide_1d=one_d,
        ratio_2d_1d=ratio,
        path=r.path,
        work_floor=r.work_floor,
        final_velocity=r.final_velocity,
        duration=(pair.npts - 1) * pair.dt,
        u=r.u,
        notes=pair.notes,
        method=method,
    )
