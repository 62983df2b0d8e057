"""The 2-DOF sliding oscillator in the plane: flexible equipment whose base slides on its floor
under two horizontal components (docs/design.md §10d).

The 1-D model of :func:`floorslide.slide_oscillator` made isotropic: the top mass on a spring and
dashpot of the same stiffness in every horizontal direction (clamped-base frequency `f`, damping
ratio `ξ`), its deformation a 2-vector ``z`` relative to the base; the base (``r = m_base/m_top``)
slides on the floor with isotropic Coulomb friction on the total weight — the friction circle of
:func:`floorslide.slide_plane`: sliding friction ``mu_k (m_base + m_top) g`` opposite the base's
velocity relative to the floor, stuck while the friction the base needs (from the floor's
acceleration and the spring and damper) stays within ``max(mu_s, mu_k) (m_base + m_top) g``.
The floor's motion is any poly motion (:mod:`floorslide.building.poly_segments`): the ground
pair, a floor of a linear building, a floor of a building on friction pendulums or lead-rubber
bearings (:class:`~floorslide.building.plane_isolation.PlaneIsolatedMotion`). Each phase is
integrated by its Taylor series to rounding and the events are located by rigorous root
isolation (:mod:`floorslide.contents._plane_oscillator_kernel`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from floorslide.building.plane_isolation import PlaneIsolatedMotion, couples_directions
from floorslide.building.poly_segments import GroundPolyMotion, LinearPolyMotion, checked_chunks
from floorslide.constants import G
from floorslide.contents import _plane_kernel as pk
from floorslide.contents import _plane_oscillator_kernel as ok
from floorslide.contents.oscillator import oscillator_parameters
from floorslide.contents.plane import DEGREE
from floorslide.contents.plane_segments import _floor_row
from floorslide.contents.sliding import friction_pairs
from floorslide.errors import ModelError, SolverLimitError
from floorslide.pair import as_pair

__all__ = [
    "PlaneOscillatorResult",
    "slide_oscillator_plane",
    "slide_oscillator_plane_on_segments",
]


@dataclass(frozen=True)
class PlaneOscillatorResult:
    """2-DOF sliding oscillators in the plane, one entry per friction pair (mu_k, mu_s).

    Attributes
    ----------
    mu_k, mu_s
        Kinetic and static friction coefficients.
    frequency, damping, mass_ratio
        The oscillator: clamped-base frequency (Hz), damping ratio, ``m_base/m_top``.
    peak_slide
        ``max |u|`` of the base's slide relative to the floor, found inside steps (every step
        of every slip phase: the maximum of ``|u|²``'s polynomial), m.
    peak_angle
        Direction of the slide at its peak, degrees from ``h1`` towards ``h2``.
    time_of_peak
        When, s (NaN: never slid).
    residual
        ``u`` at the end of the record, ``(n, 2)``, m.
    peak_deformation
        ``max |z|`` of the spring (top relative to base), inside steps, m.
    peak_top_accel
        ``max |a_top|`` of the top mass's absolute acceleration (``2ξw z' + w² z``), inside
        steps, m/s².
    slide_fraction
        Fraction of the record the base spends sliding.
    slip_phases
        Slip phases begun from rest: breakaways from stick and restarts at once after a stop
        (a reversal in 1-D), as :attr:`floorslide.contents.oscillator.OscillatorResult.
        slip_phases` counts them.
    stops
        Stops of the base (it sticks there, or slides on at once).
    path
        The base's path on the floor ``∫|u'| dt``, m.
    final_velocity
        ``u'`` at the end, ``(n, 2)``, m/s.
    duration
        Duration of the record, s.
    u, z
        ``(n, npts, 2)`` the slide and the spring's deformation at the samples, when requested.
    notes
        What was done to the input (padding of the components), one line each.
    """

    mu_k: np.ndarray
    mu_s: np.ndarray
    frequency: float
    damping: float
    mass_ratio: float
    peak_slide: np.ndarray
    peak_angle: np.ndarray
    time_of_peak: np.ndarray
    residual: np.ndarray
    peak_deformation: np.ndarray
    peak_top_accel: np.ndarray
    slide_fraction: np.ndarray
    slip_phases: np.ndarray
    stops: np.ndarray
    path: np.ndarray
    final_velocity: np.ndarray
    duration: float
    u: np.ndarray | None = field(default=None, repr=False)
    z: np.ndarray | None = field(default=None, repr=False)
    notes: tuple[str, ...] = ()


def _friction(mu_k, mu_s) -> tuple[np.ndarray, np.ndarray]:
    """:func:`~floorslide.contents.sliding.friction_pairs`, with ``mu_k > 0`` (a base without
    kinetic friction is not modelled in the plane: refused in one line)."""
    if mu_k is None:
        raise ModelError("mu (the kinetic friction coefficient or coefficients) is required",
                         "mu")  # fmt: skip
    mk, ms = friction_pairs(mu_k, mu_s)
    if np.any(mk <= 0.0):
        raise ModelError(
            f"mu must be > 0 for the oscillator in the plane (a base without kinetic friction "
            f"is not modelled), got {mk.tolist()}",
            "mu",
        )
    return mk, ms


def slide_oscillator_plane_on_segments(
    motion,
    floor: int | None = None,
    mu_k=None,
    mu_s=None,
    *,
    frequency: float | None = None,
    damping: float = 0.02,
    mass_ratio: float = 1.0,
    histories: bool = False,
) -> PlaneOscillatorResult:
    """Peak slide, spring deformation and top acceleration of 2-DOF sliding oscillators in the
    plane on one floor of a poly motion, exact to rounding for the motion's polynomials.

    Parameters
    ----------
    motion
        A poly motion (``dt``, ``npts``, ``floors``, ``notes``, ``poly_chunks()``:
        :mod:`floorslide.building.poly_segments`).
    floor
        The floor the oscillators stand on (default: the motion's only floor).
    mu_k, mu_s
        Kinetic (> 0) and static coefficients of the base on the floor (breakaway at
        ``max(mu_s, mu_k)``; ``mu_s`` defaults to ``mu_k``); many values in one compiled loop.
    frequency
        Clamped-base natural frequency of the equipment, Hz (> 0), the same in every direction.
    damping
        Its damping ratio on its clamped base, in [0, 1).
    mass_ratio
        ``r = m_base / m_top`` (> 0).
    histories
        Also return ``u`` and ``z`` at the samples.

    Returns
    -------
    PlaneOscillatorResult

    Raises
    ------
    ModelError
        Invalid friction, oscillator or floor; segments that break the contract.
    SolverLimitError
        More than :data:`~floorslide.contents._plane_kernel.MAX_EVENTS` stops and breakaways, or
        :data:`~floorslide.contents._plane_kernel.MAX_STEPS` series steps, of one oscillator
        inside one segment.

    Notes
    -----
    Per unit top mass, with ``q = 2ξw z' + w² z``, ``k = 1 + 1/r``, ``a`` the floor's absolute
    acceleration and ``w_u = u'/|u'|``: stuck, ``z'' = −a − q`` and the friction needed is
    ``F = r a − q`` (stuck while ``|F| ≤ max(mu_s, mu_k)(1 + r) g``); sliding,
    ``u'' = −a + q/r − mu_k (1 + r) g/r · w_u`` and ``z'' = −k q + mu_k (1 + r) g/r · w_u``. Along
    one direction this is :func:`floorslide.slide_oscillator` (Westermo & Udwadia 1983).

    References
    ----------
    Westermo, B., Udwadia, F. (1983). Periodic response of a sliding oscillator system to
    harmonic excitation. *Earthquake Eng. Struct. Dyn.* 11, 135–146.
    Jorba, À., Zou, M. (2005). A software package for the numerical integration of ODEs by means
    of high-order Taylor methods. *Experimental Mathematics* 14(1), 99–117.
    """
    mk, ms = _friction(mu_k, mu_s)
    f, xi, r = oscillator_parameters(frequency, damping, mass_ratio)
    row = _floor_row(motion, floor)
    MU = np.ascontiguousarray(np.vstack([np.maximum(mk, ms), mk]))
    states = np.zeros((mk.size, ok.NCOL))
    states[:, pk.LIMIT_AT] = -1.0
    states[:, pk.T_PEAK] = np.nan
    npts = int(motion.npts)
    hist = np.zeros((mk.size, npts, 4) if histories else (0, 0, 4))
    w = 2.0 * math.pi * f
    first = True
    for seg in checked_chunks(motion):
        t0, length, coef = (np.ascontiguousarray(a, dtype=float)
                            for a in (seg.t0, seg.length, seg.coef))  # fmt: skip
        ok.plane_oscillator_kernel(
            t0, length, seg.step, seg.ends, coef, row, first, G, MU, w, xi, r, states, hist,
            histories, DEGREE, pk.MAX_EVENTS,
        )  # fmt: skip
        first = False
    hit = np.flatnonzero(states[:, pk.LIMIT_AT] >= 0.0)
    if hit.size:
        i = int(hit[0])
        raise SolverLimitError(
            f"slide_oscillator_plane: more than {pk.MAX_EVENTS} stops and breakaways, or "
            f"{pk.MAX_STEPS} series steps, inside one segment at t = "
            f"{states[i, pk.LIMIT_AT]:.6g} s (mu_k = {mk[i]:g}): stick-slip chatter or creep "
            "the solver cannot resolve",
            "mu",
        )
    duration = (npts - 1) * float(motion.dt)
    return PlaneOscillatorResult(
        mu_k=mk,
        mu_s=ms,
        frequency=f,
        damping=xi,
        mass_ratio=r,
        peak_slide=states[:, pk.PEAK].copy(),
        peak_angle=np.degrees(states[:, pk.ANGLE]),
        time_of_peak=states[:, pk.T_PEAK].copy(),
        residual=states[:, [pk.UX, pk.UY]].copy(),
        peak_deformation=states[:, ok.PEAK_Z].copy(),
        peak_top_accel=states[:, ok.PEAK_TOP].copy(),
        slide_fraction=states[:, pk.SLIDE_TIME] / duration if duration > 0 else np.zeros(mk.size),
        slip_phases=states[:, pk.SLIPS].astype(int),
        stops=states[:, pk.STOPS].astype(int),
        path=states[:, pk.PATH].copy(),
        final_velocity=states[:, [pk.VX, pk.VY]].copy(),
        duration=duration,
        u=hist[:, :, :2].copy() if histories else None,
        z=hist[:, :, 2:].copy() if histories else None,
        notes=tuple(motion.notes),
    )


def slide_oscillator_plane(
    acc,
    dt: float | None = None,
    mu=None,
    frequency: float | None = None,
    damping: float = 0.02,
    mass_ratio: float = 1.0,
    *,
    mu_s=None,
    building=None,
    floor: int | None = None,
    histories: bool = False,
    vertical=None,
) -> PlaneOscillatorResult:
    """Peak slide, spring deformation and top acceleration of 2-DOF sliding oscillators in the
    plane (isotropic spring and damper, isotropic Coulomb friction under the base) under two
    horizontal components.

    Parameters
    ----------
    acc, dt
        A :class:`~floorslide.records.pairs.RecordPair`, ``(a_x, a_y)`` or an array
        ``(2, npts)`` of ground accelerations (m/s²) along ``h1`` and ``h2``, and the time step
        (s; with arrays).
    mu
        Kinetic friction coefficient(s) of the base, > 0, required.
    frequency
        Clamped-base natural frequency of the equipment, Hz; required.
    damping
        Damping ratio of the equipment on its clamped base, in [0, 1).
    mass_ratio
        ``r = m_base / m_top`` (> 0).
    mu_s
        Static coefficient(s) (default `mu`; breakaway at ``max(mu_s, mu)``).
    building, floor
        Put the oscillators on `floor` of `building`: a linear building (both directions), a
        :class:`~floorslide.building.directions.BuildingPair` (a model per direction), or a
        :class:`~floorslide.NonlinearIsolatedBuilding` on friction pendulums or lead-rubber
        bearings (its exact motion in the plane). `floor` is required with a building.
    histories
        Also return ``u`` and ``z`` at the samples.
    vertical
        Not modelled for the oscillator in the plane: refused.

    Returns
    -------
    PlaneOscillatorResult
        See :func:`slide_oscillator_plane_on_segments`, whose Notes give the equations.

    Raises
    ------
    ModelError
        Invalid input, in one line naming the argument.
    SolverLimitError
        Stick-slip chatter or creep the solver cannot resolve inside one segment.
    """
    if vertical is not None:
        raise ModelError(
            "vertical= is not modelled for the oscillator in the plane (slide_plane takes it)",
            "vertical",
        )
    pair = as_pair(acc, dt)
    mk, ms = _friction(mu, mu_s)
    f, xi, r = oscillator_parameters(frequency, damping, mass_ratio)
    if building is None:
        if floor not in (None, 0):
            raise ModelError(f"floor={floor!r} needs building= (without, the ground)", "floor")
        motion = GroundPolyMotion(pair)
        floor = None
    elif floor is None:
        raise ModelError("floor is required with building=", "floor")
    elif couples_directions(building):
        motion = PlaneIsolatedMotion(building, pair.h1, pair.h2, pair.dt)
    else:
        motion = LinearPolyMotion(building, pair, floors=[floor])
    res = slide_oscillator_plane_on_segments(
        motion, floor, mk, ms, frequency=f, damping=xi, mass_ratio=r, histories=histories
    )
    extra = tuple(pair.notes)
    if res.notes != extra:
        from dataclasses import replace

        res = replace(res, notes=extra + tuple(n for n in res.notes if n not in extra))
    return res
