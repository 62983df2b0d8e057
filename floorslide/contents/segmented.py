"""Contents on a segmented floor motion — a floor of a building on nonlinear isolation.

The building is integrated once (:class:`floorslide.building.nonlinear_motion.NonlinearMotion`);
each function here advances one kind of content through the recorded segments of its floor's
exact motion, by the same exact step the content takes on a linear building's floor:

- rigid blocks: :func:`floorslide.contents._kernels.objects_on_substep` (closed forms where a
  rigorous enclosure of the floor acceleration decides, the event-driven step otherwise);
- 2-DOF sliding oscillators: the 2-DOF kernel's event-driven part step
  (:func:`floorslide.contents._oscillator_kernel._advance_part`) in parts short for it;
- rocking blocks: :func:`floorslide.contents._rocking_kernel.block_through`.

:func:`floorslide.slide`, :func:`floorslide.slide_oscillator` and :func:`floorslide.rock` call
these when handed such a floor (or a building on nonlinear isolation with ``floor=``).
"""

from __future__ import annotations

import numpy as np

from floorslide.constants import G
from floorslide.contents import _segment_kernels as sk
from floorslide.errors import SolverLimitError

__all__ = ["oscillators_on_segments", "rockers_on_segments", "slide_on_segments"]


def _rows(fm):
    """The motion's arrays a consumer reads: its kernel (rows, chord rows) and the floor's output
    row and state index."""
    mo = fm.motion
    return mo, mo.kernel, fm.row, fm.floor


def slide_on_segments(fm, mk: np.ndarray, ms: np.ndarray, direction: str, histories: bool,
                      notes: tuple[str, ...] = (), vertical: np.ndarray | None = None):  # fmt: skip
    """Rigid blocks (kinetic ``mk``, static ``ms`` friction, one per block) on the floor `fm` of a
    segmented motion; as :func:`floorslide.slide`, with `vertical` (m/s², the record's samples)
    scaling the blocks' friction by ``1 + a_v/g`` — for an isolation layer the vertical does not
    act on (lead-rubber). Returns a :class:`~floorslide.contents.sliding.SlideResult`."""
    from floorslide.contents._kernels import (
        DISP,
        LIMIT_AT,
        NCOL,
        PEAK_ACC,
        PEAK_DISP,
        SLIDE_TIME,
        SLIPS,
        T_PEAK,
    )
    from floorslide.contents.events import SLIDE_MAX_EVENTS
    from floorslide.contents.sliding import SlideResult

    mo, kn, row, floor = _rows(fm)
    mb = np.maximum(mk, ms)
    nblk = mk.size
    BLK = np.empty((2, nblk), dtype=np.int64)
    BLK[0] = row
    BLK[1] = floor
    MU = np.ascontiguousarray(np.vstack([mb, mk]))
    bstates = np.zeros((nblk, NCOL))
    bstates[:, LIMIT_AT] = -1.0
    hist = np.zeros((nblk, mo.npts) if histories else (0, 0))
    buf, rw, pk, flags = sk.block_workspace(
        kn.K, NCOL, G, direction != "negative", direction != "positive"
    )
    has_vert = vertical is not None
    accv = np.ascontiguousarray(vertical, dtype=float) if has_vert else np.zeros(1)
    for SI, SF, SX, SY, count in mo.chunks():
        sk.blocks_on_segments(SI, SF, SX, SY, count, mo.substeps, kn.G, kn.OR, kn.OB, kn.n,
                              BLK, MU, bstates, buf, rw, pk, flags, G, hist, accv, has_vert,
                              mo.dt)  # fmt: skip
    if (bstates[:, LIMIT_AT] >= 0).any():
        t = float(bstates[bstates[:, LIMIT_AT] >= 0, LIMIT_AT].min())
        raise SolverLimitError(
            f"more than {SLIDE_MAX_EVENTS} friction events of a block inside one segment at "
            f"t = {t:.6g} s: stick-slip chatter the exact solver cannot resolve",
            "mu_k",
        )
    duration = (mo.npts - 1) * mo.dt
    S = bstates
    lift = (0.0, 0)
    if has_vert:
        from floorslide.contents.plane import liftoff

        lift = liftoff(accv, mo.dt)
    return SlideResult(
        mu_k=mk,
        mu_s=np.asarray(ms, dtype=float).copy(),
        peak_slide=S[:, PEAK_DISP].copy(),
        residual_slide=S[:, DISP].copy(),
        peak_abs_accel=S[:, PEAK_ACC].copy(),
        slide_fraction=S[:, SLIDE_TIME] / duration if duration > 0 else np.zeros(nblk),
        slip_phases=S[:, SLIPS].astype(np.int64),
        time_of_peak=S[:, T_PEAK].copy(),
        liftoff_time=lift[0],
        liftoff_count=lift[1],
        duration=duration,
        method="exact",
        direction=direction,
        u=hist if histories else None,
        notes=tuple(notes),
    )


def oscillators_on_segments(fm, mk, ms, frequency: float, damping: float, mass_ratio: float,
                            histories: bool, notes: tuple[str, ...] = ()):  # fmt: skip
    """2-DOF sliding oscillators (one kind, friction pairs ``mk``/``ms``) on the floor `fm` of a
    segmented motion; as :func:`floorslide.slide_oscillator`. Returns an
    :class:`~floorslide.contents.oscillator.OscillatorResult`."""
    from floorslide.building.exact import substeps_for, taylor_degree
    from floorslide.contents import _oscillator_kernel as cols
    from floorslide.contents.events import OSCILLATOR_MAX_EVENTS
    from floorslide.contents.oscillator import OscillatorResult, phase_radius

    mo, kn, row, _floor = _rows(fm)
    w2 = 2 * np.pi * float(frequency)
    rho_obj = phase_radius(w2, float(damping), float(mass_ratio))
    ho2 = mo.h / substeps_for(rho_obj, mo.h)
    rho = kn.rho  # the building's own (its sub-steps' ρ)
    K2 = max(kn.K, taylor_degree(max(rho, rho_obj) * ho2))
    flex = np.array([row, w2, float(damping), float(mass_ratio), ho2, K2])
    mub2 = np.ascontiguousarray(np.maximum(mk, ms), dtype=float)
    muk2 = np.ascontiguousarray(mk, dtype=float)
    S2 = np.zeros((muk2.size, cols.O_NCOL))
    S2[:, cols.O_LIMIT_AT] = -1.0
    H2 = np.zeros((muk2.size, mo.npts, 4) if histories else (0, 0, 4))
    af = fm.samples() if histories else np.zeros(0)
    c2, cs2, Y2, poly2, y2, pk2, work2 = sk.flexible_workspace(K2)
    if histories:
        H2[:, 0, 3] = af[0]
    for SI, SF, SX, _SY, count in mo.chunks():
        sk.flexible_on_segments(SI, SF, SX, count, mo.substeps, kn.OR, kn.OB, kn.K, flex, G,
                                mub2, muk2, S2, c2, cs2, Y2, poly2, y2, pk2, work2, H2,
                                af)  # fmt: skip
    if (S2[:, cols.O_LIMIT_AT] >= 0).any():
        raise SolverLimitError(
            f"more than {OSCILLATOR_MAX_EVENTS} friction events of a 2-DOF oscillator inside one "
            "part: stick-slip chatter the exact solver cannot resolve",
            "slide_oscillator",
        )
    duration = (mo.npts - 1) * mo.dt
    S, H = S2, H2
    return OscillatorResult(
        mu_k=mk,
        mu_s=np.asarray(ms, dtype=float).copy(),
        peak_slide=S[:, cols.O_PEAK_U].copy(),
        residual_slide=S[:, cols.O_U].copy(),
        peak_deformation=S[:, cols.O_PEAK_Z].copy(),
        peak_top_accel=S[:, cols.O_PEAK_TOP].copy(),
        peak_base_accel=S[:, cols.O_PEAK_BASE].copy(),
        slide_fraction=S[:, cols.O_SLIDE_TIME] / duration if duration > 0 else np.zeros(mk.size),
        slip_phases=S[:, cols.O_SLIPS].astype(int),
        u=H[:, :, 0].copy() if histories else None,
        z=H[:, :, 1].copy() if histories else None,
        top_accel=H[:, :, 2].copy() if histories else None,
        base_accel=H[:, :, 3].copy() if histories else None,
        notes=tuple(notes),
    )


def rockers_on_segments(fm, par: np.ndarray, states: np.ndarray, nonlinear: bool,
                        histories: bool) -> np.ndarray | None:  # fmt: skip
    """Rocking blocks (parameters ``par``, states ``states`` updated in place: the columns of
    :mod:`floorslide.contents._rocking_kernel`) on the floor `fm` of a segmented motion, each
    through every segment in parts with ``p·L ≤`` the kernel's phase; returns ``θ`` at the
    samples (NaN once overturned) with `histories`."""
    from floorslide.building.exact import taylor_degree
    from floorslide.contents import _rocking_kernel as rk

    mo, kn, row, _floor = _rows(fm)
    phase = rk.NONLINEAR_PHASE if nonlinear else rk.LINEAR_PHASE
    D = max(kn.K + 2, taylor_degree(phase * (2.0 if nonlinear else 1.0)))
    rk_out = np.full(par.shape[0], row, dtype=np.int64)
    hist = np.zeros((par.shape[0], mo.npts) if histories else (0, 0))
    if histories:
        hist[:, 0] = np.where(states[:, rk.MODE] == rk.OVERTURNED, np.nan, states[:, rk.TH])
    RB = sk.rocker_workspace(kn.K, D)
    for SI, SF, SX, _SY, count in mo.chunks():
        sk.rockers_on_segments(SI, SF, SX, count, mo.substeps, kn.OR, kn.OB, kn.K, rk_out, par,
                               states, G, D, nonlinear, phase, rk.ROCK_MAX_EVENTS, RB,
                               hist)  # fmt: skip
    return hist if histories else None
