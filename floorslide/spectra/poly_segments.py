"""Response and RotD spectra on a poly motion: any building's floors read as polynomial
segments (:mod:`floorslide.building.poly_segments`, docs/design.md §6 and §10b).

The same quantities as :func:`floorslide.response_spectrum` and :func:`floorslide.rotd_spectrum`
(``sd = max|q|``, ``sv = max|q'|``, ``sa = max|ω²q + 2ξωq'|``, ``psa = ω²·sd``, ``psv = ω·sd``;
RotD50/RotD100 of Boore 2010), the oscillators driven by the segments' polynomials as given:
their Taylor series on each segment (cut where ``ω·L`` is too large) summed to rounding, the
peaks found inside every piece (:mod:`floorslide.spectra._poly_segment_kernels`).
"""

from __future__ import annotations

import numpy as np

from floorslide.building.poly_segments import checked_chunks
from floorslide.errors import ModelError
from floorslide.spectra import _poly_segment_kernels as PK
from floorslide.spectra.core import Spectrum, check_oscillators, damping_ratios, period_grid
from floorslide.spectra.rotd import MAX_VALUES, RotDSpectrum, _angle_count

__all__ = ["rotd_on_poly", "spectrum_on_poly"]


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


def _direction(direction) -> tuple[float, float]:
    """``(cos, sin)`` of the direction: the int 0 (``x``) or 1 (``y``), or an azimuth in degrees
    (a float, from ``x`` towards ``y``)."""
    if isinstance(direction, bool):
        raise ModelError(f"direction must be 0, 1 or an azimuth in degrees, got {direction!r}",
                         "direction")  # fmt: skip
    if isinstance(direction, int | np.integer):
        if direction not in (0, 1):
            raise ModelError(
                f"direction {direction} is not 0 (x) or 1 (y); give an azimuth as a float "
                "(degrees)",
                "direction",
            )
        return (1.0, 0.0) if direction == 0 else (0.0, 1.0)
    try:
        th = float(direction)
    except (TypeError, ValueError):
        raise ModelError(f"direction must be 0, 1 or an azimuth in degrees, got {direction!r}",
                         "direction") from None  # fmt: skip
    if not np.isfinite(th):
        raise ModelError(f"direction must be finite, got {direction!r}", "direction")
    r = np.radians(th)
    return float(np.cos(r)), float(np.sin(r))


def _grid(motion, periods, damping):
    """Periods and damping validated as the ground spectra do; the positive periods' oscillators
    ``(w, xi)`` damping-major (row ``i·nT + j``: damping ``i``, period ``j``)."""
    if periods is None:
        raise ModelError("periods are required: a list in s or {min, max, n}", "periods")
    T = period_grid(periods)
    Z = damping_ratios(damping)
    check_oscillators(T, Z, motion.dt)
    pos = T > 0
    Tp = T[pos]
    w = np.tile(2.0 * np.pi / Tp, Z.size)
    xi = np.repeat(Z, Tp.size)
    return T, Z, pos, np.ascontiguousarray(w), np.ascontiguousarray(xi)


def _chunks(motion):
    """The motion's chunks, validated, as contiguous float arrays ``(t0, length, coef)``."""
    for seg in checked_chunks(motion):
        yield tuple(np.ascontiguousarray(a, dtype=float) for a in (seg.t0, seg.length, seg.coef))


def spectrum_on_poly(motion, floor: int | None, periods, damping=0.05, *,
                     direction=0) -> Spectrum:  # fmt: skip
    """Response spectrum of a linear oscillator driven by a floor's absolute acceleration along
    one direction of a poly motion, exact to rounding for its polynomials.

    Parameters
    ----------
    motion
        A poly motion (:mod:`floorslide.building.poly_segments`).
    floor
        The floor (None: the motion's only floor).
    periods
        Oscillator periods (s, list; 0 gives the true peak of the motion) or
        ``{"min", "max", "n"}``; the limits of :func:`~floorslide.response_spectrum`.
    damping
        Damping ratio or ratios.
    direction
        ``0`` (``x``, ``h1``), ``1`` (``y``, ``h2``), or an azimuth in degrees from ``x`` towards
        ``y`` given as a float (the motion ``a_x cos θ + a_y sin θ``).

    Returns
    -------
    Spectrum
        As :func:`~floorslide.response_spectrum` (``method="exact"``).

    References
    ----------
    Nigam, N. C., Jennings, P. C. (1969). Calculation of response spectra from strong-motion
    earthquake records. *Bull. Seismol. Soc. Am.* 59(2), 909–922.
    """
    row = _floor_row(motion, floor)
    cx, cy = _direction(direction)
    T, Z, pos, w, xi = _grid(motion, periods, damping)
    acc = _SpectrumPeaks(w.size, cx, cy)
    work = PK.new_scratch()
    for t0, length, coef in _chunks(motion):
        acc.advance(t0, length, coef, row, w, xi, work)
    return acc.spectrum(T, Z, pos, motion.notes)


class _SpectrumPeaks:
    """The running peaks of one direction's oscillators (:func:`spectrum_on_poly`), advanced
    chunk by chunk, so that several consumers share one pass over a motion."""

    def __init__(self, nosc: int, cx: float, cy: float):
        self.cx, self.cy = cx, cy
        self.S = np.zeros((nosc, 2))
        self.out = np.zeros((nosc, 3))
        self.rigid = np.zeros(2)

    def advance(self, t0, length, coef, row, w, xi, work) -> None:
        """Through one chunk."""
        PK.spectrum_segments_kernel(t0, length, coef, row, self.cx, self.cy, w, xi, self.S,
                                    self.out, self.rigid, work)  # fmt: skip

    def spectrum(self, T, Z, pos, notes) -> Spectrum:
        """The :class:`~floorslide.spectra.core.Spectrum` of the peaks so far."""
        out, rigid = self.out, self.rigid
        shape = (Z.size, T.size)
        sd, sv, sa = np.zeros(shape), np.zeros(shape), np.zeros(shape)
        for arr, col in ((sd, 0), (sv, 1), (sa, 2)):
            arr[:, pos] = out[:, col].reshape(Z.size, -1)
        sa[:, ~pos] = rigid[0]
        wT = np.where(pos, 2 * np.pi / np.where(pos, T, 1.0), 0.0)
        psa = sd * wT**2
        psa[:, ~pos] = sa[:, ~pos]
        return Spectrum(periods=T, damping=Z, psa=psa, sa=sa, sv=sv, sd=sd, psv=sd * wT,
                        method="exact", notes=tuple(notes))  # fmt: skip


def rotd_on_poly(motion, floor: int | None, periods, damping=0.05, *, angles: int = 180,
                 directions: bool = True) -> RotDSpectrum:  # fmt: skip
    """RotD50 and RotD100 spectra (Boore 2010) of a floor of a poly motion, exact to rounding
    for its polynomials; as :func:`~floorslide.rotd_spectrum`.

    Parameters
    ----------
    motion
        A poly motion (:mod:`floorslide.building.poly_segments`).
    floor
        The floor (None: the motion's only floor).
    periods, damping
        As :func:`~floorslide.rotd_spectrum` (period 0: the peaks of the floor motion itself).
    angles
        Number ``n`` of angles ``θ_j = j·180°/n`` of RotD50.
    directions
        Also compute ``h1`` and ``h2``, the ordinary spectra along ``x`` and ``y``
        (:func:`spectrum_on_poly`), in the same pass over the motion.

    Returns
    -------
    RotDSpectrum

    References
    ----------
    Boore, D. M. (2010). Orientation-independent, nongeometric-mean measures of seismic
    intensity from two horizontal components of motion. *Bull. Seismol. Soc. Am.* 100(4),
    1830–1835.
    """
    row = _floor_row(motion, floor)
    T, Z, pos, w, xi = _grid(motion, periods, damping)
    n_ang = _angle_count(angles)
    if T.size * Z.size * n_ang > MAX_VALUES:
        raise ModelError(
            f"{T.size} periods x {Z.size} damping ratios x {n_ang} angles = "
            f"{T.size * Z.size * n_ang} peaks: at most {MAX_VALUES}",
            "angles",
        )
    theta = np.arange(n_ang) * (180.0 / n_ang)
    rad = np.deg2rad(theta)
    cs, sn = np.cos(rad), np.sin(rad)
    nosc = w.size
    S = np.zeros((nosc, 4))
    M = np.zeros((nosc, n_ang))
    R2 = np.zeros(nosc)
    W = np.zeros((nosc, 3))
    M0 = np.zeros((1, n_ang))
    R20 = np.zeros(1)
    W0 = np.zeros((1, 3))
    work = PK.new_scratch()
    comps = [_SpectrumPeaks(nosc, 1.0, 0.0), _SpectrumPeaks(nosc, 0.0, 1.0)] if directions else []
    for t0, length, coef in _chunks(motion):
        PK.rotd_segments_kernel(t0, length, coef, row, w, xi, cs, sn, S, M, R2, W, M0, R20, W0,
                                work)  # fmt: skip
        for comp in comps:
            comp.advance(t0, length, coef, row, w, xi, work)
    shape = (Z.size, T.size)
    psa_angles = np.zeros((*shape, n_ang))
    rotd100 = np.zeros(shape)
    where = np.zeros((*shape, 3))
    if nosc:
        w2 = (w**2).reshape(Z.size, -1)
        psa_angles[:, pos] = M.reshape(Z.size, -1, n_ang) * w2[..., None]
        rotd100[:, pos] = np.sqrt(R2).reshape(Z.size, -1) * w2
        where[:, pos] = W.reshape(Z.size, -1, 3)
    if not pos.all():
        psa_angles[:, ~pos] = M0[0]
        rotd100[:, ~pos] = np.sqrt(R20[0])
        where[:, ~pos] = W0[0]
    angle100 = np.degrees(np.arctan2(where[..., 2], where[..., 1])) % 180.0
    angle100[(rotd100 == 0) | (angle100 >= 180.0)] = 0.0
    sp1 = sp2 = None
    if directions:
        sp1, sp2 = (comp.spectrum(T, Z, pos, motion.notes) for comp in comps)
    return RotDSpectrum(
        periods=T,
        damping=Z,
        rotd50=np.median(psa_angles, axis=-1),
        rotd100=rotd100,
        angle100=angle100,
        time100=where[..., 0],
        psa_angles=psa_angles,
        angles=theta,
        h1=sp1,
        h2=sp2,
        method="exact",
        notes=tuple(motion.notes),
    )
