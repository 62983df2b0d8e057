"""Rigid blocks rocking on a floor: impacts, overturning, the exact solver (Housner 1963).

Conventions (docs/design.md §10c): a block of base width ``B`` and height ``H`` (centre of mass at
mid-height) has ``R = ½√(B² + H²)``, slenderness ``α = atan(B/H)`` and frequency parameter
``p = √(3g/(4R))``. ``θ > 0`` is rotation about the corner that a *negative* floor acceleration
lifts onto: at rest the block uplifts at the first instant ``a_f < −g tan α`` (``θ > 0``) or
``a_f > g tan α`` (``θ < 0``). Rocking, ``θ'' = p²(θ − α sgn θ) − p² a_f/g`` (linearised,
``method="exact"``) or ``θ'' = −p² [sin(α sgn θ − θ) + (a_f/g) cos(α sgn θ − θ)]``
(``method="nonlinear"``); at each impact (``θ`` back to 0) the angular velocity is multiplied by
the restitution ``r`` (default Housner's ``1 − 1.5 sin²α``); the block overturns when ``|θ|``
reaches ``α``. Friction is assumed to hold the corner (no sliding: the Shenton check in
:mod:`floorslide.contents.rocking` says when that is so).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from floorslide.building.exact import taylor_degree
from floorslide.building.exact_motion import FloorMotion, single_use_motion, unwrap
from floorslide.building.model import LinearBuilding
from floorslide.constants import G
from floorslide.contents import _rocking_kernel as rk
from floorslide.errors import ModelError, SolverLimitError
from floorslide.inputs import RecordLike

ROCK_METHODS = ("exact", "nonlinear", "rk4", "solve_ivp")
APPROXIMATE = ("rk4", "solve_ivp")


@dataclass(frozen=True)
class RockResult:
    """Rocking of rigid blocks, one entry per block.

    Attributes
    ----------
    width, height
        Base width and height, m.
    alpha, p, restitution
        Slenderness ``atan(B/H)`` (rad), frequency parameter ``√(3g/(4R))`` (rad/s) and the
        restitution used.
    peak_ratio
        ``max|θ|/α`` found inside steps (1 for a block that overturned).
    peak_time
        Time of the peak, s (NaN when the block never uplifted).
    impacts
        Impacts (``θ`` back to 0 while rocking), the whole cascade of ever smaller impacts to
        rest included (up to ``log(10⁻¹²)/log r`` after each excitation).
    significant_impacts
        Impacts at ``|θ'| ≥ p·α·√(f(2 − f))``, ``f = 0.01``: those ending an excursion to at
        least 1 % of α in free rocking
        (:data:`~floorslide.contents._rocking_kernel.SIGNIFICANT_TILT`); None for the
        approximate methods.
    uplifts
        Uplifts from rest.
    rocking_time
        Time spent rocking, s.
    overturned
        Whether ``|θ|`` reached ``α``.
    overturn_time
        When it did, s (NaN otherwise).
    mode
        What the block did: ``"rest"`` (never uplifted), ``"rock"`` or ``"overturn"``.
    duration
        Duration of the record, s.
    method
        ``"exact"`` (linearised equation) or ``"nonlinear"`` (full equation).
    theta
        ``θ`` at the samples (``(n_blocks, npts)``, rad; NaN once overturned), when requested.
    notes
        What was done to the input record.
    """

    width: np.ndarray
    height: np.ndarray
    alpha: np.ndarray
    p: np.ndarray
    restitution: np.ndarray
    peak_ratio: np.ndarray
    peak_time: np.ndarray
    impacts: np.ndarray
    uplifts: np.ndarray
    rocking_time: np.ndarray
    overturned: np.ndarray
    overturn_time: np.ndarray
    mode: tuple[str, ...]
    duration: float
    method: str
    theta: np.ndarray | None = field(default=None, repr=False)
    notes: tuple[str, ...] = ()
    significant_impacts: np.ndarray | None = None

    def to_records(self) -> list[dict]:
        """One JSON-ready dict per block (snake_case keys, SI values)."""
        return [
            dict(
                width=float(self.width[i]),
                height=float(self.height[i]),
                alpha=float(self.alpha[i]),
                p=float(self.p[i]),
                restitution=float(self.restitution[i]),
                peak_ratio=float(self.peak_ratio[i]),
                peak_time=float(self.peak_time[i]),
                impacts=int(self.impacts[i]),
                significant_impacts=None
                if self.significant_impacts is None
                else int(self.significant_impacts[i]),
                uplifts=int(self.uplifts[i]),
                rocking_time=float(self.rocking_time[i]),
                overturned=bool(self.overturned[i]),
                overturn_time=float(self.overturn_time[i]),
                mode=self.mode[i],
            )
            for i in range(self.width.size)
        ]


def block_geometry(width, height, restitution=None, g: float = G):
    """``(B, H, α, p, r)`` of blocks, broadcast to equal 1-D arrays: ``α = atan(B/H)``,
    ``p = √(3g/(4R))`` with ``R = ½√(B² + H²)``, ``r`` given or Housner's ``1 − 1.5 sin²α``
    (Housner 1963, eq. 17)."""
    if width is None or height is None:
        raise ModelError("width and height (m) are required to rock a block", "width")
    B = np.atleast_1d(np.asarray(width, dtype=float)).ravel()
    H = np.atleast_1d(np.asarray(height, dtype=float)).ravel()
    r_in = np.atleast_1d(
        np.asarray(np.nan if restitution is None else restitution, dtype=float)
    ).ravel()
    try:
        B, H, r_in = np.broadcast_arrays(B, H, r_in)
    except ValueError:
        raise ModelError(
            f"width ({B.size}), height ({H.size}) and restitution ({r_in.size}) must be one "
            "value or one per block",
            "width",
        ) from None
    for name, arr in (("width", B), ("height", H)):
        if arr.size == 0 or not np.all(np.isfinite(arr)) or np.any(arr <= 0):
            raise ModelError(f"{name} must be finite and > 0 m, got {arr.tolist()}", name)
    alpha = np.arctan2(B, H)
    R = 0.5 * np.hypot(B, H)
    p = np.sqrt(3.0 * g / (4.0 * R))
    if restitution is None:
        r = 1.0 - 1.5 * np.sin(alpha) ** 2
    else:
        r = r_in.astype(float)
        if not np.all((r >= 0.0) & (r <= 1.0)):
            raise ModelError(f"restitution must be in [0, 1], got {r.tolist()}", "restitution")
    if np.any(r < 0.0):
        raise ModelError(
            "Housner's restitution 1 − 1.5 sin²α is negative for blocks with B/H > "
            f"{np.tan(np.arcsin(np.sqrt(2.0 / 3.0))):.3f} (a squat block does not rock this "
            "way): give restitution",
            "restitution",
        )
    return (
        np.ascontiguousarray(B, dtype=float),
        np.ascontiguousarray(H, dtype=float),
        alpha,
        p,
        np.ascontiguousarray(r, dtype=float),
    )


def rock(
    acc: RecordLike | FloorMotion,
    dt: float | None = None,
    width=None,
    height=None,
    *,
    restitution=None,
    building: LinearBuilding | None = None,
    floor: int | None = None,
    method: str = "exact",
    histories: bool = False,
    initial_angle=None,
    substeps: int = 4,
    rtol: float = 1e-6,
    integrator: str = "RK45",
) -> RockResult:
    """Rocking, impacts and overturning of rigid blocks on a floor (friction holds the corner).

    Parameters
    ----------
    acc
        Ground acceleration samples, m/s² (with `building`), or the motion the blocks stand on
        (without), piecewise linear; an ObsPy Trace; a :class:`~floorslide.FloorMotion`; or a
        :class:`~floorslide.building.poly_peaks.PolyComponent` (one floor of a poly motion
        along one component — a building on friction pendulums under a pair: the block's
        faces along that component; exact methods only).
    dt
        Time step, s (as for :func:`~floorslide.slide`).
    width, height
        Base width and height of each block, m (one value or one per block; many blocks are
        advanced in one compiled loop).
    restitution
        Ratio of angular velocities after/before an impact, in [0, 1] (default Housner's
        ``1 − 1.5 sin²α``, which needs ``B/H < 1.41``).
    building, floor
        Put the blocks on `floor` of `building`: fixed-base, linearly isolated, or on nonlinear
        isolation (:class:`~floorslide.NonlinearIsolatedBuilding`: the blocks ride along in its
        event-driven integration, exact end to end).
    method
        ``"exact"``: the linearised (slender-block) equation, exact for the piecewise-linear
        record; ``"nonlinear"``: the full equation, its Taylor series exact to rounding.
        Approximate, for comparison (the full equation, on the floor's samples re-interpolated
        linearly; :mod:`floorslide.contents.rocking_approx`): ``"rk4"`` (fixed steps of
        ``dt/substeps``, events by linear interpolation) and ``"solve_ivp"`` (SciPy
        `integrator` at `rtol`, ``max_step = dt``, events located); no histories.
    histories
        Also return ``θ`` at the samples.
    initial_angle
        ``θ`` at t = 0, rad (one value or one per block, ``|θ0| < α``; the block at rest there,
        ``θ' = 0``): free-rocking checks. Default 0 (upright, at rest).
    substeps, rtol, integrator
        Settings of the approximate methods.

    Returns
    -------
    RockResult

    Raises
    ------
    ModelError
        Invalid geometry, restitution, method or floor.
    SolverLimitError
        More than :data:`~floorslide.contents._rocking_kernel.ROCK_MAX_EVENTS` events of one
        block inside one sub-step.

    References
    ----------
    Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes.
    *Bull. Seismol. Soc. Am.* 53(2), 403–417.
    Makris, N., Roussos, Y. S. (2000). Rocking response of rigid blocks under near-source ground
    motions. *Géotechnique* 50(3), 243–262.
    """
    if method not in ROCK_METHODS:
        raise ModelError(
            f"unknown method {method!r}; expected one of {', '.join(ROCK_METHODS)}", "method"
        )
    from floorslide.building.poly_peaks import PolyComponent

    poly = acc if isinstance(acc, PolyComponent) else None
    if poly is not None:
        if building is not None or floor is not None:
            raise ModelError(
                "acc is a PolyComponent (one floor along one component): give no building= "
                "or floor=",
                "building",
            )
        if dt is not None and not np.isclose(float(dt), poly.dt, rtol=1e-9, atol=0.0):
            raise ModelError(f"dt={dt} differs from the PolyComponent's dt={poly.dt}", "dt")
        if method in APPROXIMATE:
            raise ModelError(
                f"method={method!r} reads samples; a PolyComponent is rocked by 'exact' or "
                "'nonlinear' (its polynomial segments)",
                "method",
            )
        fm, a, dt, notes = None, None, poly.dt, tuple(getattr(poly.motion, "notes", ()))
    else:
        fm, a, dt, notes = unwrap(acc, dt, building, floor)
    if fm is not None:
        building, floor = fm.building, fm.floor
    # a floor of a building on nonlinear isolation: its segments, integrated once
    on_isolation = getattr(building, "segmented", False)
    if building is None and floor not in (None, 0):
        raise ModelError("floor= needs building=", "floor")
    if building is not None and floor is None:
        raise ModelError("floor is required with building=", "floor")
    B, H, alpha, p, r = block_geometry(width, height, restitution)
    if method in APPROXIMATE:
        return _approximate(acc, dt, building, floor, B, H, alpha, p, r, method, substeps, rtol,
                            integrator, histories, initial_angle)  # fmt: skip
    nonlinear = method == "nonlinear"
    phase_max = rk.NONLINEAR_PHASE if nonlinear else rk.LINEAR_PHASE
    par = np.empty((B.size, rk.NPAR))
    par[:, rk.P_ALPHA] = alpha
    par[:, rk.P_P] = p
    par[:, rk.P_R] = r
    par[:, rk.P_TAN] = B / H
    par[:, rk.P_PARTS] = 1
    if on_isolation:
        if fm is None:
            fm = building.motion(a, dt, floors=[floor]).floor(floor)
    elif poly is None:
        if fm is None:
            fm = single_use_motion(building, a, dt, floor)
        parts = np.maximum(1, np.ceil(p * fm.h / phase_max - 1e-12)).astype(int)
        phase = float(np.max(p * fm.h / parts))
        D = max(fm.order + 2, taylor_degree(2.0 * phase if nonlinear else phase))
        par[:, rk.P_PARTS] = parts
    states = np.zeros((B.size, rk.NCOL))
    states[:, rk.T_OVER] = -1.0
    states[:, rk.LIMIT_AT] = -1.0
    states[:, rk.T_PEAK] = np.nan
    if initial_angle is not None:
        th0 = np.broadcast_to(np.asarray(initial_angle, dtype=float).ravel(), B.shape)
        if not np.all(np.isfinite(th0)) or np.any(np.abs(th0) >= alpha):
            raise ModelError(
                f"initial_angle must be finite with |θ0| < α = {alpha.tolist()} rad, got "
                f"{th0.tolist()}",
                "initial_angle",
            )
        states[:, rk.TH] = th0
        states[:, rk.MODE] = np.sign(th0)
        states[:, rk.PEAK] = np.abs(th0) / alpha
        states[:, rk.T_PEAK] = np.where(th0 != 0.0, 0.0, np.nan)
    npts = poly.npts if poly is not None else a.size
    if poly is not None:
        hist = _rock_on_poly(poly, par, states, nonlinear, histories)
    elif on_isolation:
        from floorslide.contents.segmented import rockers_on_segments

        hist = rockers_on_segments(fm, par, states, nonlinear, histories)
    else:
        hist = np.zeros((B.size, npts) if histories else (0, 0))
        for k0, X in fm.chunks():
            rk.rock_kernel(
                X,
                k0,
                fm.R,
                fm.beta,
                a,
                fm.substeps,
                fm.h,
                G,
                par,
                states,
                hist,
                histories,
                nonlinear,
                D,
                rk.ROCK_MAX_EVENTS,
            )
    hit = np.flatnonzero(states[:, rk.LIMIT_AT] >= 0.0)
    if hit.size:
        i = int(hit[0])
        raise SolverLimitError(
            f"rock: more than {rk.ROCK_MAX_EVENTS} impacts or uplifts inside one sub-step at "
            f"t = {states[i, rk.LIMIT_AT]:.6g} s (block {B[i]:g} × {H[i]:g} m): an impact "
            "cascade the exact solver cannot resolve",
            "width",
        )
    over = states[:, rk.MODE] == rk.OVERTURNED
    mode = tuple(
        "overturn"
        if over[i]
        else ("rock" if states[i, rk.UPLIFTS] > 0 or states[i, rk.ROCK_TIME] > 0 else "rest")
        for i in range(B.size)
    )
    result = RockResult(
        width=B,
        height=H,
        alpha=alpha,
        p=p,
        restitution=r,
        peak_ratio=states[:, rk.PEAK].copy(),
        peak_time=states[:, rk.T_PEAK].copy(),
        impacts=states[:, rk.IMPACTS].astype(int),
        significant_impacts=states[:, rk.SIGNIFICANT].astype(int),
        uplifts=states[:, rk.UPLIFTS].astype(int),
        rocking_time=states[:, rk.ROCK_TIME].copy(),
        overturned=over,
        overturn_time=np.where(over, states[:, rk.T_OVER], np.nan),
        mode=mode,
        duration=(npts - 1) * dt,
        method=method,
        theta=hist if histories else None,
    )
    return replace(result, notes=notes) if notes else result


def _rock_on_poly(poly, par, states, nonlinear, histories):
    """Rocking blocks on one floor of a poly motion along one component (its segments'
    polynomials, :func:`~floorslide.contents._segment_kernels.rockers_on_poly`); ``θ`` at the
    samples with `histories`."""
    from floorslide.building.poly_segments import DEGREE, checked_chunks
    from floorslide.contents import _segment_kernels as sk

    K = DEGREE - 1
    phase = rk.NONLINEAR_PHASE if nonlinear else rk.LINEAR_PHASE
    D = max(K + 2, taylor_degree(phase * (2.0 if nonlinear else 1.0)))
    hist = np.zeros((par.shape[0], poly.npts) if histories else (0, 0))
    if histories:
        hist[:, 0] = states[:, rk.TH]
    RB = sk.rocker_workspace(K, D)
    row, d = poly.row, poly.direction
    for seg in checked_chunks(poly.motion):
        C = np.ascontiguousarray(seg.coef[:, row, d])
        sk.rockers_on_poly(seg.t0, seg.length, seg.step, seg.ends, C, par, states, G, D,
                           nonlinear, phase, rk.ROCK_MAX_EVENTS, RB, hist)  # fmt: skip
    return hist


def _approximate(acc, dt, building, floor, B, H, alpha, p, r, method, substeps, rtol, integrator,
                 histories, initial_angle) -> RockResult:  # fmt: skip
    """:func:`rock` by an approximate method on the floor's samples."""
    from floorslide.building.exact_motion import floor_motion
    from floorslide.building.nonlinear_motion import NonlinearFloorMotion
    from floorslide.contents import rocking_approx as ra

    if histories or initial_angle is not None:
        raise ModelError(
            f"method={method!r} gives peaks only (no histories, no initial angle)", "method"
        )
    if isinstance(acc, FloorMotion | NonlinearFloorMotion):
        af, dt, notes = acc.samples(), acc.dt, acc.notes
    elif getattr(building, "segmented", False):
        fm = building.motion(acc, dt, floors=[floor]).floor(floor)
        af, dt, notes = fm.samples(), fm.dt, fm.notes
    else:
        fm = floor_motion(building, acc, 0 if building is None else floor, dt)
        af, dt, notes = fm.samples(), fm.dt, fm.notes
    tan_a = B / H
    if method == "rk4":
        out = ra.rk4(af, dt, alpha, p, r, tan_a, G, True, substeps)
    else:
        out = ra.solve_ivp_blocks(af, dt, alpha, p, r, tan_a, G, True, rtol, integrator)
    over = out[:, 4] > 0
    return RockResult(
        width=B,
        height=H,
        alpha=alpha,
        p=p,
        restitution=r,
        peak_ratio=out[:, 0].copy(),
        peak_time=np.full(B.size, np.nan),
        impacts=out[:, 1].astype(int),
        uplifts=out[:, 2].astype(int),
        rocking_time=out[:, 3].copy(),
        overturned=over,
        overturn_time=np.where(over, out[:, 5], np.nan),
        mode=tuple(
            "overturn" if over[i] else ("rock" if out[i, 2] > 0 else "rest") for i in range(B.size)
        ),
        duration=(af.size - 1) * dt,
        method=method,
        notes=tuple(notes),
    )
