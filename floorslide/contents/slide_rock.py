"""Rigid blocks that rest, slide, rock, or slide and rock at once on a floor (docs/design.md
§10g; Shenton & Jones 1991, Shenton 1996).

One block, four modes: it slides where friction gives way before it tips, rocks where friction
holds its corner, and does both where the friction a rocking block needs exceeds what the
contact gives. :func:`slide_rock` follows the block through every change of mode on the exact
floor motion of any building — the ground, a linear building, a building on nonlinear isolation
in one direction, or one floor of a poly motion along one component — with the series of the
full (not linearised) equations to rounding and every event located rigorously
(:mod:`floorslide.contents._sliderock_kernel`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from floorslide.building.exact import taylor_degree
from floorslide.building.exact_motion import FloorMotion, unwrap
from floorslide.building.nonlinear_motion import NonlinearFloorMotion
from floorslide.building.poly_segments import (
    GroundPolyMotion,
    LinearPolyMotion,
    checked_chunks,
)
from floorslide.constants import G
from floorslide.contents import _sliderock_kernel as sk
from floorslide.contents.rocking_block import block_geometry
from floorslide.errors import ModelError, SolverLimitError
from floorslide.inputs import RecordLike

__all__ = ["MODES", "SLIDE_ROCK_METHODS", "SlideRockResult", "slide_rock"]

SLIDE_ROCK_METHODS = ("exact", "fixed_step")
MODES = ("rest", "slide", "rock", "slide-rock")
"""The four modes, in the order of :attr:`SlideRockResult.mode_time`'s columns."""
_CODE_NAMES = ("rest", "slide", "rock", "slide-rock", "overturn")


@dataclass(frozen=True)
class SlideRockResult:
    """Blocks that rest, slide, rock or slide and rock, one entry per block.

    Attributes
    ----------
    width, height
        Base width and height, m.
    alpha, p, restitution, mu_k, mu_s
        Slenderness ``atan(B/H)`` (rad), frequency parameter (rad/s), restitution, kinetic and
        static friction.
    peak_slide
        ``max |U|``, m: the block's upright position relative to the floor, inside steps.
    residual_slide
        ``U`` at the end (at the overturning for a block that overturned), m.
    peak_ratio
        ``max |θ|/α`` inside steps (1 for a block that overturned).
    peak_time
        Time of the peak rotation, s (NaN when it never rocked).
    impacts
        Impacts (``θ`` back to 0), the cascade to rest included (as :func:`floorslide.rock`).
    significant_impacts
        Impacts at ``|θ'| ≥ p·α·√(f(2 − f))``, ``f = 0.01`` (as :func:`floorslide.rock`'s);
        None for the approximate method.
    overturned, overturn_time
        Whether ``|θ|`` reached ``α``, and when (NaN otherwise).
    mode_time
        ``(n_blocks, 4)``: seconds spent in rest, slide, rock, slide–rock (:data:`MODES`).
    mode_entries
        ``(n_blocks, 4)``: entries into each mode (the start counts as one rest).
    mode
        What the block did: ``"rest"``, ``"slide"``, ``"rock"``, ``"slide-rock"`` (it spent
        time sliding and rocking at once, or both slid and rocked), or ``"overturn"``.
    sequence
        The first mode changes, e.g. ``"rest 0 → rock 2.31 → slide-rock 2.4 → rock 2.43"``
        (times in s; ``(+N more)`` when there were more than
        :data:`~floorslide.contents._sliderock_kernel.LOG_SIZE`).
    energy
        ``(n_blocks, 4)`` per unit mass, J/kg: ``E_end − E_0``, the floor's work on the block
        (its inertial force in the floor's frame), friction's dissipation, impacts' losses —
        ``E_end − E_0 = W_floor − W_friction − W_impacts`` (docs/design.md §10g); NaN unless
        asked for (``energy=True``).
    duration
        Duration of the record, s.
    method
        ``"exact"`` or an approximate method.
    theta, slide, mode_history
        With `histories`: ``θ`` (rad) and ``U`` (m), NaN once overturned, and the mode code
        (0 rest, 1 slide, 2 rock, 3 slide–rock, 4 overturned) at the samples,
        ``(n_blocks, npts)``.
    notes
        What was done to the input record.
    """

    width: np.ndarray
    height: np.ndarray
    alpha: np.ndarray
    p: np.ndarray
    restitution: np.ndarray
    mu_k: np.ndarray
    mu_s: np.ndarray
    peak_slide: np.ndarray
    residual_slide: np.ndarray
    peak_ratio: np.ndarray
    peak_time: np.ndarray
    impacts: np.ndarray
    overturned: np.ndarray
    overturn_time: np.ndarray
    mode_time: np.ndarray
    mode_entries: np.ndarray
    mode: tuple[str, ...]
    sequence: tuple[str, ...]
    energy: np.ndarray
    duration: float
    method: str
    theta: np.ndarray | None = field(default=None, repr=False)
    slide: np.ndarray | None = field(default=None, repr=False)
    mode_history: np.ndarray | None = field(default=None, repr=False)
    notes: tuple[str, ...] = ()
    significant_impacts: np.ndarray | None = None

    def to_records(self) -> list[dict]:
        """One JSON-ready dict per block (snake_case keys, SI values)."""
        out = []
        for i in range(self.width.size):
            d = dict(
                width=float(self.width[i]),
                height=float(self.height[i]),
                mu_k=float(self.mu_k[i]),
                mu_s=float(self.mu_s[i]),
                peak_slide=float(self.peak_slide[i]),
                residual_slide=float(self.residual_slide[i]),
                peak_ratio=float(self.peak_ratio[i]),
                impacts=int(self.impacts[i]),
                overturned=bool(self.overturned[i]),
                overturn_time=float(self.overturn_time[i]),
                mode=self.mode[i],
                sequence=self.sequence[i],
            )
            for j, name in enumerate(MODES):
                d[f"time_{name.replace('-', '_')}"] = float(self.mode_time[i, j])
            out.append(d)
        return out


def _friction(mu, mu_s, n):
    """``(mu_k, mu_s)`` broadcast to `n` blocks, checked."""
    if mu is None:
        raise ModelError("mu (kinetic friction) is required", "mu")
    mk = np.atleast_1d(np.asarray(mu, dtype=float)).ravel()
    ms = mk if mu_s is None else np.atleast_1d(np.asarray(mu_s, dtype=float)).ravel()
    try:
        mk, ms = (np.ascontiguousarray(np.broadcast_to(x, (n,)), dtype=float) for x in (mk, ms))
    except ValueError:
        raise ModelError(f"mu and mu_s must be one value or one per block ({n})", "mu") from None
    for name, arr in (("mu", mk), ("mu_s", ms)):
        if not np.all(np.isfinite(arr)) or np.any(arr <= 0.0):
            raise ModelError(f"{name} must be finite and > 0, got {arr.tolist()}", name)
    if np.any(ms < mk):
        raise ModelError(f"mu_s {ms.tolist()} must be ≥ mu (kinetic) {mk.tolist()}", "mu_s")
    return mk, ms


def _poly_source(acc, dt, building, floor):
    """``(poly motion, floor row, direction, dt, notes)`` for what :func:`slide_rock` was
    given."""
    from floorslide.building.poly_peaks import PolyComponent
    from floorslide.building.segment_polys import SegmentedPolyMotion

    if isinstance(acc, PolyComponent):
        if building is not None or floor is not None:
            raise ModelError(
                "acc is a PolyComponent (one floor along one component): give no building= "
                "or floor=",
                "building",
            )
        if dt is not None and not np.isclose(float(dt), acc.dt, rtol=1e-9, atol=0.0):
            raise ModelError(f"dt={dt} differs from the PolyComponent's dt={acc.dt}", "dt")
        return acc.motion, acc.row, acc.direction, acc.dt, tuple(getattr(acc.motion, "notes", ()))
    fm, a, dt, notes = unwrap(acc, dt, building, floor)
    if fm is not None:
        building, floor = fm.building, fm.floor
    if building is None:
        if floor not in (None, 0):
            raise ModelError("floor= needs building=", "floor")
        return GroundPolyMotion(a, np.zeros_like(a), dt), 0, 0, dt, tuple(notes)
    if floor is None:
        raise ModelError("floor is required with building=", "floor")
    if getattr(building, "segmented", False):
        if isinstance(fm, NonlinearFloorMotion):
            motion = fm.motion
        else:
            motion = building.motion(a, dt, floors=[floor])
        return SegmentedPolyMotion(motion, [floor]), 0, 0, dt, tuple(notes)
    # a linear building's (a FloorMotion's or the record's): its floor polynomials
    poly = LinearPolyMotion(building, a, np.zeros_like(a), dt, floors=[floor])
    return poly, 0, 0, dt, tuple(notes)


def slide_rock(
    acc: RecordLike | FloorMotion,
    dt: float | None = None,
    width=None,
    height=None,
    mu=None,
    *,
    mu_s=None,
    restitution=None,
    building=None,
    floor: int | None = None,
    method: str = "exact",
    histories: bool = False,
    energy: bool = False,
    substeps: int = 8,
    vertical=None,
    direction=None,
) -> SlideRockResult:
    """Rigid blocks that rest, slide, rock, or slide and rock at once, on a floor.

    Parameters
    ----------
    acc
        Ground acceleration samples, m/s² (with `building`), or the motion the blocks stand on
        (without), piecewise linear; an ObsPy Trace; a :class:`~floorslide.FloorMotion` (a
        linear building's or one on nonlinear isolation); or a
        :class:`~floorslide.building.poly_peaks.PolyComponent` (one floor of a poly motion
        along one component: a building on friction pendulums under a pair).
    dt
        Time step, s.
    width, height
        Base width and height of each block, m (one value or one per block).
    mu
        Kinetic friction coefficient(s) at the contact.
    mu_s
        Static friction (default `mu`; ``mu_s ≥ mu``).
    restitution
        Ratio of angular velocities after/before an impact of a block whose corner does not
        slip (default Housner's ``1 − 1.5 sin²α``, which needs ``B/H < 1.41``).
    building, floor
        Put the blocks on `floor` of `building`: fixed-base, linearly isolated or on nonlinear
        isolation in one direction.
    method
        ``"exact"``: the series of the full equations of every mode, to rounding, every mode
        change located rigorously. ``"fixed_step"`` (approximate, for comparison): RK4 on
        ``dt/substeps`` with events interpolated in the step
        (:mod:`floorslide.contents.slide_rock_approx`), on the floor's samples; peaks only.
    histories
        Also return ``θ``, ``U`` and the mode at the samples.
    energy
        Also account the energy terms (:attr:`SlideRockResult.energy`, the balance of
        docs/design.md §10g; the contact forces' series on every rocking part: slower). Exact
        method only.
    substeps
        Steps per record step of ``"fixed_step"``.
    vertical, direction
        Not modelled for slide–rock (refused in one line if given).

    Returns
    -------
    SlideRockResult

    Raises
    ------
    ModelError
        Invalid geometry, friction, restitution, method, floor; vertical or one-way sliding.
    SolverLimitError
        Free flight (the normal force reaching 0), the Painlevé case, or more than
        :data:`~floorslide.contents._sliderock_kernel.MAX_EVENTS` events of a block in one part.

    References
    ----------
    Shenton, H. W., Jones, N. P. (1991). Base excitation of rigid bodies. I: Formulation.
    *J. Eng. Mech.* 117(10), 2286–2306.
    Shenton, H. W. (1996). Criteria for initiation of slide, rock, and slide-rock rigid-body
    modes. *J. Eng. Mech.* 122(7), 690–693.
    Housner, G. W. (1963). *Bull. Seismol. Soc. Am.* 53(2), 403–417.
    """
    if vertical is not None:
        raise ModelError(
            "slide_rock does not model vertical shaking (fs.slide and fs.slide_plane do)",
            "vertical",
        )
    if direction is not None:
        raise ModelError(
            "slide_rock slides both ways (one-way sliding is fs.slide's direction=)", "direction"
        )
    if method not in SLIDE_ROCK_METHODS:
        raise ModelError(
            f"unknown method {method!r}; expected one of {', '.join(SLIDE_ROCK_METHODS)}",
            "method",
        )
    B, H, alpha, p, r = block_geometry(width, height, 1.0 if restitution is None else restitution)
    if restitution is None:
        # Housner's, at 0 for a block too squat to keep any (B/H > 1.41: it slides anyway
        # unless mu_s exceeds B/H)
        r = np.maximum(1.0 - 1.5 * np.sin(alpha) ** 2, 0.0)
    n = B.size
    for m in (mu, mu_s):
        if m is not None and np.size(m) > 1:
            if n not in (1, np.size(m)):
                raise ModelError(
                    f"width/height ({n}) and mu/mu_s ({np.size(m)}) must be one value or one "
                    "per block",
                    "mu",
                )
            n = np.size(m)
    mk, ms = _friction(mu, mu_s, n)
    B, H, alpha, p, r = (
        np.ascontiguousarray(np.broadcast_to(x, (n,)), dtype=float) for x in (B, H, alpha, p, r)
    )
    if method != "exact":
        if energy:
            raise ModelError("energy=True needs method='exact'", "energy")
        return _approximate(acc, dt, building, floor, B, H, alpha, p, r, mk, ms, histories,
                            substeps)  # fmt: skip
    motion, row, d, dt, notes = _poly_source(acc, dt, building, floor)
    par = np.empty((B.size, sk.NPAR))
    par[:, sk.P_ALPHA] = alpha
    par[:, sk.P_P] = p
    par[:, sk.P_RAD] = 0.5 * np.hypot(B, H)
    par[:, sk.P_TAN] = B / H
    par[:, sk.P_MUK] = mk
    par[:, sk.P_MUS] = ms
    par[:, sk.P_R] = r
    par[:, sk.P_ENERGY] = 1.0 if energy else 0.0
    states = np.zeros((B.size, sk.NCOL))
    states[:, sk.T_OVER] = -1.0
    states[:, sk.LIMIT_AT] = -1.0
    states[:, sk.T_PEAK] = np.nan
    states[:, sk.LOG + 1] = sk.REST
    states[:, sk.NLOG] = 1.0
    states[:, sk.LAST] = sk.REST
    states[:, sk.N_MODE + sk.REST] = 1.0
    npts = int(motion.npts)
    hist = np.zeros((B.size, 3, npts) if histories else (0, 3, 0))
    D0 = taylor_degree(2.0 * sk.PHASE) + 2
    for seg in checked_chunks(motion):
        C = seg.coef[:, row, d, :]
        nz = np.flatnonzero(np.any(C != 0.0, axis=0))
        K = max(1, int(nz[-1]) if nz.size else 1)
        C = np.ascontiguousarray(C[:, : K + 1])
        D = max(K + 2, D0)
        sk.sliderock_on_poly(seg.t0, seg.length, seg.step, seg.ends, C, par, states, G, D,
                             sk.MAX_EVENTS, hist)  # fmt: skip
    _raise_errors(states, B, H)
    return _result(states, B, H, alpha, p, r, mk, ms, (npts - 1) * dt, hist if histories else None,
                   notes, energy)  # fmt: skip


def _raise_errors(states, B, H) -> None:
    """A block stopped by free flight, the Painlevé case or the event limit: one line."""
    for i in range(B.size):
        st = states[i]
        where = f"(block {B[i]:g} × {H[i]:g} m)"
        if st[sk.ERR] == sk.FLIGHT:
            raise SolverLimitError(
                f"slide_rock: the normal force reaches 0 at t = {st[sk.ERR_T]:.6g} s {where}: "
                "the block would leave the floor (free flight is not modelled)",
                "width",
            )
        if st[sk.ERR] == sk.PAINLEVE:
            raise SolverLimitError(
                f"slide_rock: at t = {st[sk.ERR_T]:.6g} s {where} sliding while rocking has no "
                "solution with this friction (Painlevé's case of Coulomb friction: mu too "
                "large for the block's shape)",
                "mu",
            )
        if st[sk.ERR] == sk.INCONSISTENT:
            raise SolverLimitError(
                f"slide_rock: at t = {st[sk.ERR_T]:.6g} s {where} the corner can neither stick "
                "nor slip consistently (a Painlevé-type ambiguity of Coulomb friction)",
                "mu",
            )
        if st[sk.LIMIT_AT] >= 0.0:
            raise SolverLimitError(
                f"slide_rock: more than {sk.MAX_EVENTS} mode changes inside one part at "
                f"t = {st[sk.LIMIT_AT]:.6g} s {where}",
                "width",
            )


def _sequence(st) -> str:
    """The logged mode changes of one block, as text."""
    n = int(st[sk.NLOG])
    parts = []
    for j in range(min(n, sk.LOG_SIZE)):
        t = st[sk.LOG + 2 * j]
        code = int(st[sk.LOG + 2 * j + 1])
        parts.append(f"{_CODE_NAMES[code]} {t:.4g}")
    text = " → ".join(parts)
    if n > sk.LOG_SIZE:
        text += f" (+{n - sk.LOG_SIZE} more)"
    return text


def _mode(mode_time, overturned) -> str:
    """The result's one-word mode of a block."""
    if overturned:
        return "overturn"
    slid = mode_time[1] > 0.0
    rocked = mode_time[2] > 0.0
    if mode_time[3] > 0.0 or (slid and rocked):
        return "slide-rock"
    if rocked:
        return "rock"
    return "slide" if slid else "rest"


def _result(
    states, B, H, alpha, p, r, mk, ms, duration, hist, notes, with_energy
) -> SlideRockResult:
    over = states[:, sk.MODE] == sk.OVERTURNED
    mode_time = states[:, sk.T_MODE : sk.T_MODE + 4].copy()
    e_end = np.array(
        [sk.energy(states[i], _par_row(alpha[i], B[i], H[i]), G) for i in range(B.size)]
    )
    energy = np.column_stack(
        [e_end - states[:, sk.E0], states[:, sk.W_FLOOR], states[:, sk.W_FRIC], states[:, sk.W_IMP]]
    )
    if not with_energy:
        energy[:] = np.nan
    return SlideRockResult(
        width=B,
        height=H,
        alpha=alpha,
        p=p,
        restitution=r,
        mu_k=mk,
        mu_s=ms,
        peak_slide=states[:, sk.PEAK_U].copy(),
        residual_slide=states[:, sk.U].copy(),
        peak_ratio=states[:, sk.PEAK].copy(),
        peak_time=states[:, sk.T_PEAK].copy(),
        impacts=states[:, sk.IMPACTS].astype(int),
        significant_impacts=states[:, sk.SIGNIF].astype(int),
        overturned=over,
        overturn_time=np.where(over, states[:, sk.T_OVER], np.nan),
        mode_time=mode_time,
        mode_entries=states[:, sk.N_MODE : sk.N_MODE + 4].astype(int),
        mode=tuple(_mode(mode_time[i], over[i]) for i in range(B.size)),
        sequence=tuple(_sequence(states[i]) for i in range(B.size)),
        energy=energy,
        duration=float(duration),
        method="exact",
        theta=None if hist is None else hist[:, 0].copy(),
        slide=None if hist is None else hist[:, 1].copy(),
        mode_history=None if hist is None else _with_start(hist[:, 2], states),
        notes=tuple(notes),
    )


def _with_start(modes: np.ndarray, states: np.ndarray) -> np.ndarray:
    """The mode codes at the samples with sample 0 filled in: the mode the block is in after the
    events at t = 0 (a record that starts beyond the rest level starts a slide or a rock at
    once), the last one logged at t = 0."""
    out = modes.astype(np.int8)
    for i in range(out.shape[0]):
        n = min(int(states[i, sk.NLOG]), sk.LOG_SIZE)
        code = sk.REST
        for j in range(n):
            if states[i, sk.LOG + 2 * j] > 0.0:
                break
            code = int(states[i, sk.LOG + 2 * j + 1])
        out[i, 0] = code
    return out


def _par_row(alpha, B, H) -> np.ndarray:
    """The parameters :func:`~floorslide.contents._sliderock_kernel.energy` reads."""
    par = np.zeros(sk.NPAR)
    par[sk.P_ALPHA] = alpha
    par[sk.P_RAD] = 0.5 * np.hypot(B, H)
    return par


def _approximate(acc, dt, building, floor, B, H, alpha, p, r, mk, ms, histories, substeps):
    """:func:`slide_rock` by the fixed-step scheme on the floor's samples."""
    from floorslide.building.exact_motion import floor_motion
    from floorslide.contents import slide_rock_approx as sra

    if histories:
        raise ModelError("method='fixed_step' gives peaks only (no histories)", "method")
    if isinstance(acc, FloorMotion | NonlinearFloorMotion):
        af, dt, notes = acc.samples(), acc.dt, acc.notes
    elif getattr(building, "segmented", False):
        fm = building.motion(acc, dt, floors=[floor]).floor(floor)
        af, dt, notes = fm.samples(), fm.dt, fm.notes
    else:
        fm = floor_motion(building, acc, 0 if building is None else floor, dt)
        af, dt, notes = fm.samples(), fm.dt, fm.notes
    if not (isinstance(substeps, int | np.integer) and substeps >= 1):
        raise ModelError(f"substeps must be an integer ≥ 1, got {substeps!r}", "substeps")
    out = sra.fixed_step(np.ascontiguousarray(af, dtype=float), float(dt), B, H, mk, ms, r, G,
                         int(substeps))  # fmt: skip
    over = out[:, 3] > 0
    mode_time = out[:, 6:10].copy()
    nan4 = np.full((B.size, 4), np.nan)
    return SlideRockResult(
        width=B,
        height=H,
        alpha=alpha,
        p=p,
        restitution=r,
        mu_k=mk,
        mu_s=ms,
        peak_slide=out[:, 0].copy(),
        residual_slide=out[:, 1].copy(),
        peak_ratio=out[:, 2].copy(),
        peak_time=np.full(B.size, np.nan),
        impacts=out[:, 5].astype(int),
        overturned=over,
        overturn_time=np.where(over, out[:, 4], np.nan),
        mode_time=mode_time,
        mode_entries=np.zeros((B.size, 4), dtype=int),
        mode=tuple(_mode(mode_time[i], over[i]) for i in range(B.size)),
        sequence=("",) * B.size,
        energy=nan4,
        duration=(af.size - 1) * dt,
        method="fixed_step",
        notes=tuple(notes),
    )
