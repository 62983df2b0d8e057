"""Rigid blocks sliding with Coulomb friction on a floor: the exact, vectorised solver.

Conventions (docs/design.md §2): ``u`` is the object's displacement relative to its floor; while
sliding ``u'' = −a_f(t) − mu_k·N(t)·sign(u')`` with ``N = g`` (or ``g + a_v(t)`` with vertical
shaking); the object starts or restarts sliding only when ``|a_f| > mu_s·N``. With
``mu_s < mu_k`` a breakaway between ``mu_s·N`` and ``mu_k·N`` cannot move the block (kinetic
friction exceeds the drive at once), so the block effectively starts at ``max(mu_s, mu_k)·N``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from floorslide.building.exact_motion import FloorMotion, single_use_motion, unwrap
from floorslide.building.model import LinearBuilding
from floorslide.constants import MAX_ACCELERATION, G
from floorslide.contents import _kernels as cols
from floorslide.contents._ground_kernel import LIMIT_REACHED, NOT_FINITE, ground_kernel
from floorslide.contents._kernels import slide_kernel
from floorslide.contents.events import SLIDE_MAX_EVENTS, check_event_limit
from floorslide.errors import ModelError
from floorslide.inputs import DT_RTOL, RecordLike, as_record, check_record, is_stream, is_trace

DIRECTIONS = ("both", "positive", "negative")
METHODS = ("exact", "slammer", "newmark", "solve_ivp", "reinterpolated")


@dataclass(frozen=True)
class SlideResult:
    """Sliding of rigid blocks, one entry per friction pair (mu_k, mu_s).

    Attributes
    ----------
    mu_k, mu_s
        Kinetic and static friction coefficients.
    peak_slide
        ``max |u|``, m.
    residual_slide
        ``u`` at the end of the record, m.
    peak_abs_accel
        Peak absolute acceleration of the object, m/s².
    slide_fraction
        Fraction of the record duration spent sliding.
    slip_phases
        Number of slip phases (breakaways and reversals).
    time_of_peak
        Time of the peak slide, s.
    liftoff_time
        Total time with ``g + a_v ≤ 0`` (no normal force), s; 0 without vertical input.
    liftoff_count
        Number of lift-off intervals.
    duration
        Duration of the record, s.
    method, direction
        How it was computed.
    u, v, abs_accel
        Histories at the samples (``(n_mu, npts)``), only when requested.
    notes
        What was done to the input records (e.g. ``acc: data of ... converted from 'g' to
        'm/s**2' (factor 9.80665)`` for an ObsPy Trace in g), one line each; empty for samples
        given in m/s².
    """

    mu_k: np.ndarray
    mu_s: np.ndarray
    peak_slide: np.ndarray
    residual_slide: np.ndarray
    peak_abs_accel: np.ndarray
    slide_fraction: np.ndarray
    slip_phases: np.ndarray
    time_of_peak: np.ndarray
    liftoff_time: float = 0.0
    liftoff_count: int = 0
    duration: float = 0.0
    method: str = "exact"
    direction: str = "both"
    u: np.ndarray | None = field(default=None, repr=False)
    v: np.ndarray | None = field(default=None, repr=False)
    abs_accel: np.ndarray | None = field(default=None, repr=False)
    notes: tuple[str, ...] = ()

    def to_records(self) -> list[dict]:
        """One JSON-ready dict per friction pair (snake_case keys, SI values)."""
        out = []
        for i in range(self.mu_k.size):
            out.append(
                dict(
                    mu_k=float(self.mu_k[i]),
                    mu_s=float(self.mu_s[i]),
                    peak_slide=float(self.peak_slide[i]),
                    residual_slide=float(self.residual_slide[i]),
                    peak_abs_accel=float(self.peak_abs_accel[i]),
                    slide_fraction=float(self.slide_fraction[i]),
                    slip_phases=int(self.slip_phases[i]),
                    time_of_peak=float(self.time_of_peak[i]),
                    liftoff_time=float(self.liftoff_time),
                )
            )
        return out


def friction_pairs(mu_k, mu_s=None) -> tuple[np.ndarray, np.ndarray]:
    """Broadcast kinetic and static coefficients to two equal 1-D arrays (``mu_s`` defaults to
    ``mu_k``); both must be finite and ≥ 0."""
    mk = np.atleast_1d(np.asarray(mu_k, dtype=float)).ravel()
    ms = mk.copy() if mu_s is None else np.atleast_1d(np.asarray(mu_s, dtype=float)).ravel()
    if mk.size == 0:
        raise ModelError("mu_k must hold at least one friction coefficient", "mu_k")
    try:
        mk, ms = np.broadcast_arrays(mk, ms)
    except ValueError:
        raise ModelError(
            f"mu_s ({ms.size} values) must be one value or one per mu_k ({mk.size})", "mu_s"
        ) from None
    for name, arr in (("mu_k", mk), ("mu_s", ms)):
        if not np.all(np.isfinite(arr)) or np.any(arr < 0):
            raise ModelError(f"{name} must be finite and ≥ 0, got {arr.tolist()}", name)
    return np.ascontiguousarray(mk), np.ascontiguousarray(ms)


def _allowed(direction: str) -> tuple[bool, bool]:
    if direction not in DIRECTIONS:
        raise ModelError(
            f"direction must be one of {', '.join(DIRECTIONS)}, got {direction!r}", "direction"
        )
    # "positive": positive floor accelerations drive the block (Newmark's slope convention),
    # i.e. only slip with negative relative velocity; "negative" the mirror image.
    return direction in ("both", "negative"), direction in ("both", "positive")


def slide(
    acc: RecordLike | FloorMotion,
    dt: float | None = None,
    mu_k=None,
    mu_s=None,
    *,
    building: LinearBuilding | None = None,
    floor: int | None = None,
    vertical: RecordLike | None = None,
    direction: str = "both",
    method: str = "exact",
    histories: bool = False,
    substeps: int = 4,
    rtol: float = 1e-8,
    integrator: str = "DOP853",
    max_step: float | None = None,
) -> SlideResult:
    """Peak and residual sliding of rigid blocks (Coulomb friction) on a floor.

    Parameters
    ----------
    acc
        Ground acceleration samples, m/s² (with `building`), or the motion the object stands
        on (without), taken as piecewise linear. Or an ObsPy Trace or one-trace Stream: dt from
        ``stats.delta``, units from ``stats.units`` (converted to m/s² with a
        :class:`~floorslide.errors.UnitsConversionWarning` and a line in ``notes``; a trace
        without units or in unknown units is refused — see :mod:`floorslide.inputs`).
        Or a :class:`~floorslide.FloorMotion` (:func:`~floorslide.floor_motion`): the floor's
        exact motion integrated once, for many calls on one floor (then no `building` or
        `floor` here).
    dt
        Time step, s; required for samples, optional for a Trace (must equal
        ``stats.delta``) or a FloorMotion.
    mu_k
        Kinetic friction coefficient(s), required; many values are advanced in one compiled
        loop.
    mu_s
        Static coefficient(s) (default ``mu_k``); any positive pair, either order.
    building, floor
        Put the objects on `floor` of `building`: the floor motion is the building's exact
        response to the piecewise-linear ground record (floor 0 of a fixed-base building is the
        ground itself).
    vertical
        Vertical ground acceleration samples (same dt and length), m/s², or a Trace (converted
        like `acc`; its ``stats.delta`` must equal the horizontal's dt): the friction limit
        becomes ``mu·(g + a_v)``; lift-off (``g + a_v ≤ 0``) is reported. The building is rigid
        vertically.
    direction
        ``"both"`` (default); ``"positive"``: one-way sliding driven by positive floor
        accelerations above ``mu·g`` (Newmark 1965 slope convention, as in SLAMMER — the
        relative displacement is then ≤ 0 and its magnitude is Newmark's displacement);
        ``"negative"``: the mirror image.
    method
        ``"exact"`` (event-driven, exact for the piecewise-linear ground record); approximate:
        ``"slammer"`` (Jibson 1993 per-sample trapezoid on sampled floor motion),
        ``"newmark"`` (average acceleration with stick/slip checks at ``dt/substeps``),
        ``"solve_ivp"`` (SciPy `integrator` with events at `rtol`), ``"reinterpolated"``
        (exact solver on floor samples re-interpolated linearly).
    histories
        Also return ``u``, ``v`` and the object's absolute acceleration at the samples.
    substeps, rtol, integrator, max_step
        Settings of the approximate methods (``max_step`` limits solve_ivp's steps: without it,
        threshold excursions shorter than one of its steps go unnoticed).

    Returns
    -------
    SlideResult

    Raises
    ------
    ModelError
        Invalid parameters (``mu_k`` missing or negative, a floor without a building, ...).
    RecordError, UnitsError
        A Trace or Stream that cannot be used as is (see :mod:`floorslide.inputs`).

    References
    ----------
    Newmark, N. M. (1965). Effects of earthquakes on dams and embankments. *Géotechnique* 15(2).
    Westermo, B., Udwadia, F. (1983). Periodic response of a sliding oscillator system to harmonic
    excitation. *Earthquake Eng. Struct. Dyn.* 11, 135–146.
    Shenton, H. W. (1996). Criteria for initiation of slide, rock, and slide-rock rigid-body modes.
    *J. Eng. Mech.* 122(7), 690–693.
    Jibson, R. W. (1993). Predicting earthquake-induced landslide displacements using Newmark's
    sliding block analysis. *Transportation Research Record* 1411, 9–17.
    """
    if building is None and floor is None and vertical is None and method == "exact":
        # the ground: plain inputs are checked cheaply here and solved by the ground's kernel
        result = _ground_fast(acc, dt, mu_k, mu_s, direction, histories)
        if result is not None:
            return result
    fm, a, dt, notes = unwrap(acc, dt, building, floor)
    if getattr(fm, "segmented", False) or getattr(building, "segmented", False):
        # a floor of a building on nonlinear isolation: its segments, integrated once
        return _slide_segmented(fm, a, dt, notes, building, floor, mu_k, mu_s, vertical, method,
                                direction, histories)  # fmt: skip
    if fm is not None:
        building, floor = fm.building, fm.floor
    if mu_k is None:
        raise ModelError("mu_k (the kinetic friction coefficient or coefficients) is required")
    mk, ms = friction_pairs(mu_k, mu_s)
    _allow_pos, _allow_neg = _allowed(direction)
    if method not in METHODS:
        raise ModelError(f"unknown method {method!r}; expected one of {', '.join(METHODS)}")
    if building is None and floor not in (None, 0):
        raise ModelError("floor= needs building=", "floor")
    if building is not None and floor is None:
        raise ModelError("floor is required with building=", "floor")
    vert = None
    if vertical is not None:
        vert, vnotes = _vertical_samples(vertical, dt, a.size)
        notes += vnotes
    if method != "exact":
        from floorslide.contents import approximate

        result = approximate.slide(
            a,
            dt,
            mk,
            ms,
            building,
            floor,
            vert,
            direction,
            method,
            histories,
            substeps,
            rtol,
            integrator,
            max_step,
        )
    elif fm is None and building is None and vert is None:
        # the ground (floor None or 0, checked above): no motion to build
        result = _slide_ground(a, dt, _friction_rows(mk, ms), direction, histories)
    else:
        if fm is None:
            fm = single_use_motion(building, a, dt, floor)
        result = _slide_exact(fm, mk, ms, vert, direction, histories)
    return replace(result, notes=notes) if notes else result


_ALLOWED = {d: _allowed(d) for d in DIRECTIONS}


def _ground_fast(acc, dt, mu_k, mu_s, direction, histories) -> SlideResult | None:
    """:func:`slide` on the ground without vertical shaking, exact, for plain inputs: samples
    as a 1-D C-ordered float64 array, a float `dt`, friction as numbers or arrays, a known
    `direction`. Checked here at a few attribute reads each (the samples' finiteness by the
    kernel, as it reads them); None when an input is not plain or not valid — then
    :func:`slide`'s full path checks everything in its order (the same errors as ever) and
    solves it."""
    if not (
        type(acc) is np.ndarray
        and acc.ndim == 1
        and acc.dtype == np.float64
        and acc.size > 0
        and acc.flags.c_contiguous
        and isinstance(dt, float | int)
        and 0.0 < dt < np.inf
        and direction in DIRECTIONS
    ):
        return None
    if isinstance(mu_k, float | int) and (mu_s is None or isinstance(mu_s, float | int)):
        k = float(mu_k)
        s = k if mu_s is None else float(mu_s)
        if not (0.0 <= k < np.inf and 0.0 <= s < np.inf):
            return None
        # breakaway, kinetic, static (the breakaway as np.maximum picks it)
        MU = np.array([k if k >= s else s, k, s]).reshape(3, 1)
    elif mu_k is None:
        return None
    else:
        try:
            mk, ms = friction_pairs(mu_k, mu_s)
        except ModelError:
            return None
        MU = _friction_rows(mk, ms)
    return _slide_ground(acc, float(dt), MU, direction, histories)


def _slide_exact(
    fm: FloorMotion, mk, ms, vert, direction, histories, general: bool = False
) -> SlideResult:
    """The exact solver on a floor motion: the ground's own kernel on the ground without
    vertical shaking (:func:`_slide_ground`), else the general kernel (always, with
    ``general=True``: the reference of the ground's kernel in the tests)."""
    if fm.ground and vert is None and not general:
        return _slide_ground(fm.acc, fm.dt, _friction_rows(mk, ms), direction, histories)
    allow_pos, allow_neg = _allowed(direction)
    a, dt = fm.acc, fm.dt
    nobj = mk.size
    states = np.zeros((nobj, cols.NCOL))
    states[:, cols.LIMIT_AT] = -1.0
    npts = a.size
    shape = (nobj, npts) if histories else (0, 0)
    hu, hv, ha = np.zeros(shape), np.zeros(shape), np.zeros(shape)
    lift = np.zeros(3)
    mub = np.maximum(mk, ms)
    for k0, X in fm.chunks():
        slide_kernel(
            X,
            k0,
            fm.R,
            fm.beta,
            fm.rv,
            fm.rd,
            a,
            vert if vert is not None else np.zeros(1),
            vert is not None,
            fm.substeps,
            fm.h,
            G,
            mub,
            mk,
            allow_pos,
            allow_neg,
            states,
            hu,
            hv,
            ha,
            histories,
            lift,
            SLIDE_MAX_EVENTS,
        )
    return _result(states, mk, ms, a.size, dt, direction, lift, hu, hv, ha, histories)


def _slide_ground(a, dt, MU, direction, histories) -> SlideResult:
    """Rigid blocks on the ground without vertical shaking: the ground's kernel
    (:func:`floorslide.contents._ground_kernel.ground_kernel`), the general kernel's results
    bit for bit at a fraction of its cost. `a`: samples (float64, C-ordered; NaN or infinite
    ones raise here); `MU`: the ``(3, n_obj)`` rows breakaway, kinetic and static friction
    (:func:`_friction_rows`)."""
    allow_pos, allow_neg = _ALLOWED[direction]
    nobj = MU.shape[1]
    npts = a.size
    states = np.empty((nobj, cols.NCOL))
    hist = np.empty((3, nobj, npts) if histories else (3, 0, 0))
    P = np.array(
        [dt, G, allow_pos, allow_neg, SLIDE_MAX_EVENTS, bool(histories), MAX_ACCELERATION],
        dtype=float,
    )
    code = ground_kernel(a, MU, P, states, hist)
    if code == NOT_FINITE:
        check_record(a, dt)  # raises: NaN or infinite samples, or beyond MAX_ACCELERATION
        raise ModelError("acc has NaN or infinite samples", "acc")
    hu, hv, ha = hist if histories else (None, None, None)
    return _result(
        states,
        MU[1],
        MU[2],
        npts,
        dt,
        direction,
        None,
        hu,
        hv,
        ha,
        histories,
        code == LIMIT_REACHED,
    )


def _friction_rows(mk, ms) -> np.ndarray:
    """The ``(3, n)`` rows breakaway ``max(mu_s, mu_k)``, kinetic and static friction of the
    ground's kernel, from :func:`friction_pairs`' arrays."""
    MU = np.empty((3, mk.size))
    np.maximum(mk, ms, out=MU[0])
    MU[1] = mk
    MU[2] = ms
    return MU


def _result(
    states, mk, ms, npts, dt, direction, lift, hu, hv, ha, histories, limit=True
) -> SlideResult:
    """The :class:`SlideResult` of the kernels' final states (and lift-off record ``lift``,
    None without vertical shaking); raises if an object reached the event limit (checked when
    `limit`: a kernel that says none was reached spares the look)."""
    if limit:
        check_event_limit(states[:, cols.LIMIT_AT], mk, SLIDE_MAX_EVENTS, "slide")
    nobj = mk.size
    duration = (npts - 1) * dt
    columns = states.T.copy()  # one copy: each result field is a row of it
    return SlideResult(
        mu_k=mk,
        mu_s=ms,
        peak_slide=columns[cols.PEAK_DISP],
        residual_slide=columns[cols.DISP],
        peak_abs_accel=columns[cols.PEAK_ACC],
        slide_fraction=columns[cols.SLIDE_TIME] / duration if duration > 0 else np.zeros(nobj),
        slip_phases=columns[cols.SLIPS].astype(int),
        time_of_peak=columns[cols.T_PEAK],
        liftoff_time=0.0 if lift is None else float(lift[0]),
        liftoff_count=0 if lift is None else int(lift[1]),
        duration=duration,
        method="exact",
        direction=direction,
        u=hu if histories else None,
        v=hv if histories else None,
        abs_accel=ha if histories else None,
    )


def _vertical_samples(vertical, dt: float, npts: int):
    """The vertical record's samples and notes, checked against the horizontal one (its dt and
    length)."""
    samples = not (is_trace(vertical) or is_stream(vertical))
    vert, vdt, vnotes = as_record(vertical, dt if samples else None, "vertical")
    if not abs(vdt - dt) <= DT_RTOL * dt:
        raise ModelError(f"vertical has dt = {vdt:g} s, the horizontal record {dt:g} s", "vertical")
    if vert.size != npts:
        raise ModelError(
            f"vertical has {vert.size} samples, the horizontal record {npts}", "vertical"
        )
    return np.ascontiguousarray(vert, dtype=float), vnotes


def _slide_on_pendulums_vertical(building, a, dt, notes, floor, mk, ms, vert, direction,
                                 histories) -> SlideResult:  # fmt: skip
    """:func:`slide` with vertical shaking on a floor of a building on friction pendulums: the
    bearing's friction and restoring force scale with ``g + a_v`` (docs/design.md §10b), which
    the coupled plane integrator carries (:class:`~floorslide.building.plane_isolation.
    PlaneIsolatedMotion` under the record and a still second component); the blocks slide on
    its segments (:func:`~floorslide.contents.plane_segments.slide_plane_on_segments`), which
    along one axis is the 1-D law exactly. The blocks' peak absolute acceleration is not
    tracked there (NaN, said in the notes)."""
    from floorslide.building.plane_isolation import PlaneIsolatedMotion
    from floorslide.contents.plane_segments import slide_plane_on_segments

    if direction != "both":
        raise ModelError(
            "one-way sliding with vertical shaking on friction pendulums is not available (the "
            "bearing's vertical response is integrated by the plane solver, whose blocks slide "
            "both ways)",
            "direction",
        )
    motion = PlaneIsolatedMotion(building, a, np.zeros_like(a), dt, vertical=vert)
    r = slide_plane_on_segments(motion, floor, mk, ms, vertical=vert, histories=histories,
                                compare_1d=False)  # fmt: skip
    extra = (
        "vertical shaking on friction pendulums: the bearing's friction and restoring force "
        "scale with g + a_v (the coupled plane solver, second component still); "
        "peak_abs_accel is not tracked there (NaN)",
    )
    return SlideResult(
        mu_k=mk,
        mu_s=ms,
        peak_slide=r.peak_slide,
        residual_slide=r.residual[:, 0].copy(),
        peak_abs_accel=np.full(mk.size, np.nan),
        slide_fraction=r.slide_fraction,
        # breakaways and reversals, as 1-D counts them: each stop of the plane solver is
        # followed by one or the other, and a block still sliding at the end had one more
        slip_phases=(r.stops + (np.abs(r.final_velocity[:, 0]) > 0.0)).astype(int),
        time_of_peak=r.time_of_peak,
        liftoff_time=r.liftoff_time,
        liftoff_count=r.liftoff_count,
        duration=r.duration,
        method="exact",
        direction=direction,
        u=r.u[:, :, 0].copy() if histories else None,
        notes=tuple(notes) + tuple(motion.notes) + extra,
    )


def _slide_segmented(fm, a, dt, notes, building, floor, mu_k, mu_s, vertical, method, direction,
                     histories):  # fmt: skip
    """:func:`slide` on a floor of a building on nonlinear isolation (a segmented motion);
    with vertical shaking, on lead-rubber the blocks' friction scales with ``g + a_v`` on the
    building's segments, on friction pendulums the bearing's too
    (:func:`_slide_on_pendulums_vertical`)."""
    from floorslide.building.isolators import FrictionPendulum
    from floorslide.contents.segmented import slide_on_segments

    if mu_k is None:
        raise ModelError("mu_k (the kinetic friction coefficient or coefficients) is required")
    if method != "exact":
        raise ModelError(
            f"method={method!r} is not available on a building on nonlinear isolation (the "
            "exact method is)",
            "method",
        )
    mk, ms = friction_pairs(mu_k, mu_s)
    _allowed(direction)
    vert = None
    if vertical is not None:
        vert, vnotes = _vertical_samples(vertical, dt, a.size)
        notes = tuple(notes) + tuple(vnotes)
        if isinstance((building if fm is None else fm.building).isolator, FrictionPendulum):
            if fm is not None:
                raise ModelError(
                    "this floor motion of a building on friction pendulums was integrated "
                    "without the vertical, which scales its bearing's friction and restoring "
                    "force: give the record with building= and floor= instead",
                    "vertical",
                )
            if floor is None:
                raise ModelError("floor is required with building=", "floor")
            return _slide_on_pendulums_vertical(building, a, dt, notes, int(floor), mk, ms,
                                                vert, direction, histories)  # fmt: skip
    if fm is None:
        if floor is None:
            raise ModelError("floor is required with building=", "floor")
        fm = building.motion(a, dt, floors=[floor]).floor(floor)
    return slide_on_segments(fm, mk, ms, direction, histories, notes, vertical=vert)
